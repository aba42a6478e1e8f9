//! A jointed rock slope: a slope profile cut into blocks by two persistent joint sets, on a
//! fixed L-shaped base (ground and back wall).
//!
//! The rock mass is the convex profile toe (0, 0) → (x_r, 0) → (x_r, H) → crest (H / tan β, H)
//! (face angle β, a crest bench of width `crest_width` behind it). Set 1 dips `dip_out`
//! towards the face (out of the slope), set 2 dips `dip_in` into the slope; joints of a set are
//! `spacing` apart (measured normal to the joints). Every block is the profile clipped by the
//! two strips of a lattice cell: a convex polygon. With `stagger`, set 2 is offset by half a
//! spacing in every other row of set 1 (cross joints that end at the bedding, T-junctions),
//! otherwise both sets are persistent.
//!
//! The construction is exact: every vertex is the intersection of two lines (a profile edge or a
//! joint) computed from that pair alone, always in the same order, so neighbouring blocks share
//! bit-identical vertices and never overlap. The lattice offsets are chosen so that no joint
//! passes near a corner of the profile and no block has an edge shorter than 1e-3 spacing.
//! Fragments smaller than `min_piece` of a lattice cell are left out (small voids along the
//! boundary of the rock mass, as loose pieces would have fallen).

use super::fmt_exact;
use crate::geometry::{cross, dot, sub, Vec2};
use crate::model::Mode;

/// Rock density (kg/m³).
pub const SLOPE_DENSITY: f64 = 2650.0;
/// Young's modulus of the rock (Pa).
pub const SLOPE_YOUNG: f64 = 1.0e10;
/// Poisson's ratio of the rock.
pub const SLOPE_POISSON: f64 = 0.25;
/// Friction angle of the joints (degrees).
pub const SLOPE_FRICTION_ANGLE: f64 = 35.0;
/// Normal and shear contact penalty (N/m).
pub const SLOPE_PENALTY: f64 = 1.0e10;

#[derive(Debug, Clone, PartialEq)]
pub struct SlopeOptions {
    /// Slope height H (m).
    pub height: f64,
    /// Face angle β from the horizontal (degrees, in (0, 90]).
    pub face_angle: f64,
    /// Width of the crest bench behind the crest (m).
    pub crest_width: f64,
    /// Dip of joint set 1, towards the face (degrees, in [0, 90)).
    pub dip_out: f64,
    /// Dip of joint set 2, into the slope (degrees, in (0, 90]).
    pub dip_in: f64,
    /// Normal spacing of sets 1 and 2 (m).
    pub spacing: [f64; 2],
    /// Set 2 offset by half a spacing in every other row of set 1.
    pub stagger: bool,
    /// Fragments with less than this fraction of a lattice cell's area are left out.
    pub min_piece: f64,
    pub steps: usize,
    /// Time step (s).
    pub dt: f64,
    /// Mathematical mesh size h (m).
    pub cover: f64,
    pub mode: Mode,
}

impl SlopeOptions {
    /// A 60° slope of height `height` with a crest bench of H/2, set 1 dipping 25° out of the
    /// slope (below the joints' 35°), set 2 dipping 70° into it, both 0.5 m apart, cover
    /// 0.5 m (the joint spacing, as the wall's cover is the brick height); 20 dynamic steps of 1 ms.
    pub fn new(height: f64) -> Self {
        SlopeOptions {
            height,
            face_angle: 60.0,
            crest_width: 0.5 * height,
            dip_out: 25.0,
            dip_in: 70.0,
            spacing: [0.5, 0.5],
            stagger: false,
            min_piece: 0.05,
            steps: 20,
            dt: 0.001,
            cover: 0.5,
            mode: Mode::Dynamic,
        }
    }

