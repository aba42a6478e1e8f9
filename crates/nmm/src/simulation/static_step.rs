//! The static strategy of a step (`mode = "static"`): the equilibrium under the loads of
//! t_{n+1}, by one linear solve when nothing is in contact, by Newton with continuation in
//! its tangent, by pseudo-transient continuation with inner Newton solves, and, where no
//! equilibrium exists (a mechanism), by DDA's quasi-static step of limited motion.

use super::{Rhs, Simulation, MAX_REJECTIONS};
use crate::solver::{NewtonReport, Regularisation};

/// Outer iterations of the static continuation ([`Simulation::static_continuation`]).
pub const STATIC_OUTER_ITERATIONS: usize = 40;

/// Largest motion of a static step that found no equilibrium, as a fraction of the cover
/// size h (DDA's step-by-step development of a mechanism).
pub const STATIC_MAX_MOTION: f64 = 0.1;

impl Simulation {
    /// The static strategy of a step attempt: the equilibrium under the loads of t_{n+1}
    /// from Δu = 0 (in `du`), and whether it was reached. Without contacts the problem is
    /// linear (one solve); otherwise Newton with continuation in its tangent, then the
    /// continuation with inner solves ([`Simulation::static_continuation`]); where no
    /// equilibrium exists (a mechanism), DDA's quasi-static step with Δt shortened until no
    /// point moves more than [`STATIC_MAX_MOTION`] × h.
    pub(super) fn static_step(
        &mut self,
        rhs: &Rhs,
        cm: f64,
        du: &mut [f64],
    ) -> (NewtonReport, bool) {
        let n = du.len();
        let sigma0 = cm.max(self.static_regularisation());
        // Without contacts the problem is linear: one solve of K Δu = F is the
        // equilibrium (if K holds every block). Otherwise, and when that fails (a block
        // that nothing holds), Newton with continuation in its tangent first, from DDA's
        // inertia of Δt (cheap when it works), then the continuation with inner solves
        // from at least the model's regularisation (robust), then no equilibrium.
        let mut rep = NewtonReport::default();
        if self.contacts.contacts.is_empty() {
            rep = self.solve(
                rhs,
                0.0,
                None,
                Regularisation::None { fallback: cm },
                0,
                None,
                false,
                du,
            );
            if !rep.converged {
                du.iter_mut().for_each(|x| *x = 0.0);
            }
        }
        if !rep.converged {
            let spent = rep.iterations;
            rep = self.solve(
                rhs,
                0.0,
                None,
                Regularisation::Continuation {
                    initial: cm,
                    floor: 1e-6 * cm,
                },
                1,
                None,
                false,
                du,
            );
            rep.iterations += spent;
        }
        let mut reached = rep.converged;
        if !reached && rep.error.is_none() {
            du.iter_mut().for_each(|x| *x = 0.0);
            let spent = rep.iterations;
            let (r, ok) = self.static_continuation(rhs, sigma0, du);
            rep = r;
            rep.iterations += spent;
            reached = ok;
        }
        if reached || matches!(rep.error, Some(crate::solver::SolveError::OutOfMemory)) {
            (rep, true)
        } else {
            // No equilibrium: DDA's quasi-static step from where the continuation
            // stopped (the parts that have an equilibrium are in it there; only the
            // mechanism's modes carry a residual): the inertia of Δt, anchored at that
            // point, moves the mechanism and leaves the rest; Δt is shortened (the
            // inertia raised) until no point moves more than STATIC_MAX_MOTION × h.
            let limit = STATIC_MAX_MOTION * self.model.cover_size;
            // the anchor only where it is itself within the limit (a continuation that
            // wandered off is no point to start a limited step from)
            let anchor = if self.largest_motion(du) <= limit {
                du.to_vec()
            } else {
                vec![0.0; n]
            };
            let mut c = cm;
            let mut limited = false;
            let mut spent = rep.iterations;
            let mut last = rep;
            for _ in 0..12 {
                du.copy_from_slice(&anchor);
                let mut r = self.solve(
                    rhs,
                    0.0,
                    Some((&anchor, c)),
                    Regularisation::None { fallback: c },
                    MAX_REJECTIONS,
                    None,
                    false,
                    du,
                );
                spent += r.iterations;
                r.iterations = spent;
                if !r.converged {
                    last = r;
                    if last.error.is_some() {
                        break;
                    }
                    c *= 10.0;
                    continue;
                }
                // the motion of the step, from its start
                let motion = self.largest_motion(du);
                last = r;
                if motion <= limit {
                    limited = true;
                    break;
                }
                c *= (1.2 * motion / limit).max(2.0);
            }
            if !limited && last.converged {
                // no inertia held the step within the limit: a shorter step
                last.converged = false;
                last.residuals.push(f64::NAN);
            }
            (last, false)
        }
    }

