//! Restitution of impacts: a normal dashpot calibrated against the time integration.
//!
//! An `[[interface]]` with `restitution = e` puts a dashpot beside the normal penalty spring
//! of each of its closed contacts, over the step:
//!
//! t_N = p_N g_N + (c_N/Δt)(g_N − g_N⁰)   while g_N < 0 and t_N < 0 (else the contact is open),
//!
//! with g_N⁰ the gap at the step's start: the force of the mean closing rate over the step,
//! which dissipates c_N (Δg_N)²/Δt ≥ 0 in every step, and is never tensile (the contact
//! opens where the dashpot would pull).
//!
//! **Coefficient.** A contact k between blocks a and b is a one-degree-of-freedom oscillator
//! of stiffness p_N,k and mass m_k = m_a,k m_b,k/(m_a,k + m_b,k), where each block lends
//! the contact the share of its mass that the contact has of the block's normal stiffness,
//! m_a,k = m_a p_N,k / Σ_{contacts of a} p_N (a fixed block: m = ∞). For a block landing
//! on a fixed base on any number of contacts this gives the block's own oscillator: total
//! stiffness K = Σ p_N,k, total damping Σ c_k = 2ζ√(m K). Then c_N,k = 2 ζ √(p_N,k m_k).
//!
//! **Calibration.** The implicit scheme (β = ½, γ = 1) itself dissipates an impact: an
//! undamped contact of Ω = ωΔt = 0.3 already rebounds with e ≈ 0.80, one of Ω = 1 with 0.56.
//! So ζ is not the continuous Kelvin–Voigt ratio for e: for each Ω the ζ is found for which
//! the oscillator, integrated by the solver's own step with the dashpot and the
//! no-tension rule, rebounds with e (the mean over four phases of the first touch within a
//! step) — [`discrete_restitution`], tabulated per e over Ω ∈ [10⁻², 1] by
//! [`DashpotTable`]. Where the scheme alone already rebounds below e (Ω large: a contact
//! resolved in a few steps), no dashpot is added and the impact is as lossy as the step
//! makes it: a smaller Δt or a softer normal penalty restores e.

/// Ω = ωΔt of the table's ends; below the first the continuum limit is reached (the value
/// at 10⁻² is used); beyond the last (a contact resolved in fewer than π steps, whose
/// undamped rebound is already e ≈ 0.5 or less and whose damped one is erratic in ζ) no
/// dashpot is added.
const OMEGA_MIN: f64 = 1e-2;
const OMEGA_MAX: f64 = 1.0;
const POINTS: usize = 41;

/// The rebound ratio v_out / v_in of a unit oscillator (m = 1, k = 1, so ω = 1) hitting
/// at v_in = 1 with the normal dashpot of ratio `zeta` (c = 2ζ) over steps of Δt = `omega_dt`,
/// integrated by the solver's step (Newmark β = ½, γ = 1: a_{n+1} = (2/Δt²)(Δg − Δt v_n),
/// v_{n+1} = 2Δg/Δt − v_n) with the force of the contact law (closed while g < 0 and the
/// force is compressive); the mean over four phases of the first touch within a step.
pub fn discrete_restitution(zeta: f64, omega_dt: f64) -> f64 {
    let dt = omega_dt;
    let d = 2.0 * zeta / dt;
    let mut sum = 0.0;
    const PHASES: [f64; 4] = [0.125, 0.375, 0.625, 0.875];
    for phase in PHASES {
        // start `phase` of a step's travel above the contact, approaching at v = −1
        let (mut g, mut v) = (phase * dt, -1.0f64);
        let max_steps = (20.0 * std::f64::consts::PI / dt) as usize + 100;
        let mut touched = false;
        let mut out = 0.0;
        for _ in 0..max_steps {
            // closed: (2/Δt²)(Δg − Δt v) + g + Δg + d Δg = 0
            let dg_closed = (2.0 / dt * v - g) / (2.0 / (dt * dt) + 1.0 + d);
            let g1 = g + dg_closed;
            let t = g1 + d * dg_closed;
            let dg = if g1 < 0.0 && t < 0.0 {
                touched = true;
                dg_closed
            } else {
                dt * v
            };
            v = 2.0 * dg / dt - v;
            g += dg;
            if touched && g >= 0.0 && v > 0.0 {
                out = v;
                break;
            }
        }
        sum += out;
    }
    sum / PHASES.len() as f64
}

/// The dashpot ratio ζ(Ω) that gives the rebound ratio `e` under the solver's step, on a
/// grid of Ω (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct DashpotTable {
    pub e: f64,
    /// ln Ω of the grid.
    log_omega: Vec<f64>,
    zeta: Vec<f64>,
}

