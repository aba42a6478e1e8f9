//! A tunnel in a rock mass (issue 17, items 1–3): in-situ stress, a block with a hole and
//! its plug (or a closed joint loop), excavation in a stage — against Kirsch.
//!
//! The model: a square of side L = 20 a around a circular tunnel of radius a (a polygon of
//! 64 chords), under the in-situ stress σxx = −K p, σyy = −p (plane strain, E = 1 GPa,
//! ν = 0.25, p = 1 MPa); its outer edges loaded by the in-situ tractions σ·n, three point
//! constraints on the symmetry axes against rigid motion (their reactions are zero by
//! symmetry). Stage "insitu" (static, one step): the plug in its hole, the contacts
//! carrying σ·n; stage "dig" (static, one step) excavates the plug.
//!
//! Closed forms (plane strain, G = E/2(1+ν), κ = 3 − 4ν), the displacement the excavation
//! induces at the wall and the hoop stress there, θ from +x:
//! u_r(a, θ) = (a/4G) [(σxx + σyy) + κ (σxx − σyy) cos 2θ],
//! σθθ(a, θ) = (σxx + σyy) − 2 (σxx − σyy) cos 2θ;
//! hydrostatic: u_r = −p a (1+ν)/E, σθθ = −2p.
//!
//! **The outer boundary.** The edges carry the in-situ tractions, so the excavation's
//! disturbance (σ_r of the hydrostatic case decays as p a²/r²: 1% of p at r = 10 a) meets a
//! boundary that holds it at zero: the wall displacement of a thick cylinder of outer
//! radius b with its outer face free is [b² + (1−2ν)a²]/(b² − a²) times the infinite one,
//! +1.5% for b = 10 a, +0.8% for b = 14.1 a (the square's corners): the square of side
//! 20 a lies between (measured below: +1.1% against a square of side 40 a at the same
//! cover, `the_boundary_effect_of_side_20a`). Fixed edges would give (1 − a²/b²)/(1 +
//! a²/((1−2ν)b²)) = −2.9% for b = 10 a. So the loaded edges take 1.1% of the 5% tolerance.
//!
//! Tolerances (the issue's): wall displacement within 5%, hoop stress within 10%, crown
//! and sidewall displacements (K = 0.5) within 5%, and no point moving more than 1e-3 of
//! the wall displacement before the excavation. Each can fail: a missing in-situ stress
//! moves nothing (0% of the closed form), contacts without the in-situ traction let the
//! plug squeeze in before the excavation (measured 30% of the wall displacement when the
//! contact prestress is switched off), an excavation that leaves the plug's contacts or
//! stiffness gives no displacement at all.

use nmm::cover::MaterialPoint;
use nmm::model::parse_model;
use nmm::simulation::Simulation;
use std::path::Path;

const A: f64 = 1.0;
const P: f64 = 1.0e6;
const E: f64 = 1.0e9;
const NU: f64 = 0.25;
const CHORDS: usize = 64;

fn pts(p: &[[f64; 2]]) -> String {
    let v: Vec<String> = p
        .iter()
        .map(|x| format!("[{:?}, {:?}]", x[0], x[1]))
        .collect();
    format!("[{}]", v.join(", "))
}

fn circle(r: f64) -> Vec<[f64; 2]> {
    (0..CHORDS)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / CHORDS as f64;
            [r * t.cos(), r * t.sin()]
        })
        .collect()
}

/// How the tunnel is drawn.
#[derive(Clone, Copy, PartialEq)]
enum Drawn {
    /// A rock block with a hole, and the plug as a block of its own.
    Plug,
    /// A closed `[[joint]]` loop "tunnel" cutting the rock (`excavate` names the loop: the
    /// pieces it cut out).
    Loop,
}

