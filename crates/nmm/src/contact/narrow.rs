//! Narrow phase: vertex–edge contact detection between two closed polylines
//! (geometry only, no physics).
//!
//! Both polylines are closed and counter-clockwise (CCW), without a repeated
//! closing vertex. Segment `j` of `B` runs from `b[j]` to `b[(j+1) % n]`. A block with
//! holes has several loops ([`Outline::new`]): each with the material on
//! its left (the holes clockwise), one after the other in the list, segment `j` running
//! to the next vertex of its own loop; everything below holds loop by loop.
//!
//! # Conventions
//! * `tangent t = (b[j+1] − b[j]) / L`, unit, along the segment;
//! * `normal n = (t_y, −t_x)`: the outward unit normal of `B` (right of a CCW edge);
//! * `gap = (P − b[j])·n`, the signed distance of `A`'s vertex `P` to the line of
//!   the segment: **negative = penetration** (the `g_N` of `friction.rs`);
//! * `ξ = (P − b[j])·t / L`, reported clamped to `[0, 1]`.
//!
//! # Rules (for each vertex `P = a[i]` of `A`, at most one segment of `B`)
//! 1. *Reach*: the segment's strip holds `P`: `ξ L ∈ [−τ, L + τ]` with the end
//!    tolerance `τ = end_tolerance` if `P` is a corner of `A` and a round-off
//!    tolerance (`1e-9 L`) otherwise; and `gap ∈ [−max_penetration, search]`.
//!    A vertex beyond the ends of a segment (by more than `τ`) is not in contact
//!    with it. A non-corner vertex (a refined point of a straight edge of `A`)
//!    gets no end tolerance: near a corner of `B` the contact there is `B`'s
//!    vertex on `A`'s edge, found by the call with the roles swapped.
//! 2. *Side*: `gap < 0` only if `P` is inside `B`, `gap > 0` only if outside.
//!    Inside/outside is decided locally from the nearest boundary feature of
//!    `B` (its normal, or at a vertex the sum of the two adjacent normals, the
//!    2-D pseudo-normal), which is exact for simple polygons and needed near
//!    reflex corners of a non-convex `B`. Exception (*face overlap*): a corner of `A`
//!    outside `B` by less than `CORNER_SIDE` × the reach (and at most `CORNER_SIDE_MAX` × the
//!    size of `B`: a hair, not a wide search's reach) keeps a penetrating candidate
//!    segment when an edge of `A` at the corner runs along that segment (parallel
//!    within the fit angle) back into its extent. Two blocks whose faces meet corner to
//!    corner (the voussoirs of an arch at its extrados and intrados) leave, once they
//!    deform, each corner a hair outside the other block and across the other's face:
//!    the faces overlap in a sliver between the corners, and dropping those contacts
//!    would leave the joint without its hinge. A corner passing around a corner of `B`
//!    (its edges leaving the segment's extent) is not in that case.
//! 3. *Fit* (the DDA angle condition): the wedge of `A` at `P` must lie on the
//!    outer side of the segment's line, within the angle `fit_angle`:
//!    `u·n ≥ −sin(fit_angle)` for both unit directions `u` from `P` to its
//!    neighbours. A non-corner vertex thus only touches nearly parallel edges;
//!    reflex (concave) vertices of `A` never make vertex–edge contact.
//! 4. *Entrance edge* (vertex–vertex: `P` near a vertex of `B`, several segments
//!    pass 1–3): a segment whose line `P` is deeper inside than the shallowest
//!    candidate's by more than a third of `max_penetration` is not the one it came
//!    through, and is passed over (`ENTRANCE_SLACK`); then the segment whose outward
//!    normal best opposes the outward
//!    direction `d` of `A` at `P` — for a corner, the exterior bisector
//!    `normalize(n_prev + n_next)` of `A`'s two adjacent edge normals, for a
//!    non-corner vertex the normal of the straight edge through it (the same
//!    formula) — i.e. the smallest `n·d`. If two segments tie (within 0.02 in
//!    `n·d`, e.g. a square corner against a square corner), the one whose strip
//!    holds `P` deepest (largest `min(ξL, (1−ξ)L)`) wins: for a penetrating
//!    vertex at a square corner this is the edge of *smallest penetration*, the
//!    one the vertex came through, as in DDA. If `P` is *at* a vertex of `B` (both
//!    depths equal within round-off: faces that meet vertex for vertex, a plug in
//!    its hole, the faces of a cut block), the segment along which `A`'s own edges
//!    at `P` run furthest (parallel within `fit_angle`, projected and clipped to the
//!    segment) wins: the contact then stands for the interface it mostly carries.
//!    Left to the order of `B`'s segments, a corner of `A` whose edge on one side
//!    runs only to a refinement point of `B` just past the corner (a mesh line or a
//!    joint crossing the face 10⁻³–10⁻² of its length from the corner) took that
//!    short segment: its tributary length, and so its springs, 10⁻³–10⁻¹ of the
//!    other's, and under in-situ stress its force (mostly from the long edge, normal
//!    to the *other* face) at about 45° to its normal at an octagon's corner, beyond
//!    friction: the contact slid and the model moved (`tests/tunnel.rs`).
//!
//! For long polylines `B`, segments are bucketed per call in a uniform grid of
//! cells (a sorted list of `(cell, segment)` keys), so each vertex query costs
//! `O(log n + local segments)`.

