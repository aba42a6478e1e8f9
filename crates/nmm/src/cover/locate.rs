//! Point queries on the current geometry of a discretisation.
//!
//! * [`Discretisation::locate`]: the element of a block containing a point, on the
//!   *current* element polygons (they move with the material), boundary-tolerant: the
//!   element whose closed polygon is nearest to the point is chosen, and accepted if that
//!   distance is at most `Discretisation::locate_tol` (`LOCATE_TOL · h` = 2e-5 h, twice
//!   the width of the slivers that discretisation drops, plus the largest reach of a
//!   dropped piece), so points on the block boundary (or within round-off of it, or in a
//!   dropped piece) are found.
//! * [`Discretisation::boundary_pieces`]: splits a segment a→b lying on (or inside) a
//!   block into pieces each inside one element, returning each piece's end points as
//!   material points and its length.
//! * [`Discretisation::displacement_at`]: `u(p) = Σ_k w_k u_{cover k}` (covers without
//!   unknowns, i.e. of fixed blocks, contribute zero).
//!
//! The searches scan the block's elements with a bounding-box test (O(elements of the
//! block) per query); callers with many queries on one geometry should build an
//! [`ElementIndex`] (uniform bucket grid over the block's elements, O(1) average).

use super::build::distance_to_polygon;
use super::{barycentric, Discretisation, MaterialPoint};
use crate::geometry::{dist, lerp, Aabb, Vec2};

/// Relative (to h) tolerance for accepting a point near an element.
pub const LOCATE_TOL: f64 = 2.0 * super::build::MIN_PIECE_WIDTH;

fn poly_box(p: &[Vec2]) -> Aabb {
    Aabb::of_points(p)
}

/// Uniform bucket grid over one block's current element polygons.
#[derive(Debug, Clone)]
pub struct ElementIndex {
    pub block: usize,
    bbox: Aabb,
    cw: f64,
    ch: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    items: Vec<u32>,
}

impl ElementIndex {
    /// Builds the index of `block`'s elements on their current polygons.
    pub fn new(d: &Discretisation, block: usize) -> ElementIndex {
        let elems: &[usize] = d.block_elements.get(block).map_or(&[], |v| v.as_slice());
        let boxes: Vec<Aabb> = elems
            .iter()
            .map(|&e| poly_box(&d.elements[e].polygon))
            .collect();
        let bbox = boxes
            .iter()
            .fold(Aabb::empty(), |a, b| a.merge(b))
            .inflate(d.locate_tol);
        let cell = d.mesh.h;
        let (nx, ny) = if elems.is_empty() {
            (1, 1)
        } else {
            (
                (((bbox.max[0] - bbox.min[0]) / cell).ceil() as usize).clamp(1, 1 << 14),
                (((bbox.max[1] - bbox.min[1]) / cell).ceil() as usize).clamp(1, 1 << 14),
            )
        };
        let cw = ((bbox.max[0] - bbox.min[0]) / nx as f64).max(f64::MIN_POSITIVE);
        let ch = ((bbox.max[1] - bbox.min[1]) / ny as f64).max(f64::MIN_POSITIVE);
        let range = |b: &Aabb| {
            let i0 = (((b.min[0] - bbox.min[0]) / cw).floor().max(0.0) as usize).min(nx - 1);
            let i1 = (((b.max[0] - bbox.min[0]) / cw).floor().max(0.0) as usize).min(nx - 1);
            let j0 = (((b.min[1] - bbox.min[1]) / ch).floor().max(0.0) as usize).min(ny - 1);
            let j1 = (((b.max[1] - bbox.min[1]) / ch).floor().max(0.0) as usize).min(ny - 1);
            (i0, i1, j0, j1)
        };
        let mut count = vec![0u32; nx * ny + 1];
        for b in &boxes {
            let (i0, i1, j0, j1) = range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    count[j * nx + i + 1] += 1;
                }
            }
        }
        for k in 1..count.len() {
            count[k] += count[k - 1];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[nx * ny] as usize];
        for (b, &e) in boxes.iter().zip(elems) {
            let (i0, i1, j0, j1) = range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let c = j * nx + i;
                    items[fill[c] as usize] = e as u32;
                    fill[c] += 1;
                }
            }
        }
        ElementIndex {
            block,
            bbox,
            cw,
            ch,
            nx,
            ny,
            start: count,
            items,
        }
    }

    fn cells(&self, b: &Aabb) -> Option<(usize, usize, usize, usize)> {
        if !self.bbox.overlaps(b) {
            return None;
        }
        let c = |v: f64, lo: f64, s: f64, n: usize| {
            (((v - lo) / s).floor().max(0.0) as usize).min(n - 1)
        };
        Some((
            c(b.min[0], self.bbox.min[0], self.cw, self.nx),
            c(b.max[0], self.bbox.min[0], self.cw, self.nx),
            c(b.min[1], self.bbox.min[1], self.ch, self.ny),
            c(b.max[1], self.bbox.min[1], self.ch, self.ny),
        ))
    }

    /// Candidate elements whose boxes may overlap `b` (may repeat).
    pub fn candidates<'a>(&'a self, b: &Aabb) -> impl Iterator<Item = usize> + 'a {
        let (i0, i1, j0, j1) = self.cells(b).unwrap_or((1, 0, 1, 0));
        (j0..=j1).flat_map(move |j| {
            (i0..=i1).flat_map(move |i| {
                let c = j * self.nx + i;
                self.items[self.start[c] as usize..self.start[c + 1] as usize]
                    .iter()
                    .map(|&e| e as usize)
            })
        })
    }

    /// Like [`Discretisation::locate`], through the index.
    pub fn locate(&self, d: &Discretisation, x: Vec2) -> Option<MaterialPoint> {
        let tol = d.locate_tol;
        d.nearest_of(self.candidates(&Aabb { min: x, max: x }.inflate(tol)), x)
    }
}

