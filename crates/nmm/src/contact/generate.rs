//! Seeded generators of contact geometry for benchmarks and tests.
//!
//! [`brick_wall`] lays out a running-bond wall: courses of rectangular bricks
//! (length `BRICK_LENGTH`, height `BRICK_HEIGHT`, metres), every other course
//! shifted by half a brick, neighbours separated by joints of random width in
//! `[0.5, 1.5] × 1e-6 × BRICK_LENGTH` (touching to the eye, never overlapping).
//! Each brick is a closed CCW polyline: its 4 corners plus 1–3 refined points
//! at random positions on every edge, as the boundary of a block cut by a
//! cover mesh would be. The same `(n, seed)` always gives the same wall.

use crate::geometry::Vec2;

/// Brick length (m).
pub const BRICK_LENGTH: f64 = 0.2;
/// Brick height (m).
pub const BRICK_HEIGHT: f64 = 0.1;
/// Mean joint width relative to the brick length.
pub const JOINT: f64 = 1e-6;

/// SplitMix64: a small, well-mixed, seeded generator (not cryptographic).
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A running-bond wall of `n` bricks (see the module docs), as CCW polylines.
/// Bricks per course: `⌈√(n·H/L)⌉`, so the wall is about square; the last
/// course may be partial.
pub fn brick_wall(n: usize, seed: u64) -> Vec<Vec<Vec2>> {
    let mut rng = SplitMix64::new(seed);
    let per_course = ((n as f64 * BRICK_HEIGHT / BRICK_LENGTH).sqrt().ceil() as usize).max(1);
    let joint = |rng: &mut SplitMix64| JOINT * BRICK_LENGTH * (0.5 + rng.next_f64());
    let mut bricks = Vec::with_capacity(n);
    let mut y = 0.0;
    let mut course = 0;
    while bricks.len() < n {
        let mut x = if course % 2 == 1 {
            0.5 * BRICK_LENGTH
        } else {
            0.0
        };
        for _ in 0..per_course.min(n - bricks.len()) {
            bricks.push(refined_rectangle(
                [x, y],
                [x + BRICK_LENGTH, y + BRICK_HEIGHT],
                &mut rng,
            ));
            x += BRICK_LENGTH + joint(&mut rng);
        }
        y += BRICK_HEIGHT + joint(&mut rng);
        course += 1;
    }
    bricks
}

/// Rectangle `[lo, hi]` as a CCW polyline with 1–3 random points on each edge.
fn refined_rectangle(lo: Vec2, hi: Vec2, rng: &mut SplitMix64) -> Vec<Vec2> {
    let corners = [lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
    let mut poly = Vec::with_capacity(16);
    for e in 0..4 {
        let (p, q) = (corners[e], corners[(e + 1) % 4]);
        poly.push(p);
        let k = 1 + (rng.next_u64() % 3) as usize;
        let mut ts: Vec<f64> = (0..k).map(|_| 0.05 + 0.9 * rng.next_f64()).collect();
        ts.sort_by(f64::total_cmp);
        for t in ts {
            poly.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Aabb;

    fn signed_area(p: &[Vec2]) -> f64 {
        (0..p.len())
            .map(|i| crate::geometry::cross(p[i], p[(i + 1) % p.len()]))
            .sum::<f64>()
            / 2.0
    }

    #[test]
    fn wall_is_seeded_ccw_and_joints_are_open() {
        let w = brick_wall(200, 7);
        assert_eq!(w.len(), 200);
        assert_eq!(w, brick_wall(200, 7));
        assert_ne!(w, brick_wall(200, 8));
        for b in &w {
            assert!((8..=16).contains(&b.len()));
            assert!((signed_area(b) - BRICK_LENGTH * BRICK_HEIGHT).abs() < 1e-12);
        }
        // No two bricks overlap; neighbours are within 1.5e-6 L.
        let boxes: Vec<Aabb> = w.iter().map(|b| Aabb::of_points(b)).collect();
        let mut touching = 0;
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                let (a, b) = (&boxes[i], &boxes[j]);
                let ox = a.max[0].min(b.max[0]) - a.min[0].max(b.min[0]);
                let oy = a.max[1].min(b.max[1]) - a.min[1].max(b.min[1]);
                assert!(ox <= 0.0 || oy <= 0.0, "bricks {i} and {j} overlap");
                if a.inflate(2e-6 * BRICK_LENGTH).overlaps(b) {
                    touching += 1;
                }
            }
        }
        // Running bond, 20 courses of 10: 9 head joints per course, and 19 bricks
        // pairs across each of the 19 bed joints (every brick spans two above it).
        assert_eq!(touching, 20 * 9 + 19 * 19);
    }
}
