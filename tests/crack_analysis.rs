//! Cracks analysed through the simulation (issue 15): traces that end inside a block split
//! its covers, their faces are contact faces of the block with itself (`cover::slit`,
//! `contact::set::slits`), and a crack-tip monitor records K_I and K_II (`simulation::tips`).
//! Every model here is a plane-strain plate (E = 1 GPa, ν = 0.25) loaded on two opposite
//! edges, held by point springs that take no load (the loads balance), solved in one static
//! step — except the checkpoint test. Tolerances and measured figures are given per test;
//! the references are closed forms (Tada, Paris & Irwin; Westergaard; the sliding crack).

use nmm::model::parse_model;
use nmm::simulation::{monitor_values, Simulation};
use std::path::Path;

const E: f64 = 1.0e9;
const NU: f64 = 0.25;

/// A square or rectangular plate `[x0, x1] × [y0, y1]` with the crack `crack` (a `[[joint]]`
/// polyline), edge tractions `ty` on the top and `−ty` on the bottom (Pa, y component),
/// cover size `h`, order `order`, friction angle `phi` and the analysis' `friction` law, and
/// the monitors `monitors` (TOML text).
#[allow(clippy::too_many_arguments)]
fn plate(
    [x0, x1, y0, y1]: [f64; 4],
    crack: &[[f64; 2]],
    ty: f64,
    h: f64,
    order: usize,
    phi: f64,
    friction: &str,
    monitors: &str,
) -> String {
    let pts: Vec<String> = crack
        .iter()
        .map(|p| format!("[{}, {}]", p[0], p[1]))
        .collect();
    let ym = 0.5 * (y0 + y1);
    format!(
        "[analysis]\nmode = \"static\"\ndt = 0.001\nsteps = 1\nfriction = \"{friction}\"\n\
         [cover]\nsize = {h}\norigin = [{ox}, {oy}]\norder = {order}\n\
         [[material]]\nname = \"m\"\ndensity = 1000.0\nyoung = {E:e}\npoisson = {NU}\n\
         [[block]]\nname = \"plate\"\nmaterial = \"m\"\n\
         vertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]\n\
         [[joint]]\nname = \"crack\"\npoints = [{pts}]\n\
         [[interface]]\nfriction_angle = {phi}\nnormal_penalty = 1.0e11\nshear_penalty = 1.0e11\n\
         [[load]]\nblock = \"plate\"\nedge = [[{x0}, {y1}], [{x1}, {y1}]]\ntraction = [0.0, {ty:e}]\n\
         [[load]]\nblock = \"plate\"\nedge = [[{x0}, {y0}], [{x1}, {y0}]]\ntraction = [0.0, {mty:e}]\n\
         [[constraint]]\nblock = \"plate\"\npoint = [{x1}, {ym}]\nux = 0.0\nuy = 0.0\n\
         [[constraint]]\nblock = \"plate\"\npoint = [{x1}, {yq}]\nux = 0.0\n\
         {monitors}",
        ox = 0.31 * h,
        oy = 0.37 * h,
        pts = pts.join(", "),
        mty = -ty,
        yq = 0.5 * (ym + y1),
    )
}

fn point(name: &str, p: [f64; 2]) -> String {
    format!(
        "[[monitor]]\nname = \"{name}\"\npoint = [{:e}, {:e}]\n",
        p[0], p[1]
    )
}

fn tip(name: &str, p: [f64; 2]) -> String {
    format!(
        "[[monitor]]\nname = \"{name}\"\ncrack = \"crack\"\ntip = [{}, {}]\n",
        p[0], p[1]
    )
}

/// Runs the model to its end; the simulation and the monitor values of the last step.
fn solve(text: &str) -> (Simulation, Vec<f64>) {
    let mut sim = Simulation::new(parse_model(text, Path::new(".")).unwrap()).unwrap();
    while !sim.finished() {
        sim.advance().unwrap();
    }
    let v = monitor_values(&sim);
    (sim, v)
}

