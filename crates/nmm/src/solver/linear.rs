//! Direct sparse solvers behind one small trait ([`DirectSolver`]), so that another backend
//! (e.g. UMFPACK for very large unsymmetric systems) can be plugged in.
//!
//! The symbolic analysis (fill-reducing ordering, elimination tree) depends only
//! on the pattern; it is kept and reused while the pattern is the same `Arc`
//! (or an equal pattern), which is most of the saving on repeated solves.

use super::sparse::{SparseMatrix, SparsePattern};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, Lu, SymbolicLlt, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Side};
use std::sync::Arc;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error("the system matrix is not positive definite (a block or cover is not restrained?)")]
    NotPositiveDefinite,
    #[error("the system matrix is singular")]
    Singular,
    #[error("out of memory in the linear solver")]
    OutOfMemory,
    #[error("linear solver failure: {0}")]
    Other(String),
}

/// Factorise once, solve many times.
pub trait DirectSolver {
    /// Factorise `a` (reusing the symbolic analysis when the pattern is unchanged).
    fn factorize(&mut self, a: &SparseMatrix) -> Result<(), SolveError>;
    /// Solve A x = b in place (b becomes x) with the last factorisation.
    fn solve_in_place(&self, b: &mut [f64]) -> Result<(), SolveError>;
    /// How many symbolic analyses were done (for reports and tests).
    fn symbolic_count(&self) -> usize;
}

/// faer runs sequentially: on these 2-core machines two threads were slower than one
/// for sparse factorisations (`dependencies.md`), and for the small systems of block
/// models the thread start-up dominates.
fn sequential() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| faer::set_global_parallelism(faer::Par::Seq));
}

fn views(a: &SparseMatrix) -> SparseColMatRef<'_, usize, f64> {
    sequential();
    let p = &a.pattern;
    let sym = SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx);
    SparseColMatRef::new(sym, &a.values)
}

fn same_pattern(cached: &Option<Arc<SparsePattern>>, p: &Arc<SparsePattern>) -> bool {
    match cached {
        Some(c) => Arc::ptr_eq(c, p) || **c == **p,
        None => false,
    }
}

/// A factorisation that keeps its symbolic analysis while the pattern is unchanged.
struct Cached<S, N> {
    pattern: Option<Arc<SparsePattern>>,
    symbolic: Option<S>,
    numeric: Option<N>,
    symbolic_count: usize,
}

impl<S, N> Default for Cached<S, N> {
    fn default() -> Self {
        Cached {
            pattern: None,
            symbolic: None,
            numeric: None,
            symbolic_count: 0,
        }
    }
}

impl<S: Clone, N: Solve<f64>> Cached<S, N> {
    fn factorize(
        &mut self,
        a: &SparseMatrix,
        analyse: impl FnOnce(SymbolicSparseColMatRef<'_, usize>) -> Result<S, SolveError>,
        numeric: impl FnOnce(S, SparseColMatRef<'_, usize, f64>) -> Result<N, SolveError>,
    ) -> Result<(), SolveError> {
        let m = views(a);
        let symbolic = match &self.symbolic {
            Some(s) if same_pattern(&self.pattern, &a.pattern) => s.clone(),
            _ => {
                let s = analyse(m.symbolic())?;
                self.symbolic = Some(s.clone());
                self.pattern = Some(a.pattern.clone());
                self.symbolic_count += 1;
                s
            }
        };
        self.numeric = Some(numeric(symbolic, m)?);
        Ok(())
    }

    fn solve_in_place(&self, b: &mut [f64]) -> Result<(), SolveError> {
        let f = self
            .numeric
            .as_ref()
            .ok_or_else(|| SolveError::Other("solve before factorize".into()))?;
        let n = b.len();
        f.solve_in_place(MatMut::from_column_major_slice_mut(b, n, 1));
        check_finite(b)
    }
}

/// Sparse Cholesky LLᵀ (faer, AMD ordering) for symmetric positive-definite matrices.
#[derive(Default)]
pub struct FaerCholesky(Cached<SymbolicLlt<usize>, Llt<usize, f64>>);

impl DirectSolver for FaerCholesky {
    fn factorize(&mut self, a: &SparseMatrix) -> Result<(), SolveError> {
        self.0.factorize(
            a,
            |m| {
                SymbolicLlt::try_new(m, Side::Lower)
                    .map_err(|e| SolveError::Other(format!("{e:?}")))
            },
            |s, m| {
                Llt::try_new_with_symbolic(s, m, Side::Lower)
                    .map_err(|_| SolveError::NotPositiveDefinite)
            },
        )
    }
    fn solve_in_place(&self, b: &mut [f64]) -> Result<(), SolveError> {
        self.0.solve_in_place(b)
    }
    fn symbolic_count(&self) -> usize {
        self.0.symbolic_count
    }
}

/// Sparse LU (faer, COLAMD ordering, partial pivoting) for unsymmetric matrices.
#[derive(Default)]
pub struct FaerLu(Cached<SymbolicLu<usize>, Lu<usize, f64>>);

impl DirectSolver for FaerLu {
    fn factorize(&mut self, a: &SparseMatrix) -> Result<(), SolveError> {
        self.0.factorize(
            a,
            |m| SymbolicLu::try_new(m).map_err(|e| SolveError::Other(format!("{e:?}"))),
            |s, m| Lu::try_new_with_symbolic(s, m).map_err(|_| SolveError::Singular),
        )
    }
    fn solve_in_place(&self, b: &mut [f64]) -> Result<(), SolveError> {
        self.0.solve_in_place(b)
    }
    fn symbolic_count(&self) -> usize {
        self.0.symbolic_count
    }
}

fn check_finite(x: &[f64]) -> Result<(), SolveError> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SolveError::Singular)
    }
}

