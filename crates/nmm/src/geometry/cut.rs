//! Cutting a simple polygon by joint traces: the pieces the traces separate, the faces
//! each trace made, and the parts of traces that end inside a piece (cracks).
//!
//! Owns [`cut_polygon`]. Input: a simple CCW polygon `P`, trace polylines (each with the
//! id of the joint it belongs to) and the model's length tolerance `tol`. The method is
//! the planar arrangement of `P`'s boundary and the traces (as in DDA's block cutting):
//!
//! 1. **Segments**: `P`'s edges and every trace segment. Candidate pairs come from a
//!    uniform grid over `P`'s box (each segment is registered in the cells it passes
//!    within `tol` of), so the cost grows with the number of crossings, not with the
//!    square of the number of segments.
//! 2. **Intersections**: an endpoint within `tol` of the other segment is a junction on
//!    it (this covers T-junctions, touching and collinear overlap); otherwise a proper
//!    crossing (strict orientation tests) adds its intersection point to both.
//! 3. **Snapping**: points closer than `tol` are one vertex (a corner of `P` is kept
//!    exactly, so that neighbouring blocks still meet at the same coordinates); then
//!    every vertex within `tol` of a segment becomes a junction of that segment. After
//!    this no vertex lies within `tol` of an edge it is not on, so the angular order
//!    around a vertex is decided by directions at least `tol / length` apart.
//! 4. **Edges**: each segment is split at its junctions (sorted along it); coincident
//!    edges are merged (an edge on `P`'s boundary stays a boundary edge: a trace along an
//!    existing edge makes no face); trace edges whose midpoint is not strictly inside
//!    `P` (farther than `tol` from its boundary) are discarded.
//! 5. **Cracks**: vertices of degree 1 are removed repeatedly. The removed trace edges end
//!    inside a piece and separate nothing; grouped per trace into connected polylines
//!    (split where they meet a piece's boundary) they are the *cracks*.
//! 6. **Enclosed loops**: a loop of traces that reaches neither the boundary nor a trace
//!    that does would leave the piece around it with a hole, and a loop hanging from
//!    the rest by one vertex or one edge would pinch it: a block (a simple polygon) can
//!    have neither. Only the biconnected component of the outline (Tarjan's low-link) is
//!    kept; on a biconnected plane graph every face is bounded by one simple cycle. The
//!    other edges are cracks too (closed ones), and each region they enclose is
//!    reported in [`Cut::enclosed`] as a part of the piece around it.
//! 7. **Faces**: with the outgoing edges of each vertex sorted by angle, the face to the
//!    left of half-edge `u → v` continues with the edge that precedes `v → u`
//!    counter-clockwise around `v`. Faces of positive area are the pieces; the only
//!    face of negative area must be `P`'s outline.
//! 8. **Merging** (optional `min_area`): repeatedly, the smallest piece below `min_area`
//!    is merged into the neighbour with which it shares the longest total length of trace
//!    edges (ties: the neighbour found first) **among the safe ones**; every merge is
//!    reported in [`Cut::merged`]. A piece that merging encloses joins the piece around it
//!    (reported there too). A neighbour is *not safe* when, for some trace of the faces
//!    they share, the trace goes on past an end of the shared run as a face (an alive edge
//!    of the same trace, between two different pieces): (a) past both ends — the trace is
//!    a face of the mass on both sides of the small piece, and the merged block would
//!    straddle it —, or (b) past one end as a face of the small piece or of the neighbour —
//!    the merged block would lie on both sides of the trace and keep its face on its own
//!    boundary: a step that keys into the blocks around it (a face sliver merged across a
//!    persistent bedding plane into the block above). A small piece without a safe
//!    neighbour is kept and reported in [`Cut::kept`] as it ends (a smaller piece may
//!    still merge into it; one that then merges on or reaches `min_area` is not kept).
//! 9. **Output**: vertices of degree 2 that are not corners of `P`, between two collinear
//!    edges of the same origin (a crack's root on an edge, a junction whose other edges
//!    were removed) are dropped. Each piece is CCW, starts at its lowest-then-leftmost
//!    vertex, and carries one tag per edge: `Some(joint)` for an edge a trace made, `None`
//!    for a part of `P`'s boundary. Pieces are ordered by centroid: bottom to top (y
//!    compared on a grid of step `tol` from `P`'s lowest point), then left to right.
//!    When nothing is cut, the single piece is `P` itself, vertex for vertex.
//!
//! Consistency is checked, not assumed: the piece areas must add up to `P`'s area (to
//! 1e-6 relative; the tests check 1e-9) and every face walk must close.

// `!(x > tol)` is deliberate throughout: a NaN fails the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use super::polygon::{point_in_polygon, point_segment_distance, signed_area, Location};
use super::region::Region;
use super::{cross, dist, dot, lerp, sub, Aabb, Vec2};
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// A joint trace: a polyline (at least two points) and the id of its joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub points: Vec<Vec2>,
    pub joint: usize,
}

/// A piece of the cut polygon: its outer loop and its holes ([`super::region`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    /// Simple polygon, CCW.
    pub vertices: Vec<Vec2>,
    /// Holes, each a simple polygon, clockwise (empty for most pieces).
    pub holes: Vec<Vec<Vec2>>,
    /// Per edge, over the loops in order (outer loop first, then each hole; edge `i` of a
    /// loop joins its vertex `i` to vertex `i + 1 mod n`): the joint whose trace made it,
    /// or `None` for a part of the polygon's boundary.
    pub edge_joint: Vec<Option<usize>>,
}

/// A part of one trace that ends inside a piece and so does not split it.
#[derive(Debug, Clone, PartialEq)]
pub struct Crack {
    /// Index into [`Cut::pieces`] of the piece it lies in.
    pub piece: usize,
    /// Index of the trace (in the input slice) and its joint.
    pub trace: usize,
    pub joint: usize,
    /// The crack as a polyline (at least two points).
    pub points: Vec<Vec2>,
}

/// A piece smaller than `min_area` merged into a neighbour.
#[derive(Debug, Clone, PartialEq)]
pub struct Merge {
    /// Index into [`Cut::pieces`] of the piece it is now part of.
    pub into: usize,
    pub area: f64,
    pub centroid: Vec2,
    /// A merge across a joint face whose trace goes on past one end of it as a face of
    /// other pieces (module doc, step 8): that joint's id.
    pub bridges: Option<usize>,
}

/// The result of [`cut_polygon`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Cut {
    pub pieces: Vec<Piece>,
    pub cracks: Vec<Crack>,
    /// Pieces merged because they were smaller than `min_area` (or enclosed by a merge).
    pub merged: Vec<Merge>,
    /// Regions enclosed by a loop of traces that reaches neither the boundary nor a trace
    /// that does: the loop is a (closed) crack and the region stays part of the piece
    /// `into` (a piece with a hole is not a simple polygon).
    pub enclosed: Vec<Merge>,
    /// Pieces smaller than `min_area` kept because every merge would bridge a joint
    /// (module doc, step 8); `into` is the piece itself, `area` and `centroid` its own.
    pub kept: Vec<Merge>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CutError {
    #[error("cutting is inconsistent near ({0}, {1}): {2} (traces crossing within the geometric tolerance of each other in an unresolvable way)")]
    Inconsistent(f64, f64, String),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// Edge `i` of the polygon.
    Boundary(u32),
    /// A segment of trace `trace`.
    Trace(u32),
}

struct Seg {
    a: Vec2,
    b: Vec2,
    /// Point ids of the two ends.
    ends: [u32; 2],
    kind: Kind,
    /// Junctions: (parameter along the segment, point id, later vertex id).
    stops: Vec<(f64, u32)>,
}

/// A uniform grid of cells, each listing the segments that pass within `tol` of it.
struct SegGrid {
    min: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    cells: Vec<Vec<u32>>,
}

impl SegGrid {
    fn new(bbox: Aabb, n_segments: usize) -> SegGrid {
        let w = (bbox.max[0] - bbox.min[0]).max(0.0);
        let h = (bbox.max[1] - bbox.min[1]).max(0.0);
        let big = w.max(h);
        let cell = ((w * h / (4.0 * n_segments.max(1) as f64)).sqrt())
            .max(big / 2048.0)
            .max(f64::MIN_POSITIVE);
        let nx = ((w / cell).floor() as usize + 1).min(4096);
        let ny = ((h / cell).floor() as usize + 1).min(4096);
        SegGrid {
            min: bbox.min,
            cell,
            nx,
            ny,
            cells: vec![Vec::new(); nx * ny],
        }
    }

    fn col(&self, x: f64) -> usize {
        (((x - self.min[0]) / self.cell).floor().max(0.0) as usize).min(self.nx - 1)
    }
    fn row(&self, y: f64) -> usize {
        (((y - self.min[1]) / self.cell).floor().max(0.0) as usize).min(self.ny - 1)
    }

