//! `nmm plot`: pictures of a model as cut and of a run's frames, as [`Scene`]s that
//! [`crate::output::plot::plot_scene`] draws (PNG or SVG).
//!
//! * [`model_scene`]: the blocks as cut (fixed blocks grey, the others in pastel colours,
//!   names at their centroids), joint faces coloured by joint set or joint (one colour per
//!   joint id, listed in the legend), cracks in red, loads as arrows (edge loads at the
//!   middle of their segment), constraints in magenta (edges as thick lines, points as
//!   squares), point monitors as circles with their names, and the manifold elements of the
//!   cover when a discretisation is given (`--mesh`), rock bolts as dark blue lines between
//!   their anchors.
//! * [`frame_scene`]: one frame of a run's `blocks.pvd` (the deformed manifold elements
//!   filled by a field, block outlines, a colour bar with the unit) and the contacts of the
//!   same step from `contacts.pvd` (grey open, green stick, red slide) and the installed
//!   bolts of that step from `bolts.pvd` (dark blue, orange when yielded); the title names
//!   the run, the step, the time and the field.

use crate::cover::Discretisation;
use crate::model::{ConstraintGeometry, LoadKind, Model, MonitorKind};
use crate::output::plot::{colour_map, MarkerShape, Rgb, Scene, SceneMarker, ScenePolygon};
use crate::output::vtk::{read_pvd, read_vtu, ReadGrid};
use std::collections::HashMap;
use std::path::Path;

/// Rock bolts: installed (and as drawn), yielded.
const BOLT: Rgb = (23, 55, 94);
const BOLT_YIELDED: Rgb = (255, 127, 14);

/// Joint colours (Tableau 10 without red, which marks cracks and sliding contacts).
const JOINTS: [Rgb; 9] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (188, 189, 34),
    (23, 190, 207),
    (0, 0, 0),
];
/// Pastel fills of free blocks.
const FILLS: [Rgb; 6] = [
    (174, 199, 232),
    (255, 187, 120),
    (152, 223, 138),
    (197, 176, 213),
    (196, 156, 148),
    (219, 219, 141),
];
const GREY: Rgb = (150, 150, 150);
const RED: Rgb = (214, 39, 40);
const MAGENTA: Rgb = (190, 0, 160);
const LOAD: Rgb = (200, 30, 30);

fn xy(v: &[[f64; 2]]) -> Vec<(f64, f64)> {
    v.iter().map(|p| (p[0], p[1])).collect()
}

fn centroid(v: &[[f64; 2]]) -> (f64, f64) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..v.len() {
        let (p, q) = (v[i], v[(i + 1) % v.len()]);
        let c = p[0] * q[1] - q[0] * p[1];
        a += c;
        cx += (p[0] + q[0]) * c;
        cy += (p[1] + q[1]) * c;
    }
    if a.abs() < 1e-300 {
        let n = v.len().max(1) as f64;
        return (
            v.iter().map(|p| p[0]).sum::<f64>() / n,
            v.iter().map(|p| p[1]).sum::<f64>() / n,
        );
    }
    (cx / (3.0 * a), cy / (3.0 * a))
}

