//! The nonlinear system of one step, for the Newton driver.
//!
//! R(Δu) = F − L Δu − f_c(Δu), with L = K + c_m M + P the step's linear part (elastic
//! stiffness, inertia, constraint penalties; symmetric, on the element pattern) and f_c the
//! contact forces (piecewise affine in Δu, see `contact/set.rs`). The tangent on the chosen
//! branches is L + K_c (+ σ M, the regularisation). It is applied matrix-free (L by rows,
//! the contacts by their rank-2 blocks); it is assembled only when the tangent solver
//! refreshes its factorisation, over the *tangent pattern*: the element pattern plus the
//! couplings reserved for contacts, which hold every contact coupling of the step and change
//! only when a contact needs one they do not (see [`TangentPattern`]). Rock bolts ([`crate::bolt`])
//! are pieces of the system too (elastic or yielding), their couplings in the element
//! pattern.

use super::Penalty;
use crate::assembly::global;
use crate::contact::set::{Contact, ContactRow, ContactSet, MAX_CONTACT_DOFS};
use crate::cover::basis::NO_DOF;
use crate::solver::{PiecewiseSystem, SparsePattern, TangentOperator};
use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

/// A contact coupling: the free unknowns of a contact, sorted, each once, padded with
/// [`NO_DOF`] to the contact's length (contacts between the same two elements share it).
pub(crate) type CouplingKey = ContactRow<usize>;

/// See [`TangentPattern::assembled`].
type AssemblyKey = (u64, usize, bool, u64);

/// The free unknowns of a coupling key: its leading entries before the [`NO_DOF`] padding.
fn free_unknowns(key: &[usize]) -> &[usize] {
    &key[..key.iter().take_while(|&&d| d != NO_DOF).count()]
}

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

/// The coupling a contact reserves in the pattern when it needs one: without its small rows
/// ([`Contact::preconditioner_dofs`]).
fn contact_key(c: &Contact) -> CouplingKey {
    coupling_key(&c.preconditioner_dofs())
}

/// The key a contact finds its reserved coupling by when the pattern need not be complete:
/// the unknowns of its rows above the required floor ([`Contact::required_dofs`]), which a
/// weight that wanders about a mesh line, or a vertex on one that detection puts in either
/// element, does not change. (Where it must be complete: its whole coupling.)
fn index_key(c: &Contact) -> CouplingKey {
    coupling_key(&c.required_dofs())
}

/// Whether the coupling `key` holds every unknown of `dofs` ([`NO_DOF`] skipped).
fn holds(key: &[usize], dofs: &[usize]) -> bool {
    let k = free_unknowns(key);
    dofs.iter()
        .all(|&d| d == NO_DOF || k.binary_search(&d).is_ok())
}

/// The coupling of the unknowns of `a` and of the key `b`; `b` where they do not fit in one
/// key (two contacts found by one index key from different pairs of elements, each with
/// its own small rows: the pattern then leaves out the other's, see `complete`).
fn union_key(a: &CouplingKey, b: &CouplingKey) -> CouplingKey {
    let mut all: Vec<usize> = free_unknowns(a)
        .iter()
        .chain(free_unknowns(b))
        .copied()
        .collect();
    all.sort_unstable();
    all.dedup();
    if all.len() > a.len() {
        return b.clone();
    }
    let mut k = a.clone();
    k[..all.len()].copy_from_slice(&all);
    k[all.len()..].iter_mut().for_each(|x| *x = NO_DOF);
    k
}

/// Steps a reserved coupling that no contact uses is kept through a rebuild of the pattern.
pub(crate) const KEEP_STEPS: usize = 200;

/// Most couplings no current contact uses that a rebuild keeps, for `current` couplings in
/// use: an eighth as many, and 16 (a bound on the fill they add). Measured on the 20×20 wall
/// (40 steps): a budget of a half gave 17 symbolic analyses and 1.33× the factor's values of
/// the exact pattern, an eighth 19 and 1.11×, none (16) 40 and 1.0×.
fn stale_budget(current: usize) -> usize {
    current / 8 + 16
}