/// (closed, all) contacts of the block with itself (its crack faces), those within `near`
/// of the point `tip` left out.
fn crack_contacts(sim: &Simulation, tip: [f64; 2], near: f64) -> (usize, usize) {
    let own: Vec<_> = sim
        .contacts
        .contacts
        .iter()
        .filter(|c| c.key.0 == c.key.2 && nmm::geometry::dist(c.position, tip) >= near)
        .collect();
    let closed = own.iter().filter(|c| c.response.tn < 0.0).count();
    (closed, own.len())
}

/// Single-edge-cracked plate (W = 1, height 4 W, a/W = 0.4) in tension σ = 1 MPa, against
/// Tada–Paris–Irwin (0.5%): CMOD = 4σaV(α)/E′, V(0.4) = 3.2288; K_I = σ√(πa)F(α),
/// F(0.4) = 2.1036. CMOD is the opening of the mouth between monitors 1e-6 m either side
/// of it. Tolerance 10% at h = W/40 (the issue's), met with first-order covers (measured
/// CMOD −6.0%, K_I −3.8%); constant covers converge at first order in h (measured CMOD
/// −22.4%, −11.3%, −5.3% at W/20, W/40, W/80: the jump fades over the element holding the
/// tip, which is not split, so the crack acts about h/2 short; K_I −15.3%, −7.5%, −3.9%).
/// In tension every crack contact (farther than 2h from the tip) is open.
#[test]
fn single_edge_cracked_plate_in_tension() {
    let (w, a, sigma) = (1.0, 0.4, 1.0e6);
    let alpha: f64 = a / w;
    let c = (std::f64::consts::FRAC_PI_2 * alpha).cos();
    let v = (1.46 + 3.42 * (1.0 - c)) / (c * c);
    let f = 1.12 - 0.231 * alpha + 10.55 * alpha.powi(2) - 21.72 * alpha.powi(3)
        + 30.39 * alpha.powi(4);
    let e_eff = E / (1.0 - NU * NU);
    let cmod_ref = 4.0 * sigma * a * v / e_eff;
    let k_ref = sigma * (std::f64::consts::PI * a).sqrt() * f;
    let monitors = format!(
        "{}{}{}",
        point("up", [0.0, 1e-6]),
        point("lo", [0.0, -1e-6]),
        tip("k", [a, 0.0])
    );
    let errors = |order: usize, div: f64| {
        let text = plate(
            [0.0, w, -2.0 * w, 2.0 * w],
            &[[-0.1, 0.0], [a, 0.0]],
            sigma,
            w / div,
            order,
            30.0,
            "return-mapping",
            &monitors,
        );
        let (sim, v) = solve(&text);
        // within 2h of the tip, where the faces share covers, a contact may be closed
        let (closed, all) = crack_contacts(&sim, [a, 0.0], 2.0 * w / div);
        assert!(all > 0, "no contacts on the crack faces");
        assert_eq!(
            closed, 0,
            "order {order}, W/{div}: {closed} of {all} closed in tension"
        );
        let cmod = v[1] - v[5];
        let (ec, ek) = (cmod / cmod_ref - 1.0, v[8] / k_ref - 1.0);
        eprintln!(
            "order {order}, h = W/{div}: CMOD {cmod:.5e} ({:+.2}% of {cmod_ref:.5e}), K_I {:.5e} ({:+.2}% of {k_ref:.5e}), K_II {:.2e}; {all} crack contacts, all open",
            100.0 * ec,
            v[8],
            100.0 * ek,
            v[9]
        );
        (ec, ek)
    };
    let (ec, ek) = errors(1, 40.0);
    assert!(ec.abs() < 0.10, "CMOD at W/40, order 1: {ec:+.4}");
    assert!(ek.abs() < 0.10, "K_I at W/40, order 1: {ek:+.4}");
    let e0: Vec<(f64, f64)> = [20.0, 40.0, 80.0].iter().map(|&d| errors(0, d)).collect();
    assert!(e0[2].0.abs() < 0.10 && e0[1].1.abs() < 0.10, "{e0:?}");
    for k in 0..2 {
        assert!(
            e0[k].0.abs() > 1.7 * e0[k + 1].0.abs() && e0[k].1.abs() > 1.7 * e0[k + 1].1.abs(),
            "no first-order convergence: {e0:?}"
        );
    }
}

