//! Contact laws behind one interface, [`FrictionLaw`], and the one registry of their names,
//! [`LAWS`].
//!
//! A law owns, for one contact,
//! * its **selection** ([`FrictionLaw::selection`]): named by `[analysis] friction` (and
//!   `--friction`), or chosen by an `[[interface]]` that sets one of the law's own keys;
//! * its **constants** ([`FrictionLaw::interface_values`]: the law's own `[[interface]]`
//!   keys, checked and defaulted when the model is read; [`FrictionLaw::own_constants`]:
//!   their share for one contact, kept in [`FrictionParams::own`] beside the springs and the
//!   Coulomb strength every interface has);
//! * its **state** ([`LawState`]: words only the law reads; [`FrictionLaw::new_state`]: the
//!   state of a contact first detected, e.g. DDA's lock of the contacts that touch at the
//!   start of the analysis; [`FrictionLaw::lasting`]: a state kept while the contact is open
//!   or out of sight, e.g. a broken bond; checkpoints keep the words bit for bit);
//! * its **response** at a Newton iterate, on its own branch or on a branch the iteration
//!   asks for ([`FrictionLaw::on_branch`]: the affine piece, forces and tangent),
//! * the **branch** an iteration linearises on ([`FrictionLaw::iteration_branch`]: the
//!   semi-smooth Newton rules; the closed-contact predictor of the first iterate),
//! * its **commit** at the end of a converged step ([`FrictionLaw::commit`]).
//!
//! The laws are piecewise affine in (g_N, Δg_S): each [`Branch`] is one affine piece. With
//! the contact kinematics linear in the step's increment Δu, the step's residual is then
//! piecewise affine in Δu, and Newton's method is an active-set method: the iterate solves
//! the affine system of the branches chosen at the previous iterate exactly. A law's
//! [`FrictionLaw::on_branch`] returns the affine continuation of a branch also where the law
//! itself is on another branch, so that the iteration can hold a branch (e.g. stick) for one
//! iteration. Within a step a law is continuous in (g_N, Δg_S) (a jump, such as a bond that
//! breaks, is decided by [`FrictionLaw::commit`] between steps), so that the active-set
//! iteration has a solution to find.
//!
//! # The laws
//! | name | file | selected by |
//! |---|---|---|
//! | `"return-mapping"` | [`super::friction`] ([`super::friction::ReturnMapping`]) | `[analysis] friction` (the default) |
//! | `"conventional"` | [`super::friction`] ([`super::friction::Conventional`]) | `[analysis] friction` |
//! | `"bonded"` | [`super::bonded`] ([`super::bonded::Bonded`]) | `[[interface]] tensile_strength` or `residual_friction_angle` |
//!
//! # Adding a law
//! 1. One file in `contact/` (declared in `contact/mod.rs`): the law as a pure function
//!    (forces, tangent, new state) with its module docs (equations, sign conventions), and
//!    its implementation of [`FrictionLaw`]: its name, how it is selected, its own interface
//!    keys (numbers) with their checks and defaults, its state in [`LawState`]'s words.
//! 2. Its line in [`LAWS`].
//!
//! Nothing else changes: the model reader takes the names a `friction` may have and the
//! `[[interface]]` keys from [`LAWS`] (and reports a law's own errors at the key's line),
//! `--friction` and `nmm check` print registry names, the contact set calls the law of each
//! contact through this trait, and checkpoints save each contact's law by name and its state
//! words.

use super::friction::{FrictionParams, LawResponse};

/// One affine piece of a contact law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Branch {
    /// No force.
    #[default]
    Open,
    /// Closed, elastic shear spring.
    Stick,
    /// Closed, shear force on the strength limit, sliding in the direction of the sign (±1).
    Slide(i8),
    /// Another piece on a strength limit, numbered by its law (e.g. the bonded law's
    /// tension cut-off and its corner with the shear limit), with a direction (±1, or 0).
    /// Counted with the sliding contacts.
    Limit(u8, i8),
}

