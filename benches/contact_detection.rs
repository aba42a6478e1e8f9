//! Contact detection on a running-bond brick wall (`nmm::contact::brick_wall`,
//! seeded): N = 1e3, 1e4, 1e5 bricks with 1–3 refined points per brick edge and
//! joints of ~1e-6 brick length. Times the broad phase alone (boxes + sweep and
//! prune) and broad + narrow phase (vertex–edge detection both ways over every
//! candidate pair). The search distance is 1e-3 brick length.
//!
//! Run: `cargo bench --bench contact_detection`.
//!
//! Measured on the shared 2-core development machine (medians, under load):
//! broad 0.59 ms / 6.4 ms / 95 ms and broad+narrow 12 ms / 147 ms / 1.34 s
//! for N = 1e3 / 1e4 / 1e5 (about 12 000 / 120 000 / 1.2 M vertices,
//! 2.9 k / 30 k / 299 k candidate pairs): close to linear growth.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nmm::contact::generate::BRICK_LENGTH;
use nmm::contact::{brick_wall, corner_flags, sweep_and_prune, vertex_edge_contacts};
use nmm::geometry::{Aabb, Vec2};
use std::hint::black_box;
use std::time::Duration;

const SEARCH: f64 = 1e-3 * BRICK_LENGTH;

fn boxes(wall: &[Vec<Vec2>]) -> Vec<Aabb> {
    wall.iter()
        .map(|b| Aabb::of_points(b).inflate(0.5 * SEARCH))
        .collect()
}

/// Broad + narrow phase; returns (pairs, vertex–edge contacts).
fn detect(wall: &[Vec<Vec2>], corners: &[Vec<bool>]) -> (usize, usize) {
    let pairs = sweep_and_prune(&boxes(wall));
    let mut contacts = 0;
    for &(i, j) in &pairs {
        contacts += vertex_edge_contacts(&wall[i], &wall[j], SEARCH, &corners[i]).len();
        contacts += vertex_edge_contacts(&wall[j], &wall[i], SEARCH, &corners[j]).len();
    }
    (pairs.len(), contacts)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact_detection");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for n in [1_000usize, 10_000, 100_000] {
        let wall = brick_wall(n, 42);
        let corners: Vec<Vec<bool>> = wall.iter().map(|b| corner_flags(b, 1e-6)).collect();
        let (pairs, contacts) = detect(&wall, &corners);
        let vertices: usize = wall.iter().map(Vec::len).sum();
        eprintln!("N = {n}: {vertices} vertices, {pairs} candidate pairs, {contacts} vertex-edge contacts");
        group.bench_with_input(BenchmarkId::new("broad", n), &wall, |b, w| {
            b.iter(|| black_box(sweep_and_prune(&boxes(w)).len()))
        });
        group.bench_with_input(BenchmarkId::new("broad+narrow", n), &wall, |b, w| {
            b.iter(|| black_box(detect(w, &corners)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
