//! The writers of a run's outputs: the history row of the monitors, the block table and
//! the VTK frames of the blocks and the contacts (`docs/outputs.md` documents the fields).

use super::run::{io, RunError};
use super::Simulation;
use crate::material::out_of_plane_stress;
use crate::model::{Model, MonitorKind};
use crate::output::vtk::{write_vtu, Cell, DataArray, FieldStrings, Grid, PvdWriter};
use std::path::{Path, PathBuf};

/// The integer columns history.csv ends with (after `iterations` and, with stages,
/// `stage`): each step's linear solves, its failed attempts' included (the figures of
/// summary.json's `iterations`), and how many times Δt was halved before it converged.
pub const HISTORY_COUNTS: [&str; 2] = ["solves", "cuts"];

/// The text column history.csv has after `iterations` when the model has stages.
pub const STAGE_COLUMN: &str = "stage";

/// history.csv's header as a run of `model` writes it: `step,time`, the monitors'
/// columns ([`history_columns`]), `iterations`, `stage` (with stages), [`HISTORY_COUNTS`].
pub fn history_header(model: &Model) -> Vec<String> {
    let mut cols = vec!["step".to_string(), "time".to_string()];
    cols.extend(history_columns(model));
    cols.push("iterations".into());
    if !model.stages.is_empty() {
        cols.push(STAGE_COLUMN.into());
    }
    cols.extend(HISTORY_COUNTS.iter().map(|c| c.to_string()));
    cols
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
            MonitorKind::Tip { .. } => &["KI", "KII"],
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
            (
                &MonitorKind::Tip {
                    block,
                    tip,
                    dir,
                    radii,
                    ..
                },
                _,
            ) => vals.extend_from_slice(&sim.stress_intensity(block, tip, dir, radii)),
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
        if sim.is_excavated(e.block) {
            continue; // gone from the stage that excavated it on
        }
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
    let mut bond = vec![];
    for c in sim.contacts.snapshots() {
        bond.push(c.bond.map_or(-1, i32::from));
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
    // a model with bonded interfaces: 1 bonded, 0 broken, −1 no bond
    if crate::contact::set::uses_bonds(&sim.model) {
        g.cell_data.push(DataArray::int32("bond", bond));
    }
    g
}

pub(super) struct Frames {
    dir: PathBuf,
    pub(super) blocks: PvdWriter,
    pub(super) contacts: PvdWriter,
    /// A model with bolts: their frames, with the blocks'.
    bolts: Option<PvdWriter>,
}

impl Frames {
    pub(super) fn new(out: &Path, bolts: bool) -> Result<Frames, RunError> {
        Frames::with(out, Default::default(), Default::default(), bolts)
    }
    /// The collections with the frames written so far (a resumed run).
    pub(super) fn with(
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
    pub(super) fn write(&mut self, sim: &Simulation) -> Result<(), RunError> {
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
                sim.output_time(),
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
                sim.output_time(),
                &format!("vtk/{name}"),
                sim.stage_name().unwrap_or(""),
            )
            .map_err(|e| io(&path, e))?;
        }
        Ok(())
    }
}