use crate::geometry::{cross, dot, norm, scale, sub, Aabb, Vec2};

/// One vertex of `A` against one segment of `B`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexEdge {
    /// Index of the vertex in `A`.
    pub vertex: usize,
    /// Index of the segment in `B` (from `b[segment]` to `b[segment + 1]`).
    pub segment: usize,
    /// Position of the projection along the segment, clamped to `[0, 1]`.
    pub xi: f64,
    /// Signed distance to the segment's line; negative = penetration.
    pub gap: f64,
    /// Outward unit normal of the segment (points out of `B`).
    pub normal: Vec2,
    /// Unit direction of the segment.
    pub tangent: Vec2,
}

/// How much deeper than a vertex's shallowest candidate face another may lie and still be
/// its entrance face, as a fraction of the largest penetration reported (rule 4): the
/// penetration reported is a few motions of a step, the entrance face's at most one.
const ENTRANCE_SLACK: f64 = 1.0 / 3.0;

/// Tolerances of the detection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NarrowParams {
    /// Largest positive gap reported (contact search distance).
    pub search: f64,
    /// Largest penetration reported.
    pub max_penetration: f64,
    /// How far beyond a segment's ends a *corner* of `A` may lie.
    pub end_tolerance: f64,
    /// Angle tolerance (radians) of the wedge-fit test.
    pub fit_angle: f64,
}

impl NarrowParams {
    /// The largest distance from `B` at which any rule can accept a vertex.
    pub fn reach(&self) -> f64 {
        self.search.max(0.0).max(self.max_penetration.max(0.0)) + self.end_tolerance.max(0.0)
    }

    /// Defaults: `max_penetration = end_tolerance = search`, `fit_angle = 20°`.
    pub fn new(search: f64) -> Self {
        NarrowParams {
            search,
            max_penetration: search,
            end_tolerance: search,
            fit_angle: 20f64.to_radians(),
        }
    }
}

/// Vertex–edge contacts of `A`'s vertices on `B`'s segments, with the default
/// tolerances of [`NarrowParams::new`]. `corner_a[i]` says whether vertex `i` of
/// `A` is a polygon corner (a missing entry counts as a corner).
pub fn vertex_edge_contacts(
    a: &[Vec2],
    b: &[Vec2],
    search: f64,
    corner_a: &[bool],
) -> Vec<VertexEdge> {
    vertex_edge_contacts_with(a, b, corner_a, &NarrowParams::new(search))
}

/// The loops of a polyline: the first vertex of each (empty or `[0]`: one loop).
#[derive(Clone, Copy)]
struct Loops<'a> {
    starts: &'a [usize],
    n: usize,
}

impl Loops<'_> {
    #[cfg(test)]
    fn one(n: usize) -> Self {
        Loops { starts: &[], n }
    }
    #[inline]
    fn next(&self, i: usize) -> usize {
        crate::geometry::region::loop_next(self.starts, self.n, i)
    }
    #[inline]
    fn prev(&self, i: usize) -> usize {
        crate::geometry::region::loop_prev(self.starts, self.n, i)
    }
}

/// Corner flags of a closed polyline: vertex `i` is a corner when the
/// direction turns there by more than `angle` (radians) either way.
pub fn corner_flags(poly: &[Vec2], angle: f64) -> Vec<bool> {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let u = unit(sub(poly[i], poly[(i + n - 1) % n]));
            let v = unit(sub(poly[(i + 1) % n], poly[i]));
            let turn = cross(u, v).atan2(dot(u, v));
            turn.abs() > angle
        })
        .collect()
}

#[inline]
fn unit(v: Vec2) -> Vec2 {
    let l = norm(v);
    if l > 0.0 {
        scale(v, 1.0 / l)
    } else {
        [0.0, 0.0]
    }
}

#[inline]
fn outward(t: Vec2) -> Vec2 {
    [t[1], -t[0]]
}

/// Segments of `B`, precomputed.
struct Segments {
    p0: Vec<Vec2>,
    t: Vec<Vec2>,
    len: Vec<f64>,
}

impl Segments {
    fn new(b: &[Vec2], lb: Loops) -> Self {
        let n = b.len();
        let mut s = Segments {
            p0: Vec::with_capacity(n),
            t: Vec::with_capacity(n),
            len: Vec::with_capacity(n),
        };
        for j in 0..n {
            let e = sub(b[lb.next(j)], b[j]);
            let l = norm(e);
            s.p0.push(b[j]);
            s.len.push(l);
            s.t.push(if l > 0.0 {
                scale(e, 1.0 / l)
            } else {
                [0.0, 0.0]
            });
        }
        s
    }
    fn normal(&self, j: usize) -> Vec2 {
        outward(self.t[j])
    }
}

/// Uniform grid over `B`'s segments: sorted `(cell key, segment)` pairs.
struct Grid {
    origin: Vec2,
    cell: f64,
    nx: u64,
    ny: u64,
    entries: Vec<(u64, u32)>,
}

