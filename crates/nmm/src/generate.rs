//! Model generators (TOML text that `nmm run` reads) for benchmarks, scaling studies and tests:
//! a seeded elastic block ([`elastic_block`]), the running-bond brick wall of the peer
//! comparison with ntdda ([`brick_wall_model`]) and a jointed rock slope
//! ([`jointed_slope_model`]).

mod arch;
mod slope;
mod wall;

pub use arch::{arch_model, arch_voussoirs, stack_model, ArchOptions, ARCH_MIN_THICKNESS_RATIO};
pub use slope::{
    jointed_slope_model, slope_geometry, SlopeGeometry, SlopeOptions, SLOPE_DENSITY,
    SLOPE_FRICTION_ANGLE, SLOPE_PENALTY, SLOPE_POISSON, SLOPE_YOUNG,
};
pub use wall::{
    brick_wall_model, wall_base_extent, wall_course_offset, wall_geometry, wall_geometry_with,
    WallGeometry, WallOptions, WALL_BASE_DEPTH, WALL_BRICK_HEIGHT, WALL_BRICK_LENGTH,
    WALL_FRICTION_ANGLE, WALL_PENALTY, WALL_POISSON, WALL_UNIT_WEIGHT, WALL_YOUNG,
};

use crate::geometry::Vec2;

/// `x` as C's `%.9g` (Python's `f"{x:.9g}"`), the brick wall's coordinates.
pub fn fmt_g9(x: f64) -> String {
    fmt_g(x, 9)
}

/// `x` as C's `%.{p}g`: `p` significant digits, trailing zeros dropped, exponent form
/// (`e+09`, `e-05`) below 1e-4 and from 10^p.
pub fn fmt_g(x: f64, p: usize) -> String {
    let p = p.max(1);
    if x == 0.0 || !x.is_finite() {
        return if x == 0.0 { "0".into() } else { x.to_string() };
    }
    let e = format!("{x:.*e}", p - 1);
    let (mant, exp) = e.split_once('e').expect("exponent form");
    let exp: i32 = exp.parse().expect("exponent");
    let strip = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if (-4..p as i32).contains(&exp) {
        strip(&format!("{x:.*}", (p as i32 - 1 - exp) as usize))
    } else {
        format!(
            "{}e{}{:02}",
            strip(mant),
            if exp < 0 { '-' } else { '+' },
            exp.abs()
        )
    }
}

/// `x` exactly (shortest round-trip form, a TOML float), −0 written as 0.
pub fn fmt_exact(x: f64) -> String {
    format!("{:?}", x + 0.0)
}

/// A polygon as a TOML array with [`fmt_g9`] coordinates.
pub(crate) fn fmt_poly(p: &[Vec2]) -> String {
    let v: Vec<String> = p
        .iter()
        .map(|q| format!("[{}, {}]", fmt_g9(q[0]), fmt_g9(q[1])))
        .collect();
    format!("[{}]", v.join(", "))
}

/// xorshift64*: a tiny reproducible generator (no dependency needed for a few numbers).
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// One elastic block with about `target` unknowns: a 4 m × 1 m rectangle with a seeded
/// rotation (±5°) and offset relative to the mesh (so it has cut cells), clamped along
/// its base, under gravity, static mode.
pub fn elastic_block(target: usize, seed: u64) -> String {
    let mut rng = Rng::new(seed);
    let mut rnd = || rng.next_f64();
    let (w, ht) = (4.0, 1.0);
    // unknowns ≈ 2 × covers ≈ 2 × (w/h)(ht/h) for right-triangle meshes
    let h = (2.0 * w * ht / target as f64).sqrt();
    let angle: f64 = (rnd() - 0.5) * 10.0;
    let (ox, oy) = (rnd() * h, rnd() * h);
    let (sn, cs) = angle.to_radians().sin_cos();
    let p = |x: f64, y: f64| [ox + cs * x - sn * y, oy + sn * x + cs * y];
    let v = [p(0.0, 0.0), p(w, 0.0), p(w, ht), p(0.0, ht)];
    format!(
        r#"
[analysis]
mode = "static"
dt = 1.0
steps = 1
gravity = [0.0, -9.81]
[cover]
size = {h}
[[material]]
name = "rock"
density = 2500.0
young = 1.0e10
poisson = 0.25
[[block]]
name = "b"
material = "rock"
vertices = [[{}, {}], [{}, {}], [{}, {}], [{}, {}]]
[[constraint]]
block = "b"
edge = [[{}, {}], [{}, {}]]
ux = 0.0
uy = 0.0
"#,
        v[0][0],
        v[0][1],
        v[1][0],
        v[1][1],
        v[2][0],
        v[2][1],
        v[3][0],
        v[3][1],
        v[0][0],
        v[0][1],
        v[1][0],
        v[1][1]
    )
}
