//! Contacts of a block with itself across a crack: each face of a slit
//! ([`crate::cover::slit`]) against the other face.
//!
//! The narrow phase is the crack's own, not the polygon one of [`super::super::narrow`]
//! (a slit has no inside): every vertex P of one face is paired with the segment of the
//! other face nearest to it (the point of the segment nearest to P, ties to the first
//! segment), with that segment's outward normal n — pointing from the other face's
//! material into the crack, towards P's side — and its unit direction t. The gap
//! g = (P − Q₀)·n (Q₀ the segment's start) is the opening (negative: the faces
//! interpenetrate); the pair is a contact when g ∈ [−search, search] and P's projection lies
//! on the segment within half its length beyond either end (at a kink of the crack a vertex
//! may project just past the ends of both segments there).
//!
//! A face vertex and its facing segment in the same element (at a tip, the element holding
//! it is not split: there the faces carry no jump) have no relative motion and make no
//! contact. Everything else — the kinematics, the tributary weights (half the face's
//! length on either side of the vertex, ½ of each adjacent segment, ⅓/⅔ with the midpoints
//! of first-order covers; both faces are taken, each vertex with half its tributary length,
//! as for two blocks), the interface (the crack's joint, else the block's own pair, else
//! the default), the law and its state — is that of a contact between two blocks; the key
//! is (block, contact-vertex number of the face vertex, block), the face vertices numbered
//! after the block's boundary vertices ([`crate::cover::Slit::first`]).

use super::{contact_rows, ContactSet, NewContact};
use crate::contact::InterfaceView;
use crate::cover::{barycentric, Discretisation, Slit};
use crate::geometry::{dist, dot, lerp, norm, sub, Vec2};

/// A vertex against its nearest segment of the other face: (segment, ξ ∈ [0, 1] of the
/// nearest point, unclamped ξ, gap along the segment's outward normal, normal, tangent).
type Facing = (usize, f64, f64, f64, Vec2, Vec2);

/// The segment of `face` (current points) nearest to `p` ([`Facing`]), the outward normal
/// that of face `side` (+1: face 0, −1: face 1).
fn nearest_segment(p: Vec2, face: &[Vec2], side: f64) -> Option<Facing> {
    let mut best: Option<(f64, Facing)> = None;
    for j in 0..face.len().saturating_sub(1) {
        let (a, b) = (face[j], face[j + 1]);
        let d = sub(b, a);
        let len = norm(d);
        if len == 0.0 {
            continue;
        }
        let t = [d[0] / len, d[1] / len];
        // outward normal of face 0 (material on the left): right of its direction; of
        // face 1: left
        let n = [side * t[1], -side * t[0]];
        let xi = dot(sub(p, a), t) / len;
        let xc = xi.clamp(0.0, 1.0);
        let dd = dist(p, lerp(a, b, xc));
        if best.as_ref().is_none_or(|(bd, _)| dd < *bd) {
            best = Some((dd, (j, xc, xi, dot(sub(p, a), n), n, t)));
        }
    }
    best.map(|(_, r)| r)
}

impl ContactSet {
    /// The contacts of the blocks' crack faces with each other (module doc).
    pub(super) fn detect_slits(
        &mut self,
        disc: &Discretisation,
        model: &dyn InterfaceView,
        u: &[f64],
        search: f64,
        density: f64,
        has_midpoints: bool,
    ) {
        for s in &disc.slits {
            let b = s.block;
            if model.is_fixed(b) || self.removed(b) {
                continue;
            }
            let Some(iface) = model.interface_for_face(b, b, Some(s.joint)) else {
                continue;
            };
            let cur: [Vec<Vec2>; 2] =
                std::array::from_fn(|f| disc.current_positions(&s.faces[f].vertices, u));
            for f in 0..2 {
                let g = 1 - f;
                // the outward normal of face g: face 0's is right of the crack's direction
                let side_g = if g == 0 { 1.0 } else { -1.0 };
                self.face_contacts(
                    disc,
                    model,
                    s,
                    (f, g),
                    &cur,
                    side_g,
                    search,
                    density,
                    has_midpoints,
                    iface,
                );
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn face_contacts(
        &mut self,
        disc: &Discretisation,
        model: &dyn InterfaceView,
        s: &Slit,
        (f, g): (usize, usize),
        cur: &[Vec<Vec2>; 2],
        side_g: f64,
        search: f64,
        density: f64,
        has_midpoints: bool,
        iface: &crate::model::Interface,
    ) {
        let b = s.block;
        let (fv, gv) = (&s.faces[f].vertices, &s.faces[g].vertices);
        let n_f = fv.len();
        for i in 0..n_f {
            let p = cur[f][i];
            let Some((j, xi, xi_raw, gap, n, t)) = nearest_segment(p, &cur[g], side_g) else {
                continue;
            };
            if !(-0.5..=1.5).contains(&xi_raw) || gap < -search || gap > search {
                continue;
            }
            let ea = fv[i].at.element;
            let eb = s.faces[g].segment_elements[j];
            if ea == eb {
                continue;
            }
            // tributary length on its own face
            let share = super::tributary_share(has_midpoints, fv[i].midpoint);
            let mut lambda = 0.0;
            if i > 0 {
                lambda += share * dist(cur[f][i - 1], p);
            }
            if i + 1 < n_f {
                lambda += share * dist(p, cur[f][i + 1]);
            }
            let weight = 0.5 * lambda;
            if weight <= 0.0 {
                continue;
            }
            // the facing point as a material point of the segment's element
            let q0 = lerp(gv[j].x0, gv[j + 1].x0, xi);
            let wb = barycentric(&disc.elements[eb].nodes, q0);
            let rows = contact_rows(disc, (ea, &fv[i].at.weights), (eb, &wb), n, t);
            let x = fv[i].x0;
            self.push_contact(
                model,
                NewContact {
                    key: (b, s.vertex_number(f, i), b),
                    segment: j,
                    rows,
                    gap,
                    weight,
                    density,
                    frame: (n, t),
                    position: p,
                    iface,
                    joint: Some(s.joint),
                },
                // σ₀ on the vertex's face (outward normal −n) over its weight
                |st| {
                    let sg = st.at(x[1]);
                    let m = [-n[0], -n[1]];
                    [
                        weight * (sg[0] * m[0] + sg[2] * m[1]),
                        weight * (sg[2] * m[0] + sg[1] * m[1]),
                    ]
                },
            );
        }
    }
}
