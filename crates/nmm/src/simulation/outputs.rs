//! The run driver: steps the simulation and writes its outputs.
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
use super::{Simulation, StepError, Timings};
use crate::contact::friction::ContactStatus;
use crate::material::out_of_plane_stress;
use crate::model::{Model, MonitorKind};
use crate::output::history::HistoryWriter;
use crate::output::vtk::{write_vtu, Cell, DataArray, FieldStrings, Grid, PvdWriter};
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
    pub friction: Option<crate::model::FrictionAlgorithm>,
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
                "cholesky_factorisations": self.linear.factorisations,
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

fn io(path: &Path, e: std::io::Error) -> RunError {
    RunError::Io(format!("{}: {e}", path.display()))
}

/// History columns after `step,time` and before `iterations`.
pub fn history_columns(model: &Model) -> Vec<String> {
    let mut cols = Vec::new();
    for m in &model.monitors {
        let names: &[&str] = match m.kind {
            MonitorKind::Point { .. } => &["ux", "uy", "vx", "vy"],
            MonitorKind::Interface { .. } => &["fx", "fy", "fn", "nc"],
            MonitorKind::Block { .. } => &["x", "y", "rotation"],
            MonitorKind::Bolt { .. } => &["force", "elongation"],
        };
        cols.extend(names.iter().map(|c| format!("{}.{}", m.name, c)));
    }
    cols
}

/// The monitor values of the current state, in column order.
pub fn monitor_values(sim: &Simulation) -> Vec<f64> {
    let mut vals = Vec::new();
    for (m, mp) in sim.model.monitors.iter().zip(&sim.monitor_points) {
        match (&m.kind, mp) {
            (MonitorKind::Point { .. }, Some(p)) => {
                let u = sim.displacement_at(p);
                let v = sim.velocity_at(p);
                vals.extend_from_slice(&[u[0], u[1], v[0], v[1]]);
            }
            (MonitorKind::Interface { first, second }, _) => {
                let f = sim.contacts.interface_force_between(first, second);
                vals.extend_from_slice(&[f.fx, f.fy, f.fn_sum, f.count as f64]);
            }
            (MonitorKind::Block { blocks }, _) => {
                vals.extend_from_slice(&block_motion(sim, blocks))
            }
            (MonitorKind::Bolt { bolt }, _) => {
                let b = &sim.bolts.bolts[*bolt];
                vals.extend_from_slice(&[b.force, b.elongation]);
            }
            _ => vals.extend_from_slice(&[f64::NAN; 4]),
        }
    }
    vals
}

/// The displacement of the centroid of `blocks` (together) and their mean rotation: the
/// area-weighted means over their manifold elements (in the current geometry) of the
/// displacement and of each element's rotation θ = atan2(∂uy/∂x − ∂ux/∂y, 2 − ∂ux/∂x −
/// ∂uy/∂y) (rad, counter-clockwise; the rotation of the element's deformation, exact for a
/// rigid rotation of any size, ½(∂uy/∂x − ∂ux/∂y) when small).
pub fn block_motion(sim: &Simulation, blocks: &[usize]) -> [f64; 3] {
    let (mut a, mut ux, mut uy, mut rot) = (0.0, 0.0, 0.0, 0.0);
    let basis = sim.disc.basis;
    for &b in blocks {
        for &ei in &sim.disc.block_elements[b] {
            let e = &sim.disc.elements[ei];
            let area = crate::geometry::polygon::signed_area(&e.polygon);
            if area.is_nan() || area <= 0.0 {
                continue;
            }
            let c = crate::geometry::moments::polygon_moments(&e.polygon, e.polygon[0]).centroid();
            let dofs = sim.elem_dofs.of(ei);
            let mut ue = [0.0; crate::cover::basis::MAX_ELEMENT_DOFS];
            let ue = &mut ue[..dofs.len()];
            crate::assembly::global::gather_into(&sim.u, dofs, ue);
            let w = e.weights(c);
            let u = basis.interpolate(e, &w, ue);
            ux += area * u[0];
            uy += area * u[1];
            // ∂u_i/∂x_j
            let d = basis.displacement_gradient(e, &w, ue);
            rot += area * (d[1][0] - d[0][1]).atan2(2.0 - d[0][0] - d[1][1]);
            a += area;
        }
    }
    if a > 0.0 {
        [ux / a, uy / a, rot / a]
    } else {
        [f64::NAN; 3]
    }
}