/// The tunnel model (module doc): side `side`, cover `h`, order, K.
fn model(side: f64, h: f64, order: usize, k: f64, drawn: Drawn) -> String {
    let half = side / 2.0;
    let (sx, sy) = (-k * P, -P);
    let outer = [[-half, -half], [half, -half], [half, half], [-half, half]];
    let mut t = format!(
        "[cover]\nsize = {h:?}\norder = {order}\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = {E:?}\npoisson = {NU:?}\n\
         [initial_stress]\nstress = [{sx:?}, {sy:?}, 0.0]\n\
         [[stage]]\nname = \"insitu\"\nmode = \"static\"\ndt = 1.0\nsteps = 1\n\
         [[stage]]\nname = \"dig\"\nmode = \"static\"\ndt = 1.0\nsteps = 1\nexcavate = [\"tunnel\"]\n\
         [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n"
    );
    match drawn {
        Drawn::Plug => {
            t += &format!(
                "[[block]]\nname = \"rock\"\nmaterial = \"rock\"\nvertices = {}\nholes = [{}]\n\
                 [[block]]\nname = \"tunnel\"\nmaterial = \"rock\"\nvertices = {}\n",
                pts(&outer),
                pts(&circle(A)),
                pts(&circle(A))
            );
        }
        Drawn::Loop => {
            let mut ring = circle(A);
            ring.push(ring[0]);
            t += &format!(
                "[[block]]\nname = \"rock\"\nmaterial = \"rock\"\nvertices = {}\n\
                 [[joint]]\nname = \"tunnel\"\npoints = {}\n",
                pts(&outer),
                pts(&ring)
            );
        }
    }
    for (e, tr) in [
        ([[-half, -half], [half, -half]], [0.0, -sy]),
        ([[half, -half], [half, half]], [sx, 0.0]),
        ([[half, half], [-half, half]], [0.0, sy]),
        ([[-half, half], [-half, -half]], [-sx, 0.0]),
    ] {
        t += &format!(
            "[[load]]\nblock = \"rock\"\nedge = {}\ntraction = [{:?}, {:?}]\n",
            pts(&e),
            tr[0],
            tr[1]
        );
    }
    for (p, c) in [
        ([0.0, -half], "ux"),
        ([0.0, half], "ux"),
        ([-half, 0.0], "uy"),
    ] {
        t += &format!(
            "[[constraint]]\nblock = \"rock\"\npoint = [{:?}, {:?}]\n{c} = 0.0\n",
            p[0], p[1]
        );
    }
    t
}

/// The result of a tunnel run.
struct Dug {
    /// Largest displacement of any cover after the in-situ stage (m).
    insitu_motion: f64,
    /// u_r at the wall points (the polygon's vertices) and their angles.
    wall: Vec<(f64, f64)>,
    /// σθθ at the wall points.
    hoop: Vec<f64>,
    unknowns: usize,
}

/// The closed forms at the wall (module doc).
fn kirsch_ur(k: f64, theta: f64) -> f64 {
    let g = E / (2.0 * (1.0 + NU));
    let (sx, sy) = (-k * P, -P);
    A / (4.0 * g) * ((sx + sy) + (3.0 - 4.0 * NU) * (sx - sy) * (2.0 * theta).cos())
}

fn kirsch_hoop(k: f64, theta: f64) -> f64 {
    let (sx, sy) = (-k * P, -P);
    (sx + sy) - 2.0 * (sx - sy) * (2.0 * theta).cos()
}

fn run(text: &str) -> Dug {
    let model = parse_model(text, Path::new(".")).unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let rock = sim
        .model
        .blocks
        .iter()
        .position(|b| !b.holes.is_empty())
        .expect("a rock with a hole");
    // the wall points as material points of the rock, on the initial geometry
    let wall: Vec<(f64, MaterialPoint, [f64; 2])> = circle(A)
        .into_iter()
        .map(|x| (x[1].atan2(x[0]), sim.disc.locate(rock, x).unwrap(), x))
        .collect();
    sim.advance().unwrap();
    assert_eq!(sim.stage_name(), Some("insitu"));
    let insitu_motion = sim
        .disc
        .covers
        .iter()
        .filter_map(|c| c.dof)
        .map(|d| sim.u[d].hypot(sim.u[d + 1]))
        .fold(0.0, f64::max);
    let unknowns = sim.n_dofs();
    while !sim.finished() {
        sim.advance().unwrap();
    }
    assert_eq!(sim.stage_name(), Some("dig"));
    let order1 = sim.disc.basis != nmm::cover::CoverBasis::Constant;
    let mut ur = Vec::new();
    let mut hoop = Vec::new();
    for (theta, mp, x) in &wall {
        let u = sim.displacement_at(mp);
        let n = [x[0] / A, x[1] / A];
        ur.push((*theta, u[0] * n[0] + u[1] * n[1]));
        let s = if order1 {
            let sn = &sim.stress_nodes[3 * mp.element..3 * mp.element + 3];
            let w = mp.weights;
            std::array::from_fn(|c| w[0] * sn[0][c] + w[1] * sn[1][c] + w[2] * sn[2][c])
        } else {
            sim.stress[mp.element]
        };
        let t = [-n[1], n[0]];
        hoop.push(t[0] * (s[0] * t[0] + s[2] * t[1]) + t[1] * (s[2] * t[0] + s[1] * t[1]));
    }
    Dug {
        insitu_motion,
        wall: ur,
        hoop,
        unknowns,
    }
}

