//! The numeric supernodal Cholesky factorisation over faer's symbolic analysis, ours so that
//! two threads can factorise the two independent parts of the elimination tree at once.
//!
//! Left-looking, as faer's own (`factorize_supernodal_numeric_llt`), on the same storage:
//! supernode s is a dense column-major block of its w columns over its w diagonal rows and
//! the rows of its pattern. For each s in order: its entries of P A Pᵀ (placed by a map the
//! analysis made, [`FactorPlan::place`]); minus the update of every descendant d whose
//! pattern meets s's columns (`L_d[rows ≥ s] · L_d[rows of s]ᵀ`, in increasing d, scattered
//! through the local row numbers of s); then the panel's own Cholesky (the diagonal block
//! factorised, the rows below divided by its transpose).
//!
//! A supernode's descendants lie in its own subtree, so the two parts of a split tree
//! (cholesky.rs `split_tree`: whole subtrees) are factorised by two threads with nothing
//! shared but the finished factor they read, and then the top, whose descendants are in
//! both. For the LU, each part's thread then sums its part's updates of the top's
//! supernodes apart (a part's `top_sums`), and the top adds both sums to its A entries
//! before the updates of its own descendants — by two threads again for a large supernode,
//! each updating half of its rows (`lu_top_supernode`). The sums are in a fixed order
//! whatever the thread count (A + part 0's + part 1's, then the top's own, each in
//! increasing order), so that the factor is the same on one thread and on two. Each supernode's operations and their order are the same whichever thread does
//! them: the factor does not depend on the thread count, bit for bit.
//!
//! For the same reason a held factor can be **updated**: only the supernodes whose columns
//! of A changed and their ancestors are factorised again (cholesky.rs
//! `Cholesky::mark_redo`), the others' values are those a factorisation from scratch would
//! compute, bit for bit. Between the Newton iterations of a step only the contacts that
//! changed branch change A: measured (2026-12-04, one thread, alternated, results
//! identical to the byte), the factorisation stage of the 40×40 wall's 12 steps 1.363 →
//! 0.998 s (minima of 3), the 20×20 wall's 0.261 → 0.207 s, the arch example's 7.08 → 5.40
//! s, the shaken slope's 11.9 → 10.3 s; the tunnel's and the static jointed slope's within
//! noise (one Newton iteration a step, or a regularisation that changes every value).
//!
//! Why an update still costs most of a factorisation on the brick walls, and why another
//! scheme of updates was not built (2026-12-05, a flop model counted on the 20×20 wall's
//! refreshes, steps 11 and 12: each supernode's panel w²(w + p) and each descendant's
//! update of it w_d p_d w_s, w its columns, p its pattern's rows): the Newton iterations
//! of a step redid 858 (the first, every supernode), 364, 229, 148, 57 and 23 of the 858
//! supernodes, whose ancestors hold most of the work (the top's separators), and a
//! redone supernode takes the updates of all its descendants, redone or not: 1.00, 0.97,
//! 0.96, 0.94, 0.84 and 0.73 of a whole factorisation (5.44 a step; timed, 0.55–0.65 for
//! the later ones). Even the redone supernodes' own panels are 0.13–0.25 of it. A
//! multifrontal factorisation keeping every supernode's update matrix (so that a redone
//! one adds its unchanged children's as they were, and computes only its own front:
//! w²(w + p) + w p²) would cost 1.00, 0.92, 0.87, 0.81, 0.64 and 0.46 (4.70 a step, 14%
//! less, about 6% of the step, for a second engine and the update matrices' memory);
//! subtracting the old updates of the redone descendants and adding their new ones
//! (twice the products, but only theirs) 1.75, 1.52, 1.36, 1.25, 0.89 and 0.52. The
//! changes of a wall's Newton iteration are spread over the whole wall, and every one of
//! them reaches the top.
//!
//! Kernels: each update by faer's dense product into a dense block, then scattered
//! (measured against plain loops column by column for descendants narrower than 16
//! columns: the arch's tangent 0.25 → 0.20 ms, a 20×20 wall's 2.4 → 1.8 ms, a 40×40 wall's
//! 15.7 → 11.2 ms, minima of 40 interleaved); the panel of a supernode narrower than
//! `WIDE_SUPERNODE` columns by plain loops (left-looking by columns: the same time as
//! faer's kernels within the machine's noise), a wider one by faer's `cholesky_in_place`
//! and a triangular solve.

use super::cholesky::{
    layout, on_both, try_zeroed, PartWork, Split, SupernodalSymbolic, WIDE_SUPERNODE,
};
use super::linear::SolveError;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::{matmul, triangular_solve};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

/// Columns of a supernode updated by one dense product (bounds the workspace: a
/// supernode's longest pattern times this; and leaves out most of the product above the
/// diagonal).
const UPDATE_COLUMNS: usize = 32;

