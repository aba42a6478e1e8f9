//! The run driver: steps the simulation and writes its outputs.
//!
//! `DIR/history.csv` (a row per step, columns per the model contract),
//! `DIR/blocks.pvd` over `DIR/vtk/blocks_NNNNNN.vtu` (deformed manifold elements, with
//! displacement and velocity per vertex, stress and block id per element) and
//! `DIR/contacts.pvd` over `DIR/vtk/contacts_NNNNNN.vtu` (contact points with their
//! normal, forces and state). Frames at step 0, every `output_every` steps and at
//! the last step. Every row is flushed before an error or an interrupt is reported,
//! so a run that stops midway keeps all it wrote.

use super::{Simulation, StepError, Timings};
use crate::material::out_of_plane_stress;
use crate::model::{Model, MonitorKind};
use crate::output::history::HistoryWriter;
use crate::output::vtk::{write_vtu, Cell, DataArray, Grid, PvdWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// What a caller sees of a run while it goes (the command line draws a progress bar).
/// Every method has an empty default.
pub trait RunObserver {
    /// The run starts at `step` (0 unless resumed) of `total_steps`.
    fn start(&mut self, _step: usize, _total_steps: usize) {}
    /// A step was completed: `step` steps done, simulated time `time`.
    fn step_done(&mut self, _step: usize, _time: f64) {}
    /// One line of information (e.g. a warning or a step cut).
    fn message(&mut self, _line: &str) {}
    /// The run ended (normally, by an interrupt or by an error).
    fn finish(&mut self) {}
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
}

impl RunOptions {
    pub fn new() -> Self {
        RunOptions {
            interrupt: None,
            vtk: true,
        }
    }
}

#[derive(Debug, Clone, Default)]
pub struct RunSummary {
    pub steps: usize,
    pub time: f64,
    /// Newton iterations of every step.
    pub iterations: Vec<usize>,
    /// Steps whose Δt had to be cut, with the number of cuts.
    pub cut_steps: Vec<(usize, usize)>,
    pub interrupted: bool,
    pub timings: Timings,
    pub n_dofs: usize,
    pub n_elements: usize,
    pub n_covers: usize,
    pub out_dir: PathBuf,
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
        let names: [&str; 4] = match m.kind {
            MonitorKind::Point { .. } => ["ux", "uy", "vx", "vy"],
            MonitorKind::Interface { .. } => ["fx", "fy", "fn", "nc"],
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
            _ => vals.extend_from_slice(&[f64::NAN; 4]),
        }
    }
    vals
}

