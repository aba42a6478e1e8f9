//! Rock bolts (`[[bolt]]`, `crate::bolt`): the bolted block of issue 17 against its closed
//! forms, installation at a stage's start, outputs, checkpoints and `nmm resume`.
//!
//! The bolted block: the slider of the `incline` case (0.5 m × 0.25 m, ρ = 2000 kg/m³,
//! E = 1 GPa: m = 250 kg per metre) on a plane dipping θ = 30° with φ = 20° < θ, held by a
//! bolt along the slope from the slider's centre line (0.1 m inside its upslope face) to
//! an abutment of the fixed base 0.2 m upslope of it (the base's top face steps up there).
//! The model is drawn with the plane along x and rotated by −θ, so that the mathematical
//! mesh is not aligned with it.

use nmm::model::parse_model;
use nmm::simulation::{monitor_values, Simulation};
use nmm::verify::cases::{place, point, poly};
use std::path::Path;

const THETA: f64 = 30.0;
const PHI: f64 = 20.0;
const G: f64 = 9.81;
/// The slider's mass per metre: ρ × 0.5 m × 0.25 m.
const MASS: f64 = 2000.0 * 0.5 * 0.25;

/// The slope's driving force net of friction, m g (sin θ − cos θ tan φ) (N/m).
fn net_force() -> f64 {
    let (s, c) = THETA.to_radians().sin_cos();
    MASS * G * (s - c * PHI.to_radians().tan())
}

/// The bolted block (see the module docs) with `analysis` (the `[analysis]` keys and any
/// `[[stage]]`), the bolt's `bolt` keys and `[cover] extra` keys. Monitors: `c` (the
/// slider's centre), `s` (the slider as a block), `b1` (the bolt).
fn bolted_block(analysis: &str, bolt: &str, cover: &str) -> String {
    let rot = |pts: &[[f64; 2]]| place(pts, -THETA, [0.0, 2.5]);
    let base = rot(&[
        [0.0, -0.5],
        [4.0, -0.5],
        [4.0, 0.0],
        [0.3, 0.0],
        [0.3, 0.25],
        [0.0, 0.25],
    ]);
    let slider = rot(&[[0.5, 0.0], [1.0, 0.0], [1.0, 0.25], [0.5, 0.25]]);
    let anchors = rot(&[[0.6, 0.125], [0.15, 0.125]]);
    let c = rot(&[[0.75, 0.125]])[0];
    format!(
        "{analysis}\n[cover]\nsize = 0.0625\n{cover}\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = {}\nfixed = true\n\
         [[block]]\nname = \"slider\"\nmaterial = \"rock\"\nvertices = {}\n\
         [[interface]]\nfriction_angle = {PHI}\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n\
         [[bolt]]\nname = \"b1\"\npoints = [{}, {}]\n{bolt}\n\
         [[monitor]]\nname = \"c\"\npoint = {}\n\
         [[monitor]]\nname = \"s\"\nblock = \"slider\"\n\
         [[monitor]]\nname = \"b1\"\nbolt = \"b1\"\n",
        poly(&base),
        poly(&slider),
        point(anchors[0]),
        point(anchors[1]),
        point(c),
    )
}

fn simulate(text: &str) -> Simulation {
    Simulation::new(parse_model(text, Path::new(".")).unwrap()).unwrap()
}

/// The monitor values by column name after the last step.
struct Values {
    v: Vec<f64>,
}

impl Values {
    fn of(sim: &Simulation) -> Values {
        Values {
            v: monitor_values(sim),
        }
    }
    /// Columns: c.ux c.uy c.vx c.vy | s.x s.y s.rotation | b1.force b1.elongation.
    fn slip(&self) -> f64 {
        let (s, c) = THETA.to_radians().sin_cos();
        self.v[4] * c - self.v[5] * s
    }
    fn speed(&self) -> f64 {
        let (s, c) = THETA.to_radians().sin_cos();
        self.v[2] * c - self.v[3] * s
    }
    fn force(&self) -> f64 {
        self.v[7]
    }
    fn elongation(&self) -> f64 {
        self.v[8]
    }
}

