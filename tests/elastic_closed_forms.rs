//! Verification of the continuum part against closed forms: self-weight column,
//! cantilever (Timoshenko beam), free fall, the period of an elastic bar, and a
//! model of several blocks.

mod common;
use common::*;
use nmm::simulation::Simulation;

fn material(e: f64, nu: f64, rho: f64, plane: &str) -> String {
    format!("[[material]]\nname = \"m\"\ndensity = {rho}\nyoung = {e}\npoisson = {nu}\nplane = \"{plane}\"\n")
}

/// Column of height L under its own weight, base on rollers (uy = 0) and pinned at
/// one corner; ν = 0 so the exact solution is one-dimensional: u_y(top) = −ρ g L²/(2E).
fn column_top_error(n_per_length: usize) -> f64 {
    let (l, w, e, rho, g) = (10.0, 1.0, 1.0e9, 2000.0, 9.81);
    let (x0, y0) = (0.013, 0.021);
    let h = l / n_per_length as f64;
    let text = format!(
        r#"
[analysis]
mode = "static"
dt = 100.0
steps = 1
gravity = [0.0, -{g}]
[cover]
size = {h}
{mat}
[[block]]
name = "column"
material = "m"
vertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]
[[constraint]]
block = "column"
edge = [[{x0}, {y0}], [{x1}, {y0}]]
uy = 0.0
[[constraint]]
block = "column"
point = [{x0}, {y0}]
ux = 0.0
[[monitor]]
name = "top"
point = [{xm}, {y1}]
"#,
        mat = material(e, 0.0, rho, "strain"),
        x1 = x0 + w,
        y1 = y0 + l,
        xm = x0 + 0.5 * w
    );
    let mut sim = Simulation::new(model(&text)).unwrap();
    sim.advance().unwrap();
    let vals = nmm::simulation::monitor_values(&sim);
    let exact = -rho * g * l * l / (2.0 * e);
    ((vals[1] - exact) / exact).abs()
}

#[test]
fn self_weight_column_top_displacement() {
    let errs: Vec<f64> = [20, 40, 80].iter().map(|&n| column_top_error(n)).collect();
    eprintln!(
        "self-weight column: relative errors at h = L/20, L/40, L/80: {errs:?}, orders {:?}",
        orders(&errs)
    );
    assert!(errs[0] < 0.01, "h = L/20: {:.3e}", errs[0]);
    // linear covers: the error falls at least like h (observed order ≥ 1) until it
    // reaches the penalty/inertia floor of ~1e-7.
    for (i, w) in errs.windows(2).enumerate() {
        assert!(
            w[1] <= w[0] / 1.9 || w[1] < 1e-6,
            "refinement {i}: {errs:?}"
        );
    }
}

/// Cantilever (plane stress), length L, depth d, clamped at x = 0 by edge penalty,
/// uniform shear traction of resultant P at x = L. Reference: Timoshenko beam,
/// δ = P L³/(3EI) + P L/(κ G A), κ = 5/6.
fn cantilever_tip(h: f64) -> f64 {
    let (l, d, e, nu, p) = (10.0, 1.0, 1.0e9, 0.3, 1.0e3);
    let text = format!(
        r#"
[analysis]
mode = "static"
dt = 100.0
steps = 1
[cover]
size = {h}
{mat}
[[block]]
name = "beam"
material = "m"
vertices = [[0.0, 0.0], [{l}, 0.0], [{l}, {d}], [0.0, {d}]]
[[constraint]]
block = "beam"
edge = [[0.0, 0.0], [0.0, {d}]]
ux = 0.0
uy = 0.0
[[load]]
block = "beam"
edge = [[{l}, 0.0], [{l}, {d}]]
traction = [0.0, -{t}]
[[monitor]]
name = "tip"
point = [{l}, {hd}]
"#,
        mat = material(e, nu, 2000.0, "stress"),
        t = p / d,
        hd = 0.5 * d
    );
    let mut sim = Simulation::new(model(&text)).unwrap();
    sim.advance().unwrap();
    -nmm::simulation::monitor_values(&sim)[1]
}

#[test]
fn cantilever_tip_deflection_converges_to_timoshenko() {
    let (l, d, e, nu, p) = (10.0f64, 1.0f64, 1.0e9, 0.3, 1.0e3);
    let i = d.powi(3) / 12.0;
    let g = e / (2.0 * (1.0 + nu));
    let reference = p * l.powi(3) / (3.0 * e * i) + p * l / (5.0 / 6.0 * g * d);
    let tips: Vec<f64> = [2.0, 4.0, 8.0, 16.0]
        .iter()
        .map(|n| cantilever_tip(d / n))
        .collect();
    let errs: Vec<f64> = tips
        .iter()
        .map(|t| (t - reference).abs() / reference)
        .collect();
    eprintln!(
        "cantilever: reference {reference:.6e}, tips {tips:?}, errors {errs:?}, orders {:?}",
        orders(&errs)
    );
    // constant-strain elements are stiff in bending: the tip deflection grows toward
    // the reference as h falls, with observed order close to 2 on the coarse meshes.
    assert!(tips.windows(2).all(|w| w[1] > w[0]), "{tips:?}");
    let o = orders(&errs);
    assert!(o[0] > 1.5 && o[1] > 1.5, "orders {o:?}");
    assert!(errs[3] < 0.03, "h = d/16: {:.3e}", errs[3]);
}

