//! Sparse Cholesky LLᵀ (faer's AMD ordering and supernodal analysis, our numeric
//! factorisation and solves) that allocates nothing per factorisation.
//!
//! The **numeric factorisation** is ours (supernodal.rs): faer's left-looking supernodal
//! algorithm on faer's storage, every update by faer's dense product, so that two threads
//! can factorise the two parts of a split elimination tree (below) at once. Measured
//! (2026-12-04, tangents taken from runs at their 20th factorisation, faer's and ours
//! interleaved in one process, minimum/median of 40, two runs): the arch's (1,000 unknowns,
//! 24,900 values) 0.20/0.21 ms with faer's, 0.115/0.117 with ours; a 20×20 wall's (4,800
//! unknowns, 175,000 values) 1.71/1.77 and 1.28/1.36 ms, 0.88/1.5 on two threads; a 40×40
//! wall's (19,200 unknowns, 943,000 values) 10.0/11.1 and 8.9/9.7 ms, 6.2/8.5–10.6 on two
//! threads (the machine's noise is in the medians). The factors agree to round-off and
//! ours is the same bit for bit on one thread and two.
//!
//! Always **supernodal**: faer's automatic choice takes the simplicial factorisation for
//! the block models' small and medium matrices, where the supernodal one was measured
//! faster (numeric factorisation of a 10×10 brick wall's tangent, 1,200 unknowns: 1.0
//! against 2.6 ms; of a 40×40 wall's, 19,200 unknowns: 54 against 290 ms; of the arch's,
//! 1,000 unknowns: 0.3 against 0.5 ms), at the cost of 20–50% more stored values (the
//! padding of the supernodes).
//!
//! The triangular solves (one pair per GMRES iteration: about 60% of an iteration's time on
//! the block models) run over faer's supernodal factor in `supernodal_solve`: plain loops
//! over each narrow supernode's contiguous columns, faer's dense kernels for supernodes of
//! `WIDE_SUPERNODE` columns or more. Measured (2026-12-03, alternated against the build
//! before, which called faer's supernodal solve): the arch example (8,020 steps; 1,000
//! unknowns, 116 supernodes, 26,000 values in the factor) solve stage 6.4–6.9 → 5.6–5.7 s,
//! run 18.8–20.6 → 18.3–18.8 s; the brick walls (wide supernodes) unchanged; the shaken
//! slope (922 unknowns, 47,000 values) about 5% off its solve stage. The threshold: 8 and 64
//! were no better on the arch, 64 worse on the 40×40 wall (solve 2.65 against 2.36 s).
//! Measured and rejected: a column-by-column copy of the factor after each factorisation,
//! solved with faer's sparse triangular solves (arch, 2,520 steps: solve 2.03 → 1.93 s, the
//! copies as much again); a more relaxed supernode amalgamation ((8, 1.0), (32, 0.8), (64,
//! 0.2) and wider: 93 and 83 supernodes with 32,800 and 40,500 values instead of 25,800 on
//! the arch, the same run time).
//!
//! **Two threads** split the triangular solves of a large factor (`MIN_SPLIT_VALUES`): the
//! elimination tree of supernodes is cut into two parts of whole subtrees with balanced
//! values and the rest, the top (`split_tree`; a 40×40 wall's factor: 431,000 and 397,000
//! values, top 115,000). The parts' forward steps are independent (a supernode's pattern
//! holds only its ancestors): each runs on its own copy of x and sums its contributions to
//! the top's rows apart; then the top forward and backward; then the parts' backward steps,
//! each on its own copy (`solve_split`). One thread does the same operations in the same
//! order, so the result does not depend on the thread count (histories byte-identical at 1
//! and 2 threads: 20×20 and 40×40 walls, the arch). Measured (2026-12-04, 40×40 wall, 12
//! steps, two alternated runs, with the one-pass contact product of the same commit): solve
//! stage 2.58/2.62 s on one thread, 2.34/2.37 s on two (against 2.98/3.40 and 2.66/2.86 for
//! the build before). The numeric factorisation is split the same way (above): the parts'
//! supernodes depend only on their own descendants.
//!
//! Measured and rejected (2026-12-04, 40×40 wall, 19,200 unknowns): one level of nested
//! dissection so that two threads factorise and solve the two halves (each half with the
//! separator appended and ordered last, the separator's Schur complement T₀T₀ᵀ + T₁T₁ᵀ − Aₛₛ
//! from the halves' trailing blocks, factorised densely). Graph separators of the tangent
//! were large — 430–650 unknowns from breadth-first level structures or the bisector
//! d(u, ·) − d(v, ·) of a pseudo-peripheral pair, the contacts coupling 24 unknowns each —
//! and the halves held 3.6–4.2 million values against 2.48 million for AMD on the whole: on
//! two threads the larger half alone took 52–56 ms against 49 ms for the whole on one.
//! Splitting AMD's own elimination tree instead (no extra fill) leaves 19–23% of the flops
//! in its top (the ancestors of two balanced subtrees, 850–980 columns), which the split
//! would factorise three times with faer (it factorises whole matrices: each part's with
//! the top appended); our own factorisation does it once. faer's parallel factorisation:
//! 55 against 49 ms.
//!
//! Measured and rejected (2026-12-04): the preconditioner of an unsymmetric tangent
//! factorised and solved in single precision (f32 values through faer's generic
//! factorisation and the same supernodal solve; double precision kept for symmetric
//! tangents, whose solve is direct). Flushing subnormals was necessary (x86 MXCSR FTZ/DAZ:
//! the factor's decaying fill reaches 1e-38, and the factorisations took 3× longer than in
//! double without it). With it, mean numeric factorisation 10.5 → 8.4 ms (20×20 wall), 33 →
//! 19 ms (30×30), 58 → 43 ms (40×40), but GMRES needed 21% more iterations (40×40: 400 →
//! 483 in 12 steps; the preconditioner's own error, cond · 6e-8, against the 1e-10 the
//! Newton direction asks for), and per step: 20×20 0.71× and 0.92× in two alternated runs,
//! 30×30 0.81×, 40×40 0.97× twice (within the machine's noise); the arch example worse
//! (GMRES 65,897 → 91,093 iterations, 36 → 41 s).
//!
//! The symbolic analysis is done here in two parts: faer's AMD ordering P of the pattern
//! (the ordering faer's own analysis would take), then faer's supernodal analysis of
//! P A Pᵀ with no further ordering. Each numeric factorisation places A's values once,
//! through a map made by the analysis, straight into the factor's storage (their entries of
//! the lower triangle of P A Pᵀ); solves permute the right-hand side. Before, faer permuted A at
//! every numeric factorisation (`permute_self_adjoint_to_unsorted`: 7.9% of the arch
//! example's run, and 1.3% in checking A's pattern): a factorisation of the arch's tangent
//! (1,000 unknowns, assembly included) went from 0.48 to 0.44 ms.
//!
//! The symbolic analysis (ordering, elimination tree, supernodes) is kept while the pattern
//! is unchanged; the factor's values and faer's workspaces are kept across symbolic analyses
//! and grown only when a new analysis needs more (a fresh allocation of that size is fresh
//! pages the kernel must zero: 9% of a 40×40 wall's run before), and reused by every numeric
//! factorisation and solve. Every allocation is fallible: an allocation failure is
//! [`SolveError::OutOfMemory`], never an abort.

use super::dot;
use super::linear::SolveError;
use super::sparse::{SparseMatrix, SparsePattern};
use super::supernodal::{FactorPlan, FactorWork, Schedule};
use crate::same_bits;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::{matmul, triangular_solve};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Accum, Conj, MatMut, MatRef, Par, Side};
use std::sync::Arc;

