//! Any cover size gives a right answer (issue: the contact solve, item 6): a stable arch, a
//! stack and a wall released under gravity stand — no boundary point moves more than 1 mm
//! in 1 s (dynamic, Δt = 1 ms) — with mathematical covers from a quarter of the smallest
//! block dimension to three times the largest (one manifold element per block and beyond,
//! as DDA users model).
//!
//! Reference: statics. Each structure has an equilibrium (the arch at t/r = 0.15 is above
//! Heyman's minimum 0.1075 with φ = 35°; stack and wall are stacked on a level base with
//! φ = 30–35°), so after the elastic settlement under the sudden release (penalty 1e10 N/m:
//! tens of μm) nothing may move. 1 mm is 20× the settlement and 1/300 of the blocks: a
//! hinge opening, a sliding block or a block thrown off exceed it at once.
//!
//! The block dimensions are the sides of each movable block's bounding box. The wall is
//! laid with closers (half bricks at the ends of the odd courses): without them the top
//! course's end brick has its centre of mass exactly above the edge of the brick below, a
//! neutral equilibrium that topples (and does, at fine covers: 0.17 m in 1 s at h = L/8).

use nmm::generate::{arch_model, brick_wall_model, stack_model, ArchOptions, WallOptions};
use nmm::simulation::Simulation;
use nmm::verify::cases::model;

struct Stand {
    worst: f64,
    cuts: usize,
    max_solves: usize,
}

/// Runs a model to its end; the largest displacement of any boundary vertex of a movable
/// block at any step.
fn run(text: &str, what: &str) -> Stand {
    let mut sim = Simulation::new(model(text).unwrap()).unwrap();
    let (mut worst, mut cuts, mut max_solves) = (0.0f64, 0, 0);
    while !sim.finished() {
        let r = sim
            .advance()
            .unwrap_or_else(|e| panic!("{what}: step {}: {e}", sim.step));
        cuts += r.cuts;
        max_solves = max_solves.max(r.solves);
        for (b, boundary) in sim.disc.boundaries.iter().enumerate() {
            if sim.model.blocks[b].fixed {
                continue;
            }
            for v in &boundary.vertices {
                let d = sim.displacement_at(&v.at);
                worst = worst.max(d[0].hypot(d[1]));
            }
        }
    }
    Stand {
        worst,
        cuts,
        max_solves,
    }
}

/// Smallest and largest side of the movable blocks' bounding boxes.
fn block_dimensions(text: &str) -> (f64, f64) {
    let m = model(text).unwrap();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for b in m.blocks.iter().filter(|b| !b.fixed) {
        for k in 0..2 {
            let (a, z) = b
                .vertices
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, z), p| {
                    (a.min(p[k]), z.max(p[k]))
                });
            lo = lo.min(z - a);
            hi = hi.max(z - a);
        }
    }
    (lo, hi)
}

/// Covers from a quarter of the smallest block dimension to three times the largest.
fn covers(lo: f64, hi: f64) -> Vec<f64> {
    let (a, z) = (0.25 * lo, 3.0 * hi);
    // geometric steps, both ends included
    let n = 5;
    (0..=n)
        .map(|k| a * (z / a).powf(k as f64 / n as f64))
        .collect()
}

fn sweep(make: impl Fn(f64) -> String, what: &str) {
    let (lo, hi) = block_dimensions(&make(1.0));
    let mut failed = Vec::new();
    for h in covers(lo, hi) {
        let s = run(&make(h), &format!("{what} h = {h:.4}"));
        eprintln!(
            "{what}: h = {h:.4} m ({:.2} × smallest, {:.2} × largest): largest motion {:.3e} m, {} cuts, at most {} solves in a step",
            h / lo,
            h / hi,
            s.worst,
            s.cuts,
            s.max_solves
        );
        if s.worst > 1e-3 {
            failed.push((h, s.worst));
        }
    }
    assert!(
        failed.is_empty(),
        "{what}: moved more than 1 mm at h = {failed:?}"
    );
}

#[test]
fn arch_stands_at_every_cover_size() {
    sweep(
        |h| {
            let mut o = ArchOptions::new();
            o.cover = h;
            o.steps = 1000;
            arch_model(&o)
        },
        "arch",
    );
}

#[test]
fn stack_stands_at_every_cover_size() {
    sweep(|h| stack_model(5, 0.5, 0.3, h, 1000), "stack");
}

#[test]
fn wall_stands_at_every_cover_size() {
    sweep(
        |h| {
            let mut o = WallOptions::new(5, 5);
            o.closers = true;
            o.cover = h;
            o.steps = 1000;
            brick_wall_model(&o)
        },
        "wall",
    );
}
