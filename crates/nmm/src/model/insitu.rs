//! The keys of a tunnel or a cut: `[[block]] holes` (checked here), `[initial_stress]`
//! and `[[stage]] excavate` (with the monitors an excavation would end).
//!
//! * A hole is a simple polygon strictly inside its block (farther than the model
//!   tolerance from its boundary) and from the other holes; it is stored clockwise
//!   ([`crate::geometry::region`]).
//! * `[initial_stress]`: `stress = [σxx, σyy, τxy]` (Pa, tension positive, as in the VTK
//!   output) at y = `y_ref` (default 0), `gradient = d[σxx, σyy, τxy]/dy` (Pa/m, default 0).
//! * `excavate = ["name", …]` in a `[[stage]]`: blocks as drawn (all their pieces) or
//!   pieces, or — a name that is no block's — a closed `[[joint]]` loop: the pieces it
//!   cut out (every block whose polygon lies inside the loop); a block may be excavated
//!   once, by one stage; a monitor on a block that some stage excavates is refused (its
//!   values would end with the block).

// `!(x > tol)` is deliberate throughout: a NaN fails the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use super::lines::Doc;
use super::reader::{array, array_of_tables, error, number, string, table, Fields, R};
use super::validate::Names;
use super::{Block, InitialStress, Joint, JointKind, Monitor, MonitorKind, Stage};
use crate::geometry::polygon::{
    degeneracy, point_in_polygon, segment_segment_distance, self_intersection, signed_area,
    Degeneracy, Location,
};
use toml::Value;

/// Check block `i`'s holes (its polygon already checked and counter-clockwise) and orient
/// them clockwise.
pub(crate) fn check_holes(root: &Doc, i: usize, b: &mut Block, tol: f64) -> R<()> {
    let at = root.at("block", Some(i), Some("holes"));
    let name = b.name.clone();
    let err = |msg: String| error(format!("[[block]] {name:?}: key `holes`: {msg}{at}"));
    for (k, h) in b.holes.iter_mut().enumerate() {
        let n = h.len();
        if let Some(d) = degeneracy(h, tol).filter(|d| *d != Degeneracy::ZeroArea) {
            return Err(err(match d {
                Degeneracy::TooFewVertices(m) => {
                    format!(
                        "hole {}: a polygon needs at least 3 vertices, got {m}",
                        k + 1
                    )
                }
                Degeneracy::RepeatedVertex(j) => format!(
                    "hole {}: degenerate polygon: vertices {} and {} coincide",
                    k + 1,
                    j + 1,
                    (j + 1) % n + 1
                ),
                Degeneracy::Collinear => {
                    format!(
                        "hole {}: degenerate polygon: all vertices are collinear",
                        k + 1
                    )
                }
                Degeneracy::FoldBack(j) => format!(
                    "hole {}: degenerate polygon: the boundary folds back on itself at vertex {}",
                    k + 1,
                    j + 1
                ),
                Degeneracy::ZeroArea => unreachable!("filtered"),
            }));
        }
        if let Some((p, q)) = self_intersection(h, tol) {
            return Err(err(format!(
                "hole {}: polygon self-intersects (edges {} and {})",
                k + 1,
                p + 1,
                q + 1
            )));
        }
        if degeneracy(h, tol) == Some(Degeneracy::ZeroArea) {
            return Err(err(format!(
                "hole {}: degenerate polygon: zero area",
                k + 1
            )));
        }
        if signed_area(h) > 0.0 {
            h.reverse();
        }
    }
    let outer = &b.vertices;
    let apart = |p: &[crate::geometry::Vec2], q: &[crate::geometry::Vec2]| {
        (0..p.len()).all(|i| {
            (0..q.len()).all(|j| {
                let (a, b) = (p[i], p[(i + 1) % p.len()]);
                let (c, d) = (q[j], q[(j + 1) % q.len()]);
                segment_segment_distance(a, b, c, d) > tol
            })
        })
    };
    for (k, h) in b.holes.iter().enumerate() {
        let inside = h
            .iter()
            .all(|&p| point_in_polygon(outer, p, tol) == Location::Inside);
        if !inside || !apart(h, outer) {
            return Err(err(format!(
                "hole {} is not strictly inside the block's polygon (a hole may not touch or cross the block's boundary)",
                k + 1
            )));
        }
        for (j, g) in b.holes.iter().enumerate().take(k) {
            let nested = point_in_polygon(g, h[0], tol) != Location::Outside
                || point_in_polygon(h, g[0], tol) != Location::Outside;
            if nested || !apart(h, g) {
                return Err(err(format!(
                    "holes {} and {} overlap or touch",
                    j + 1,
                    k + 1
                )));
            }
        }
    }
    Ok(())
}