/// A Cholesky factorisation with reusable storage (see the module docs).
#[derive(Default)]
pub struct Cholesky {
    pattern: Option<Arc<SparsePattern>>,
    symbolic: Option<SymbolicCholesky<usize>>,
    values: Vec<f64>,
    /// The fill-reducing ordering: `inv[i]` is the position of unknown i in the factor.
    inv: Vec<usize>,
    /// The lower triangle of P A Pᵀ (column pointers, row indices; the values only for
    /// faer's numeric factorisation, [`Cholesky::faer_numeric`]) ...
    lower_col_ptr: Vec<usize>,
    lower_row_idx: Vec<usize>,
    lower_values: Vec<f64>,
    /// ... and, for each of its slots, the slot of A's pattern it takes its value from (a
    /// branch-free gather over half of A's entries: the former scatter over all of them,
    /// skipping the upper triangle, was 4.4% of the arch example's run).
    gather: Vec<u32>,
    /// A right-hand side in the factor's order.
    permuted: Vec<f64>,
    /// The below-diagonal part of one supernode times a vector (the triangular solves').
    below: Vec<f64>,
    /// The factor's elimination tree split in two independent parts and the top
    /// ([`split_tree`]), and the parts' workspaces.
    split: Option<Split>,
    /// What our numeric factorisation needs ([`super::supernodal`]).
    plan: Option<FactorPlan>,
    part_work: [PartWork; 2],
    /// faer's workspaces with the (size, alignment) they were made for.
    factor_work: Option<(MemBuffer, (usize, usize))>,
    solve_work: Option<(MemBuffer, (usize, usize))>,
    /// Uᵀ of an LU factorisation without pivoting ([`Cholesky::factorize_lu_on`]; L in
    /// `values`), in the factor's layout; empty until the first.
    upper: Vec<f64>,
    /// For each slot of the lower triangle of P A Pᵀ off its diagonal, the slot of A's
    /// pattern of the transposed entry and where the LU puts it (`usize::MAX` on the
    /// diagonal; below the factor's length: in `values`, a diagonal block's upper part;
    /// from it on: in `upper`); made at the first LU of an analysis.
    mirror: Vec<(u32, usize)>,
    /// The held numeric factorisation is an LU (`values` and `upper`), not a Cholesky one.
    lu_held: bool,
    /// The values of the A the held factor is of ([`Cholesky::mark_redo`]) ...
    previous: Vec<f64>,
    /// ... the supernodes to factorise again (their A changed, or a descendant's) ...
    redo: Vec<bool>,
    /// ... each supernode's parent in the elimination tree (`usize::MAX`: a root) and the
    /// supernode of each column of the factor (made with the analysis).
    parent: Vec<usize>,
    sn_of: Vec<usize>,
    /// A numeric factorisation is held.
    valid: bool,
    /// Symbolic analyses done.
    pub symbolic_count: usize,
    /// Numeric factorisations done.
    pub numeric_count: usize,
}

fn faer_error(e: faer::sparse::FaerError) -> SolveError {
    match e {
        faer::sparse::FaerError::OutOfMemory => SolveError::OutOfMemory,
        e => SolveError::Other(format!("{e:?}")),
    }
}

