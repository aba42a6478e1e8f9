//! The contact set of a step: detection on the NMM geometry, vertex–edge
//! kinematics on the covers, and the friction law at every Newton iterate.
//!
//! **Kinematics.** A contact is a boundary vertex P of block A (a material point
//! of element e_A with weights w_A) against a boundary segment of block B, at the
//! point Q of the segment nearest to P (a material point of the segment's element
//! e_B with weights w_B). With n the outward unit normal of B's segment and t its
//! unit direction, both taken on the geometry at the start of the step (small
//! displacement per step, as in DDA/NMM):
//!
//! g_N(Δu) = g_N⁰ + n · (Δu_P − Δu_Q),   Δg_S(Δu) = t · (Δu_P − Δu_Q),
//!
//! with Δu_P = Σ_k w_A,k Δu_k and Δu_Q = Σ_k w_B,k Δu_k, i.e. g_N = g_N⁰ + b_Nᵀ Δu and
//! Δg_S = b_Sᵀ Δu over the (up to 12) unknowns of the two elements.
//!
//! **Forces.** The contact's virtual work t_N δg_N + t_S δg_S gives the internal force
//! f_c = b_N t_N + b_S t_S and the tangent
//! K_c = b_N (∂t_N/∂g_N b_Nᵀ + ∂t_N/∂g_S b_Sᵀ) + b_S (∂t_S/∂g_N b_Nᵀ + ∂t_S/∂g_S b_Sᵀ),
//! unsymmetric for a sliding contact under return mapping. The force on block A is
//! −(t_N n + t_S t) (t_N ≤ 0: it pushes A out of B) and on block B the opposite.
//!
//! **Identity and state.** A contact is identified by (block A, vertex of A, block B),
//! so that it keeps its elastic shear gap and its stick/slide state when its vertex
//! passes from one segment of B to the next. States are committed only when a
//! step converges.

use super::broad::sweep_and_prune;
use super::friction::{self, ContactStatus, FrictionParams, LawResponse, ShearHistory};
use super::narrow::vertex_edge_contacts;
use crate::assembly::global::NO_DOF;
use crate::contact::narrow::VertexEdge;
use crate::cover::{barycentric, Discretisation};
use crate::geometry::{cross, dist, dot, norm, sub, Aabb, Vec2};
use crate::model::{FrictionAlgorithm, Model};
use crate::solver::SparseMatrix;
use std::collections::HashMap;

/// (block of the vertex, vertex index on its refined boundary, block of the edge).
pub type ContactKey = (usize, usize, usize);

#[derive(Debug, Clone)]
pub struct Contact {
    pub key: ContactKey,
    /// Segment of the edge block's boundary.
    pub segment: usize,
    pub dofs: [usize; 12],
    pub bn: [f64; 12],
    pub bs: [f64; 12],
    /// Normal gap at the start of the step (negative: penetration).
    pub gn0: f64,
    pub params: FrictionParams,
    /// Committed history (end of the last converged step).
    pub history: ShearHistory,
    /// Response at the latest Newton iterate.
    pub response: LawResponse,
    /// Vertex position at the start of the step.
    pub position: Vec2,
    pub normal: Vec2,
    pub tangent: Vec2,
    /// Joint that made the edge block's face, if any (it chose the interface).
    pub joint: Option<usize>,
}

impl Contact {
    fn gaps(&self, du: &[f64]) -> (f64, f64) {
        let (mut gn, mut gs) = (self.gn0, 0.0);
        for i in 0..12 {
            let d = self.dofs[i];
            if d != NO_DOF {
                gn += self.bn[i] * du[d];
                gs += self.bs[i] * du[d];
            }
        }
        (gn, gs)
    }
}

/// Summed contact force on one block from another.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfaceForce {
    pub fx: f64,
    pub fy: f64,
    /// Sum of the normal force magnitudes |t_N|.
    pub fn_sum: f64,
    /// Number of closed (stick or slide) contacts.
    pub count: usize,
}