/// Hydrostatic in-situ stress: the wall's mean radial displacement and hoop stress, and
/// nothing moving before the excavation.
fn check_hydrostatic(label: &str, d: &Dug) {
    let want = kirsch_ur(1.0, 0.0);
    let mean = d.wall.iter().map(|w| w.1).sum::<f64>() / d.wall.len() as f64;
    let spread = d
        .wall
        .iter()
        .map(|w| (w.1 - mean).abs())
        .fold(0.0, f64::max);
    let hoop = d.hoop.iter().sum::<f64>() / d.hoop.len() as f64;
    eprintln!(
        "{label}: {} unknowns; wall u_r {mean:.6e} m (closed form {want:.6e}: {:+.2}%, spread ±{:.2}%), \
         hoop stress {:.4} p (closed form −2: {:+.2}%), in-situ motion {:.2e} of the wall's",
        d.unknowns,
        100.0 * (mean / want - 1.0),
        100.0 * spread / want.abs(),
        hoop / P,
        100.0 * (hoop / (-2.0 * P) - 1.0),
        d.insitu_motion / want.abs()
    );
    assert!(
        (mean / want - 1.0).abs() < 0.05,
        "{label}: wall displacement"
    );
    assert!(
        (hoop / (-2.0 * P) - 1.0).abs() < 0.10,
        "{label}: hoop stress"
    );
    assert!(
        d.insitu_motion < 1e-3 * want.abs(),
        "{label}: the in-situ stage moved {:.3e} m",
        d.insitu_motion
    );
}

/// Acceptance: Kirsch's tunnel under hydrostatic stress, the tunnel drawn as a plug in a
/// block with a hole, at constant covers (h = a/4).
#[test]
fn kirsch_tunnel_hydrostatic_plug_order_0() {
    let d = run(&model(20.0 * A, 0.25 * A, 0, 1.0, Drawn::Plug));
    check_hydrostatic("plug, order 0, h = a/4", &d);
}

/// The same at first-order covers (h = a/2).
#[test]
fn kirsch_tunnel_hydrostatic_plug_order_1() {
    let d = run(&model(20.0 * A, 0.5 * A, 1, 1.0, Drawn::Plug));
    check_hydrostatic("plug, order 1, h = a/2", &d);
}

/// The tunnel drawn as a closed joint loop in one rock block (it cuts out the plug).
#[test]
fn kirsch_tunnel_hydrostatic_joint_loop() {
    let d = run(&model(20.0 * A, 0.25 * A, 0, 1.0, Drawn::Loop));
    check_hydrostatic("joint loop, order 0, h = a/4", &d);
}

