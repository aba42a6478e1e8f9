//! The `nmm` command line: `run`, `check`.
use anyhow::Context;
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

mod progress;

#[derive(Parser)]
#[command(
    name = "nmm",
    version,
    about = "Numerical Manifold Method for 2-D blocks in contact"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a model and write its outputs (history.csv, VTK frames) into DIR.
    Run {
        model: PathBuf,
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Override [analysis] friction ("return-mapping" | "conventional").
        #[arg(long)]
        friction: Option<String>,
        /// Do not write VTK frames.
        #[arg(long)]
        no_vtk: bool,
        /// Do not print the model's warnings (they stay in DIR/summary.json).
        #[arg(long)]
        quiet: bool,
        /// Also write a checkpoint every N steps (checkpoints are always written at the end
        /// of each stage and on Ctrl-C), in DIR/checkpoints.
        #[arg(long, value_name = "N")]
        checkpoint_every: Option<usize>,
        /// Start from a checkpoint of another run (DIR/checkpoints/step_NNNNNNNN.ckpt):
        /// the model's later stages run from that saved state. Its blocks, joints, cover,
        /// materials and stages up to the checkpoint must be those of the saved run.
        #[arg(long, value_name = "CHECKPOINT")]
        from: Option<PathBuf>,
        /// Threads to compute on (default: NMM_THREADS, else the cores the process may
        /// use); the results are the same, bit for bit, whatever the count.
        #[arg(long, value_name = "N", value_parser = parse_threads)]
        threads: Option<usize>,
    },
    /// Continue an interrupted (or finished) run in DIR from its latest checkpoint, with
    /// the options it was started with; its outputs continue as if it had not stopped.
    Resume {
        #[arg(value_name = "DIR")]
        dir: PathBuf,
        /// Do not print the model's warnings.
        #[arg(long)]
        quiet: bool,
        /// Threads to compute on (as for `run`; the results do not depend on it).
        #[arg(long, value_name = "N", value_parser = parse_threads)]
        threads: Option<usize>,
    },
    /// Validate a model and print a summary (blocks, covers, elements, unknowns) without running it.
    Check {
        model: PathBuf,
        /// Print the summary as one JSON object.
        #[arg(long)]
        json: bool,
        /// Do not print the model's warnings.
        #[arg(long)]
        quiet: bool,
    },
    /// Run the verification set against closed forms and references; write a report.
    Verify {
        /// Report folder (report.md and plots).
        #[arg(long, value_name = "DIR", default_value = "verify-report")]
        out: PathBuf,
        /// The test suite's sizes instead of the quick ones.
        #[arg(long)]
        full: bool,
    },
    /// Draw the paper's Figure 4 (direct shear) and Figure 6 (shaking table) as PNG and SVG.
    Figures {
        #[arg(long, value_name = "DIR", default_value = "figures")]
        out: PathBuf,
    },
    /// Draw a model as cut (MODEL.toml) or a frame of a run (RUN_DIR) into a PNG or SVG.
    Plot {
        /// A model file, or a run's output folder.
        #[arg(value_name = "MODEL.toml|RUN_DIR")]
        target: PathBuf,
        /// The picture (.png or .svg); with --every, a folder for the sequence.
        #[arg(long, value_name = "FILE")]
        out: PathBuf,
        /// Run: the frame to draw, 0 = the first frame of blocks.pvd.
        #[arg(long, value_name = "N", conflicts_with_all = ["time", "last", "every"])]
        frame: Option<usize>,
        /// Run: the frame nearest to this time (s).
        #[arg(long, value_name = "T", conflicts_with_all = ["last", "every"])]
        time: Option<f64>,
        /// Run: the last frame (the default).
        #[arg(long, conflicts_with = "every")]
        last: bool,
        /// Run: every K-th frame (and the last) as DIR/frame_NNNN.png, and all of them as
        /// the animation DIR/frames.gif (one view and one colour range).
        #[arg(long, value_name = "K")]
        every: Option<usize>,
        /// Run: the field the blocks are coloured by: u, ux, uy, sxx, syy or sxy.
        #[arg(long, default_value = "u")]
        field: String,
        /// Model: draw the cover's manifold elements too.
        #[arg(long)]
        mesh: bool,
        /// Width of the picture in pixels.
        #[arg(long, default_value_t = 1200)]
        width: u32,
    },
}

