//! The scaling study of issue 8: brick walls and jointed slopes of growing size, run by the
//! `nmm` binary, per-step cost from whole-process wall times, per-stage times, iterations,
//! contacts and peak memory, with fitted growth exponents; optionally against ntdda.
//!
//! ```sh
//! cargo build --release                                    # the nmm binary it drives
//! cargo run --release --example scaling_study -- --quick   # CI size, well under a minute
//! cargo run --release --example scaling_study -- --json scaling.jsonl   # the full study
//! cargo run --release --example scaling_study -- --walls 10,20,40 --slopes none \
//!     --peer /path/to/ntdda/build/pipeline_test           # with the DDA peer
//! ```
//!
//! Per-step cost = (T(s₂) − T(s₁)) / (s₂ − s₁), T the whole-process wall time of
//! `nmm run MODEL --out DIR --no-vtk` with s₁ and s₂ steps, runs alternated s₁, s₂, s₁, s₂ …
//! (`--reps` times) and the median taken. See `--help` for every option.

mod study;

use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;
use study::{report, Case, Config};

#[derive(Parser)]
#[command(
    name = "scaling_study",
    about = "Scaling study of nmm on brick walls and jointed slopes"
)]
struct Args {
    /// The CI preset: walls 10×10 and 20×20, a slope of ~100 blocks, steps 1 and 3, one
    /// repetition (other options still override it).
    #[arg(long)]
    quick: bool,
    /// The nmm binary to run.
    #[arg(long, value_name = "PATH", default_value = "target/release/nmm")]
    nmm: PathBuf,
    /// Also time ntdda (the DDA peer's driver, run as `PATH wall.geo wall.ana`) on the walls.
    #[arg(long, value_name = "PATH")]
    peer: Option<PathBuf>,
    /// Walls: N (N×N) or NXxNY, comma-separated, or `none` [default: 10,20,30,40,60,80,100].
    #[arg(long, value_name = "LIST")]
    walls: Option<String>,
    /// Slopes: approximate block counts, comma-separated, or `none`
    /// [default: 100,250,500,1000,2000].
    #[arg(long, value_name = "LIST")]
    slopes: Option<String>,
    /// The two step counts s1,s2 [default: 2,12].
    #[arg(long, value_name = "S1,S2")]
    steps: Option<String>,
    /// Repetitions of each (s1, s2) pair; medians are reported [default: 3].
    #[arg(long)]
    reps: Option<usize>,
    /// Time step (s).
    #[arg(long, default_value_t = 0.001)]
    dt: f64,
    /// Analysis mode: dynamic or static.
    #[arg(long, default_value = "dynamic")]
    mode: String,
    /// Mesh size of the walls (m).
    #[arg(long, default_value_t = 0.2)]
    cover: f64,
    /// Mesh size of the slopes (m).
    #[arg(long, default_value_t = 0.5)]
    slope_cover: f64,
    /// Slopes with cross joints offset by half a spacing in every other row.
    #[arg(long)]
    stagger: bool,
    /// Walls entering the fit: bricks per course and courses in LO:HI [default: 20:100].
    #[arg(long, value_name = "LO:HI")]
    fit: Option<String>,
    /// Slopes entering the fit: blocks in LO:HI [default: all].
    #[arg(long, value_name = "LO:HI")]
    slope_fit: Option<String>,
    /// Kill a run after this many seconds.
    #[arg(long, value_name = "SECS")]
    timeout: Option<u64>,
    /// Folder for models and runs (kept); default a temporary folder, removed at the end.
    #[arg(long, value_name = "DIR")]
    work: Option<PathBuf>,
    /// Keep the temporary folder.
    #[arg(long)]
    keep: bool,
    /// Also write the results as JSON Lines: one object per row, then one per fit.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Only write the models (TOML, and ntdda inputs with --peer) into DIR, run nothing.
    #[arg(long, value_name = "DIR")]
    write_models: Option<PathBuf>,
    /// No progress on stderr.
    #[arg(long)]
    quiet: bool,
}

fn list(s: &str) -> Vec<&str> {
    if s.trim() == "none" || s.trim().is_empty() {
        return Vec::new();
    }
    s.split(',').map(str::trim).collect()
}

fn range(s: &str) -> Result<(usize, usize), String> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| format!("expected LO:HI, got {s:?}"))?;
    let p = |x: &str| {
        x.trim()
            .parse::<usize>()
            .map_err(|_| format!("expected LO:HI, got {s:?}"))
    };
    Ok((p(a)?, p(b)?))
}