/// Static: the bolt holds the block. It slides until the bolt carries what friction does
/// not, F = m g (sin θ − cos θ tan φ), by F/k. Tolerances 1% (the issue's); what is left is
/// the block's elastic distortion between the anchor and its centroid (F/E ~ 5e-7 m
/// against a slip of 4.5e-3 m) and the Newton tolerance.
#[test]
fn a_bolt_holds_the_block_with_the_force_friction_leaves() {
    for order in [0, 1] {
        let k = 1.0e5;
        let text = bolted_block(
            "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = 3\ngravity = [0.0, -9.81]",
            &format!("stiffness = {k:e}\ncapacity = 1.0e4"),
            &format!("order = {order}"),
        );
        let mut sim = simulate(&text);
        while !sim.finished() {
            let r = sim.advance().unwrap();
            assert!(r.equilibrium);
        }
        let v = Values::of(&sim);
        let f = net_force();
        eprintln!(
            "order {order}: bolt force {:.6} N vs m g (sin θ − cos θ tan φ) = {f:.6} N ({:+.4}%); \
             slip {:.6e} m vs F/k = {:.6e} m ({:+.4}%); elongation {:.6e} m",
            v.force(),
            (v.force() / f - 1.0) * 100.0,
            v.slip(),
            v.force() / k,
            (v.slip() / (v.force() / k) - 1.0) * 100.0,
            v.elongation()
        );
        assert!((v.force() / f - 1.0).abs() < 0.01);
        assert!((v.slip() / (v.force() / k) - 1.0).abs() < 0.01);
    }
}

/// Dynamic, with a capacity F_y below that force: the bolt yields and the block slides
/// with a = g (sin θ − cos θ tan φ) − F_y/m. The acceleration is measured from the
/// centre's velocity along the slope between t = 0.4 s and t = 1 s (after the bolt has
/// yielded), tolerance 1% (the issue's).
#[test]
fn a_yielding_bolt_lets_the_block_slide_with_the_reduced_acceleration() {
    yielding_bolt(0);
}

/// The same at `[cover] order = 1`.
#[test]
fn a_yielding_bolt_lets_the_block_slide_with_the_reduced_acceleration_at_order_1() {
    yielding_bolt(1);
}

fn yielding_bolt(order: usize) {
    let (k, fy) = (1.0e5, 200.0);
    let text = bolted_block(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 1000\ngravity = [0.0, -9.81]",
        &format!("stiffness = {k:e}\ncapacity = {fy:e}"),
        &format!("order = {order}"),
    );
    let mut sim = simulate(&text);
    let mut v1 = None;
    while !sim.finished() {
        sim.advance().unwrap();
        if (sim.time - 0.4).abs() < 1e-9 {
            v1 = Some(Values::of(&sim).speed());
        }
    }
    let v = Values::of(&sim);
    let a = (v.speed() - v1.unwrap()) / 0.6;
    let exact = net_force() / MASS - fy / MASS;
    eprintln!(
        "yielding bolt, order {order}: a = {a:.6} m/s² vs g (sin θ − cos θ tan φ) − F_y/m = {exact:.6} ({:+.4}%); \
         force {} N, elongation {:.6} m, slip {:.6} m",
        (a / exact - 1.0) * 100.0,
        v.force(),
        v.elongation(),
        v.slip()
    );
    assert_eq!(v.force(), fy);
    assert!((a / exact - 1.0).abs() < 0.01);
}