/// What a Newton iteration tells the law about a contact when it asks for its branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationContext {
    /// The branch used for this contact at the previous iterate of the step (`None` at the
    /// first iterate).
    pub previous: Option<Branch>,
    /// The contact touched at the start of the step (normal gap within the touching
    /// tolerance).
    pub touching: bool,
}

/// The committed state of one contact under its law: words whose meaning only the law
/// knows (numbers as their bits, so that a checkpoint keeps them exactly). A law that needs
/// more words than [`LawState::WORDS`] raises the constant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct LawState(pub [u64; LawState::WORDS]);

impl LawState {
    /// Words of every law's state.
    pub const WORDS: usize = 5;
}

/// How a model selects a law.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Selection {
    /// Named by `[analysis] friction` (or a stage's, or `--friction`): the law of every
    /// interface that does not select a law of its own.
    Analysis,
    /// Chosen by every `[[interface]]` that sets any of these keys (numbers, read by
    /// [`FrictionLaw::interface_values`]), whatever `friction` says.
    Interface(&'static [&'static str]),
}

/// A contact law (see the module docs).
pub trait FrictionLaw: Send + Sync {
    /// Its name in the registry (`[analysis] friction`, `--friction`, checkpoints).
    fn name(&self) -> &'static str;

    /// How a model selects it.
    fn selection(&self) -> Selection;

    /// The law's own `[[interface]]` values from the numbers given for its keys (`given[i]`
    /// for the i-th key of [`Selection::Interface`], `None` when absent): checked and
    /// defaulted. The interface's `friction_angle` (degrees) and `cohesion` (Pa) are given
    /// for checks against them. An error names the key by its index.
    fn interface_values(
        &self,
        friction_angle: f64,
        cohesion: f64,
        given: &[Option<f64>],
    ) -> Result<Vec<f64>, (usize, String)> {
        let _ = (friction_angle, cohesion);
        Ok(given.iter().map(|g| g.unwrap_or(0.0)).collect())
    }

    /// A one-line warning about valid interface values that are likely to mislead (see
    /// `model/warnings.rs`), if any.
    fn interface_warning(
        &self,
        friction_angle: f64,
        cohesion: f64,
        values: &[f64],
    ) -> Option<String> {
        let _ = (friction_angle, cohesion, values);
        None
    }

    /// The contact's own constants ([`FrictionParams::own`]) for an interface with the
    /// values of [`FrictionLaw::interface_values`], the contact standing for `weight` m of
    /// the interface (per-length strengths become forces × `weight`, as the cohesion).
    fn own_constants(&self, values: &[f64], weight: f64) -> [f64; 4] {
        let _ = (values, weight);
        [0.0; 4]
    }

    /// The state of a contact first detected: at the start of the analysis (`at_start`) or
    /// later, touching (`touching`: gap within the touching tolerance) or not.
    fn new_state(&self, touching: bool, at_start: bool) -> LawState {
        let _ = (touching, at_start);
        LawState::default()
    }

    /// The law's own branch at (g_N, Δg_S).
    fn branch(&self, p: &FrictionParams, h: &LawState, gn: f64, dgs: f64) -> Branch;

    /// Response of the affine piece `branch` at (g_N, Δg_S), also outside the region where
    /// the law is on that branch.
    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse;

    /// The law's response (on its own branch).
    fn response(&self, p: &FrictionParams, h: &LawState, gn: f64, dgs: f64) -> LawResponse {
        self.on_branch(p, h, gn, dgs, self.branch(p, h, gn, dgs))
    }

    /// The branch a Newton iteration linearises on at (g_N, Δg_S). Default: the law's own
    /// branch, except at the first iterate of a step, where a contact that touched at the
    /// start of the step is held closed and stuck (the closed-contact predictor: the law's
    /// tangent at g_N = 0⁺ is zero, and the first direction of a wall whose blocks just
    /// touch would otherwise be a free fall that drives every joint deep into the penalty
    /// springs; DDA likewise starts its open–close iteration with touching contacts locked).
    fn iteration_branch(
        &self,
        p: &FrictionParams,
        h: &LawState,
        gn: f64,
        dgs: f64,
        ctx: IterationContext,
    ) -> Branch {
        let own = self.branch(p, h, gn, dgs);
        if ctx.previous.is_none() && ctx.touching && own == Branch::Open {
            return Branch::Stick;
        }
        own
    }