/// The deformed manifold elements as a VTK grid.
pub fn blocks_grid(sim: &Simulation) -> Grid {
    let mut g = Grid::default();
    let (mut disp, mut vel) = (Vec::new(), Vec::new());
    let (mut block, mut stress, mut cell_u) = (Vec::new(), Vec::new(), Vec::new());
    let basis = sim.disc.basis;
    let (mut ue, mut ve) = (
        [0.0; crate::cover::basis::MAX_ELEMENT_DOFS],
        [0.0; crate::cover::basis::MAX_ELEMENT_DOFS],
    );
    for (ei, e) in sim.disc.elements.iter().enumerate() {
        let start = g.points.len();
        let dofs = sim.elem_dofs.of(ei);
        let (ue, ve) = (&mut ue[..dofs.len()], &mut ve[..dofs.len()]);
        crate::assembly::global::gather_into(&sim.u, dofs, ue);
        crate::assembly::global::gather_into(&sim.v, dofs, ve);
        let mut c = [0.0; 2];
        for x in &e.polygon {
            let w = e.weights(*x);
            g.points.push(*x);
            let u = basis.interpolate(e, &w, ue);
            disp.extend_from_slice(&u);
            vel.extend_from_slice(&basis.interpolate(e, &w, ve));
            c[0] += u[0] / e.polygon.len() as f64;
            c[1] += u[1] / e.polygon.len() as f64;
        }
        g.cells
            .push(Cell::polygon((start..g.points.len()).collect()));
        block.push(e.block as i32);
        let s = sim.stress[ei];
        let mat = &sim.model.materials[sim.model.blocks[e.block].material];
        stress.extend_from_slice(&[
            s[0],
            s[1],
            s[2],
            out_of_plane_stress(mat.poisson, mat.plane, s),
        ]);
        cell_u.extend_from_slice(&c);
    }
    g.point_data.push(DataArray::vector2("displacement", disp));
    g.point_data.push(DataArray::vector2("velocity", vel));
    g.cell_data.push(DataArray::int32("block", block));
    g.cell_data.push(DataArray::named_components(
        "stress",
        &["sxx", "syy", "txy", "szz"],
        stress,
    ));
    g.cell_data
        .push(DataArray::vector2("mean_displacement", cell_u));
    g.field_data.push(FieldStrings::new(
        "block_names",
        sim.model.blocks.iter().map(|b| b.name.clone()).collect(),
    ));
    g
}

/// `DIR/blocks.csv`: `id,name,material,fixed`, one row per block in file order; `id` is the
/// 0-based index of the VTK `block` arrays.
pub fn write_block_table(model: &Model, path: &Path) -> Result<(), RunError> {
    let e = |e: csv::Error| RunError::Io(format!("{}: {e}", path.display()));
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_path(path)
        .map_err(e)?;
    w.write_record(["id", "name", "material", "fixed"])
        .map_err(e)?;
    for (i, b) in model.blocks.iter().enumerate() {
        w.write_record([
            i.to_string().as_str(),
            &b.name,
            &model.materials[b.material].name,
            if b.fixed { "true" } else { "false" },
        ])
        .map_err(e)?;
    }
    w.flush().map_err(|x| io(path, x))
}

/// The contacts as a VTK grid of vertices; `joint` is the id of the joint that made the
/// edge block's face (`Model::joints` index), −1 for a face of a block as drawn.
pub fn contacts_grid(sim: &Simulation) -> Grid {
    let mut g = Grid::default();
    let (mut normal, mut force, mut tn, mut ts, mut state, mut pair, mut joint) =
        (vec![], vec![], vec![], vec![], vec![], vec![], vec![]);
    for c in sim.contacts.snapshots() {
        g.cells.push(Cell::vertex(g.points.len()));
        g.points.push(c.position);
        normal.extend_from_slice(&c.normal);
        force.extend_from_slice(&c.force_on_first);
        tn.push(c.normal_force);
        ts.push(c.shear_force);
        state.push(c.state as i32);
        pair.extend_from_slice(&[c.first as f64, c.second as f64]);
        joint.push(c.joint.map_or(-1, |j| j as i32));
    }
    g.cell_data.push(DataArray::vector2("normal", normal));
    g.cell_data
        .push(DataArray::vector2("force_on_vertex_block", force));
    g.cell_data.push(DataArray::scalars("normal_force", tn));
    g.cell_data.push(DataArray::scalars("shear_force", ts));
    g.cell_data.push(DataArray::int32("state", state));
    g.cell_data.push(DataArray::named_components(
        "blocks",
        &["vertex_block", "edge_block"],
        pair,
    ));
    g.cell_data.push(DataArray::int32("joint", joint));
    g
}