/// What the numeric factorisation needs beyond faer's symbolic analysis (made once per
/// analysis).
#[derive(Debug, Default)]
pub(super) struct FactorPlan {
    /// For each slot of the lower triangle of P A Pᵀ (cholesky.rs `lower_*`), its position
    /// in the factor's values.
    pub place: Vec<usize>,
    /// The supernodes that update supernode s: `updates[update_ptr[s]..update_ptr[s + 1]]`,
    /// in increasing order.
    update_ptr: Vec<usize>,
    updates: Vec<u32>,
    /// The widest supernode and the longest pattern: the workspaces' sizes.
    widest: usize,
    longest: usize,
}

/// One thread's workspace of the factorisation.
#[derive(Default)]
pub(super) struct FactorWork {
    /// Local row numbers in the supernode being factorised, by global row.
    local: Vec<usize>,
    /// The local rows of one update.
    rel: Vec<usize>,
    /// One update's dense column or block.
    block: Vec<f64>,
    /// faer's workspace for a wide diagonal block.
    stack: Option<MemBuffer>,
    /// A panel of this factorisation was not positive definite (reset at the start of
    /// every factorisation).
    failed: bool,
}

impl FactorPlan {
    /// The plan for `sn`, the supernodal analysis of the lower triangle (`lower_ptr`,
    /// `lower_rows`: column pointers and rows) of P A Pᵀ, whose column j is in supernode
    /// `sn_of[j]`.
    pub fn new(
        sn: &SupernodalSymbolic,
        sn_of: &[usize],
        lower_ptr: &[usize],
        lower_rows: &[usize],
    ) -> Result<FactorPlan, SolveError> {
        let ns = sn.n_supernodes();
        let (begin, end, val_ptr) = layout(sn);
        let n = end.last().copied().unwrap_or(0);
        // the entries' places: column j of supernode s, row i at its local row
        let mut place = Vec::new();
        try_zeroed(&mut place, lower_rows.len())?;
        let mut local = Vec::new();
        try_zeroed(&mut local, n)?;
        let mut longest = 0;
        for s in 0..ns {
            let (b, e) = (begin[s], end[s]);
            let w = e - b;
            let pattern = sn.supernode(s).pattern();
            longest = longest.max(pattern.len());
            for (i, &r) in pattern.iter().enumerate() {
                local[r] = w + i;
            }
            let rows = w + pattern.len();
            for j in b..e {
                for t in lower_ptr[j]..lower_ptr[j + 1] {
                    let i = lower_rows[t];
                    let li = if i < e { i - b } else { local[i] };
                    place[t] = val_ptr[s] + (j - b) * rows + li;
                }
            }
        }
        // the updates: d updates every supernode its pattern meets
        let mut count = vec![0usize; ns + 1];
        let each = |f: &mut dyn FnMut(usize, usize)| {
            for d in 0..ns {
                let mut last = usize::MAX;
                for &r in sn.supernode(d).pattern() {
                    let s = sn_of[r];
                    if s != last {
                        f(d, s);
                        last = s;
                    }
                }
            }
        };
        each(&mut |_, s| count[s + 1] += 1);
        for s in 0..ns {
            count[s + 1] += count[s];
        }
        let mut updates = Vec::new();
        try_zeroed(&mut updates, count[ns])?;
        let mut next = count[..ns].to_vec();
        each(&mut |d, s| {
            updates[next[s]] = d as u32;
            next[s] += 1;
        });
        let widest = (0..ns).map(|k| end[k] - begin[k]).max().unwrap_or(0);
        Ok(FactorPlan {
            place,
            update_ptr: count,
            updates,
            widest,
            longest,
        })
    }

    /// Size `w` for this plan.
    pub fn prepare(&self, w: &mut FactorWork, n: usize) -> Result<(), SolveError> {
        try_zeroed(&mut w.local, n)?;
        try_zeroed(&mut w.rel, self.longest)?;
        try_zeroed(&mut w.block, self.longest * UPDATE_COLUMNS)?;
        let req = faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<f64>(
            self.widest,
            Par::Seq,
            Default::default(),
        );
        let have = w.stack.as_ref().map_or(0, |b| b.len());
        if have < req.size_bytes() || w.stack.is_none() {
            w.stack = None;
            w.stack = Some(
                MemBuffer::try_new(req.and(StackReq::new::<u8>(64)))
                    .map_err(|_| SolveError::OutOfMemory)?,
            );
        }
        Ok(())
    }
}

/// The factor's values, shared by the threads of one factorisation: each supernode's block
/// is written by the one thread that factorises it, and read (by the factorisations of its
/// ancestors) only after it is finished.
struct Values(*mut f64, usize);
// SAFETY: see the type's docs; the parts' threads write disjoint supernodes and read only
// their own finished descendants (the top is factorised after both parts have joined).
unsafe impl Sync for Values {}
unsafe impl Send for Values {}