    /// The state kept once the step has converged with response `r`.
    fn commit(&self, p: &FrictionParams, h: &LawState, r: &LawResponse) -> LawState;

    /// Whether the committed state `h` must be kept while its contact is open or not
    /// detected (irreversible damage: a broken bond). Default: no, an open contact starts
    /// afresh.
    fn lasting(&self, h: &LawState) -> bool {
        let _ = h;
        false
    }

    /// The normal spring force and the shear force the contact holds at the step's start,
    /// at the gap g_N⁰ = `gn0` (the energy bookkeeping of the step).
    fn start_forces(&self, p: &FrictionParams, h: &LawState, gn0: f64) -> (f64, f64);

    /// Whether the contact is bonded (`Some(true)`), was bonded and broke (`Some(false)`),
    /// or the law has no bond (`None`).
    fn bond(&self, h: &LawState) -> Option<bool> {
        let _ = h;
        None
    }

    /// Whether the law has bonds ([`FrictionLaw::bond`] is `Some`): outputs add the bond
    /// state of the contacts when a model uses such a law.
    fn has_bonds(&self) -> bool {
        false
    }

    /// Whether `h` is a state this law can write (a checkpoint's states are checked).
    fn valid_state(&self, h: &LawState) -> bool;
}

/// Every law, in a fixed order (a [`LawId`] is an index): the one registry. Adding a law
/// is one line here (see the module docs).
pub static LAWS: &[&dyn FrictionLaw] = &[
    &super::friction::ReturnMapping,
    &super::friction::Conventional,
    &super::bonded::Bonded,
];

/// The first kink of a law along a line: the smallest α in (`from`, `to`] at which its own
/// branch at (g_N + α d_N, Δg_S + α d_S) differs from its branch at α = `from`, found by
/// bisection to 2⁻⁴⁰ of the interval and returned just past the kink (on the new branch);
/// `None` if the branch at `to` is the one at `from` (a line that leaves a branch and
/// comes back to it within the interval is not seen). Every law's branches are regions of
/// (g_N, Δg_S) that a line crosses at most a few times, and only the law's own
/// [`FrictionLaw::branch`] is asked, so this serves every law of the registry.
#[allow(clippy::too_many_arguments)]
pub fn first_kink(
    law: &dyn FrictionLaw,
    p: &FrictionParams,
    h: &LawState,
    (gn, dgs): (f64, f64),
    (dn, ds): (f64, f64),
    from: f64,
    to: f64,
) -> Option<f64> {
    let at = |a: f64| law.branch(p, h, gn + a * dn, dgs + a * ds);
    let b0 = at(from);
    if to <= from || at(to) == b0 {
        return None;
    }
    let (mut lo, mut hi) = (from, to);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if at(mid) == b0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(hi)
}

/// A law of the registry: its index in [`LAWS`]. Prints as its name.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LawId(u8);

impl LawId {
    /// Every law of the registry, in order.
    pub fn all() -> impl Iterator<Item = LawId> {
        (0..LAWS.len()).map(|i| LawId(i as u8))
    }

    /// The law named `name`.
    pub fn by_name(name: &str) -> Option<LawId> {
        LawId::all().find(|l| l.name() == name)
    }

    /// The law named `name` if `[analysis] friction` may name it.
    pub fn for_analysis(name: &str) -> Option<LawId> {
        LawId::by_name(name).filter(|l| l.law().selection() == Selection::Analysis)
    }

