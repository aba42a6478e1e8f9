//! Solving with the tangent of a step: one sparse factorisation serves many solves.
//!
//! The tangent J of a contact problem changes at every Newton iterate, but only where
//! contacts change branch, and from step to step only as much as the geometry moves. A
//! factorisation is therefore reused as the **preconditioner of GMRES** on the current
//! tangent ([`super::krylov`]) until it stops paying for itself:
//!
//! 1. GMRES on J (applied matrix-free by the system) preconditioned by the held factor (a
//!    Cholesky one: an LU is refreshed at every solve, `STALE_LU_ITERATIONS`), however old
//!    (an earlier iterate of the step);
//! 2. if it does not converge in `STALE_ITERATIONS` (or the last solve needed more than
//!    `REFRESH_AFTER`): **refresh**, on one symbolic analysis (our supernodal
//!    factorisation, [`Cholesky`], no allocation, the analysis kept while the pattern is
//!    unchanged; within a step the held matrix is updated by the contacts that changed
//!    branch since its last assembly, [`TangentOperator::update_assembly`], and the held
//!    factor by the supernodes whose columns changed):
//!    * when at least `MIN_LU_PIECES` sliding contacts make J unsymmetric: the **LU without
//!      pivoting of J** itself ([`Cholesky::factorize_lu_on`]: the same ordering,
//!      supernodes and storage as the Cholesky factor, L and Uᵀ; a negative pivot is
//!      accepted, a zero one is not), then GMRES preconditioned by it, which converges in
//!      one iteration (two when the pattern leaves out small entries) — or, for a loose
//!      solve of a dynamic step's tangent (`DIRECT_RTOL`), the LU's own solve, with no
//!      product with the tangent to check it; if the LU meets a
//!      zero pivot or GMRES does not converge in `FRESH_LU_ITERATIONS`, the step goes on
//!      with the Cholesky factor below;
//!    * else the **Cholesky** factorisation of the symmetric part the system assembles: J
//!      without the unsymmetric friction coupling of sliding contacts (∂t_S/∂g_N), which
//!      is symmetric positive definite; if J is symmetric this is J itself and the solve
//!      is direct; otherwise GMRES converges in about as many iterations as the coupling
//!      has independent directions that matter (2 with two sliding contacts, 10 with
//!      hundreds);
//! 3. if that fails too (a factorisation that is not positive definite, or GMRES that does
//!    not converge): sparse **LU** with pivoting of the full unsymmetric J (faer, COLAMD),
//!    a direct solve.
//!
//! A tangent whose pattern leaves out some small entries
//! ([`TangentOperator::pattern_is_complete`]: a contact's rows of weight below 10⁻⁴,
//! contact/set.rs `PRECONDITIONER_WEIGHT`) is never solved directly: its factor
//! preconditions GMRES on the full tangent (but for the loose solves of a dynamic step
//! above: the entries left out are below the loose tolerance).
//!
//! Why the LU without pivoting (2026-12-04): the Cholesky factor of the symmetric part
//! left ~10 GMRES iterations per solve on the brick walls and ~18 on the shaken slope
//! example, each a pair of triangular solves and a product with J. faer's sparse LU was
//! about 6× the Cholesky factorisation on the walls (its own ordering, pivoting and
//! storage), ours about 2× (the same analysis; every update twice, L's and Uᵀ's). Whole
//! runs, one thread, alternated with the Cholesky factor alone (single runs): the shaken
//! slope example 33.1 → 21.0 s (GMRES iterations 197,227 → 25,273; cut steps 23 → 21; at
//! 0.25 / 0.35 g 22 → 15 and 49 → 33), the jointed slope example 10.7 → 7.2 s, the tunnel
//! 22.7 → 21.5 s, the arch example 18.8 → 18.4 s, the shaking-table slope 1.71 → 1.74 s;
//! the 20×20 and 40×40 walls' factorisation and solve 0.543 → 0.397 s and 1.730 → 1.566 s
//! (minima of 3–5 alternated runs; GMRES iterations 603 → 122 and 400 → 106). Pivots:
//! a pivot that is not positive refused the LU in 948 of 2,293 attempts on the shaken
//! slope (its static settling and its sliding wedges make the symmetric part indefinite)
//! and in every one on the static jointed slope; accepted, every LU succeeded and
//! preconditioned GMRES to convergence in ~2 iterations.
//!
//! Measured and rejected as the preconditioner (2026-12-03, 20×20 wall, 12 steps): an SPD
//! approximation of each sliding contact's unsymmetric 2×2 block instead of dropping its
//! coupling — its symmetric part with the negative eigenvalue set to zero: 6,089 GMRES
//! iterations and 44 LU fallbacks against 603; with the eigenvalue's absolute value: 2,557.
//! faer's LU for every unsymmetric tangent on the shaken slope (to 0.8 s of shaking): 11.0 s
//! of factorisations (3,478, 3.2 ms each) and 0.5 s of solves, against 2.9 s and 6.3 s with
//! the Cholesky factor and GMRES.

