//! The nonlinear system of one step, for the Newton driver.
//!
//! R(Δu) = F − L Δu − f_c(Δu), with L = K + c_m M + P the step's linear part (elastic
//! stiffness, inertia, constraint penalties; symmetric, on the element pattern) and f_c the
//! contact forces (piecewise affine in Δu, see `contact/set.rs`). The tangent on the chosen
//! branches is L + K_c (+ σ M, the regularisation). It is applied matrix-free (L by rows,
//! the contacts by their rank-2 blocks); it is assembled only when the tangent solver
//! refreshes its factorisation, over the *tangent pattern*: the element pattern plus every
//! contact coupling of the step (see [`TangentPattern`]).

use super::Penalty;
use crate::contact::set::ContactSet;
use crate::cover::basis::NO_DOF;
use crate::solver::{PiecewiseSystem, SparsePattern, TangentOperator};
use std::sync::Arc;

/// The tangent pattern cache (see the module docs), kept across steps.
#[derive(Debug, Clone)]
pub(crate) struct TangentPattern {
    /// The element pattern (elements and constraint penalties) and its dof groups.
    element: Arc<SparsePattern>,
    element_groups: Vec<Vec<usize>>,
    /// The element pattern plus the contact couplings of `contact_groups`.
    combined: Option<Arc<SparsePattern>>,
    contact_groups: Vec<Vec<usize>>,
    /// Slot in `combined` of each slot of `element`.
    map: Vec<u32>,
}

impl TangentPattern {
    pub fn new(element: Arc<SparsePattern>, element_groups: Vec<Vec<usize>>) -> Self {
        TangentPattern {
            element,
            element_groups,
            combined: None,
            contact_groups: Vec::new(),
            map: Vec::new(),
        }
    }

    pub fn element(&self) -> &Arc<SparsePattern> {
        &self.element
    }

    /// A pattern holding the element couplings and every contact coupling of `contacts`,
    /// bound to them (their tangent slots computed).
    ///
    /// The pattern is a function of the current contacts only (not of earlier steps), so
    /// that a run resumed from a checkpoint factorises exactly the same matrices: it is
    /// rebuilt when the contact couplings change, and its symbolic analysis is redone only
    /// then (the factorisation keeps it while the pattern is equal).
    fn for_contacts(&mut self, contacts: &mut ContactSet) -> Arc<SparsePattern> {
        let mut groups = contacts.dof_groups();
        groups.sort_unstable();
        groups.dedup();
        if let Some(p) = &self.combined {
            if groups == self.contact_groups {
                contacts.bind(p);
                return p.clone();
            }
        }
        let all = self.element_groups.iter().chain(groups.iter());
        let p = Arc::new(SparsePattern::from_groups(
            self.element.n,
            all.map(|g| g.as_slice()),
        ));
        self.map = embed(&self.element, &p);
        self.contact_groups = groups;
        self.combined = Some(p.clone());
        contacts.bind(&p);
        p
    }
}

/// Positions in `big` (a superset pattern) of every entry of `small`.
fn embed(small: &SparsePattern, big: &SparsePattern) -> Vec<u32> {
    let mut map = vec![0u32; small.nnz()];
    for c in 0..small.n {
        let (bs, be) = (big.col_ptr[c], big.col_ptr[c + 1]);
        let mut k = bs;
        let (a, b) = (small.col_ptr[c], small.col_ptr[c + 1]);
        for (m, &r) in map[a..b].iter_mut().zip(&small.row_idx[a..b]) {
            while big.row_idx[k] != r {
                k += 1;
                debug_assert!(k < be);
            }
            *m = k as u32;
        }
    }
    map
}

/// y = A x for a symmetric A stored in full over `p` (computed by rows = columns, so each
/// y_i is one ordered sum).
pub(crate) fn sym_mul(p: &SparsePattern, a: &[f64], x: &[f64], y: &mut [f64]) {
    for (i, yi) in y.iter_mut().enumerate() {
        let mut s = 0.0;
        for k in p.col_ptr[i]..p.col_ptr[i + 1] {
            s += a[k] * x[p.row_idx[k]];
        }
        *yi = s;
    }
}

