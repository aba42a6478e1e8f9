//! What `nmm check` reports about a validated, discretised model, as one JSON object
//! (`nmm check --json`; the Python package's `nmm.check` returns the same keys).

use crate::simulation::Simulation;
use serde_json::{json, Value};

/// The summary of `nmm check --json`: `model` (the source named by `model`), `blocks`,
/// `fixed_blocks`, `cut_blocks`, `joints`, `cracks`, `merged_pieces`, `enclosed_pieces`,
/// `physical_covers`, `manifold_elements`, `unknowns`, `block_area_total`,
/// `smallest_block_area`, `smallest_block`, `stages` (the `[[stage]]` names), then
/// `base_motion` (null without one: else one object per record, see [`record_json`]),
/// then `crack_list` (one object per crack: `joint`, `block`, `length`, `tips`, `mouths`:
/// [`crack_list`]), in that order.
pub fn check_json(sim: &Simulation, model: &str) -> Value {
    let m = &sim.model;
    let areas: Vec<f64> = m.blocks.iter().map(|b| b.area()).collect();
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
        "base_motion": m.base_motion.as_ref().map(|b| b.records.iter().map(record_json).collect::<Vec<_>>()),
        "crack_list": crack_list(m).iter().map(|c| json!({
            "joint": c.joint,
            "block": c.block,
            "length": c.length,
            "tips": c.tips,
            "mouths": c.mouths,
        })).collect::<Vec<_>>(),
    })
}

/// One crack as `nmm check` lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackInfo {
    /// The joint's name.
    pub joint: String,
    /// The block's name.
    pub block: String,
    /// Length of the polyline (m).
    pub length: f64,
    /// Its ends inside the block (the tips).
    pub tips: Vec<[f64; 2]>,
    /// Its ends on the block's boundary (an edge crack's mouth, or where it meets a joint
    /// face).
    pub mouths: Vec<[f64; 2]>,
}

/// The model's cracks (block, joint, length, tips), in the model's order.
pub fn crack_list(m: &crate::model::Model) -> Vec<CrackInfo> {
    m.cracks
        .iter()
        .map(|c| {
            let b = &m.blocks[c.block];
            let size = crate::geometry::Aabb::of_points(&b.vertices).diagonal();
            let tol = 1e-9 * size;
            let n = c.points.len();
            let closed = n > 2 && c.points[0] == c.points[n - 1];
            let (mut tips, mut mouths) = (Vec::new(), Vec::new());
            if !closed {
                for p in [c.points[0], c.points[n - 1]] {
                    match b.region().locate(p, tol) {
                        crate::geometry::polygon::Location::Inside => tips.push(p),
                        _ => mouths.push(p),
                    }
                }
            }
            CrackInfo {
                joint: m.joints[c.joint].name.clone(),
                block: b.name.clone(),
                length: c
                    .points
                    .windows(2)
                    .map(|w| crate::geometry::dist(w[0], w[1]))
                    .sum(),
                tips,
                mouths,
            }
        })
        .collect()
}

/// One base-motion record as read and as applied: `axis` ("x", "y" or "x, y"),
/// `source` (the file as written, or "table"), `samples`, `dt` (smallest interval, s),
/// `dt_max`, `record_start` and `record_end` (times of its first and last sample, s),
/// `pga_read_g` (peak |a| as read, g, per axis [x, y]), `start` and `duration` (the window
/// used, s), `scale` (the factor applied), `pga_applied_g` (peak |a| as applied, g, per
/// axis). g = 9.80665 m/s².
pub fn record_json(r: &crate::model::RecordInfo) -> Value {
    let g = crate::motion::G;
    json!({
        "axis": r.axis,
        "source": r.source,
        "samples": r.samples,
        "dt": r.dt.0,
        "dt_max": r.dt.1,
        "record_start": r.span.0,
        "record_end": r.span.1,
        "pga_read_g": [r.pga_read[0] / g, r.pga_read[1] / g],
        "start": r.start,
        "duration": r.duration,
        "scale": r.scale,
        "pga_applied_g": [r.pga_applied[0] / g, r.pga_applied[1] / g],
    })
}

