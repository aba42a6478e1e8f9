//! The cover basis: how the displacement of a manifold element depends on the unknowns.
//!
//! An element carries the covers of its triangle's three nodes (`ELEMENT_COVERS`); each
//! cover has `COVER_DOFS` unknowns (constant cover functions: u_x, u_y). With the weight
//! functions w_k (the triangle's barycentric coordinates, a partition of unity)
//!
//! u(x) = Σ_k w_k(x) u_k,   ε(x) = Σ_k sym(∇w_k ⊗ u_k) = B u_e,
//!
//! with the element vector u_e = [u_0x, u_0y, u_1x, u_1y, u_2x, u_2y]. Everything that
//! depends on this layout — an element's global unknowns, the interpolation at a point, the
//! B-operator — is here, so that higher-order cover functions change this module only.

use super::{Discretisation, ManifoldElement, COVER_DOFS};
use crate::geometry::Vec2;

/// Covers per manifold element (the triangle's nodes).
pub const ELEMENT_COVERS: usize = 3;
/// Unknowns per manifold element.
pub const ELEMENT_DOFS: usize = ELEMENT_COVERS * COVER_DOFS;

/// Global unknowns of an element, in element-vector order; [`NO_DOF`] for a cover without
/// unknowns (a cover of a fixed block: its displacement is zero).
pub type ElementDofs = [usize; ELEMENT_DOFS];
/// An element vector (displacements or forces).
pub type ElementVector = [f64; ELEMENT_DOFS];

/// Marks a local unknown that has no global unknown.
pub const NO_DOF: usize = usize::MAX;

// Constant cover functions: (u_x, u_y) at `dof`, `dof + 1`.
const _: () = assert!(COVER_DOFS == 2);

/// The global unknowns of element `e`.
pub fn element_dofs(disc: &Discretisation, e: &ManifoldElement) -> ElementDofs {
    let mut d = [NO_DOF; ELEMENT_DOFS];
    for k in 0..ELEMENT_COVERS {
        if let Some(g) = disc.covers[e.covers[k]].dof {
            for c in 0..COVER_DOFS {
                d[COVER_DOFS * k + c] = g + c;
            }
        }
    }
    d
}

/// The interpolation rows at a point with weights `w`: u_c(x) = Σ_i n[c][i] u_e[i].
#[inline]
pub fn interpolation(w: &[f64; ELEMENT_COVERS]) -> [ElementVector; 2] {
    let mut n = [[0.0; ELEMENT_DOFS]; 2];
    for k in 0..ELEMENT_COVERS {
        n[0][COVER_DOFS * k] = w[k];
        n[1][COVER_DOFS * k + 1] = w[k];
    }
    n
}

/// The displacement at a point with weights `w` from the element vector `ue`.
#[inline]
pub fn interpolate(w: &[f64; ELEMENT_COVERS], ue: &ElementVector) -> Vec2 {
    let mut u = [0.0; 2];
    for k in 0..ELEMENT_COVERS {
        u[0] += w[k] * ue[COVER_DOFS * k];
        u[1] += w[k] * ue[COVER_DOFS * k + 1];
    }
    u
}

/// The direction `d` component of the interpolation at weights `w`: the row r with
/// d · u(x) = r · u_e.
#[inline]
pub fn directional_row(w: &[f64; ELEMENT_COVERS], d: Vec2) -> ElementVector {
    let mut r = [0.0; ELEMENT_DOFS];
    for k in 0..ELEMENT_COVERS {
        r[COVER_DOFS * k] = w[k] * d[0];
        r[COVER_DOFS * k + 1] = w[k] * d[1];
    }
    r
}

/// Strain–displacement operator B (3 × ELEMENT_DOFS, Voigt order εxx, εyy, γxy) from the
/// weight gradients ∇w_k.
pub fn b_operator(g: &[Vec2; ELEMENT_COVERS]) -> [ElementVector; 3] {
    let mut b = [[0.0; ELEMENT_DOFS]; 3];
    for k in 0..ELEMENT_COVERS {
        b[0][COVER_DOFS * k] = g[k][0];
        b[1][COVER_DOFS * k + 1] = g[k][1];
        b[2][COVER_DOFS * k] = g[k][1];
        b[2][COVER_DOFS * k + 1] = g[k][0];
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
