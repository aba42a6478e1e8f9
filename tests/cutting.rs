//! Block cutting by joint sets and joints (`nmm::geometry::cut` and the model's
//! `[[joint_set]]` / `[[joint]]`): the pieces tile the block exactly, their number
//! agrees with an independent count (Euler's formula for lines across a convex polygon;
//! a flood fill of a fine raster whose neighbours connect unless a trace or the boundary
//! lies between them, which counts what cracks do not separate), and the result does not
//! depend on the vertex order or on where the model is. A property test draws random
//! polygons and sets.

use nmm::geometry::cut::{cut_polygon, Cut, Trace};
use nmm::geometry::polygon::{
    degeneracy, is_ccw, point_in_polygon, point_segment_distance, segment_on_boundary,
    self_intersection, signed_area, Location,
};
use nmm::geometry::region::{regions_overlap, Region};
use nmm::geometry::{Aabb, Vec2};
use nmm::model::parse_model;
use proptest::prelude::*;
use std::path::Path;

#[path = "support/proptest_cases.rs"]
mod proptest_cases;
use proptest_cases::cases;

const TOL: f64 = 1e-9;

/// A joint set: (angle in degrees, spacing, origin, optional (trace, bridge)).
type Set = (f64, f64, Vec2, Option<(f64, f64)>);

/// The traces of a set over the box `bb` (written independently of the model's generator).
fn set_traces(set: Set, joint: usize, bb: Aabb) -> Vec<Trace> {
    let (angle, s, o, pattern) = set;
    let (sn, cs) = angle.to_radians().sin_cos();
    let (d, n) = ([cs, sn], [-sn, cs]);
    let corners = [
        bb.min,
        [bb.max[0], bb.min[1]],
        bb.max,
        [bb.min[0], bb.max[1]],
    ];
    let proj = |p: Vec2, a: Vec2| (p[0] - o[0]) * a[0] + (p[1] - o[1]) * a[1];
    let us: Vec<f64> = corners.iter().map(|&p| proj(p, n) / s).collect();
    let ws: Vec<f64> = corners.iter().map(|&p| proj(p, d)).collect();
    let (u0, u1) = (
        us.iter().cloned().fold(f64::MAX, f64::min),
        us.iter().cloned().fold(f64::MIN, f64::max),
    );
    let (w0, w1) = (
        ws.iter().cloned().fold(f64::MAX, f64::min) - 1.0,
        ws.iter().cloned().fold(f64::MIN, f64::max) + 1.0,
    );
    let at = |k: f64, w: f64| {
        [
            o[0] + k * s * n[0] + w * d[0],
            o[1] + k * s * n[1] + w * d[1],
        ]
    };
    let mut out = Vec::new();
    let mut k = u0.ceil();
    while k <= u1 {
        match pattern {
            None => out.push(Trace {
                points: vec![at(k, w0), at(k, w1)],
                joint,
            }),
            Some((l, b)) => {
                let mut m = (w0 / (l + b)).floor();
                while m * (l + b) < w1 {
                    out.push(Trace {
                        points: vec![at(k, m * (l + b)), at(k, m * (l + b) + l)],
                        joint,
                    });
                    m += 1.0;
                }
            }
        }
        k += 1.0;
    }
    out
}

fn traces_of(sets: &[Set], poly: &[Vec2]) -> Vec<Trace> {
    let bb = Aabb::of_points(poly);
    sets.iter()
        .enumerate()
        .flat_map(|(j, &s)| set_traces(s, j, bb))
        .collect()
}

fn area(p: &[Vec2]) -> f64 {
    signed_area(p)
}

fn region(p: &nmm::geometry::cut::Piece) -> Region<'_> {
    Region {
        outer: &p.vertices,
        holes: &p.holes,
    }
}

