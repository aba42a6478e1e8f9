//! The two faces of a crack (its *slit*): contact faces of the block with itself.
//!
//! A crack ([`super::CoverCrack`]) splits the covers it crosses ([`super::crack`]); its two
//! faces are then free to open, close and slide like a joint between two blocks. Each
//! face is a polyline of [`BoundaryVertex`]es along the crack, from the crack's first point
//! to its last, refined where the crack crosses a mesh line or another crack of the block,
//! so that every face segment lies in one manifold element *of its own side*:
//!
//! * face 0 carries the material on the **left** of the crack's direction (first point to
//!   last), face 1 the material on its right;
//! * a face vertex or segment is located in the element on its side: the point is moved
//!   off the crack by `SIDE_OFFSET · h` along the face's outward side (away from the other
//!   face) before the nearest element is taken. Its weights are those of the point on the
//!   crack itself;
//! * at a tip (an end inside the block) the element holding the tip is not split
//!   ([`super::crack`]): both faces' last vertices, and any face segment inside that element,
//!   are in the same element, and carry no jump — the displacement is continuous beyond
//!   the tip. The contacts skip them ([`crate::contact`]: a face vertex whose own element is
//!   the element of the facing segment has no relative motion).
//!
//! At order 1 the faces gain the midpoint of every segment (the contact quadrature points
//! of first-order covers, as on block boundaries).

use super::{barycentric, BoundaryVertex, ManifoldElement, MaterialPoint};
use crate::geometry::{dist, lerp, norm, sub, Vec2};

/// Offset (× h) of the point used to pick a face's element off the crack.
pub const SIDE_OFFSET: f64 = 1e-7;

/// One face of a crack: a polyline of refined vertices from the crack's first point to its
/// last; segment i (vertex i to i + 1) lies in element `segment_elements[i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SlitFace {
    pub vertices: Vec<BoundaryVertex>,
    pub segment_elements: Vec<usize>,
}

/// Both faces of one crack of one block.
#[derive(Debug, Clone, PartialEq)]
pub struct Slit {
    pub block: usize,
    /// Index into `Discretisation::cracks`.
    pub crack: usize,
    /// The joint the crack is a trace of (its faces' interface).
    pub joint: usize,
    /// Face 0 (material on the left of the crack's direction) and face 1 (on its right).
    pub faces: [SlitFace; 2],
    /// Number of the first vertex of face 0 among the block's contact vertices: its
    /// boundary's vertices come first, then each slit's faces in order (face 0, face 1).
    /// Vertex `i` of face `f` is contact vertex `first + f · faces[0].vertices.len() + i`.
    pub first: usize,
}

impl Slit {
    /// The contact-vertex number of vertex `i` of face `f`.
    pub fn vertex_number(&self, f: usize, i: usize) -> usize {
        self.first + f * self.faces[0].vertices.len() + i
    }

    /// (face, vertex) of a contact-vertex number of this slit, if it is one of its.
    pub fn vertex_of(&self, number: usize) -> Option<(usize, usize)> {
        let n0 = self.faces[0].vertices.len();
        let k = number.checked_sub(self.first)?;
        if k < n0 {
            Some((0, k))
        } else if k < n0 + self.faces[1].vertices.len() {
            Some((1, k - n0))
        } else {
            None
        }
    }

    /// Number of contact vertices of both faces.
    pub fn vertex_count(&self) -> usize {
        self.faces[0].vertices.len() + self.faces[1].vertices.len()
    }
}

/// Parameters in (0, 1) where the segment p→q crosses a line of the mesh (grid coordinates
/// relative to `origin`, spacing `h`: x = i, y = j, x − y = k), appended to `out` (the
/// refinement points of block boundaries and of crack faces).
pub(super) fn mesh_crossings(p: Vec2, q: Vec2, origin: Vec2, h: f64, out: &mut Vec<f64>) {
    let gp = [(p[0] - origin[0]) / h, (p[1] - origin[1]) / h];
    let gq = [(q[0] - origin[0]) / h, (q[1] - origin[1]) / h];
    for (f0, f1) in [
        (gp[0], gq[0]),
        (gp[1], gq[1]),
        (gp[0] - gp[1], gq[0] - gq[1]),
    ] {
        if f0 == f1 {
            continue;
        }
        let (lo, hi) = (f0.min(f1), f0.max(f1));
        let mut m = lo.ceil();
        while m <= hi {
            let t = (m - f0) / (f1 - f0);
            if t > 0.0 && t < 1.0 {
                out.push(t);
            }
            m += 1.0;
        }
    }
}

/// Parameter in (0, 1) along p→q where it crosses the segment a→b, if it does.
fn segment_crossing(p: Vec2, q: Vec2, a: Vec2, b: Vec2) -> Option<f64> {
    let r = sub(q, p);
    let s = sub(b, a);
    let den = crate::geometry::cross(r, s);
    if den == 0.0 {
        return None;
    }
    let ap = sub(a, p);
    let t = crate::geometry::cross(ap, s) / den;
    let u = crate::geometry::cross(ap, r) / den;
    (t > 0.0 && t < 1.0 && (0.0..=1.0).contains(&u)).then_some(t)
}