    /// [`SlopeOptions::new`] with the height that gives about `blocks` blocks: a start from the
    /// profile's area over a lattice cell's, then a few corrections by the count made (the
    /// pieces along the boundary add to it); the nearest count found wins (within a few per
    /// cent of `blocks` from ~50 blocks up).
    pub fn with_blocks(blocks: usize) -> Self {
        let at = |h: f64| SlopeOptions {
            crest_width: 0.5 * h,
            ..SlopeOptions::new(h)
        };
        let unit = at(1.0);
        // area = H² (crest ratio + 1 / (2 tan β)), with the crest bench proportional to H
        let per_h2 = unit.crest_width + 0.5 / unit.face_angle.to_radians().tan();
        let target = blocks.max(1) as f64;
        let mut h = (target * unit.cell_area() / per_h2).sqrt();
        let mut best = (f64::INFINITY, h);
        for _ in 0..6 {
            let Ok(g) = slope_geometry(&at(h)) else { break };
            let n = g.blocks.len().max(1) as f64;
            if (n - target).abs() < best.0 {
                best = ((n - target).abs(), h);
            }
            if n == target {
                break;
            }
            h *= (target / n).sqrt();
        }
        at(best.1)
    }

    /// Area of one lattice cell (m²).
    pub fn cell_area(&self) -> f64 {
        let [t1, t2] = self.joint_angles();
        self.spacing[0] * self.spacing[1] / (t2 - t1).to_radians().sin().abs()
    }

    /// Direction angles of the two joint sets from the +x axis (degrees).
    fn joint_angles(&self) -> [f64; 2] {
        [self.dip_out, 180.0 - self.dip_in]
    }

    fn check(&self) -> Result<(), String> {
        let bad = |what: &str| Err(format!("jointed slope: {what}"));
        if !(self.height > 0.0 && self.height.is_finite()) {
            return bad("height must be positive");
        }
        if !(self.face_angle > 0.0 && self.face_angle <= 90.0) {
            return bad("face angle must be in (0, 90]");
        }
        if self.crest_width.is_nan() || self.crest_width < 0.0 {
            return bad("crest width must be >= 0");
        }
        if !(self.dip_out >= 0.0 && self.dip_out < 90.0 && self.dip_in > 0.0 && self.dip_in <= 90.0)
        {
            return bad("dips must be in [0, 90) (out of the slope) and (0, 90] (into it)");
        }
        if !(self.dip_out + self.dip_in > 5.0 && self.dip_out + self.dip_in < 175.0) {
            return bad("the two joint sets are nearly parallel");
        }
        if !(self.spacing.iter().all(|s| *s > 0.0 && s.is_finite())) {
            return bad("spacings must be positive");
        }
        if !(0.0..1.0).contains(&self.min_piece) {
            return bad("min_piece must be in [0, 1)");
        }
        let xc = self.height / self.face_angle.to_radians().tan();
        if xc + self.crest_width <= 1e-9 * self.height {
            return bad("the profile has no width (face angle 90° and no crest bench)");
        }
        Ok(())
    }
}

/// The blocks of a jointed slope.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeGeometry {
    /// The fixed base: ground below the slope and a back wall, counter-clockwise.
    pub base: Vec<Vec2>,
    /// The rock profile (toe, back bottom, back top, crest), counter-clockwise.
    pub profile: [Vec2; 4],
    /// The rock blocks, each convex and counter-clockwise.
    pub blocks: Vec<Vec<Vec2>>,
    /// The `crest` monitor: the centroid of the block nearest the crest.
    pub monitor: Vec2,
    /// Area of a lattice cell (m²).
    pub cell_area: f64,
}

/// The line n·p = c a block edge lies on: a profile edge or a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum LineId {
    /// 0 bottom, 1 back, 2 top, 3 face.
    Profile(u8),
    /// Joint k of set 1.
    Set1(i64),
    /// Joint j of set 2 in set-1 row `row` (row 0 for every row when the sets are persistent).
    Set2 { row: i64, j: i64 },
}

struct Lattice {
    n: [Vec2; 2],
    s: [f64; 2],
    o: [f64; 2],
    stagger: bool,
    profile: [(Vec2, f64); 4],
}

impl Lattice {
    fn line(&self, id: LineId) -> (Vec2, f64) {
        match id {
            LineId::Profile(e) => self.profile[e as usize],
            LineId::Set1(k) => (self.n[0], self.o[0] + k as f64 * self.s[0]),
            LineId::Set2 { row, j } => (
                self.n[1],
                self.o[1] + (j as f64 + self.shift(row)) * self.s[1],
            ),
        }
    }