/// The pieces tile `poly`: areas add up (1e-9 relative), pieces are simple CCW polygons
/// (with clockwise holes where a loop of traces cut out pieces inside them) that do not
/// overlap, edges tagged `None` lie on the block's boundary and edges tagged `Some(j)` on
/// a trace of joint j, and every sample point inside the block is inside (or on the
/// boundary of) a piece and strictly inside at most one.
fn assert_tiles(label: &str, poly: &[Vec2], traces: &[Trace], cut: &Cut) {
    let a0 = area(poly);
    let total: f64 = cut.pieces.iter().map(|p| region(p).area()).sum();
    assert!(
        ((total - a0) / a0).abs() < 1e-9,
        "{label}: pieces' area {total} vs {a0}"
    );
    let tol = TOL * Aabb::of_points(poly).diagonal();
    for (i, p) in cut.pieces.iter().enumerate() {
        let v = &p.vertices;
        assert!(is_ccw(v), "{label}: piece {i} not CCW");
        assert_eq!(
            degeneracy(v, tol),
            None,
            "{label}: piece {i} degenerate: {v:?}"
        );
        assert_eq!(
            self_intersection(v, tol),
            None,
            "{label}: piece {i} self-intersects"
        );
        assert_eq!(
            p.edge_joint.len(),
            region(p).edge_count(),
            "{label}: piece {i}"
        );
        for h in &p.holes {
            assert!(
                signed_area(h) < 0.0,
                "{label}: piece {i}: a hole not clockwise"
            );
            assert_eq!(self_intersection(h, tol), None, "{label}: piece {i}");
        }
        let edges = region(p)
            .loops()
            .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])));
        for (k, (a, b)) in edges.enumerate() {
            match p.edge_joint[k] {
                None => assert!(
                    segment_on_boundary(poly, a, b, 10.0 * tol),
                    "{label}: piece {i} edge {k} is untagged but not on the block's boundary"
                ),
                Some(j) => assert!(
                    traces
                        .iter()
                        .filter(|t| t.joint == j)
                        .any(|t| t.points.windows(2).any(|w| {
                            point_segment_distance(a, w[0], w[1]) <= 10.0 * tol
                                && point_segment_distance(b, w[0], w[1]) <= 10.0 * tol
                        })),
                    "{label}: piece {i} edge {k} tagged {j} is on no trace of joint {j}"
                ),
            }
        }
    }
    let boxes: Vec<Aabb> = cut
        .pieces
        .iter()
        .map(|p| Aabb::of_points(&p.vertices))
        .collect();
    for i in 0..cut.pieces.len() {
        for j in i + 1..cut.pieces.len() {
            if boxes[i].overlaps(&boxes[j]) {
                assert!(
                    !regions_overlap(region(&cut.pieces[i]), region(&cut.pieces[j]), 10.0 * tol),
                    "{label}: pieces {i} and {j} overlap"
                );
            }
        }
    }
    // sample points on a skewed lattice
    let bb = Aabb::of_points(poly);
    let (w, h) = (bb.max[0] - bb.min[0], bb.max[1] - bb.min[1]);
    for k in 0..400 {
        let p = [
            bb.min[0] + w * ((k as f64 * 0.618_033_988_7) % 1.0),
            bb.min[1] + h * ((k as f64 * 0.414_213_562_3 + 0.5 / 400.0) % 1.0),
        ];
        if point_in_polygon(poly, p, tol) != Location::Inside {
            continue;
        }
        let locs: Vec<Location> = cut
            .pieces
            .iter()
            .map(|pc| region(pc).locate(p, 10.0 * tol))
            .collect();
        let inside = locs.iter().filter(|&&l| l == Location::Inside).count();
        let on = locs.iter().filter(|&&l| l == Location::Boundary).count();
        assert!(
            inside + on >= 1 && inside <= 1 && !(inside == 1 && on > 0),
            "{label}: sample {p:?} is inside {inside} and on {on} pieces"
        );
    }
}

/// Strict crossing of the closed segments pq and ab (touching counts as crossing).
fn crosses(p: Vec2, q: Vec2, a: Vec2, b: Vec2) -> bool {
    let o =
        |u: Vec2, v: Vec2, w: Vec2| (v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0]);
    let (d1, d2) = (o(a, b, p), o(a, b, q));
    let (d3, d4) = (o(p, q, a), o(p, q, b));
    (d1 * d2 <= 0.0) && (d3 * d4 <= 0.0)
}

/// Independent count of the pieces: a raster of step `step` over the polygon's box; two
/// neighbouring samples inside the polygon are connected unless the segment between them
/// touches a trace or the polygon's boundary. Components = pieces, as long as every piece
/// and every gap (between a crack's tip and a trace, across a notch) is several steps wide.
fn raster_count(poly: &[Vec2], traces: &[Trace], step: f64) -> usize {
    raster_components(poly, traces, step).len()
}

/// The raster's components: (a sample point, number of samples) each.
fn raster_components(poly: &[Vec2], traces: &[Trace], step: f64) -> Vec<(Vec2, usize)> {
    let bb = Aabb::of_points(poly);
    let nx = ((bb.max[0] - bb.min[0]) / step).ceil() as usize + 1;
    let ny = ((bb.max[1] - bb.min[1]) / step).ceil() as usize + 1;
    let at = |i: usize, j: usize| {
        [
            bb.min[0] + (i as f64 + 0.37) * step,
            bb.min[1] + (j as f64 + 0.29) * step,
        ]
    };
    let inside: Vec<bool> = (0..nx * ny)
        .map(|k| point_in_polygon(poly, at(k % nx, k / nx), 0.0) == Location::Inside)
        .collect();
    let mut segs: Vec<(Vec2, Vec2)> = traces
        .iter()
        .flat_map(|t| {
            t.points
                .windows(2)
                .map(|w| (w[0], w[1]))
                .collect::<Vec<_>>()
        })
        .collect();
    for k in 0..poly.len() {
        segs.push((poly[k], poly[(k + 1) % poly.len()]));
    }
    // bucket segments by raster row ranges to keep this quick
    let blocked = |p: Vec2, q: Vec2| {
        segs.iter().any(|&(a, b)| {
            let lo = [a[0].min(b[0]), a[1].min(b[1])];
            let hi = [a[0].max(b[0]), a[1].max(b[1])];
            !(p[0].max(q[0]) < lo[0]
                || p[0].min(q[0]) > hi[0]
                || p[1].max(q[1]) < lo[1]
                || p[1].min(q[1]) > hi[1])
                && crosses(p, q, a, b)
        })
    };
    let mut label = vec![usize::MAX; nx * ny];
    let mut count = 0;
    let mut comps = Vec::new();
    for start in 0..nx * ny {
        if !inside[start] || label[start] != usize::MAX {
            continue;
        }
        let mut stack = vec![start];
        label[start] = count;
        let mut size = 0;
        while let Some(k) = stack.pop() {
            size += 1;
            let (i, j) = (k % nx, k / nx);
            let mut nb = Vec::new();
            if i + 1 < nx {
                nb.push(k + 1);
            }
            if i > 0 {
                nb.push(k - 1);
            }
            if j + 1 < ny {
                nb.push(k + nx);
            }
            if j > 0 {
                nb.push(k - nx);
            }
            for m in nb {
                if inside[m] && label[m] == usize::MAX && !blocked(at(i, j), at(m % nx, m / nx)) {
                    label[m] = count;
                    stack.push(m);
                }
            }
        }
        comps.push((at(start % nx, start / nx), size));
        count += 1;
    }
    comps
}