impl Grid {
    fn new(b: &[Vec2], lb: Loops, seg: &Segments, bbox: &Aabb, reach: f64) -> Self {
        let n = seg.len.len();
        let mean = seg.len.iter().sum::<f64>() / n as f64;
        let diag = bbox.diagonal().max(f64::MIN_POSITIVE);
        let cell = mean.max(reach).max(diag * 1e-6).max(f64::MIN_POSITIVE);
        let origin = [bbox.min[0] - reach, bbox.min[1] - reach];
        let nx =
            (((bbox.max[0] - bbox.min[0] + 2.0 * reach) / cell).floor() as u64).saturating_add(1);
        let ny =
            (((bbox.max[1] - bbox.min[1] + 2.0 * reach) / cell).floor() as u64).saturating_add(1);
        let mut g = Grid {
            origin,
            cell,
            nx,
            ny,
            entries: Vec::with_capacity(4 * n),
        };
        for j in 0..n {
            let sb = Aabb::of_points(&[b[j], b[lb.next(j)]]).inflate(reach);
            let (x0, y0) = g.coords(sb.min);
            let (x1, y1) = g.coords(sb.max);
            for ix in x0..=x1 {
                for iy in y0..=y1 {
                    g.entries.push((ix * g.ny + iy, j as u32));
                }
            }
        }
        g.entries.sort_unstable();
        g
    }
    fn coords(&self, p: Vec2) -> (u64, u64) {
        let f = |v: f64, o: f64, n: u64| (((v - o) / self.cell).floor().max(0.0) as u64).min(n - 1);
        (
            f(p[0], self.origin[0], self.nx),
            f(p[1], self.origin[1], self.ny),
        )
    }
    fn query(&self, p: Vec2) -> &[(u64, u32)] {
        let (ix, iy) = self.coords(p);
        let k = ix * self.ny + iy;
        let lo = self.entries.partition_point(|e| e.0 < k);
        let hi = self.entries.partition_point(|e| e.0 <= k);
        &self.entries[lo..hi]
    }
}

/// Polylines with more segments than this get a grid.
const GRID_THRESHOLD: usize = 32;
/// Near-tie tolerance of the entrance rule, in `n·d`.
const TIE: f64 = 0.02;
/// A corner of A outside B by less than this fraction of the reach may still touch a
/// face it overlaps (rule 2).
const CORNER_SIDE: f64 = 0.1;
/// ... and by at most this fraction of B's size (the diagonal of its box).
const CORNER_SIDE_MAX: f64 = 1e-3;

/// Whether an edge of A at its vertex (unit directions `u_prev`, `u_next` to the
/// neighbours) runs along segment `j` of B, parallel within the fit angle, from the
/// vertex's arc length `s` back into the segment's extent: the two faces overlap.
fn edge_overlaps_face(seg: &Segments, j: usize, s: f64, u: [Vec2; 2], sin_fit: f64) -> bool {
    let t = seg.t[j];
    let l = seg.len[j];
    u.iter().any(|&u| {
        let along = dot(u, t);
        cross(u, t).abs() <= sin_fit
            && ((s > 0.5 * l && along < 0.0) || (s <= 0.5 * l && along > 0.0))
    })
}

struct Candidate {
    j: usize,
    s: f64,
    gap: f64,
}

/// As [`vertex_edge_contacts`], with explicit tolerances.
pub fn vertex_edge_contacts_with(
    a: &[Vec2],
    b: &[Vec2],
    corner_a: &[bool],
    prm: &NarrowParams,
) -> Vec<VertexEdge> {
    vertex_edge_contacts_of(&Outline::new(a, &[]), &Outline::new(b, &[]), corner_a, prm)
}

/// A closed polyline (of one loop or several) with what the narrow phase computes of it
/// whichever the other block is: its segments, its box, at each vertex the unit
/// directions to its neighbours and the turn there, and for a long polyline its grid of
/// segments for one reach ([`Outline::with_grid`]). Made once per block per detection and
/// shared by all of the block's pairs, as `A` and as `B` ([`vertex_edge_contacts_of`]);
/// the same numbers as computed pair by pair.
pub struct Outline<'a> {
    pts: &'a [Vec2],
    loops: Loops<'a>,
    seg: Segments,
    bbox: Aabb,
    /// At each vertex: (u_prev, u_next), the unit directions to its neighbours ...
    dirs: Vec<[Vec2; 2]>,
    /// ... and the signed angle from the incoming direction to the outgoing one (below
    /// −fit angle: a reflex vertex, which never touches an edge with its tip).
    turn: Vec<f64>,
    /// The grid of the segments made for a reach (a polyline of more than
    /// `GRID_THRESHOLD` segments), used by the pairs whose rules reach as far.
    grid: Option<(f64, Grid)>,
}

impl<'a> Outline<'a> {
    /// The outline of the polyline `pts` whose loops start at `loops` (empty or `[0]`: one
    /// loop; see the module doc).
    pub fn new(pts: &'a [Vec2], loops: &'a [usize]) -> Self {
        let lp = Loops {
            starts: loops,
            n: pts.len(),
        };
        let (dirs, turn) = (0..pts.len())
            .map(|i| {
                let p = pts[i];
                let u_prev = unit(sub(pts[lp.prev(i)], p));
                let u_next = unit(sub(pts[lp.next(i)], p));
                let d_in = scale(u_prev, -1.0);
                (
                    [u_prev, u_next],
                    cross(d_in, u_next).atan2(dot(d_in, u_next)),
                )
            })
            .unzip();
        Outline {
            pts,
            loops: lp,
            seg: Segments::new(pts, lp),
            bbox: Aabb::of_points(pts),
            dirs,
            turn,
            grid: None,
        }
    }