    /// Set 2's offset in row `row`, in spacings.
    fn shift(&self, row: i64) -> f64 {
        if self.stagger && row.rem_euclid(2) == 1 {
            0.5
        } else {
            0.0
        }
    }

    fn row_key(&self, k: i64) -> i64 {
        if self.stagger {
            k
        } else {
            0
        }
    }

    /// The intersection of two lines, computed from the ordered pair (so every block sharing
    /// this vertex gets the same bits); exact on axis-parallel lines.
    fn meet(&self, a: LineId, b: LineId) -> Vec2 {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        let ((na, ca), (nb, cb)) = (self.line(a), self.line(b));
        let det = cross(na, nb);
        let mut p = [
            (ca * nb[1] - cb * na[1]) / det,
            (na[0] * cb - nb[0] * ca) / det,
        ];
        for (n, c) in [(na, ca), (nb, cb)] {
            if n[1] == 0.0 {
                p[0] = c / n[0];
            }
            if n[0] == 0.0 {
                p[1] = c / n[1];
            }
        }
        p
    }
}

/// A convex polygon: vertex i and the line of edge i → i+1.
type Poly = Vec<(Vec2, LineId)>;

/// Clip a convex polygon to the half-plane `sense · (n·p − c) ≤ 0` of line `id`.
fn clip(lat: &Lattice, poly: &Poly, id: LineId, sense: f64) -> Poly {
    let (n, c) = lat.line(id);
    let side = |p: Vec2| sense * (dot(n, p) - c);
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let (cur, e) = poly[i];
        let nxt = poly[(i + 1) % poly.len()].0;
        let (dc, dn) = (side(cur), side(nxt));
        if dc <= 0.0 {
            out.push((cur, e));
            if dn > 0.0 {
                out.push((lat.meet(e, id), id));
            }
        } else if dn <= 0.0 {
            out.push((lat.meet(e, id), e));
        }
    }
    out
}

fn area(p: &[Vec2]) -> f64 {
    0.5 * (0..p.len())
        .map(|i| cross(p[i], p[(i + 1) % p.len()]))
        .sum::<f64>()
}