/// One contact as written to the VTK output.
#[derive(Debug, Clone, Copy)]
pub struct ContactSnapshot {
    pub position: Vec2,
    pub normal: Vec2,
    pub force_on_first: Vec2,
    pub normal_force: f64,
    pub shear_force: f64,
    /// 0 open, 1 stick, 2 slide.
    pub state: u8,
    pub first: usize,
    pub second: usize,
    /// Joint that made the face of `second` the contact is on, if any.
    pub joint: Option<usize>,
}

#[derive(Debug, Clone, Default)]
pub struct ContactSet {
    pub contacts: Vec<Contact>,
    /// Committed history of each closed contact, with the outward normal it had.
    committed: HashMap<ContactKey, (ShearHistory, Vec2)>,
    algorithm: Option<FrictionAlgorithm>,
    last_status: Vec<ContactStatus>,
    /// Gaps up to this count as touching (`REL_TOL` × the model's size).
    touch_tol: f64,
    /// Converged steps committed so far.
    commits: usize,
}

fn status_code(s: ContactStatus) -> u8 {
    match s {
        ContactStatus::Open => 0,
        ContactStatus::Stick => 1,
        ContactStatus::Slide => 2,
    }
}

/// Adds one contact's tangent K_c = b_N (a b_N + b b_S)ᵀ + b_S (c b_N + d b_S)ᵀ with
/// `[a, b, c, d]` = [∂t_N/∂g_N, ∂t_N/∂g_S, ∂t_S/∂g_N, ∂t_S/∂g_S].
fn add_tangent(
    j: &mut SparseMatrix,
    dofs: &[usize; 12],
    bn: &[f64; 12],
    bs: &[f64; 12],
    [a, b, c, d]: [f64; 4],
) {
    for jj in 0..12 {
        let cj = dofs[jj];
        if cj == NO_DOF {
            continue;
        }
        let vn = a * bn[jj] + b * bs[jj];
        let vs = c * bn[jj] + d * bs[jj];
        for ii in 0..12 {
            let ri = dofs[ii];
            if ri == NO_DOF {
                continue;
            }
            let v = bn[ii] * vn + bs[ii] * vs;
            if v != 0.0 {
                j.add(ri, cj, v);
            }
        }
    }
}

