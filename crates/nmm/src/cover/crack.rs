//! Cracks in the discretisation: traces that end inside a block split the manifold
//! elements they cross and so the physical covers, the mathematical mesh staying as it is.
//!
//! A crack ([`CoverCrack`]) is a polyline of one block with at least one end inside the
//! block (the other may be on the block's boundary: an edge crack). With cracks:
//!
//! * **Manifold elements** are the connected pieces of (mesh triangle ∩ block) *minus the
//!   crack polylines*. Each clipped piece of a triangle that a crack passes near is cut by
//!   the crack segments near the triangle with the planar arrangement of
//!   [`crate::geometry::cut::cut_polygon`] (length tolerance `CUT_TOL · h`): a crack that
//!   crosses the piece from boundary to boundary splits it in two; a crack that ends
//!   inside it (the triangle holding a *tip*) separates nothing and leaves it whole (the
//!   slit has no area, so the element's polygon is the piece itself).
//! * **Physical covers** are the connected pieces of (node star ∩ block) minus the cracks.
//!   The union–find of `build.rs` joins elements of neighbouring triangles whose polygons
//!   lie along a common part of the shared mesh edge; the parts of a mesh edge covered by
//!   a crack (a crack running along a mesh line) are removed from that coverage
//!   ([`Cracks::on_edge`]), so no connection passes through a crack. Where a crack
//!   separates a star it gives separate covers; around a tip the star stays connected
//!   through the element holding the tip, and the displacement is continuous there: the
//!   jump of the displacement across the faces fades over the triangles next to the tip
//!   (the covers the two sides share carry no jump) and is zero beyond the tip.
//! * **Material points** are located on the current element polygons
//!   ([`super::Discretisation::locate`]): a point off a crack lies in exactly one of the two
//!   elements the crack separates, so it belongs to the side it lies on. A point exactly
//!   on a crack is on both polygons' boundaries; it goes to the first element found.
//!
//! Cracks on several segments, edge cracks, several and crossing cracks in one block all
//! follow from the arrangement (crossing cracks meet at a vertex of the cut). A closed loop
//! of cracks that lies inside a single mesh triangle does not split it (the arrangement
//! keeps an enclosed region as part of the piece around it).

use crate::geometry::cut::{cut_polygon, Trace};
use crate::geometry::{dot, sub, Aabb, Vec2};

/// Length tolerance of the crack arrangement in a triangle, relative to h (as the
/// discretisation's `EDGE_TOL`).
pub const CUT_TOL: f64 = 1e-9;

/// A crack of one block: a polyline (at least two points) ending inside the block at one
/// or both ends, with the joint it belongs to (its faces' interface).
#[derive(Debug, Clone, PartialEq)]
pub struct CoverCrack {
    /// Index of the block.
    pub block: usize,
    /// Index of the joint (`Model::joints`) whose trace it is.
    pub joint: usize,
    /// The crack as a polyline (at least two points, initial positions).
    pub points: Vec<Vec2>,
}

/// The crack segments of one block, for the cuts of its triangles.
#[derive(Debug, Clone, Default)]
pub(super) struct Cracks {
    segs: Vec<(Vec2, Vec2)>,
    boxes: Vec<Aabb>,
}

impl Cracks {
    /// The segments of `cracks` that belong to `block`.
    pub(super) fn of_block(cracks: &[CoverCrack], block: usize) -> Cracks {
        let segs: Vec<(Vec2, Vec2)> = cracks
            .iter()
            .filter(|c| c.block == block)
            .flat_map(|c| c.points.windows(2).map(|w| (w[0], w[1])))
            .filter(|(p, q)| p != q)
            .collect();
        let boxes = segs
            .iter()
            .map(|&(p, q)| Aabb::of_points(&[p, q]))
            .collect();
        Cracks { segs, boxes }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.segs.is_empty()
    }

    /// The segments (for rasterising them onto the mesh squares).
    pub(super) fn segments(&self) -> &[(Vec2, Vec2)] {
        &self.segs
    }