fn main() -> ExitCode {
    // Rust ignores SIGPIPE, so that printing into a pipe its reader closed (`nmm check
    // MODEL | head`) panics; the default action ends the program quietly instead, as any
    // Unix tool does (a run's outputs are files, written and flushed as it goes).
    #[cfg(unix)]
    // SAFETY: setting a signal's disposition to its default before any thread starts
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run {
            model,
            out,
            friction,
            no_vtk,
            quiet,
            checkpoint_every,
            from,
            threads,
        } => run(
            &model,
            &out,
            friction.as_deref(),
            !no_vtk,
            quiet,
            checkpoint_every.unwrap_or(0),
            from.as_deref(),
            threads,
        ),
        Command::Resume {
            dir,
            quiet,
            threads,
        } => resume(&dir, quiet, threads),
        Command::Check { model, json, quiet } => check(&model, json, quiet),
        Command::Verify { out, full } => verify(&out, full),
        Command::Figures { out } => figures(&out),
        Command::Plot {
            target,
            out,
            frame,
            time,
            last: _,
            every,
            field,
            mesh,
            width,
        } => plot(&target, &out, (frame, time, every), &field, mesh, width),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", one_line(&format!("{e:#}")));
            ExitCode::FAILURE
        }
    }
}

/// Errors are reported on one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The cutting of the model's blocks by its joints, in one line (None without joints).
fn cutting_line(m: &nmm::model::Model) -> Option<String> {
    if m.joints.is_empty() {
        return None;
    }
    let sets = m
        .joints
        .iter()
        .filter(|j| matches!(j.kind, nmm::model::JointKind::Set { .. }))
        .count();
    let pieces = m.blocks.iter().filter(|b| b.parent.is_some()).count();
    let parents = nmm::check::cut_blocks(m);
    let mut line = format!(
        "cutting: {} joint set(s) and {} joint(s) cut {} block(s) into {pieces} pieces; {} crack(s)",
        sets,
        m.joints.len() - sets,
        parents.len(),
        m.cracks.len()
    );
    if !m.enclosed.is_empty() {
        line.push_str(&format!(
            "; {} region(s) enclosed by a loop of traces that reaches no block boundary kept inside their block (the loops are cracks)",
            m.enclosed.len()
        ));
    }
    if let Some(a) = m.min_block_area {
        line.push_str(&format!(
            "; {} piece(s) smaller than min_block_area = {a} m² merged into their neighbours",
            m.merged.len()
        ));
        if !m.kept_small.is_empty() {
            line.push_str(&format!(
                ", {} kept (no merge that bridges no joint)",
                m.kept_small.len()
            ));
        }
    }
    Some(line)
}