impl Values {
    /// Supernode blocks [a, b) of the values.
    ///
    /// SAFETY: no other thread writes [a, b) during the borrow.
    unsafe fn get(&self, a: usize, b: usize) -> &[f64] {
        debug_assert!(a <= b && b <= self.1);
        std::slice::from_raw_parts(self.0.add(a), b - a)
    }
    /// SAFETY: no other reference to [a, b) exists during the borrow.
    #[allow(clippy::mut_from_ref)]
    unsafe fn get_mut(&self, a: usize, b: usize) -> &mut [f64] {
        debug_assert!(a <= b && b <= self.1);
        std::slice::from_raw_parts_mut(self.0.add(a), b - a)
    }
}

/// Factorise into `values` (the A entries already placed, the rest zero): the supernodes of
/// `split`'s parts on two of `threads` if it has two, then the top; without a split all in
/// order on the calling thread. `Err(NotPositiveDefinite)` if a pivot is not positive.
pub(super) fn factorize(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    schedule: Schedule,
    values: &mut [f64],
    work: &mut [PartWork; 2],
    threads: &crate::parallel::Threads,
) -> Result<(), SolveError> {
    let shared = Values(values.as_mut_ptr(), values.len());
    let kernel = |s, w: &mut FactorWork| {
        // SAFETY: s is this thread's; its descendants are finished (see `Values`)
        unsafe { factor_supernode(sn, plan, &shared, s, w) }
    };
    in_tree_order(
        sn,
        schedule,
        work,
        threads,
        kernel,
        |_, _| true,
        |s, w, _| kernel(s, &mut w.factor),
    )
}

/// The LU factorisation without pivoting A = L U of a matrix with the symmetric pattern of
/// the analysis, L's values in `lower` and Uᵀ's in `upper`, both in the Cholesky factor's
/// layout (A's entries placed by `place(s, L's block, Uᵀ's block)` just before supernode
/// s is factorised, on the thread that factorises it: its lower triangle and its upper
/// one within the diagonal blocks in `lower`, the rest of its upper triangle, transposed,
/// in `upper`, the fill zero). L holds the
/// pivots on its diagonal, U a unit diagonal (stored): the solves are then the Cholesky
/// factor's, forward with L and backward with (Uᵀ)ᵀ (cholesky.rs `supernodal_solve`).
/// Left-looking as [`factorize`]: each supernode's L columns and Uᵀ rows less the updates
/// of its descendants, then its diagonal block's LU (Doolittle, no pivoting; the pivots
/// moved into L) and the blocks below it by triangular solves. The same operations in the
/// same order on one thread and on two. `Err(Singular)` at a pivot that is zero or not
/// finite (the caller falls back to the symmetric part's Cholesky factor); a negative
/// one is no failure (with sliding contacts the symmetric part may be indefinite: on the
/// shaken slope example 948 of 2,293 LUs met one; whether the factor is accurate, GMRES
/// preconditioned by it tells).
pub(super) fn factorize_lu(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    schedule: Schedule,
    (lower, upper): (&mut [f64], &mut [f64]),
    place: &PlaceEntries,
    work: &mut [PartWork; 2],
    threads: &crate::parallel::Threads,
) -> Result<(), SolveError> {
    let l = Values(lower.as_mut_ptr(), lower.len());
    let u = Values(upper.as_mut_ptr(), upper.len());
    let (l, u) = (&l, &u);
    // the top's supernodes and the places of their sums in a part's `top_sums`
    let (begin, _, val_ptr) = layout(sn);
    let mut top_places = Vec::new();
    if let Some(split) = schedule.split {
        let mut at = 0;
        for &s in &split.top {
            let size = val_ptr[s + 1] - val_ptr[s];
            top_places.push((s, at, size));
            at += 2 * size;
        }
        for w in work.iter_mut() {
            if w.top_sums.len() != at {
                try_zeroed(&mut w.top_sums, at)?;
            }
        }
    }
    let part_of = |d: usize| schedule.split.map_or(2, |sp| sp.owner(begin[d]));
    // whether each part redoes any of its supernodes: one that does not keeps its sums of
    // the top's updates from the factorisation before (they are of its factor, unchanged;
    // a top supernode redone now was redone, and its sums made, whenever one of the part's
    // supernodes that update it was — the first factorisation on an analysis redoes all)
    let mut part_redone = [false; 2];
    if schedule.split.is_some() {
        for (d, &r) in schedule.redo.iter().enumerate() {
            match part_of(d) {
                p @ (0 | 1) if r => part_redone[p as usize] = true,
                _ => {}
            }
        }
    }
    // SAFETY (of every use): s is the calling thread's (see `Values`)
    let place_own = |s: usize| unsafe {
        place(
            s,
            l.get_mut(val_ptr[s], val_ptr[s + 1]),
            u.get_mut(val_ptr[s], val_ptr[s + 1]),
        )
    };
    in_tree_order(
        sn,
        schedule,
        work,
        threads,
        // SAFETY: as in `factorize`, for both arrays
        |s, w| {
            place_own(s);
            unsafe { lu_supernode(sn, plan, (l, u), s, w) }
        },
        // a part's updates of the top's supernodes, into its `top_sums`
        |p, w| {
            if !part_redone[p] {
                return true;
            }
            for &(s, at, size) in &top_places {
                if !schedule.redo[s] {
                    continue;
                }
                let (ls, us) = w.top_sums[at..at + 2 * size].split_at_mut(size);
                ls.iter_mut().for_each(|x| *x = 0.0);
                us.iter_mut().for_each(|x| *x = 0.0);
                // SAFETY: the part's supernodes are finished; the sums are this part's own
                unsafe {
                    lu_updates(
                        sn,
                        plan,
                        (l, u),
                        s,
                        &mut w.factor,
                        0..usize::MAX,
                        (ls.as_mut_ptr(), us.as_mut_ptr()),
                        |d| part_of(d) as usize == p,
                    )
                };
            }
            true
        },
        // SAFETY: as in `factorize`; the two halves write disjoint rows of s
        |s, w0, w1| unsafe {
            place_own(s);
            let &(_, at, size) = top_places
                .iter()
                .find(|t| t.0 == s)
                .expect("a top supernode");
            lu_top_supernode(sn, plan, (l, u), s, [w0, w1], (at, size), &part_of, threads)
        },
    )
    .map_err(|_| SolveError::Singular)
}