/// An unsupported block under gravity falls ½ g t²: the scheme integrates a constant
/// acceleration exactly and the consistent mass carries the body force exactly.
#[test]
fn free_fall_is_exact() {
    let text = format!(
        r#"
[analysis]
mode = "dynamic"
dt = 0.01
steps = 100
gravity = [0.0, -9.81]
[cover]
size = 0.3
{}
[[block]]
name = "b"
material = "m"
vertices = [[0.1, 0.2], [1.1, 0.25], [0.9, 1.0], [0.2, 0.8]]
[[monitor]]
name = "c"
point = [0.5, 0.5]
"#,
        material(1.0e9, 0.25, 2500.0, "strain")
    );
    let sim = run(&text);
    let v = nmm::simulation::monitor_values(&sim);
    let t: f64 = 1.0;
    let exact = -0.5 * 9.81 * t * t;
    assert!(((v[1] - exact) / exact).abs() < 1e-6, "{} vs {exact}", v[1]);
    assert!(v[0].abs() < 1e-6 * exact.abs());
    assert!(((v[3] + 9.81 * t) / (9.81 * t)).abs() < 1e-6);
}

/// First period of a bar fixed at one end and loaded suddenly at the other:
/// T = 4 L / c, c = √(E/ρ) (ν = 0). 40 steps per period. The scheme (β = ½, γ = 1)
/// lengthens the period by 0.28% and damps the amplitude by 22% per period at this
/// step (`nmm::time::amplification`): the measured period must be within 1% of T.
#[test]
fn elastic_bar_period() {
    let (l, e, rho, sx) = (10.0f64, 1.0e9f64, 2000.0f64, 1.0e6);
    let c = (e / rho).sqrt();
    let period = 4.0 * l / c;
    let dt = period / 40.0;
    let text = format!(
        r#"
[analysis]
mode = "dynamic"
dt = {dt}
steps = 160
[cover]
size = 0.25
{}
[[block]]
name = "bar"
material = "m"
vertices = [[0.0, 0.0], [{l}, 0.0], [{l}, 0.5], [0.0, 0.5]]
[[constraint]]
block = "bar"
edge = [[0.0, 0.0], [0.0, 0.5]]
ux = 0.0
uy = 0.0
[[load]]
block = "bar"
edge = [[{l}, 0.0], [{l}, 0.5]]
traction = [{sx}, 0.0]
[[monitor]]
name = "tip"
point = [{l}, 0.25]
"#,
        material(e, 0.0, rho, "stress")
    );
    let mut sim = Simulation::new(model(&text)).unwrap();
    let u_static = sx * l / e;
    let mut hist = vec![(0.0, -u_static)];
    while !sim.finished() {
        sim.advance().unwrap();
        hist.push((
            sim.time,
            nmm::simulation::monitor_values(&sim)[0] - u_static,
        ));
    }
    // upward zero crossings, linearly interpolated
    let ups: Vec<f64> = hist
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1))
        .collect();
    assert!(ups.len() >= 3, "{ups:?}");
    let measured = ups[2] - ups[1];
    let (_, elongation) = nmm::time::amplification(2.0 * std::f64::consts::PI / 40.0);
    eprintln!(
        "bar: T = {period:.6e}, measured {measured:.6e} ({:+.3}%), scheme elongation {:+.3}%",
        (measured / period - 1.0) * 100.0,
        (elongation - 1.0) * 100.0
    );
    assert!(
        (measured / period - 1.0).abs() < 0.01,
        "{measured} vs {period}"
    );
}

/// Several blocks in one model: each has its own covers, the fixed one has no
/// unknowns and stays at zero displacement, the free ones respond independently.
#[test]
fn several_blocks_each_with_own_covers() {
    let text = format!(
        r#"
[analysis]
mode = "static"
dt = 1000.0
steps = 2
gravity = [0.0, -9.81]
[cover]
size = 0.2
{}
[[block]]
name = "base"
material = "m"
vertices = [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]]
fixed = true
[[block]]
name = "left"
material = "m"
vertices = [[0.05, 2.0], [1.05, 2.0], [1.05, 2.5], [0.05, 2.5]]
[[block]]
name = "right"
material = "m"
vertices = [[1.5, 2.03], [2.5, 2.03], [2.5, 2.53], [1.5, 2.53]]
[[interface]]
friction_angle = 30.0
normal_penalty = 1e10
shear_penalty = 1e9
[[constraint]]
block = "left"
edge = [[0.05, 2.0], [1.05, 2.0]]
ux = 0.0
uy = 0.0
[[constraint]]
block = "right"
edge = [[1.5, 2.03], [2.5, 2.03]]
ux = 0.0
uy = 0.0
[[monitor]]
name = "base"
point = [1.5, 0.5]
"#,
        material(1.0e9, 0.2, 2000.0, "strain")
    );
    let sim = run(&text);
    let n_blocks = 3;
    for b in 0..n_blocks {
        let covers: Vec<_> = sim.disc.covers.iter().filter(|c| c.block == b).collect();
        assert!(!covers.is_empty());
        for &e in &sim.disc.block_elements[b] {
            for &c in &sim.disc.elements[e].covers {
                assert_eq!(
                    sim.disc.covers[c].block, b,
                    "element of block {b} uses a cover of another block"
                );
            }
        }
        if b == 0 {
            assert!(covers.iter().all(|c| c.dof.is_none()));
        } else {
            assert!(covers.iter().all(|c| c.dof.is_some()));
        }
    }
    let v = nmm::simulation::monitor_values(&sim);
    assert_eq!(&v[..4], &[0.0, 0.0, 0.0, 0.0]);
    // the two hanging blocks compress identically under their weight (same geometry, shifted)
    let top = |b: usize, x: f64, y: f64| {
        let mp = sim.disc.locate(b, [x, y]).unwrap();
        sim.displacement_at(&mp)[1]
    };
    let (a, c) = (top(1, 0.55, 2.4), top(2, 2.0, 2.43));
    assert!(a < 0.0 && ((a - c) / a).abs() < 1e-3, "{a} {c}");
}
