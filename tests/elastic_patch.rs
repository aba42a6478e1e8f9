//! Patch tests: a block not aligned with the mathematical mesh reproduces a
//! uniform stress state and the linear displacement field.
//!
//! Tolerance 1e-8 relative: the field is in the approximation space (constant
//! covers × linear weights reproduce linear fields), so only round-off and the
//! static mode's inertia term (2ρ/Δt²)·u — 1e-12 relative here with Δt = 1000 s —
//! separate the result from the exact one.

mod common;
use common::*;
use nmm::geometry::Vec2;

/// Self-equilibrated tractions t = σ n on every edge of a rotated rectangle, with
/// three point constraints taking out the rigid modes (they carry no reaction).
fn rotated_patch(angle: f64, h: f64, offset: [f64; 2]) {
    let (e, nu) = (1.0e9, 0.25);
    let sigma = [2.0e6, -1.0e6, 0.5e6]; // σxx, σyy, τxy
    let (w, ht) = (1.0, 0.6);
    let local = [[0.0, 0.0], [w, 0.0], [w, ht], [0.0, ht]];
    let pts = place(&local, angle, offset);
    let mut loads = String::new();
    for i in 0..4 {
        let (a, b) = (pts[i], pts[(i + 1) % 4]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let n = [(b[1] - a[1]) / len, -(b[0] - a[0]) / len]; // outward for CCW
        let t = [
            sigma[0] * n[0] + sigma[2] * n[1],
            sigma[2] * n[0] + sigma[1] * n[1],
        ];
        loads += &format!(
            "[[load]]\nblock = \"b\"\nedge = {}\ntraction = [{:.17e}, {:.17e}]\n",
            poly(&[a, b]),
            t[0],
            t[1]
        );
    }
    let (pa, pb) = (pts[0], pts[1]);
    let text = format!(
        r#"
[analysis]
mode = "static"
dt = 1000.0
steps = 1
[cover]
size = {h}
[[material]]
name = "m"
density = 2000.0
young = {e}
poisson = {nu}
plane = "stress"
[[block]]
name = "b"
material = "m"
vertices = {}
{loads}
[[constraint]]
block = "b"
point = {}
ux = 0.0
uy = 0.0
[[constraint]]
block = "b"
point = {}
uy = 0.0
"#,
        poly(&pts),
        poly(&[pa]).trim_start_matches('[').trim_end_matches(']'),
        poly(&[pb]).trim_start_matches('[').trim_end_matches(']'),
    );
    let sim = run(&text);
    // exact strain (plane stress)
    let eps = [
        (sigma[0] - nu * sigma[1]) / e,
        (sigma[1] - nu * sigma[0]) / e,
        2.0 * (1.0 + nu) * sigma[2] / e,
    ];
    let smax = sigma.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    for (i, s) in sim.stress.iter().enumerate() {
        for k in 0..3 {
            assert!(
                (s[k] - sigma[k]).abs() < 1e-8 * smax,
                "angle {angle} h {h}: element {i} stress {s:?}"
            );
        }
    }
    // displacement: u(x) = ε·(x − a) + ω (−(y − a_y), x − a_x) with u(a) = 0 and u_y(b) = 0
    let lin = |x: Vec2, om: f64| -> Vec2 {
        let d = [x[0] - pa[0], x[1] - pa[1]];
        [
            eps[0] * d[0] + 0.5 * eps[2] * d[1] - om * d[1],
            0.5 * eps[2] * d[0] + eps[1] * d[1] + om * d[0],
        ]
    };
    let om = -lin(pb, 0.0)[1] / (pb[0] - pa[0]);
    let umax = lin(pts[2], om)[0].abs().max(lin(pts[2], om)[1].abs());
    for e in &sim.disc.elements {
        for x in &e.polygon {
            let w = e.weights(*x);
            let mut u = [0.0; 2];
            for k in 0..3 {
                if let Some(d) = sim.disc.covers[e.covers[k]].dof {
                    u[0] += w[k] * sim.u[d];
                    u[1] += w[k] * sim.u[d + 1];
                }
            }
            // x is the deformed position: x0 = x − u
            let x0 = [x[0] - u[0], x[1] - u[1]];
            let want = lin(x0, om);
            assert!(
                (u[0] - want[0]).abs() < 1e-8 * umax && (u[1] - want[1]).abs() < 1e-8 * umax,
                "angle {angle} h {h}: u {u:?} vs {want:?}"
            );
        }
    }
}

#[test]
fn rotated_blocks_reproduce_uniform_stress_and_linear_displacement() {
    for (angle, h) in [
        (0.0, 0.17),
        (13.0, 0.1),
        (37.0, 0.23),
        (61.0, 0.07),
        (90.0, 0.13),
    ] {
        rotated_patch(angle, h, [0.0123, 0.0456]);
    }
}

/// Rollers by edge penalty on the left and bottom edges, uniform tension on the
/// right edge. The stress is exact; the displacement is the linear field shifted
/// by the penalty stretch t/p of the loaded roller (stated: p = c E / h).
#[test]
fn roller_patch_with_penalty_constraints() {
    let (e, sx, h) = (1.0e9, 1.0e6, 0.09);
    let (x0, y0, w, ht) = (0.031, 0.017, 1.0, 0.5);
    let text = format!(
        r#"
[analysis]
mode = "static"
dt = 1000.0
steps = 1
[cover]
size = {h}
[[material]]
name = "m"
density = 2000.0
young = {e}
poisson = 0.0
[[block]]
name = "b"
material = "m"
vertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]
[[load]]
block = "b"
edge = [[{x1}, {y0}], [{x1}, {y1}]]
traction = [{sx}, 0.0]
[[constraint]]
block = "b"
edge = [[{x0}, {y0}], [{x0}, {y1}]]
ux = 0.0
[[constraint]]
block = "b"
edge = [[{x0}, {y0}], [{x1}, {y0}]]
uy = 0.0
"#,
        x1 = x0 + w,
        y1 = y0 + ht
    );
    let mut sim = nmm::simulation::Simulation::new(model(&text)).unwrap();
    let mp = sim.disc.locate(0, [x0 + w, y0 + 0.5 * ht]).unwrap();
    sim.advance().unwrap();
    for s in &sim.stress {
        assert!(
            (s[0] - sx).abs() < 1e-8 * sx && s[1].abs() < 1e-8 * sx && s[2].abs() < 1e-8 * sx,
            "{s:?}"
        );
    }
    // penalty stretch of the left roller: t / p with p = 1e6 E / h
    let offset = -sx / (1e6 * e / h);
    let want_right = sx / e * w + offset;
    let u = sim.displacement_at(&mp);
    assert!(
        (u[0] - want_right).abs() < 1e-8 * want_right.abs(),
        "{} vs {}",
        u[0],
        want_right
    );
}
