//! The scaling study: generate the models, run the `nmm` binary (and optionally the DDA peer)
//! as subprocesses, difference whole-process wall times between two step counts, read each
//! run's `summary.json`, and report.
//!
//! Included by `examples/scaling_study/main.rs` (the command line) and by
//! `tests/scaling_study.rs` (an end-to-end run of the quick preset).

pub mod ntdda;
pub mod process;
pub mod report;

use nmm::generate::{brick_wall_model, jointed_slope_model, SlopeOptions, WallOptions};
use nmm::model::Mode;
use process::{run_timed, Exit, Timed};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// A model family of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    Wall,
    Slope,
}

impl Family {
    pub fn name(self) -> &'static str {
        match self {
            Family::Wall => "wall",
            Family::Slope => "slope",
        }
    }
}

/// One model of the study.
#[derive(Debug, Clone, PartialEq)]
pub enum Case {
    /// A running-bond wall of `nx` bricks per course and `ny` courses.
    Wall { nx: usize, ny: usize },
    /// A jointed slope of about `blocks` blocks.
    Slope { blocks: usize },
}

impl Case {
    pub fn family(&self) -> Family {
        match self {
            Case::Wall { .. } => Family::Wall,
            Case::Slope { .. } => Family::Slope,
        }
    }
    /// `20×20`, `~500`.
    pub fn label(&self) -> String {
        match self {
            Case::Wall { nx, ny } => format!("{nx}×{ny}"),
            Case::Slope { blocks } => format!("~{blocks}"),
        }
    }
    /// File-name stem: `wall_20x20`, `slope_500`.
    pub fn stem(&self) -> String {
        match self {
            Case::Wall { nx, ny } => format!("wall_{nx}x{ny}"),
            Case::Slope { blocks } => format!("slope_{blocks}"),
        }
    }
}

#[derive(Debug, Clone)]
pub struct Config {
    /// The `nmm` binary.
    pub nmm: PathBuf,
    /// The ntdda driver (`pipeline_test GEO ANA`), for walls.
    pub peer: Option<PathBuf>,
    pub cases: Vec<Case>,
    /// The two step counts s₁ < s₂.
    pub steps: (usize, usize),
    pub reps: usize,
    pub dt: f64,
    pub mode: Mode,
    /// Mesh size of the walls (m).
    pub wall_cover: f64,
    /// Mesh size of the slopes (m).
    pub slope_cover: f64,
    /// Slopes with staggered cross joints.
    pub stagger: bool,
    /// Per run.
    pub timeout: Duration,
    /// Where models and run folders go.
    pub work: PathBuf,
    /// Walls whose bricks per course and courses both lie in this range enter the fit.
    pub wall_fit: (usize, usize),
    /// Slopes whose block count lies in this range enter the fit.
    pub slope_fit: (usize, usize),
    /// Progress on stderr.
    pub verbose: bool,
}

impl Config {
    /// The full study: walls 10×10 … 100×100 and slopes of ~100 … 2,000 blocks, steps 2 → 12,
    /// 3 repetitions, the fit over walls 20×20 … 100×100.
    pub fn full(nmm: PathBuf, work: PathBuf) -> Self {
        let mut cases: Vec<Case> = [10, 20, 30, 40, 60, 80, 100]
            .into_iter()
            .map(|n| Case::Wall { nx: n, ny: n })
            .collect();
        cases.extend(
            [100, 250, 500, 1000, 2000]
                .into_iter()
                .map(|blocks| Case::Slope { blocks }),
        );
        Config {
            nmm,
            peer: None,
            cases,
            steps: (2, 12),
            reps: 3,
            dt: 0.001,
            mode: Mode::Dynamic,
            wall_cover: 0.2,
            slope_cover: 0.5,
            stagger: false,
            timeout: Duration::from_secs(3600),
            work,
            wall_fit: (20, 100),
            slope_fit: (0, usize::MAX),
            verbose: false,
        }
    }

    /// The CI preset (well under a minute): walls 10×10 and 20×20, a slope of ~100 blocks,
    /// steps 1 → 3, one repetition.
    pub fn quick(nmm: PathBuf, work: PathBuf) -> Self {
        Config {
            cases: vec![
                Case::Wall { nx: 10, ny: 10 },
                Case::Wall { nx: 20, ny: 20 },
                Case::Slope { blocks: 100 },
            ],
            steps: (1, 3),
            reps: 1,
            timeout: Duration::from_secs(300),
            wall_fit: (10, 20),
            ..Config::full(nmm, work)
        }
    }

