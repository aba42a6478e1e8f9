//! The running-bond brick wall of the peer comparison with ntdda (the DDA code): `nx` bricks
//! of 0.4 × 0.2 m per course, `ny` courses, odd courses shifted by half a brick (so every
//! block is a whole brick and the wall ends are staggered), on a fixed base block 0.5 m deep
//! reaching from x = −0.5 to x = 0.4 `nx` + 0.7; E 7 GPa, ν 0.33, unit weight 22 kN/m³,
//! φ 30°, normal and shear penalties 1e10 N/m, gravity; a monitor `top` at the centre of the
//! middle brick of the top course.

use super::{fmt_g9, fmt_poly};
use crate::geometry::Vec2;
use crate::model::Mode;

/// Brick length (m).
pub const WALL_BRICK_LENGTH: f64 = 0.4;
/// Brick height (m).
pub const WALL_BRICK_HEIGHT: f64 = 0.2;
/// Unit weight of the bricks (N/m³); density = unit weight / 9.81.
pub const WALL_UNIT_WEIGHT: f64 = 22_000.0;
/// Young's modulus (Pa).
pub const WALL_YOUNG: f64 = 7.0e9;
/// Poisson's ratio.
pub const WALL_POISSON: f64 = 0.33;
/// Friction angle of every joint (degrees).
pub const WALL_FRICTION_ANGLE: f64 = 30.0;
/// Normal and shear contact penalty (N/m).
pub const WALL_PENALTY: f64 = 1.0e10;
/// Depth of the fixed base block below the first course (m).
pub const WALL_BASE_DEPTH: f64 = 0.5;

/// A brick wall model: geometry `nx × ny` and the analysis settings.
#[derive(Debug, Clone, PartialEq)]
pub struct WallOptions {
    /// Bricks per course.
    pub nx: usize,
    /// Courses.
    pub ny: usize,
    pub steps: usize,
    /// Time step (s).
    pub dt: f64,
    /// Mathematical mesh size h (m).
    pub cover: f64,
    pub mode: Mode,
    /// Half bricks (closers) at both ends of the odd courses, as masonry walls are laid,
    /// so that every course ends flush with the wall's ends. Without them (the peer's
    /// geometry) the odd courses overhang the wall's right end by half a brick and the
    /// top course's end brick has its centre of mass exactly above the edge of the brick
    /// below: a neutral equilibrium that topples under any perturbation.
    pub closers: bool,
}

impl WallOptions {
    /// The peer comparison's settings: 20 steps of 1 ms, dynamic, cover 0.2 m.
    pub fn new(nx: usize, ny: usize) -> Self {
        WallOptions {
            nx,
            ny,
            steps: 20,
            dt: 0.001,
            cover: 0.2,
            mode: Mode::Dynamic,
            closers: false,
        }
    }
}

/// The geometry of a wall: the fixed base and the bricks, course by course from the bottom
/// (brick `k * nx + i` is brick `i` of course `k`), each counter-clockwise from its lower
/// left corner.
#[derive(Debug, Clone, PartialEq)]
pub struct WallGeometry {
    pub base: [Vec2; 4],
    pub bricks: Vec<[Vec2; 4]>,
    /// (course, index within the course) of each brick.
    pub places: Vec<(usize, usize)>,
    /// The `top` monitor: centre of brick `nx / 2` of the top course.
    pub monitor: Vec2,
}

/// Horizontal offset of course `k` (odd courses shifted by half a brick).
pub fn wall_course_offset(k: usize) -> f64 {
    if k % 2 == 0 {
        0.0
    } else {
        WALL_BRICK_LENGTH / 2.0
    }
}

/// The base block's extent in x: from −0.5 to W + L/2 + 0.5 (W = nx L, L the brick length).
pub fn wall_base_extent(nx: usize) -> (f64, f64) {
    let w = nx as f64 * WALL_BRICK_LENGTH;
    (-0.5, w + WALL_BRICK_LENGTH / 2.0 + 0.5)
}

/// The wall's blocks (see [`WallGeometry`]), the peer's geometry (no closers).
pub fn wall_geometry(nx: usize, ny: usize) -> WallGeometry {
    wall_geometry_with(nx, ny, false)
}

/// The wall's blocks, with or without closers (see [`WallOptions::closers`]).
pub fn wall_geometry_with(nx: usize, ny: usize, closers: bool) -> WallGeometry {
    let (bw, bh) = (WALL_BRICK_LENGTH, WALL_BRICK_HEIGHT);
    let (xl, xr) = wall_base_extent(nx);
    let d = WALL_BASE_DEPTH;
    let base = [[xl, -d], [xr, -d], [xr, 0.0], [xl, 0.0]];
    let mut bricks = Vec::with_capacity(nx * ny);
    let mut places = Vec::with_capacity(nx * ny);
    for k in 0..ny {
        let off = wall_course_offset(k);
        let (y0, y1) = (k as f64 * bh, (k + 1) as f64 * bh);
        // the joints of the course, from its left end to its right
        let mut xs: Vec<f64> = (0..=nx).map(|i| off + i as f64 * bw).collect();
        if closers && off > 0.0 {
            xs.insert(0, 0.0);
            *xs.last_mut().unwrap() = nx as f64 * bw;
        }
        for (i, w) in xs.windows(2).enumerate() {
            let (x0, x1) = (w[0], w[1]);
            bricks.push([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]);
            places.push((k, i));
        }
    }
    let top = ny.saturating_sub(1);
    let monitor = [
        wall_course_offset(top) + (nx / 2) as f64 * bw + bw / 2.0,
        top as f64 * bh + bh / 2.0,
    ];
    WallGeometry {
        base,
        bricks,
        places,
        monitor,
    }
}

