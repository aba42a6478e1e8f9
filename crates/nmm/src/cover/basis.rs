//! The cover basis: how the displacement of a manifold element depends on the unknowns.
//! This module is the one place that knows how many unknowns a cover has and how an
//! element's unknowns are laid out; everything else asks it ([`CoverBasis`]).
//!
//! An element carries the covers of its triangle's three nodes (`ELEMENT_COVERS`), with the
//! weight functions w_k (the triangle's barycentric coordinates, a partition of unity). Each
//! cover k carries a cover function u_k(x) of `terms` terms per component:
//!
//! * **order 0** (constant covers, [`CoverBasis::Constant`]): u_k = U_k0 — 2 unknowns;
//! * **order 1** (first-order covers, [`CoverBasis::Linear`]):
//!   u_k(x) = U_k0 + U_k1 ξ_k + U_k2 η_k, (ξ_k, η_k) = (x − x_k)/h — 6 unknowns,
//!
//! and u(x) = Σ_k w_k(x) u_k(x) = Σ_a N_a(x) U_a over the element's scalar shape functions
//! N_a = w_k p_j (a = terms · k + j; p_0 = 1, p_1 = ξ_k, p_2 = η_k). U_k0 is the displacement
//! of node k (w_j(x_k) = δ_jk and ξ_k(x_k) = 0).
//!
//! **Element vector.** Unknown `2 a + c` of an element is component c (x, y) of shape a:
//! order 0 `[u_0x, u_0y, u_1x, u_1y, u_2x, u_2y]`, order 1 `[U_00x, U_00y, U_01x, U_01y,
//! U_02x, U_02y, U_10x, …]`. A cover's unknowns are numbered consecutively in this order
//! (`PhysicalCover::dof` is its U_0x, `PhysicalCover::terms` its higher terms' x unknowns);
//! an unknown that does not exist (a cover of a fixed block, a term removed for linear
//! dependence) is [`NO_DOF`].
//!
//! **Local coordinates.** (ξ_k, η_k) are taken on the element's *reference* triangle — the
//! mesh triangle (R_m = (X_m − X_0)/h, fixed) — through the weights:
//! (ξ_k, η_k) = Σ_m w_m R_m − R_k. On the initial geometry this is (x − x_k)/h exactly; as the
//! element moves, its cover functions ride with the affine motion of its nodes, as its weight
//! functions do. So a material point is its element and its weights, at every order (no
//! position is needed), and a point's shape functions are a function of its weights alone.
//!
//! **Linear dependence (order 1).** Σ_k w_k (x − x_k) ≡ 0, so the first-order basis is
//! linearly dependent: per block (per edge-connected cluster of its elements) the vectors
//! U_k1 = a + c Y_k, U_k2 = b − c X_k (U_k0 = 0, X, Y the nodes in units of h; any a, b, c,
//! per component) give u ≡ 0, a null space of 6 per block shared by the stiffness and the
//! mass. [`super::dependence`] removes exactly that many higher-term unknowns per block, at
//! covers chosen so that the removed unknowns determine the null space: the approximation
//! space is unchanged and the system is regular.

// index loops over small fixed blocks read as the formulas they implement
#![allow(clippy::needless_range_loop)]

use super::{Discretisation, ManifoldElement};
use crate::geometry::Vec2;

/// Covers per manifold element (the triangle's nodes).
pub const ELEMENT_COVERS: usize = 3;
/// Unknowns per element of the constant basis (order 0).
pub const ELEMENT_DOFS: usize = ELEMENT_COVERS * super::COVER_DOFS;

/// Global unknowns of an element of the constant basis, in element-vector order.
pub type ElementDofs = [usize; ELEMENT_DOFS];
/// An element vector of the constant basis (displacements or forces).
pub type ElementVector = [f64; ELEMENT_DOFS];

/// Marks a local unknown that has no global unknown.
pub const NO_DOF: usize = usize::MAX;

/// Most cover-function terms per component of any basis.
pub const MAX_TERMS: usize = 3;
/// Most scalar shape functions of an element of any basis.
pub const MAX_ELEMENT_SHAPES: usize = ELEMENT_COVERS * MAX_TERMS;
/// Most unknowns of an element of any basis (stack buffers).
pub const MAX_ELEMENT_DOFS: usize = 2 * MAX_ELEMENT_SHAPES;

