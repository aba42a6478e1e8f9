//! The axial law of a rock bolt: elastic–perfectly plastic, by return mapping. Pure
//! functions of numbers (no NMM), tested against their closed form and their tangent
//! against finite differences.
//!
//! **Variables.** δ: the elongation, the change of the anchors' distance since the bolt was
//! installed (m, lengthening positive); p: the plastic elongation (m), the state; N: the
//! axial force (N per metre of thickness, **tension positive**); k: the axial stiffness
//! (N/m); F_y: the capacity (N).
//!
//! **Law.** N = k (δ − p), |N| ≤ F_y. A pretension N₀ is a plastic elongation at
//! installation, p₀ = −N₀/k (the bolt's stress-free length is N₀/k shorter than the
//! anchors' distance), so that N = N₀ at δ = 0 (0 ≤ N₀ ≤ F_y).
//!
//! **Return mapping** from the committed p_n, at a trial elongation δ:
//! * trial N* = k (δ − p_n);
//! * |N*| ≤ F_y: **elastic**, N = N*, p = p_n, ∂N/∂δ = k;
//! * N* > F_y: **tension yield**, N = F_y, p = δ − F_y/k, ∂N/∂δ = 0;
//! * N* < −F_y: **compression yield**, N = −F_y, p = δ + F_y/k, ∂N/∂δ = 0.
//!
//! On each branch N is affine in δ (the piecewise-affine systems of
//! [`crate::solver::newton`]); it is continuous at the kinks |N*| = F_y, which belong to
//! the elastic branch.
//!
//! **Compression.** The same capacity in compression. A grouted bar's steel yields at
//! about the same force in both senses; an elastic compression branch would let a
//! slender bar carry unlimited thrust (it buckles long before), and a bolt without any
//! compressive stiffness (a cable) would make the member unilateral, with a kink and no
//! stiffness at zero force exactly where a pretension of zero installs it. One yield
//! function |N| ≤ F_y keeps one return mapping, and a bolt that yielded in tension
//! unloads elastically through zero with its own stiffness.
//!
//! **Energy.** Stored: ½ k (δ − p)² = ½ N²/k. Dissipated over an increment of p:
//! N Δp ≥ 0 (on a yield branch Δp has the sign of N).

/// A bolt's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoltParams {
    /// Axial stiffness k, N/m (> 0).
    pub stiffness: f64,
    /// Capacity F_y, N (> 0): the yield force in tension and in compression.
    pub capacity: f64,
}

/// The branch of the law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BoltBranch {
    #[default]
    Elastic,
    /// N = F_y.
    Tension,
    /// N = −F_y.
    Compression,
}

impl BoltBranch {
    /// Whether the branch is a yield branch.
    pub fn yielding(self) -> bool {
        self != BoltBranch::Elastic
    }
}

/// The law's answer at an elongation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoltResponse {
    /// Axial force N (tension positive).
    pub force: f64,
    /// ∂N/∂δ on the branch (k or 0).
    pub tangent: f64,
    /// The plastic elongation after the increment.
    pub plastic: f64,
    pub branch: BoltBranch,
}

impl BoltParams {
    /// The plastic elongation of a bolt installed with the force `pretension` (N₀):
    /// p₀ = −N₀/k.
    pub fn installed_plastic(&self, pretension: f64) -> f64 {
        -pretension / self.stiffness
    }

    /// The law's own branch at elongation `delta` from the committed plastic elongation
    /// `plastic` (the kinks |N*| = F_y are elastic).
    pub fn branch(&self, plastic: f64, delta: f64) -> BoltBranch {
        let trial = self.stiffness * (delta - plastic);
        if trial > self.capacity {
            BoltBranch::Tension
        } else if trial < -self.capacity {
            BoltBranch::Compression
        } else {
            BoltBranch::Elastic
        }
    }