/// Euler's formula for lines across a polygon (convex or not) in general position: the
/// lines' parts inside the polygon (intervals between boundary crossings) and the
/// boundary form a connected plane graph, so with K intervals and I crossings of two
/// intervals, V − E + F = 2 gives pieces = 1 + K + I.
fn euler_count(poly: &[Vec2], lines: &[(Vec2, Vec2)]) -> usize {
    let side = |p: Vec2, (a, b): (Vec2, Vec2)| {
        (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
    };
    // inside intervals of each line, as (line, t0, t1) with t along a → b
    let mut intervals: Vec<(usize, f64, f64)> = Vec::new();
    for (li, &(a, b)) in lines.iter().enumerate() {
        let mut ts = Vec::new();
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            let (sp, sq) = (side(p, (a, b)), side(q, (a, b)));
            assert!(
                sp.abs() > 1e-9 && sq.abs() > 1e-9,
                "test configuration: a line through a vertex"
            );
            if (sp > 0.0) != (sq > 0.0) {
                // crossing point x = p + (q - p) sp / (sp - sq); its parameter on a → b
                let x = [
                    p[0] + (q[0] - p[0]) * sp / (sp - sq),
                    p[1] + (q[1] - p[1]) * sp / (sp - sq),
                ];
                let d = [b[0] - a[0], b[1] - a[1]];
                ts.push(
                    ((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]),
                );
            }
        }
        ts.sort_by(f64::total_cmp);
        for w in ts.chunks(2) {
            intervals.push((li, w[0], w[1]));
        }
    }
    let point = |(li, t, _): (usize, f64, f64)| -> Vec2 {
        let (a, b) = lines[li];
        [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
    };
    let mut crossings = 0;
    for i in 0..intervals.len() {
        for j in i + 1..intervals.len() {
            let (x, y) = (intervals[i], intervals[j]);
            if x.0 == y.0 {
                continue;
            }
            let ((a, b), (c, d)) = (lines[x.0], lines[y.0]);
            let den = (b[0] - a[0]) * (d[1] - c[1]) - (b[1] - a[1]) * (d[0] - c[0]);
            if den.abs() < 1e-12 {
                continue;
            }
            let t = ((c[0] - a[0]) * (d[1] - c[1]) - (c[1] - a[1]) * (d[0] - c[0])) / den;
            let u = ((c[0] - a[0]) * (b[1] - a[1]) - (c[1] - a[1]) * (b[0] - a[0])) / den;
            if t > x.1 && t < x.2 && u > y.1 && u < y.2 {
                crossings += 1;
            }
        }
    }
    let _ = point;
    1 + intervals.len() + crossings
}

/// The smallest distance from a trace end inside the polygon to another trace it does not
/// touch: the raster count is valid only when it is several raster steps.
fn tip_gap(poly: &[Vec2], traces: &[Trace]) -> f64 {
    let mut gap = f64::INFINITY;
    for (i, t) in traces.iter().enumerate() {
        for &p in [t.points[0], t.points[t.points.len() - 1]].iter() {
            if point_in_polygon(poly, p, 0.0) != Location::Inside {
                continue;
            }
            for (j, u) in traces.iter().enumerate() {
                if i == j {
                    continue;
                }
                for w in u.points.windows(2) {
                    let d = point_segment_distance(p, w[0], w[1]);
                    if d > 1e-12 {
                        gap = gap.min(d);
                    }
                }
            }
        }
    }
    gap
}

/// The smallest width (2 × area / perimeter) of the pieces: the raster count is valid
/// only when it is several raster steps.
fn min_width(cut: &Cut) -> f64 {
    cut.pieces
        .iter()
        .map(|p| {
            let per: f64 = region(p)
                .loops()
                .map(|v| {
                    (0..v.len())
                        .map(|k| nmm::geometry::dist(v[k], v[(k + 1) % v.len()]))
                        .sum::<f64>()
                })
                .sum();
            2.0 * region(p).area() / per
        })
        .fold(f64::INFINITY, f64::min)
}

const SETS: [Set; 3] = [
    (0.0, 0.77, [0.1, 0.05], None),
    (63.0, 0.91, [0.3, 0.2], None),
    (131.0, 1.13, [0.05, 0.4], None),
];

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
    vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
}

