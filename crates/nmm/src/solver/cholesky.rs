//! Sparse Cholesky LLᵀ (faer, AMD ordering) that allocates nothing per factorisation.
//!
//! The symbolic analysis (ordering, elimination tree, supernodes) is kept while the pattern
//! is unchanged; the factor's values and faer's workspaces are allocated once per symbolic
//! analysis and reused by every numeric factorisation and solve. Every allocation is
//! fallible: an allocation failure is [`SolveError::OutOfMemory`], never an abort.

use super::linear::SolveError;
use super::sparse::{SparseMatrix, SparsePattern};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;

/// A Cholesky factorisation with reusable storage (see the module docs).
#[derive(Default)]
pub struct Cholesky {
    pattern: Option<Arc<SparsePattern>>,
    symbolic: Option<SymbolicCholesky<usize>>,
    values: Vec<f64>,
    factor_work: Option<MemBuffer>,
    solve_work: Option<MemBuffer>,
    /// A numeric factorisation is held.
    valid: bool,
    /// Symbolic analyses done.
    pub symbolic_count: usize,
    /// Numeric factorisations done.
    pub numeric_count: usize,
}

fn views(a: &SparseMatrix) -> SparseColMatRef<'_, usize, f64> {
    let p = &a.pattern;
    let sym = SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx);
    SparseColMatRef::new(sym, &a.values)
}

fn buffer(req: faer::dyn_stack::StackReq) -> Result<MemBuffer, SolveError> {
    MemBuffer::try_new(req).map_err(|_| SolveError::OutOfMemory)
}

impl Cholesky {
    /// Whether a numeric factorisation is held.
    pub fn is_valid(&self) -> bool {
        self.valid
    }

    /// Forget the numeric factorisation (the symbolic analysis is kept).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Number of stored values of the factor.
    pub fn factor_len(&self) -> usize {
        self.values.len()
    }

    /// The pattern of the held factorisation.
    pub fn pattern(&self) -> Option<&Arc<SparsePattern>> {
        self.pattern.as_ref()
    }

    /// Factorise `a` (its lower triangle is read).
    pub fn factorize(&mut self, a: &SparseMatrix) -> Result<(), SolveError> {
        self.valid = false;
        let m = views(a);
        let same = match &self.pattern {
            Some(p) => Arc::ptr_eq(p, &a.pattern) || **p == *a.pattern,
            None => false,
        };
        if !same || self.symbolic.is_none() {
            let s = factorize_symbolic_cholesky(
                m.symbolic(),
                Side::Lower,
                Default::default(),
                Default::default(),
            )
            .map_err(|e| match e {
                faer::sparse::FaerError::OutOfMemory => SolveError::OutOfMemory,
                e => SolveError::Other(format!("{e:?}")),
            })?;
            let len = s.len_val();
            self.values.clear();
            self.values
                .try_reserve_exact(len)
                .map_err(|_| SolveError::OutOfMemory)?;
            self.values.resize(len, 0.0);
            self.factor_work = Some(buffer(
                s.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            )?);
            self.solve_work = Some(buffer(s.solve_in_place_scratch::<f64>(1, Par::Seq))?);
            self.symbolic = Some(s);
            self.pattern = Some(a.pattern.clone());
            self.symbolic_count += 1;
        }
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        let work = self.factor_work.as_mut().expect("workspace");
        s.factorize_numeric_llt::<f64>(
            &mut self.values,
            m,
            Side::Lower,
            Default::default(),
            Par::Seq,
            MemStack::new(work),
            Default::default(),
        )
        .map_err(|_| SolveError::NotPositiveDefinite)?;
        self.numeric_count += 1;
        self.valid = true;
        Ok(())
    }

    /// Solve A x = b in place with the held factorisation.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolveError> {
        if !self.valid {
            return Err(SolveError::Other("solve before factorize".into()));
        }
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        let l = LltRef::<'_, usize, f64>::new(s, &self.values);
        let n = b.len();
        let work = self.solve_work.as_mut().expect("workspace");
        l.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(b, n, 1),
            Par::Seq,
            MemStack::new(work),
        );
        if b.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(SolveError::Singular)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn laplacian(n: usize) -> SparseMatrix {
        let groups: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
        let p = Arc::new(SparsePattern::from_groups(n, groups.iter().map(|g| &g[..])));
        let mut a = SparseMatrix::zeros(p);
        for i in 0..n {
            a.add(i, i, 2.0 + 0.1 * i as f64);
            if i + 1 < n {
                a.add(i, i + 1, -1.0);
                a.add(i + 1, i, -1.0);
            }
        }
        a
    }

    #[test]
    fn solves_and_reuses_its_storage() {
        let a = laplacian(200);
        let b: Vec<f64> = (0..200).map(|i| (i as f64 * 0.3).sin()).collect();
        let mut c = Cholesky::default();
        for round in 0..3 {
            let mut a2 = a.clone();
            a2.values.iter_mut().for_each(|v| *v *= 1.0 + round as f64);
            c.factorize(&a2).unwrap();
            let mut x = b.clone();
            c.solve_in_place(&mut x).unwrap();
            let mut y = vec![0.0; 200];
            a2.mul_vec(&x, &mut y);
            let err = y
                .iter()
                .zip(&b)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-12, "{err}");
        }
        assert_eq!((c.symbolic_count, c.numeric_count), (1, 3));
        let mut neg = a.clone();
        neg.values.iter_mut().for_each(|v| *v = -*v);
        assert_eq!(c.factorize(&neg), Err(SolveError::NotPositiveDefinite));
        assert!(!c.is_valid());
    }
}
