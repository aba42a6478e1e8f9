//! The run driver: steps the simulation, writes its outputs through the writers
//! (`writers.rs`), its checkpoints and its summary.
//!
//! `DIR/history.csv` (a row per step, columns per the model contract),
//! `DIR/blocks.csv` (the block table: `id,name,material,fixed`, `id` the 0-based index used
//! in the VTK `block` arrays), `DIR/blocks.pvd` over `DIR/vtk/blocks_NNNNNN.vtu` (deformed
//! manifold elements, with displacement and velocity per vertex, stress and block id per
//! element, the block names as field data) and `DIR/contacts.pvd` over
//! `DIR/vtk/contacts_NNNNNN.vtu` (contact points with their normal, forces and state; a
//! step without contacts is a valid piece of zero points and zero cells). Frames at step 0,
//! every `output_every` steps and at the last step. Every row is flushed before an error or
//! an interrupt is reported, so a run that stops midway keeps all it wrote; `DIR/summary.json`
//! ([`RunSummary::to_json`]) is written at the end of every run, finished, interrupted or
//! failed. The files and fields are documented in `docs/outputs.md`.

use super::checkpoint::{Checkpoint, SavedOptions, SavedOutputs};
use super::writers::{
    history_columns, monitor_values, write_block_table, Frames, HISTORY_COUNTS, STAGE_COLUMN,
};
use super::{Simulation, StepError, Timings};
use crate::contact::friction::ContactStatus;
use crate::model::Model;
use crate::output::history::HistoryWriter;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// What a caller sees of a run while it goes (the command line draws a progress bar).
/// Every method has an empty default.
pub trait RunObserver: Send {
    /// The run starts at `step` (0 unless resumed) of `total_steps`.
    fn start(&mut self, _step: usize, _total_steps: usize) {}
    /// A step was completed: `step` steps done, simulated time `time`.
    fn step_done(&mut self, _step: usize, _time: f64) {}
    /// The run's counters so far, after each step: linear solves (every Newton iteration,
    /// failed attempts included), Δt cuts and contact active-set changes.
    fn counts(&mut self, _solves: usize, _cuts: usize, _active_set_changes: usize) {}
    /// The run's linear-solver counters so far, after each step (factorisations, symbolic
    /// analyses, GMRES iterations: why a run is slow).
    fn linear(&mut self, _stats: &crate::solver::LinearStats) {}
    /// One line of information.
    fn message(&mut self, _line: &str) {}
    /// A warning about the model ([`Simulation::warnings`]), one line, before the first step.
    fn warning(&mut self, _line: &str) {}
    /// The run ended: finished, interrupted or failed. (Not called when the model could not
    /// be discretised: that run never started.)
    fn finish(&mut self, _status: RunStatus) {}
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RunStatus {
    /// Every step done.
    #[default]
    Finished,
    /// Stopped cleanly by [`RunOptions::interrupt`].
    Interrupted,
    /// Stopped by an error (a step that did not converge, an output that could not be written).
    Failed,
}

impl RunStatus {
    /// `"finished"`, `"interrupted"` or `"failed"` (as in summary.json).
    pub fn as_str(self) -> &'static str {
        match self {
            RunStatus::Finished => "finished",
            RunStatus::Interrupted => "interrupted",
            RunStatus::Failed => "failed",
        }
    }
}

/// An observer that ignores everything.
pub struct Silent;
impl RunObserver for Silent {}

#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Set to true (e.g. by a Ctrl-C handler) to stop cleanly after the current step.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Write VTK frames (default true through [`RunOptions::new`]).
    pub vtk: bool,
    /// The model file, for summary.json (`"model": null` without it) and checkpoints.
    pub model_path: Option<PathBuf>,
    /// Also write a checkpoint every N steps (0: only at the end of each stage and when
    /// interrupted). Checkpoints are written only with a `model_path`.
    pub checkpoint_every: usize,
    /// The `--friction` override the model was loaded with (recorded in checkpoints).
    pub friction: Option<crate::model::LawId>,
    /// Where the run starts: afresh, resuming its own checkpoint, or branching from a
    /// checkpoint of another run.
    pub start: Start,
    /// Threads to compute on (None: `NMM_THREADS`, else the cores the process may use;
    /// see [`crate::parallel`]: the results do not depend on it).
    pub threads: Option<usize>,
}