/// The model as cut: see the module doc. `mesh`: draw these manifold elements too.
pub fn model_scene(model: &Model, mesh: Option<&Discretisation>, title: &str) -> Scene {
    let mut s = Scene {
        title: title.to_string(),
        ..Scene::default()
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in &model.blocks {
        for p in &b.vertices {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
    // blocks with holes first, each with its holes in white, so that what lies in a hole
    // (a tunnel's plug) is drawn over it; then the others
    let fills: Vec<_> = {
        let mut free = 0usize;
        model
            .blocks
            .iter()
            .map(|b| {
                if b.fixed {
                    GREY
                } else {
                    free += 1;
                    FILLS[(free - 1) % FILLS.len()]
                }
            })
            .collect()
    };
    for with_holes in [true, false] {
        for (b, &fill) in model.blocks.iter().zip(&fills) {
            if b.holes.is_empty() == with_holes {
                continue;
            }
            s.polygons.push(ScenePolygon {
                points: xy(&b.vertices),
                fill: Some((fill, if b.fixed { 0.5 } else { 0.8 })),
                outline: Some(((0, 0, 0), 1)),
            });
            for h in &b.holes {
                s.polygons.push(ScenePolygon {
                    points: xy(h),
                    fill: Some(((255, 255, 255), 1.0)),
                    outline: Some(((0, 0, 0), 1)),
                });
            }
        }
    }
    if let Some(d) = mesh {
        for e in &d.elements {
            s.polygons.push(ScenePolygon {
                points: xy(&e.polygon),
                fill: None,
                outline: Some(((120, 120, 120), 1)),
            });
        }
    }
    let mut used = vec![false; model.joints.len()];
    for b in &model.blocks {
        for ((p, q), j) in b.edges().zip(&b.edge_joint) {
            if let Some(j) = *j {
                used[j] = true;
                s.lines.push((xy(&[p, q]), JOINTS[j % JOINTS.len()], 2));
            }
        }
    }
    for (j, joint) in model.joints.iter().enumerate() {
        if used[j] {
            s.legend
                .push((format!("joint {}", joint.name), JOINTS[j % JOINTS.len()]));
        }
    }
    for c in &model.cracks {
        s.lines.push((xy(&c.points), RED, 2));
    }
    if !model.cracks.is_empty() {
        s.legend
            .push((format!("{} crack(s)", model.cracks.len()), RED));
    }
    if model.blocks.iter().any(|b| b.fixed) {
        s.legend.push(("fixed block".into(), GREY));
    }
    let arrow = 0.08 * span;
    for l in &model.loads {
        let (at, dir) = match l.kind {
            LoadKind::Edge { a, b, traction } => {
                s.lines.push((xy(&[a, b]), LOAD, 3));
                ([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])], traction)
            }
            LoadKind::Point { p, force } => (p, force),
        };
        let n = (dir[0] * dir[0] + dir[1] * dir[1]).sqrt();
        if n > 0.0 {
            // the arrow ends at the point of application
            let from = (at[0] - arrow * dir[0] / n, at[1] - arrow * dir[1] / n);
            s.arrows.push((from, (at[0], at[1]), LOAD));
        }
    }
    if !model.loads.is_empty() {
        s.legend.push(("load".into(), LOAD));
    }
    for c in &model.constraints {
        match c.geometry {
            ConstraintGeometry::Edge { a, b } => s.lines.push((xy(&[a, b]), MAGENTA, 5)),
            ConstraintGeometry::Point { p } => s.markers.push(SceneMarker {
                at: (p[0], p[1]),
                shape: MarkerShape::Square,
                colour: MAGENTA,
                size: 5,
            }),
        }
    }
    if !model.constraints.is_empty() {
        s.legend.push(("constraint".into(), MAGENTA));
    }
    for b in &model.bolts {
        s.lines.push((xy(&b.points), BOLT, 3));
    }
    if !model.bolts.is_empty() {
        s.legend.push(("bolt".into(), BOLT));
    }
    let label_size = if model.blocks.len() > 60 { 9 } else { 12 };
    for b in &model.blocks {
        s.labels
            .push((centroid(&b.vertices), b.name.clone(), label_size));
    }
    let mut monitors = false;
    for m in &model.monitors {
        if let MonitorKind::Point { p, .. } = m.kind {
            monitors = true;
            s.markers.push(SceneMarker {
                at: (p[0], p[1]),
                shape: MarkerShape::Circle,
                colour: (255, 215, 0),
                size: 5,
            });
            s.labels
                .push(((p[0], p[1] + 0.025 * span), m.name.clone(), label_size + 1));
        }
    }
    if monitors {
        s.legend.push(("monitor".into(), (255, 215, 0)));
    }
    s
}

/// A field of a run's frame that `nmm plot` colours the blocks by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Field {
    /// |displacement| (m).
    U,
    Ux,
    Uy,
    Sxx,
    Syy,
    Sxy,
}

impl Field {
    /// `u`, `ux`, `uy`, `sxx`, `syy`, `sxy` (also `txy`).
    pub fn parse(s: &str) -> Result<Field, String> {
        Ok(match s {
            "u" => Field::U,
            "ux" => Field::Ux,
            "uy" => Field::Uy,
            "sxx" => Field::Sxx,
            "syy" => Field::Syy,
            "sxy" | "txy" => Field::Sxy,
            other => {
                return Err(format!(
                    "--field: unknown field \"{other}\" (expected u, ux, uy, sxx, syy or sxy)"
                ))
            }
        })
    }

