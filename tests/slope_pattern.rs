//! The tangent's pattern of a jointed slope whose face starts to slide (simulation/step.rs,
//! `TangentPattern`: keys and hysteresis).

use nmm::generate::{jointed_slope_model, SlopeOptions};
use nmm::simulation::Simulation;
use nmm::verify::cases::model;

/// A sliding face's contacts face points micrometres off mesh nodes, whose weights creep
/// across the pattern's floor (10⁻⁴ of the contact's largest row) step by step, and vertices
/// on mesh lines that detection puts in either element: found by their index key, they keep
/// their couplings, and the pattern (so the symbolic analysis) holds after the first steps
/// (measured on this slope, 12 steps: 8 symbolic analyses, one in each of the last 6 steps,
/// when couplings were found only by their exact unknowns; 2, in the first two, with the
/// index keys).
#[test]
fn a_sliding_slope_keeps_its_tangent_pattern() {
    let mut o = SlopeOptions::new(8.0);
    o.steps = 12;
    o.dt = 1e-3;
    let text = jointed_slope_model(&o).unwrap();
    let mut sim = Simulation::new(model(&text).unwrap()).unwrap();
    let mut symbolic = Vec::new();
    while !sim.finished() {
        let rep = sim.advance().unwrap();
        assert_eq!(rep.cuts, 0);
        symbolic.push(rep.linear.symbolic_analyses);
    }
    let later: usize = symbolic[2..].iter().sum();
    eprintln!("symbolic analyses per step: {symbolic:?}");
    assert!(
        later <= 2,
        "{later} symbolic analyses in steps 3 to 12: {symbolic:?}"
    );
}