    fn slope_options(&self, blocks: usize, steps: usize) -> SlopeOptions {
        SlopeOptions {
            steps,
            dt: self.dt,
            cover: self.slope_cover,
            mode: self.mode,
            stagger: self.stagger,
            ..SlopeOptions::with_blocks(blocks)
        }
    }

    /// The model file of `case` with `steps` steps (TOML text).
    pub fn model_text(&self, case: &Case, steps: usize) -> Result<String, String> {
        match *case {
            Case::Wall { nx, ny } => Ok(brick_wall_model(&WallOptions {
                nx,
                ny,
                steps,
                dt: self.dt,
                cover: self.wall_cover,
                mode: self.mode,
                closers: false,
            })),
            Case::Slope { blocks } => jointed_slope_model(&self.slope_options(blocks, steps)),
        }
    }

    /// Blocks of `case`, the fixed base included (the generator's count).
    pub fn blocks(&self, case: &Case) -> Result<usize, String> {
        match *case {
            Case::Wall { nx, ny } => Ok(nx * ny + 1),
            Case::Slope { blocks } => nmm::generate::slope_geometry(&self.slope_options(blocks, 1))
                .map(|g| g.blocks.len() + 1),
        }
    }

    fn log(&self, msg: &str) {
        if self.verbose {
            eprintln!("{msg}");
        }
    }
}

/// Write every model of the study (both step counts) and, with a peer, its ntdda inputs into
/// `dir`; returns the files written.
pub fn write_models(cfg: &Config, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut files = Vec::new();
    for case in &cfg.cases {
        for s in [cfg.steps.0, cfg.steps.1] {
            let path = dir.join(format!("{}_s{s}.toml", case.stem()));
            std::fs::write(&path, cfg.model_text(case, s)?)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            files.push(path);
            if let (Some(_), Case::Wall { nx, ny }) = (&cfg.peer, case) {
                let d = dir.join(format!("ntdda_{}_s{s}", case.stem()));
                ntdda::write_wall(&d, *nx, *ny, s, cfg.dt)
                    .map_err(|e| format!("{}: {e}", d.display()))?;
                files.push(d);
            }
        }
    }
    Ok(files)
}

/// What one `nmm run` reported (from `summary.json`, or from `history.csv` and the stderr
/// summary lines where `summary.json` is missing).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunInfo {
    /// `"summary.json"` or `"history.csv+stderr"`.
    pub source: String,
    pub unknowns: Option<f64>,
    pub contacts_max: Option<f64>,
    pub contacts_mean: Option<f64>,
    pub iterations_total: Option<f64>,
    pub iterations_median: Option<f64>,
    pub iterations_max: Option<f64>,
    pub cuts: Option<f64>,
    /// Seconds: cover, assembly, contact, factorisation, solve (totals of the run).
    pub timings: [Option<f64>; 5],
    pub peak_memory_bytes: Option<f64>,
    pub steps: Option<f64>,
    pub status: Option<String>,
    pub error: Option<String>,
}

pub const STAGES: [&str; 5] = ["cover", "assembly", "contact", "factorisation", "solve"];

fn at<'a>(v: &'a Value, path: &[&str]) -> Option<&'a Value> {
    path.iter().try_fold(v, |v, k| v.get(k))
}

fn num(v: &Value, path: &[&str]) -> Option<f64> {
    at(v, path)
        .and_then(Value::as_f64)
        .filter(|x| x.is_finite())
}