#[test]
fn rectangle_cut_by_one_two_and_three_persistent_sets() {
    let poly = rect(0.0, 0.0, 7.3, 4.1);
    for k in 1..=3 {
        let traces = traces_of(&SETS[..k], &poly);
        let cut = cut_polygon(&poly, &traces, TOL * 8.4, None).unwrap();
        let lines: Vec<(Vec2, Vec2)> = traces.iter().map(|t| (t.points[0], t.points[1])).collect();
        let euler = euler_count(&poly, &lines);
        eprintln!("{k} set(s): {} pieces, Euler {euler}", cut.pieces.len());
        assert_eq!(cut.pieces.len(), euler, "{k} sets");
        assert!(cut.cracks.is_empty());
        assert_tiles(&format!("{k} sets"), &poly, &traces, &cut);
    }
}

/// Non-convex blocks (an L, a comb with two notches) cut by persistent sets: a trace may
/// cross a block several times and a set's cell may fall apart into several pieces.
#[test]
fn non_convex_polygons_cut_by_persistent_sets() {
    let l_shape = vec![
        [0.0, 0.0],
        [6.0, 0.0],
        [6.0, 2.0],
        [2.5, 2.0],
        [2.5, 5.0],
        [0.0, 5.0],
    ];
    let comb = vec![
        [0.0, 0.0],
        [7.0, 0.0],
        [7.0, 4.0],
        [5.5, 4.0],
        [5.5, 1.5],
        [4.5, 1.5],
        [4.5, 4.0],
        [2.5, 4.0],
        [2.5, 1.5],
        [1.5, 1.5],
        [1.5, 4.0],
        [0.0, 4.0],
    ];
    for (name, poly) in [("L", l_shape), ("comb", comb)] {
        for k in 1..=3 {
            let traces = traces_of(&SETS[..k], &poly);
            let cut = cut_polygon(&poly, &traces, TOL * 9.0, None).unwrap();
            let lines: Vec<(Vec2, Vec2)> =
                traces.iter().map(|t| (t.points[0], t.points[1])).collect();
            let euler = euler_count(&poly, &lines);
            eprintln!(
                "{name}, {k} set(s): {} pieces, Euler {euler}",
                cut.pieces.len()
            );
            assert_eq!(cut.pieces.len(), euler, "{name}, {k} sets");
            assert_tiles(&format!("{name}, {k} sets"), &poly, &traces, &cut);
        }
    }
}

/// Non-persistent traces cut only where they fully cross a piece; what ends inside is a
/// crack. One persistent set with one non-persistent set, and two non-persistent sets.
#[test]
fn non_persistent_sets_cut_only_where_they_cross() {
    let poly = rect(0.0, 0.0, 8.0, 5.0);
    let cases: [(&str, [Set; 2]); 2] = [
        (
            "persistent + non-persistent",
            [
                (10.0, 1.3, [0.2, 0.25], None),
                (95.0, 1.7, [0.5, 0.0], Some((2.1, 1.2))),
            ],
        ),
        (
            "two non-persistent",
            [
                (20.0, 1.1, [0.7, 0.1], Some((3.3, 1.4))),
                (110.0, 1.6, [0.35, 0.5], Some((2.6, 1.0))),
            ],
        ),
    ];
    for (name, sets) in cases {
        let traces = traces_of(&sets, &poly);
        let cut = cut_polygon(&poly, &traces, TOL * 9.4, None).unwrap();
        let step = 0.01;
        let raster = raster_count(&poly, &traces, step);
        eprintln!(
            "{name}: {} pieces, {} cracks, {} enclosed, raster {raster}, narrowest piece {:.3}",
            cut.pieces.len(),
            cut.cracks.len(),
            cut.enclosed.len(),
            min_width(&cut)
        );
        assert!(
            min_width(&cut) > 3.0 * step,
            "test configuration: a piece too thin for the raster"
        );
        assert!(
            tip_gap(&poly, &traces) > 3.0 * step,
            "test configuration: a crack tip too close to a trace for the raster"
        );
        // the raster also counts the regions that loops enclose (kept inside a piece)
        assert_eq!(cut.pieces.len() + cut.enclosed.len(), raster, "{name}");
        assert!(
            !cut.cracks.is_empty(),
            "{name}: a non-persistent set leaves cracks"
        );
        assert_tiles(name, &poly, &traces, &cut);
        // every crack lies inside its piece and is part of one trace of its joint
        for c in &cut.cracks {
            let piece = &cut.pieces[c.piece].vertices;
            for w in c.points.windows(2) {
                let mid = [(w[0][0] + w[1][0]) / 2.0, (w[0][1] + w[1][1]) / 2.0];
                assert_eq!(
                    region(&cut.pieces[c.piece]).locate(mid, 1e-9),
                    Location::Inside,
                    "{name}: crack {:?} in piece {} {:?}",
                    c.points,
                    c.piece,
                    piece
                );
            }
            let t = &traces[c.trace];
            assert_eq!(t.joint, c.joint);
            for &p in &c.points {
                assert!(
                    point_segment_distance(p, t.points[0], t.points[1]) < 1e-8,
                    "{name}"
                );
            }
        }
    }
}

