//! Independent reference: Newmark (1965) rigid sliding block, written without
//! any `nmm` code, to check the shaken-slope results of the solver.
//!
//! Include from an integration test with
//! `#[path = "../crates/nmm/src/verify/newmark_sliding.rs"] mod newmark_sliding;`.
//!
//! # Geometry and sign conventions
//!
//! A rigid block rests on a plane dipping `θ`, the slope surface going **down
//! toward −x**: the downslope unit vector is `s = (−cos θ, −sin θ)` and the
//! plane's normal, pointing into the block, `n = (−sin θ, cos θ)`. The base
//! accelerates by `a_h(t)` (positive +x) and `a_v(t)` (positive +y, up).
//! In the base frame the block feels gravity and the inertial force `−m a_base`,
//! i.e. per unit mass `f = (−a_h, −g − a_v)`. Hence a **positive `a_h` pushes
//! the block downslope**. Per unit mass:
//!
//! ```text
//! driving (downslope)  D = f·s  = (g + a_v) sin θ + a_h cos θ
//! normal  (pressing)   N = −f·n = (g + a_v) cos θ − a_h sin θ
//! friction limit       R = tan φ · max(N, 0)
//! ```
//!
//! Yield (downslope, `a_v = 0`): `D = R` ⇔ `a_h = g tan(φ − θ)`; upslope
//! sliding needs `a_h < −g tan(φ + θ)`.
//!
//! # Dynamics (Coulomb, both directions)
//!
//! `u` is the slip along `s` (positive downslope), `v = du/dt`.
//! * Stuck (`v = 0`): stays stuck while `|D| ≤ R`; starts sliding in the
//!   direction of `D` when `|D| > R`.
//! * Sliding with direction `σ = sign v`: `dv/dt = D − σ R`; when `v` reaches
//!   zero the block sticks again (and restarts at once if `|D| > R`).
//! * `N < 0` (lift-off) is treated as frictionless contact (`R = 0`): the
//!   block stays on the plane. Keep `|a_h| tan θ < g` to stay clear of it.
//!
//! # Integration
//! Each output step `dt` is split into 10 substeps `h`. Over a substep the
//! acceleration `A = D − σR` is taken linear between its end values, and
//! integrated exactly: `v₁ = v₀ + h (A₀ + A₁)/2`, `u₁ = u₀ + v₀ h + h² (2A₀ + A₁)/6`
//! (exact for constant or linearly varying forcing). The start of sliding is
//! located by linear interpolation of the excess `|D| − R` inside the substep,
//! and the stop (`v = 0`) by bisection on the quadratic `v(τ)`.
#![allow(dead_code)]

/// Substeps per output step.
const SUBSTEPS: usize = 10;

/// Downslope driving force `D` and normal force `N` per unit mass (see the
/// module doc) for base accelerations `a_h`, `a_v`, on a plane dipping
/// `theta_deg`.
pub fn driving_and_normal(theta_deg: f64, g: f64, a_h: f64, a_v: f64) -> (f64, f64) {
    let (s, c) = theta_deg.to_radians().sin_cos();
    ((g + a_v) * s + a_h * c, (g + a_v) * c - a_h * s)
}

/// Horizontal base acceleration (+x, pushing the block downslope) at which
/// the block starts to slide downslope: `g tan(φ − θ)` (angles in degrees).
pub fn yield_acceleration(theta_deg: f64, phi_deg: f64, g: f64) -> f64 {
    g * (phi_deg - theta_deg).to_radians().tan()
}

/// Slide history `(t, u, v)` at `t = 0, dt, 2dt, … ≤ t_end` for a block on a
/// plane dipping `theta_deg` with friction angle `phi_deg`, under base
/// acceleration `accel(t) = (a_h, a_v)`. `u` is the slip along the plane,
/// positive downslope (toward −x), `v` its rate.
pub fn slide(
    theta_deg: f64,
    phi_deg: f64,
    g: f64,
    dt: f64,
    accel: &dyn Fn(f64) -> (f64, f64),
    t_end: f64,
) -> Vec<(f64, f64, f64)> {
    assert!(dt > 0.0 && t_end >= 0.0, "dt > 0 and t_end >= 0");
    let mu = phi_deg.to_radians().tan();
    // (D, R) at time t
    let forces = |t: f64| {
        let (a_h, a_v) = accel(t);
        let (d, n) = driving_and_normal(theta_deg, g, a_h, a_v);
        (d, mu * n.max(0.0))
    };
    let steps = (t_end / dt + 1e-9).floor() as usize;
    let h = dt / SUBSTEPS as f64;
    let (mut u, mut v, mut dir) = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut out = Vec::with_capacity(steps + 1);
    out.push((0.0, u, v));
    for k in 0..steps {
        for j in 0..SUBSTEPS {
            let t0 = k as f64 * dt + j as f64 * h;
            let t1 = t0 + h;
            let (d0, r0) = forces(t0);
            let (d1, r1) = forces(t1);
            // Start time of the sliding part of this substep, if any.
            let mut ts = t0;
            if dir == 0.0 {
                // excess of driving over friction, downslope (+1) and upslope (−1)
                let start = [1.0, -1.0].into_iter().find(|&sg: &f64| sg * d1 - r1 > 0.0);
                let Some(sg) = start else { continue };
                let (e0, e1) = (sg * d0 - r0, sg * d1 - r1);
                if e0 < 0.0 {
                    ts = t0 + h * (-e0 / (e1 - e0));
                }
                dir = sg;
            }
            let tau = t1 - ts;
            let a0 = if ts > t0 {
                let (d, r) = forces(ts);
                d - dir * r
            } else {
                d0 - dir * r0
            };
            let a1 = d1 - dir * r1;
            let v1 = v + tau * (a0 + a1) / 2.0;
            if dir * v1 > 0.0 {
                u += v * tau + tau * tau * (2.0 * a0 + a1) / 6.0;
                v = v1;
            } else {
                // stops inside: v(s) = v + a0 s + (a1 − a0) s²/(2τ) reaches 0
                let vel = |s: f64| v + a0 * s + (a1 - a0) * s * s / (2.0 * tau);
                let (mut lo, mut hi) = (0.0, tau);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if dir * vel(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let s = 0.5 * (lo + hi);
                u += v * s + a0 * s * s / 2.0 + (a1 - a0) * s * s * s / (6.0 * tau);
                v = 0.0;
                dir = 0.0;
            }
        }
        out.push(((k + 1) as f64 * dt, u, v));
    }
    out
}

/// First time the slip magnitude exceeds `threshold`, linearly interpolated
/// between history samples; `None` if it never does.
pub fn onset(history: &[(f64, f64, f64)], threshold: f64) -> Option<f64> {
    let i = history.iter().position(|&(_, u, _)| u.abs() > threshold)?;
    if i == 0 {
        return Some(history[0].0);
    }
    let (ta, ua, _) = history[i - 1];
    let (tb, ub, _) = history[i];
    let (ua, ub) = (ua.abs(), ub.abs());
    Some(ta + (tb - ta) * (threshold - ua) / (ub - ua))
}