/// The tangent pattern (see the module docs), kept across steps: the element pattern plus a
/// set of **reserved couplings** that holds every coupling of the current contacts. While
/// the contacts' couplings stay within the reserved set the pattern (and so the symbolic
/// analysis of the factorisation: ordering, elimination tree, supernodes) is the same from
/// step to step; unused entries hold explicit zeros. A contact whose coupling is not
/// reserved **rebuilds** it: the reserved set becomes the current couplings plus those a
/// contact used within the last [`KEEP_STEPS`] steps (contacts that open and close again,
/// pairs that come in and out of the search, keep their place), and the pattern is built
/// anew. Each contact's tangent slots are bound through its coupling (contacts between the
/// same two elements share one), not searched entry by entry.
///
/// **Keys and hysteresis.** A contact finds its coupling by its whole coupling, else by its
/// *index key*: the unknowns of its rows above 10⁻² of its largest ([`index_key`],
/// [`Contact::required_dofs`]); a coupling found by the index key may lack the contact's
/// smaller rows (the pattern is then not complete, below). A rebuild adds to the coupling
/// of each key what its contacts need now (their unknowns above 10⁻⁴, [`contact_key`]; whole
/// ones for a complete pattern) and keeps what it held: a coupling only grows while it is
/// reserved. Why (2026-12-05): on the jointed slope of ~1,000 blocks (scaling study) a
/// sliding face's contacts have points micrometres off mesh nodes whose weights creep
/// across the 10⁻⁴ floor (6·10⁻⁵ … 8·10⁻⁵ of the largest), and vertices on mesh lines that
/// detection puts in either element; with couplings found only by their exact unknowns
/// that rebuilt the pattern in 9 of 10 steps (1 to 86 contacts missing of 20,000), each
/// rebuild 23 ms of pattern and 17 ms of symbolic analysis: 2 symbolic analyses in 12
/// steps instead of 7, 161 → 133 ms/step (medians of 5, alternated); arch example 138 →
/// 96 analyses, tunnel 164 → 145; walls unchanged (byte-identical histories).
///
/// A contact's coupling is its unknowns with rows that are not zeros
/// ([`Contact::coupled_dofs`]: a point on a mesh edge has a cover of weight zero), found by
/// that set, else by its index key (below). Measured (2026-12-04, 12 steps, alternated with the build
/// before, medians of 3 in one slow hour of the 2-core machine; the same iteration counts,
/// histories within 10⁻¹¹ of uy; two runs): 20×20 wall 270 → 145 and 137 → 125 ms/step,
/// 40×40 wall 1,162 → 815 and 1,161 → 805 ms/step, peak memory 164 → 133 MB — every vertex of a running-bond wall lies on mesh
/// lines and so does the point it faces. The cost: a contact whose point leaves a mesh edge
/// needs a coupling it did not have, so the tunnel example (blocks cut from one mass, each
/// side of a joint refined at the same mesh lines) does 186 symbolic analyses instead of 82
/// (its factorisation stage 8.8–11.0 → 13.7 s, single runs), the arch example 157 instead
/// of 125.
///
/// The pattern is the factorised **preconditioner's**: a contact's unknowns whose rows are
/// below 10⁻⁴ of its largest (a point micrometres off a mesh line, weights 10⁻⁹…10⁻⁵) are
/// left out where the rest of its coupling is reserved ([`contact_key`],
/// [`Contact::preconditioner_dofs`]); the pattern is then not complete
/// ([`TangentOperator::pattern_is_complete`]) and every solve is GMRES on the full tangent,
/// preconditioned by that factor — the Newton direction as accurate as before. At a step whose
/// tangent is symmetric when the step first asks for its pattern, or regularised (a static
/// step: its solves are near mechanisms), the whole couplings are required (rebuilt if
/// missing, the reduced ones reserved beside them: no further fill), so that its solves stay
/// direct (with the reduced pattern a static collapsing arch's step failed and was cut:
/// `tests/energy.rs`). Measured (2026-12-04, 12 steps): the settling walls' corner
/// contacts no longer rebuild the pattern every step — 20×20 12 → 1 symbolic analyses, 40×40
/// 12 → 1, factorisation stage 2.95 → 1.58 s, peak memory 132 → 95 MB, the same iteration
/// counts; tunnel 186 → 163 analyses, arch and shaken slope within their round-off spread.
/// A rebuild for a tangent that turned symmetric within a step (rejected): the shaken slope
/// 193 → 348 symbolic analyses.
///
/// Why (tunnel example, 767 steps, before): the pattern followed the current contacts
/// exactly and was rebuilt in 724 steps; building it took 10.7 s, its symbolic analyses
/// 5.8 s, the numeric factorisations 4.6 s of a 37.5 s run.
///
/// Measured and rejected earlier (40×40 wall, 12 steps): a pattern that reserves the
/// couplings of a 3× wider search with the neighbouring segments needed one symbolic
/// analysis instead of 12 but 2.3× the factor's values (5.5 against 2.4 million); reusing
/// the minimum-degree ordering of an earlier step's pattern while fewer than 5% of the
/// couplings were new gave 1.2–1.7× the fill of the pattern's own ordering; (2026-12-04,
/// before the zero-weight rule) reserving for each contact whose facing point was within
/// the search distance of its segment's end the coupling it would have on the adjacent
/// segment (the wall's rebuilds come from corner contacts that go from one segment to the
/// next) needed one symbolic analysis instead of 12, but every contact of the wall is at a
/// segment end: 4.9 million values in the factor against 2.48, factorisation stage 5.4–5.7
/// s against 4.4–5.2 s. Couplings
/// reserved because they were used recently cost little fill: they are couplings of
/// neighbours in contact.
///
/// The reserved set (keys and couplings) and the step each was last used are state that
/// crosses steps: checkpoints keep them ([`TangentPattern::saved`], [`TangentPattern::restore`]), and the
/// pattern is a function of them, so a resumed run factorises exactly the matrices the
/// uninterrupted run did. Nothing depends on the thread count.
#[derive(Debug, Clone)]
pub(crate) struct TangentPattern {
    /// The element pattern (elements, constraint penalties, ghost ties, bolts).
    element: Arc<SparsePattern>,
    /// The keys contacts find the reserved couplings by ([`index_key`], or a whole
    /// coupling), sorted (see above).
    keys: Vec<CouplingKey>,
    /// The coupling reserved for each key: its unknowns and those its contacts needed
    /// while it was reserved (it holds its key).
    reserved: Vec<CouplingKey>,
    /// The last step a contact used each reserved coupling.
    last_used: Vec<usize>,
    /// Unknowns of a contact (its row length) the reserved couplings are for.
    contact_dofs: usize,
    /// The step being solved (set by the simulation).
    pub step: usize,
    /// Patterns built (for tests and reports).
    pub builds: usize,
    /// The element pattern plus `reserved` (a cache: a function of `reserved`).
    combined: Option<Arc<SparsePattern>>,
    /// Index of each key of `keys`.
    index: HashMap<CouplingKey, u32, foldhash::fast::RandomState>,
    /// Slot in `combined` of each slot of `element`.
    map: Vec<u32>,
    /// Slots of each coupling's entries (n², n the unknowns of a contact, row-major over its
    /// key).
    key_slots: Vec<u32>,
    /// Each current contact's coupling (index in `reserved`) and the place of each of its
    /// unknowns in that coupling's key ([`global::NO_PLACE`]: no slot), for the contact
    /// list of generation and step `bound`: its tangent entries' slots are the coupling's
    /// (`key_slots`), through [`global::scatter_through`].
    contact_bindings: Vec<Binding>,
    bound: Option<(u64, usize)>,
    /// The last assembly of the tangent into the solver's matrix
    /// ([`TangentOperator::assemble`], then [`TangentOperator::update_assembly`]): the
    /// contact list's generation, the step, whether only the symmetric part, σ's bits;
    /// and each contact's coefficients it holds (a record for the updates: not state
    /// that crosses steps).
    assembled: Option<AssemblyKey>,
    assembled_coef: Vec<[f64; 4]>,
    /// Whether the bound contacts' slots hold every entry of their tangents (else some
    /// contact's rows below [`Contact::preconditioner_dofs`]' floor have no slot).
    complete: bool,
}