/// One line per base-motion record for `nmm check`: dt, duration, PGA as read and as
/// applied.
pub fn record_lines(m: &crate::model::Model) -> Vec<String> {
    let Some(b) = &m.base_motion else {
        return Vec::new();
    };
    let g = crate::motion::G;
    b.records
        .iter()
        .map(|r| {
            let axes: Vec<usize> = match r.axis.as_str() {
                "x" => vec![0],
                "y" => vec![1],
                _ => vec![0, 1],
            };
            let pga = |p: [f64; 2]| {
                axes.iter()
                    .map(|&k| {
                        format!(
                            "{}{:.4} g ({:.4} m/s²)",
                            if axes.len() > 1 { ["x ", "y "][k] } else { "" },
                            p[k] / g,
                            p[k]
                        )
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            let dt = if r.dt.1 - r.dt.0 <= 1e-6 * r.dt.1 {
                format!("dt = {} s", sig(r.dt.0))
            } else {
                format!("dt = {} … {} s", sig(r.dt.0), sig(r.dt.1))
            };
            format!(
                "base motion {}: {}: {} samples, {dt}, {} s long ({} … {} s); PGA as read {}; used {} … {} s ({} s, its t = 0 at {} s) × {} → PGA as applied {}",
                r.axis,
                r.source,
                r.samples,
                sig(r.span.1 - r.span.0),
                sig(r.span.0),
                sig(r.span.1),
                pga(r.pga_read),
                sig(r.start),
                sig(r.start + r.duration),
                sig(r.duration),
                sig(r.start),
                sig(r.scale),
                pga(r.pga_applied)
            )
        })
        .collect()
}

/// `x` to 9 significant digits, shortest form (`0.005`, not `0.004999999999999893`).
fn sig(x: f64) -> String {
    format!("{:.8e}", x)
        .parse::<f64>()
        .map_or_else(|_| x.to_string(), |v| v.to_string())
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

/// One line per `[[interface]]` that selects a law of its own (the registry's name and its
/// keys' values, defaults included) for `nmm check`, e.g.
/// `interface #2: law "bonded" (tensile_strength = 50000, residual_friction_angle = 30)`.
pub fn interface_law_lines(m: &crate::model::Model) -> Vec<String> {
    m.interfaces
        .iter()
        .enumerate()
        .filter_map(|(k, i)| {
            let l = i.law.as_ref()?;
            let values: Vec<String> = l
                .law
                .keys()
                .iter()
                .zip(&l.values)
                .map(|(key, v)| format!("{key} = {v}"))
                .collect();
            Some(format!(
                "interface #{}: law {:?} ({})",
                k + 1,
                l.law.name(),
                values.join(", ")
            ))
        })
        .collect()
}

/// The in-situ stress and the bolts for `nmm check`: `initial stress: [σxx, σyy, τxy] Pa at
/// y = y_ref, gradient [..] Pa/m` (nothing without `[initial_stress]`), then one line per
/// `[[bolt]]` with its anchors' blocks, stiffness, capacity, pretension and installation.
pub fn insitu_and_bolt_lines(m: &crate::model::Model) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(s) = &m.initial_stress {
        out.push(format!(
            "initial stress: {:?} Pa at y = {} m, gradient {:?} Pa/m (tension positive)",
            s.stress, s.y_ref, s.gradient
        ));
    }
    for b in &m.bolts {
        let when = match b.stage {
            Some(k) => format!("installed at the start of stage {:?}", m.stages[k].name),
            None => "installed from the start".to_string(),
        };
        out.push(format!(
            "bolt {:?}: [{}, {}] in block {:?} to [{}, {}] in block {:?}, stiffness {} N/m, capacity {} N, pretension {} N, {when}",
            b.name,
            b.points[0][0],
            b.points[0][1],
            m.blocks[b.blocks[0]].name,
            b.points[1][0],
            b.points[1][1],
            m.blocks[b.blocks[1]].name,
            b.stiffness,
            b.capacity,
            b.pretension
        ));
    }
    out
}

/// `, excavates "a", "b"` for a stage that excavates blocks (empty otherwise).
pub fn excavation_suffix(m: &crate::model::Model, stage: &crate::model::Stage) -> String {
    if stage.excavate.is_empty() {
        return String::new();
    }
    let names: Vec<String> = stage
        .excavate
        .iter()
        .map(|&b| format!("{:?}", m.blocks[b].name))
        .collect();
    format!(", excavates {}", names.join(", "))
}