    /// The cells within `pad` of the segment `ab` (a superset: per column strip, the
    /// rows spanned by the segment's part in the strip, widened by `pad`).
    fn cells_of(&self, a: Vec2, b: Vec2, pad: f64, mut f: impl FnMut(usize)) {
        let (x0, x1) = (a[0].min(b[0]) - pad, a[0].max(b[0]) + pad);
        let (c0, c1) = (self.col(x0), self.col(x1));
        let dx = b[0] - a[0];
        for c in c0..=c1 {
            let sx0 = (self.min[0] + c as f64 * self.cell).max(x0);
            let sx1 = (self.min[0] + (c + 1) as f64 * self.cell).min(x1);
            let (ylo, yhi) = if dx.abs() > 0.0 {
                let y_at = |x: f64| a[1] + (b[1] - a[1]) * ((x - a[0]) / dx).clamp(0.0, 1.0);
                let (p, q) = (y_at(sx0), y_at(sx1));
                (p.min(q), p.max(q))
            } else {
                (a[1].min(b[1]), a[1].max(b[1]))
            };
            for r in self.row(ylo - pad)..=self.row(yhi + pad) {
                f(r * self.nx + c);
            }
        }
    }

    fn insert(&mut self, id: u32, a: Vec2, b: Vec2, pad: f64) {
        let mut cs = Vec::new();
        self.cells_of(a, b, pad, |c| cs.push(c));
        for c in cs {
            self.cells[c].push(id);
        }
    }
}

/// Union–find with path halving.
struct Dsu(Vec<u32>);
impl Dsu {
    fn new(n: usize) -> Dsu {
        Dsu((0..n as u32).collect())
    }
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let p = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = p;
            x = p;
        }
        x
    }
    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.0[hi as usize] = lo;
        }
    }
}

/// Parameter of the projection of `p` on the segment `ab` (not clamped).
fn param(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    if l2 > 0.0 {
        dot(sub(p, a), ab) / l2
    } else {
        0.0
    }
}

/// An undirected edge of the arrangement.
#[derive(Debug, Clone, Copy)]
struct Edge {
    v: [u32; 2],
    kind: Kind,
    alive: bool,
}

/// The faces of the alive edges: (half-edges of each face, face of each half-edge).
/// Half-edge `2e` runs `v[0] → v[1]` of edge `e`, `2e + 1` the other way.
fn faces(pos: &[Vec2], edges: &[Edge]) -> Result<(Vec<Vec<u32>>, Vec<u32>), CutError> {
    let nv = pos.len();
    let mut out: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (e, ed) in edges.iter().enumerate() {
        if ed.alive {
            out[ed.v[0] as usize].push(2 * e as u32);
            out[ed.v[1] as usize].push(2 * e as u32 + 1);
        }
    }
    let head = |h: u32| -> u32 {
        let ed = &edges[(h / 2) as usize];
        ed.v[(h % 2) as usize]
    };
    let tail = |h: u32| -> u32 {
        let ed = &edges[(h / 2) as usize];
        ed.v[1 - (h % 2) as usize]
    };
    let mut slot = vec![u32::MAX; 2 * edges.len()];
    for (v, list) in out.iter_mut().enumerate() {
        let p = pos[v];
        list.sort_by(|&x, &y| {
            let (qx, qy) = (pos[tail(x) as usize], pos[tail(y) as usize]);
            let ax = (qx[1] - p[1]).atan2(qx[0] - p[0]);
            let ay = (qy[1] - p[1]).atan2(qy[0] - p[0]);
            ax.total_cmp(&ay).then(x.cmp(&y))
        });
        for (i, &h) in list.iter().enumerate() {
            slot[h as usize] = i as u32;
        }
    }
    let n_half = 2 * edges.len();
    let mut face_of = vec![u32::MAX; n_half];
    let mut faces: Vec<Vec<u32>> = Vec::new();
    for start in 0..n_half as u32 {
        if !edges[(start / 2) as usize].alive || face_of[start as usize] != u32::MAX {
            continue;
        }
        let f = faces.len() as u32;
        let mut walk = Vec::new();
        let mut h = start;
        loop {
            if face_of[h as usize] != u32::MAX || walk.len() > n_half {
                let p = pos[head(h) as usize];
                return Err(CutError::Inconsistent(
                    p[0],
                    p[1],
                    "a face walk does not close".into(),
                ));
            }
            face_of[h as usize] = f;
            walk.push(h);
            // h = u → v; continue around v from the twin v → u, clockwise
            let v = tail(h) as usize;
            let twin = h ^ 1;
            let list = &out[v];
            let i = slot[twin as usize] as usize;
            h = list[(i + list.len() - 1) % list.len()];
            if h == start {
                break;
            }
        }
        faces.push(walk);
    }
    Ok((faces, face_of))
}

fn face_polygon(pos: &[Vec2], edges: &[Edge], face: &[u32]) -> Vec<Vec2> {
    face.iter()
        .map(|&h| {
            let ed = &edges[(h / 2) as usize];
            pos[ed.v[(h % 2) as usize] as usize]
        })
        .collect()
}

/// Remove vertices of degree 1 repeatedly; returns the edges removed, in order.
fn prune(nv: usize, edges: &mut [Edge]) -> Vec<u32> {
    let mut deg = vec![0u32; nv];
    let mut inc: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (e, ed) in edges.iter().enumerate() {
        if ed.alive {
            for &v in &ed.v {
                deg[v as usize] += 1;
                inc[v as usize].push(e as u32);
            }
        }
    }
    let mut queue: Vec<u32> = (0..nv as u32).filter(|&v| deg[v as usize] == 1).collect();
    let mut removed = Vec::new();
    while let Some(v) = queue.pop() {
        if deg[v as usize] != 1 {
            continue;
        }
        let Some(&e) = inc[v as usize].iter().find(|&&e| edges[e as usize].alive) else {
            continue;
        };
        edges[e as usize].alive = false;
        removed.push(e);
        for &w in &edges[e as usize].v {
            deg[w as usize] -= 1;
            if deg[w as usize] == 1 {
                queue.push(w);
            }
        }
    }
    removed
}

/// Cut the simple CCW polygon `poly` by `traces` at the length tolerance `tol` (see the
/// module doc). `min_area`: pieces smaller than this are merged into a neighbour.
pub fn cut_polygon(
    poly: &[Vec2],
    traces: &[Trace],
    tol: f64,
    min_area: Option<f64>,
) -> Result<Cut, CutError> {
    cut_region(Region::simple(poly), traces, tol, min_area)
}

