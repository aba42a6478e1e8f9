//! `[[joint_set]]` and `[[joint]]`: reading them, and cutting the blocks they cross.
//!
//! Cutting happens during validation, so that the rest of the program sees plain blocks.
//! Each block is cut on its own by the traces that apply to it
//! ([`crate::geometry::cut::cut_polygon`] at the model tolerance):
//!
//! * a joint set with angle α, spacing s and origin o has the trace lines
//!   `{x : n · (x − o) = k s}`, k ∈ ℤ, with d = (cos α, sin α) and n = (−sin α, cos α);
//!   with `trace_length` L and `bridge` B each line carries the traces
//!   `d · (x − o) ∈ [m (L + B), m (L + B) + L]`, m ∈ ℤ;
//! * a joint is its polyline.
//!
//! The pieces of a block cut in two or more keep its material and `fixed` flag and are
//! named `NAME.1`, `NAME.2`, … by centroid, bottom to top, then left to right (see
//! [`crate::geometry::cut`]); they take the block's place in the block list. A block that
//! is not split keeps its name (traces ending inside it are cracks). A loop of traces
//! that touches nothing else cuts out the pieces inside it (the piece around them gets a
//! hole); one that would pinch the piece around it (hanging from the rest by one vertex)
//! is a closed crack: the region it encloses stays part of the block around it and is
//! listed in `Model::enclosed`. A block with holes is cut the same way (its holes' edges
//! are boundary edges). Joint ids are the sets in file
//! order, then the joints in file order.
//!
//! **Thin pieces.** A piece whose width 2A/P is below [`MIN_PIECE_WIDTH`] × h is refused
//! with a hint to set `[cover] min_block_area` (which merges it first).
//!
//! **Limit.** `[cover] max_blocks` (default [`DEFAULT_MAX_BLOCKS`]) bounds the number of
//! blocks. Before cutting, each set is checked, in file order, against an estimate of
//! the blocks the sets so far make: per block, 1 + (traces) + Σ over pairs of
//! non-parallel sets n_i n_j f_i f_j, with n the number of trace lines crossing the block
//! and f = L / (L + B) the persistence (1 for a persistent set) — the count of pieces of
//! a convex block by Euler's formula when every crossing falls inside. After cutting, the
//! actual count is checked too.

// `!(x > tol)` is deliberate throughout: a NaN fails the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use super::lines::Doc;
use super::reader::{
    array, array_of_tables, error, fmt_num, number, point, points, string, Fields, R,
};
use super::{Block, Crack, Joint, JointKind, MergedPiece};
use crate::geometry::cut::{cut_region, Trace};
use crate::geometry::polygon::{degeneracy, self_intersection};
use crate::geometry::{dist, dot, Aabb, Vec2};
use std::collections::HashMap;

/// Default of `[cover] max_blocks`.
pub const DEFAULT_MAX_BLOCKS: usize = 100_000;

/// A piece thinner (2 × area / perimeter) than this × h is refused: the discretisation
/// drops manifold elements thinner than 1e-5 h (`cover::MIN_PIECE_WIDTH`), and a block
/// that thin has nothing left to carry it.
pub const MIN_PIECE_WIDTH: f64 = 1e-4;