use super::cholesky::Cholesky;
use super::krylov::Gmres;
use super::linear::{DirectSolver, FaerLu, SolveError};
use super::sparse::{SparseMatrix, SparsePattern};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A linear operator with a sparse pattern that can be assembled: the tangent of a step.
pub trait TangentOperator {
    fn size(&self) -> usize;
    /// y = A v.
    fn apply(&self, v: &[f64], y: &mut [f64]);
    /// The pattern of A.
    fn pattern(&mut self) -> Arc<SparsePattern>;
    /// Assemble A into `values` over `pattern()`; `symmetric`: only its symmetric positive
    /// definite part (see the module docs).
    fn assemble(&mut self, values: &mut [f64], symmetric: bool);
    /// Bring `values` to A (`symmetric`: its symmetric part) when they hold this
    /// operator's last assembly of the same kind, made since the caller last invalidated
    /// what it holds (a new step, another inertia coefficient or regularisation: see
    /// [`LinearSolver::invalidate`]), with only what changed since (contacts that changed
    /// branch). Returns false, `values` untouched, when it cannot (the caller then
    /// assembles anew); the default always does.
    fn update_assembly(&mut self, values: &mut [f64], symmetric: bool) -> bool {
        let _ = (values, symmetric);
        false
    }
    /// Whether A equals its symmetric part.
    fn is_symmetric(&self) -> bool;
    /// How many pieces (contacts) make A unsymmetric: the rank of A less its symmetric
    /// part, at most (0 if A is symmetric; by default unknown: `usize::MAX`).
    fn unsymmetric_pieces(&self) -> usize {
        if self.is_symmetric() {
            0
        } else {
            usize::MAX
        }
    }
    /// The threads the solves may use (default: the calling thread only).
    fn threads(&self) -> crate::parallel::Threads {
        crate::parallel::Threads::default()
    }
    /// Whether A holds a step's inertia (the tangent of a dynamic step, (2/Δt²) M among its
    /// terms), so that its LU without pivoting is accurate: the mass term holds the modes
    /// that contacts leave free. Default: no.
    fn has_inertia(&self) -> bool {
        false
    }
    /// Whether `pattern()` holds every entry of A (valid after `pattern()`). If not,
    /// `assemble` leaves some small entries out (a preconditioner's pattern): no solve
    /// with an assembled matrix is then direct, each preconditions GMRES on A.
    fn pattern_is_complete(&self) -> bool {
        true
    }
}

/// The linear solver of the Newton driver and of [`crate::simulation::Simulation`]: solves
/// with a step's tangent, given as an operator that applies and assembles itself.
/// [`TangentSolver`] is the one nmm uses; another (an iterative solver for millions of
/// unknowns, a GPU one) is one new implementation of this trait.
pub trait LinearSolver: Send {
    /// Solve A x = rhs to ‖rhs − A x‖ ≤ `rtol` ‖rhs‖ (`x` holds a first guess on entry).
    fn solve(
        &mut self,
        op: &mut dyn TangentOperator,
        rhs: &[f64],
        x: &mut [f64],
        rtol: f64,
    ) -> Result<(), SolveError>;
    /// Forget what the solver holds for the tangent (its next solve starts afresh): at the
    /// start of every step, and when the inertia coefficient or the regularisation
    /// changed. A solver must compute the same results after this as a new one, so that a
    /// run resumed from a checkpoint repeats the uninterrupted run bit for bit.
    fn invalidate(&mut self);
    /// Whether a solve with `op` to a loose tolerance (10⁻³) costs less than an accurate one
    /// (so that the Newton driver may ask for loose solves while the active set moves).
    /// Default: no.
    fn loose_solves_pay(&self, op: &dyn TangentOperator) -> bool {
        let _ = op;
        false
    }
    /// Counts and times of the solves so far.
    fn stats(&self) -> LinearStats;
    /// Stored values of the factor it holds (for memory reports; 0 for none).
    fn factor_len(&self) -> usize {
        0
    }
}

