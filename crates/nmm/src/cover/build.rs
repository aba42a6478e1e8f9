//! Building the discretisation: manifold elements, physical covers, dof map, refined
//! block boundaries.
//!
//! For each block `b` (a CCW simple polygon) and each mesh square overlapping its box:
//!
//! 1. **Rasterise** the block's edges onto the squares (`marked` = some block edge passes
//!    within `EDGE_TOL = 1e-9 h` of the square).
//! 2. **Unmarked squares** are entirely inside or entirely outside the block; a scan line
//!    through the row's square centres (crossing parity) decides which. Inside squares give
//!    two elements whose polygons are their triangles (the *fast path*: no clipping).
//! 3. **Marked squares**: each triangle is clipped by the block
//!    ([`Clipper::clip_polygon_by_triangle`], one fixed integer grid for the model); one
//!    element per connected piece. Pieces thinner than `MIN_PIECE_WIDTH · h` = 1e-5 h
//!    (width = area / half-perimeter: slivers where a block edge passes close to a mesh
//!    line or node) are dropped. Their vertices are only known to ~1e-15 of the model
//!    size after clipping, so their own area, and the equilibrium of a cover supported
//!    only by them, carry relative errors of 1e-15 × size / width: kept, a sliver of
//!    width 1e-12 h put errors of 1e-3 in its stress. Dropped, they remove at most
//!    1e-5 h × perimeter from a block's area (and mass and weight), and the neighbouring
//!    element carries the boundary (its weights extend linearly over the gap, exactly
//!    for a linear field). A dropped piece need not be a strip: the tip of a block corner
//!    a few 1e-5 h across a mesh line is small in every direction. Point searches
//!    therefore accept elements up to `Discretisation::locate_tol`, which adds the
//!    largest *reach* of a dropped piece (distance from its vertices to its part of the
//!    triangle's edges) to `2 · MIN_PIECE_WIDTH · h`.
//!    `tests/elastic_patch.rs` checks the patch test to 1e-8 with edges 1e-12 h … 1e-3 h
//!    from mesh lines.
//!
//! **Physical covers.** For mesh node `n` and block `b`, the elements of `b` in the star of
//! `n` are grouped into connected pieces: elements `e` ⊂ triangle `t` and `e'` ⊂ triangle
//! `t'`, with `t, t'` sharing a mesh edge incident to `n`, are connected when both their
//! polygons have boundary pieces lying on that edge and those pieces overlap over a length
//! `> EDGE_TOL`. A union–find over the slots `(element, local node)` realises this; each
//! class is one [`PhysicalCover`]. Covers are numbered block by block, and by node index
//! within a block; free blocks' covers get the basis's unknowns per cover consecutively in
//! that order (row-major node order keeps the bandwidth ≈ (nx + 1) · unknowns per cover),
//! less, at order 1, the higher terms [`super::dependence`] removes.
//!
//! **Boundaries.** Each block edge is split at every crossing with a mesh line (vertical,
//! horizontal, or diagonal `u − v ∈ ℤ` in grid coordinates); crossings closer than
//! `EDGE_TOL` to a previous split point or to the edge's end are merged with it. Each
//! vertex becomes a [`MaterialPoint`] in the element of the block nearest to it (distance
//! 0 when inside or on its boundary), and each segment gets the element nearest to its
//! midpoint; because of the merging, a segment lies in its element up to `EDGE_TOL`.

use super::crack::{subtract_intervals, CoverCrack, Cracks};
use super::{
    barycentric, BlockBoundary, BoundaryVertex, CoverBasis, Discretisation, ManifoldElement,
    MaterialPoint, MathMesh, PhysicalCover,
};
use crate::geometry::clip::Clipper;
use crate::geometry::moments::polygon_area;
use crate::geometry::polygon::point_segment_distance;
use crate::geometry::{Aabb, Vec2};

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct DiscretiseError(pub String);

/// Largest mathematical mesh accepted (nodes).
pub const MAX_MESH_NODES: usize = 50_000_000;

/// Relative (to h) tolerance for "touching" a mesh edge and for overlap lengths.
const EDGE_TOL: f64 = 1e-9;
/// Relative (to h²) area below which clipped pieces are dropped.
/// Pieces thinner than this (× h) are dropped (see the module docs).
pub const MIN_PIECE_WIDTH: f64 = 1e-5;

/// A block to discretise: its polygon (counter-clockwise), its holes (clockwise,
/// strictly inside it: [`crate::geometry::region`]) and whether it is fixed.
#[derive(Debug, Clone, Copy)]
pub struct Shape<'a> {
    pub outer: &'a [Vec2],
    pub holes: &'a [Vec<Vec2>],
    pub fixed: bool,
}

impl Shape<'_> {
    /// The loops: the polygon, then the holes.
    fn loops(&self) -> Vec<&[Vec2]> {
        std::iter::once(self.outer)
            .chain(self.holes.iter().map(|h| h.as_slice()))
            .collect()
    }
}

/// The shapes of blocks `(vertices, fixed)` without holes.
fn plain(blocks: &[(Vec<Vec2>, bool)]) -> Vec<Shape<'_>> {
    blocks
        .iter()
        .map(|(p, fixed)| Shape {
            outer: p,
            holes: &[],
            fixed: *fixed,
        })
        .collect()
}

