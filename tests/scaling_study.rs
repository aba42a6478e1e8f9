//! The scaling study (examples/scaling_study) end to end at its smallest: the quick preset's
//! models are generated and pass `nmm check`'s parser, and one tiny study (a 10×10 wall and a
//! slope of ~100 blocks, steps 1 and 2) runs the real `nmm` binary and reports rows of finite
//! numbers. Not a timing test: no figure is compared with a time.

#[allow(dead_code)]
#[path = "../examples/scaling_study/study/mod.rs"]
mod study;

use study::{report, Case, Config, Family};

fn work(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("nmm-scaling-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn nmm() -> std::path::PathBuf {
    env!("CARGO_BIN_EXE_nmm").into()
}

#[test]
fn quick_preset_models_parse() {
    let dir = work("models");
    let cfg = Config::quick(nmm(), dir.clone());
    let files = study::write_models(&cfg, &dir).expect("models written");
    assert_eq!(files.len(), 2 * cfg.cases.len());
    for (f, case) in files.iter().zip(cfg.cases.iter().flat_map(|c| [c, c])) {
        let text = std::fs::read_to_string(f).unwrap();
        let m = nmm::model::parse_model(&text, &dir).unwrap_or_else(|e| panic!("{f:?}: {e}"));
        assert_eq!(m.blocks.len(), cfg.blocks(case).unwrap(), "{f:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tiny_study_reports_finite_numbers() {
    let dir = work("run");
    let cfg = Config {
        cases: vec![Case::Wall { nx: 10, ny: 10 }, Case::Slope { blocks: 100 }],
        steps: (1, 2),
        reps: 1,
        wall_fit: (10, 10),
        ..Config::quick(nmm(), dir.clone())
    };
    let rows = study::run(&cfg);
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert_eq!(r.status, "ok", "{:?}", r.case);
        let finite = |x: Option<f64>, what: &str| {
            let v = x.unwrap_or_else(|| panic!("{:?}: no {what}", r.case));
            assert!(v.is_finite(), "{:?}: {what} = {v}", r.case);
            v
        };
        // Whole-process times are positive; their difference is finite (it may be negative on
        // a noisy machine at this size).
        assert!(finite(r.t1_s, "T(s1)") > 0.0 && finite(r.t2_s, "T(s2)") > 0.0);
        finite(r.per_step_ms, "per-step cost");
        let unknowns = finite(r.unknowns(), "unknowns");
        assert!(unknowns > 0.0 && unknowns.fract() == 0.0);
        let its = finite(r.info.iterations_max, "iterations");
        assert!(its >= 1.0);
        assert_eq!(r.check.blocks, Some(r.blocks));
        if cfg!(target_os = "linux") {
            // The parent's wait4 measure: an nmm process is more than a megabyte.
            assert!(finite(r.peak_mb, "peak memory") > 1.0);
        }
    }
    assert_eq!(rows[0].blocks, 101);
    assert_eq!(rows[0].case.family(), Family::Wall);

    let md = report::markdown(&cfg, &rows, "header");
    let table_rows: Vec<&str> = md
        .lines()
        .filter(|l| l.starts_with("| 10×10 |") || l.starts_with("| ~100 |"))
        .collect();
    assert_eq!(table_rows.len(), 2, "{md}");
    for l in &table_rows {
        let cells: Vec<&str> = l.trim_matches('|').split('|').map(str::trim).collect();
        assert_eq!(cells.len(), 12, "{l}");
        // blocks, unknowns, ms/step and peak memory are numbers.
        for i in [1, 2, 10, 11] {
            let v: f64 = cells[i]
                .replace(',', "")
                .parse()
                .unwrap_or_else(|_| panic!("cell {i} of {l}"));
            assert!(v.is_finite());
        }
    }
    assert!(md.contains("### Brick walls") && md.contains("### Jointed slopes"));

    let json = report::json_lines(&cfg, &rows, Some("nmm test"));
    assert_eq!(json.iter().filter(|v| v["kind"] == "row").count(), 2);
    assert_eq!(json[0]["blocks"], 101);
    assert!(json[0]["ms_per_step"].as_f64().unwrap().is_finite());
    std::fs::remove_dir_all(&dir).unwrap();
}