    /// The outline with its grid of segments made now for the reach of `prm`'s rules (if
    /// the polyline is long enough to have one), for every pair that reaches as far: on a
    /// brick wall's base, which borders a whole row of bricks, the grid made for each of
    /// them was a quarter of the pairs' work (the 10×10 wall: 227 → 166 µs a detection).
    pub fn with_grid(mut self, prm: &NarrowParams) -> Self {
        if self.pts.len() > GRID_THRESHOLD {
            let reach = prm.reach();
            let g = Grid::new(self.pts, self.loops, &self.seg, &self.bbox, reach);
            self.grid = Some((reach, g));
        }
        self
    }
}

/// As [`vertex_edge_contacts_with`], of two outlines (of one loop or several).
pub fn vertex_edge_contacts_of(
    a: &Outline,
    b: &Outline,
    corner_a: &[bool],
    prm: &NarrowParams,
) -> Vec<VertexEdge> {
    detect(a, b, corner_a, prm, b.pts.len() > GRID_THRESHOLD)
}

fn detect(
    oa: &Outline,
    ob: &Outline,
    corner_a: &[bool],
    prm: &NarrowParams,
    use_grid: bool,
) -> Vec<VertexEdge> {
    let (a, la, b, lb) = (oa.pts, oa.loops, ob.pts, ob.loops);
    let (na, nb) = (a.len(), b.len());
    let mut out = Vec::new();
    if na < 3 || nb < 3 {
        return out;
    }
    let search = prm.search.max(0.0);
    let max_pen = prm.max_penetration.max(0.0);
    let end_tol = prm.end_tolerance.max(0.0);
    let sin_fit = prm.fit_angle.sin();
    let reach = prm.reach();
    let bbox_b = ob.bbox;
    let outer = bbox_b.inflate(reach);
    let seg = &ob.seg;
    let scale_b = bbox_b.diagonal();
    let on_tol = 1e-12 * scale_b;
    let corner_tol = (CORNER_SIDE * reach).min(CORNER_SIDE_MAX * scale_b);
    // the outline's grid where it was made for this reach (bit for bit), else one made now
    let made;
    let grid = match (&ob.grid, use_grid) {
        (Some((r, g)), true) if r.to_bits() == reach.to_bits() => Some(g),
        (_, true) => {
            made = Grid::new(b, lb, seg, &bbox_b, reach);
            Some(&made)
        }
        (_, false) => None,
    };
    let all: Vec<(u64, u32)> = if grid.is_none() {
        (0..nb as u32).map(|j| (0, j)).collect()
    } else {
        Vec::new()
    };

    let mut cands: Vec<Candidate> = Vec::new();
    for i in 0..na {
        let p = a[i];
        if !outer.overlaps(&Aabb { min: p, max: p }) {
            continue;
        }
        let is_corner = corner_a.get(i).copied().unwrap_or(true);
        let [u_prev, u_next] = oa.dirs[i];
        // Reflex vertices of A (beyond the fit tolerance) never touch an edge with their tip.
        if oa.turn[i] < -prm.fit_angle {
            continue;
        }
        let tol_end = if is_corner { end_tol } else { 0.0 };
        let list: &[(u64, u32)] = match grid {
            Some(g) => g.query(p),
            None => &all,
        };
        cands.clear();
        // Nearest boundary feature: (distance, segment, clamped arc length).
        let mut nearest = (f64::INFINITY, usize::MAX, 0.0);
        for &(_, j) in list {
            let j = j as usize;
            let l = seg.len[j];
            if l <= on_tol {
                continue;
            }
            let w = sub(p, seg.p0[j]);
            let t = seg.t[j];
            let n = outward(t);
            let s = dot(w, t);
            let gap = dot(w, n);
            let sc = s.clamp(0.0, l);
            let d = norm(sub(w, scale(t, sc)));
            if d < nearest.0 {
                nearest = (d, j, sc);
            }
            let tol = tol_end + 1e-9 * l;
            if s < -tol || s > l + tol || gap < -max_pen || gap > search {
                continue;
            }
            if dot(u_prev, n) < -sin_fit || dot(u_next, n) < -sin_fit {
                continue;
            }
            cands.push(Candidate { j, s, gap });
        }
        if cands.is_empty() || nearest.0 > reach {
            continue;
        }
        let inside = is_inside(seg, (b, lb), p, nearest);
        // a corner a hair outside B still touches a face it overlaps: rule 2's exception
        let overlap = is_corner && !inside && nearest.0 <= corner_tol;
        cands.retain(|c| {
            c.gap.abs() <= on_tol
                || (c.gap < 0.0) == inside
                || (overlap && edge_overlaps_face(seg, c.j, c.s, [u_prev, u_next], sin_fit))
        });
        // a vertex comes through the face it is nearest to: a candidate deeper inside B than
        // the shallowest by more than a step's motion is another face's line (rule 4)
        if cands.len() > 1 {
            let shallow = cands
                .iter()
                .map(|c| c.gap.abs())
                .fold(f64::INFINITY, f64::min);
            let slack = ENTRANCE_SLACK * max_pen;
            cands.retain(|c| c.gap >= 0.0 || -c.gap <= shallow + slack);
        }
        let d_a = exterior_direction(u_prev, u_next);
        let (q_prev, q_next) = (a[la.prev(i)], a[la.next(i)]);
        let best = cands.iter().min_by(|x, y| {
            let sx = dot(seg.normal(x.j), d_a);
            let sy = dot(seg.normal(y.j), d_a);
            if (sx - sy).abs() > TIE {
                return sx.total_cmp(&sy);
            }
            let dx = x.s.min(seg.len[x.j] - x.s);
            let dy = y.s.min(seg.len[y.j] - y.s);
            if (dx - dy).abs() > on_tol {
                return dy.total_cmp(&dx);
            }
            // P at a vertex of B (the faces meet vertex for vertex): the segment along
            // which A's own edges at P run furthest
            let ox = along(seg, x, p, [q_prev, q_next], sin_fit);
            let oy = along(seg, y, p, [q_prev, q_next], sin_fit);
            oy.total_cmp(&ox)
        });
        if let Some(c) = best {
            out.push(VertexEdge {
                vertex: i,
                segment: c.j,
                xi: (c.s / seg.len[c.j]).clamp(0.0, 1.0),
                gap: c.gap,
                normal: seg.normal(c.j),
                tangent: seg.t[c.j],
            });
        }
    }
    out
}

