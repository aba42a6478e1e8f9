//! summary.json and the run's closing lines after stages and `nmm resume`: the "not in
//! equilibrium: N of M static step(s)" count counts the static steps only; a resumed run's
//! `equilibrium` is reported (not null) and its `timings.total` covers the whole run, as
//! its other timings do.

use std::path::Path;
use std::process::Command;

/// The incline example (φ below the plane's 30°: no equilibrium) settled statically for
/// `n_static` steps, then `n_dynamic` dynamic steps.
fn staged(dir: &Path, n_static: usize, n_dynamic: usize) -> std::path::PathBuf {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/incline.toml"),
    )
    .unwrap()
    .replace("mode = \"dynamic\"\ndt = 0.001\nsteps = 1000\n", "");
    let text = format!(
        "{text}\n[[stage]]\nname = \"settle\"\nmode = \"static\"\ndt = 0.001\nsteps = {n_static}\n\
         [[stage]]\nname = \"go\"\nmode = \"dynamic\"\ndt = 0.001\nsteps = {n_dynamic}\n"
    );
    let p = dir.join("incline_staged.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn nmm(args: &[&std::ffi::OsStr]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn the_equilibrium_line_counts_static_steps_only() {
    let dir = tempfile::tempdir().unwrap();
    let model = staged(dir.path(), 12, 30);
    let out = dir.path().join("run");
    let (ok, err) = nmm(&[
        "run".as_ref(),
        model.as_os_str(),
        "--no-vtk".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(ok, "{err}");
    let line = err
        .lines()
        .find(|l| l.starts_with("not in equilibrium:"))
        .expect(&err);
    let s = summary(&out);
    let n = s["equilibrium"]["steps_not_in_equilibrium"]
        .as_u64()
        .unwrap();
    assert!((1..=12).contains(&n), "{n}");
    assert!(
        line.starts_with(&format!("not in equilibrium: {n} of 12 static step(s)")),
        "{line}"
    );
}

#[test]
fn a_resumed_run_reports_equilibrium_and_its_whole_time() {
    let dir = tempfile::tempdir().unwrap();
    let model = staged(dir.path(), 150, 10);
    let out = dir.path().join("run");
    let (ok, err) = nmm(&[
        "run".as_ref(),
        model.as_os_str(),
        "--no-vtk".as_ref(),
        "--checkpoint-every".as_ref(),
        "1000".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(ok, "{err}");
    let first = summary(&out);
    // a finished run resumed from its last checkpoint (in the dynamic stage): nothing left
    // to do, but the summary must still report the whole run
    let (ok, err) = nmm(&["resume".as_ref(), out.as_os_str(), "--quiet".as_ref()]);
    assert!(ok, "{err}");
    check(&summary(&out), &first);
    // resume from the end of the static stage: drop the later checkpoint
    let ckpts = out.join("checkpoints");
    let mut names: Vec<_> = std::fs::read_dir(&ckpts)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    assert!(names.len() >= 2, "{names:?}");
    assert!(names[0].ends_with("step_00000150.ckpt"), "{names:?}");
    for n in &names[1..] {
        std::fs::remove_file(n).unwrap();
    }
    let (ok, err) = nmm(&["resume".as_ref(), out.as_os_str(), "--quiet".as_ref()]);
    assert!(ok, "{err}");
    check(&summary(&out), &first);
    let line = err.lines().find(|l| l.starts_with("not in equilibrium:"));
    if let Some(line) = line {
        assert!(line.contains(" of 150 static step(s)"), "{line}");
    }
}

/// A resumed run's summary against the uninterrupted run's: the same steps and equilibrium,
/// a total time that covers the whole run.
fn check(s: &serde_json::Value, first: &serde_json::Value) {
    assert_eq!(s["steps"], 160);
    assert!(!s["equilibrium"].is_null());
    assert_eq!(
        s["equilibrium"], first["equilibrium"],
        "{}",
        s["equilibrium"]
    );
    let t = &s["timings"];
    let parts: f64 = [
        "cover",
        "assembly",
        "contact",
        "factorisation",
        "solve",
        "output",
    ]
    .iter()
    .map(|k| t[k].as_f64().unwrap())
    .sum();
    let total = t["total"].as_f64().unwrap();
    assert!(
        total >= parts,
        "total {total} s below the sum of its parts {parts} s"
    );
    let first_steps: f64 = ["assembly", "contact", "factorisation", "solve"]
        .iter()
        .map(|k| first["timings"][k].as_f64().unwrap())
        .sum();
    assert!(
        total >= 0.5 * first_steps,
        "total {total} s vs the first run's steps {first_steps} s"
    );
}