/// The wall as a model file (TOML text `nmm run` reads). Block names: `base`, then
/// `b{course}_{index}`.
///
/// # Panics
/// If `nx` or `ny` is zero.
pub fn brick_wall_model(o: &WallOptions) -> String {
    assert!(o.nx > 0 && o.ny > 0, "a wall needs at least one brick");
    let g = wall_geometry_with(o.nx, o.ny, o.closers);
    let mode = match o.mode {
        Mode::Dynamic => "dynamic",
        Mode::Static => "static",
    };
    let mut s = format!(
        r#"# Running-bond brick wall {nx} x {ny} (nmm::generate::brick_wall_model)
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
name = "brick"
density = {density:.6}
young = 7.0e9
poisson = 0.33

[[interface]]
friction_angle = 30.0
normal_penalty = 1.0e10
shear_penalty = 1.0e10

[[block]]
name = "base"
material = "brick"
fixed = true
vertices = {base}
"#,
        nx = o.nx,
        ny = o.ny,
        dt = o.dt,
        steps = o.steps,
        cover = o.cover,
        density = WALL_UNIT_WEIGHT / 9.81,
        base = fmt_poly(&g.base),
    );
    for (b, &(k, i)) in g.bricks.iter().zip(&g.places) {
        s.push_str(&format!(
            "\n[[block]]\nname = \"b{k}_{i}\"\nmaterial = \"brick\"\nvertices = {}\n",
            fmt_poly(b)
        ));
    }
    s.push_str(&format!(
        "\n[[monitor]]\nname = \"top\"\npoint = [{}, {}]\n",
        fmt_g9(g.monitor[0]),
        fmt_g9(g.monitor[1])
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{parse_model, Mode};
    use std::path::Path;

    #[test]
    fn wall_model_parses_and_has_the_peer_geometry() {
        for (nx, ny) in [(1, 1), (3, 2), (10, 10), (7, 12)] {
            let mut o = WallOptions::new(nx, ny);
            o.steps = 7;
            o.dt = 0.002;
            o.cover = 0.15;
            o.mode = Mode::Static;
            let m = parse_model(&brick_wall_model(&o), Path::new(".")).expect("parses");
            assert_eq!(m.blocks.len(), nx * ny + 1);
            assert_eq!(m.analysis.steps, 7);
            assert_eq!(m.analysis.dt, 0.002);
            assert_eq!(m.analysis.mode, Mode::Static);
            assert_eq!(m.analysis.gravity, [0.0, -9.81]);
            assert_eq!(m.cover_size, 0.15);
            let mat = &m.materials[0];
            assert!((mat.density * 9.81 - 22_000.0).abs() < 1e-3);
            assert_eq!((mat.young, mat.poisson), (7.0e9, 0.33));
            assert_eq!(m.interfaces.len(), 1);
            let i = &m.interfaces[0];
            assert_eq!(i.scope, crate::model::InterfaceScope::Default);
            assert_eq!(i.friction_angle, 30.0);
            assert_eq!((i.normal_penalty, i.shear_penalty), (1e10, 1e10));

            // The base: fixed, 0.5 m deep, from x = -0.5 to W + 0.7.
            let w = nx as f64 * 0.4;
            let base = &m.blocks[0];
            assert!(base.fixed && m.blocks[1..].iter().all(|b| !b.fixed));
            let bx = crate::geometry::Aabb::of_points(&base.vertices);
            for (a, b) in [(bx.min, [-0.5, -0.5]), (bx.max, [w + 0.7, 0.0])] {
                assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
            }
            // Running bond: brick i of course k spans [off + 0.4 i, off + 0.4 (i + 1)] ×
            // [0.2 k, 0.2 (k + 1)], off = 0.2 on odd courses.
            for k in 0..ny {
                for i in 0..nx {
                    let b = &m.blocks[1 + k * nx + i];
                    assert_eq!(b.name, format!("b{k}_{i}"));
                    assert_eq!(b.vertices.len(), 4);
                    let bb = crate::geometry::Aabb::of_points(&b.vertices);
                    let x0 = if k % 2 == 1 { 0.2 } else { 0.0 } + 0.4 * i as f64;
                    let want = [[x0, 0.2 * k as f64], [x0 + 0.4, 0.2 * (k + 1) as f64]];
                    for (got, want) in [(bb.min, want[0]), (bb.max, want[1])] {
                        assert!(
                            (got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9,
                            "brick {k}_{i}: {got:?} != {want:?}"
                        );
                    }
                    let area = crate::geometry::polygon::signed_area(&b.vertices);
                    assert!((area - 0.08).abs() < 1e-9);
                }
            }
            // The monitor sits in the middle brick of the top course.
            let top = ny - 1;
            let want = [
                if top % 2 == 1 { 0.2 } else { 0.0 } + 0.4 * (nx / 2) as f64 + 0.2,
                0.2 * top as f64 + 0.1,
            ];
            let crate::model::MonitorKind::Point { p, .. } = m.monitors[0].kind else {
                panic!("a point monitor")
            };
            assert!((p[0] - want[0]).abs() < 1e-9 && (p[1] - want[1]).abs() < 1e-9);
        }
    }

    #[test]
    fn coordinates_are_written_as_python_g9() {
        for (x, s) in [
            (0.0, "0"),
            (1.2000000000000002, "1.2"),
            (0.30000000000000004, "0.3"),
            (-0.5, "-0.5"),
            (40.9, "40.9"),
            (0.0001, "0.0001"),
            (0.00001, "1e-05"),
            (123456789.0, "123456789"),
            (1234567891.0, "1.23456789e+09"),
            (9.9999999999, "10"),
            (2.0 / 3.0, "0.666666667"),
        ] {
            assert_eq!(super::super::fmt_g9(x), s, "{x}");
        }
    }
}