/// Read a run folder: `summary.json` first; every figure it lacks is taken from `history.csv`
/// (iterations per step) or the stderr summary lines of `nmm run`, if they have it.
pub fn read_run(dir: &Path, stderr: &str) -> RunInfo {
    let mut r = RunInfo::default();
    let summary = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok());
    if let Some(v) = &summary {
        r.source = "summary.json".into();
        r.unknowns = num(v, &["unknowns"]);
        r.contacts_max = num(v, &["contacts", "max"]);
        r.contacts_mean = num(v, &["contacts", "mean"]);
        r.iterations_total = num(v, &["iterations", "total"]);
        r.iterations_median = num(v, &["iterations", "median"]);
        r.iterations_max = num(v, &["iterations", "max"]);
        r.cuts = num(v, &["cuts", "total"]);
        for (t, s) in r.timings.iter_mut().zip(STAGES) {
            *t = num(v, &["timings", s]);
        }
        r.peak_memory_bytes = num(v, &["peak_memory_bytes"]);
        r.steps = num(v, &["steps"]);
        r.status = at(v, &["status"])
            .and_then(Value::as_str)
            .map(str::to_string);
        r.error = at(v, &["error"])
            .and_then(Value::as_str)
            .map(str::to_string);
    }
    let mut fell_back = false;
    if r.iterations_median.is_none() || r.iterations_max.is_none() {
        if let Some(its) = history_iterations(&dir.join("history.csv")) {
            let mut s = its.clone();
            s.sort_by(f64::total_cmp);
            r.iterations_total.get_or_insert(its.iter().sum());
            r.iterations_median
                .get_or_insert(median(&s).unwrap_or(f64::NAN));
            r.iterations_max
                .get_or_insert(*s.last().unwrap_or(&f64::NAN));
            r.steps.get_or_insert(its.len() as f64);
            fell_back = true;
        }
    }
    let fb = parse_stderr(stderr);
    if r.unknowns.is_none() && fb.unknowns.is_some() {
        r.unknowns = fb.unknowns;
        fell_back = true;
    }
    if r.cuts.is_none() && fb.cuts.is_some() {
        r.cuts = fb.cuts;
        fell_back = true;
    }
    for (t, f) in r.timings.iter_mut().zip(fb.timings) {
        if t.is_none() && f.is_some() {
            *t = f;
            fell_back = true;
        }
    }
    if fell_back {
        r.source = if summary.is_some() {
            "summary.json+history.csv+stderr".into()
        } else {
            "history.csv+stderr".into()
        };
    }
    r
}

/// The `iterations` column of `history.csv`.
fn history_iterations(path: &Path) -> Option<Vec<f64>> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut lines = text.lines();
    let col = lines
        .next()?
        .split(',')
        .position(|h| h.trim() == "iterations")?;
    let v: Vec<f64> = lines
        .filter(|l| !l.trim().is_empty())
        .filter_map(|l| l.split(',').nth(col)?.trim().parse().ok())
        .collect();
    (!v.is_empty()).then_some(v)
}

/// The summary lines `nmm run` prints on stderr: "… N unknowns; Newton iterations median M,
/// max X; K step(s) cut" and "time: cover X s, assembly X s, contact X s, factorisation X s,
/// solve X s".
fn parse_stderr(text: &str) -> RunInfo {
    let mut r = RunInfo::default();
    let number_before = |l: &str, key: &str| -> Option<f64> {
        let i = l.find(key)?;
        l[..i].split_whitespace().last()?.parse().ok()
    };
    for l in text.lines() {
        if l.contains(" unknowns") && l.contains("Newton iterations") {
            r.unknowns = number_before(l, " unknowns");
            r.cuts = number_before(l, " step(s) cut");
        }
        if let Some(rest) = l.trim().strip_prefix("time:") {
            for part in rest.split(',') {
                let w: Vec<&str> = part.split_whitespace().collect();
                if let [name, value, "s"] = w[..] {
                    if let Some(i) = STAGES.iter().position(|s| *s == name) {
                        r.timings[i] = value.parse().ok();
                    }
                }
            }
        }
    }
    r
}

/// What `nmm check` prints: blocks, physical covers, manifold elements, unknowns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CheckInfo {
    pub blocks: Option<usize>,
    pub physical_covers: Option<usize>,
    pub manifold_elements: Option<usize>,
    pub unknowns: Option<usize>,
}

pub fn parse_check(stdout: &str) -> CheckInfo {
    let field = |key: &str| {
        stdout.lines().find_map(|l| {
            l.strip_prefix(key)?
                .split_whitespace()
                .next()?
                .parse::<usize>()
                .ok()
        })
    };
    CheckInfo {
        blocks: field("blocks:"),
        physical_covers: field("physical covers:"),
        manifold_elements: field("manifold elements:"),
        unknowns: field("unknowns:"),
    }
}

pub fn median(sorted_or_not: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = sorted_or_not
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// The peer's figures for one wall.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PeerRow {
    /// `"ok"`, `"crashed"`, `"timed out"`, or `"blocks N ≠ M"` (its cutter lost blocks).
    pub status: String,
    pub detail: Option<String>,
    pub blocks: Option<usize>,
    pub per_step_ms: Option<f64>,
    pub t1_s: Option<f64>,
    pub t2_s: Option<f64>,
    pub peak_mb: Option<f64>,
}