/// The reserved couplings of a tangent pattern as a checkpoint keeps them: the contact row
/// length, each key and coupling (padded with [`NO_DOF`]) and the step it was last used.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct SavedPattern {
    pub contact_dofs: usize,
    pub reserved: Vec<(Vec<usize>, Vec<usize>, usize)>,
}

impl TangentPattern {
    pub fn new(element: Arc<SparsePattern>) -> Self {
        TangentPattern {
            element,
            keys: Vec::new(),
            reserved: Vec::new(),
            last_used: Vec::new(),
            contact_dofs: 0,
            step: 0,
            builds: 0,
            combined: None,
            index: HashMap::default(),
            map: Vec::new(),
            key_slots: Vec::new(),
            contact_bindings: Vec::new(),
            bound: None,
            complete: true,
            assembled: None,
            assembled_coef: Vec::new(),
        }
    }

    pub fn element(&self) -> &Arc<SparsePattern> {
        &self.element
    }

    /// The state a checkpoint keeps.
    pub fn saved(&self) -> SavedPattern {
        SavedPattern {
            contact_dofs: self.contact_dofs,
            reserved: self
                .keys
                .iter()
                .zip(&self.reserved)
                .zip(&self.last_used)
                .map(|((p, k), &t)| (p.to_vec(), k.to_vec(), t))
                .collect(),
        }
    }

    /// Restore the state of a checkpoint (on a pattern of the same element pattern).
    pub fn restore(&mut self, s: &SavedPattern) -> Result<(), String> {
        let n = self.element.n;
        let mut keys = Vec::with_capacity(s.reserved.len());
        let mut reserved = Vec::with_capacity(s.reserved.len());
        let mut last_used = Vec::with_capacity(s.reserved.len());
        let fits =
            |k: &[usize]| k.len() == s.contact_dofs && k.iter().all(|&d| d == NO_DOF || d < n);
        for (p, k, t) in &s.reserved {
            if !fits(p) || !fits(k) || !holds(k, p) {
                return Err("a reserved coupling of the tangent does not fit the model".into());
            }
            keys.push(CouplingKey::from(&p[..]));
            reserved.push(CouplingKey::from(&k[..]));
            last_used.push(*t);
        }
        if !keys.windows(2).all(|w| w[0] < w[1]) {
            return Err("the reserved couplings of the tangent are not sorted".into());
        }
        self.keys = keys;
        self.reserved = reserved;
        self.last_used = last_used;
        self.contact_dofs = s.contact_dofs;
        self.combined = None;
        self.bound = None;
        self.assembled = None;
        Ok(())
    }

    /// Build `combined` and its slots from `reserved`.
    fn build(&mut self) {
        let nc = self.contact_dofs;
        let n2 = nc * nc;
        let p = Arc::new(
            self.element
                .with_groups(self.reserved.iter().map(|k| free_unknowns(k))),
        );
        self.map = embed(&self.element, &p);
        self.key_slots.clear();
        self.key_slots.resize(self.reserved.len() * n2, u32::MAX);
        self.index.clear();
        self.index.reserve(self.keys.len());
        for (i, (key, k)) in self.keys.iter().zip(&self.reserved).enumerate() {
            sorted_group_slots(&p, k, &mut self.key_slots[i * n2..(i + 1) * n2]);
            self.index.insert(key.clone(), i as u32);
        }
        self.combined = Some(p);
        self.builds += 1;
    }

    /// Reserve the couplings the current contacts need: those of `kept` as they are, and
    /// for each (key, need) of `needs` the coupling of that key with the need added to it
    /// (reserved anew if there is none) — a coupling gathers what its contacts need while
    /// it is reserved, so that a weight that wanders about the floor rebuilds once, not at
    /// every crossing; of the couplings reserved now that no current contact uses, those
    /// used within the last [`KEEP_STEPS`] steps are kept, at most [`stale_budget`] of
    /// them, the most recently used first; build the pattern.
    fn rebuild(&mut self, kept: &[u32], mut needs: Vec<(CouplingKey, CouplingKey)>) {
        let step = self.step;
        let mut grown: Vec<Option<CouplingKey>> = vec![None; self.keys.len()];
        for &k in kept {
            grown[k as usize] = Some(self.reserved[k as usize].clone());
        }
        needs.sort_unstable();
        let mut fresh: Vec<(CouplingKey, CouplingKey)> = Vec::new();
        for (key, need) in needs {
            if let Ok(i) = self.keys.binary_search(&key) {
                let r = grown[i].take().unwrap_or_else(|| self.reserved[i].clone());
                grown[i] = Some(union_key(&r, &need));
                continue;
            }
            match fresh.last_mut() {
                Some((p, k)) if *p == key => *k = union_key(k, &need),
                _ => fresh.push((key, need)),
            }
        }
        let mut current: Vec<(CouplingKey, CouplingKey, usize)> =
            fresh.into_iter().map(|(p, k)| (p, k, step)).collect();
        let mut stale: Vec<(usize, CouplingKey, CouplingKey)> = Vec::new();
        for (((p, k), t), g) in self
            .keys
            .drain(..)
            .zip(self.reserved.drain(..))
            .zip(self.last_used.drain(..))
            .zip(grown)
        {
            match g {
                Some(g) => current.push((p, g, step)),
                None if step.saturating_sub(t) <= KEEP_STEPS => stale.push((t, p, k)),
                None => {}
            }
        }
        // the most recently used first, then by key
        stale.sort_unstable_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
        stale.truncate(stale_budget(current.len()));
        current.extend(stale.into_iter().map(|(t, p, k)| (p, k, t)));
        current.sort_unstable_by(|a, b| a.0.cmp(&b.0));
        for (p, k, t) in current {
            self.keys.push(p);
            self.reserved.push(k);
            self.last_used.push(t);
        }
        self.build();
    }