/// Where a run starts.
#[derive(Debug, Clone, Default)]
pub enum Start {
    /// From the model's initial state, with new outputs.
    #[default]
    Fresh,
    /// From the run's own checkpoint, continuing its outputs (history.csv is cut back to
    /// the checkpoint's step and continued).
    Resume(Box<Checkpoint>),
    /// From another run's checkpoint (`--from`): new outputs, whose rows start after the
    /// checkpoint's step.
    Branch(Box<Checkpoint>),
}

impl RunOptions {
    pub fn new() -> Self {
        RunOptions {
            vtk: true,
            ..Default::default()
        }
    }
}

/// What a run did: the figures of summary.json ([`RunSummary::to_json`]).
#[derive(Debug, Clone, Default)]
pub struct RunSummary {
    /// Completed steps (a cut step counts once per completed part).
    pub steps: usize,
    /// Simulated time at the end (s).
    pub time: f64,
    /// Newton iterations (linear solves) of the accepted attempt of every step.
    pub iterations: Vec<usize>,
    /// Linear solves of every step, failed attempts included.
    pub solves: Vec<usize>,
    /// Contact branch changes over the Newton iterations, summed over the steps.
    pub active_set_changes: usize,
    /// Static mode: steps that did not end in equilibrium.
    pub not_in_equilibrium: usize,
    /// Steps done in static mode (all the run's, a resumed run's included).
    pub static_steps: usize,
    /// A resumed run: the wall-clock time of the run before its checkpoint, and the cover
    /// time it had then.
    pub prior_total: Duration,
    pub prior_cover: Duration,
    /// Whether the last step ended in equilibrium.
    pub last_equilibrium: bool,
    /// The analysis is static.
    pub static_mode: bool,
    /// Linear solver work over the run.
    pub linear: crate::solver::LinearStats,
    /// Steps whose Δt had to be cut, with the number of cuts.
    pub cut_steps: Vec<(usize, usize)>,
    pub interrupted: bool,
    /// How the run ended.
    pub status: RunStatus,
    /// The error that stopped a failed run, one line.
    pub error: Option<String>,
    pub timings: Timings,
    /// Time spent writing history.csv, blocks.csv and the VTK frames.
    pub output_time: Duration,
    /// Wall-clock time of the whole run, cover generation included.
    pub total_time: Duration,
    pub n_blocks: usize,
    pub n_dofs: usize,
    /// Threads the run computed on.
    pub threads: usize,
    pub n_elements: usize,
    pub n_covers: usize,
    /// Closed (stick or slide) contacts at the end of every step.
    pub contacts: Vec<usize>,
    /// Energy balance: `None` (null) until the solver reports it.
    pub energy: Option<Value>,
    /// Equilibrium check at the end: `None` (null) until the solver reports it.
    pub equilibrium: Option<Value>,
    /// The model's warnings ([`Simulation::warnings`]).
    pub warnings: Vec<String>,
    /// With `[[stage]]`: the stage of the last step (`None` without stages).
    pub stage: Option<String>,
    /// A model with bonded interfaces: the contacts' bonds at the end, (intact, broken)
    /// ([`crate::contact::set::ContactSet::bond_counts`]); `None` otherwise (no key).
    pub bonds: Option<(usize, usize)>,
    /// Peak resident memory of the process (Linux: VmHWM), `None` elsewhere.
    pub peak_memory_bytes: Option<u64>,
    pub model_path: Option<PathBuf>,
    pub out_dir: PathBuf,
}

