//! Restart: a run interrupted at several steps — by SIGINT (it stops cleanly and writes a
//! checkpoint) or by SIGKILL (it resumes from its last periodic checkpoint) — and resumed
//! with `nmm resume DIR` writes a history.csv identical, byte for byte, to the
//! uninterrupted run's; `nmm run MODEL --from CHECKPOINT` branches a new model's later
//! stages from a saved state exactly as that model's own run; a checkpoint of another
//! model or of another program version is refused with one line.
//!
//! The model: the shaken-slope block settled in a static stage, then shaken at 0.5 g, 5 Hz
//! (it slides: the contacts' stick/slide states and elastic shear gaps must carry over),
//! on a fine cover so that a run lasts long enough to be interrupted midway.

use nmm::verify::cases::{slope_model, SineMotion};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const SHAKE_STEPS: usize = 1000;
const SETTLE_STEPS: usize = 5;

fn model_text(amplitude: f64) -> String {
    let motion = SineMotion {
        amplitude,
        frequency: 5.0,
        ramp: 0.0,
        duration: 1.0,
    };
    let text = slope_model(30.0, &motion, "return-mapping", 1e-3)
        .replace("[cover]\nsize = 0.1\n", "[cover]\nsize = 0.025\n")
        .replace("[analysis]\n", "[analysis]\noutput_every = 100\n");
    assert!(text.contains("size = 0.025") && text.contains("output_every = 100"));
    format!(
        "{text}[[monitor]]\nname = \"joint\"\ninterface = [\"slider\", \"base\"]\n\
         [[stage]]\nname = \"settle\"\nmode = \"static\"\ndt = 0.01\nsteps = {SETTLE_STEPS}\n\
         [[stage]]\nname = \"shake\"\ndt = 0.001\nsteps = {SHAKE_STEPS}\nbase_motion = true\n"
    )
}

fn nmm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(args)
        .output()
        .unwrap()
}

fn write_model(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn rows(hist: &Path) -> usize {
    std::fs::read_to_string(hist)
        .map(|s| s.lines().count().saturating_sub(1))
        .unwrap_or(0)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `model` into `out`, sends `signal` once history.csv has `at` rows, and returns
/// the rows it had written when it stopped.
fn interrupted_run(model: &Path, out: &Path, signal: &str, at: usize) -> usize {
    let mut child = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            s(model),
            "--out",
            s(out),
            "--checkpoint-every",
            "40",
            "--quiet",
        ])
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let hist = out.join("history.csv");
    let t0 = Instant::now();
    while rows(&hist) < at {
        assert!(t0.elapsed() < Duration::from_secs(120), "no progress");
        std::thread::sleep(Duration::from_millis(2));
    }
    let ok = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
    let status = child.wait().unwrap();
    if signal == "-INT" {
        assert_eq!(status.code(), Some(130), "interrupted by SIGINT");
    } else {
        assert!(status.code().is_none(), "killed by SIGKILL: {status:?}");
    }
    rows(&hist)
}