    /// The response on branch `b` (affine in `delta`), from the committed `plastic`.
    pub fn on_branch(&self, plastic: f64, delta: f64, b: BoltBranch) -> BoltResponse {
        let (k, fy) = (self.stiffness, self.capacity);
        match b {
            BoltBranch::Elastic => BoltResponse {
                force: k * (delta - plastic),
                tangent: k,
                plastic,
                branch: b,
            },
            BoltBranch::Tension => BoltResponse {
                force: fy,
                tangent: 0.0,
                plastic: delta - fy / k,
                branch: b,
            },
            BoltBranch::Compression => BoltResponse {
                force: -fy,
                tangent: 0.0,
                plastic: delta + fy / k,
                branch: b,
            },
        }
    }

    /// The return mapping: the response on the law's own branch.
    pub fn response(&self, plastic: f64, delta: f64) -> BoltResponse {
        self.on_branch(plastic, delta, self.branch(plastic, delta))
    }

    /// The elastic energy ½ k (δ − p)² = ½ N²/k of a bolt with force `force`.
    pub fn stored_energy(&self, force: f64) -> f64 {
        0.5 * force * force / self.stiffness
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: BoltParams = BoltParams {
        stiffness: 2.0e7,
        capacity: 1.0e5,
    };
    /// The yield elongation F_y/k = 5 mm.
    const DY: f64 = 5.0e-3;

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-12 * scale
    }

    #[test]
    fn below_the_capacity_the_bolt_is_a_linear_spring() {
        for delta in [-4.0e-3, -1.0e-3, 0.0, 2.0e-3, 4.999e-3] {
            let r = P.response(0.0, delta);
            assert_eq!(r.branch, BoltBranch::Elastic);
            assert!(close(r.force, P.stiffness * delta, P.capacity), "{r:?}");
            assert_eq!(r.tangent, P.stiffness);
            assert_eq!(r.plastic, 0.0);
        }
        // the kink belongs to the elastic branch: N = F_y exactly, no plastic flow
        let r = P.response(0.0, DY);
        assert_eq!(r.branch, BoltBranch::Elastic);
        assert!(close(r.force, P.capacity, P.capacity));
    }

    #[test]
    fn in_tension_it_yields_at_the_capacity_and_keeps_the_plastic_elongation() {
        // loading to 12 mm: N = F_y, p = 12 − 5 = 7 mm
        let r = P.response(0.0, 12.0e-3);
        assert_eq!(r.branch, BoltBranch::Tension);
        assert_eq!(r.force, P.capacity);
        assert_eq!(r.tangent, 0.0);
        assert!(close(r.plastic, 7.0e-3, DY), "{r:?}");
        // unloading to 10 mm from that state: elastic, N = k (10 − 7) mm = 0.6 F_y
        let u = P.response(r.plastic, 10.0e-3);
        assert_eq!(u.branch, BoltBranch::Elastic);
        assert!(close(u.force, 0.6 * P.capacity, P.capacity), "{u:?}");
        assert_eq!(u.plastic, r.plastic);
        // through zero force at δ = p into compression, yielding at −F_y at δ = p − 5 mm
        assert!(close(P.response(r.plastic, 7.0e-3).force, 0.0, P.capacity));
        let c = P.response(r.plastic, 1.0e-3);
        assert_eq!(c.branch, BoltBranch::Compression);
        assert_eq!(c.force, -P.capacity);
        assert!(close(c.plastic, 6.0e-3, DY), "{c:?}");
    }

    #[test]
    fn compression_has_the_same_capacity() {
        let r = P.response(0.0, -8.0e-3);
        assert_eq!(r.branch, BoltBranch::Compression);
        assert_eq!(r.force, -P.capacity);
        assert!(close(r.plastic, -3.0e-3, DY), "{r:?}");
        // the law is odd: N(−δ; −p) = −N(δ; p)
        for (p, d) in [(0.0, 3.0e-3), (1.0e-3, 9.0e-3), (-2.0e-3, 1.0e-3)] {
            let a = P.response(p, d);
            let b = P.response(-p, -d);
            assert_eq!(a.force, -b.force);
            assert_eq!(a.plastic, -b.plastic);
        }
    }

