//! Newton-Raphson on a nonlinear system R(x) = 0.
//!
//! Convention: the system returns the out-of-balance force R(x) = F − f(x) and
//! the tangent J = ∂f/∂x (for sliding contacts with the consistent friction
//! tangent, J is unsymmetric). Each iteration solves J δ = R and sets x ← x + δ.
//!
//! Convergence (as in deal.II step-42): ‖R‖ ≤ tol · ‖F_ref‖ and either the
//! increment is small (‖δ‖ ≤ tol · ‖x‖) or the system's active set (contact
//! states) did not change in the last iteration. The iteration count is the
//! number of linear solves.

use super::linear::{AutoSolver, LinearSolver, SolveError};
use super::sparse::SparseMatrix;
use std::time::{Duration, Instant};

/// Per-stage wall-clock times, summed over iterations and steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimes {
    pub assembly: Duration,
    pub contact: Duration,
    pub factorisation: Duration,
    pub solve: Duration,
}

impl std::ops::AddAssign for StageTimes {
    fn add_assign(&mut self, o: StageTimes) {
        self.assembly += o.assembly;
        self.contact += o.contact;
        self.factorisation += o.factorisation;
        self.solve += o.solve;
    }
}

pub trait NonlinearSystem {
    /// Evaluate R(x) into `r` and the tangent into `j` (whose pattern the system
    /// owns). Returns whether `j` is symmetric. Contact work may be timed into `times.contact`.
    fn evaluate(
        &mut self,
        x: &[f64],
        r: &mut [f64],
        j: &mut SparseMatrix,
        times: &mut StageTimes,
    ) -> bool;
    /// Scale of the forces for the relative residual test.
    fn reference_norm(&self) -> f64;
    /// Whether the active set (e.g. stick/slide/open states) changed during the last `evaluate`.
    fn active_set_changed(&self) -> bool;
}

#[derive(Debug, Clone, Copy)]
pub struct NewtonOptions {
    pub max_iterations: usize,
    pub tolerance: f64,
}

#[derive(Debug, Clone, Default)]
pub struct NewtonReport {
    pub converged: bool,
    /// Number of linear solves.
    pub iterations: usize,
    /// ‖R‖ at every evaluation (the first is the initial residual).
    pub residuals: Vec<f64>,
    pub times: StageTimes,
    /// Set when the linear solve failed.
    pub error: Option<SolveError>,
    /// Total halvings of Newton steps by the line search.
    pub backtracks: usize,
    /// Length of the last accepted increment ‖α δ‖.
    pub last_step: f64,
}

