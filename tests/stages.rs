//! `[[stage]]`: a block on a plane (φ = 40.5° above the plane's 30°) settled in a static
//! stage, then shaken in a dynamic stage whose base-motion record starts at the stage's
//! start. Its slip during the shaking against the Newmark (1965) rigid-block reference
//! under the same record (+1.9% as docs/model-format.md states, ±0.3%), and no drop
//! at the start of the shaking: the block settles less than 1e-6 m further when the
//! dynamic stage begins (the unsettled dynamic run drops onto its joint's springs).

use nmm::model::parse_model;
use nmm::simulation::{monitor_values, Simulation};
use nmm::verify::cases::{
    run_staged_slope, slope_model, staged_newmark_slip, staged_slope_model, STAGED_SETTLE_STEPS,
    STEADY_2HZ,
};
use std::path::Path;

const THETA: f64 = 30.0;
const SETTLE_STEPS: usize = STAGED_SETTLE_STEPS;

/// The shaken-slope model with a static settle stage before the shaking.
fn staged_model() -> String {
    staged_slope_model(THETA, 0)
}

/// The Newmark (1965) rigid block's slip under the record of the staged model `text`,
/// starting at the shake stage's start.
fn newmark_slip(text: &str) -> f64 {
    staged_newmark_slip(text, THETA).unwrap()
}

/// (time, slip along the plane (+ downslope), settlement into the plane) at every step,
/// and the stage of every step.
fn run(text: &str) -> (Vec<(f64, f64, f64)>, Vec<String>) {
    let r = run_staged_slope(text, THETA).unwrap();
    (r.history, r.stages)
}

#[test]
fn settle_then_shake_matches_newmark_without_a_drop() {
    let (h, stages) = run(&staged_model());
    assert_eq!(h.len(), SETTLE_STEPS + 4000);
    assert!(stages[..SETTLE_STEPS].iter().all(|s| s == "settle"));
    assert!(stages[SETTLE_STEPS..].iter().all(|s| s == "shake"));
    // time continues across stages, on the grid of each stage
    assert_eq!(h[SETTLE_STEPS - 1].0, 0.2);
    assert_eq!(h[SETTLE_STEPS].0, 0.201);
    assert_eq!(h.last().unwrap().0, 4.2);
    let settled = h[SETTLE_STEPS - 1];
    // no drop: settlement in the first 0.2 s of shaking (the record is still small there)
    let extra = h[SETTLE_STEPS..SETTLE_STEPS + 200]
        .iter()
        .map(|r| r.2 - settled.2)
        .fold(0.0f64, f64::max);
    // ... and in its first 20 steps (0.02 s, a record of at most 0.01 m/s²), against the
    // same block shaken without settling first, which drops onto its joint at t = 0
    let early = h[SETTLE_STEPS..SETTLE_STEPS + 20]
        .iter()
        .map(|r| (r.2 - settled.2).abs())
        .fold(0.0f64, f64::max);
    let unsettled = slope_model(THETA, &STEADY_2HZ, "return-mapping", 1e-3);
    let (d, _) = run(&unsettled);
    let drop = d[..20].iter().map(|r| r.2).fold(0.0f64, f64::max);
    // the Newmark reference, its record starting at the shake stage's start
    let t0 = settled.0;
    let slip = h.last().unwrap().1 - settled.1;
    let slip_ref = newmark_slip(&staged_model());
    eprintln!(
        "settled at t = {t0}: settlement {:.3e} m; extra settlement in the first 0.2 s of shaking {extra:.3e} m \
         ; in its first 20 steps {early:.3e} m (the unsettled run drops {drop:.3e} m); slip {slip:.5} m vs Newmark {slip_ref:.5} m ({:+.2}%)",
        settled.2,
        (slip / slip_ref - 1.0) * 100.0
    );
    assert!(
        extra < 1e-6,
        "the block settles {extra} m when shaking begins"
    );
    assert!(
        early < 0.01 * drop,
        "{early} m in the first steps of shaking vs the unsettled drop {drop} m"
    );
    assert!(slip_ref > 0.01, "the record makes the reference slide");
    // the figures docs/model-format.md states: +1.9% on the Newmark slip (the elastic
    // block's creep by partial slip, see tests/shaken_slope.rs; ±0.3%, the spread of the
    // shaken-slope cases is 1.2–2.8%), 8.5e-11 m and 9.1e-8 m (to the digits stated, ±5%)
    let err = slip / slip_ref - 1.0;
    assert!(
        (err - 0.019).abs() < 0.003,
        "slip {slip} vs Newmark {slip_ref}: {err:+.4}, the docs say +1.9%"
    );
    assert!(
        (early / 8.5e-11 - 1.0).abs() < 0.05,
        "{early} m, the docs say 8.5e-11"
    );
    assert!(
        (drop / 9.1e-8 - 1.0).abs() < 0.05,
        "{drop} m, the docs say 9.1e-8"
    );
}

