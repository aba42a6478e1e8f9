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
mod tangent;

pub use cholesky::Cholesky;
pub use krylov::{Gmres, GmresReport};
pub use linear::{AutoSolver, DirectSolver, FaerCholesky, FaerLu, SolveError};
pub use newton::{
    solve_piecewise, NewtonOptions, NewtonReport, PiecewiseSystem, Regularisation, StageTimes,
    MAX_REJECTIONS, MIN_STEP,
};
pub use sparse::{SparseMatrix, SparsePattern};
pub use tangent::{LinearSolver, LinearStats, TangentOperator, TangentSolver};