impl DashpotTable {
    /// The table for the restitution `e` (0 < e ≤ 1).
    pub fn new(e: f64) -> DashpotTable {
        let (lo, hi) = (OMEGA_MIN.ln(), OMEGA_MAX.ln());
        let log_omega: Vec<f64> = (0..POINTS)
            .map(|i| lo + (hi - lo) * i as f64 / (POINTS - 1) as f64)
            .collect();
        let zeta = log_omega.iter().map(|l| solve_zeta(e, l.exp())).collect();
        DashpotTable { e, log_omega, zeta }
    }

    /// ζ at Ω = `omega_dt` (linear in ln Ω between the grid points).
    pub fn zeta(&self, omega_dt: f64) -> f64 {
        if omega_dt.is_nan() || omega_dt <= 0.0 {
            return 0.0;
        }
        let l = omega_dt.ln();
        let n = self.log_omega.len();
        if l <= self.log_omega[0] {
            return self.zeta[0];
        }
        if l > self.log_omega[n - 1] {
            return 0.0;
        }
        let step = self.log_omega[1] - self.log_omega[0];
        let i = (((l - self.log_omega[0]) / step) as usize).min(n - 2);
        let s = (l - self.log_omega[i]) / step;
        self.zeta[i] + s * (self.zeta[i + 1] - self.zeta[i])
    }
}

/// ζ ≥ 0 with [`discrete_restitution`](ζ, Ω) = e, by bisection (0 where the scheme alone
/// rebounds below e).
fn solve_zeta(e: f64, omega_dt: f64) -> f64 {
    if e >= 1.0 || omega_dt > OMEGA_MAX || discrete_restitution(0.0, omega_dt) <= e {
        return 0.0;
    }
    // e(ζ) falls from the scheme's own rebound to a least value and rises again (a dashpot
    // far stiffer than the spring bounces the block back itself): stay on the falling branch
    let (mut lo, mut hi) = (0.0, 0.0);
    let mut least = discrete_restitution(0.0, omega_dt);
    loop {
        let next = hi + 0.05;
        let r = discrete_restitution(next, omega_dt);
        if r <= e {
            hi = next;
            break;
        }
        if r >= least || next > 4.0 {
            // e is below the least rebound this dashpot can give: the least one
            return hi;
        }
        least = r;
        lo = next;
        hi = next;
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if discrete_restitution(mid, omega_dt) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The Kelvin–Voigt ratio for the restitution e of a continuous oscillator without the
/// no-tension rule, ζ = −ln e / √(π² + ln² e): the reference the calibration departs from.
pub fn kelvin_voigt_ratio(e: f64) -> f64 {
    let l = e.ln();
    -l / (std::f64::consts::PI.powi(2) + l * l).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Undamped, the scheme's own loss: e → 1 as Ω → 0 (one step's travel resolves the
    /// contact), about e^{−πΩ/4} for small Ω (the scheme's damping ratio Ω/4 over half a
    /// period).
    #[test]
    fn the_scheme_alone_rebounds_below_one_as_its_damping_says() {
        for omega in [0.01, 0.05, 0.1] {
            let e = discrete_restitution(0.0, omega);
            let expected = (-std::f64::consts::PI * omega / 4.0).exp();
            assert!(
                (e - expected).abs() < 0.2 * (1.0 - expected),
                "{omega}: {e} {expected}"
            );
        }
        assert!(discrete_restitution(0.0, 1.0) < 0.6);
    }

    /// The table gives back e through the oscillator it was built on, between its grid
    /// points too (interpolation error), where e is reachable; and 0 where it is not.
    #[test]
    fn the_table_gives_back_its_restitution() {
        for e in [0.2, 0.5, 0.8] {
            let t = DashpotTable::new(e);
            for omega in [0.013, 0.07, 0.31, 0.55] {
                if discrete_restitution(0.0, omega) <= e {
                    // unreachable: (almost) no dashpot, the scheme's own rebound
                    assert!(
                        t.zeta(omega) < 0.01,
                        "e {e}, Ω {omega}: ζ {}",
                        t.zeta(omega)
                    );
                    continue;
                }
                let got = discrete_restitution(t.zeta(omega), omega);
                assert!((got - e).abs() < 0.01, "e {e}, Ω {omega}: {got}");
            }
        }
        // e = 1: no dashpot
        assert_eq!(DashpotTable::new(1.0).zeta(0.1), 0.0);
    }

    /// In the continuum limit (Ω small) the dashpot needed is of the Kelvin–Voigt ratio's
    /// size: the no-tension rule ends the contact early (the dashpot no longer pulls at the
    /// end of the rebound), so a somewhat larger ζ is needed for the same e.
    #[test]
    fn the_continuum_limit_is_near_kelvin_voigt() {
        for e in [0.3, 0.5, 0.8] {
            let z = DashpotTable::new(e).zeta(0.01);
            let kv = kelvin_voigt_ratio(e);
            assert!(z > 0.8 * kv && z < 2.0 * kv, "e {e}: ζ {z} against KV {kv}");
        }
    }
}