/// The deformed manifold elements as a VTK grid.
pub fn blocks_grid(sim: &Simulation) -> Grid {
    let mut g = Grid::default();
    let (mut disp, mut vel) = (Vec::new(), Vec::new());
    let (mut block, mut stress, mut cell_u) = (Vec::new(), Vec::new(), Vec::new());
    for (ei, e) in sim.disc.elements.iter().enumerate() {
        let start = g.points.len();
        let dofs = &sim.elem_dofs[ei];
        let ue: [f64; 6] = crate::assembly::global::gather(&sim.u, dofs);
        let ve: [f64; 6] = crate::assembly::global::gather(&sim.v, dofs);
        let mut c = [0.0; 2];
        for x in &e.polygon {
            let w = e.weights(*x);
            g.points.push(*x);
            let u = [
                w[0] * ue[0] + w[1] * ue[2] + w[2] * ue[4],
                w[0] * ue[1] + w[1] * ue[3] + w[2] * ue[5],
            ];
            disp.extend_from_slice(&u);
            vel.extend_from_slice(&[
                w[0] * ve[0] + w[1] * ve[2] + w[2] * ve[4],
                w[0] * ve[1] + w[1] * ve[3] + w[2] * ve[5],
            ]);
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
    g
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
}

impl Frames {
    fn new(out: &Path) -> Result<Frames, RunError> {
        let dir = out.join("vtk");
        std::fs::create_dir_all(&dir).map_err(|e| io(&dir, e))?;
        let b = out.join("blocks.pvd");
        let c = out.join("contacts.pvd");
        Ok(Frames {
            blocks: PvdWriter::new(&b).map_err(|e| io(&b, e))?,
            contacts: PvdWriter::new(&c).map_err(|e| io(&c, e))?,
            dir,
        })
    }
    fn write(&mut self, sim: &Simulation) -> Result<(), RunError> {
        for (series, grid) in [
            ("blocks", blocks_grid(sim)),
            ("contacts", contacts_grid(sim)),
        ] {
            let name = format!("{series}_{:06}.vtu", sim.step);
            let path = self.dir.join(&name);
            write_vtu(&path, &grid).map_err(|e| io(&path, e))?;
            let pvd = if series == "blocks" {
                &mut self.blocks
            } else {
                &mut self.contacts
            };
            pvd.add(sim.time, &format!("vtk/{name}"))
                .map_err(|e| io(&path, e))?;
        }
        Ok(())
    }
}

/// Run a validated model, writing its outputs into `out`.
pub fn run(model: Model, out: &Path, opts: &RunOptions) -> Result<RunSummary, RunError> {
    run_observed(model, out, opts, &mut Silent)
}

/// As [`run`], reporting progress to `observer`.
pub fn run_observed(
    model: Model,
    out: &Path,
    opts: &RunOptions,
    observer: &mut dyn RunObserver,
) -> Result<RunSummary, RunError> {
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    let mut sim = Simulation::new(model).map_err(RunError::Setup)?;
    run_simulation(&mut sim, out, opts, observer)
}

/// Step an existing simulation to its end time, writing outputs.
pub fn run_simulation(
    sim: &mut Simulation,
    out: &Path,
    opts: &RunOptions,
    progress: &mut dyn RunObserver,
) -> Result<RunSummary, RunError> {
    std::fs::create_dir_all(out).map_err(|e| io(out, e))?;
    let hist_path = out.join("history.csv");
    let mut hist = HistoryWriter::create(&hist_path, &history_columns(&sim.model))
        .map_err(|e| io(&hist_path, e))?;
    let mut frames = if opts.vtk {
        Some(Frames::new(out)?)
    } else {
        None
    };
    if let Some(f) = frames.as_mut() {
        f.write(sim)?;
    }
    let every = sim.model.analysis.output_every.max(1);
    progress.start(sim.step, sim.model.analysis.steps);
    let mut summary = RunSummary {
        n_dofs: sim.n_dofs(),
        n_elements: sim.disc.elements.len(),
        n_covers: sim.disc.covers.len(),
        out_dir: out.to_path_buf(),
        ..Default::default()
    };
    let mut last_written = sim.step;
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
                progress.finish();
                return Err(RunError::Step {
                    error,
                    completed: sim.step,
                    dir: out.display().to_string(),
                });
            }
        };
        if rep.cuts > 0 {
            summary.cut_steps.push((sim.step, rep.cuts));
            progress.message(&format!(
                "step {}: Δt cut {} time(s) to {:.3e} s to converge",
                sim.step, rep.cuts, rep.dt
            ));
        }
        summary.iterations.push(rep.iterations);
        hist.write_row(sim.step, sim.time, &monitor_values(sim), rep.iterations)
            .map_err(|e| io(&hist_path, e))?;
        let interrupted = opts
            .interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::SeqCst));
        if let Some(f) = frames.as_mut() {
            if sim.step % every == 0 || sim.finished() || interrupted {
                f.write(sim)?;
                last_written = sim.step;
            }
        }
        progress.step_done(sim.step, sim.time);
        if interrupted {
            summary.interrupted = true;
            break;
        }
    }
    hist.flush().map_err(|e| io(&hist_path, e))?;
    progress.finish();
    summary.steps = sim.step;
    summary.time = sim.time;
    summary.timings = sim.timings;
    Ok(summary)
}
