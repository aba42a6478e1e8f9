//! `[base_motion]` records windowed (`start`, `duration`), scaled to a PGA (`pga`), in two
//! components at once (`x = {…}`, `y = {…}`), and an older PEER header (NPTS/DT line, units
//! in words).
//!
//! The acceptance check: the shaken-slope block (a block on a 30° plane, φ = 40.5°) driven
//! by a PEER-format record windowed to 2 … 5 s and scaled to 0.45 g horizontally, with a
//! vertical component from the same record in the older PEER layout (in cm/s², units in
//! words) scaled to 0.15 g, slides as the Newmark (1965) rigid block under the same
//! windowed, scaled motion predicts, within 5% (the tolerance of tests/shaken_slope.rs: the
//! NMM block is elastic on penalty springs, the reference rigid). The reference motion is
//! built here from the record's text with its own few lines of reading, windowing and
//! scaling, not with nmm's.

use nmm::model::parse_model;
use nmm::simulation::{monitor_values, Simulation};
use nmm::verify::cases::{slope_model, STEADY_2HZ};
use std::path::{Path, PathBuf};

#[path = "../crates/nmm/src/verify/newmark_sliding.rs"]
mod newmark_sliding;

const G: f64 = 9.80665;
const RECORD: &str = "examples/arch_earthquake_record.AT2";
const THETA: f64 = 30.0;
const START: f64 = 2.0;
const DURATION: f64 = 3.0;
const PGA_X: f64 = 0.45;
const PGA_Y: f64 = 0.15;

fn record_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(RECORD)
}

/// The record's values (in g) and DT, read independently: four header lines, then numbers.
fn read_at2(text: &str) -> (Vec<f64>, f64) {
    let lines: Vec<&str> = text.lines().collect();
    let dt_line = lines[3].to_ascii_uppercase();
    let dt: f64 = dt_line
        .split("DT=")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let values = lines[4..]
        .iter()
        .flat_map(|l| l.split_whitespace())
        .map(|t| t.parse::<f64>().unwrap())
        .collect();
    (values, dt)
}

/// The same record in the older PEER layout: NPTS/DT line with a two-decimal-less DT,
/// units in words (cm/s²), five values per line.
fn old_peer(values_g: &[f64], dt: f64) -> String {
    let mut s = String::from(
        "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.\n\
         SYNTHETIC 01/01/00 0000, NMM EXAMPLE, UP\n\
         ACCELERATION TIME HISTORY IN CENTIMETERS PER SECOND PER SECOND\n",
    );
    s.push_str(&format!("NPTS=  {}, DT= {:.5} SEC\n", values_g.len(), dt).replace("0.", "."));
    for chunk in values_g.chunks(5) {
        for v in chunk {
            s.push_str(&format!(" {:14.7E}", v * G * 100.0));
        }
        s.push('\n');
    }
    s
}

/// Samples (t, a) in m/s² of `values` (× `unit`) at `dt`, cut to [START, START + DURATION]
/// with interpolated ends, shifted to start at 0 and scaled so that its peak is `pga` g.
fn windowed(values: &[f64], unit: f64, dt: f64, pga: f64) -> Vec<(f64, f64)> {
    let at = |t: f64| {
        let i = (t / dt).floor() as usize;
        let f = t / dt - i as f64;
        unit * (values[i] + f * (values[(i + 1).min(values.len() - 1)] - values[i]))
    };
    let first = (START / dt).ceil() as usize;
    let last = ((START + DURATION) / dt).floor() as usize;
    let mut s = vec![(0.0, at(START))];
    for (i, v) in values.iter().enumerate().take(last + 1).skip(first) {
        let t = i as f64 * dt - START;
        if t > 1e-12 && t < DURATION - 1e-12 {
            s.push((t, unit * v));
        }
    }
    s.push((DURATION, at(START + DURATION)));
    let peak = s.iter().fold(0.0f64, |p, r| p.max(r.1.abs()));
    s.iter().map(|&(t, a)| (t, a * pga * G / peak)).collect()
}

