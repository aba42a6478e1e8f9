//! The bonded joint that breaks: Mohr–Coulomb with a tension cut-off, then residual
//! friction. A pure function of numbers ([`bonded`]) and its [`FrictionLaw`] ([`Bonded`],
//! the law named `"bonded"`).
//!
//! # Selection and constants
//! An `[[interface]]` that sets `tensile_strength = T` (Pa, default 0) or
//! `residual_friction_angle = φ_r` (degrees, default `friction_angle`) takes this law, whatever
//! `[analysis] friction` says; an interface without them keeps the analysis' law, and its
//! `cohesion` its meaning there (a strength never lost). Each contact standing for the
//! length w of interface (its share of the tributary length, as for the cohesion) carries
//! the forces per metre of thickness `c = c̄ w` (in [`FrictionParams::cohesion`]),
//! `T = T̄ w` (`own[0]`) and `tan φ_r` (`own[1]`), with c̄, T̄ the interface's values in Pa.
//!
//! # Sign conventions
//! As in [`super::friction`]: `g_N < 0` is penetration; but here the normal force
//! `t_N = p_N g_N` (plus the restitution dashpot, if any) holds in **both** signs while the
//! bond holds: `t_N < 0` compression, `t_N > 0` **tension** (the bond pulls the faces
//! together). `t_S = p_S g_S^e`, `Δg_S = Δg_S^e + Δγ`.
//!
//! # The intact bond (a contact that touched at the start of the analysis)
//! Elastic domain, in the (t_N, t_S) plane:
//!
//! f_S = |t_S| − (c − t_N tan φ) ≤ 0   (shear: Mohr–Coulomb, S(t_N) = c − t_N tan φ),
//! f_T = t_N − T_c ≤ 0                 (tension cut-off),
//!
//! with `T_c = min(T, c / tan φ)`: a cut-off beyond the apex c/tan φ of the Mohr–Coulomb
//! line would not cut (FLAC's rule; a warning tells when T is above the apex). The flow is
//! non-associated without dilatancy, as in the Coulomb laws: shear yield slips (Δγ), tension
//! yield opens (Δg_N^p), each only along its own direction. From the trial forces
//! `t_N^tr = p_N g_N`, `t_S^tr = p_S (g_S^e|ₙ + Δg_S)` the return mapping has five branches:
//!
//! | branch | where | t_N | t_S | ∂(t_N, t_S)/∂(g_N, Δg_S) |
//! |---|---|---|---|---|
//! | elastic (`Stick`) | t_N^tr ≤ T_c, \|t_S^tr\| < S(t_N^tr) | t_N^tr | t_S^tr | [p_N 0; 0 p_S] |
//! | shear yield (`Slide(s)`) | t_N^tr ≤ T_c, \|t_S^tr\| ≥ S(t_N^tr) | t_N^tr | s S(t_N^tr) | [p_N 0; −s p_N tan φ 0] |
//! | tension ([`TENSION`]) | t_N^tr > T_c, \|t_S^tr\| < S(T_c) | T_c | t_S^tr | [0 0; 0 p_S] |
//! | corner ([`corner`]`(s)`) | t_N^tr > T_c, \|t_S^tr\| ≥ S(T_c) | T_c | s S(T_c) | [0 0; 0 0] |
//! | broken | the bond broke in an earlier step | residual Coulomb | | (open, stick, slide) |
//!
//! with `s = sgn t_S^tr`, plastic slip `Δγ = (t_S^tr − t_S)/p_S` and plastic opening
//! `Δg_N^p = (t_N^tr − T_c)/p_N` (tension and corner). The branches meet continuously (at
//! t_N^tr = T_c shear yield and corner agree, at |t_S^tr| = S(T_c) tension and corner), so the
//! law is piecewise affine and continuous in (g_N, Δg_S) within a step, as the semi-smooth
//! Newton iteration of [`super::law`] needs; the shear-yield tangent is unsymmetric, as
//! the return mapping's.
//!
//! # Breaking
//! A step that converges with an intact contact on a yield branch (shear yield, tension or
//! corner: Δγ ≠ 0 or Δg_N^p > 0) breaks the bond, for good ([`commit`]): in that step the
//! forces are on the peak surface, from the next step on the contact is the residual
//! Coulomb law ([`super::friction::return_mapping`] with `tan φ_r`, c = T = 0), starting from
//! the elastic shear gap the peak force stretched (so that its first residual step returns
//! t_S to σ_n tan φ_r). Breaking at the commit, not within the Newton iteration, keeps the law
//! of each step continuous (a jump from the peak to the residual surface inside the iteration
//! would make it cycle between the two); the drop is a step late, as a brittle failure
//! resolved by the time step. A broken contact keeps its state while it is open or out of
//! sight ([`FrictionLaw::lasting`]) and never bonds again. A contact first detected after the
//! analysis' first step, or not touching at the start, never had a bond ([`Bond::Never`]):
//! it has the residual friction from the start (the joint's surface where it was not
//! bonded), and is not counted as broken.
//!
//! While its bond holds, a contact is kept by the detection even when its vertex passes the
//! end of the other block's face by its elastic shear (`held_edge` in
//! [`super::set`]): the bond ties the vertex to the face's end.