pub(crate) struct StepSystem<'a> {
    pub l: &'a [f64],
    pub m: &'a [f64],
    pub f: &'a [f64],
    /// |f_ext| per unknown (loads, weights, base inertia).
    pub f_ext_abs: &'a [f64],
    pub penalties: &'a [Penalty],
    /// Each penalty's prescribed value at the end of the step.
    pub targets: &'a [f64],
    /// Displacement at the step start.
    pub u_n: &'a [f64],
    pub contacts: &'a mut ContactSet,
    pub tangent: &'a mut TangentPattern,
    pub sigma: f64,
    pub scale: f64,
    pub work: Vec<f64>,
}

impl StepSystem<'_> {
    fn linear_residual(&self, x: &[f64], r: &mut [f64]) {
        sym_mul(self.tangent.element(), self.l, x, r);
        for (ri, fi) in r.iter_mut().zip(self.f) {
            *ri = fi - *ri;
        }
    }
}

impl TangentOperator for StepSystem<'_> {
    fn size(&self) -> usize {
        self.f.len()
    }

    fn apply(&self, v: &[f64], y: &mut [f64]) {
        let p = self.tangent.element();
        let sigma = self.sigma;
        for (i, yi) in y.iter_mut().enumerate() {
            let mut s = 0.0;
            for k in p.col_ptr[i]..p.col_ptr[i + 1] {
                s += (self.l[k] + sigma * self.m[k]) * v[p.row_idx[k]];
            }
            *yi = s;
        }
        self.contacts.apply_tangent(v, y);
    }

    fn pattern(&mut self) -> Arc<SparsePattern> {
        self.tangent.for_contacts(self.contacts)
    }

    fn assemble(&mut self, values: &mut [f64], symmetric: bool) {
        let _ = self.tangent.for_contacts(self.contacts);
        for (k, &slot) in self.tangent.map.iter().enumerate() {
            values[slot as usize] += self.l[k] + self.sigma * self.m[k];
        }
        self.contacts.assemble_tangent(values, symmetric);
    }

    fn is_symmetric(&self) -> bool {
        self.contacts.tangent_is_symmetric()
    }
}

impl PiecewiseSystem for StepSystem<'_> {
    fn choose_branches(&mut self, x: &[f64], first: bool) -> usize {
        self.contacts.choose_branches(x, first)
    }

    fn choose_own_branches(&mut self, x: &[f64]) -> usize {
        self.contacts.choose_own_branches(x)
    }

    fn residual_on_chosen(&mut self, x: &[f64], r: &mut [f64]) {
        self.linear_residual(x, r);
        self.contacts.add_forces(x, r, false);
    }

    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> usize {
        self.linear_residual(x, r);
        let inconsistent = self.contacts.add_forces(x, r, true);
        // physical force scale: loads and weights, constraint reactions, contact forces
        let w = &mut self.work;
        w.clear();
        w.extend_from_slice(self.f_ext_abs);
        for (p, &target) in self.penalties.iter().zip(self.targets) {
            for i in 0..3 {
                if p.dofs[i] == NO_DOF {
                    continue;
                }
                let mut f = -target * p.g[i];
                for j in 0..3 {
                    let d = p.dofs[j];
                    if d != NO_DOF {
                        f += p.k[i * 3 + j] * (self.u_n[d] + x[d]);
                    }
                }
                w[p.dofs[i]] += f.abs();
            }
        }
        self.contacts.add_force_magnitudes(w);
        self.scale = w.iter().map(|v| v * v).sum::<f64>().sqrt();
        inconsistent
    }

    fn force_scale(&self) -> f64 {
        self.scale
    }

    fn set_regularisation(&mut self, sigma: f64) {
        self.sigma = sigma;
    }

    /// The largest relative motion (normal or tangential) a direction makes at a contact.
    fn step_size(&self, d: &[f64]) -> f64 {
        self.contacts.largest_relative_motion(d)
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;

    #[test]
    fn embedding_finds_every_entry() {
        let small = SparsePattern::from_groups(5, [&[0usize, 2][..], &[3, 4][..]].into_iter());
        let big = SparsePattern::from_groups(
            5,
            [&[0usize, 2][..], &[3, 4][..], &[1, 2, 4][..]].into_iter(),
        );
        let map = embed(&small, &big);
        for c in 0..5 {
            for s in small.col_ptr[c]..small.col_ptr[c + 1] {
                let r = small.row_idx[s];
                assert_eq!(big.slot(r, c), Some(map[s] as usize));
            }
        }
    }
}