/// Discretise blocks `(vertices CCW, fixed)` with a mathematical mesh of size `h`
/// covering all blocks (see [`MathMesh::covering`]).
pub fn discretise(blocks: &[(Vec<Vec2>, bool)], h: f64) -> Result<Discretisation, DiscretiseError> {
    discretise_through(blocks, h, None)
}

/// As [`discretise`], with a mesh node at `origin` when given (`[cover] origin`).
pub fn discretise_through(
    blocks: &[(Vec<Vec2>, bool)],
    h: f64,
    origin: Option<Vec2>,
) -> Result<Discretisation, DiscretiseError> {
    discretise_with(blocks, h, origin, CoverBasis::Constant)
}

/// As [`discretise_through`], with the cover functions `basis` (`[cover] order`).
pub fn discretise_with(
    blocks: &[(Vec<Vec2>, bool)],
    h: f64,
    origin: Option<Vec2>,
    basis: CoverBasis,
) -> Result<Discretisation, DiscretiseError> {
    discretise_shapes(&plain(blocks), &[], h, origin, basis)
}

/// As [`discretise_with`], the covers split by `cracks` (traces ending inside their
/// blocks, [`super::crack`]).
pub fn discretise_cracked(
    blocks: &[(Vec<Vec2>, bool)],
    cracks: &[CoverCrack],
    h: f64,
    origin: Option<Vec2>,
    basis: CoverBasis,
) -> Result<Discretisation, DiscretiseError> {
    discretise_shapes(&plain(blocks), cracks, h, origin, basis)
}

/// As [`discretise_cracked`], for blocks that may have holes: the general entry.
pub fn discretise_shapes(
    blocks: &[Shape],
    cracks: &[CoverCrack],
    h: f64,
    origin: Option<Vec2>,
    basis: CoverBasis,
) -> Result<Discretisation, DiscretiseError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(DiscretiseError(format!(
            "mesh size h = {h} must be finite and positive"
        )));
    }
    if blocks.is_empty() {
        return Err(DiscretiseError("no blocks to discretise".into()));
    }
    for (b, shape) in blocks.iter().enumerate() {
        validate_shape(b, shape)?;
    }
    let bbox = blocks
        .iter()
        .fold(Aabb::empty(), |acc, s| acc.merge(&Aabb::of_points(s.outer)));
    let mesh = MathMesh::covering_through(&bbox, h, MAX_MESH_NODES, origin).ok_or_else(|| {
        DiscretiseError(format!(
            "mesh size h = {h} gives too many nodes for the model box (limit {MAX_MESH_NODES})"
        ))
    })?;
    discretise_shapes_on_mesh(blocks, cracks, mesh, basis)
}

/// Discretise blocks on a given mathematical mesh (every block strictly inside the
/// mesh box). Blocks are validated as in [`discretise`].
pub fn discretise_on_mesh(
    blocks: &[(Vec<Vec2>, bool)],
    mesh: MathMesh,
) -> Result<Discretisation, DiscretiseError> {
    discretise_on_mesh_with(blocks, mesh, CoverBasis::Constant)
}

/// As [`discretise_on_mesh`], with the cover functions `basis`.
pub fn discretise_on_mesh_with(
    blocks: &[(Vec<Vec2>, bool)],
    mesh: MathMesh,
    basis: CoverBasis,
) -> Result<Discretisation, DiscretiseError> {
    discretise_shapes_on_mesh(&plain(blocks), &[], mesh, basis)
}

/// As [`discretise_on_mesh_with`], the covers split by `cracks` ([`super::crack`]).
pub fn discretise_on_mesh_cracked(
    blocks: &[(Vec<Vec2>, bool)],
    cracks: &[CoverCrack],
    mesh: MathMesh,
    basis: CoverBasis,
) -> Result<Discretisation, DiscretiseError> {
    discretise_shapes_on_mesh(&plain(blocks), cracks, mesh, basis)
}

/// As [`discretise_on_mesh_cracked`], for blocks that may have holes.
pub fn discretise_shapes_on_mesh(
    blocks: &[Shape],
    cracks: &[CoverCrack],
    mesh: MathMesh,
    basis: CoverBasis,
) -> Result<Discretisation, DiscretiseError> {
    if !(mesh.h.is_finite() && mesh.h > 0.0 && mesh.nx > 0 && mesh.ny > 0) {
        return Err(DiscretiseError("invalid mathematical mesh".into()));
    }
    let mb = mesh.bbox();
    for (b, shape) in blocks.iter().enumerate() {
        validate_shape(b, shape)?;
        let poly = shape.outer;
        if poly.iter().any(|p| {
            !(p[0] > mb.min[0] && p[0] < mb.max[0] && p[1] > mb.min[1] && p[1] < mb.max[1])
        }) {
            return Err(DiscretiseError(format!(
                "block {b} is not strictly inside the mathematical mesh"
            )));
        }
    }
    let clipper = Clipper::new(mb).map_err(|e| DiscretiseError(format!("clipper: {e}")))?;

    let mut d = Discretisation {
        locate_tol: super::LOCATE_TOL * mesh.h,
        mesh,
        covers: Vec::new(),
        elements: Vec::new(),
        block_elements: Vec::with_capacity(blocks.len()),
        boundaries: Vec::with_capacity(blocks.len()),
        n_dofs: 0,
        basis,
        cracks: cracks.to_vec(),
        slits: Vec::new(),
    };
    for c in cracks {
        validate_crack(c, blocks.len())?;
    }
    for (b, shape) in blocks.iter().enumerate() {
        build_block(&mut d, &clipper, b, shape, &Cracks::of_block(cracks, b))?;
    }
    if basis != CoverBasis::Constant {
        for bd in &mut d.boundaries {
            *bd = with_midpoints(&d.elements, bd);
        }
    }
    // the slits' contact vertices follow their block's boundary vertices
    let mut next_vertex: Vec<usize> = d.boundaries.iter().map(|b| b.vertices.len()).collect();
    for s in &mut d.slits {
        s.first = next_vertex[s.block];
        next_vertex[s.block] += s.vertex_count();
    }
    // Dof numbering: covers are already block by block, node by node; at order 1 less the
    // higher terms removed for linear dependence.
    let fixed: Vec<bool> = blocks.iter().map(|b| b.fixed).collect();
    let kept = match basis {
        CoverBasis::Constant => Vec::new(),
        CoverBasis::Linear => super::dependence::kept_terms(&d, &fixed).terms,
    };
    let mut next = 0;
    for (ci, c) in d.covers.iter_mut().enumerate() {
        if !fixed[c.block] {
            c.dof = Some(next);
            next += 2;
            for j in 1..basis.terms() {
                if kept[ci][j - 1] {
                    c.terms.push(next);
                    next += 2;
                } else {
                    c.terms.push(super::basis::NO_DOF);
                }
            }
        }
    }
    d.n_dofs = next;
    Ok(d)
}