/// Cut a region (a simple CCW polygon with clockwise holes, [`super::region`]) by
/// `traces`, as [`cut_polygon`] does a polygon (module doc; the holes' edges are boundary
/// edges like the outer loop's).
pub fn cut_region(
    region: Region,
    traces: &[Trace],
    tol: f64,
    min_area: Option<f64>,
) -> Result<Cut, CutError> {
    let poly = region.outer;
    let n = region.edge_count();
    let n_outer = poly.len();
    let whole = || Cut {
        pieces: vec![Piece {
            vertices: poly.to_vec(),
            holes: region.holes.to_vec(),
            edge_joint: vec![None; n],
        }],
        cracks: Vec::new(),
        merged: Vec::new(),
        enclosed: Vec::new(),
        kept: Vec::new(),
    };
    let bbox = Aabb::of_points(poly);
    let tol = if tol > 0.0 {
        tol
    } else {
        1e-12 * bbox.diagonal()
    };
    let area_p = region.area();
    let gbox = bbox.inflate(2.0 * tol);

    // 1. points and segments: the loops' corners first (ids 0..n), in loop order
    let mut pts: Vec<Vec2> = region.loops().flatten().copied().collect();
    let mut segs: Vec<Seg> = Vec::with_capacity(n);
    let mut start = 0;
    for l in region.loops() {
        let m = l.len();
        segs.extend((0..m).map(|i| Seg {
            a: l[i],
            b: l[(i + 1) % m],
            ends: [(start + i) as u32, (start + (i + 1) % m) as u32],
            kind: Kind::Boundary((start + i) as u32),
            stops: Vec::new(),
        }));
        start += m;
    }
    for (ti, t) in traces.iter().enumerate() {
        let mut prev: Option<u32> = None;
        for (k, &p) in t.points.iter().enumerate() {
            let id = pts.len() as u32;
            pts.push(p);
            if let Some(q) = prev {
                let a = t.points[k - 1];
                let sb = Aabb::of_points(&[a, p]);
                if dist(a, p) > tol && sb.overlaps(&gbox) {
                    segs.push(Seg {
                        a,
                        b: p,
                        ends: [q, id],
                        kind: Kind::Trace(ti as u32),
                        stops: Vec::new(),
                    });
                }
            }
            prev = Some(id);
        }
    }
    if segs.len() == n {
        return Ok(whole());
    }

    // 2. intersections of candidate pairs
    let mut grid = SegGrid::new(gbox, segs.len());
    for (i, s) in segs.iter().enumerate() {
        grid.insert(i as u32, s.a, s.b, tol);
    }
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for c in &grid.cells {
        for (k, &i) in c.iter().enumerate() {
            for &j in &c[k + 1..] {
                let (i, j) = (i.min(j), i.max(j));
                if (j as usize) >= n {
                    pairs.push((i, j));
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    for (i, j) in pairs {
        let (i, j) = (i as usize, j as usize);
        let (a, b, ea) = (segs[i].a, segs[i].b, segs[i].ends);
        let (c, d, ec) = (segs[j].a, segs[j].b, segs[j].ends);
        if !Aabb::of_points(&[a, b])
            .inflate(tol)
            .overlaps(&Aabb::of_points(&[c, d]))
        {
            continue;
        }
        let mut found = false;
        for (p, id) in [(a, ea[0]), (b, ea[1])] {
            if point_segment_distance(p, c, d) <= tol {
                segs[j].stops.push((param(p, c, d), id));
                found = true;
            }
        }
        for (p, id) in [(c, ec[0]), (d, ec[1])] {
            if point_segment_distance(p, a, b) <= tol {
                segs[i].stops.push((param(p, a, b), id));
                found = true;
            }
        }
        if found {
            continue;
        }
        let o1 = cross(sub(b, a), sub(c, a));
        let o2 = cross(sub(b, a), sub(d, a));
        let o3 = cross(sub(d, c), sub(a, c));
        let o4 = cross(sub(d, c), sub(b, c));
        if ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0))
            && ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0))
        {
            let ts = o3 / (o3 - o4);
            let tu = o1 / (o1 - o2);
            let id = pts.len() as u32;
            pts.push(lerp(a, b, ts));
            segs[i].stops.push((ts, id));
            segs[j].stops.push((tu, id));
        }
    }

    // 3. cluster points closer than tol; a polygon corner represents its cluster
    let mut dsu = Dsu::new(pts.len());
    {
        let key = |p: Vec2| -> (i64, i64) {
            (
                ((p[0] - gbox.min[0]) / tol).floor() as i64,
                ((p[1] - gbox.min[1]) / tol).floor() as i64,
            )
        };
        let mut hash: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
        for (i, &p) in pts.iter().enumerate() {
            if !(p[0] >= gbox.min[0] - tol
                && p[0] <= gbox.max[0] + tol
                && p[1] >= gbox.min[1] - tol
                && p[1] <= gbox.max[1] + tol)
            {
                continue;
            }
            let (kx, ky) = key(p);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    if let Some(list) = hash.get(&(kx + dx, ky + dy)) {
                        for &j in list {
                            if dist(pts[j as usize], p) <= tol {
                                dsu.union(i as u32, j);
                            }
                        }
                    }
                }
            }
            hash.entry((kx, ky)).or_default().push(i as u32);
        }
    }
    // Roots are the smallest member (union keeps the smaller id), and corners have the
    // smallest ids: a cluster with a corner is represented by it.
    let mut vid = vec![u32::MAX; pts.len()];
    let mut pos: Vec<Vec2> = Vec::new();
    let mut corner: Vec<bool> = Vec::new();
    for i in 0..pts.len() as u32 {
        let r = dsu.find(i);
        if vid[r as usize] == u32::MAX {
            vid[r as usize] = pos.len() as u32;
            pos.push(pts[r as usize]);
            corner.push((r as usize) < n);
        }
        vid[i as usize] = vid[r as usize];
    }
    for s in segs.iter_mut() {
        for st in s.stops.iter_mut() {
            st.1 = vid[st.1 as usize];
        }
        s.ends = [vid[s.ends[0] as usize], vid[s.ends[1] as usize]];
    }

    // 3b. every vertex within tol of a segment becomes a junction of it
    for (v, &p) in pos.iter().enumerate() {
        if !(p[0] >= gbox.min[0]
            && p[0] <= gbox.max[0]
            && p[1] >= gbox.min[1]
            && p[1] <= gbox.max[1])
        {
            continue;
        }
        let mut cand: Vec<u32> = Vec::new();
        grid.cells_of(p, p, tol, |c| cand.extend_from_slice(&grid.cells[c]));
        cand.sort_unstable();
        cand.dedup();
        for si in cand {
            let s = &mut segs[si as usize];
            let v = v as u32;
            if s.ends.contains(&v) || s.stops.iter().any(|st| st.1 == v) {
                continue;
            }
            if point_segment_distance(p, s.a, s.b) <= tol {
                s.stops.push((param(p, s.a, s.b), v));
            }
        }
    }

    // 4. edges: segments split at their junctions, coincident edges merged
    let mut edges: Vec<Edge> = Vec::new();
    let mut index: HashMap<(u32, u32), u32> = HashMap::new();
    let mut chain: Vec<(f64, u32)> = Vec::new();
    for s in &segs {
        chain.clear();
        chain.push((0.0, s.ends[0]));
        chain.push((1.0, s.ends[1]));
        for &(_, v) in &s.stops {
            chain.push((param(pos[v as usize], s.a, s.b), v));
        }
        chain.sort_by(|x, y| x.0.total_cmp(&y.0));
        chain.dedup_by_key(|x| x.1);
        for w in chain.windows(2) {
            let (u, v) = (w[0].1, w[1].1);
            if u == v {
                continue;
            }
            let key = (u.min(v), u.max(v));
            if index.contains_key(&key) {
                continue; // boundary edges come first, then traces in order
            }
            let mut alive = true;
            if let Kind::Trace(_) = s.kind {
                let mid = lerp(pos[u as usize], pos[v as usize], 0.5);
                alive = region.locate(mid, tol) == Location::Inside;
            }
            if alive {
                index.insert(key, edges.len() as u32);
                edges.push(Edge {
                    v: [u, v],
                    kind: s.kind,
                    alive: true,
                });
            }
        }
    }
    if edges.iter().all(|e| matches!(e.kind, Kind::Boundary(_))) {
        return Ok(whole());
    }

    // 5. cracks: trace edges hanging from a vertex of degree 1
    let nv = pos.len();
    let mut removed = prune(nv, &mut edges);
    if let Some(&e) = removed
        .iter()
        .find(|&&e| matches!(edges[e as usize].kind, Kind::Boundary(_)))
    {
        let p = pos[edges[e as usize].v[0] as usize];
        return Err(CutError::Inconsistent(
            p[0],
            p[1],
            "the block's boundary does not close".into(),
        ));
    }
    // 6. what would pinch a piece (loops hanging from the rest by one vertex or one
    // edge); loops of traces that touch nothing else are kept: they cut out a piece
    let (closed, islands, island_edges) = remove_islands(&pos, &mut edges, None)?;
    removed.extend(closed);

    // 7. faces
    let (mut fcs, face_of) = faces(&pos, &edges)?;
    check_faces(&pos, &edges, &fcs, &face_of)?;
    let mut lay = layout(&pos, &edges, &fcs, n_outer, tol)?;

    // degree of every vertex in the pieces' boundaries before merging (a crack stops
    // where it meets one)
    let mut deg_cut = vec![0u32; nv];
    for e in edges.iter().filter(|e| e.alive) {
        deg_cut[e.v[0] as usize] += 1;
        deg_cut[e.v[1] as usize] += 1;
    }

    // 8. merging
    let mut merged = Vec::new();
    let mut kept_small: Vec<(u32, f64, Vec2)> = Vec::new();
    if let Some(min) = min_area.filter(|&m| m > 0.0) {
        let (merges, root_of, kept) = merge_small(&pos, &mut edges, &fcs, &face_of, &lay, min);
        kept_small = kept;
        if !merges.is_empty() {
            // a merge may enclose a piece: it joins the piece around it (its faces go)
            let ghost = prune(nv, &mut edges);
            debug_assert!(ghost.is_empty());
            let (_, enclosed, _) = remove_islands(&pos, &mut edges, Some(&island_edges))?;
            let (f2, fo2) = faces(&pos, &edges)?;
            check_faces(&pos, &edges, &f2, &fo2)?;
            lay = layout(&pos, &edges, &f2, n_outer, tol)?;
            // the final face of each merged piece, through a surviving half-edge of a member
            let mut final_of_root: HashMap<u32, u32> = HashMap::new();
            for (h, &nf) in fo2.iter().enumerate() {
                if nf != u32::MAX {
                    final_of_root
                        .entry(root_of[face_of[h] as usize])
                        .or_insert(nf);
                }
            }
            for (root, area, centroid, b) in merges {
                merged.push((final_of_root.get(&root).copied(), area, centroid, b));
            }
            // a kept piece that a merge enclosed is gone (it joins `merged` below, as enclosed)
            kept_small = kept_small
                .into_iter()
                .filter_map(|(root, a, c)| final_of_root.get(&root).map(|&nf| (nf, a, c)))
                .collect();
            merged.extend(enclosed.into_iter().map(|(a, c)| (None, a, c, None)));
            fcs = f2;
        }
    }

    // 9. output
    let alive_trace = edges
        .iter()
        .any(|e| e.alive && matches!(e.kind, Kind::Trace(_)));
    let mut deg = vec![0u32; nv];
    for e in edges.iter().filter(|e| e.alive) {
        deg[e.v[0] as usize] += 1;
        deg[e.v[1] as usize] += 1;
    }
    let mut pieces: Vec<(Piece, Vec2, u32)> = Vec::new();
    if !alive_trace {
        pieces.push((whole().pieces.remove(0), [0.0; 2], 0));
    } else {
        // a loop of the output: its vertices and the tag of the edge leaving each,
        // without the removable vertices, starting at the lowest, then leftmost vertex
        let ring_of = |f: &[u32]| -> (Vec<Vec2>, Vec<Option<usize>>) {
            let k = f.len();
            // (vertex, tag of the edge leaving it)
            let mut ring: Vec<(u32, Kind)> = f
                .iter()
                .map(|&h| {
                    let ed = &edges[(h / 2) as usize];
                    (ed.v[(h % 2) as usize], ed.kind)
                })
                .collect();
            // drop removable vertices: degree 2, not a corner, same origin on both sides, collinear
            let mut keep = vec![true; k];
            for i in 0..k {
                let (v, kin) = ring[i];
                let (_, kprev) = ring[(i + k - 1) % k];
                if corner[v as usize] || deg[v as usize] != 2 || kin != kprev {
                    continue;
                }
                let a = pos[ring[(i + k - 1) % k].0 as usize];
                let b = pos[ring[(i + 1) % k].0 as usize];
                if point_segment_distance(pos[v as usize], a, b) <= tol {
                    keep[i] = false;
                }
            }
            let mut i = 0;
            ring.retain(|_| {
                i += 1;
                keep[i - 1]
            });
            // start at the lowest, then leftmost vertex
            let start = (0..ring.len())
                .min_by(|&x, &y| {
                    let (p, q) = (pos[ring[x].0 as usize], pos[ring[y].0 as usize]);
                    p[1].total_cmp(&q[1]).then(p[0].total_cmp(&q[0]))
                })
                .unwrap_or(0);
            ring.rotate_left(start);
            let vertices: Vec<Vec2> = ring.iter().map(|r| pos[r.0 as usize]).collect();
            let tags = ring
                .iter()
                .map(|r| match r.1 {
                    Kind::Boundary(_) => None,
                    Kind::Trace(t) => Some(traces[t as usize].joint),
                })
                .collect();
            (vertices, tags)
        };
        for (fi, f) in fcs.iter().enumerate() {
            if !lay.material[fi] {
                continue;
            }
            let (vertices, mut edge_joint) = ring_of(f);
            let mut holes = Vec::with_capacity(lay.holes[fi].len());
            for &hf in &lay.holes[fi] {
                let (hv, ht) = ring_of(&fcs[hf as usize]);
                holes.push(hv);
                edge_joint.extend(ht);
            }
            let c = if holes.is_empty() {
                super::moments::polygon_moments(&vertices, vertices[0]).centroid()
            } else {
                Region {
                    outer: &vertices,
                    holes: &holes,
                }
                .centroid()
            };
            pieces.push((
                Piece {
                    vertices,
                    holes,
                    edge_joint,
                },
                c,
                fi as u32,
            ));
        }
        // order: bottom to top (on a grid of step tol), then left to right
        let y0 = bbox.min[1];
        pieces.sort_by(|x, y| {
            let (kx, ky) = (((x.1[1] - y0) / tol).round(), ((y.1[1] - y0) / tol).round());
            kx.total_cmp(&ky).then(x.1[0].total_cmp(&y.1[0]))
        });
        let total: f64 = pieces
            .iter()
            .map(|p| {
                Region {
                    outer: &p.0.vertices,
                    holes: &p.0.holes,
                }
                .area()
            })
            .sum();
        if !((total - area_p).abs() <= 1e-6 * area_p.abs()) {
            return Err(CutError::Inconsistent(
                bbox.min[0],
                bbox.min[1],
                format!("the pieces' areas add up to {total}, the block's is {area_p}"),
            ));
        }
    }
    let final_index: HashMap<u32, usize> =
        pieces.iter().enumerate().map(|(i, p)| (p.2, i)).collect();
    let pieces: Vec<Piece> = pieces.into_iter().map(|p| p.0).collect();
    let index = PieceIndex::new(&pieces, tol);

    let merged = merged
        .into_iter()
        .map(|(f, area, centroid, b)| Merge {
            into: f
                .and_then(|f| final_index.get(&f).copied())
                .unwrap_or_else(|| index.locate(centroid)),
            area,
            centroid,
            bridges: b.map(|t: u32| traces[t as usize].joint),
        })
        .collect();
    let enclosed = islands
        .into_iter()
        .map(|(area, centroid)| Merge {
            into: index.locate(centroid),
            area,
            centroid,
            bridges: None,
        })
        .collect();

    // cracks: the pruned trace edges, per trace, as connected polylines
    let cracks = crack_polylines(&pos, &edges, &removed, &deg_cut)
        .into_iter()
        .map(|(trace, points)| {
            let mid = lerp(points[0], points[1], 0.5);
            Crack {
                piece: index.locate(mid),
                trace: trace as usize,
                joint: traces[trace as usize].joint,
                points,
            }
        })
        .collect();
    // `into` is the kept piece itself, through its face (its centroid may lie outside it)
    let kept = kept_small
        .into_iter()
        .map(|(f, area, centroid)| Merge {
            into: final_index
                .get(&f)
                .copied()
                .unwrap_or_else(|| index.locate(centroid)),
            area,
            centroid,
            bridges: None,
        })
        .collect();
    Ok(Cut {
        pieces,
        cracks,
        merged,
        enclosed,
        kept,
    })
}