#[test]
fn without_stages_time_and_record_start_at_zero() {
    // one stage: the base motion from t = 0 (the shaken-slope verification's setting)
    let text = slope_model(THETA, &STEADY_2HZ, "return-mapping", 1e-3);
    let m = parse_model(&text, Path::new(".")).unwrap();
    assert!(m.stages.is_empty());
    let sim = Simulation::new(m).unwrap();
    assert_eq!(sim.stage_name(), None);
    assert_eq!(sim.total_steps(), 4000);
    let a = sim.base_acceleration(0.3);
    assert_eq!(a[0], sim.model.base_motion.as_ref().unwrap().accel(0.3)[0]);
}

#[test]
fn a_stage_without_base_motion_feels_none() {
    let sim = Simulation::new(parse_model(&staged_model(), Path::new(".")).unwrap()).unwrap();
    assert_eq!(sim.stage_name(), Some("settle"));
    assert_eq!(sim.base_acceleration(0.3), [0.0, 0.0]);
    assert_eq!(sim.total_steps(), SETTLE_STEPS + 4000);
    assert_eq!(sim.end_time(), 4.2);
}

#[test]
fn bad_stages_get_one_line_naming_table_key_file_and_line() {
    let base = slope_model(THETA, &STEADY_2HZ, "return-mapping", 1e-3);
    let err = |extra: &str| -> String {
        let text = format!("{base}{extra}");
        nmm::model::parse_model_named(&text, Path::new("."), "m.toml")
            .map(|_| String::new())
            .unwrap_or_else(|e| e.to_string())
    };
    let lines = base.lines().count();
    let e = err("[[stage]]\nname = \"a\"\n[[stage]]\nname = \"a\"\n");
    assert_eq!(
        e,
        format!(
            "[[stage]] \"a\": key `name`: duplicate stage name (also [[stage]] #1) (m.toml, line {})",
            lines + 4
        )
    );
    let e = err("[[stage]]\nname = \"a\"\nsteps = 0\n");
    assert!(
        e.starts_with("[[stage]] \"a\": key `steps`: must be positive, got 0 (m.toml, line"),
        "{e}"
    );
    let e = err("[[stage]]\nname = \"a\"\nconstraint_penalty = -1\n");
    assert!(
        e.starts_with("[[stage]] \"a\": key `constraint_penalty`: must be positive"),
        "{e}"
    );
    let e = err("[[stage]]\nname = \"a\"\ndamping = 1\n");
    assert!(
        e.starts_with("[[stage]] \"a\": unknown key `damping`"),
        "{e}"
    );
    let e = err("[[stage]]\nname = \"a\"\nmode = \"quasi\"\n");
    assert!(
        e.starts_with("[[stage]] \"a\": key `mode`: expected one of"),
        "{e}"
    );
    assert!(e.lines().count() == 1);
    // a record asked for without one
    let no_record = base.replace(
        "[base_motion]\n",
        "[[monitor]]\nname = \"x\"\npoint = [1.0, 1.0]\n#",
    );
    let text = format!("{no_record}[[stage]]\nname = \"shake\"\nbase_motion = true\n");
    let e = nmm::model::parse_model_named(&text, Path::new("."), "m.toml")
        .map(|_| String::new())
        .unwrap_or_else(|e| e.to_string());
    assert!(
        e.starts_with("[[stage]] \"shake\": key `base_motion`: is true but the model has no [base_motion] record (m.toml, line"),
        "{e}"
    );
    // dt and steps from neither the stage nor [analysis]
    let bare = base
        .replace("dt = 0.001\n", "")
        .replace("steps = 4000\n", "");
    let text = format!("{bare}[[stage]]\nname = \"s\"\nsteps = 3\n");
    let e = nmm::model::parse_model_named(&text, Path::new("."), "m.toml")
        .map(|_| String::new())
        .unwrap_or_else(|e| e.to_string());
    assert!(
        e.starts_with(
            "[[stage]] \"s\": key `dt`: missing (set it here or in [analysis]) (m.toml, line"
        ),
        "{e}"
    );
    // ... but every stage may set them, and [analysis] may then leave them out
    let text = format!("{bare}[[stage]]\nname = \"s\"\nsteps = 3\ndt = 0.01\n");
    let m = nmm::model::parse_model_named(&text, Path::new("."), "m.toml").unwrap();
    assert_eq!(m.stages[0].analysis.dt, 0.01);
    assert_eq!(
        m.stages[0].analysis.gravity,
        [0.0, -9.81],
        "from [analysis]"
    );
    assert!(
        !m.stages[0].base_motion,
        "the record applies only where asked"
    );
    // without stages [analysis] still needs them
    let e = nmm::model::parse_model_named(&bare, Path::new("."), "m.toml")
        .map(|_| String::new())
        .unwrap_or_else(|e| e.to_string());
    assert!(
        e.starts_with("[analysis]: key `dt`: missing (required)"),
        "{e}"
    );
}