/// One row of the study: a model, its figures and its per-step cost.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub case: Case,
    /// `"ok"` or why not.
    pub status: String,
    pub blocks: usize,
    pub check: CheckInfo,
    /// Of the last s₂ run.
    pub info: RunInfo,
    /// Per step (ms), differenced between s₁ and s₂, median over repetitions: assembly,
    /// contact, factorisation, solve.
    pub stage_ms: [Option<f64>; 4],
    /// Set-up (cover) time of the s₂ run (s).
    pub cover_s: Option<f64>,
    /// Whole-process wall time per step (ms): median over repetitions of
    /// (T(s₂) − T(s₁)) / (s₂ − s₁).
    pub per_step_ms: Option<f64>,
    /// Median whole-process wall times (s).
    pub t1_s: Option<f64>,
    pub t2_s: Option<f64>,
    /// Peak resident memory of the s₂ runs, median (MB = 10⁶ bytes), measured by the parent.
    pub peak_mb: Option<f64>,
    /// `peak_memory_bytes` of `summary.json` (MB), if reported.
    pub peak_summary_mb: Option<f64>,
    pub peer: Option<PeerRow>,
}

impl Row {
    pub fn unknowns(&self) -> Option<f64> {
        self.info.unknowns.or(self.check.unknowns.map(|u| u as f64))
    }
}

/// The last non-empty line of a text (an error message).
fn last_line(text: &str) -> String {
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("")
        .trim()
        .chars()
        .take(300)
        .collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_default()
}

/// One `nmm run MODEL --out DIR --no-vtk`, timed.
fn run_nmm(cfg: &Config, model: &Path, out: &Path) -> Result<(Timed, String), String> {
    let _ = std::fs::remove_dir_all(out);
    let (o, e) = (out.with_extension("stdout"), out.with_extension("stderr"));
    let mut cmd = Command::new(&cfg.nmm);
    cmd.arg("run")
        .arg(model)
        .arg("--out")
        .arg(out)
        .arg("--no-vtk");
    let t = run_timed(&mut cmd, None, &o, &e, cfg.timeout)
        .map_err(|err| format!("{}: {err}", cfg.nmm.display()))?;
    Ok((t, read(&e)))
}

/// One ntdda run in `dir` (`wall.geo`, `wall.ana`), timed.
fn run_peer(cfg: &Config, peer: &Path, dir: &Path) -> Result<(Timed, String), String> {
    let _ = std::fs::remove_dir_all(dir.join("output"));
    let mut cmd = Command::new(peer);
    cmd.arg("wall.geo").arg("wall.ana");
    let (o, e) = (dir.join("stdout.txt"), dir.join("stderr.txt"));
    let t = run_timed(&mut cmd, Some(dir), &o, &e, cfg.timeout)
        .map_err(|err| format!("{}: {err}", peer.display()))?;
    Ok((t, read(&e)))
}

fn per_step(t1: f64, t2: f64, s: (usize, usize)) -> f64 {
    (t2 - t1) / (s.1 - s.0) as f64
}

const MB: f64 = 1e6;

