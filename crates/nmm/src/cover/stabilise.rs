//! Stabilisation of physical covers with a tiny support (ghost ties).
//!
//! A physical cover whose support is a sliver — a block edge passing close to a mesh node, a
//! corner just across a mesh line — carries almost no stiffness and almost no mass: its weight
//! ∫ w_c dΩ over the block can be 10⁻⁶ of a full cover's (h²). Its unknowns are then held by
//! almost nothing but the contacts of the boundary points it interpolates, so they can take
//! values far from the motion of the material (and the mesh node, which moves with them,
//! can invert its triangle), and under Newmark β = ½, γ = 1 their stiff-mode flutter never
//! decays (ωΔt ≈ 10⁴).
//!
//! Such a cover c (weight below [`TINY_COVER`] · h²) is tied by a penalty spring to the
//! **linear extrapolation** of a neighbouring element r of the same block whose covers are
//! all well supported (the root; the idea of aggregated cut cells, Badia et al. 2018):
//!
//! u_c ≈ Σ_j λ_j u_{r_j},   λ = barycentric coordinates of c's mesh node in r's triangle,
//!
//! with the energy ½ k_g |u_c − Σ_j λ_j u_{r_j}|², k_g = [`GHOST_STIFFNESS`] · E. At order 1
//! c's constant term (its node's displacement) is tied to the extrapolation of the root's
//! field, u_c0 ≈ Σ_a N_a(λ) U_a, and each higher term to the linear extrapolation of the
//! root covers' same term, U_cj ≈ Σ_i λ_i U_{r_i j}: every quadratic field satisfies them
//! (the higher terms of its representation are affine in the node position), and so does
//! every null vector of the first-order basis ([`super::dependence`]). A linear
//! displacement field satisfies the tie exactly (the extrapolation of a linear field is the
//! field), so the tie costs nothing in the patch test: uniform strain states, rigid motions
//! and everything they verify are unchanged. In a non-uniform field it replaces the sliver's
//! arbitrary cover value by the extrapolation of its neighbour, an error of the order of the
//! discretisation's own.

use super::Discretisation;

/// A cover is tiny when ∫ w_c dΩ over its support is below this fraction of h² (a full
/// interior cover's weight).
pub const TINY_COVER: f64 = 1e-2;

/// Stiffness of a ghost tie as a fraction of the block's Young's modulus (N/m per m; an
/// element's stiffness is of the order of E).
pub const GHOST_STIFFNESS: f64 = 0.1;

/// One tie: cover `cover` follows the linear extrapolation Σ λ_j u_{roots[j]}.
#[derive(Debug, Clone, PartialEq)]
pub struct GhostTie {
    pub cover: usize,
    pub roots: [usize; 3],
    pub lambda: [f64; 3],
    pub block: usize,
    /// The root element (whose covers are `roots`): at order 1 the tie follows its field,
    /// Σ_a N_a(λ) U_a, the extrapolation of the element's (quadratic) displacement.
    pub root: usize,
}

/// The weight ∫ w_c dΩ of every physical cover over its elements.
pub fn cover_weights(d: &Discretisation) -> Vec<f64> {
    let mut w = vec![0.0; d.covers.len()];
    for e in &d.elements {
        let o = e.nodes[0];
        let m = crate::geometry::moments::polygon_moments(&e.polygon, o);
        let g = e.weight_gradients();
        let a = [1.0, 0.0, 0.0];
        for k in 0..3 {
            w[e.covers[k]] += a[k] * m.area + g[k][0] * m.sx + g[k][1] * m.sy;
        }
    }
    w
}

/// The ghost ties of a discretisation: one per tiny cover of a free block that has a
/// well-supported neighbouring element (see the module docs).
pub fn ghost_ties(d: &Discretisation) -> Vec<GhostTie> {
    let h2 = d.mesh.h * d.mesh.h;
    let weights = cover_weights(d);
    let tiny: Vec<bool> = d
        .covers
        .iter()
        .zip(&weights)
        .map(|(c, &w)| c.dof.is_some() && w < TINY_COVER * h2)
        .collect();
    if !tiny.iter().any(|&t| t) {
        return Vec::new();
    }
    // elements of each cover
    let mut of_cover: Vec<Vec<usize>> = vec![Vec::new(); d.covers.len()];
    for (ei, e) in d.elements.iter().enumerate() {
        for &c in &e.covers {
            of_cover[c].push(ei);
        }
    }
    let mut ties = Vec::new();
    for (c, _) in tiny.iter().enumerate().filter(|(_, &t)| t) {
        let node = d.mesh.node(d.covers[c].node);
        // candidates: elements sharing a cover (other than c) with an element of c, not
        // containing c, with every cover well supported; the largest wins
        let mut best: Option<(f64, usize)> = None;
        for &e in &of_cover[c] {
            for &n in d.elements[e].covers.iter().filter(|&&n| n != c) {
                for &r in &of_cover[n] {
                    let el = &d.elements[r];
                    if el.covers.contains(&c) || el.covers.iter().any(|&k| tiny[k]) {
                        continue;
                    }
                    let area = crate::geometry::moments::polygon_area(&el.polygon);
                    if best.is_none_or(|(a, i)| area > a || (area == a && r < i)) {
                        best = Some((area, r));
                    }
                }
            }
        }
        let Some((_, r)) = best else {
            continue;
        };
        let el = &d.elements[r];
        ties.push(GhostTie {
            cover: c,
            roots: el.covers,
            lambda: super::barycentric(&el.nodes, node),
            block: d.covers[c].block,
            root: r,
        });
    }
    ties
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cover::{discretise_on_mesh, MathMesh};

    #[test]
    fn a_block_edge_close_to_a_mesh_line_gets_ties_that_linear_fields_satisfy() {
        let h = 0.1;
        let mesh = MathMesh {
            origin: [-0.25, -0.25],
            h,
            nx: 15,
            ny: 15,
        };
        // the top edge 1e-3 h above the mesh line y = 0.75 leaves covers of tiny support
        let top = 0.75 + 1e-3 * h;
        let block = vec![[0.0, 0.0], [1.0, 0.0], [1.0, top], [0.0, top]];
        let d = discretise_on_mesh(&[(block, false)], mesh).unwrap();
        let ties = ghost_ties(&d);
        assert!(!ties.is_empty());
        let weights = cover_weights(&d);
        for t in &ties {
            assert!(weights[t.cover] < TINY_COVER * h * h);
            // λ reproduces the node from the root's nodes: linear fields satisfy the tie
            let r = d.elements.iter().find(|e| e.covers == t.roots).unwrap();
            let node = d.mesh.node(d.covers[t.cover].node);
            for (c, &nc) in node.iter().enumerate() {
                let x: f64 = (0..3).map(|j| t.lambda[j] * r.nodes[j][c]).sum();
                assert!((x - nc).abs() < 1e-12);
            }
            assert!((t.lambda.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
        // a block whose edges lie far from mesh lines has none
        let block = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.7], [0.0, 0.7]];
        let mesh = MathMesh {
            origin: [-0.25, -0.25],
            h,
            nx: 15,
            ny: 15,
        };
        let d = discretise_on_mesh(&[(block, false)], mesh).unwrap();
        assert!(ghost_ties(&d).is_empty());
    }
}