/// `v` as `n` default values, allocated fallibly.
pub(super) fn try_zeroed<T: Clone + Default>(v: &mut Vec<T>, n: usize) -> Result<(), SolveError> {
    v.clear();
    v.try_reserve(n).map_err(|_| SolveError::OutOfMemory)?;
    v.resize(n, T::default());
    Ok(())
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

/// The AMD ordering of `p` (faer's), computed on its quotient graph: each run of
/// consecutive columns with the same rows (the unknowns of one cover, which every element
/// and contact couples together) is one node, ordered as a whole, its columns kept in
/// order. AMD would find these indistinguishable nodes itself, but only after reading every
/// entry: on a 40×40 brick wall's tangent (19,200 unknowns, 830,000 entries; 2 unknowns a
/// cover) the ordering took 19 ms on the unknowns and 13 ms on the covers (both measured
/// beside another job), with the same factor size within 0.01% (2,484,548 against
/// 2,484,656 values) and histories within 1e-10. `inv[i]` is the position of unknown i.
fn amd_ordering(p: &SparsePattern, inv: &mut [usize]) -> Result<(), SolveError> {
    let n = p.n;
    let rows = |c: usize| &p.row_idx[p.col_ptr[c]..p.col_ptr[c + 1]];
    // the first column of each node, and each column's node
    let mut first = Vec::new();
    let mut node_of = Vec::new();
    try_zeroed(&mut node_of, n)?;
    for (c, node) in node_of.iter_mut().enumerate() {
        if c == 0 || rows(c) != rows(c - 1) {
            first.push(c);
        }
        *node = first.len() - 1;
    }
    let m = first.len();
    first.push(n);
    // the quotient pattern: a column's rows are sorted, so their nodes are too
    let mut q_ptr = Vec::with_capacity(m + 1);
    let mut q_rows = Vec::new();
    // at most the entries of each node's first column
    let bound = first[..m].iter().map(|&f| rows(f).len()).sum();
    q_rows
        .try_reserve(bound)
        .map_err(|_| SolveError::OutOfMemory)?;
    q_ptr.push(0);
    for &f in &first[..m] {
        let mut last = usize::MAX;
        for &r in rows(f) {
            let q = node_of[r];
            if q != last {
                q_rows.push(q);
                last = q;
            }
        }
        q_ptr.push(q_rows.len());
    }
    let mut fwd = Vec::new();
    let mut q_inv = Vec::new();
    try_zeroed(&mut fwd, m)?;
    try_zeroed(&mut q_inv, m)?;
    let q = SymbolicSparseColMatRef::new_checked(m, m, &q_ptr, None, &q_rows);
    let mut mem = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(m, q_rows.len()))
        .map_err(|_| SolveError::OutOfMemory)?;
    amd::order_maybe_unsorted(
        &mut fwd,
        &mut q_inv,
        q,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(faer_error)?;
    let mut pos = 0;
    for &j in &fwd {
        for i in &mut inv[first[j]..first[j + 1]] {
            *i = pos;
            pos += 1;
        }
    }
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

    /// The symbolic analysis of pattern `p`: faer's AMD ordering P of it (as faer's own
    /// analysis computes it), the lower triangle of P A Pᵀ with the slot of each entry of A
    /// there, and the supernodal structure of P A Pᵀ without a further ordering.
    fn analyse(&mut self, p: &SparsePattern) -> Result<(), SolveError> {
        let n = p.n;
        let nnz = p.nnz();
        if nnz >= u32::MAX as usize {
            return Err(SolveError::OutOfMemory);
        }
        try_zeroed(&mut self.inv, n)?;
        amd_ordering(p, &mut self.inv)?;
        let inv = &self.inv;
        // entries per column of P A Pᵀ: lower and upper triangles (the diagonal in both)
        let mut lower_ptr = Vec::new();
        let mut upper_ptr = Vec::new();
        try_zeroed(&mut lower_ptr, n + 1)?;
        try_zeroed(&mut upper_ptr, n + 1)?;
        for c in 0..n {
            let j = inv[c];
            for &r in &p.row_idx[p.col_ptr[c]..p.col_ptr[c + 1]] {
                let i = inv[r];
                if i >= j {
                    lower_ptr[j + 1] += 1;
                }
                if i <= j {
                    upper_ptr[j + 1] += 1;
                }
            }
        }
        for j in 0..n {
            lower_ptr[j + 1] += lower_ptr[j];
            upper_ptr[j + 1] += upper_ptr[j];
        }
        let mut lower_rows = Vec::new();
        let mut upper_rows = Vec::new();
        try_zeroed(&mut lower_rows, lower_ptr[n])?;
        try_zeroed(&mut upper_rows, upper_ptr[n])?;
        try_zeroed(&mut self.gather, lower_ptr[n])?;
        let mut lpos = lower_ptr[..n].to_vec();
        let mut upos = upper_ptr[..n].to_vec();
        for c in 0..n {
            let j = inv[c];
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let i = inv[p.row_idx[k]];
                if i >= j {
                    lower_rows[lpos[j]] = i;
                    self.gather[lpos[j]] = k as u32;
                    lpos[j] += 1;
                }
                if i <= j {
                    upper_rows[upos[j]] = i;
                    upos[j] += 1;
                }
            }
        }
        let upper =
            SymbolicSparseColMatRef::new_unsorted_checked(n, n, &upper_ptr, None, &upper_rows);
        let s = factorize_symbolic_cholesky(
            upper,
            Side::Upper,
            SymmetricOrdering::Identity,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(faer_error)?;
        try_zeroed(&mut self.permuted, n)?;
        let widest_below = match s.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => (0..sn.n_supernodes())
                .map(|k| sn.supernode(k).pattern().len())
                .max()
                .unwrap_or(0),
            SymbolicCholeskyRaw::Simplicial(_) => 0,
        };
        try_zeroed(&mut self.below, widest_below)?;
        // the supernodal elimination tree: each column's supernode, each supernode's parent
        self.sn_of.clear();
        self.parent.clear();
        if let SymbolicCholeskyRaw::Supernodal(sn) = s.raw() {
            self.sn_of = supernode_of(sn)?;
            let ns = sn.n_supernodes();
            self.parent
                .try_reserve_exact(ns)
                .map_err(|_| SolveError::OutOfMemory)?;
            self.parent.extend((0..ns).map(|k| {
                sn.supernode(k)
                    .pattern()
                    .first()
                    .map_or(usize::MAX, |&r| self.sn_of[r])
            }));
        }
        self.split = match s.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) if s.len_val() >= MIN_SPLIT_VALUES => {
                split_tree(sn, &self.parent)
            }
            _ => None,
        };
        if self.split.is_some() {
            for w in &mut self.part_work {
                try_zeroed(&mut w.x, n)?;
                try_zeroed(&mut w.to_top, n)?;
                try_zeroed(&mut w.below, widest_below)?;
            }
        }
        self.plan = None;
        self.previous.clear();
        if let SymbolicCholeskyRaw::Supernodal(sn) = s.raw() {
            try_zeroed(&mut self.redo, sn.n_supernodes())?;
            let plan = FactorPlan::new(sn, &self.sn_of, &lower_ptr, &lower_rows)?;
            let parts = if self.split.is_some() { 2 } else { 1 };
            for w in &mut self.part_work[..parts] {
                plan.prepare(&mut w.factor, n)?;
            }
            self.plan = Some(plan);
        }
        self.lower_col_ptr = lower_ptr;
        self.lower_row_idx = lower_rows;
        self.mirror.clear();
        try_zeroed(&mut self.values, s.len_val())?;
        ensure(
            &mut self.solve_work,
            s.solve_in_place_scratch::<f64>(1, Par::Seq),
        )?;
        self.symbolic = Some(s);
        Ok(())
    }

    /// Factorise the symmetric `a` (of each pair of its entries, the one in the lower
    /// triangle of P A Pᵀ is read).
    pub fn factorize(&mut self, a: &SparseMatrix) -> Result<(), SolveError> {
        self.factorize_on(a, &crate::parallel::Threads::default())
    }

    /// [`Cholesky::factorize`], the two parts of a split factor (`split_tree`) on two of
    /// `threads` when it has more than one (the same factor on any number).
    pub fn factorize_on(
        &mut self,
        a: &SparseMatrix,
        threads: &crate::parallel::Threads,
    ) -> Result<(), SolveError> {
        let update = self.start_numeric(&a.pattern, false)?;
        if self.plan.is_some() {
            self.mark_redo(a, update, threads)?;
        }
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        match (&self.plan, s.raw()) {
            (Some(plan), SymbolicCholeskyRaw::Supernodal(sn)) => {
                place_lower(
                    &mut self.values,
                    Placing {
                        sn,
                        plan,
                        gather: &self.gather,
                        columns: &self.lower_col_ptr,
                        redo: &self.redo,
                    },
                    a,
                );
                super::supernodal::factorize(
                    sn,
                    plan,
                    Schedule {
                        split: self.split.as_ref(),
                        redo: &self.redo,
                    },
                    &mut self.values,
                    &mut self.part_work,
                    threads,
                )?;
            }
            // a simplicial analysis (no operation to count: a diagonal A)
            _ => self.faer_numeric(a)?,
        }
        self.numeric_count += 1;
        self.valid = true;
        Ok(())
    }

    /// The LU factorisation without pivoting of the unsymmetric `a` whose pattern is
    /// symmetric (a tangent with sliding contacts), on the symbolic analysis of its pattern
    /// (the Cholesky factor's: the same ordering, supernodes and storage for L and Uᵀ;
    /// [`super::supernodal::factorize_lu`]), the two parts of a split factor on two of
    /// `threads` as [`Cholesky::factorize_on`]. Its solves are the Cholesky factor's (the
    /// backward pass on Uᵀ). `Err(Singular)` at a pivot that is zero or not finite,
    /// `Err(Other)` for a pattern whose analysis is not supernodal: the caller falls back
    /// to the symmetric part's Cholesky factor.
    pub fn factorize_lu_on(
        &mut self,
        a: &SparseMatrix,
        threads: &crate::parallel::Threads,
    ) -> Result<(), SolveError> {
        let update = self.start_numeric(&a.pattern, true)?;
        if self.plan.is_none() {
            return Err(SolveError::Other("no supernodal analysis".into()));
        }
        self.mark_redo(a, update, threads)?;
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        let (Some(plan), SymbolicCholeskyRaw::Supernodal(sn)) = (&self.plan, s.raw()) else {
            return Err(SolveError::Other("no supernodal analysis".into()));
        };
        let len = self.values.len();
        if self.mirror.len() != self.gather.len() {
            // the transposed entries' slots and places (once per analysis)
            let p = &a.pattern;
            let (begin, end, val_ptr) = layout(sn);
            self.mirror.clear();
            self.mirror
                .try_reserve_exact(self.gather.len())
                .map_err(|_| SolveError::OutOfMemory)?;
            let mut original = Vec::new();
            try_zeroed(&mut original, p.n)?;
            for (o, &i) in self.inv.iter().enumerate() {
                original[i] = o;
            }
            // column j of the lower triangle holds slots lower_col_ptr[j]..[j + 1]
            for j in 0..p.n {
                let sj = self.sn_of[j];
                for t in self.lower_col_ptr[j]..self.lower_col_ptr[j + 1] {
                    let (k, i) = (self.gather[t], self.lower_row_idx[t]);
                    if i == j {
                        self.mirror.push((k, usize::MAX));
                        continue;
                    }
                    let Some(m) = p.slot(original[j], original[i]) else {
                        return Err(SolveError::Other("an unsymmetric pattern".into()));
                    };
                    let place = if i < end[sj] {
                        // both in j's supernode: the upper part of its diagonal
                        // block, in L's values
                        let rows = (val_ptr[sj + 1] - val_ptr[sj]) / (end[sj] - begin[sj]);
                        val_ptr[sj] + (i - begin[sj]) * rows + (j - begin[sj])
                    } else {
                        len + plan.place[t]
                    };
                    self.mirror.push((m as u32, place));
                }
            }
        }
        if self.upper.len() != len {
            try_zeroed(&mut self.upper, len)?;
        }
        // each supernode's entries of A placed by the thread that factorises it, just
        // before (the fill zero): L's lower triangle and the diagonal block's upper part,
        // Uᵀ's rows below it (`mirror`)
        let (begin, end, val_ptr) = layout(sn);
        let (gather, mirror, columns, values) =
            (&self.gather, &self.mirror, &self.lower_col_ptr, &a.values);
        let place = |s: usize, ls: &mut [f64], us: &mut [f64]| {
            let base = val_ptr[s];
            ls.iter_mut().for_each(|v| *v = 0.0);
            us.iter_mut().for_each(|v| *v = 0.0);
            let slots = columns[begin[s]]..columns[end[s]];
            for (&t, &k) in plan.place[slots.clone()].iter().zip(&gather[slots.clone()]) {
                ls[t - base] = values[k as usize];
            }
            for &(m, at) in &mirror[slots] {
                if at == usize::MAX {
                    continue;
                }
                let v = values[m as usize];
                if at < len {
                    ls[at - base] = v;
                } else {
                    us[at - len - base] = v;
                }
            }
        };
        super::supernodal::factorize_lu(
            sn,
            plan,
            Schedule {
                split: self.split.as_ref(),
                redo: &self.redo,
            },
            (&mut self.values, &mut self.upper),
            &place,
            &mut self.part_work,
            threads,
        )?;
        self.numeric_count += 1;
        self.lu_held = true;
        self.valid = true;
        Ok(())
    }

    /// Forget the held numeric factorisation; the symbolic analysis of `pattern`, unless
    /// the held one is of the same pattern. Returns whether the held factor may be updated
    /// rather than made anew (a valid one of the same kind, `lu`, on the same analysis).
    fn start_numeric(
        &mut self,
        pattern: &Arc<SparsePattern>,
        lu: bool,
    ) -> Result<bool, SolveError> {
        let held = self.valid && self.lu_held == lu;
        let analyses = self.symbolic_count;
        self.valid = false;
        self.lu_held = false;
        self.analyse_for(pattern)?;
        Ok(held && self.symbolic_count == analyses)
    }

    /// The supernodes to factorise (`redo`): with `update`, those with a column (of P A
    /// Pᵀ, either triangle) where `a` differs from the A of the held factor, and their
    /// ancestors; else all. A supernode's factor depends only on its own columns of A and
    /// on its descendants' factors, so the others' are what a factorisation from scratch
    /// would compute, bit for bit: a Newton iteration whose contacts changed branch in one
    /// corner of a wall factorises that corner's supernodes and the separators above
    /// them, not the wall.
    fn mark_redo(
        &mut self,
        a: &SparseMatrix,
        update: bool,
        threads: &crate::parallel::Threads,
    ) -> Result<(), SolveError> {
        let update = update && self.previous.len() == a.values.len();
        self.redo.iter_mut().for_each(|r| *r = !update);
        if update {
            let p = &a.pattern;
            let (inv, sn_of) = (&self.inv, &self.sn_of);
            // the columns from `c0` (their values from slot `lo` in `previous`): the
            // supernodes of the entries that changed, into `redo`
            let mark = |c0: usize, c1: usize, previous: &mut [f64], redo: &mut [bool]| {
                let lo = p.col_ptr[c0];
                for c in c0..c1 {
                    let col = p.col_ptr[c]..p.col_ptr[c + 1];
                    let prev = &mut previous[col.start - lo..col.end - lo];
                    // most columns are unchanged: compared whole, as bits
                    if same_bits(&a.values[col.clone()], prev) {
                        continue;
                    }
                    let j = inv[c];
                    for (k, pk) in col.clone().zip(prev.iter()) {
                        if a.values[k].to_bits() != pk.to_bits() {
                            let i = inv[p.row_idx[k]];
                            redo[sn_of[i.min(j)]] = true;
                        }
                    }
                    prev.copy_from_slice(&a.values[col]);
                }
            };
            // on two threads from MIN_SPLIT_VALUES entries: the two halves of the columns,
            // the second's marks joined after (the same marks on any number; 40×40 wall,
            // 2026-12-05: 0.50 → 0.26 ms a refresh, 43 refreshes in 12 steps)
            if threads.count() > 1 && p.nnz() >= MIN_SPLIT_VALUES {
                let half = p.n / 2;
                let (p0, p1) = self.previous.split_at_mut(p.col_ptr[half]);
                let mut second = vec![false; self.redo.len()];
                let redo = &mut self.redo;
                threads.join(
                    || mark(0, half, p0, redo),
                    || mark(half, p.n, p1, &mut second),
                );
                for (r, s) in self.redo.iter_mut().zip(second) {
                    *r |= s;
                }
            } else {
                mark(0, p.n, &mut self.previous, &mut self.redo);
            }
            // ancestors after descendants: one pass
            for s in 0..self.redo.len() {
                if self.redo[s] && self.parent[s] != usize::MAX {
                    self.redo[self.parent[s]] = true;
                }
            }
        } else {
            if self.previous.len() != a.values.len() {
                try_zeroed(&mut self.previous, a.values.len())?;
            }
            self.previous.copy_from_slice(&a.values);
        }
        Ok(())
    }

    /// The symbolic analysis of `pattern`, unless the held one is of the same pattern.
    fn analyse_for(&mut self, pattern: &Arc<SparsePattern>) -> Result<(), SolveError> {
        let same = match &self.pattern {
            Some(p) => Arc::ptr_eq(p, pattern) || **p == **pattern,
            None => false,
        };
        if !same || self.symbolic.is_none() {
            self.symbolic = None;
            self.pattern = None;
            self.analyse(pattern)?;
            self.pattern = Some(pattern.clone());
            self.symbolic_count += 1;
        }
        Ok(())
    }

    /// Whether the held factorisation is an LU ([`Cholesky::factorize_lu_on`]).
    pub fn holds_lu(&self) -> bool {
        self.valid && self.lu_held
    }

    /// faer's own numeric factorisation of `a` over the held analysis (the simplicial
    /// one's; in tests, the reference of ours).
    fn faer_numeric(&mut self, a: &SparseMatrix) -> Result<(), SolveError> {
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        ensure(
            &mut self.factor_work,
            s.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        )?;
        if self.lower_values.len() != self.gather.len() {
            try_zeroed(&mut self.lower_values, self.gather.len())?;
        }
        // the lower triangle of P A Pᵀ: every slot of it is one entry of A
        for (l, &k) in self.lower_values.iter_mut().zip(&self.gather) {
            *l = a.values[k as usize];
        }
        let n = a.n();
        let lower = SymbolicSparseColMatRef::new_unsorted_checked(
            n,
            n,
            &self.lower_col_ptr,
            None,
            &self.lower_row_idx,
        );
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        let work = &mut self.factor_work.as_mut().expect("workspace").0;
        s.factorize_numeric_llt::<f64>(
            &mut self.values,
            SparseColMatRef::new(lower, &self.lower_values),
            Side::Lower,
            Default::default(),
            Par::Seq,
            MemStack::new(work),
            Default::default(),
        )
        .map_err(|_| SolveError::NotPositiveDefinite)?;
        Ok(())
    }

    /// Solve A x = b in place with the held factorisation.
    pub fn solve_in_place(&mut self, b: &mut [f64]) -> Result<(), SolveError> {
        self.solve_in_place_on(b, &crate::parallel::Threads::default())
    }

    /// [`Cholesky::solve_in_place`], the two parts of a split factor (`split_tree`) on two
    /// of `threads` when it has more than one (the same result on any number).
    pub fn solve_in_place_on(
        &mut self,
        b: &mut [f64],
        threads: &crate::parallel::Threads,
    ) -> Result<(), SolveError> {
        if !self.valid {
            return Err(SolveError::Other("solve before factorize".into()));
        }
        let s = self.symbolic.as_ref().expect("symbolic analysis");
        let n = b.len();
        for (&i, &v) in self.inv.iter().zip(b.iter()) {
            self.permuted[i] = v;
        }
        let factor = (
            &self.values[..],
            if self.lu_held {
                &self.upper[..]
            } else {
                &self.values[..]
            },
        );
        match s.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => match &self.split {
                Some(split) => solve_split(
                    sn,
                    factor,
                    split,
                    &mut self.permuted,
                    &mut self.below,
                    &mut self.part_work,
                    threads,
                ),
                None => supernodal_solve(sn, factor, &mut self.permuted, &mut self.below),
            },
            SymbolicCholeskyRaw::Simplicial(_) => {
                let l = LltRef::<'_, usize, f64>::new(s, &self.values);
                let work = &mut self.solve_work.as_mut().expect("workspace").0;
                l.solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut self.permuted, n, 1),
                    Par::Seq,
                    MemStack::new(work),
                );
            }
        }
        for (&i, x) in self.inv.iter().zip(b.iter_mut()) {
            *x = self.permuted[i];
        }
        if b.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(SolveError::Singular)
        }
    }
}