/// Places a supernode's entries of A in its blocks of L and Uᵀ ([`factorize_lu`]).
pub(super) type PlaceEntries<'a> = dyn Fn(usize, &mut [f64], &mut [f64]) + Sync + 'a;

/// Which supernodes a factorisation computes, and how it shares them out.
#[derive(Clone, Copy)]
pub(super) struct Schedule<'a> {
    /// The elimination tree's two parts and top (cholesky.rs `split_tree`), if split.
    pub split: Option<&'a Split>,
    /// The supernodes to compute (the others hold their factor already:
    /// cholesky.rs `Cholesky::mark_redo`).
    pub redo: &'a [bool],
}

/// `kernel(s, work)` for every supernode s the schedule's `redo` marks, in an order in
/// which descendants come first: the parts of its split on two of `threads` (if it has
/// two), each followed by `part_tail(part, work)`, then the top by `top_kernel` (given both
/// parts' workspaces); without a split all in order on the calling thread. Stops at the first kernel that fails
/// (`Err(NotPositiveDefinite)`).
fn in_tree_order(
    sn: &SupernodalSymbolic,
    Schedule { split, redo }: Schedule,
    work: &mut [PartWork; 2],
    threads: &crate::parallel::Threads,
    kernel: impl Fn(usize, &mut FactorWork) -> bool + Sync,
    part_tail: impl Fn(usize, &mut PartWork) -> bool + Sync,
    top_kernel: impl Fn(usize, &mut PartWork, &mut PartWork) -> bool,
) -> Result<(), SolveError> {
    // (a failure must not outlive its factorisation: it once did, and every later
    // factorisation on the same analysis was refused)
    for w in work.iter_mut() {
        w.factor.failed = false;
    }
    let run = |list: &mut dyn Iterator<Item = usize>, w: &mut FactorWork| {
        for s in list.filter(|&s| redo[s]) {
            if !kernel(s, w) {
                w.failed = true;
                return;
            }
        }
    };
    match split {
        Some(split) => {
            let [w0, w1] = work;
            on_both(
                threads,
                |p, w| {
                    run(&mut split.parts[p].iter().copied(), &mut w.factor);
                    if !w.factor.failed && !part_tail(p, w) {
                        w.factor.failed = true;
                    }
                },
                w0,
                w1,
            );
            if work.iter().any(|w| w.factor.failed) {
                return Err(SolveError::NotPositiveDefinite);
            }
            let [w0, w1] = work;
            for &s in split.top.iter().filter(|&&s| redo[s]) {
                if !top_kernel(s, w0, w1) {
                    w0.factor.failed = true;
                    break;
                }
            }
        }
        None => run(&mut (0..sn.n_supernodes()), &mut work[0].factor),
    }
    match work[0].factor.failed {
        true => Err(SolveError::NotPositiveDefinite),
        false => Ok(()),
    }
}