fn interp(s: &[(f64, f64)], t: f64) -> f64 {
    if t < s[0].0 || t > s[s.len() - 1].0 {
        return 0.0;
    }
    let i = s.partition_point(|r| r.0 <= t).clamp(1, s.len() - 1);
    let (a, b) = (s[i - 1], s[i]);
    a.1 + (t - a.0) / (b.0 - a.0) * (b.1 - a.1)
}

/// The shaken-slope model with `base_motion` as its `[base_motion]` table and `steps` steps
/// of 1 ms.
fn model_text(base_motion: &str, steps: usize) -> String {
    let text = slope_model(THETA, &STEADY_2HZ, "return-mapping", 1e-3);
    let (head, rest) = text.split_once("[base_motion]\n").unwrap();
    let tail = &rest[rest.find("[[monitor]]").unwrap()..];
    let head = head.replace(
        &format!(
            "steps = {}\n",
            (STEADY_2HZ.duration / 1e-3).round() as usize
        ),
        &format!("steps = {steps}\n"),
    );
    format!("{head}[base_motion]\n{base_motion}\n{tail}")
}

fn two_component_motion(dir: &Path) -> String {
    let text = std::fs::read_to_string(record_path()).unwrap();
    let (values, dt) = read_at2(&text);
    std::fs::write(dir.join("old_up.at2"), old_peer(&values, dt)).unwrap();
    format!(
        "start = {START}\nduration = {DURATION}\nx = {{ file = {:?}, pga = {PGA_X} }}\n\
         y = {{ file = \"old_up.at2\", format = \"peer\", pga = {PGA_Y} }}\n",
        record_path().display().to_string()
    )
}

#[test]
fn old_peer_header_and_two_components_are_read_as_written() {
    let dir = tempfile::tempdir().unwrap();
    let motion = two_component_motion(dir.path());
    let m = parse_model(&model_text(&motion, 10), dir.path()).unwrap();
    let b = m.base_motion.unwrap();
    let text = std::fs::read_to_string(record_path()).unwrap();
    let (values, dt) = read_at2(&text);
    let x = windowed(&values, G, dt, PGA_X);
    let y = windowed(&values, G, dt, PGA_Y);
    // both components act at once, each its own window and peak
    let mut worst = 0.0f64;
    for k in 0..=3000 {
        let t = k as f64 * 1e-3 + 0.00037;
        let a = b.accel(t);
        worst = worst
            .max((a[0] - interp(&x, t)).abs())
            .max((a[1] - interp(&y, t)).abs());
    }
    // the old file holds 8 significant digits (cm/s², E14.7): 1e-7 relative of ~4 m/s²
    assert!(worst < 2e-6, "largest difference {worst} m/s²");
    assert_eq!(
        b.accel(DURATION + 1e-6),
        [0.0, 0.0],
        "zero after the window"
    );
    assert_eq!(b.records.len(), 2);
    let (rx, ry) = (&b.records[0], &b.records[1]);
    assert_eq!((rx.axis.as_str(), ry.axis.as_str()), ("x", "y"));
    assert_eq!(rx.samples, values.len());
    assert!((rx.dt.0 - dt).abs() < 1e-12 && (ry.dt.1 - dt).abs() < 1e-12);
    let peak_read = values.iter().fold(0.0f64, |p, v| p.max(v.abs()));
    assert!((rx.pga_read[0] / G - peak_read).abs() < 1e-12);
    assert!((ry.pga_read[1] / G - peak_read).abs() < 1e-6);
    assert!((rx.pga_applied[0] / G - PGA_X).abs() < 1e-12);
    assert!((ry.pga_applied[1] / G - PGA_Y).abs() < 1e-12);
    assert_eq!((rx.start, rx.duration), (START, DURATION));
}