/// Three numbers `[a, b, c]`.
fn triple(v: &Value) -> Result<[f64; 3], String> {
    let a = array(v)?;
    match a {
        [x, y, z] => Ok([number(x)?, number(y)?, number(z)?]),
        _ => Err(format!(
            "expected three numbers [σxx, σyy, τxy], got {} items",
            a.len()
        )),
    }
}

/// `[initial_stress]`, if present.
pub(crate) fn initial_stress(root: &Doc) -> R<Option<InitialStress>> {
    let Some(t) = table(root, "initial_stress")? else {
        return Ok(None);
    };
    let f = root.fields("[initial_stress]", t, "initial_stress", None);
    f.deny_unknown(&["stress", "gradient", "y_ref"])?;
    Ok(Some(InitialStress {
        stress: f.req("stress", triple)?,
        gradient: f.opt("gradient", triple)?.unwrap_or([0.0; 3]),
        y_ref: f.opt("y_ref", number)?.unwrap_or(0.0),
    }))
}

/// What a name that is no block's means in `excavate`.
enum Loop {
    /// No `[[joint]]` has that name.
    NoJoint,
    /// A `[[joint]]` whose last point is not its first.
    Open,
    /// A closed `[[joint]]` loop: the blocks whose polygon lies inside it.
    Inside(Vec<usize>),
}

/// The blocks a closed `[[joint]]` loop named `name` cut out: those whose polygon lies
/// inside it.
fn inside_loop(name: &str, joints: &[Joint], blocks: &[Block], tol: f64) -> Loop {
    let Some(j) = joints.iter().find(|j| j.name == name) else {
        return Loop::NoJoint;
    };
    let JointKind::Polyline { points } = &j.kind else {
        return Loop::NoJoint;
    };
    let closed =
        points.len() >= 4 && crate::geometry::dist(points[0], points[points.len() - 1]) <= tol;
    if !closed {
        return Loop::Open;
    }
    let ring = &points[..points.len() - 1];
    Loop::Inside(
        (0..blocks.len())
            .filter(|&b| {
                blocks[b]
                    .vertices
                    .iter()
                    .all(|&p| point_in_polygon(ring, p, tol) != Location::Outside)
            })
            .collect(),
    )
}