/// Where A's entries go in a factor (see [`place_lower`]).
#[derive(Clone, Copy)]
struct Placing<'a> {
    sn: &'a SupernodalSymbolic,
    plan: &'a FactorPlan,
    /// The slot of A of each entry of the lower triangle of P A Pᵀ ...
    gather: &'a [u32],
    /// ... whose column j holds the entries `columns[j]..columns[j + 1]`.
    columns: &'a [usize],
    /// The supernodes to place.
    redo: &'a [bool],
}

/// A's entries of the lower triangle of P A Pᵀ placed in the factor's `values` (at
/// `plan.place`), the rest (the fill) zero, in the supernodes `redo` marks.
fn place_lower(values: &mut [f64], at: Placing, a: &SparseMatrix) {
    let (begin, end, val_ptr) = layout(at.sn);
    for (s, _) in at.redo.iter().enumerate().filter(|r| *r.1) {
        values[val_ptr[s]..val_ptr[s + 1]]
            .iter_mut()
            .for_each(|v| *v = 0.0);
        let slots = at.columns[begin[s]]..at.columns[end[s]];
        for (&t, &k) in at.plan.place[slots.clone()].iter().zip(&at.gather[slots]) {
            values[t] = a.values[k as usize];
        }
    }
}

/// Supernodes at least this wide are solved with faer's dense kernels (on the brick walls'
/// wide supernodes they were faster than the plain loops).
pub(super) const WIDE_SUPERNODE: usize = 16;

/// Supernode `k` of the factor: first column, width, pattern (rows below), rows, values.
type Block<'a> = (usize, usize, &'a [usize], usize, &'a [f64]);

fn block<'a>(sn: &'a SupernodalSymbolic, values: &'a [f64], k: usize) -> Block<'a> {
    let (begin, end, val_ptr) = layout(sn);
    let (b, w) = (begin[k], end[k] - begin[k]);
    let pattern = sn.supernode(k).pattern();
    (
        b,
        w,
        pattern,
        w + pattern.len(),
        &values[val_ptr[k]..val_ptr[k + 1]],
    )
}