/// The boundary with the midpoint of every segment inserted (each half in the segment's
/// element and on its polygon edge): the contact quadrature points of first-order covers.
fn with_midpoints(elements: &[ManifoldElement], bd: &BlockBoundary) -> BlockBoundary {
    let m = bd.vertices.len();
    let mut out = BlockBoundary {
        vertices: Vec::with_capacity(2 * m),
        segment_elements: Vec::with_capacity(2 * m),
        segment_edges: Vec::with_capacity(2 * m),
        loops: bd.loops.iter().map(|s| 2 * s).collect(),
    };
    for i in 0..m {
        let (v, next) = (bd.vertices[i], bd.vertices[bd.next(i)]);
        let e = bd.segment_elements[i];
        let x = crate::geometry::lerp(v.x0, next.x0, 0.5);
        out.vertices.push(v);
        out.vertices.push(BoundaryVertex {
            x0: x,
            at: MaterialPoint {
                element: e,
                weights: barycentric(&elements[e].nodes, x),
            },
            corner: false,
            midpoint: true,
        });
        for _ in 0..2 {
            out.segment_elements.push(e);
            out.segment_edges.push(bd.segment_edges[i]);
        }
    }
    out
}

/// Checks a block's polygon ([`validate_block`]) and its holes (clockwise simple polygons
/// with finite coordinates).
fn validate_shape(b: usize, shape: &Shape) -> Result<(), DiscretiseError> {
    validate_block(b, shape.outer)?;
    for (k, h) in shape.holes.iter().enumerate() {
        let mut ccw = h.clone();
        ccw.reverse();
        validate_block(b, &ccw)
            .map_err(|e| DiscretiseError(format!("{} (hole {k}, clockwise)", e.0)))?;
    }
    Ok(())
}

/// Checks that a crack names a block and has finite points.
fn validate_crack(c: &CoverCrack, n_blocks: usize) -> Result<(), DiscretiseError> {
    if c.block >= n_blocks {
        return Err(DiscretiseError(format!(
            "a crack names block {} of {n_blocks}",
            c.block
        )));
    }
    if c.points.len() < 2 || c.points.iter().flatten().any(|v| !v.is_finite()) {
        return Err(DiscretiseError(format!(
            "a crack of block {} has fewer than 2 points or a non-finite point",
            c.block
        )));
    }
    Ok(())
}

/// Checks that a block is a CCW simple polygon with finite coordinates.
fn validate_block(b: usize, poly: &[Vec2]) -> Result<(), DiscretiseError> {
    let n = poly.len();
    if n < 3 {
        return Err(DiscretiseError(format!(
            "block {b} has {n} vertices (at least 3 needed)"
        )));
    }
    if poly.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return Err(DiscretiseError(format!(
            "block {b} has a non-finite vertex"
        )));
    }
    let area = polygon_area(poly);
    if area.is_nan() || area <= 0.0 {
        return Err(DiscretiseError(format!(
            "block {b} is not counter-clockwise (signed area {area:e})"
        )));
    }
    for i in 0..n {
        if poly[i] == poly[(i + 1) % n] {
            return Err(DiscretiseError(format!(
                "block {b} has a repeated vertex at index {i}"
            )));
        }
    }
    // Simplicity: no two non-adjacent edges may touch (O(n²), blocks are small).
    for i in 0..n {
        let (a, bb) = (poly[i], poly[(i + 1) % n]);
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            let (c, e) = (poly[j], poly[(j + 1) % n]);
            if segments_touch(a, bb, c, e) {
                return Err(DiscretiseError(format!(
                    "block {b} is not simple: edges {i} and {j} intersect"
                )));
            }
        }
    }
    Ok(())
}