/// How far A's edges from its vertex `p` to its neighbours `q` run along the candidate
/// segment (rule 4 at a vertex of B): the projections on the segment of those parallel
/// to it within the fit angle, clipped to it.
fn along(seg: &Segments, c: &Candidate, p: Vec2, q: [Vec2; 2], sin_fit: f64) -> f64 {
    let (t, l) = (seg.t[c.j], seg.len[c.j]);
    q.iter()
        .map(|&q| {
            let d = sub(q, p);
            let len = norm(d);
            if len == 0.0 || cross(scale(d, 1.0 / len), t).abs() > sin_fit {
                return 0.0;
            }
            let (s0, s1) = (c.s, c.s + dot(d, t));
            (s0.max(s1).min(l) - s0.min(s1).max(0.0)).max(0.0)
        })
        .sum()
}

/// Outward direction of `A` at a vertex with unit directions `u_prev`, `u_next`
/// to its neighbours: the normalised sum of the two adjacent outward edge
/// normals (exterior bisector; for a straight vertex the edge normal).
fn exterior_direction(u_prev: Vec2, u_next: Vec2) -> Vec2 {
    // Edge (prev → P) has direction −u_prev, edge (P → next) has direction u_next.
    let n1 = outward(scale(u_prev, -1.0));
    let n2 = outward(u_next);
    unit([n1[0] + n2[0], n1[1] + n2[1]])
}