pub(super) type SupernodalSymbolic =
    faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky<usize>;

/// The forward step of supernode `k` (L y = b): its diagonal block solved in `x`, then the
/// products for the rows of its pattern (`below`), each handed to `sub(row, value)`.
#[inline(always)]
fn forward_step(
    (b, w, pattern, rows, l): Block,
    x: &mut [f64],
    below: &mut [f64],
    mut sub: impl FnMut(&mut [f64], usize, f64),
) {
    if w >= WIDE_SUPERNODE {
        let (ltop, lbot) = MatRef::from_column_major_slice(l, rows, w).split_at_row(w);
        let mut top = MatMut::from_column_major_slice_mut(&mut x[b..b + w], w, 1);
        triangular_solve::solve_lower_triangular_in_place(ltop, top.rb_mut(), Par::Seq);
        let t = &mut below[..pattern.len()];
        matmul::matmul(
            MatMut::from_column_major_slice_mut(t, pattern.len(), 1),
            Accum::Replace,
            lbot,
            top.rb(),
            1.0,
            Par::Seq,
        );
        for (&r, &tv) in pattern.iter().zip(t.iter()) {
            sub(x, r, tv);
        }
        return;
    }
    let top = &mut x[b..b + w];
    for c in 0..w {
        let col = &l[c * rows..c * rows + w];
        let xc = top[c] / col[c];
        top[c] = xc;
        for (t, &v) in top[c + 1..].iter_mut().zip(&col[c + 1..]) {
            *t -= v * xc;
        }
    }
    let t = &mut below[..pattern.len()];
    t.iter_mut().for_each(|v| *v = 0.0);
    for (c, &xc) in top.iter().enumerate() {
        for (tv, &v) in t.iter_mut().zip(&l[c * rows + w..(c + 1) * rows]) {
            *tv += v * xc;
        }
    }
    for (&r, &tv) in pattern.iter().zip(t.iter()) {
        sub(x, r, tv);
    }
}

/// The backward step of supernode `k` (Lᵀ x = y): its rows of `x` from the rows of its
/// pattern (read) and its diagonal block.
#[inline(always)]
fn backward_step((b, w, pattern, rows, l): Block, x: &mut [f64], below: &mut [f64]) {
    let t = &mut below[..pattern.len()];
    for (tv, &r) in t.iter_mut().zip(pattern) {
        *tv = x[r];
    }
    if w >= WIDE_SUPERNODE {
        let (ltop, lbot) = MatRef::from_column_major_slice(l, rows, w).split_at_row(w);
        let mut top = MatMut::from_column_major_slice_mut(&mut x[b..b + w], w, 1);
        matmul::matmul(
            top.rb_mut(),
            Accum::Add,
            lbot.transpose(),
            MatRef::from_column_major_slice(&t[..], pattern.len(), 1),
            -1.0,
            Par::Seq,
        );
        triangular_solve::solve_upper_triangular_in_place(ltop.transpose(), top, Par::Seq);
        return;
    }
    let top = &mut x[b..b + w];
    for (c, xc) in top.iter_mut().enumerate() {
        *xc -= dot(&l[c * rows + w..(c + 1) * rows], t);
    }
    for c in (0..w).rev() {
        let col = &l[c * rows..c * rows + w];
        let s: f64 = col[c + 1..]
            .iter()
            .zip(&top[c + 1..])
            .map(|(v, xv)| v * xv)
            .sum();
        top[c] = (top[c] - s) / col[c];
    }
}

/// L Lᵀ x = b in place (`x`: b on entry, in the factor's order) with the supernodal
/// factor, sequentially (see [`solve_split`] for two independent parts): each supernode a
/// dense column-major block of its w columns over its w diagonal rows and the rows of its
/// pattern, the diagonal block lower triangular. The same operations as faer's own
/// supernodal solve (a triangular solve on the diagonal block, a product with the block
/// below it), as plain loops over the block's contiguous columns ([`forward_step`],
/// [`backward_step`]; faer's dense kernels for supernodes of [`WIDE_SUPERNODE`] columns or
/// more): faer's solve calls a dense kernel per supernode and pass, whose dispatch
/// dominated on the block models' narrow supernodes (the arch example: 116 supernodes of
/// 1,000 unknowns, 26,000 values; 60 µs a solve, 60% of a GMRES iteration).
///
/// `(values, upper)`: L's values and those of the backward pass — with an LU factor
/// ([`Cholesky::factorize_lu_on`]) Uᵀ's (it solves U x = y), else L's again.
fn supernodal_solve(
    sn: &SupernodalSymbolic,
    (values, upper): (&[f64], &[f64]),
    x: &mut [f64],
    below: &mut [f64],
) {
    for k in 0..sn.n_supernodes() {
        forward_step(block(sn, values, k), x, below, |x, r, t| x[r] -= t);
    }
    for k in (0..sn.n_supernodes()).rev() {
        backward_step(block(sn, upper, k), x, below);
    }
}

/// Two disjoint sets of whole subtrees of the factor's elimination tree (of supernodes) and
/// the rest, "the top": the parts' triangular solves are independent of each other (a
/// supernode's pattern holds only its ancestors), so two threads can do them at once.
#[derive(Debug, Clone, Default)]
pub(super) struct Split {
    /// Each part's supernodes, in increasing order (descendants first).
    pub parts: [Vec<usize>; 2],
    /// The others, in increasing order.
    pub top: Vec<usize>,
    /// Each column's owner: 0 or 1 (a part), 2 (the top).
    owner: Vec<u8>,
}

impl Split {
    /// The owner of column `j`: 0 or 1 (a part), 2 (the top).
    pub fn owner(&self, j: usize) -> u8 {
        self.owner[j]
    }
}

/// Smallest factor (stored values) whose factorisation and solves are split
/// ([`split_tree`]): below it the copies of x and the join cost about what the second
/// thread saves (a 1,000-unknown arch's factor holds 26,000 values, a 10×10 wall's 32,000,
/// a 40×40 wall's 940,000). 8,192 since 2026-12-05 (131,072 before, measured without the
/// pool's keepers, parallel.rs `KEEP_WARM`): the 10×10 wall's factorisation stage 1.0 →
/// 0.75–0.81 ms a step on two threads (see parallel.rs `MIN_PARALLEL` for the whole change).
const MIN_SPLIT_VALUES: usize = 1 << 13;

/// Largest share of the factor's values the top may hold for a split to be worth it.
const SPLIT_TOP_SHARE: f64 = 0.4;

/// Each supernode's first column, its end and the start of its values.
pub(super) fn layout(sn: &SupernodalSymbolic) -> (&[usize], &[usize], &[usize]) {
    (
        sn.supernode_begin(),
        sn.supernode_end(),
        sn.col_ptr_for_val(),
    )
}

/// The supernode of each column of the factor (allocated fallibly).
pub(super) fn supernode_of(sn: &SupernodalSymbolic) -> Result<Vec<usize>, SolveError> {
    let (begin, end) = (sn.supernode_begin(), sn.supernode_end());
    let mut of = Vec::new();
    try_zeroed(&mut of, end.last().copied().unwrap_or(0))?;
    for k in 0..sn.n_supernodes() {
        of[begin[k]..end[k]].iter_mut().for_each(|s| *s = k);
    }
    Ok(of)
}