fn check(path: &Path, json: bool, quiet: bool) -> anyhow::Result<ExitCode> {
    let model = nmm::model::load_model(path)?;
    let sim = nmm::simulation::Simulation::new(model)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    if !quiet {
        for w in sim.warnings() {
            eprintln!("warning: {w}");
        }
    }
    if json {
        let v = nmm::check::check_json(&sim, &path.display().to_string());
        println!("{v}");
        return Ok(ExitCode::SUCCESS);
    }
    let m = &sim.model;
    let areas: Vec<f64> = m.blocks.iter().map(|b| b.area()).collect();
    let total: f64 = areas.iter().sum();
    let (smallest, smallest_at) = nmm::check::smallest(&areas);
    let fixed = m.blocks.iter().filter(|b| b.fixed).count();
    println!("model: {}", path.display());
    println!("blocks: {} ({} fixed)", m.blocks.len(), fixed);
    println!("physical covers: {}", sim.disc.covers.len());
    println!("manifold elements: {}", sim.disc.elements.len());
    println!("unknowns: {}", sim.n_dofs());
    println!("cracks: {}", m.cracks.len());
    for c in nmm::check::crack_list(m) {
        let pts = |v: &[[f64; 2]]| {
            v.iter()
                .map(|p| format!("[{}, {}]", p[0], p[1]))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut line = format!(
            "  crack of joint \"{}\" in block \"{}\": length {:.6} m",
            c.joint, c.block, c.length
        );
        if !c.tips.is_empty() {
            line.push_str(&format!(", tip(s) {}", pts(&c.tips)));
        }
        if !c.mouths.is_empty() {
            line.push_str(&format!(", on the block's boundary at {}", pts(&c.mouths)));
        }
        if c.tips.is_empty() && c.mouths.is_empty() {
            line.push_str(", closed");
        }
        println!("{line}");
    }
    println!(
        "block area: total {total} m², smallest {smallest} m² (block \"{}\")",
        m.blocks[smallest_at].name
    );
    if let Some(line) = cutting_line(m) {
        println!("{line}");
        for g in &m.merged {
            println!(
                "  merged a piece of {} m² at [{}, {}] into block \"{}\"{}",
                g.area,
                g.centroid[0],
                g.centroid[1],
                m.blocks[g.block].name,
                g.bridges.map_or(String::new(), |j| format!(
                    " (bridging joint \"{}\")",
                    m.joints[j].name
                ))
            );
        }
        for g in &m.kept_small {
            println!(
                "  kept block \"{}\" ({} m² at [{}, {}]): smaller than min_block_area, but every merge would bridge a joint",
                m.blocks[g.block].name, g.area, g.centroid[0], g.centroid[1]
            );
        }
    }
    for line in nmm::check::record_lines(m) {
        println!("{line}");
    }
    for line in nmm::check::interface_law_lines(m) {
        println!("{line}");
    }
    for line in nmm::check::insitu_and_bolt_lines(m) {
        println!("{line}");
    }
    if m.stages.is_empty() {
        println!(
            "analysis: {:?}, dt = {} s, {} steps, friction {:?}",
            m.analysis.mode, m.analysis.dt, m.analysis.steps, m.analysis.friction
        );
    }
    for st in &m.stages {
        let a = &st.analysis;
        println!(
            "stage \"{}\": {:?}, dt = {} s, {} steps, friction {:?}{}{}",
            st.name,
            a.mode,
            a.dt,
            a.steps,
            a.friction,
            if st.base_motion { ", base motion" } else { "" },
            nmm::check::excavation_suffix(m, st)
        );
    }
    let mut covers = vec![0usize; m.blocks.len()];
    for c in &sim.disc.covers {
        covers[c.block] += 1;
    }
    for (i, b) in m.blocks.iter().enumerate() {
        println!(
            "  block \"{}\": {} covers, {} elements{}{}",
            b.name,
            covers[i],
            sim.disc.block_elements[i].len(),
            match b.holes.len() {
                0 => String::new(),
                1 => ", 1 hole".to_string(),
                n => format!(", {n} holes"),
            },
            if b.fixed { ", fixed" } else { "" }
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The `--friction` value.
fn friction_override(f: Option<&str>) -> anyhow::Result<Option<nmm::model::LawId>> {
    use nmm::model::LawId;
    Ok(match f {
        None => None,
        Some(name) => match LawId::for_analysis(name) {
            Some(law) => Some(law),
            None => {
                let names: Vec<String> = LawId::analysis_names()
                    .iter()
                    .map(|n| format!("\"{n}\""))
                    .collect();
                anyhow::bail!(
                    "--friction: expected {}, got \"{name}\"",
                    names.join(" or ")
                )
            }
        },
    })
}

/// Loads a model with the `--friction` override applied to `[analysis]` and every stage.
fn load(path: &Path, friction: Option<nmm::model::LawId>) -> anyhow::Result<nmm::model::Model> {
    Ok(nmm::simulation::with_friction(
        nmm::model::load_model(path)?,
        friction,
    ))
}

#[allow(clippy::too_many_arguments)]
fn run(
    path: &Path,
    out: &Path,
    friction: Option<&str>,
    vtk: bool,
    quiet: bool,
    checkpoint_every: usize,
    from: Option<&Path>,
    threads: Option<usize>,
) -> anyhow::Result<ExitCode> {
    let friction = friction_override(friction)?;
    let model = load(path, friction)?;
    let start = match from {
        None => nmm::simulation::Start::Fresh,
        Some(c) => nmm::simulation::branch_start(&model, &path.display().to_string(), c)
            .map_err(anyhow::Error::msg)?,
    };
    let opts = nmm::simulation::RunOptions {
        interrupt: None,
        vtk,
        model_path: Some(path.to_path_buf()),
        checkpoint_every,
        friction,
        start,
        threads,
    };
    execute(model, path, out, opts, quiet)
}

fn resume(dir: &Path, quiet: bool, threads: Option<usize>) -> anyhow::Result<ExitCode> {
    let (model, path, mut opts) = nmm::simulation::resume_start(dir).map_err(anyhow::Error::msg)?;
    if let nmm::simulation::Start::Resume(ckpt) = &opts.start {
        if !quiet {
            eprintln!(
                "resuming {} from step {} (t = {} s)",
                dir.display(),
                ckpt.step,
                ckpt.time
            );
        }
    }
    opts.threads = threads;
    execute(model, &path, dir, opts, quiet)
}

/// Runs `model` with `opts` (a Ctrl-C handler added), printing the bar and the summary.
fn execute(
    model: nmm::model::Model,
    path: &Path,
    out: &Path,
    mut opts: nmm::simulation::RunOptions,
    quiet: bool,
) -> anyhow::Result<ExitCode> {
    if let Some(line) = cutting_line(&model) {
        eprintln!("{line}");
    }
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        // A second Ctrl-C while stopping falls back to the default (immediate exit).
        let _ = ctrlc::set_handler(move || {
            if stop.swap(true, Ordering::SeqCst) {
                std::process::exit(130);
            }
        });
    }
    opts.interrupt = Some(stop);
    let total = if model.stages.is_empty() {
        model.analysis.steps
    } else {
        model.stages.iter().map(|s| s.analysis.steps).sum()
    };
    let mut bar = progress::Progress::new(total, true).quiet(quiet);
    let summary = nmm::simulation::run_observed(model, out, &opts, &mut bar)
        .with_context(|| format!("{}", path.display()))?;
    let t = summary.timings;
    let its = &summary.iterations;
    let mut sorted = its.clone();
    sorted.sort_unstable();
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0);
    eprintln!(
        "{} steps to t = {} s, {} unknowns; Newton iterations median {median}, max {}; {} step(s) cut",
        summary.steps,
        summary.time,
        summary.n_dofs,
        sorted.last().copied().unwrap_or(0),
        summary.cut_steps.len()
    );
    let l = &summary.linear;
    eprintln!(
        "linear solves {} (GMRES iterations {}), factorisations {}: Cholesky {}, unsymmetric LU {} ({} symbolic), sparse LU {}; contact branch changes {}",
        l.solves, l.gmres_iterations, l.factorisations, l.factorisations - l.unsymmetric_factorisations,
        l.unsymmetric_factorisations, l.symbolic_analyses, l.lu_factorisations,
        summary.active_set_changes
    );
    eprintln!(
        "time: cover {:.3} s, assembly {:.3} s, contact {:.3} s, factorisation {:.3} s, solve {:.3} s",
        t.cover.as_secs_f64(),
        t.stages.assembly.as_secs_f64(),
        t.stages.contact.as_secs_f64(),
        t.stages.factorisation.as_secs_f64(),
        t.stages.solve.as_secs_f64()
    );
    for line in [summary.cut_line(), summary.equilibrium_line()]
        .into_iter()
        .flatten()
    {
        eprintln!("{line}");
    }
    if summary.interrupted {
        eprintln!(
            "interrupted at step {}: outputs so far are in {}; continue with `nmm resume {}`",
            summary.steps,
            out.display(),
            out.display()
        );
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

/// `nmm plot`: a model as cut, or frames of a run.
fn plot(
    target: &Path,
    out: &Path,
    (frame, time, every): (Option<usize>, Option<f64>, Option<usize>),
    field: &str,
    mesh: bool,
    width: u32,
) -> anyhow::Result<ExitCode> {
    use nmm::output::plot::{plot_scene, scene_view, union_view, GifAnimation};
    use nmm::picture::{frame_scene, frame_scene_in, model_scene, run_frames, Field};
    if !target.is_dir() {
        if frame.is_some() || time.is_some() || every.is_some() {
            anyhow::bail!(
                "{}: --frame, --time and --every draw a run's frames: give a run's output folder",
                target.display()
            );
        }
        let model = nmm::model::load_model(target)?;
        let pieces = model.blocks.len();
        let title = format!("{}: {pieces} blocks as cut", target.display());
        let scene = if mesh {
            let sim = nmm::simulation::Simulation::new(model)
                .map_err(|e| anyhow::anyhow!("{}: {e}", target.display()))?;
            model_scene(&sim.model, Some(&sim.disc), &title)
        } else {
            model_scene(&model, None, &title)
        };
        plot_scene(out, &scene, width)?;
        println!("{}", out.display());
        return Ok(ExitCode::SUCCESS);
    }
    if mesh {
        anyhow::bail!("--mesh draws a model's cover: give a model file");
    }
    let field = Field::parse(field).map_err(anyhow::Error::msg)?;
    let frames = run_frames(target).map_err(anyhow::Error::msg)?;
    if let Some(k) = every {
        if k == 0 {
            anyhow::bail!("--every: must be at least 1");
        }
        std::fs::create_dir_all(out).with_context(|| format!("{}", out.display()))?;
        let mut indices: Vec<usize> = (0..frames.len()).step_by(k).collect();
        if indices.last() != Some(&(frames.len() - 1)) {
            indices.push(frames.len() - 1);
        }
        // the PNGs, each in its own view and colour range, as a single frame is drawn;
        // their union view and range for the GIF
        let mut view = None;
        let mut range = (f64::INFINITY, f64::NEG_INFINITY);
        for &i in &indices {
            let (scene, own) =
                frame_scene_in(target, i, field, None).map_err(anyhow::Error::msg)?;
            let file = out.join(format!("frame_{i:04}.png"));
            plot_scene(&file, &scene, width)?;
            println!("{}", file.display());
            let v = scene_view(&scene);
            view = Some(view.map_or(v.clone(), |u| union_view(&u, &v)));
            range = (range.0.min(own.0), range.1.max(own.1));
        }
        // the animation: the same frames in one view and one colour range
        let gif = out.join("frames.gif");
        let view = view.expect("at least the last frame");
        let mut animation = None;
        for &i in &indices {
            let (scene, _) =
                frame_scene_in(target, i, field, Some(range)).map_err(anyhow::Error::msg)?;
            if animation.is_none() {
                animation = Some(GifAnimation::create(&gif, &scene, width, view.clone(), 20)?);
            }
            animation.as_mut().expect("created above").add(&scene)?;
        }
        animation.expect("at least one frame").finish()?;
        println!("{}", gif.display());
        return Ok(ExitCode::SUCCESS);
    }
    let index = match (frame, time) {
        (Some(n), _) => n,
        (None, Some(t)) => frames
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 .0 - t).abs().total_cmp(&(b.1 .0 - t).abs()))
            .map_or(0, |(i, _)| i),
        (None, None) => frames.len() - 1,
    };
    let scene = frame_scene(target, index, field).map_err(anyhow::Error::msg)?;
    plot_scene(out, &scene, width)?;
    println!("{}", out.display());
    Ok(ExitCode::SUCCESS)
}

fn verify(out: &Path, full: bool) -> anyhow::Result<ExitCode> {
    use nmm::verify::report::{markdown, run, Size};
    std::fs::create_dir_all(out).with_context(|| format!("{}", out.display()))?;
    let size = if full { Size::Full } else { Size::Quick };
    let t = std::time::Instant::now();
    let cases = run(size, out);
    let md = markdown(&cases, size, out);
    let path = out.join("report.md");
    std::fs::write(&path, md).with_context(|| format!("{}", path.display()))?;
    for c in &cases {
        eprintln!("{:<34} {}", c.name, if c.pass() { "pass" } else { "FAIL" });
    }
    let failed = cases.iter().filter(|c| !c.pass()).count();
    eprintln!(
        "{} passed, {failed} failed ({:.1} s); report: {}",
        cases.len() - failed,
        t.elapsed().as_secs_f64(),
        path.display()
    );
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn figures(out: &Path) -> anyhow::Result<ExitCode> {
    use nmm::verify::cases::{direct_shear, shaken_slope, RAMPED_5HZ};
    use nmm::verify::report::{figure_direct_shear, figure_shaking_table};
    std::fs::create_dir_all(out).with_context(|| format!("{}", out.display()))?;
    let strength = 1.0e6 * 30f64.to_radians().tan();
    let rm = direct_shear(1.0e6, 30.0, "return-mapping").map_err(anyhow::Error::msg)?;
    let conv = direct_shear(1.0e6, 30.0, "conventional").map_err(anyhow::Error::msg)?;
    let mut files = figure_direct_shear(&out.join("figure4_direct_shear"), &rm, &conv, strength)
        .map_err(anyhow::Error::msg)?;
    let rm = shaken_slope(30.0, &RAMPED_5HZ, "return-mapping").map_err(anyhow::Error::msg)?;
    let conv = shaken_slope(30.0, &RAMPED_5HZ, "conventional").map_err(anyhow::Error::msg)?;
    files.extend(
        figure_shaking_table(
            &out.join("figure6_shaking_table"),
            &rm,
            &conv,
            "Shaking-table slope, θ = 30°",
        )
        .map_err(anyhow::Error::msg)?,
    );
    // The jointed slope example, as cut by its joints.
    let slope = nmm::model::parse_model(
        include_str!("../examples/jointed_slope.toml"),
        Path::new("examples"),
    )?;
    let pieces = slope.blocks.iter().filter(|b| b.parent.is_some()).count();
    files.extend(
        nmm::verify::report::figure_blocks(
            &out.join("jointed_slope"),
            &slope,
            &format!(
                "examples/jointed_slope.toml: the slope cut into {pieces} blocks, {} cracks (red)",
                slope.cracks.len()
            ),
        )
        .map_err(anyhow::Error::msg)?,
    );
    for f in files {
        println!("{}", f.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// `--threads N`: an integer ≥ 1.
fn parse_threads(v: &str) -> Result<usize, String> {
    nmm::parallel::parse_threads(v)
}
