//! Newmark time integration with β = 1/2, γ = 1 (as in DDA), and the static mode.
//!
//! u_{n+1} = u_n + Δt v_n + ½ Δt² a_{n+1},   v_{n+1} = v_n + Δt a_{n+1}.
//!
//! With the step's unknown Δu = u_{n+1} − u_n:
//! a_{n+1} = (2/Δt²)(Δu − Δt v_n), so the inertia force M a_{n+1} enters the step's
//! equations as (2/Δt²) M Δu − (2/Δt) M v_n, and v_{n+1} = 2 Δu/Δt − v_n.
//!
//! The scheme is unconditionally stable and dissipative (γ > ½ adds numerical
//! damping): for an undamped oscillator of frequency ω the amplitude ratio per
//! step is |λ| = 1/√(1 + (ωΔt)²/… ) — see [`amplification`] for the exact value.
//! Static mode (DDA's quasi-static analysis) resets the velocity to zero at the
//! start of every step, so each step is a damped move toward equilibrium.

/// Coefficient of M Δu in the step's equations: 2/Δt².
pub fn mass_coefficient(dt: f64) -> f64 {
    2.0 / (dt * dt)
}

/// Coefficient of M v_n on the right-hand side: 2/Δt.
pub fn velocity_coefficient(dt: f64) -> f64 {
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
/// of this scheme for an undamped oscillator with Ω = ωΔt.
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
    let w2 = omega_dt * omega_dt;
    let c = w2 / (2.0 + w2);
    let (a11, a12, a21, a22) = (1.0 - c, 1.0 - c, -2.0 * c, 1.0 - 2.0 * c);
    let tr = a11 + a22;
    let det = a11 * a22 - a12 * a21;
    let disc = tr * tr - 4.0 * det;
    if disc >= 0.0 {
        let r = disc.sqrt();
        let rho = ((tr - r) / 2.0).abs().max(((tr + r) / 2.0).abs());
        return (rho, f64::INFINITY);
    }
    let rho = det.sqrt();
    let theta = (tr / (2.0 * rho)).clamp(-1.0, 1.0).acos();
    (rho, omega_dt / theta)
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
}
