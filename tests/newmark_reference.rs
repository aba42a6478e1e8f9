//! Checks of the Newmark sliding-block reference (`nmm::verify::newmark_sliding`, crates/nmm/src/verify/newmark_sliding.rs)
//! against closed forms.
//!
//! Convention (from the reference): the slope goes down toward −x, a positive
//! horizontal base acceleration `a` pushes the block downslope. For a constant
//! `a` the along-slope acceleration of a sliding block is
//!
//! ```text
//! A = g sinθ + a cosθ − tanφ (g cosθ − a sinθ)  = (cosθ + tanφ sinθ)(a − a_y),
//! a_y = g tan(φ − θ),
//! ```
//!
//! the second form following from `tan(φ−θ) = (tanφ cosθ − sinθ)/(cosθ + tanφ sinθ)`
//! (divide numerator and denominator of `sin(φ−θ)/cos(φ−θ)` by `cos φ`).

#[path = "../crates/nmm/src/verify/newmark_sliding.rs"]
mod newmark_sliding;

use newmark_sliding::{driving_and_normal, onset, slide, yield_acceleration};
use std::f64::consts::PI;

const G: f64 = 9.81;

fn rad(d: f64) -> f64 {
    d.to_radians()
}

/// Along-slope acceleration for a constant horizontal acceleration `a`
/// (toward downslope), written out independently of the reference.
fn along_slope(theta: f64, phi: f64, a: f64) -> f64 {
    let (t, p) = (rad(theta), rad(phi));
    G * t.sin() + a * t.cos() - p.tan() * (G * t.cos() - a * t.sin())
}

#[test]
fn yield_acceleration_balances_driving_and_friction() {
    for &(theta, phi) in &[(0.0, 30.0), (20.0, 35.0), (30.0, 31.0), (10.0, 45.0)] {
        let ay = yield_acceleration(theta, phi, G);
        let (d, n) = driving_and_normal(theta, G, ay, 0.0);
        let excess = d - rad(phi).tan() * n;
        assert!(excess.abs() < 1e-12, "θ={theta} φ={phi}: D−R = {excess}");
        // both forms of the along-slope acceleration agree
        for &a in &[0.0, 0.5 * ay, 2.0 * ay, -1.0] {
            let factored = (rad(theta).cos() + rad(phi).tan() * rad(theta).sin()) * (a - ay);
            assert!((along_slope(theta, phi, a) - factored).abs() < 1e-12);
        }
    }
    assert!((yield_acceleration(0.0, 45.0, G) - G).abs() < 1e-12);
}

#[test]
fn constant_acceleration_above_yield_slides_as_half_a_t_squared() {
    let (theta, phi) = (20.0, 35.0);
    let a = 1.5 * yield_acceleration(theta, phi, G);
    let acc = along_slope(theta, phi, a);
    assert!(acc > 0.0);
    let h = slide(theta, phi, G, 0.01, &|_| (a, 0.0), 2.0);
    assert_eq!(h.len(), 201);
    for &(t, u, v) in &h {
        let (u_ref, v_ref) = (0.5 * acc * t * t, acc * t);
        assert!(
            (u - u_ref).abs() <= 1e-10 * (1.0 + u_ref),
            "t={t}: u={u} vs {u_ref}"
        );
        assert!(
            (v - v_ref).abs() <= 1e-10 * (1.0 + v_ref),
            "t={t}: v={v} vs {v_ref}"
        );
    }
    // 2 s at (1.5−1)·a_y·(cosθ + tanφ sinθ): about 1.1 m of slip
    let last = h.last().unwrap();
    assert!((last.0 - 2.0).abs() < 1e-12 && last.1 > 1.0);
}

#[test]
fn constant_acceleration_below_yield_does_not_move() {
    let (theta, phi) = (20.0, 35.0);
    let a = 0.95 * yield_acceleration(theta, phi, G);
    let h = slide(theta, phi, G, 0.01, &|_| (a, 0.0), 3.0);
    assert!(h.iter().all(|&(_, u, v)| u == 0.0 && v == 0.0));
    // and a sinusoid whose peak stays below yield
    let h = slide(
        theta,
        phi,
        G,
        0.01,
        &|t| (a * (2.0 * PI * t).sin(), 0.0),
        3.0,
    );
    assert!(h.iter().all(|&(_, u, v)| u == 0.0 && v == 0.0));
    assert_eq!(onset(&h, 1e-12), None);
}

#[test]
fn block_on_steep_incline_without_shaking() {
    let (theta, phi) = (35.0, 25.0);
    let acc = G * (rad(theta).sin() - rad(theta).cos() * rad(phi).tan());
    let h = slide(theta, phi, G, 0.005, &|_| (0.0, 0.0), 1.0);
    for &(t, u, _) in &h {
        let u_ref = 0.5 * acc * t * t;
        assert!(
            (u - u_ref).abs() <= 1e-10 * (1.0 + u_ref),
            "t={t}: {u} vs {u_ref}"
        );
    }
    // a steady upward base acceleration a_v acts as gravity g + a_v
    let av = 2.0;
    let acc_v = (G + av) * (rad(theta).sin() - rad(theta).cos() * rad(phi).tan());
    let h = slide(theta, phi, G, 0.005, &|_| (0.0, av), 1.0);
    let (t, u, _) = *h.last().unwrap();
    assert!((u - 0.5 * acc_v * t * t).abs() < 1e-10);
}