    /// The names `[analysis] friction` may take, in registry order.
    pub fn analysis_names() -> Vec<&'static str> {
        LawId::all()
            .filter(|l| l.law().selection() == Selection::Analysis)
            .map(LawId::name)
            .collect()
    }

    /// The `[[interface]]` keys of the laws an interface selects, in registry order.
    pub fn interface_keys() -> Vec<&'static str> {
        LawId::all()
            .flat_map(|l| l.keys().iter().copied())
            .collect()
    }

    /// The laws whose own keys an interface sets (`has(key)`), in registry order.
    pub fn for_interface(has: impl Fn(&str) -> bool) -> Vec<LawId> {
        LawId::all()
            .filter(|l| l.keys().iter().any(|k| has(k)))
            .collect()
    }

    /// The law's own `[[interface]]` keys (empty for a law of `[analysis] friction`).
    pub fn keys(self) -> &'static [&'static str] {
        match self.law().selection() {
            Selection::Analysis => &[],
            Selection::Interface(keys) => keys,
        }
    }

    pub fn name(self) -> &'static str {
        self.law().name()
    }

    #[inline]
    pub fn law(self) -> &'static dyn FrictionLaw {
        LAWS[usize::from(self.0)]
    }
}

/// Implicit return mapping: the default `[analysis] friction`.
impl Default for LawId {
    fn default() -> Self {
        LawId(0)
    }
}