    /// The field's name in titles and colour bars: `|u|`, `ux`, `uy`, `σxx`, `σyy`, `τxy`.
    pub fn name(self) -> &'static str {
        match self {
            Field::U => "|u|",
            Field::Ux => "ux",
            Field::Uy => "uy",
            Field::Sxx => "σxx",
            Field::Syy => "σyy",
            Field::Sxy => "τxy",
        }
    }

    /// A stress (Pa), not a displacement (m).
    pub fn is_stress(self) -> bool {
        matches!(self, Field::Sxx | Field::Syy | Field::Sxy)
    }
}

/// The frames `(time, file)` of a run folder's `blocks.pvd`.
pub fn run_frames(dir: &Path) -> Result<Vec<(f64, String)>, String> {
    let pvd = dir.join("blocks.pvd");
    if !pvd.exists() {
        return Err(format!(
            "{}: no blocks.pvd (not a run folder, or a run with --no-vtk)",
            dir.display()
        ));
    }
    let frames = read_pvd(&pvd)?;
    if frames.is_empty() {
        return Err(format!("{}: no frame yet", pvd.display()));
    }
    Ok(frames)
}

/// The step of a frame file `vtk/blocks_NNNNNN.vtu` (or `vtk/contacts_NNNNNN.vtu`).
pub fn step_of(file: &str) -> Option<usize> {
    let stem = Path::new(file).file_stem()?.to_str()?;
    stem.rsplit('_').next()?.parse().ok()
}

/// One frame of a run read back from its VTK output: what `nmm plot RUN_DIR` draws and the
/// Python package's `Result.frame(k)` returns.
#[derive(Clone, Debug)]
pub struct RunFrame {
    /// Its index in `blocks.pvd` (from 0).
    pub index: usize,
    /// The frame's time (s), as `blocks.pvd` lists it.
    pub time: f64,
    /// The step, from the frame's file name (`vtk/blocks_NNNNNN.vtu`).
    pub step: Option<usize>,
    /// The frame's file, relative to the run folder.
    pub file: String,
    /// The deformed manifold elements (one cell each) with their arrays.
    pub blocks: ReadGrid,
    /// The contacts of the same step from `contacts.pvd` (None when it lists no frame at
    /// that step: no contact then, or no `contacts.pvd`).
    pub contacts: Option<ReadGrid>,
}

/// Frame `index` (from 0) of the run in `dir`: its blocks and the contacts of its step.
pub fn read_frame(dir: &Path, index: usize) -> Result<RunFrame, String> {
    let frames = run_frames(dir)?;
    let (time, file) = frames.get(index).ok_or_else(|| {
        format!(
            "{}: no frame {index} (blocks.pvd has frames 0 … {})",
            dir.display(),
            frames.len() - 1
        )
    })?;
    let blocks = read_vtu(&dir.join(file))?;
    let step = step_of(file);
    let mut contacts = None;
    if let (Some(step), Ok(listed)) = (step, read_pvd(&dir.join("contacts.pvd"))) {
        if let Some((_, cfile)) = listed.iter().find(|(_, f)| step_of(f) == Some(step)) {
            contacts = Some(read_vtu(&dir.join(cfile))?);
        }
    }
    Ok(RunFrame {
        index,
        time: *time,
        step,
        file: file.clone(),
        blocks,
        contacts,
    })
}