use super::friction::{
    self, coulomb_start_forces, open_response, ContactStatus, FrictionParams, LawResponse,
    ReturnMapping, ShearHistory,
};
use super::law::{Branch, FrictionLaw, IterationContext, LawState, Selection};

/// The bonded law's own `[[interface]]` keys, in the order of its values.
pub const KEYS: &[&str] = &["tensile_strength", "residual_friction_angle"];

/// The tension cut-off branch: t_N = T_c, elastic shear.
pub const TENSION: Branch = Branch::Limit(0, 0);

/// The corner of the tension cut-off and the shear limit, sliding in the direction `s`.
pub const fn corner(s: i8) -> Branch {
    Branch::Limit(1, s)
}

/// The bond of a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bond {
    /// Bonded (the contact touched at the start of the analysis and has not failed).
    #[default]
    Intact,
    /// The bond broke: residual friction, for good.
    Broken,
    /// The contact never had a bond (first detected later, or not touching at the start):
    /// residual friction.
    Never,
}

/// The state of a bonded contact: its shear history and its bond.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BondState {
    pub shear: ShearHistory,
    pub bond: Bond,
}

impl BondState {
    /// A contact that never had a bond.
    pub const NEVER: BondState = BondState {
        shear: ShearHistory {
            ge: 0.0,
            status: ContactStatus::Open,
            tn: 0.0,
            slide_sign: 0.0,
        },
        bond: Bond::Never,
    };

    /// Words 0–3: the shear history ([`ShearHistory::to_state`]); word 4: the bond (0
    /// intact, 1 broken, 2 never bonded).
    pub fn to_state(&self) -> LawState {
        let mut s = self.shear.to_state();
        s.0[4] = match self.bond {
            Bond::Intact => 0,
            Bond::Broken => 1,
            Bond::Never => 2,
        };
        s
    }

    #[inline]
    pub fn from_state(s: &LawState) -> BondState {
        BondState {
            shear: ShearHistory::from_state(s),
            bond: match s.0[4] {
                0 => Bond::Intact,
                1 => Bond::Broken,
                _ => Bond::Never,
            },
        }
    }

    /// Residual friction only (broken, or never bonded).
    #[inline]
    pub fn residual(&self) -> bool {
        self.bond != Bond::Intact
    }
}

/// The tensile force the intact bond carries, T_c = min(T, c / tan φ) (N/m).
#[inline]
pub fn tensile_force(p: &FrictionParams) -> f64 {
    let t = p.own[0];
    if p.tan_phi > 0.0 {
        t.min(p.cohesion / p.tan_phi)
    } else {
        t
    }
}

/// The constants of the broken contact: tan φ_r, no cohesion.
#[inline]
pub fn residual(p: &FrictionParams) -> FrictionParams {
    FrictionParams {
        tan_phi: p.own[1],
        cohesion: 0.0,
        ..*p
    }
}

/// Shear strength S(t_N) = c − t_N tan φ of the intact bond (t_N > 0 is tension).
#[inline]
fn strength(p: &FrictionParams, tn: f64) -> f64 {
    p.cohesion - tn * p.tan_phi
}