/// Resolve each stage's `excavate` names to blocks (sorted): unknown names and a block
/// named twice (in one stage, or by two) are refused.
pub(crate) fn excavations(
    root: &Doc,
    mut stages: Vec<Stage>,
    names: &Names,
    (blocks, joints, tol): (&[Block], &[Joint], f64),
) -> R<Vec<Stage>> {
    let tables = array_of_tables(root, "stage")?;
    // block → (stage that excavates it, the name it was given there)
    let mut by: std::collections::HashMap<usize, (usize, String)> = Default::default();
    for (i, t) in tables.into_iter().enumerate() {
        let f = root.fields(
            format!("[[stage]] {:?}", stages[i].name),
            t,
            "stage",
            Some(i),
        );
        let Some(items) = f.opt("excavate", array)? else {
            continue;
        };
        if items.is_empty() {
            return Err(f.err("excavate", "must name at least one block"));
        }
        let mut set = Vec::new();
        for v in items {
            let name = string(v).map_err(|e| f.err("excavate", e))?;
            let named: Vec<usize> = match names.get(name) {
                Some((set, _)) => set.to_vec(),
                None => match inside_loop(name, joints, blocks, tol) {
                    Loop::Inside(set) if !set.is_empty() => set,
                    Loop::Inside(_) => {
                        return Err(f.err(
                            "excavate",
                            format!(
                                "the closed joint loop {name:?} encloses no block (a [[joint]] cuts the blocks of its `blocks`, by default every block that is not fixed)"
                            ),
                        ))
                    }
                    Loop::Open => {
                        return Err(f.err(
                            "excavate",
                            format!(
                                "no block is named {name:?}, and [[joint]] {name:?} is not a closed loop (to cut out a region its last point must repeat its first)"
                            ),
                        ))
                    }
                    Loop::NoJoint => {
                        return Err(f.err(
                            "excavate",
                            format!(
                                "unknown block {name:?} (nor a closed [[joint]] loop of that name)"
                            ),
                        ))
                    }
                },
            };
            for b in named {
                if let Some((s, other)) = by.get(&b) {
                    let also = if *s == i {
                        String::new()
                    } else {
                        format!(" by [[stage]] {:?}", stages[*s].name)
                    };
                    let what = if other == name {
                        format!("block {name:?} is excavated twice (also{also})")
                    } else {
                        format!(
                            "{name:?} names a block excavated twice: {other:?} (also{also}) means it too"
                        )
                    };
                    return Err(f.err("excavate", what.replace("(also)", "(also in this list)")));
                }
                by.insert(b, (i, name.to_string()));
                set.push(b);
            }
        }
        set.sort_unstable();
        stages[i].excavate = set;
    }
    Ok(stages)
}

/// Refuse a monitor on a block that a stage excavates.
pub(crate) fn check_monitors(root: &Doc, monitors: &[Monitor], stages: &[Stage]) -> R<()> {
    let excavated_by = |b: usize| stages.iter().find(|s| s.excavate.contains(&b));
    let tables = array_of_tables(root, "monitor")?;
    for (k, (m, t)) in monitors.iter().zip(tables).enumerate() {
        let (key, blocks): (&str, Vec<usize>) = match &m.kind {
            MonitorKind::Point { block, .. } => ("point", vec![*block]),
            MonitorKind::Block { blocks } => ("block", blocks.clone()),
            MonitorKind::Interface { first, second } => {
                ("interface", first.iter().chain(second).copied().collect())
            }
            // a bolt is refused itself when it is anchored in an excavated block
            MonitorKind::Bolt { .. } => continue,
            MonitorKind::Tip { block, .. } => ("crack", vec![*block]),
        };
        let hit = blocks.iter().find_map(|&b| excavated_by(b).map(|s| (b, s)));
        if let Some((_b, s)) = hit {
            let f: Fields = root.fields(format!("[[monitor]] {:?}", m.name), t, "monitor", Some(k));
            return Err(f.err(
                key,
                format!(
                    "it is on a block that [[stage]] {:?} excavates (a monitor on an excavated block is not allowed: its values would end with the block)",
                    s.name
                ),
            ));
        }
    }
    Ok(())
}

/// Refuse a bolt anchored in a block that a stage excavates (its anchor would go with the
/// block: install it in the rock that stays).
pub(crate) fn check_bolts(root: &Doc, bolts: &[super::types::Bolt], stages: &[Stage]) -> R<()> {
    let tables = array_of_tables(root, "bolt")?;
    for (k, (b, t)) in bolts.iter().zip(tables).enumerate() {
        for (i, &blk) in b.blocks.iter().enumerate() {
            if let Some(s) = stages.iter().find(|s| s.excavate.contains(&blk)) {
                let f: Fields = root.fields(format!("[[bolt]] {:?}", b.name), t, "bolt", Some(k));
                return Err(f.err(
                    "points",
                    format!(
                        "anchor {} is in a block that [[stage]] {:?} excavates (anchor bolts in the rock that stays)",
                        i + 1,
                        s.name
                    ),
                ));
            }
        }
    }
    Ok(())
}