impl RunSummary {
    /// One line on the Δt cuts of the run, if any: how many steps, which (the first ten),
    /// how many cuts.
    pub fn cut_line(&self) -> Option<String> {
        if self.cut_steps.is_empty() {
            return None;
        }
        let cuts: usize = self.cut_steps.iter().map(|c| c.1).sum();
        let mut which: Vec<String> = self
            .cut_steps
            .iter()
            .take(10)
            .map(|c| c.0.to_string())
            .collect();
        if self.cut_steps.len() > 10 {
            which.push("…".into());
        }
        Some(format!(
            "Δt was cut {cuts} time(s) in {} step(s) to converge ({:.2}% of the steps): step {}",
            self.cut_steps.len(),
            100.0 * self.cut_steps.len() as f64 / self.steps.max(1) as f64,
            which.join(", ")
        ))
    }

    /// Static mode: one line if some steps ended without equilibrium (a mechanism: each
    /// such step's motion was limited and the mechanism developed step by step).
    pub fn equilibrium_line(&self) -> Option<String> {
        if !self.static_mode || self.not_in_equilibrium == 0 {
            return None;
        }
        Some(format!(
            "not in equilibrium: {} of {} static step(s) found no equilibrium (a mechanism; the motion of each was limited), {}",
            self.not_in_equilibrium,
            self.static_steps,
            if self.last_equilibrium {
                "the last step did"
            } else {
                "nor did the last step: the model is not at rest"
            }
        ))
    }

    /// summary.json: every key is documented in `docs/outputs.md`; times in s.
    pub fn to_json(&self) -> Value {
        let mut v = self.json_core();
        if let Some((intact, broken)) = self.bonds {
            v["bonds"] = json!({ "intact": intact, "broken": broken });
        }
        v
    }

    fn json_core(&self) -> Value {
        let mut sorted = self.solves.clone();
        sorted.sort_unstable();
        let total: usize = sorted.iter().sum();
        let mean = |v: &[usize]| {
            if v.is_empty() {
                0.0
            } else {
                v.iter().sum::<usize>() as f64 / v.len() as f64
            }
        };
        let t = &self.timings;
        let s = |d: Duration| d.as_secs_f64();
        json!({
            "nmm_version": env!("CARGO_PKG_VERSION"),
            "model": self.model_path.as_ref().map(|p| p.display().to_string()),
            "status": self.status.as_str(),
            "error": self.error,
            "steps": self.steps,
            "time": self.time,
            "blocks": self.n_blocks,
            "unknowns": self.n_dofs,
            "physical_covers": self.n_covers,
            "manifold_elements": self.n_elements,
            "threads": self.threads,
            "iterations": {
                "total": total,
                "median": sorted.get(sorted.len() / 2).copied().unwrap_or(0),
                "max": sorted.last().copied().unwrap_or(0),
                "mean": mean(&sorted),
            },
            "cuts": {
                "total": self.cut_steps.iter().map(|c| c.1).sum::<usize>(),
                "steps_cut": self.cut_steps.len(),
            },
            "active_set_changes": self.active_set_changes,
            "linear": {
                "solves": self.linear.solves,
                "gmres_iterations": self.linear.gmres_iterations,
                "cholesky_factorisations": self.linear.factorisations
                    - self.linear.unsymmetric_factorisations,
                "unsymmetric_lu_factorisations": self.linear.unsymmetric_factorisations,
                "symbolic_analyses": self.linear.symbolic_analyses,
                "lu_factorisations": self.linear.lu_factorisations,
            },
            "contacts": {
                "max": self.contacts.iter().copied().max().unwrap_or(0),
                "mean": mean(&self.contacts),
            },
            "timings": {
                "cover": s(t.cover),
                "assembly": s(t.stages.assembly),
                "contact": s(t.stages.contact),
                "factorisation": s(t.stages.factorisation),
                "solve": s(t.stages.solve),
                "output": s(self.output_time),
                "total": s(self.total_time),
            },
            "peak_memory_bytes": self.peak_memory_bytes,
            "energy": self.energy,
            "equilibrium": self.equilibrium.clone().or_else(|| {
                self.static_mode.then(|| {
                    json!({
                        "steps_not_in_equilibrium": self.not_in_equilibrium,
                        "last_step_in_equilibrium": self.last_equilibrium,
                    })
                })
            }),
            "warnings": self.warnings,
            "stage": self.stage,
        })
    }