/// Point location among the pieces: a uniform grid of cells listing the pieces whose
/// box meets them.
struct PieceIndex<'a> {
    pieces: &'a [Piece],
    boxes: Vec<Aabb>,
    grid: SegGrid,
    tol: f64,
}

impl<'a> PieceIndex<'a> {
    fn new(pieces: &'a [Piece], tol: f64) -> Self {
        let boxes: Vec<Aabb> = pieces
            .iter()
            .map(|p| Aabb::of_points(&p.vertices).inflate(tol))
            .collect();
        let all = boxes.iter().fold(Aabb::empty(), |a, b| a.merge(b));
        let mut grid = SegGrid::new(all, pieces.len());
        for (i, b) in boxes.iter().enumerate() {
            for r in grid.row(b.min[1])..=grid.row(b.max[1]) {
                for c in grid.col(b.min[0])..=grid.col(b.max[0]) {
                    let k = r * grid.nx + c;
                    grid.cells[k].push(i as u32);
                }
            }
        }
        PieceIndex {
            pieces,
            boxes,
            grid,
            tol,
        }
    }

    /// The piece containing `p` (inside, else on its boundary, else the nearest).
    fn locate(&self, p: Vec2) -> usize {
        let cell = self.grid.row(p[1]) * self.grid.nx + self.grid.col(p[0]);
        let mut on = None;
        for &i in &self.grid.cells[cell] {
            let (i, b) = (i as usize, &self.boxes[i as usize]);
            if !(p[0] >= b.min[0] && p[0] <= b.max[0] && p[1] >= b.min[1] && p[1] <= b.max[1]) {
                continue;
            }
            let piece = &self.pieces[i];
            let region = Region {
                outer: &piece.vertices,
                holes: &piece.holes,
            };
            match region.locate(p, self.tol) {
                Location::Inside => return i,
                Location::Boundary => on = on.or(Some(i)),
                Location::Outside => {}
            }
        }
        on.unwrap_or_else(|| {
            (0..self.pieces.len())
                .map(|i| {
                    (
                        Region {
                            outer: &self.pieces[i].vertices,
                            holes: &self.pieces[i].holes,
                        }
                        .boundary_distance(p),
                        i,
                    )
                })
                .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a })
                .1
        })
    }
}

