//! The mathematical mesh: a regular right-isosceles triangular mesh.
//!
//! Layout: `nx × ny` squares of side `h`, lower-left corner `origin`. Node `(i, j)`
//! (`0 ≤ i ≤ nx`, `0 ≤ j ≤ ny`) sits at `origin + h (i, j)` and has index
//! `n = j (nx + 1) + i` (row-major, so neighbouring nodes have close indices).
//! Square `(i, j)` has index `s = j nx + i` and is split along its rising diagonal
//! `(i, j)–(i+1, j+1)` into two CCW triangles:
//!
//! ```text
//!  (i,j+1) ___ (i+1,j+1)      triangle 2s     (lower-right): [(i,j), (i+1,j), (i+1,j+1)]
//!         |  /|               triangle 2s + 1 (upper-left):  [(i,j), (i+1,j+1), (i,j+1)]
//!         | / |
//!         |/__|               Local edge k of a triangle joins its local nodes k and k+1 (mod 3).
//!  (i,j)      (i+1,j)
//! ```
//!
//! Every interior node has a star of 6 triangles. Point location is O(1): square from
//! `floor((x − origin)/h)`, then the side of the diagonal.

use crate::geometry::{Aabb, Vec2};

/// Regular triangular mesh (see module doc for the numbering).
#[derive(Debug, Clone, PartialEq)]
pub struct MathMesh {
    /// Lower-left corner of the meshed box.
    pub origin: Vec2,
    /// Square side (mesh size).
    pub h: f64,
    /// Number of squares along x.
    pub nx: usize,
    /// Number of squares along y.
    pub ny: usize,
}

impl MathMesh {
    /// A mesh of size `h` covering `bbox` enlarged by a margin of `h/2` on every side
    /// (so that blocks are strictly inside the meshed box). `None` if `h` or the box is
    /// not finite/positive or the mesh would have more than `max_nodes` nodes.
    pub fn covering(bbox: &Aabb, h: f64, max_nodes: usize) -> Option<MathMesh> {
        Self::covering_through(bbox, h, max_nodes, None)
    }