    /// Writes [`Self::to_json`] (pretty-printed, with a final line break) to `path`.
    pub fn write_json(&self, path: &Path) -> std::io::Result<()> {
        let mut text =
            serde_json::to_string_pretty(&self.to_json()).map_err(std::io::Error::other)?;
        text.push('\n');
        std::fs::write(path, text)
    }
}

/// Peak resident set size of this process: `VmHWM` of `/proc/self/status` (Linux), in bytes.
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("{0}")]
    Setup(String),
    #[error("{0}")]
    Io(String),
    #[error("{error} (outputs up to step {completed} are kept in {dir})")]
    Step {
        error: StepError,
        completed: usize,
        dir: String,
    },
}

pub(super) fn io(path: &Path, e: std::io::Error) -> RunError {
    RunError::Io(format!("{}: {e}", path.display()))
}

/// The model with a `--friction` override applied to `[analysis]` and every stage.
pub fn with_friction(mut model: Model, friction: Option<crate::model::LawId>) -> Model {
    if let Some(f) = friction {
        model.analysis.friction = f;
        for s in model.stages.iter_mut() {
            s.analysis.friction = f;
        }
    }
    model
}

/// What resuming the run in `dir` needs (`nmm resume DIR`, `nmm.resume` in Python): the
/// model read again from the file the run was made from (with the run's `--friction`
/// override) and the options of the run, starting from its latest checkpoint. A run
/// without a checkpoint, a checkpoint that cannot be read, or a model file changed since:
/// one line naming the file.
pub fn resume_start(dir: &Path) -> Result<(Model, PathBuf, RunOptions), String> {
    let Some(c) = latest_checkpoint(dir) else {
        return Err(format!(
            "{}: no checkpoint to resume from (checkpoints/ is written at the end of each stage, on Ctrl-C and with --checkpoint-every)",
            dir.display()
        ));
    };
    let ckpt = Checkpoint::read(&c)?;
    let path = PathBuf::from(&ckpt.model_path);
    let model = crate::model::load_model(&path)
        .map_err(|e| format!("{}: the run's model: {e}", c.display()))?;
    let model = with_friction(model, ckpt.options.friction);
    if !ckpt.is_of_model(&model) {
        return Err(format!(
            "{}: a checkpoint of another model: {} is not the model it was written from (start a changed model from it with `nmm run MODEL --from {}`)",
            c.display(),
            path.display(),
            c.display()
        ));
    }
    let opts = RunOptions {
        interrupt: None,
        vtk: ckpt.options.vtk,
        model_path: Some(path.clone()),
        checkpoint_every: ckpt.options.checkpoint_every,
        friction: ckpt.options.friction,
        start: Start::Resume(Box::new(ckpt)),
        threads: None,
    };
    Ok((model, path, opts))
}

/// A branch start from the checkpoint file `checkpoint` of another run (`nmm run MODEL
/// --from CKPT`, `nmm.run(..., start_from=CKPT)`): refused, in one line naming `source`
/// (the model's file) and the checkpoint, when the model differs from the saved run in what
/// defines its state.
pub fn branch_start(model: &Model, source: &str, checkpoint: &Path) -> Result<Start, String> {
    let ckpt = Checkpoint::read(checkpoint)?;
    let diff = ckpt.differences(model);
    if !diff.is_empty() {
        return Err(format!(
            "{source}: cannot start from {}: the model differs in {} (a branch keeps the saved run's blocks, joints, cover, materials, initial stress, installed bolts and stages up to the checkpoint)",
            checkpoint.display(),
            diff.join(", ")
        ));
    }
    Ok(Start::Branch(Box::new(ckpt)))
}