/// Counts and times of the linear solves.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LinearStats {
    pub solves: usize,
    pub gmres_iterations: usize,
    /// Numeric factorisations of the tangent on our supernodal analysis (refreshes of the
    /// preconditioner): Cholesky ones of its symmetric part and ...
    pub factorisations: usize,
    /// ... among them, LU ones without pivoting of the whole unsymmetric tangent.
    pub unsymmetric_factorisations: usize,
    pub symbolic_analyses: usize,
    pub lu_factorisations: usize,
    pub factorisation_time: Duration,
    pub solve_time: Duration,
}

impl std::ops::Sub for LinearStats {
    type Output = LinearStats;
    /// The counts and times since `o` (an earlier reading of the same solver).
    fn sub(self, o: LinearStats) -> LinearStats {
        LinearStats {
            solves: self.solves - o.solves,
            gmres_iterations: self.gmres_iterations - o.gmres_iterations,
            factorisations: self.factorisations - o.factorisations,
            unsymmetric_factorisations: self.unsymmetric_factorisations
                - o.unsymmetric_factorisations,
            symbolic_analyses: self.symbolic_analyses - o.symbolic_analyses,
            lu_factorisations: self.lu_factorisations - o.lu_factorisations,
            factorisation_time: self.factorisation_time - o.factorisation_time,
            solve_time: self.solve_time - o.solve_time,
        }
    }
}

impl std::ops::AddAssign for LinearStats {
    fn add_assign(&mut self, o: LinearStats) {
        self.solves += o.solves;
        self.gmres_iterations += o.gmres_iterations;
        self.factorisations += o.factorisations;
        self.unsymmetric_factorisations += o.unsymmetric_factorisations;
        self.symbolic_analyses += o.symbolic_analyses;
        self.lu_factorisations += o.lu_factorisations;
        self.factorisation_time += o.factorisation_time;
        self.solve_time += o.solve_time;
    }
}

