//! What a tunnel needs of the contact set: the in-situ stress its springs start with, and
//! the blocks an excavation removed.
//!
//! **In-situ stress in the contacts.** Under `[initial_stress]` σ₀ every block starts
//! stressed, and the blocks' internal forces ∫ Bᵀσ₀ dΩ = ∮ Nᵀ σ₀ n dΓ are the consistent
//! forces of the tractions σ₀·n on their boundaries. Where two blocks touch at the start,
//! the contacts between them must carry those tractions for the model to start in
//! equilibrium: a contact of vertex P of block A on a face of block B is given the force
//!
//! F_A = ½ Σ_pieces σ₀(x_m) n_s ℓ,
//!
//! over the parts of A's boundary that P stands for (the `share` of each of A's two
//! segments at P, ½ for the trapezoidal rule, ⅓ and ⅔ for Simpson's at order 1, as
//! [`super::tributary`] takes them), each clipped to where it lies on B's boundary (any
//! segment of it: at a corner where the faces of A and B meet vertex for vertex the piece
//! beyond the corner lies on B's next face; blocks do not overlap, so a piece on B's
//! boundary faces B), ℓ its length, n_s A's outward normal, x_m its midpoint (exact for a
//! stress linear in y), ½ for the two passes (A's vertices on B and B's on A each carry
//! half) — or 1 where B's vertex at P is reflex beyond the detection's fit angle, which
//! makes no contact of its own ([`crate::contact::narrow`], rule 3). Where A's and B's
//! faces meet vertex for vertex — the faces of a cut block, a plug in its hole — the two
//! passes then give each block exactly the consistent forces of its tractions: the model
//! does not move. (A contact has one normal: at a sharp corner of a face the force of the
//! pieces on both sides has a shear part, which friction may not hold; at the corners of
//! a polygon drawn for a circle it is a few per cent of the normal force. The narrow
//! phase puts a corner that stands at a vertex of B on the face its longer piece runs
//! along ([`crate::contact::narrow`], rule 4), so that under a hydrostatic σ₀ the shear
//! part is at most tan(θ/2) of the normal one at a turn θ of the faces: 0.41 at an
//! octagon's corner. On the face of a short piece next to the corner (a mesh line or a
//! joint just past it) it was up to tan θ: 1 at an octagon's corner, beyond φ = 40°, and
//! the corner slid.)
//!
//! The contact's force on A is −(t_N n + t_S t) (n, t: the normal and tangent of B's
//! face), so it carries t_N = −F_A·n, t_S = −F_A·t: the normal spring gets the offset
//! δ_N = t_N/p_N added to its gap (an initial overlap of the interface, kept for the
//! contact's whole life, so that it opens only when the faces separate by |δ_N|), the
//! shear spring the elastic shear gap t_S/p_S in its first step (then in its history). A
//! contact whose in-situ normal traction is not compressive (t_N ≥ 0) gets nothing: a
//! joint carries no tension.

use super::{ContactKey, ContactSet};
use crate::geometry::{dist, dot, lerp, sub, Vec2};
use crate::model::InitialStress;
use std::collections::HashMap;

/// The in-situ stress of a contact set and the offsets of the contacts that touched at
/// the start.
#[derive(Debug, Clone, Default)]
pub(crate) struct Insitu {
    pub stress: Option<InitialStress>,
    /// Per contact touching at the start: (normal gap offset δ_N, initial elastic shear
    /// gap), m.
    pub offsets: HashMap<ContactKey, (f64, f64)>,
    /// Blocks removed by an excavation: no contact with them is detected.
    pub removed: Vec<bool>,
}

/// A boundary as a flat list of loops (see [`crate::cover::BlockBoundary`]).
pub(crate) type Loops<'a> = (&'a [Vec2], &'a [usize]);