/// Run a validated model, writing its outputs into `out`.
pub fn run(model: Model, out: &Path, opts: &RunOptions) -> Result<RunSummary, RunError> {
    run_observed(model, out, opts, &mut Silent)
}

/// As [`run`], reporting progress to `observer`. A model that cannot be discretised still
/// leaves a summary.json (status "failed") in `out`.
pub fn run_observed(
    model: Model,
    out: &Path,
    opts: &RunOptions,
    observer: &mut dyn RunObserver,
) -> Result<RunSummary, RunError> {
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    let start = Instant::now();
    let n_blocks = model.blocks.len();
    let made = Simulation::new(model).and_then(|mut sim| match &opts.start {
        Start::Fresh => Ok(sim),
        Start::Resume(c) | Start::Branch(c) => sim.restore(c).map(|_| sim),
    });
    let threads = match opts.threads {
        Some(0) => Err("threads: expected an integer ≥ 1, got 0".to_string()),
        Some(n) => Ok(n),
        None => crate::parallel::default_threads(),
    }
    .and_then(crate::parallel::Threads::new);
    let made = made.and_then(|mut sim| {
        sim.set_threads(threads?);
        Ok(sim)
    });
    let mut sim = match made {
        Ok(sim) => sim,
        Err(e) => {
            let summary = RunSummary {
                status: RunStatus::Failed,
                error: Some(one_line(&e)),
                n_blocks,
                total_time: start.elapsed(),
                peak_memory_bytes: peak_memory_bytes(),
                model_path: opts.model_path.clone(),
                out_dir: out.to_path_buf(),
                ..Default::default()
            };
            let _ = summary.write_json(&out.join("summary.json"));
            return Err(RunError::Setup(e));
        }
    };
    // the whole run on the pool: its thread runs the steps and the pool's others join
    // its parallel loops (no thread of ours waits while another spins)
    let threads = sim.threads.clone();
    threads.install(|| run_simulation(&mut sim, out, opts, observer))
}

/// Step an existing simulation to its end time, writing outputs, then summary.json
/// (also when the run is interrupted or fails: the error returned is the run's, a failure
/// to write the summary is then ignored).
pub fn run_simulation(
    sim: &mut Simulation,
    out: &Path,
    opts: &RunOptions,
    progress: &mut dyn RunObserver,
) -> Result<RunSummary, RunError> {
    let start = Instant::now();
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    let mut summary = RunSummary {
        n_blocks: sim.model.blocks.len(),
        static_mode: sim.model.analysis.mode == crate::model::Mode::Static,
        n_dofs: sim.n_dofs(),
        threads: sim.threads(),
        n_elements: sim.disc.elements.len(),
        n_covers: sim.disc.covers.len(),
        warnings: sim.warnings(),
        model_path: opts.model_path.clone(),
        out_dir: out.to_path_buf(),
        ..Default::default()
    };
    for w in &summary.warnings {
        progress.warning(w);
    }
    let result = step_to_end(sim, out, opts, progress, &mut summary);
    summary.bonds = crate::contact::set::uses_bonds(&sim.model).then(|| sim.contacts.bond_counts());
    let e = sim.energy;
    summary.energy = Some(json!({
        "kinetic": e.kinetic,
        "elastic": e.elastic,
        "gravity_potential": e.gravity,
        "contact_springs": e.contact,
        "penalty_springs": e.penalty,
        "bolt_springs": e.bolts,
        "total": e.total(),
        "external_work": e.external_work,
        "initial_total": e.initial,
        "max_rise": e.max_rise(),
        "max_rise_relative": if e.scale > 0.0 { e.max_rise() / e.scale } else { 0.0 },
        "constraint_work": e.constraint_work,
        "friction_dissipation": e.friction,
        "damping_dissipation": e.damping,
        "algorithmic_dissipation": e.algorithmic,
        "static_reset": e.static_reset,
        "contact_update": e.contact_update,
        "excavated": e.excavated,
        "bolt_plastic_dissipation": e.bolt_plastic,
        "dissipated": e.dissipated(),
        "balance_error": e.balance_error(),
        "balance_error_relative": e.balance_error_relative(),
    }));
    summary.steps = sim.step;
    summary.time = sim.output_time();
    summary.stage = sim.stage_name().map(str::to_string);
    summary.timings = sim.timings;
    summary.status = match &result {
        Err(_) => RunStatus::Failed,
        Ok(()) if summary.interrupted => RunStatus::Interrupted,
        Ok(()) => RunStatus::Finished,
    };
    summary.error = result.as_ref().err().map(|e| one_line(&e.to_string()));
    // a resumed run: the time before its checkpoint, then this process's cover and steps
    summary.total_time = summary.prior_total
        + sim.timings.cover.saturating_sub(summary.prior_cover)
        + start.elapsed();
    summary.static_mode |= summary.static_steps > 0;
    summary.peak_memory_bytes = peak_memory_bytes();
    progress.finish(summary.status);
    let path = out.join("summary.json");
    let written = summary.write_json(&path);
    result?;
    written.map_err(|e| io(&path, e))?;
    Ok(summary)
}