impl ContactSet {
    /// Find the contacts on the current geometry (displacement `u` from the initial one).
    pub fn detect(&mut self, disc: &Discretisation, model: &Model, u: &[f64], search: f64) {
        self.algorithm = Some(model.analysis.friction);
        self.contacts.clear();
        self.last_status.clear();
        if model.blocks.len() < 2 {
            return;
        }
        // current boundary polylines
        let polys: Vec<Vec<Vec2>> = disc
            .boundaries
            .iter()
            .map(|b| {
                b.vertices
                    .iter()
                    .map(|v| {
                        let d = disc.displacement_at(&v.at, u);
                        [v.x0[0] + d[0], v.x0[1] + d[1]]
                    })
                    .collect()
            })
            .collect();
        let corners: Vec<Vec<bool>> = disc
            .boundaries
            .iter()
            .map(|b| b.vertices.iter().map(|v| v.corner).collect())
            .collect();
        let boxes: Vec<Aabb> = polys
            .iter()
            .map(|p| Aabb::of_points(p).inflate(search))
            .collect();
        let size = boxes
            .iter()
            .fold(Aabb::empty(), |a, b| a.merge(b))
            .diagonal();
        self.touch_tol = crate::model::REL_TOL * size;
        let mut pairs = sweep_and_prune(&boxes);
        pairs.sort_unstable();
        for (a, b) in pairs {
            if model.blocks[a].fixed && model.blocks[b].fixed {
                continue;
            }
            if !model.may_contact(a, b) {
                continue;
            }
            for (pa, pb) in [(a, b), (b, a)] {
                for mut ve in vertex_edge_contacts(&polys[pa], &polys[pb], search, &corners[pa]) {
                    let key = (pa, ve.vertex, pb);
                    if let Some((_, n_old)) = self.committed.get(&key) {
                        // Corner against corner the entrance edge is nearly a tie; keep the
                        // edge the contact had while it still holds the vertex, so that the
                        // normal does not flip between steps (which pumps energy in).
                        if dot(*n_old, ve.normal) < 0.9 {
                            if let Some(kept) =
                                keep_edge(&polys[pa][ve.vertex], &polys[pb], *n_old, search)
                            {
                                ve = VertexEdge {
                                    vertex: ve.vertex,
                                    ..kept
                                };
                            }
                        }
                    }
                    // the face's joint (if a joint made it) chooses the interface
                    let edge = disc.boundaries[pb].segment_edges[ve.segment];
                    let joint = model.blocks[pb].edge_joint.get(edge).copied().flatten();
                    let Some(iface) = model.interface_for_face(pa, pb, joint) else {
                        continue;
                    };
                    let vert = &disc.boundaries[pa].vertices[ve.vertex];
                    let eb = disc.boundaries[pb].segment_elements[ve.segment];
                    let nb = polys[pb].len();
                    let q = crate::geometry::lerp(
                        polys[pb][ve.segment],
                        polys[pb][(ve.segment + 1) % nb],
                        ve.xi,
                    );
                    let wb = barycentric(&disc.elements[eb].nodes, q);
                    let wa = vert.at.weights;
                    let ea = &disc.elements[vert.at.element];
                    let mut dofs = [NO_DOF; 12];
                    let (mut bn, mut bs) = ([0.0; 12], [0.0; 12]);
                    for k in 0..3 {
                        for (side, (el, w, sign)) in [(ea, wa, 1.0), (&disc.elements[eb], wb, -1.0)]
                            .into_iter()
                            .enumerate()
                        {
                            if let Some(g) = disc.covers[el.covers[k]].dof {
                                let i = 6 * side + 2 * k;
                                dofs[i] = g;
                                dofs[i + 1] = g + 1;
                                bn[i] = sign * w[k] * ve.normal[0];
                                bn[i + 1] = sign * w[k] * ve.normal[1];
                                bs[i] = sign * w[k] * ve.tangent[0];
                                bs[i + 1] = sign * w[k] * ve.tangent[1];
                            }
                        }
                    }
                    // tributary length of the vertex (for cohesion)
                    let np = polys[pa].len();
                    let p = polys[pa][ve.vertex];
                    let trib = 0.5
                        * (dist(p, polys[pa][(ve.vertex + 1) % np])
                            + dist(p, polys[pa][(ve.vertex + np - 1) % np]));
                    let params = FrictionParams {
                        pn: iface.normal_penalty,
                        ps: iface.shear_penalty,
                        tan_phi: iface.friction_angle.to_radians().tan(),
                        cohesion: iface.cohesion * trib,
                    };
                    let mut history = self.committed.get(&key).map(|c| c.0).unwrap_or_default();
                    if self.commits == 0
                        && history.status == ContactStatus::Open
                        && ve.gap <= self.touch_tol
                    {
                        // Touching at the start of the analysis: locked, an elastic shear
                        // spring from here (DDA's initial contacts). A contact that comes
                        // to touch later keeps its open history and closes during the
                        // step: the conventional rule then limits it by Coulomb, as every
                        // closing contact (an unlimited spring on a contact hovering at
                        // g_N = 0 makes the shear force jump as it opens, and Newton
                        // cycles; see `friction.rs`).
                        history = ShearHistory {
                            status: ContactStatus::Stick,
                            ..ShearHistory::default()
                        };
                    }
                    let response =
                        friction::evaluate(model.analysis.friction, &params, &history, ve.gap, 0.0);
                    self.contacts.push(Contact {
                        key,
                        segment: ve.segment,
                        dofs,
                        bn,
                        bs,
                        gn0: ve.gap,
                        params,
                        history,
                        response,
                        position: p,
                        normal: ve.normal,
                        tangent: ve.tangent,
                        joint,
                    });
                }
            }
        }
    }