/// Run one case: `nmm check`, then `reps` × (s₁, s₂) runs of nmm (and of the peer, for walls,
/// interleaved: nmm s₁, peer s₁, nmm s₂, peer s₂) so that drift of the machine hits both.
pub fn run_case(cfg: &Config, case: &Case) -> Row {
    let (s1, s2) = cfg.steps;
    let mut row = Row {
        case: case.clone(),
        status: "ok".into(),
        blocks: 0,
        check: CheckInfo::default(),
        info: RunInfo::default(),
        stage_ms: [None; 4],
        cover_s: None,
        per_step_ms: None,
        t1_s: None,
        t2_s: None,
        peak_mb: None,
        peak_summary_mb: None,
        peer: None,
    };
    let fail = |mut row: Row, msg: String| {
        row.status = msg;
        row
    };
    match cfg.blocks(case) {
        Ok(b) => row.blocks = b,
        Err(e) => return fail(row, e),
    }
    let dir = cfg.work.join(case.stem());
    if let Err(e) = std::fs::create_dir_all(&dir) {
        return fail(row, format!("{}: {e}", dir.display()));
    }
    let mut models = Vec::new();
    for s in [s1, s2] {
        let path = dir.join(format!("{}_s{s}.toml", case.stem()));
        match cfg
            .model_text(case, s)
            .and_then(|t| std::fs::write(&path, t).map_err(|e| e.to_string()))
        {
            Ok(()) => models.push(path),
            Err(e) => return fail(row, e),
        }
    }
    // nmm check: blocks, covers, elements, unknowns.
    cfg.log(&format!(
        "{} {}: nmm check",
        case.family().name(),
        case.label()
    ));
    match Command::new(&cfg.nmm).arg("check").arg(&models[0]).output() {
        Ok(out) if out.status.success() => {
            row.check = parse_check(&String::from_utf8_lossy(&out.stdout))
        }
        Ok(out) => {
            return fail(
                row,
                format!(
                    "nmm check failed: {}",
                    last_line(&String::from_utf8_lossy(&out.stderr))
                ),
            )
        }
        Err(e) => return fail(row, format!("{}: {e}", cfg.nmm.display())),
    }
    let peer_dirs = match (&cfg.peer, case) {
        (Some(_), Case::Wall { nx, ny }) => {
            let mut d = Vec::new();
            for s in [s1, s2] {
                let p = dir.join(format!("ntdda_s{s}"));
                if let Err(e) = ntdda::write_wall(&p, *nx, *ny, s, cfg.dt) {
                    return fail(row, format!("{}: {e}", p.display()));
                }
                d.push(p);
            }
            Some(d)
        }
        _ => None,
    };
    let mut t = [Vec::new(), Vec::new()];
    let mut stages = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
    let mut peaks = Vec::new();
    let mut peer_ok = peer_dirs.is_some();
    let mut peer = PeerRow {
        status: "ok".into(),
        ..PeerRow::default()
    };
    let mut pt = [Vec::new(), Vec::new()];
    let mut peer_peaks = Vec::new();
    for rep in 0..cfg.reps {
        let mut infos = Vec::new();
        for (i, s) in [s1, s2].into_iter().enumerate() {
            cfg.log(&format!(
                "{} {}: rep {}/{}, {s} steps",
                case.family().name(),
                case.label(),
                rep + 1,
                cfg.reps
            ));
            let out = dir.join(format!("run_s{s}"));
            let (timed, stderr) = match run_nmm(cfg, &models[i], &out) {
                Ok(x) => x,
                Err(e) => return fail(row, e),
            };
            let info = read_run(&out, &stderr);
            if !timed.exit.success() {
                let why = info.error.clone().unwrap_or_else(|| last_line(&stderr));
                row.info = info;
                return fail(
                    row,
                    format!("nmm run failed ({}): {why}", timed.exit.describe()),
                );
            }
            t[i].push(timed.wall.as_secs_f64());
            if i == 1 {
                peaks.extend(timed.peak_rss.map(|b| b as f64 / MB));
            }
            infos.push(info);
            if let (true, Some(dirs), Some(p)) = (peer_ok, &peer_dirs, &cfg.peer) {
                match run_peer(cfg, p, &dirs[i]) {
                    Ok((timed, stderr)) => {
                        let (blocks, heap) = ntdda::read_stderr(&stderr);
                        peer.blocks = blocks.or(peer.blocks);
                        if !timed.exit.success() || heap.is_some() {
                            peer.status = if timed.exit == Exit::TimedOut {
                                "timed out".into()
                            } else {
                                "crashed".into()
                            };
                            peer.detail = Some(format!(
                                "{}{}",
                                timed.exit.describe(),
                                heap.map(|h| format!(": {h}")).unwrap_or_default()
                            ));
                            peer_ok = false;
                        } else {
                            pt[i].push(timed.wall.as_secs_f64());
                            if i == 1 {
                                peer_peaks.extend(timed.peak_rss.map(|b| b as f64 / MB));
                            }
                        }
                    }
                    Err(e) => {
                        peer.status = "crashed".into();
                        peer.detail = Some(e);
                        peer_ok = false;
                    }
                }
            }
        }
        let (a, b) = (&infos[0], &infos[1]);
        for (k, st) in stages.iter_mut().enumerate() {
            if let (Some(x), Some(y)) = (a.timings[k + 1], b.timings[k + 1]) {
                st.push(1e3 * per_step(x, y, cfg.steps));
            }
        }
        row.info = infos.pop().expect("the s2 run");
    }
    let diffs: Vec<f64> = t[0]
        .iter()
        .zip(&t[1])
        .map(|(a, b)| 1e3 * per_step(*a, *b, cfg.steps))
        .collect();
    row.per_step_ms = median(&diffs);
    row.t1_s = median(&t[0]);
    row.t2_s = median(&t[1]);
    for (k, st) in stages.iter().enumerate() {
        row.stage_ms[k] = median(st);
    }
    row.cover_s = row.info.timings[0];
    row.peak_mb = median(&peaks);
    row.peak_summary_mb = row.info.peak_memory_bytes.map(|b| b / MB);
    if let Some(steps) = row.info.steps {
        if steps as usize != s2 {
            row.status = format!("ran {steps} of {s2} steps");
        }
    }
    if peer_dirs.is_some() {
        if peer_ok {
            let d: Vec<f64> = pt[0]
                .iter()
                .zip(&pt[1])
                .map(|(a, b)| 1e3 * per_step(*a, *b, cfg.steps))
                .collect();
            peer.per_step_ms = median(&d);
            peer.t1_s = median(&pt[0]);
            peer.t2_s = median(&pt[1]);
            peer.peak_mb = median(&peer_peaks);
            if let Some(b) = peer.blocks.filter(|b| *b != row.blocks) {
                peer.status = format!("blocks {b} ≠ {}", row.blocks);
            }
        }
        row.peer = Some(peer);
    }
    row
}