/// The supernode's rows (local numbers in `w.local`) and the updates' common part: for each
/// descendant d of s, `f(ld, ud, first, mid, below, rel)` with d's values as matrices, the
/// first of its rows at or below s's first column, how many of those are s's columns, how
/// many in all, and their local rows in s.
///
/// SAFETY: as for [`factor_supernode`].
#[inline(always)]
unsafe fn for_each_update(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    s: usize,
    w: &mut FactorWork,
    mut f: impl FnMut(usize, usize, usize, usize, &[usize], &mut [f64]),
) {
    let (begin, end, _) = layout(sn);
    let (sb, se) = (begin[s], end[s]);
    let sw = se - sb;
    let s_pattern = sn.supernode(s).pattern();
    for (i, &r) in s_pattern.iter().enumerate() {
        w.local[r] = sw + i;
    }
    for &d in &plan.updates[plan.update_ptr[s]..plan.update_ptr[s + 1]] {
        let d = d as usize;
        let dw = end[d] - begin[d];
        let d_pattern = sn.supernode(d).pattern();
        let start = d_pattern.partition_point(|&r| r < sb);
        let mid = d_pattern[start..].partition_point(|&r| r < se);
        let below = d_pattern.len() - start;
        let rel = &mut w.rel[..below];
        for (x, &r) in rel.iter_mut().zip(&d_pattern[start..]) {
            *x = if r < se { r - sb } else { w.local[r] };
        }
        f(d, dw + start, mid, below, rel, &mut w.block);
    }
    for &r in s_pattern {
        w.local[r] = 0;
    }
}

/// Top supernodes with at least this many rows have their descendants' updates made in
/// two halves of their rows, each half by one of the two parts' workspaces: at once on two
/// threads, one after the other on one (the same operations on any number). The top of a
/// split tree is factorised after both parts, by one thread; its updates are most of a
/// partial refresh of the factor (the 40×40 wall: 1.2 of the top's 1.8 ms, of 3.2 ms for a
/// refresh that redoes 53 of 3,415 supernodes). Each entry's operations are those of the
/// whole supernode's updates (the factor is byte-identical to the unsplit one's on the
/// walls). Measured (2026-12-05, 40×40 wall, 12 steps, medians of 5 alternated runs): two
/// threads 65.3 → 62.8 ms a step (the top 1.74 → 1.54 ms a refresh: each half still visits
/// every descendant), one thread 82.7 → 82.8. Then the parts' sums of their updates of the
/// top (made on the parts' threads): 40×40 wall 59.8 → 57.0 ms a step, 30×30 27.0 → 26.5,
/// jointed slope ~1,000 blocks 164.6 → 168.5 (within its noise: its top's refresh 5.9 →
/// 2.2 ms, but its parts are uneven, 3.5 and 1.6 ms). A part with nothing to redo keeps its
/// sums from the factorisation before (2026-12-05: slope 145.6 → 143.9 ms/step, 40×40 wall
/// 56.3 → 56.0, medians of 5 and 7: within noise; the same factor bit for bit).
pub(super) const SPLIT_TOP_ROWS: usize = 128;

/// LU-factorise supernode `s` (see [`factorize_lu`]). Returns false at a pivot that is
/// zero or not finite.
///
/// SAFETY: as for [`factor_supernode`], for both arrays.
unsafe fn lu_supernode(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    (lower, upper): (&Values, &Values),
    s: usize,
    w: &mut FactorWork,
) -> bool {
    own_updates(sn, plan, (lower, upper), s, w, |_| true);
    lu_panel(sn, (lower, upper), s, None)
}

/// [`lu_updates`] of all of supernode `s`'s rows, in its own values.
///
/// SAFETY: as for [`lu_supernode`].
unsafe fn own_updates(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    (lower, upper): (&Values, &Values),
    s: usize,
    w: &mut FactorWork,
    keep: impl Fn(usize) -> bool,
) {
    let val_ptr = layout(sn).2;
    let targets = (lower.0.add(val_ptr[s]), upper.0.add(val_ptr[s]));
    lu_updates(sn, plan, (lower, upper), s, w, 0..usize::MAX, targets, keep);
}

