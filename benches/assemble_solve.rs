//! Criterion benchmark: assembly, factorisation and solve of one elastic block at
//! about 1e4, 1e5 and 1e6 unknowns (seeded generator `nmm::generate::elastic_block`).
//! These machines are noisy (2× swings): read medians and ratios between sizes.
//! `examples/scaling.rs` prints the same stages (plus cover generation) as a table.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nmm::generate::elastic_block;
use nmm::model::parse_model;
use nmm::simulation::Simulation;
use nmm::solver::{AutoSolver, DirectSolver};
use std::time::Duration;

fn sizes() -> Vec<usize> {
    match std::env::var("NMM_BENCH_SIZES") {
        Ok(s) => s
            .split(',')
            .filter_map(|x| x.trim().parse::<f64>().ok())
            .map(|x| x as usize)
            .collect(),
        Err(_) => vec![10_000, 100_000, 1_000_000],
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("elastic_block");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for n in sizes() {
        let model = parse_model(&elastic_block(n, 7), std::path::Path::new(".")).unwrap();
        g.bench_with_input(BenchmarkId::new("cover", n), &model, |b, m| {
            b.iter(|| Simulation::new(m.clone()).unwrap())
        });
        let mut sim = Simulation::new(model).unwrap();
        g.bench_with_input(BenchmarkId::new("assembly", n), &n, |b, _| {
            b.iter(|| sim.linear_system())
        });
        let (l, f) = sim.linear_system();
        g.bench_with_input(
            BenchmarkId::new("factorisation_with_symbolic", n),
            &n,
            |b, _| {
                b.iter(|| {
                    let mut s = AutoSolver::default();
                    s.factorize_with(&l, true).unwrap();
                })
            },
        );
        let mut s = AutoSolver::default();
        s.factorize_with(&l, true).unwrap();
        g.bench_with_input(BenchmarkId::new("refactorisation", n), &n, |b, _| {
            b.iter(|| s.factorize_with(&l, true).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("solve", n), &n, |b, _| {
            b.iter(|| {
                let mut x = f.clone();
                s.solve_in_place(&mut x).unwrap();
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