/// Single joints (polylines): through the block, bent and ending inside, and two that
/// cross where only one reaches the boundary on both sides.
#[test]
fn single_joints_cut_and_crack() {
    let poly = rect(0.0, 0.0, 4.0, 3.0);
    let tr = |pts: &[Vec2], joint| Trace {
        points: pts.to_vec(),
        joint,
    };
    // through: two pieces
    let t = [tr(&[[-1.0, 0.5], [2.0, 1.5], [5.0, 2.0]], 0)];
    let c = cut_polygon(&poly, &t, 5e-9, None).unwrap();
    assert_eq!((c.pieces.len(), c.cracks.len()), (2, 0));
    assert_tiles("through", &poly, &t, &c);
    // bent, ending inside: one piece, one crack of two segments
    let t = [tr(&[[-1.0, 0.5], [2.0, 1.5], [2.5, 2.5]], 0)];
    let c = cut_polygon(&poly, &t, 5e-9, None).unwrap();
    assert_eq!((c.pieces.len(), c.cracks.len()), (1, 1));
    assert_eq!(c.pieces[0].vertices, poly);
    assert_eq!(c.cracks[0].points.len(), 3);
    // X: joint 0 crosses the block, joint 1 from the bottom to beyond joint 0, ending inside:
    // 3 pieces (joint 1 splits the lower piece) and 1 crack (joint 1's end above joint 0)
    let t = [
        tr(&[[-1.0, 1.5], [5.0, 1.5]], 0),
        tr(&[[2.0, -1.0], [2.0, 2.2]], 1),
    ];
    let c = cut_polygon(&poly, &t, 5e-9, None).unwrap();
    assert_eq!((c.pieces.len(), c.cracks.len()), (3, 1));
    assert_eq!(c.cracks[0].joint, 1);
    let top = &c.pieces[c.cracks[0].piece].vertices;
    assert!((area(top) - 6.0).abs() < 1e-12);
    assert_tiles("X", &poly, &t, &c);
    // a joint along an edge and one touching a corner make nothing
    let t = [
        tr(&[[-1.0, 3.0], [5.0, 3.0]], 0),
        tr(&[[3.0, -1.0], [5.0, 1.0]], 1),
    ];
    let c = cut_polygon(&poly, &t, 5e-9, None).unwrap();
    assert_eq!((c.pieces.len(), c.cracks.len()), (1, 0));
    assert_eq!(c.pieces[0].vertices, poly);
}

/// Traces through block corners, along edges and three through one point: the cut is
/// still exact (the tolerance snaps them together).
#[test]
fn degenerate_configurations_are_snapped() {
    let poly = rect(0.0, 0.0, 4.0, 4.0);
    let tr = |a: Vec2, b: Vec2, joint| Trace {
        points: vec![a, b],
        joint,
    };
    // both diagonals (through all four corners) and the two medians: 8 triangles
    let t = [
        tr([-1.0, -1.0], [5.0, 5.0], 0),
        tr([-1.0, 5.0], [5.0, -1.0], 0),
        tr([2.0, -1.0], [2.0, 5.0], 1),
        tr([-1.0, 2.0], [5.0, 2.0], 1),
    ];
    let c = cut_polygon(&poly, &t, 5.7e-9, None).unwrap();
    assert_eq!(c.pieces.len(), 8);
    for p in &c.pieces {
        assert!((area(&p.vertices) - 2.0).abs() < 1e-12);
        assert_eq!(p.vertices.len(), 3);
    }
    assert_tiles("star", &poly, &t, &c);
    // the same with the crossing moved by less than the tolerance
    let e = 1e-10;
    let t2 = [
        tr([-1.0, -1.0 + e], [5.0, 5.0 + e], 0),
        tr([-1.0, 5.0], [5.0, -1.0 - e], 0),
        tr([2.0 - e, -1.0], [2.0, 5.0], 1),
        tr([-1.0, 2.0], [5.0, 2.0 + e], 1),
    ];
    let c2 = cut_polygon(&poly, &t2, 5.7e-9, None).unwrap();
    assert_eq!(c2.pieces.len(), 8);
    assert_tiles("perturbed star", &poly, &t2, &c2);
}

/// A model: one free block `mass` with `joints` TOML appended.
fn model_text(vertices: &[Vec2], shift: Vec2, joints: &str) -> String {
    let pts: Vec<String> = vertices
        .iter()
        .map(|p| format!("[{:.17e}, {:.17e}]", p[0] + shift[0], p[1] + shift[1]))
        .collect();
    format!(
        "[analysis]\ndt = 0.01\nsteps = 1\n[cover]\nsize = 0.5\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"mass\"\nmaterial = \"rock\"\nvertices = [{}]\n\
         [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n{joints}",
        pts.join(", ")
    )
}