/// The same plate in compression: the crack closes (every crack contact closed) and the
/// plate is as stiff as without the crack within 1% (the issue's; measured 6.5e-6 at
/// W/40), from the shortening between the middles of the loaded edges.
#[test]
fn an_edge_crack_closes_in_compression() {
    let (w, a, sigma) = (1.0, 0.4, 1.0e6);
    let monitors = format!(
        "{}{}",
        point("top", [0.5, 2.0 * w]),
        point("bot", [0.5, -2.0 * w])
    );
    let cracked = plate(
        [0.0, w, -2.0 * w, 2.0 * w],
        &[[-0.1, 0.0], [a, 0.0]],
        -sigma,
        w / 40.0,
        0,
        30.0,
        "return-mapping",
        &monitors,
    );
    let (sim, v) = solve(&cracked);
    let (closed, all) = crack_contacts(&sim, [a, 0.0], 0.0);
    let shortening = v[1] - v[5];
    // the same plate without its crack
    let whole = cracked.replace(
        "[[joint]]\nname = \"crack\"\npoints = [[-0.1, 0], [0.4, 0]]\n",
        "",
    );
    assert_ne!(whole, cracked);
    let (sim0, v0) = solve(&whole);
    assert!(sim0.disc.slits.is_empty());
    let s0 = v0[1] - v0[5];
    eprintln!(
        "compression: {closed} of {all} crack contacts closed; shortening {shortening:.6e} m, uncracked {s0:.6e} m ({:+.2e})",
        shortening / s0 - 1.0
    );
    assert!(all > 0 && closed == all, "{closed} of {all} closed");
    assert!((shortening / s0 - 1.0).abs() < 0.01);
}

/// Centre crack 2a = 0.2 m in a plate W = 10 a (the issue's smallest) under remote tension
/// σ: K_I against σ√(πa) √sec(πa/W) (Feddersen's finite-width correction, +2.5% here,
/// 0.3% of the exact), tolerance 10% at h = a/5 and a/10 (measured −0.8%, +0.9%); the
/// opening at the centre against Westergaard's 4σ(1 − ν²)a/E (infinite plate; the finite
/// width adds ~2%), tolerance 10% at h = a/10 (measured −14.5%, −4.1% at a/5, a/10),
/// decreasing with h. Both tips give the same K (within 2%; measured 0.05%).
#[test]
fn centre_crack_in_a_large_plate() {
    let (a, sigma) = (0.1, 1.0e6);
    let half = 5.0 * a;
    let k_ref = sigma
        * (std::f64::consts::PI * a).sqrt()
        * (1.0 / (std::f64::consts::PI * a / (2.0 * half)).cos()).sqrt();
    let open_ref = 4.0 * sigma * (1.0 - NU * NU) * a / E;
    let monitors = format!(
        "{}{}{}{}",
        point("up", [0.0, 1e-7]),
        point("lo", [0.0, -1e-7]),
        tip("kr", [a, 0.0]),
        tip("kl", [-a, 0.0])
    );
    let mut open_errors = Vec::new();
    for div in [5.0, 10.0] {
        let text = plate(
            [-half, half, -half, half],
            &[[-a, 0.0], [a, 0.0]],
            sigma,
            a / div,
            0,
            30.0,
            "return-mapping",
            &monitors,
        );
        let (_, v) = solve(&text);
        let open = v[1] - v[5];
        let (kr, kl) = (v[8], v[10]);
        eprintln!(
            "h = a/{div}: K_I {kr:.5e} / {kl:.5e} ({:+.2}% / {:+.2}% of {k_ref:.5e}); opening {open:.5e} ({:+.2}% of {open_ref:.5e})",
            100.0 * (kr / k_ref - 1.0),
            100.0 * (kl / k_ref - 1.0),
            100.0 * (open / open_ref - 1.0)
        );
        assert!((kr / k_ref - 1.0).abs() < 0.10 && (kl / k_ref - 1.0).abs() < 0.10);
        assert!((kr / kl - 1.0).abs() < 0.02, "the two tips: {kr} vs {kl}");
        open_errors.push(open / open_ref - 1.0);
    }
    assert!(open_errors[1].abs() < 0.10, "{open_errors:?}");
    assert!(
        open_errors[0].abs() > 1.5 * open_errors[1].abs(),
        "{open_errors:?}"
    );
}

