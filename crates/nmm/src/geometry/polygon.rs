//! Predicates on simple polygons: orientation, validity (degeneracy,
//! self-intersection), point location, boundary membership of segments and
//! overlap of two polygons. Pure geometry: no physics, no model types.
//!
//! Conventions (see also [`crate::geometry`]): a polygon is a vertex list
//! `[p0, p1, …, p(n−1)]` without a repeated closing vertex; edge `i` runs from
//! `p(i)` to `p((i+1) mod n)`. The signed area (shoelace formula)
//!
//! ```text
//! A = ½ Σᵢ (xᵢ y₍ᵢ₊₁₎ − x₍ᵢ₊₁₎ yᵢ)
//! ```
//!
//! is positive for a counter-clockwise (CCW) polygon.
//!
//! Every predicate takes an absolute length tolerance `tol` (m): two points
//! closer than `tol` coincide, a point closer than `tol` to the boundary is
//! *on* it. Callers typically use `tol = 1e-9 × (model size)`. Nothing here
//! panics on non-finite input; results for such input are unspecified but
//! defined (NaN comparisons are simply false).

// `!(x > tol)` is deliberate throughout: a NaN fails the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use super::{cross, dist, dot, lerp, norm, sub, Aabb, Vec2};

/// Signed area by the shoelace formula: positive when counter-clockwise.
pub fn signed_area(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    // Shift to the first vertex to reduce cancellation for far-off polygons.
    let o = poly[0];
    let mut twice = 0.0;
    for i in 1..n - 1 {
        twice += cross(sub(poly[i], o), sub(poly[i + 1], o));
    }
    0.5 * twice
}

/// `true` if the polygon is counter-clockwise (positive signed area).
pub fn is_ccw(poly: &[Vec2]) -> bool {
    signed_area(poly) > 0.0
}

/// Re-orient the polygon counter-clockwise in place (reversing the vertex
/// order if it is clockwise). Returns `true` if it was reversed.
pub fn orient_ccw(poly: &mut [Vec2]) -> bool {
    if signed_area(poly) < 0.0 {
        poly.reverse();
        true
    } else {
        false
    }
}

/// The edge `i` of a polygon: `(p(i), p(i+1 mod n))`.
#[inline]
pub fn edge(poly: &[Vec2], i: usize) -> (Vec2, Vec2) {
    let n = poly.len();
    (poly[i % n], poly[(i + 1) % n])
}

/// Euclidean distance from point `p` to the closed segment `ab`.
pub fn point_segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    if l2 <= 0.0 || l2.is_nan() {
        return dist(p, a);
    }
    let t = dot(sub(p, a), ab) / l2;
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    dist(p, lerp(a, b, t))
}

/// Distance from `p` to the polygon boundary (∞ for an empty polygon).
pub fn boundary_distance(poly: &[Vec2], p: Vec2) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = edge(poly, i);
            point_segment_distance(p, a, b)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Where a point lies with respect to a polygon.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// Strictly inside: farther than `tol` from the boundary.
    Inside,
    /// Within `tol` of the boundary.
    Boundary,
    Outside,
}

/// Locate `p` with respect to the polygon (either orientation): within `tol`
/// of the boundary is [`Location::Boundary`]; otherwise the crossing-number
/// rule decides between inside and outside.
pub fn point_in_polygon(poly: &[Vec2], p: Vec2, tol: f64) -> Location {
    if poly.len() < 3 {
        return Location::Outside;
    }
    if boundary_distance(poly, p) <= tol {
        return Location::Boundary;
    }
    let mut inside = false;
    for i in 0..poly.len() {
        let (a, b) = edge(poly, i);
        // Half-open rule on y avoids double-counting vertices.
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    if inside {
        Location::Inside
    } else {
        Location::Outside
    }
}

/// Why a polygon is degenerate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Degeneracy {
    /// Fewer than three vertices (the count is given).
    TooFewVertices(usize),
    /// Vertices `i` and `i+1 (mod n)` coincide (within `tol`).
    RepeatedVertex(usize),
    /// All vertices lie on one straight line (within `tol`).
    Collinear,
    /// The boundary turns back on itself at vertex `i`: edges `i−1` and `i`
    /// are collinear and point in opposite directions (a zero-width spike).
    FoldBack(usize),
    /// The enclosed area is zero (|A| ≤ tol × diameter).
    ZeroArea,
}

