//! Crack-tip monitors: the stress intensity factors of a tip from the state of the run.
//!
//! K_I and K_II are the interaction integral of [`crate::fracture`] over the elements of the
//! tip's block that meet the ring `r_in < r < r_out` about the tip, each element with the
//! displacement gradient ∇u of the step at its centroid (constant over the element at
//! order 0; its centroid value at order 1) and the stress D ε(∇u) of its material — the
//! stress of the motion, so that with `[initial_stress]` the in-situ stress, which the
//! faces of a crack present at the start carry as contact forces, is not counted. The
//! reference (initial) geometry is used, as for the strain (small displacements).

use super::Simulation;
use crate::fracture::{stress_intensity_with_faces, FaceForce, TipDomain, TipElement, TipMaterial};
use crate::geometry::{Aabb, Vec2};

/// Distance (× h) from a tip within which the crack faces' traction is taken as the one at
/// that distance ([`crate::fracture::stress_intensity_with_faces`]): past the elements
/// around the tip, whose covers the two faces share.
pub const NEAR_TIP: f64 = 2.0;

impl Simulation {
    /// (K_I, K_II), Pa·√m, of the tip at `tip` of a crack of `block` running along `dir`.
    pub fn stress_intensity(
        &self,
        block: usize,
        tip: Vec2,
        dir: Vec2,
        radii: [f64; 2],
    ) -> [f64; 2] {
        let mat = &self.model.materials[self.model.blocks[block].material];
        let m = TipMaterial {
            young: mat.young,
            poisson: mat.poisson,
            plane: mat.plane,
        };
        let dm = crate::material::elasticity_matrix(mat.young, mat.poisson, mat.plane);
        let ring = Aabb { min: tip, max: tip }.inflate(radii[1]);
        let basis = self.disc.basis;
        let mut ue = [0.0; crate::cover::basis::MAX_ELEMENT_DOFS];
        let fields: Vec<(usize, [f64; 3], [[f64; 2]; 2])> = self.disc.block_elements[block]
            .iter()
            .filter(|&&ei| Aabb::of_points(&self.disc.elements[ei].polygon).overlaps(&ring))
            .map(|&ei| {
                let e = &self.disc.elements[ei];
                let dofs = self.elem_dofs.of(ei);
                let ue = &mut ue[..dofs.len()];
                crate::assembly::global::gather_into(&self.u, dofs, ue);
                let c =
                    crate::geometry::moments::polygon_moments(&e.polygon, e.polygon[0]).centroid();
                let g = basis.displacement_gradient(e, &e.weights(c), ue);
                let s = crate::material::stress(&dm, [g[0][0], g[1][1], g[0][1] + g[1][0]]);
                (ei, s, g)
            })
            .collect();
        let faces = self.face_forces(block, tip, radii[1]);
        stress_intensity_with_faces(
            fields.iter().map(|&(ei, stress, grad)| TipElement {
                polygon: &self.disc.elements[ei].polygon,
                stress,
                grad,
            }),
            &faces,
            NEAR_TIP * self.disc.mesh.h,
            &TipDomain {
                tip,
                dir,
                r_in: radii[0],
                r_out: radii[1],
            },
            &m,
        )
    }

    /// The forces of the contacts on the faces of the crack of `block` that ends at `tip`,
    /// within `reach` of it: on the vertex's face −(t_N n + t_S t), on the facing segment's
    /// the opposite ([`crate::contact::set`]); the face left of the crack's direction (first
    /// point to last) is the upper one (θ = π) when the tip is the crack's last point.
    fn face_forces(&self, block: usize, tip: Vec2, reach: f64) -> Vec<FaceForce> {
        let tol = 1e-9 * reach.max(f64::MIN_POSITIVE);
        let Some(slit) = self.disc.slits.iter().find(|s| {
            let p = &self.disc.cracks[s.crack].points;
            s.block == block
                && (crate::geometry::dist(p[0], tip) <= tol
                    || crate::geometry::dist(p[p.len() - 1], tip) <= tol)
        }) else {
            return Vec::new();
        };
        let pts = &self.disc.cracks[slit.crack].points;
        let tip_is_last = crate::geometry::dist(pts[pts.len() - 1], tip) <= tol;
        let mut out = Vec::new();
        for c in &self.contacts.contacts {
            if c.key.0 != block || c.key.2 != block {
                continue;
            }
            let Some((f, i)) = slit.vertex_of(c.key.1) else {
                continue;
            };
            if crate::geometry::dist(c.position, tip) >= reach {
                continue;
            }
            let (tn, ts) = (c.response.tn, c.response.ts);
            let on_vertex = [
                -(tn * c.normal[0] + ts * c.tangent[0]),
                -(tn * c.normal[1] + ts * c.tangent[1]),
            ];
            // face 0 is left of the crack's direction; upper when the tip is the last point
            let upper_f = (f == 0) == tip_is_last;
            // the contact stands for its vertex's tributary part of the face (half of it:
            // the other face's vertices stand for the other half, contact::set::slits)
            let span = slit_span(&slit.faces[f].vertices, i, self.disc.basis);
            out.push(FaceForce {
                span,
                force: on_vertex,
                upper: upper_f,
            });
            out.push(FaceForce {
                span,
                force: [-on_vertex[0], -on_vertex[1]],
                upper: !upper_f,
            });
        }
        out
    }
}

/// The part of a crack face that vertex `i` stands for (initial positions): the fraction of
/// each adjacent segment its contact integrates (½; ⅓ and ⅔ with midpoints at order 1).
fn slit_span(
    v: &[crate::cover::BoundaryVertex],
    i: usize,
    basis: crate::cover::CoverBasis,
) -> [Vec2; 2] {
    let share = crate::contact::set::tributary_share(
        basis != crate::cover::CoverBasis::Constant,
        v[i].midpoint,
    );
    let x = v[i].x0;
    let a = if i > 0 {
        crate::geometry::lerp(x, v[i - 1].x0, share)
    } else {
        x
    };
    let b = if i + 1 < v.len() {
        crate::geometry::lerp(x, v[i + 1].x0, share)
    } else {
        x
    };
    [a, b]
}
