//! Local (per manifold element) integrals, exact for constant cover functions (order 0;
//! order 1: [`super::quadratic`]). The cover basis ([`crate::cover::basis`]) chooses which.
//!
//! In a manifold element the weight functions are linear,
//! w_i(x) = a_i + g_i · (x − o) with g_i = ∇w_i and o the element's first mesh node
//! (so a = [1, 0, 0]), and u(x) = Σ_i w_i(x) u_i. The unknowns of the element are
//! ordered `[u_0x, u_0y, u_1x, u_1y, u_2x, u_2y]`.
//!
//! * strain ε = B u_e with B = [B_0 B_1 B_2], B_i = [[g_ix, 0], [0, g_iy], [g_iy, g_ix]]:
//!   constant over the element, so the stiffness is exactly K_e = A Bᵀ D B;
//! * consistent mass M_ij = ρ ∫ w_i w_j dΩ · I₂, a quadratic integrand, exact from the
//!   polygon moments ∫1, ∫(x−o), ∫(x−o)(x−o)ᵀ (Green's theorem);
//! * body force f_i = ρ b ∫ w_i dΩ;
//! * internal force of a stress σ (constant per element): f_e = A Bᵀ σ.

use crate::cover::ManifoldElement;
use crate::geometry::{moments::polygon_moments, Vec2};
use crate::material::Mat3;

/// The integrals of one manifold element on its current geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementIntegrals {
    /// Area A = ∫ dΩ.
    pub area: f64,
    /// ∇w_i (constant).
    pub grads: [Vec2; 3],
    /// ∫ w_i dΩ.
    pub int_w: [f64; 3],
    /// ∫ w_i w_j dΩ.
    pub int_ww: [[f64; 3]; 3],
}

/// Integrals of the weight functions over the element polygon.
pub fn element_integrals(e: &ManifoldElement) -> ElementIntegrals {
    let o = e.nodes[0];
    let m = polygon_moments(&e.polygon, o);
    let g = e.weight_gradients();
    let a = [1.0, 0.0, 0.0];
    let s1 = [m.sx, m.sy];
    let mut int_w = [0.0; 3];
    let mut int_ww = [[0.0; 3]; 3];
    for i in 0..3 {
        int_w[i] = a[i] * m.area + g[i][0] * s1[0] + g[i][1] * s1[1];
        for j in 0..3 {
            let gi_s2_gj = g[i][0] * (m.sxx * g[j][0] + m.sxy * g[j][1])
                + g[i][1] * (m.sxy * g[j][0] + m.syy * g[j][1]);
            int_ww[i][j] = a[i] * a[j] * m.area
                + a[i] * (g[j][0] * s1[0] + g[j][1] * s1[1])
                + a[j] * (g[i][0] * s1[0] + g[i][1] * s1[1])
                + gi_s2_gj;
        }
    }
    ElementIntegrals {
        area: m.area,
        grads: g,
        int_w,
        int_ww,
    }
}

/// Strain-displacement matrix B (3 × 6) of the constant basis: the basis's own
/// ([`crate::cover::basis::b_operator`]).
pub fn b_matrix(g: &[Vec2; 3]) -> [[f64; 6]; 3] {
    crate::cover::basis::b_operator(g)
}

/// ε = B u_e.
pub fn strain(g: &[Vec2; 3], ue: &[f64; 6]) -> [f64; 3] {
    let b = b_matrix(g);
    let mut e = [0.0; 3];
    for (k, ek) in e.iter_mut().enumerate() {
        *ek = (0..6).map(|c| b[k][c] * ue[c]).sum();
    }
    e
}

/// K_e = A Bᵀ D B (6 × 6, row-major).
pub fn stiffness(area: f64, g: &[Vec2; 3], d: &Mat3) -> [f64; 36] {
    let b = b_matrix(g);
    let mut db = [[0.0; 6]; 3];
    for r in 0..3 {
        for c in 0..6 {
            db[r][c] = (0..3).map(|k| d[r][k] * b[k][c]).sum();
        }
    }
    let mut k = [0.0; 36];
    for i in 0..6 {
        for j in 0..6 {
            k[i * 6 + j] = area * (0..3).map(|r| b[r][i] * db[r][j]).sum::<f64>();
        }
    }
    k
}

/// Consistent mass ρ ∫ w_i w_j dΩ · I₂ (6 × 6, row-major), scaled by `factor`.
pub fn mass(density: f64, int_ww: &[[f64; 3]; 3], factor: f64) -> [f64; 36] {
    let mut m = [0.0; 36];
    for i in 0..3 {
        for j in 0..3 {
            let v = factor * density * int_ww[i][j];
            m[(2 * i) * 6 + 2 * j] = v;
            m[(2 * i + 1) * 6 + 2 * j + 1] = v;
        }
    }
    m
}

