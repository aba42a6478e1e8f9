//! Newmark time integration with β = 1/2, γ = 1 (as in DDA), the static mode, Rayleigh
//! damping in the step's equations, and the times of the step grid.
//!
//! u_{n+1} = u_n + Δt v_n + ½ Δt² a_{n+1},   v_{n+1} = v_n + Δt a_{n+1}.
//!
//! With the step's unknown Δu = u_{n+1} − u_n:
//! a_{n+1} = (2/Δt²)(Δu − Δt v_n), so the inertia force M a_{n+1} enters the step's
//! equations as (2/Δt²) M Δu − (2/Δt) M v_n, and v_{n+1} = 2 Δu/Δt − v_n.
//!
//! # Damping
//! A viscous force C v_{n+1} (Rayleigh: C = αM + βK, per material, see
//! [`crate::model::Rayleigh`]) is taken at the end of the step, like the inertia force:
//! C v_{n+1} = (2/Δt) C Δu − C v_n. So the step's matrix gains (2/Δt) C
//! ([`damping_coefficient`]) and its right-hand side gains + C v_n:
//!
//! [K + (2/Δt²) M + (2/Δt) C] Δu = f_ext − f_int(σ_n) + (2/Δt) M v_n + C v_n.
//!
//! The static mode (v_n = 0 at every step) has no damping term: damping there would only
//! slow each step's move toward equilibrium.
//!
//! # Dissipation of the scheme, and how it combines with damping
//! The scheme is unconditionally stable and dissipative (γ > ½ adds numerical damping).
//! For a mode ü + 2ζω u̇ + ω²u = 0 (C = αM + βK keeps the modes uncoupled, with
//! 2ζω = α + βω²) each step maps (u, Δt v) by a 2 × 2 matrix whose eigenvalues
//! ρ e^{±iθ} give the amplitude ratio per step ρ and the period 2πΔt/θ:
//! [`amplification_damped`], and the decay per period as a logarithmic decrement
//! δ = −2π ln ρ / θ: [`log_decrement`]. Undamped (ζ = 0) and for Ω = ωΔt ≪ 1,
//! ρ ≈ 1 − Ω²/4, i.e. δ_scheme ≈ πΩ/2 = π² Δt/T (0.25 at 40 steps per period, an
//! amplitude loss of 22% per period). With damping the two add, to first order in both:
//! δ ≈ 2πζ + πΩ/2 (at ζ = 0.05 and 100 steps per period the sum is within 1% of the
//! exact δ, see the tests). The physical decrement 2πζ/√(1 − ζ²) is therefore seen alone
//! only when π² Δt/T is negligible beside it, e.g. at ζ = 0.05 below 1% of it needs
//! T/Δt ≥ 3200.
//!
//! Static mode (DDA's quasi-static analysis) resets the velocity to zero at the start of
//! every step, so each step is a damped move toward equilibrium.
//!
//! # Times
//! The time at the end of step k of a stage that starts at t₀ is t₀ + kΔt, computed by
//! [`grid_time`] from k (never by summing Δt, which drifts: ten steps of 0.1 sum to
//! 0.9999999999999999) and, when t₀ and Δt are short decimals, as the double nearest to the
//! exact decimal t₀ + kΔt (so 3 × 0.1 is 0.3, not 0.30000000000000004).

/// Coefficient of M Δu in the step's equations: 2/Δt².
pub fn mass_coefficient(dt: f64) -> f64 {
    // mutation check (scripts/mutants; never enabled in CI): no inertia
    2.0 / (dt * dt)
        * if cfg!(feature = "mutant-no-mass") {
            0.0
        } else {
            1.0
        }
}

/// Coefficient of M v_n on the right-hand side: 2/Δt.
pub fn velocity_coefficient(dt: f64) -> f64 {
    2.0 / dt
        * if cfg!(feature = "mutant-no-mass") {
            0.0
        } else {
            1.0
        }
}

/// Coefficient of C Δu (the damping matrix) in the step's equations: 2/Δt. (The damping
/// force's share of the right-hand side, + C v_n, has coefficient 1.)
pub fn damping_coefficient(dt: f64) -> f64 {
    2.0 / dt
}

/// v_{n+1} = 2 Δu/Δt − v_n.
pub fn velocity_update(du: f64, v_n: f64, dt: f64) -> f64 {
    2.0 * du / dt - v_n
}

/// a_{n+1} = (2/Δt²)(Δu − Δt v_n).
pub fn acceleration(du: f64, v_n: f64, dt: f64) -> f64 {
    2.0 / (dt * dt) * (du - dt * v_n)
}

