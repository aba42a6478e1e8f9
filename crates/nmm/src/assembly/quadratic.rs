//! Element integrals of the first-order cover basis ([`crate::cover::basis`], order 1),
//! exact: the shape functions are quadratic polynomials, so every integrand is a polynomial
//! of known degree, integrated by exact polygon moments up to degree 4
//! ([`crate::geometry::moments::polygon_moments_upto`]).
//!
//! In the local coordinates s = (x − o)/L of an element (o its first node, L the length of its
//! first edge: s = O(1), so the moments carry no cancellation) the weights are linear,
//! w_k(s) = a_k + ĝ_k · s (ĝ_k = L ∇w_k), the reference position r(s) = Σ_m w_m(s) R_m is
//! linear, and the shapes N_{3k} = w_k, N_{3k+1+i} = w_k (r_i − R_k,i) are quadratic. With
//! the stress linear in the weights, σ(s) = Σ_m w_m(s) σ_m:
//!
//! | integral | integrand degree |
//! |---|---|
//! | stiffness K = ∫ Bᵀ D B dA = Σ D_{v(c,i) v(d,j)} ∫ ∂_i N_a ∂_j N_b ds | 2 |
//! | mass M = ρ ∫ N_a N_b dA | 4 |
//! | body force ∫ ρ N_a dA | 2 |
//! | internal force ∫ Bᵀ σ dA = L Σ σ_m,v(c,i) ∫ w_m ∂_i N_a ds | 2 |
//!
//! (v(c, i) the Voigt index of ∂u_c/∂x_i: v(x, x) = 0, v(y, y) = 1, v(x, y) = v(y, x) = 2.)

// index loops over small fixed blocks read as the formulas they implement
#![allow(clippy::needless_range_loop)]

use crate::cover::basis::reference_triangle;
use crate::cover::ManifoldElement;
use crate::geometry::moments::polygon_moments_upto;
use crate::geometry::{dist, Vec2};
use crate::material::Mat3;

/// A polynomial of degree ≤ 2 in s: coefficients of 1, s_x, s_y, s_x², s_x s_y, s_y².
pub type Quad = [f64; 6];
/// A polynomial of degree ≤ 1 in s: coefficients of 1, s_x, s_y.
pub type Lin = [f64; 3];

/// Exponents (p, q) of the monomials of [`Quad`] (the first three are [`Lin`]'s).
const EXP: [(usize, usize); 6] = [(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)];

/// Voigt index of ∂u_c/∂x_i.
const VOIGT: [[usize; 2]; 2] = [[0, 2], [2, 1]];

/// The nine shape functions of an element in its local coordinates.
#[derive(Debug, Clone, Copy)]
pub struct ElementShapes {
    /// Origin o and scale L of s = (x − o)/L.
    pub origin: Vec2,
    pub scale: f64,
    /// w_k(s).
    pub weights: [Lin; 3],
    /// N_a(s).
    pub n: [Quad; 9],
    /// ∂N_a/∂s_i.
    pub grad: [[Lin; 2]; 9],
}

fn mul(a: &Lin, b: &Lin) -> Quad {
    [
        a[0] * b[0],
        a[0] * b[1] + a[1] * b[0],
        a[0] * b[2] + a[2] * b[0],
        a[1] * b[1],
        a[1] * b[2] + a[2] * b[1],
        a[2] * b[2],
    ]
}

/// The shape functions of element `e` on its current geometry.
pub fn element_shapes(e: &ManifoldElement) -> ElementShapes {
    let o = e.nodes[0];
    let scale = dist(e.nodes[0], e.nodes[1]);
    let g = e.weight_gradients();
    let a = [1.0, 0.0, 0.0];
    let weights: [Lin; 3] = std::array::from_fn(|k| [a[k], scale * g[k][0], scale * g[k][1]]);
    let rf = reference_triangle(e);
    let r: [Lin; 2] = std::array::from_fn(|i| {
        std::array::from_fn(|c| (0..3).map(|m| rf[m][i] * weights[m][c]).sum())
    });
    let mut n = [[0.0; 6]; 9];
    for k in 0..3 {
        let w = &weights[k];
        n[3 * k] = [w[0], w[1], w[2], 0.0, 0.0, 0.0];
        for i in 0..2 {
            let xi = [r[i][0] - rf[k][i], r[i][1], r[i][2]];
            n[3 * k + 1 + i] = mul(w, &xi);
        }
    }
    let grad = n.map(|p| [[p[1], 2.0 * p[3], p[4]], [p[2], p[4], 2.0 * p[5]]]);
    ElementShapes {
        origin: o,
        scale,
        weights,
        n,
        grad,
    }
}

/// Integral (in s) of the product of two polynomials given by coefficients over the first
/// `la`/`lb` monomials of [`EXP`], from the moments `m`.
#[inline]
fn int_product(a: &[f64], b: &[f64], m: &[[f64; 5]; 5]) -> f64 {
    let mut s = 0.0;
    for (i, &ai) in a.iter().enumerate() {
        if ai == 0.0 {
            continue;
        }
        let (p, q) = EXP[i];
        for (j, &bj) in b.iter().enumerate() {
            let (r, t) = EXP[j];
            s += ai * bj * m[p + r][q + t];
        }
    }
    s
}

