//! Broad phase: which pairs of axis-aligned boxes overlap.
//!
//! [`sweep_and_prune`] sorts the boxes on `min.x` and sweeps along x. The boxes
//! whose x-interval contains the sweep position form the *active set*, kept
//! ordered on `min.y` (a `BTreeSet`), and expired in `max.x` order. A new box
//! `[x₀,x₁]×[y₀,y₁]` is tested only against active boxes with
//! `min.y ∈ [y₀ − H, y₁]`, `H` the largest box height: every active box that
//! overlaps it in y is among them. Cost: `O(n log n + k + c)`, `k` the number
//! of overlapping pairs and `c` the number of active boxes inside that y-window
//! that do not overlap, which is `O(k)` when box heights are comparable (blocks
//! of one model) and never worse than a plain x-sweep.
//!
//! Overlap is closed (touching boxes overlap), exactly as [`Aabb::overlaps`].
//! Boxes with a NaN coordinate or `min > max` (e.g. [`Aabb::empty`]) overlap
//! nothing. Callers inflate boxes by half the contact search distance (or by
//! the search distance on one side) before calling.

use crate::geometry::Aabb;
use std::collections::BTreeSet;

/// A total, order-preserving integer key for a finite `f64`.
#[inline]
fn key(x: f64) -> i64 {
    let b = (x + 0.0).to_bits() as i64; // −0.0 → +0.0
    b ^ (((b >> 63) as u64) >> 1) as i64
}

fn is_valid(b: &Aabb) -> bool {
    b.min[0] <= b.max[0] && b.min[1] <= b.max[1]
}

/// All pairs `(i, j)`, `i < j`, of boxes that overlap, sorted.
pub fn sweep_and_prune(boxes: &[Aabb]) -> Vec<(usize, usize)> {
    let mut by_min: Vec<usize> = (0..boxes.len()).filter(|&i| is_valid(&boxes[i])).collect();
    if by_min.len() < 2 {
        return Vec::new();
    }
    let mut by_max = by_min.clone();
    by_min.sort_unstable_by(|&a, &b| boxes[a].min[0].total_cmp(&boxes[b].min[0]));
    by_max.sort_unstable_by(|&a, &b| boxes[a].max[0].total_cmp(&boxes[b].max[0]));
    let h_max = by_min
        .iter()
        .map(|&i| boxes[i].max[1] - boxes[i].min[1])
        .fold(0.0, f64::max);

    let mut active: BTreeSet<(i64, usize)> = BTreeSet::new();
    let mut expire = 0;
    let mut pairs = Vec::new();
    for &i in &by_min {
        let b = &boxes[i];
        // Expire boxes that end strictly before this one starts (they were
        // inserted: min.x ≤ max.x < b.min.x).
        while expire < by_max.len() && boxes[by_max[expire]].max[0] < b.min[0] {
            let e = by_max[expire];
            active.remove(&(key(boxes[e].min[1]), e));
            expire += 1;
        }
        // Slack for the rounding of `min.y + height − H`.
        let slack = 4.0 * f64::EPSILON * (b.min[1].abs() + h_max);
        let lo = (key(b.min[1] - h_max - slack), 0);
        let hi = (key(b.max[1]), usize::MAX);
        for &(_, j) in active.range(lo..=hi) {
            if b.overlaps(&boxes[j]) {
                pairs.push(if i < j { (i, j) } else { (j, i) });
            }
        }
        active.insert((key(b.min[1]), i));
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn brute(boxes: &[Aabb]) -> Vec<(usize, usize)> {
        let mut v = Vec::new();
        for i in 0..boxes.len() {
            for j in i + 1..boxes.len() {
                if is_valid(&boxes[i]) && is_valid(&boxes[j]) && boxes[i].overlaps(&boxes[j]) {
                    v.push((i, j));
                }
            }
        }
        v
    }

    #[test]
    fn key_preserves_order() {
        let xs = [-1e300, -2.5, -1e-300, -0.0, 0.0, 1e-300, 3.0, 1e300];
        for w in xs.windows(2) {
            assert!(key(w[0]) <= key(w[1]), "{} {}", w[0], w[1]);
        }
    }

    #[test]
    fn touching_and_invalid_boxes() {
        let b = |x0: f64, y0: f64, x1: f64, y1: f64| Aabb {
            min: [x0, y0],
            max: [x1, y1],
        };
        let boxes = [
            b(0., 0., 1., 1.),
            b(1., 1., 2., 2.),
            b(2.0001, 0., 3., 1.),
            Aabb::empty(),
            b(0.5, 0.5, f64::NAN, 0.7),
        ];
        assert_eq!(sweep_and_prune(&boxes), vec![(0, 1)]);
        assert!(sweep_and_prune(&[]).is_empty());
    }

    fn arb_box() -> impl Strategy<Value = Aabb> {
        (-50.0..50.0f64, -50.0..50.0f64, 0.0..8.0f64, 0.0..8.0f64).prop_map(|(x, y, w, h)| Aabb {
            min: [x, y],
            max: [x + w, y + h],
        })
    }

    proptest! {
        #[test]
        fn matches_brute_force(boxes in prop::collection::vec(arb_box(), 0..120)) {
            prop_assert_eq!(sweep_and_prune(&boxes), brute(&boxes));
        }

        #[test]
        fn matches_brute_force_on_a_lattice(n in 1usize..60, seed in 0u64..1000) {
            // Many exact coincidences of coordinates (touching boxes).
            let boxes: Vec<Aabb> = (0..n)
                .map(|k| {
                    let s = (k as u64).wrapping_mul(2654435761).wrapping_add(seed);
                    let x = (s % 7) as f64;
                    let y = ((s / 7) % 5) as f64;
                    Aabb { min: [x, y], max: [x + 1.0 + (s % 2) as f64, y + 1.0] }
                })
                .collect();
            prop_assert_eq!(sweep_and_prune(&boxes), brute(&boxes));
        }
    }
}