/// Is `p` inside `B`, judged from its nearest boundary feature
/// `(distance, segment, arc length of the nearest point)`?
fn is_inside(
    seg: &Segments,
    (b, lb): (&[Vec2], Loops),
    p: Vec2,
    nearest: (f64, usize, f64),
) -> bool {
    let (_, j, sc) = nearest;
    let l = seg.len[j];
    let (v, m) = if sc <= 0.0 {
        let jp = lb.prev(j);
        (
            b[j],
            [
                seg.normal(jp)[0] + seg.normal(j)[0],
                seg.normal(jp)[1] + seg.normal(j)[1],
            ],
        )
    } else if sc >= l {
        let jn = lb.next(j);
        (
            b[jn],
            [
                seg.normal(j)[0] + seg.normal(jn)[0],
                seg.normal(j)[1] + seg.normal(jn)[1],
            ],
        )
    } else {
        (b[j], seg.normal(j))
    };
    dot(sub(p, v), m) < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Rule 4 passes over a candidate face whose line the vertex is deeper inside than its
    /// shallowest candidate by more than a third of the largest penetration: the corner of
    /// A rests 10 µm inside B's right face, 2.1 cm inside the line of B's chamfer
    /// next to it (within the chamfer's end tolerance); the chamfer's normal opposes A's
    /// corner best, and was chosen before (a penalty force on 2.1 cm).
    #[test]
    fn a_vertex_enters_through_the_face_it_is_nearest_to() {
        let b = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.9], [0.9, 1.0], [0.0, 1.0]];
        let p = [0.99999, 0.87];
        let a = [p, [1.3, 0.87], [1.3, 1.164], [1.06, 1.164]];
        // the corner's contact with a search (and largest penetration) of `search`
        let corner = |search: f64| {
            vertex_edge_contacts_with(&a, &b, &[true; 4], &NarrowParams::new(search))
                .into_iter()
                .find(|c| c.vertex == 0)
                .expect("the corner touches")
        };
        let c = corner(0.03);
        assert_eq!(c.segment, 1, "{c:?}");
        assert_relative_eq!(c.gap, -1e-5, max_relative = 1e-6);
        // with a larger penetration allowed the chamfer is within the slack: its normal
        // (rule 4's normal criterion) decides, as before
        let c = corner(0.1);
        assert_eq!(c.segment, 2, "{c:?}");
        assert!((c.gap + 0.0212).abs() < 1e-3, "{}", c.gap);
    }

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }

    /// Rectangle with `k` equally spaced refined points per edge, and its corner flags.
    fn refined_rect(x0: f64, y0: f64, x1: f64, y1: f64, k: usize) -> (Vec<Vec2>, Vec<bool>) {
        let c = rect(x0, y0, x1, y1);
        let mut pts = Vec::new();
        let mut corner = Vec::new();
        for e in 0..4 {
            let (p, q) = (c[e], c[(e + 1) % 4]);
            for m in 0..=k {
                let s = m as f64 / (k + 1) as f64;
                pts.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
                corner.push(m == 0);
            }
        }
        (pts, corner)
    }

    #[test]
    fn corner_flags_of_refined_rectangle() {
        let (p, c) = refined_rect(0.0, 0.0, 2.0, 1.0, 3);
        assert_eq!(corner_flags(&p, 1e-3), c);
    }

    #[test]
    fn block_resting_on_block_flat_face() {
        // A (1 × 0.5) centred on B (3 × 1), lifted by g = 1e-4; 3 refined points per edge.
        let g = 1e-4;
        let (a, ca) = refined_rect(1.0, 1.0 + g, 2.0, 1.5 + g, 3);
        let (b, _) = refined_rect(0.0, 0.0, 3.0, 1.0, 3);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &ca);
        // The bottom edge of A: corners 0 and 4 (= first of the next edge) and refined 1..3.
        let verts: Vec<usize> = c.iter().map(|v| v.vertex).collect();
        assert_eq!(verts, vec![0, 1, 2, 3, 4]);
        for v in &c {
            assert_relative_eq!(v.gap, g, epsilon = 1e-12);
            assert_eq!(v.normal, [0.0, 1.0]);
            assert_eq!(v.tangent, [-1.0, 0.0]);
            // B's top edge is edge 2, refined into segments 8..12 running from x = 3 to x = 0.
            assert!((8..12).contains(&v.segment));
            let s = &b[v.segment];
            let e = &b[(v.segment + 1) % b.len()];
            let x = s[0] + v.xi * (e[0] - s[0]);
            assert_relative_eq!(x, a[v.vertex][0], epsilon = 1e-12);
        }
        // Penetrating by 2e-5 instead: the same vertices, negative gaps.
        let (a2, _) = refined_rect(1.0, 1.0 - 2e-5, 2.0, 1.5 - 2e-5, 3);
        let c2 = vertex_edge_contacts(&a2, &b, 1e-3, &ca);
        assert_eq!(c2.len(), 5);
        assert!(c2.iter().all(|v| (v.gap + 2e-5).abs() < 1e-12));
        // B's vertices on A: only those under A's bottom edge, B's refined top points x = 1.5 (x = 0.75, 2.25 lie outside).
        let (_, cb) = refined_rect(0.0, 0.0, 3.0, 1.0, 3);
        let rev = vertex_edge_contacts(&b, &a, 1e-3, &cb);
        assert_eq!(rev.len(), 1);
        assert_eq!(b[rev[0].vertex], [1.5, 1.0]);
        assert_relative_eq!(rev[0].gap, g, epsilon = 1e-12);
        assert_eq!(rev[0].normal, [0.0, -1.0]);
    }

    #[test]
    fn corner_into_a_face() {
        // A square rotated 45°, its bottom corner 3e-5 into B's top face.
        let pen = 3e-5;
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let a = vec![
            [1.0, 1.0 - pen],
            [1.0 + r, 1.0 - pen + r],
            [1.0, 1.0 - pen + 2.0 * r],
            [1.0 - r, 1.0 - pen + r],
        ];
        let b = rect(0.0, 0.0, 2.0, 1.0);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].vertex, c[0].segment), (0, 2));
        assert_relative_eq!(c[0].gap, -pen, epsilon = 1e-14);
        assert_relative_eq!(c[0].xi, 0.5, epsilon = 1e-14);
        assert_eq!(c[0].normal, [0.0, 1.0]);
        // The face of B does not touch A's edges through its vertices (they are far away).
        assert!(vertex_edge_contacts(&b, &a, 1e-3, &[true; 4]).is_empty());
    }

    #[test]
    fn corner_to_corner_chooses_entrance_edge() {
        // B = unit square; A's bottom-left corner near B's top-right corner.
        let b = rect(0.0, 0.0, 1.0, 1.0);
        // Above-right, mostly above: it lands on the top edge (segment 2).
        let a = rect(1.0 + 1e-5, 1.0 + 4e-5, 2.0, 2.0);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].vertex, c[0].segment), (0, 2));
        assert_relative_eq!(c[0].gap, 4e-5, epsilon = 1e-15);
        assert_eq!(c[0].xi, 0.0);
        // Mostly to the right: the right edge (segment 1).
        let a = rect(1.0 + 4e-5, 1.0 + 1e-5, 2.0, 2.0);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!((c[0].vertex, c[0].segment), (0, 1));
        assert_relative_eq!(c[0].gap, 4e-5, epsilon = 1e-15);
        // Penetrated 1e-5 down and 4e-5 left: entered through the top (smallest penetration).
        let a = rect(1.0 - 4e-5, 1.0 - 1e-5, 2.0, 2.0);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].vertex, c[0].segment), (0, 2));
        assert_relative_eq!(c[0].gap, -1e-5, epsilon = 1e-15);
        // Stacked blocks with aligned corners: A's bottom-left corner on B's
        // top-left corner is on the top edge, never on B's left side.
        let a = rect(0.0, 1.0 + 1e-6, 1.0, 2.0);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!(
            c.iter().map(|v| (v.vertex, v.segment)).collect::<Vec<_>>(),
            vec![(0, 2), (1, 2)]
        );
        // Side by side, same course: A's left corners on B's right side.
        let a = rect(1.0 + 1e-6, 0.0, 2.0, 1.0);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!(
            c.iter().map(|v| (v.vertex, v.segment)).collect::<Vec<_>>(),
            vec![(0, 1), (3, 1)]
        );
        // A rotated CCW by 10° about its corner: the normal opposing the bisector best is the top.
        let (sn, cs) = 10f64.to_radians().sin_cos();
        let p0 = [1.0 + 1e-5, 1.0 + 1e-5];
        let a: Vec<Vec2> = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
            .iter()
            .map(|q| [p0[0] + cs * q[0] - sn * q[1], p0[1] + sn * q[0] + cs * q[1]])
            .collect();
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        assert_eq!((c[0].vertex, c[0].segment), (0, 2));
    }

    #[test]
    fn vertex_beyond_the_end_of_an_edge_is_excluded() {
        let b = rect(0.0, 0.0, 1.0, 1.0);
        // A's corner 0.1 beyond the end of B's top edge, 1e-4 above its line.
        let a = rect(1.1, 1.0 + 1e-4, 2.0, 2.0);
        assert!(vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]).is_empty());
        // A corner 5e-4 beyond the end, with an end tolerance of 1e-4.
        let a = rect(1.0 + 5e-4, 1.0 + 3e-4, 2.0, 2.0);
        let prm = NarrowParams {
            end_tolerance: 1e-4,
            ..NarrowParams::new(1e-3)
        };
        assert!(vertex_edge_contacts_with(&a, &b, &[true; 4], &prm).is_empty());
        // A refined (non-corner) vertex 1e-5 beyond the end gets no end tolerance.
        let y = 1.0 + 1e-4;
        let a = vec![[0.5, y], [1.0 + 1e-5, y], [2.0, y], [2.0, 2.0], [0.5, 2.0]];
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true, false, true, true, true]);
        assert_eq!(
            c.iter().map(|v| (v.vertex, v.segment)).collect::<Vec<_>>(),
            vec![(0, 2)]
        );
        // Flagged as a corner, it is in contact with the top edge at its end.
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 5]);
        assert_eq!(
            c.iter()
                .map(|v| (v.vertex, v.segment, v.xi))
                .collect::<Vec<_>>(),
            vec![(0, 2, 0.5), (1, 2, 0.0)]
        );
    }

    #[test]
    fn separated_blocks_beyond_search_distance() {
        let b = rect(0.0, 0.0, 1.0, 1.0);
        let a = rect(0.2, 1.0 + 2e-3, 0.8, 2.0);
        assert!(vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]).is_empty());
        assert_eq!(vertex_edge_contacts(&a, &b, 3e-3, &[true; 4]).len(), 2);
        // Deep penetration beyond max_penetration is not reported either.
        let a = rect(0.2, 1.0 - 2e-3, 0.8, 2.0);
        assert!(vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]).is_empty());
    }

    // L-shaped B, CCW; reflex corner at (1, 1); notch x > 1, y > 1.
    use crate::geometry::fixtures::l_shape;

    #[test]
    fn corner_in_the_notch_of_a_non_convex_b() {
        // A's corner 1e-4 from the vertical inner face (segment 3), 5e-4 above the horizontal one (2).
        let b = l_shape();
        let a = rect(1.0 + 1e-4, 1.0 + 5e-4, 1.5, 1.5);
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 4]);
        // Vertex 0 fits both faces and the bisector ties: the strip that holds it deeper wins.
        let got: Vec<_> = c.iter().map(|v| (v.vertex, v.segment)).collect();
        assert_eq!(got, vec![(0, 3), (1, 2), (3, 3)]);
        assert_relative_eq!(c[0].gap, 1e-4, epsilon = 1e-15);
        // A wedge poking through the vertical face, just above the reflex corner: inside B.
        let a = vec![[1.0 - 5e-4, 1.0 + 1e-4], [1.5, 1.0 + 1e-4], [1.5, 1.4]];
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true; 3]);
        let v0: Vec<_> = c.iter().filter(|v| v.vertex == 0).collect();
        assert_eq!((v0[0].segment, v0.len()), (3, 1));
        assert_relative_eq!(v0[0].gap, -5e-4, epsilon = 1e-15);
    }

    /// Rule 4 at a vertex of B: A's corner exactly at B's reflex corner (a plug in its
    /// notch, vertex for vertex), one of the faces refined 1e-4 from the corner on both
    /// blocks. The contact goes on the face A's long edge runs along, whichever comes
    /// first in B's list (left to the list's order, the second case took the tiny one).
    #[test]
    fn a_corner_at_a_corner_takes_the_face_its_long_edge_runs_along() {
        let e = 1e-4;
        // the vertical face refined: B's segment 3 is (1, 1) → (1, 1 + e)
        let b = vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 1.0 + e],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let a = vec![
            [1.0, 1.0],
            [1.5, 1.0],
            [1.5, 1.5],
            [1.0, 1.5],
            [1.0, 1.0 + e],
        ];
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true, true, true, true, false]);
        let v0: Vec<_> = c.iter().filter(|v| v.vertex == 0).collect();
        assert_eq!((v0.len(), v0[0].segment), (1, 2));
        // the horizontal face refined: B's segment 3 is (1 + e, 1) → (1, 1)
        let b = vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0 + e, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let a = vec![
            [1.0, 1.0],
            [1.0 + e, 1.0],
            [1.5, 1.0],
            [1.5, 1.5],
            [1.0, 1.5],
        ];
        let c = vertex_edge_contacts(&a, &b, 1e-3, &[true, false, true, true, true]);
        let v0: Vec<_> = c.iter().filter(|v| v.vertex == 0).collect();
        assert_eq!((v0.len(), v0[0].segment), (1, 4));
        assert_eq!(v0[0].normal, [1.0, 0.0]);
    }

    /// Crossing-number point-in-polygon, the reference for the local side test.
    fn crossing_inside(poly: &[Vec2], p: Vec2) -> bool {
        let n = poly.len();
        let mut inside = false;
        for i in 0..n {
            let (u, v) = (poly[i], poly[(i + 1) % n]);
            if (u[1] > p[1]) != (v[1] > p[1])
                && p[0] < u[0] + (p[1] - u[1]) / (v[1] - u[1]) * (v[0] - u[0])
            {
                inside = !inside;
            }
        }
        inside
    }

    #[test]
    fn local_side_test_matches_point_in_polygon() {
        let b = l_shape();
        let seg = Segments::new(&b, Loops::one(b.len()));
        let mut state = 12345u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..5000 {
            let p = [-0.2 + 2.4 * rnd(), -0.2 + 2.4 * rnd()];
            let mut nearest = (f64::INFINITY, 0, 0.0);
            for j in 0..b.len() {
                let w = sub(p, seg.p0[j]);
                let sc = dot(w, seg.t[j]).clamp(0.0, seg.len[j]);
                let d = norm(sub(w, scale(seg.t[j], sc)));
                if d < nearest.0 {
                    nearest = (d, j, sc);
                }
            }
            assert_eq!(
                is_inside(&seg, (&b, Loops::one(b.len())), p, nearest),
                crossing_inside(&b, p),
                "at {p:?}"
            );
        }
    }

    #[test]
    fn grid_and_brute_force_agree_on_long_polylines() {
        // B: a long refined rectangle (grid path); A: a block lying along its top face.
        let (b, _) = refined_rect(0.0, 0.0, 10.0, 1.0, 40);
        assert!(b.len() > GRID_THRESHOLD);
        let (a, ca) = refined_rect(3.0, 1.0 + 1e-5, 7.05, 2.0, 17);
        let prm = NarrowParams::new(1e-3);
        let fast = detect(
            &Outline::new(&a, &[]),
            &Outline::new(&b, &[]),
            &ca,
            &prm,
            true,
        );
        assert_eq!(
            fast,
            detect(
                &Outline::new(&a, &[]),
                &Outline::new(&b, &[]),
                &ca,
                &prm,
                false
            )
        );
        // B's grid made once (for every pair that reaches as far) finds the same
        let b_outline = Outline::new(&b, &[]).with_grid(&prm);
        assert!(b_outline.grid.is_some());
        assert_eq!(
            fast,
            vertex_edge_contacts_of(&Outline::new(&a, &[]), &b_outline, &ca, &prm)
        );
        // Every vertex of A's bottom edge: 2 corners and 17 refined points.
        assert_eq!(fast.len(), 19);
        for v in &fast {
            assert_relative_eq!(v.gap, 1e-5, epsilon = 1e-12);
        }
        // Other poses, including penetration, rotation and corners near B's corners.
        for (k, (dx, dy, th)) in [
            (-3.02, 0.0, 0.0),
            (5.96, -2e-4, 0.05),
            (2.0, 3e-4, -0.1),
            (-3.0, -1.0 - 1e-4, 0.0),
        ]
        .into_iter()
        .enumerate()
        {
            let (sn, cs) = f64::sin_cos(th);
            let moved: Vec<Vec2> = a
                .iter()
                .map(|p| {
                    [
                        3.0 + dx + cs * (p[0] - 3.0) - sn * (p[1] - 1.0),
                        1.0 + dy + sn * (p[0] - 3.0) + cs * (p[1] - 1.0),
                    ]
                })
                .collect();
            let g = detect(
                &Outline::new(&moved, &[]),
                &Outline::new(&b, &[]),
                &ca,
                &prm,
                true,
            );
            assert_eq!(
                g,
                detect(
                    &Outline::new(&moved, &[]),
                    &Outline::new(&b, &[]),
                    &ca,
                    &prm,
                    false
                ),
                "pose {k}"
            );
            assert_eq!(
                g,
                detect(
                    &Outline::new(&moved, &[]),
                    &Outline::new(&b, &[]),
                    &ca,
                    &prm,
                    true
                )
            );
        }
    }
}