/// K = 0.5: the crown (θ = 90°) and the sidewall (θ = 0) against Kirsch, in a square of
/// side 40 a. The sidewall's displacement is the small difference of the isotropic and
/// deviatoric parts (Kirsch: −0.5 against −2.5 at the crown, in p a/4G), and the
/// deviatoric part of the disturbance decays only as 4 a²/r² at the edges: at side 20 a the
/// loaded edges alone take −6.6% from the sidewall and +2.3% from the crown (order 1,
/// h = a/2, against side 80 a), beyond the tolerance; at 40 a −1.3% and +0.6%. Constant
/// covers need h = a/8 there (at a/4: +4.2% and −3.7%).
#[test]
fn kirsch_tunnel_k_half() {
    let k = 0.5;
    for (order, h) in [(0, 0.125), (1, 0.5)] {
        let d = run(&model(40.0 * A, h * A, order, k, Drawn::Plug));
        let at = |theta: f64| {
            d.wall
                .iter()
                .find(|w| (w.0 - theta).abs() < 1e-9)
                .unwrap()
                .1
        };
        let (side, crown) = (at(0.0), at(std::f64::consts::FRAC_PI_2));
        let (ws, wc) = (kirsch_ur(k, 0.0), kirsch_ur(k, std::f64::consts::FRAC_PI_2));
        eprintln!(
            "K = {k}, order {order}, h = {h} a, side 40 a: {} unknowns; sidewall {side:.4e} m \
             (Kirsch {ws:.4e}: {:+.2}%), crown {crown:.4e} m (Kirsch {wc:.4e}: {:+.2}%), hoop \
             stress at the sidewall {:.3} p (Kirsch {:.3}), at the crown {:.3} p (Kirsch {:.3}); \
             in-situ motion {:.2e} of the crown's",
            d.unknowns,
            100.0 * (side / ws - 1.0),
            100.0 * (crown / wc - 1.0),
            d.hoop[0] / P,
            kirsch_hoop(k, 0.0) / P,
            d.hoop[CHORDS / 4] / P,
            kirsch_hoop(k, std::f64::consts::FRAC_PI_2) / P,
            d.insitu_motion / wc.abs()
        );
        assert!((side / ws - 1.0).abs() < 0.05, "order {order}: sidewall");
        assert!((crown / wc - 1.0).abs() < 0.05, "order {order}: crown");
        assert!(
            d.insitu_motion < 1e-3 * ws.abs(),
            "order {order}: in-situ motion"
        );
    }
}

/// The boundary effect of the side 20 a (module doc): against a square of side 40 a at the
/// same cover. Slow (4× the unknowns): run with `--ignored`.
#[test]
#[ignore]
fn the_boundary_effect_of_side_20a() {
    let near = run(&model(20.0 * A, 0.25 * A, 0, 1.0, Drawn::Plug));
    let far = run(&model(40.0 * A, 0.25 * A, 0, 1.0, Drawn::Plug));
    let mean = |d: &Dug| d.wall.iter().map(|w| w.1).sum::<f64>() / d.wall.len() as f64;
    let effect = mean(&near) / mean(&far) - 1.0;
    eprintln!(
        "side 20 a vs 40 a: wall u_r {:.6e} vs {:.6e} m: {:+.2}%",
        mean(&near),
        mean(&far),
        100.0 * effect
    );
    // the thick-cylinder bounds of the module doc: between +0.8% and +1.5% (for 40 a
    // against an infinite medium the same bounds are 4× smaller)
    assert!(effect > 0.0 && effect < 0.02, "{effect}");
}

/// The largest displacement of any cover.
fn largest_motion(sim: &Simulation) -> f64 {
    sim.disc
        .covers
        .iter()
        .filter_map(|c| c.dof)
        .map(|d| sim.u[d].hypot(sim.u[d + 1]))
        .fold(0.0, f64::max)
}

/// A regular polygon of `n` sides, radius `r`, centre `c`, one vertex at angle `t0`.
fn ngon(n: usize, r: f64, c: [f64; 2], t0: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let t = t0 + std::f64::consts::TAU * k as f64 / n as f64;
            [c[0] + r * t.cos(), c[1] + r * t.sin()]
        })
        .collect()
}