/// Check a polygon for degeneracy (not for self-intersection: see
/// [`self_intersection`]). Vertices are numbered from 0. A vertex in the
/// middle of a straight edge (collinear neighbours, same direction) is *not*
/// degenerate.
pub fn degeneracy(poly: &[Vec2], tol: f64) -> Option<Degeneracy> {
    let n = poly.len();
    if n < 3 {
        return Some(Degeneracy::TooFewVertices(n));
    }
    for i in 0..n {
        let (a, b) = edge(poly, i);
        if !(dist(a, b) > tol) {
            return Some(Degeneracy::RepeatedVertex(i));
        }
    }
    // All collinear: every vertex within tol of the line through the two
    // vertices farthest apart along the diameter of the bounding box.
    let bb = Aabb::of_points(poly);
    let diam = bb.diagonal();
    let (mut ia, mut ib, mut dmax) = (0, 0, -1.0);
    for i in 0..n {
        let d = dist(poly[0], poly[i]);
        if d > dmax {
            (ia, dmax) = (i, d);
        }
    }
    dmax = -1.0;
    for i in 0..n {
        let d = dist(poly[ia], poly[i]);
        if d > dmax {
            (ib, dmax) = (i, d);
        }
    }
    let (la, lb) = (poly[ia], poly[ib]);
    let len = dist(la, lb);
    if len > 0.0
        && poly
            .iter()
            .all(|&p| (cross(sub(lb, la), sub(p, la)) / len).abs() <= tol)
    {
        return Some(Degeneracy::Collinear);
    }
    for i in 0..n {
        let prev = poly[(i + n - 1) % n];
        let (cur, next) = (poly[i], poly[(i + 1) % n]);
        let (u, v) = (sub(cur, prev), sub(next, cur));
        let (lu, lv) = (norm(u), norm(v));
        // Sine of the turn angle times the shorter length: the offset of the
        // shorter edge's far end from the other edge's line.
        let offset = cross(u, v).abs() / lu.max(lv);
        if offset <= tol && dot(u, v) < 0.0 {
            return Some(Degeneracy::FoldBack(i));
        }
    }
    let area = signed_area(poly);
    if !(area.abs() > tol * diam) {
        return Some(Degeneracy::ZeroArea);
    }
    None
}