struct Frames {
    dir: PathBuf,
    blocks: PvdWriter,
    contacts: PvdWriter,
    /// A model with bolts: their frames, with the blocks'.
    bolts: Option<PvdWriter>,
}

impl Frames {
    fn new(out: &Path, bolts: bool) -> Result<Frames, RunError> {
        Frames::with(out, Default::default(), Default::default(), bolts)
    }
    /// The collections with the frames written so far (a resumed run).
    fn with(
        out: &Path,
        blocks: (Vec<(f64, String)>, Vec<String>),
        contacts: (Vec<(f64, String)>, Vec<String>),
        bolts: bool,
    ) -> Result<Frames, RunError> {
        let dir = out.join("vtk");
        std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
        let b = out.join("blocks.pvd");
        let c = out.join("contacts.pvd");
        let bolts = match bolts {
            false => None,
            true => {
                let p = out.join("bolts.pvd");
                let frames = super::bolt_frames::frames_of_blocks(&blocks.0);
                Some(PvdWriter::with_frames(&p, frames, blocks.1.clone()).map_err(|e| io(&p, e))?)
            }
        };
        Ok(Frames {
            bolts,
            blocks: PvdWriter::with_frames(&b, blocks.0, blocks.1).map_err(|e| io(&b, e))?,
            contacts: PvdWriter::with_frames(&c, contacts.0, contacts.1).map_err(|e| io(&c, e))?,
            dir,
        })
    }
    /// Frames of the current state; a contact frame only if there is a contact (a grid
    /// without cells is valid VTK, but meshio cannot read it).
    fn write(&mut self, sim: &Simulation) -> Result<(), RunError> {
        for (series, grid) in [
            ("blocks", blocks_grid(sim)),
            ("contacts", contacts_grid(sim)),
        ] {
            if grid.cells.is_empty() {
                continue;
            }
            let name = format!("{series}_{:06}.vtu", sim.step);
            let path = self.dir.join(&name);
            write_vtu(&path, &grid).map_err(|e| io(&path, e))?;
            let pvd = if series == "blocks" {
                &mut self.blocks
            } else {
                &mut self.contacts
            };
            pvd.add_named(
                sim.time,
                &format!("vtk/{name}"),
                sim.stage_name().unwrap_or(""),
            )
            .map_err(|e| io(&path, e))?;
        }
        if let Some(pvd) = self.bolts.as_mut() {
            let name = format!("bolts_{:06}.vtu", sim.step);
            let path = self.dir.join(&name);
            write_vtu(&path, &super::bolts_grid(sim)).map_err(|e| io(&path, e))?;
            pvd.add_named(
                sim.time,
                &format!("vtk/{name}"),
                sim.stage_name().unwrap_or(""),
            )
            .map_err(|e| io(&path, e))?;
        }
        Ok(())
    }
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
        "bolt_plastic_dissipation": e.bolt_plastic,
        "dissipated": e.dissipated(),
        "balance_error": e.balance_error(),
        "balance_error_relative": e.balance_error_relative(),
    }));
    summary.steps = sim.step;
    summary.time = sim.time;
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
    let stage_column = staged.then_some("stage");
    let resumed = match &opts.start {
        Start::Resume(c) => Some(c.as_ref()),
        _ => None,
    };
    let mut hist = match resumed {
        Some(c) => HistoryWriter::append_after(&hist_path, &columns, staged, c.outputs.history_len)
            .map_err(|e| io(&hist_path, e))?,
        None => HistoryWriter::create_with_text(&hist_path, &columns, stage_column)
            .map_err(|e| io(&hist_path, e))?,
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
        hist.write_row_text(
            sim.step,
            sim.time,
            &monitor_values(sim),
            rep.iterations,
            sim.stage_name(),
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
        progress.step_done(sim.full_steps_done(), sim.time);
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
