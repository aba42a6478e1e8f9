//! `--threads` (issue 14): the run's local work spread over threads and gathered in a
//! fixed order, so that every output is byte-identical whatever the thread count; the
//! count is reported in summary.json; a bad count is one line and a non-zero exit.

use nmm::generate::{brick_wall_model, WallOptions};
use std::path::Path;
use std::process::Command;

fn run(model: &Path, out: &Path, args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_nmm"));
    c.args([
        "run",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--no-vtk",
        "--quiet",
    ])
    .args(args)
    .env_remove("NMM_THREADS");
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

fn summary(out: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// A 24×24 wall (about 2,700 elements, 4,800 contacts, 6,900 unknowns: above the size at
/// which loops go parallel, checked below) for 4 steps on 1, 2 and 3 threads: history.csv
/// and blocks.csv the same bytes.
#[test]
fn a_wall_gives_the_same_bytes_on_any_number_of_threads() {
    let dir = tempfile::tempdir().unwrap();
    let mut o = WallOptions::new(24, 24);
    o.steps = 4;
    let model = dir.path().join("wall.toml");
    std::fs::write(&model, brick_wall_model(&o)).unwrap();
    let mut histories = Vec::new();
    for t in ["1", "2", "3"] {
        let out = dir.path().join(format!("t{t}"));
        let r = run(&model, &out, &["--threads", t], &[]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let s = summary(&out);
        assert_eq!(s["threads"], t.parse::<u64>().unwrap());
        // the element and contact loops are long enough to be spread over the threads
        let least = nmm::parallel::MIN_PARALLEL as u64;
        assert!(s["manifold_elements"].as_u64().unwrap() >= least, "{s}");
        assert!(s["contacts"]["max"].as_u64().unwrap() >= least, "{s}");
        histories.push((
            std::fs::read(out.join("history.csv")).unwrap(),
            std::fs::read(out.join("blocks.csv")).unwrap(),
        ));
    }
    // the wall moves (gravity settles it): the comparison is not of zeros
    let text = String::from_utf8(histories[0].0.clone()).unwrap();
    assert_eq!(text.lines().count(), 5, "{text}");
    assert!(histories.iter().all(|h| *h == histories[0]));
    // NMM_THREADS sets the default; --threads overrides it
    let out = dir.path().join("env");
    let r = run(&model, &out, &[], &[("NMM_THREADS", "2")]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(summary(&out)["threads"], 2);
    assert_eq!(
        std::fs::read(out.join("history.csv")).unwrap(),
        histories[0].0
    );
}

#[test]
fn a_bad_thread_count_is_one_line_and_a_non_zero_exit() {
    let dir = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/incline.toml");
    let r = run(&model, &dir.path().join("a"), &["--threads", "0"], &[]);
    assert!(!r.status.success());
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("expected an integer ≥ 1"), "{err}");
    let r = run(
        &model,
        &dir.path().join("b"),
        &[],
        &[("NMM_THREADS", "many")],
    );
    assert!(!r.status.success());
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        err.contains("NMM_THREADS") && err.trim().lines().count() == 1,
        "{err}"
    );
}