/// One face of negative area per connected component of the alive edges (its outline;
/// one component without holes or islands) and no edge with the same face on both sides
/// (what [`remove_islands`] leaves).
fn check_faces(
    pos: &[Vec2],
    edges: &[Edge],
    fcs: &[Vec<u32>],
    face_of: &[u32],
) -> Result<(), CutError> {
    let mut dsu = Dsu::new(pos.len());
    let mut used = vec![false; pos.len()];
    for ed in edges.iter().filter(|e| e.alive) {
        dsu.union(ed.v[0], ed.v[1]);
        used[ed.v[0] as usize] = true;
        used[ed.v[1] as usize] = true;
    }
    let components = (0..pos.len() as u32)
        .filter(|&v| used[v as usize] && dsu.find(v) == v)
        .count();
    let mut outer = 0;
    for f in fcs {
        let poly = face_polygon(pos, edges, f);
        if !(signed_area(&poly) > 0.0) {
            outer += 1;
            if outer > components {
                let p = poly.first().copied().unwrap_or([0.0; 2]);
                return Err(CutError::Inconsistent(
                    p[0],
                    p[1],
                    "a face is not simple".into(),
                ));
            }
        }
    }
    for (e, ed) in edges.iter().enumerate() {
        if ed.alive && face_of[2 * e] == face_of[2 * e + 1] {
            let p = lerp(pos[ed.v[0] as usize], pos[ed.v[1] as usize], 0.5);
            return Err(CutError::Inconsistent(
                p[0],
                p[1],
                "an edge has the same face on both sides".into(),
            ));
        }
    }
    Ok(())
}

/// Which faces are pieces, and the holes of each.
struct Layout {
    /// Per face: a piece of material (positive area, and every edge of the region's
    /// boundary on it run in the boundary's own direction: the material on its left).
    /// A positive face that runs a boundary edge backwards is a hole of the region.
    material: Vec<bool>,
    /// Per face: the faces that are its holes — the outlines (negative faces) of the
    /// components that lie inside it, touching nothing else: a hole of the region that no
    /// trace reaches, or a loop of traces (which cuts out the pieces inside it).
    holes: Vec<Vec<u32>>,
}

/// The [`Layout`] of the faces `fcs` of the alive edges; `n_outer`: the edges of the
/// region's outer loop are `Boundary(0..n_outer)`.
fn layout(
    pos: &[Vec2],
    edges: &[Edge],
    fcs: &[Vec<u32>],
    n_outer: usize,
    tol: f64,
) -> Result<Layout, CutError> {
    let polys: Vec<Vec<Vec2>> = fcs.iter().map(|f| face_polygon(pos, edges, f)).collect();
    let area: Vec<f64> = polys.iter().map(|p| signed_area(p)).collect();
    let mut out = Layout {
        material: vec![false; fcs.len()],
        holes: vec![Vec::new(); fcs.len()],
    };
    let mut rings = Vec::new();
    for (fi, f) in fcs.iter().enumerate() {
        let kinds = f.iter().map(|&h| (h, edges[(h / 2) as usize].kind));
        if area[fi] > 0.0 {
            out.material[fi] = kinds
                .clone()
                .all(|(h, k)| !matches!(k, Kind::Boundary(_)) || h % 2 == 0);
        } else {
            let outline = kinds
                .clone()
                .any(|(_, k)| matches!(k, Kind::Boundary(g) if (g as usize) < n_outer));
            if !outline {
                rings.push(fi);
            }
        }
    }
    for fi in rings {
        let p = polys[fi][0];
        let inside = (0..fcs.len())
            .filter(|&g| out.material[g] && point_in_polygon(&polys[g], p, tol) == Location::Inside)
            .min_by(|&a, &b| area[a].total_cmp(&area[b]));
        let Some(g) = inside else {
            return Err(CutError::Inconsistent(
                p[0],
                p[1],
                "a closed loop lies in no piece".into(),
            ));
        };
        out.holes[g].push(fi as u32);
    }
    Ok(out)
}

/// The biconnected component of every alive edge (`u32::MAX` for dead edges), by
/// Tarjan's low-link with an edge stack (iteratively).
fn biconnected(nv: usize, edges: &[Edge]) -> Vec<u32> {
    let mut adj: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nv];
    for (e, ed) in edges.iter().enumerate() {
        if ed.alive {
            adj[ed.v[0] as usize].push((ed.v[1], e as u32));
            adj[ed.v[1] as usize].push((ed.v[0], e as u32));
        }
    }
    let mut comp = vec![u32::MAX; edges.len()];
    let mut n_comp = 0u32;
    let mut disc = vec![u32::MAX; nv];
    let mut low = vec![0u32; nv];
    let mut time = 0u32;
    let mut estack: Vec<u32> = Vec::new();
    for s in 0..nv {
        if disc[s] != u32::MAX || adj[s].is_empty() {
            continue;
        }
        disc[s] = time;
        low[s] = time;
        time += 1;
        // (vertex, edge it was reached by, next neighbour to visit)
        let mut stack: Vec<(u32, u32, usize)> = vec![(s as u32, u32::MAX, 0)];
        while let Some(top) = stack.last_mut() {
            let (v, pe) = (top.0 as usize, top.1);
            if top.2 < adj[v].len() {
                let (w, e) = adj[v][top.2];
                top.2 += 1;
                if e == pe {
                    continue;
                }
                let w = w as usize;
                if disc[w] == u32::MAX {
                    estack.push(e);
                    disc[w] = time;
                    low[w] = time;
                    time += 1;
                    stack.push((w as u32, e, 0));
                } else if disc[w] < disc[v] {
                    estack.push(e);
                    low[v] = low[v].min(disc[w]);
                }
            } else {
                stack.pop();
                if let Some(parent) = stack.last() {
                    let u = parent.0 as usize;
                    low[u] = low[u].min(low[v]);
                    if low[v] >= disc[u] {
                        while let Some(e) = estack.pop() {
                            comp[e as usize] = n_comp;
                            if e == pe {
                                break;
                            }
                        }
                        n_comp += 1;
                    }
                }
            }
        }
    }
    comp
}

/// Remove what would pinch a piece: every alive edge outside the biconnected components
/// that hold a loop of the region's boundary (bridges, loops hanging from one vertex).
/// A biconnected component of traces alone that shares no vertex with another cycle (a
/// loop of traces touching nothing else) is kept — it cuts out the pieces inside it —
/// when `islands` is `None`; with `islands` (the edges kept so on the first call), only
/// the components made of those edges are (a loop that merging cut free goes). On a
/// biconnected plane graph every face is bounded by one simple cycle. Returns the removed
/// edges, per region they enclose (a bounded face of the removed edges) its (area,
/// centroid), and the flags of the edges kept as such loops.
#[allow(clippy::type_complexity)]
fn remove_islands(
    pos: &[Vec2],
    edges: &mut [Edge],
    islands: Option<&[bool]>,
) -> Result<(Vec<u32>, Vec<(f64, Vec2)>, Vec<bool>), CutError> {
    let comp = biconnected(pos.len(), edges);
    let mut flags = vec![false; edges.len()];
    if !edges
        .iter()
        .any(|e| e.alive && matches!(e.kind, Kind::Boundary(_)))
    {
        return Ok((Vec::new(), Vec::new(), flags));
    }
    let nc = edges
        .iter()
        .zip(&comp)
        .filter(|(e, _)| e.alive)
        .map(|(_, &c)| c as usize + 1)
        .max()
        .unwrap_or(0);
    let (mut size, mut boundary, mut flagged) = (vec![0usize; nc], vec![false; nc], vec![true; nc]);
    for (e, ed) in edges.iter().enumerate() {
        if ed.alive {
            let c = comp[e] as usize;
            size[c] += 1;
            boundary[c] |= matches!(ed.kind, Kind::Boundary(_));
            flagged[c] &= islands.is_some_and(|f| f[e]);
        }
    }
    // cycles (components of two edges or more) that share a vertex with another cycle
    let mut first_at = vec![u32::MAX; pos.len()];
    let mut shared = vec![false; nc];
    for (e, ed) in edges.iter().enumerate() {
        let c = comp[e];
        if !ed.alive || size[c as usize] < 2 {
            continue;
        }
        for &v in &ed.v {
            let f = &mut first_at[v as usize];
            if *f == u32::MAX {
                *f = c;
            } else if *f != c {
                shared[c as usize] = true;
                shared[*f as usize] = true;
            }
        }
    }
    let keep: Vec<bool> = (0..nc)
        .map(|c| {
            size[c] >= 2
                && (boundary[c]
                    || match islands {
                        None => !shared[c],
                        Some(_) => flagged[c],
                    })
        })
        .collect();
    let out: Vec<u32> = (0..edges.len() as u32)
        .filter(|&e| edges[e as usize].alive && !keep[comp[e as usize] as usize])
        .collect();
    for (e, ed) in edges.iter().enumerate() {
        let c = comp[e] as usize;
        flags[e] = ed.alive && keep[c] && !boundary[c];
    }
    if out.is_empty() {
        return Ok((out, Vec::new(), flags));
    }
    let mut sub: Vec<Edge> = edges.iter().map(|e| Edge { alive: false, ..*e }).collect();
    for &e in &out {
        sub[e as usize].alive = true;
        edges[e as usize].alive = false;
    }
    let mut enclosed = Vec::new();
    let (fs, _) = faces(pos, &sub)?;
    for f in &fs {
        let p = face_polygon(pos, &sub, f);
        let a = signed_area(&p);
        if a > 0.0 {
            enclosed.push((a, super::moments::polygon_moments(&p, p[0]).centroid()));
        }
    }
    Ok((out, enclosed, flags))
}

