//! The bolts' VTK frames (`DIR/bolts.pvd` over `DIR/vtk/bolts_NNNNNN.vtu`, documented in
//! docs/outputs.md): one line cell per `[[bolt]]`, written with every blocks frame of a
//! model that has bolts, so that the two collections list the same frames.

use super::Simulation;
use crate::output::vtk::{Cell, DataArray, FieldStrings, Grid};

/// The bolts as a VTK grid: a line cell per bolt (in file order) between its anchors'
/// current positions, with its committed force and elongation. A bolt not yet installed
/// is drawn too, with `installed` 0 and no force.
pub fn bolts_grid(sim: &Simulation) -> Grid {
    let mut g = Grid::default();
    let (mut force, mut elongation, mut plastic) = (vec![], vec![], vec![]);
    let (mut installed, mut yielded, mut id) = (vec![], vec![], vec![]);
    for (i, b) in sim.bolts.bolts.iter().enumerate() {
        let [a, c] = b.positions(&sim.disc, &sim.u);
        g.cells.push(Cell::line(g.points.len(), g.points.len() + 1));
        g.points.extend_from_slice(&[a, c]);
        force.push(b.force);
        elongation.push(b.elongation);
        plastic.push(if b.installed {
            b.plastic - b.params.installed_plastic(b.pretension)
        } else {
            0.0
        });
        installed.push(i32::from(b.installed));
        yielded.push(i32::from(b.yielded));
        id.push(i as i32);
    }
    g.cell_data.push(DataArray::scalars("force", force));
    g.cell_data
        .push(DataArray::scalars("elongation", elongation));
    g.cell_data
        .push(DataArray::scalars("plastic_elongation", plastic));
    g.cell_data.push(DataArray::int32("installed", installed));
    g.cell_data.push(DataArray::int32("yielded", yielded));
    g.cell_data.push(DataArray::int32("bolt", id));
    g.field_data.push(FieldStrings::new(
        "bolt_names",
        sim.model.bolts.iter().map(|b| b.name.clone()).collect(),
    ));
    g
}

/// The bolts' frames of a resumed run: those of the blocks (written at the same steps),
/// renamed.
pub(super) fn frames_of_blocks(blocks: &[(f64, String)]) -> Vec<(f64, String)> {
    blocks
        .iter()
        .map(|(t, f)| (*t, f.replacen("vtk/blocks_", "vtk/bolts_", 1)))
        .collect()
}