/// [`lu_supernode`] for a supernode of the top of a split tree: its A entries plus the
/// parts' sums of their updates (made by the parts' threads after their own supernodes:
/// `top_sums` at `place`, L's then Uᵀ's), less the updates of its descendants in the top —
/// with [`SPLIT_TOP_ROWS`] rows or more in two halves of its rows (of about equal work),
/// with `w[0]` and `w[1]`, on two of `threads` if it has them —, then its panel (the two
/// triangular solves likewise).
///
/// SAFETY: as for [`lu_supernode`].
#[allow(clippy::too_many_arguments)]
unsafe fn lu_top_supernode(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    (lower, upper): (&Values, &Values),
    s: usize,
    [w0, w1]: [&mut PartWork; 2],
    (place, size): (usize, usize),
    part_of: &(impl Fn(usize) -> u8 + Sync),
    threads: &crate::parallel::Threads,
) -> bool {
    let (begin, end, val_ptr) = layout(sn);
    let sw = end[s] - begin[s];
    let srows = (val_ptr[s + 1] - val_ptr[s]) / sw;
    {
        let ls = lower.get_mut(val_ptr[s], val_ptr[s + 1]);
        let us = upper.get_mut(val_ptr[s], val_ptr[s + 1]);
        let (l0, u0) = w0.top_sums[place..place + 2 * size].split_at(size);
        let (l1, u1) = w1.top_sums[place..place + 2 * size].split_at(size);
        for ((x, a), b) in ls.iter_mut().zip(l0).zip(l1) {
            *x = (*x + a) + b;
        }
        for ((x, a), b) in us.iter_mut().zip(u0).zip(u1) {
            *x = (*x + a) + b;
        }
    }
    let in_top = |d: usize| part_of(d) == 2;
    if srows < SPLIT_TOP_ROWS {
        own_updates(sn, plan, (lower, upper), s, &mut w0.factor, in_top);
        return lu_panel(sn, (lower, upper), s, Some(threads));
    }
    let targets = (lower.0.add(val_ptr[s]), upper.0.add(val_ptr[s]));
    // rows of the diagonal block take L's updates, those below it L's and Uᵀ's
    let half = (sw + 2 * (srows - sw)) / 2;
    let cut = if half <= sw {
        half
    } else {
        sw + (half - sw) / 2
    };
    let targets = (SendPtr(targets.0), SendPtr(targets.1));
    let one = |rows: std::ops::Range<usize>, w: &mut FactorWork| {
        let t = (targets.0.get(), targets.1.get());
        // SAFETY: the halves write disjoint rows of s; see the function's contract
        unsafe { lu_updates(sn, plan, (lower, upper), s, w, rows, t, in_top) }
    };
    let (f0, f1) = (&mut w0.factor, &mut w1.factor);
    threads.join(|| one(0..cut, f0), || one(cut..srows, f1));
    lu_panel(sn, (lower, upper), s, Some(threads))
}

/// A pointer into the factor's values that the halves of [`lu_top_supernode`] share (they
/// write disjoint rows).
#[derive(Clone, Copy)]
struct SendPtr(*mut f64);

impl SendPtr {
    fn get(self) -> *mut f64 {
        self.0
    }
}

// SAFETY: see the type's docs
unsafe impl Sync for SendPtr {}
unsafe impl Send for SendPtr {}

/// Supernode `s`'s L columns and Uᵀ rows (at `targets`: blocks of s's layout) less the
/// updates of its descendants that `keep` keeps, in its local rows `rows` only (each
/// entry's operations are the same whatever the range).
///
/// SAFETY: as for [`factor_supernode`], for both arrays; no other thread writes the rows
/// `rows` of the targets.
#[allow(clippy::too_many_arguments)]
unsafe fn lu_updates(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    (lower, upper): (&Values, &Values),
    s: usize,
    w: &mut FactorWork,
    rows: std::ops::Range<usize>,
    (ls, us): (*mut f64, *mut f64),
    keep: impl Fn(usize) -> bool,
) {
    let (begin, end, val_ptr) = layout(sn);
    let sw = end[s] - begin[s];
    let srows = sw + sn.supernode(s).pattern().len();
    for_each_update(sn, plan, s, w, |d, first, mid, below, rel, block| {
        if !keep(d) {
            return;
        }
        let (dw, drows) = (end[d] - begin[d], val_ptr[d + 1] - val_ptr[d]);
        let drows = drows / dw;
        let ld = MatRef::from_column_major_slice(lower.get(val_ptr[d], val_ptr[d + 1]), drows, dw);
        let ud = MatRef::from_column_major_slice(upper.get(val_ptr[d], val_ptr[d + 1]), drows, dw);
        // d's rows whose local rows in s are in `rows` (local rows increase with d's)
        let lo = rel[..below].partition_point(|&r| r < rows.start);
        let hi = rel[..below].partition_point(|&r| r < rows.end);
        let ulo = lo.max(mid);
        for j0 in (0..mid).step_by(UPDATE_COLUMNS) {
            let cols = UPDATE_COLUMNS.min(mid - j0);
            let targets = &rel[j0..j0 + cols];
            // L's columns of s (the whole diagonal block and below): L_d · (U_d's columns)
            if hi > lo {
                subtract_product(
                    ls,
                    srows,
                    (ld.subrows(first + lo, hi - lo), &rel[lo..hi]),
                    (ud.subrows(first + j0, cols), targets),
                    block,
                );
            }
            // Uᵀ's rows below the diagonal block: (U_d's rows)ᵀ · L_d's rows of s
            if hi > ulo {
                subtract_product(
                    us,
                    srows,
                    (ud.subrows(first + ulo, hi - ulo), &rel[ulo..hi]),
                    (ld.subrows(first + j0, cols), targets),
                    block,
                );
            }
        }
    });
}

