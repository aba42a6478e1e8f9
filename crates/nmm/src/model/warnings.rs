//! Warnings about a valid model that is likely to mislead: one line each, never an error.
//!
//! The command line prints them on stderr before a run (`nmm run`, `nmm check`; `--quiet`
//! hides them) and every run lists them in `summary.json`. Each heuristic and its threshold
//! (documented in `docs/model-format.md`, "Warnings"):
//!
//! * **nothing holds the model**: no block is `fixed` and there is no `[[constraint]]`; the
//!   model is a free body (it falls under gravity, drifts under a base motion).
//! * **lengths in mm**: every block is larger than [`MM_BLOCK_SIZE`] (100 m, the size of a
//!   block being √area) while every material has the density of rock or masonry in SI units
//!   (at least [`SI_ROCK_DENSITY`] = 1000 kg/m³): a drawing in mm read as m. nmm reads m.
//! * **density in another unit**: a density below [`MIN_DENSITY`] (100 kg/m³), far below any
//!   rock or masonry (t/m³, g/cm³ or the t/mm³ of a consistent mm–t–s–MPa system).
//! * **normal penalty**: an interface's `normal_penalty` outside [`PENALTY_RANGE`] = 1–1000 ×
//!   the largest Young's modulus of the model (in models of two or more blocks). Below, the
//!   blocks interpenetrate; above, the system is ill-conditioned and the time step must be
//!   tiny. The shear penalty is often far softer (the paper's slope: p_S = 1e-3 p_N) and is
//!   not checked.
//! * **a law's own warning** about an interface's values (the law's
//!   [`crate::contact::law::FrictionLaw::interface_warning`]): a bonded interface whose
//!   `tensile_strength` is above the apex c / tan φ of its Mohr–Coulomb line.
//! * **cover much finer than the blocks need** ([`cover_warnings`], on the discretisation):
//!   in a model of two or more blocks, more than [`UNKNOWNS_PER_BLOCK`] (2000) unknowns per
//!   free block on average, i.e. more than about 30 mesh cells across a block. For blocks in
//!   contact a few cells across each block usually suffice; a single block (a continuum
//!   analysis) is never warned about.

use super::InterfaceScope;
use super::{Interface, Model};
use crate::geometry::moments::polygon_area;

/// Every block larger than this (√area, m) with rock densities suggests lengths in mm.
pub const MM_BLOCK_SIZE: f64 = 100.0;
/// The least density (kg/m³) counted as rock or masonry in SI units.
pub const SI_ROCK_DENSITY: f64 = 1000.0;
/// A density below this (kg/m³) is in some other unit.
pub const MIN_DENSITY: f64 = 100.0;
/// The usual range of `normal_penalty / E_max` (N/m per Pa).
pub const PENALTY_RANGE: (f64, f64) = (1.0, 1000.0);
/// The average unknowns per free block above which the cover is much finer than needed.
pub const UNKNOWNS_PER_BLOCK: f64 = 2000.0;

/// `x` to 4 significant digits.
fn fmt_short(x: f64) -> String {
    format!("{x:.4e}")
        .parse::<f64>()
        .map_or_else(|_| x.to_string(), |v| v.to_string())
}