fn orient(a: Vec2, b: Vec2, c: Vec2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Closed segments ab and cd share a point.
fn segments_touch(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    let on = |p: Vec2, q: Vec2, r: Vec2| {
        r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
        && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
    {
        return true;
    }
    (o1 == 0.0 && on(a, b, c))
        || (o2 == 0.0 && on(a, b, d))
        || (o3 == 0.0 && on(c, d, a))
        || (o4 == 0.0 && on(c, d, b))
}

/// Coverage of one triangle edge by an element's boundary.
#[derive(Debug, Clone, Copy)]
enum Cov {
    None,
    Full,
    /// Range into the interval list: parameters along the edge from its local node k
    /// to node k+1.
    Part(u32, u32),
}

/// Per-block lookup triangle → its elements (contiguous in `Discretisation::elements`),
/// dense over the block's square range.
struct TriMap {
    i0: usize,
    j0: usize,
    w: usize,
    hgt: usize,
    nx: usize,
    first: Vec<u32>,
    count: Vec<u16>,
}

impl TriMap {
    fn slot(&self, t: usize) -> Option<usize> {
        let s = t / 2;
        let (i, j) = (s % self.nx, s / self.nx);
        if i < self.i0 || j < self.j0 || i >= self.i0 + self.w || j >= self.j0 + self.hgt {
            return None;
        }
        Some(2 * ((j - self.j0) * self.w + (i - self.i0)) + t % 2)
    }
    /// Global element indices in triangle t.
    fn elements(&self, t: usize) -> std::ops::Range<usize> {
        match self.slot(t) {
            Some(s) if self.count[s] > 0 => {
                let f = self.first[s] as usize;
                f..f + self.count[s] as usize
            }
            _ => 0..0,
        }
    }
}

/// The squares `i0..=i1 × j0..=j1` of one block.
struct SquareRange {
    i0: usize,
    i1: usize,
    j0: usize,
    j1: usize,
}

impl SquareRange {
    /// Marks the squares that the segment p→q (grid coordinates) passes within
    /// `EDGE_TOL` of (`marked` is row-major over the range).
    fn rasterise(&self, p: Vec2, q: Vec2, marked: &mut [bool]) {
        let SquareRange { i0, i1, j0, j1 } = *self;
        let w = i1 - i0 + 1;
        let (vlo, vhi) = (p[1].min(q[1]) - EDGE_TOL, p[1].max(q[1]) + EDGE_TOL);
        let jlo = ((vlo - 1.0).ceil().max(j0 as f64) as usize).max(j0);
        let jhi = (vhi.floor().max(0.0) as usize).min(j1);
        for j in jlo..=jhi {
            // Parameter range where v(t) ∈ [j − tol, j + 1 + tol].
            let (ya, yb) = (j as f64 - EDGE_TOL, j as f64 + 1.0 + EDGE_TOL);
            let (ta, tb) = if (q[1] - p[1]).abs() < 1e-300 {
                if p[1] >= ya && p[1] <= yb {
                    (0.0, 1.0)
                } else {
                    continue;
                }
            } else {
                let t1 = (ya - p[1]) / (q[1] - p[1]);
                let t2 = (yb - p[1]) / (q[1] - p[1]);
                (t1.min(t2).max(0.0), t1.max(t2).min(1.0))
            };
            if ta > tb {
                continue;
            }
            let ua = p[0] + ta * (q[0] - p[0]);
            let ub = p[0] + tb * (q[0] - p[0]);
            let (ulo, uhi) = (ua.min(ub) - EDGE_TOL, ua.max(ub) + EDGE_TOL);
            let ilo = ((ulo - 1.0).ceil().max(i0 as f64) as usize).max(i0);
            let ihi = (uhi.floor().max(0.0) as usize).min(i1);
            for i in ilo..=ihi {
                marked[(j - j0) * w + (i - i0)] = true;
            }
        }
    }
}

struct UnionFind(Vec<u32>);
impl UnionFind {
    fn new(n: usize) -> Self {
        UnionFind((0..n as u32).collect())
    }
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let p = self.0[x as usize];
            self.0[x as usize] = self.0[p as usize];
            x = p;
        }
        x
    }
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.0[hi as usize] = lo;
        }
    }
}