fn config(a: &Args) -> Result<Config, String> {
    let work = a.work.clone().unwrap_or_else(|| {
        std::env::temp_dir().join(format!("nmm-scaling-study-{}", std::process::id()))
    });
    let mut nmm = a.nmm.clone();
    if !nmm.exists() && nmm == std::path::Path::new("target/release/nmm") {
        let alt = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(&nmm);
        if alt.exists() {
            nmm = alt;
        }
    }
    if a.write_models.is_none() && !nmm.exists() {
        return Err(format!(
            "{}: no nmm binary there; build it with `cargo build --release` or pass --nmm PATH",
            nmm.display()
        ));
    }
    let mut c = if a.quick {
        Config::quick(nmm, work)
    } else {
        Config::full(nmm, work)
    };
    let mut cases: Vec<Case> = c.cases.clone();
    if let Some(w) = &a.walls {
        cases.retain(|c| !matches!(c, Case::Wall { .. }));
        for item in list(w) {
            let (nx, ny) = match item.split_once(['x', 'X', '×']) {
                Some((x, y)) => (x.trim().parse(), y.trim().parse()),
                None => (item.parse(), item.parse()),
            };
            match (nx, ny) {
                (Ok(nx), Ok(ny)) if nx > 0 && ny > 0 => cases.push(Case::Wall { nx, ny }),
                _ => return Err(format!("--walls: expected N or NXxNY, got {item:?}")),
            }
        }
    }
    if let Some(s) = &a.slopes {
        cases.retain(|c| !matches!(c, Case::Slope { .. }));
        for item in list(s) {
            match item.parse::<usize>() {
                Ok(b) if b > 0 => cases.push(Case::Slope { blocks: b }),
                _ => return Err(format!("--slopes: expected a block count, got {item:?}")),
            }
        }
    }
    cases.sort_by_key(|c| c.family() == study::Family::Slope);
    c.cases = cases;
    if let Some(s) = &a.steps {
        let v: Vec<usize> = s
            .split(',')
            .map(|x| x.trim().parse::<usize>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("--steps: expected S1,S2, got {s:?}"))?;
        match v[..] {
            [s1, s2] if 0 < s1 && s1 < s2 => c.steps = (s1, s2),
            _ => {
                return Err(format!(
                    "--steps: expected S1,S2 with 0 < S1 < S2, got {s:?}"
                ))
            }
        }
    }
    if let Some(r) = a.reps {
        if r == 0 {
            return Err("--reps: at least 1".into());
        }
        c.reps = r;
    }
    if !(a.dt > 0.0 && a.cover > 0.0 && a.slope_cover > 0.0) {
        return Err("--dt, --cover and --slope-cover must be positive".into());
    }
    c.dt = a.dt;
    c.wall_cover = a.cover;
    c.slope_cover = a.slope_cover;
    c.mode = match a.mode.as_str() {
        "dynamic" => nmm::model::Mode::Dynamic,
        "static" => nmm::model::Mode::Static,
        m => return Err(format!("--mode: expected dynamic or static, got {m:?}")),
    };
    c.stagger = a.stagger;
    if let Some(f) = &a.fit {
        c.wall_fit = range(f).map_err(|e| format!("--fit: {e}"))?;
    }
    if let Some(f) = &a.slope_fit {
        c.slope_fit = range(f).map_err(|e| format!("--slope-fit: {e}"))?;
    }
    if let Some(t) = a.timeout {
        c.timeout = Duration::from_secs(t);
    }
    c.peer = a.peer.clone();
    c.verbose = !a.quiet;
    Ok(c)
}

/// Where and what was measured: nmm's version and commit, the processor, the command.
fn header(cfg: &Config) -> String {
    let version = study::nmm_version(&cfg.nmm).unwrap_or_else(|| "nmm (version unknown)".into());
    let commit = std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| {
            format!(
                " (checkout at {})",
                String::from_utf8_lossy(&o.stdout).trim()
            )
        })
        .unwrap_or_default();
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let args: Vec<String> = std::env::args().skip(1).collect();
    format!(
        "{version}{commit}, {cpu}, {cores} core(s); `scaling_study {}`",
        args.join(" ")
    )
}

fn main() -> ExitCode {
    let args = Args::parse();
    let cfg = match config(&args) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Some(dir) = &args.write_models {
        return match study::write_models(&cfg, dir) {
            Ok(files) => {
                for f in files {
                    println!("{}", f.display());
                }
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::FAILURE
            }
        };
    }
    let head = header(&cfg);
    let rows = study::run(&cfg);
    print!("{}", report::markdown(&cfg, &rows, &head));
    let mut code = ExitCode::SUCCESS;
    if let Some(path) = &args.json {
        let version = study::nmm_version(&cfg.nmm);
        let text: String = report::json_lines(&cfg, &rows, version.as_deref())
            .iter()
            .map(|v| format!("{v}\n"))
            .collect();
        if let Err(e) = std::fs::write(path, text) {
            eprintln!("error: {}: {e}", path.display());
            code = ExitCode::FAILURE;
        }
    }
    if args.work.is_none() && !args.keep {
        let _ = std::fs::remove_dir_all(&cfg.work);
    } else {
        eprintln!("models and runs kept in {}", cfg.work.display());
    }
    if rows.iter().any(|r| r.status != "ok") {
        eprintln!("some runs failed: see the table");
        code = ExitCode::FAILURE;
    }
    code
}
