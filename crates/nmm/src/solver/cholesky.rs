//! Sparse Cholesky LLᵀ (faer, AMD ordering) that allocates nothing per factorisation.
//!
//! Always **supernodal**: faer's automatic choice takes the simplicial factorisation for
//! the block models' small and medium matrices, where the supernodal one was measured
//! faster (numeric factorisation of a 10×10 brick wall's tangent, 1,200 unknowns: 1.0
//! against 2.6 ms; of a 40×40 wall's, 19,200 unknowns: 54 against 290 ms; of the arch's,
//! 1,000 unknowns: 0.3 against 0.5 ms), at the cost of 20–50% more stored values (the
//! padding of the supernodes).
//!
//! The symbolic analysis (ordering, elimination tree, supernodes) is kept while the pattern
//! is unchanged; the factor's values and faer's workspaces are kept across symbolic analyses
//! and grown only when a new analysis needs more (a fresh allocation of that size is fresh
//! pages the kernel must zero: 9% of a 40×40 wall's run before), and reused by every numeric
//! factorisation and solve. Every allocation is fallible: an allocation failure is
//! [`SolveError::OutOfMemory`], never an abort.

use super::linear::SolveError;
use super::sparse::{SparseMatrix, SparsePattern};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::sync::Arc;

/// A Cholesky factorisation with reusable storage (see the module docs).
#[derive(Default)]
pub struct Cholesky {
    pattern: Option<Arc<SparsePattern>>,
    symbolic: Option<SymbolicCholesky<usize>>,
    values: Vec<f64>,
    /// faer's workspaces with the (size, alignment) they were made for.
    factor_work: Option<(MemBuffer, (usize, usize))>,
    solve_work: Option<(MemBuffer, (usize, usize))>,
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

/// A workspace of at least `req`: the held one if it is large enough, else a new one.
fn ensure(
    held: &mut Option<(MemBuffer, (usize, usize))>,
    req: faer::dyn_stack::StackReq,
) -> Result<(), SolveError> {
    let need = (req.size_bytes(), req.align_bytes());
    if held
        .as_ref()
        .is_some_and(|(_, have)| have.0 >= need.0 && have.1 >= need.1)
    {
        return Ok(());
    }
    *held = None; // free the old one before taking the new
    let b = MemBuffer::try_new(req).map_err(|_| SolveError::OutOfMemory)?;
    *held = Some((b, need));
    Ok(())
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
                CholeskySymbolicParams {
                    supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                    ..Default::default()
                },
            )
            .map_err(|e| match e {
                faer::sparse::FaerError::OutOfMemory => SolveError::OutOfMemory,
                e => SolveError::Other(format!("{e:?}")),
            })?;
            let len = s.len_val();
            self.values.clear();
            self.values
                .try_reserve(len)
                .map_err(|_| SolveError::OutOfMemory)?;
            self.values.resize(len, 0.0);
            ensure(
                &mut self.factor_work,
                s.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            )?;
            ensure(
                &mut self.solve_work,
                s.solve_in_place_scratch::<f64>(1, Par::Seq),
            )?;
            self.symbolic = Some(s);
            self.pattern = Some(a.pattern.clone());
            self.symbolic_count += 1;
        }
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        let work = &mut self.factor_work.as_mut().expect("workspace").0;
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
        let work = &mut self.solve_work.as_mut().expect("workspace").0;
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

#[cfg(test)]
mod allocation_tests {
    use super::*;

    /// An allocation the machine cannot make (exabytes) is `OutOfMemory`, returned, not an
    /// abort, and nothing is held afterwards.
    #[test]
    fn an_impossible_workspace_is_out_of_memory_not_an_abort() {
        let mut held = None;
        let req = faer::dyn_stack::StackReq::new::<f64>(usize::MAX / 16);
        assert_eq!(ensure(&mut held, req), Err(SolveError::OutOfMemory));
        assert!(held.is_none());
        // a possible one afterwards is made
        assert_eq!(
            ensure(&mut held, faer::dyn_stack::StackReq::new::<f64>(8)),
            Ok(())
        );
        assert!(held.is_some());
    }
}