/// The split of the elimination tree (see [`Split`]) with the parts' values balanced within
/// about 10%: from the roots, the heaviest subtree is moved to the top (its children become
/// candidates) until the candidates share out evenly (largest first, to the lighter part).
/// `None` if the top would hold more than [`SPLIT_TOP_SHARE`] of the values (or the tree is
/// a chain). Depends only on the symbolic analysis (`parent`: each supernode's parent,
/// `usize::MAX` for a root).
fn split_tree(sn: &SupernodalSymbolic, parent: &[usize]) -> Option<Split> {
    let ns = sn.n_supernodes();
    let (begin, end, val_ptr) = layout(sn);
    let n = end.last().copied().unwrap_or(0);
    let parent: Vec<Option<usize>> = parent
        .iter()
        .map(|&p| (p != usize::MAX).then_some(p))
        .collect();
    let mut children = vec![Vec::new(); ns];
    let mut work: Vec<f64> = (0..ns)
        .map(|k| (val_ptr[k + 1] - val_ptr[k]) as f64)
        .collect();
    let total: f64 = work.iter().sum();
    for k in 0..ns {
        if let Some(p) = parent[k] {
            // a parent comes after its children: their subtree work is complete here
            children[p].push(k);
            work[p] += work[k];
        }
    }
    let mut candidates: Vec<usize> = (0..ns).filter(|&k| parent[k].is_none()).collect();
    let mut top: Vec<usize> = Vec::new();
    let mut top_work = 0.0;
    let assign = |cands: &[usize]| {
        let mut sorted = cands.to_vec();
        sorted.sort_by(|a, b| work[*b].total_cmp(&work[*a]).then(a.cmp(b)));
        let mut bins = [(0.0, Vec::new()), (0.0, Vec::new())];
        for k in sorted {
            let i = usize::from(bins[1].0 < bins[0].0);
            bins[i].0 += work[k];
            bins[i].1.push(k);
        }
        bins
    };
    loop {
        let bins = assign(&candidates);
        let (a, b) = (bins[0].0, bins[1].0);
        if a.max(b) <= 1.1 * 0.5 * (a + b) && !bins[0].1.is_empty() && !bins[1].1.is_empty() {
            if top_work > SPLIT_TOP_SHARE * total {
                return None;
            }
            let mut owner = vec![2u8; n];
            let mut parts = [Vec::new(), Vec::new()];
            for (p, (_, roots)) in bins.iter().enumerate() {
                let mut stack = roots.clone();
                while let Some(k) = stack.pop() {
                    parts[p].push(k);
                    owner[begin[k]..end[k]]
                        .iter_mut()
                        .for_each(|o| *o = p as u8);
                    stack.extend(&children[k]);
                }
                parts[p].sort_unstable();
            }
            top.sort_unstable();
            return Some(Split { parts, top, owner });
        }
        // the heaviest candidate goes to the top
        let (i, &k) = candidates
            .iter()
            .enumerate()
            .max_by(|x, y| work[*x.1].total_cmp(&work[*y.1]).then(y.1.cmp(x.1)))?;
        candidates.swap_remove(i);
        top.push(k);
        top_work += (val_ptr[k + 1] - val_ptr[k]) as f64;
        if top_work > SPLIT_TOP_SHARE * total || (candidates.is_empty() && children[k].is_empty()) {
            return None;
        }
        candidates.extend(&children[k]);
    }
}

/// `f(0, w0)` and `f(1, w1)`: at once on two threads when `threads` has them, else one
/// after the other.
pub(super) fn on_both(
    threads: &crate::parallel::Threads,
    f: impl Fn(usize, &mut PartWork) + Sync,
    w0: &mut PartWork,
    w1: &mut PartWork,
) {
    threads.join(|| f(0, w0), || f(1, w1));
}

/// Per-part workspaces of [`solve_split`]: a copy of x, the contributions to the top's
/// rows, and the products below a supernode.
#[derive(Default)]
pub(super) struct PartWork {
    x: Vec<f64>,
    to_top: Vec<f64>,
    below: Vec<f64>,
    /// The numeric factorisation's workspace ([`super::supernodal`]).
    pub factor: FactorWork,
    /// The LU's updates of the top's supernodes from this part's ([`super::supernodal`]).
    pub top_sums: Vec<f64>,
}

/// [`supernodal_solve`] over a [`Split`]: the two parts' forward steps (each on its own copy
/// of x, its contributions to the top's rows summed apart), the top's rows then less the
/// part 0's and the part 1's sums, the top forward and backward, the parts' backward steps
/// (each on its own copy). The same operations in the same order on one thread and on two:
/// the result does not depend on the thread count.
fn solve_split(
    sn: &SupernodalSymbolic,
    (values, upper): (&[f64], &[f64]),
    split: &Split,
    x: &mut [f64],
    below: &mut [f64],
    work: &mut [PartWork; 2],
    threads: &crate::parallel::Threads,
) {
    let owner = &split.owner;
    let forward = |p: usize, w: &mut PartWork| {
        w.x.copy_from_slice(x);
        for &k in &split.top {
            for r in sn.supernode_begin()[k]..sn.supernode_end()[k] {
                w.to_top[r] = 0.0;
            }
        }
        let PartWork {
            x: px,
            to_top,
            below,
            ..
        } = w;
        for &k in &split.parts[p] {
            forward_step(block(sn, values, k), px, below, |x, r, t| {
                if owner[r] as usize == p {
                    x[r] -= t;
                } else {
                    to_top[r] += t;
                }
            });
        }
    };
    let [w0, w1] = work;
    on_both(threads, forward, w0, w1);
    for (r, xr) in x.iter_mut().enumerate() {
        match owner[r] {
            0 => *xr = w0.x[r],
            1 => *xr = w1.x[r],
            _ => *xr = *xr - w0.to_top[r] - w1.to_top[r],
        }
    }
    for &k in &split.top {
        forward_step(block(sn, values, k), x, below, |x, r, t| x[r] -= t);
    }
    for &k in split.top.iter().rev() {
        backward_step(block(sn, upper, k), x, below);
    }
    let backward = |p: usize, w: &mut PartWork| {
        w.x.copy_from_slice(x);
        for &k in split.parts[p].iter().rev() {
            backward_step(block(sn, upper, k), &mut w.x, &mut w.below);
        }
    };
    on_both(threads, backward, w0, w1);
    for (r, xr) in x.iter_mut().enumerate() {
        match owner[r] {
            0 => *xr = w0.x[r],
            1 => *xr = w1.x[r],
            _ => {}
        }
    }
}