#[test]
fn windowed_scaled_two_component_record_slides_as_newmark_predicts() {
    let dir = tempfile::tempdir().unwrap();
    let motion = two_component_motion(dir.path());
    let steps = (DURATION / 1e-3).round() as usize;
    let model = parse_model(&model_text(&motion, steps), dir.path()).unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let (s, c) = THETA.to_radians().sin_cos();
    let mut slip = 0.0;
    while !sim.finished() {
        sim.advance().unwrap();
        let v = monitor_values(&sim);
        // the plane dips toward +x: down-slope (c, −s)
        slip = v[0] * c - v[1] * s;
    }
    let text = std::fs::read_to_string(record_path()).unwrap();
    let (values, dt) = read_at2(&text);
    let (x, y) = (
        windowed(&values, G, dt, PGA_X),
        windowed(&values, G, dt, PGA_Y),
    );
    // the reference plane dips toward −x: mirror the horizontal component
    let accel = |t: f64| (-interp(&x, t), interp(&y, t));
    let reference = newmark_sliding::slide(THETA, 40.5, 9.81, 1e-3, &accel, DURATION);
    let slip_ref = reference.last().unwrap().1;
    // the same without the vertical component: it must matter, or the test shows nothing
    let horizontal = |t: f64| (-interp(&x, t), 0.0);
    let slip_h = newmark_sliding::slide(THETA, 40.5, 9.81, 1e-3, &horizontal, DURATION)
        .last()
        .unwrap()
        .1;
    eprintln!(
        "slip {slip:.5} m vs Newmark {slip_ref:.5} m ({:+.2}%); Newmark without the vertical component {slip_h:.5} m",
        (slip / slip_ref - 1.0) * 100.0
    );
    assert!(slip_ref > 0.02, "the record makes the reference slide");
    assert!(
        (slip_h - slip_ref).abs() > 0.1 * slip_ref,
        "the vertical component changes the reference by more than 10%"
    );
    assert!(
        ((slip - slip_ref) / slip_ref).abs() < 0.05,
        "slip {slip} vs Newmark {slip_ref}"
    );
}

/// `(FILE, line N)` of the first line of `text` that contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn bad_records_get_one_line_naming_table_key_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let rec = format!("{:?}", record_path().display().to_string());
    let cases: Vec<(String, &str, &str, &str)> = vec![
        (
            format!("file = {rec}\nscale = 2.0\npga = 0.3"),
            "[base_motion]: key `pga`",
            "pga = 0.3",
            "not both",
        ),
        (
            format!("file = {rec}\npga = -0.3"),
            "[base_motion]: key `pga`",
            "pga = -0.3",
            "must be positive",
        ),
        (
            format!("file = {rec}\nstart = 6.0\nduration = 5.0"),
            "[base_motion]: key `duration`",
            "duration = 5.0",
            "after the record's end at 8 s",
        ),
        (
            format!("file = {rec}\nstart = 9.0"),
            "[base_motion]: key `start`",
            "start = 9.0",
            "at or after the record's end",
        ),
        (
            format!("file = {rec}\nstart = -1.0"),
            "[base_motion]: key `start`",
            "start = -1.0",
            "at least 0",
        ),
        (
            format!("x = {{ file = {rec}, pga = 0.3, scale = 1.0 }}"),
            "[base_motion.x]: key `pga`",
            "x = {",
            "not both",
        ),
        (
            "y = { table = [[0.0, 0.0, 1.0], [1.0, 0.0, 2.0]] }".into(),
            "[base_motion.y]: key `table`",
            "y = {",
            "rows are [t, a]",
        ),
        (
            "[base_motion.y]\ntable = [[0.0, 1.0], [1.0, 2.0]]\ncomponent = \"x\"".into(),
            "[base_motion.y]: unknown key `component`",
            "component = ",
            "allowed",
        ),
        (
            format!("file = {rec}\nx = {{ file = {rec} }}"),
            "[base_motion]: key `file`",
            "file = ",
            "give each record's keys in its own table",
        ),
        (
            "x = 3".into(),
            "[base_motion]: key `x`",
            "x = 3",
            "must be a table",
        ),
    ];
    for (motion, place, at, what) in cases {
        // a `[base_motion.y]` header must come after the top-level keys
        let text = if motion.starts_with("[base_motion.y]") {
            model_text("", 10).replace("[base_motion]\n", &format!("[base_motion]\n{motion}\n"))
        } else {
            model_text(&motion, 10)
        };
        let e = nmm::model::parse_model_named(&text, dir.path(), "slope.toml")
            .unwrap_err()
            .to_string();
        let line = line_of(&text, at);
        assert!(!e.contains('\n'), "one line: {e}");
        assert!(e.starts_with(place), "{e}");
        assert!(e.contains(what), "{e}");
        assert!(
            e.ends_with(&format!("(slope.toml, line {line})")),
            "{e} (line {line})"
        );
    }
    // a unit the older header states that is not an acceleration unit: the record file's line
    let text = std::fs::read_to_string(record_path()).unwrap();
    let (values, dt) = read_at2(&text);
    let old = old_peer(&values, dt).replace(
        "CENTIMETERS PER SECOND PER SECOND",
        "FEET PER SECOND PER SECOND",
    );
    std::fs::write(dir.path().join("feet.at2"), old).unwrap();
    let text = model_text("file = \"feet.at2\"\nformat = \"peer\"", 10);
    let e = nmm::model::parse_model_named(&text, dir.path(), "slope.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("[base_motion]: key `file`:"), "{e}");
    assert!(
        e.contains("feet.at2: line 3: unknown acceleration unit 'FEET'"),
        "{e}"
    );
    assert!(
        e.ends_with(&format!("(slope.toml, line {})", line_of(&text, "file = "))),
        "{e}"
    );
}

