//! Running-bond brick walls (the DDA peer's benchmark geometry, `nmm::generate::wall`):
//! dynamic release under gravity (Δt = 1 ms, 20 steps) with no step cut and few Newton
//! iterations, and static settling with Δt = 1 s in 3 steps, whose base reaction equals the
//! weight. CI runs the 10 × 10 and 20 × 20 walls; larger ones are ignored tests
//! (`cargo test --release --test walls -- --ignored`) and benchmarks.
//!
//! Reference for the static case: statics — the fixed base carries the whole weight,
//! W = γ · (area of bricks), to 1e-6 relative (the equilibrium tolerance is 1e-9 of the
//! physical forces; the base reaction is summed from the contact forces).

use nmm::generate::{
    brick_wall_model, WallOptions, WALL_BRICK_HEIGHT, WALL_BRICK_LENGTH, WALL_UNIT_WEIGHT,
};
use nmm::model::Mode;
use nmm::simulation::Simulation;
use nmm::verify::cases::{median, model};

struct WallRun {
    solves: Vec<usize>,
    /// Residual norms of every step's accepted Newton iterates.
    residuals: Vec<Vec<f64>>,
    cuts: usize,
    base_reaction: f64,
    weight: f64,
}

fn run_wall(n: usize, mode: Mode, dt: f64, steps: usize) -> WallRun {
    run_wall_order(n, mode, dt, steps, 0)
}

/// [`run_wall`] with the covers of `order` (0 or 1).
fn run_wall_order(n: usize, mode: Mode, dt: f64, steps: usize, order: usize) -> WallRun {
    let mut o = WallOptions::new(n, n);
    o.mode = mode;
    o.dt = dt;
    o.steps = steps;
    let text =
        brick_wall_model(&o).replacen("[cover]\n", &format!("[cover]\norder = {order}\n"), 1);
    let mut sim = Simulation::new(model(&text).unwrap()).unwrap();
    let (mut solves, mut cuts, mut residuals) = (Vec::new(), 0, Vec::new());
    while !sim.finished() {
        let rep = sim
            .advance()
            .unwrap_or_else(|e| panic!("{n}×{n} {mode:?}: {e}"));
        solves.push(rep.solves);
        cuts += rep.cuts;
        residuals.push(rep.residuals.clone());
    }
    // block 0 is the base: the force on every brick from the base, summed
    let base_reaction: f64 = (1..sim.model.blocks.len())
        .map(|b| sim.contacts.interface_force(b, 0).fy)
        .sum();
    let weight = WALL_UNIT_WEIGHT * WALL_BRICK_LENGTH * WALL_BRICK_HEIGHT * (n * n) as f64;
    WallRun {
        solves,
        residuals,
        cuts,
        base_reaction,
        weight,
    }
}

/// The acceptance target: median linear solves per step of the dynamic release.
const MEDIAN_TARGET: usize = 4;

fn dynamic(n: usize, max_median: usize) {
    let r = run_wall(n, Mode::Dynamic, 1e-3, 20);
    eprintln!(
        "{n}×{n} dynamic: solves per step {:?} (median {}), cuts {}",
        r.solves,
        median(&r.solves),
        r.cuts
    );
    assert_eq!(r.cuts, 0, "{n}×{n}");
    // Once the active set holds, the consistent tangent makes the next iterate exact (the
    // contact forces are piecewise affine): the last residual is round-off next to the one
    // before it, in every step that took more than one iterate.
    for (k, res) in r.residuals.iter().enumerate() {
        let m = res.len();
        if m >= 2 {
            assert!(
                res[m - 1] < 1e-3 * res[m - 2],
                "{n}×{n} step {}: residuals {res:?}",
                k + 1
            );
        }
    }
    assert!(
        median(&r.solves) <= max_median,
        "{n}×{n}: median {}",
        median(&r.solves)
    );
}

fn settled(n: usize) {
    let r = run_wall(n, Mode::Static, 1.0, 3);
    let rel = (r.base_reaction / r.weight - 1.0).abs();
    eprintln!(
        "{n}×{n} static, Δt = 1 s: solves per step {:?}, cuts {}, base reaction {:.9e} vs weight {:.9e} (rel {rel:.1e})",
        r.solves, r.cuts, r.base_reaction, r.weight
    );
    assert_eq!(r.cuts, 0, "{n}×{n}");
    assert!(rel < 1e-6, "{n}×{n}: {} vs {}", r.base_reaction, r.weight);
}

#[test]
fn wall_10_dynamic_release() {
    dynamic(10, MEDIAN_TARGET);
}