    /// The free unknowns each contact couples (for the sparsity pattern).
    pub fn dof_groups(&self) -> Vec<Vec<usize>> {
        self.contacts
            .iter()
            .map(|c| {
                let mut g: Vec<usize> = c.dofs.iter().copied().filter(|&d| d != NO_DOF).collect();
                g.sort_unstable();
                g.dedup();
                g
            })
            .collect()
    }

    /// Return-map every contact at the iterate Δu = `du`; subtract the contact forces
    /// from the residual `r` and add the tangent to `j`. Returns (tangent symmetric,
    /// active set changed since the previous evaluation).
    ///
    /// With `predictor` (the first evaluation of a step, at Δu = 0), a contact that is
    /// touching (gap ≤ `touch_tol`) but not yet pressed adds its closed (stick) stiffness
    /// to the tangent without any
    /// force: the law's tangent at g_N = 0⁺ is zero, and without this the first Newton
    /// direction of a wall whose blocks just touch is a free fall that drives every joint
    /// deep into the penalty springs (DDA likewise starts the open–close iteration with
    /// the touching contacts locked). Only the first direction changes; the solution and
    /// the converged tangent are those of the law.
    pub fn evaluate(
        &mut self,
        du: &[f64],
        r: &mut [f64],
        j: &mut SparseMatrix,
        predictor: bool,
    ) -> (bool, bool) {
        let alg = self.algorithm.unwrap_or(FrictionAlgorithm::ReturnMapping);
        let mut symmetric = true;
        let mut changed = self.last_status.len() != self.contacts.len();
        self.last_status
            .resize(self.contacts.len(), ContactStatus::Open);
        for (ci, c) in self.contacts.iter_mut().enumerate() {
            let (gn, gs) = c.gaps(du);
            let resp = friction::evaluate(alg, &c.params, &c.history, gn, gs);
            c.response = resp;
            if self.last_status[ci] != resp.status {
                changed = true;
                self.last_status[ci] = resp.status;
            }
            if resp.status == ContactStatus::Open {
                // at Δu = 0, g_N is the gap at the start of the step
                if predictor && gn <= self.touch_tol {
                    let (pn, ps) = (c.params.pn, c.params.ps);
                    add_tangent(j, &c.dofs, &c.bn, &c.bs, [pn, 0.0, 0.0, ps]);
                }
                continue;
            }
            if resp.dts_dgn != 0.0 || resp.dtn_dgs != 0.0 {
                symmetric = false;
            }
            for i in 0..12 {
                if c.dofs[i] != NO_DOF {
                    r[c.dofs[i]] -= c.bn[i] * resp.tn + c.bs[i] * resp.ts;
                }
            }
            add_tangent(
                j,
                &c.dofs,
                &c.bn,
                &c.bs,
                [resp.dtn_dgn, resp.dtn_dgs, resp.dts_dgn, resp.dts_dgs],
            );
        }
        (symmetric, changed)
    }

    /// Commit the converged increment: every contact's law response becomes its history.
    pub fn commit(&mut self, du: &[f64]) {
        let alg = self.algorithm.unwrap_or(FrictionAlgorithm::ReturnMapping);
        self.commits += 1;
        self.committed.clear();
        for c in self.contacts.iter_mut() {
            let (gn, gs) = c.gaps(du);
            c.response = friction::evaluate(alg, &c.params, &c.history, gn, gs);
            let h = friction::commit(alg, &c.params, &c.history, &c.response);
            c.history = h;
            if c.response.status != ContactStatus::Open {
                self.committed.insert(c.key, (h, c.normal));
            }
        }
    }

    /// Total force on block `first` from block `second` at the last evaluation.
    pub fn interface_force(&self, first: usize, second: usize) -> InterfaceForce {
        self.interface_force_between(&[first], &[second])
    }

