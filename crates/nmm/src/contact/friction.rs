//! Penalty contact laws with Coulomb friction: pure functions of numbers.
//!
//! This module owns the *constitutive* part of contact: given the committed
//! shear history of one contact and the current kinematic quantities, it
//! returns the normal and shear forces, their derivatives (the tangent used by
//! Newton-Raphson) and the new trial state. It knows nothing of geometry or of
//! covers; kinematics (how `g_N`, `Δg_S` depend on the unknowns) lives elsewhere.
//!
//! # Sign conventions and symbols
//! * `g_N` (`gn`): signed normal gap; **negative = penetration**.
//! * `t_N` (`tn`): normal force, `t_N = p_N g_N` if `g_N < 0`, else `0`.
//!   Hence `t_N ≤ 0` always (compression); these laws never pull (the bonded law of
//!   [`super::bonded`] does, while its bond holds).
//! * `Δg_S` (`dgs`): shear displacement increment of the current step (relative
//!   tangential motion since the last converged state).
//! * `g_S^e` (`ge`): elastic shear gap; `t_S = p_S g_S^e` (`ts`).
//! * `Δγ` (`slip`): signed plastic slip of the step, `Δg_S = Δ(g_S^e) + Δγ`,
//!   i.e. `slip = Δg_S − (g_S^e − g_S^e|ₙ)`.
//! * Strength: `S = |t_N| tan φ + c`, with `c` the cohesion as a *force*
//!   (cohesion stress × tributary length, N/m). Yield function `f = |t_S| − S`.
//!
//! Forces are per metre of thickness (N/m), penalties in N/m per m of gap.
//!
//! # Return mapping ([`return_mapping`], the method of the paper)
//! Evaluated at every Newton iterate from the *committed* state (step `n`):
//! * open (`g_N ≥ 0`): `t_N = t_S = 0`, zero tangent, `g_S^e` reset to 0;
//! * trial: `g_S^e,tr = g_S^e|ₙ + Δg_S`, `t_S^tr = p_S g_S^e,tr`;
//! * stick if `|t_S^tr| < S`: `t_S = t_S^tr`, tangent `∂t_S/∂g_S = p_S`, `∂t_S/∂g_N = 0`;
//! * slide otherwise: `t_S = sgn(t_S^tr) S`, `g_S^e = t_S / p_S`,
//!   `Δγ = sgn(t_S^tr) (|t_S^tr| − S)/p_S`, consistent tangent
//!   `∂t_S/∂g_N = −sgn(t_S^tr) p_N tan φ` (because `|t_N| = −p_N g_N`),
//!   `∂t_S/∂g_S = 0` — unsymmetric.
//!
//! In both branches `∂t_N/∂g_N = p_N` (closed) and `∂t_N/∂g_S = 0`.
//! The shear force never exceeds the strength of the *current* normal force.
//!
//! # Conventional rule ([`conventional`], classical DDA/NMM open–close, for comparison)
//! The contact mode (stick or slide) is frozen during a step and taken from the
//! committed state; only the end-of-step check ([`commit`]) changes it:
//! * committed `Stick`: the shear spring is elastic for the whole step,
//!   `t_S = p_S (g_S^e|ₙ + Δg_S)`, tangent `p_S`, **no limit**;
//! * committed `Open` (a contact that closes during the step, including one that only
//!   touches at its start): Coulomb-limited by its
//!   current normal force, as by the return mapping. Such a contact has no elastic shear
//!   history; left unlimited, the spring would be stretched by the whole step's slip and
//!   the Newton iteration cycles between opening and closing it (DDA's open–close
//!   iteration likewise checks a new contact's shear against its strength before
//!   locking it). The overshoot this rule is kept for — contacts that were sticking and
//!   start to slide — is unchanged;
//! * committed `Slide` with direction `s = slide_sign`: the shear force is the
//!   friction force of the **last committed** normal force,
//!   `t_S = s (|t_N|ₙ tan φ + c)`, tangent `∂t_S/∂g_N = ∂t_S/∂g_S = 0`; while the
//!   contact unloads (`|t_N| < |t_N|ₙ`) this force is scaled by `t_N / t_Nₙ`, so that it
//!   vanishes as the contact opens — a constant friction force on a contact that may open
//!   within the step is discontinuous and makes the iteration cycle. The lag (the force
//!   of the previous normal force) is kept whenever the normal force grows;
//!   the mode is frozen for the whole step (as in DDA's open–close iteration, the mode
//!   changes are decided between steps; deciding them at every Newton iterate makes the
//!   iteration cycle between two states);
//! * commit: if an elastic (stick) contact ends the step with `|t_S| ≥ S(t_N)`,
//!   it is switched to `Slide` *for the next step*, with `slide_sign = sgn t_S`
//!   and `g_S^e = slide_sign·S/p_S`; a sliding contact whose slip reversed during the
//!   step (`s Δg_S < 0`) returns to `Stick` for the next step, elastic from its force.
//!
//! ## Why the conventional rule overshoots
//! Within the step in which the strength is first exceeded, the converged
//! shear force is the elastic one, `p_S (g_S^e|ₙ + Δg_S) > S`: the excess is
//! neither returned to the yield surface nor redistributed to the rest of the
//! system in that step; it is only "pulled back" at the start of the next step,
//! when the mode has become `Slide`. Moreover, while sliding, the friction force
//! uses the normal force of the previous step, so it lags any change of `t_N`.
//! The return mapping projects onto `|t_S| = S(t_N)` inside the Newton loop,
//! with the current `t_N`, and so never overshoots.

