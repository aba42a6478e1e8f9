//! Verification of contact and friction: the paper's direct shear test with both
//! algorithms, a block sliding on an incline, stacks and a wall settling under
//! gravity, and Newton's convergence.

mod common;
use common::*;
use nmm::model::FrictionAlgorithm;
use nmm::simulation::{monitor_values, Simulation};

fn direct_shear(sigma_n: f64, phi: f64, alg: &str) -> String {
    format!(
        r#"
[analysis]
mode = "static"
dt = 1.0
steps = 5
friction = "{alg}"
[cover]
size = 0.025
[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.0
[[block]]
name = "lower"
material = "rock"
vertices = [[0.0, 0.0], [0.2, 0.0], [0.2, 0.1], [0.0, 0.1]]
fixed = true
[[block]]
name = "upper"
material = "rock"
vertices = [[0.05, 0.1], [0.15, 0.1], [0.15, 0.2], [0.05, 0.2]]
[[interface]]
friction_angle = {phi}
normal_penalty = 1.0e11
shear_penalty = 1.0e11
[[load]]
block = "upper"
edge = [[0.05, 0.2], [0.15, 0.2]]
traction = [0.0, -{sigma_n}]
[[constraint]]
block = "upper"
edge = [[0.05, 0.1], [0.05, 0.2]]
ux = [[0.0, 0.0], [5.0, 3.0e-4]]
[[monitor]]
name = "joint"
interface = ["upper", "lower"]
"#
    )
}

/// Shear stress on the joint (−fx / length) and normal stress (fn / length) at each step.
fn shear_history(text: &str) -> Vec<(f64, f64, usize)> {
    let mut sim = Simulation::new(model(text)).unwrap();
    let mut out = Vec::new();
    while !sim.finished() {
        let rep = sim.advance().unwrap();
        let v = monitor_values(&sim);
        out.push((-v[0] / 0.1, v[2] / 0.1, rep.iterations));
    }
    out
}

#[test]
fn direct_shear_return_mapping_stays_at_the_strength() {
    for (sigma_n, phi) in [(1.0e6, 30.0), (0.5e6, 20.0), (2.0e6, 40.0)] {
        let strength = sigma_n * f64::tan(f64::to_radians(phi));
        let h = shear_history(&direct_shear(sigma_n, phi, "return-mapping"));
        eprintln!("return mapping σn={sigma_n} φ={phi}: {h:?} strength {strength}");
        for (step, (tau, sn, _)) in h.iter().enumerate() {
            // the normal stress carried by the joint is the applied one
            assert!((sn - sigma_n).abs() < 1e-6 * sigma_n, "step {step}: σn {sn}");
            assert!(((tau - strength) / strength).abs() < 1e-3, "step {}: τ = {tau}, strength {strength}", step + 1);
        }
    }
}

#[test]
fn direct_shear_conventional_overshoots_the_strength() {
    for (sigma_n, phi) in [(1.0e6, 30.0), (0.5e6, 20.0), (2.0e6, 40.0)] {
        let strength = sigma_n * f64::tan(f64::to_radians(phi));
        let h = shear_history(&direct_shear(sigma_n, phi, "conventional"));
        eprintln!("conventional σn={sigma_n} φ={phi}: {h:?} strength {strength}");
        assert!(h[0].0 > 1.001 * strength, "first step τ = {} vs {strength}", h[0].0);
        assert!(h.iter().all(|s| s.0 >= strength * (1.0 - 1e-3)));
    }
}

/// A block on a plane dipping θ (both blocks rotated: the mesh is not aligned).
fn incline(theta: f64, phi: f64, dt: f64, steps: usize) -> String {
    let rot = |pts: &[[f64; 2]]| place(pts, -theta, [0.0, 2.5]);
    let base = rot(&[[0.0, -0.5], [4.0, -0.5], [4.0, 0.0], [0.0, 0.0]]);
    let slider = rot(&[[0.5, 0.0], [1.0, 0.0], [1.0, 0.25], [0.5, 0.25]]);
    let c = rot(&[[0.75, 0.125]]);
    format!(
        r#"
[analysis]
mode = "dynamic"
dt = {dt}
steps = {steps}
gravity = [0.0, -9.81]
[cover]
size = 0.0625
[[material]]
name = "rock"
density = 2000.0
young = 1.0e9
poisson = 0.25
[[block]]
name = "base"
material = "rock"
vertices = {}
fixed = true
[[block]]
name = "slider"
material = "rock"
vertices = {}
[[interface]]
friction_angle = {phi}
normal_penalty = 1.0e9
shear_penalty = 1.0e9
[[monitor]]
name = "c"
point = {}
[[monitor]]
name = "joint"
interface = ["slider", "base"]
"#,
        poly(&base),
        poly(&slider),
        poly(&c).trim_start_matches('[').trim_end_matches(']')
    )
}

fn slip_along(theta: f64, v: &[f64]) -> f64 {
    let (s, c) = theta.to_radians().sin_cos();
    v[0] * c - v[1] * s
}

#[test]
fn block_slides_down_incline_as_closed_form() {
    let (theta, phi) = (30.0f64, 20.0f64);
    let mut sim = Simulation::new(model(&incline(theta, phi, 1e-3, 1000))).unwrap();
    let mut its = Vec::new();
    while !sim.finished() {
        its.push(sim.advance().unwrap().iterations);
    }
    let slip = slip_along(theta, &monitor_values(&sim));
    let (s, c) = theta.to_radians().sin_cos();
    let exact = 0.5 * 9.81 * (s - c * phi.to_radians().tan()) * 1.0;
    its.sort_unstable();
    eprintln!("incline: slip {slip:.6} vs {exact:.6} ({:+.3}%), median iterations {}", (slip / exact - 1.0) * 100.0, its[its.len() / 2]);
    assert!(((slip - exact) / exact).abs() < 0.02, "{slip} vs {exact}");
    assert!(its[its.len() / 2] <= 4);
}

#[test]
fn block_holds_on_incline_when_friction_exceeds_slope() {
    let sim = run(&incline(30.0, 35.0, 1e-3, 1000));
    let slip = slip_along(30.0, &monitor_values(&sim));
    eprintln!("incline φ > θ: slip {slip:.3e} m");
    assert!(slip.abs() < 1e-3, "{slip}");
}

fn rect(x0: f64, y0: f64, w: f64, h: f64) -> String {
    poly(&[[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
}

/// Blocks settle under gravity on a fixed base: the total vertical contact force on
/// the base equals the weight, velocities vanish, penetration stays at the level
/// the penalty implies (weight share / p_N).
fn settle(blocks: &[(f64, f64, f64, f64)], steps: usize, label: &str) {
    let (rho, g, pn) = (2000.0, 9.81, 1.0e10);
    let mut text = format!(
        r#"
[analysis]
mode = "dynamic"
dt = 0.002
steps = {steps}
gravity = [0.0, -{g}]
[cover]
size = 0.1
[[material]]
name = "brick"
density = {rho}
young = 5.0e9
poisson = 0.2
[[block]]
name = "base"
material = "brick"
vertices = {}
fixed = true
[[interface]]
friction_angle = 35.0
normal_penalty = {pn}
shear_penalty = {pn}
"#,
        rect(-0.5, -0.3, 4.0, 0.3)
    );
    let mut weight = 0.0;
    for (i, &(x, y, w, h)) in blocks.iter().enumerate() {
        text += &format!("[[block]]\nname = \"b{i}\"\nmaterial = \"brick\"\nvertices = {}\n", rect(x, y, w, h));
        text += &format!("[[monitor]]\nname = \"p{i}\"\npoint = [{}, {}]\n", x + 0.5 * w, y + 0.5 * h);
        weight += rho * g * w * h;
    }
    let mut sim = Simulation::new(model(&text)).unwrap();
    let mut its = Vec::new();
    while !sim.finished() {
        its.push(sim.advance().unwrap().iterations);
    }
    // total vertical force on the base from every block
    let fy: f64 = (1..=blocks.len()).map(|b| sim.contacts.interface_force(0, b).fy).sum();
    let vmax = sim.v.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let max_pen = sim.contacts.contacts.iter().map(|c| -c.response.tn / c.params.pn).fold(0.0f64, f64::max);
    its.sort_unstable();
    eprintln!(
        "{label}: base force {:.9e} vs weight {weight:.9e} (rel {:.2e}), max |v| {vmax:.2e}, max penetration {max_pen:.2e}, median iterations {}",
        -fy,
        (-fy - weight).abs() / weight,
        its[its.len() / 2]
    );
    assert!(((-fy - weight) / weight).abs() < 1e-6, "{label}: {fy} vs {weight}");
    assert!(vmax < 1e-6, "{label}: max velocity {vmax}");
    // no contact carries more than the whole weight: penetration ≤ weight / p_N
    assert!(max_pen <= weight / pn, "{label}: penetration {max_pen}");
    assert!(its[its.len() / 2] <= 4, "{label}: median iterations {}", its[its.len() / 2]);
}

#[test]
fn stack_of_blocks_settles_to_rest() {
    settle(&[(0.0, 0.0, 1.0, 0.4), (0.1, 0.4, 0.8, 0.4), (0.2, 0.8, 0.6, 0.4)], 1500, "stack");
}

#[test]
fn masonry_wall_settles_to_rest() {
    // three courses of running bond
    let (bw, bh) = (0.6, 0.25);
    let mut bricks = Vec::new();
    for course in 0..3 {
        let shift = if course % 2 == 0 { 0.0 } else { 0.5 * bw };
        let n = if course % 2 == 0 { 4 } else { 3 };
        for k in 0..n {
            bricks.push((shift + k as f64 * bw, course as f64 * bh, bw, bh));
        }
    }
    settle(&bricks, 1500, "wall");
}

#[test]
fn newton_converges_fast_when_contacts_slide() {
    // Direct shear, return mapping: the tangent is unsymmetric while sliding and Newton
    // finds the active set in a few iterations; once it is found the residual drops to
    // round-off in one more iteration (the law is piecewise linear in the gaps).
    let mut sim = Simulation::new(model(&direct_shear(1.0e6, 30.0, "return-mapping"))).unwrap();
    assert_eq!(sim.model.analysis.friction, FrictionAlgorithm::ReturnMapping);
    while !sim.finished() {
        let rep = sim.advance().unwrap();
        let r = &rep.residuals;
        eprintln!("step {}: residuals {r:?}", sim.step);
        let k = r.len() - 1;
        assert!(r[k] < 1e-8 * r[0], "{r:?}");
        // superlinear end: the last ratio is far below the one before it
        if k >= 2 {
            assert!(r[k] / r[k - 1] < 1e-3, "{r:?}");
        }
    }
}