/// Inclined centre crack (2a = 0.2 m at β = 45° from the load axis) in a plate W = 10 a
/// under uniaxial compression p = 1 MPa: on the crack σ_n = −p/2 and τ = p/2, so the faces
/// slide when tan φ < 1. Above that (φ = 60°) they stick: the sliding displacement at the
/// centre is only the shear penalty's elastic slip (bound 1e-3 of the sliding case's
/// reference; measured 1.25e-8 m against 1.19e-4 m). Below (φ = 20°) they slide with the
/// displacement at the centre 4(1 − ν²) τ_eff a / E, τ_eff = τ − |σ_n| tan φ (a crack in
/// an infinite plate under the shear τ_eff), tolerance 10% (the issue's), and K_II against
/// τ_eff √(πa), tolerance 15% (the issue's), with first-order covers at h = a/10 (measured
/// −7.5% and +11.1%; with W = 20 a −9.6% and +8.8%; constant covers with W = 20 a: sliding
/// −12.5%, −6.2% at h = a/10, a/20, K_II +23.6%, +17.5%). With `friction = "conventional"` one static step leaves the
/// faces stuck (the explicit treatment slides by the last step's state).
#[test]
fn an_inclined_closed_crack_sticks_or_slides_by_its_friction() {
    let (a, p) = (0.1, 1.0e6);
    let half = 5.0 * a;
    let (s, c) = std::f64::consts::FRAC_PI_4.sin_cos();
    let dir = [s, c];
    let n = [c, -s];
    let e = 1e-7;
    let monitors = format!(
        "{}{}{}",
        point("p", [-e * n[0], -e * n[1]]),
        point("m", [e * n[0], e * n[1]]),
        tip("k", [a * dir[0], a * dir[1]])
    );
    let crack = [[-a * dir[0], -a * dir[1]], [a * dir[0], a * dir[1]]];
    let run = |phi: f64, div: f64, order: usize, friction: &str| {
        let text = plate(
            [-half, half, -half, half],
            &crack,
            -p,
            a / div,
            order,
            phi,
            friction,
            &monitors,
        );
        let (sim, v) = solve(&text);
        let slide = (v[0] - v[4]) * dir[0] + (v[1] - v[5]) * dir[1];
        let (closed, all) = crack_contacts(&sim, [0.0, 0.0], 0.0);
        (slide.abs(), v[9].abs(), closed, all)
    };
    let tau_eff = 0.5 * p * (1.0 - 20f64.to_radians().tan());
    let slide_ref = 4.0 * (1.0 - NU * NU) * tau_eff * a / E;
    let k_ref = tau_eff * (std::f64::consts::PI * a).sqrt();
    let (stick, _, closed, all) = run(60.0, 10.0, 0, "return-mapping");
    eprintln!("φ = 60°: sliding {stick:.3e} m ({closed} of {all} crack contacts closed)");
    assert!(stick < 1e-3 * slide_ref && closed > 0);
    let (slide, k2, _, _) = run(20.0, 10.0, 1, "return-mapping");
    eprintln!(
        "φ = 20°, h = a/10, order 1: sliding {slide:.5e} m ({:+.2}% of {slide_ref:.5e}), K_II {k2:.5e} ({:+.2}% of {k_ref:.5e})",
        100.0 * (slide / slide_ref - 1.0),
        100.0 * (k2 / k_ref - 1.0)
    );
    assert!((slide / slide_ref - 1.0).abs() < 0.10);
    assert!((k2 / k_ref - 1.0).abs() < 0.15);
    // the conventional (explicit) friction: each step slides by the state of the last
    // one, so that one static step holds the faces stuck
    let (conv, _, _, _) = run(20.0, 10.0, 0, "conventional");
    eprintln!("φ = 20°, conventional friction, one step: sliding {conv:.3e} m");
    assert!(conv < 1e-3 * slide_ref);
}