    /// The true residual norm of the static problem (L = K + P) at `du` and its physical
    /// force scale.
    pub(super) fn static_merit(&mut self, rhs: &Rhs, du: &[f64]) -> (f64, f64) {
        self.with_system(rhs, 0.0, None, |sys, _| {
            let mut r = vec![0.0; du.len()];
            crate::solver::PiecewiseSystem::residual(sys, du, &mut r);
            (
                r.iter().map(|v| v * v).sum::<f64>().sqrt(),
                crate::solver::PiecewiseSystem::force_scale(sys),
            )
        })
    }

    /// A static step by pseudo-transient continuation with inner Newton solves: from
    /// Δu₀ = 0, each outer iteration k solves the regularised problem
    /// R(Δu) − σ_k M (Δu − Δu_k) = 0 (a quasi-static step of DDA's kind with the inertia of
    /// σ_k, well conditioned whatever the contacts do), then lowers σ with the static
    /// residual (σ_{k+1} = σ_k ‖R(Δu_{k+1})‖/‖R(Δu_k)‖, switched evolution relaxation) until
    /// the static residual ‖R‖ is below the tolerance: the point reached is the static
    /// equilibrium. Each inner solve after a converged one starts from the contacts'
    /// branches that solve ended on (a warm start, [`crate::solver::NewtonOptions`]): the
    /// problems differ only in σ and the anchor, and their active sets little. Measured
    /// (`examples/shaken_slope.toml`, its settle's first step: gravity on 61 blocks at rest):
    /// the inner solves took 20, 9, 9, 7, 5, 5 linear solves choosing afresh, each first
    /// direction from the fresh choice raising the residual by 10⁴–10⁸ and returned from by
    /// the watchdog; 20, 4, 4, 2, 1, 1 warm; the step 61 → 38 solves, the stage 71 → 48.
    /// Returns the report (iterations summed over the inner solves) and
    /// whether the equilibrium was reached; it is not when the residual stops falling (a
    /// mechanism: no equilibrium exists) or the outer iterations run out.
    fn static_continuation(
        &mut self,
        rhs: &Rhs,
        sigma0: f64,
        du: &mut [f64],
    ) -> (NewtonReport, bool) {
        let tolerance = self.model.analysis.tolerance;
        let mut sigma = sigma0;
        let floor = 1e-8 * sigma0;
        let mut anchor = du.to_vec();
        let (mut merit, _) = self.static_merit(rhs, du);
        let mut total = NewtonReport::default();
        let mut stalled = 0;
        // the contacts' branches are those the last inner solve converged on
        let mut warm = false;
        for _ in 0..STATIC_OUTER_ITERATIONS {
            // the inner problem only needs to be solved well below the static residual
            let (_, scale) = self.static_merit(rhs, du);
            let inner = (0.01 * merit / scale.max(f64::MIN_POSITIVE)).clamp(tolerance, 1e-4);
            let mut rep = self.solve(
                rhs,
                0.0,
                Some((&anchor, sigma)),
                Regularisation::None { fallback: sigma },
                MAX_REJECTIONS,
                Some(inner),
                warm,
                du,
            );
            total.iterations += rep.iterations;
            total.active_set_changes += rep.active_set_changes;
            total.linear += rep.linear;
            total.residuals.append(&mut rep.residuals);
            total.error = rep.error.clone();
            if rep.error.is_some() {
                return (total, false);
            }
            warm = rep.converged;
            if !rep.converged {
                // the inner problem needs more inertia: from the last anchor
                du.copy_from_slice(&anchor);
                sigma *= 10.0;
                stalled += 1;
                if stalled > 3 {
                    break;
                }
                continue;
            }
            let (m, scale) = self.static_merit(rhs, du);
            if m <= tolerance * scale {
                total.converged = true;
                total.residuals.push(m);
                return (total, true);
            }
            if m < 0.9 * merit {
                stalled = 0;
            } else {
                stalled += 1;
                if stalled > 2 {
                    break;
                }
            }
            sigma = (sigma * (m / merit).min(1.0)).max(floor);
            merit = merit.min(m);
            anchor.copy_from_slice(du);
        }
        (total, false)
    }

    /// The regularisation coefficient of static steps (on the mass matrix, 1/s²): 1% of
    /// the largest contact stiffness per vertex (p_N) over the mass of a cover of the
    /// lightest material (ρ h²), so that a cover held only by the regularisation (its
    /// contacts all open or sliding) moves about 100 × its unbalanced force / p_N per
    /// iteration. Without contacts, 1% of the largest E over ρ h² (the elastic scale).
    fn static_regularisation(&self) -> f64 {
        let h = self.model.cover_size;
        let rho = self
            .model
            .materials
            .iter()
            .map(|m| m.density)
            .fold(f64::INFINITY, f64::min);
        let stiffness = self
            .model
            .interfaces
            .iter()
            .map(|i| i.normal_penalty)
            .fold(0.0, f64::max)
            .max(
                self.model
                    .materials
                    .iter()
                    .map(|m| m.young)
                    .fold(0.0, f64::max),
            );
        0.01 * stiffness / (rho * h * h)
    }
}
