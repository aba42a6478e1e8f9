//! Contacts cannot be tunneled through (issue: the contact solve, item 5). The contacts
//! of a step are searched on the geometry at its start within a distance of three times
//! the last step's largest motion; a converged step that moves any point farther than
//! half that distance (`OUTRUN_FRACTION`: two blocks closing on each other) is redone with
//! contacts searched over three times its motion, so no vertex can pass through an edge
//! that was never looked at.
//!
//! 1. A block dropped 1 m onto a plate 2 cm thick with Δt = 5 ms: at impact it moves
//!    2.2 cm per step, more than the plate's thickness. It must come to rest on the plate.
//! 2. A static pile of six random blocks (found by the soak of tests/random_models.rs):
//!    a converged static step moved blocks 0.1–0.5 m at once, beyond the contact search;
//!    a vertex then started the next step 0.24 m inside another block, the penalty crushed
//!    an element and the run failed at step 662 with "manifold element 120 would be
//!    inverted". It must run on with no contact deeper than 1e-4 m.

use nmm::model::load_model;
use nmm::simulation::Simulation;
use nmm::verify::cases::model;
use std::path::Path;

fn deepest(sim: &Simulation) -> f64 {
    sim.contacts
        .contacts
        .iter()
        .map(|c| c.gn0)
        .fold(0.0, f64::min)
}

#[test]
fn a_fast_block_lands_on_a_thin_plate() {
    let text = "[analysis]\nmode = \"dynamic\"\ndt = 0.005\nsteps = 160\ngravity = [0.0, -9.81]\n\
         [cover]\nsize = 0.1\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
         [[block]]\nname = \"plate\"\nmaterial = \"rock\"\nfixed = true\n\
         vertices = [[-1.0, -0.02], [1.0, -0.02], [1.0, 0.0], [-1.0, 0.0]]\n\
         [[block]]\nname = \"block\"\nmaterial = \"rock\"\n\
         vertices = [[-0.1, 1.0], [0.1, 1.0], [0.1, 1.2], [-0.1, 1.2]]\n\
         [[monitor]]\nname = \"c\"\npoint = [0.0, 1.1]\n";
    let mut sim = Simulation::new(model(text).unwrap()).unwrap();
    let mut worst = 0.0f64;
    while !sim.finished() {
        sim.advance()
            .unwrap_or_else(|e| panic!("step {}: {e}", sim.step));
        worst = worst.min(deepest(&sim));
    }
    let bd = &sim.disc.boundaries[1];
    let lowest = bd
        .vertices
        .iter()
        .map(|v| v.x0[1] + sim.displacement_at(&v.at)[1])
        .fold(f64::INFINITY, f64::min);
    eprintln!("block's lowest point at {lowest:.4e} m, deepest contact {worst:.3e} m");
    assert!(
        lowest > -1e-3,
        "the block passed into or through the plate: {lowest}"
    );
    assert!(worst > -1e-3, "a contact started {worst} m deep");
}

#[test]
fn static_pile_found_by_the_soak_runs_on() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/static_pile_outrun.toml");
    let mut sim = Simulation::new(load_model(&path).unwrap()).unwrap();
    let mut worst = 0.0f64;
    while !sim.finished() {
        sim.advance()
            .unwrap_or_else(|e| panic!("step {}: {e}", sim.step));
        worst = worst.min(deepest(&sim));
    }
    eprintln!("{} steps, deepest contact {worst:.3e} m", sim.step);
    assert!(worst > -1e-4, "a contact started {worst} m deep");
}