use super::law::{Branch, FrictionLaw, IterationContext, LawState, Selection};

/// Material constants of one contact. The laws assume `pn > 0`, `ps > 0`,
/// `tan_phi ≥ 0`, `cohesion ≥ 0` (validated with the model).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionParams {
    /// Normal penalty `p_N` (N/m per m).
    pub pn: f64,
    /// Shear penalty `p_S` (N/m per m).
    pub ps: f64,
    /// `tan φ`.
    pub tan_phi: f64,
    /// Cohesion as a force, N/m: cohesion stress × tributary length.
    pub cohesion: f64,
    /// Normal dashpot over the step, c_N/Δt (N/m per m; 0: none), see
    /// [`crate::contact::restitution`].
    pub dashpot: f64,
    /// Normal gap at the step's start, g_N⁰ (the dashpot acts on g_N − g_N⁰).
    pub gn0: f64,
    /// The contact's constants of its law's own, as the law defines them
    /// ([`FrictionLaw::own_constants`]: e.g. the bonded law's tensile force and tan φ_r);
    /// zero for the Coulomb laws of this module.
    pub own: [f64; 4],
}

impl FrictionParams {
    /// The normal force of a closed contact at g_N: `p_N g_N`, plus the dashpot's
    /// `(c_N/Δt)(g_N − g_N⁰)` when there is one.
    #[inline]
    pub fn closed_normal(&self, gn: f64) -> f64 {
        if self.dashpot == 0.0 {
            self.pn * gn
        } else {
            self.pn * gn + self.dashpot * (gn - self.gn0)
        }
    }

    /// ∂t_N/∂g_N of a closed contact: p_N + c_N/Δt.
    #[inline]
    pub fn normal_stiffness(&self) -> f64 {
        self.pn + self.dashpot
    }

    /// Whether the contact is closed at g_N: penetrating, with a compressive normal force
    /// (a dashpot never pulls: the contact opens where it would).
    #[inline]
    pub fn is_closed(&self, gn: f64) -> bool {
        gn < 0.0 && (self.dashpot == 0.0 || self.closed_normal(gn) < 0.0)
    }

    /// The energy ½ t_N²/p_N + ½ t_S²/p_S of the contact's springs holding the normal
    /// spring force `tn_spring` and the shear force `ts`.
    #[inline]
    pub fn spring_energy(&self, tn_spring: f64, ts: f64) -> f64 {
        0.5 * tn_spring * tn_spring / self.pn + 0.5 * ts * ts / self.ps
    }

    /// The spring's share p_N g_N of a closed contact's normal force `tn` (without the
    /// dashpot's).
    #[inline]
    pub fn spring_normal(&self, tn: f64) -> f64 {
        if self.dashpot == 0.0 || tn == 0.0 {
            tn
        } else {
            self.pn * (tn + self.dashpot * self.gn0) / (self.pn + self.dashpot)
        }
    }

    /// Shear strength `S = |t_N| tan φ + c` for the normal force `tn` (≤ 0).
    #[inline]
    pub fn strength(&self, tn: f64) -> f64 {
        tn.abs() * self.tan_phi + self.cohesion
    }
}

/// State of a contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactStatus {
    /// `g_N ≥ 0`: no force.
    #[default]
    Open,
    /// Closed, elastic shear spring.
    Stick,
    /// Closed, shear force on the Coulomb limit.
    Slide,
}

/// Committed (converged) shear history of one contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShearHistory {
    /// Elastic shear gap `g_S^e`.
    pub ge: f64,
    pub status: ContactStatus,
    /// Last committed normal force `t_N` (≤ 0).
    pub tn: f64,
    /// Direction of sliding (±1) when `status == Slide`, else 0.
    pub slide_sign: f64,
}

impl ShearHistory {
    /// The history as a law's opaque state ([`LawState`]): words 0–3 are `ge`, the status
    /// code (0 open, 1 stick, 2 slide), `tn` and `slide_sign`, the numbers as their bits
    /// (so that a checkpoint keeps them exactly); the other words are zero.
    pub fn to_state(&self) -> LawState {
        let mut w = [0u64; LawState::WORDS];
        w[0] = self.ge.to_bits();
        w[1] = match self.status {
            ContactStatus::Open => 0,
            ContactStatus::Stick => 1,
            ContactStatus::Slide => 2,
        };
        w[2] = self.tn.to_bits();
        w[3] = self.slide_sign.to_bits();
        LawState(w)
    }

