//! The nonlinear system of one step, for the Newton driver.
//!
//! R(Δu) = F − L Δu − f_c(Δu), with L = K + c_m M + P the step's linear part (elastic
//! stiffness, inertia, constraint penalties; symmetric, on the element pattern) and f_c the
//! contact forces (piecewise affine in Δu, see `contact/set.rs`). The tangent on the chosen
//! branches is L + K_c (+ σ M, the regularisation). It is applied matrix-free (L by rows,
//! the contacts by their rank-2 blocks); it is assembled only when the tangent solver
//! refreshes its factorisation, over the *tangent pattern*: the element pattern plus every
//! contact coupling of the step (see [`TangentPattern`]). Rock bolts ([`crate::bolt`])
//! are pieces of the system too (elastic or yielding), their couplings in the element
//! pattern.

use super::Penalty;
use crate::assembly::global;
use crate::contact::set::{ContactRow, ContactSet};
use crate::cover::basis::NO_DOF;
use crate::solver::{PiecewiseSystem, SparsePattern, TangentOperator};
use std::collections::HashMap;
use std::sync::Arc;

/// A contact coupling: the free unknowns of a contact, sorted, each once, padded with
/// [`NO_DOF`] to the contact's length (contacts between the same two elements share it).
pub(crate) type CouplingKey = ContactRow<usize>;

fn coupling_key(dofs: &[usize]) -> CouplingKey {
    let mut key: CouplingKey = dofs.into();
    let k: &mut [usize] = &mut key;
    k.sort_unstable(); // NO_DOF = usize::MAX sorts last
    let mut w = 0;
    for r in 0..k.len() {
        if k[r] != NO_DOF && (w == 0 || k[w - 1] != k[r]) {
            k[w] = k[r];
            w += 1;
        }
    }
    k[w..].iter_mut().for_each(|x| *x = NO_DOF);
    key
}

/// The tangent pattern (see the module docs), kept across steps: the element pattern plus
/// the couplings of the current contacts, exactly. It is rebuilt when the contacts'
/// couplings change (most steps of a moving model: the symbolic analysis is then redone);
/// each contact's tangent slots are bound through its coupling (contacts between the same
/// two elements share one), not searched entry by entry.
///
/// Measured and rejected (40×40 wall, 12 steps): a pattern that **reserves** couplings for
/// a window of steps (the contacts of a 3× wider search with the neighbouring segments)
/// needed one symbolic analysis instead of 12 but 2.3× the factor's values (5.5 against
/// 2.4 million); reusing the minimum-degree ordering of an earlier step's pattern while
/// fewer than 5% of the couplings were new gave 1.2–1.7× the fill of the pattern's own
/// ordering. The symbolic analysis costs about one numeric factorisation, against five
/// numeric factorisations a step: fill costs more than the analysis saves.
///
/// The pattern is a function of the current contacts only, so a resumed run factorises
/// exactly the matrices the uninterrupted run did.
#[derive(Debug, Clone)]
pub(crate) struct TangentPattern {
    /// The element pattern (elements and constraint penalties) and its dof groups.
    element: Arc<SparsePattern>,
    element_groups: Vec<Vec<usize>>,
    /// The couplings of the contacts `combined` was built for, sorted.
    current: Vec<CouplingKey>,
    /// The element pattern plus `current`.
    combined: Option<Arc<SparsePattern>>,
    /// Index of each coupling of `current`.
    index: HashMap<CouplingKey, u32>,
    /// Slot in `combined` of each slot of `element`.
    map: Vec<u32>,
    /// Slots of each coupling's entries (n², n the unknowns of a contact, row-major over its
    /// key).
    key_slots: Vec<u32>,
    /// Slots of each current contact's tangent entries (n², row-major over the contact's
    /// own unknowns), for the contact list of generation `bound`.
    contact_slots: Vec<u32>,
    /// Unknowns of a contact (its row length) of the bound contact list.
    contact_dofs: usize,
    bound: Option<u64>,
}

impl TangentPattern {
    pub fn new(element: Arc<SparsePattern>, element_groups: Vec<Vec<usize>>) -> Self {
        TangentPattern {
            element,
            element_groups,
            current: Vec::new(),
            combined: None,
            index: HashMap::new(),
            map: Vec::new(),
            key_slots: Vec::new(),
            contact_slots: Vec::new(),
            contact_dofs: 0,
            bound: None,
        }
    }

    pub fn element(&self) -> &Arc<SparsePattern> {
        &self.element
    }

    fn pattern_with(&self, keys: &[CouplingKey]) -> SparsePattern {
        let free = |k: &CouplingKey| -> usize { k.iter().take_while(|&&d| d != NO_DOF).count() };
        let all = self
            .element_groups
            .iter()
            .map(|g| g.as_slice())
            .chain(keys.iter().map(|k| &k[..free(k)]));
        SparsePattern::from_groups(self.element.n, all)
    }