/// The stepping loop of [`run_simulation`]: history rows, frames, the block table,
/// checkpoints.
fn step_to_end(
    sim: &mut Simulation,
    out: &Path,
    opts: &RunOptions,
    progress: &mut dyn RunObserver,
    summary: &mut RunSummary,
) -> Result<(), RunError> {
    let t_run = Instant::now();
    let t_out = t_run;
    write_block_table(&sim.model, &out.join("blocks.csv"))?;
    let hist_path = out.join("history.csv");
    let columns = history_columns(&sim.model);
    let staged = !sim.model.stages.is_empty();
    let stage_column = staged.then_some(STAGE_COLUMN);
    let resumed = match &opts.start {
        Start::Resume(c) => Some(c.as_ref()),
        _ => None,
    };
    let mut hist = match resumed {
        Some(c) => HistoryWriter::append_after(
            &hist_path,
            &columns,
            staged,
            HISTORY_COUNTS.len(),
            c.outputs.history_len,
        )
        .map_err(|e| io(&hist_path, e))?,
        None => {
            HistoryWriter::create_with_counts(&hist_path, &columns, stage_column, &HISTORY_COUNTS)
                .map_err(|e| io(&hist_path, e))?
        }
    };
    let mut last_written = sim.step;
    let mut frames = match (opts.vtk, resumed) {
        (false, _) => None,
        (true, Some(c)) => {
            last_written = c.outputs.last_frame;
            Some(Frames::with(
                out,
                (
                    c.outputs.blocks_frames.clone(),
                    c.outputs.blocks_names.clone(),
                ),
                (
                    c.outputs.contacts_frames.clone(),
                    c.outputs.contacts_names.clone(),
                ),
                !sim.bolts.is_empty(),
            )?)
        }
        (true, None) => {
            let mut f = Frames::new(out, !sim.bolts.is_empty())?;
            f.write(sim)?;
            Some(f)
        }
    };
    if let Some(c) = resumed {
        let o = &c.outputs;
        summary.iterations = o.iterations.clone();
        summary.solves = o.solves.clone();
        summary.contacts = o.contacts.clone();
        summary.cut_steps = o.cut_steps.clone();
        summary.active_set_changes = o.active_set_changes;
        summary.not_in_equilibrium = o.not_in_equilibrium;
        summary.last_equilibrium = o.last_equilibrium;
        summary.static_steps = o.static_steps;
        summary.prior_total = o.total;
        summary.prior_cover = o.timings[0];
        let l = o.linear;
        summary.linear.solves = l[0];
        summary.linear.gmres_iterations = l[1];
        summary.linear.factorisations = l[2];
        summary.linear.symbolic_analyses = l[3];
        summary.linear.lu_factorisations = l[4];
        summary.linear.unsymmetric_factorisations = l[5];
        let t = o.timings;
        sim.timings.cover += t[0];
        sim.timings.stages.assembly += t[1];
        sim.timings.stages.contact += t[2];
        sim.timings.stages.factorisation += t[3];
        sim.timings.stages.solve += t[4];
        summary.output_time += t[5];
    }
    summary.output_time += t_out.elapsed();
    let mut checkpoints = Checkpoints::new(out, opts);
    progress.start(sim.full_steps_done(), sim.total_steps());
    // running totals for the progress line (a resumed run starts from its checkpoint's)
    let mut solves_total: usize = summary.solves.iter().sum();
    let mut cuts_total: usize = summary.cut_steps.iter().map(|c| c.1).sum();
    while !sim.finished() {
        let rep = match sim.advance() {
            Ok(r) => r,
            Err(error) => {
                hist.flush().map_err(|e| io(&hist_path, e))?;
                if let Some(f) = frames.as_mut() {
                    if last_written != sim.step {
                        f.write(sim)?;
                    }
                }
                return Err(RunError::Step {
                    error,
                    completed: sim.step,
                    dir: out.display().to_string(),
                });
            }
        };
        if rep.cuts > 0 {
            // one line for all of them at the end (RunSummary::cut_line), not one per cut
            summary.cut_steps.push((sim.step, rep.cuts));
            cuts_total += rep.cuts;
        }
        summary.iterations.push(rep.iterations);
        summary.solves.push(rep.solves);
        solves_total += rep.solves;
        summary.active_set_changes += rep.active_set_changes;
        summary.not_in_equilibrium += usize::from(!rep.equilibrium);
        summary.last_equilibrium = rep.equilibrium;
        summary.static_steps += usize::from(sim.model.analysis.mode == crate::model::Mode::Static);
        summary.linear += rep.linear;
        summary.contacts.push(
            sim.contacts
                .contacts
                .iter()
                .filter(|c| c.response.status != ContactStatus::Open)
                .count(),
        );
        let t_out = Instant::now();
        hist.write_row_counts(
            sim.step,
            sim.output_time(),
            &monitor_values(sim),
            rep.iterations,
            sim.stage_name(),
            &[rep.solves, rep.cuts],
        )
        .map_err(|e| io(&hist_path, e))?;
        let interrupted = opts
            .interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::SeqCst));
        let every = sim.model.analysis.output_every.max(1);
        let stage_end = sim.stage_finished();
        if let Some(f) = frames.as_mut() {
            if sim.step % every == 0 || stage_end || interrupted {
                f.write(sim)?;
                last_written = sim.step;
            }
        }
        let periodic =
            opts.checkpoint_every > 0 && (sim.step % opts.checkpoint_every == 0 || sim.finished());
        // without stages, no checkpoint at the end unless asked for (outputs as before)
        if (stage_end && staged) || interrupted || periodic {
            let history_len = hist.position().map_err(|e| io(&hist_path, e))?;
            let saved = SavedOutputs {
                history_len,
                blocks_frames: frames
                    .as_ref()
                    .map(|f| f.blocks.frames().to_vec())
                    .unwrap_or_default(),
                contacts_frames: frames
                    .as_ref()
                    .map(|f| f.contacts.frames().to_vec())
                    .unwrap_or_default(),
                blocks_names: frames
                    .as_ref()
                    .map(|f| f.blocks.frame_names().to_vec())
                    .unwrap_or_default(),
                contacts_names: frames
                    .as_ref()
                    .map(|f| f.contacts.frame_names().to_vec())
                    .unwrap_or_default(),
                last_frame: last_written,
                iterations: summary.iterations.clone(),
                solves: summary.solves.clone(),
                contacts: summary.contacts.clone(),
                cut_steps: summary.cut_steps.clone(),
                active_set_changes: summary.active_set_changes,
                not_in_equilibrium: summary.not_in_equilibrium,
                last_equilibrium: summary.last_equilibrium,
                static_steps: summary.static_steps,
                total: summary.prior_total
                    + sim.timings.cover.saturating_sub(summary.prior_cover)
                    + t_run.elapsed(),
                linear: [
                    summary.linear.solves,
                    summary.linear.gmres_iterations,
                    summary.linear.factorisations,
                    summary.linear.symbolic_analyses,
                    summary.linear.lu_factorisations,
                    summary.linear.unsymmetric_factorisations,
                ],
                timings: [
                    sim.timings.cover,
                    sim.timings.stages.assembly,
                    sim.timings.stages.contact,
                    sim.timings.stages.factorisation,
                    sim.timings.stages.solve,
                    summary.output_time + t_out.elapsed(),
                ],
            };
            checkpoints.write(sim, &saved, stage_end)?;
        }
        summary.output_time += t_out.elapsed();
        progress.step_done(sim.full_steps_done(), sim.output_time());
        progress.counts(solves_total, cuts_total, summary.active_set_changes);
        progress.linear(&summary.linear);
        if interrupted {
            summary.interrupted = true;
            break;
        }
    }
    hist.flush().map_err(|e| io(&hist_path, e))
}