fn min_edge(p: &[Vec2]) -> f64 {
    (0..p.len())
        .map(|i| {
            let d = sub(p[(i + 1) % p.len()], p[i]);
            dot(d, d).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Distance of x to the nearest integer.
fn frac_dist(x: f64) -> f64 {
    (x - x.round()).abs()
}

/// Offsets (in [0, s)) of a joint set, best first: those keeping every profile corner farthest
/// from the joints (for every shift in `shifts`, in spacings).
fn offset_candidates(proj: &[f64], s: f64, shifts: &[f64]) -> Vec<f64> {
    const N: usize = 64;
    let mut c: Vec<(f64, f64)> = (0..N)
        .map(|i| {
            let o = s * (i as f64 + 0.5) / N as f64;
            let score = proj
                .iter()
                .flat_map(|p| shifts.iter().map(move |sh| frac_dist((p - o) / s - sh)))
                .fold(f64::INFINITY, f64::min);
            (score, o)
        })
        .collect();
    c.sort_by(|a, b| b.0.total_cmp(&a.0));
    c.into_iter().take(8).map(|(_, o)| o).collect()
}

/// The blocks of a jointed slope (see the module docs).
pub fn slope_geometry(o: &SlopeOptions) -> Result<SlopeGeometry, String> {
    o.check()?;
    let h = o.height;
    let beta = o.face_angle.to_radians();
    let xc = if o.face_angle == 90.0 {
        0.0
    } else {
        h / beta.tan()
    };
    let xr = xc + o.crest_width;
    let (sb, cb) = beta.sin_cos();
    let profile_lines = [
        ([0.0, -1.0], 0.0),
        ([1.0, 0.0], xr),
        ([0.0, 1.0], h),
        ([-sb, cb], 0.0),
    ];
    let corners = [[0.0, 0.0], [xr, 0.0], [xr, h], [xc, h]];
    let normals = o.joint_angles().map(|t| {
        let (s, c) = t.to_radians().sin_cos();
        [-s, c]
    });
    let proj = |k: usize| corners.map(|p| dot(normals[k], p));
    let shifts: &[f64] = if o.stagger { &[0.0, 0.5] } else { &[0.0] };
    let cand1 = offset_candidates(&proj(0), o.spacing[0], &[0.0]);
    let cand2 = offset_candidates(&proj(1), o.spacing[1], shifts);
    let cell_area = o.cell_area();
    let min_len = 1e-3 * o.spacing[0].min(o.spacing[1]);
    for &o2 in &cand2 {
        for &o1 in &cand1 {
            let lat = Lattice {
                n: normals,
                s: o.spacing,
                o: [o1, o2],
                stagger: o.stagger,
                profile: profile_lines,
            };
            if let Some(blocks) = cut(&lat, cell_area * o.min_piece, min_len) {
                return Ok(finish(o, &lat, blocks, xr, xc, cell_area));
            }
        }
    }
    Err("jointed slope: no lattice offset avoids edges shorter than 1e-3 spacing".into())
}

/// Cut the profile by the lattice; `None` if some kept block has an edge shorter than `min_len`.
fn cut(lat: &Lattice, min_area: f64, min_len: f64) -> Option<Vec<Vec<Vec2>>> {
    let ids = [0u8, 1, 2, 3].map(LineId::Profile);
    let profile: Poly = (0..4)
        .map(|i| (lat.meet(ids[(i + 3) % 4], ids[i]), ids[i]))
        .collect();
    let range = |poly: &Poly, n: Vec2, o: f64, s: f64, shift: f64| {
        let (lo, hi) = poly
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), v| {
                let t = (dot(n, v.0) - o) / s - shift;
                (l.min(t), u.max(t))
            });
        (lo.floor() as i64, hi.ceil() as i64)
    };
    let mut blocks = Vec::new();
    let (k0, k1) = range(&profile, lat.n[0], lat.o[0], lat.s[0], 0.0);
    for k in k0..k1 {
        let strip = clip(lat, &profile, LineId::Set1(k), -1.0);
        let strip = clip(lat, &strip, LineId::Set1(k + 1), 1.0);
        if strip.len() < 3 {
            continue;
        }
        let row = lat.row_key(k);
        let (j0, j1) = range(&strip, lat.n[1], lat.o[1], lat.s[1], lat.shift(k));
        for j in j0..j1 {
            let cell = clip(lat, &strip, LineId::Set2 { row, j }, -1.0);
            let cell = clip(lat, &cell, LineId::Set2 { row, j: j + 1 }, 1.0);
            if cell.len() < 3 {
                continue;
            }
            let pts: Vec<Vec2> = cell.iter().map(|v| v.0).collect();
            if area(&pts) < min_area.max(f64::MIN_POSITIVE) {
                continue;
            }
            if min_edge(&pts) < min_len {
                return None;
            }
            blocks.push(pts);
        }
    }
    Some(blocks)
}

fn finish(
    o: &SlopeOptions,
    lat: &Lattice,
    blocks: Vec<Vec<Vec2>>,
    xr: f64,
    xc: f64,
    cell_area: f64,
) -> SlopeGeometry {
    let h = o.height;
    let toe_margin = 0.25 * h + 1.0;
    let (depth, back) = (1.0, 1.0);
    let ids = [0u8, 1, 2, 3].map(LineId::Profile);
    let profile = [0, 1, 2, 3].map(|i| lat.meet(ids[(i + 3) % 4], ids[i]));
    // Ground and back wall; its inner corner is the profile's back-bottom corner.
    let base = vec![
        [-toe_margin, -depth],
        [xr + back, -depth],
        [xr + back, h],
        profile[2],
        profile[1],
        [-toe_margin, 0.0],
    ];
    let centroid = |p: &[Vec2]| {
        let a = area(p);
        let (mut cx, mut cy) = (0.0, 0.0);
        for i in 0..p.len() {
            let (u, v) = (p[i], p[(i + 1) % p.len()]);
            let w = cross(u, v);
            cx += (u[0] + v[0]) * w;
            cy += (u[1] + v[1]) * w;
        }
        [cx / (6.0 * a), cy / (6.0 * a)]
    };
    let crest = [xc, h];
    let monitor = blocks
        .iter()
        .map(|b| centroid(b))
        .min_by(|a, b| {
            let d = |p: &Vec2| dot(sub(*p, crest), sub(*p, crest));
            d(a).total_cmp(&d(b))
        })
        .unwrap_or([0.5 * (xc + xr), 0.5 * h]);
    SlopeGeometry {
        base,
        profile,
        blocks,
        monitor,
        cell_area,
    }
}

/// The slope as a model file (TOML text `nmm run` reads). Block names: `base`, then `r{i}`.
/// Coordinates are written exactly (shortest round-trip form).
pub fn jointed_slope_model(o: &SlopeOptions) -> Result<String, String> {
    let g = slope_geometry(o)?;
    let mode = match o.mode {
        Mode::Dynamic => "dynamic",
        Mode::Static => "static",
    };
    let poly = |p: &[Vec2]| {
        let v: Vec<String> = p
            .iter()
            .map(|q| format!("[{}, {}]", fmt_exact(q[0]), fmt_exact(q[1])))
            .collect();
        format!("[{}]", v.join(", "))
    };
    let mut s = format!(
        r#"# Jointed rock slope (nmm::generate::jointed_slope_model): {blocks} blocks, H = {h} m,
# face {beta} deg, joint sets dipping {d1} deg out of and {d2} deg into the slope, spacing {s1} / {s2} m{stagger}
[analysis]
mode = "{mode}"
dt = {dt}
steps = {steps}
gravity = [0.0, -9.81]
friction = "return-mapping"
output_every = 1000000

[cover]
size = {cover}

[[material]]
name = "rock"
density = {SLOPE_DENSITY:?}
young = {SLOPE_YOUNG:e}
poisson = {SLOPE_POISSON:?}

[[interface]]
friction_angle = {SLOPE_FRICTION_ANGLE:?}
normal_penalty = {SLOPE_PENALTY:e}
shear_penalty = {SLOPE_PENALTY:e}

[[block]]
name = "base"
material = "rock"
fixed = true
vertices = {base}
"#,
        blocks = g.blocks.len(),
        h = fmt_exact(o.height),
        beta = o.face_angle,
        d1 = o.dip_out,
        d2 = o.dip_in,
        s1 = o.spacing[0],
        s2 = o.spacing[1],
        stagger = if o.stagger { ", staggered" } else { "" },
        dt = fmt_exact(o.dt),
        steps = o.steps,
        cover = fmt_exact(o.cover),
        base = poly(&g.base),
    );
    for (i, b) in g.blocks.iter().enumerate() {
        s.push_str(&format!(
            "\n[[block]]\nname = \"r{i}\"\nmaterial = \"rock\"\nvertices = {}\n",
            poly(b)
        ));
    }
    s.push_str(&format!(
        "\n[[monitor]]\nname = \"crest\"\npoint = [{}, {}]\n",
        fmt_exact(g.monitor[0]),
        fmt_exact(g.monitor[1])
    ));
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::polygon::{point_in_polygon, Location};
    use crate::model::parse_model;
    use std::collections::HashMap;
    use std::path::Path;

    fn is_convex_ccw(p: &[Vec2]) -> bool {
        let n = p.len();
        n >= 3
            && (0..n).all(|i| {
                let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
                cross(sub(b, a), sub(c, b)) > 0.0
            })
    }

    /// Checks shared by every variant; returns vertex multiplicities of interior vertices.
    fn check_geometry(o: &SlopeOptions, g: &SlopeGeometry) -> Vec<usize> {
        let profile_area = area(&g.profile);
        let mut total = 0.0;
        for b in &g.blocks {
            assert!(is_convex_ccw(b), "{b:?}");
            let a = area(b);
            assert!(a >= o.min_piece * g.cell_area * (1.0 - 1e-12));
            assert!(a <= g.cell_area * (1.0 + 1e-9));
            assert!(min_edge(b) >= 1e-3 * o.spacing[0].min(o.spacing[1]));
            for &v in b {
                let tol = 1e-9 * o.height;
                assert_ne!(point_in_polygon(&g.profile, v, tol), Location::Outside);
            }
            total += a;
        }
        // Blocks fill the profile but for the left-out fragments (a band of cells along the
        // boundary at most), and never more than it.
        assert!(total <= profile_area * (1.0 + 1e-9));
        let perimeter: f64 = (0..4)
            .map(|i| crate::geometry::dist(g.profile[i], g.profile[(i + 1) % 4]))
            .sum();
        let cell_size = g.cell_area.sqrt();
        assert!(profile_area - total <= o.min_piece * perimeter * cell_size * 3.0 + 1e-9);
        // Vertices of blocks well inside the profile, by bits.
        let mut count: HashMap<[u64; 2], usize> = HashMap::new();
        for b in &g.blocks {
            for v in b {
                let inner = (0..4).all(|i| {
                    crate::geometry::polygon::point_segment_distance(
                        *v,
                        g.profile[i],
                        g.profile[(i + 1) % 4],
                    ) > 3.0 * o.spacing[0].max(o.spacing[1])
                });
                if inner {
                    *count.entry([v[0].to_bits(), v[1].to_bits()]).or_default() += 1;
                }
            }
        }
        count.into_values().collect()
    }

    #[test]
    fn persistent_sets_share_every_lattice_node_bit_for_bit() {
        for n in [100, 500] {
            let o = SlopeOptions::with_blocks(n);
            let g = slope_geometry(&o).unwrap();
            let k = g.blocks.len() as f64;
            assert!(
                (k / n as f64 - 1.0).abs() < 0.05,
                "{n} blocks asked, {k} made"
            );
            let mult = check_geometry(&o, &g);
            assert!(!mult.is_empty());
            // A node of the lattice is a corner of the four cells around it.
            assert!(mult.iter().all(|&m| m == 4), "{mult:?}");
            let text = jointed_slope_model(&o).unwrap();
            let m = parse_model(&text, Path::new(".")).expect("the slope parses");
            assert_eq!(m.blocks.len(), g.blocks.len() + 1);
            assert!(m.blocks[0].fixed && m.blocks[1..].iter().all(|b| !b.fixed));
            assert_eq!(m.cover_size, 0.5);
            // Written exactly: the parsed vertices are the generated ones (up to orientation,
            // which is already counter-clockwise).
            for (b, p) in m.blocks[1..].iter().zip(&g.blocks) {
                assert_eq!(&b.vertices, p);
            }
        }
    }

    #[test]
    fn staggered_and_other_angles_parse() {
        let variants = [
            SlopeOptions {
                stagger: true,
                ..SlopeOptions::with_blocks(300)
            },
            SlopeOptions {
                face_angle: 45.0,
                dip_out: 10.0,
                dip_in: 80.0,
                spacing: [0.4, 0.7],
                ..SlopeOptions::new(6.0)
            },
            SlopeOptions {
                face_angle: 90.0,
                dip_out: 0.0,
                dip_in: 90.0,
                ..SlopeOptions::new(4.0)
            },
        ];
        for o in variants {
            let g = slope_geometry(&o).unwrap();
            let mult = check_geometry(&o, &g);
            if o.stagger {
                // A corner of a row's cell lies on the edge of a cell of the next row: two
                // blocks share it as a vertex.
                assert!(!mult.is_empty() && mult.iter().all(|&m| m == 2), "{mult:?}");
            }
            let m = parse_model(&jointed_slope_model(&o).unwrap(), Path::new("."))
                .unwrap_or_else(|e| panic!("{o:?}: {e}"));
            assert_eq!(m.blocks.len(), g.blocks.len() + 1);
        }
    }

    #[test]
    fn block_counts_follow_the_target_and_bad_options_are_refused() {
        for n in [50, 150, 1000] {
            let g = slope_geometry(&SlopeOptions::with_blocks(n)).unwrap();
            let k = g.blocks.len() as f64;
            assert!(
                (k / n as f64 - 1.0).abs() < 0.05,
                "{n} blocks asked, {k} made"
            );
        }
        let bad = [
            SlopeOptions {
                height: 0.0,
                ..SlopeOptions::new(1.0)
            },
            SlopeOptions {
                dip_out: 1.0,
                dip_in: 2.0,
                ..SlopeOptions::new(5.0)
            },
            SlopeOptions {
                min_piece: 1.0,
                ..SlopeOptions::new(5.0)
            },
        ];
        for o in bad {
            assert!(slope_geometry(&o).is_err(), "{o:?}");
        }
    }
}