/// The energy balance closes with bolts: stored + dissipated (friction, the bolt's plastic
/// work, the scheme's) = work done (gravity, the pretension at installation), for a
/// yielding bolt with a pretension and for an elastic one that catches the block (it
/// oscillates on the bolt, friction damping it). Tolerance 1e-8 of the largest energy
/// flow.
#[test]
fn the_energy_balance_closes_with_bolts() {
    for (fy, pre) in [(200.0, 50.0), (1.0e4, 0.0)] {
        let text = bolted_block(
            "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 600\ngravity = [0.0, -9.81]",
            &format!("stiffness = 1.0e5\ncapacity = {fy:e}\npretension = {pre:e}"),
            "",
        );
        let mut sim = simulate(&text);
        while !sim.finished() {
            sim.advance().unwrap();
        }
        let e = sim.energy;
        eprintln!(
            "F_y {fy} N, N₀ {pre} N: balance error {:.3e} (relative {:.3e}); bolt stored {:.6} J, plastic {:.6} J, friction {:.6} J, algorithmic {:.6e} J, gravity {:.6} J",
            e.balance_error(),
            e.balance_error_relative(),
            e.bolts,
            e.bolt_plastic,
            e.friction,
            e.algorithmic,
            e.gravity
        );
        // measured 5e-11 and 7e-11 of the energy flow (the Newton tolerance, 1e-9)
        assert!(e.balance_error_relative().abs() < 1e-8);
    }
}

/// The bolted block in stages: `slide` (100 steps of 1 ms, no bolt: the block slides
/// freely), `support` (the bolt installed at its start with a pretension of 50 N and the
/// given capacity — 200 N: it yields —; 100 steps), `hold` (50 more steps).
fn staged(capacity: f64) -> String {
    bolted_block(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 100\ngravity = [0.0, -9.81]\noutput_every = 25\n\
         [[stage]]\nname = \"slide\"\n[[stage]]\nname = \"support\"\n[[stage]]\nname = \"hold\"\nsteps = 50",
        &format!("stiffness = 1.0e5\ncapacity = {capacity:e}\npretension = 50.0\nstage = \"support\""),
        "",
    )
}

/// Installed at the start of its stage, a bolt takes nothing from the motion before: during
/// `slide` its force and elongation are 0 while the block slides ½ a t² (within 2%); from
/// `support` on its elongation is the slip since the installation (the block's centroid
/// along the bolt, to 10 N/E — the block's distortion between anchor and centroid under
/// the bolt's force N — plus 1e-6 of it) and its force is the pretension + k × elongation
/// (capacity 1e4 N: elastic throughout).
#[test]
fn a_bolt_installed_at_a_stage_takes_no_load_from_earlier_motion() {
    let mut sim = simulate(&staged(1.0e4));
    let mut installed_at = None;
    let mut worst = 0.0f64;
    while !sim.finished() {
        sim.advance().unwrap();
        let v = Values::of(&sim);
        match sim.stage_name() {
            Some("slide") => {
                assert_eq!((v.force(), v.elongation()), (0.0, 0.0));
                assert!(!sim.bolts.bolts[0].installed);
            }
            _ => {
                let s0 = *installed_at.get_or_insert_with(|| {
                    // the slip at the end of `slide`: ½ a t² with a = g (sin θ − cos θ tan φ)
                    let slip = v.slip() - v.elongation();
                    let exact = 0.5 * net_force() / MASS * 0.1 * 0.1;
                    eprintln!(
                        "slip before the bolt: {slip:.6e} m vs ½ a t² = {exact:.6e} m ({:+.3}%)",
                        (slip / exact - 1.0) * 100.0
                    );
                    assert!((slip / exact - 1.0).abs() < 0.02);
                    slip
                });
                let since = v.slip() - s0;
                // the anchor moves with the block up to the block's distortion under the
                // bolt's force, of order N/E (5e-8 m at the pretension)
                let tol = 10.0 * v.force().abs() / 1.0e9 + 1e-6 * since.abs();
                worst = worst.max((v.elongation() - since).abs() / tol);
                assert!(
                    (v.elongation() - since).abs() <= tol,
                    "t = {}: elongation {} vs slip since installation {since}",
                    sim.time,
                    v.elongation()
                );
                assert!((v.force() - (50.0 + 1.0e5 * v.elongation())).abs() < 1e-6 * v.force());
            }
        }
    }
    assert!(installed_at.is_some());
    eprintln!(
        "elongation vs slip since installation: largest difference {worst:.3} of the tolerance"
    );
}