fn sign(x: f64) -> i8 {
    if x < 0.0 {
        -1
    } else {
        1
    }
}

/// The intact bond's branch at (g_N, Δg_S) (see the module docs).
pub fn intact_branch(p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> Branch {
    let tn = p.closed_normal(gn);
    let tc = tensile_force(p);
    let trial = p.ps * (h.ge + dgs);
    if tn <= tc {
        if trial.abs() < strength(p, tn) {
            Branch::Stick
        } else {
            Branch::Slide(sign(trial))
        }
    } else if trial.abs() < strength(p, tc) {
        TENSION
    } else {
        corner(sign(trial))
    }
}

/// The intact bond's affine piece `branch` at (g_N, Δg_S), also outside its region.
pub fn intact_on_branch(
    p: &FrictionParams,
    h: &ShearHistory,
    gn: f64,
    dgs: f64,
    branch: Branch,
) -> LawResponse {
    let tn = p.closed_normal(gn);
    match branch {
        Branch::Open => open_response(),
        Branch::Stick => friction::stick_response(p, h, gn, dgs),
        Branch::Slide(s) => {
            let s = f64::from(s);
            friction::slide(p, h, tn, dgs, s, s * strength(p, tn))
        }
        Branch::Limit(piece, s) => {
            let tc = tensile_force(p);
            let trial = p.ps * (h.ge + dgs);
            let opening = (tn - tc) / p.normal_stiffness();
            if piece == 0 {
                LawResponse {
                    tn: tc,
                    ts: trial,
                    dtn_dgn: 0.0,
                    dtn_dgs: 0.0,
                    dts_dgn: 0.0,
                    dts_dgs: p.ps,
                    status: ContactStatus::Stick,
                    ge: h.ge + dgs,
                    slip: 0.0,
                    opening,
                }
            } else {
                let ts = f64::from(s) * strength(p, tc);
                LawResponse {
                    tn: tc,
                    ts,
                    dtn_dgn: 0.0,
                    dtn_dgs: 0.0,
                    dts_dgn: 0.0,
                    dts_dgs: 0.0,
                    status: ContactStatus::Slide,
                    ge: ts / p.ps,
                    slip: (trial - ts) / p.ps,
                    opening,
                }
            }
        }
    }
}

/// The bonded law at (g_N, Δg_S) from the committed state `h` (see the module docs).
pub fn bonded(p: &FrictionParams, h: &BondState, gn: f64, dgs: f64) -> LawResponse {
    if h.residual() {
        return friction::return_mapping(&residual(p), &h.shear, gn, dgs);
    }
    intact_on_branch(p, &h.shear, gn, dgs, intact_branch(p, &h.shear, gn, dgs))
}

/// The state kept once the step has converged with response `r`: an intact contact on a
/// yield branch (plastic slip or opening) breaks (see the module docs).
pub fn commit(p: &FrictionParams, h: &BondState, r: &LawResponse) -> BondState {
    if h.residual() {
        return BondState {
            shear: friction::commit_return_mapping(&residual(p), &h.shear, r),
            bond: h.bond,
        };
    }
    BondState {
        shear: friction::commit_return_mapping(p, &h.shear, r),
        bond: if r.status == ContactStatus::Slide || r.opening > 0.0 {
            Bond::Broken
        } else {
            Bond::Intact
        },
    }
}

/// The law named `"bonded"` (see the module docs). Its state is a [`BondState`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Bonded;

impl FrictionLaw for Bonded {
    fn name(&self) -> &'static str {
        "bonded"
    }

    fn selection(&self) -> Selection {
        Selection::Interface(KEYS)
    }

    /// `tensile_strength` T ≥ 0 (default 0), `residual_friction_angle` φ_r in [0, φ]
    /// (default φ).
    fn interface_values(
        &self,
        friction_angle: f64,
        cohesion: f64,
        given: &[Option<f64>],
    ) -> Result<Vec<f64>, (usize, String)> {
        let _ = cohesion;
        let t = given.first().copied().flatten().unwrap_or(0.0);
        // a NaN is refused too (numbers are finite when the model reader gives them)
        if t.is_nan() || t < 0.0 {
            return Err((0, format!("must be zero or positive (Pa), got {t}")));
        }
        let phi_r = given.get(1).copied().flatten().unwrap_or(friction_angle);
        if !(0.0..90.0).contains(&phi_r) {
            return Err((1, format!("must be in [0, 90) degrees, got {phi_r}")));
        }
        if phi_r > friction_angle {
            return Err((
                1,
                format!(
                    "must not exceed friction_angle = {friction_angle} (the friction left once a \
                     contact breaks), got {phi_r}"
                ),
            ));
        }
        Ok(vec![t, phi_r])
    }

    fn interface_warning(
        &self,
        friction_angle: f64,
        cohesion: f64,
        values: &[f64],
    ) -> Option<String> {
        let tan_phi = friction_angle.to_radians().tan();
        let t = values[0];
        (tan_phi > 0.0 && t > cohesion / tan_phi).then(|| {
            format!(
                "tensile_strength {t} Pa is above the apex c / tan φ = {:.0} Pa of the Mohr–Coulomb \
                 line: the bond carries at most that tension (set cohesion ≥ T tan φ for more)",
                cohesion / tan_phi
            )
        })
    }

    fn own_constants(&self, values: &[f64], weight: f64) -> [f64; 4] {
        [values[0] * weight, values[1].to_radians().tan(), 0.0, 0.0]
    }

    /// Bonded if it touches at the start of the analysis; otherwise never bonded.
    fn new_state(&self, touching: bool, at_start: bool) -> LawState {
        if touching && at_start {
            BondState::default().to_state()
        } else {
            BondState::NEVER.to_state()
        }
    }

    fn branch(&self, p: &FrictionParams, h: &LawState, gn: f64, dgs: f64) -> Branch {
        let h = BondState::from_state(h);
        if h.residual() {
            ReturnMapping::branch_of(&residual(p), &h.shear, gn, dgs)
        } else {
            intact_branch(p, &h.shear, gn, dgs)
        }
    }

    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse {
        let h = BondState::from_state(h);
        if h.residual() {
            ReturnMapping::on_branch_of(&residual(p), &h.shear, gn, dgs, branch)
        } else {
            intact_on_branch(p, &h.shear, gn, dgs, branch)
        }
    }

    /// Broken: the return mapping's rules. Intact: the law's own branch, except that a
    /// contact on a shear limit (shear yield or corner) that would now slide the other way
    /// is held elastic in shear for this iterate (as the return mapping's reversing slide).
    fn iteration_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        ctx: IterationContext,
    ) -> Branch {
        let h = BondState::from_state(h);
        if h.residual() {
            return ReturnMapping::iteration_branch_of(&residual(p), &h.shear, gn, dgs, ctx);
        }
        let own = intact_branch(p, &h.shear, gn, dgs);
        match (ctx.previous, own) {
            (Some(Branch::Slide(a)), Branch::Slide(b)) if a != b => Branch::Stick,
            (Some(Branch::Limit(1, a)), Branch::Limit(1, b)) if a != b => TENSION,
            _ => own,
        }
    }

    fn commit(&self, p: &FrictionParams, h: &LawState, r: &LawResponse) -> LawState {
        commit(p, &BondState::from_state(h), r).to_state()
    }

    /// A broken bond is kept (a contact that never had one needs nothing kept: a contact
    /// detected anew has none).
    fn lasting(&self, h: &LawState) -> bool {
        BondState::from_state(h).bond == Bond::Broken
    }

    fn start_forces(&self, p: &FrictionParams, h: &LawState, gn0: f64) -> (f64, f64) {
        let h = BondState::from_state(h);
        if h.residual() {
            coulomb_start_forces(p, &h.shear, gn0)
        } else {
            (p.pn * gn0, p.ps * h.shear.ge)
        }
    }

    fn bond(&self, h: &LawState) -> Option<bool> {
        match BondState::from_state(h).bond {
            Bond::Intact => Some(true),
            Bond::Broken => Some(false),
            Bond::Never => None,
        }
    }

    fn has_bonds(&self) -> bool {
        true
    }

    fn valid_state(&self, h: &LawState) -> bool {
        ShearHistory::is_encoded(h) && h.0[4] <= 2
    }
}
