//! `nmm run` with stderr not a terminal: plain progress lines every `NMM_PROGRESS_SECONDS`
//! (10 s by default), none with `--quiet`.

use std::process::Command;

fn run(extra: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("NMM_PROGRESS_SECONDS", "0.1")
        .args(["run", "examples/incline.toml", "--no-vtk", "--out"])
        .arg(&out)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success());
    String::from_utf8(o.stderr).unwrap()
}

#[test]
fn plain_progress_lines_on_a_pipe() {
    let e = run(&[]);
    let lines: Vec<&str> = e
        .lines()
        .filter(|l| l.starts_with("progress: step "))
        .collect();
    assert!(!lines.is_empty(), "{e}");
    assert!(
        lines[0].contains("/1000 (") && lines[0].contains("s elapsed"),
        "{}",
        lines[0]
    );
    let quiet = run(&["--quiet"]);
    assert!(!quiet.contains("progress:"), "{quiet}");
}