/// The cover functions of a discretisation (`[cover] order`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CoverBasis {
    /// Order 0: constant cover functions, 2 unknowns per cover (constant strain per element).
    #[default]
    Constant,
    /// Order 1: linear cover functions in (x − x_k)/h, 6 unknowns per cover (linear strain
    /// per element; every quadratic displacement field reproduced).
    Linear,
}

impl CoverBasis {
    /// The basis of `[cover] order = n` (`None` for an order that does not exist).
    pub fn from_order(order: usize) -> Option<CoverBasis> {
        match order {
            0 => Some(CoverBasis::Constant),
            1 => Some(CoverBasis::Linear),
            _ => None,
        }
    }

    /// The polynomial order of the cover functions.
    pub fn order(self) -> usize {
        match self {
            CoverBasis::Constant => 0,
            CoverBasis::Linear => 1,
        }
    }

    /// Terms of a cover function per component (1, ξ, η, …).
    #[inline]
    pub fn terms(self) -> usize {
        match self {
            CoverBasis::Constant => 1,
            CoverBasis::Linear => 3,
        }
    }

    /// Unknowns per cover.
    #[inline]
    pub fn cover_dofs(self) -> usize {
        2 * self.terms()
    }

    /// Scalar shape functions per element.
    #[inline]
    pub fn element_shapes(self) -> usize {
        ELEMENT_COVERS * self.terms()
    }

    /// Unknowns per element.
    #[inline]
    pub fn element_dofs(self) -> usize {
        2 * self.element_shapes()
    }

    /// Values of the stress field kept per element: its constant (order 0), or its values at
    /// the triangle's three nodes, the stress being linear in the weights (order 1).
    #[inline]
    pub fn stress_values(self) -> usize {
        match self {
            CoverBasis::Constant => 1,
            CoverBasis::Linear => 3,
        }
    }

    /// The global unknowns of element `e` into `out` (`element_dofs()` of them).
    #[inline]
    pub fn element_dofs_into(self, disc: &Discretisation, e: &ManifoldElement, out: &mut [usize]) {
        if self == CoverBasis::Constant {
            let out: &mut [usize; ELEMENT_DOFS] = (&mut out[..ELEMENT_DOFS]).try_into().unwrap();
            for k in 0..ELEMENT_COVERS {
                let (x, y) = match disc.covers[e.covers[k]].dof {
                    Some(g) => (g, g + 1),
                    None => (NO_DOF, NO_DOF),
                };
                out[2 * k] = x;
                out[2 * k + 1] = y;
            }
            return;
        }
        let t = self.terms();
        let cd = 2 * t;
        for k in 0..ELEMENT_COVERS {
            let cover = &disc.covers[e.covers[k]];
            for j in 0..t {
                let first = match (j, cover.dof) {
                    (_, None) => NO_DOF,
                    (0, Some(g)) => g,
                    (_, Some(_)) => cover.terms.get(j - 1).copied().unwrap_or(NO_DOF),
                };
                for c in 0..2 {
                    out[cd * k + 2 * j + c] = if first == NO_DOF { NO_DOF } else { first + c };
                }
            }
        }
    }

    /// The scalar shape functions N_a of element `e` at weights `w` into `out`
    /// (`element_shapes()` of them).
    #[inline]
    pub fn shapes(self, e: &ManifoldElement, w: &[f64; 3], out: &mut [f64]) {
        match self {
            CoverBasis::Constant => out[..3].copy_from_slice(w),
            CoverBasis::Linear => {
                let rf = reference_triangle(e);
                let r = [
                    w[0] * rf[0][0] + w[1] * rf[1][0] + w[2] * rf[2][0],
                    w[0] * rf[0][1] + w[1] * rf[1][1] + w[2] * rf[2][1],
                ];
                for k in 0..3 {
                    out[3 * k] = w[k];
                    out[3 * k + 1] = w[k] * (r[0] - rf[k][0]);
                    out[3 * k + 2] = w[k] * (r[1] - rf[k][1]);
                }
            }
        }
    }

