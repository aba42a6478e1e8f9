//! Rayleigh damping on a free elastic bar (one block, no contact): the logarithmic
//! decrement of its first axial mode against the closed form 2πζ/√(1 − ζ²), at a Δt where
//! the scheme's own dissipation is negligible, and against the scheme's exact discrete
//! decrement (physical and numerical damping together) at a coarse Δt.

use nmm::model::Rayleigh;
use nmm::time::{exact_log_decrement, log_decrement};
use nmm::verify::cases::damped_bar;

/// ζ = 0.1 at the bar's first mode, T/Δt = 4000: the scheme alone would give
/// δ = π²Δt/T = 0.0025, 0.39% of the physical δ = 0.6315.
const FINE: f64 = 4000.0;

fn check_closed_form(label: &str, damping: &str, zeta_at: impl Fn(f64) -> f64) {
    let bar = damped_bar(damping, FINE, 2.4).unwrap();
    let zeta = zeta_at(bar.omega);
    let want = exact_log_decrement(zeta);
    assert!(
        log_decrement(bar.omega * bar.dt, 0.0) < 0.005 * want,
        "the scheme's dissipation is not negligible"
    );
    assert!(!bar.decrements.is_empty());
    for d in &bar.decrements {
        eprintln!("{label}: ζ = {zeta:.4}, δ = {d:.5}, closed form {want:.5}");
        assert!((d / want - 1.0).abs() < 0.02, "{label}: δ {d} vs {want}");
    }
    // the damped period 2π/(ω√(1 − ζ²)) (the mesh's frequency error is ~0.1%)
    let period = std::f64::consts::TAU / (bar.omega * (1.0 - zeta * zeta).sqrt());
    assert!(
        (bar.period / period - 1.0).abs() < 0.005,
        "{label}: period {} vs {period}",
        bar.period
    );
}

#[test]
fn mass_proportional_damping_decays_as_the_closed_form() {
    let omega = nmm::verify::cases::damped_bar_omega();
    let alpha = 2.0 * 0.1 * omega;
    check_closed_form("α", &format!("{{ alpha = {alpha} }}"), |w| {
        Rayleigh { alpha, beta: 0.0 }.ratio_at(w)
    });
}

#[test]
fn stiffness_proportional_damping_decays_as_the_closed_form() {
    let omega = nmm::verify::cases::damped_bar_omega();
    let beta = 2.0 * 0.1 / omega;
    check_closed_form("β", &format!("{{ beta = {beta} }}"), |w| {
        Rayleigh { alpha: 0.0, beta }.ratio_at(w)
    });
}

#[test]
fn ratio_at_two_frequencies_decays_as_the_closed_form() {
    // ζ = 0.1 at f/2 and 2f: at f (their geometric mean) ζ = 0.1 × 2f/(f/2 + 2f) = 0.08
    let f = nmm::verify::cases::damped_bar_omega() / std::f64::consts::TAU;
    let text = format!(
        "{{ ratio = 0.1, frequencies = [{}, {}] }}",
        f / 2.0,
        2.0 * f
    );
    check_closed_form("ratio", &text, |w| {
        let r = Rayleigh::from_ratio(0.1, f / 2.0, 2.0 * f).ratio_at(w);
        assert!((r - 0.08).abs() < 1e-3, "{r}");
        r
    });
}

/// At 40 steps per period the scheme's own damping (δ ≈ 0.25) is as large as the
/// physical (ζ = 0.05, δ = 0.31): the decay is the scheme's exact discrete decrement with
/// damping, not their closed forms.
#[test]
fn coarse_steps_decay_by_the_discrete_amplification() {
    let omega = nmm::verify::cases::damped_bar_omega();
    let (alpha, beta) = (0.05 * omega, 0.05 / omega); // ζ = 0.025 + 0.025
    let bar = damped_bar(&format!("{{ alpha = {alpha}, beta = {beta} }}"), 40.0, 3.4).unwrap();
    let zeta = Rayleigh { alpha, beta }.ratio_at(bar.omega);
    let want = log_decrement(bar.omega * bar.dt, zeta);
    assert!(want > 1.5 * exact_log_decrement(zeta));
    for d in &bar.decrements {
        eprintln!("coarse: ζ = {zeta:.4}, δ = {d:.5}, discrete {want:.5}");
        assert!((d / want - 1.0).abs() < 0.02, "δ {d} vs {want}");
    }
}

/// Static mode resets the velocity every step and has no damping term: a damped material
/// settles exactly as an undamped one; in dynamic mode the same damping changes the motion.
#[test]
fn static_mode_ignores_damping() {
    let text = |mode: &str, damping: &str| {
        format!(
            "[analysis]\nmode = \"{mode}\"\ndt = 0.001\nsteps = 20\ngravity = [0.0, -9.81]\n\
             [cover]\nsize = 0.25\n\
             [[material]]\nname = \"m\"\ndensity = 2500.0\nyoung = 1.0e7\npoisson = 0.2\n{damping}\n\
             [[block]]\nname = \"column\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [0.5, 0.0], [0.5, 2.0], [0.0, 2.0]]\n\
             [[constraint]]\nblock = \"column\"\nedge = [[0.0, 0.0], [0.5, 0.0]]\nux = 0.0\nuy = 0.0\n\
             [[monitor]]\nname = \"top\"\npoint = [0.25, 2.0]\n"
        )
    };
    let top = |text: String| {
        let model = nmm::model::parse_model(&text, std::path::Path::new(".")).unwrap();
        let mut sim = nmm::simulation::Simulation::new(model).unwrap();
        while !sim.finished() {
            sim.advance().unwrap();
        }
        nmm::simulation::monitor_values(&sim)[1]
    };
    let damped = "damping = { alpha = 50.0, beta = 0.01 }";
    let (s0, s1) = (top(text("static", "")), top(text("static", damped)));
    assert!(s0 < 0.0);
    assert_eq!(s0.to_bits(), s1.to_bits(), "{s0} vs {s1}");
    let (d0, d1) = (top(text("dynamic", "")), top(text("dynamic", damped)));
    assert!((d0 - d1).abs() > 0.05 * d0.abs(), "{d0} vs {d1}");
}
