//! Clipping a simple (possibly non-convex) polygon by a triangle.
//!
//! Owns [`Clipper`], a thin wrapper around the `i_overlay` boolean engine that fixes ONE
//! float→integer transform for a whole model: `x_int = round((x − c) · s)` with `c` the
//! centre of the model box and `s` a power of two chosen so that the box maps into
//! `|x_int| ≤ 2^52` (integers exactly representable in `f64`, grid step ≈ 2.2e-16 × the
//! box half-size). Because every clip of the model uses the same transform, a point shared
//! by two clips (a mesh node, a block vertex, the crossing of a block edge with a mesh
//! edge) snaps to the same integer point in both.
//!
//! After the overlay, every output vertex lying within two grid steps of an input vertex
//! (triangle node or polygon vertex) is replaced by that input vertex exactly, so that
//! element polygons share bit-identical vertices with the mesh and the blocks. Remaining
//! vertices are edge–edge intersections, exact to the grid step.
//!
//! Output conventions: every piece is CCW (positive signed area), has no repeated closing
//! vertex, no two consecutive equal vertices, and collinear vertices removed.
//! The intersection of a triangle (convex) with a simple polygon has no holes, so each
//! connected piece is one simple polygon.

use super::{Aabb, Vec2};
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay::ShapeType;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::float::overlay::FloatOverlay;
use i_overlay::i_float::adapter::FloatPointAdapter;
use i_overlay::i_float::float::rect::FloatRect;

/// Errors of the clipper (never panics on bad input).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClipError {
    #[error("clipper box is empty, degenerate or not finite")]
    BadBox,
    #[error("point ({0}, {1}) is outside the clipper's box or not finite")]
    OutsideBox(f64, f64),
    #[error("a hole of the block near ({0}, {1}) lies inside one triangle of the cover mesh: make [cover] size smaller than the hole")]
    HoleInside(f64, f64),
}

/// A polygon clipper with one fixed float→integer transform (see the module doc).
#[derive(Clone)]
pub struct Clipper {
    adapter: FloatPointAdapter<Vec2, i64>,
    bbox: Aabb,
    /// Integer grid scale `s` (grid step = 1/s).
    pub scale: f64,
}

impl std::fmt::Debug for Clipper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Clipper")
            .field("bbox", &self.bbox)
            .field("scale", &self.scale)
            .finish()
    }
}

impl Clipper {
    /// A clipper for all geometry inside `bbox` (the model's box, e.g. the mesh box).
    pub fn new(bbox: Aabb) -> Result<Self, ClipError> {
        let ok = bbox
            .min
            .iter()
            .chain(bbox.max.iter())
            .all(|v| v.is_finite())
            && bbox.max[0] > bbox.min[0]
            && bbox.max[1] > bbox.min[1];
        if !ok {
            return Err(ClipError::BadBox);
        }
        let radius = 0.5 * (bbox.max[0] - bbox.min[0]).max(bbox.max[1] - bbox.min[1]);
        // Largest power of two s with radius·s ≤ 2^52 (inputs are inside the box).
        let scale = 2f64.powi(52 - radius.log2().ceil() as i32);
        let rect = FloatRect::new(bbox.min[0], bbox.max[0], bbox.min[1], bbox.max[1])
            .map_err(|_| ClipError::BadBox)?;
        let adapter = FloatPointAdapter::<Vec2, i64>::try_with_scale_conservative(rect, scale)
            .map_err(|_| ClipError::BadBox)?;
        Ok(Clipper {
            adapter,
            bbox,
            scale,
        })
    }

    /// The box this clipper accepts points in.
    pub fn bbox(&self) -> Aabb {
        self.bbox
    }

    /// Grid step 1/s of the integer snapping.
    pub fn grid_step(&self) -> f64 {
        1.0 / self.scale
    }

    fn check(&self, p: Vec2) -> Result<(), ClipError> {
        let b = &self.bbox;
        if p[0].is_finite()
            && p[1].is_finite()
            && p[0] >= b.min[0]
            && p[0] <= b.max[0]
            && p[1] >= b.min[1]
            && p[1] <= b.max[1]
        {
            Ok(())
        } else {
            Err(ClipError::OutsideBox(p[0], p[1]))
        }
    }

    /// All connected pieces of `tri ∩ poly` (`poly` a simple polygon, either orientation;
    /// `tri` either orientation). Each piece is CCW, without duplicate vertices.
    pub fn clip_polygon_by_triangle(
        &self,
        poly: &[Vec2],
        tri: &[Vec2; 3],
    ) -> Result<Vec<Vec<Vec2>>, ClipError> {
        self.clip_loops_by_triangle(&[poly], tri)
    }