    /// The gradients ∇N_a (current geometry) of element `e`'s shape functions at weights `w`.
    pub fn shape_gradients(self, e: &ManifoldElement, w: &[f64; 3], out: &mut [Vec2]) {
        let g = e.weight_gradients();
        match self {
            CoverBasis::Constant => out[..3].copy_from_slice(&g),
            CoverBasis::Linear => {
                let rf = reference_triangle(e);
                let r = [
                    w[0] * rf[0][0] + w[1] * rf[1][0] + w[2] * rf[2][0],
                    w[0] * rf[0][1] + w[1] * rf[1][1] + w[2] * rf[2][1],
                ];
                // ∇r_i = Σ_m R_m,i g_m
                let dr = [0, 1].map(|i| {
                    [
                        (0..3).map(|m| rf[m][i] * g[m][0]).sum::<f64>(),
                        (0..3).map(|m| rf[m][i] * g[m][1]).sum::<f64>(),
                    ]
                });
                for k in 0..3 {
                    out[3 * k] = g[k];
                    for i in 0..2 {
                        let xi = r[i] - rf[k][i];
                        out[3 * k + 1 + i] = [
                            g[k][0] * xi + w[k] * dr[i][0],
                            g[k][1] * xi + w[k] * dr[i][1],
                        ];
                    }
                }
            }
        }
    }

    /// The displacement at weights `w` of element `e` from its element vector `ue`.
    #[inline]
    pub fn interpolate(self, e: &ManifoldElement, w: &[f64; 3], ue: &[f64]) -> Vec2 {
        match self {
            CoverBasis::Constant => {
                let mut u = [0.0; 2];
                for k in 0..ELEMENT_COVERS {
                    u[0] += w[k] * ue[2 * k];
                    u[1] += w[k] * ue[2 * k + 1];
                }
                u
            }
            CoverBasis::Linear => {
                let mut n = [0.0; MAX_ELEMENT_SHAPES];
                self.shapes(e, w, &mut n);
                let mut u = [0.0; 2];
                for (a, na) in n[..9].iter().enumerate() {
                    u[0] += na * ue[2 * a];
                    u[1] += na * ue[2 * a + 1];
                }
                u
            }
        }
    }

    /// The direction `d` component of the interpolation at weights `w`: the row r with
    /// d · u(x) = r · u_e, into `out` (`element_dofs()` long).
    #[inline]
    pub fn directional_row(self, e: &ManifoldElement, w: &[f64; 3], d: Vec2, out: &mut [f64]) {
        if self == CoverBasis::Constant {
            out[..ELEMENT_DOFS].copy_from_slice(&directional_row(w, d));
            return;
        }
        let mut n = [0.0; MAX_ELEMENT_SHAPES];
        self.shapes(e, w, &mut n);
        for a in 0..self.element_shapes() {
            out[2 * a] = n[a] * d[0];
            out[2 * a + 1] = n[a] * d[1];
        }
    }

    /// The displacement of the element's node `k` (U_k0) from its element vector.
    #[inline]
    pub fn node_displacement(self, ue: &[f64], k: usize) -> Vec2 {
        let cd = self.cover_dofs();
        [ue[cd * k], ue[cd * k + 1]]
    }

    /// ∂u_i/∂x_j at weights `w` from the element vector `ue` (current geometry).
    pub fn displacement_gradient(
        self,
        e: &ManifoldElement,
        w: &[f64; 3],
        ue: &[f64],
    ) -> [[f64; 2]; 2] {
        match self {
            CoverBasis::Constant => {
                let g = e.weight_gradients();
                let d = |i: usize, j: usize| (0..3).map(|k| g[k][j] * ue[2 * k + i]).sum::<f64>();
                [[d(0, 0), d(0, 1)], [d(1, 0), d(1, 1)]]
            }
            CoverBasis::Linear => {
                let mut g = [[0.0; 2]; MAX_ELEMENT_SHAPES];
                self.shape_gradients(e, w, &mut g);
                let d = |i: usize, j: usize| (0..9).map(|a| g[a][j] * ue[2 * a + i]).sum::<f64>();
                [[d(0, 0), d(0, 1)], [d(1, 0), d(1, 1)]]
            }
        }
    }

    /// The strain (εxx, εyy, γxy) at weights `w` from the element vector `ue`.
    pub fn strain(self, e: &ManifoldElement, w: &[f64; 3], ue: &[f64]) -> [f64; 3] {
        match self {
            CoverBasis::Constant => {
                let ue: &ElementVector = ue[..ELEMENT_DOFS].try_into().expect("element vector");
                crate::assembly::local::strain(&e.weight_gradients(), ue)
            }
            CoverBasis::Linear => {
                let d = self.displacement_gradient(e, w, ue);
                [d[0][0], d[1][1], d[0][1] + d[1][0]]
            }
        }
    }

