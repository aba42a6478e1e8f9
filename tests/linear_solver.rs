//! The linear solver behind one interface (issue 14, requirement 2): a simulation solves
//! its steps with any `LinearSolver` it is given (`Simulation::set_linear_solver`), every
//! solve of the Newton driver going through it; one that fails makes the step fail with an
//! error, not a panic.

use nmm::generate::{brick_wall_model, WallOptions};
use nmm::model::parse_model;
use nmm::simulation::Simulation;
use nmm::solver::{LinearSolver, LinearStats, SolveError, TangentOperator, TangentSolver};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

fn wall() -> Simulation {
    let mut o = WallOptions::new(4, 4);
    o.steps = 4;
    let model = parse_model(&brick_wall_model(&o), std::path::Path::new(".")).unwrap();
    Simulation::new(model).unwrap()
}

/// The `TangentSolver`, counting the solves and invalidations it is asked for; with
/// `fail_from`, every solve from that one on fails.
struct Counting {
    inner: TangentSolver,
    solves: Arc<AtomicUsize>,
    invalidations: Arc<AtomicUsize>,
    fail_from: Option<usize>,
}

impl LinearSolver for Counting {
    fn solve(
        &mut self,
        op: &mut dyn TangentOperator,
        rhs: &[f64],
        x: &mut [f64],
        rtol: f64,
    ) -> Result<(), SolveError> {
        let k = self.solves.fetch_add(1, Ordering::SeqCst);
        if self.fail_from.is_some_and(|f| k >= f) {
            return Err(SolveError::Singular);
        }
        self.inner.solve(op, rhs, x, rtol)
    }
    fn invalidate(&mut self) {
        self.invalidations.fetch_add(1, Ordering::SeqCst);
        self.inner.invalidate();
    }
    fn loose_solves_pay(&self, op: &dyn TangentOperator) -> bool {
        self.inner.loose_solves_pay(op)
    }
    fn stats(&self) -> LinearStats {
        self.inner.stats()
    }
}

fn counting(fail_from: Option<usize>) -> (Counting, Arc<AtomicUsize>, Arc<AtomicUsize>) {
    let (s, i) = (Arc::new(AtomicUsize::new(0)), Arc::new(AtomicUsize::new(0)));
    let c = Counting {
        inner: TangentSolver::default(),
        solves: s.clone(),
        invalidations: i.clone(),
        fail_from,
    };
    (c, s, i)
}

#[test]
fn a_simulation_solves_through_the_solver_it_is_given() {
    let mut plain = wall();
    let mut given = wall();
    let (c, solves, invalidations) = counting(None);
    given.set_linear_solver(Box::new(c));
    let mut reported = 0;
    for step in 1..=4 {
        let a = plain.advance().unwrap();
        let b = given.advance().unwrap();
        // the same solver behind the interface: the same iterates, bit for bit
        assert_eq!(a.residuals, b.residuals, "step {step}");
        assert_eq!(a.iterations, b.iterations, "step {step}");
        reported += b.linear.solves;
        // at least one invalidation a step: no factorisation crosses a step boundary
        assert!(invalidations.load(Ordering::SeqCst) >= step, "step {step}");
    }
    // every linear solve of the steps went through the given solver
    assert!(reported >= 4, "{reported}");
    assert_eq!(solves.load(Ordering::SeqCst), reported);
}

#[test]
fn a_solver_that_fails_fails_the_step_with_an_error() {
    let mut sim = wall();
    let (c, solves, _) = counting(Some(0));
    sim.set_linear_solver(Box::new(c));
    let e = sim.advance().expect_err("every solve fails");
    let msg = e.to_string();
    assert!(msg.contains("did not converge"), "{msg}");
    assert!(solves.load(Ordering::SeqCst) >= 1);
}