fn joints_toml(shift: Vec2) -> String {
    let o = |x: f64, y: f64| format!("[{:.17e}, {:.17e}]", x + shift[0], y + shift[1]);
    format!(
        "[[joint_set]]\nname = \"a\"\nangle = 25.0\nspacing = 0.9\norigin = {}\n\
         [[joint_set]]\nname = \"b\"\nangle = 105.0\nspacing = 1.3\norigin = {}\ntrace_length = 2.5\nbridge = 0.8\n\
         [[joint]]\nname = \"f\"\npoints = [{}, {}, {}]\n",
        o(0.1, 0.2),
        o(0.3, 0.0),
        o(-1.0, 3.1),
        o(3.0, 2.2),
        o(4.5, 3.9)
    )
}

/// (name, area, centroid relative to the shift, number of tagged edges) per block.
fn summary(text: &str, shift: Vec2) -> (Vec<(String, f64, Vec2, usize)>, usize) {
    let m = parse_model(text, Path::new(".")).unwrap();
    let blocks = m
        .blocks
        .iter()
        .map(|b| {
            let c = nmm::geometry::moments::polygon_moments(&b.vertices, b.vertices[0]).centroid();
            (
                b.name.clone(),
                area(&b.vertices),
                [c[0] - shift[0], c[1] - shift[1]],
                b.edge_joint.iter().filter(|j| j.is_some()).count(),
            )
        })
        .collect();
    (blocks, m.cracks.len())
}

/// The same block written from another vertex, clockwise, or the whole model translated:
/// the same pieces, with the same names.
#[test]
fn cutting_is_invariant_to_vertex_order_and_translation() {
    let poly = vec![
        [0.0, 0.0],
        [6.0, 0.0],
        [6.0, 3.0],
        [3.5, 5.0],
        [1.0, 5.0],
        [0.0, 2.5],
    ];
    let (reference, cracks) = summary(
        &model_text(&poly, [0.0, 0.0], &joints_toml([0.0, 0.0])),
        [0.0, 0.0],
    );
    assert!(reference.len() > 10, "{}", reference.len());
    assert!(cracks > 0);
    let total: f64 = reference.iter().map(|b| b.1).sum();
    assert!((total - area(&poly)).abs() < 1e-9 * area(&poly));
    let mut rotated = poly.clone();
    rotated.rotate_left(3);
    let mut reversed = poly.clone();
    reversed.reverse();
    let shift = [1234.5, -987.25];
    let variants = [
        (
            "rotated",
            model_text(&rotated, [0.0, 0.0], &joints_toml([0.0, 0.0])),
            [0.0, 0.0],
        ),
        (
            "clockwise",
            model_text(&reversed, [0.0, 0.0], &joints_toml([0.0, 0.0])),
            [0.0, 0.0],
        ),
        (
            "translated",
            model_text(&poly, shift, &joints_toml(shift)),
            shift,
        ),
    ];
    for (label, text, s) in variants {
        let (blocks, k) = summary(&text, s);
        assert_eq!(blocks.len(), reference.len(), "{label}");
        assert_eq!(k, cracks, "{label}");
        for (b, r) in blocks.iter().zip(&reference) {
            assert_eq!(b.0, r.0, "{label}");
            assert!(
                (b.1 - r.1).abs() < 1e-9 * total,
                "{label}: {} area {} vs {}",
                b.0,
                b.1,
                r.1
            );
            assert!(
                (b.2[0] - r.2[0]).abs() < 1e-8 && (b.2[1] - r.2[1]).abs() < 1e-8,
                "{label}: {} centroid {:?} vs {:?}",
                b.0,
                b.2,
                r.2
            );
            assert_eq!(b.3, r.3, "{label}: {} tagged edges", b.0);
        }
    }
}

/// A 100 m × 100 m block cut by two persistent sets 1 m apart (traces also along its
/// edges and through its corners): 10⁴ blocks of 1 m², named by centroid row by row.
/// Prints the time of the whole model validation (cutting included).
#[test]
fn ten_thousand_blocks() {
    let poly = rect(0.0, 0.0, 100.0, 100.0);
    let joints = "[[joint_set]]\nname = \"h\"\nangle = 0.0\nspacing = 1.0\n\
                  [[joint_set]]\nname = \"v\"\nangle = 90.0\nspacing = 1.0\n";
    let text = model_text(&poly, [0.0, 0.0], joints);
    let t = std::time::Instant::now();
    let m = parse_model(&text, Path::new(".")).unwrap();
    let secs = t.elapsed().as_secs_f64();
    eprintln!("10^4 blocks: model read, cut and validated in {secs:.3} s");
    assert_eq!(m.blocks.len(), 10_000);
    assert!(m.cracks.is_empty());
    for (k, b) in m.blocks.iter().enumerate() {
        assert_eq!(b.name, format!("mass.{}", k + 1));
        assert!((area(&b.vertices) - 1.0).abs() < 1e-9, "{}", b.name);
        let c = nmm::geometry::moments::polygon_moments(&b.vertices, b.vertices[0]).centroid();
        let (row, col) = (k / 100, k % 100);
        assert!(
            (c[0] - (col as f64 + 0.5)).abs() < 1e-9 && (c[1] - (row as f64 + 0.5)).abs() < 1e-9
        );
        assert_eq!(b.vertices.len(), 4, "{}", b.name);
    }
}