impl std::fmt::Debug for LawId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::friction::{
        self, commit_return_mapping, ContactStatus, Conventional, ReturnMapping, ShearHistory,
    };

    const P: FrictionParams = FrictionParams {
        pn: 1.0e11,
        ps: 1.0e9,
        tan_phi: 0.577_350_269_189_625_8,
        cohesion: 1.0e3,
        dashpot: 0.0,
        gn0: 0.0,
        own: [0.0; 4],
    };

    #[test]
    fn the_registry_names_each_law_once() {
        let names: Vec<&str> = LawId::all().map(LawId::name).collect();
        assert_eq!(names, ["return-mapping", "conventional", "bonded"]);
        assert_eq!(LawId::default().name(), "return-mapping");
        assert_eq!(LawId::analysis_names(), ["return-mapping", "conventional"]);
        assert_eq!(
            LawId::interface_keys(),
            ["tensile_strength", "residual_friction_angle"]
        );
        assert_eq!(LawId::for_analysis("bonded"), None);
        assert_eq!(LawId::by_name("bonded").map(LawId::name), Some("bonded"));
        assert_eq!(
            LawId::for_interface(|k| k == "residual_friction_angle"),
            [LawId::by_name("bonded").unwrap()]
        );
        assert!(LawId::for_interface(|k| k == "cohesion").is_empty());
        assert_eq!(format!("{:?}", LawId::default()), "return-mapping");
    }

    #[test]
    fn shear_histories_round_trip_through_their_state() {
        let hs = [
            ShearHistory::default(),
            ShearHistory {
                ge: -0.0,
                status: ContactStatus::Slide,
                tn: -1.25e6,
                slide_sign: -1.0,
            },
            ShearHistory {
                ge: 3e-7,
                status: ContactStatus::Stick,
                tn: -2.0,
                slide_sign: 0.0,
            },
        ];
        for h in hs {
            let s = h.to_state();
            let back = ShearHistory::from_state(&s);
            assert_eq!(back.ge.to_bits(), h.ge.to_bits());
            assert_eq!(back, h);
            assert!(ReturnMapping.valid_state(&s) && Conventional.valid_state(&s));
        }
        assert_eq!(ShearHistory::default().to_state(), LawState::default());
        let mut bad = ShearHistory::default().to_state();
        bad.0[1] = 7;
        assert!(!ReturnMapping.valid_state(&bad));
    }

    /// On its own branch, `on_branch` is the law's pure function.
    #[test]
    fn own_branch_response_is_the_pure_law() {
        let hs = [
            ShearHistory::default(),
            ShearHistory {
                ge: 2e-4,
                status: ContactStatus::Stick,
                tn: -1e6,
                slide_sign: 0.0,
            },
            ShearHistory {
                ge: -5e-4,
                status: ContactStatus::Slide,
                tn: -1.2e6,
                slide_sign: -1.0,
            },
        ];
        for h in &hs {
            let s = h.to_state();
            for (gn, dgs) in [
                (1e-6, 0.0),
                (-1e-5, 1e-4),
                (-1e-5, 3e-3),
                (-1e-5, -3e-3),
                (-2e-6, 4e-4),
            ] {
                let a = ReturnMapping.response(&P, &s, gn, dgs);
                let b = friction::return_mapping(&P, h, gn, dgs);
                assert_eq!(a.status, b.status);
                for (x, y) in [
                    (a.tn, b.tn),
                    (a.ts, b.ts),
                    (a.dts_dgn, b.dts_dgn),
                    (a.dts_dgs, b.dts_dgs),
                    (a.ge, b.ge),
                    (a.slip, b.slip),
                ] {
                    assert!((x - y).abs() <= 1e-12 * (1.0 + y.abs()), "{x} {y}");
                }
                assert_eq!(
                    Conventional.response(&P, &s, gn, dgs),
                    friction::conventional(&P, h, gn, dgs)
                );
                // the commit through the state is the pure commit
                assert_eq!(
                    ShearHistory::from_state(&ReturnMapping.commit(&P, &s, &a)),
                    commit_return_mapping(&P, h, &a)
                );
            }
        }
    }

    /// Each branch is affine: its tangent is the exact derivative of its forces anywhere.
    #[test]
    fn branches_are_affine_with_their_tangent() {
        let h = ShearHistory {
            ge: 1e-4,
            status: ContactStatus::Stick,
            tn: -1e6,
            slide_sign: 0.0,
        }
        .to_state();
        for b in [Branch::Stick, Branch::Slide(1), Branch::Slide(-1)] {
            let (gn, dgs) = (-3e-6, 2e-4);
            let r = ReturnMapping.on_branch(&P, &h, gn, dgs, b);
            for (dn, ds) in [(1e-7, 0.0), (0.0, 1e-5), (-2e-7, 3e-5), (5e-6, -1e-4)] {
                let q = ReturnMapping.on_branch(&P, &h, gn + dn, dgs + ds, b);
                let tn = r.tn + r.dtn_dgn * dn + r.dtn_dgs * ds;
                let ts = r.ts + r.dts_dgn * dn + r.dts_dgs * ds;
                assert!((q.tn - tn).abs() <= 1e-9 * tn.abs().max(1.0));
                assert!((q.ts - ts).abs() <= 1e-9 * ts.abs().max(1.0), "{b:?}");
            }
        }
    }

    #[test]
    fn semi_smooth_rules() {
        let h = LawState::default();
        let ctx = |previous, touching| IterationContext { previous, touching };
        // the predictor holds a touching open contact closed at the first iterate only
        assert_eq!(
            ReturnMapping.iteration_branch(&P, &h, 1e-12, 0.0, ctx(None, true)),
            Branch::Stick
        );
        assert_eq!(
            ReturnMapping.iteration_branch(&P, &h, 1e-12, 0.0, ctx(None, false)),
            Branch::Open
        );
        assert_eq!(
            ReturnMapping.iteration_branch(&P, &h, 1e-12, 0.0, ctx(Some(Branch::Stick), true)),
            Branch::Open
        );
        // a reversing slide is held in stick for one iterate
        let slide_neg = (-1e-5, -1e-2);
        assert_eq!(
            ReturnMapping.branch(&P, &h, slide_neg.0, slide_neg.1),
            Branch::Slide(-1)
        );
        assert_eq!(
            ReturnMapping.iteration_branch(
                &P,
                &h,
                slide_neg.0,
                slide_neg.1,
                ctx(Some(Branch::Slide(1)), true)
            ),
            Branch::Stick
        );
        assert_eq!(
            ReturnMapping.iteration_branch(
                &P,
                &h,
                slide_neg.0,
                slide_neg.1,
                ctx(Some(Branch::Slide(-1)), true)
            ),
            Branch::Slide(-1)
        );
        // the conventional rule locks the contacts touching at the start only
        let hs = ShearHistory::from_state(&Conventional.new_state(true, true));
        assert_eq!(hs.status, ContactStatus::Stick);
        assert_eq!(Conventional.new_state(false, true), LawState::default());
        assert_eq!(Conventional.new_state(true, false), LawState::default());
        assert_eq!(ReturnMapping.new_state(true, true), LawState::default());
    }
}