    /// Length of an element's local record (see [`CoverBasis::element_local`]): its
    /// stiffness and mass (`element_dofs()`² each, row-major), the body-force integrals
    /// ∫ ρ N_a (`element_shapes()`) and the internal force (`element_dofs()`).
    pub fn record_len(self) -> usize {
        let n = self.element_dofs();
        2 * n * n + self.element_shapes() + n
    }

    /// The element's stiffness, consistent mass, body-force integrals and internal force on
    /// its current geometry, exact for the polynomial degree of each integrand, into `out`
    /// (laid out as [`CoverBasis::record_len`] says). The mass is conserved: the density is
    /// `density0 · area0 / A`. `stress`: the element's stress values
    /// ([`CoverBasis::stress_values`]).
    pub fn element_local(
        self,
        e: &ManifoldElement,
        density0: f64,
        area0: f64,
        d: &crate::material::Mat3,
        stress: &[[f64; 3]],
        out: &mut [f64],
    ) {
        let n = self.element_dofs();
        let (k_out, rest) = out.split_at_mut(n * n);
        let (m_out, rest) = rest.split_at_mut(n * n);
        let (b_out, f_out) = rest.split_at_mut(self.element_shapes());
        match self {
            CoverBasis::Constant => {
                use crate::assembly::local;
                let it = local::element_integrals(e);
                // conserved mass: the current density is ρ₀ A₀ / A
                let rho = density0 * area0 / it.area;
                k_out.copy_from_slice(&local::stiffness(it.area, &it.grads, d));
                m_out.copy_from_slice(&local::mass(rho, &it.int_ww, 1.0));
                for i in 0..3 {
                    b_out[i] = rho * it.int_w[i];
                }
                f_out.copy_from_slice(&local::internal_force(it.area, &it.grads, &stress[0]));
            }
            CoverBasis::Linear => {
                crate::assembly::quadratic::element_local(
                    e,
                    density0,
                    area0,
                    d,
                    stress[..3].try_into().expect("three nodal stresses"),
                    k_out,
                    m_out,
                    b_out,
                    f_out,
                );
            }
        }
    }

    /// The displacement of a material point (element `element`, weights `w`) from the global
    /// vector `u` (covers without unknowns contribute zero).
    pub fn displacement_at(
        self,
        disc: &Discretisation,
        element: usize,
        w: &[f64; 3],
        u: &[f64],
    ) -> Vec2 {
        let el = &disc.elements[element];
        match self {
            CoverBasis::Constant => {
                let mut out = [0.0, 0.0];
                for k in 0..3 {
                    if let Some(dof) = disc.covers[el.covers[k]].dof {
                        out[0] += w[k] * u[dof];
                        out[1] += w[k] * u[dof + 1];
                    }
                }
                out
            }
            CoverBasis::Linear => {
                let mut dofs = [NO_DOF; MAX_ELEMENT_DOFS];
                self.element_dofs_into(disc, el, &mut dofs);
                let mut ue = [0.0; MAX_ELEMENT_DOFS];
                crate::assembly::global::gather_into(u, &dofs[..18], &mut ue[..18]);
                self.interpolate(el, w, &ue[..18])
            }
        }
    }
}

/// The global unknowns of every element of a discretisation, in element-vector order
/// (`basis.element_dofs()` per element, [`NO_DOF`] where a local unknown has none).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ElementDofTable {
    stride: usize,
    dofs: Vec<usize>,
    /// How many elements have an unknown (the others lie in fixed blocks).
    free: usize,
}

impl ElementDofTable {
    /// The table of `disc` (its basis's layout).
    pub fn new(disc: &Discretisation) -> ElementDofTable {
        let stride = disc.basis.element_dofs();
        let mut dofs = vec![NO_DOF; stride * disc.elements.len()];
        for (e, out) in disc
            .elements
            .iter()
            .zip(dofs.chunks_exact_mut(stride.max(1)))
        {
            disc.basis.element_dofs_into(disc, e, out);
        }
        let free = dofs
            .chunks_exact(stride.max(1))
            .filter(|d| d.iter().any(|&x| x != NO_DOF))
            .count();
        ElementDofTable { stride, dofs, free }
    }