/// How many halvings gave the step factor `alpha`.
fn backtracks_of(alpha: f64) -> usize {
    (-alpha.log2()).round() as usize
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Solve R(x) = 0 from the initial guess in `x` (updated in place).
///
/// Each Newton direction δ is tried in full first; if the residual norm does not fall
/// (‖R(x + δ)‖ > (1 − 10⁻⁴)‖R(x)‖), the step is halved up to [`MAX_BACKTRACKS`] times
/// and the last trial is taken (backtracking line search). Near the solution the full
/// step is always accepted, so the quadratic convergence is kept; far from it the line
/// search breaks the two-state cycles that the non-smooth contact laws (open/closed,
/// stick/slide) otherwise cause.
pub fn newton(
    sys: &mut dyn NonlinearSystem,
    jac: &mut SparseMatrix,
    solver: &mut AutoSolver,
    x: &mut [f64],
    opts: NewtonOptions,
) -> NewtonReport {
    let n = x.len();
    let mut r = vec![0.0; n];
    let mut delta = vec![0.0; n];
    let mut trial = vec![0.0; n];
    let mut rep = NewtonReport::default();
    let mut symmetric = evaluate(sys, x, &mut r, jac, &mut rep.times);
    let mut rn = norm(&r);
    rep.residuals.push(rn);
    let scale = sys.reference_norm().max(f64::MIN_POSITIVE);
    for it in 0..=opts.max_iterations {
        if !rn.is_finite() {
            return rep;
        }
        if it > 0 {
            let small_r = rn <= opts.tolerance * scale;
            let small_dx = rep.last_step <= opts.tolerance * norm(x).max(f64::MIN_POSITIVE);
            if small_r && (small_dx || !sys.active_set_changed()) {
                rep.converged = true;
                return rep;
            }
        }
        if it == opts.max_iterations {
            return rep;
        }
        let t1 = Instant::now();
        if let Err(e) = solver.factorize_with(jac, symmetric) {
            rep.error = Some(e);
            return rep;
        }
        let t2 = Instant::now();
        rep.times.factorisation += t2 - t1;
        delta.copy_from_slice(&r);
        if let Err(e) = solver.solve_in_place(&mut delta) {
            rep.error = Some(e);
            return rep;
        }
        rep.times.solve += t2.elapsed();
        rep.iterations += 1;
        // backtracking line search on ‖R‖
        let mut alpha = 1.0;
        loop {
            for i in 0..n {
                trial[i] = x[i] + alpha * delta[i];
            }
            symmetric = evaluate(sys, &trial, &mut r, jac, &mut rep.times);
            let rt = norm(&r);
            if rt <= (1.0 - 1e-4 * alpha) * rn || backtracks_of(alpha) >= MAX_BACKTRACKS {
                x.copy_from_slice(&trial);
                rn = rt;
                break;
            }
            alpha *= 0.5;
            rep.backtracks += 1;
        }
        rep.last_step = alpha * norm(&delta);
        rep.residuals.push(rn);
    }
    rep
}

/// Most halvings of a Newton step in the line search.
pub const MAX_BACKTRACKS: usize = 6;

fn evaluate(
    sys: &mut dyn NonlinearSystem,
    x: &[f64],
    r: &mut [f64],
    jac: &mut SparseMatrix,
    times: &mut StageTimes,
) -> bool {
    let t0 = Instant::now();
    let contact_before = times.contact;
    jac.clear();
    let symmetric = sys.evaluate(x, r, jac, times);
    // assembly time excludes what the system booked as contact work
    times.assembly += t0.elapsed().saturating_sub(times.contact - contact_before);
    symmetric
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::SparsePattern;
    use std::sync::Arc;

    /// R(x) = b − (A x + c x³) componentwise-coupled: a smooth nonlinear test problem.
    struct Cubic {
        b: Vec<f64>,
    }
    impl NonlinearSystem for Cubic {
        fn evaluate(
            &mut self,
            x: &[f64],
            r: &mut [f64],
            j: &mut SparseMatrix,
            _t: &mut StageTimes,
        ) -> bool {
            let n = x.len();
            for i in 0..n {
                let left = if i > 0 { x[i - 1] } else { 0.0 };
                let right = if i + 1 < n { x[i + 1] } else { 0.0 };
                r[i] = self.b[i] - (2.0 * x[i] - left - right + x[i].powi(3));
                j.add(i, i, 2.0 + 3.0 * x[i] * x[i]);
                if i > 0 {
                    j.add(i, i - 1, -1.0);
                }
                if i + 1 < n {
                    j.add(i, i + 1, -1.0);
                }
            }
            true
        }
        fn reference_norm(&self) -> f64 {
            norm(&self.b)
        }
        fn active_set_changed(&self) -> bool {
            true
        }
    }

    #[test]
    fn newton_converges_quadratically_on_a_smooth_problem() {
        let n = 20;
        let groups: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
        let p = Arc::new(SparsePattern::from_groups(n, groups.iter().map(|g| &g[..])));
        let mut j = SparseMatrix::zeros(p);
        let mut sys = Cubic {
            b: (0..n).map(|i| 1.0 + (i as f64).cos()).collect(),
        };
        let mut x = vec![0.0; n];
        let mut s = AutoSolver::default();
        let rep = newton(
            &mut sys,
            &mut j,
            &mut s,
            &mut x,
            NewtonOptions {
                max_iterations: 30,
                tolerance: 1e-12,
            },
        );
        assert!(rep.converged, "{rep:?}");
        // quadratic: r_{k+1} / r_k^2 stays bounded in the last iterations
        let r = &rep.residuals;
        let k = r.len() - 2;
        assert!(
            r[k] < 1e-6 && r[k + 1] <= 10.0 * r[k] * r[k] + 1e-14,
            "{r:?}"
        );
        assert_eq!(s.symbolic_count(), 1);
    }
}