/// Supernode `s`'s panel, its updates made: its diagonal block's LU, then the blocks below
/// it (with `threads`, the two triangular solves of a wide one at once on two threads).
/// Returns false at a pivot that is zero or not finite.
///
/// SAFETY: as for [`factor_supernode`], for both arrays.
unsafe fn lu_panel(
    sn: &SupernodalSymbolic,
    (lower, upper): (&Values, &Values),
    s: usize,
    threads: Option<&crate::parallel::Threads>,
) -> bool {
    let (begin, end, val_ptr) = layout(sn);
    let sw = end[s] - begin[s];
    let srows = sw + sn.supernode(s).pattern().len();
    let ls = lower.get_mut(val_ptr[s], val_ptr[s + 1]);
    let us = upper.get_mut(val_ptr[s], val_ptr[s + 1]);
    // the diagonal block: Doolittle L₁ U₁ in place, then L = L₁ diag(u), Uᵀ = (diag(u)⁻¹ U₁)ᵀ
    {
        let mut lp = MatMut::from_column_major_slice_mut(&mut *ls, srows, sw);
        if !lu_in_place(lp.rb_mut().subrows_mut(0, sw)) {
            return false;
        }
    }
    for c in 0..sw {
        let u = ls[c * srows + c];
        let inv = 1.0 / u;
        for r in c + 1..sw {
            ls[c * srows + r] *= u;
            us[c * srows + r] = ls[r * srows + c] * inv;
        }
        us[c * srows + c] = 1.0;
    }
    // below it: L_R = B U⁻¹ (Uᵀ unit lower), Uᵀ_R = B' L⁻ᵀ
    if sw >= WIDE_SUPERNODE {
        let (ltop, lbot) = MatMut::from_column_major_slice_mut(ls, srows, sw).split_at_row_mut(sw);
        let (utop, ubot) = MatMut::from_column_major_slice_mut(us, srows, sw).split_at_row_mut(sw);
        let l = || {
            triangular_solve::solve_unit_lower_triangular_in_place(
                utop.rb(),
                lbot.transpose_mut(),
                Par::Seq,
            )
        };
        let u = || {
            triangular_solve::solve_lower_triangular_in_place(
                ltop.rb(),
                ubot.transpose_mut(),
                Par::Seq,
            )
        };
        match threads {
            Some(t) => {
                t.join(l, u);
            }
            None => {
                l();
                u();
            }
        }
        return true;
    }
    for c in 0..sw {
        for k in 0..c {
            // U[k, c] = Uᵀ[c, k]; L[c, k]
            let (ukc, lck) = (us[k * srows + c], ls[k * srows + c]);
            for r in sw..srows {
                ls[c * srows + r] -= ls[k * srows + r] * ukc;
                us[c * srows + r] -= us[k * srows + r] * lck;
            }
        }
        let inv = 1.0 / ls[c * srows + c];
        us[c * srows + sw..(c + 1) * srows]
            .iter_mut()
            .for_each(|x| *x *= inv);
    }
    true
}