/// Spectral radius (amplitude ratio per step) and period elongation ratio T_num/T
/// of this scheme for an undamped oscillator with Ω = ωΔt: [`amplification_damped`] with
/// ζ = 0.
///
/// For ü + ω²u = 0 the step maps (u, Δt v) by the matrix
/// A = [[1 − c, 1 − c], [−2c, 1 − 2c]] with c = Ω²/(2 + Ω²) (from the update formulas
/// above). While its eigenvalues are complex, λ = ρ e^{±iθ}, ρ = √det A = √(1 − c) and
/// T_num = 2πΔt/θ. For Ω > 2 + 2√2 ≈ 4.83 they are real: the motion no longer oscillates
/// at ω, one eigenvalue tends to 0 (the displacement is damped out in a step) and the
/// other to −1 (the velocity flips sign from step to step and decays only by about
/// 2/Ω² per step). Very stiff modes (contact penalties) therefore leave a two-step
/// velocity flutter in dynamic runs; static mode, which resets the velocity, settles a
/// model to rest. The period ratio returned is infinite in that case.
pub fn amplification(omega_dt: f64) -> (f64, f64) {
    amplification_damped(omega_dt, 0.0)
}

/// The step matrix A of the scheme for ü + 2ζω u̇ + ω²u = 0, acting on (u, Δt v), with
/// Ω = ωΔt. The step equation (2/Δt²)(Δu − Δt v) + 2ζω(2Δu/Δt − v) + ω²(u + Δu) = 0 gives
/// Δu = [(2 + 2ζΩ) Δt v − Ω² u] / D with D = 2 + 4ζΩ + Ω², then u' = u + Δu and
/// Δt v' = 2Δu − Δt v.
pub fn step_matrix(omega_dt: f64, zeta: f64) -> [[f64; 2]; 2] {
    let w2 = omega_dt * omega_dt;
    let d = 2.0 + 4.0 * zeta * omega_dt + w2;
    let b = (2.0 + 2.0 * zeta * omega_dt) / d;
    let c = w2 / d;
    [[1.0 - c, b], [-2.0 * c, 2.0 * b - 1.0]]
}

/// The eigenvalues ρ e^{±iθ} of [`step_matrix`] as (ρ, θ), or `None` where they are real
/// (with the larger modulus) and the discrete motion does not oscillate.
fn eigen(omega_dt: f64, zeta: f64) -> Result<(f64, f64), f64> {
    let a = step_matrix(omega_dt, zeta);
    let tr = a[0][0] + a[1][1];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let disc = tr * tr - 4.0 * det;
    if disc >= 0.0 {
        let r = disc.sqrt();
        return Err(((tr - r) / 2.0).abs().max(((tr + r) / 2.0).abs()));
    }
    let rho = det.sqrt();
    Ok((rho, (tr / (2.0 * rho)).clamp(-1.0, 1.0).acos()))
}

/// Spectral radius ρ (amplitude ratio per step) and period ratio T_num/T_d of the scheme
/// for a damped oscillator ü + 2ζω u̇ + ω²u = 0 (ζ < 1) with Ω = ωΔt, from the
/// eigenvalues ρ e^{±iθ} of [`step_matrix`] (T_num = 2πΔt/θ, T_d = 2π/(ω√(1 − ζ²)) the
/// damped period of the exact solution). Where the eigenvalues are real (no oscillation)
/// the period ratio is infinite.
pub fn amplification_damped(omega_dt: f64, zeta: f64) -> (f64, f64) {
    match eigen(omega_dt, zeta) {
        Ok((rho, theta)) => (rho, omega_dt * (1.0 - zeta * zeta).sqrt() / theta),
        Err(rho) => (rho, f64::INFINITY),
    }
}

/// Logarithmic decrement δ = ln(x_k / x_{k+1}) between successive peaks of the scheme's
/// discrete free vibration: δ = −2π ln ρ / θ (ρ e^{±iθ} the eigenvalues of
/// [`step_matrix`]). Infinite where the discrete motion does not oscillate. The exact
/// solution's is [`exact_log_decrement`].
pub fn log_decrement(omega_dt: f64, zeta: f64) -> f64 {
    match eigen(omega_dt, zeta) {
        Ok((rho, theta)) => -std::f64::consts::TAU * rho.ln() / theta,
        Err(_) => f64::INFINITY,
    }
}

/// The exact free vibration's logarithmic decrement 2πζ/√(1 − ζ²) (ζ < 1).
pub fn exact_log_decrement(zeta: f64) -> f64 {
    std::f64::consts::TAU * zeta / (1.0 - zeta * zeta).sqrt()
}