/// Acceptance: a model in its in-situ state does not move. A 6 m × 4 m rock with an
/// octagonal hole and its plug, both cut by two joint sets (30° and 120°), under
/// σ₀ = (−3, −5, 1) MPa (a shear stress on every joint: mobilised friction 21° at most,
/// against φ = 40°), its edges loaded by σ₀·n, three point constraints against rigid
/// motion: two static steps at constant and at first-order covers, h = 0.2 and 0.4, and
/// the same without the joints (the rock then one block with a hole). Every face between
/// two blocks meets its neighbour vertex for vertex, so the contacts carry exactly the
/// consistent forces of σ₀·n (the octagon's reflex corners, which make no contact of
/// their own, through the plug's corners), and the blocks' internal forces balance them
/// and the loads: no cover moves more than 1e-9 of σL/E (measured: 0, no Newton
/// iteration; without the contacts' in-situ forces 5e-3 of it, printed).
///
/// The plug's corners are the hard part: a mesh line (h = 0.4) or a joint (h = 0.2)
/// crosses a face of the octagon 6e-4 m or 7e-3 m from its corner, so that face is
/// refined at the corner into a short segment on both blocks. Before the narrow phase chose, at a vertex
/// of B, the face A's long edge runs along (`contact/narrow.rs`, rule 4), the corner's
/// contact took the short segment (by the order of B's segments): its force, mostly that
/// of the long edge, stood at 45° to its normal, beyond friction; it slid, and the model
/// moved (order 1) 1.4e-2 of σL/E at h = 0.2 and 1.0 at h = 0.4, (order 0) 1.6e-2 at
/// h = 0.4, with 112, 123 and 202 contact branch changes in the two steps (without the
/// joints at h = 0.4: 15 and 11).
#[test]
fn an_in_situ_state_with_matching_tractions_does_not_move() {
    let mut cases = Vec::new();
    for order in [0, 1] {
        for h in [0.2, 0.4] {
            for jointed in [true, false] {
                cases.push((order, h, jointed));
            }
        }
    }
    in_situ_state_at_rest(&cases);
}

fn in_situ_state_at_rest(cases: &[(usize, f64, bool)]) {
    let (w, hgt) = (6.0, 4.0);
    let s0 = [-3.0e6, -5.0e6, 1.0e6];
    let hole = ngon(8, 0.8, [3.0, 2.0], 0.3);
    let scale = 5.0e6 * w / E;
    for &(order, h, jointed) in cases {
        let mut t = format!(
            "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 2\n\
             [cover]\nsize = {h:?}\norder = {order}\n\
             [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = {E:?}\npoisson = {NU:?}\n\
             [initial_stress]\nstress = [{:?}, {:?}, {:?}]\n\
             [[block]]\nname = \"rock\"\nmaterial = \"rock\"\nvertices = {}\nholes = [{}]\n\
             [[block]]\nname = \"plug\"\nmaterial = \"rock\"\nvertices = {}\n\
             [[interface]]\nfriction_angle = 40.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n",
            s0[0],
            s0[1],
            s0[2],
            pts(&[[0.0, 0.0], [w, 0.0], [w, hgt], [0.0, hgt]]),
            pts(&hole),
            pts(&hole),
        );
        if jointed {
            t += "[[joint_set]]\nname = \"a\"\nangle = 30.0\nspacing = 1.1\norigin = [0.05, 0.1]\n\
                  [[joint_set]]\nname = \"b\"\nangle = 120.0\nspacing = 1.3\norigin = [0.2, 0.0]\n";
        }
        // σ·n on each edge: bottom n = (0, −1), right (1, 0), top (0, 1), left (−1, 0)
        for (e, n) in [
            ([[0.0, 0.0], [w, 0.0]], [0.0, -1.0]),
            ([[w, 0.0], [w, hgt]], [1.0, 0.0]),
            ([[w, hgt], [0.0, hgt]], [0.0, 1.0]),
            ([[0.0, hgt], [0.0, 0.0]], [-1.0, 0.0]),
        ] {
            let tr = [s0[0] * n[0] + s0[2] * n[1], s0[2] * n[0] + s0[1] * n[1]];
            t += &format!(
                "[[load]]\nblock = \"rock\"\nedge = {}\ntraction = [{:?}, {:?}]\n",
                pts(&e),
                tr[0],
                tr[1]
            );
        }
        for (p, c) in [([0.5, 0.0], "ux"), ([0.5, 0.0], "uy"), ([w, 3.5], "uy")] {
            t += &format!(
                "[[constraint]]\nblock = \"rock\"\npoint = [{:?}, {:?}]\n{c} = 0.0\n",
                p[0], p[1]
            );
        }
        let model = parse_model(&t, Path::new(".")).unwrap();
        let pieces = model.blocks.len();
        let with_holes = model.blocks.iter().filter(|b| !b.holes.is_empty()).count();
        assert!(
            if jointed { pieces > 10 } else { pieces == 2 },
            "{pieces} blocks"
        );
        let mut sim = Simulation::new(model).unwrap();
        while !sim.finished() {
            sim.advance().unwrap();
        }
        let m = largest_motion(&sim);
        eprintln!(
            "order {order}, h = {h}: {pieces} blocks ({with_holes} with a hole), {} contacts, \
             largest motion {:.2e} of σL/E",
            sim.contacts.contacts.len(),
            m / scale
        );
        assert!(m <= 1e-9 * scale, "order {order}: moved {m:.3e} m");
    }
}