fn build_block(
    d: &mut Discretisation,
    clipper: &Clipper,
    b: usize,
    shape: &Shape,
    cracks: &Cracks,
) -> Result<(), DiscretiseError> {
    let mesh = d.mesh.clone();
    let h = mesh.h;
    let poly = shape.outer;
    let loops = shape.loops();
    let bbox = Aabb::of_points(poly).inflate(EDGE_TOL * h);
    let (i0, i1, j0, j1) = mesh
        .square_range(&bbox)
        .ok_or_else(|| DiscretiseError(format!("block {b} misses the mesh")))?;
    let (w, hgt) = (i1 - i0 + 1, j1 - j0 + 1);
    // The block's edges (every loop's) in grid coordinates.
    let grid = |p: &Vec2| [(p[0] - mesh.origin[0]) / h, (p[1] - mesh.origin[1]) / h];
    let edges: Vec<(Vec2, Vec2)> = loops
        .iter()
        .flat_map(|l| (0..l.len()).map(move |k| (grid(&l[k]), grid(&l[(k + 1) % l.len()]))))
        .collect();

    // 1. Rasterise the edges (and the cracks: their squares are cut by them).
    let range = SquareRange { i0, i1, j0, j1 };
    let mut marked = vec![false; w * hgt];
    for &(p, q) in &edges {
        range.rasterise(p, q, &mut marked);
    }
    let mut crack_marked = Vec::new();
    if !cracks.is_empty() {
        crack_marked = vec![false; w * hgt];
        for &(p, q) in cracks.segments() {
            range.rasterise(grid(&p), grid(&q), &mut crack_marked);
        }
        for (m, &c) in marked.iter_mut().zip(&crack_marked) {
            *m |= c;
        }
    }

    // 2./3. Elements, square by square, row by row.
    let first_elem = d.elements.len();
    let mut map = TriMap {
        i0,
        j0,
        w,
        hgt,
        nx: mesh.nx,
        first: vec![0; 2 * w * hgt],
        count: vec![0; 2 * w * hgt],
    };
    let mut cov: Vec<[Cov; 3]> = Vec::new();
    let mut intervals: Vec<[f64; 2]> = Vec::new();
    let mut crossings: Vec<f64> = Vec::new();
    let min_width = MIN_PIECE_WIDTH * h;
    for j in j0..=j1 {
        let yc = j as f64 + 0.5;
        crossings.clear();
        for &(p, q) in &edges {
            if (p[1] <= yc) != (q[1] <= yc) {
                crossings.push(p[0] + (yc - p[1]) / (q[1] - p[1]) * (q[0] - p[0]));
            }
        }
        crossings.sort_by(f64::total_cmp);
        let mut ptr = 0;
        for i in i0..=i1 {
            let xc = i as f64 + 0.5;
            while ptr < crossings.len() && crossings[ptr] < xc {
                ptr += 1;
            }
            let is_marked = marked[(j - j0) * w + (i - i0)];
            let is_cracked = !crack_marked.is_empty() && crack_marked[(j - j0) * w + (i - i0)];
            if !is_marked && ptr % 2 == 0 {
                continue; // outside
            }
            for upper in [false, true] {
                let t = mesh.triangle_index(i, j, upper);
                let slot = map.slot(t).expect("square in range");
                map.first[slot] = d.elements.len() as u32;
                let tri = mesh.triangle_points(t);
                if !is_marked {
                    push_element(d, b, t, tri, tri.to_vec());
                    cov.push([Cov::Full; 3]);
                    map.count[slot] = 1;
                    continue;
                }
                let pieces = clipper
                    .clip_loops_by_triangle(&loops, &tri)
                    .map_err(|e| DiscretiseError(format!("block {b}: {e}")))?;
                let pieces = if is_cracked {
                    let mut split = Vec::new();
                    for piece in pieces {
                        split.extend(
                            cracks
                                .split(piece, &tri, h)
                                .map_err(|e| DiscretiseError(format!("block {b}: crack: {e}")))?,
                        );
                    }
                    split
                } else {
                    pieces
                };
                let mut cnt = 0u16;
                for piece in pieces {
                    if piece_width(&piece) < min_width {
                        let reach = dropped_reach(&tri, &piece, h);
                        d.locate_tol = d.locate_tol.max(super::LOCATE_TOL * h + reach);
                        continue;
                    }
                    let mut c = edge_coverage(&tri, &piece, h, &mut intervals);
                    if is_cracked {
                        c = without_cracks(c, &tri, cracks, h, &mut intervals);
                    }
                    cov.push(c);
                    push_element(d, b, t, tri, piece);
                    cnt += 1;
                }
                map.count[slot] = cnt;
            }
        }
    }
    let n_elem = d.elements.len() - first_elem;
    if n_elem == 0 {
        return Err(DiscretiseError(format!(
            "block {b} produced no manifold elements"
        )));
    }
    d.block_elements
        .push((first_elem..d.elements.len()).collect());

    // Physical covers by union–find over (element, local node) slots.
    let mut uf = UnionFind::new(3 * n_elem);
    let ltol = EDGE_TOL;
    for le in 0..n_elem {
        let e = first_elem + le;
        let t = d.elements[e].triangle;
        for k in 0..3 {
            let Some((tn, kn)) = mesh.neighbour(t, k) else {
                continue;
            };
            if tn < t {
                continue; // each shared edge once
            }
            let ce = cov[le][k];
            if matches!(ce, Cov::None) {
                continue;
            }
            for en in map.elements(tn) {
                let ln = en - first_elem;
                let cn = cov[ln][kn];
                if overlaps(ce, cn, &intervals, ltol) {
                    // Node k of t is node kn+1 of tn, node k+1 of t is node kn of tn.
                    uf.union((3 * le + k) as u32, (3 * ln + (kn + 1) % 3) as u32);
                    uf.union((3 * le + (k + 1) % 3) as u32, (3 * ln + kn) as u32);
                }
            }
        }
    }
    // Temporary covers in first-appearance order, then sorted by node.
    let mut root_cover = vec![u32::MAX; 3 * n_elem];
    let mut tmp_nodes: Vec<usize> = Vec::new();
    let mut slot_cover = vec![0u32; 3 * n_elem];
    for le in 0..n_elem {
        let nodes = mesh.triangle(d.elements[first_elem + le].triangle);
        for k in 0..3 {
            let r = uf.find((3 * le + k) as u32) as usize;
            if root_cover[r] == u32::MAX {
                root_cover[r] = tmp_nodes.len() as u32;
                tmp_nodes.push(nodes[k]);
            }
            slot_cover[3 * le + k] = root_cover[r];
        }
    }
    let mut order: Vec<u32> = (0..tmp_nodes.len() as u32).collect();
    order.sort_by_key(|&c| tmp_nodes[c as usize]); // stable: ties keep first appearance
    let mut final_id = vec![0usize; tmp_nodes.len()];
    let base = d.covers.len();
    for (rank, &c) in order.iter().enumerate() {
        final_id[c as usize] = base + rank;
        d.covers.push(PhysicalCover {
            block: b,
            node: tmp_nodes[c as usize],
            dof: None,
            terms: Vec::new(),
            support_area: 0.0,
        });
    }
    for le in 0..n_elem {
        let e = first_elem + le;
        let area = polygon_area(&d.elements[e].polygon);
        for k in 0..3 {
            let c = final_id[slot_cover[3 * le + k] as usize];
            d.elements[e].covers[k] = c;
            d.covers[c].support_area += area;
        }
    }

    // Refined boundary.
    let boundary = refine_boundary(d, &map, b, &loops)?;
    d.boundaries.push(boundary);

    // The faces of the block's cracks.
    if !cracks.is_empty() {
        let midpoints = d.basis != CoverBasis::Constant;
        let mut slits = Vec::new();
        for (ci, c) in d.cracks.iter().enumerate().filter(|(_, c)| c.block == b) {
            let others: Vec<(Vec2, Vec2)> = d
                .cracks
                .iter()
                .enumerate()
                .filter(|&(k, o)| k != ci && o.block == b)
                .flat_map(|(_, o)| o.points.windows(2).map(|w| (w[0], w[1])))
                .collect();
            let pts = super::slit::refine(&c.points, &others, mesh.origin, h, EDGE_TOL * h);
            let nearest = |x: Vec2| nearest_element(d, &map, x);
            let mut faces = Vec::with_capacity(2);
            for side in [1.0, -1.0] {
                faces.push(
                    super::slit::face(&pts, side, h, &d.elements, midpoints, &nearest)
                        .map_err(|e| DiscretiseError(format!("block {b}, crack {ci}: {e}")))?,
                );
            }
            let f1 = faces.pop().unwrap();
            let f0 = faces.pop().unwrap();
            slits.push(super::slit::Slit {
                block: b,
                crack: ci,
                joint: c.joint,
                faces: [f0, f1],
                first: 0,
            });
        }
        d.slits.extend(slits);
    }
    Ok(())
}