/// A joint with the blocks (indices into the blocks as drawn) it cuts and where it is written.
pub(crate) struct JointSpec {
    pub joint: Joint,
    pub blocks: Vec<usize>,
    /// ("joint_set" | "joint", index among the tables of that kind)
    pub table: (&'static str, usize),
}

/// The blocks after cutting.
pub(crate) struct Cutting {
    pub blocks: Vec<Block>,
    /// For each block as drawn: its pieces (indices into `blocks`).
    pub pieces_of: Vec<Vec<usize>>,
    pub cracks: Vec<Crack>,
    pub merged: Vec<MergedPiece>,
    pub enclosed: Vec<MergedPiece>,
    pub kept_small: Vec<MergedPiece>,
}

fn place(kind: &str, name: &str) -> String {
    format!("[[{kind}]] {name:?}")
}

/// Read `blocks` (default: every block that is not fixed).
fn cut_blocks(f: &Fields, blocks: &[Block]) -> R<Vec<usize>> {
    if !f.has("blocks") {
        return Ok((0..blocks.len()).filter(|&i| !blocks[i].fixed).collect());
    }
    let items = f.req("blocks", array)?;
    let mut out = Vec::new();
    for v in items {
        let name = string(v).map_err(|e| f.err("blocks", e))?;
        let i = blocks
            .iter()
            .position(|b| b.name == name)
            .ok_or_else(|| f.err("blocks", format!("unknown block {name:?}")))?;
        if out.contains(&i) {
            return Err(f.err("blocks", format!("block {name:?} is listed twice")));
        }
        out.push(i);
    }
    if out.is_empty() {
        return Err(f.err("blocks", "must name at least one block"));
    }
    Ok(out)
}

/// Read the `[[joint_set]]` and `[[joint]]` tables.
pub(crate) fn read(root: &Doc, blocks: &[Block], tol: f64) -> R<Vec<JointSpec>> {
    let mut out: Vec<JointSpec> = Vec::new();
    let mut seen: HashMap<String, String> = HashMap::new();
    let mut check_name = |f: &Fields, name: &str, here: String| -> R<()> {
        if let Some(other) = seen.get(name) {
            return Err(f.err(
                "name",
                format!(
                    "duplicate joint name (also {other}); joint and joint set names share one list"
                ),
            ));
        }
        seen.insert(name.to_string(), here);
        Ok(())
    };
    for (i, t) in array_of_tables(root, "joint_set")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[joint_set]] #{}", i + 1), t, "joint_set", Some(i));
        let name = f.name("name")?;
        f.set_place(place("joint_set", &name));
        f.deny_unknown(&[
            "name",
            "angle",
            "spacing",
            "origin",
            "blocks",
            "trace_length",
            "bridge",
        ])?;
        check_name(&f, &name, format!("[[joint_set]] #{}", i + 1))?;
        let angle = f.req("angle", number)?;
        if !(0.0..180.0).contains(&angle) {
            return Err(f.err(
                "angle",
                format!(
                    "must be in [0, 180) degrees (counter-clockwise from +x), got {}",
                    fmt_num(angle)
                ),
            ));
        }
        let spacing = f.req("spacing", number)?;
        if !(spacing > 0.0) {
            return Err(f.err(
                "spacing",
                format!("must be positive, got {}", fmt_num(spacing)),
            ));
        }
        if !(spacing > tol) {
            return Err(f.err(
                "spacing",
                format!(
                    "{} is not larger than the geometric tolerance ({:e} m)",
                    fmt_num(spacing),
                    tol
                ),
            ));
        }
        let origin = f.opt("origin", point)?.unwrap_or([0.0, 0.0]);
        let pattern = match (f.opt("trace_length", number)?, f.opt("bridge", number)?) {
            (None, None) => None,
            (Some(_), None) => {
                return Err(f.err(
                    "bridge",
                    "missing: `trace_length` needs `bridge` (the rock bridge between traces, m)",
                ))
            }
            (None, Some(_)) => {
                return Err(f.err(
                    "trace_length",
                    "missing: `bridge` needs `trace_length` (the length of each trace, m)",
                ))
            }
            (Some(l), Some(b)) => {
                if !(l > tol) {
                    return Err(f.err(
                        "trace_length",
                        format!("must be positive, got {}", fmt_num(l)),
                    ));
                }
                if !(b > tol) {
                    return Err(f.err(
                        "bridge",
                        format!(
                            "must be positive (leave out `trace_length` and `bridge` for persistent traces), got {}",
                            fmt_num(b)
                        ),
                    ));
                }
                Some((l, b))
            }
        };
        let cuts = cut_blocks(&f, blocks)?;
        out.push(JointSpec {
            joint: Joint {
                name,
                kind: JointKind::Set {
                    angle,
                    spacing,
                    origin,
                    pattern,
                },
            },
            blocks: cuts,
            table: ("joint_set", i),
        });
    }
    for (i, t) in array_of_tables(root, "joint")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[joint]] #{}", i + 1), t, "joint", Some(i));
        let name = f.name("name")?;
        f.set_place(place("joint", &name));
        f.deny_unknown(&["name", "points", "blocks"])?;
        check_name(&f, &name, format!("[[joint]] #{}", i + 1))?;
        let pts = f.req("points", points)?;
        if pts.len() < 2 {
            return Err(f.err(
                "points",
                format!("a joint needs at least 2 points, got {}", pts.len()),
            ));
        }
        if let Some(k) = (0..pts.len() - 1).find(|&k| !(dist(pts[k], pts[k + 1]) > tol)) {
            return Err(f.err(
                "points",
                format!(
                    "segment {} has zero length (points {} and {} coincide)",
                    k + 1,
                    k + 1,
                    k + 2
                ),
            ));
        }
        let cuts = cut_blocks(&f, blocks)?;
        out.push(JointSpec {
            joint: Joint {
                name,
                kind: JointKind::Polyline { points: pts },
            },
            blocks: cuts,
            table: ("joint", i),
        });
    }
    Ok(out)
}

/// Direction d and normal n of a set's lines.
fn axes(angle: f64) -> (Vec2, Vec2) {
    let (s, c) = angle.to_radians().sin_cos();
    ([c, s], [-s, c])
}

