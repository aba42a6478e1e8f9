//! Restitution (issue 18, item 5): a block dropped from H onto a fixed base rebounds to e²H
//! with `[[interface]] restitution = e`, whatever the time step (the dashpot is calibrated
//! against the scheme's own dissipation, see `nmm::contact::restitution`); without it the
//! impact loses only what the time integration takes; the energy the dashpot takes is
//! reported as damping and the balance closes.
//!
//! The block (0.4 × 0.2 m, ρ = 2500, E = 50 GPa) lands on penalty springs (10⁸ N/m/m) about
//! 150 times softer than itself, so it lands as a rigid body (with E = 10 GPa and springs of
//! 10⁹ the block's own compliance, in series with the dashpot, let it rebound 9% above e);
//! it falls H = 0.05 m flat onto the base. The rebound height is the block's highest mean displacement after the
//! impact above where it touched (−H). Tolerance 5% of e²H (the acceptance item): the table's
//! interpolation (< 1% in e) and the first touch's phase within a step (the table averages
//! four phases; one phase departs from their mean by up to ±6% in e at Ω = 0.58, ±1.5% at
//! Ω = 0.14) are below it at the Δt used here.

use nmm::simulation::Simulation;
use nmm::verify::cases::model;

const H: f64 = 0.05;

struct Drop {
    rebound: f64,
    damping: f64,
    balance: f64,
}

fn drop(restitution: Option<f64>, dt: f64) -> Drop {
    let g = 9.81;
    let steps = (0.17 / dt).ceil() as usize;
    let e = restitution.map_or(String::new(), |e| format!("restitution = {e}\n"));
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -{g}]\n\
         [cover]\nsize = 0.2\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 5.0e10\npoisson = 0.25\n\
         [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e8\nshear_penalty = 1.0e8\n{e}\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nfixed = true\n\
         vertices = [[-1.0, -0.3], [1.4, -0.3], [1.4, 0.0], [-1.0, 0.0]]\n\
         [[block]]\nname = \"block\"\nmaterial = \"rock\"\n\
         vertices = [[0.0, {H}], [0.4, {H}], [0.4, {top}], [0.0, {top}]]\n",
        top = H + 0.2
    );
    let mut sim = Simulation::new(model(&text).unwrap()).unwrap();
    let block = 1;
    let mean_uy = |sim: &Simulation| {
        let (mut s, mut n) = (0.0, 0);
        for c in &sim.disc.covers {
            if let (Some(d), true) = (c.dof, c.block == block) {
                s += sim.u[d + 1];
                n += 1;
            }
        }
        s / n as f64
    };
    let (mut landed, mut highest) = (false, f64::NEG_INFINITY);
    let mut worst = 0.0f64;
    while !sim.finished() {
        sim.advance()
            .unwrap_or_else(|e| panic!("step {}: {e}", sim.step));
        worst = worst.max(sim.energy.balance_error_relative().abs());
        let uy = mean_uy(&sim);
        let closed = sim.contacts.contacts.iter().any(|c| c.response.tn < 0.0);
        if closed {
            landed = true;
        } else if landed {
            highest = highest.max(uy);
        }
    }
    assert!(
        landed && highest.is_finite(),
        "the block never landed and left"
    );
    Drop {
        rebound: highest + H,
        damping: sim.energy.damping,
        balance: worst,
    }
}

/// e = 0.5 and 0.8 at Δt = 75 µs: Ω = ωΔt = 0.14 for the contact's ω ≈ 1,900 rad/s (22
/// steps per contact period); measured +2.7% and −2.6% of e²H. (At Ω = 0.28 and 0.57 the
/// same drop gave +8% and −7%: there the rebound of one drop depends on where in a step the
/// first touch falls, see docs/model-format.md.) Without restitution the scheme alone
/// rebounds with e ≈ 0.87 at this Ω.
#[test]
fn a_dropped_block_rebounds_to_e_squared_h() {
    for (e, dt) in [(0.5, 7.5e-5), (0.8, 7.5e-5)] {
        let d = drop(Some(e), dt);
        let expected = e * e * H;
        let rel = (d.rebound - expected) / expected;
        eprintln!(
            "e = {e}, Δt = {dt}: rebound {:.5} m against e²H = {expected:.5} ({rel:+.3e}); dashpot took {:.4e} J/m; balance {:.2e}",
            d.rebound, d.damping, d.balance
        );
        assert!(
            rel.abs() <= 0.05,
            "e {e}, Δt {dt}: rebound {} against {expected}",
            d.rebound
        );
        assert!(d.damping > 0.0);
        assert!(d.balance <= 0.01, "balance off by {:.3e}", d.balance);
    }
    let d = drop(None, 7.5e-5);
    eprintln!(
        "no restitution: rebound {:.5} m ({:.3} H)",
        d.rebound,
        d.rebound / H
    );
    assert_eq!(d.damping, 0.0);
    assert!(
        d.rebound > 0.7 * H,
        "rebound {} without restitution",
        d.rebound
    );
}

#[test]
fn a_restitution_outside_zero_to_one_is_refused() {
    for bad in ["0.0", "1.5", "-0.2"] {
        let text = format!(
            "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 1\n[cover]\nsize = 0.2\n\
             [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e10\npoisson = 0.25\n\
             [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\nrestitution = {bad}\n\
             [[block]]\nname = \"a\"\nmaterial = \"rock\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n\
             [[block]]\nname = \"b\"\nmaterial = \"rock\"\nvertices = [[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]]\n"
        );
        let err = model(&text).unwrap_err().to_string();
        assert!(
            err.contains("restitution") && err.contains("(0, 1]") && err.contains("line"),
            "{bad}: {err}"
        );
    }
}