/// Most GMRES iterations with a held (stale) preconditioner before refreshing it.
///
/// Measured (user time of whole runs, 2-core machine): a sparse Cholesky costs about ten
/// GMRES iterations, and a factor held across an active-set change needs two to three
/// times the iterations of a fresh one, so refreshing early pays: with (6, 3) against the
/// former (30, 15) the 40×40 wall (20 steps) took 10.6 s instead of 16.1 s (GMRES iterations
/// 2,408 → 1,086, factorisations 81 → 111), the seismic arch (2,500 steps) 7.6 s instead of
/// 8.3 s, the jointed slope example 3.4 s instead of 3.9 s.
///
/// Measured and rejected (2026-12-03, 40×40 wall, 12 steps): measuring "stale" against the
/// iterations the fresh factor itself needed (budget 6 + fresh, refresh after 3 + fresh, so
/// that the sliding coupling's share, which no refresh removes, does not force a refresh
/// after every solve) took 44 factorisations instead of 57 but 854 GMRES iterations instead
/// of 400: factorisation and solve 7.7 s against 6.7 s. A factor held across an active-set
/// change costs more iterations than a refresh saves.
const STALE_ITERATIONS: usize = 6;
/// A solve that needed more GMRES iterations than this refreshes the factor for the next.
const REFRESH_AFTER: usize = 3;
/// Most GMRES iterations with a fresh preconditioner before falling back to LU.
const FRESH_ITERATIONS: usize = 120;
const RESTART: usize = 40;
/// Fewest unsymmetric pieces (sliding contacts) for which the tangent is factorised whole
/// (LU without pivoting) rather than by its symmetric part. With the symmetric part's
/// factor GMRES needs more iterations the more contacts slide (on a fresh factor, the arch
/// example: 2.2 with 2 sliding contacts, 4.3 with 4–15, 6.2 with 16–63; the 20×20 wall: 9.9
/// with 256 or more), with the whole tangent's 1 to 2; the LU costs about two Cholesky
/// factorisations. Measured (2026-12-04, one thread, single runs; threshold 1 / 8 / 16 /
/// 32 / never): arch example 19.1 / 18.2 / 18.9 / 19.4 / 20.0 s (GMRES iterations 20,887 /
/// 39,466 / 52,653 / 66,120 / 67,212), tunnel 24.2 / 22.3 / 22.0 / 22.9 / 22.5 s; the arch's
/// one cut step at 1 and 16 moves with any change of rounding (0 at 8, 32 and never).
pub const MIN_LU_PIECES: usize = 8;
/// Most GMRES iterations with a fresh LU of the whole tangent before it is given up for the
/// step (an exact factor needs one, two with a pattern that leaves out small entries).
const FRESH_LU_ITERATIONS: usize = 12;
/// Loosest relative residual asked of a solve (the Newton driver's solves while the active
/// set moves, newton.rs `LOOSE`) that a fresh LU of the whole tangent of an operator with
/// inertia ([`TangentOperator::has_inertia`]) answers by its own solve, unchecked: GMRES
/// took one iteration there (the LU is of the tangent without its rows below the pattern's
/// floor, 10⁻⁴ of a contact's largest), and that iteration's product with the tangent was
/// as costly as the triangular solves. Measured (2026-12-05, two threads): the walls' 12
/// steps the same Newton solves (54 / 66 / 57 / 57 at 10×10 … 40×40), GMRES iterations 59 /
/// 71 / 62 / 59 → 6 / 6 / 6 / 4; alternated, medians of 15: 10×10 1.89 → 1.84 ms/step,
/// 20×20 10.43 → 9.99 (its solve stage 17–19 → 11 ms over the 12 steps), 40×40 56.8 → 54.4
/// (3); the slope of ~1000 blocks 126.2 → 124.3 ms/step; the arch example 0 cuts both,
/// 18,908 → 19,511 solves, 8.9 → 8.8 s; the tunnel 1,047 → 1,060 solves; the shaking-table
/// slope as before; the shaken slope (a chaotic problem: read the sums of its families, 28
/// PGAs from 0.24 to 0.38 g, one thread) 701 → 705 cut steps of about 71,000, 374,248 →
/// 370,119 solves (the 14 PGAs of the stops before 298 → 367, 14 new ones halfway between
/// them 403 → 338); the example (0.3 g) 13 → 15 cut steps, the most solves in a step (its
/// failed attempts counted) 56 → 46.
/// Not in static steps (no inertia): the jointed slope example, static, found no
/// equilibrium in 5 of its 40 steps instead of 1 and took 233 solves instead of 200 — near
/// a mechanism the LU without pivoting is inaccurate and GMRES's iteration corrected it.
const DIRECT_RTOL: f64 = 1e-3;
/// Most GMRES iterations with a held LU before refreshing it: none. A factor of the last
/// iterate's tangent, held across its active-set change, wasted its budget in 42 of 64
/// solves of the 20×20 wall (12 steps): budget 3 took 255 GMRES iterations and 55
/// factorisations, 0.458 s of factorisation and solve; none 122 and 64, 0.397 s (minima
/// of 5 alternated runs; the 40×40 wall 1.742 and 1.566 s). Measured and rejected: trying
/// a held LU only when at most 2 pieces had changed branch since it was made (with 2c + 2
/// iterations for c changes) saved 8 of 64 factorisations on the 20×20 wall (GMRES 122 →
/// 127), but the shaken slope at 0.25 / 0.3 / 0.35 g cut 32 / 30 / 34 steps against 15 /
/// 21 / 33 (single runs of a chaotic problem). Re-measured with the loose solves of a
/// moving active set (newton.rs `INEXACT`; 2026-12-05, 12 steps, one thread), budget 0 /
/// 3 / 6: the 10×10 wall 54 / 59 / 58 solves, 59 / 174 / 222 GMRES iterations, 53 / 42 /
/// 38 LU factorisations, factorisation and solve 21 / 28 / 31 ms; the 20×20 wall 66 / 69 /
/// 69, 71 / 217 / 322, 65 / 55 / 52, 145 / 213 / 278 ms; the 40×40 wall 57 / 62 / 61, 59 /
/// 184 / 271, 55 / 45 / 42, 965 / 1,276 / 1,400 ms.
const STALE_LU_ITERATIONS: usize = 0;

/// The tangent solver (see the module docs). Keep one per simulation: its workspaces are
/// reused across iterations and steps. Every decision it takes depends on iteration counts,
/// never on measured times, so its results are the same on every run; the caller
/// invalidates it at the start of every step, so that no factorisation crosses a step
/// boundary and a run resumed at any step computes bit for bit what the uninterrupted run
/// did.
pub struct TangentSolver {
    chol: Cholesky,
    lu: FaerLu,
    gmres: Gmres,
    matrix: Option<SparseMatrix>,
    /// Refresh before the next solve.
    refresh: bool,
    /// The LU of the unsymmetric tangent failed in this step: the symmetric part's
    /// Cholesky factor for the rest of it.
    lu_refused: bool,
    /// `matrix` holds the operator's assembly of this kind (`Some(true)`: its symmetric
    /// part), made since the last invalidation: the next refresh of the same kind may
    /// update it ([`TangentOperator::update_assembly`]).
    assembled: Option<bool>,
    pub stats: LinearStats,
}