/// What [`merge_small`] returns: (root face merged into, area, centroid) per merge, the
/// root of every face, and (root face, area, centroid) of each small piece kept, as it is
/// once merging is over (it may have absorbed smaller pieces).
/// A merge: (root face merged into, area, centroid, the trace it bridges if any).
type MergeNote = (u32, f64, Vec2, Option<u32>);
type Merged = (Vec<MergeNote>, Vec<u32>, Vec<(u32, f64, Vec2)>);

/// Merge pieces smaller than `min` (module doc, step 8): marks the edges between merged
/// pieces dead and returns (root face of the piece merged into, area, centroid) per merge,
/// the root of every face, and the small pieces kept because no merge was safe (those
/// still below `min` at the end, with their final area and centroid).
fn merge_small(
    pos: &[Vec2],
    edges: &mut [Edge],
    fcs: &[Vec<u32>],
    face_of: &[u32],
    lay: &Layout,
    min: f64,
) -> Merged {
    let nf = fcs.len();
    // alive trace edges at each vertex
    let mut at_vertex: HashMap<u32, Vec<u32>> = HashMap::new();
    for (e, ed) in edges.iter().enumerate() {
        if ed.alive && matches!(ed.kind, Kind::Trace(_)) {
            at_vertex.entry(ed.v[0]).or_default().push(e as u32);
            at_vertex.entry(ed.v[1]).or_default().push(e as u32);
        }
    }
    // roots found without a safe neighbour; reported at the end if still roots below `min`
    // (a kept piece may still absorb a smaller one, and then merge or outgrow `min`)
    let mut no_safe = vec![false; nf];
    let mut bridging: Vec<(usize, u32)> = Vec::new();
    let polys: Vec<Vec<Vec2>> = fcs.iter().map(|f| face_polygon(pos, edges, f)).collect();
    let piece: Vec<bool> = lay.material.clone();
    // a piece's area and first moment less its holes' (negative faces: negative area)
    let mut area: Vec<f64> = polys
        .iter()
        .enumerate()
        .map(|(f, p)| {
            if piece[f] {
                signed_area(p)
                    + lay.holes[f]
                        .iter()
                        .map(|&h| signed_area(&polys[h as usize]))
                        .sum::<f64>()
            } else {
                signed_area(p)
            }
        })
        .collect();
    if piece.iter().filter(|&&p| p).count() < 2 {
        return (Vec::new(), (0..nf as u32).collect(), Vec::new());
    }
    let mut moment: Vec<Vec2> = polys
        .iter()
        .enumerate()
        .map(|(f, p)| {
            if !piece[f] {
                [0.0; 2]
            } else if lay.holes[f].is_empty() {
                let a = area[f];
                let c = super::moments::polygon_moments(p, p[0]).centroid();
                [c[0] * a, c[1] * a]
            } else {
                let holes: Vec<Vec<Vec2>> = lay.holes[f]
                    .iter()
                    .map(|&h| polys[h as usize].clone())
                    .collect();
                let c = Region {
                    outer: p,
                    holes: &holes,
                }
                .centroid();
                [c[0] * area[f], c[1] * area[f]]
            }
        })
        .collect();
    let mut dsu = Dsu::new(nf);
    let mut members: Vec<Vec<u32>> = (0..nf as u32).map(|f| vec![f]).collect();
    let mut heap: BinaryHeap<Reverse<(OrdF64, u32)>> = (0..nf as u32)
        .filter(|&f| piece[f as usize] && area[f as usize] < min)
        .map(|f| Reverse((OrdF64(area[f as usize]), f)))
        .collect();
    let mut out = Vec::new();
    while let Some(Reverse((OrdF64(a), f))) = heap.pop() {
        if dsu.find(f) != f || a != area[f as usize] || !(a < min) {
            continue;
        }
        // shared trace length with each neighbouring piece
        let mut shared: Vec<(u32, f64)> = Vec::new();
        for &m in &members[f as usize] {
            for &h in &fcs[m as usize] {
                let ed = &edges[(h / 2) as usize];
                if !ed.alive || !matches!(ed.kind, Kind::Trace(_)) {
                    continue;
                }
                let g = face_of[(h ^ 1) as usize];
                if !piece[g as usize] {
                    continue;
                }
                let rg = dsu.find(g);
                if rg == f {
                    continue;
                }
                let len = dist(pos[ed.v[0] as usize], pos[ed.v[1] as usize]);
                match shared.iter_mut().find(|s| s.0 == rg) {
                    Some(s) => s.1 += len,
                    None => shared.push((rg, len)),
                }
            }
        }
        let c = [moment[f as usize][0] / a, moment[f as usize][1] / a];
        // the safe neighbours; those whose merge bridges no trace first
        let mut safe: Vec<(u32, f64, Option<u32>)> = Vec::new();
        for &(g, len) in &shared {
            if let Some(b) = safe_merge(edges, face_of, &piece, &mut dsu, &at_vertex, f, g) {
                safe.push((g, len, b));
            }
        }
        let clean = safe.iter().any(|s| s.2.is_none());
        safe.retain(|s| s.2.is_none() == clean);
        let Some(&(into, _, bridges)) = safe.iter().reduce(|x, y| if y.1 > x.1 { y } else { x })
        else {
            no_safe[f as usize] = true;
            continue;
        };
        if let Some(t) = bridges {
            bridging.push((out.len(), t));
        }
        out.push((into, a, c));
        // union: `into` stays the root
        dsu.0[f as usize] = into;
        area[into as usize] += a;
        moment[into as usize] = [
            moment[into as usize][0] + moment[f as usize][0],
            moment[into as usize][1] + moment[f as usize][1],
        ];
        let moved = std::mem::take(&mut members[f as usize]);
        members[into as usize].extend(moved);
        if area[into as usize] < min {
            heap.push(Reverse((OrdF64(area[into as usize]), into)));
        }
    }
    // an edge between two faces of one merged piece disappears
    for e in 0..edges.len() {
        if edges[e].alive {
            let (f, g) = (face_of[2 * e], face_of[2 * e + 1]);
            if piece[f as usize] && piece[g as usize] && dsu.find(f) == dsu.find(g) {
                edges[e].alive = false;
            }
        }
    }
    // report the piece each merge ended in
    let mut bridge_of: Vec<Option<u32>> = vec![None; out.len()];
    for (k, t) in bridging {
        bridge_of[k] = Some(t);
    }
    let out = out
        .into_iter()
        .zip(bridge_of)
        .map(|((into, a, c), b)| (dsu.find(into), a, c, b))
        .collect();
    let root_of = (0..nf as u32).map(|f| dsu.find(f)).collect();
    // the kept pieces as they ended: still roots, still below the minimum
    let kept = (0..nf as u32)
        .filter(|&f| no_safe[f as usize] && dsu.find(f) == f)
        .filter_map(|f| {
            let a = area[f as usize];
            let m = moment[f as usize];
            (a < min).then(|| (f, a, [m[0] / a, m[1] / a]))
        })
        .collect();
    (out, root_of, kept)
}

/// Whether merging the pieces with roots `f` and `g` keeps every joint face (module doc,
/// step 8): for each trace of the edges they share, the trace must not go on as a face
/// past both ends of the shared run, nor past either end as a face of `f` or `g` (`None`:
/// not safe). `Some(Some(trace))`: safe, but that trace goes on past one end as a face of
/// other pieces (the merge bridges it there); `Some(None)`: no shared trace goes on.
fn safe_merge(
    edges: &[Edge],
    face_of: &[u32],
    piece: &[bool],
    dsu: &mut Dsu,
    at_vertex: &HashMap<u32, Vec<u32>>,
    f: u32,
    g: u32,
) -> Option<Option<u32>> {
    // (root of one side, root of the other) of an alive trace edge between two pieces
    let sides = |e: u32, dsu: &mut Dsu| -> Option<(u32, u32)> {
        let (a, b) = (face_of[2 * e as usize], face_of[2 * e as usize + 1]);
        if !(piece[a as usize] && piece[b as usize]) {
            return None;
        }
        let (ra, rb) = (dsu.find(a), dsu.find(b));
        (ra != rb).then_some((ra, rb))
    };
    // the shared edges, by trace; the degree of each vertex among them
    let mut shared: HashMap<u32, HashMap<u32, u32>> = HashMap::new();
    let mut is_shared: Vec<u32> = Vec::new();
    for (e, ed) in edges.iter().enumerate() {
        let Kind::Trace(t) = ed.kind else { continue };
        if !ed.alive {
            continue;
        }
        if let Some((ra, rb)) = sides(e as u32, dsu) {
            if (ra == f && rb == g) || (ra == g && rb == f) {
                is_shared.push(e as u32);
                let deg = shared.entry(t).or_default();
                *deg.entry(ed.v[0]).or_default() += 1;
                *deg.entry(ed.v[1]).or_default() += 1;
            }
        }
    }
    let mut bridged = None;
    for (t, deg) in shared {
        let mut beyond = 0;
        for (&v, &d) in &deg {
            if d != 1 {
                continue; // inside the shared run
            }
            let mut goes_on = false;
            let mut own_face = false;
            for &e in at_vertex.get(&v).into_iter().flatten() {
                if is_shared.contains(&e) || edges[e as usize].kind != Kind::Trace(t) {
                    continue;
                }
                if let Some((ra, rb)) = sides(e, dsu) {
                    goes_on = true;
                    own_face |= [ra, rb].iter().any(|&r| r == f || r == g);
                }
            }
            if own_face {
                return None;
            }
            beyond += usize::from(goes_on);
        }
        if beyond >= 2 {
            return None;
        }
        if beyond == 1 {
            bridged = Some(t);
        }
    }
    Some(bridged)
}