#[test]
fn interrupted_and_resumed_runs_write_the_same_history() {
    let dir = tempfile::tempdir().unwrap();
    let model = write_model(dir.path(), "slope.toml", &model_text(0.5 * 9.81));
    let full = dir.path().join("full");
    let o = nmm(&["run", s(&model), "--out", s(&full), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reference = std::fs::read(full.join("history.csv")).unwrap();
    let text = String::from_utf8(reference.clone()).unwrap();
    assert_eq!(text.lines().count(), 1 + SETTLE_STEPS + SHAKE_STEPS);
    assert!(text
        .lines()
        .next()
        .unwrap()
        .ends_with(",iterations,stage,solves,cuts"));
    // it slides: the contacts change state during the run
    let last: Vec<&str> = text.lines().last().unwrap().split(',').collect();
    assert!(last[2].parse::<f64>().unwrap() > 0.01, "slip {}", last[2]);
    let summary_of = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap()
    };
    let full_summary = summary_of(&full);
    for (k, (signal, at)) in [("-INT", 60), ("-INT", 420), ("-KILL", 150), ("-KILL", 700)]
        .into_iter()
        .enumerate()
    {
        let out = dir.path().join(format!("run{k}"));
        let stopped = interrupted_run(&model, &out, signal, at);
        assert!(
            stopped < SETTLE_STEPS + SHAKE_STEPS,
            "{signal} at {at}: the run had finished"
        );
        let o = nmm(&["resume", s(&out), "--quiet"]);
        assert!(
            o.status.success(),
            "{signal} at {at}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let resumed = std::fs::read(out.join("history.csv")).unwrap();
        assert!(
            resumed == reference,
            "{signal} after {stopped} rows: history differs from the uninterrupted run's"
        );
        let sm = summary_of(&out);
        assert_eq!(sm["status"], "finished");
        assert_eq!(sm["steps"], full_summary["steps"]);
        assert_eq!(sm["iterations"], full_summary["iterations"]);
        assert_eq!(sm["energy"], full_summary["energy"]);
        assert_eq!(sm["stage"], "shake");
        // the VTK collections list every frame of the uninterrupted run once, and the
        // frame written at a SIGINT
        let pvd = std::fs::read_to_string(out.join("blocks.pvd")).unwrap();
        let interrupt_frame = format!("blocks_{stopped:06}.vtu");
        let kept: Vec<&str> = pvd
            .lines()
            .filter(|l| signal != "-INT" || !l.contains(&interrupt_frame))
            .collect();
        let want = std::fs::read_to_string(full.join("blocks.pvd")).unwrap();
        assert_eq!(kept, want.lines().collect::<Vec<_>>());
        eprintln!("{signal} after {stopped} rows: resumed, history identical");
    }

    // a finished run resumes to the same outputs
    let o = nmm(&["resume", s(&full), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read(full.join("history.csv")).unwrap() == reference);

    // another model: the file changed since the run
    let changed = model_text(0.5 * 9.81).replace("friction_angle = 40.5", "friction_angle = 41");
    std::fs::write(&model, &changed).unwrap();
    let o = nmm(&["resume", s(&full)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("a checkpoint of another model"), "{err}");
}

#[test]
fn a_checkpoint_of_another_version_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = model_text(0.5 * 9.81).replace(
        &format!("steps = {SHAKE_STEPS}\nbase_motion"),
        "steps = 3\nbase_motion",
    );
    let model = write_model(dir.path(), "short.toml", &text);
    let out = dir.path().join("out");
    assert!(nmm(&["run", s(&model), "--out", s(&out), "--quiet"])
        .status
        .success());
    let ckpt = nmm::simulation::latest_checkpoint(&out).unwrap();
    assert!(ckpt.ends_with("step_00000008.ckpt"), "{}", ckpt.display());
    let mut bytes = std::fs::read(&ckpt).unwrap();
    let v = env!("CARGO_PKG_VERSION").as_bytes();
    let at = bytes.windows(v.len()).position(|w| w == v).unwrap();
    bytes[at] = if bytes[at] == b'9' { b'8' } else { b'9' };
    std::fs::write(&ckpt, bytes).unwrap();
    let o = nmm(&["resume", s(&out)]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("checkpoint written by nmm"), "{err}");
    // no checkpoint at all
    let o = nmm(&["resume", s(dir.path())]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("no checkpoint"),
        "{err}"
    );
}

#[test]
fn a_branch_from_the_settled_state_runs_as_the_new_models_own_run() {
    let dir = tempfile::tempdir().unwrap();
    let short = |a: f64| {
        model_text(a).replace(
            &format!("steps = {SHAKE_STEPS}\nbase_motion"),
            "steps = 150\nbase_motion",
        )
    };
    let a = write_model(dir.path(), "a.toml", &short(0.5 * 9.81));
    let b = write_model(dir.path(), "b.toml", &short(0.3 * 9.81));
    let (oa, ob, ob_fresh) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("b-fresh"),
    );
    assert!(nmm(&["run", s(&a), "--out", s(&oa), "--quiet"])
        .status
        .success());
    let settled = oa.join("checkpoints").join("step_00000005.ckpt");
    assert!(
        settled.exists(),
        "a checkpoint at the end of the settle stage"
    );
    let o = nmm(&[
        "run",
        s(&b),
        "--out",
        s(&ob),
        "--from",
        s(&settled),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(nmm(&["run", s(&b), "--out", s(&ob_fresh), "--quiet"])
        .status
        .success());
    let branch = std::fs::read_to_string(ob.join("history.csv")).unwrap();
    let fresh = std::fs::read_to_string(ob_fresh.join("history.csv")).unwrap();
    let fresh_rows: Vec<&str> = fresh.lines().collect();
    let branch_rows: Vec<&str> = branch.lines().collect();
    assert_eq!(branch_rows[0], fresh_rows[0], "same header");
    // the branch's rows are the shaking's: those of b's own run after its settling
    assert_eq!(&branch_rows[1..], &fresh_rows[1 + SETTLE_STEPS..]);
    assert!(branch_rows[1].starts_with("6,0.051,"));

    // a model whose saved-state parts differ is refused, naming them
    let c = write_model(
        dir.path(),
        "c.toml",
        &short(0.3 * 9.81).replace("young = 7.0e9", "young = 8.0e9"),
    );
    let o = nmm(&[
        "run",
        s(&c),
        "--out",
        s(&dir.path().join("c")),
        "--from",
        s(&settled),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("the model differs in materials ("), "{err}");
}

/// The shaken slope with a bonded joint (c = 1.5 kPa, T = 1 kPa, φ_r = 35°) on the cover of
/// 0.1 m: settled (the heel's bonds break in tension as the block leans on its toe), then
/// shaken in three stages (each stage's end writes a checkpoint; the record starts again
/// with each), which break the other bonds; the block then slides on the residual friction.
fn bonded_model_text() -> String {
    let motion = SineMotion {
        amplitude: 0.5 * 9.81,
        frequency: 5.0,
        ramp: 0.0,
        duration: 0.4,
    };
    let text = slope_model(30.0, &motion, "return-mapping", 1e-3).replace(
        "friction_angle = 40.5\n",
        "friction_angle = 40.5\ncohesion = 1500.0\ntensile_strength = 1000.0\nresidual_friction_angle = 35.0\n",
    );
    assert!(text.contains("tensile_strength"));
    let mut stages = format!(
        "[[stage]]\nname = \"settle\"\nmode = \"static\"\ndt = 0.01\nsteps = {SETTLE_STEPS}\n"
    );
    for (k, steps) in [30, 30, 340].into_iter().enumerate() {
        stages += &format!(
            "[[stage]]\nname = \"shake {}\"\ndt = 0.001\nsteps = {steps}\nbase_motion = true\n",
            k + 1
        );
    }
    format!("{text}[[monitor]]\nname = \"joint\"\ninterface = [\"slider\", \"base\"]\n{stages}")
}

/// The bonds (intact, broken) of the state saved in checkpoint `ckpt` of `model`.
fn saved_bonds(model: &Path, ckpt: &Path) -> (usize, usize) {
    let m = nmm::model::load_model(model).unwrap();
    let mut sim = nmm::simulation::Simulation::new(m).unwrap();
    let c = nmm::simulation::checkpoint::Checkpoint::read(ckpt).unwrap();
    sim.restore(&c).unwrap();
    sim.contacts.bond_counts()
}

/// Checkpoints and `nmm resume` with bonded joints: resumed from a checkpoint before the
/// bonds break (the intact states cross it) and from one after (the broken states, kept
/// while the contacts are open or out of sight, cross it), the history is the
/// uninterrupted run's byte for byte, and so are the bonds in summary.json.
#[test]
fn resumed_runs_with_bonded_joints_write_the_same_history() {
    let dir = tempfile::tempdir().unwrap();
    let model = write_model(dir.path(), "bonded.toml", &bonded_model_text());
    let full = dir.path().join("full");
    let o = nmm(&[
        "run",
        s(&model),
        "--out",
        s(&full),
        "--checkpoint-every",
        "20",
        "--no-vtk",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reference = std::fs::read(full.join("history.csv")).unwrap();
    let summary_of = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap()
    };
    let full_summary = summary_of(&full);
    assert_eq!(
        full_summary["bonds"]["intact"], 0,
        "{}",
        full_summary["bonds"]
    );
    // the checkpoints, in step order, with their bonds
    let mut ckpts: Vec<PathBuf> = std::fs::read_dir(full.join("checkpoints"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ckpt"))
        .collect();
    ckpts.sort();
    let bonds: Vec<(usize, usize)> = ckpts.iter().map(|c| saved_bonds(&model, c)).collect();
    eprintln!("bonds (intact, broken) at the checkpoints: {bonds:?}");
    let last = *bonds.last().unwrap();
    assert_eq!(last.0, 0, "every bond broke by the end");
    // intact bonds that break later cross the first; broken ones the last but one
    let before = bonds
        .iter()
        .position(|b| b.0 > 0 && b.1 < last.1)
        .expect("a checkpoint with bonds that break later");
    let after = bonds.len() - 2;
    assert!(bonds[after].1 > 0 && after > before);
    eprintln!(
        "bonds at {}: {:?}; at {}: {:?}; at the end {}",
        ckpts[before].display(),
        bonds[before],
        ckpts[after].display(),
        bonds[after],
        full_summary["bonds"]
    );
    for (k, at) in [before, after].into_iter().enumerate() {
        // the run as left at that checkpoint: its later checkpoints removed
        let out = dir.path().join(format!("resumed{k}"));
        std::fs::create_dir_all(out.join("checkpoints")).unwrap();
        for f in ["history.csv", "summary.json"] {
            std::fs::copy(full.join(f), out.join(f)).unwrap();
        }
        let name = ckpts[at].file_name().unwrap();
        std::fs::copy(&ckpts[at], out.join("checkpoints").join(name)).unwrap();
        let o = nmm(&["resume", s(&out), "--quiet"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let resumed = std::fs::read(out.join("history.csv")).unwrap();
        assert!(
            resumed == reference,
            "resumed from {}: history differs from the uninterrupted run's",
            ckpts[at].display()
        );
        let sm = summary_of(&out);
        assert_eq!(sm["bonds"], full_summary["bonds"]);
        assert_eq!(sm["energy"], full_summary["energy"]);
        assert_eq!(sm["iterations"], full_summary["iterations"]);
    }
}

/// Points `[[x, y], …]` in TOML.
fn toml_points(p: &[[f64; 2]]) -> String {
    let v: Vec<String> = p
        .iter()
        .map(|x| format!("[{:?}, {:?}]", x[0], x[1]))
        .collect();
    format!("[{}]", v.join(", "))
}

/// A regular octagon of radius 0.7 around `c`.
fn octagon(c: [f64; 2]) -> Vec<[f64; 2]> {
    (0..8)
        .map(|k| {
            let t = 0.3 + std::f64::consts::TAU * k as f64 / 8.0;
            [c[0] + 0.7 * t.cos(), c[1] + 0.7 * t.sin()]
        })
        .collect()
}

/// Two tunnels in an 8 m × 4 m rock under the in-situ stress σ₀ = (−2, −3, 0.5) MPa (its
/// edges loaded by σ₀·n, three point constraints against rigid motion; E = 1 GPa, cover
/// 0.2 m): the west tunnel drawn as a hole in the rock and its plug, the east one as a
/// closed `[[joint]]` loop "east" that cuts it out of the rock. Dynamic stages of 1 ms:
/// `insitu` (10 steps: nothing moves), `west` (excavates the plug; 15 steps), `support`
/// (the bolt b1 above the west tunnel installed, with `capacity`; 10 steps), `east`
/// (excavates the loop's piece: the bolt's unknowns are numbered again; `east_steps`).
/// Monitors: the west crown, the bolt, the east wall. The stages' ends write checkpoints
/// at steps 10, 25, 35 and 35 + `east_steps`.
fn tunnel_model_text(sigma0: [f64; 3], capacity: f64, east_steps: usize) -> String {
    let (w, h) = (8.0, 4.0);
    let west = octagon([2.5, 2.0]);
    let mut east = octagon([5.5, 2.0]);
    east.push(east[0]);
    let mut t = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 15\noutput_every = 5\n\
         [cover]\nsize = 0.2\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [initial_stress]\nstress = [{:?}, {:?}, {:?}]\n\
         [[block]]\nname = \"rock\"\nmaterial = \"rock\"\nvertices = {}\nholes = [{}]\n\
         [[block]]\nname = \"plug\"\nmaterial = \"rock\"\nvertices = {}\n\
         [[joint]]\nname = \"east\"\npoints = {}\n\
         [[interface]]\nfriction_angle = 40.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
         [[stage]]\nname = \"insitu\"\nsteps = 10\n\
         [[stage]]\nname = \"west\"\nexcavate = [\"plug\"]\n\
         [[stage]]\nname = \"support\"\nsteps = 10\n\
         [[stage]]\nname = \"east\"\nexcavate = [\"east\"]\nsteps = {east_steps}\n\
         [[bolt]]\nname = \"b1\"\npoints = [[2.5, 2.8], [2.5, 3.7]]\nstiffness = 1.0e7\n\
         capacity = {capacity:?}\npretension = 1.0e3\nstage = \"support\"\n\
         [[monitor]]\nname = \"crown\"\npoint = [2.5, 2.8]\n\
         [[monitor]]\nname = \"bolt\"\nbolt = \"b1\"\n\
         [[monitor]]\nname = \"east wall\"\npoint = [4.7, 2.0]\n",
        sigma0[0],
        sigma0[1],
        sigma0[2],
        toml_points(&[[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]),
        toml_points(&west),
        toml_points(&west),
        toml_points(&east),
    );
    // σ₀·n on each edge: bottom n = (0, −1), right (1, 0), top (0, 1), left (−1, 0)
    for (e, n) in [
        ([[0.0, 0.0], [w, 0.0]], [0.0, -1.0]),
        ([[w, 0.0], [w, h]], [1.0, 0.0]),
        ([[w, h], [0.0, h]], [0.0, 1.0]),
        ([[0.0, h], [0.0, 0.0]], [-1.0, 0.0]),
    ] {
        let tr = [
            sigma0[0] * n[0] + sigma0[2] * n[1],
            sigma0[2] * n[0] + sigma0[1] * n[1],
        ];
        t += &format!(
            "[[load]]\nblock = \"rock\"\nedge = {}\ntraction = [{:?}, {:?}]\n",
            toml_points(&e),
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
    t
}

const SIGMA0: [f64; 3] = [-2.0e6, -3.0e6, 0.5e6];

/// The `NumberOfCells` of a VTK frame.
fn cells(frame: &Path) -> usize {
    let text = std::fs::read_to_string(frame).unwrap();
    let at = text.find("NumberOfCells=\"").unwrap() + "NumberOfCells=\"".len();
    text[at..].split('"').next().unwrap().parse().unwrap()
}

/// Checkpoints and `nmm resume` with in-situ stress and excavations: the two-tunnel model
/// (`tunnel_model_text`) resumed from the checkpoint before the first excavation (step 10),
/// from the one between the excavations before the bolt's installation (step 25), and
/// from the one with the bolt installed before the second excavation (step 35), its later
/// checkpoints, rows, frames and summary removed, writes history.csv, blocks.pvd,
/// bolts.pvd and the last frames byte for byte as the uninterrupted run, and the same
/// energy (`excavated` among it), iterations and steps in summary.json. Branches
/// (`--from`): a model whose bolt and last stage differ starts from step 25 (the bolt not
/// installed yet) and writes its own run's rows; from step 35 it is refused, naming the
/// bolts; a model whose in-situ stress differs, or whose first excavation does, is
/// refused naming that.
#[test]
fn resumed_runs_with_excavations_write_the_same_history() {
    let dir = tempfile::tempdir().unwrap();
    let model = write_model(
        dir.path(),
        "tunnels.toml",
        &tunnel_model_text(SIGMA0, 2.0e4, 15),
    );
    let full = dir.path().join("full");
    let o = nmm(&["run", s(&model), "--out", s(&full), "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ckpt = |d: &Path, k: usize| d.join(format!("checkpoints/step_{k:08}.ckpt"));
    for k in [10, 25, 35, 50] {
        assert!(ckpt(&full, k).exists(), "checkpoint {k}");
    }
    let reference = std::fs::read(full.join("history.csv")).unwrap();
    let text = String::from_utf8(reference.clone()).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(
        rows[0].join(","),
        "step,time,crown.ux,crown.uy,crown.vx,crown.vy,bolt.force,bolt.elongation,\
         east wall.ux,east wall.uy,east wall.vx,east wall.vy,iterations,stage,solves,cuts"
    );
    assert_eq!(rows.len(), 1 + 50);
    let at = |step: usize, col: usize| rows[step][col].parse::<f64>().unwrap();
    // at rest in situ; the west crown falls by millimetres once the plug is gone; the bolt
    // holds from `support` on; the east wall moves most once the east tunnel is dug
    for row in &rows[1..=10] {
        let u = |col: usize| row[col].parse::<f64>().unwrap().abs();
        assert!(u(3) < 1e-9 && u(8) < 1e-9, "{row:?}");
    }
    assert!(at(25, 3) < -1e-3, "crown {:?}", rows[25]);
    assert_eq!((at(25, 6), rows[26][13]), (0.0, "support"));
    assert!(at(26, 6) > 0.0, "bolt {:?}", rows[26]);
    let east_before = (11..=35).map(|k| at(k, 8).abs()).fold(0.0, f64::max);
    let east_after = (36..=50).map(|k| at(k, 8).abs()).fold(0.0, f64::max);
    assert!(east_after > 1.5 * east_before, "{east_before} {east_after}");
    // the frames drop the excavated blocks' elements
    let frame = |d: &Path, k: usize| d.join(format!("vtk/blocks_{k:06}.vtu"));
    let n = [10, 25, 50].map(|k| cells(&frame(&full, k)));
    assert!(n[0] > n[1] && n[1] > n[2], "cells {n:?}");
    let summary = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("summary.json")).unwrap()).unwrap()
    };
    let full_summary = summary(&full);
    let energy = &full_summary["energy"];
    assert!(energy["excavated"].as_f64().unwrap() > 0.0, "{energy}");
    for from in [10, 25, 35] {
        // the run as left at that checkpoint
        let out = dir.path().join(format!("resumed{from}"));
        let o = Command::new("cp")
            .args(["-r", s(&full), s(&out)])
            .status()
            .unwrap();
        assert!(o.success());
        for k in [25, 35, 50].into_iter().filter(|&k| k > from) {
            std::fs::remove_file(ckpt(&out, k)).unwrap();
        }
        let head: Vec<&str> = text.lines().take(1 + from).collect();
        std::fs::write(out.join("history.csv"), head.join("\n") + "\n").unwrap();
        std::fs::remove_file(out.join("summary.json")).unwrap();
        for k in (from + 5..=50).step_by(5) {
            std::fs::remove_file(frame(&out, k)).unwrap();
            std::fs::remove_file(out.join(format!("vtk/bolts_{k:06}.vtu"))).unwrap();
        }
        let o = nmm(&["resume", s(&out), "--quiet"]);
        assert!(
            o.status.success(),
            "resumed from {from}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            std::fs::read(out.join("history.csv")).unwrap() == reference,
            "resumed from {from}: history differs from the uninterrupted run's"
        );
        for f in [
            "blocks.pvd",
            "bolts.pvd",
            "vtk/blocks_000050.vtu",
            "vtk/bolts_000050.vtu",
        ] {
            assert!(
                std::fs::read(out.join(f)).unwrap() == std::fs::read(full.join(f)).unwrap(),
                "resumed from {from}: {f} differs"
            );
        }
        let sm = summary(&out);
        assert_eq!(sm["status"], "finished");
        for key in ["energy", "iterations", "steps"] {
            assert_eq!(sm[key], full_summary[key], "resumed from {from}: {key}");
        }
        eprintln!("resumed from step {from}: history, frames and summary energy identical");
    }

    // branches: another bolt (capacity 30 kN) and a longer last stage
    let other = write_model(
        dir.path(),
        "other.toml",
        &tunnel_model_text(SIGMA0, 3.0e4, 20),
    );
    let own = dir.path().join("own");
    let o = nmm(&["run", s(&other), "--out", s(&own), "--no-vtk", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let branch = dir.path().join("branch");
    let o = nmm(&[
        "run",
        s(&other),
        "--out",
        s(&branch),
        "--from",
        s(&ckpt(&full, 25)),
        "--no-vtk",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let lines = |d: &Path, skip: usize| -> Vec<String> {
        std::fs::read_to_string(d.join("history.csv"))
            .unwrap()
            .lines()
            .skip(skip)
            .map(str::to_string)
            .collect()
    };
    let own_rows = lines(&own, 1 + 25);
    assert_eq!(own_rows.len(), 10 + 20);
    assert!(
        own_rows == lines(&branch, 1),
        "the branch differs from the model's own run"
    );
    let refused = |model: &Path, from: usize, what: &str| {
        let o = nmm(&[
            "run",
            s(model),
            "--out",
            s(&dir.path().join("refused")),
            "--from",
            s(&ckpt(&full, from)),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{what}: accepted");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains("cannot start from") && err.contains(what),
            "{what}: {err}"
        );
    };
    refused(&other, 35, "the model differs in bolts (");
    let stressed = write_model(
        dir.path(),
        "stressed.toml",
        &tunnel_model_text([-2.0e6, -3.5e6, 0.5e6], 2.0e4, 15),
    );
    refused(&stressed, 10, "the model differs in initial stress (");
    let swapped = write_model(
        dir.path(),
        "swapped.toml",
        &tunnel_model_text(SIGMA0, 2.0e4, 15)
            .replace("excavate = [\"plug\"]", "excavate = [\"PLUG\"]")
            .replace("excavate = [\"east\"]", "excavate = [\"plug\"]")
            .replace("excavate = [\"PLUG\"]", "excavate = [\"east\"]"),
    );
    refused(
        &swapped,
        25,
        "the model differs in stage #2 (stage \"west\") (",
    );
}