/// The range of line numbers k whose line meets the polygon, and the range of
/// d · (x − o) over it.
fn line_range(poly: &[Vec2], angle: f64, spacing: f64, origin: Vec2) -> (f64, f64, f64, f64) {
    let (d, n) = axes(angle);
    let (mut u0, mut u1, mut w0, mut w1) =
        (f64::INFINITY, -f64::INFINITY, f64::INFINITY, -f64::INFINITY);
    for &p in poly {
        let r = [p[0] - origin[0], p[1] - origin[1]];
        let u = dot(r, n) / spacing;
        let w = dot(r, d);
        u0 = u0.min(u);
        u1 = u1.max(u);
        w0 = w0.min(w);
        w1 = w1.max(w);
    }
    (u0.ceil(), u1.floor(), w0, w1)
}

/// The traces of joint `j` that may cross `poly`.
fn traces_for(joint: &Joint, id: usize, poly: &[Vec2], tol: f64, out: &mut Vec<Trace>) {
    match &joint.kind {
        JointKind::Set {
            angle,
            spacing,
            origin,
            pattern,
        } => {
            let (d, n) = axes(*angle);
            let (k0, k1, w0, w1) = line_range(poly, *angle, *spacing, *origin);
            if !(k1 >= k0) {
                return;
            }
            let pad = 0.01 * (w1 - w0) + 10.0 * tol;
            let (lo, hi) = (w0 - pad, w1 + pad);
            let at = |k: f64, w: f64| -> Vec2 {
                [
                    origin[0] + k * spacing * n[0] + w * d[0],
                    origin[1] + k * spacing * n[1] + w * d[1],
                ]
            };
            let mut k = k0;
            while k <= k1 {
                match pattern {
                    None => out.push(Trace {
                        points: vec![at(k, lo), at(k, hi)],
                        joint: id,
                    }),
                    Some((len, bridge)) => {
                        let period = len + bridge;
                        let mut m = (lo / period).floor();
                        while m * period <= hi {
                            let (a, b) = ((m * period).max(lo), (m * period + len).min(hi));
                            if b > a {
                                out.push(Trace {
                                    points: vec![at(k, a), at(k, b)],
                                    joint: id,
                                });
                            }
                            m += 1.0;
                        }
                    }
                }
                k += 1.0;
            }
        }
        JointKind::Polyline { points } => {
            if Aabb::of_points(points)
                .inflate(tol)
                .overlaps(&Aabb::of_points(poly))
            {
                out.push(Trace {
                    points: points.clone(),
                    joint: id,
                });
            }
        }
    }
}

/// Refuse, in file order, the first set whose traces would make more than `max_blocks`
/// blocks (estimate of the module doc).
pub(crate) fn check_estimate(
    root: &Doc,
    blocks: &[Block],
    specs: &[JointSpec],
    max_blocks: usize,
) -> R<()> {
    // per block: (Σ traces, list of (angle, lines, persistence) of the sets so far)
    let mut traces = vec![0.0f64; blocks.len()];
    let mut sets: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new(); blocks.len()];
    let mut crossings = vec![0.0f64; blocks.len()];
    for s in specs {
        let JointKind::Set {
            angle,
            spacing,
            origin,
            pattern,
        } = &s.joint.kind
        else {
            for &b in &s.blocks {
                if let JointKind::Polyline { points } = &s.joint.kind {
                    traces[b] += (points.len() - 1) as f64;
                }
            }
            continue;
        };
        for &b in &s.blocks {
            let (k0, k1, w0, w1) = line_range(&blocks[b].vertices, *angle, *spacing, *origin);
            let lines = (k1 - k0 + 1.0).max(0.0);
            let (f, per_line) = match pattern {
                None => (1.0, 1.0),
                Some((l, br)) => (l / (l + br), ((w1 - w0) / (l + br)).ceil() + 1.0),
            };
            traces[b] += lines * per_line;
            for &(a2, n2, f2) in &sets[b] {
                if (a2 - angle).abs() > 1e-9 {
                    crossings[b] += lines * n2 * f * f2;
                }
            }
            sets[b].push((*angle, lines, f));
        }
        let total: f64 = (0..blocks.len())
            .map(|b| 1.0 + traces[b] + crossings[b])
            .sum();
        if !(total <= max_blocks as f64) {
            let (kind, i) = s.table;
            let at = root.at(kind, Some(i), Some("spacing"));
            return Err(error(format!(
                "{}: key `spacing`: with the joint sets before it, it would cut the blocks into about {:.0} blocks, more than `[cover] max_blocks` = {max_blocks} (raise it, or use a larger spacing){at}",
                place(kind, &s.joint.name),
                total
            )));
        }
    }
    Ok(())
}