#[test]
fn wall_20_dynamic_release() {
    // A regression guard, not the target: the 20×20 wall takes a median of 5 solves (its
    // head joints, which carry almost no normal force, go stick → slide → stick between
    // the first iterates). The target (MEDIAN_TARGET) is the ignored test below; open.
    dynamic(20, 5);
}

#[test]
#[ignore = "the acceptance target at 20×20, not met yet (median 5): run with --ignored"]
fn wall_20_dynamic_release_target() {
    dynamic(20, MEDIAN_TARGET);
}

/// A wall that has come to rest (after some 30 steps of the dynamic release its contacts no
/// longer change branch from step to step) takes one linear solve a step: the first choice
/// of branches is the last step's where it was right the last time the two predictions
/// differed (contact/set.rs `FirstChoice`). With the law's own branch at the predicted
/// increment alone, the rest's small oscillation put 6 to 14 contacts on another branch at
/// every first iterate: 2 or 3 solves a step.
#[test]
fn wall_10_at_rest_takes_one_solve_a_step() {
    let r = run_wall(10, Mode::Dynamic, 1e-3, 45);
    eprintln!("10×10 dynamic, 45 steps: solves per step {:?}", r.solves);
    assert_eq!(r.cuts, 0);
    let rest = &r.solves[37..];
    assert!(rest.iter().all(|&s| s == 1), "{:?}", r.solves);
}

#[test]
fn wall_10_static_with_one_second_steps() {
    settled(10);
}

#[test]
fn wall_20_static_with_one_second_steps() {
    settled(20);
}

#[test]
#[ignore = "large: run with --ignored"]
fn walls_30_to_50_dynamic_release() {
    for n in [30, 40, 50] {
        dynamic(n, MEDIAN_TARGET);
    }
}

#[test]
#[ignore = "large: run with --ignored"]
fn walls_30_to_50_static_with_one_second_steps() {
    for n in [30, 40, 50] {
        settled(n);
    }
}

/// A wall of n × n at order 1: the dynamic release (20 steps, Δt = 1 ms) and static
/// settling (Δt = 1 s, 3 steps) without a cut, the settled base reaction equal to the weight.
fn order_1(n: usize) {
    for (mode, dt, steps) in [(Mode::Dynamic, 1e-3, 20), (Mode::Static, 1.0, 3)] {
        let r = run_wall_order(n, mode, dt, steps, 1);
        let rel = (r.base_reaction / r.weight - 1.0).abs();
        eprintln!(
            "{n}×{n} {mode:?} at order 1: solves per step {:?} (median {}), cuts {}, base reaction / weight − 1 = {rel:.1e}",
            r.solves,
            median(&r.solves),
            r.cuts
        );
        assert_eq!(r.cuts, 0, "{n}×{n} {mode:?}");
        if mode == Mode::Static {
            assert!(rel < 1e-6, "{} vs {}", r.base_reaction, r.weight);
        }
    }
}

/// The walls at order 1 (issue 16: "walls run with 0 cuts"), 10×10 in CI.
#[test]
fn wall_10_at_order_1() {
    order_1(10);
}

/// The same at 20×20 (minutes at order 1: not in CI):
/// `cargo test --release --test walls wall_20_at_order_1 -- --ignored --nocapture`.
#[test]
#[ignore]
fn wall_20_at_order_1() {
    order_1(20);
}

/// The settling wall's corner contacts face points that wander micrometres about mesh lines,
/// each step onto covers of weight 10⁻⁹…10⁻⁵ that the last step's couplings did not hold.
/// Those rows stay out of the tangent's pattern (contact/set.rs, `PRECONDITIONER_WEIGHT`):
/// the pattern, and so the symbolic analysis of the factorisation, holds from the first step
/// on (measured: 11 analyses in 12 steps of the 10×10 wall before, 2 after), and the
/// iterations are those of the exact pattern (the direction is solved to the same
/// tolerance by GMRES on the full tangent).
#[test]
fn a_settling_wall_keeps_its_tangent_pattern() {
    let mut o = WallOptions::new(10, 10);
    o.dt = 1e-3;
    o.steps = 12;
    let mut sim = Simulation::new(model(&brick_wall_model(&o)).unwrap()).unwrap();
    let (mut symbolic, mut solves) = (0, 0);
    while !sim.finished() {
        let rep = sim.advance().unwrap();
        assert_eq!(rep.cuts, 0);
        symbolic += rep.linear.symbolic_analyses;
        solves += rep.solves;
    }
    eprintln!("10×10, 12 steps: {symbolic} symbolic analyses, {solves} solves");
    assert!(symbolic <= 2, "{symbolic} symbolic analyses in 12 steps");
    assert!(solves <= 12 * 5, "{solves} solves");
}