/// f_e = A Bᵀ σ.
pub fn internal_force(area: f64, g: &[Vec2; 3], sigma: &[f64; 3]) -> [f64; 6] {
    let b = b_matrix(g);
    let mut f = [0.0; 6];
    for (c, fc) in f.iter_mut().enumerate() {
        *fc = area * (0..3).map(|k| b[k][c] * sigma[k]).sum::<f64>();
    }
    f
}

/// Body force ρ b ∫ w_i dΩ for an acceleration field b (m/s²).
pub fn body_force(density: f64, int_w: &[f64; 3], b: Vec2) -> [f64; 6] {
    let mut f = [0.0; 6];
    for i in 0..3 {
        f[2 * i] = density * b[0] * int_w[i];
        f[2 * i + 1] = density * b[1] * int_w[i];
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{elasticity_matrix, energy_density};
    use crate::model::Plane;

    fn element(poly: Vec<Vec2>) -> ManifoldElement {
        ManifoldElement {
            block: 0,
            triangle: 0,
            nodes: [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            covers: [0, 1, 2],
            polygon: poly,
        }
    }

    #[test]
    fn full_triangle_integrals_match_closed_forms() {
        let e = element(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        let it = element_integrals(&e);
        assert!((it.area - 0.5).abs() < 1e-15);
        // ∫ w_i = A/3, ∫ w_i² = A/6, ∫ w_i w_j = A/12
        for i in 0..3 {
            assert!((it.int_w[i] - 0.5 / 3.0).abs() < 1e-15);
            for j in 0..3 {
                let want = if i == j { 0.5 / 6.0 } else { 0.5 / 12.0 };
                assert!((it.int_ww[i][j] - want).abs() < 1e-15, "{i}{j}");
            }
        }
    }

    #[test]
    fn cut_element_partition_of_unity_and_mass() {
        // A quadrilateral piece of the triangle.
        let e = element(vec![[0.0, 0.0], [0.6, 0.0], [0.3, 0.5], [0.0, 0.5]]);
        let it = element_integrals(&e);
        let a = it.area;
        assert!((it.int_w.iter().sum::<f64>() - a).abs() < 1e-14);
        let tot: f64 = it.int_ww.iter().flatten().sum();
        assert!((tot - a).abs() < 1e-14);
        // ∫ w_1 = ∫ x over the polygon (w_1 = x for this triangle)
        let m = polygon_moments(&e.polygon, [0.0, 0.0]);
        assert!((it.int_w[1] - m.sx).abs() < 1e-15);
        assert!((it.int_ww[1][1] - m.sxx).abs() < 1e-15);
    }

    #[test]
    fn stiffness_is_the_hessian_of_the_energy_and_kills_rigid_modes() {
        let e = element(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
        let it = element_integrals(&e);
        let d = elasticity_matrix(1e9, 0.25, Plane::Strain);
        let k = stiffness(it.area, &it.grads, &d);
        let u = [1e-3, -2e-3, 0.5e-3, 1e-3, -1e-3, 0.2e-3];
        // f = K u equals the gradient of A·W(ε(u)) (finite differences)
        for c in 0..6 {
            let h = 1e-7;
            let (mut up, mut um) = (u, u);
            up[c] += h;
            um[c] -= h;
            let fd = it.area
                * (energy_density(&d, strain(&it.grads, &up))
                    - energy_density(&d, strain(&it.grads, &um)))
                / (2.0 * h);
            let ku: f64 = (0..6).map(|j| k[c * 6 + j] * u[j]).sum();
            assert!((fd - ku).abs() < 1e-6 * ku.abs().max(1.0), "{c}: {fd} {ku}");
            // and K u = A Bᵀ D B u = internal_force(σ(ε(u)))
            let f = internal_force(
                it.area,
                &it.grads,
                &crate::material::stress(&d, strain(&it.grads, &u)),
            );
            assert!((f[c] - ku).abs() < 1e-6 * ku.abs().max(1.0));
        }
        // translations and the infinitesimal rotation produce no force
        let nodes = e.nodes;
        for mode in [[1.0, 0.0], [0.0, 1.0], [f64::NAN, f64::NAN]] {
            let mut ue = [0.0; 6];
            for i in 0..3 {
                let (x, y) = (nodes[i][0], nodes[i][1]);
                let v = if mode[0].is_nan() { [-y, x] } else { mode };
                ue[2 * i] = v[0];
                ue[2 * i + 1] = v[1];
            }
            for r in 0..6 {
                let f: f64 = (0..6).map(|j| k[r * 6 + j] * ue[j]).sum();
                assert!(f.abs() < 1e-6, "{f}");
            }
        }
    }
}
