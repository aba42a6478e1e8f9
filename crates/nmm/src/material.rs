//! Linear elasticity: pure functions.
//!
//! Voigt notation with engineering shear strain: ε = [ε_xx, ε_yy, γ_xy],
//! σ = [σ_xx, σ_yy, τ_xy], Δσ = D Δε.
//!
//! Plane strain (ε_zz = 0):
//! D = E / ((1+ν)(1−2ν)) · [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]], σ_zz = ν (σ_xx + σ_yy).
//!
//! Plane stress (σ_zz = 0):
//! D = E / (1−ν²) · [[1, ν, 0], [ν, 1, 0], [0, 0, (1−ν)/2]].

use crate::model::Plane;

pub type Mat3 = [[f64; 3]; 3];

/// Elasticity matrix D (Pa).
pub fn elasticity_matrix(young: f64, poisson: f64, plane: Plane) -> Mat3 {
    let (e, v) = (young, poisson);
    match plane {
        Plane::Strain => {
            let c = e / ((1.0 + v) * (1.0 - 2.0 * v));
            [
                [c * (1.0 - v), c * v, 0.0],
                [c * v, c * (1.0 - v), 0.0],
                [0.0, 0.0, c * (1.0 - 2.0 * v) / 2.0],
            ]
        }
        Plane::Stress => {
            let c = e / (1.0 - v * v);
            [
                [c, c * v, 0.0],
                [c * v, c, 0.0],
                [0.0, 0.0, c * (1.0 - v) / 2.0],
            ]
        }
    }
}

/// σ = D ε.
pub fn stress(d: &Mat3, strain: [f64; 3]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (i, si) in s.iter_mut().enumerate() {
        *si = d[i][0] * strain[0] + d[i][1] * strain[1] + d[i][2] * strain[2];
    }
    s
}

/// Out-of-plane stress σ_zz: ν (σ_xx + σ_yy) in plane strain, 0 in plane stress.
pub fn out_of_plane_stress(poisson: f64, plane: Plane, s: [f64; 3]) -> f64 {
    match plane {
        Plane::Strain => poisson * (s[0] + s[1]),
        Plane::Stress => 0.0,
    }
}

/// Complementary energy density ½ σᵀ D⁻¹ σ of a stress (equal to the strain energy
/// density of the strain it comes from).
pub fn stress_energy_density(d: &Mat3, s: [f64; 3]) -> f64 {
    // D is block diagonal: a 2×2 normal block and the shear term
    let det = d[0][0] * d[1][1] - d[0][1] * d[1][0];
    let ex = (d[1][1] * s[0] - d[0][1] * s[1]) / det;
    let ey = (-d[1][0] * s[0] + d[0][0] * s[1]) / det;
    let g = s[2] / d[2][2];
    0.5 * (s[0] * ex + s[1] * ey + s[2] * g)
}

/// The bilinear form of [`stress_energy_density`]: ½ aᵀ D⁻¹ b (per unit volume), so that the
/// energy of a stress field σ = Σ_m w_m σ_m is ∫ Σ_mn w_m w_n ½ σ_mᵀ D⁻¹ σ_n.
pub fn stress_energy_product(d: &Mat3, a: [f64; 3], b: [f64; 3]) -> f64 {
    let det = d[0][0] * d[1][1] - d[0][1] * d[1][0];
    let ex = (d[1][1] * b[0] - d[0][1] * b[1]) / det;
    let ey = (-d[1][0] * b[0] + d[0][0] * b[1]) / det;
    let g = b[2] / d[2][2];
    0.5 * (a[0] * ex + a[1] * ey + a[2] * g)
}

/// Strain energy density ½ εᵀ D ε (its gradient in ε is σ).
pub fn energy_density(d: &Mat3, strain: [f64; 3]) -> f64 {
    let s = stress(d, strain);
    0.5 * (s[0] * strain[0] + s[1] * strain[1] + s[2] * strain[2])
}

/// P-wave modulus of a bar in uniaxial strain along its axis for the given plane
/// assumption with free lateral faces: E in plane stress, E/(1−ν²) in plane strain.
pub fn bar_modulus(young: f64, poisson: f64, plane: Plane) -> f64 {
    match plane {
        Plane::Stress => young,
        Plane::Strain => young / (1.0 - poisson * poisson),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_stress_closed_form() {
        // Plane stress, σ_xx = s, σ_yy = 0: ε_xx = s/E, ε_yy = −ν s/E.
        let (e, v, s) = (2.0e9, 0.3, 1.0e6);
        let d = elasticity_matrix(e, v, Plane::Stress);
        let sig = stress(&d, [s / e, -v * s / e, 0.0]);
        assert!((sig[0] - s).abs() < 1e-9 * s && sig[1].abs() < 1e-9 * s);
        // Plane strain, σ_yy = 0: ε_xx = s (1−ν²)/E, ε_yy = −ν(1+ν) s/E, σ_zz = ν s.
        let d = elasticity_matrix(e, v, Plane::Strain);
        let sig = stress(&d, [s * (1.0 - v * v) / e, -v * (1.0 + v) * s / e, 0.0]);
        assert!((sig[0] - s).abs() < 1e-9 * s && sig[1].abs() < 1e-9 * s);
        assert!((out_of_plane_stress(v, Plane::Strain, sig) - v * s).abs() < 1e-9 * s);
        // Pure shear: τ = G γ, G = E / (2(1+ν)) in both.
        for plane in [Plane::Strain, Plane::Stress] {
            let d = elasticity_matrix(e, v, plane);
            let g = e / (2.0 * (1.0 + v));
            assert!((stress(&d, [0.0, 0.0, 1e-3])[2] - g * 1e-3).abs() < 1e-6);
        }
    }

    #[test]
    fn stress_is_the_gradient_of_the_energy() {
        let d = elasticity_matrix(7e9, 0.33, Plane::Strain);
        let eps = [1.3e-4, -0.7e-4, 2.1e-4];
        let s = stress(&d, eps);
        for k in 0..3 {
            let h = 1e-8;
            let (mut a, mut b) = (eps, eps);
            a[k] += h;
            b[k] -= h;
            let fd = (energy_density(&d, a) - energy_density(&d, b)) / (2.0 * h);
            assert!(
                (fd - s[k]).abs() < 1e-6 * s[k].abs().max(1.0),
                "{k}: {fd} vs {}",
                s[k]
            );
        }
        assert_eq!(d[0][1], d[1][0]);
    }
}
