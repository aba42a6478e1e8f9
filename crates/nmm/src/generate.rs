//! Seeded generators of models (TOML text) for benchmarks, scaling studies and tests.

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