/// Exact powers of ten 10⁰ … 10²² (every one is a double).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// `x` as n × 10^(−e) from its shortest round-trip decimal form, e.g. 0.001 → (1, 3),
/// 2.5 → (25, 1), 300 → (300, 0); `None` if that needs more than 10²² as the scale.
fn decimal(x: f64) -> Option<(i128, u32)> {
    if !x.is_finite() {
        return None;
    }
    let s = format!("{x:e}"); // e.g. "-1.25e-3"
    let (mantissa, exp) = s.split_once('e')?;
    let exp: i32 = exp.parse().ok()?;
    let (int, frac) = mantissa.split_once('.').unwrap_or((mantissa, ""));
    let n: i128 = format!("{int}{frac}").parse().ok()?;
    let scale = frac.len() as i32 - exp;
    if scale >= 0 {
        (scale <= 22).then_some((n, scale as u32))
    } else {
        Some((n.checked_mul(10i128.checked_pow((-scale) as u32)?)?, 0))
    }
}

/// The time t₀ + kΔt at the end of full step `k` of a step grid that starts at `t0`.
///
/// When t₀ and Δt are short decimals (their shortest round-trip forms n₀·10^(−e₀) and
/// n·10^(−e)) and the exact decimal numerator of t₀ + kΔt = N / 10^E fits in 53 bits, the
/// result is the one division N / 10^E of two exact doubles, i.e. the double nearest to
/// the decimal value: `grid_time(0.0, 3, 0.1)` is 0.3 and `grid_time(0.0, 50, 0.001)` is
/// 0.05. Otherwise it is t₀ + k·Δt, rounded once (never a sum over steps).
pub fn grid_time(t0: f64, k: u64, dt: f64) -> f64 {
    let exact = || -> Option<f64> {
        let ((n0, e0), (n, e)) = (decimal(t0)?, decimal(dt)?);
        let big = e0.max(e);
        let a = n0.checked_mul(10i128.checked_pow(big - e0)?)?;
        let b = (k as i128)
            .checked_mul(n)?
            .checked_mul(10i128.checked_pow(big - e)?)?;
        let num = a.checked_add(b)?;
        (num.unsigned_abs() <= 1u128 << 53).then(|| num as f64 / POW10[big as usize])
    };
    exact().unwrap_or(t0 + k as f64 * dt)
}