    /// The history of words 0–3 of a state written by [`ShearHistory::to_state`] (an
    /// unknown status code reads as open: [`ShearHistory::is_encoded`] tells).
    #[inline]
    pub fn from_state(s: &LawState) -> ShearHistory {
        let w = &s.0;
        ShearHistory {
            ge: f64::from_bits(w[0]),
            status: match w[1] {
                1 => ContactStatus::Stick,
                2 => ContactStatus::Slide,
                _ => ContactStatus::Open,
            },
            tn: f64::from_bits(w[2]),
            slide_sign: f64::from_bits(w[3]),
        }
    }

    /// Whether words 0–3 of `s` are a history [`ShearHistory::to_state`] can write (a
    /// known status code, finite numbers).
    pub fn is_encoded(s: &LawState) -> bool {
        let h = ShearHistory::from_state(s);
        s.0[1] <= 2 && h.ge.is_finite() && h.tn.is_finite() && h.slide_sign.is_finite()
    }
}

/// Forces, tangent and trial state returned by a law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawResponse {
    pub tn: f64,
    pub ts: f64,
    pub dtn_dgn: f64,
    pub dtn_dgs: f64,
    pub dts_dgn: f64,
    pub dts_dgs: f64,
    pub status: ContactStatus,
    /// Trial elastic shear gap `g_S^e`.
    pub ge: f64,
    /// Signed slip `Δγ` of the step.
    pub slip: f64,
    /// Plastic normal opening `Δg_N^p ≥ 0` of the step (a law with a tension cut-off;
    /// zero for the Coulomb laws).
    pub opening: f64,
}

/// The response of an open contact: no force, no stiffness.
pub fn open_response() -> LawResponse {
    LawResponse::open()
}

