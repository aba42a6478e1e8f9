//! A step that does not converge is cut (Δt halved) up to `max_step_cuts` times, and then
//! the run stops with a one-line error and a non-zero exit, keeping every output written
//! so far; it never continues with an unconverged state.

use std::process::Command;

#[test]
fn unconverged_step_is_cut_then_reported_and_outputs_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    // direct shear: step 1 (elastic → sliding) needs more than one iteration; allow only 1
    let model = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/direct_shear.toml"
    ))
    .unwrap()
    .replace(
        "output_every = 1",
        "output_every = 1\nmax_iterations = 1\nmax_step_cuts = 2",
    );
    let path = dir.path().join("m.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.path().join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].contains("did not converge after 2 time-step cuts"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"));
    // what was written before the failure is there: the header and the initial frame
    let hist = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert!(hist.starts_with(
        "step,time,joint.fx,joint.fy,joint.fn,joint.nc,top.ux,top.uy,top.vx,top.vy,iterations"
    ));
    assert!(out.join("blocks.pvd").exists() && out.join("vtk/blocks_000000.vtu").exists());
}