#[test]
fn nmm_check_prints_each_record_and_exits_non_zero_on_a_bad_one() {
    let dir = tempfile::tempdir().unwrap();
    let motion = two_component_motion(dir.path());
    let path = dir.path().join("slope.toml");
    std::fs::write(&path, model_text(&motion, 10)).unwrap();
    let nmm = env!("CARGO_BIN_EXE_nmm");
    let out = std::process::Command::new(nmm)
        .args(["check", "--quiet"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(out.status.success());
    let stdout = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("base motion"))
        .collect();
    assert_eq!(lines.len(), 2, "{stdout}");
    assert!(lines[0].starts_with("base motion x: "), "{}", lines[0]);
    assert!(lines[0].contains("dt = 0.005 s, 8 s long"), "{}", lines[0]);
    assert!(lines[0].contains("PGA as read 0.2500 g"), "{}", lines[0]);
    assert!(lines[0].contains("used 2 … 5 s (3 s"), "{}", lines[0]);
    assert!(lines[0].contains("PGA as applied 0.4500 g"), "{}", lines[0]);
    assert!(
        lines[1].starts_with("base motion y: old_up.at2: 1601 samples"),
        "{}",
        lines[1]
    );
    assert!(lines[1].contains("PGA as applied 0.1500 g"), "{}", lines[1]);
    let out = std::process::Command::new(nmm)
        .args(["check", "--quiet", "--json"])
        .arg(&path)
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let r = &v["base_motion"];
    assert_eq!(r.as_array().unwrap().len(), 2);
    assert_eq!(r[0]["axis"], "x");
    assert_eq!(r[0]["start"], START);
    assert_eq!(r[0]["duration"], DURATION);
    assert!((r[0]["pga_applied_g"][0].as_f64().unwrap() - PGA_X).abs() < 1e-12);
    assert!((r[1]["pga_applied_g"][1].as_f64().unwrap() - PGA_Y).abs() < 1e-12);
    assert!((r[0]["pga_read_g"][0].as_f64().unwrap() - 0.25).abs() < 1e-3);
    assert!((r[0]["dt"].as_f64().unwrap() - 0.005).abs() < 1e-12);
    // a bad record: one line on stderr, non-zero exit
    std::fs::write(&path, model_text(&format!("{motion}\nscale = 2.0"), 10)).unwrap();
    let out = std::process::Command::new(nmm)
        .args(["check"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.starts_with("error: [base_motion]: key `scale`"),
        "{stderr}"
    );
}