/// The stick (elastic) response at (g_N, Δg_S), also at a gap (g_N ≥ 0, a contact held
/// closed by the iteration): `t_N = p_N g_N`, `t_S = p_S (g_S^e|ₙ + Δg_S)`.
pub fn stick_response(p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> LawResponse {
    stick(p, h, p.closed_normal(gn), dgs)
}

impl LawResponse {
    fn open() -> Self {
        LawResponse {
            tn: 0.0,
            ts: 0.0,
            dtn_dgn: 0.0,
            dtn_dgs: 0.0,
            dts_dgn: 0.0,
            dts_dgs: 0.0,
            status: ContactStatus::Open,
            ge: 0.0,
            slip: 0.0,
            opening: 0.0,
        }
    }
}

/// Sign with `sgn(0) = +1` (only reached when the force is zero anyway).
#[inline]
fn sgn(x: f64) -> f64 {
    if x < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Elastic (stick) response from the committed elastic gap.
fn stick(p: &FrictionParams, h: &ShearHistory, tn: f64, dgs: f64) -> LawResponse {
    let ge = h.ge + dgs;
    LawResponse {
        tn,
        ts: p.ps * ge,
        dtn_dgn: p.normal_stiffness(),
        dtn_dgs: 0.0,
        dts_dgn: 0.0,
        dts_dgs: p.ps,
        status: ContactStatus::Stick,
        ge,
        slip: 0.0,
        opening: 0.0,
    }
}

/// Implicit return mapping (see the module docs).
pub fn return_mapping(p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> LawResponse {
    if !p.is_closed(gn) {
        return LawResponse::open();
    }
    let tn = p.closed_normal(gn);
    let strength = p.strength(tn);
    let trial = p.ps * (h.ge + dgs);
    // mutation check (scripts/mutants; never enabled in CI): no projection on the cone
    if trial.abs() < strength || cfg!(feature = "mutant-no-return-mapping") {
        return stick(p, h, tn, dgs);
    }
    // mutation check (scripts/mutants; never enabled in CI): friction along the slip
    let s = sgn(trial)
        * if cfg!(feature = "mutant-contact-sign") {
            -1.0
        } else {
            1.0
        };
    slide(p, h, tn, dgs, s, s * strength)
}

/// The sliding response in direction `s` (±1) with shear force `ts`: consistent tangent
/// ∂t_S/∂g_N = −s p_N tan φ, no shear stiffness; the elastic gap is what `ts` stretches,
/// the rest of the trial gap is slip.
pub fn slide(
    p: &FrictionParams,
    h: &ShearHistory,
    tn: f64,
    dgs: f64,
    s: f64,
    ts: f64,
) -> LawResponse {
    let trial = p.ps * (h.ge + dgs);
    LawResponse {
        tn,
        ts,
        dtn_dgn: p.normal_stiffness(),
        dtn_dgs: 0.0,
        dts_dgn: -s * p.normal_stiffness() * p.tan_phi,
        dts_dgs: 0.0,
        status: ContactStatus::Slide,
        ge: ts / p.ps,
        slip: (trial - ts) / p.ps,
        opening: 0.0,
    }
}

/// Conventional open–close rule (see the module docs).
pub fn conventional(p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> LawResponse {
    if !p.is_closed(gn) {
        return LawResponse::open();
    }
    let tn = p.closed_normal(gn);
    match h.status {
        // A contact that was open at the start of the step has no elastic shear history
        // to overshoot from: it is limited by the current strength (see the module docs).
        ContactStatus::Open => return_mapping(p, h, gn, dgs),
        ContactStatus::Stick => stick(p, h, tn, dgs),
        ContactStatus::Slide => {
            let s = if h.slide_sign == 0.0 {
                1.0
            } else {
                sgn(h.slide_sign)
            };
            // friction force of the last committed normal force, lowered in proportion
            // when the contact unloads (r < 1) so that it vanishes as the contact opens
            let (r, dr_dgn) = if h.tn < 0.0 && tn > h.tn {
                (tn / h.tn, p.normal_stiffness() / h.tn)
            } else {
                (1.0, 0.0)
            };
            let ts = s * p.strength(h.tn) * r;
            let ge = ts / p.ps;
            LawResponse {
                tn,
                ts,
                dtn_dgn: p.normal_stiffness(),
                dtn_dgs: 0.0,
                dts_dgn: s * p.strength(h.tn) * dr_dgn,
                dts_dgs: 0.0,
                status: ContactStatus::Slide,
                ge,
                slip: dgs - (ge - h.ge),
                opening: 0.0,
            }
        }
    }
}

/// The history return mapping keeps once the step has converged with response `r`: the
/// response state as it is.
pub fn commit_return_mapping(
    p: &FrictionParams,
    h: &ShearHistory,
    r: &LawResponse,
) -> ShearHistory {
    commit(false, p, h, r)
}

/// The history the conventional rule keeps once the step has converged with response `r`:
/// an elastic contact whose force reached the strength `S(r.tn)` is switched to `Slide`
/// for the next step (its force in this step stays as computed: the overshoot), with
/// `g_S^e = sgn(t_S) S / p_S`; a sliding contact whose slip reversed returns to `Stick`.
pub fn commit_conventional(p: &FrictionParams, h: &ShearHistory, r: &LawResponse) -> ShearHistory {
    commit(true, p, h, r)
}

/// [`commit_return_mapping`] (`conventional` false) or [`commit_conventional`].
fn commit(
    conventional: bool,
    p: &FrictionParams,
    h: &ShearHistory,
    r: &LawResponse,
) -> ShearHistory {
    // mutation check (scripts/mutants; never enabled in CI): the step's state is not kept
    if cfg!(feature = "mutant-no-commit") {
        return *h;
    }
    match r.status {
        ContactStatus::Open => ShearHistory::default(),
        // Conventional: a sliding contact whose slip reversed during the step returns to
        // the elastic spring for the next step (the mode is frozen within a step).
        ContactStatus::Slide
            if conventional && h.status == ContactStatus::Slide && h.slide_sign * r.slip < 0.0 =>
        {
            ShearHistory {
                ge: r.ge,
                status: ContactStatus::Stick,
                tn: r.tn,
                slide_sign: 0.0,
            }
        }
        ContactStatus::Slide => ShearHistory {
            ge: r.ge,
            status: ContactStatus::Slide,
            tn: r.tn,
            slide_sign: if !conventional || h.slide_sign == 0.0 {
                sgn(r.ts)
            } else {
                sgn(h.slide_sign)
            },
        },
        ContactStatus::Stick => {
            let strength = p.strength(r.tn);
            if conventional && r.ts.abs() >= strength {
                let s = sgn(r.ts);
                ShearHistory {
                    ge: s * strength / p.ps,
                    status: ContactStatus::Slide,
                    tn: r.tn,
                    slide_sign: s,
                }
            } else {
                ShearHistory {
                    ge: r.ge,
                    status: ContactStatus::Stick,
                    tn: r.tn,
                    slide_sign: 0.0,
                }
            }
        }
    }
}

/// Implicit return mapping with the consistent tangent ([`return_mapping`]): the law named
/// `"return-mapping"` (`[analysis] friction`, the default). Its state is a [`ShearHistory`].
#[derive(Debug, Clone, Copy, Default)]
pub struct ReturnMapping;

/// The conventional open–close rule ([`conventional`]): the law named `"conventional"`.
/// Its state is a [`ShearHistory`].
#[derive(Debug, Clone, Copy, Default)]
pub struct Conventional;

fn branch_of(r: &LawResponse) -> Branch {
    match r.status {
        ContactStatus::Open => Branch::Open,
        ContactStatus::Stick => Branch::Stick,
        ContactStatus::Slide => Branch::Slide(if r.ts < 0.0 { -1 } else { 1 }),
    }
}

/// The energy bookkeeping's spring forces of a Coulomb contact at the step's start: the
/// normal spring `p_N min(g_N⁰, 0)` (it holds no tension) and the shear spring `p_S g_S^e`.
pub fn coulomb_start_forces(p: &FrictionParams, h: &ShearHistory, gn0: f64) -> (f64, f64) {
    (p.pn * gn0.min(0.0), p.ps * h.ge)
}

impl ReturnMapping {
    /// The branch of [`return_mapping`] at (g_N, Δg_S).
    pub fn branch_of(p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> Branch {
        branch_of(&return_mapping(p, h, gn, dgs))
    }

    /// The affine piece `branch` of [`return_mapping`] at (g_N, Δg_S), also outside the
    /// region where the law is on it.
    pub fn on_branch_of(
        p: &FrictionParams,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse {
        let tn = p.closed_normal(gn);
        match branch {
            Branch::Open => open_response(),
            Branch::Slide(s) => {
                let s = f64::from(s);
                // t_S = s (−tan φ p_N g_N + c): the affine continuation of s·S(t_N)
                slide(p, h, tn, dgs, s, s * (-p.tan_phi * tn + p.cohesion))
            }
            // Stick, and any other law's piece: the elastic spring
            _ => stick_response(p, h, gn, dgs),
        }
    }

    /// The semi-smooth Newton rules: the closed-contact predictor of the default; at the
    /// first iterate a contact that slid at the end of the last step goes on sliding; and a
    /// contact that slid one way at the previous iterate and would now slide the other way
    /// is held in stick for this iterate. A sliding contact has no shear stiffness; a Newton
    /// step computed with it overshoots across the stick band (2S/p_S wide, often 1e-8 m
    /// against increments of 1e-5 m) and the return mapping then jumps from one slide
    /// direction to the other. With the stick tangent the iterate lands in the band when the
    /// solution sticks, and slides on at the next iterate otherwise.
    pub fn iteration_branch_of(
        p: &FrictionParams,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
        ctx: IterationContext,
    ) -> Branch {
        let own = Self::branch_of(p, h, gn, dgs);
        match (ctx.previous, own) {
            (None, Branch::Open) if ctx.touching => Branch::Stick,
            // a contact that slid at the end of the last step starts the step sliding the
            // same way: at Δg_S = 0 its trial force is exactly its strength, and the law's
            // branch there is a tie decided by round-off
            (None, Branch::Stick) if h.status == ContactStatus::Slide && h.slide_sign != 0.0 => {
                Branch::Slide(if h.slide_sign < 0.0 { -1 } else { 1 })
            }
            (Some(Branch::Slide(a)), Branch::Slide(b)) if a != b => Branch::Stick,
            _ => own,
        }
    }
}

impl FrictionLaw for ReturnMapping {
    fn name(&self) -> &'static str {
        "return-mapping"
    }

    fn selection(&self) -> Selection {
        Selection::Analysis
    }

    fn branch(&self, p: &FrictionParams, h: &LawState, gn: f64, dgs: f64) -> Branch {
        Self::branch_of(p, &ShearHistory::from_state(h), gn, dgs)
    }

    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse {
        Self::on_branch_of(p, &ShearHistory::from_state(h), gn, dgs, branch)
    }

    fn response(&self, p: &FrictionParams, h: &LawState, gn: f64, dgs: f64) -> LawResponse {
        let h = ShearHistory::from_state(h);
        Self::on_branch_of(p, &h, gn, dgs, Self::branch_of(p, &h, gn, dgs))
    }

    fn iteration_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        ctx: IterationContext,
    ) -> Branch {
        Self::iteration_branch_of(p, &ShearHistory::from_state(h), gn, dgs, ctx)
    }

    fn commit(&self, p: &FrictionParams, h: &LawState, r: &LawResponse) -> LawState {
        commit_return_mapping(p, &ShearHistory::from_state(h), r).to_state()
    }

    fn start_forces(&self, p: &FrictionParams, h: &LawState, gn0: f64) -> (f64, f64) {
        coulomb_start_forces(p, &ShearHistory::from_state(h), gn0)
    }

    fn valid_state(&self, h: &LawState) -> bool {
        ShearHistory::is_encoded(h) && h.0[4..].iter().all(|&w| w == 0)
    }
}

impl FrictionLaw for Conventional {
    fn name(&self) -> &'static str {
        "conventional"
    }

    fn selection(&self) -> Selection {
        Selection::Analysis
    }

    /// Contacts touching at the start of the analysis are locked: an elastic shear spring
    /// from there on (DDA's initial contacts). A contact that comes to touch later keeps its
    /// open history and is limited by Coulomb while it closes (see the module docs).
    fn new_state(&self, touching: bool, at_start: bool) -> LawState {
        if touching && at_start {
            ShearHistory {
                status: ContactStatus::Stick,
                ..ShearHistory::default()
            }
            .to_state()
        } else {
            LawState::default()
        }
    }

    fn branch(&self, p: &FrictionParams, h: &LawState, gn: f64, dgs: f64) -> Branch {
        branch_of(&conventional(p, &ShearHistory::from_state(h), gn, dgs))
    }

    /// The mode of a closed contact is frozen within the step (it is the committed one):
    /// only open and closed are branches the iteration may hold.
    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse {
        let h = ShearHistory::from_state(h);
        match branch {
            Branch::Open => open_response(),
            _ if p.is_closed(gn) => conventional(p, &h, gn, dgs),
            // held closed at a gap (the predictor): the elastic stick spring
            _ => stick_response(p, &h, gn, dgs),
        }
    }

    fn commit(&self, p: &FrictionParams, h: &LawState, r: &LawResponse) -> LawState {
        commit_conventional(p, &ShearHistory::from_state(h), r).to_state()
    }

    fn start_forces(&self, p: &FrictionParams, h: &LawState, gn0: f64) -> (f64, f64) {
        coulomb_start_forces(p, &ShearHistory::from_state(h), gn0)
    }

    fn valid_state(&self, h: &LawState) -> bool {
        ShearHistory::is_encoded(h) && h.0[4..].iter().all(|&w| w == 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const P: FrictionParams = FrictionParams {
        pn: 1.0e11,
        ps: 1.0e9,
        tan_phi: 0.577_350_269_189_625_8,
        cohesion: 0.0,
        dashpot: 0.0,
        gn0: 0.0,
        own: [0.0; 4],
    };

    fn committed(ge: f64, status: ContactStatus, tn: f64, slide_sign: f64) -> ShearHistory {
        ShearHistory {
            ge,
            status,
            tn,
            slide_sign,
        }
    }

    #[test]
    fn open_contact_has_no_force_and_resets_elastic_gap() {
        let h = committed(1e-4, ContactStatus::Stick, -1e6, 0.0);
        for law in [return_mapping, conventional] {
            let r = law(&P, &h, 1e-6, 3e-4);
            assert_eq!(r.status, ContactStatus::Open);
            assert_eq!((r.tn, r.ts, r.ge), (0.0, 0.0, 0.0));
            assert_eq!(
                (r.dtn_dgn, r.dtn_dgs, r.dts_dgn, r.dts_dgs),
                (0.0, 0.0, 0.0, 0.0)
            );
            // g_N = 0 exactly counts as open.
            assert_eq!(law(&P, &h, 0.0, 3e-4).status, ContactStatus::Open);
        }
    }

    #[test]
    fn no_tensile_normal_force() {
        let h = ShearHistory::default();
        for gn in [-1e-3, -1e-8, 0.0, 1e-8, 1.0] {
            for law in [return_mapping, conventional] {
                assert!(law(&P, &h, gn, 0.0).tn <= 0.0);
            }
        }
        assert_relative_eq!(return_mapping(&P, &h, -1e-5, 0.0).tn, -1e6);
    }

    /// The first kink of the return-mapping law along a line of (g_N, Δg_S) against its
    /// closed forms: closing where g_N crosses 0, sliding where p_S (g_e + Δg_S) reaches
    /// tan φ p_N |g_N|; found just past the crossing (on the new branch), within 2⁻⁴⁰.
    #[test]
    fn first_kink_of_return_mapping_closed_forms() {
        use crate::contact::law::{first_kink, Branch, FrictionLaw};
        let law: &dyn FrictionLaw = &ReturnMapping;
        let h = committed(0.0, ContactStatus::Stick, -1e6, 0.0).to_state();
        let close = |gn, dn| first_kink(law, &P, &h, (gn, 0.0), (dn, 0.0), 0.0, 1.0);
        // open at 2 µm, closing by 8 µm: at a quarter of the line
        let a = close(2e-6, -8e-6).expect("closes");
        assert!(a > 0.25 && a - 0.25 <= 1e-11, "{a}");
        assert_eq!(law.branch(&P, &h, 2e-6 - a * 8e-6, 0.0), Branch::Stick);
        // closing by less than it is open: no kink; opening further: none
        assert_eq!(close(2e-6, -1e-6), None);
        assert_eq!(close(2e-6, 1e-6), None);
        // closed at 10 µm (t_N = −1 MN/m, strength 577 kN/m), sheared by 1 mm: the trial
        // force p_S Δg_S reaches the strength at Δg_S = 0.577 mm, either way
        let strength = P.tan_phi * P.pn * 1e-5;
        for sign in [1.0, -1.0] {
            let a = first_kink(law, &P, &h, (-1e-5, 0.0), (0.0, sign * 1e-3), 0.0, 1.0)
                .expect("slides");
            let at = strength / (P.ps * 1e-3);
            assert!(a > at && a - at <= 1e-11, "{a} against {at}");
            assert_eq!(
                law.branch(&P, &h, -1e-5, sign * a * 1e-3),
                Branch::Slide(sign as i8)
            );
            // not within the interval asked: none
            assert_eq!(
                first_kink(law, &P, &h, (-1e-5, 0.0), (0.0, sign * 1e-3), 0.0, 0.5 * at),
                None
            );
        }
        // a sliding contact pulled on along its slip: no kink; opened on the way: at g_N = 0
        assert_eq!(
            first_kink(law, &P, &h, (-1e-5, 1e-3), (0.0, 1e-3), 0.0, 1.0),
            None
        );
        // (g_N = 0 is open: the crossing itself is on the new branch)
        let a = first_kink(law, &P, &h, (-1e-5, 1e-3), (4e-5, 0.0), 0.0, 1.0).expect("opens");
        assert!(a >= 0.25 && a - 0.25 <= 1e-11, "{a}");
        assert_eq!(law.branch(&P, &h, -1e-5 + a * 4e-5, 1e-3), Branch::Open);
    }

    #[test]
    fn return_mapping_stick_closed_form() {
        let h = committed(2e-4, ContactStatus::Stick, -1e6, 0.0);
        let r = return_mapping(&P, &h, -1e-5, 1e-4); // t_N = −1 MPa·m, S = 577 kN/m
        assert_eq!(r.status, ContactStatus::Stick);
        assert_relative_eq!(r.ts, 3e5, max_relative = 1e-14);
        assert_relative_eq!(r.ge, 3e-4, max_relative = 1e-14);
        assert_eq!((r.dtn_dgn, r.dts_dgn, r.dts_dgs), (P.pn, 0.0, P.ps));
        assert_eq!(r.slip, 0.0);
    }

    #[test]
    fn return_mapping_slide_closed_form_both_directions() {
        let h = committed(0.0, ContactStatus::Stick, -1e6, 0.0);
        let s = 1e6 * P.tan_phi;
        for dir in [1.0, -1.0] {
            let r = return_mapping(&P, &h, -1e-5, dir * 1e-3); // trial 1e6 > S
            assert_eq!(r.status, ContactStatus::Slide);
            assert_relative_eq!(r.ts, dir * s, max_relative = 1e-14);
            assert_relative_eq!(r.ge, dir * s / P.ps, max_relative = 1e-14);
            assert_relative_eq!(r.slip, dir * (1e6 - s) / P.ps, max_relative = 1e-12);
            assert_relative_eq!(r.dts_dgn, -dir * P.pn * P.tan_phi, max_relative = 1e-14);
            assert_eq!(r.dts_dgs, 0.0);
            // Additive split: Δg_S = Δg_S^e + Δγ.
            assert_relative_eq!(r.ge - h.ge + r.slip, dir * 1e-3, max_relative = 1e-12);
        }
    }

    #[test]
    fn cohesion_adds_to_strength() {
        let p = FrictionParams { cohesion: 2e5, ..P };
        let h = ShearHistory::default();
        // trial 7e5 < 1e6 tanφ + 2e5 = 777 kN/m: stick (it would slide without cohesion).
        assert_eq!(
            return_mapping(&p, &h, -1e-5, 7e-4).status,
            ContactStatus::Stick
        );
        assert_eq!(
            return_mapping(&P, &h, -1e-5, 7e-4).status,
            ContactStatus::Slide
        );
        let r = return_mapping(&p, &h, -1e-5, 1e-3);
        assert_relative_eq!(r.ts, 1e6 * P.tan_phi + 2e5, max_relative = 1e-14);
        // The consistent tangent does not depend on c.
        assert_relative_eq!(r.dts_dgn, -P.pn * P.tan_phi, max_relative = 1e-14);
        // Conventional slide uses the committed force plus cohesion.
        let hs = committed(0.0, ContactStatus::Slide, -2e6, 1.0);
        assert_relative_eq!(
            conventional(&p, &hs, -3e-5, 1e-4).ts,
            2e6 * P.tan_phi + 2e5,
            max_relative = 1e-14
        );
    }

    #[test]
    fn conventional_branches_closed_form() {
        // Stick: elastic without limit, even far above the strength.
        let h = committed(1e-4, ContactStatus::Stick, -1e6, 0.0);
        let r = conventional(&P, &h, -1e-5, 9e-4);
        assert_eq!(r.status, ContactStatus::Stick);
        assert_relative_eq!(r.ts, 1e6, max_relative = 1e-14);
        assert_eq!((r.dts_dgn, r.dts_dgs), (0.0, P.ps));
        // Slide: the force of the last committed t_N, not the current (larger) one, zero tangent.
        let h = committed(-3e-4, ContactStatus::Slide, -2e6, -1.0);
        let r = conventional(&P, &h, -3e-5, -1e-4);
        assert_eq!(r.status, ContactStatus::Slide);
        assert_relative_eq!(r.ts, -2e6 * P.tan_phi, max_relative = 1e-14);
        assert_eq!((r.dts_dgn, r.dts_dgs), (0.0, 0.0));
        assert_relative_eq!(r.slip, -1e-4 - (r.ge - h.ge), max_relative = 1e-12);
        // Unloading (|t_N| = 1e6 < 2e6): the force is scaled by t_N / t_Nₙ = 0.5.
        let r = conventional(&P, &h, -1e-5, -1e-4);
        assert_relative_eq!(r.ts, -1e6 * P.tan_phi, max_relative = 1e-14);
        assert_relative_eq!(
            r.dts_dgn,
            -2e6 * P.tan_phi * P.pn / -2e6,
            max_relative = 1e-14
        );
        // Reversal within the step: the mode stays frozen (friction force of the step) ...
        let r = conventional(&P, &h, -3e-5, 1e-4);
        assert_eq!(r.status, ContactStatus::Slide);
        assert_relative_eq!(r.ts, -2e6 * P.tan_phi, max_relative = 1e-14);
        // ... and the commit returns the contact to stick for the next step.
        let c = commit_conventional(&P, &h, &r);
        assert_eq!(c.status, ContactStatus::Stick);
        assert_relative_eq!(c.ge, r.ts / P.ps, max_relative = 1e-14);
    }

    #[test]
    fn conventional_commit_switches_to_slide_for_next_step() {
        let h = committed(0.0, ContactStatus::Stick, -1e6, 0.0);
        let r = conventional(&P, &h, -1e-5, 1e-3);
        assert!(r.ts > P.strength(r.tn)); // the overshoot of this step
        let c = commit_conventional(&P, &h, &r);
        assert_eq!(c.status, ContactStatus::Slide);
        assert_eq!(c.slide_sign, 1.0);
        assert_relative_eq!(c.ge, P.strength(r.tn) / P.ps, max_relative = 1e-14);
        assert_eq!(c.tn, r.tn);
        // Return-mapping commit keeps the response state.
        let r = return_mapping(&P, &h, -1e-5, 1e-3);
        let c = commit_return_mapping(&P, &h, &r);
        assert_eq!(
            (c.status, c.ge, c.tn, c.slide_sign),
            (ContactStatus::Slide, r.ge, r.tn, 1.0)
        );
        // Below the strength, both keep sticking.
        for (law, commit) in [
            (
                return_mapping as fn(&_, &_, _, _) -> _,
                commit_return_mapping as fn(&_, &_, &_) -> _,
            ),
            (conventional, commit_conventional),
        ] {
            let r = law(&P, &h, -1e-5, 1e-4);
            let c = commit(&P, &h, &r);
            assert_eq!((c.status, c.ge), (ContactStatus::Stick, 1e-4));
        }
        // Opening resets everything.
        let r = conventional(&P, &h, 1e-6, 1e-3);
        assert_eq!(commit_conventional(&P, &h, &r), ShearHistory::default());
    }

    /// Central finite differences of (t_N, t_S) in (g_N, Δg_S).
    fn check_tangent(
        law: fn(&FrictionParams, &ShearHistory, f64, f64) -> LawResponse,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
    ) {
        let r = law(&P, h, gn, dgs);
        let (eg, es) = (1e-9 * gn.abs(), 1e-9 * dgs.abs().max(1e-6));
        let fd = |f: &dyn Fn(&LawResponse) -> f64| {
            let dn = (f(&law(&P, h, gn + eg, dgs)) - f(&law(&P, h, gn - eg, dgs))) / (2.0 * eg);
            let ds = (f(&law(&P, h, gn, dgs + es)) - f(&law(&P, h, gn, dgs - es))) / (2.0 * es);
            (dn, ds)
        };
        let (a, b) = fd(&|x| x.tn);
        let (c, d) = fd(&|x| x.ts);
        let scale = P.pn.max(P.ps);
        for (fdv, an) in [
            (a, r.dtn_dgn),
            (b, r.dtn_dgs),
            (c, r.dts_dgn),
            (d, r.dts_dgs),
        ] {
            assert!(
                (fdv - an).abs() <= 1e-5 * scale,
                "status {:?}: fd {fdv} vs analytic {an}",
                r.status
            );
        }
    }

    #[test]
    fn tangents_match_central_finite_differences() {
        let stick = committed(1e-4, ContactStatus::Stick, -1e6, 0.0);
        let slide = committed(5e-4, ContactStatus::Slide, -1.2e6, 1.0);
        for law in [return_mapping as fn(&_, &_, _, _) -> _, conventional] {
            for h in [&stick, &slide] {
                for (gn, dgs) in [
                    (-1e-5, 1e-4),
                    (-1e-5, 2e-3),
                    (-1e-5, -2e-3),
                    (-3e-6, 5e-4),
                    (2e-6, 1e-4),
                ] {
                    check_tangent(law, h, gn, dgs);
                }
            }
        }
        // The slide branch of return mapping really is unsymmetric.
        let r = return_mapping(&P, &stick, -1e-5, 2e-3);
        assert_eq!(r.status, ContactStatus::Slide);
        assert!(r.dts_dgn != r.dtn_dgs);
    }
}
