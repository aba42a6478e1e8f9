//! What `nmm check` reports about a validated, discretised model, as one JSON object
//! (`nmm check --json`; the Python package's `nmm.check` returns the same keys).

use crate::simulation::Simulation;
use serde_json::{json, Value};

/// The summary of `nmm check --json`: `model` (the source named by `model`), `blocks`,
/// `fixed_blocks`, `cut_blocks`, `joints`, `cracks`, `merged_pieces`, `enclosed_pieces`,
/// `physical_covers`, `manifold_elements`, `unknowns`, `block_area_total`,
/// `smallest_block_area`, `smallest_block`, `stages` (the `[[stage]]` names), in that order.
pub fn check_json(sim: &Simulation, model: &str) -> Value {
    let m = &sim.model;
    let areas: Vec<f64> = m
        .blocks
        .iter()
        .map(|b| crate::geometry::polygon::signed_area(&b.vertices))
        .collect();
    let total: f64 = areas.iter().sum();
    let (smallest, smallest_at) = smallest(&areas);
    json!({
        "model": model,
        "blocks": m.blocks.len(),
        "fixed_blocks": m.blocks.iter().filter(|b| b.fixed).count(),
        "cut_blocks": cut_blocks(m).len(),
        "joints": m.joints.len(),
        "cracks": m.cracks.len(),
        "merged_pieces": m.merged.len(),
        "enclosed_pieces": m.enclosed.len(),
        "physical_covers": sim.disc.covers.len(),
        "manifold_elements": sim.disc.elements.len(),
        "unknowns": sim.n_dofs(),
        "block_area_total": total,
        "smallest_block_area": smallest,
        "smallest_block": m.blocks.get(smallest_at).map(|b| b.name.as_str()),
        "stages": m.stages.iter().map(|st| st.name.as_str()).collect::<Vec<_>>(),
    })
}

/// The smallest of `areas` and its index (∞ and 0 when empty).
pub fn smallest(areas: &[f64]) -> (f64, usize) {
    areas.iter().enumerate().fold(
        (f64::INFINITY, 0),
        |acc, (i, &a)| if a < acc.0 { (a, i) } else { acc },
    )
}

/// The names of the blocks the joints cut (each once, in block order).
pub fn cut_blocks(m: &crate::model::Model) -> Vec<&str> {
    let mut parents: Vec<&str> = m
        .blocks
        .iter()
        .filter_map(|b| b.parent.as_deref())
        .collect();
    parents.dedup();
    parents
}