    /// The pattern for the current `contacts`, with their tangent slots bound.
    /// `complete`: every contact's whole coupling (a symmetric tangent, whose solve with
    /// the factor is then direct), else its coupling without its small rows where only that
    /// one is reserved (see [`contact_key`]). Decided at the first request of a step (a
    /// tangent that turns symmetric later in the step keeps the step's pattern: a rebuild
    /// within the step cost more symbolic analyses than the direct solves saved).
    fn for_contacts(
        &mut self,
        contacts: &ContactSet,
        complete: bool,
        threads: &crate::parallel::Threads,
    ) -> Arc<SparsePattern> {
        if self.bound == Some((contacts.generation(), self.step)) {
            if let Some(p) = &self.combined {
                return p.clone();
            }
        }
        let cs = &contacts.contacts;
        // every contact of a discretisation has the same number of unknowns
        let nc = contacts.contact_dofs();
        if nc != self.contact_dofs {
            self.keys.clear();
            self.reserved.clear();
            self.last_used.clear();
            self.contact_dofs = nc;
            self.combined = None;
        }
        if self.combined.is_none() {
            self.build();
        }
        // each contact's coupling (see the type's docs: by its whole coupling or its index
        // key; all its coupled unknowns when the pattern must be complete); a contact with
        // none rebuilds the pattern (and whether it was bound through a coupling that
        // leaves some of its rows out); local work of each contact, on the run's threads
        let lookup = |index: &HashMap<CouplingKey, u32, _>, reserved: &[CouplingKey]| {
            threads.map(cs.len(), |i| {
                let c = &cs[i];
                let coupled = c.coupled_dofs();
                // the whole coupling, else the one of its index key (which holds the
                // required unknowns, and maybe all)
                if let Some(&k) = index.get(&coupling_key(&coupled)) {
                    return (k, false);
                }
                if let Some(&k) = index.get(&index_key(c)) {
                    let whole = holds(&reserved[k as usize], &coupled);
                    if whole || !complete {
                        return (k, !whole);
                    }
                }
                (u32::MAX, false)
            })
        };
        let mut found = lookup(&self.index, &self.reserved);
        if found.iter().any(|f| f.0 == u32::MAX) {
            // a complete pattern: the contacts that found their whole coupling keep it, the
            // others reserve theirs (found by itself); else every contact's coupling
            // without its small rows ([`contact_key`]) and the one it was found by (if
            // any), under its index key
            let (kept, needs): (Vec<u32>, Vec<_>) = match complete {
                true => (
                    found
                        .iter()
                        .map(|f| f.0)
                        .filter(|&k| k != u32::MAX)
                        .collect(),
                    cs.iter()
                        .zip(&found)
                        .filter(|(_, f)| f.0 == u32::MAX)
                        .map(|(c, _)| {
                            let k = coupling_key(&c.coupled_dofs());
                            (k.clone(), k)
                        })
                        .collect(),
                ),
                false => (
                    Vec::new(),
                    cs.iter()
                        .zip(&found)
                        .map(|(c, f)| {
                            let need = contact_key(c);
                            let need = match f.0 {
                                u32::MAX => need,
                                k => union_key(&self.reserved[k as usize], &need),
                            };
                            (index_key(c), need)
                        })
                        .collect(),
                ),
            };
            self.rebuild(&kept, needs);
            found = lookup(&self.index, &self.reserved);
        }
        self.complete = !found.iter().any(|f| f.1);
        for &(ki, _) in &found {
            self.last_used[ki as usize] = self.step;
        }
        // bind: each contact's unknowns to their places in its coupling (on the run's
        // threads)
        let reserved = &self.reserved;
        self.contact_bindings = threads.map(cs.len(), |ci| {
            let (c, ki) = (&cs[ci], found[ci].0);
            let key = &reserved[ki as usize];
            let places = match (key.fixed(), c.dofs.fixed()) {
                // constant covers: arrays of a known length
                (Some(k), Some(dofs)) => bind(k, dofs),
                _ => {
                    let (k, dofs): (&[usize], &[usize]) = (key, &c.dofs);
                    bind(k, dofs)
                }
            };
            Binding {
                coupling: ki,
                places,
            }
        });
        self.bound = Some((contacts.generation(), self.step));
        self.combined.clone().expect("pattern")
    }
}

/// A contact's coupling and the places of its unknowns in it (see
/// [`TangentPattern::contact_bindings`]).
#[derive(Debug, Clone, Copy)]
struct Binding {
    coupling: u32,
    places: [u8; MAX_CONTACT_DOFS],
}

impl Binding {
    /// values += the contact's local tangent block `k` (n² row-major over its n unknowns).
    #[inline]
    fn scatter(&self, values: &mut [f64], key_slots: &[u32], n: usize, k: &[f64]) {
        let n2 = n * n;
        let c = self.coupling as usize;
        global::scatter_through(
            values,
            &key_slots[c * n2..(c + 1) * n2],
            &self.places[..n],
            k,
        );
    }

    /// [`Binding::scatter`] into the part of the values that holds slots `lo ..`
    /// ([`global::scatter_through_part`]).
    #[inline]
    fn scatter_part(&self, part: &mut [f64], lo: usize, key_slots: &[u32], n: usize, k: &[f64]) {
        let n2 = n * n;
        let c = self.coupling as usize;
        global::scatter_through_part(
            part,
            lo,
            &key_slots[c * n2..(c + 1) * n2],
            &self.places[..n],
            k,
        );
    }
}