    /// The pattern for the current `contacts`, with their tangent slots bound.
    fn for_contacts(&mut self, contacts: &ContactSet) -> Arc<SparsePattern> {
        if self.bound == Some(contacts.generation()) {
            if let Some(p) = &self.combined {
                return p.clone();
            }
        }
        let keys: Vec<CouplingKey> = contacts
            .contacts
            .iter()
            .map(|c| coupling_key(&c.dofs))
            .collect();
        // every contact of a discretisation has the same number of unknowns
        let nc = contacts.contact_dofs();
        let n2 = nc * nc;
        let mut current = keys.clone();
        current.sort_unstable();
        current.dedup();
        if self.combined.is_none() || current != self.current || nc != self.contact_dofs {
            let p = Arc::new(self.pattern_with(&current));
            self.map = embed(&self.element, &p);
            self.key_slots.clear();
            self.key_slots.resize(current.len() * n2, u32::MAX);
            self.index.clear();
            self.index.reserve(current.len());
            for (i, k) in current.iter().enumerate() {
                global::group_slots(&p, k, &mut self.key_slots[i * n2..(i + 1) * n2]);
                self.index.insert(k.clone(), i as u32);
            }
            self.current = current;
            self.combined = Some(p);
            self.contact_dofs = nc;
        }
        // bind: each contact's slots, from its coupling's, in the contact's own order
        self.contact_slots.clear();
        self.contact_slots.resize(keys.len() * n2, u32::MAX);
        for (ci, (c, key)) in contacts.contacts.iter().zip(&keys).enumerate() {
            let g = self.index[key] as usize * n2;
            let out = &mut self.contact_slots[ci * n2..(ci + 1) * n2];
            let slots = &self.key_slots[g..g + n2];
            match (key.fixed(), c.dofs.fixed()) {
                // constant covers: arrays of a known length
                (Some(k), Some(dofs)) => bind(k, dofs, slots, out),
                _ => {
                    let (k, dofs): (&[usize], &[usize]) = (key, &c.dofs);
                    bind(k, dofs, slots, out)
                }
            }
        }
        self.bound = Some(contacts.generation());
        self.combined.clone().expect("pattern")
    }
}

/// A contact's tangent slots (`out`, n² row-major over its unknowns `dofs`) from its
/// coupling's (`slots`, n² row-major over the coupling's `key`).
#[inline(always)]
fn bind(key: &[usize], dofs: &[usize], slots: &[u32], out: &mut [u32]) {
    let nc = dofs.len();
    let mut pos = [usize::MAX; crate::contact::set::MAX_CONTACT_DOFS];
    for (p, &d) in pos.iter_mut().zip(dofs) {
        if d != NO_DOF {
            *p = key.iter().position(|&x| x == d).expect("dof in its key");
        }
    }
    for i in 0..nc {
        if pos[i] == usize::MAX {
            continue;
        }
        for j in 0..nc {
            if pos[j] != usize::MAX {
                out[i * nc + j] = slots[pos[i] * nc + pos[j]];
            }
        }
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
    pub bolts: &'a mut crate::bolt::BoltSet,
    pub tangent: &'a mut TangentPattern,
    pub threads: &'a crate::parallel::Threads,
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
        let (l, m) = (self.l, self.m);
        // by rows (= columns: L and M are symmetric), each row one ordered sum
        self.threads.for_each_mut(y, |i, yi| {
            let mut s = 0.0;
            for k in p.col_ptr[i]..p.col_ptr[i + 1] {
                s += (l[k] + sigma * m[k]) * v[p.row_idx[k]];
            }
            *yi = s;
        });
        self.contacts.apply_tangent(v, y);
        self.bolts.apply_tangent(v, y);
    }

    fn pattern(&mut self) -> Arc<SparsePattern> {
        self.tangent.for_contacts(self.contacts)
    }

    fn assemble(&mut self, values: &mut [f64], symmetric: bool) {
        let _ = self.tangent.for_contacts(self.contacts);
        for (k, &slot) in self.tangent.map.iter().enumerate() {
            values[slot as usize] += self.l[k] + self.sigma * self.m[k];
        }
        let nc = self.contacts.contact_dofs();
        let n2 = nc * nc;
        let mut k = vec![0.0; n2];
        for (ci, c) in self.contacts.contacts.iter().enumerate() {
            if ContactSet::tangent_block_into(c, symmetric, &mut k) {
                global::scatter(
                    values,
                    &self.tangent.contact_slots[ci * n2..(ci + 1) * n2],
                    &k,
                );
            }
        }
        self.bolts.assemble(values, &self.tangent.map);
    }

    fn is_symmetric(&self) -> bool {
        self.contacts.tangent_is_symmetric()
    }
}

impl PiecewiseSystem for StepSystem<'_> {
    fn choose_branches(&mut self, x: &[f64], first: bool) -> usize {
        self.contacts.choose_branches(x, first) + self.bolts.choose_branches(x)
    }

    fn choose_own_branches(&mut self, x: &[f64]) -> usize {
        self.contacts.choose_own_branches(x) + self.bolts.choose_branches(x)
    }

    fn residual_on_chosen(&mut self, x: &[f64], r: &mut [f64]) {
        self.linear_residual(x, r);
        self.contacts.add_forces(x, r, false);
        self.bolts.add_forces(x, r, false);
    }

    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> usize {
        self.linear_residual(x, r);
        let inconsistent = self.contacts.add_forces(x, r, true) + self.bolts.add_forces(x, r, true);
        // physical force scale: loads and weights, constraint reactions, contact forces
        let w = &mut self.work;
        w.clear();
        w.extend_from_slice(self.f_ext_abs);
        for (p, &target) in self.penalties.iter().zip(self.targets) {
            let n = p.dofs.len();
            for i in 0..n {
                if p.dofs[i] == NO_DOF {
                    continue;
                }
                let mut f = -target * p.g[i];
                for j in 0..n {
                    let d = p.dofs[j];
                    if d != NO_DOF {
                        f += p.k[i * n + j] * (self.u_n[d] + x[d]);
                    }
                }
                w[p.dofs[i]] += f.abs();
            }
        }
        self.contacts.add_force_magnitudes(w);
        self.bolts.add_force_magnitudes(x, w);
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