fn push_element(d: &mut Discretisation, b: usize, t: usize, tri: [Vec2; 3], polygon: Vec<Vec2>) {
    d.elements.push(ManifoldElement {
        block: b,
        triangle: t,
        nodes: tri,
        covers: [0; 3],
        polygon,
    });
}

/// Which parts of each triangle edge the piece's boundary lies on.
fn edge_coverage(
    tri: &[Vec2; 3],
    piece: &[Vec2],
    h: f64,
    intervals: &mut Vec<[f64; 2]>,
) -> [Cov; 3] {
    let mut out = [Cov::None; 3];
    let m = piece.len();
    for (k, c) in out.iter_mut().enumerate() {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        let len = len2.sqrt();
        let dtol = EDGE_TOL * h;
        let param = |p: Vec2| ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / len2;
        let on = |p: Vec2| {
            let dist = ((p[0] - a[0]) * ab[1] - (p[1] - a[1]) * ab[0]).abs() / len;
            let s = param(p);
            dist <= dtol && (-EDGE_TOL..=1.0 + EDGE_TOL).contains(&s)
        };
        let start = intervals.len();
        for i in 0..m {
            let (p, q) = (piece[i], piece[(i + 1) % m]);
            if on(p) && on(q) {
                let (sp, sq) = (param(p).clamp(0.0, 1.0), param(q).clamp(0.0, 1.0));
                if (sq - sp).abs() > 0.0 {
                    intervals.push([sp.min(sq), sp.max(sq)]);
                }
            }
        }
        let cnt = intervals.len() - start;
        *c = if cnt == 0 {
            Cov::None
        } else if cnt == 1 && intervals[start][0] == 0.0 && intervals[start][1] == 1.0 {
            intervals.truncate(start);
            Cov::Full
        } else {
            Cov::Part(start as u32, cnt as u32)
        };
    }
    out
}

/// The coverage `c` less the parts of the triangle's edges that a crack runs along (no
/// connection of covers passes through a crack).
fn without_cracks(
    c: [Cov; 3],
    tri: &[Vec2; 3],
    cracks: &Cracks,
    h: f64,
    intervals: &mut Vec<[f64; 2]>,
) -> [Cov; 3] {
    let mut out = c;
    for (k, ck) in out.iter_mut().enumerate() {
        if matches!(ck, Cov::None) {
            continue;
        }
        let holes = cracks.on_edge(tri[k], tri[(k + 1) % 3], h);
        if holes.is_empty() {
            continue;
        }
        let from: Vec<[f64; 2]> = match *ck {
            Cov::None => Vec::new(),
            Cov::Full => vec![[0.0, 1.0]],
            Cov::Part(s, n) => intervals[s as usize..(s + n) as usize].to_vec(),
        };
        let left = subtract_intervals(&from, &holes, EDGE_TOL);
        *ck = if left.is_empty() {
            Cov::None
        } else {
            let start = intervals.len() as u32;
            intervals.extend_from_slice(&left);
            Cov::Part(start, left.len() as u32)
        };
    }
    out
}

