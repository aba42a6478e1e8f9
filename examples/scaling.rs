//! Scaling generator: per-stage timings (cover generation, assembly, factorisation,
//! solve) of one elastic block at growing numbers of unknowns.
//!
//! `cargo run --release --example scaling -- 1e4 1e5 1e6`
//!
//! The block is a rectangle with a seeded random rotation and offset relative to
//! the mathematical mesh (so that it has cut cells), clamped along its base and
//! loaded by gravity; sizes are approximate (the number of covers follows h).

use nmm::generate::elastic_block;
use nmm::model::parse_model;
use nmm::simulation::Simulation;
use nmm::solver::{AutoSolver, DirectSolver};
use std::time::Instant;

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse::<f64>().ok())
        .map(|x| x as usize)
        .collect();
    let sizes = if sizes.is_empty() {
        vec![10_000, 100_000]
    } else {
        sizes
    };
    println!("unknowns,elements,cover_s,assembly_s,symbolic+numeric_factorisation_s,refactorisation_s,solve_s");
    for n in sizes {
        let model =
            parse_model(&elastic_block(n, 7), std::path::Path::new(".")).expect("generated model");
        let t = Instant::now();
        let mut sim = Simulation::new(model).expect("discretise");
        let cover = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let (l, f) = sim.linear_system();
        let assembly = t.elapsed().as_secs_f64();
        let mut solver = AutoSolver::default();
        let t = Instant::now();
        solver.factorize_with(&l, true).expect("factorise");
        let fact = t.elapsed().as_secs_f64();
        let t = Instant::now();
        solver.factorize_with(&l, true).expect("factorise");
        let refact = t.elapsed().as_secs_f64();
        let mut x = f.clone();
        let t = Instant::now();
        solver.solve_in_place(&mut x).expect("solve");
        let solve = t.elapsed().as_secs_f64();
        println!(
            "{},{},{cover:.4},{assembly:.4},{fact:.4},{refact:.4},{solve:.4}",
            sim.n_dofs(),
            sim.disc.elements.len()
        );
    }
}