/// Random star-shaped polygons (convex or not) and one to three random sets.
fn polygon_strategy() -> impl Strategy<Value = Vec<Vec2>> {
    (
        5usize..12,
        prop::collection::vec((0.0f64..1.0, 0.5f64..1.0), 12),
    )
        .prop_map(|(n, params)| {
            let mut angles: Vec<f64> = params[..n]
                .iter()
                .map(|p| p.0 * std::f64::consts::TAU)
                .collect();
            angles.sort_by(f64::total_cmp);
            // keep vertices apart in angle
            for (k, a) in angles.iter_mut().enumerate() {
                *a = *a * 0.5 + (k as f64) * std::f64::consts::TAU / n as f64 * 0.5;
            }
            angles
                .iter()
                .zip(&params[..n])
                .map(|(&a, p)| [5.0 + 4.0 * p.1 * a.cos(), 5.0 + 4.0 * p.1 * a.sin()])
                .collect()
        })
}

fn set_strategy() -> impl Strategy<Value = Set> {
    (
        0.0f64..180.0,
        0.4f64..3.0,
        0.0f64..3.0,
        0.0f64..3.0,
        prop::option::of((0.5f64..4.0, 0.2f64..2.0)),
    )
        .prop_map(|(a, s, ox, oy, p)| (a, s, [ox, oy], p))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(48), ..ProptestConfig::default() })]

    #[test]
    fn random_polygons_and_sets_are_tiled(
        poly in polygon_strategy(),
        sets in prop::collection::vec(set_strategy(), 1..4),
        min_area in prop::option::of(0.01f64..0.5),
    ) {
        prop_assume!(self_intersection(&poly, 1e-6).is_none() && is_ccw(&poly));
        let traces = traces_of(&sets, &poly);
        let tol = 1e-9 * Aabb::of_points(&poly).diagonal();
        match cut_polygon(&poly, &traces, tol, min_area) {
            Ok(cut) => {
                assert_tiles("random", &poly, &traces, &cut);
                if let Some(m) = min_area {
                    // a piece below the minimum remains only if the block was not cut at all,
                    // or if it is reported kept (every merge would have bridged a joint)
                    if cut.pieces.len() > 1 {
                        for (k, p) in cut.pieces.iter().enumerate() {
                            let kept = cut.kept.iter().any(|g| g.into == k);
                            prop_assert!(
                                region(p).area() >= m || kept,
                                "piece of {} < {m}",
                                region(p).area()
                            );
                        }
                        for g in &cut.kept {
                            prop_assert!(g.area < m && g.into < cut.pieces.len());
                            let a = region(&cut.pieces[g.into]).area();
                            prop_assert!((a - g.area).abs() <= 1e-9 * a.max(1.0), "{a} vs {}", g.area);
                        }
                    }
                    // merged: pieces below the minimum, and any piece a merge enclosed
                    for g in &cut.merged {
                        prop_assert!(g.area > 0.0 && g.into < cut.pieces.len());
                    }
                }
            }
            Err(e) => prop_assert!(false, "{e}"),
        }
    }
}

/// A fixed base and a 2 m × 1 m block on it, cut by one vertical joint into two pieces,
/// settling in static mode; the interface monitor names the cut block.
fn settling_pieces(steps: usize) -> String {
    format!(
        "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = {steps}\ngravity = [0.0, -9.81]\n[cover]\nsize = 0.25\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = [[-0.5, -0.5], [2.5, -0.5], [2.5, 0.0], [-0.5, 0.0]]\nfixed = true\n\
         [[block]]\nname = \"mass\"\nmaterial = \"rock\"\nvertices = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]\n\
         [[joint]]\nname = \"j\"\npoints = [[1.1, -0.2], [1.1, 1.2]]\n\
         [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
         [[monitor]]\nname = \"m\"\ninterface = [\"mass\", \"base\"]\n"
    )
}

/// The interface monitor of a cut block sums the contact forces over its pieces: after
/// settling, the base carries the block's whole weight.
#[test]
fn interface_monitor_of_a_cut_block_sums_its_pieces() {
    let model = parse_model(&settling_pieces(40), Path::new(".")).unwrap();
    assert_eq!(model.blocks.len(), 3);
    let mut sim = nmm::simulation::Simulation::new(model).unwrap();
    while !sim.finished() {
        sim.advance().unwrap();
    }
    let v = nmm::simulation::monitor_values(&sim);
    let weight = 2000.0 * 9.81 * 2.0;
    eprintln!(
        "force on the pieces from the base: {:?}, weight {weight}",
        &v[..4]
    );
    assert!(
        (v[1] - weight).abs() < 1e-6 * weight,
        "{} vs {weight}",
        v[1]
    );
    // the same as the sum of the pieces' own interface forces
    let per_piece: f64 = (1..=2).map(|b| sim.contacts.interface_force(b, 0).fy).sum();
    assert!((per_piece - v[1]).abs() < 1e-9 * weight);
    assert!(v[3] > 0.0);
}