/// Run every case of the study, in order.
pub fn run(cfg: &Config) -> Vec<Row> {
    cfg.cases.iter().map(|c| run_case(cfg, c)).collect()
}

/// `nmm --version`, e.g. `nmm 0.1.0`.
pub fn nmm_version(nmm: &Path) -> Option<String> {
    let out = Command::new(nmm).arg("--version").output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stderr_and_check_are_read() {
        let err = "12 steps to t = 0.012000 s, 1200 unknowns; Newton iterations median 3, max 5; 1 step(s) cut\n\
                   time: cover 0.011 s, assembly 0.020 s, contact 0.003 s, factorisation 0.100 s, solve 0.004 s\n";
        let r = parse_stderr(err);
        assert_eq!(r.unknowns, Some(1200.0));
        assert_eq!(r.cuts, Some(1.0));
        assert_eq!(
            r.timings,
            [
                Some(0.011),
                Some(0.020),
                Some(0.003),
                Some(0.100),
                Some(0.004)
            ]
        );
        let c = parse_check("model: m.toml\nblocks: 101 (1 fixed)\nphysical covers: 640\nmanifold elements: 900\nunknowns: 1200\n");
        assert_eq!(
            c,
            CheckInfo {
                blocks: Some(101),
                physical_covers: Some(640),
                manifold_elements: Some(900),
                unknowns: Some(1200)
            }
        );
    }

    #[test]
    fn summary_json_is_preferred_and_missing_keys_stay_missing() {
        let dir = std::env::temp_dir().join(format!("nmm-study-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("summary.json"),
            r#"{"unknowns": 4800, "iterations": {"total": 30, "median": 3, "max": 4},
                "contacts": {"max": 900}, "timings": {"assembly": 0.5, "solve": null},
                "peak_memory_bytes": 1.5e8, "steps": 10}"#,
        )
        .unwrap();
        std::fs::write(dir.join("history.csv"), "step,time,iterations\n1,0.001,7\n").unwrap();
        let r = read_run(&dir, "");
        assert_eq!(r.source, "summary.json");
        assert_eq!(r.unknowns, Some(4800.0));
        assert_eq!(
            (r.iterations_median, r.iterations_max),
            (Some(3.0), Some(4.0))
        );
        assert_eq!((r.contacts_max, r.contacts_mean), (Some(900.0), None));
        assert_eq!(r.timings[1], Some(0.5));
        assert_eq!(r.timings[4], None);
        assert_eq!(r.cuts, None);
        // Without summary.json: history.csv's iterations column.
        std::fs::remove_file(dir.join("summary.json")).unwrap();
        std::fs::write(
            dir.join("history.csv"),
            "step,time,top.ux,iterations\n1,0.001,0,2\n2,0.002,0,6\n3,0.003,0,3\n",
        )
        .unwrap();
        let r = read_run(&dir, "");
        assert_eq!(r.source, "history.csv+stderr");
        assert_eq!(
            (r.iterations_total, r.iterations_median, r.iterations_max),
            (Some(11.0), Some(3.0), Some(6.0))
        );
        assert_eq!(r.unknowns, None);
        std::fs::remove_dir_all(&dir).unwrap();
        // Nothing at all.
        assert_eq!(read_run(&dir, "").source, "");
    }

    #[test]
    fn medians() {
        assert_eq!(median(&[]), None);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median(&[f64::NAN, 1.0]), Some(1.0));
    }
}