impl Default for TangentSolver {
    fn default() -> Self {
        TangentSolver {
            chol: Cholesky::default(),
            lu: FaerLu::default(),
            gmres: Gmres::new(RESTART),
            matrix: None,
            refresh: true,
            lu_refused: false,
            assembled: None,
            stats: LinearStats::default(),
        }
    }
}

impl LinearSolver for TangentSolver {
    fn solve(
        &mut self,
        op: &mut dyn TangentOperator,
        rhs: &[f64],
        x: &mut [f64],
        rtol: f64,
    ) -> Result<(), SolveError> {
        TangentSolver::solve(self, op, rhs, x, rtol)
    }

    /// The next solve refreshes the factorisation.
    fn invalidate(&mut self) {
        self.refresh = true;
        self.lu_refused = false;
        self.assembled = None;
        // (and no update of the held factor: every value of a new step's tangent differs)
        self.chol.invalidate();
    }

    fn stats(&self) -> LinearStats {
        self.stats
    }

    /// With the LU of the whole tangent (enough sliding contacts, `MIN_LU_PIECES`): one
    /// GMRES iteration reaches a loose tolerance, two an accurate one when the pattern
    /// leaves out small entries. With the symmetric part's factor a loose solve stops
    /// GMRES early, on a direction that costs Newton iterations (see newton.rs `INEXACT`).
    fn loose_solves_pay(&self, op: &dyn TangentOperator) -> bool {
        !self.lu_refused && op.unsymmetric_pieces() >= MIN_LU_PIECES
    }

    fn factor_len(&self) -> usize {
        self.chol.factor_len()
    }
}

impl TangentSolver {
    /// `matrix` := the operator's tangent (`symmetric`: its symmetric part) on its
    /// pattern: the held one updated where it holds the last assembly of that kind, else
    /// assembled anew.
    fn assembled_matrix(
        &mut self,
        op: &mut dyn TangentOperator,
        symmetric: bool,
    ) -> Result<(), SolveError> {
        let p = op.pattern();
        let held = match &self.matrix {
            Some(m) => Arc::ptr_eq(&m.pattern, &p),
            None => false,
        };
        if !(held
            && self.assembled == Some(symmetric)
            && op.update_assembly(&mut self.matrix.as_mut().expect("matrix").values, symmetric))
        {
            let m = self.matrix_for(op)?;
            op.assemble(&mut m.values, symmetric);
        }
        self.assembled = Some(symmetric);
        Ok(())
    }

    fn matrix_for(
        &mut self,
        op: &mut dyn TangentOperator,
    ) -> Result<&mut SparseMatrix, SolveError> {
        self.assembled = None;
        let p = op.pattern();
        let fresh = match &self.matrix {
            Some(m) => !Arc::ptr_eq(&m.pattern, &p),
            None => true,
        };
        if fresh {
            // the old values' storage serves the new pattern when it is large enough
            let mut values = self.matrix.take().map(|m| m.values).unwrap_or_default();
            values.clear();
            values
                .try_reserve(p.nnz())
                .map_err(|_| SolveError::OutOfMemory)?;
            values.resize(p.nnz(), 0.0);
            self.matrix = Some(SparseMatrix { pattern: p, values });
        }
        let m = self.matrix.as_mut().expect("matrix");
        m.values.iter_mut().for_each(|v| *v = 0.0);
        Ok(m)
    }

    /// Refresh the held factor: with `lu` the LU without pivoting of the whole (unsymmetric)
    /// tangent ([`Cholesky::factorize_lu_on`]), else the Cholesky factor of its symmetric
    /// part; both on the same symbolic analysis.
    fn refresh(&mut self, op: &mut dyn TangentOperator, lu: bool) -> Result<(), SolveError> {
        let t = Instant::now();
        let before = self.chol.symbolic_count;
        self.assembled_matrix(op, !lu)?;
        let m = self.matrix.as_ref().expect("matrix");
        let r = match lu {
            true => self.chol.factorize_lu_on(m, &op.threads()),
            false => self.chol.factorize_on(m, &op.threads()),
        };
        self.stats.factorisation_time += t.elapsed();
        self.stats.factorisations += 1;
        self.stats.unsymmetric_factorisations += usize::from(lu);
        self.stats.symbolic_analyses += self.chol.symbolic_count - before;
        self.refresh = false;
        r
    }

