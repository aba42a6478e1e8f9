//! What a run leaves in its output folder besides history.csv: summary.json (finished,
//! failed), blocks.csv and the block names in the VTK field data, and contact frames only
//! where there are contacts (a grid without cells breaks meshio). Interrupted runs:
//! tests/interrupt.rs.

use std::path::Path;
use std::process::Command;

fn nmm_run(model: &str, dir: &Path, extra: &[&str]) -> (bool, String) {
    let path = dir.join("m.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.join("out");
    let mut args = vec![
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(&args)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("out/summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// A block 5 mm above a fixed base falls onto it: no contact for the first frames, then
/// contacts. Block names with a comma and a quote.
const DROP: &str = r#"
[analysis]
dt = 0.002
steps = 30
gravity = [0.0, -9.81]
output_every = 5
[cover]
size = 0.25
[[material]]
name = "stone"
density = 2500.0
young = 1.0e9
poisson = 0.2
[[block]]
name = "base, \"fixed\""
material = "stone"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 0.5], [0.0, 0.5]]
fixed = true
[[block]]
name = "falling"
material = "stone"
vertices = [[0.5, 0.505], [1.5, 0.505], [1.5, 1.005], [0.5, 1.005]]
[[interface]]
friction_angle = 30.0
normal_penalty = 1.0e10
shear_penalty = 1.0e9
[[monitor]]
name = "joint"
interface = ["falling", "base, \"fixed\""]
"#;

#[test]
fn a_finished_run_writes_its_summary_block_table_and_frames() {
    let dir = tempfile::tempdir().unwrap();
    let start = std::time::Instant::now();
    let (ok, stderr) = nmm_run(DROP, dir.path(), &[]);
    let wall = start.elapsed().as_secs_f64();
    assert!(ok, "{stderr}");
    let out = dir.path().join("out");
    let s = summary(dir.path());
    assert_eq!(s["status"], "finished");
    assert!(s["error"].is_null());
    assert_eq!(s["nmm_version"], env!("CARGO_PKG_VERSION"));
    assert!(s["model"].as_str().unwrap().ends_with("m.toml"));
    assert_eq!(s["steps"], 30);
    assert_eq!(s["time"], 0.06);
    assert_eq!(s["blocks"], 2);
    for k in ["unknowns", "physical_covers", "manifold_elements"] {
        assert!(s[k].as_u64().unwrap() > 0, "{k}");
    }
    let it = &s["iterations"];
    assert!(it["total"].as_u64().unwrap() >= 30);
    assert!(it["max"].as_u64().unwrap() >= it["median"].as_u64().unwrap());
    assert!(it["mean"].as_f64().unwrap() >= 1.0);
    assert_eq!(s["cuts"]["steps_cut"], 0);
    assert!(
        s["contacts"]["max"].as_u64().unwrap() >= 2,
        "{}",
        s["contacts"]
    );
    // the stage timings (issue 19: were only checked ≥ 0): every stage that works in a
    // 30-step run with contacts took some time, the stages add up to no more than the
    // total, and the total to no more than the process's wall time
    let t = &s["timings"];
    let stages = [
        "cover",
        "assembly",
        "contact",
        "factorisation",
        "solve",
        "output",
    ];
    for k in stages.iter().chain(&["total"]) {
        assert!(t[*k].as_f64().unwrap() > 0.0, "timings.{k}: {}", t[*k]);
    }
    let sum: f64 = stages.iter().map(|k| t[*k].as_f64().unwrap()).sum();
    let total = t["total"].as_f64().unwrap();
    assert!(
        sum <= total * (1.0 + 1e-9),
        "stages {sum} s > total {total} s"
    );
    assert!(
        total <= wall,
        "total {total} s > the process's wall time {wall} s"
    );
    if cfg!(target_os = "linux") {
        // the process's peak: more than its binary's few MB, less than 1 GB for 46 unknowns
        let peak = s["peak_memory_bytes"].as_u64().unwrap();
        assert!(peak > 1 << 20 && peak < 1 << 30, "{peak}");
    }
    // the counts `nmm check --json` gives for the same model
    let check = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "check",
            dir.path().join("m.toml").to_str().unwrap(),
            "--json",
        ])
        .output()
        .unwrap();
    let check: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
    for k in ["unknowns", "physical_covers", "manifold_elements"] {
        assert_eq!(s[k], check[k], "{k}");
    }
    // the iteration statistics from history.csv's iterations column (no step cut: its
    // solves are the same), the columns after it
    let hist = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert!(hist
        .lines()
        .next()
        .unwrap()
        .ends_with(",iterations,solves,cuts"));
    // the header the library (and Python's `Model.history_columns`) says a run writes
    let model = nmm::model::parse_model(DROP, dir.path()).unwrap();
    assert_eq!(
        hist.lines().next().unwrap(),
        nmm::simulation::history_header(&model).join(",")
    );
    let last3 =
        |l: &str| -> Vec<u64> { l.rsplit(',').take(3).map(|x| x.parse().unwrap()).collect() };
    assert!(hist
        .lines()
        .skip(1)
        .all(|l| matches!(last3(l)[..], [0, s, i] if s == i)));
    let its: Vec<u64> = hist.lines().skip(1).map(|l| last3(l)[2]).collect();
    assert_eq!(its.len(), 30);
    assert_eq!(s["iterations"]["total"], its.iter().sum::<u64>());
    assert_eq!(s["iterations"]["max"], *its.iter().max().unwrap());
    // the energy's total is the sum of its parts, and the drop created none
    let e = &s["energy"];
    let parts: f64 = [
        "kinetic",
        "elastic",
        "gravity_potential",
        "contact_springs",
        "penalty_springs",
    ]
    .iter()
    .map(|k| e[*k].as_f64().unwrap())
    .sum();
    let etotal = e["total"].as_f64().unwrap();
    assert!(
        (parts - etotal).abs() <= 1e-12 * e["gravity_potential"].as_f64().unwrap().abs(),
        "{e}"
    );
    assert!(
        etotal < 0.0 && e["max_rise"].as_f64().unwrap() <= 1e-9 * etotal.abs(),
        "{e}"
    );
    assert!(s["active_set_changes"].as_u64().is_some());
    // a dynamic run: the energy balance, no equilibrium block (static mode only)
    assert!(s["energy"]["total"].as_f64().is_some(), "energy");
    assert!(s["energy"]["max_rise"].as_f64().is_some(), "energy");
    assert!(s["equilibrium"].is_null(), "equilibrium");
    assert_eq!(s["warnings"], serde_json::json!([]));

    // the block table, its ids those of the VTK `block` arrays
    let table = std::fs::read_to_string(out.join("blocks.csv")).unwrap();
    assert_eq!(
        table,
        "id,name,material,fixed\n0,\"base, \"\"fixed\"\"\",stone,true\n1,falling,stone,false\n"
    );
    let vtu = std::fs::read_to_string(out.join("vtk/blocks_000000.vtu")).unwrap();
    assert!(vtu.contains(r#"<FieldData>"#) && vtu.contains(r#"Name="block_names""#));

    // contact frames exist only where the blocks touch, and the collection names only them
    let pvd = std::fs::read_to_string(out.join("contacts.pvd")).unwrap();
    let listed: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|p| &p[..p.find('"').unwrap()])
        .collect();
    assert!(!listed.is_empty(), "{pvd}");
    assert!(!listed.contains(&"vtk/contacts_000000.vtu"), "{pvd}");
    let on_disk: Vec<String> = std::fs::read_dir(out.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("contacts_"))
        .collect();
    assert_eq!(on_disk.len(), listed.len());
    for f in &listed {
        let text = std::fs::read_to_string(out.join(f)).unwrap();
        assert!(!text.contains(r#"NumberOfCells="0""#), "{f}");
    }
    // every block frame is there, the first at t = 0
    let blocks = std::fs::read_to_string(out.join("blocks.pvd")).unwrap();
    assert_eq!(blocks.matches("<DataSet").count(), 7);
    assert!(blocks.contains(r#"timestep="0" "#));
}

#[test]
fn a_failed_run_writes_its_summary_with_the_error() {
    let dir = tempfile::tempdir().unwrap();
    let model = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/direct_shear.toml"
    ))
    .unwrap()
    .replace(
        "output_every = 1",
        "output_every = 1\nmax_iterations = 1\nmax_step_cuts = 2",
    );
    let (ok, stderr) = nmm_run(&model, dir.path(), &["--no-vtk"]);
    assert!(!ok);
    let s = summary(dir.path());
    assert_eq!(s["status"], "failed");
    let error = s["error"].as_str().unwrap();
    assert!(
        error.contains("did not converge after 2 time-step cuts"),
        "{error}"
    );
    assert!(!error.contains('\n'));
    assert!(stderr.contains(error), "{stderr} / {error}");
    assert_eq!(s["steps"], 0);
    assert!(dir.path().join("out/blocks.csv").exists());
    assert!(dir.path().join("out/history.csv").exists());
}