/// x[rows, cols] −= a bᵀ for the column-major `x` (`srows` rows): row i of the product to
/// row `rows[i]`, column j to column `cols[j]`; the product made whole first (faer's dense
/// kernel) in `t`, then scattered.
///
/// SAFETY: `x` points to `srows` × (largest of `cols` + 1) values that no other thread
/// reads or writes in the rows `rows` of the columns `cols` during the call.
#[inline]
unsafe fn subtract_product(
    x: *mut f64,
    srows: usize,
    (a, rows): (MatRef<'_, f64>, &[usize]),
    (b, cols): (MatRef<'_, f64>, &[usize]),
    t: &mut [f64],
) {
    let (m, n) = (a.nrows(), b.nrows());
    let t = &mut t[..m * n];
    matmul::matmul(
        MatMut::from_column_major_slice_mut(t, m, n),
        Accum::Replace,
        a,
        b.transpose(),
        1.0,
        Par::Seq,
    );
    for (jj, &c) in cols.iter().enumerate() {
        let col = x.add(c * srows);
        for (&r, &tv) in rows.iter().zip(&t[jj * m..(jj + 1) * m]) {
            *col.add(r) -= tv;
        }
    }
}

/// LU without pivoting of the square `a` in place (Doolittle: L unit lower below the
/// diagonal, U on and above it): by halves (the top-left block, the blocks beside and
/// below it by triangular solves, the bottom-right less their product) down to
/// [`WIDE_SUPERNODE`] columns, then by columns. False at a pivot that is zero or not
/// finite.
fn lu_in_place(mut a: MatMut<'_, f64>) -> bool {
    let n = a.nrows();
    if n < 2 * WIDE_SUPERNODE {
        for k in 0..n {
            let p = a[(k, k)];
            if !p.is_finite() || p == 0.0 {
                return false;
            }
            let inv = 1.0 / p;
            for i in k + 1..n {
                a[(i, k)] *= inv;
            }
            for j in k + 1..n {
                let akj = a[(k, j)];
                if akj != 0.0 {
                    for i in k + 1..n {
                        let v = a[(i, k)];
                        a[(i, j)] -= v * akj;
                    }
                }
            }
        }
        return true;
    }
    let h = n / 2;
    let (mut a11, mut a12, mut a21, mut a22) = a.rb_mut().split_at_mut(h, h);
    if !lu_in_place(a11.rb_mut()) {
        return false;
    }
    triangular_solve::solve_unit_lower_triangular_in_place(a11.rb(), a12.rb_mut(), Par::Seq);
    triangular_solve::solve_lower_triangular_in_place(
        a11.rb().transpose(),
        a21.rb_mut().transpose_mut(),
        Par::Seq,
    );
    matmul::matmul(a22.rb_mut(), Accum::Add, a21.rb(), a12.rb(), -1.0, Par::Seq);
    lu_in_place(a22)
}

/// Factorise supernode `s` (see the module docs). Returns false if its panel is not
/// positive definite.
///
/// SAFETY: the calling thread alone holds supernode s, and every descendant of s is
/// finished.
unsafe fn factor_supernode(
    sn: &SupernodalSymbolic,
    plan: &FactorPlan,
    values: &Values,
    s: usize,
    w: &mut FactorWork,
) -> bool {
    let (begin, end, val_ptr) = layout(sn);
    let (sb, se) = (begin[s], end[s]);
    let sw = se - sb;
    let s_pattern = sn.supernode(s).pattern();
    let srows = sw + s_pattern.len();
    let ls = values.get_mut(val_ptr[s], val_ptr[s + 1]);
    for_each_update(sn, plan, s, w, |d, first, mid, below, rel, block| {
        let dw = end[d] - begin[d];
        let drows = (val_ptr[d + 1] - val_ptr[d]) / dw;
        let ld = values.get(val_ptr[d], val_ptr[d + 1]);
        // T = L_d[rows ≥ s] · L_d[rows of s]ᵀ, UPDATE_COLUMNS columns of s at a time
        // from their diagonal row down, then scattered
        let ld = MatRef::from_column_major_slice(ld, drows, dw);
        for j0 in (0..mid).step_by(UPDATE_COLUMNS) {
            let (cols, rows) = (UPDATE_COLUMNS.min(mid - j0), below - j0);
            let t = &mut block[..rows * cols];
            matmul::matmul(
                MatMut::from_column_major_slice_mut(t, rows, cols),
                Accum::Replace,
                ld.subrows(first + j0, rows),
                ld.subrows(first + j0, cols).transpose(),
                1.0,
                Par::Seq,
            );
            for jj in 0..cols {
                let j = j0 + jj;
                let col = &mut ls[rel[j] * srows..(rel[j] + 1) * srows];
                for i in j..below {
                    col[rel[i]] -= t[jj * rows + i - j0];
                }
            }
        }
    });
    if sw >= WIDE_SUPERNODE {
        let mut panel = MatMut::from_column_major_slice_mut(ls, srows, sw);
        let (mut top, bot) = panel.rb_mut().split_at_row_mut(sw);
        let stack = MemStack::new(w.stack.as_mut().expect("workspace"));
        if faer::linalg::cholesky::llt::factor::cholesky_in_place(
            top.rb_mut(),
            Default::default(),
            Par::Seq,
            stack,
            Default::default(),
        )
        .is_err()
        {
            return false;
        }
        triangular_solve::solve_lower_triangular_in_place(top.rb(), bot.transpose_mut(), Par::Seq);
        return true;
    }
    // the panel left-looking by columns: column c less its products with the columns before
    // it (from its diagonal row down), then divided by its pivot's square root
    for c in 0..sw {
        let (done, rest) = ls.split_at_mut(c * srows);
        let col = &mut rest[c..srows];
        for k in 0..c {
            let ck = &done[k * srows + c..(k + 1) * srows];
            let a = ck[0];
            for (x, &v) in col.iter_mut().zip(ck) {
                *x -= v * a;
            }
        }
        let d = col[0];
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let d = d.sqrt();
        col[0] = d;
        let inv = 1.0 / d;
        col[1..].iter_mut().for_each(|x| *x *= inv);
    }
    true
}
