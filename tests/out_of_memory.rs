//! Out of memory is said as such (issue 19, item 4): a model too large for the memory the
//! process may use is refused before its covers are built, with one line naming the
//! estimate and the limit, a non-zero exit, no panic or abort, and a summary.json — here
//! under an address-space limit of 300 MB set with the shell's `ulimit -v` (the run's own
//! estimate for this block, 81,200 unknowns, is about 700 MB). The fallible allocations of
//! the factorisation itself are unit-tested in solver/cholesky.rs.

use std::process::Command;

#[test]
fn a_model_too_large_for_the_memory_limit_is_one_line_and_a_non_zero_exit() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("big.toml");
    std::fs::write(
        &model,
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\n[cover]\nsize = 0.01\n\
         [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]\n\
         [[constraint]]\nblock = \"b\"\nedge = [[0.0, 0.0], [2.0, 0.0]]\nux = 0.0\nuy = 0.0\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 300000 && exec '{}' run '{}' --out '{}' --no-vtk",
            env!("CARGO_BIN_EXE_nmm"),
            model.display(),
            out.display()
        ))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].contains("needs about")
            && lines[0].contains("MB of memory")
            && lines[0].contains("ulimit -v"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"failed\""), "{summary}");
}