/// The warnings that need only the model (see the module doc), in a fixed order.
pub fn warnings(model: &Model) -> Vec<String> {
    let mut out = Vec::new();
    for g in &model.merged {
        if let Some(j) = g.bridges {
            out.push(format!(
                "a piece of {:.4} m² at [{}, {}] was merged into block \"{}\" across joint \"{}\", \
                 which goes on past it as a face of other blocks: the merged block bridges that joint \
                 (check the mechanism, or lower [cover] min_block_area)",
                g.area,
                fmt_short(g.centroid[0]),
                fmt_short(g.centroid[1]),
                model.blocks[g.block].name,
                model.joints.get(j).map_or("?", |j| j.name.as_str())
            ));
        }
    }
    if !model.kept_small.is_empty() {
        let g = &model.kept_small[0];
        out.push(format!(
            "{} piece(s) smaller than [cover] min_block_area kept unmerged, because every merge would \
             bridge a joint that goes on past them (the first: block \"{}\", {:.4} m² at [{}, {}])",
            model.kept_small.len(),
            model.blocks[g.block].name,
            g.area,
            fmt_short(g.centroid[0]),
            fmt_short(g.centroid[1])
        ));
    }
    if !model.blocks.iter().any(|b| b.fixed) && model.constraints.is_empty() {
        out.push(
            "no block is fixed and there is no [[constraint]]: nothing holds the model, \
             which moves as a free body (it falls under gravity)"
                .to_string(),
        );
    }
    let sizes: Vec<f64> = model
        .blocks
        .iter()
        .map(|b| polygon_area(&b.vertices).abs().sqrt())
        .collect();
    let smallest = sizes.iter().copied().fold(f64::INFINITY, f64::min);
    if smallest > MM_BLOCK_SIZE && model.materials.iter().all(|m| m.density >= SI_ROCK_DENSITY) {
        out.push(format!(
            "every block is larger than {MM_BLOCK_SIZE} m (the smallest, \"{}\", is {} m across) \
             with the densities of rock: are the coordinates in mm? nmm reads lengths in m",
            model.blocks[sizes.iter().position(|&s| s == smallest).unwrap_or(0)].name,
            short(smallest)
        ));
    }
    for m in &model.materials {
        if m.density < MIN_DENSITY {
            out.push(format!(
                "[[material]] {:?}: density {} kg/m³ is far below any rock or masonry \
                 (about 1000–3000 kg/m³): nmm reads SI units (kg/m³, Pa, m), not t/m³, g/cm³ \
                 or t/mm³",
                m.name,
                short(m.density)
            ));
        }
    }
    if model.blocks.len() >= 2 {
        let e_max = model.materials.iter().map(|m| m.young).fold(0.0, f64::max);
        for (k, i) in model.interfaces.iter().enumerate() {
            let ratio = i.normal_penalty / e_max;
            if !(PENALTY_RANGE.0..=PENALTY_RANGE.1).contains(&ratio) {
                out.push(format!(
                    "{}: normal_penalty {} N/m is {} × the largest Young's modulus ({} Pa), \
                     outside the usual {}–{} × E ({}): try 10–100 × E",
                    interface_place(model, k, i),
                    short(i.normal_penalty),
                    short(ratio),
                    short(e_max),
                    PENALTY_RANGE.0,
                    PENALTY_RANGE.1,
                    if ratio < PENALTY_RANGE.0 {
                        "softer: the blocks will interpenetrate"
                    } else {
                        "stiffer: an ill-conditioned system that needs a tiny time step"
                    }
                ));
            }
        }
    }
    // loads and constraints on a block that a stage excavates end with it
    for (what, blocks) in [
        (
            "[[load]]",
            model.loads.iter().map(|l| l.block).collect::<Vec<_>>(),
        ),
        (
            "[[constraint]]",
            model
                .constraints
                .iter()
                .map(|c| c.block)
                .collect::<Vec<_>>(),
        ),
    ] {
        let mut seen = Vec::new();
        for b in blocks {
            if seen.contains(&b) {
                continue;
            }
            seen.push(b);
            if let Some(st) = model.stages.iter().find(|s| s.excavate.contains(&b)) {
                out.push(format!(
                    "a {what} acts on block \"{}\", which [[stage]] \"{}\" excavates: it \
                     acts until then and is gone with the block from that stage on",
                    model.blocks[b].name, st.name
                ));
            }
        }
    }
    // a law's own warning about its interface values (e.g. a tensile strength above the
    // apex of the Mohr–Coulomb line)
    for (k, i) in model.interfaces.iter().enumerate() {
        if let Some(l) = &i.law {
            if let Some(w) = l
                .law
                .law()
                .interface_warning(i.friction_angle, i.cohesion, &l.values)
            {
                out.push(format!("{}: {w}", interface_place(model, k, i)));
            }
        }
    }
    out
}

/// The warning about the cover's fineness, given the unknowns of each block (0 for a
/// fixed block) of the model's discretisation.
pub fn cover_warnings(model: &Model, unknowns_per_block: &[usize]) -> Vec<String> {
    let free: Vec<usize> = model
        .blocks
        .iter()
        .zip(unknowns_per_block)
        .filter(|(b, _)| !b.fixed)
        .map(|(_, &n)| n)
        .collect();
    if model.blocks.len() < 2 || free.is_empty() {
        return Vec::new();
    }
    let mean = free.iter().sum::<usize>() as f64 / free.len() as f64;
    if mean <= UNKNOWNS_PER_BLOCK {
        return Vec::new();
    }
    vec![format!(
        "[cover] size {} m gives {} unknowns per free block on average (more than {}, about \
         30 mesh cells across a block): blocks in contact seldom need so fine a cover; a larger \
         size runs much faster",
        short(model.cover_size),
        mean.round(),
        UNKNOWNS_PER_BLOCK
    )]
}

/// `[[interface]] #k (blocks "a", "b")` or `[[interface]] #k (default)`, as in errors.
fn interface_place(model: &Model, k: usize, i: &Interface) -> String {
    let name = |set: &[usize]| {
        set.first()
            .map(|&b| {
                let blk = &model.blocks[b];
                blk.parent.clone().unwrap_or_else(|| blk.name.clone())
            })
            .unwrap_or_default()
    };
    match &i.scope {
        InterfaceScope::Blocks(a, b) => format!(
            "[[interface]] #{} (blocks {:?}, {:?})",
            k + 1,
            name(a),
            name(b)
        ),
        InterfaceScope::Joint(j) => format!(
            "[[interface]] #{} (joint {:?})",
            k + 1,
            model.joints[*j].name
        ),
        InterfaceScope::Default => format!("[[interface]] #{} (default)", k + 1),
    }
}

/// A number in messages: four significant digits, shortest form.
fn short(x: f64) -> String {
    let s = format!("{x:.3e}");
    let v: f64 = s.parse().unwrap_or(x);
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        format!("{m}e{e}")
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn numbers_are_short() {
        assert_eq!(short(1.0e10), "1e10");
        assert_eq!(short(7.0e9), "7e9");
        assert_eq!(short(1.4285714), "1.429");
        assert_eq!(short(0.0142857), "0.01429");
        assert_eq!(short(2.5e-9), "2.5e-9");
        assert_eq!(short(1000.0), "1000");
    }
}