/// A stage may change `constraint_penalty` (any `[analysis]` key may be set in a stage):
/// a block standing on a constrained bottom edge settles into it by its weight's traction
/// × h / (factor × E); with the factor 1000 times smaller in a second static stage, the
/// bottom sinks 1000 times further. The mean sink of the edge (trapezoid rule over nine
/// monitors along it; the displacement is piecewise linear along the edge with kinks at
/// the mesh's nodes, h = 0.25, so the rule is exact on the monitors at those nodes) is the
/// weight over the edge's spring p L = (factor E / h) × 1 m by equilibrium alone: the
/// only error is the Newton tolerance (1e-9 of the forces) — asserted to 1e-6. Its middle
/// sinks 13% more than the mean (the stretch is not uniform along the edge, it is larger
/// at its middle): the README's formula is the mean's.
#[test]
fn a_stage_changes_the_constraint_springs() {
    let mut text = String::from(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\ngravity = [0.0, -10.0]\n\
        [cover]\nsize = 0.25\n\
        [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.0\n\
        [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n\
        [[constraint]]\nblock = \"b\"\nedge = [[0.0, 0.0], [1.0, 0.0]]\nux = 0.0\nuy = 0.0\n\
        [[stage]]\nname = \"stiff\"\n\
        [[stage]]\nname = \"soft\"\nconstraint_penalty = 1.0e3\n",
    );
    for k in 0..=8 {
        text += &format!(
            "[[monitor]]\nname = \"f{k}\"\npoint = [{}, 0.0]\n",
            k as f64 / 8.0
        );
    }
    let mut sim = Simulation::new(parse_model(&text, Path::new(".")).unwrap()).unwrap();
    let (mut mean, mut middle) = (Vec::new(), Vec::new());
    while !sim.finished() {
        sim.advance().unwrap();
        let m = monitor_values(&sim);
        let uy: Vec<f64> = (0..=8).map(|k| -m[4 * k + 1]).collect();
        let trapezoid = (0.5 * (uy[0] + uy[8]) + uy[1..8].iter().sum::<f64>()) / 8.0;
        mean.push(trapezoid);
        middle.push(uy[4]);
    }
    // traction ρ g H = 2e4 Pa; stretch = 2e4 × 0.25 / (factor × 1e9)
    let (stiff, soft) = (mean[0], mean[1]);
    eprintln!(
        "edge sinks {stiff:.6e} m on average, {:.3e} at its middle (factor 1e6), then {soft:.6e} m, {:.3e} (factor 1e3)",
        middle[0], middle[1]
    );
    assert!((stiff / 5e-12 - 1.0).abs() < 1e-6, "{stiff}");
    assert!((soft / 5e-9 - 1.0).abs() < 1e-6, "{soft}");
}

/// Stages at order 1 (issue 16, item 4): the same settle-then-shake model with first-order
/// covers runs its two stages on their grids, does not drop when the shaking begins, and
/// slides as the Newmark block within 5% (order 0: +1.9%, from the elastic block's creep by
/// partial slip, which the first-order block, less stiff, may show differently: printed).
#[test]
fn settle_then_shake_at_order_1() {
    let text = staged_slope_model(THETA, 1);
    assert!(text.contains("order = 1"));
    let (h, stages) = run(&text);
    assert_eq!(h.len(), SETTLE_STEPS + 4000);
    assert!(stages[..SETTLE_STEPS].iter().all(|s| s == "settle"));
    assert!(stages[SETTLE_STEPS..].iter().all(|s| s == "shake"));
    assert_eq!(h.last().unwrap().0, 4.2);
    let settled = h[SETTLE_STEPS - 1];
    let extra = h[SETTLE_STEPS..SETTLE_STEPS + 200]
        .iter()
        .map(|r| r.2 - settled.2)
        .fold(0.0f64, f64::max);
    let slip = h.last().unwrap().1 - settled.1;
    let err = slip / newmark_slip(&text) - 1.0;
    eprintln!(
        "order 1: extra settlement {extra:.3e} m, slip {slip:.5} m ({:+.2}% of Newmark)",
        100.0 * err
    );
    assert!(
        extra < 1e-6,
        "the block settles {extra} m when shaking begins"
    );
    assert!(err.abs() < 0.05, "slip {slip}: {err:+.4} of Newmark");
}