/// The place in its coupling's `key` of each of a contact's unknowns `dofs` (the contact's
/// tangent entry (i, j) is the key's entry (place i, place j)). An unknown of the contact's
/// that is not in the key (its rows are zeros, or below the pattern's floor:
/// [`contact_key`], [`TangentPattern::complete`]) has no place, nor slot.
#[inline(always)]
fn bind(key: &[usize], dofs: &[usize]) -> [u8; MAX_CONTACT_DOFS] {
    let mut places = [global::NO_PLACE; MAX_CONTACT_DOFS];
    for (p, &d) in places.iter_mut().zip(dofs) {
        if d != NO_DOF {
            *p = key
                .iter()
                .position(|&x| x == d)
                .map_or(global::NO_PLACE, |i| i as u8);
        }
    }
    places
}

/// [`global::group_slots`] of a coupling key (its unknowns sorted, [`NO_DOF`] last): each
/// column's rows found by one merge along the column instead of a search per entry.
fn sorted_group_slots(p: &SparsePattern, key: &[usize], out: &mut [u32]) {
    let m = key.len();
    out.iter_mut().for_each(|s| *s = u32::MAX);
    let free = free_unknowns(key);
    for (j, &col) in free.iter().enumerate() {
        let (mut k, end) = (p.col_ptr[col], p.col_ptr[col + 1]);
        for (i, &row) in free.iter().enumerate() {
            while k < end && p.row_idx[k] < row {
                k += 1;
            }
            assert!(
                k < end && p.row_idx[k] == row,
                "a coupling of the key is missing from the pattern"
            );
            out[i * m + j] = k as u32;
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

/// y = A x for a symmetric A stored in full over `p`, on the calling thread ([`rows_mul`]:
/// each y_i one ordered sum).
pub(crate) fn sym_mul(p: &SparsePattern, a: &[f64], x: &[f64], y: &mut [f64]) {
    sym_mul_on(&crate::parallel::Threads::default(), p, a, x, y);
}

/// [`sym_mul`] on `threads` (the same y whatever their number).
pub(crate) fn sym_mul_on(
    threads: &crate::parallel::Threads,
    p: &SparsePattern,
    a: &[f64],
    x: &[f64],
    y: &mut [f64],
) {
    rows_mul(threads, p, |k| a[k], x, y);
}

/// y = A v for a symmetric A over `p` whose entry in slot k is `value(k)`, by rows (= columns),
/// each row one ordered sum (the same result for every thread count).
fn rows_mul(
    threads: &crate::parallel::Threads,
    p: &SparsePattern,
    value: impl Fn(usize) -> f64 + Sync,
    v: &[f64],
    y: &mut [f64],
) {
    threads.for_each_mut(y, |i, yi| {
        let mut s = 0.0;
        for k in p.col_ptr[i]..p.col_ptr[i + 1] {
            s += value(k) * v[p.row_idx[k]];
        }
        *yi = s;
    });
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
    /// The step's inertia coefficient is in `l` (a dynamic step).
    pub inertia: bool,
    pub sigma: f64,
    pub scale: f64,
    pub work: Vec<f64>,
}

impl StepSystem<'_> {
    /// What an assembly of the tangent depends on besides the contacts' coefficients (see
    /// [`TangentPattern::assembled`]).
    fn assembly_key(&self, symmetric: bool) -> AssemblyKey {
        (
            self.contacts.generation(),
            self.tangent.step,
            symmetric,
            self.sigma.to_bits(),
        )
    }

    /// The true residual at `x` (every piece on its own branch) into `r`, with the physical
    /// force scale; with `along` = Some(d), the largest relative motion of d at a contact
    /// ([`PiecewiseSystem::step_size`]) in the same pass (0 without). Returns how many
    /// pieces are on another branch than the chosen one, and that motion.
    fn residual_measuring(
        &mut self,
        x: &[f64],
        along: Option<&[f64]>,
        r: &mut [f64],
    ) -> (usize, f64) {
        self.linear_residual(x, r);
        // physical force scale: loads and weights, constraint reactions, contact forces
        let mut w = std::mem::take(&mut self.work);
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
        let (inconsistent, motion) =
            self.contacts
                .add_forces_along(x, along, r, true, Some(&mut w));
        let inconsistent = inconsistent + self.bolts.add_forces(x, r, true);
        self.bolts.add_force_magnitudes(x, &mut w);
        self.scale = w.iter().map(|v| v * v).sum::<f64>().sqrt();
        self.work = w;
        (inconsistent, motion)
    }

    fn linear_residual(&self, x: &[f64], r: &mut [f64]) {
        // the same row sums as sym_mul, on the run's threads
        let l = self.l;
        rows_mul(self.threads, self.tangent.element(), |k| l[k], x, r);
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
        // by rows (= columns: L and M are symmetric), each row one ordered sum; without
        // regularisation (every dynamic step) L alone: l + 0·m is l, bit for bit, and M's
        // values need not be read
        if sigma == 0.0 {
            rows_mul(self.threads, p, |k| l[k], v, y);
        } else {
            rows_mul(self.threads, p, |k| l[k] + sigma * m[k], v, y);
        }
        self.contacts.apply_tangent(v, y);
        self.bolts.apply_tangent(v, y);
    }

    fn has_inertia(&self) -> bool {
        self.inertia
    }

    fn pattern(&mut self) -> Arc<SparsePattern> {
        // a regularised (static) step's solves are near mechanisms: whole couplings too
        let complete = self.contacts.tangent_is_symmetric() || self.sigma > 0.0;
        self.tangent
            .for_contacts(self.contacts, complete, self.threads)
    }

    /// The element part, then every contact's block in contact order, into each slot. On
    /// two threads the slots are split in two parts by columns (about half the stored
    /// values each), each part's thread adding what falls in its own: a contact's block
    /// is computed by each part that holds one of its columns (its unknowns). Every slot
    /// receives the same sums in the same order on any number of threads.
    fn assemble(&mut self, values: &mut [f64], symmetric: bool) {
        let p = self.pattern();
        let nc = self.contacts.contact_dofs();
        let cs = &self.contacts.contacts;
        let t = &mut *self.tangent;
        t.assembled_coef.clear();
        t.assembled_coef
            .extend(cs.iter().map(|c| ContactSet::tangent_coef(c, symmetric)));
        let (l, m, sigma) = (self.l, self.m, self.sigma);
        let (map, key_slots, bindings) = (&t.map, &t.key_slots, &t.contact_bindings);
        let coefs = &t.assembled_coef;
        // the slots lo .. lo + part.len() of columns `cols`, whose element entries are `ks`
        let part = |part: &mut [f64], lo: usize, cols: Range<usize>, ks: Range<usize>| {
            for (&slot, k) in map[ks.clone()].iter().zip(ks) {
                part[slot as usize - lo] += l[k] + sigma * m[k];
            }
            let mut k = vec![0.0; nc * nc];
            for (ci, c) in cs.iter().enumerate() {
                if !c.dofs.iter().any(|d| cols.contains(d)) {
                    continue;
                }
                if ContactSet::block_into(c, coefs[ci], &mut k) {
                    bindings[ci].scatter_part(part, lo, key_slots, nc, &k);
                }
            }
        };
        let element = t.element();
        let threads = self
            .threads
            .for_items(cs.len(), crate::parallel::MIN_PARALLEL);
        if threads.count() > 1 && p.n > 1 {
            // the first column whose slots start past half of them (the element entries of
            // a column map into the same column's slots: embed)
            let mid = p.col_ptr[1..p.n].partition_point(|&s| s < p.nnz() / 2) + 1;
            let (s, ke) = (p.col_ptr[mid], element.col_ptr[mid]);
            let (a, b) = values.split_at_mut(s);
            threads.join(
                || part(a, 0, 0..mid, 0..ke),
                || part(b, s, mid..p.n, ke..element.nnz()),
            );
        } else {
            part(values, 0, 0..p.n, 0..element.nnz());
        }
        self.bolts.assemble(values, &self.tangent.map);
        self.tangent.assembled = Some(self.assembly_key(symmetric));
    }

    /// Bring `values`, which hold this tangent's last assembly (`assemble`, then any
    /// updates), to the tangent of the branches chosen now: only the contacts whose
    /// coefficients changed since, each by the block of the difference (the block is
    /// linear in them). Refused (false, `values` untouched) when anything else may have
    /// changed: another contact list or step, another kind (`symmetric`), another σ, or
    /// bolts (whose tangent is assembled whole).
    fn update_assembly(&mut self, values: &mut [f64], symmetric: bool) -> bool {
        let key = self.assembly_key(symmetric);
        let t = &mut *self.tangent;
        let cs = &self.contacts.contacts;
        if t.assembled != Some(key)
            || !self.bolts.is_empty()
            || t.assembled_coef.len() != cs.len()
            || t.bound != Some((self.contacts.generation(), t.step))
        {
            return false;
        }
        let nc = self.contacts.contact_dofs();
        let n2 = nc * nc;
        // the contacts whose coefficients changed since the assembly, with the change:
        // found in two halves on the run's threads (each contact read where the passes over
        // the contacts read it, contact/set.rs `split_pass`), then scattered in contact order
        let scan = |cs: &[Contact], old: &mut [[f64; 4]], first: usize| {
            let mut changed = Vec::new();
            for (i, (c, old)) in cs.iter().zip(old.iter_mut()).enumerate() {
                let new = ContactSet::tangent_coef(c, symmetric);
                if new == *old {
                    continue;
                }
                let delta = [
                    new[0] - old[0],
                    new[1] - old[1],
                    new[2] - old[2],
                    new[3] - old[3],
                ];
                *old = new;
                changed.push((first + i, delta));
            }
            changed
        };
        let threads = self
            .threads
            .for_items(cs.len(), crate::parallel::MIN_PARALLEL);
        let changed = if threads.count() > 1 {
            let mid = cs.len() / 2;
            let (c0, c1) = cs.split_at(mid);
            let (o0, o1) = t.assembled_coef.split_at_mut(mid);
            let (mut a, b) = threads.join(|| scan(c0, o0, 0), || scan(c1, o1, mid));
            a.extend(b);
            a
        } else {
            scan(cs, &mut t.assembled_coef, 0)
        };
        let mut k = vec![0.0; n2];
        for (ci, delta) in changed {
            if ContactSet::block_into(&cs[ci], delta, &mut k) {
                t.contact_bindings[ci].scatter(values, &t.key_slots, nc, &k);
            }
        }
        true
    }

    fn is_symmetric(&self) -> bool {
        self.contacts.tangent_is_symmetric()
    }

    fn unsymmetric_pieces(&self) -> usize {
        self.contacts.unsymmetric_count()
    }

    fn pattern_is_complete(&self) -> bool {
        self.tangent.complete
    }

    fn threads(&self) -> crate::parallel::Threads {
        self.threads.clone()
    }
}

impl PiecewiseSystem for StepSystem<'_> {
    fn choose_branches(&mut self, x: &[f64], first: bool) -> usize {
        self.contacts.choose_branches(x, first) + self.bolts.choose_branches(x)
    }

    fn choose_own_branches(&mut self, x: &[f64]) -> usize {
        self.contacts.choose_own_branches(x) + self.bolts.choose_branches(x)
    }

    /// (Bolts are always on their own branches.)
    fn chosen_are_own(&self) -> bool {
        self.contacts.chosen_are_own()
    }

    fn residual_on_chosen(&mut self, x: &[f64], r: &mut [f64]) {
        self.linear_residual(x, r);
        self.contacts.add_forces(x, r, false, None);
        self.bolts.add_forces(x, r, false);
    }

    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> usize {
        self.residual_measuring(x, None, r).0
    }

    /// The true residual and the direction's size ([`StepSystem::step_size`]) in one pass
    /// over the contacts.
    fn residual_along(&mut self, x: &[f64], d: &[f64], r: &mut [f64]) -> (usize, f64) {
        self.residual_measuring(x, Some(d), r)
    }

    fn force_scale(&self) -> f64 {
        self.scale
    }

    fn set_regularisation(&mut self, sigma: f64) {
        self.sigma = sigma;
    }

    fn first_kink(&self, x: &[f64], d: &[f64]) -> f64 {
        self.contacts.first_kink(x, d)
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

    fn key(d: &[usize], n: usize) -> CouplingKey {
        let mut k = vec![NO_DOF; n];
        k[..d.len()].copy_from_slice(d);
        coupling_key(&k)
    }

    /// A coupling gathers its contacts' unknowns while they fit in one key; one that
    /// would not fit is the new need alone (which holds the key it is found by).
    #[test]
    fn couplings_gather_what_their_contacts_need() {
        let a = key(&[7, 2, 4], 6);
        assert!(holds(&a, &[2, NO_DOF, 7]));
        assert!(!holds(&a, &[2, 3]));
        let u = union_key(&a, &key(&[4, 9], 6));
        assert_eq!(free_unknowns(&u), &[2, 4, 7, 9]);
        assert_eq!(u.len(), 6);
        let b = key(&[1, 3, 5, 6], 6);
        assert_eq!(union_key(&u, &b), b, "8 unknowns do not fit in 6");
    }

    #[test]
    fn sorted_group_slots_are_group_slots() {
        let p = SparsePattern::from_groups(
            9,
            [&[0usize, 2, 5][..], &[3, 4][..], &[1, 2, 4, 8][..]].into_iter(),
        );
        let key = [1usize, 2, 4, 8, NO_DOF, NO_DOF];
        let (mut a, mut b) = ([0u32; 36], [0u32; 36]);
        sorted_group_slots(&p, &key, &mut a);
        global::group_slots(&p, &key, &mut b);
        assert_eq!(a, b);
    }

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

#[cfg(test)]
mod update_tests {
    use super::super::{Rhs, Simulation};
    use crate::contact::law::Branch;
    use crate::solver::{PiecewiseSystem, TangentOperator};

    /// The simulation of the model `text` after its first `steps` steps.
    fn after_steps(text: &str, steps: usize) -> Simulation {
        let model = crate::model::parse_model(text, std::path::Path::new(".")).unwrap();
        let mut sim = Simulation::new(model).unwrap();
        for _ in 0..steps {
            sim.advance().unwrap();
        }
        sim
    }

    /// A 10×10 brick wall (the scaling study's) after its first two steps: enough contacts
    /// for the passes' two halves, some sliding.
    fn wall_after_two_steps() -> Simulation {
        let mut o = crate::generate::WallOptions::new(10, 10);
        o.steps = 3;
        after_steps(&crate::generate::brick_wall_model(&o), 2)
    }

    /// a sin(i f) over n unknowns: an increment or a direction of every unknown.
    fn wave(n: usize, a: f64, f: f64) -> Vec<f64> {
        (0..n).map(|i| a * ((i as f64) * f).sin()).collect()
    }

    /// The values as bits (bit-for-bit comparisons).
    fn bits(v: &[f64]) -> Vec<u64> {
        v.iter().map(|x| x.to_bits()).collect()
    }

    /// `f` on the next step's system (Δt 1 ms) with no load: its tangents only are used.
    fn with_zero_load<T>(sim: &mut Simulation, f: impl FnOnce(&mut super::StepSystem) -> T) -> T {
        let n = sim.n_dofs();
        let (load, load_abs) = (vec![0.0; n], vec![0.0; n]);
        let rhs = Rhs {
            f: &load,
            f_ext_abs: &load_abs,
            t1: sim.time + 0.001,
            dt: 0.001,
        };
        sim.with_system(&rhs, 1.0e6, None, |sys, _| f(sys))
    }

    /// A tangent updated contact by contact ([`TangentOperator::update_assembly`]) is the
    /// tangent assembled anew, to rounding, whatever branches the contacts moved between
    /// (open, stuck, sliding); an update is refused for another kind or another σ.
    #[test]
    fn an_updated_tangent_is_the_tangent_assembled_anew() {
        let text = "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 2\n\
             gravity = [0.0, -9.81]\nfriction = \"return-mapping\"\n\
             [cover]\nsize = 0.25\n\
             [[material]]\nname = \"m\"\ndensity = 2500.0\nyoung = 1.0e9\npoisson = 0.25\n\
             [[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
             [[block]]\nname = \"base\"\nmaterial = \"m\"\nfixed = true\n\
             vertices = [[-1.0, -0.5], [2.0, -0.5], [2.0, 0.0], [-1.0, 0.0]]\n\
             [[block]]\nname = \"a\"\nmaterial = \"m\"\n\
             vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]]\n\
             [[block]]\nname = \"b\"\nmaterial = \"m\"\n\
             vertices = [[0.2, 0.5], [0.8, 0.5], [0.8, 1.0], [0.2, 1.0]]\n";
        let mut sim = after_steps(text, 1);
        let n = sim.n_dofs();
        with_zero_load(&mut sim, |sys| {
            assert!(sys.contacts.contacts.len() >= 4);
            let nnz = sys.pattern().nnz();
            let fresh = |sys: &mut super::StepSystem, symmetric| {
                let mut v = vec![0.0; nnz];
                sys.assemble(&mut v, symmetric);
                v
            };
            // motions that open, press and shear the joints by turns
            let motion = |s: f64| -> Vec<f64> {
                (0..n)
                    .map(|i| s * 1e-6 * ((i as f64) * 1.7 + s).sin())
                    .collect()
            };
            sys.choose_branches(&vec![0.0; n], true);
            let mut held = fresh(sys, false);
            let mut changed = 0;
            for s in 1..=6 {
                changed += sys.choose_branches(&motion(s as f64), false);
                assert!(sys.update_assembly(&mut held, false));
                // (an assembly anew records the coefficients `held` now holds)
                let anew = fresh(sys, false);
                let big = anew.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (h, a) in held.iter().zip(&anew) {
                    assert!((h - a).abs() <= 1e-13 * big, "{h} vs {a}");
                }
            }
            assert!(changed > 0, "no contact changed branch");
            // another kind, another σ: refused, the values untouched
            let before = held.clone();
            assert!(!sys.update_assembly(&mut held, true));
            sys.set_regularisation(1.0);
            assert!(!sys.update_assembly(&mut held, false));
            assert_eq!(held, before);
        });
    }

    /// The tangent assembled on two threads (its slots in two parts by columns, each
    /// part's thread adding the element part and every contact block that falls in it) is
    /// the one assembled on one, bit for bit: every slot the same sums in the same order.
    #[test]
    fn a_tangent_assembled_in_two_parts_is_the_one_assembled_whole() {
        let mut sim = wall_after_two_steps();
        let n = sim.n_dofs();
        let mut assembled = Vec::new();
        for t in [1, 2] {
            sim.set_threads(crate::parallel::Threads::new(t).unwrap());
            assembled.push(with_zero_load(&mut sim, |sys| {
                // enough contacts for two parts, some of them sliding (unsymmetric blocks)
                assert!(sys.contacts.contacts.len() >= crate::parallel::MIN_PARALLEL);
                sys.choose_branches(&wave(n, 1e-5, 1.7), true);
                let mut v = vec![0.0; sys.pattern().nnz()];
                sys.assemble(&mut v, false);
                (v, sys.unsymmetric_pieces())
            }));
        }
        assert!(assembled[0].1 > 0, "no contact slides");
        assert!(assembled[0].0.iter().any(|&v| v != 0.0));
        assert_eq!(bits(&assembled[0].0), bits(&assembled[1].0));
    }

    /// The full step's residual and its direction's size in one pass
    /// ([`PiecewiseSystem::residual_along`]) are, bit for bit, the true residual (with its
    /// force scale and count of pieces off their chosen branches) and the step size
    /// computed apart, on one thread and on two.
    #[test]
    fn a_residual_along_a_direction_is_the_residual_and_the_step_size() {
        let mut sim = wall_after_two_steps();
        let n = sim.n_dofs();
        for t in [1, 2] {
            sim.set_threads(crate::parallel::Threads::new(t).unwrap());
            with_zero_load(&mut sim, |sys| {
                let (x, d) = (wave(n, 1e-5, 1.7), wave(n, 3e-6, 0.9));
                sys.choose_branches(&x, true);
                let (mut r0, mut r1) = (vec![0.0; n], vec![0.0; n]);
                let inc0 = sys.residual(&x, &mut r0);
                let (scale0, size0) = (sys.force_scale(), sys.step_size(&d));
                let (inc1, size1) = sys.residual_along(&x, &d, &mut r1);
                assert!(size0 > 0.0 && inc0 > 0, "{size0} {inc0}");
                assert_eq!(inc0, inc1);
                assert_eq!(size0.to_bits(), size1.to_bits());
                assert_eq!(scale0.to_bits(), sys.force_scale().to_bits());
                assert_eq!(bits(&r0), bits(&r1));
            });
        }
    }

    /// A choice of branches at the iterate of the latest true residual takes what that
    /// evaluation prepared (contact/set.rs `ContactSet::evaluated`): it is, bit for bit, the
    /// choice made afresh from the same branches — at that iterate, and at another one
    /// (where nothing prepared may be taken).
    #[test]
    fn a_choice_after_a_true_residual_is_the_choice_made_afresh() {
        let mut sim = wall_after_two_steps();
        let n = sim.n_dofs();
        with_zero_load(&mut sim, |sys| {
            let at = |a: f64, f: f64| wave(n, a, f);
            let state = |sys: &super::StepSystem| -> Vec<(Branch, [u64; 4])> {
                sys.contacts
                    .contacts
                    .iter()
                    .map(|c| (c.branch, c.coef.map(f64::to_bits)))
                    .collect()
            };
            let restore = |sys: &mut super::StepSystem, s: &[(Branch, [u64; 4])]| {
                for (c, (b, k)) in sys.contacts.contacts.iter_mut().zip(s) {
                    c.branch = *b;
                    c.coef = k.map(f64::from_bits);
                }
            };
            sys.choose_branches(&at(1e-5, 1.7), true);
            let mut r = vec![0.0; n];
            let mut changes = 0;
            for (k, (a, f)) in [(2e-5, 0.3), (1e-5, 2.9), (3e-5, 1.1), (5e-6, 0.7)]
                .into_iter()
                .enumerate()
            {
                let x = at(a, f);
                let before = state(sys);
                // afresh
                let fresh = sys.choose_branches(&x, false);
                let (fresh_state, fresh_own) = (state(sys), sys.chosen_are_own());
                // after a true residual at x (prepared), or at another iterate
                restore(sys, &before);
                let evaluated = if k % 2 == 0 {
                    x.clone()
                } else {
                    at(a, 1.3 * f)
                };
                sys.residual(&evaluated, &mut r);
                let prepared = sys.choose_branches(&x, false);
                assert_eq!(prepared, fresh, "iterate {k}");
                assert_eq!(sys.chosen_are_own(), fresh_own, "iterate {k}");
                assert!(state(sys) == fresh_state, "iterate {k}");
                changes += fresh;
            }
            assert!(changes > 0, "no contact changed branch");
        });
    }
}