/// The contact output carries the joint of the face a contact is on: the joint's id for
/// contacts between the two pieces across the joint face, −1 elsewhere (and everywhere in
/// a model without joints).
#[test]
fn contacts_on_joint_faces_carry_the_joint_id() {
    use nmm::output::vtk::Values;
    for (text, jointed) in [
        (settling_pieces(1), true),
        (
            settling_pieces(1).replace(
                "[[joint]]\nname = \"j\"\npoints = [[1.1, -0.2], [1.1, 1.2]]\n",
                "",
            ),
            false,
        ),
    ] {
        let model = parse_model(&text, Path::new(".")).unwrap();
        let mut sim = nmm::simulation::Simulation::new(model).unwrap();
        sim.advance().unwrap();
        let g = nmm::simulation::contacts_grid(&sim);
        let joint = g
            .cell_data
            .iter()
            .find(|a| a.name == "joint")
            .expect("a joint field");
        let Values::Int32(joint) = &joint.values else {
            panic!("joint is not Int32")
        };
        let blocks = g.cell_data.iter().find(|a| a.name == "blocks").unwrap();
        let Values::Float64(blocks) = &blocks.values else {
            panic!()
        };
        let normals = g.cell_data.iter().find(|a| a.name == "normal").unwrap();
        let Values::Float64(normals) = &normals.values else {
            panic!()
        };
        assert_eq!(joint.len(), g.cells.len());
        assert!(!joint.is_empty());
        let mut across = 0;
        for (k, &j) in joint.iter().enumerate() {
            let (a, b) = (blocks[2 * k] as usize, blocks[2 * k + 1] as usize);
            let pieces = a != 0 && b != 0;
            if jointed && pieces {
                assert_eq!(j, 0, "contact {k} between the pieces");
                assert!(normals[2 * k].abs() > 0.99, "the joint is vertical");
                across += 1;
            } else {
                assert_eq!(j, -1, "contact {k} between blocks {a} and {b}");
            }
        }
        assert_eq!(across > 0, jointed);
    }
}

/// `nmm check --json` prints one JSON object with the summary; `nmm check` the same
/// numbers as text.
#[test]
fn check_prints_the_summary_as_json_and_as_text() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    let text = settling_pieces(1).replace(
        "[[interface]]",
        "[[joint]]\nname = \"crack\"\npoints = [[0.2, 0.5], [0.6, 0.5]]\n[[interface]]",
    );
    std::fs::write(&path, text).unwrap();
    let run = |json: bool| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"));
        c.arg("check");
        if json {
            c.arg("--json");
        }
        let out = c.arg(&path).output().unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let out = run(true);
    assert_eq!(out.trim().lines().count(), 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["blocks"], 3);
    assert_eq!(v["fixed_blocks"], 1);
    assert_eq!(v["cut_blocks"], 1);
    assert_eq!(v["joints"], 2);
    assert_eq!(v["cracks"], 1);
    let total = v["block_area_total"].as_f64().unwrap();
    assert!((total - 3.5).abs() < 1e-12, "{total}");
    let smallest = v["smallest_block_area"].as_f64().unwrap();
    assert!((smallest - 0.9).abs() < 1e-12, "{smallest}");
    assert_eq!(v["smallest_block"], "mass.2");
    for key in ["physical_covers", "manifold_elements", "unknowns"] {
        assert!(v[key].as_u64().unwrap() > 0, "{key}");
    }
    let text = run(false);
    for line in [
        "blocks: 3 (1 fixed)".to_string(),
        format!("physical covers: {}", v["physical_covers"]),
        format!("manifold elements: {}", v["manifold_elements"]),
        format!("unknowns: {}", v["unknowns"]),
        "cracks: 1".to_string(),
        "block area: total 3.5 m², smallest ".to_string(),
        "cutting: 0 joint set(s) and 2 joint(s) cut 1 block(s) into 2 pieces; 1 crack(s)"
            .to_string(),
    ] {
        assert!(text.contains(&line), "{line:?} not in {text}");
    }
}

/// The shipped jointed slope: one mass cut by two sets and a fault into 100+ blocks, with
/// cracks and merged slivers reported; `nmm check` accepts it.
#[test]
fn the_jointed_slope_example_is_cut_as_described() {
    let text = include_str!("../examples/jointed_slope.toml");
    let m = parse_model(text, Path::new("examples")).unwrap();
    let pieces = m
        .blocks
        .iter()
        .filter(|b| b.parent.as_deref() == Some("slope"))
        .count();
    assert_eq!(pieces + 1, m.blocks.len());
    assert!(pieces >= 100, "{pieces}");
    assert_eq!(m.joints.len(), 3);
    assert!(!m.cracks.is_empty() && !m.merged.is_empty());
    let total: f64 = m.blocks.iter().map(|b| area(&b.vertices)).sum();
    assert!((total - 830.0).abs() < 1e-9 * 830.0, "{total}");
    // every block is at least min_block_area, but the pieces kept because every merge
    // would have bridged a joint (one, of 0.0002 m²)
    assert_eq!(m.kept_small.len(), 1);
    for (i, b) in m.blocks.iter().enumerate().skip(1) {
        assert!(
            area(&b.vertices) >= 0.05 || m.kept_small.iter().any(|g| g.block == i),
            "{} is below min_block_area",
            b.name
        );
    }
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args(["check", "examples/jointed_slope.toml"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains(&format!("blocks: {} (1 fixed)", m.blocks.len())),
        "{stdout}"
    );
}