#[cfg(test)]
fn solve_residual(c: &mut Cholesky, a: &SparseMatrix, b: &[f64]) -> f64 {
    let mut x = b.to_vec();
    c.solve_in_place(&mut x).unwrap();
    let mut y = vec![0.0; b.len()];
    a.mul_vec(&x, &mut y);
    y.iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
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
    fn the_ordering_keeps_a_covers_unknowns_together() {
        // a chain of 2-unknown nodes plus one lone unknown: columns 2k, 2k+1 have the
        // same rows and stay consecutive; the ordering is a permutation
        let nodes = 40;
        let n = 2 * nodes + 1;
        let groups: Vec<Vec<usize>> = (0..nodes - 1)
            .map(|k| vec![2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3])
            .chain(std::iter::once(vec![0, 1, n - 1]))
            .collect();
        let p = SparsePattern::from_groups(n, groups.iter().map(|g| &g[..]));
        let mut inv = vec![0; n];
        amd_ordering(&p, &mut inv).unwrap();
        let mut seen = vec![false; n];
        for &i in &inv {
            assert!(!seen[i]);
            seen[i] = true;
        }
        for k in 0..nodes {
            assert_eq!(inv[2 * k + 1], inv[2 * k] + 1, "node {k}");
        }
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
            let err = solve_residual(&mut c, &a2, &b);
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
mod solve_tests {
    use super::*;

    /// A 2-D grid of blocks, each a dense group of `dofs` unknowns coupled to its right and
    /// upper neighbours (like covers of blocks in contact), diagonally dominant.
    fn block_grid(nx: usize, ny: usize, dofs: usize) -> SparseMatrix {
        let n = nx * ny * dofs;
        let at = |i: usize, j: usize| (j * nx + i) * dofs;
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let own: Vec<usize> = (at(i, j)..at(i, j) + dofs).collect();
                for (di, dj) in [(1, 0), (0, 1)] {
                    if i + di < nx && j + dj < ny {
                        let mut g = own.clone();
                        g.extend(at(i + di, j + dj)..at(i + di, j + dj) + dofs);
                        groups.push(g);
                    }
                }
                groups.push(own);
            }
        }
        let p = Arc::new(SparsePattern::from_groups(n, groups.iter().map(|g| &g[..])));
        let mut a = SparseMatrix::zeros(p.clone());
        for c in 0..n {
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let r = p.row_idx[k];
                if r > c {
                    let v = -(((r * 7 + c * 13) % 10) as f64 + 1.0) / 40.0;
                    a.add(r, c, v);
                    a.add(c, r, v);
                }
            }
        }
        for c in 0..n {
            let off: f64 = (p.col_ptr[c]..p.col_ptr[c + 1])
                .filter(|&k| p.row_idx[k] != c)
                .map(|k| a.values[k].abs())
                .sum();
            a.add(c, c, off + 1.0 + (c % 3) as f64);
        }
        a
    }

    /// The plain-loop supernodal solve and faer's dense kernels (wide supernodes) give the
    /// solution of A x = b: narrow supernodes (2 unknowns a block) and wide ones (24).
    /// A grid's factor splits into two parts of balanced values with a small top, and the
    /// split solve gives the sequential one's solution, bit for bit on one thread and two.
    #[test]
    fn the_split_solve_is_the_sequential_one_on_one_thread_and_two() {
        let a = block_grid(90, 60, 2);
        let n = a.n();
        let mut c = Cholesky::default();
        c.factorize(&a).unwrap();
        assert!(c.factor_len() >= MIN_SPLIT_VALUES, "{}", c.factor_len());
        let SymbolicCholeskyRaw::Supernodal(sn) = c.symbolic.as_ref().unwrap().raw() else {
            panic!("supernodal")
        };
        let split = c.split.clone().expect("a grid's tree splits");
        let vals = |ks: &[usize]| -> usize {
            ks.iter()
                .map(|&k| sn.col_ptr_for_val()[k + 1] - sn.col_ptr_for_val()[k])
                .sum()
        };
        let (p0, p1, top) = (
            vals(&split.parts[0]),
            vals(&split.parts[1]),
            vals(&split.top),
        );
        eprintln!("split: parts {p0} and {p1} values, top {top}");
        assert_eq!(p0 + p1 + top, c.factor_len());
        assert!(
            p0.max(p1) as f64 <= 1.1 * 0.5 * (p0 + p1) as f64,
            "{p0} {p1}"
        );
        assert!(
            top as f64 <= SPLIT_TOP_SHARE * c.factor_len() as f64,
            "{top}"
        );
        let b: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.0) / 3.0).collect();
        let mut one = b.clone();
        c.solve_in_place(&mut one).unwrap();
        let mut two = b.clone();
        let threads = crate::parallel::Threads::new(2).unwrap();
        c.solve_in_place_on(&mut two, &threads).unwrap();
        assert_eq!(one, two);
        let mut seq: Vec<f64> = vec![0.0; n];
        for (&i, &v) in c.inv.iter().zip(&b) {
            seq[i] = v;
        }
        let mut below = vec![0.0; n];
        let SymbolicCholeskyRaw::Supernodal(sn) = c.symbolic.as_ref().unwrap().raw() else {
            panic!("supernodal")
        };
        supernodal_solve(sn, (&c.values, &c.values), &mut seq, &mut below);
        for (&i, &v) in c.inv.iter().zip(&one) {
            assert!(
                (seq[i] - v).abs() <= 1e-12 * v.abs().max(1.0),
                "{} {v}",
                seq[i]
            );
        }
        assert!(solve_residual(&mut c, &a, &b) < 1e-11);
    }

    /// Our numeric factorisation (supernodal.rs) gives faer's factor to round-off, on
    /// narrow supernodes (2 unknowns a block), wide ones (24), whole or split in two parts;
    /// bit for bit the same on one thread and two; and a matrix that is not positive
    /// definite is said to be so (a narrow panel and a wide one).
    #[test]
    fn our_factor_is_faers_and_the_same_on_one_thread_and_two() {
        let two = crate::parallel::Threads::new(2).unwrap();
        for (nx, ny, dofs, split) in [
            (12, 9, 2, false),
            (2, 2, 24, false),
            (6, 5, 24, true),
            (90, 60, 2, true),
        ] {
            let a = block_grid(nx, ny, dofs);
            let mut c = Cholesky::default();
            c.factorize(&a).unwrap();
            assert_eq!(c.split.is_some(), split, "{nx}x{ny}x{dofs}");
            let ours = c.values.clone();
            c.factorize_on(&a, &two).unwrap();
            assert_eq!(ours, c.values, "{nx}x{ny}x{dofs}: one thread and two");
            c.faer_numeric(&a).unwrap();
            let big = c.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            // the factor's entries: each supernode's columns from their diagonal row down
            // (above it, faer's dense kernel leaves its workings)
            let SymbolicCholeskyRaw::Supernodal(sn) = c.symbolic.as_ref().unwrap().raw() else {
                panic!("supernodal")
            };
            let mut diff = 0.0f64;
            for k in 0..sn.n_supernodes() {
                let (_, w, _, rows, _) = block(sn, &c.values, k);
                let at = sn.col_ptr_for_val()[k];
                for j in 0..w {
                    for i in j..rows {
                        let t = at + j * rows + i;
                        diff = diff.max((ours[t] - c.values[t]).abs());
                    }
                }
            }
            assert!(diff <= 1e-13 * big, "{nx}x{ny}x{dofs}: {diff} of {big}");
            c.factorize_on(&a, &two).unwrap();
            let b: Vec<f64> = (0..a.n()).map(|i| (i as f64 * 0.3).cos()).collect();
            assert!(solve_residual(&mut c, &a, &b) < 1e-11);
            // indefinite: the last unknown's diagonal (in the last, widest supernode) and
            // the first's made negative in turn
            for i in [a.n() - 1, 0] {
                let mut m = a.clone();
                let k = m.pattern.slot(i, i).unwrap();
                m.values[k] = -1.0;
                for th in [&crate::parallel::Threads::default(), &two] {
                    assert!(
                        matches!(c.factorize_on(&m, th), Err(SolveError::NotPositiveDefinite)),
                        "{nx}x{ny}x{dofs}: unknown {i}"
                    );
                    assert!(!c.is_valid());
                    // a failure does not outlive its factorisation
                    c.factorize_on(&a, th).unwrap();
                    assert!(solve_residual(&mut c, &a, &b) < 1e-11);
                }
            }
        }
    }

    /// The LU without pivoting on the Cholesky analysis (supernodal.rs `factorize_lu`)
    /// solves an unsymmetric A with a symmetric pattern (a grid made unsymmetric, as
    /// sliding contacts make the tangent) to round-off: narrow supernodes, wide ones (the
    /// diagonal blocks' LU by halves from 32 columns), a factor split in two parts; the
    /// same bit for bit on one thread and two; a Cholesky factorisation after it is a
    /// Cholesky one again; a negative pivot is no failure, a zero one is.
    #[test]
    fn the_lu_solves_an_unsymmetric_matrix_on_one_thread_and_two() {
        let two = crate::parallel::Threads::new(2).unwrap();
        for (nx, ny, dofs) in [(12, 9, 2), (6, 5, 24), (3, 3, 40), (90, 60, 2)] {
            let sym = block_grid(nx, ny, dofs);
            let mut a = sym.clone();
            let p = a.pattern.clone();
            for c in 0..a.n() {
                for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                    let r = p.row_idx[k];
                    if r != c {
                        a.values[k] += (((r * 3 + c * 5) % 7) as f64 - 3.0) / 60.0;
                    }
                }
            }
            let mut c = Cholesky::default();
            c.factorize_lu_on(&a, &Default::default()).unwrap();
            assert!(c.holds_lu());
            if dofs == 40 {
                let SymbolicCholeskyRaw::Supernodal(sn) = c.symbolic.as_ref().unwrap().raw() else {
                    panic!("supernodal")
                };
                let widest = (0..sn.n_supernodes())
                    .map(|k| sn.supernode_end()[k] - sn.supernode_begin()[k])
                    .max()
                    .unwrap();
                assert!(widest >= 2 * WIDE_SUPERNODE, "{widest}");
            }
            if (nx, ny) == (90, 60) {
                // the top of the split tree has a supernode whose updates are made in two
                // halves of its rows (supernodal.rs `lu_top_supernode`)
                let SymbolicCholeskyRaw::Supernodal(sn) = c.symbolic.as_ref().unwrap().raw() else {
                    panic!("supernodal")
                };
                let (begin, end, val_ptr) = layout(sn);
                let split = c.split.as_ref().expect("a split tree");
                assert!(split
                    .top
                    .iter()
                    .any(|&s| (val_ptr[s + 1] - val_ptr[s]) / (end[s] - begin[s])
                        >= super::super::supernodal::SPLIT_TOP_ROWS));
            }
            let (l, u) = (c.values.clone(), c.upper.clone());
            c.factorize_lu_on(&a, &two).unwrap();
            assert_eq!(
                (l, u),
                (c.values.clone(), c.upper.clone()),
                "{nx}x{ny}x{dofs}"
            );
            let b: Vec<f64> = (0..a.n()).map(|i| (i as f64 * 0.3).cos()).collect();
            let mut one = b.clone();
            c.solve_in_place(&mut one).unwrap();
            let mut twice = b.clone();
            c.solve_in_place_on(&mut twice, &two).unwrap();
            assert_eq!(one, twice);
            let err = solve_residual(&mut c, &a, &b);
            assert!(err < 1e-11, "{nx}x{ny}x{dofs}: {err}");
            // not the symmetric matrix's solution: the unsymmetric part was read
            assert!(solve_residual(&mut c, &sym, &b) > 1e-6);
            c.factorize(&sym).unwrap();
            assert!(!c.holds_lu());
            assert!(solve_residual(&mut c, &sym, &b) < 1e-11);
            // a negative pivot is no failure (an indefinite symmetric part): the last
            // unknown's diagonal made negative
            let last = a.n() - 1;
            let mut m = a.clone();
            m.values[m.pattern.slot(last, last).unwrap()] = -1.0;
            c.factorize_lu_on(&m, &two).unwrap();
            let err = solve_residual(&mut c, &m, &b);
            assert!(err < 1e-10, "{nx}x{ny}x{dofs}: {err}");
            // a zero pivot is: the last unknown's row and column zero
            for col in 0..m.n() {
                for k in p.col_ptr[col]..p.col_ptr[col + 1] {
                    if col == last || p.row_idx[k] == last {
                        m.values[k] = 0.0;
                    }
                }
            }
            for th in [&crate::parallel::Threads::default(), &two] {
                assert!(matches!(
                    c.factorize_lu_on(&m, th),
                    Err(SolveError::Singular)
                ));
                assert!(!c.is_valid());
            }
            c.factorize_on(&sym, &two).unwrap();
            assert!(solve_residual(&mut c, &sym, &b) < 1e-11);
        }
    }

    /// A held factor updated supernode by supernode (`mark_redo`: the supernodes whose A
    /// changed and their ancestors) is the factor made from scratch, bit for bit: Cholesky
    /// and LU, narrow and wide supernodes, a split factor on one thread and two; a change
    /// in one corner redoes a part of the supernodes only, a change of kind (Cholesky after
    /// LU) or an invalidated factor all of them.
    #[test]
    fn an_updated_factor_is_the_factor_made_anew() {
        let two = crate::parallel::Threads::new(2).unwrap();
        for (nx, ny, dofs) in [(12, 9, 2), (6, 5, 24), (90, 60, 2)] {
            let a = block_grid(nx, ny, dofs);
            let p = a.pattern.clone();
            let mut unsym = a.clone();
            for c in 0..a.n() {
                for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                    if p.row_idx[k] != c {
                        unsym.values[k] += (((p.row_idx[k] * 3 + c * 5) % 7) as f64 - 3.0) / 60.0;
                    }
                }
            }
            // the first unknown's coupling to its neighbour (symmetric: the Cholesky
            // factor reads one triangle) and its diagonal
            let changed = |m: &SparseMatrix| {
                let mut m = m.clone();
                for (r, c, dv) in [(0, 0, 0.5), (0, 1, 0.01), (1, 0, 0.01)] {
                    if let Some(k) = p.slot(r, c) {
                        m.values[k] += dv;
                    }
                }
                m
            };
            for th in [&crate::parallel::Threads::default(), &two] {
                for lu in [false, true] {
                    let (m0, m1) = if lu {
                        (unsym.clone(), changed(&unsym))
                    } else {
                        (a.clone(), changed(&a))
                    };
                    let factorize = |c: &mut Cholesky, m: &SparseMatrix| match lu {
                        true => c.factorize_lu_on(m, th).unwrap(),
                        false => c.factorize_on(m, th).unwrap(),
                    };
                    let mut held = Cholesky::default();
                    factorize(&mut held, &m0);
                    assert!(held.redo.iter().all(|&r| r));
                    factorize(&mut held, &m1);
                    let redone = held.redo.iter().filter(|&&r| r).count();
                    assert!(redone >= 1 && redone < held.redo.len(), "{redone}");
                    let mut fresh = Cholesky::default();
                    factorize(&mut fresh, &m1);
                    assert_eq!(held.values, fresh.values, "{nx}x{ny}x{dofs} lu {lu}");
                    assert_eq!(held.upper, fresh.upper, "{nx}x{ny}x{dofs} lu {lu}");
                    let b: Vec<f64> = (0..a.n()).map(|i| (i as f64 * 0.7).sin()).collect();
                    assert!(solve_residual(&mut held, &m1, &b) < 1e-10);
                    // the same matrix again: nothing to redo
                    factorize(&mut held, &m1);
                    assert!(held.redo.iter().all(|&r| !r));
                    assert_eq!(held.values, fresh.values);
                    // the last unknown's coupling too (elsewhere in the tree: a part that
                    // redoes nothing keeps its sums of the top's updates), then back
                    let n = a.n();
                    let mut m2 = m1.clone();
                    for (r, c, dv) in [
                        (n - 1, n - 1, 0.5),
                        (n - 1, n - 2, 0.01),
                        (n - 2, n - 1, 0.01),
                    ] {
                        if let Some(k) = p.slot(r, c) {
                            m2.values[k] += dv;
                        }
                    }
                    for m in [&m2, &m1, &m2] {
                        factorize(&mut held, m);
                        let mut fresh = Cholesky::default();
                        factorize(&mut fresh, m);
                        assert_eq!(held.values, fresh.values, "{nx}x{ny}x{dofs} lu {lu}");
                        assert_eq!(held.upper, fresh.upper, "{nx}x{ny}x{dofs} lu {lu}");
                    }
                    factorize(&mut held, &m1);
                    // invalidated, or of the other kind: made anew
                    held.invalidate();
                    factorize(&mut held, &m0);
                    assert!(held.redo.iter().all(|&r| r));
                }
                let mut c = Cholesky::default();
                c.factorize_lu_on(&unsym, th).unwrap();
                c.factorize_on(&a, th).unwrap();
                assert!(c.redo.iter().all(|&r| r));
            }
        }
    }

    #[test]
    fn supernodal_solve_solves_narrow_and_wide_supernodes() {
        for (nx, ny, dofs) in [(12, 9, 2), (6, 5, 24), (30, 1, 6)] {
            let a = block_grid(nx, ny, dofs);
            let n = a.n();
            let mut c = Cholesky::default();
            c.factorize(&a).unwrap();
            let SymbolicCholeskyRaw::Supernodal(sn) = c.symbolic.as_ref().unwrap().raw() else {
                panic!("supernodal")
            };
            let widest = (0..sn.n_supernodes())
                .map(|k| sn.supernode_end()[k] - sn.supernode_begin()[k])
                .max()
                .unwrap();
            if dofs == 24 {
                assert!(widest >= WIDE_SUPERNODE, "{widest}");
            }
            let b: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.0) / 3.0).collect();
            let err = solve_residual(&mut c, &a, &b);
            assert!(err < 1e-11, "{nx}x{ny}x{dofs}: {err}");
        }
    }
}

