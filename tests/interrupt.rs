//! Ctrl-C (SIGINT) stops a run cleanly: exit status 130, every row written so far in
//! history.csv complete and parseable, the VTK collections valid, summary.json with status
//! "interrupted" and the steps done.

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn sigint_keeps_every_output_written_so_far() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    // the shaking-table slope for 100 s of (zero) motion: far longer than the test waits
    let model = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/shaking_table_slope.toml"
    ))
    .unwrap()
    .replace("steps = 10000", "steps = 100000")
    .replace(
        "file = \"shaking_table_motion.csv\"",
        "table = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0]]",
    );
    let path = dir.path().join("long.toml");
    std::fs::write(&path, model).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // wait until some rows are written, then interrupt
    let hist = out.join("history.csv");
    let t0 = Instant::now();
    while std::fs::read_to_string(&hist)
        .map(|s| s.lines().count())
        .unwrap_or(0)
        < 50
    {
        assert!(t0.elapsed() < Duration::from_secs(60), "no progress");
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out_status = child.wait().unwrap();
    assert_eq!(out_status.code(), Some(130), "exit status");
    let text = std::fs::read_to_string(&hist).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mut rows = 0;
    for (i, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), header.len(), "row {i} incomplete: {line}");
        assert_eq!(fields[0].parse::<usize>().unwrap(), i + 1);
        rows += 1;
    }
    assert!((50..100000).contains(&rows), "{rows} rows");
    assert!(text.ends_with('\n'));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    assert!(summary["error"].is_null());
    assert_eq!(summary["steps"].as_u64(), Some(rows as u64));
    assert_eq!(
        summary["iterations"]["total"]
            .as_u64()
            .map(|t| t >= rows as u64),
        Some(true)
    );
    let stderr = {
        use std::io::Read;
        let mut s = String::new();
        child.stderr.take().unwrap().read_to_string(&mut s).unwrap();
        s
    };
    assert!(stderr.contains("interrupted at step"), "{stderr}");
    // the collections list frames that exist
    for pvd in ["blocks.pvd", "contacts.pvd"] {
        let s = std::fs::read_to_string(out.join(pvd)).unwrap();
        assert!(s.trim_end().ends_with("</VTKFile>"), "{pvd}");
        for part in s.split("file=\"").skip(1) {
            let f = &part[..part.find('"').unwrap()];
            assert!(out.join(f).exists(), "{f}");
        }
    }
}
