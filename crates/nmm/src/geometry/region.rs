//! A region: a simple polygon with holes, as the loops that bound it. The boundary of a
//! block is such a list of loops (the outer one first, then one per hole), and every
//! loop is oriented with the material on its **left**: the outer loop counter-clockwise,
//! each hole clockwise. So the outward normal of every boundary edge is its direction
//! turned clockwise, on every loop alike (the convention of [`crate::contact::narrow`]).
//!
//! Edges are numbered over the loops in order: the outer loop's edges first (edge `i`
//! joins vertex `i` to vertex `i + 1` of that loop, the last closing it), then each
//! hole's. [`Region::loop_of_edge`] maps a global edge index back to (loop, edge in loop).
//!
//! Predicates take the absolute length tolerance `tol` of [`super::polygon`].

// `!(x > tol)` is deliberate throughout: a NaN fails the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use super::polygon::{
    boundary_distance, edge, point_in_polygon, push_cuts, segment_boundary_intervals,
    segment_on_boundary, Location,
};
use super::{dot, lerp, sub, Aabb, Vec2};

/// A polygon with holes: `outer` (counter-clockwise) and `holes` (clockwise), each
/// without a repeated closing vertex.
#[derive(Debug, Clone, Copy)]
pub struct Region<'a> {
    pub outer: &'a [Vec2],
    pub holes: &'a [Vec<Vec2>],
}