/// Distance between two closed segments `ab` and `cd` (0 if they cross).
pub fn segment_segment_distance(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> f64 {
    if segments_cross_properly(a, b, c, d) {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// `true` if the open segments `ab` and `cd` cross at a single point interior
/// to both (strict orientation tests, no tolerance).
pub fn segments_cross_properly(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let o1 = cross(sub(b, a), sub(c, a));
    let o2 = cross(sub(b, a), sub(d, a));
    let o3 = cross(sub(d, c), sub(a, c));
    let o4 = cross(sub(d, c), sub(b, c));
    ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
}

/// The first pair of edges `(i, j)`, `i < j`, that intersect where they
/// should not: non-adjacent edges closer than `tol` (crossing or touching),
/// or adjacent edges overlapping beyond their shared vertex. `None` for a
/// simple polygon. O(n²).
pub fn self_intersection(poly: &[Vec2], tol: f64) -> Option<(usize, usize)> {
    let n = poly.len();
    if n < 3 {
        return None;
    }
    let boxes: Vec<Aabb> = (0..n)
        .map(|i| {
            let (a, b) = edge(poly, i);
            Aabb::of_points(&[a, b]).inflate(tol)
        })
        .collect();
    for i in 0..n {
        let (a, b) = edge(poly, i);
        for j in i + 1..n {
            if !boxes[i].overlaps(&boxes[j]) {
                continue;
            }
            let (c, d) = edge(poly, j);
            if j == i + 1 {
                // Shared vertex b == c: they overlap if a far end lies on the other edge.
                if point_segment_distance(a, c, d) <= tol || point_segment_distance(d, a, b) <= tol
                {
                    return Some((i, j));
                }
            } else if i == 0 && j == n - 1 {
                // Shared vertex a == d.
                if point_segment_distance(b, c, d) <= tol || point_segment_distance(c, a, b) <= tol
                {
                    return Some((i, j));
                }
            } else if segment_segment_distance(a, b, c, d) <= tol {
                return Some((i, j));
            }
        }
    }
    None
}

/// `true` if the segment `ab` lies along the polygon boundary (within `tol`),
/// possibly spanning several consecutive collinear edges. A segment shorter
/// than `tol` is never on the boundary.
pub fn segment_on_boundary(poly: &[Vec2], a: Vec2, b: Vec2, tol: f64) -> bool {
    let ab = sub(b, a);
    let len = norm(ab);
    if !(len > tol) || poly.len() < 2 {
        return false;
    }
    let dir = [ab[0] / len, ab[1] / len];
    // Parameter intervals (in length units along ab) covered by edges lying on the line ab.
    let mut covered: Vec<(f64, f64)> = Vec::new();
    for i in 0..poly.len() {
        let (p, q) = edge(poly, i);
        let off_p = cross(dir, sub(p, a)).abs();
        let off_q = cross(dir, sub(q, a)).abs();
        if off_p <= tol && off_q <= tol {
            let (s0, s1) = (dot(sub(p, a), dir), dot(sub(q, a), dir));
            let (lo, hi) = if s0 <= s1 { (s0, s1) } else { (s1, s0) };
            if hi >= -tol && lo <= len + tol {
                covered.push((lo, hi));
            }
        }
    }
    covered.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut reach = 0.0;
    for (lo, hi) in covered {
        if lo > reach + tol {
            return false;
        }
        reach = f64::max(reach, hi);
        if reach >= len - tol {
            return true;
        }
    }
    false
}

/// The parts of the segment `ab` that lie along the polygon's boundary (within `tol`),
/// as sorted, disjoint parameter intervals `[t0, t1] ⊂ [0, 1]` (t along a → b; gaps up
/// to `tol` are closed, and an interval within `tol` of an end reaches it).
pub fn segment_boundary_intervals(poly: &[Vec2], a: Vec2, b: Vec2, tol: f64) -> Vec<(f64, f64)> {
    let ab = sub(b, a);
    let len = norm(ab);
    if !(len > tol) || poly.len() < 2 {
        return Vec::new();
    }
    let dir = [ab[0] / len, ab[1] / len];
    let mut covered: Vec<(f64, f64)> = Vec::new();
    for i in 0..poly.len() {
        let (p, q) = edge(poly, i);
        if cross(dir, sub(p, a)).abs() <= tol && cross(dir, sub(q, a)).abs() <= tol {
            let (s0, s1) = (dot(sub(p, a), dir), dot(sub(q, a), dir));
            let (lo, hi) = (s0.min(s1).max(0.0), s0.max(s1).min(len));
            if hi - lo > tol {
                covered.push((lo, hi));
            }
        }
    }
    covered.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (lo, hi) in covered {
        match out.last_mut() {
            Some(last) if lo <= last.1 + tol => last.1 = last.1.max(hi),
            _ => out.push((lo, hi)),
        }
    }
    out.into_iter()
        .map(|(lo, hi)| {
            let t0 = if lo <= tol { 0.0 } else { lo / len };
            let t1 = if hi >= len - tol { 1.0 } else { hi / len };
            (t0, t1)
        })
        .collect()
}

/// `true` if the interiors of two simple polygons intersect with positive
/// area (beyond `tol`). Touching along an edge or at a point is not overlap.
///
/// Method: every edge of each polygon is split at its intersections with the
/// other polygon's boundary; if the midpoint of some piece is strictly inside
/// the other polygon (farther than `tol` from its boundary) they overlap.
/// This catches proper crossings, vertices strictly inside and containment.
/// If no piece is inside and every piece of both boundaries lies on the other
/// boundary, the boundaries coincide: identical polygons, which overlap.
pub fn polygons_overlap(p: &[Vec2], q: &[Vec2], tol: f64) -> bool {
    if p.len() < 3 || q.len() < 3 {
        return false;
    }
    if !Aabb::of_points(p)
        .inflate(-tol)
        .overlaps(&Aabb::of_points(q))
    {
        return false;
    }
    let (p_in_q, p_all_on) = classify_boundary(p, q, tol);
    if p_in_q {
        return true;
    }
    let (q_in_p, q_all_on) = classify_boundary(q, p, tol);
    q_in_p || (p_all_on && q_all_on)
}

/// The parameters t ∈ [0, 1] along a→b where the closed loop `q` splits it: its vertices
/// within `tol` of ab and its edges' proper crossings with ab (pushed onto `cuts`).
pub(crate) fn push_cuts(a: Vec2, b: Vec2, q: &[Vec2], tol: f64, cuts: &mut Vec<f64>) {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    for j in 0..q.len() {
        let (c, d) = edge(q, j);
        // Vertices of q on ab split it.
        for v in [c, d] {
            if point_segment_distance(v, a, b) <= tol {
                cuts.push((dot(sub(v, a), ab) / l2).clamp(0.0, 1.0));
            }
        }
        // Proper crossings of ab with cd.
        if segments_cross_properly(a, b, c, d) {
            let cd = sub(d, c);
            let den = cross(ab, cd);
            if den != 0.0 {
                let t = cross(sub(c, a), cd) / den;
                if t.is_finite() {
                    cuts.push(t.clamp(0.0, 1.0));
                }
            }
        }
    }
}

/// Split each edge of `p` at the boundary of `q` and classify the pieces.
/// Returns (some piece strictly inside q, every piece on q's boundary).
fn classify_boundary(p: &[Vec2], q: &[Vec2], tol: f64) -> (bool, bool) {
    let mut all_on = true;
    let mut cuts: Vec<f64> = Vec::new();
    for i in 0..p.len() {
        let (a, b) = edge(p, i);
        let ab = sub(b, a);
        let l2 = dot(ab, ab);
        if !(l2 > 0.0) {
            continue;
        }
        cuts.clear();
        cuts.push(0.0);
        cuts.push(1.0);
        push_cuts(a, b, q, tol, &mut cuts);
        cuts.sort_by(f64::total_cmp);
        for w in cuts.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            if !(t1 > t0) {
                continue;
            }
            let m = lerp(a, b, 0.5 * (t0 + t1));
            match point_in_polygon(q, m, tol) {
                Location::Inside => return (true, false),
                Location::Outside => all_on = false,
                Location::Boundary => {}
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

    #[test]
    fn area_and_orientation() {
        let mut sq = square(0.0, 0.0, 2.0);
        assert_eq!(signed_area(&sq), 4.0);
        assert!(is_ccw(&sq));
        sq.reverse();
        assert_eq!(signed_area(&sq), -4.0);
        assert!(!is_ccw(&sq));
        assert!(orient_ccw(&mut sq));
        assert_eq!(signed_area(&sq), 4.0);
        assert!(!orient_ccw(&mut sq));
        // L-shape: area 3.
        let l = crate::geometry::fixtures::l_shape();
        assert_eq!(signed_area(&l), 3.0);
        // Far from the origin: still exact for this representable square.
        assert_eq!(signed_area(&square(1e6, 1e6, 0.5)), 0.25);
        assert_eq!(signed_area(&[[0.0, 0.0], [1.0, 1.0]]), 0.0);
    }

    #[test]
    fn distance_to_segment() {
        let (a, b) = ([0.0, 0.0], [2.0, 0.0]);
        assert_eq!(point_segment_distance([1.0, 3.0], a, b), 3.0);
        assert_eq!(point_segment_distance([-3.0, 4.0], a, b), 5.0);
        assert_eq!(point_segment_distance([5.0, -4.0], a, b), 5.0);
        assert_eq!(point_segment_distance([1.0, 0.0], a, b), 0.0);
        // Degenerate segment: distance to the point.
        assert_eq!(point_segment_distance([3.0, 4.0], a, a), 5.0);
        // Non-finite input does not panic.
        let _ = point_segment_distance([f64::NAN, 0.0], a, b);
        let _ = point_segment_distance([1e308, -1e308], [-1e308, 1e308], b);
    }

    #[test]
    fn location() {
        let sq = square(0.0, 0.0, 1.0);
        assert_eq!(point_in_polygon(&sq, [0.5, 0.5], TOL), Location::Inside);
        assert_eq!(point_in_polygon(&sq, [1.5, 0.5], TOL), Location::Outside);
        assert_eq!(point_in_polygon(&sq, [1.0, 0.5], TOL), Location::Boundary);
        assert_eq!(
            point_in_polygon(&sq, [1.0 + 1e-10, 0.5], TOL),
            Location::Boundary
        );
        assert_eq!(
            point_in_polygon(&sq, [1.0 + 1e-6, 0.5], TOL),
            Location::Outside
        );
        assert_eq!(point_in_polygon(&sq, [0.0, 0.0], TOL), Location::Boundary);
        // Ray through a vertex of a non-convex polygon.
        let l = crate::geometry::fixtures::l_shape();
        assert_eq!(point_in_polygon(&l, [0.5, 1.0], TOL), Location::Inside);
        assert_eq!(point_in_polygon(&l, [1.5, 1.5], TOL), Location::Outside);
        assert_eq!(point_in_polygon(&l, [-1.0, 1.0], TOL), Location::Outside);
        // Orientation does not matter.
        let mut r = l.to_vec();
        r.reverse();
        assert_eq!(point_in_polygon(&r, [0.5, 1.0], TOL), Location::Inside);
        assert_eq!(point_in_polygon(&r, [1.5, 1.5], TOL), Location::Outside);
    }

    #[test]
    fn degenerate_polygons() {
        assert_eq!(degeneracy(&square(0.0, 0.0, 1.0), TOL), None);
        assert_eq!(
            degeneracy(&[[0.0, 0.0], [1.0, 0.0]], TOL),
            Some(Degeneracy::TooFewVertices(2))
        );
        assert_eq!(
            degeneracy(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]], TOL),
            Some(Degeneracy::RepeatedVertex(1))
        );
        // Closing vertex repeated: last edge has zero length.
        assert_eq!(
            degeneracy(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]], TOL),
            Some(Degeneracy::RepeatedVertex(3))
        );
        assert_eq!(
            degeneracy(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], TOL),
            Some(Degeneracy::Collinear)
        );
        assert_eq!(
            degeneracy(&[[0.0, 0.0], [1.0, 0.0], [3.0, 0.0], [2.0, 0.0]], TOL),
            Some(Degeneracy::Collinear)
        );
        // A zero-width spike.
        let spike = [
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [1.0, 2.0],
            [0.0, 1.0],
        ];
        assert_eq!(degeneracy(&spike, TOL), Some(Degeneracy::FoldBack(3)));
        // A vertex in the middle of a straight edge is fine.
        let mid = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        assert_eq!(degeneracy(&mid, TOL), None);
        // NaN coordinates are reported, not a panic.
        assert!(degeneracy(&[[f64::NAN, 0.0], [1.0, 0.0], [0.0, 1.0]], TOL).is_some());
    }

    #[test]
    fn self_intersections() {
        assert_eq!(self_intersection(&square(0.0, 0.0, 1.0), TOL), None);
        // Bow-tie: edges 0 and 2 cross.
        let bow = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(self_intersection(&bow, TOL), Some((0, 2)));
        // A vertex touching a non-adjacent edge.
        let touch = [[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [2.0, 0.0], [0.0, 4.0]];
        assert!(self_intersection(&touch, TOL).is_some());
        // Pentagon with edges 1 and 3 crossing.
        let p = [[0.0, 0.0], [3.0, 0.0], [0.0, 2.0], [3.0, 2.0], [-1.0, 1.0]];
        let (i, j) = self_intersection(&p, TOL).unwrap();
        let (a, b) = edge(&p, i);
        let (c, d) = edge(&p, j);
        assert!(segment_segment_distance(a, b, c, d) <= TOL);
        // Adjacent edges folding back are reported too.
        let spike = [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(self_intersection(&spike, TOL).is_some());
        // Non-convex but simple.
        let l = crate::geometry::fixtures::l_shape();
        assert_eq!(self_intersection(&l, TOL), None);
    }

    #[test]
    fn segments_on_the_boundary() {
        let sq = square(0.0, 0.0, 1.0);
        assert!(segment_on_boundary(&sq, [0.0, 1.0], [1.0, 1.0], TOL));
        assert!(segment_on_boundary(&sq, [1.0, 1.0], [0.0, 1.0], TOL));
        assert!(segment_on_boundary(&sq, [0.2, 0.0], [0.7, 0.0], TOL));
        assert!(segment_on_boundary(
            &sq,
            [1.0, 0.1],
            [1.0, 0.9 + 1e-11],
            TOL
        ));
        assert!(!segment_on_boundary(&sq, [0.0, 0.5], [1.0, 0.5], TOL));
        assert!(!segment_on_boundary(&sq, [0.5, 1.0], [1.5, 1.0], TOL));
        // Around a corner: not a straight piece of boundary.
        assert!(!segment_on_boundary(&sq, [0.0, 0.0], [1.0, 1.0], TOL));
        assert!(!segment_on_boundary(&sq, [0.5, 0.5], [0.5, 0.5], TOL));
        // Several consecutive collinear edges.
        let mid = [
            [0.0, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [3.0, 0.0],
            [3.0, 1.0],
            [0.0, 1.0],
        ];
        assert!(segment_on_boundary(&mid, [0.5, 0.0], [2.5, 0.0], TOL));
        assert!(segment_on_boundary(&mid, [0.0, 0.0], [3.0, 0.0], TOL));
        // A U shape: the two prong tops are collinear but the gap is not boundary.
        let u = [
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 2.0],
            [2.0, 2.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        assert!(segment_on_boundary(&u, [0.0, 2.0], [1.0, 2.0], TOL));
        assert!(!segment_on_boundary(&u, [0.0, 2.0], [3.0, 2.0], TOL));
    }

    #[test]
    fn overlap() {
        let a = square(0.0, 0.0, 1.0);
        // Touching along an edge, at a corner, along part of an edge: no overlap.
        assert!(!polygons_overlap(&a, &square(1.0, 0.0, 1.0), TOL));
        assert!(!polygons_overlap(&a, &square(1.0, 1.0, 1.0), TOL));
        assert!(!polygons_overlap(&a, &square(1.0, 0.5, 1.0), TOL));
        assert!(!polygons_overlap(&a, &square(0.25, 1.0, 0.5), TOL));
        assert!(!polygons_overlap(&a, &square(3.0, 0.0, 1.0), TOL));
        // Crossing edges.
        assert!(polygons_overlap(&a, &square(0.5, 0.5, 1.0), TOL));
        // Identical, contained, containing.
        assert!(polygons_overlap(&a, &a, TOL));
        assert!(polygons_overlap(&a, &square(0.25, 0.25, 0.5), TOL));
        assert!(polygons_overlap(&square(0.25, 0.25, 0.5), &a, TOL));
        // Contained while sharing the whole boundary partly: half of the square.
        let tri = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        assert!(polygons_overlap(&a, &tri, TOL));
        assert!(polygons_overlap(&tri, &a, TOL));
        // Complementary triangle: touching along the diagonal only.
        let tri2 = [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(!polygons_overlap(&tri, &tri2, TOL));
        // Inscribed diamond: vertices on the boundary, interior inside.
        let diamond = [[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5]];
        assert!(polygons_overlap(&a, &diamond, TOL));
        assert!(polygons_overlap(&diamond, &a, TOL));
        // A cross: no vertex of either inside the other, only edge crossings.
        let h = [[-1.0, 0.4], [2.0, 0.4], [2.0, 0.6], [-1.0, 0.6]];
        let v = [[0.4, -1.0], [0.6, -1.0], [0.6, 2.0], [0.4, 2.0]];
        assert!(polygons_overlap(&h, &v, TOL));
        // Independent of orientation.
        let mut r = square(0.5, 0.5, 1.0);
        r.reverse();
        assert!(polygons_overlap(&a, &r, TOL));
        // A block sitting in a notch of an L-shape: touching on two edges.
        let l = crate::geometry::fixtures::l_shape();
        assert!(!polygons_overlap(&l, &square(1.0, 1.0, 1.0), TOL));
        assert!(polygons_overlap(&l, &square(0.9, 0.9, 1.0), TOL));
        // Interpenetration shallower than tol is not overlap.
        assert!(!polygons_overlap(&a, &square(1.0 - 1e-12, 0.0, 1.0), TOL));
    }

    fn rect(x0: i32, y0: i32, w: i32, h: i32) -> Vec<Vec2> {
        let (x0, y0, x1, y1) = (x0 as f64, y0 as f64, (x0 + w) as f64, (y0 + h) as f64);
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }

    proptest::proptest! {
        /// Axis-aligned rectangles on an integer grid (so touching is frequent):
        /// overlap iff both interval intersections have positive length, whatever
        /// the orientation and starting vertex of either polygon.
        #[test]
        fn rectangle_overlap_matches_intervals(
            a in (0..6i32, 0..6i32, 1..5i32, 1..5i32),
            b in (0..6i32, 0..6i32, 1..5i32, 1..5i32),
            rot in 0..4usize,
            rev in proptest::bool::ANY,
        ) {
            let p = rect(a.0, a.1, a.2, a.3);
            let mut q = rect(b.0, b.1, b.2, b.3);
            q.rotate_left(rot);
            if rev {
                q.reverse();
            }
            let ox = (a.0 + a.2).min(b.0 + b.2) - a.0.max(b.0);
            let oy = (a.1 + a.3).min(b.1 + b.3) - a.1.max(b.1);
            let expected = ox > 0 && oy > 0;
            proptest::prop_assert_eq!(polygons_overlap(&p, &q, TOL), expected);
            proptest::prop_assert_eq!(polygons_overlap(&q, &p, TOL), expected);
        }

        /// A sub-segment of any edge of a rectangle is on its boundary; the same
        /// segment shifted inwards by more than the tolerance is not.
        #[test]
        fn edge_pieces_are_on_the_boundary(
            a in (0..6i32, 0..6i32, 1..5i32, 1..5i32),
            e in 0..4usize,
            s in 0.0..0.5f64,
            t in 0.5..1.0f64,
        ) {
            let p = rect(a.0, a.1, a.2, a.3);
            let (u, v) = edge(&p, e);
            let (m0, m1) = (lerp(u, v, s), lerp(u, v, t));
            proptest::prop_assert!(segment_on_boundary(&p, m0, m1, TOL));
            proptest::prop_assert!(segment_on_boundary(&p, m1, m0, TOL));
            let c = lerp(p[0], p[2], 0.5);
            let inward = |x: Vec2| lerp(x, c, 1e-3);
            proptest::prop_assert!(!segment_on_boundary(&p, inward(m0), inward(m1), TOL));
            proptest::prop_assert_eq!(point_in_polygon(&p, lerp(m0, m1, 0.5), TOL), Location::Boundary);
            proptest::prop_assert_eq!(point_in_polygon(&p, c, TOL), Location::Inside);
        }
    }
}
