//! Friction laws behind one interface: [`FrictionLaw`].
//!
//! A law owns, for one contact,
//! * its **initial state** ([`FrictionLaw::initial_history`]: e.g. DDA's lock of the contacts
//!   that touch at the start of the analysis),
//! * its **response** at a Newton iterate, on its own branch or on a branch the iteration asks
//!   for ([`FrictionLaw::on_branch`]: the affine piece, forces and tangent),
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
//! iteration.
//!
//! Adding a law (dilatancy, softening) means one implementation of this trait; the contact
//! set, the Newton iteration and the outputs do not change. The history type is shared
//! ([`ShearHistory`]); `slip` accumulates the plastic slip for laws that need it.

use super::friction::{self, ContactStatus, FrictionParams, LawResponse, ShearHistory};
use crate::model::FrictionAlgorithm;

/// One affine piece of a contact law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Branch {
    /// No force.
    #[default]
    Open,
    /// Closed, elastic shear spring.
    Stick,
    /// Closed, shear force on the Coulomb limit, sliding in the direction of the sign (±1).
    Slide(i8),
}

impl Branch {
    pub fn status(self) -> ContactStatus {
        match self {
            Branch::Open => ContactStatus::Open,
            Branch::Stick => ContactStatus::Stick,
            Branch::Slide(_) => ContactStatus::Slide,
        }
    }
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

/// A friction law (see the module docs).
pub trait FrictionLaw: Send + Sync {
    /// The name used in the model file (`[analysis] friction`).
    fn name(&self) -> &'static str;

    /// History of a contact first detected at the start of the analysis, touching
    /// (`touching`: gap within the touching tolerance) or not.
    fn initial_history(&self, touching: bool) -> ShearHistory {
        let _ = touching;
        ShearHistory::default()
    }

    /// The law's own branch at (g_N, Δg_S).
    fn branch(&self, p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> Branch;

    /// Response of the affine piece `branch` at (g_N, Δg_S), also outside the region where
    /// the law is on that branch.
    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse;

    /// The law's response (on its own branch).
    fn response(&self, p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> LawResponse {
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
        h: &ShearHistory,
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

    /// The history kept once the step has converged with response `r`.
    fn commit(&self, p: &FrictionParams, h: &ShearHistory, r: &LawResponse) -> ShearHistory;
}

/// Implicit return mapping with the consistent tangent ([`friction::return_mapping`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct ReturnMapping;

/// The conventional open–close rule ([`friction::conventional`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct Conventional;

/// The law selected in the model.
pub fn law_for(alg: FrictionAlgorithm) -> &'static dyn FrictionLaw {
    match alg {
        FrictionAlgorithm::ReturnMapping => &ReturnMapping,
        FrictionAlgorithm::Conventional => &Conventional,
    }
}

fn branch_of(r: &LawResponse) -> Branch {
    match r.status {
        ContactStatus::Open => Branch::Open,
        ContactStatus::Stick => Branch::Stick,
        ContactStatus::Slide => Branch::Slide(if r.ts < 0.0 { -1 } else { 1 }),
    }
}

impl FrictionLaw for ReturnMapping {
    fn name(&self) -> &'static str {
        "return-mapping"
    }

    fn branch(&self, p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> Branch {
        branch_of(&friction::return_mapping(p, h, gn, dgs))
    }

    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse {
        let tn = p.closed_normal(gn);
        match branch {
            Branch::Open => friction::open_response(),
            Branch::Stick => friction::stick_response(p, h, gn, dgs),
            Branch::Slide(s) => {
                let s = f64::from(s);
                // t_S = s (−tan φ p_N g_N + c): the affine continuation of s·S(t_N)
                friction::slide(p, h, tn, dgs, s, s * (-p.tan_phi * tn + p.cohesion))
            }
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
    fn iteration_branch(
        &self,
        p: &FrictionParams,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
        ctx: IterationContext,
    ) -> Branch {
        let own = self.branch(p, h, gn, dgs);
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

    fn commit(&self, p: &FrictionParams, h: &ShearHistory, r: &LawResponse) -> ShearHistory {
        friction::commit(FrictionAlgorithm::ReturnMapping, p, h, r)
    }
}

impl FrictionLaw for Conventional {
    fn name(&self) -> &'static str {
        "conventional"
    }

    /// Contacts touching at the start of the analysis are locked: an elastic shear spring
    /// from there on (DDA's initial contacts). A contact that comes to touch later keeps its
    /// open history and is limited by Coulomb while it closes (see [`friction`]).
    fn initial_history(&self, touching: bool) -> ShearHistory {
        if touching {
            ShearHistory {
                status: ContactStatus::Stick,
                ..ShearHistory::default()
            }
        } else {
            ShearHistory::default()
        }
    }

    fn branch(&self, p: &FrictionParams, h: &ShearHistory, gn: f64, dgs: f64) -> Branch {
        branch_of(&friction::conventional(p, h, gn, dgs))
    }

    /// The mode of a closed contact is frozen within the step (it is the committed one):
    /// only open and closed are branches the iteration may hold.
    fn on_branch(
        &self,
        p: &FrictionParams,
        h: &ShearHistory,
        gn: f64,
        dgs: f64,
        branch: Branch,
    ) -> LawResponse {
        match branch {
            Branch::Open => friction::open_response(),
            _ if p.is_closed(gn) => friction::conventional(p, h, gn, dgs),
            // held closed at a gap (the predictor): the elastic stick spring
            _ => friction::stick_response(p, h, gn, dgs),
        }
    }

    fn commit(&self, p: &FrictionParams, h: &ShearHistory, r: &LawResponse) -> ShearHistory {
        friction::commit(FrictionAlgorithm::Conventional, p, h, r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: FrictionParams = FrictionParams {
        pn: 1.0e11,
        ps: 1.0e9,
        tan_phi: 0.577_350_269_189_625_8,
        cohesion: 1.0e3,
        dashpot: 0.0,
        gn0: 0.0,
    };

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
            for (gn, dgs) in [
                (1e-6, 0.0),
                (-1e-5, 1e-4),
                (-1e-5, 3e-3),
                (-1e-5, -3e-3),
                (-2e-6, 4e-4),
            ] {
                let a = ReturnMapping.response(&P, h, gn, dgs);
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
                    Conventional.response(&P, h, gn, dgs),
                    friction::conventional(&P, h, gn, dgs)
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
        };
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
        let h = ShearHistory::default();
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
        // the conventional rule keeps its frozen mode
        let hs = Conventional.initial_history(true);
        assert_eq!(hs.status, ContactStatus::Stick);
        assert_eq!(Conventional.initial_history(false), ShearHistory::default());
        assert_eq!(ReturnMapping.initial_history(true), ShearHistory::default());
    }
}