impl Discretisation {
    /// Nearest (within tolerance) of the given elements to x, as a material point.
    fn nearest_of(&self, cands: impl Iterator<Item = usize>, x: Vec2) -> Option<MaterialPoint> {
        let tol = self.locate_tol;
        let mut best: Option<(f64, usize)> = None;
        for e in cands {
            let dd = distance_to_polygon(&self.elements[e].polygon, x);
            if dd <= tol && best.is_none_or(|(bd, be)| dd < bd || (dd == bd && e < be)) {
                best = Some((dd, e));
                if dd == 0.0 {
                    break; // an exact hit is a valid answer
                }
            }
        }
        best.map(|(_, e)| MaterialPoint {
            element: e,
            weights: barycentric(&self.elements[e].nodes, x),
        })
    }

    fn block_candidates<'a>(&'a self, block: usize, b: Aabb) -> impl Iterator<Item = usize> + 'a {
        self.block_elements
            .get(block)
            .map_or(&[][..], |v| v.as_slice())
            .iter()
            .copied()
            .filter(move |&e| poly_box(&self.elements[e].polygon).overlaps(&b))
    }

    /// The element of `block` containing `x` on the current geometry, as a material point
    /// (see module doc for the boundary tolerance). `None` if x is not in the block.
    pub fn locate(&self, block: usize, x: Vec2) -> Option<MaterialPoint> {
        let tol = self.locate_tol;
        self.nearest_of(
            self.block_candidates(block, Aabb { min: x, max: x }.inflate(tol)),
            x,
        )
    }

    /// Splits segment a→b (on the boundary of, or inside, `block`) into pieces each inside
    /// one element: `(start, end, length)`, in order from a to b. Parts of the segment
    /// outside the block are skipped.
    pub fn boundary_pieces(
        &self,
        block: usize,
        a: Vec2,
        b: Vec2,
    ) -> Vec<(MaterialPoint, MaterialPoint, f64)> {
        let len = dist(a, b);
        let tol = self.locate_tol;
        let sb = Aabb::of_points(&[a, b]).inflate(tol);
        // keep only the elements near the segment itself (a long oblique segment's box
        // holds a large share of the block): centre within radius + tol of the segment
        let near = |e: &usize| {
            let p = &self.elements[*e].polygon;
            let c = p.iter().fold([0.0, 0.0], |s, v| {
                [s[0] + v[0] / p.len() as f64, s[1] + v[1] / p.len() as f64]
            });
            let r = p.iter().map(|v| dist(*v, c)).fold(0.0, f64::max);
            crate::geometry::polygon::point_segment_distance(c, a, b) <= r + tol
        };
        let cands: Vec<usize> = self.block_candidates(block, sb).filter(near).collect();
        if len == 0.0 || cands.is_empty() {
            return Vec::new();
        }
        // Split parameters: crossings of a→b with every candidate polygon edge, and
        // projections of polygon vertices lying on the segment.
        let ab = [b[0] - a[0], b[1] - a[1]];
        let mut ts = vec![0.0, 1.0];
        for &e in &cands {
            let p = &self.elements[e].polygon;
            let m = p.len();
            for i in 0..m {
                let (c, dd) = (p[i], p[(i + 1) % m]);
                let cd = [dd[0] - c[0], dd[1] - c[1]];
                let den = ab[0] * cd[1] - ab[1] * cd[0];
                let ac = [c[0] - a[0], c[1] - a[1]];
                if den.abs() > 1e-14 * len * crate::geometry::norm(cd) {
                    let t = (ac[0] * cd[1] - ac[1] * cd[0]) / den;
                    let s = (ac[0] * ab[1] - ac[1] * ab[0]) / den;
                    if (0.0..=1.0).contains(&t) && (-1e-12..=1.0 + 1e-12).contains(&s) {
                        ts.push(t);
                    }
                }
                // Vertex c on the segment (covers collinear overlaps).
                let t = (ac[0] * ab[0] + ac[1] * ab[1]) / (len * len);
                if (0.0..=1.0).contains(&t) && dist(lerp(a, b, t), c) <= tol {
                    ts.push(t);
                }
            }
        }
        ts.sort_by(f64::total_cmp);
        let min_dt = 1e-12;
        let mut pieces: Vec<(MaterialPoint, MaterialPoint, f64)> = Vec::new();
        let mut last_t = 0.0;
        let mut open: Option<(usize, f64, f64)> = None; // (element, t0, t1)
        let flush = |open: &mut Option<(usize, f64, f64)>,
                     out: &mut Vec<(MaterialPoint, MaterialPoint, f64)>| {
            if let Some((e, t0, t1)) = open.take() {
                let (x0, x1) = (lerp(a, b, t0), lerp(a, b, t1));
                let n = &self.elements[e].nodes;
                out.push((
                    MaterialPoint {
                        element: e,
                        weights: barycentric(n, x0),
                    },
                    MaterialPoint {
                        element: e,
                        weights: barycentric(n, x1),
                    },
                    (t1 - t0) * len,
                ));
            }
        };
        for &t in &ts[1..] {
            if t - last_t <= min_dt {
                continue;
            }
            let mid = lerp(a, b, 0.5 * (last_t + t));
            let found = self
                .nearest_of(cands.iter().copied(), mid)
                .map(|mp| mp.element);
            match (found, open) {
                (Some(e), Some((oe, t0, _))) if e == oe => open = Some((e, t0, t)),
                (Some(e), _) => {
                    flush(&mut open, &mut pieces);
                    open = Some((e, last_t, t));
                }
                (None, _) => flush(&mut open, &mut pieces),
            }
            last_t = t;
        }
        flush(&mut open, &mut pieces);
        pieces
    }

    /// Displacement of a material point: `Σ_a N_a u_a` of its element's basis (order 0:
    /// `Σ_k w_k u_{cover k}`; zero for covers without unknowns). `u` is the global vector
    /// (length ≥ `n_dofs`).
    pub fn displacement_at(&self, p: &MaterialPoint, u: &[f64]) -> Vec2 {
        self.basis.displacement_at(self, p.element, &p.weights, u)
    }

    /// The current positions (initial plus displacement `u`) of boundary vertices.
    pub fn current_positions(&self, vertices: &[super::BoundaryVertex], u: &[f64]) -> Vec<Vec2> {
        vertices
            .iter()
            .map(|v| {
                let d = self.displacement_at(&v.at, u);
                [v.x0[0] + d[0], v.x0[1] + d[1]]
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use crate::cover::discretise;

    #[test]
    fn locate_follows_moved_elements_and_index_agrees() {
        let l = crate::geometry::fixtures::l_shape();
        let mut d = discretise(&[(l, false)], 0.3).unwrap();
        // Rigid motion of every element: rotate by 0.3 rad and translate.
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let mv = |p: [f64; 2]| [c * p[0] - s * p[1] + 5.0, s * p[0] + c * p[1] - 1.0];
        for el in &mut d.elements {
            el.nodes = el.nodes.map(mv);
            el.polygon.iter_mut().for_each(|p| *p = mv(*p));
        }
        let idx = super::ElementIndex::new(&d, 0);
        for x0 in [
            [0.5, 0.5],
            [1.5, 0.2],
            [0.2, 1.9],
            [1.0, 1.0],
            [2.0, 0.0],
            [0.0, 1.3],
        ] {
            let x = mv(x0);
            let a = d.locate(0, x).expect("inside or on boundary");
            let b = idx.locate(&d, x).expect("index finds it too");
            for mp in [a, b] {
                let n = d.elements[mp.element].nodes;
                let y = [0, 1].map(|i| (0..3).map(|k| mp.weights[k] * n[k][i]).sum::<f64>());
                assert!(crate::geometry::dist(x, y) < 1e-12);
            }
        }
        // Outside the (moved) L: the notch and far away.
        assert!(d.locate(0, mv([1.5, 1.5])).is_none());
        assert!(idx.locate(&d, mv([1.5, 1.5])).is_none());
        assert!(d.locate(0, [0.5, 0.5]).is_none());
        // Boundary pieces of the moved bottom edge cover it.
        let p = d.boundary_pieces(0, mv([0.0, 0.0]), mv([2.0, 0.0]));
        let len: f64 = p.iter().map(|x| x.2).sum();
        assert!((len - 2.0).abs() < 1e-12);
        assert!(p.len() >= 7); // split at every mesh line crossed (h = 0.3)
    }
}
