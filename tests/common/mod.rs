//! Helpers shared by the verification tests.
#![allow(dead_code)]

use nmm::model::{parse_model, Model};
use nmm::simulation::Simulation;
use std::path::Path;

/// Parse a model text (panics with the model error: a test bug).
pub fn model(text: &str) -> Model {
    parse_model(text, Path::new("."))
        .unwrap_or_else(|e| panic!("test model does not parse: {e}\n{text}"))
}

/// Build and run a simulation to its end, returning it.
pub fn run(text: &str) -> Simulation {
    let mut sim = Simulation::new(model(text)).expect("simulation setup");
    while !sim.finished() {
        sim.advance().expect("step converges");
    }
    sim
}

/// A TOML polygon literal.
pub fn poly(pts: &[[f64; 2]]) -> String {
    let items: Vec<String> = pts
        .iter()
        .map(|p| format!("[{:.17e}, {:.17e}]", p[0], p[1]))
        .collect();
    format!("[{}]", items.join(", "))
}

/// Rotate and translate points.
pub fn place(pts: &[[f64; 2]], angle_deg: f64, offset: [f64; 2]) -> Vec<[f64; 2]> {
    let (s, c) = angle_deg.to_radians().sin_cos();
    pts.iter()
        .map(|p| {
            [
                offset[0] + c * p[0] - s * p[1],
                offset[1] + s * p[0] + c * p[1],
            ]
        })
        .collect()
}

/// Observed convergence order from errors at successive halvings of h.
pub fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}