impl<'a> Region<'a> {
    /// A region without holes.
    pub fn simple(outer: &'a [Vec2]) -> Region<'a> {
        Region { outer, holes: &[] }
    }

    /// The loops: the outer one, then the holes.
    pub fn loops(&self) -> impl Iterator<Item = &'a [Vec2]> + 'a {
        std::iter::once(self.outer).chain(self.holes.iter().map(|h| h.as_slice()))
    }

    /// Number of edges over all loops.
    pub fn edge_count(&self) -> usize {
        self.loops().map(<[Vec2]>::len).sum()
    }

    /// The (loop, edge within the loop) of global edge `e` (loops in order, outer first).
    pub fn loop_of_edge(&self, mut e: usize) -> Option<(usize, usize)> {
        for (k, l) in self.loops().enumerate() {
            if e < l.len() {
                return Some((k, e));
            }
            e -= l.len();
        }
        None
    }

    /// Where `p` lies: within `tol` of any loop is the boundary; inside the outer loop
    /// and outside every hole is inside.
    pub fn locate(&self, p: Vec2, tol: f64) -> Location {
        match point_in_polygon(self.outer, p, tol) {
            Location::Inside => {}
            other => return other,
        }
        for h in self.holes {
            match point_in_polygon(h, p, tol) {
                Location::Inside => return Location::Outside,
                Location::Boundary => return Location::Boundary,
                Location::Outside => {}
            }
        }
        Location::Inside
    }

    /// Distance from `p` to the nearest loop.
    pub fn boundary_distance(&self, p: Vec2) -> f64 {
        self.loops()
            .map(|l| boundary_distance(l, p))
            .fold(f64::INFINITY, f64::min)
    }

    /// Area: the outer loop's less the holes'.
    pub fn area(&self) -> f64 {
        self.loops().map(super::polygon::signed_area).sum()
    }

    /// Centroid of the region (the loops' first moments, holes counting negative).
    pub fn centroid(&self) -> Vec2 {
        let o = self.outer.first().copied().unwrap_or([0.0; 2]);
        let (mut a, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for l in self.loops() {
            let m = super::moments::polygon_moments(l, o);
            a += m.area;
            sx += m.sx;
            sy += m.sy;
        }
        if a != 0.0 {
            [o[0] + sx / a, o[1] + sy / a]
        } else {
            o
        }
    }

    /// Whether the segment `ab` lies along one loop of the boundary (within `tol`).
    pub fn segment_on_boundary(&self, a: Vec2, b: Vec2, tol: f64) -> bool {
        self.loops().any(|l| segment_on_boundary(l, a, b, tol))
    }

    /// The parts of `ab` along the boundary (any loop), as sorted disjoint parameter
    /// intervals (see [`segment_boundary_intervals`]).
    pub fn segment_boundary_intervals(&self, a: Vec2, b: Vec2, tol: f64) -> Vec<(f64, f64)> {
        let mut all: Vec<(f64, f64)> = self
            .loops()
            .flat_map(|l| segment_boundary_intervals(l, a, b, tol))
            .collect();
        all.sort_by(|x, y| x.0.total_cmp(&y.0));
        let len = super::dist(a, b);
        let gap = if len > 0.0 { tol / len } else { 0.0 };
        let mut out: Vec<(f64, f64)> = Vec::new();
        for (lo, hi) in all {
            match out.last_mut() {
                Some(last) if lo <= last.1 + gap => last.1 = last.1.max(hi),
                _ => out.push((lo, hi)),
            }
        }
        out
    }

    /// Bounding box of the outer loop (holes lie inside it).
    pub fn bbox(&self) -> Aabb {
        Aabb::of_points(self.outer)
    }
}

/// The index after `i` in a list of `n` points holding loops that start at `starts`
/// (sorted, the first 0; empty or `[0]`: one loop): the next point of `i`'s loop.
#[inline]
pub fn loop_next(starts: &[usize], n: usize, i: usize) -> usize {
    if starts.len() <= 1 {
        return (i + 1) % n;
    }
    let k = starts.partition_point(|&s| s <= i) - 1;
    let end = starts.get(k + 1).copied().unwrap_or(n);
    if i + 1 == end {
        starts[k]
    } else {
        i + 1
    }
}

/// The index before `i` (see [`loop_next`]).
#[inline]
pub fn loop_prev(starts: &[usize], n: usize, i: usize) -> usize {
    if starts.len() <= 1 {
        return (i + n - 1) % n;
    }
    let k = starts.partition_point(|&s| s <= i) - 1;
    let end = starts.get(k + 1).copied().unwrap_or(n);
    if i == starts[k] {
        end - 1
    } else {
        i - 1
    }
}

/// Whether two regions overlap with positive area (beyond `tol`): touching along an edge
/// or at a point, or one lying in a hole of the other, is not overlap. The method of
/// [`super::polygon::polygons_overlap`] on every loop: each edge is split where the other
/// region's loops meet it; a piece whose midpoint is strictly inside the other region
/// means overlap, and so do two boundaries lying entirely on each other (the same region).
pub fn regions_overlap(p: Region, q: Region, tol: f64) -> bool {
    if p.outer.len() < 3 || q.outer.len() < 3 {
        return false;
    }
    if p.holes.is_empty() && q.holes.is_empty() {
        return super::polygon::polygons_overlap(p.outer, q.outer, tol);
    }
    if !p.bbox().inflate(-tol).overlaps(&q.bbox()) {
        return false;
    }
    let (p_in_q, p_all_on) = classify(p, q, tol);
    if p_in_q {
        return true;
    }
    let (q_in_p, q_all_on) = classify(q, p, tol);
    q_in_p || (p_all_on && q_all_on)
}

/// Split each edge of `p`'s loops at `q`'s loops and classify the pieces against `q`:
/// (some piece strictly inside q, every piece on q's boundary).
fn classify(p: Region, q: Region, tol: f64) -> (bool, bool) {
    let mut all_on = true;
    let mut cuts: Vec<f64> = Vec::new();
    for pl in p.loops() {
        for i in 0..pl.len() {
            let (a, b) = edge(pl, i);
            let ab = sub(b, a);
            let l2 = dot(ab, ab);
            if !(l2 > 0.0) {
                continue;
            }
            cuts.clear();
            cuts.push(0.0);
            cuts.push(1.0);
            for ql in q.loops() {
                push_cuts(a, b, ql, tol, &mut cuts);
            }
            cuts.sort_by(f64::total_cmp);
            for w in cuts.windows(2) {
                let (t0, t1) = (w[0], w[1]);
                if !(t1 > t0) {
                    continue;
                }
                match q.locate(lerp(a, b, 0.5 * (t0 + t1)), tol) {
                    Location::Inside => return (true, false),
                    Location::Outside => all_on = false,
                    Location::Boundary => {}
                }
            }
        }
    }
    (false, all_on)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: f64 = 1e-9;

    fn square(x0: f64, y0: f64, s: f64) -> Vec<Vec2> {
        vec![[x0, y0], [x0 + s, y0], [x0 + s, y0 + s], [x0, y0 + s]]
    }

    fn cw(mut p: Vec<Vec2>) -> Vec<Vec2> {
        p.reverse();
        p
    }

    #[test]
    fn a_square_with_a_square_hole() {
        let outer = square(0.0, 0.0, 4.0);
        let holes = vec![cw(square(1.0, 1.0, 2.0))];
        let r = Region {
            outer: &outer,
            holes: &holes,
        };
        assert_eq!(r.area(), 12.0);
        assert_eq!(r.centroid(), [2.0, 2.0]);
        assert_eq!(r.edge_count(), 8);
        assert_eq!(r.loop_of_edge(5), Some((1, 1)));
        assert_eq!(r.loop_of_edge(8), None);
        assert_eq!(r.locate([0.5, 0.5], TOL), Location::Inside);
        assert_eq!(r.locate([2.0, 2.0], TOL), Location::Outside);
        assert_eq!(r.locate([1.0, 2.0], TOL), Location::Boundary);
        assert_eq!(r.locate([5.0, 2.0], TOL), Location::Outside);
        assert!(r.segment_on_boundary([1.0, 1.5], [1.0, 2.5], TOL));
        assert!(!r.segment_on_boundary([0.5, 1.5], [0.5, 2.5], TOL));
        // a hole off-centre moves the centroid away from it
        let holes = vec![cw(square(2.0, 1.0, 2.0))];
        let r = Region {
            outer: &outer,
            holes: &holes,
        };
        let c = r.centroid();
        assert!(
            (c[0] - (16.0 * 2.0 - 4.0 * 3.0) / 12.0).abs() < 1e-14,
            "{c:?}"
        );
        assert!((c[1] - 2.0).abs() < 1e-14);
    }

    #[test]
    fn next_and_previous_on_loops() {
        // loops [0, 1, 2, 3], [4, 5, 6]
        let s = [0, 4];
        let next: Vec<usize> = (0..7).map(|i| loop_next(&s, 7, i)).collect();
        assert_eq!(next, [1, 2, 3, 0, 5, 6, 4]);
        let prev: Vec<usize> = (0..7).map(|i| loop_prev(&s, 7, i)).collect();
        assert_eq!(prev, [3, 0, 1, 2, 6, 4, 5]);
        assert_eq!(loop_next(&[0], 3, 2), 0);
        assert_eq!(loop_prev(&[], 3, 0), 2);
    }

    #[test]
    fn a_plug_in_the_hole_does_not_overlap_its_rock() {
        let outer = square(0.0, 0.0, 4.0);
        let holes = vec![cw(square(1.0, 1.0, 2.0))];
        let rock = Region {
            outer: &outer,
            holes: &holes,
        };
        let plug = square(1.0, 1.0, 2.0);
        assert!(!regions_overlap(rock, Region::simple(&plug), TOL));
        assert!(!regions_overlap(Region::simple(&plug), rock, TOL));
        // a smaller block in the hole, and one across the hole's wall
        let small = square(1.5, 1.5, 0.5);
        assert!(!regions_overlap(rock, Region::simple(&small), TOL));
        let across = square(0.5, 1.5, 1.0);
        assert!(regions_overlap(rock, Region::simple(&across), TOL));
        // a solid block over the whole rock overlaps it; so does the rock with itself
        assert!(regions_overlap(rock, Region::simple(&outer), TOL));
        assert!(regions_overlap(rock, rock, TOL));
        // a block beside the rock, touching it along an edge
        let beside = square(4.0, 0.0, 4.0);
        assert!(!regions_overlap(rock, Region::simple(&beside), TOL));
    }
}