    /// As [`MathMesh::covering`], with a mesh node at `through` when given (the mesh
    /// is then shifted by less than h so that the point is a node; `[cover] origin`).
    pub fn covering_through(
        bbox: &Aabb,
        h: f64,
        max_nodes: usize,
        through: Option<Vec2>,
    ) -> Option<MathMesh> {
        if !(h.is_finite() && h > 0.0) {
            return None;
        }
        if !bbox
            .min
            .iter()
            .chain(bbox.max.iter())
            .all(|v| v.is_finite())
            || bbox.max[0] < bbox.min[0]
            || bbox.max[1] < bbox.min[1]
        {
            return None;
        }
        let margin = 0.5 * h;
        let mut origin = [bbox.min[0] - margin, bbox.min[1] - margin];
        if let Some(p) = through {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return None;
            }
            // the largest node p - k h (k integer) at or below the default origin
            for c in 0..2 {
                let k = ((p[c] - origin[c]) / h).ceil();
                origin[c] = p[c] - k * h;
            }
        }
        let fx = (bbox.max[0] + margin - origin[0]) / h;
        let fy = (bbox.max[1] + margin - origin[1]) / h;
        if !(fx.is_finite() && fy.is_finite()) || (fx + 2.0) * (fy + 2.0) > max_nodes as f64 {
            return None;
        }
        let nx = (fx.ceil() as usize).max(1);
        let ny = (fy.ceil() as usize).max(1);
        Some(MathMesh { origin, h, nx, ny })
    }

    /// The box covered by the mesh.
    pub fn bbox(&self) -> Aabb {
        Aabb {
            min: self.origin,
            max: [
                self.origin[0] + self.nx as f64 * self.h,
                self.origin[1] + self.ny as f64 * self.h,
            ],
        }
    }

    pub fn node_count(&self) -> usize {
        (self.nx + 1) * (self.ny + 1)
    }

    pub fn triangle_count(&self) -> usize {
        2 * self.nx * self.ny
    }

    /// Node index of grid point `(i, j)`.
    #[inline]
    pub fn node_index(&self, i: usize, j: usize) -> usize {
        j * (self.nx + 1) + i
    }

    /// Position of node `n`.
    #[inline]
    pub fn node(&self, n: usize) -> Vec2 {
        let i = n % (self.nx + 1);
        let j = n / (self.nx + 1);
        [
            self.origin[0] + i as f64 * self.h,
            self.origin[1] + j as f64 * self.h,
        ]
    }

    /// The three nodes of triangle `t`, CCW.
    #[inline]
    pub fn triangle(&self, t: usize) -> [usize; 3] {
        let s = t / 2;
        let (i, j) = (s % self.nx, s / self.nx);
        let a = self.node_index(i, j);
        let c = self.node_index(i + 1, j + 1);
        if t % 2 == 0 {
            [a, a + 1, c]
        } else {
            [a, c, c - 1]
        }
    }

    /// Positions of the three nodes of triangle `t`, CCW.
    #[inline]
    pub fn triangle_points(&self, t: usize) -> [Vec2; 3] {
        let [a, b, c] = self.triangle(t);
        [self.node(a), self.node(b), self.node(c)]
    }

    /// Triangle index for square `(i, j)`, `upper` = upper-left half.
    #[inline]
    pub fn triangle_index(&self, i: usize, j: usize, upper: bool) -> usize {
        2 * (j * self.nx + i) + upper as usize
    }

    /// The triangle containing `x` (closed triangles; points on shared edges go to
    /// one of them), or `None` outside the meshed box. O(1).
    pub fn locate(&self, x: Vec2) -> Option<usize> {
        let u = (x[0] - self.origin[0]) / self.h;
        let v = (x[1] - self.origin[1]) / self.h;
        if !(u >= 0.0 && v >= 0.0 && u <= self.nx as f64 && v <= self.ny as f64) {
            return None;
        }
        let i = (u.floor() as usize).min(self.nx - 1);
        let j = (v.floor() as usize).min(self.ny - 1);
        let (fu, fv) = (u - i as f64, v - j as f64);
        Some(self.triangle_index(i, j, fv > fu))
    }

    /// Square index range `(i0..=i1, j0..=j1)` of squares whose closed box overlaps
    /// `b`, or `None` if `b` misses the mesh.
    pub fn square_range(&self, b: &Aabb) -> Option<(usize, usize, usize, usize)> {
        let u0 = (b.min[0] - self.origin[0]) / self.h;
        let u1 = (b.max[0] - self.origin[0]) / self.h;
        let v0 = (b.min[1] - self.origin[1]) / self.h;
        let v1 = (b.max[1] - self.origin[1]) / self.h;
        if !(u0.is_finite() && u1.is_finite() && v0.is_finite() && v1.is_finite()) {
            return None;
        }
        // Square i covers [i, i+1]; it overlaps [u0, u1] iff u0 − 1 ≤ i ≤ u1.
        let range = |a: f64, b: f64, n: usize| -> Option<(usize, usize)> {
            if b < 0.0 || a > n as f64 || a > b {
                return None;
            }
            let lo = (a - 1.0).ceil().max(0.0) as usize;
            let hi = (b.floor() as usize).min(n - 1);
            (lo <= hi).then_some((lo, hi))
        };
        let (i0, i1) = range(u0, u1, self.nx)?;
        let (j0, j1) = range(v0, v1, self.ny)?;
        Some((i0, i1, j0, j1))
    }

    /// Triangles whose bounding box (their square) overlaps `b` (conservative).
    pub fn triangles_overlapping(&self, b: &Aabb) -> impl Iterator<Item = usize> + '_ {
        let r = self.square_range(b);
        let (i0, i1, j0, j1) = r.unwrap_or((1, 0, 1, 0));
        (j0..=j1).flat_map(move |j| {
            (i0..=i1).flat_map(move |i| {
                [
                    self.triangle_index(i, j, false),
                    self.triangle_index(i, j, true),
                ]
            })
        })
    }

    /// The triangle across local edge `k` of triangle `t` and the local index of the
    /// same edge in it, or `None` on the mesh boundary.
    pub fn neighbour(&self, t: usize, k: usize) -> Option<(usize, usize)> {
        let s = t / 2;
        let (i, j) = (s % self.nx, s / self.nx);
        if t % 2 == 0 {
            match k {
                0 => (j > 0).then(|| (self.triangle_index(i, j - 1, true), 1)),
                1 => (i + 1 < self.nx).then(|| (self.triangle_index(i + 1, j, true), 2)),
                _ => Some((t + 1, 0)),
            }
        } else {
            match k {
                0 => Some((t - 1, 2)),
                1 => (j + 1 < self.ny).then(|| (self.triangle_index(i, j + 1, false), 0)),
                _ => (i > 0).then(|| (self.triangle_index(i - 1, j, false), 1)),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cover::barycentric;

    #[test]
    fn covering_through_a_point_puts_a_node_there() {
        let bbox = Aabb {
            min: [0.0, 0.0],
            max: [2.0, 1.0],
        };
        for p in [[0.0, 0.0], [0.37, 0.81], [-5.0, 13.1], [1.0, 0.5]] {
            let m = MathMesh::covering_through(&bbox, 0.3, 1000, Some(p)).unwrap();
            for c in 0..2 {
                let k = (p[c] - m.origin[c]) / m.h;
                assert!((k - k.round()).abs() < 1e-9, "{p:?}: {k}");
                // blocks strictly inside, with at least the default margin
                assert!(m.origin[c] <= bbox.min[c] - 0.5 * m.h + 1e-12);
                assert!(m.origin[c] > bbox.min[c] - 1.5 * m.h - 1e-12);
            }
            let b = m.bbox();
            assert!(b.max[0] >= bbox.max[0] + 0.5 * m.h && b.max[1] >= bbox.max[1] + 0.5 * m.h);
        }
        assert_eq!(
            MathMesh::covering_through(&bbox, 0.3, 1000, None),
            MathMesh::covering(&bbox, 0.3, 1000)
        );
    }

    fn mesh() -> MathMesh {
        MathMesh {
            origin: [-1.0, 2.0],
            h: 0.5,
            nx: 5,
            ny: 4,
        }
    }

    #[test]
    fn triangles_are_ccw_and_tile_the_box() {
        let m = mesh();
        let mut area = 0.0;
        for t in 0..m.triangle_count() {
            let [a, b, c] = m.triangle_points(t);
            let s = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
            assert!((s - 0.125).abs() < 1e-15);
            area += s;
        }
        assert!((area - 2.5 * 2.0).abs() < 1e-12);
        assert_eq!(m.node_count(), 30);
    }

    #[test]
    fn neighbours_share_the_edge_reversed() {
        let m = mesh();
        for t in 0..m.triangle_count() {
            let n = m.triangle(t);
            for k in 0..3 {
                if let Some((u, l)) = m.neighbour(t, k) {
                    let nu = m.triangle(u);
                    assert_eq!((n[k], n[(k + 1) % 3]), (nu[(l + 1) % 3], nu[l]));
                    assert_eq!(m.neighbour(u, l), Some((t, k)));
                }
            }
        }
    }

    #[test]
    fn locate_finds_containing_triangle() {
        let m = mesh();
        for k in 0..200 {
            let x = [
                -1.0 + 2.5 * ((k * 37 % 101) as f64 / 100.0),
                2.0 + 2.0 * ((k * 53 % 97) as f64 / 96.0),
            ];
            let t = m.locate(x).unwrap();
            let w = barycentric(&m.triangle_points(t), x);
            assert!(w.iter().all(|&v| v >= -1e-12), "{x:?} {w:?}");
        }
        assert!(m.locate([-1.1, 2.5]).is_none());
    }

    #[test]
    fn overlapping_is_conservative() {
        let m = mesh();
        let b = Aabb {
            min: [0.1, 2.6],
            max: [0.4, 3.0],
        };
        let ts: Vec<usize> = m.triangles_overlapping(&b).collect();
        for t in 0..m.triangle_count() {
            let tb = Aabb::of_points(&m.triangle_points(t));
            if tb.overlaps(&b) {
                assert!(ts.contains(&t), "missing {t}");
            }
        }
        assert!(m
            .triangles_overlapping(&Aabb {
                min: [10.0, 10.0],
                max: [11.0, 11.0]
            })
            .next()
            .is_none());
    }
}