#[test]
fn strong_negative_acceleration_slides_upslope() {
    let (theta, phi) = (15.0, 30.0);
    // upslope yield: a < −g tan(φ + θ)
    let a_up = -G * rad(phi + theta).tan();
    let below = slide(theta, phi, G, 0.01, &|_| (0.95 * a_up, 0.0), 1.0);
    assert!(below.iter().all(|&(_, u, _)| u == 0.0));
    let a = 1.2 * a_up;
    let (t_, p_) = (rad(theta), rad(phi));
    // sliding upslope: friction acts downslope
    let acc = G * t_.sin() + a * t_.cos() + p_.tan() * (G * t_.cos() - a * t_.sin());
    assert!(acc < 0.0);
    let h = slide(theta, phi, G, 0.01, &|_| (a, 0.0), 1.0);
    for &(t, u, v) in &h {
        assert!((u - 0.5 * acc * t * t).abs() < 1e-10, "t={t}: {u}");
        assert!((v - acc * t).abs() < 1e-10);
    }
}

#[test]
fn pulse_then_rest_stops_and_sticks() {
    // constant a for T, then nothing: the block decelerates at
    // g (sinθ − cosθ tanφ) < 0 and sticks for good (no upslope return).
    let (theta, phi) = (20.0, 35.0);
    let a = 2.0 * yield_acceleration(theta, phi, G);
    let t_pulse = 0.5;
    let a1 = along_slope(theta, phi, a);
    let a2 = along_slope(theta, phi, 0.0);
    assert!(a1 > 0.0 && a2 < 0.0);
    let v_peak = a1 * t_pulse;
    let t_stop = t_pulse + v_peak / -a2;
    let u_final = 0.5 * a1 * t_pulse * t_pulse + v_peak * v_peak / (2.0 * -a2);
    let dt = 0.001;
    let h = slide(
        theta,
        phi,
        G,
        dt,
        &|t| (if t < t_pulse { a } else { 0.0 }, 0.0),
        2.0,
    );
    for &(t, u, v) in &h {
        if t <= t_pulse {
            // the step at t_pulse falls inside one substep: allow its smearing
            assert!((u - 0.5 * a1 * t * t).abs() < 1e-3 * u_final, "t={t}");
        } else if t > t_stop + dt {
            assert_eq!(v, 0.0, "t={t}: still moving after {t_stop}");
            assert!(
                (u - u_final).abs() < 1e-3 * u_final,
                "t={t}: {u} vs {u_final}"
            );
        } else {
            assert!(v >= 0.0, "t={t}: block going upslope");
        }
    }
    // slip never decreases
    assert!(h.windows(2).all(|w| w[1].1 >= w[0].1));
}

#[test]
fn sinusoid_onset_and_first_slide_match_closed_form() {
    let (theta, phi) = (20.0, 30.0);
    let ay = yield_acceleration(theta, phi, G);
    let (a0, omega) = (2.0 * ay, 2.0 * PI);
    let t_star = (ay / a0).asin() / omega;
    let dt = 1e-4;
    let h = slide(theta, phi, G, dt, &|t| (a0 * (omega * t).sin(), 0.0), 1.2);

    // onset: slip grows like k τ³/6 after t*, so a tiny threshold sits at t*
    let t_on = onset(&h, 1e-12).expect("the block slides");
    assert!((t_on - t_star).abs() < 3.0 * dt, "onset {t_on} vs {t_star}");

    // while sliding: v = c[a0/ω (cos ωt* − cos ωt) − a_y (t − t*)],
    //                u = c[a0/ω ((t−t*) cos ωt* − (sin ωt − sin ωt*)/ω) − a_y (t−t*)²/2]
    let c = rad(theta).cos() + rad(phi).tan() * rad(theta).sin();
    let v_cf = |t: f64| {
        c * (a0 / omega * ((omega * t_star).cos() - (omega * t).cos()) - ay * (t - t_star))
    };
    let u_cf = |t: f64| {
        let s = t - t_star;
        c * (a0 / omega
            * (s * (omega * t_star).cos() - ((omega * t).sin() - (omega * t_star).sin()) / omega)
            - ay * s * s / 2.0)
    };
    // stop time: first zero of v_cf after t* (bisection on the closed form)
    let (mut lo, mut hi) = (t_star + 0.1, 1.0);
    assert!(v_cf(lo) > 0.0 && v_cf(hi) < 0.0);
    for _ in 0..80 {
        let m = 0.5 * (lo + hi);
        if v_cf(m) > 0.0 {
            lo = m
        } else {
            hi = m
        }
    }
    let t_stop = 0.5 * (lo + hi);
    let u_stop = u_cf(t_stop);
    assert!(u_stop > 0.01, "meaningful slip: {u_stop}");
    let mut checked = 0;
    for &(t, u, v) in &h {
        if t < t_star - dt {
            assert_eq!(u, 0.0);
        } else if t > t_star + dt && t < t_stop - dt {
            assert!(
                (u - u_cf(t)).abs() < 1e-6 * u_stop,
                "t={t}: {u} vs {}",
                u_cf(t)
            );
            assert!((v - v_cf(t)).abs() < 1e-5, "t={t}: {v} vs {}", v_cf(t));
            checked += 1;
        } else if t > t_stop + dt && t < t_star + 1.0 - dt {
            // stuck until the next cycle's onset at t* + 1 s
            assert_eq!(v, 0.0, "t={t}");
            assert!((u - u_stop).abs() < 1e-6 * u_stop, "t={t}: {u} vs {u_stop}");
        }
    }
    assert!(checked > 1000);
    // the second cycle adds the same slip again
    let (_, u_end, _) = *h.last().unwrap();
    assert!(u_end > u_stop * (1.0 + 1e-3));
}