    #[test]
    fn a_pretension_is_the_force_at_installation() {
        let n0 = 0.3 * P.capacity;
        let p0 = P.installed_plastic(n0);
        assert!(close(P.response(p0, 0.0).force, n0, P.capacity));
        // it yields after F_y − N₀ more of force: at δ = (F_y − N₀)/k
        let dy = (P.capacity - n0) / P.stiffness;
        assert_eq!(P.branch(p0, dy * (1.0 - 1e-9)), BoltBranch::Elastic);
        assert_eq!(P.branch(p0, dy * (1.0 + 1e-9)), BoltBranch::Tension);
        // a pretension at the capacity installs it on the kink
        let p = P.installed_plastic(P.capacity);
        assert_eq!(P.branch(p, 0.0), BoltBranch::Elastic);
        assert!(close(P.response(p, 0.0).force, P.capacity, P.capacity));
    }

    #[test]
    fn the_force_is_continuous_and_the_dissipation_nonnegative() {
        // along a cyclic path the force never leaves [−F_y, F_y], is continuous in δ, and
        // every committed increment of p dissipates N Δp ≥ 0
        let mut p = P.installed_plastic(0.2 * P.capacity);
        let path: Vec<f64> = (0..=400)
            .map(|i| 12.0e-3 * (i as f64 * std::f64::consts::TAU / 150.0).sin())
            .collect();
        let mut last: Option<f64> = None;
        for d in path {
            let r = P.response(p, d);
            assert!(r.force.abs() <= P.capacity * (1.0 + 1e-15), "{r:?}");
            if let Some(f) = last {
                // an increment of δ of at most 0.51 mm changes N by at most k × that
                assert!(
                    (r.force - f).abs() <= P.stiffness * 0.51e-3 + 1e-6,
                    "{f} → {r:?}"
                );
            }
            assert!(r.force * (r.plastic - p) >= 0.0, "{r:?}");
            p = r.plastic;
            last = Some(r.force);
        }
    }

    /// The tangent on every branch against central differences of the force on that
    /// branch, and of the return mapping itself away from the kinks.
    #[test]
    fn the_tangent_is_the_derivative_of_the_force() {
        let h = 1.0e-9;
        for p in [0.0, 4.0e-3, -6.0e-3] {
            for d in [-20.0e-3, -8.0e-3, -2.0e-3, 0.5e-3, 3.0e-3, 7.0e-3, 15.0e-3] {
                let r = P.response(p, d);
                let fd = (P.response(p, d + h).force - P.response(p, d - h).force) / (2.0 * h);
                // away from the kinks (|N*| = F_y, within 2h of δ) the law is smooth
                let trial = P.stiffness * (d - p);
                if (trial.abs() - P.capacity).abs() > 2.0 * h * P.stiffness {
                    assert!(
                        (fd - r.tangent).abs() <= 1e-6 * P.stiffness,
                        "p {p} δ {d}: {fd} vs {}",
                        r.tangent
                    );
                }
                for b in [
                    BoltBranch::Elastic,
                    BoltBranch::Tension,
                    BoltBranch::Compression,
                ] {
                    let t = P.on_branch(p, d, b).tangent;
                    let fd = (P.on_branch(p, d + h, b).force - P.on_branch(p, d - h, b).force)
                        / (2.0 * h);
                    assert!((fd - t).abs() <= 1e-6 * P.stiffness, "{b:?}: {fd} vs {t}");
                }
            }
        }
    }

    #[test]
    fn the_stored_energy_is_half_n_squared_over_k() {
        let r = P.response(1.0e-3, 4.0e-3);
        let e = 0.5 * P.stiffness * (4.0e-3 - 1.0e-3f64).powi(2);
        assert!(close(P.stored_energy(r.force), e, e));
    }
}
