//! Known failures, kept as ignored tests so that they are run on purpose
//! (`cargo test --release --test known_failures -- --ignored`) and not forgotten.

use nmm::model::load_model;
use nmm::simulation::Simulation;
use std::path::Path;

/// A pile of nine random blocks dropped in dynamic mode with return mapping
/// (found by `tests/random_models.rs`). Measured over steps 1001–1029: the largest cover
/// velocity alternates between 23.5 and 25.6 m/s from step to step, and the smallest
/// manifold element is 3.6e-8 m² (7e-6 h²). At step 1030 that element inverts (area
/// −1.9e-8 m², largest stress 1.5 GPa) and step 1031 fails ("the system matrix is not
/// positive definite"). Our reading, not yet verified: the element carries a contact, its
/// covers have almost no mass (p_N against ρA/3 gives ωΔt ≈ 2e4), so the β = ½, γ = 1
/// velocity flutter of that stiff mode does not decay. Merging covers whose support is
/// tiny into a neighbour would remove such covers.
#[test]
#[ignore = "known failure: tiny cut element in dynamic contact inverts (see doc)"]
fn tiny_cut_element_in_contact_does_not_invert() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/tiny_element_pile.toml");
    let mut sim = Simulation::new(load_model(&path).unwrap()).unwrap();
    while !sim.finished() {
        if let Err(e) = sim.advance() {
            panic!("{e}");
        }
    }
}