/// Where a run's checkpoints go: `DIR/checkpoints/step_NNNNNNNN.ckpt`. Those at the end of
/// a stage are kept (the branch points of parameter studies); a periodic or interrupt
/// checkpoint replaces the previous periodic one.
struct Checkpoints {
    dir: PathBuf,
    model_path: Option<String>,
    options: SavedOptions,
    /// The last checkpoint that was not at the end of a stage.
    last_periodic: Option<PathBuf>,
}

impl Checkpoints {
    fn new(out: &Path, opts: &RunOptions) -> Checkpoints {
        Checkpoints {
            dir: out.join("checkpoints"),
            model_path: opts.model_path.as_ref().map(|p| {
                std::path::absolute(p)
                    .unwrap_or_else(|_| p.clone())
                    .display()
                    .to_string()
            }),
            options: SavedOptions {
                friction: opts.friction,
                vtk: opts.vtk,
                checkpoint_every: opts.checkpoint_every,
            },
            last_periodic: None,
        }
    }

    fn write(
        &mut self,
        sim: &Simulation,
        outputs: &SavedOutputs,
        stage_end: bool,
    ) -> Result<(), RunError> {
        let Some(model) = &self.model_path else {
            return Ok(());
        };
        std::fs::create_dir_all(&self.dir).map_err(|e| io(&self.dir, e))?;
        let path = self.dir.join(checkpoint_name(sim.step));
        sim.write_checkpoint(&path, model, &self.options, outputs)
            .map_err(|e| io(&path, e))?;
        if let Some(old) = self.last_periodic.take() {
            if old != path {
                let _ = std::fs::remove_file(old);
            }
        }
        if !stage_end {
            self.last_periodic = Some(path);
        }
        Ok(())
    }
}

/// `step_NNNNNNNN.ckpt`: the checkpoint after `step` completed steps.
pub fn checkpoint_name(step: usize) -> String {
    format!("step_{step:08}.ckpt")
}

/// The latest checkpoint of a run folder (the one after the most steps), if any.
pub fn latest_checkpoint(out: &Path) -> Option<PathBuf> {
    let dir = out.join("checkpoints");
    std::fs::read_dir(&dir)
        .ok()?
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let step: usize = name
                .strip_prefix("step_")?
                .strip_suffix(".ckpt")?
                .parse()
                .ok()?;
            Some((step, e.path()))
        })
        .max_by_key(|(s, _)| *s)
        .map(|(_, p)| p)
}

/// Any line breaks of a message as spaces.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}