/// Do the coverages of one mesh edge seen from its two triangles overlap by more than
/// `tol` (in edge parameter)? `b` is parametrised in the opposite direction.
fn overlaps(a: Cov, b: Cov, intervals: &[[f64; 2]], tol: f64) -> bool {
    let list = |c: Cov| -> &[[f64; 2]] {
        match c {
            Cov::None => &[],
            Cov::Full => &[[0.0, 1.0]],
            Cov::Part(s, n) => &intervals[s as usize..(s + n) as usize],
        }
    };
    if matches!(a, Cov::None) || matches!(b, Cov::None) {
        return false;
    }
    for ia in list(a) {
        for ib in list(b) {
            let (lo, hi) = (1.0 - ib[1], 1.0 - ib[0]);
            if ia[1].min(hi) - ia[0].max(lo) > tol {
                return true;
            }
        }
    }
    false
}

/// Distance from `x` to the closed polygon (0 inside or on it).
pub(crate) fn distance_to_polygon(poly: &[Vec2], x: Vec2) -> f64 {
    let n = poly.len();
    let mut inside = false;
    let mut best = f64::INFINITY;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > x[1]) != (b[1] > x[1]) {
            let xc = a[0] + (x[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if x[0] < xc {
                inside = !inside;
            }
        }
        let ab = [b[0] - a[0], b[1] - a[1]];
        let l2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = if l2 > 0.0 {
            (((x[0] - a[0]) * ab[0] + (x[1] - a[1]) * ab[1]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dx = a[0] + t * ab[0] - x[0];
        let dy = a[1] + t * ab[1] - x[1];
        best = best.min(dx.hypot(dy));
    }
    if inside {
        0.0
    } else {
        best
    }
}

/// Width of a piece: area / half-perimeter (δ for a strip of width δ).
fn piece_width(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    let half_perimeter: f64 = 0.5
        * (0..n)
            .map(|i| crate::geometry::dist(poly[i], poly[(i + 1) % n]))
            .sum::<f64>();
    if half_perimeter > 0.0 {
        polygon_area(poly) / half_perimeter
    } else {
        0.0
    }
}

/// Reach of a dropped piece of triangle `tri`: an upper bound on the distance from a
/// point of its block-edge boundary to the *joins*, the parts of its boundary lying on
/// the triangle's edges (where the rest of the block continues into the neighbouring
/// triangles). Along a block-edge segment pq, the distance to one join J is convex, so
/// it is at most max(d(p, J), d(q, J)); the distance to the nearest join is also at most
/// (d(p) + d(q) + |pq|) / 2. The smaller of the two bounds is taken, segment by segment.
/// Interior points are within the piece's width (< `MIN_PIECE_WIDTH · h`) of its
/// boundary. A piece with no join (a whole block inside one triangle) reaches its own
/// diameter.
fn dropped_reach(tri: &[Vec2; 3], piece: &[Vec2], h: f64) -> f64 {
    let m = piece.len();
    let dtol = EDGE_TOL * h;
    let on_edge = |p: Vec2, k: usize| point_segment_distance(p, tri[k], tri[(k + 1) % 3]) <= dtol;
    let is_join = |p: Vec2, q: Vec2| (0..3).any(|k| on_edge(p, k) && on_edge(q, k));
    let segments = (0..m).map(|i| (piece[i], piece[(i + 1) % m]));
    let joins: Vec<(Vec2, Vec2)> = segments.clone().filter(|&(p, q)| is_join(p, q)).collect();
    if joins.is_empty() {
        return Aabb::of_points(piece).diagonal();
    }
    let to_join = |x: Vec2, j: &(Vec2, Vec2)| point_segment_distance(x, j.0, j.1);
    let to_joins = |x: Vec2| {
        joins
            .iter()
            .map(|j| to_join(x, j))
            .fold(f64::INFINITY, f64::min)
    };
    segments
        .filter(|&(p, q)| !is_join(p, q))
        .map(|(p, q)| {
            let per_join = joins
                .iter()
                .map(|j| to_join(p, j).max(to_join(q, j)))
                .fold(f64::INFINITY, f64::min);
            let along = 0.5 * (to_joins(p) + to_joins(q) + crate::geometry::dist(p, q));
            per_join.min(along)
        })
        .fold(0.0, f64::max)
}

/// Nearest element of the block (through the triangle map) to `x`, within
/// `d.locate_tol` (a boundary point may lie in a dropped piece).
fn nearest_element(d: &Discretisation, map: &TriMap, x: Vec2) -> Option<usize> {
    let tol = d.locate_tol;
    let bx = Aabb { min: x, max: x }.inflate(tol);
    let mut best: Option<(f64, usize)> = None;
    for t in d.mesh.triangles_overlapping(&bx) {
        for e in map.elements(t) {
            let dist = distance_to_polygon(&d.elements[e].polygon, x);
            if best.is_none_or(|(bd, _)| dist < bd) {
                best = Some((dist, e));
            }
        }
    }
    best.map(|(_, e)| e)
}

fn refine_boundary(
    d: &Discretisation,
    map: &TriMap,
    b: usize,
    loops: &[&[Vec2]],
) -> Result<BlockBoundary, DiscretiseError> {
    let mesh = &d.mesh;
    let h = mesh.h;
    let total: usize = loops.iter().map(|l| l.len()).sum();
    let mut pts: Vec<(Vec2, bool)> = Vec::with_capacity(2 * total);
    let mut segment_edges: Vec<usize> = Vec::with_capacity(2 * total);
    let mut starts: Vec<usize> = Vec::with_capacity(loops.len());
    let mut ts: Vec<f64> = Vec::new();
    let mut first_edge = 0;
    for poly in loops {
        starts.push(pts.len());
        let n = poly.len();
        for k in 0..n {
            let (p, q) = (poly[k], poly[(k + 1) % n]);
            pts.push((p, true));
            segment_edges.push(first_edge + k);
            let len = crate::geometry::dist(p, q);
            ts.clear();
            super::slit::mesh_crossings(p, q, mesh.origin, h, &mut ts);
            ts.sort_by(f64::total_cmp);
            let tol = EDGE_TOL * h;
            let mut last = 0.0;
            for &t in &ts {
                if (t - last) * len > tol && (1.0 - t) * len > tol {
                    pts.push((crate::geometry::lerp(p, q, t), false));
                    segment_edges.push(first_edge + k);
                    last = t;
                }
            }
        }
        first_edge += n;
    }
    let mut vertices = Vec::with_capacity(pts.len());
    for &(x, corner) in &pts {
        let e = nearest_element(d, map, x).ok_or_else(|| {
            DiscretiseError(format!("block {b}: no element at boundary point {x:?}"))
        })?;
        vertices.push(BoundaryVertex {
            x0: x,
            at: MaterialPoint {
                element: e,
                weights: barycentric(&d.elements[e].nodes, x),
            },
            corner,
            midpoint: false,
        });
    }
    let m = pts.len();
    let mut segment_elements = Vec::with_capacity(m);
    for i in 0..m {
        let next = crate::geometry::region::loop_next(&starts, m, i);
        let mid = crate::geometry::lerp(pts[i].0, pts[next].0, 0.5);
        let e = nearest_element(d, map, mid).ok_or_else(|| {
            DiscretiseError(format!("block {b}: no element at boundary point {mid:?}"))
        })?;
        segment_elements.push(e);
    }
    Ok(BlockBoundary {
        vertices,
        segment_elements,
        segment_edges,
        loops: starts,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_on_aligned_mesh() {
        let sq = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let d = discretise(&[(sq, false)], 0.25).unwrap();
        let area: f64 = d.elements.iter().map(|e| polygon_area(&e.polygon)).sum();
        assert!((area - 1.0).abs() < 1e-12);
        // Mesh offset by h/2: 5×5 nodes inside, plus cut cells: every element has 3 covers.
        let total_support: f64 = d.covers.iter().map(|c| c.support_area).sum();
        assert!((total_support - 3.0).abs() < 1e-12);
        assert_eq!(d.n_dofs, 2 * d.covers.len());
        // Each segment of the boundary is short (≤ h) and the loop is closed.
        let bd = &d.boundaries[0];
        assert_eq!(bd.vertices.len(), bd.segment_elements.len());
        assert_eq!(bd.vertices.iter().filter(|v| v.corner).count(), 4);
    }

    /// A corner 3.8e-5 h across a vertical mesh line: the piece beyond the line is small in
    /// every direction (width < 1e-5 h, so dropped), yet the corner is farther than
    /// 2e-5 h from the kept elements. The boundary and point searches must still find it.
    #[test]
    fn corner_tip_just_across_a_mesh_line() {
        let h = 0.25;
        let mesh = MathMesh {
            origin: [-1.0, -1.0],
            h,
            nx: 12,
            ny: 12,
        };
        let tip = [0.5 + 3.8e-5 * h, 0.3];
        let wedge = vec![[-0.5, 0.0], [0.2, 0.2], tip, [0.2, 0.4], [-0.5, 0.55]];
        let d = discretise_on_mesh(&[(wedge, false)], mesh).unwrap();
        assert!(d.locate_tol > LOCATE_TOL_TEST * h, "a piece was dropped");
        assert!(d.locate_tol < 1e-4 * h);
        let mp = d.locate(0, tip).expect("tip located");
        let e = &d.elements[mp.element];
        let back = [
            (0..3).map(|k| mp.weights[k] * e.nodes[k][0]).sum::<f64>(),
            (0..3).map(|k| mp.weights[k] * e.nodes[k][1]).sum::<f64>(),
        ];
        assert!(crate::geometry::dist(back, tip) < 1e-12);
        assert!(d.boundaries[0].vertices.iter().any(|v| v.x0 == tip));
    }
    const LOCATE_TOL_TEST: f64 = super::super::LOCATE_TOL;

    #[test]
    fn fixed_blocks_have_no_dofs() {
        let sq = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let sq2 = vec![[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        let d = discretise(&[(sq, true), (sq2, false)], 0.3).unwrap();
        assert!(d.covers.iter().all(|c| (c.block == 0) == c.dof.is_none()));
        let free = d.covers.iter().filter(|c| c.block == 1).count();
        assert_eq!(d.n_dofs, 2 * free);
    }

    #[test]
    fn bad_input_is_an_error() {
        let cw = vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        assert!(discretise(&[(cw, false)], 0.1).is_err());
        let bow = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(discretise(&[(bow, false)], 0.1).is_err());
        let sq = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(discretise(&[(sq.clone(), false)], 0.0).is_err());
        assert!(discretise(&[(sq.clone(), false)], f64::NAN).is_err());
        assert!(discretise(&[(sq, false)], 1e-9).is_err());
    }
}