    /// All connected pieces of `tri ∩ region`, the region bounded by `loops` (the outer
    /// loop counter-clockwise, holes clockwise: [`super::region`]). A piece with a hole (a
    /// hole of the region lying inside the triangle, touching none of its edges) is an
    /// error: elements are simple polygons.
    pub fn clip_loops_by_triangle(
        &self,
        loops: &[&[Vec2]],
        tri: &[Vec2; 3],
    ) -> Result<Vec<Vec<Vec2>>, ClipError> {
        for p in loops.iter().flat_map(|l| l.iter()).chain(tri.iter()) {
            self.check(*p)?;
        }
        if loops.first().is_none_or(|l| l.len() < 3) {
            return Ok(Vec::new());
        }
        let total: usize = loops.iter().map(|l| l.len()).sum();
        let mut overlay = FloatOverlay::<Vec2, i64>::with_adapter(self.adapter.clone(), total + 3)
            .unsafe_add_contour(tri, ShapeType::Subject);
        for l in loops {
            overlay = overlay.unsafe_add_contour(l, ShapeType::Clip);
        }
        let shapes = overlay.overlay(OverlayRule::Intersect, FillRule::NonZero);

        // Input vertices near the triangle, for snapping back.
        let tb = Aabb::of_points(tri).inflate(4.0 * self.grid_step());
        let near: Vec<Vec2> = tri
            .iter()
            .copied()
            .chain(
                loops
                    .iter()
                    .flat_map(|l| l.iter().copied())
                    .filter(|p| point_in_box(*p, &tb)),
            )
            .collect();
        let tol = 2.0 * self.grid_step();

        let mut out = Vec::with_capacity(shapes.len());
        for shape in shapes {
            // shape[0] is the outer contour; a simple `poly` makes no holes (see module
            // doc); a hole of the region inside the triangle does
            let mut contours = shape.into_iter();
            let Some(outer) = contours.next() else {
                continue;
            };
            if loops.len() > 1 {
                if let Some(h) = contours.next().and_then(|h| h.first().copied()) {
                    return Err(ClipError::HoleInside(h[0], h[1]));
                }
            }
            let mut piece: Vec<Vec2> = Vec::with_capacity(outer.len());
            for p in outer {
                let q = near
                    .iter()
                    .find(|v| (v[0] - p[0]).abs() <= tol && (v[1] - p[1]).abs() <= tol)
                    .copied()
                    .unwrap_or(p);
                if piece.last() != Some(&q) {
                    piece.push(q);
                }
            }
            while piece.len() > 1 && piece.first() == piece.last() {
                piece.pop();
            }
            if piece.len() < 3 {
                continue;
            }
            if signed_area(&piece) < 0.0 {
                piece.reverse();
            }
            out.push(piece);
        }
        Ok(out)
    }
}

/// Free-function form of [`Clipper::clip_polygon_by_triangle`].
pub fn clip_polygon_by_triangle(
    clipper: &Clipper,
    poly: &[Vec2],
    tri: &[Vec2; 3],
) -> Result<Vec<Vec<Vec2>>, ClipError> {
    clipper.clip_polygon_by_triangle(poly, tri)
}

fn point_in_box(p: Vec2, b: &Aabb) -> bool {
    p[0] >= b.min[0] && p[0] <= b.max[0] && p[1] >= b.min[1] && p[1] <= b.max[1]
}

/// Signed area (shoelace), positive for CCW.
fn signed_area(p: &[Vec2]) -> f64 {
    let n = p.len();
    let o = p[0];
    let mut s = 0.0;
    for i in 1..n.saturating_sub(1) {
        let a = [p[i][0] - o[0], p[i][1] - o[1]];
        let b = [p[i + 1][0] - o[0], p[i + 1][1] - o[1]];
        s += a[0] * b[1] - a[1] * b[0];
    }
    0.5 * s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clipper() -> Clipper {
        Clipper::new(Aabb {
            min: [-10.0, -10.0],
            max: [10.0, 10.0],
        })
        .unwrap()
    }

    #[test]
    fn square_cut_by_triangle() {
        let c = clipper();
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let tri = [[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]];
        let r = c.clip_polygon_by_triangle(&sq, &tri).unwrap();
        assert_eq!(r.len(), 1);
        // The square is cut by the line x + y = 2 only at its corner (1,1): whole square.
        assert!((signed_area(&r[0]) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn u_shape_gives_two_pieces() {
        let c = clipper();
        // U: legs at x∈[0,1] and x∈[2,3], joined below y=0.
        let u = [
            [0.0, -1.0],
            [3.0, -1.0],
            [3.0, 2.0],
            [2.0, 2.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let tri = [[-1.0, 0.5], [4.0, 0.5], [1.5, 5.0]];
        let r = c.clip_polygon_by_triangle(&u, &tri).unwrap();
        assert_eq!(r.len(), 2);
        for p in &r {
            assert!(signed_area(p) > 0.0);
        }
    }

    #[test]
    fn outside_box_is_an_error() {
        let c = clipper();
        let tri = [[0.0, 0.0], [20.0, 0.0], [0.0, 1.0]];
        assert!(c.clip_polygon_by_triangle(&tri.clone(), &tri).is_err());
    }

    #[test]
    fn vertices_snap_back_exactly() {
        let c = clipper();
        let tri = [[0.1, 0.2], [0.7, 0.2], [0.1, 0.9]];
        let big = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let r = c.clip_polygon_by_triangle(&big, &tri).unwrap();
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].len(), 3);
        for v in &r[0] {
            assert!(tri.contains(v));
        }
    }
}
