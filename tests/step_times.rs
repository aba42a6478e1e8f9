//! Times are t₀ + kΔt, never a running sum, and are written in their shortest form: a
//! run's history and collections read 0.05, not 0.05000000000000003, and a run whose
//! steps were cut lands on the same times as an uncut run at the ends of full steps.

use std::path::Path;
use std::process::Command;

fn run(model: &str, dir: &Path) -> String {
    let path = dir.join("m.toml");
    std::fs::write(&path, model).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The `time` column as written.
fn times(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("out/history.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().to_string())
        .collect()
}

#[test]
fn times_are_short_decimals_of_the_step_grid() {
    let dir = tempfile::tempdir().unwrap();
    // free fall of one block for 300 steps of 1 ms (a running sum reads 0.05000000000000003
    // at step 50)
    let model = "[analysis]\ndt = 0.001\nsteps = 300\noutput_every = 50\ngravity = [0.0, -9.81]\n\
                 [cover]\nsize = 0.5\n[[material]]\nname = \"m\"\ndensity = 2500.0\nyoung = 1e9\npoisson = 0.2\n\
                 [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n";
    run(model, dir.path());
    let t = times(dir.path());
    assert_eq!(t.len(), 300);
    for (k, s) in t.iter().enumerate() {
        let k = k + 1;
        // the shortest decimal of k/1000 (k/1000 in doubles is the nearest to the decimal)
        assert_eq!(*s, format!("{}", k as f64 / 1000.0), "step {k}");
        assert!(s.len() <= 5, "step {k}: {s}");
    }
    assert_eq!(t[49], "0.05");
    let pvd = std::fs::read_to_string(dir.path().join("out/blocks.pvd")).unwrap();
    for want in [
        "timestep=\"0\"",
        "timestep=\"0.05\"",
        "timestep=\"0.1\"",
        "timestep=\"0.3\"",
    ] {
        assert!(pvd.contains(want), "{want} not in {pvd}");
    }
}

#[test]
fn cut_steps_rejoin_the_step_grid() {
    let dir = tempfile::tempdir().unwrap();
    // direct shear, Δt = 1 s: with at most 2 Newton iterations step 1 (elastic → sliding) is
    // cut to 1/4 s; later steps must end at 1, 2, 3, 4, 5 s
    let model = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/direct_shear.toml"
    ))
    .unwrap()
    .replace("output_every = 1", "output_every = 1\nmax_iterations = 2");
    let stderr = run(&model, dir.path());
    // one summary line for all the cuts, not one per cut
    let lines = stderr.lines().filter(|l| l.contains("Δt was cut")).count();
    assert_eq!(lines, 1, "no step was cut, or one line per cut: {stderr}");
    let t = times(dir.path());
    assert!(t.len() > 5, "{t:?}");
    let full: Vec<&str> = t
        .iter()
        .map(String::as_str)
        .filter(|s| !s.contains('.'))
        .collect();
    assert_eq!(full, ["1", "2", "3", "4", "5"], "{t:?}");
    // the cut steps cover the first interval exactly
    let first: Vec<f64> = t
        .iter()
        .map(|s| s.parse().unwrap())
        .take_while(|&x| x < 1.0)
        .collect();
    assert!(
        !first.is_empty() && first.windows(2).all(|w| w[0] < w[1]),
        "{t:?}"
    );
    assert_eq!(t.last().unwrap(), "5");
    // each row's linear solves (its failed attempts' included) and cuts: a cut step's row
    // counts the attempts that failed, and summary.json's `iterations` are those solves
    let text = std::fs::read_to_string(dir.path().join("out/history.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    assert_eq!(header[header.len() - 3..], ["iterations", "solves", "cuts"]);
    let rows: Vec<[usize; 3]> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<usize> = l
                .split(',')
                .rev()
                .take(3)
                .map(|x| x.parse().unwrap())
                .collect();
            [f[2], f[1], f[0]]
        })
        .collect();
    let cut: Vec<&[usize; 3]> = rows.iter().filter(|r| r[2] > 0).collect();
    assert!(!cut.is_empty(), "no row with a cut: {rows:?}");
    assert!(rows.iter().all(|r| r[1] >= r[0]), "{rows:?}");
    assert!(cut.iter().all(|r| r[1] > r[0]), "{cut:?}");
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("out/summary.json")).unwrap(),
    )
    .unwrap();
    let solves: Vec<usize> = rows.iter().map(|r| r[1]).collect();
    assert_eq!(summary["iterations"]["total"], solves.iter().sum::<usize>());
    assert_eq!(summary["iterations"]["max"], *solves.iter().max().unwrap());
    let cuts: usize = rows.iter().map(|r| r[2]).sum();
    assert_eq!(summary["cuts"]["total"], cuts);
    assert_eq!(summary["cuts"]["steps_cut"], cut.len());
}

#[test]
fn times_inside_cut_steps_are_short_decimals_too() {
    let dir = tempfile::tempdir().unwrap();
    // a block dropped 1 m onto a fixed one, Δt = 2 ms, at most 2 Newton iterations: its
    // impact steps (from step 467, t ≈ 0.93 s) are cut in halves and quarters, whose ends
    // t₀ + kΔt + mΔt/2^j a running sum writes as 0.9384999999999999
    let model = "[analysis]\ndt = 0.002\nsteps = 480\nmax_iterations = 2\ngravity = [0.0, -9.81]\n\
                 [cover]\nsize = 0.5\n[[material]]\nname = \"m\"\ndensity = 2500.0\nyoung = 1e9\npoisson = 0.2\n\
                 [[block]]\nname = \"base\"\nmaterial = \"m\"\nvertices = [[-1.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-1.0, 0.0]]\nfixed = true\n\
                 [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]\n\
                 [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n";
    run(model, dir.path());
    let t = times(dir.path());
    let text = std::fs::read_to_string(dir.path().join("out/history.csv")).unwrap();
    let cut = text.lines().skip(1).filter(|l| !l.ends_with(",0")).count();
    assert!(cut > 0, "no step was cut");
    assert!(
        t.len() > 480,
        "no inner point of a cut step: {} rows",
        t.len()
    );
    let inner: Vec<&String> = t
        .iter()
        .filter(|s| {
            let x: f64 = s.parse().unwrap();
            ((x / 0.002) - (x / 0.002).round()).abs() > 1e-6
        })
        .collect();
    assert!(!inner.is_empty());
    for s in &inner {
        // at most three halvings of 2 ms here: 0.00025 s, five decimals
        let decimals = s.split_once('.').map_or(0, |(_, f)| f.len());
        assert!(decimals <= 5, "{s} in {inner:?}");
    }
    assert_eq!(t.last().unwrap(), "0.96");
}