/// A layered column at rest under gravity, its in-situ stress growing with depth:
/// σyy = ρ g (y − H), σxx = K σyy (`gradient`, `y_ref` at the top), horizontal bedding
/// joints every 1.5 m, rollers on the sides and the base, the top free. The stress is
/// linear in y: constant covers hold its internal force exactly (constant B), first-order
/// covers the stress itself; the beds' contacts carry the stress at their height exactly (it
/// is constant along a horizontal joint); the rollers' penalty springs give way by
/// reaction/(c E/h), ~1e-7 of ρgH²/E. Bound: 1e-5 of ρgH²/E.
#[test]
fn a_column_at_rest_under_a_stress_growing_with_depth() {
    let (w, hgt, rho, g, k) = (4.0, 6.0, 2500.0, 9.81, 0.6);
    let scale = rho * g * hgt * hgt / E;
    for (order, h) in [(0, 0.25), (1, 0.5)] {
        let t = format!(
            "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 2\ngravity = [0.0, {:?}]\n\
             [cover]\nsize = {h:?}\norder = {order}\n\
             [[material]]\nname = \"rock\"\ndensity = {rho:?}\nyoung = {E:?}\npoisson = {NU:?}\n\
             [initial_stress]\nstress = [0.0, 0.0, 0.0]\ngradient = [{:?}, {:?}, 0.0]\ny_ref = {hgt:?}\n\
             [[block]]\nname = \"col\"\nmaterial = \"rock\"\nvertices = {}\n\
             [[joint_set]]\nname = \"beds\"\nangle = 0.0\nspacing = 1.5\norigin = [0.0, 0.1]\n\
             [[interface]]\nfriction_angle = 35.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
             [[constraint]]\nblock = \"col\"\nedge = [[0.0, 0.0], [{w:?}, 0.0]]\nuy = 0.0\n\
             [[constraint]]\nblock = \"col\"\nedge = [[0.0, 0.0], [0.0, {hgt:?}]]\nux = 0.0\n\
             [[constraint]]\nblock = \"col\"\nedge = [[{w:?}, 0.0], [{w:?}, {hgt:?}]]\nux = 0.0\n",
            -g,
            k * rho * g,
            rho * g,
            pts(&[[0.0, 0.0], [w, 0.0], [w, hgt], [0.0, hgt]]),
        );
        let model = parse_model(&t, Path::new(".")).unwrap();
        assert_eq!(model.blocks.len(), 5);
        let mut sim = Simulation::new(model).unwrap();
        // the stress as set: at the centroid of each element (order 0)
        let e0 = &sim.disc.elements[0];
        let c = nmm::geometry::moments::polygon_moments(&e0.polygon, e0.polygon[0]).centroid();
        let s = sim.stress[0];
        assert!((s[1] - rho * g * (c[1] - hgt)).abs() < 1e-9 * rho * g * hgt);
        assert!((s[0] - k * s[1]).abs() < 1e-9 * rho * g * hgt);
        while !sim.finished() {
            sim.advance().unwrap();
        }
        let m = largest_motion(&sim);
        eprintln!(
            "column, order {order}, h = {h}: largest motion {:.2e} of ρgH²/E",
            m / scale
        );
        assert!(m <= 1e-5 * scale, "order {order}: moved {m:.3e} m");
    }
}