/// The installed bolts of step `step` from the run's `bolts.pvd` (if it lists that step) as
/// lines of `s`: dark blue, orange when yielded.
fn bolt_lines(dir: &Path, step: Option<usize>, s: &mut Scene) -> Result<(), String> {
    let (Some(step), Ok(listed)) = (step, read_pvd(&dir.join("bolts.pvd"))) else {
        return Ok(());
    };
    let Some((_, file)) = listed.iter().find(|(_, f)| step_of(f) == Some(step)) else {
        return Ok(());
    };
    let g = read_vtu(&dir.join(file))?;
    let column = |name: &str| g.cell_data.get(name).map(|(_, v)| v.clone());
    let (installed, yielded) = (column("installed"), column("yielded"));
    let mut seen = [false; 2];
    for (i, cell) in g.cells.iter().enumerate() {
        if installed.as_ref().is_some_and(|v| v[i] == 0.0) || cell.len() != 2 {
            continue;
        }
        let y = usize::from(yielded.as_ref().is_some_and(|v| v[i] != 0.0));
        seen[y] = true;
        let (a, b) = (g.points[cell[0]], g.points[cell[1]]);
        s.lines
            .push((vec![(a[0], a[1]), (b[0], b[1])], [BOLT, BOLT_YIELDED][y], 3));
    }
    for (k, name) in ["bolt", "bolt yielded"].iter().enumerate() {
        if seen[k] {
            s.legend.push((name.to_string(), [BOLT, BOLT_YIELDED][k]));
        }
    }
    Ok(())
}

/// The value of `field` per cell of a blocks frame: `u` the mean of the cell's vertex
/// |displacement|, `ux`, `uy` the means of its components, `sxx`, `syy`, `sxy` the
/// `stress` array.
pub fn cell_values(g: &ReadGrid, field: Field) -> Result<Vec<f64>, String> {
    if field.is_stress() {
        let (c, v) = g
            .cell_data
            .get("stress")
            .ok_or("the frame has no stress array")?;
        let k = match field {
            Field::Sxx => 0,
            Field::Syy => 1,
            _ => 2,
        };
        return Ok((0..g.cells.len()).map(|i| v[i * c + k]).collect());
    }
    let (c, v) = g
        .point_data
        .get("displacement")
        .ok_or("the frame has no displacement array")?;
    Ok(g.cells
        .iter()
        .map(|cell| {
            let f = |p: usize| {
                let (x, y) = (v[p * c], v[p * c + 1]);
                match field {
                    Field::Ux => x,
                    Field::Uy => y,
                    _ => (x * x + y * y).sqrt(),
                }
            };
            cell.iter().map(|&p| f(p)).sum::<f64>() / cell.len().max(1) as f64
        })
        .collect())
}

/// A unit for values of `field` up to `max` in magnitude: (factor to divide by, name):
/// m or mm for displacements, Pa, kPa or MPa for stresses.
pub fn unit(field: Field, max: f64) -> (f64, &'static str) {
    if field.is_stress() {
        if max >= 1e6 {
            (1e6, "MPa")
        } else if max >= 1e3 {
            (1e3, "kPa")
        } else {
            (1.0, "Pa")
        }
    } else if max < 0.01 {
        (1e-3, "mm")
    } else {
        (1.0, "m")
    }
}

/// The block outline edges of a blocks frame: the cell edges not shared with another cell
/// of the same block, as (block id, from, to), in cell order. Points closer than 1e-7 of
/// the frame's extent are one point.
pub fn outline_edges(g: &ReadGrid) -> Vec<(i64, [f64; 2], [f64; 2])> {
    let blocks = g.cell_data.get("block").map(|(_, b)| b);
    let key = point_key(g);
    type Edge = (i64, (i64, i64), (i64, i64));
    let mut count: HashMap<Edge, usize> = HashMap::new();
    for (i, cell) in g.cells.iter().enumerate() {
        let b = blocks.map_or(0, |b| b[i] as i64);
        for k in 0..cell.len() {
            let (a, c) = (
                key(g.points[cell[k]]),
                key(g.points[cell[(k + 1) % cell.len()]]),
            );
            *count.entry((b, a.min(c), a.max(c))).or_default() += 1;
        }
    }
    let mut out = Vec::new();
    for (i, cell) in g.cells.iter().enumerate() {
        let b = blocks.map_or(0, |b| b[i] as i64);
        for k in 0..cell.len() {
            let (pa, pc) = (g.points[cell[k]], g.points[cell[(k + 1) % cell.len()]]);
            let (a, c) = (key(pa), key(pc));
            if count.get(&(b, a.min(c), a.max(c))) == Some(&1) {
                out.push((b, pa, pc));
            }
        }
    }
    out
}

