//! Sparse linear algebra and the Newton driver. Knows nothing of the NMM.
//!
//! * [`SparsePattern`] / [`SparseMatrix`]: compressed sparse columns with a *fixed*
//!   pattern: values are re-assembled into it, and the symbolic factorisation is reused
//!   while the pattern is unchanged.
//! * [`Cholesky`]: sparse LLᵀ (faer, AMD ordering, supernodal) without allocation per
//!   factorisation; [`DirectSolver`]: the small trait behind which the direct solvers sit
//!   ([`FaerCholesky`], [`FaerLu`], [`AutoSolver`]).
//! * [`Gmres`]: restarted, right-preconditioned GMRES.
//! * [`LinearSolver`]: the one interface through which the Newton driver and the
//!   simulation solve with a step's tangent; [`TangentSolver`] implements it — a held
//!   factorisation as the preconditioner of GMRES, refreshed when it stops paying, LU as
//!   the last resort.
//! * [`solve_piecewise`]: semi-smooth Newton (active set) with a globalisation that never
//!   accepts a rise of the merit, on any [`PiecewiseSystem`].

mod cholesky;
mod krylov;
mod linear;
mod newton;
mod sparse;
mod supernodal;
mod tangent;

pub use cholesky::Cholesky;
pub use krylov::{Gmres, GmresReport};
pub use linear::{AutoSolver, DirectSolver, FaerCholesky, FaerLu, SolveError};
pub use newton::{
    solve_piecewise, NewtonOptions, NewtonReport, PiecewiseSystem, Regularisation, StageTimes,
    MAX_REJECTIONS, MIN_STEP,
};
pub use sparse::{SparseMatrix, SparsePattern};
pub use tangent::{LinearSolver, LinearStats, TangentOperator, TangentSolver, MIN_LU_PIECES};

/// Σ aᵢ bᵢ in four interleaved partial sums, so that it vectorises (a sum in one
/// accumulator waits on each addition: the Gram–Schmidt of GMRES was about a tenth of a
/// GMRES iteration on the block models); a fixed order, so the same result on every run.
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (ac, bc) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ac
        .remainder()
        .iter()
        .zip(bc.remainder())
        .map(|(x, y)| x * y)
        .sum();
    let mut s = [0.0; 4];
    for (x, y) in ac.zip(bc) {
        for i in 0..4 {
            s[i] += x[i] * y[i];
        }
    }
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}