/// The force F_A on A from B that the contact of A's vertex `i` carries under the stress
/// `s` (module doc): `share` of each of A's segments at the vertex facing B's face of
/// outward normal `n`, clipped to B's boundary (within `tol`), halved for the two passes.
pub(crate) fn force_on_vertex(
    (a, la): Loops,
    i: usize,
    share: f64,
    (b, lb): Loops,
    s: &InitialStress,
    tol: f64,
) -> Vec2 {
    let m = a.len();
    let p = a[i];
    let next = crate::geometry::region::loop_next(la, m, i);
    let prev = crate::geometry::region::loop_prev(la, m, i);
    let passes = if reflex_at((b, lb), p, tol) { 1.0 } else { 0.5 };
    let mut f = [0.0; 2];
    for (q, from_p) in [(a[next], true), (a[prev], false)] {
        let d = if from_p { sub(q, p) } else { sub(p, q) };
        let len = crate::geometry::norm(d);
        if len == 0.0 {
            continue;
        }
        let ns = [d[1] / len, -d[0] / len];
        let end = lerp(p, q, share);
        let piece = dist(p, end);
        for (t0, t1) in on_boundary((b, lb), p, end, tol) {
            let x = lerp(p, end, 0.5 * (t0 + t1));
            let sg = s.at(x[1]);
            let traction = [sg[0] * ns[0] + sg[2] * ns[1], sg[2] * ns[0] + sg[1] * ns[1]];
            let l = (t1 - t0) * piece;
            f[0] += passes * l * traction[0];
            f[1] += passes * l * traction[1];
        }
    }
    f
}

/// Whether `b` has a vertex at `p` (within `tol`) that is reflex beyond the narrow
/// phase's fit angle (it touches no edge with its tip).
fn reflex_at((b, lb): Loops, p: Vec2, tol: f64) -> bool {
    let fit = crate::contact::narrow::NarrowParams::new(0.0).fit_angle;
    let n = b.len();
    (0..n).any(|j| {
        if dist(b[j], p) > tol {
            return false;
        }
        let prev = b[crate::geometry::region::loop_prev(lb, n, j)];
        let next = b[crate::geometry::region::loop_next(lb, n, j)];
        let d_in = sub(b[j], prev);
        let u = sub(next, b[j]);
        crate::geometry::cross(d_in, u).atan2(dot(d_in, u)) < -fit
    })
}

/// The parts of the segment `pq` along the loops of `b` (parameter intervals).
fn on_boundary((b, lb): Loops, p: Vec2, q: Vec2, tol: f64) -> Vec<(f64, f64)> {
    let box_pq = crate::geometry::Aabb::of_points(&[p, q]).inflate(tol);
    let n = b.len();
    let mut starts: Vec<usize> = lb.to_vec();
    if starts.is_empty() {
        starts.push(0);
    }
    let mut out = Vec::new();
    for (k, &s) in starts.iter().enumerate() {
        let e = starts.get(k + 1).copied().unwrap_or(n);
        let ring = &b[s..e];
        if !crate::geometry::Aabb::of_points(ring)
            .inflate(tol)
            .overlaps(&box_pq)
        {
            continue;
        }
        out.extend(crate::geometry::polygon::segment_boundary_intervals(
            ring, p, q, tol,
        ));
    }
    out
}

impl ContactSet {
    /// The in-situ stress the contacts touching at the start carry (`None`: none).
    pub fn set_initial_stress(&mut self, stress: Option<InitialStress>) {
        self.insitu.stress = stress;
    }

    /// Excavated blocks: no contact with them is detected from the next detection on.
    pub fn set_removed_blocks(&mut self, removed: Vec<bool>) {
        self.insitu.removed = removed;
    }

    /// Whether block `b` was excavated.
    pub(crate) fn removed(&self, b: usize) -> bool {
        self.insitu.removed.get(b).copied().unwrap_or(false)
    }

    /// The in-situ offsets of the contacts (for checkpoints), sorted by key: (key, normal
    /// gap offset, initial elastic shear gap).
    pub fn insitu_offsets(&self) -> Vec<(ContactKey, f64, f64)> {
        let mut v: Vec<_> = self
            .insitu
            .offsets
            .iter()
            .map(|(k, o)| (*k, o.0, o.1))
            .collect();
        v.sort_by_key(|x| x.0);
        v
    }

    /// Restore the in-situ offsets of [`ContactSet::insitu_offsets`].
    pub fn restore_insitu_offsets(&mut self, offsets: &[(ContactKey, f64, f64)]) {
        self.insitu.offsets = offsets.iter().map(|(k, a, b)| (*k, (*a, *b))).collect();
    }