/// Cholesky when the matrix is symmetric, LU otherwise (the consistent friction
/// tangent of sliding contacts is unsymmetric). Each keeps its own symbolic analysis.
#[derive(Default)]
pub struct AutoSolver {
    pub cholesky: FaerCholesky,
    pub lu: FaerLu,
    use_lu: bool,
}

impl AutoSolver {
    /// Factorise, choosing by the caller's knowledge of symmetry.
    pub fn factorize_with(&mut self, a: &SparseMatrix, symmetric: bool) -> Result<(), SolveError> {
        self.use_lu = !symmetric;
        if symmetric {
            self.cholesky.factorize(a)
        } else {
            self.lu.factorize(a)
        }
    }
    /// Whether the last factorisation was LU.
    pub fn used_lu(&self) -> bool {
        self.use_lu
    }
}

impl DirectSolver for AutoSolver {
    fn factorize(&mut self, a: &SparseMatrix) -> Result<(), SolveError> {
        let sym = a.is_symmetric(1e-13);
        self.factorize_with(a, sym)
    }
    fn solve_in_place(&self, b: &mut [f64]) -> Result<(), SolveError> {
        if self.use_lu {
            self.lu.solve_in_place(b)
        } else {
            self.cholesky.solve_in_place(b)
        }
    }
    fn symbolic_count(&self) -> usize {
        self.cholesky.symbolic_count() + self.lu.symbolic_count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn laplacian(n: usize, skew: f64) -> SparseMatrix {
        let groups: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
        let p = Arc::new(SparsePattern::from_groups(n, groups.iter().map(|g| &g[..])));
        let mut a = SparseMatrix::zeros(p);
        for i in 0..n {
            a.add(i, i, 2.0);
            if i + 1 < n {
                a.add(i, i + 1, -1.0 + skew);
                a.add(i + 1, i, -1.0 - skew);
            }
        }
        a
    }

    fn residual(a: &SparseMatrix, x: &[f64], b: &[f64]) -> f64 {
        let mut y = vec![0.0; x.len()];
        a.mul_vec(x, &mut y);
        y.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn cholesky_solves_and_reuses_symbolic() {
        let a = laplacian(50, 0.0);
        let b: Vec<f64> = (0..50).map(|i| (i as f64).sin()).collect();
        let mut s = FaerCholesky::default();
        s.factorize(&a).unwrap();
        let mut x = b.clone();
        s.solve_in_place(&mut x).unwrap();
        assert!(residual(&a, &x, &b) < 1e-12);
        let mut a2 = a.clone();
        a2.values.iter_mut().for_each(|v| *v *= 2.0);
        s.factorize(&a2).unwrap();
        assert_eq!(s.symbolic_count(), 1);
    }

    #[test]
    fn lu_solves_unsymmetric() {
        let a = laplacian(40, 0.3);
        assert!(!a.is_symmetric(1e-13));
        let b: Vec<f64> = (0..40).map(|i| 1.0 + i as f64).collect();
        let mut s = AutoSolver::default();
        s.factorize(&a).unwrap();
        assert!(s.used_lu());
        let mut x = b.clone();
        s.solve_in_place(&mut x).unwrap();
        assert!(residual(&a, &x, &b) < 1e-10);
    }

    #[test]
    fn indefinite_matrix_is_reported_not_panicking() {
        let mut a = laplacian(5, 0.0);
        a.values.iter_mut().for_each(|v| *v = -*v);
        let mut s = FaerCholesky::default();
        assert_eq!(s.factorize(&a), Err(SolveError::NotPositiveDefinite));
    }
}
