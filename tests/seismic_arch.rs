//! A seismic run of an arch on its abutments (issue: the contact solve): the 19-voussoir
//! semicircular arch of `nmm::generate::arch_model` (t/r = 0.15, φ = 35°, cover 0.1 m)
//! under 2.5 s of a horizontal 2 Hz base motion of 0.2 g (ramped over 0.5 s), Δt = 1 ms:
//! its joints open and close and slip every cycle (the arch rocks), and at most 1% of the
//! steps may need a Δt cut (before the rewrite: 307 cuts in 2,500 steps on such a run).
//! The arch must ride it out, and it must have been shaken out of its elastic state.
//! No closed form exists for a rocking arch, and its final displacement is chaotic: a
//! change of the last bits of the linear solves (the supernodal factorisation) moved it
//! from 2.88e-2 to 1.94e-2 m (3.9e-2 m in an earlier session), so no regression figure
//! pins it. The bounds come from the geometry instead: it stays standing — its largest
//! final displacement is below a fifth of the voussoir thickness t = 0.3 m (6 cm; a
//! collapse moves the crown by metres, and the former check, < 0.1 m, was a third of t) —
//! and it rocked — above 5 mm, where the arch under gravity alone moves 1e-5 m.

use nmm::generate::{arch_model, ArchOptions};
use nmm::simulation::Simulation;
use nmm::verify::cases::model;

#[test]
fn arch_under_base_motion_needs_few_cuts() {
    let mut o = ArchOptions::new();
    o.steps = 2500;
    let (f, amp) = (2.0, 0.2 * 9.81);
    o.base_motion = Some(
        (0..=2600)
            .map(|k| {
                let t = k as f64 * 1e-3;
                let ramp = (t / 0.5).min(1.0);
                (t, amp * ramp * (std::f64::consts::TAU * f * t).sin())
            })
            .collect(),
    );
    let mut sim = Simulation::new(model(&arch_model(&o)).unwrap()).unwrap();
    let (mut cuts, mut cut_steps, mut solves, mut changes) = (0, 0, Vec::new(), 0);
    let mut drift = 0.0f64;
    while !sim.finished() {
        let r = sim
            .advance()
            .unwrap_or_else(|e| panic!("step {}: {e}", sim.step));
        cuts += r.cuts;
        cut_steps += usize::from(r.cuts > 0);
        solves.push(r.solves);
        changes += r.active_set_changes;
    }
    for bd in sim.disc.boundaries.iter().skip(1) {
        for v in &bd.vertices {
            let d = sim.displacement_at(&v.at);
            drift = drift.max(d[0].hypot(d[1]));
        }
    }
    let steps = solves.len();
    solves.sort_unstable();
    eprintln!(
        "seismic arch: {steps} steps, {cut_steps} steps cut ({cuts} cuts), solves median {} max {}, {changes} active-set changes, largest final displacement {drift:.3e} m",
        solves[steps / 2],
        solves[steps - 1]
    );
    assert!(
        cut_steps as f64 <= 0.01 * steps as f64,
        "{cut_steps} of {steps} steps cut"
    );
    let t = o.thickness;
    assert!(
        drift < 0.2 * t && drift > 5e-3,
        "largest final displacement {drift} m: not within (5 mm, t/5 = {} m)",
        0.2 * t
    );
}