    /// GMRES on `op` preconditioned by the held factor (ours), or by faer's held LU (`lu`).
    fn gmres(
        &mut self,
        op: &dyn TangentOperator,
        rhs: &[f64],
        x: &mut [f64],
        rtol: f64,
        max_iter: usize,
        lu: bool,
    ) -> Result<bool, SolveError> {
        let t = Instant::now();
        let (chol, lu_factor) = (&mut self.chol, &self.lu);
        let threads = op.threads();
        let mut failed = None;
        let rep = self.gmres.solve(
            |v, y| op.apply(v, y),
            |v| {
                let r = if lu {
                    lu_factor.solve_in_place(v)
                } else {
                    chol.solve_in_place_on(v, &threads)
                };
                if let Err(e) = r {
                    failed = Some(e);
                }
            },
            rhs,
            x,
            rtol,
            max_iter,
        );
        let dt = t.elapsed();
        self.stats.solve_time += dt;
        self.stats.gmres_iterations += rep.iterations;

        if let Some(e) = failed {
            return Err(e);
        }
        if rep.converged && rep.iterations > REFRESH_AFTER {
            // the held factor has drifted from the tangent: refresh next time
            self.refresh = true;
        }
        Ok(rep.converged)
    }

    /// Solve A x = rhs to ‖rhs − A x‖ ≤ `rtol` ‖rhs‖ (the direct solves are exact).
    pub fn solve(
        &mut self,
        op: &mut dyn TangentOperator,
        rhs: &[f64],
        x: &mut [f64],
        rtol: f64,
    ) -> Result<(), SolveError> {
        self.stats.solves += 1;
        let rtol = rtol.max(1e-14);
        // 1. the held factorisation as a preconditioner
        let stale = if self.chol.holds_lu() {
            STALE_LU_ITERATIONS
        } else {
            STALE_ITERATIONS
        };
        if !self.refresh
            && stale > 0
            && self.chol.is_valid()
            && self.gmres(op, rhs, x, rtol, stale, false)?
        {
            return Ok(());
        }
        // 2. refresh: the LU of a tangent that enough sliding contacts make unsymmetric,
        // else (or if that fails) the Cholesky factor of its symmetric part
        if !self.lu_refused && op.unsymmetric_pieces() >= MIN_LU_PIECES {
            let r = match self.refresh(op, true) {
                Ok(()) if rtol >= DIRECT_RTOL && op.has_inertia() => {
                    let t = Instant::now();
                    x.copy_from_slice(rhs);
                    let r = self.chol.solve_in_place_on(x, &op.threads());
                    self.stats.solve_time += t.elapsed();
                    // (a solve that is not finite: the symmetric part's factor, as below)
                    r.map(|()| x.iter().all(|v| v.is_finite()))
                }
                Ok(()) => self.gmres(op, rhs, x, rtol, FRESH_LU_ITERATIONS, false),
                Err(e) => Err(e),
            };
            match r {
                Ok(true) => return Ok(()),
                Err(SolveError::OutOfMemory) => return Err(SolveError::OutOfMemory),
                // a zero pivot, a solve that is not finite, GMRES that did not converge:
                // the symmetric part's factor, for the rest of the step
                Ok(false) | Err(_) => self.lu_refused = true,
            }
        }
        match self.refresh(op, false) {
            Ok(()) => {
                if op.is_symmetric() && op.pattern_is_complete() {
                    let t = Instant::now();
                    x.copy_from_slice(rhs);
                    let r = self.chol.solve_in_place_on(x, &op.threads());
                    self.stats.solve_time += t.elapsed();
                    return r;
                }
                if self.gmres(op, rhs, x, rtol, FRESH_ITERATIONS, false)? {
                    return Ok(());
                }
            }
            Err(SolveError::OutOfMemory) => return Err(SolveError::OutOfMemory),
            Err(_) => {}
        }
        // 3. LU of the full tangent
        let t = Instant::now();
        self.assembled_matrix(op, false)?;
        let r = self.lu.factorize(self.matrix.as_ref().expect("matrix"));
        self.stats.factorisation_time += t.elapsed();
        self.stats.lu_factorisations += 1;
        r?;
        // the held Cholesky factor is kept as the next preconditioner
        if !op.pattern_is_complete() {
            // the LU of a matrix without some small entries of A: GMRES on A with it
            return match self.gmres(op, rhs, x, rtol, FRESH_ITERATIONS, true)? {
                true => Ok(()),
                false => Err(SolveError::Other(
                    "GMRES did not converge with the LU of the tangent".into(),
                )),
            };
        }
        let t = Instant::now();
        x.copy_from_slice(rhs);
        let r = self.lu.solve_in_place(x);
        self.stats.solve_time += t.elapsed();
        r
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    /// A tridiagonal operator a_ii = d_i, a_{i,i±1} = −1, plus an unsymmetric coupling
    /// `c` at (0, n−1) that only the full tangent has (the symmetric part drops it, as it
    /// drops the friction coupling of sliding contacts).
    struct Tri {
        d: Vec<f64>,
        c: f64,
        /// A symmetric coupling of unknowns 0 and n/2 that A has but the pattern has not
        /// (a contact's small rows left out of the pattern).
        hidden: f64,
        /// What [`TangentOperator::has_inertia`] says.
        inertia: bool,
        pattern: Arc<SparsePattern>,
    }

    impl Tri {
        fn new(d: Vec<f64>, c: f64) -> Tri {
            let n = d.len();
            let mut groups: Vec<Vec<usize>> = (0..n - 1).map(|i| vec![i, i + 1]).collect();
            groups.push(vec![0, n - 1]);
            let pattern = Arc::new(SparsePattern::from_groups(n, groups.iter().map(|g| &g[..])));
            Tri {
                d,
                c,
                hidden: 0.0,
                inertia: false,
                pattern,
            }
        }
        fn dense(&self) -> Vec<Vec<f64>> {
            let n = self.d.len();
            let mut a = vec![vec![0.0; n]; n];
            for i in 0..n {
                a[i][i] = self.d[i];
                if i + 1 < n {
                    a[i][i + 1] = -1.0;
                    a[i + 1][i] = -1.0;
                }
            }
            a[0][n - 1] += self.c;
            a[0][n / 2] += self.hidden;
            a[n / 2][0] += self.hidden;
            a
        }
    }

    impl TangentOperator for Tri {
        fn size(&self) -> usize {
            self.d.len()
        }
        fn apply(&self, v: &[f64], y: &mut [f64]) {
            let a = self.dense();
            for i in 0..v.len() {
                y[i] = (0..v.len()).map(|j| a[i][j] * v[j]).sum();
            }
        }
        fn pattern(&mut self) -> Arc<SparsePattern> {
            self.pattern.clone()
        }
        fn assemble(&mut self, values: &mut [f64], symmetric: bool) {
            let a = self.dense();
            let n = self.d.len();
            for i in 0..n {
                for j in 0..n {
                    let mut v = a[i][j];
                    if symmetric && i == 0 && j == n - 1 {
                        v -= self.c;
                    }
                    if let Some(s) = self.pattern.slot(i, j) {
                        values[s] += v;
                    }
                }
            }
        }
        fn is_symmetric(&self) -> bool {
            self.c == 0.0
        }
        fn pattern_is_complete(&self) -> bool {
            self.hidden == 0.0
        }
        fn has_inertia(&self) -> bool {
            self.inertia
        }
    }

    fn residual(op: &Tri, x: &[f64], b: &[f64]) -> f64 {
        let mut y = vec![0.0; x.len()];
        op.apply(x, &mut y);
        y.iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn symmetric_tangent_is_one_direct_solve() {
        let mut op = Tri::new(vec![3.0; 30], 0.0);
        let b: Vec<f64> = (0..30).map(|i| (i as f64).cos()).collect();
        let mut s = TangentSolver::default();
        let mut x = vec![0.0; 30];
        s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
        assert!(residual(&op, &x, &b) < 1e-12);
        let st = s.stats();
        assert_eq!(
            (st.factorisations, st.gmres_iterations, st.lu_factorisations),
            (1, 0, 0)
        );
    }

    #[test]
    fn unsymmetric_coupling_is_solved_by_gmres_on_the_symmetric_factor() {
        let mut op = Tri::new(vec![3.0; 30], 0.7);
        let b: Vec<f64> = (0..30).map(|i| (i as f64).sin()).collect();
        let mut s = TangentSolver::default();
        let mut x = vec![0.0; 30];
        s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
        assert!(residual(&op, &x, &b) < 1e-10, "{}", residual(&op, &x, &b));
        let st = s.stats();
        // rank-one coupling: GMRES converges in about two iterations
        assert_eq!((st.factorisations, st.lu_factorisations), (1, 0));
        assert!(
            st.gmres_iterations >= 1 && st.gmres_iterations <= 4,
            "{st:?}"
        );
    }

    /// A loose solve (to 10⁻³, as Newton's while the active set moves) with a fresh LU of
    /// the whole tangent of an operator with inertia is the LU's own solve, no product with
    /// the tangent; an accurate solve, or one of an operator without inertia, goes through
    /// GMRES. With a small coupling left out of the pattern the LU's own solve is still
    /// within the loose tolerance.
    #[test]
    fn a_loose_solve_with_inertia_is_the_lus_own() {
        let b: Vec<f64> = (0..30).map(|i| 1.0 + (i as f64 * 0.7).sin()).collect();
        let bn = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (inertia, rtol, hidden, direct) in [
            (true, 1e-3, 0.0, true),
            (true, 1e-3, 1e-4, true),
            (true, 1e-8, 1e-4, false),
            (false, 1e-3, 1e-4, false),
        ] {
            let mut op = Tri::new(vec![3.0; 30], 0.7);
            op.inertia = inertia;
            op.hidden = hidden;
            let mut s = TangentSolver::default();
            let mut x = vec![0.0; 30];
            s.solve(&mut op, &b, &mut x, rtol).unwrap();
            let st = s.stats();
            let case = format!("inertia {inertia}, rtol {rtol}, hidden {hidden}: {st:?}");
            assert_eq!(st.unsymmetric_factorisations, 1, "{case}");
            assert_eq!(st.gmres_iterations == 0, direct, "{case}");
            let r = residual(&op, &x, &b) / bn;
            assert!(r <= rtol.max(1e-12), "{case}: residual {r}");
            if hidden == 0.0 {
                // the LU of the whole tangent: exact
                assert!(r < 1e-12, "{case}: residual {r}");
            }
        }
    }

    #[test]
    fn a_stale_factor_serves_a_changed_tangent_then_is_refreshed() {
        let mut s = TangentSolver::default();
        let b: Vec<f64> = (0..40).map(|i| 1.0 + (i as f64 * 0.3).sin()).collect();
        let mut op = Tri::new(vec![3.0; 40], 0.0);
        let mut x = vec![0.0; 40];
        s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
        // a small change (a contact's stiffness at one unknown): the held factor preconditions
        // GMRES, no new factorisation
        let mut d = vec![3.0; 40];
        d[7] = 3.5;
        let mut op = Tri::new(d, 0.0);
        s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
        assert!(residual(&op, &x, &b) < 1e-10);
        assert_eq!(s.stats().factorisations, 1, "{:?}", s.stats());
        assert!(s.stats().gmres_iterations >= 1);
        // a change everywhere: the stale factor does not converge within its budget and is
        // refreshed; the solve is then direct (symmetric)
        let mut op = Tri::new((0..40).map(|i| 2.1 + i as f64).collect(), 0.0);
        s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
        assert!(residual(&op, &x, &b) < 1e-9, "{}", residual(&op, &x, &b));
        assert_eq!(s.stats().factorisations, 2, "{:?}", s.stats());
        // invalidate: the next solve factorises afresh
        LinearSolver::invalidate(&mut s);
        s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
        assert_eq!(s.stats().factorisations, 3);
    }

    #[test]
    fn a_pattern_without_small_entries_preconditions_gmres_instead_of_solving_directly() {
        let b: Vec<f64> = (0..30).map(|i| 1.0 + (i as f64 * 0.7).cos()).collect();
        for c in [0.0, 0.7] {
            let mut op = Tri::new(vec![3.0; 30], c);
            op.hidden = 1e-3;
            let mut s = TangentSolver::default();
            let mut x = vec![0.0; 30];
            s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
            // the factor lacks the hidden coupling: a direct solve would be off by ~1e-3
            assert!(
                residual(&op, &x, &b) < 1e-10,
                "c {c}: {}",
                residual(&op, &x, &b)
            );
            let st = s.stats();
            assert_eq!(
                (st.factorisations, st.lu_factorisations),
                (1, 0),
                "c {c}: {st:?}"
            );
            assert!(st.gmres_iterations >= 1, "c {c}: {st:?}");
        }
    }

    #[test]
    fn an_indefinite_symmetric_part_falls_back_to_lu() {
        // d = 1 with off-diagonals −1: the symmetric part is indefinite (Cholesky fails);
        // with the coupling the full tangent is regular: LU solves it directly; with a
        // pattern that lacks an entry of A (`hidden`) its LU preconditions GMRES
        for hidden in [0.0, 1e-3] {
            let mut d = vec![1.0; 12];
            d[0] = -2.0;
            let mut op = Tri::new(d, 0.5);
            op.hidden = hidden;
            let b: Vec<f64> = (0..12).map(|i| i as f64 - 3.0).collect();
            let mut s = TangentSolver::default();
            let mut x = vec![0.0; 12];
            s.solve(&mut op, &b, &mut x, 1e-12).unwrap();
            let r = residual(&op, &x, &b);
            assert!(r < 1e-9, "hidden {hidden}: {r}");
            assert_eq!(s.stats().lu_factorisations, 1, "{:?}", s.stats());
        }
    }
}