/// Integer keys of points: points closer than 1e-7 of the grid's extent share a key.
fn point_key(g: &ReadGrid) -> impl Fn([f64; 2]) -> (i64, i64) {
    let (mut mn, mut mx) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &g.points {
        mn = mn.min(p[0]).min(p[1]);
        mx = mx.max(p[0]).max(p[1]);
    }
    let q = ((mx - mn).abs().max(1e-9)) * 1e-7;
    move |p: [f64; 2]| ((p[0] / q).round() as i64, (p[1] / q).round() as i64)
}

/// The deformed outlines of the blocks of a blocks frame: per block id (0 … the largest id
/// in the frame's `block` array), its closed outlines (no point repeated), each
/// counter-clockwise, the largest first. The cells are counter-clockwise (as the library
/// writes them), so each outline edge has the block on its left; the outline is followed
/// edge to edge, and where several edges leave a point (elements of one block touching at
/// a point only) the one turning furthest to the left is taken, so that such a block gives
/// one outline per part rather than a figure of eight. Built from [`outline_edges`].
pub fn block_outlines(g: &ReadGrid) -> Vec<Vec<Vec<[f64; 2]>>> {
    let edges = outline_edges(g);
    let n = edges.iter().map(|e| e.0 + 1).max().unwrap_or(0).max(0) as usize;
    let key = point_key(g);
    let angle = |p: [f64; 2], q: [f64; 2]| (q[1] - p[1]).atan2(q[0] - p[0]);
    let mut out = vec![Vec::new(); n];
    for (b, loops) in out.iter_mut().enumerate() {
        let mine: Vec<([f64; 2], [f64; 2])> = edges
            .iter()
            .filter(|e| e.0 == b as i64)
            .map(|e| (e.1, e.2))
            .collect();
        let mut from: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (i, (p, _)) in mine.iter().enumerate() {
            from.entry(key(*p)).or_default().push(i);
        }
        let mut used = vec![false; mine.len()];
        for start in 0..mine.len() {
            if used[start] {
                continue;
            }
            used[start] = true;
            let first = key(mine[start].0);
            let mut ring = vec![mine[start].0];
            let mut edge = start;
            loop {
                let (p, q) = mine[edge];
                if key(q) == first {
                    break;
                }
                ring.push(q);
                // the edge leaving q first met turning clockwise from q → p
                let back = angle(q, p);
                let next = from.get(&key(q)).and_then(|v| {
                    v.iter().copied().filter(|&e| !used[e]).min_by(|&x, &y| {
                        let cw = |e: usize| {
                            (back - angle(mine[e].0, mine[e].1)).rem_euclid(std::f64::consts::TAU)
                        };
                        cw(x).total_cmp(&cw(y))
                    })
                });
                let Some(next) = next else {
                    break; // an open chain: kept as it is
                };
                used[next] = true;
                edge = next;
            }
            if crate::geometry::polygon::signed_area(&ring) < 0.0 {
                ring.reverse();
            }
            loops.push(ring);
        }
        loops.sort_by(|a, b| {
            let area = |r: &Vec<[f64; 2]>| crate::geometry::polygon::signed_area(r).abs();
            area(b).total_cmp(&area(a))
        });
    }
    out
}

/// Frame `index` of the run in `dir` coloured by `field`: see the module doc.
pub fn frame_scene(dir: &Path, index: usize, field: Field) -> Result<Scene, String> {
    Ok(frame_scene_in(dir, index, field, None)?.0)
}