/// The time at a point inside step k + 1 of the grid that cut steps reach: t₀ + kΔt plus
/// `partial`, the time the halves of Δt covered so far. The cuts halve what remains, so
/// `partial` is m·Δt/2^j; the result is then [`grid_time`]`(t₀, 2^j k + m, Δt/2^j)`, the
/// double nearest the decimal when t₀ and Δt are short decimals (a half of a short decimal
/// is one; halving a double is exact): 1.481, not 1.4809999999999999, at Δt = 2 ms (else
/// one rounding of that product, as grid_time). A `partial` that is no such fraction (m
/// within 10⁻⁶ of an integer, j ≤ 30), or a result more than a few roundings from the sum,
/// gives grid_time + partial.
pub fn cut_time(t0: f64, k: u64, dt: f64, partial: f64) -> f64 {
    let summed = grid_time(t0, k, dt) + partial;
    if partial == 0.0 || dt.is_nan() || dt <= 0.0 {
        return summed;
    }
    let f = partial / dt;
    for j in 1..=30u32 {
        let scaled = f * f64::from(1u32 << j);
        let m = scaled.round();
        if (scaled - m).abs() <= 1e-6 {
            let Some(steps) = k
                .checked_mul(1u64 << j)
                .and_then(|s| s.checked_add(m as u64))
            else {
                return summed;
            };
            let t = grid_time(t0, steps, dt / f64::from(1u32 << j));
            // (the same point: a few roundings apart at most)
            let near = (t - summed).abs() <= 64.0 * f64::EPSILON * summed.abs().max(dt);
            return if near { t } else { summed };
        }
    }
    summed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_acceleration_is_integrated_exactly() {
        // ü = g: Δu from the step equation (2/Δt²)(Δu − Δt v) = g
        let (g, dt) = (-9.81, 0.013);
        let (mut u, mut v) = (0.0, 0.0);
        for _ in 0..100 {
            let du = dt * v + 0.5 * dt * dt * g;
            assert!((acceleration(du, v, dt) - g).abs() < 1e-9);
            v = velocity_update(du, v, dt);
            u += du;
        }
        let t = 100.0 * dt;
        assert!((u - 0.5 * g * t * t).abs() < 1e-12 * (0.5 * g * t * t).abs());
        assert!((v - g * t).abs() < 1e-12);
    }

    #[test]
    fn oscillator_amplification_matches_direct_integration() {
        let (w, dt) = (2.0 * std::f64::consts::PI, 1.0 / 40.0);
        let (mut u, mut v) = (1.0, 0.0);
        let k = mass_coefficient(dt);
        let n = 400;
        for _ in 0..n {
            // (2/Δt²) Δu − (2/Δt) v + ω² (u + Δu) = 0
            let du = (velocity_coefficient(dt) * v - w * w * u) / (k + w * w);
            v = velocity_update(du, v, dt);
            u += du;
        }
        let (rho, _) = amplification(w * dt);
        let amp = (u * u + (v / w).powi(2)).sqrt();
        // amplitude after n steps decays like rho^n (within the phase-dependent wobble)
        let want = rho.powi(n);
        assert!((amp / want - 1.0).abs() < 0.1, "{amp} vs {want}");
        assert!(rho < 1.0);
    }

    #[test]
    fn stiff_modes_keep_a_slowly_decaying_velocity_flutter() {
        // Ω = 100: the displacement is gone after a step, the velocity alternates in sign
        let (w, dt) = (100.0, 1.0);
        let (mut u, mut v) = (0.0, 1.0);
        let k = mass_coefficient(dt);
        let mut vs = Vec::new();
        for _ in 0..10 {
            let du = (velocity_coefficient(dt) * v - w * w * u) / (k + w * w);
            v = velocity_update(du, v, dt);
            u += du;
            vs.push(v);
        }
        assert!(vs.windows(2).all(|p| p[0] * p[1] < 0.0), "{vs:?}");
        let (rho, period) = amplification(w * dt);
        assert!(period.is_infinite() && rho > 0.999 && rho < 1.0);
        assert!((vs[9].abs() / vs[8].abs() - rho).abs() < 1e-3);
    }

    #[test]
    fn undamped_step_matrix_is_the_classic_one() {
        for w in [0.01, 0.3, 1.0, 3.0, 10.0] {
            let c = w * w / (2.0 + w * w);
            let a = step_matrix(w, 0.0);
            let want = [[1.0 - c, 1.0 - c], [-2.0 * c, 1.0 - 2.0 * c]];
            for i in 0..2 {
                for j in 0..2 {
                    assert!((a[i][j] - want[i][j]).abs() < 1e-15, "{w}: {a:?}");
                }
            }
        }
    }

    /// One step of ü + 2ζω u̇ + ω²u = 0 with the step's own equations, the damping terms
    /// as the assembly writes them ((2/Δt) C on the matrix, C v_n on the right-hand side).
    fn damped_step(u: f64, v: f64, w: f64, zeta: f64, dt: f64) -> (f64, f64) {
        let c = 2.0 * zeta * w;
        let lhs = mass_coefficient(dt) + damping_coefficient(dt) * c + w * w;
        let du = (velocity_coefficient(dt) * v + c * v - w * w * u) / lhs;
        (u + du, velocity_update(du, v, dt))
    }

    #[test]
    fn step_matrix_is_the_damped_step() {
        let w = 3.0;
        for (dt, zeta) in [(0.01, 0.0), (0.1, 0.05), (0.5, 0.3), (2.0, 0.9)] {
            let (u, v) = (0.7, -1.3);
            let (u1, v1) = damped_step(u, v, w, zeta, dt);
            let a = step_matrix(w * dt, zeta);
            assert!((a[0][0] * u + a[0][1] * dt * v - u1).abs() < 1e-14);
            assert!((a[1][0] * u + a[1][1] * dt * v - dt * v1).abs() < 1e-14);
        }
    }

    /// Peaks of the directly integrated damped oscillator decay by exp(log_decrement) per
    /// period (400 steps per period: a sampled peak is within 3e-5 of the envelope).
    #[test]
    fn damped_oscillator_decays_by_the_discrete_log_decrement() {
        let w = std::f64::consts::TAU;
        let dt = 1.0 / 400.0;
        for zeta in [0.0, 0.02, 0.1, 0.3] {
            let (mut u, mut v) = (1.0f64, 0.0f64);
            let mut us = vec![u];
            for _ in 0..2400 {
                (u, v) = damped_step(u, v, w, zeta, dt);
                us.push(u);
            }
            let peaks: Vec<f64> = (1..us.len() - 1)
                .filter(|&i| us[i] > us[i - 1] && us[i] >= us[i + 1])
                .map(|i| us[i])
                .collect();
            assert!(peaks.len() >= 3, "ζ = {zeta}: {peaks:?}");
            let want = log_decrement(w * dt, zeta);
            for p in peaks.windows(2) {
                let got = (p[0] / p[1]).ln();
                assert!((got - want).abs() < 1e-4, "ζ = {zeta}: δ {got} vs {want}");
            }
        }
    }

    #[test]
    fn scheme_and_rayleigh_decrements_add_to_first_order() {
        // undamped: δ ≈ πΩ/2
        let o = std::f64::consts::TAU / 400.0;
        let d0 = log_decrement(o, 0.0);
        assert!(
            (d0 / (std::f64::consts::PI * o / 2.0) - 1.0).abs() < 1e-3,
            "{d0}"
        );
        // ζ = 0.05 at 100 steps per period: exact δ within 1% of 2πζ/√(1−ζ²) + πΩ/2
        let o = std::f64::consts::TAU / 100.0;
        let d = log_decrement(o, 0.05);
        let sum = exact_log_decrement(0.05) + std::f64::consts::PI * o / 2.0;
        assert!((d / sum - 1.0).abs() < 0.01, "{d} vs {sum}");
        // and the scheme alone is negligible (< 1%) at 3200 steps per period
        let o = std::f64::consts::TAU / 3200.0;
        let d = log_decrement(o, 0.05);
        assert!((d / exact_log_decrement(0.05) - 1.0).abs() < 0.01, "{d}");
        assert!(d > exact_log_decrement(0.05));
    }

    #[test]
    fn times_inside_a_cut_step_are_the_nearest_doubles_to_the_decimals() {
        // Δt = 2 ms cut in half at step 741, then the second half cut again
        let dt = 0.002;
        let t = grid_time(0.0, 740, dt);
        assert_eq!(t + 0.001, 1.4809999999999999);
        assert_eq!(cut_time(0.0, 740, dt, 0.001), 1.481);
        let quarter = (dt - 0.001) / 2.0;
        assert_eq!(cut_time(0.0, 740, dt, 0.001 + quarter), 1.4815);
        let eighth = (dt - 0.001 - quarter) / 2.0;
        assert_eq!(cut_time(0.0, 740, dt, 0.001 + quarter + eighth), 1.48175);
        // on the grid: grid_time itself
        assert_eq!(cut_time(0.0, 741, dt, 0.0), grid_time(0.0, 741, dt));
        assert_eq!(cut_time(2.5, 7, 0.01, 0.005), 2.575);
        // binary fractions stay as they were
        assert_eq!(cut_time(0.0, 0, 1.0, 0.25), 0.25);
        // a Δt that is no short decimal: t₀ + 7 Δt/2 rounded once, as grid_time does
        let dt = 1.0 / 3.0;
        let t = cut_time(0.0, 3, dt, dt / 2.0);
        assert_eq!(t, 7.0 * (dt / 2.0));
        assert!((t - (grid_time(0.0, 3, dt) + dt / 2.0)).abs() < 1e-15);
        // a partial that is no halving of Δt: the sum
        assert_eq!(
            cut_time(0.0, 740, 0.002, 0.0007),
            grid_time(0.0, 740, 0.002) + 0.0007
        );
    }

    #[test]
    fn grid_times_are_the_nearest_doubles_to_the_decimals() {
        assert_eq!(grid_time(0.0, 3, 0.1), 0.3);
        assert_eq!(grid_time(0.0, 50, 0.001), 0.05);
        assert_eq!(grid_time(0.0, 10, 0.1), 1.0);
        assert_eq!(grid_time(2.5, 7, 0.01), 2.57);
        assert_eq!(grid_time(0.0, 0, 0.001), 0.0);
        assert_eq!(grid_time(-1.0, 3, 0.5), 0.5);
        assert_eq!(grid_time(0.0, 123_456, 1e-5), 1.23456);
        assert_eq!(grid_time(0.0, 4, 1e3), 4000.0);
        // a Δt that is no short decimal: one rounding of t₀ + kΔt
        let dt = 1.0 / 3.0;
        assert_eq!(grid_time(0.0, 3000, dt), 3000.0 * dt);
        let dt = std::f64::consts::PI * 1e-3;
        assert_eq!(grid_time(1.0, 77, dt), 1.0 + 77.0 * dt);
        // summing drifts, the grid does not
        let mut t = 0.0;
        for k in 1..=1000u64 {
            t += 0.001;
            let g = grid_time(0.0, k, 0.001);
            assert_eq!(g, format!("{}", k as f64 / 1000.0).parse::<f64>().unwrap());
        }
        assert_ne!(t, 1.0);
        assert_eq!(grid_time(0.0, 1000, 0.001), 1.0);
    }
}