/// The refined points of a crack polyline (its own points, then where it crosses mesh lines
/// and the segments `others` of the block's other cracks), dropping points closer than
/// `tol` to the previous one.
pub(super) fn refine(
    points: &[Vec2],
    others: &[(Vec2, Vec2)],
    origin: Vec2,
    h: f64,
    tol: f64,
) -> Vec<Vec2> {
    let mut out: Vec<Vec2> = Vec::with_capacity(2 * points.len());
    let mut ts: Vec<f64> = Vec::new();
    for w in points.windows(2) {
        let (p, q) = (w[0], w[1]);
        if out.last().is_none_or(|&l| dist(l, p) > tol) {
            out.push(p);
        }
        ts.clear();
        mesh_crossings(p, q, origin, h, &mut ts);
        ts.extend(
            others
                .iter()
                .filter_map(|&(a, b)| segment_crossing(p, q, a, b)),
        );
        ts.sort_by(f64::total_cmp);
        let len = dist(p, q);
        for &t in &ts {
            let x = lerp(p, q, t);
            if dist(*out.last().unwrap(), x) > tol && (1.0 - t) * len > tol {
                out.push(x);
            }
        }
    }
    let last = *points.last().unwrap();
    if dist(*out.last().unwrap(), last) > tol {
        out.push(last);
    } else if out.len() > 1 {
        *out.last_mut().unwrap() = last;
    }
    out
}

/// The left unit normal of the direction p→q.
fn left_normal(p: Vec2, q: Vec2) -> Vec2 {
    let t = sub(q, p);
    let l = norm(t);
    [-t[1] / l, t[0] / l]
}

/// One face (`side` +1: face 0, on the left; −1: face 1) of the refined crack `pts`, its
/// points located by `nearest` off the crack on the face's side; with `midpoints` (order 1)
/// every segment's midpoint inserted.
pub(super) fn face(
    pts: &[Vec2],
    side: f64,
    h: f64,
    elements: &[ManifoldElement],
    midpoints: bool,
    nearest: &dyn Fn(Vec2) -> Option<usize>,
) -> Result<SlitFace, String> {
    let n = pts.len();
    let off = SIDE_OFFSET * h;
    let normals: Vec<Vec2> = pts
        .windows(2)
        .map(|w| {
            let l = left_normal(w[0], w[1]);
            [side * l[0], side * l[1]]
        })
        .collect();
    let at = |x: Vec2, probe: Vec2| -> Result<MaterialPoint, String> {
        let e = nearest(probe).ok_or_else(|| format!("no element at crack point {x:?}"))?;
        Ok(MaterialPoint {
            element: e,
            weights: barycentric(&elements[e].nodes, x),
        })
    };
    let mut vertices = Vec::with_capacity(2 * n);
    let mut segment_elements = Vec::with_capacity(2 * n);
    for i in 0..n {
        let x = pts[i];
        let nv = match (i.checked_sub(1).map(|k| normals[k]), normals.get(i)) {
            (Some(a), Some(b)) => {
                let s = [a[0] + b[0], a[1] + b[1]];
                let l = norm(s);
                if l > 1e-12 {
                    [s[0] / l, s[1] / l]
                } else {
                    *b
                }
            }
            (Some(a), None) => a,
            (None, Some(b)) => *b,
            (None, None) => [0.0, 0.0],
        };
        let probe = [x[0] + off * nv[0], x[1] + off * nv[1]];
        vertices.push(BoundaryVertex {
            x0: x,
            at: at(x, probe)?,
            corner: false,
            midpoint: false,
        });
        if i + 1 < n {
            let m = lerp(x, pts[i + 1], 0.5);
            let nm = normals[i];
            let e = nearest([m[0] + off * nm[0], m[1] + off * nm[1]])
                .ok_or_else(|| format!("no element at crack point {m:?}"))?;
            if midpoints {
                segment_elements.push(e);
                vertices.push(BoundaryVertex {
                    x0: m,
                    at: MaterialPoint {
                        element: e,
                        weights: barycentric(&elements[e].nodes, m),
                    },
                    corner: false,
                    midpoint: true,
                });
            }
            segment_elements.push(e);
        }
    }
    Ok(SlitFace {
        vertices,
        segment_elements,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_crack_is_refined_at_mesh_lines_and_other_cracks() {
        // h = 1, origin 0: the segment (0.5, 0.25) → (2.5, 0.25) crosses x = 1, 2 and the
        // diagonals x − y = 1, 2; another crack crosses it at x = 1.8
        let pts = refine(
            &[[0.5, 0.25], [2.5, 0.25]],
            &[([1.8, -1.0], [1.8, 1.0])],
            [0.0, 0.0],
            1.0,
            1e-9,
        );
        let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
        let want = [0.5, 1.0, 1.25, 1.8, 2.0, 2.25, 2.5];
        assert_eq!(xs.len(), want.len(), "{xs:?}");
        for (a, b) in xs.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{xs:?}");
        }
    }

    #[test]
    fn segment_crossings() {
        assert_eq!(
            segment_crossing([0.0, 0.0], [2.0, 0.0], [1.0, -1.0], [1.0, 1.0]),
            Some(0.5)
        );
        assert_eq!(
            segment_crossing([0.0, 0.0], [2.0, 0.0], [3.0, -1.0], [3.0, 1.0]),
            None
        );
        assert_eq!(
            segment_crossing([0.0, 0.0], [2.0, 0.0], [0.0, 1.0], [2.0, 1.0]),
            None
        );
    }
}