/// Cut every block by the traces that apply to it; name the pieces.
pub(crate) fn cut(
    root: &Doc,
    blocks: Vec<Block>,
    specs: &[JointSpec],
    tol: f64,
    (h, min_area, max_blocks): (f64, Option<f64>, usize),
) -> R<Cutting> {
    let mut by_block: Vec<Vec<usize>> = vec![Vec::new(); blocks.len()];
    for (j, s) in specs.iter().enumerate() {
        for &b in &s.blocks {
            by_block[b].push(j);
        }
    }
    let originals: Vec<String> = blocks.iter().map(|b| b.name.clone()).collect();
    let mut out = Cutting {
        blocks: Vec::new(),
        pieces_of: Vec::new(),
        cracks: Vec::new(),
        merged: Vec::new(),
        enclosed: Vec::new(),
        kept_small: Vec::new(),
    };
    let mut traces = Vec::new();
    for (bi, block) in blocks.into_iter().enumerate() {
        if by_block[bi].is_empty() {
            out.pieces_of.push(vec![out.blocks.len()]);
            out.blocks.push(block);
            continue;
        }
        traces.clear();
        for &j in &by_block[bi] {
            traces_for(&specs[j].joint, j, &block.vertices, tol, &mut traces);
        }
        let at = root.at("block", Some(bi), Some("vertices"));
        let c = cut_region(block.region(), &traces, tol, min_area).map_err(|e| {
            error(format!(
                "[[block]] {:?}: key `vertices`: cutting by the joints: {e}{at}",
                block.name
            ))
        })?;
        let first = out.blocks.len();
        let split = c.pieces.len() > 1;
        if split {
            // names must not clash with a block as drawn
            for k in 1..=c.pieces.len() {
                let name = format!("{}.{k}", block.name);
                if let Some(o) = originals.iter().position(|n| *n == name) {
                    return Err(error(format!(
                        "[[block]] {:?}: key `name`: the joints cut it into {} pieces named {:?} … {:?}, but {name:?} is the name of [[block]] #{}: rename one of them{}",
                        block.name,
                        c.pieces.len(),
                        format!("{}.1", block.name),
                        format!("{}.{}", block.name, c.pieces.len()),
                        o + 1,
                        root.at("block", Some(bi), Some("name"))
                    )));
                }
            }
        }
        for (k, p) in c.pieces.iter().enumerate() {
            let region = crate::geometry::region::Region {
                outer: &p.vertices,
                holes: &p.holes,
            };
            if split {
                let area = region.area();
                let perimeter: f64 = region
                    .loops()
                    .map(|l| {
                        (0..l.len())
                            .map(|i| dist(l[i], l[(i + 1) % l.len()]))
                            .sum::<f64>()
                    })
                    .sum();
                let width = 2.0 * area / perimeter;
                if !(width >= MIN_PIECE_WIDTH * h) {
                    return Err(error(format!(
                        "[[block]] {:?}: key `vertices`: the joints cut off a piece ({:?}, area {area:.3e} m²) only {width:.3e} m thick, thinner than the mesh can resolve ({MIN_PIECE_WIDTH:e} × [cover] size); set [cover] min_block_area to merge such pieces into their neighbours, or move the joints{at}",
                        block.name,
                        format!("{}.{}", block.name, k + 1),
                    )));
                }
            }
            let bad = region
                .loops()
                .any(|l| degeneracy(l, tol).is_some() || self_intersection(l, tol).is_some());
            if bad {
                let q = p.vertices[0];
                return Err(error(format!(
                    "[[block]] {:?}: key `vertices`: cutting by the joints made a degenerate piece at [{},{}] (traces closer to each other or to a corner than the geometric tolerance allows){at}",
                    block.name,
                    fmt_num(q[0]),
                    fmt_num(q[1])
                )));
            }
            out.blocks.push(Block {
                name: if split {
                    format!("{}.{}", block.name, k + 1)
                } else {
                    block.name.clone()
                },
                material: block.material,
                vertices: p.vertices.clone(),
                fixed: block.fixed,
                edge_joint: p.edge_joint.clone(),
                parent: split.then(|| block.name.clone()),
                holes: p.holes.clone(),
            });
        }
        out.pieces_of.push((first..out.blocks.len()).collect());
        out.cracks.extend(c.cracks.into_iter().map(|k| Crack {
            block: first + k.piece,
            joint: k.joint,
            points: k.points,
        }));
        let note = |m: crate::geometry::cut::Merge| MergedPiece {
            block: first + m.into,
            area: m.area,
            centroid: m.centroid,
            bridges: m.bridges,
        };
        out.merged.extend(c.merged.into_iter().map(note));
        out.enclosed.extend(c.enclosed.into_iter().map(note));
        out.kept_small.extend(c.kept.into_iter().map(note));
        if out.blocks.len() > max_blocks {
            return Err(error(format!(
                "[cover]: key `max_blocks`: the joints cut the blocks into more than {max_blocks} blocks (raise `max_blocks`, or use larger spacings){}",
                root.at("cover", None, Some("max_blocks"))
            )));
        }
    }
    Ok(out)
}