/// A crack ending inside a block: the faces open apart (a jump of the displacement across
/// them), and there is none ahead of the tip — monitors 1e-7 m either side of the crack's
/// line, half an element and one element ahead of the tip, move alike (to 1e-5 of the
/// opening: what is left is the strain across the 2e-7 m between them; measured 8e-7 and
/// 5e-7); 2h behind the tip they part.
#[test]
fn the_displacement_jumps_across_the_faces_and_not_beyond_the_tip() {
    let (w, a, h) = (1.0, 0.4, 1.0 / 40.0);
    let e = 1e-7;
    let at = |x: f64| {
        [
            point(&format!("u{x}"), [x, e]),
            point(&format!("d{x}"), [x, -e]),
        ]
        .concat()
    };
    let xs = [a - 2.0 * h, a + 0.5 * h, a + h];
    let monitors: String = xs.iter().map(|&x| at(x)).collect();
    let text = plate(
        [0.0, w, -2.0 * w, 2.0 * w],
        &[[-0.1, 0.0], [a, 0.0]],
        1.0e6,
        h,
        0,
        30.0,
        "return-mapping",
        &monitors,
    );
    let (_, v) = solve(&text);
    let jump = |k: usize| v[8 * k + 1] - v[8 * k + 5];
    let behind = jump(0);
    eprintln!(
        "opening 2h behind the tip {behind:.4e} m; h/2 ahead {:.2e}, h ahead {:.2e}",
        jump(1),
        jump(2)
    );
    assert!(behind > 1e-4);
    assert!(jump(1).abs() < 1e-5 * behind && jump(2).abs() < 1e-5 * behind);
}

fn nmm(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(args)
        .output()
        .unwrap()
}