#[cfg(test)]
mod ordering_tests {
    use super::*;

    /// The ordering is faer's own AMD: the factor has as many values as faer's analysis of
    /// the unpermuted pattern gives (a 2-D grid of 5-point stencils with a few long-range
    /// couplings, like contacts between blocks).
    #[test]
    fn the_factor_is_as_large_as_faers_own_analysis_makes_it() {
        let m = 30;
        let n = m * m;
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for i in 0..m {
            for j in 0..m {
                let k = i * m + j;
                if j + 1 < m {
                    groups.push(vec![k, k + 1]);
                }
                if i + 1 < m {
                    groups.push(vec![k, k + m]);
                }
            }
        }
        for k in (0..n).step_by(37) {
            groups.push(vec![k, (k * 7 + 11) % n]);
        }
        let p = Arc::new(SparsePattern::from_groups(
            n,
            groups.iter().map(|g| g.as_slice()),
        ));
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &p.col_ptr, None, &p.row_idx);
        let faer_own = factorize_symbolic_cholesky(
            sym,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .unwrap();
        let mut a = SparseMatrix::zeros(p.clone());
        for g in &groups {
            a.add(g[0], g[0], 1.0);
            a.add(g[1], g[1], 1.0);
            a.add(g[0], g[1], -1.0);
            a.add(g[1], g[0], -1.0);
        }
        for i in 0..n {
            a.add(i, i, 0.01 * (1.0 + (i % 7) as f64));
        }
        let mut c = Cholesky::default();
        c.factorize(&a).unwrap();
        assert_eq!(c.factor_len(), faer_own.len_val());
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let err = solve_residual(&mut c, &a, &b);
        assert!(err < 1e-9, "{err}");
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