/// A total order on f64 for the heap (areas are finite).
#[derive(Debug, Clone, Copy, PartialEq)]
struct OrdF64(f64);
impl Eq for OrdF64 {}
impl PartialOrd for OrdF64 {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for OrdF64 {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// The removed trace edges grouped per trace into polylines: (trace, points).
/// A polyline stops where it meets a piece's boundary (`deg_cut > 0`): the parts of one
/// trace on the two sides of a joint it crosses are two cracks.
fn crack_polylines(
    pos: &[Vec2],
    edges: &[Edge],
    removed: &[u32],
    deg_cut: &[u32],
) -> Vec<(u32, Vec<Vec2>)> {
    let mut by_trace: HashMap<u32, Vec<u32>> = HashMap::new();
    for &e in removed {
        if let Kind::Trace(t) = edges[e as usize].kind {
            by_trace.entry(t).or_default().push(e);
        }
    }
    let mut traces: Vec<u32> = by_trace.keys().copied().collect();
    traces.sort_unstable();
    let mut out = Vec::new();
    for t in traces {
        let mut es = by_trace.remove(&t).unwrap_or_default();
        es.sort_unstable();
        // adjacency among this trace's crack edges
        let mut inc: HashMap<u32, Vec<u32>> = HashMap::new();
        for &e in &es {
            for &v in &edges[e as usize].v {
                inc.entry(v).or_default().push(e);
            }
        }
        let mut used: HashMap<u32, bool> = es.iter().map(|&e| (e, false)).collect();
        // walks start at vertices of odd degree first (the ends), then anywhere
        let mut starts: Vec<u32> = inc
            .iter()
            .filter(|(_, l)| l.len() % 2 == 1)
            .map(|(&v, _)| v)
            .collect();
        starts.sort_unstable();
        let mut rest: Vec<u32> = inc.keys().copied().collect();
        rest.sort_unstable();
        starts.extend(rest);
        for s in starts {
            while let Some(&first) = inc[&s].iter().find(|e| !used[e]) {
                let mut pts = vec![pos[s as usize]];
                let (mut v, mut e) = (s, first);
                loop {
                    used.insert(e, true);
                    let ed = &edges[e as usize];
                    v = if ed.v[0] == v { ed.v[1] } else { ed.v[0] };
                    pts.push(pos[v as usize]);
                    match inc[&v].iter().find(|e| !used[e]) {
                        Some(&next) if inc[&v].len() == 2 && deg_cut[v as usize] == 0 => e = next,
                        _ => break,
                    }
                }
                out.push((t, pts));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }
    fn line(a: Vec2, b: Vec2, joint: usize) -> Trace {
        Trace {
            points: vec![a, b],
            joint,
        }
    }
    fn total_area(c: &Cut) -> f64 {
        c.pieces.iter().map(|p| signed_area(&p.vertices)).sum()
    }

    #[test]
    fn no_trace_gives_the_polygon_itself() {
        let p = rect(0.0, 0.0, 2.0, 1.0);
        let c = cut_polygon(&p, &[line([5.0, 5.0], [6.0, 6.0], 0)], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 1);
        assert_eq!(c.pieces[0].vertices, p);
        assert_eq!(c.pieces[0].edge_joint, vec![None; 4]);
    }

    #[test]
    fn one_line_splits_a_rectangle() {
        let p = rect(0.0, 0.0, 2.0, 1.0);
        let c = cut_polygon(&p, &[line([1.0, -1.0], [1.0, 2.0], 3)], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 2);
        assert!(c.cracks.is_empty());
        // left piece first (same centroid height)
        assert_eq!(c.pieces[0].vertices, rect(0.0, 0.0, 1.0, 1.0));
        assert_eq!(c.pieces[0].edge_joint, vec![None, Some(3), None, None]);
        assert_eq!(c.pieces[1].vertices, rect(1.0, 0.0, 2.0, 1.0));
        assert_eq!(c.pieces[1].edge_joint, vec![None, None, None, Some(3)]);
    }

    #[test]
    fn a_trace_ending_inside_is_a_crack() {
        let p = rect(0.0, 0.0, 2.0, 1.0);
        let c = cut_polygon(&p, &[line([1.0, -1.0], [1.0, 0.5], 0)], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 1);
        assert_eq!(c.pieces[0].vertices, p);
        assert_eq!(c.cracks.len(), 1);
        let k = &c.cracks[0];
        assert_eq!(k.piece, 0);
        let mut pts = k.points.clone();
        pts.sort_by(|a, b| a[1].total_cmp(&b[1]));
        assert_eq!(pts, vec![[1.0, 0.0], [1.0, 0.5]]);
    }

    #[test]
    fn crossing_traces_cut_at_their_intersection_and_leave_the_dangling_part() {
        // a full vertical cut, and a horizontal trace from the left edge to x = 1.5:
        // it cuts the left half and is a crack in the right half.
        let p = rect(0.0, 0.0, 2.0, 1.0);
        let t = [
            line([1.0, -1.0], [1.0, 2.0], 0),
            line([-1.0, 0.5], [1.5, 0.5], 1),
        ];
        let c = cut_polygon(&p, &t, 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 3);
        assert!((total_area(&c) - 2.0).abs() < 1e-12);
        assert_eq!(c.cracks.len(), 1);
        assert_eq!(c.cracks[0].joint, 1);
        let right = c
            .pieces
            .iter()
            .position(|p| (signed_area(&p.vertices) - 1.0).abs() < 1e-12)
            .unwrap();
        assert_eq!(c.cracks[0].piece, right);
    }

    #[test]
    fn a_trace_along_an_edge_or_through_a_corner_makes_no_face() {
        let p = rect(0.0, 0.0, 2.0, 1.0);
        let t = [
            line([-1.0, 1.0], [3.0, 1.0], 0),  // along the top edge
            line([-1.0, -1.0], [0.5, 0.5], 1), // through the corner (0, 0), ends inside
            line([1.0, -1.0], [3.0, 1.0], 2),  // touches the corner (2, 0) from outside
        ];
        let c = cut_polygon(&p, &t, 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 1, "{c:?}");
        assert_eq!(c.pieces[0].vertices, p);
        assert_eq!(c.cracks.len(), 1);
    }

    #[test]
    fn a_closed_loop_cuts_out_its_piece() {
        // a square loop inside, and one hanging from the boundary by a single trace: each
        // cuts out its square, and the piece around them has two holes; the stem is a crack
        let p = rect(0.0, 0.0, 6.0, 4.0);
        let sq = Trace {
            points: vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0], [1.0, 1.0]],
            joint: 0,
        };
        let hanging = Trace {
            points: vec![[4.0, 1.0], [5.0, 1.0], [5.0, 2.0], [4.0, 2.0], [4.0, 1.0]],
            joint: 1,
        };
        let stem = line([4.5, 2.0], [4.5, 5.0], 2);
        let c = cut_polygon(&p, &[sq, hanging, stem], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 3);
        assert!(c.enclosed.is_empty());
        // by centroid: the rock (y = 2), then the squares left to right (y = 1.5 < 2)
        let (left, right, rock) = (&c.pieces[0], &c.pieces[1], &c.pieces[2]);
        assert_eq!(rock.vertices, p);
        assert_eq!(rock.holes.len(), 2);
        let area = |q: &Piece| {
            Region {
                outer: &q.vertices,
                holes: &q.holes,
            }
            .area()
        };
        assert!((area(rock) - 22.0).abs() < 1e-12);
        assert!(rock.holes.iter().all(|h| signed_area(h) < 0.0));
        assert_eq!(&rock.edge_joint[..4], &[None; 4]);
        assert_eq!(rock.edge_joint.len(), 12);
        let mut tags: Vec<Option<usize>> = rock.edge_joint[4..].to_vec();
        tags.sort();
        assert_eq!(tags, [[Some(0); 4], [Some(1); 4]].concat());
        for (q, j, x) in [(left, 0, 1.5), (right, 1, 4.5)] {
            assert!((area(q) - 1.0).abs() < 1e-12 && q.holes.is_empty());
            assert!(q.edge_joint.iter().all(|&t| t == Some(j)));
            let c = crate::geometry::moments::polygon_moments(&q.vertices, q.vertices[0]);
            assert!((c.centroid()[0] - x).abs() < 1e-12);
        }
        // the stem is the only crack, from the loop to the boundary, in the rock
        assert_eq!(c.cracks.len(), 1);
        assert_eq!((c.cracks[0].joint, c.cracks[0].piece), (2, 2));
        let crack_length: f64 = c.cracks[0]
            .points
            .windows(2)
            .map(|w| dist(w[0], w[1]))
            .sum();
        assert!((crack_length - 2.0).abs() < 1e-12, "{crack_length}");
    }

    #[test]
    fn a_pinched_loop_is_a_closed_crack() {
        // a loop touching the boundary at one point, and two loops touching each other at
        // one point: none can be a piece (it would pinch the piece around it)
        let p = rect(0.0, 0.0, 6.0, 4.0);
        let touching = Trace {
            points: vec![[1.0, 0.0], [2.0, 1.0], [1.0, 2.0], [0.5, 1.0], [1.0, 0.0]],
            joint: 0,
        };
        let a = Trace {
            points: vec![[3.0, 1.0], [4.0, 1.0], [4.0, 2.0], [3.0, 2.0], [3.0, 1.0]],
            joint: 1,
        };
        let b = Trace {
            points: vec![[4.0, 2.0], [5.0, 2.0], [5.0, 3.0], [4.0, 3.0], [4.0, 2.0]],
            joint: 1,
        };
        let c = cut_polygon(&p, &[touching, a, b], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 1);
        assert_eq!(c.pieces[0].vertices, p);
        assert!(c.pieces[0].holes.is_empty());
        assert_eq!(c.enclosed.len(), 3);
        assert!(c.enclosed.iter().all(|e| e.into == 0));
        let crack_length: f64 = c
            .cracks
            .iter()
            .map(|k| k.points.windows(2).map(|w| dist(w[0], w[1])).sum::<f64>())
            .sum();
        let diamond = 2.0 * (2f64.sqrt() + 1.25f64.sqrt());
        assert!(
            (crack_length - diamond - 8.0).abs() < 1e-12,
            "{crack_length}"
        );
    }

    #[test]
    fn a_region_with_a_hole_is_cut_around_it() {
        // a rectangle with a square hole: a line through the hole splits it in two C-shaped
        // pieces (no hole); a line beside the hole leaves the hole in one piece
        let p = rect(0.0, 0.0, 6.0, 4.0);
        let mut hole = rect(2.0, 1.0, 4.0, 3.0);
        hole.reverse();
        let holes = vec![hole];
        let region = Region {
            outer: &p,
            holes: &holes,
        };
        let through = line([-1.0, 2.0], [7.0, 2.0], 0);
        let c = cut_region(region, &[through], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 2);
        for q in &c.pieces {
            assert!(q.holes.is_empty());
            assert!((signed_area(&q.vertices) - 10.0).abs() < 1e-12);
            assert_eq!(q.edge_joint.iter().filter(|t| t.is_some()).count(), 2);
        }
        let beside = line([1.0, -1.0], [1.0, 5.0], 0);
        let c = cut_region(region, &[beside], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 2);
        let (left, right) = (&c.pieces[0], &c.pieces[1]);
        assert!(left.holes.is_empty() && (signed_area(&left.vertices) - 4.0).abs() < 1e-12);
        assert_eq!(right.holes.len(), 1);
        assert!((signed_area(&right.vertices) - 20.0).abs() < 1e-12);
        assert!((signed_area(&right.holes[0]) + 4.0).abs() < 1e-12);
        assert_eq!(right.edge_joint.len(), 8);
        assert!(right.edge_joint[4..].iter().all(Option::is_none));
        // a trace inside the hole is no trace; one from the wall into the rock is a crack
        let inside = line([2.5, 1.5], [3.5, 2.5], 0);
        let spur = line([4.0, 2.0], [5.0, 2.0], 1);
        let c = cut_region(region, &[inside, spur], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 1);
        assert_eq!(c.pieces[0].holes, holes);
        assert_eq!(c.cracks.len(), 1);
        assert_eq!(c.cracks[0].joint, 1);
        // a loop around the hole cuts out a ring with the hole in it
        let ring = Trace {
            points: vec![[1.0, 0.5], [5.0, 0.5], [5.0, 3.5], [1.0, 3.5], [1.0, 0.5]],
            joint: 2,
        };
        let c = cut_region(region, &[ring], 1e-9, None).unwrap();
        assert_eq!(c.pieces.len(), 2);
        let areas: Vec<f64> = c
            .pieces
            .iter()
            .map(|q| {
                Region {
                    outer: &q.vertices,
                    holes: &q.holes,
                }
                .area()
            })
            .collect();
        let total: f64 = areas.iter().sum();
        assert!((total - 20.0).abs() < 1e-12, "{areas:?}");
        let inner = c
            .pieces
            .iter()
            .position(|q| q.edge_joint[0].is_some())
            .unwrap();
        assert!((areas[inner] - 8.0).abs() < 1e-12);
        // the hole as given, starting at its lowest, then leftmost corner
        assert_eq!(
            c.pieces[inner].holes,
            [[[2.0, 1.0], [2.0, 3.0], [4.0, 3.0], [4.0, 1.0]]]
        );
        assert_eq!(c.pieces[1 - inner].holes.len(), 1);
    }

    #[test]
    fn small_pieces_merge_across_their_longest_joint_face() {
        // vertical cuts at x = 1 and x = 1.05: the 0.05-wide strip joins a neighbour
        let p = rect(0.0, 0.0, 2.0, 1.0);
        let t = [
            line([1.0, -1.0], [1.0, 2.0], 0),
            line([1.05, -1.0], [1.05, 2.0], 1),
        ];
        let c = cut_polygon(&p, &t, 1e-9, Some(0.1)).unwrap();
        assert_eq!(c.pieces.len(), 2);
        assert_eq!(c.merged.len(), 1);
        assert!((c.merged[0].area - 0.05).abs() < 1e-12);
        assert!((total_area(&c) - 2.0).abs() < 1e-12);
        let into = &c.pieces[c.merged[0].into];
        assert!(
            (signed_area(&into.vertices) - 1.05).abs() < 1e-12
                || (signed_area(&into.vertices) - 1.0).abs() < 1e-12
        );
    }

    #[test]
    fn a_small_piece_is_not_hooked_across_a_joint_that_goes_on() {
        // a thin bed (bedding y = 0.2) with a cross joint at x = 1 ending on the bedding, a
        // thick bed above with a cross joint at x = 2: the sliver [0, 1] × [0, 0.2] shares
        // 1 m of bedding with the block above and 0.2 m of cross joint with the block
        // behind it. Merging across the longest face would hook the block above into the
        // lower bed (the bedding goes on past the sliver as that block's own face): it joins
        // the block behind it, [1, 3] × [0, 0.2], in its own bed.
        let p = rect(0.0, 0.0, 3.0, 2.0);
        let t = [
            line([-1.0, 0.2], [4.0, 0.2], 0),
            line([1.0, 0.0], [1.0, 0.2], 1),
            line([2.0, 0.2], [2.0, 2.0], 1),
        ];
        let c = cut_polygon(&p, &t, 1e-9, Some(0.3)).unwrap();
        assert_eq!(c.merged.len(), 1);
        assert!(c.kept.is_empty());
        let into = &c.pieces[c.merged[0].into];
        assert!(
            (signed_area(&into.vertices) - 0.6).abs() < 1e-12,
            "{into:?}"
        );
        assert!(
            into.vertices.iter().all(|v| v[1] <= 0.2 + 1e-12),
            "{into:?}"
        );
        assert_eq!(c.merged[0].bridges, None);
    }

    #[test]
    fn a_small_piece_between_joints_that_go_on_everywhere_is_kept() {
        // a 0.1 × 0.1 piece at the crossing of two persistent strips: every face's joint
        // goes on past both of its ends, so no merge is safe
        let p = rect(0.0, 0.0, 3.0, 3.0);
        let t = [
            line([1.45, -1.0], [1.45, 4.0], 0),
            line([1.55, -1.0], [1.55, 4.0], 0),
            line([-1.0, 1.45], [4.0, 1.45], 1),
            line([-1.0, 1.55], [4.0, 1.55], 1),
        ];
        let c = cut_polygon(&p, &t, 1e-9, Some(0.05)).unwrap();
        assert_eq!(c.pieces.len(), 9);
        assert!(c.merged.is_empty(), "{:?}", c.merged);
        assert_eq!(c.kept.len(), 1);
        assert!((c.kept[0].area - 0.01).abs() < 1e-12);
        assert!((c.kept[0].centroid[0] - 1.5).abs() < 1e-12);
    }
}