/// [`frame_scene`] with the colour bar's range given (`range`: the lowest and highest
/// values, e.g. those of a whole sequence; None: the frame's own), and the frame's own
/// range of values returned beside the scene.
pub fn frame_scene_in(
    dir: &Path,
    index: usize,
    field: Field,
    range: Option<(f64, f64)>,
) -> Result<(Scene, (f64, f64)), String> {
    let frame = read_frame(dir, index)?;
    let g = &frame.blocks;
    let values = cell_values(g, field)?;
    let own = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let (lo, hi) = match range {
        Some(r) if r.0 <= r.1 => r,
        _ if own.0 > own.1 => (0.0, 1.0),
        _ => own,
    };
    let (factor, unit) = unit(field, lo.abs().max(hi.abs()));
    let mut s = Scene {
        title: format!(
            "{} — {}t = {} s — {}",
            dir.display(),
            frame.step.map_or(String::new(), |k| format!("step {k}, ")),
            frame.time,
            field.name()
        ),
        ..Scene::default()
    };
    let span = hi - lo;
    for (cell, v) in g.cells.iter().zip(&values) {
        let t = if span > 0.0 { (v - lo) / span } else { 0.5 };
        s.polygons.push(ScenePolygon {
            points: cell
                .iter()
                .map(|&p| (g.points[p][0], g.points[p][1]))
                .collect(),
            fill: Some((colour_map(t), 1.0)),
            outline: None,
        });
    }
    for (_, pa, pc) in outline_edges(g) {
        s.lines
            .push((vec![(pa[0], pa[1]), (pc[0], pc[1])], (0, 0, 0), 1));
    }
    s.colour_bar = Some((
        lo / factor,
        hi / factor,
        format!("{} ({unit})", field.name()),
    ));
    // contacts of the same step
    if let Some(c) = &frame.contacts {
        let states = c.cell_data.get("state").map(|(_, v)| v.clone());
        let mut seen = [false; 3];
        for (i, cell) in c.cells.iter().enumerate() {
            let st = states.as_ref().map_or(0, |v| v[i] as usize).min(2);
            seen[st] = true;
            let p = c.points[cell[0]];
            s.markers.push(SceneMarker {
                at: (p[0], p[1]),
                shape: MarkerShape::Circle,
                colour: [GREY, (44, 160, 44), RED][st],
                size: 3,
            });
        }
        for (k, name) in ["contact open", "contact stick", "contact slide"]
            .iter()
            .enumerate()
        {
            if seen[k] {
                s.legend
                    .push((name.to_string(), [GREY, (44, 160, 44), RED][k]));
            }
        }
    }
    bolt_lines(dir, frame.step, &mut s)?;
    Ok((s, own))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A grid of cells of the given blocks (each cell with its own copies of its points).
    fn grid(cells: &[(usize, Vec<[f64; 2]>)]) -> ReadGrid {
        let mut g = ReadGrid::default();
        let mut blocks = Vec::new();
        for (b, pts) in cells {
            let first = g.points.len();
            g.points.extend(pts);
            g.cells.push((first..first + pts.len()).collect());
            blocks.push(*b as f64);
        }
        g.cell_data.insert("block".into(), (1, blocks));
        g
    }

    #[test]
    fn outlines_join_the_unshared_edges_of_each_block() {
        // block 0: a unit square as two triangles; block 1: a triangle touching it along
        // x = 1 (an edge of another block is still an outline)
        let g = grid(&[
            (0, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]),
            (0, vec![[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
            (1, vec![[1.0, 0.0], [2.0, 0.5], [1.0, 1.0]]),
        ]);
        assert_eq!(outline_edges(&g).len(), 4 + 3);
        let o = block_outlines(&g);
        assert_eq!(o.len(), 2);
        assert_eq!(o[0].len(), 1, "one outline");
        let square = &o[0][0];
        assert_eq!(square.len(), 4);
        assert!((crate::geometry::polygon::signed_area(square) - 1.0).abs() < 1e-15);
        assert!((crate::geometry::polygon::signed_area(&o[1][0]) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn a_block_whose_elements_touch_at_a_point_has_two_outlines() {
        // two squares touching at (1, 1), the lower one as two triangles listed around the
        // upper one: at (1, 1) the upper square's edge is found first, and following it
        // would walk a figure of eight
        let g = grid(&[
            (0, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]),
            (0, vec![[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]]),
            (0, vec![[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]),
        ]);
        let o = block_outlines(&g);
        assert_eq!(o[0].len(), 2, "{:?}", o[0]);
        assert_eq!((o[0][0].len(), o[0][1].len()), (4, 4));
        // the largest first, both counter-clockwise
        let areas: Vec<f64> = o[0]
            .iter()
            .map(|r| crate::geometry::polygon::signed_area(r))
            .collect();
        assert!((areas[0] - 4.0).abs() < 1e-15 && (areas[1] - 1.0).abs() < 1e-15);
    }
}