    /// Total force on the blocks `first` from the blocks `second` (sorted, disjoint index
    /// lists) at the last evaluation.
    pub fn interface_force_between(&self, first: &[usize], second: &[usize]) -> InterfaceForce {
        let mut f = InterfaceForce::default();
        let (is_first, is_second) = (
            |b: usize| first.binary_search(&b).is_ok(),
            |b: usize| second.binary_search(&b).is_ok(),
        );
        for c in &self.contacts {
            let sign = if is_first(c.key.0) && is_second(c.key.2) {
                -1.0
            } else if is_second(c.key.0) && is_first(c.key.2) {
                1.0
            } else {
                continue;
            };
            let r = &c.response;
            f.fx += sign * (r.tn * c.normal[0] + r.ts * c.tangent[0]);
            f.fy += sign * (r.tn * c.normal[1] + r.ts * c.tangent[1]);
            f.fn_sum += r.tn.abs();
            if r.status != ContactStatus::Open {
                f.count += 1;
            }
        }
        f
    }

    /// The contacts for output.
    pub fn snapshots(&self) -> Vec<ContactSnapshot> {
        self.contacts
            .iter()
            .map(|c| {
                let r = &c.response;
                ContactSnapshot {
                    position: c.position,
                    normal: c.normal,
                    force_on_first: [
                        -(r.tn * c.normal[0] + r.ts * c.tangent[0]),
                        -(r.tn * c.normal[1] + r.ts * c.tangent[1]),
                    ],
                    normal_force: r.tn.abs(),
                    shear_force: r.ts,
                    state: status_code(r.status),
                    first: c.key.0,
                    second: c.key.2,
                    joint: c.joint,
                }
            })
            .collect()
    }
}

/// The segment of `b` whose outward normal is (nearly) `n_old` and that still holds
/// vertex `p` (projection within the segment, gap within [−search, search]).
fn keep_edge(p: &Vec2, b: &[Vec2], n_old: Vec2, search: f64) -> Option<VertexEdge> {
    let m = b.len();
    let mut best: Option<VertexEdge> = None;
    for j in 0..m {
        let (a, q) = (b[j], b[(j + 1) % m]);
        let d = sub(q, a);
        let len = norm(d);
        if len == 0.0 {
            continue;
        }
        let t = [d[0] / len, d[1] / len];
        // CCW polygon: the outward normal is the tangent turned clockwise
        let n = [t[1], -t[0]];
        if dot(n, n_old) < 0.99 {
            continue;
        }
        let xi = dot(sub(*p, a), t) / len;
        let gap = -cross(d, sub(*p, a)) / len;
        if !(-1e-9..=1.0 + 1e-9).contains(&xi) || gap.abs() > search {
            continue;
        }
        if best.is_none_or(|bst| gap.abs() < bst.gap.abs()) {
            best = Some(VertexEdge {
                vertex: 0,
                segment: j,
                xi: xi.clamp(0.0, 1.0),
                gap,
                normal: n,
                tangent: t,
            });
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertex exactly at a corner of B: the entrance edge is a tie; the edge with the
    /// normal the contact had is kept.
    #[test]
    fn keep_edge_follows_the_previous_normal_at_a_corner() {
        let b = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let corner = [1.0, 1.0 + 1e-6];
        let top = keep_edge(&corner, &b, [0.0, 1.0], 1e-3).unwrap();
        assert_eq!(top.segment, 2);
        assert_eq!(top.normal, [0.0, 1.0]);
        assert!((top.gap - 1e-6).abs() < 1e-12 && (top.xi - 0.0).abs() < 1e-12);
        let side = keep_edge(&[1.0 + 1e-6, 1.0], &b, [1.0, 0.0], 1e-3).unwrap();
        assert_eq!(side.segment, 1);
        assert!((side.gap - 1e-6).abs() < 1e-12);
        // beyond the search distance, or past the end of the edge: nothing kept
        assert!(keep_edge(&[0.5, 1.1], &b, [0.0, 1.0], 1e-3).is_none());
        assert!(keep_edge(&[1.5, 1.0], &b, [0.0, 1.0], 1e-3).is_none());
    }
}