fn nmm(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(args)
        .output()
        .unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Checkpoints and `nmm resume` with bolts: the staged, yielding bolt run with checkpoints
/// kept at the ends of its stages (steps 100, 200, 250), resumed from step 100 (the bolt
/// not yet installed: installed after the resume) and from step 200 (installed, yielding,
/// with a plastic elongation) writes history.csv, bolts.pvd and the last bolts frame byte
/// for byte as the uninterrupted run, and the same energy in summary.json. A branch
/// (`--from`) of a model whose bolt differs starts from step 100 (the bolt was not
/// installed yet) and writes the rows that model's own run writes; from step 200 it is
/// refused, naming the bolts.
#[test]
fn checkpoints_and_resume_are_exact_with_bolts() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("bolted.toml");
    std::fs::write(&model, staged(200.0)).unwrap();
    let full = dir.path().join("full");
    let o = nmm(&["run", s(&model), "--out", s(&full), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ckpt = |d: &Path, k: usize| d.join(format!("checkpoints/step_{k:08}.ckpt"));
    for k in [100, 200, 250] {
        assert!(ckpt(&full, k).exists(), "checkpoint {k}");
    }
    let history = std::fs::read(full.join("history.csv")).unwrap();
    let text = String::from_utf8(history.clone()).unwrap();
    let last: Vec<&str> = text.lines().last().unwrap().split(',').collect();
    // the bolt yielded: its force is the capacity at the end
    assert_eq!(last[9], "200", "{last:?}");
    let summary = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap()
    };
    let full_summary = summary(&full);
    assert!(
        full_summary["energy"]["bolt_plastic_dissipation"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    for from in [100, 200] {
        let out = dir.path().join(format!("resumed{from}"));
        let o = std::process::Command::new("cp")
            .args(["-r", s(&full), s(&out)])
            .status()
            .unwrap();
        assert!(o.success());
        for k in [100, 200, 250].into_iter().filter(|&k| k > from) {
            std::fs::remove_file(ckpt(&out, k)).unwrap();
        }
        let o = nmm(&["resume", s(&out), "--quiet"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(
            std::fs::read(out.join("history.csv")).unwrap() == history,
            "resumed from {from}: history differs"
        );
        for f in ["bolts.pvd", "blocks.pvd", "vtk/bolts_000250.vtu"] {
            assert!(
                std::fs::read(out.join(f)).unwrap() == std::fs::read(full.join(f)).unwrap(),
                "resumed from {from}: {f} differs"
            );
        }
        assert_eq!(summary(&out)["energy"], full_summary["energy"]);
        eprintln!("resumed from step {from}: history, bolts.pvd and the last frame identical");
    }
    // branches: another bolt (capacity 300 N)
    let other = dir.path().join("other.toml");
    std::fs::write(&other, staged(300.0)).unwrap();
    let own = dir.path().join("own");
    let o = nmm(&["run", s(&other), "--out", s(&own), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let branch = dir.path().join("branch");
    let o = nmm(&[
        "run",
        s(&other),
        "--out",
        s(&branch),
        "--from",
        s(&ckpt(&full, 100)),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let own_rows: Vec<String> = std::fs::read_to_string(own.join("history.csv"))
        .unwrap()
        .lines()
        .skip(1 + 100)
        .map(str::to_string)
        .collect();
    let branch_rows: Vec<String> = std::fs::read_to_string(branch.join("history.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(str::to_string)
        .collect();
    assert_eq!(own_rows.len(), 150);
    assert!(
        own_rows == branch_rows,
        "the branch differs from the model's own run"
    );
    let o = nmm(&[
        "run",
        s(&other),
        "--out",
        s(&dir.path().join("refused")),
        "--from",
        s(&ckpt(&full, 200)),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bolts"), "{err}");
}