    /// The offsets (δ_N, initial shear gap) of contact `key` for this detection: computed
    /// by `force` (F_A, module doc) for a contact that touches at the start (before the
    /// first commit, gap within the touching tolerance), else those it got then; the
    /// shear gap only before the first commit (it is in the contact's history after).
    pub(super) fn insitu_offset(
        &mut self,
        key: ContactKey,
        gap: f64,
        (pn, ps): (f64, f64),
        (n, t): (Vec2, Vec2),
        force: impl FnOnce(&InitialStress) -> Vec2,
    ) -> (f64, f64) {
        let Some(s) = self.insitu.stress else {
            return (0.0, 0.0);
        };
        if self.commits > 0 {
            return self
                .insitu
                .offsets
                .get(&key)
                .map_or((0.0, 0.0), |o| (o.0, 0.0));
        }
        if gap.abs() > self.touch_tol {
            self.insitu.offsets.remove(&key);
            return (0.0, 0.0);
        }
        let f = force(&s);
        let (tn, ts) = (-dot(f, n), -dot(f, t));
        if tn.is_nan() || tn >= 0.0 {
            self.insitu.offsets.remove(&key);
            return (0.0, 0.0);
        }
        let o = (tn / pn, ts / ps);
        self.insitu.offsets.insert(key, o);
        o
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square A on the top face of a wider B: under σ₀ = (σxx, σyy, τ), the vertex
    /// at the corner of A carries half (two passes) of half its bottom segment's traction
    /// σ₀·(0, −1); its side is not on B. Clipped to B: B's face ends at x = 0.25, so only
    /// that part of A's half segment counts.
    #[test]
    fn a_corner_carries_half_of_its_face_share() {
        let s = InitialStress {
            stress: [-2.0, -5.0, 1.0],
            gradient: [0.0; 3],
            y_ref: 0.0,
        };
        let a = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let b = [[-1.0, -1.0], [2.0, -1.0], [2.0, 0.0], [-1.0, 0.0]];
        let f = force_on_vertex((&a, &[0]), 0, 0.5, (&b, &[0]), &s, 1e-12);
        // traction on A's bottom (n_s = (0, −1)): (−τ, −σyy) = (−1, 5), over 0.5 m, halved
        assert_eq!(f, [-0.25, 1.25]);
        let b_short = [[-1.0, -1.0], [0.25, -1.0], [0.25, 0.0], [-1.0, 0.0]];
        let f = force_on_vertex((&a, &[0]), 0, 0.5, (&b_short, &[0]), &s, 1e-12);
        assert_eq!(f, [-0.125, 0.625]);
        // a stress varying with y: taken at the piece's midpoint
        let g = InitialStress {
            stress: [0.0, -5.0, 0.0],
            gradient: [0.0, 2.0, 0.0],
            y_ref: 1.0,
        };
        let f = force_on_vertex((&a, &[0]), 0, 0.5, (&b, &[0]), &g, 1e-12);
        assert_eq!(f, [0.0, 0.25 * 7.0]);
    }

    /// A plug in a square hole, vertex for vertex: at the plug's corner both of its half
    /// segments lie on the rock (the hole's left side and bottom); the rock's corner there
    /// is reflex (it makes no contact), so the plug's carries both passes' share. At the
    /// rock's corner, were it found, the plug's corner is convex: half.
    #[test]
    fn at_a_shared_corner_both_faces_count() {
        let s = InitialStress {
            stress: [-3.0, -3.0, 0.0],
            gradient: [0.0; 3],
            y_ref: 0.0,
        };
        // the rock: an outer square and the hole (clockwise); the plug: the hole, CCW
        let rock = [
            [-2.0, -2.0],
            [2.0, -2.0],
            [2.0, 2.0],
            [-2.0, 2.0],
            [-1.0, -1.0],
            [-1.0, 1.0],
            [1.0, 1.0],
            [1.0, -1.0],
        ];
        let plug = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        // the plug's faces at the corner: bottom (normal −y) and left (normal −x): traction
        // −3 n = (0, 3) and (3, 0) over 1 m each, both passes: (3, 3)
        let f = force_on_vertex((&plug, &[0]), 0, 0.5, (&rock, &[0, 4]), &s, 1e-12);
        assert_eq!(f, [3.0, 3.0]);
        // the rock's corner on the plug: its faces' normals +x and +y, half
        let f = force_on_vertex((&rock, &[0, 4]), 4, 0.5, (&plug, &[0]), &s, 1e-12);
        assert_eq!(f, [-1.5, -1.5]);
        assert!(reflex_at((&rock, &[0, 4]), [-1.0, -1.0], 1e-12));
        assert!(!reflex_at((&plug, &[0]), [-1.0, -1.0], 1e-12));
    }
}