    /// Segments whose box meets the triangle's box inflated by `tol`.
    fn near(&self, tri: &[Vec2; 3], tol: f64) -> impl Iterator<Item = (Vec2, Vec2)> + '_ {
        let tb = Aabb::of_points(tri).inflate(tol);
        self.segs
            .iter()
            .zip(&self.boxes)
            .filter(move |(_, b)| b.overlaps(&tb))
            .map(|(s, _)| *s)
    }

    /// The connected pieces of `piece` (a CCW simple polygon inside triangle `tri`) minus
    /// the crack segments, each CCW. `piece` itself (one element) when no crack crosses it.
    pub(super) fn split(
        &self,
        piece: Vec<Vec2>,
        tri: &[Vec2; 3],
        h: f64,
    ) -> Result<Vec<Vec<Vec2>>, String> {
        let tol = CUT_TOL * h;
        let traces: Vec<Trace> = self
            .near(tri, tol)
            .map(|(p, q)| Trace {
                points: vec![p, q],
                joint: 0,
            })
            .collect();
        if traces.is_empty() {
            return Ok(vec![piece]);
        }
        let cut = cut_polygon(&piece, &traces, tol, None).map_err(|e| e.to_string())?;
        if cut.pieces.len() == 1 {
            // nothing separated (a tip, or a crack outside the piece): the piece as clipped
            return Ok(vec![piece]);
        }
        Ok(cut.pieces.into_iter().map(|p| p.vertices).collect())
    }

    /// Parameter intervals (from `a`, in [0, 1]) of the mesh edge a→b that a crack segment
    /// lies along (both its ends within `CUT_TOL · h` of the edge's line), sorted; empty
    /// for most edges.
    pub(super) fn on_edge(&self, a: Vec2, b: Vec2, h: f64) -> Vec<[f64; 2]> {
        let tol = CUT_TOL * h;
        let ab = sub(b, a);
        let len2 = dot(ab, ab);
        let len = len2.sqrt();
        let eb = Aabb::of_points(&[a, b]).inflate(tol);
        let mut out: Vec<[f64; 2]> = Vec::new();
        for (&(p, q), bx) in self.segs.iter().zip(&self.boxes) {
            if !bx.overlaps(&eb) {
                continue;
            }
            let off = |x: Vec2| crate::geometry::cross(ab, sub(x, a)).abs() / len;
            if off(p) > tol || off(q) > tol {
                continue;
            }
            let (sp, sq) = (dot(sub(p, a), ab) / len2, dot(sub(q, a), ab) / len2);
            let (lo, hi) = (sp.min(sq).max(0.0), sp.max(sq).min(1.0));
            if hi - lo > CUT_TOL {
                out.push([lo, hi]);
            }
        }
        out.sort_by(|x, y| x[0].total_cmp(&y[0]));
        out
    }
}

/// `from` (disjoint intervals) minus `holes` (sorted), keeping parts longer than `tol`.
pub(super) fn subtract_intervals(from: &[[f64; 2]], holes: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for &[lo, hi] in from {
        let mut start = lo;
        for &[hlo, hhi] in holes {
            if hhi <= start || hlo >= hi {
                continue;
            }
            if hlo - start > tol {
                out.push([start, hlo]);
            }
            start = start.max(hhi);
        }
        if hi - start > tol {
            out.push([start, hi]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_minus_holes() {
        let r = subtract_intervals(&[[0.0, 1.0]], &[[0.2, 0.3], [0.5, 0.6]], 1e-9);
        assert_eq!(r, vec![[0.0, 0.2], [0.3, 0.5], [0.6, 1.0]]);
        let r = subtract_intervals(&[[0.0, 0.4], [0.7, 1.0]], &[[0.3, 0.8]], 1e-9);
        assert_eq!(r, vec![[0.0, 0.3], [0.8, 1.0]]);
        assert!(subtract_intervals(&[[0.0, 1.0]], &[[-0.1, 1.1]], 1e-9).is_empty());
    }

    #[test]
    fn a_crack_across_a_triangle_splits_it_and_a_tip_does_not() {
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let across = Cracks::of_block(
            &[CoverCrack {
                block: 0,
                joint: 0,
                points: vec![[-0.5, 0.25], [0.5, 0.25], [2.0, 0.25]],
            }],
            0,
        );
        let pieces = across.split(tri.to_vec(), &tri, 1.0).unwrap();
        assert_eq!(pieces.len(), 2);
        let area: f64 = pieces
            .iter()
            .map(|p| crate::geometry::moments::polygon_area(p))
            .sum();
        assert!((area - 0.5).abs() < 1e-14);
        let tip = Cracks::of_block(
            &[CoverCrack {
                block: 0,
                joint: 0,
                points: vec![[-0.5, 0.25], [0.3, 0.25]],
            }],
            0,
        );
        assert_eq!(
            tip.split(tri.to_vec(), &tri, 1.0).unwrap(),
            vec![tri.to_vec()]
        );
        // a crack along the edge y = 0 from x = 0.2 to 0.7
        let along = Cracks::of_block(
            &[CoverCrack {
                block: 0,
                joint: 0,
                points: vec![[0.2, 0.0], [0.7, 0.0]],
            }],
            0,
        );
        let iv = along.on_edge(tri[0], tri[1], 1.0);
        assert_eq!(iv.len(), 1);
        assert!((iv[0][0] - 0.2).abs() < 1e-15 && (iv[0][1] - 0.7).abs() < 1e-15);
        assert!(along.on_edge(tri[1], tri[2], 1.0).is_empty());
    }
}