/// The local record of an element of the first-order basis (see
/// [`crate::cover::CoverBasis::element_local`]): stiffness `k` and mass `m` (18 × 18,
/// row-major), body-force integrals ρ ∫ N_a `body` (9), internal force of the stress with
/// nodal values `stress` `internal` (18).
#[allow(clippy::too_many_arguments)]
pub fn element_local(
    e: &ManifoldElement,
    density0: f64,
    area0: f64,
    d: &Mat3,
    stress: &[[f64; 3]; 3],
    k: &mut [f64],
    m: &mut [f64],
    body: &mut [f64],
    internal: &mut [f64],
) {
    const N: usize = 18;
    let sh = element_shapes(e);
    let l = sh.scale;
    let mo = polygon_moments_upto(&e.polygon, sh.origin, l, 4);
    let area = l * l * mo[0][0];
    let rho = density0 * area0 / area;
    // mass and body force
    for a in 0..9 {
        body[a] = rho * l * l * int_product(&sh.n[a], &[1.0], &mo);
        for b in a..9 {
            let v = rho * l * l * int_product(&sh.n[a], &sh.n[b], &mo);
            for c in 0..2 {
                m[(2 * a + c) * N + 2 * b + c] = v;
                m[(2 * b + c) * N + 2 * a + c] = v;
            }
            for c in 0..2 {
                m[(2 * a + c) * N + 2 * b + 1 - c] = 0.0;
                m[(2 * b + c) * N + 2 * a + 1 - c] = 0.0;
            }
        }
    }
    // stiffness: G^{ij}_ab = ∫ ∂_i N_a ∂_j N_b ds
    for a in 0..9 {
        for b in a..9 {
            let mut gab = [[0.0; 2]; 2];
            for (i, gi) in gab.iter_mut().enumerate() {
                for (j, gij) in gi.iter_mut().enumerate() {
                    *gij = int_product(&sh.grad[a][i], &sh.grad[b][j], &mo);
                }
            }
            for c in 0..2 {
                for dd in 0..2 {
                    let mut v = 0.0;
                    for i in 0..2 {
                        for j in 0..2 {
                            v += d[VOIGT[c][i]][VOIGT[dd][j]] * gab[i][j];
                        }
                    }
                    k[(2 * a + c) * N + 2 * b + dd] = v;
                    k[(2 * b + dd) * N + 2 * a + c] = v;
                }
            }
        }
    }
    // internal force: L Σ_i Σ_m σ_m,v(c,i) ∫ w_m ∂_i N_a ds
    for a in 0..9 {
        let mut wd = [[0.0; 2]; 3];
        for (mm, row) in wd.iter_mut().enumerate() {
            for (i, x) in row.iter_mut().enumerate() {
                *x = int_product(&sh.weights[mm], &sh.grad[a][i], &mo);
            }
        }
        for c in 0..2 {
            let mut f = 0.0;
            for i in 0..2 {
                for (mm, s) in stress.iter().enumerate() {
                    f += s[VOIGT[c][i]] * wd[mm][i];
                }
            }
            internal[2 * a + c] = l * f;
        }
    }
}

/// ∫ w_m w_n dA over the element (for the elastic energy of a stress linear in the weights).
pub fn weight_products(e: &ManifoldElement) -> [[f64; 3]; 3] {
    crate::assembly::local::element_integrals(e).int_ww
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cover::CoverBasis;

    fn element(poly: Vec<Vec2>, triangle: usize, nodes: [Vec2; 3]) -> ManifoldElement {
        ManifoldElement {
            block: 0,
            triangle,
            nodes,
            covers: [0, 1, 2],
            polygon: poly,
        }
    }

    /// The polynomial shapes agree with the basis's point evaluation and gradients.
    #[test]
    fn polynomial_shapes_agree_with_point_evaluation() {
        let h = 0.5;
        let nodes = [[1.0, 2.0], [1.0 + h, 2.0 + h], [1.0, 2.0 + h]];
        // a little deformed: the nodes moved
        let moved = [
            [nodes[0][0] + 0.01, nodes[0][1]],
            [nodes[1][0], nodes[1][1] - 0.02],
            nodes[2],
        ];
        let e = element(moved.to_vec(), 1, moved);
        let sh = element_shapes(&e);
        let mut n = [0.0; 9];
        let mut g = [[0.0; 2]; 9];
        for w in [[0.2, 0.3, 0.5], [1.0, 0.0, 0.0], [0.1, 0.8, 0.1]] {
            let x = [0, 1].map(|c| (0..3).map(|k| w[k] * moved[k][c]).sum::<f64>());
            let s = [
                (x[0] - sh.origin[0]) / sh.scale,
                (x[1] - sh.origin[1]) / sh.scale,
            ];
            let mono = [1.0, s[0], s[1], s[0] * s[0], s[0] * s[1], s[1] * s[1]];
            CoverBasis::Linear.shapes(&e, &w, &mut n);
            CoverBasis::Linear.shape_gradients(&e, &w, &mut g);
            for a in 0..9 {
                let v: f64 = (0..6).map(|i| sh.n[a][i] * mono[i]).sum();
                assert!((v - n[a]).abs() < 1e-14, "{a}: {v} {}", n[a]);
                for i in 0..2 {
                    let d: f64 = (0..3).map(|c| sh.grad[a][i][c] * mono[c]).sum::<f64>() / sh.scale;
                    assert!((d - g[a][i]).abs() < 1e-12, "{a} {i}: {d} {}", g[a][i]);
                }
            }
        }
    }
}
