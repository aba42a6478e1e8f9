//! Sparse linear algebra and the Newton-Raphson driver. Knows nothing of the NMM.
//!
//! * [`SparsePattern`] / [`SparseMatrix`]: compressed sparse columns with a *fixed*
//!   pattern: values are re-assembled into it every iteration, and the symbolic
//!   factorisation is reused while the pattern is unchanged.
//! * [`LinearSolver`]: the small trait behind which the direct solvers sit:
//!   [`FaerCholesky`] (sparse LLᵀ, AMD ordering) for symmetric positive-definite
//!   systems and [`FaerLu`] (sparse LU, COLAMD) for the unsymmetric consistent
//!   friction tangent. [`AutoSolver`] picks one per factorisation.
//! * [`newton`]: Newton-Raphson on any [`NonlinearSystem`].

mod linear;
mod newton;
mod sparse;

pub use linear::{AutoSolver, FaerCholesky, FaerLu, LinearSolver, SolveError};
pub use newton::{newton, NewtonOptions, NewtonReport, NonlinearSystem, StageTimes};
pub use sparse::{SparseMatrix, SparsePattern};