/// Checkpoints and `nmm resume` with cracks: a dynamic run of the edge-cracked plate
/// (loaded suddenly, so the crack opens as the plate rings; a tip monitor) in two stages of
/// 20 and 40 steps, resumed from the checkpoint at the end of the first, writes
/// history.csv and the last frames byte for byte as the uninterrupted run.
#[test]
fn checkpoints_and_resume_are_exact_with_cracks() {
    let (w, a) = (1.0, 0.4);
    let text = plate(
        [0.0, w, -2.0 * w, 2.0 * w],
        &[[-0.1, 0.0], [a, 0.0]],
        1.0e6,
        w / 10.0,
        0,
        30.0,
        "return-mapping",
        &format!(
            "{}{}{}",
            point("up", [0.0, 1e-6]),
            point("lo", [0.0, -1e-6]),
            tip("k", [a, 0.0])
        ),
    )
    .replace(
        "mode = \"static\"\ndt = 0.001\nsteps = 1",
        "mode = \"dynamic\"\ndt = 0.0001\nsteps = 60\noutput_every = 20",
    ) + "[[stage]]\nname = \"a\"\nsteps = 20\n[[stage]]\nname = \"b\"\nsteps = 40\n";
    assert!(text.contains("steps = 60"));
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("cracked.toml");
    std::fs::write(&model, text).unwrap();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let full = dir.path().join("full");
    let o = nmm(&["run", &s(&model), "--out", &s(&full), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let history = std::fs::read(full.join("history.csv")).unwrap();
    let text = String::from_utf8(history.clone()).unwrap();
    // the crack's mouth opened
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (up, lo) = (col("up.uy"), col("lo.uy"));
    let opening: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            v[up].parse::<f64>().unwrap() - v[lo].parse::<f64>().unwrap()
        })
        .collect();
    assert!(opening.iter().any(|&o| o > 1e-5), "{opening:?}");
    let out = dir.path().join("resumed");
    assert!(std::process::Command::new("cp")
        .args(["-r", &s(&full), &s(&out)])
        .status()
        .unwrap()
        .success());
    assert!(out.join("checkpoints/step_00000020.ckpt").exists());
    std::fs::remove_file(out.join("checkpoints/step_00000060.ckpt")).unwrap();
    let o = nmm(&["resume", &s(&out), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        std::fs::read(out.join("history.csv")).unwrap() == history,
        "resumed from step 20: history differs"
    );
    for f in [
        "contacts.pvd",
        "vtk/contacts_000060.vtu",
        "vtk/blocks_000060.vtu",
    ] {
        assert!(
            std::fs::read(out.join(f)).unwrap() == std::fs::read(full.join(f)).unwrap(),
            "{f} differs"
        );
    }
}

/// Bad crack-tip monitors get one line naming the monitor, the key and the line; a crack
/// that splits no cover (inside the elements holding its tips) is warned about.
#[test]
fn bad_crack_tip_monitors_and_ineffective_cracks() {
    let base = |crack: &[[f64; 2]], monitors: &str| {
        plate(
            [0.0, 1.0, -2.0, 2.0],
            crack,
            1.0e6,
            0.1,
            0,
            30.0,
            "return-mapping",
            monitors,
        )
    };
    let edge = [[-0.1, 0.0], [0.4, 0.0]];
    for (monitor, want) in [
        (
            "[[monitor]]\nname = \"k\"\ncrack = \"nope\"\ntip = [0.4, 0.0]\n",
            "unknown joint \"nope\"",
        ),
        (
            "[[monitor]]\nname = \"k\"\ncrack = \"crack\"\ntip = [0.8, 0.0]\n",
            "no tip of joint \"crack\" within the cover size 0.1 of [0.8,0]: the nearest is [0.4,0]",
        ),
        (
            "[[monitor]]\nname = \"k\"\ncrack = \"crack\"\ntip = [0.4, 0.0]\nradii = [0.3, 0.2]\n",
            "0 < r_in < r_out",
        ),
        (
            "[[monitor]]\nname = \"k\"\npoint = [0.5, 0.5]\ntip = [0.4, 0.0]\n",
            "belongs to a crack-tip monitor",
        ),
        (
            "[[monitor]]\nname = \"k\"\ncrack = \"crack\"\n",
            "tip",
        ),
    ] {
        let err = parse_model(&base(&edge, monitor), Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("accepted: {monitor}"))
            .to_string();
        eprintln!("{err}");
        assert!(err.contains(want) && err.contains("[[monitor]]"), "{err}");
        assert!(err.contains("line"), "no line: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    // a joint through the whole plate cuts it: no crack, so no tip
    let err = parse_model(
        &base(
            &[[-0.1, 0.0], [1.1, 0.0]],
            "[[monitor]]\nname = \"k\"\ncrack = \"crack\"\ntip = [1.0, 0.0]\n",
        ),
        Path::new("."),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(err.contains("has no crack tip inside a block"), "{err}");
    // a crack inside the elements at its tips splits nothing: warned
    let sim = Simulation::new(
        parse_model(&base(&[[0.3, 0.01], [0.3001, 0.01]], ""), Path::new(".")).unwrap(),
    )
    .unwrap();
    let w = sim.warnings();
    assert!(
        w.iter()
            .any(|w| w.contains("1 of 1 crack(s) split no physical cover")),
        "{w:?}"
    );
}

/// A crack of several segments (a kink) and two cracks that cross, in one plate under
/// tension: the discretisation splits covers along all of them, every crack contact away
/// from the tips opens (but on the crack along the load, pressed by the other's T-stress),
/// and the kinked and the horizontal crack open at their middles (monitors 1e-7 m either
/// side).
#[test]
fn kinked_and_crossing_cracks_open_under_tension() {
    let h = 0.05;
    // a kinked crack on the left, an X of two cracks on the right (one joint each: the
    // crossing pair as two joints)
    let kinked = [[0.1, 0.2], [0.3, 0.3], [0.5, 0.2]];
    let text = plate(
        [0.0, 2.0, -1.0, 1.0],
        &kinked,
        1.0e6,
        h,
        0,
        30.0,
        "return-mapping",
        &[
            point("ku", [0.3, 0.3 + 1e-7]),
            point("kd", [0.3, 0.3 - 1e-7]),
            point("xu", [1.2, -0.2 + 1e-7]),
            point("xd", [1.2, -0.2 - 1e-7]),
        ]
        .concat(),
    ) + "[[joint]]\nname = \"x1\"\npoints = [[1.1, -0.2], [1.5, -0.2]]\n\
         [[joint]]\nname = \"x2\"\npoints = [[1.3, -0.45], [1.3, 0.05]]\n";
    let (sim, v) = solve(&text);
    // the crossing traces are cut at their crossing: two cracks each
    assert!(sim.model.cracks.len() >= 3, "{:?}", sim.model.cracks);
    assert!(sim.disc.slits.len() >= 3);
    // in tension every crack contact farther than 2h from every tip is open
    let tips: Vec<[f64; 2]> = sim
        .model
        .cracks
        .iter()
        .flat_map(|c| [c.points[0], *c.points.last().unwrap()])
        .collect();
    let loaded: Vec<_> = sim
        .contacts
        .contacts
        .iter()
        .filter(|c| c.key.0 == c.key.2)
        .filter(|c| {
            tips.iter()
                .all(|&t| nmm::geometry::dist(c.position, t) > 2.0 * h)
        })
        .filter(|c| c.response.tn < 0.0)
        .collect();
    // the vertical crack x2 (joint 2), parallel to the load, is pressed shut where it
    // crosses the horizontal one: along a crack opened by σ_yy the stress parallel to it
    // is about −σ_yy (the T-stress of a Griffith crack); every other crack contact opens
    let closed_x2 = loaded.iter().filter(|c| c.joint == Some(2)).count();
    let others = loaded.len() - closed_x2;
    eprintln!("closed crack contacts: {closed_x2} on the vertical crack, {others} elsewhere");
    assert_eq!(others, 0);
    let (kink, cross) = (v[1] - v[5], v[9] - v[13]);
    eprintln!("opening of the kinked crack {kink:.4e} m, of the crossing one {cross:.4e} m");
    assert!(kink > 1e-5 && cross > 1e-5);
}

/// In-situ stress with a crack: a plate with an inclined closed crack, the in-situ stress
/// σ₀ = −1 MPa (hydrostatic) and the boundary tractions σ₀·n that hold it, stays exactly at
/// rest — the crack faces' contacts carry σ₀·n from the start (their in-situ offsets), no
/// Newton iteration is needed and no point moves.
#[test]
fn a_crack_under_in_situ_stress_stays_at_rest() {
    let (s, c) = std::f64::consts::FRAC_PI_4.sin_cos();
    let a = 0.1;
    let mut text = plate(
        [-1.0, 1.0, -1.0, 1.0],
        &[[-a * s, -a * c], [a * s, a * c]],
        -1.0e6,
        0.02,
        0,
        20.0,
        "return-mapping",
        &[point("p", [-7e-8, 7e-8]), point("corner", [-1.0, 1.0])].concat(),
    )
    .replace("steps = 1", "steps = 3");
    text += "[initial_stress]\nstress = [-1.0e6, -1.0e6, 0.0]\n\
             [[load]]\nblock = \"plate\"\nedge = [[-1.0, -1.0], [-1.0, 1.0]]\ntraction = [1.0e6, 0.0]\n\
             [[load]]\nblock = \"plate\"\nedge = [[1.0, -1.0], [1.0, 1.0]]\ntraction = [-1.0e6, 0.0]\n";
    let mut sim = Simulation::new(parse_model(&text, Path::new(".")).unwrap()).unwrap();
    let mut iterations = 0;
    while !sim.finished() {
        iterations += sim.advance().unwrap().iterations;
    }
    let v = monitor_values(&sim);
    let (closed, all) = crack_contacts(&sim, [0.0, 0.0], 0.0);
    eprintln!(
        "in-situ: {iterations} iterations, monitors {v:?}, {closed} of {all} crack contacts closed"
    );
    assert!(all > 0 && closed > 0);
    assert_eq!(iterations, 0);
    assert!(v.iter().all(|x| x.abs() < 1e-12), "{v:?}");
}