    /// How many elements have at least one unknown.
    pub fn free_elements(&self) -> usize {
        self.free
    }

    /// The unknowns of element `e`.
    #[inline]
    pub fn of(&self, e: usize) -> &[usize] {
        &self.dofs[e * self.stride..(e + 1) * self.stride]
    }

    /// Unknowns per element.
    #[inline]
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.dofs.len().checked_div(self.stride).unwrap_or(0)
    }

    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// The elements' unknowns in element order.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, usize> {
        self.dofs.chunks_exact(self.stride.max(1))
    }
}

/// The element's reference triangle in units of h, relative to its first node: the mesh
/// triangle's shape ([`super::MathMesh`]: lower-right `(0,0), (1,0), (1,1)` for even
/// triangles, upper-left `(0,0), (1,1), (0,1)` for odd ones).
#[inline]
pub fn reference_triangle(e: &ManifoldElement) -> [Vec2; 3] {
    if e.triangle % 2 == 0 {
        [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]
    } else {
        [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    }
}

/// The global unknowns of element `e` of the constant basis.
pub fn element_dofs(disc: &Discretisation, e: &ManifoldElement) -> ElementDofs {
    let mut d = [NO_DOF; ELEMENT_DOFS];
    CoverBasis::Constant.element_dofs_into(disc, e, &mut d);
    d
}

/// The interpolation rows of the constant basis at a point with weights `w`:
/// u_c(x) = Σ_i n[c][i] u_e[i].
#[inline]
pub fn interpolation(w: &[f64; ELEMENT_COVERS]) -> [ElementVector; 2] {
    let mut n = [[0.0; ELEMENT_DOFS]; 2];
    for k in 0..ELEMENT_COVERS {
        n[0][2 * k] = w[k];
        n[1][2 * k + 1] = w[k];
    }
    n
}

/// The displacement of the constant basis at a point with weights `w` from the element
/// vector `ue`.
#[inline]
pub fn interpolate(w: &[f64; ELEMENT_COVERS], ue: &ElementVector) -> Vec2 {
    let mut u = [0.0; 2];
    for k in 0..ELEMENT_COVERS {
        u[0] += w[k] * ue[2 * k];
        u[1] += w[k] * ue[2 * k + 1];
    }
    u
}

/// The direction `d` component of the constant basis's interpolation at weights `w`.
#[inline]
pub fn directional_row(w: &[f64; ELEMENT_COVERS], d: Vec2) -> ElementVector {
    let mut r = [0.0; ELEMENT_DOFS];
    for k in 0..ELEMENT_COVERS {
        r[2 * k] = w[k] * d[0];
        r[2 * k + 1] = w[k] * d[1];
    }
    r
}

/// Strain–displacement operator B of the constant basis (3 × ELEMENT_DOFS, Voigt order εxx,
/// εyy, γxy) from the weight gradients ∇w_k (constant over the element).
pub fn b_operator(g: &[Vec2; ELEMENT_COVERS]) -> [ElementVector; 3] {
    let mut b = [[0.0; ELEMENT_DOFS]; 3];
    for k in 0..ELEMENT_COVERS {
        b[0][2 * k] = g[k][0];
        b[1][2 * k + 1] = g[k][1];
        b[2][2 * k] = g[k][1];
        b[2][2 * k + 1] = g[k][0];
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_reproduces_nodal_values_and_rows_agree() {
        let ue = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        for w in [[1.0, 0.0, 0.0], [0.2, 0.3, 0.5], [0.0, 0.0, 1.0]] {
            let u = interpolate(&w, &ue);
            let n = interpolation(&w);
            for c in 0..2 {
                let r: f64 = (0..ELEMENT_DOFS).map(|i| n[c][i] * ue[i]).sum();
                assert!((r - u[c]).abs() < 1e-14);
            }
            let d = [0.6, -0.8];
            let row = directional_row(&w, d);
            let r: f64 = (0..ELEMENT_DOFS).map(|i| row[i] * ue[i]).sum();
            assert!((r - (d[0] * u[0] + d[1] * u[1])).abs() < 1e-14);
        }
        assert_eq!(interpolate(&[0.0, 1.0, 0.0], &ue), [3.0, 4.0]);
    }
}
