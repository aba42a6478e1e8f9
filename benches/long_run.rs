//! Long run: the two-block shaking-table slope over a 30 s record at Δt = 1 ms
//! (30,000 steps), return mapping. Prints the wall-clock time and the per-stage split.
//! `cargo bench --bench long_run` (a single timed run: criterion's ten samples of a
//! 10-second run would take minutes for no better figure).

use nmm::simulation::Simulation;
use nmm::verify::cases::{model, slope_model, SineMotion};
use std::time::Instant;

fn main() {
    let motion = SineMotion {
        amplitude: 0.25 * 9.81,
        frequency: 2.0,
        ramp: 1.0,
        duration: 30.0,
    };
    for algorithm in ["return-mapping", "conventional"] {
        let m = model(&slope_model(30.0, &motion, algorithm, 1e-3)).expect("model");
        let t = Instant::now();
        let mut sim = Simulation::new(m).expect("setup");
        let mut its = 0;
        while !sim.finished() {
            its += sim.advance().expect("step").iterations;
        }
        let s = sim.timings.stages;
        println!(
            "{algorithm}: {} steps in {:.2} s ({:.1} µs/step, {:.2} Newton iterations/step); assembly {:.2} s, contact {:.2} s, factorisation {:.2} s, solve {:.2} s",
            sim.step,
            t.elapsed().as_secs_f64(),
            t.elapsed().as_secs_f64() / sim.step as f64 * 1e6,
            its as f64 / sim.step as f64,
            s.assembly.as_secs_f64(),
            s.contact.as_secs_f64(),
            s.factorisation.as_secs_f64(),
            s.solve.as_secs_f64()
        );
    }
}
