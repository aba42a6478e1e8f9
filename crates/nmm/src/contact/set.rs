//! The contact set of a step: detection on the NMM geometry, vertex–edge kinematics on the
//! covers, tributary weights, and the friction law at every Newton iterate.
//!
//! **Kinematics.** A contact is a boundary vertex P of block A (a material point of element
//! e_A with weights w_A) against a boundary segment of block B, at the point Q of the
//! segment nearest to P (a material point of the segment's element e_B with weights w_B).
//! With n the outward unit normal of B's segment and t its unit direction, both taken on
//! the geometry at the start of the step (small displacement per step, as in DDA/NMM):
//!
//! g_N(Δu) = g_N⁰ + n · (Δu_P − Δu_Q),   Δg_S(Δu) = t · (Δu_P − Δu_Q),
//!
//! with Δu_P = Σ_k w_A,k Δu_k and Δu_Q = Σ_k w_B,k Δu_k, i.e. g_N = g_N⁰ + b_Nᵀ Δu and
//! Δg_S = b_Sᵀ Δu over the unknowns of the two elements (2 × the basis's unknowns per
//! element: [`CONTACT_DOFS`] for constant covers; the rows are the basis's
//! [`crate::cover::CoverBasis::directional_row`]s).
//!
//! **Integration of the contact traction (tributary weights, two passes).** The contact
//! virtual work ∫_Γ (t_N δg_N + t_S δg_S) dΓ is integrated by the vertex (trapezoidal)
//! rule: the interface tractions are τ_N = ε_N g_N and τ_S = ε_S g_S^e with the penalties
//! per unit length ε = 2 p / s̄ (`normal_penalty`, `shear_penalty` p in N/m per metre of
//! thickness; s̄ the mean length of the model's boundary segments, i.e. the mean spacing of
//! boundary vertices — block corners and the points where block edges cross mesh lines).
//! As in DDA, where every vertex contact is a spring p, every vertex of either face of an
//! interface carries about one spring p; unlike a spring per vertex, the springs are
//! weighted by the length of interface each vertex stands for, so that the traction is
//! consistent. Each vertex contact stands for its **tributary length**
//!
//! λ_P = ½ Σ_{s ∋ P} |proj_B(s_½)|,
//!
//! the projected length, onto B's segment and clipped to the polygon edge of B that the
//! segment belongs to, of the half of each of A's two boundary segments at P that faces B
//! (outward normals opposed, n_s · n < 0; a segment facing away counts zero). The vertices
//! of A on B and the vertices of B on A are both taken (a corner of either block on a face
//! of the other is then always found), each with **half** its tributary length, so that the
//! two passes integrate the same traction once, not twice. For two flat faces pressed
//! together, each pass alone is the trapezoidal rule of the interface, exact for the
//! uniform traction whatever the refinement points of the two faces are (they are where the
//! faces cross mesh lines): a uniform pressure is transmitted as a uniform pressure, on,
//! near or between mesh lines (`tests/contact_patch.rs`). Each contact is then a spring
//! pair p_N = ε_N w, p_S = ε_S w with w = λ_P / 2 and cohesion c w; its Coulomb law is the
//! law of the tractions scaled by w (the laws are homogeneous of degree one in (p, c)).
//! A point contact (a corner on a face) carries the springs of its corner's tributary
//! length: about p when the corner's edges are about s̄ long.
//!
//! **Forces.** The contact's virtual work t_N δg_N + t_S δg_S gives the internal force
//! f_c = b_N t_N + b_S t_S and the tangent
//! K_c = b_N (∂t_N/∂g_N b_Nᵀ + ∂t_N/∂g_S b_Sᵀ) + b_S (∂t_S/∂g_N b_Nᵀ + ∂t_S/∂g_S b_Sᵀ),
//! unsymmetric for a sliding contact under return mapping. The force on block A is
//! −(t_N n + t_S t) (t_N ≤ 0: it pushes A out of B) and on block B the opposite.
//!
//! **Identity and state.** A contact is identified by (block A, vertex of A, block B), so
//! that it keeps its elastic shear gap and its stick/slide state when its vertex passes
//! from one segment of B to the next. States are committed only when a step converges.
//! Each contact has its law ([`LawId`]: its interface's own, else the analysis'
//! `friction`), which owns its state ([`LawState`]) and chooses the branch the contact is
//! linearised on at a Newton iterate ([`ContactSet::choose_branches`]). The state of a
//! closed contact is kept for the next step; an open one starts afresh, unless its law
//! keeps the state ([`super::law::FrictionLaw::lasting`]: a broken bond), which then outlives the
//! contact's detection. A contact whose law changed (its vertex passed onto a face of
//! another interface) starts afresh under its new law.

use super::broad::sweep_and_prune;
use super::friction::{ContactStatus, FrictionParams, LawResponse};
use super::law::{Branch, IterationContext, LawId, LawState};
use super::narrow::{vertex_edge_contacts_of, NarrowParams, Outline, VertexEdge};
use super::restitution::DashpotTable;
use super::InterfaceView;
use crate::cover::basis::{ELEMENT_DOFS, MAX_ELEMENT_DOFS, NO_DOF};
use crate::cover::{barycentric, Discretisation};
use crate::geometry::{cross, dot, norm, sub, Aabb, Vec2};
use crate::model::Model;
use crate::same_bits;
/// The contact set's maps by contact (looked up for every contact at every step; SipHash,
/// the standard library's default, was 1% of the arch example's run). Random per process,
/// like the default: nothing may depend on their order.
type HashMap<K, V> = std::collections::HashMap<K, V, foldhash::fast::RandomState>;
type HashSet<K> = std::collections::HashSet<K, foldhash::fast::RandomState>;

mod insitu;
mod saved;
mod slits;
pub use saved::SavedContacts;

/// Unknowns a contact couples with constant covers: those of the vertex's element and of
/// the edge's element (with first-order covers 36: [`ContactSet::contact_dofs`]).
pub const CONTACT_DOFS: usize = 2 * ELEMENT_DOFS;

/// Most unknowns of a contact of any basis (two elements of first-order covers).
pub const MAX_CONTACT_DOFS: usize = 2 * crate::cover::basis::MAX_ELEMENT_DOFS;

/// A contact's row over its unknowns: an array of [`CONTACT_DOFS`] for constant covers (no
/// allocation, loops of a known length), boxed for longer rows (first-order covers).
#[derive(Clone, Debug)]
pub enum ContactRow<T: Copy> {
    Fixed([T; CONTACT_DOFS]),
    Long(Box<[T]>),
}

impl<T: Copy> ContactRow<T> {
    /// A row of `n` copies of `x`.
    pub fn filled(x: T, n: usize) -> Self {
        if n == CONTACT_DOFS {
            ContactRow::Fixed([x; CONTACT_DOFS])
        } else {
            ContactRow::Long(vec![x; n].into_boxed_slice())
        }
    }

    /// The row as an array of the constant basis's length, if it is one.
    #[inline(always)]
    pub fn fixed(&self) -> Option<&[T; CONTACT_DOFS]> {
        match self {
            ContactRow::Fixed(a) => Some(a),
            ContactRow::Long(_) => None,
        }
    }
}

impl<T: Copy> From<&[T]> for ContactRow<T> {
    fn from(s: &[T]) -> Self {
        match <[T; CONTACT_DOFS]>::try_from(s) {
            Ok(a) => ContactRow::Fixed(a),
            Err(_) => ContactRow::Long(s.into()),
        }
    }
}

impl<T: Copy> std::ops::Deref for ContactRow<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        match self {
            ContactRow::Fixed(a) => a,
            ContactRow::Long(b) => b,
        }
    }
}

impl<T: Copy> std::ops::DerefMut for ContactRow<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        match self {
            ContactRow::Fixed(a) => a,
            ContactRow::Long(b) => b,
        }
    }
}

impl<T: Copy + PartialEq> PartialEq for ContactRow<T> {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}
impl<T: Copy + Eq> Eq for ContactRow<T> {}
impl<T: Copy + std::hash::Hash> std::hash::Hash for ContactRow<T> {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        (**self).hash(state)
    }
}
impl<T: Copy + Ord> PartialOrd for ContactRow<T> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl<T: Copy + Ord> Ord for ContactRow<T> {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        (**self).cmp(&**other)
    }
}

/// (block of the vertex, vertex index on its refined boundary, block of the edge).
pub type ContactKey = (usize, usize, usize);

#[derive(Debug, Clone)]
pub struct Contact {
    pub key: ContactKey,
    /// Segment of the edge block's boundary.
    pub segment: usize,
    pub dofs: ContactRow<usize>,
    pub bn: ContactRow<f64>,
    pub bs: ContactRow<f64>,
    /// Normal gap at the start of the step (negative: penetration; with in-situ stress the
    /// offset of [`insitu`] included).
    pub gn0: f64,
    /// Shear gap the contact starts its step with (the in-situ shear of a contact in the
    /// first step, [`insitu`]; else 0).
    pub gs0: f64,
    /// Length of interface this contact stands for (m): half its tributary length.
    pub weight: f64,
    /// The contact's springs and strength: the interface's per-length values × `weight`.
    pub params: FrictionParams,
    /// The contact's law.
    pub law: LawId,
    /// Committed state under its law (end of the last converged step).
    pub history: LawState,
    /// The contact is new to this step and its gap at the start of the step is within the
    /// touching tolerance (the closed-contact predictor holds it closed at the first iterate).
    pub touching: bool,
    /// Branch the latest Newton iterate was linearised on.
    pub branch: Branch,
    /// Its tangent [∂t_N/∂g_N, ∂t_N/∂g_S, ∂t_S/∂g_N, ∂t_S/∂g_S] (constant on a branch).
    pub coef: [f64; 4],
    /// The law's response (on its own branch) at the latest true evaluation.
    pub response: LawResponse,
    /// The branch the iteration rules choose at the latest true evaluation (from the
    /// branch chosen then), whether it is the law's own there, and its tangent: what
    /// [`ContactSet::choose_branches`] computes at that point (see `ContactSet::evaluated`).
    next: (Branch, bool, [f64; 4]),
    /// Vertex position at the start of the step.
    pub position: Vec2,
    pub normal: Vec2,
    pub tangent: Vec2,
    /// Joint that made the edge block's face, if any (it chose the interface).
    pub joint: Option<usize>,
    /// The branch it ended the last committed step on, and its record of the first
    /// iterate's predictions (`None`: it was not closed then).
    pub last: Option<(Branch, FirstChoice)>,
    /// The law's own branch at the first iterate of the step (its other prediction).
    pub first_own: Branch,
    /// The interface's restitution, if it has one (its dashpot is in `params`).
    pub restitution: Option<f64>,
}

/// Which prediction of a contact's branch at the first iterate of a step was right the last
/// time the two differed ([`ContactSet::choose_branches`]): the branch the contact ended the
/// step before on (`Last`), or the law's own branch at the step's first iterate (`Own`);
/// `Unknown` while they never differed (the contact then follows the majority of the last
/// step's contacts that had to choose, `ContactSet::prefer_last`).
///
/// Why two predictions (2026-12-05). The law's own branch at the first iterate (the last
/// increment repeated) foresees a contact that starts or stops sliding under a steady
/// drive, but not under an oscillation: a 10×10 brick wall come to rest (its contacts the
/// same from step to step after some 30 steps) put 6 to 14 contacts on another branch at
/// every first iterate — 2 or 3 solves a step where the last step's branches needed one.
/// Counted where the two differed and the step ended on one of them (a contact that stuck
/// last step and is predicted to slide): the last branch was right 358 times against 71 on
/// that wall, 122 against 1,183 on the shaking-table slope, 140 against 160 in the tunnel's
/// shaking; the trial's excess over the friction cone (10⁻⁶ to 10 times it) does not tell
/// them apart. So each contact keeps which one was right for it. Measured against the law's
/// own branch alone: the walls' 12 steps 54 / 66 / 57 / 57 → 51 / 65 / 57 / 58 solves
/// (10×10 … 40×40), the 10×10 wall's 40 steps 127 → 107 (1 a step from step 33 on); the
/// shaken slope's families (28 PGAs from 0.24 to 0.38 g, one thread; a chaotic problem:
/// read the sums) 705 → 513 cut steps, 370,119 → 332,034 solves, runs with more than 1% of
/// their steps cut 11 → 5; its example (0.3 g) 15 → 11 cut steps; the arch example 19,511 →
/// 18,345 solves (0 cuts both); the static jointed slope 200 both; but the tunnel 1,060 →
/// 1,085 solves (its static stages 19 both) and the shaking-table slope 10,544 → 10,579.
/// Measured and rejected: the last branch wherever the contact was closed (no record):
/// families 501 cut steps, 337,530 solves, but the tunnel 1,120, the shaking-table slope
/// 10,971, the jointed slope 218; the step's majority alone (no record per contact):
/// families 568 and 338,928, the tunnel 1,076, the example 22 cut steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FirstChoice {
    #[default]
    Unknown,
    Last,
    Own,
}

impl FirstChoice {
    /// Whether the last branch is taken when the predictions differ (`default`: the
    /// contacts' majority in the last step, for a contact with no record of its own).
    fn takes_last(self, default: bool) -> bool {
        match self {
            FirstChoice::Last => true,
            FirstChoice::Own => false,
            FirstChoice::Unknown => default,
        }
    }
}

/// A closed contact as committed at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Committed {
    pub law: LawId,
    /// Its state under its law.
    pub state: LawState,
    /// The outward normal it had.
    pub normal: Vec2,
    /// The branch the step ended on.
    pub branch: Branch,
    /// Its record of the first iterate's predictions.
    pub first_choice: FirstChoice,
}

/// (a + b_N · v, b_S · v) over a contact's rows.
#[inline(always)]
fn row_products(a: f64, dofs: &[usize], bn: &[f64], bs: &[f64], v: &[f64]) -> (f64, f64) {
    let (mut gn, mut gs) = (a, 0.0);
    for ((&d, bn), bs) in dofs.iter().zip(bn).zip(bs) {
        if d != NO_DOF {
            gn += bn * v[d];
            gs += bs * v[d];
        }
    }
    (gn, gs)
}

/// Kinks closer than this fraction of a direction are ties ([`ContactSet::first_kink`]).
const KINK_FLOOR: f64 = 1e-6;

/// y[d_i] += b_N,i t_N + b_S,i t_S over a contact's rows.
#[inline(always)]
fn row_scatter(dofs: &[usize], bn: &[f64], bs: &[f64], tn: f64, ts: f64, y: &mut [f64]) {
    for ((&d, bn), bs) in dofs.iter().zip(bn).zip(bs) {
        if d != NO_DOF {
            y[d] += bn * tn + bs * ts;
        }
    }
}

impl Contact {
    /// Whether its tangent block is unsymmetric (the friction coupling of a sliding
    /// contact, ∂t_N/∂g_S or ∂t_S/∂g_N).
    pub fn unsymmetric(&self) -> bool {
        self.coef[1] != 0.0 || self.coef[2] != 0.0
    }

    /// The rows as arrays of the constant basis's length (its loops then have a length the
    /// compiler knows), or `None` for another basis.
    #[inline(always)]
    fn fixed_rows(
        &self,
    ) -> Option<(
        &[usize; CONTACT_DOFS],
        &[f64; CONTACT_DOFS],
        &[f64; CONTACT_DOFS],
    )> {
        Some((self.dofs.fixed()?, self.bn.fixed()?, self.bs.fixed()?))
    }

    /// The unknowns the contact couples in the tangent: those whose rows are not both
    /// zero — a cover of weight zero at the vertex or at the point it faces (a point on a
    /// mesh edge, [`ZERO_WEIGHT`]) has rows of exact zeros —; [`NO_DOF`] for the others.
    pub fn coupled_dofs(&self) -> ContactRow<usize> {
        let mut dofs = self.dofs.clone();
        for ((d, &bn), &bs) in dofs.iter_mut().zip(self.bn.iter()).zip(self.bs.iter()) {
            if bn == 0.0 && bs == 0.0 {
                *d = NO_DOF;
            }
        }
        dofs
    }

    /// The unknowns of the contact's coupling in the tangent's **pattern** (the factorised
    /// preconditioner's): [`Contact::coupled_dofs`] without those whose rows are below
    /// [`PRECONDITIONER_WEIGHT`] of the contact's largest (|b_N| + |b_S| per unknown: at
    /// least the cover's weight, at most √2 times it, for order 0). The tangent applied to
    /// a vector keeps every row: only the factorised matrix leaves these out.
    pub fn preconditioner_dofs(&self) -> ContactRow<usize> {
        self.dofs_above(PRECONDITIONER_WEIGHT)
    }

    /// The unknowns the coupling a contact is bound through must hold where the pattern
    /// need not be complete: [`Contact::coupled_dofs`] without those whose rows are below
    /// [`REQUIRED_WEIGHT`] of the contact's largest (see there).
    pub fn required_dofs(&self) -> ContactRow<usize> {
        self.dofs_above(REQUIRED_WEIGHT)
    }

    /// [`Contact::coupled_dofs`] without those whose rows (|b_N| + |b_S|) are below
    /// `fraction` of the contact's largest.
    fn dofs_above(&self, fraction: f64) -> ContactRow<usize> {
        let size = |(bn, bs): (&f64, &f64)| bn.abs() + bs.abs();
        let largest = self
            .bn
            .iter()
            .zip(self.bs.iter())
            .map(size)
            .fold(0.0, f64::max);
        let floor = fraction * largest;
        let mut dofs = self.dofs.clone();
        for (d, r) in dofs.iter_mut().zip(self.bn.iter().zip(self.bs.iter())) {
            let s = size(r);
            if s == 0.0 || s < floor {
                *d = NO_DOF;
            }
        }
        dofs
    }

    /// (g_N, Δg_S) at the increment `du`.
    #[inline(always)]
    pub fn gaps(&self, du: &[f64]) -> (f64, f64) {
        let (gn, gs) = match self.fixed_rows() {
            Some((d, bn, bs)) => row_products(self.gn0, d, bn, bs, du),
            None => row_products(self.gn0, &self.dofs, &self.bn, &self.bs, du),
        };
        if self.gs0 != 0.0 {
            (gn, gs + self.gs0)
        } else {
            (gn, gs)
        }
    }

    /// (b_N · v, b_S · v) for a direction v.
    #[inline(always)]
    fn rates(&self, v: &[f64]) -> (f64, f64) {
        match self.fixed_rows() {
            Some((d, bn, bs)) => row_products(0.0, d, bn, bs, v),
            None => row_products(0.0, &self.dofs, &self.bn, &self.bs, v),
        }
    }

    /// The tangent's forces (t_N, t_S) for a direction `v` on the chosen branch, `None` for
    /// a zero tangent (an open contact).
    #[inline(always)]
    fn tangent_forces(&self, v: &[f64]) -> Option<(f64, f64)> {
        let [a, b, cc, d] = self.coef;
        if a == 0.0 && b == 0.0 && cc == 0.0 && d == 0.0 {
            return None;
        }
        let (gn, gs) = self.rates(v);
        Some((a * gn + b * gs, cc * gn + d * gs))
    }

    /// f += |b_N t_N + b_S t_S| componentwise (the force magnitudes of the force scale).
    #[inline(always)]
    fn add_magnitudes(&self, tn: f64, ts: f64, f: &mut [f64]) {
        for ((&d, bn), bs) in self.dofs.iter().zip(self.bn.iter()).zip(self.bs.iter()) {
            if d != NO_DOF {
                f[d] += (bn * tn + bs * ts).abs();
            }
        }
    }

    /// y += b_N t_N + b_S t_S.
    #[inline(always)]
    fn scatter(&self, tn: f64, ts: f64, y: &mut [f64]) {
        match self.fixed_rows() {
            Some((d, bn, bs)) => row_scatter(d, bn, bs, tn, ts, y),
            None => row_scatter(&self.dofs, &self.bn, &self.bs, tn, ts, y),
        }
    }
}

fn tangent4(r: &LawResponse) -> [f64; 4] {
    [r.dtn_dgn, r.dtn_dgs, r.dts_dgn, r.dts_dgs]
}

/// Contacts from which the tangent product ([`ContactSet::apply_tangent`]) sums its two
/// halves apart (on two threads when the run has them). Fixed, not the thread count's: the
/// sums are the same on any number. Measured (2026-12-04, 40×40 wall, 18,750 contacts, 12
/// steps, two threads, three alternated runs on a busy machine): solve stage 2.02/3.11/2.62
/// → 1.91/2.68/2.61 s, histories byte-identical at 1 and 2 threads. Below it, one pass
/// (each contact's rates and scatter at once: half the reads of a map then a scatter).
/// 256, not 2048 as first (2026-12-05, with the pool's keepers, parallel.rs `KEEP_WARM`):
/// the 10×10 wall's ~1,000 contacts are then split too (see parallel.rs `MIN_PARALLEL` for
/// what the three thresholds lowered together gave).
const SPLIT_PRODUCT: usize = 256;

thread_local! {
    /// The second half's sum of the tangent product (kept: a fresh allocation of that size
    /// is fresh pages every product).
    static PRODUCT_HALF: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
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
    /// Tributary length of the contact (m).
    pub weight: f64,
    /// 0 open, 1 stick, 2 slide.
    pub state: u8,
    /// Its bond, under a law with bonds: intact (`Some(true)`) or broken (`Some(false)`),
    /// as committed at the end of the step.
    pub bond: Option<bool>,
    pub first: usize,
    pub second: usize,
    /// Joint that made the face of `second` the contact is on, if any.
    pub joint: Option<usize>,
}

/// Counts of one evaluation of the contact set.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BranchCounts {
    pub open: usize,
    pub stick: usize,
    pub slide: usize,
}

#[derive(Clone)]
pub struct ContactSet {
    pub contacts: Vec<Contact>,
    /// Committed state of each closed contact under its law, with the outward normal it had.
    committed: HashMap<ContactKey, Committed>,
    /// At the first iterate, a contact whose predictions differ and that has no record of
    /// its own takes the last branch ([`FirstChoice`]): the last branch was right more
    /// often than the law's own at the last committed step's contacts that had to choose.
    prefer_last: bool,
    /// The committed states their laws keep while the contacts are open or out of sight
    /// ([`super::law::FrictionLaw::lasting`]).
    lasting: HashMap<ContactKey, (LawId, LawState)>,
    /// Every contact of the last committed step, open ones included.
    seen: HashSet<ContactKey>,
    /// See [`ContactSet::chosen_are_own`].
    chosen_own: bool,
    /// See [`ContactSet::unsymmetric_count`].
    unsymmetric: usize,
    /// The iterate of the latest true evaluation ([`ContactSet::add_forces`] with `own`),
    /// bit for bit, while each contact's `next` holds the choice of branches there (made
    /// from the branches chosen then; emptied by any other evaluation, choice, commit or
    /// detection: empty, nothing is held): a choice at that iterate takes it instead of
    /// evaluating every contact again.
    evaluated: Vec<f64>,
    /// The run's threads: the laws of the contacts are evaluated on them (local work), the
    /// forces scattered in contact order.
    pub threads: crate::parallel::Threads,
    /// The second half's sums of a pass over the contacts ([`ContactSet::split_pass`];
    /// kept: a fresh allocation of that size is fresh pages every pass).
    half: Vec<f64>,
    /// Each contact's dissipation in the last commit (a workspace of
    /// [`ContactSet::commit`]).
    dissipated: Vec<StepDissipation>,
    /// Gaps up to this count as touching (`REL_TOL` × the model's size).
    touch_tol: f64,
    /// Mean length of the boundary segments of the model's blocks, s̄ (m).
    spacing: f64,
    /// Converged steps committed so far.
    commits: usize,
    /// For each block, each boundary segment's polygon edge as (first, last) vertex indices
    /// of the refined boundary (the corners that bound it). Built at the first detection.
    faces: Vec<Vec<(usize, usize)>>,
    /// For each block, whether each vertex of its refined boundary is a corner of the
    /// polygon (built with `faces`).
    corners: Vec<Vec<bool>>,
    /// Bumped whenever the contacts are replaced (detection, restore): the tangent pattern
    /// binds its slots to one generation.
    generation: u64,
    /// Unknowns of each contact (2 × the basis's unknowns per element).
    row_len: usize,
    /// What the contacts dissipated in the last committed step.
    dissipation: StepDissipation,
    /// The blocks' masses (restitution dashpots), `f64::INFINITY` for fixed blocks.
    block_mass: Vec<f64>,
    /// The time step of the coming solve (`None`: static).
    step_dt: Option<f64>,
    /// The dashpot tables of the restitutions met so far.
    dashpot_tables: Vec<std::sync::Arc<DashpotTable>>,
    /// In-situ stress and excavated blocks ([`insitu`]).
    insitu: insitu::Insitu,
}

/// The energy balance of the contacts over one committed step (J per metre of thickness).
///
/// Over the step a contact's forces at the step's end (t_N, t_S) do the work
/// t_N Δg_N + t_S Δg_S on its relative motion (Δg_N = g_N − g_N⁰, from the gap at the step's
/// start). Of that work,
/// * `friction` is t_S Δγ, the force on the Coulomb limit times the plastic slip of the
///   step (≥ 0: the slip is along the force), plus t_N Δg_N^p, the force on a tension
///   cut-off times the plastic opening of the step (a bonded contact, ≥ 0);
/// * the springs store the change of ½ t_N²/p_N + ½ t_S²/p_S, from its value at the step's
///   start, `start_energy` (the normal spring at the gap g_N⁰, the shear spring at its
///   committed elastic gap);
/// * `algorithmic` is the rest: what the implicit scheme dissipates by taking the forces at
///   the step's end. For a contact closed over the whole step it is
///   (Δt_N)²/2p_N + (Δt_S^e)²/2p_S ≥ 0, with Δt_S^e the change of the elastic shear force;
///   for one closing within the step it also holds −t_N g_N⁰ ≥ 0 (the force at the end,
///   times the gap still open at the start).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepDissipation {
    pub friction: f64,
    /// The restitution dashpots' (c_N/Δt)(Δg_N)², ≥ 0.
    pub damping: f64,
    pub algorithmic: f64,
    /// Σ of the contacts' spring energies at the step's start.
    pub start_energy: f64,
}

/// [`StepDissipation`] of one contact, whose committed response at the step's end is
/// `c.response` at the gaps (g_N, Δg_S) = (`gn`, `gs`); `c.history` is still the state at
/// the step's start.
fn step_dissipation(c: &Contact, gn: f64, gs: f64) -> StepDissipation {
    let r = &c.response;
    let p = &c.params;
    // an in-situ shear gap is part of the springs' state at the step's start, not motion:
    // the start forces are the law's response at (g_N⁰, g_S⁰) (elastic: the in-situ state
    // is inside the strength)
    let (tn0, ts0, gs) = if c.gs0 != 0.0 {
        let s = c.law.law().response(p, &c.history, c.gn0, c.gs0);
        (p.spring_normal(s.tn), s.ts, gs - c.gs0)
    } else {
        let (tn0, ts0) = c.law.law().start_forces(p, &c.history, c.gn0);
        (tn0, ts0, gs)
    };
    if r.status == ContactStatus::Open && tn0 == 0.0 && ts0 == 0.0 {
        return StepDissipation::default();
    }
    let start = p.spring_energy(tn0, ts0);
    let tn_spring = p.spring_normal(r.tn);
    let end = p.spring_energy(tn_spring, r.ts);
    let work = r.tn * (gn - c.gn0) + r.ts * gs;
    let mut friction = r.ts * r.slip;
    if r.opening != 0.0 {
        friction += r.tn * r.opening;
    }
    // the restitution dashpot's force (c_N/Δt) Δg_N over Δg_N
    let damping = (r.tn - tn_spring) * (gn - c.gn0);
    StepDissipation {
        friction,
        damping,
        algorithmic: work - (end - start) - friction - damping,
        start_energy: start,
    }
}

impl Default for ContactSet {
    fn default() -> Self {
        ContactSet {
            contacts: Vec::new(),
            committed: HashMap::default(),
            prefer_last: false,
            lasting: HashMap::default(),
            seen: HashSet::default(),
            chosen_own: false,
            unsymmetric: 0,
            threads: Default::default(),
            half: Vec::new(),
            evaluated: Vec::new(),
            dissipated: Vec::new(),
            touch_tol: 0.0,
            spacing: 0.0,
            commits: 0,
            faces: Vec::new(),
            corners: Vec::new(),
            generation: 0,
            row_len: CONTACT_DOFS,
            dissipation: StepDissipation::default(),
            block_mass: Vec::new(),
            step_dt: None,
            dashpot_tables: Vec::new(),
            insitu: Default::default(),
        }
    }
}

impl std::fmt::Debug for ContactSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactSet")
            .field("contacts", &self.contacts.len())
            .field("commits", &self.commits)
            .finish()
    }
}

fn status_code(s: ContactStatus) -> u8 {
    match s {
        ContactStatus::Open => 0,
        ContactStatus::Stick => 1,
        ContactStatus::Slide => 2,
    }
}

/// [`polygon_faces`] of each loop of a boundary of several loops (`loops`: the first
/// vertex of each), as indices into the whole list.
fn polygon_faces_of_loops(corner: &[bool], loops: &[usize]) -> Vec<(usize, usize)> {
    if loops.len() <= 1 {
        return polygon_faces(corner);
    }
    let mut out = Vec::with_capacity(corner.len());
    for (k, &s) in loops.iter().enumerate() {
        let e = loops.get(k + 1).copied().unwrap_or(corner.len());
        out.extend(
            polygon_faces(&corner[s..e])
                .into_iter()
                .map(|(a, b)| (a + s, b + s)),
        );
    }
    out
}

/// For each segment of a refined boundary, the (first, last) vertex indices of the polygon
/// edge it belongs to: the corners before and after it.
fn polygon_faces(corner: &[bool]) -> Vec<(usize, usize)> {
    let n = corner.len();
    if !corner.iter().any(|&c| c) {
        return (0..n).map(|j| (j, (j + 1) % n)).collect();
    }
    (0..n)
        .map(|j| {
            let mut a = j;
            while !corner[a] {
                a = (a + n - 1) % n;
            }
            let mut b = (j + 1) % n;
            while !corner[b] {
                b = (b + 1) % n;
            }
            (a, b)
        })
        .collect()
}

/// The fraction of each adjacent segment a vertex's contact integrates: ½ (the
/// trapezoidal rule) without midpoints; with them (first-order covers, Simpson's rule) ⅓ at
/// a segment's end and ⅔ at its midpoint.
pub(crate) fn tributary_share(has_midpoints: bool, midpoint: bool) -> f64 {
    match (has_midpoints, midpoint) {
        (false, _) => 0.5,
        (true, false) => 1.0 / 3.0,
        (true, true) => 2.0 / 3.0,
    }
}

/// Tributary length of vertex `i` of the closed polyline `a` on the segment of `b` with
/// origin `p0`, unit direction `t` and outward normal `n`, whose polygon edge spans
/// `[s_lo, s_hi]` in the coordinate s = (x − p0)·t: the fraction `share` (½: the trapezoidal
/// rule; ⅓ at a segment's end and ⅔ at its midpoint: Simpson's) of each adjacent segment
/// that faces the segment (outward normals opposed), projected on t and clipped to the edge.
#[allow(clippy::too_many_arguments)]
fn tributary(
    (a, loops): (&[Vec2], &[usize]),
    i: usize,
    share: f64,
    p0: Vec2,
    t: Vec2,
    n: Vec2,
    s_lo: f64,
    s_hi: f64,
) -> f64 {
    let m = a.len();
    let p = a[i];
    let sp = dot(sub(p, p0), t);
    let mut w = 0.0;
    let (next, prev) = (
        crate::geometry::region::loop_next(loops, m, i),
        crate::geometry::region::loop_prev(loops, m, i),
    );
    // segment i → i+1 (outward normal of a CCW edge: direction turned clockwise), and the
    // segment i−1 → i
    for (q, from_p) in [(a[next], true), (a[prev], false)] {
        let d = if from_p { sub(q, p) } else { sub(p, q) };
        let len = norm(d);
        if len == 0.0 {
            continue;
        }
        let ns = [d[1] / len, -d[0] / len];
        if dot(ns, n) >= 0.0 {
            continue;
        }
        let half = share * dot(sub(q, p), t);
        let (lo, hi) = if half < 0.0 {
            (sp + half, sp)
        } else {
            (sp, sp + half)
        };
        w += (hi.min(s_hi) - lo.max(s_lo)).max(0.0);
    }
    w
}

/// A weight of a contact point's cover below this is zero up to round-off: the point lies
/// on the opposite edge of the element's triangle (within 10⁻⁹ of its height). Every shape
/// function of a cover is its weight times a polynomial ([`crate::cover::basis`]), so that
/// cover's rows are then exact zeros, and the tangent's pattern leaves the contact's
/// coupling with its unknowns out (simulation/step.rs, `TangentPattern`).
///
/// Why: vertices on mesh lines are common — every vertex of a refined boundary where a mesh
/// line crosses it, and every brick corner of a wall whose cover divides the bricks — and
/// their contacts coupled all six (order 0) or eighteen (order 1) unknowns of both elements,
/// a third of them through rows of 10⁻¹⁷, which the factorisation filled in like any other
/// coupling. Measured: see `TangentPattern`.
///
/// Measured and rejected: a tolerance of 10⁻³ (a point within 10⁻³ of the triangle's height
/// of an edge taken onto it) also kept a settling wall's corner contacts, whose edge point
/// wanders micrometres about a mesh line, on one coupling from step to step (one symbolic
/// analysis in 12 steps instead of 12; 20×20 wall 117 ms/step, 40×40 551, against 145 and
/// 805–815 with 10⁻⁹ and 270 and 1,162 before, alternated in one slow hour), but failed the
/// contact patch test (`tests/contact_patch.rs`) by 18–40% of the traction with the
/// interface 10⁻³ h from a mesh line: the cover it drops there is a sliver's, whose
/// displacement is large enough that a weight of 10⁻³ matters.
const ZERO_WEIGHT: f64 = 1e-9;

/// A contact's unknowns whose rows are smaller than this fraction of its largest stay out
/// of the tangent's pattern where the rest of its coupling is reserved
/// ([`Contact::preconditioner_dofs`]; simulation/step.rs, `TangentPattern`): the factorised
/// matrix then lacks their entries (at most 10⁻⁴ of the contact's penalty) and preconditions
/// GMRES on the full tangent, which the Newton direction solves as accurately as before
/// (`solver/tangent.rs`: no solve is direct with such a pattern).
///
/// Why: a contact point that wanders micrometres off a mesh line gets covers of weight
/// 10⁻⁹…10⁻⁵ (a settling brick wall's corner contacts, every step), each a coupling the
/// pattern did not have: a new symbolic analysis every step and more fill, for entries
/// that change nothing a preconditioner needs. Unlike dropping such weights from the
/// contact's rows ([`ZERO_WEIGHT`]: rejected at 10⁻³, it failed the contact patch test),
/// the forces and the tangent GMRES applies keep every row: the solution is the same.
/// Measured (2026-12-04, 12 steps, against 10⁻³⁰⁰ — the exact pattern — in the same build):
/// 20×20 wall 12 → 1 symbolic analyses, factorisation stage 0.49 → 0.31 s; 40×40 wall 12 → 1,
/// factorisation 2.95 → 1.58 s, run 9.0 → 6.5–6.8 s, peak memory 132 → 95 MB; the same
/// Newton, GMRES and branch-change counts on both; histories within 1.4e-9 relative. 10⁻⁶
/// left 11 of the 20×20 wall's 12 analyses; 10⁻² gave the same counts as 10⁻⁴.
const PRECONDITIONER_WEIGHT: f64 = 1e-4;

/// A contact finds its reserved coupling by its unknowns whose rows are at least this
/// fraction of its largest ([`Contact::required_dofs`]; simulation/step.rs,
/// `TangentPattern`, its index key); a rebuild reserves those above
/// [`PRECONDITIONER_WEIGHT`]. Between the two the factorised matrix may lack a
/// contact's entries (at most 10⁻² of its penalty: GMRES on the full tangent solves the
/// Newton direction as accurately), and a weight that creeps across 10⁻⁴ as its point
/// slides away from a mesh line does not rebuild the pattern at every step.
const REQUIRED_WEIGHT: f64 = 1e-2;

/// `w` with the weights below [`ZERO_WEIGHT`] set to zero (the others as they are: they
/// sum to 1 within 10⁻⁹, and a weight that small is round-off of an exact zero).
fn without_zero_weights(w: &[f64; 3]) -> [f64; 3] {
    w.map(|x| if x.abs() < ZERO_WEIGHT { 0.0 } else { x })
}

/// The rows b_N, b_S of a contact of a vertex (element `a`, weights) against a point of a
/// segment (element `b`, weights) with normal `n` and tangent `t` (module doc), over the
/// two elements' unknowns; each point's weights [`without_zero_weights`] (a cover of
/// weight zero has rows of exact zeros).
fn contact_rows(
    disc: &Discretisation,
    (ea, wa): (usize, &[f64; 3]),
    (eb, wb): (usize, &[f64; 3]),
    n: Vec2,
    t: Vec2,
) -> (ContactRow<usize>, ContactRow<f64>, ContactRow<f64>) {
    let basis = disc.basis;
    let ne = basis.element_dofs();
    let mut dofs = ContactRow::filled(NO_DOF, 2 * ne);
    let mut bn = ContactRow::filled(0.0, 2 * ne);
    let mut bs = ContactRow::filled(0.0, 2 * ne);
    let mut ed = [NO_DOF; MAX_ELEMENT_DOFS];
    let (mut rn, mut rs) = ([0.0; MAX_ELEMENT_DOFS], [0.0; MAX_ELEMENT_DOFS]);
    for (side, (el, w, sign)) in [
        (&disc.elements[ea], without_zero_weights(wa), 1.0),
        (&disc.elements[eb], without_zero_weights(wb), -1.0),
    ]
    .into_iter()
    .enumerate()
    {
        basis.element_dofs_into(disc, el, &mut ed[..ne]);
        basis.directional_row(el, &w, n, &mut rn[..ne]);
        basis.directional_row(el, &w, t, &mut rs[..ne]);
        for i in 0..ne {
            let k = ne * side + i;
            dofs[k] = ed[i];
            if ed[i] != NO_DOF {
                bn[k] = sign * rn[i];
                bs[k] = sign * rs[i];
            }
        }
    }
    (dofs, bn, bs)
}

/// A contact found by a detection, before its law and state are attached
/// ([`ContactSet::push_contact`]).
struct NewContact<'a> {
    key: ContactKey,
    segment: usize,
    rows: (ContactRow<usize>, ContactRow<f64>, ContactRow<f64>),
    /// Normal gap on the current geometry.
    gap: f64,
    /// Length of interface the contact stands for (half its tributary length).
    weight: f64,
    /// Springs per unit length of interface per unit penalty (2 / s̄).
    density: f64,
    /// (normal, tangent) of the segment.
    frame: (Vec2, Vec2),
    position: Vec2,
    iface: &'a crate::model::Interface,
    joint: Option<usize>,
}

/// How deep inside a face a detection finds a vertex, pair by pair: the sum of the two
/// blocks' reach (a few times each one's motion in the last step), at least `floor`, at
/// most the search distance. A vertex cannot have come through a face deeper than the two
/// blocks moved; with one global depth (the search distance, set by the fastest block of
/// the model) a vertex resting on one face of a slow block, near another face's end, was
/// found 8 cm inside that other face's line, and the penalty's force on that depth threw
/// the block out (a jointed slope shaken at 0.32 g: two blocks moving ~1 mm a step, the
/// search distance 8 cm from a block thrown onto the base; the total energy rose 1.8 times
/// its scale in one step, and the run failed 18 steps later).
#[derive(Debug, Clone, Copy)]
pub struct PenetrationReach<'a> {
    /// Each block's reach (m).
    pub blocks: &'a [f64],
    /// The least depth (m).
    pub floor: f64,
}

/// What a detection's pairs read: the current boundaries and the model's interfaces.
struct DetectGeometry<'a> {
    disc: &'a Discretisation,
    model: &'a dyn InterfaceView,
    /// Current boundary polylines, their outlines and their corner flags, by block.
    polys: &'a [Vec<Vec2>],
    outlines: &'a [Outline<'a>],
    corners: &'a [Vec<bool>],
    /// The bonded vertices held on their faces ([`held_edge`]), by (vertex block, edge
    /// block).
    held: &'a HashMap<(usize, usize), Vec<(usize, Vec2)>>,
    search: f64,
    /// The pair-by-pair depth (`None`: the search distance for every pair).
    reach: Option<PenetrationReach<'a>>,
    has_midpoints: bool,
}

/// A contact a pair's search found (before [`ContactSet::push_contact`]).
struct Found<'a> {
    key: ContactKey,
    segment: usize,
    rows: (ContactRow<usize>, ContactRow<f64>, ContactRow<f64>),
    gap: f64,
    weight: f64,
    frame: (Vec2, Vec2),
    iface: &'a crate::model::Interface,
    joint: Option<usize>,
    /// The vertex's share of its neighbouring segments ([`tributary_share`]).
    share: f64,
}

impl ContactSet {
    /// The contacts of the vertices of block `pa` on the faces of block `pb` (local work of
    /// a detection: reads the committed states only).
    fn pair_contacts<'g>(
        &self,
        g: &DetectGeometry<'g>,
        (pa, pb): (usize, usize),
    ) -> Vec<Found<'g>> {
        let (disc, model, polys, search) = (g.disc, g.model, g.polys, g.search);
        let (la, lb) = (&disc.boundaries[pa].loops, &disc.boundaries[pb].loops);
        let max_penetration = match g.reach {
            Some(r) => (r.blocks[pa] + r.blocks[pb]).max(r.floor).min(search),
            None => search,
        };
        let mut found = vertex_edge_contacts_of(
            &g.outlines[pa],
            &g.outlines[pb],
            &g.corners[pa],
            &NarrowParams {
                max_penetration,
                ..NarrowParams::new(search)
            },
        );
        if let Some(hs) = g.held.get(&(pa, pb)) {
            for &(v, n_old) in hs {
                if found.iter().any(|f| f.vertex == v) {
                    continue;
                }
                if let Some(e) = held_edge(&polys[pa][v], (&polys[pb], lb), n_old, search) {
                    found.push(VertexEdge { vertex: v, ..e });
                }
            }
        }
        let mut out = Vec::with_capacity(found.len());
        for mut ve in found {
            let key = (pa, ve.vertex, pb);
            if let Some(Committed { normal: n_old, .. }) = self.committed.get(&key) {
                // Corner against corner the entrance edge is nearly a tie; keep the
                // edge the contact had while it still holds the vertex, so that the
                // normal does not flip between steps (which pumps energy in).
                if dot(*n_old, ve.normal) < 0.9 {
                    if let Some(kept) =
                        keep_edge(&polys[pa][ve.vertex], (&polys[pb], lb), *n_old, search)
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
            let joint = model.face_joint(pb, edge);
            let Some(iface) = model.interface_for_face(pa, pb, joint) else {
                continue;
            };
            let pb_poly = &polys[pb];
            let p0 = pb_poly[ve.segment];
            let (f0, f1) = self.faces[pb][ve.segment];
            let s_lo = dot(sub(pb_poly[f0], p0), ve.tangent);
            let s_hi = dot(sub(pb_poly[f1], p0), ve.tangent);
            let share = tributary_share(
                g.has_midpoints,
                disc.boundaries[pa].vertices[ve.vertex].midpoint,
            );
            let lambda = tributary(
                (&polys[pa], la),
                ve.vertex,
                share,
                p0,
                ve.tangent,
                ve.normal,
                s_lo.min(s_hi),
                s_lo.max(s_hi),
            );
            let weight = 0.5 * lambda;
            if weight <= 0.0 {
                continue;
            }
            let vert = &disc.boundaries[pa].vertices[ve.vertex];
            let eb = disc.boundaries[pb].segment_elements[ve.segment];
            let q = crate::geometry::lerp(p0, pb_poly[disc.boundaries[pb].next(ve.segment)], ve.xi);
            let wb = barycentric(&disc.elements[eb].nodes, q);
            let rows = contact_rows(
                disc,
                (vert.at.element, &vert.at.weights),
                (eb, &wb),
                ve.normal,
                ve.tangent,
            );
            out.push(Found {
                key,
                segment: ve.segment,
                rows,
                gap: ve.gap,
                weight,
                frame: (ve.normal, ve.tangent),
                iface,
                joint,
                share,
            });
        }
        out
    }

    /// Keep a contact a pair's search found ([`ContactSet::push_contact`]).
    fn keep_found(&mut self, g: &DetectGeometry, density: f64, c: Found) {
        let (pa, vertex, pb) = c.key;
        let (polys, disc) = (g.polys, g.disc);
        let (la, lb) = (&disc.boundaries[pa].loops, &disc.boundaries[pb].loops);
        let tol = self.touch_tol;
        let share = c.share;
        self.push_contact(g.model, c.into_new(g, density), |s| {
            insitu::force_on_vertex((&polys[pa], la), vertex, share, (&polys[pb], lb), s, tol)
        });
    }

    /// Keep every contact the pairs' searches found, in order: without in-situ stress (no
    /// offsets to record) each made in its place of the list on the run's threads (local
    /// work, the list's order fixed by the pairs': the same on any thread count), else one
    /// after the other ([`ContactSet::keep_found`]).
    fn keep_all_found(&mut self, g: &DetectGeometry, density: f64, found: Vec<Vec<Found>>) {
        if self.insitu.stress.is_some() {
            for c in found.into_iter().flatten() {
                self.keep_found(g, density, c);
            }
            return;
        }
        let total: usize = found.iter().map(Vec::len).sum();
        let mut contacts = std::mem::take(&mut self.contacts);
        let start = contacts.len();
        contacts.reserve(total);
        {
            // each pair's slots, in order
            let mut rest = &mut contacts.spare_capacity_mut()[..total];
            let mut jobs = Vec::with_capacity(found.len());
            for f in found {
                let (slots, tail) = std::mem::take(&mut rest).split_at_mut(f.len());
                jobs.push((slots, f));
                rest = tail;
            }
            let this = &*self;
            this.threads.for_each_mut(&mut jobs, |_, (slots, f)| {
                for (slot, c) in slots.iter_mut().zip(std::mem::take(f)) {
                    slot.write(this.make_contact(g.model, c.into_new(g, density), (0.0, 0.0)));
                }
            });
        }
        // SAFETY: the loop above wrote each of the `total` slots after `start` (a panic
        // there leaves the list as it was, the contacts written leaked)
        unsafe { contacts.set_len(start + total) };
        self.contacts = contacts;
    }
}

impl Found<'_> {
    /// The contact to keep, at the vertex's current position.
    fn into_new<'a>(self, g: &DetectGeometry<'a>, density: f64) -> NewContact<'a>
    where
        Self: 'a,
    {
        let (pa, vertex, _) = self.key;
        NewContact {
            key: self.key,
            segment: self.segment,
            rows: self.rows,
            gap: self.gap,
            weight: self.weight,
            density,
            frame: self.frame,
            position: g.polys[pa][vertex],
            iface: self.iface,
            joint: self.joint,
        }
    }
}

impl NewContact<'_> {
    /// The contact's normal and shear penalties (N/m): the interface's per length × its
    /// springs' density × its weight.
    fn penalties(&self) -> (f64, f64) {
        (
            self.iface.normal_penalty * self.density * self.weight,
            self.iface.shear_penalty * self.density * self.weight,
        )
    }
}

impl ContactSet {
    /// Attach its springs, law and state to a contact found by a detection, and keep it:
    /// `insitu_force` is the force σ₀ puts on its vertex (only asked for a contact touching
    /// at the start under in-situ stress).
    fn push_contact(
        &mut self,
        model: &dyn InterfaceView,
        c: NewContact,
        insitu_force: impl FnOnce(&crate::model::InitialStress) -> Vec2,
    ) {
        let (pn, ps) = c.penalties();
        // in-situ stress: the springs of a contact touching at the start carry σ₀·n
        let offsets = self.insitu_offset(c.key, c.gap, (pn, ps), c.frame, insitu_force);
        let contact = self.make_contact(model, c, offsets);
        self.contacts.push(contact);
    }

    /// The contact of `c` with its springs, law and state, given its in-situ offsets
    /// (δ_N, initial shear gap; [`ContactSet::insitu_offset`]): reads the committed states
    /// only (local work of a detection).
    fn make_contact(
        &self,
        model: &dyn InterfaceView,
        c: NewContact,
        (offset, gs0): (f64, f64),
    ) -> Contact {
        let (pn, ps) = c.penalties();
        let NewContact {
            key,
            segment,
            rows: (dofs, bn, bs),
            gap,
            weight,
            density: _,
            frame: (normal, tangent),
            position,
            iface,
            joint,
        } = c;
        let gn0 = if offset != 0.0 { gap + offset } else { gap };
        // the interface's own law, else the analysis'
        let (law, own) = match &iface.law {
            Some(l) => (l.law, l.law.law().own_constants(&l.values, weight)),
            None => (model.default_law(), [0.0; 4]),
        };
        let params = FrictionParams {
            pn,
            ps,
            tan_phi: iface.friction_angle.to_radians().tan(),
            cohesion: iface.cohesion * weight,
            // set by `apply_dashpots` once every contact of the step is known
            dashpot: 0.0,
            gn0,
            own,
        };
        // a contact new to this step that touches: the predictor holds it closed at the
        // first iterate (a contact of the last step keeps the state the last step found
        // for it)
        let touching = gap <= self.touch_tol && !self.seen.contains(&key);
        let (kept, last) = match self.committed.get(&key) {
            Some(c) => (Some((c.law, c.state)), Some((c.branch, c.first_choice))),
            None => (self.lasting.get(&key).copied(), None),
        };
        let history = match kept {
            Some((l, h)) if l == law => h,
            _ => law.law().new_state(touching, self.commits == 0),
        };
        let response = law.law().response(&params, &history, gn0, gs0);
        Contact {
            key,
            segment,
            dofs,
            bn,
            bs,
            gn0,
            gs0,
            weight,
            params,
            law,
            history,
            touching,
            branch: Branch::Open,
            coef: [0.0; 4],
            response,
            next: (Branch::Open, false, [0.0; 4]),
            position,
            normal,
            tangent,
            joint,
            restitution: iface.restitution,
            last,
            first_own: Branch::Open,
        }
    }
}

impl ContactSet {
    /// Gaps up to this count as touching.
    pub fn touch_tolerance(&self) -> f64 {
        self.touch_tol
    }

    /// Unknowns of each contact: its two elements' (2 × the basis's per element).
    pub fn contact_dofs(&self) -> usize {
        self.row_len
    }

    /// Find the contacts on the current geometry (displacement `u` from the initial one):
    /// gaps up to `search`, penetrations as deep as `reach` allows for each pair of blocks
    /// (`None`: `search` too).
    pub fn detect(
        &mut self,
        disc: &Discretisation,
        model: &dyn InterfaceView,
        u: &[f64],
        search: f64,
        reach: Option<PenetrationReach<'_>>,
    ) {
        self.contacts.clear();
        self.chosen_own = false;
        self.unsymmetric = 0;
        self.generation += 1;
        self.evaluated.clear();
        let basis = disc.basis;
        let ne = basis.element_dofs();
        self.row_len = 2 * ne;
        let has_midpoints = disc
            .boundaries
            .iter()
            .any(|b| b.vertices.iter().any(|v| v.midpoint));
        if self.faces.len() != disc.boundaries.len() {
            // s̄: the mean segment length of the refined boundaries (midpoints, the quadrature
            // points of first-order covers, do not count: the interface is as stiff as at
            // order 0)
            let (mut len, mut count) = (0.0, 0usize);
            for b in &disc.boundaries {
                let m = b.vertices.len();
                for i in 0..m {
                    len += crate::geometry::dist(b.vertices[i].x0, b.vertices[b.next(i)].x0);
                }
                count += b.vertices.iter().filter(|v| !v.midpoint).count();
            }
            self.spacing = len / count.max(1) as f64;
            self.corners = disc
                .boundaries
                .iter()
                .map(|b| b.vertices.iter().map(|v| v.corner).collect())
                .collect();
            self.faces = disc
                .boundaries
                .iter()
                .zip(&self.corners)
                .map(|(b, c)| polygon_faces_of_loops(c, &b.loops))
                .collect();
        }
        // current boundary polylines (each block's on the run's threads)
        let nb = disc.boundaries.len();
        let polys: Vec<Vec<Vec2>> = self.threads.map(nb, |i| {
            disc.current_positions(&disc.boundaries[i].vertices, u)
        });
        // (taken while the pairs read it; put back below)
        let corners = std::mem::take(&mut self.corners);
        let boxes: Vec<Aabb> = polys
            .iter()
            .map(|p| Aabb::of_points(p).inflate(search))
            .collect();
        let size = boxes
            .iter()
            .fold(Aabb::empty(), |a, b| a.merge(b))
            .diagonal();
        self.touch_tol = crate::model::REL_TOL * size;
        // springs per unit length of interface per unit penalty: 2 / s̄
        let density = 2.0 / self.spacing;
        let mut pairs = sweep_and_prune(&boxes);
        pairs.sort_unstable();
        // An intact bond holds its contact: a bonded vertex that passed the end of its face
        // (by the bond's elastic shear, or round-off) stays in contact with that face
        // ([`held_edge`]); only laws with bonds have such contacts.
        let mut held: HashMap<(usize, usize), Vec<(usize, Vec2)>> = HashMap::default();
        for (k, c) in &self.committed {
            if c.law.law().bond(&c.state) == Some(true) {
                held.entry((k.0, k.2)).or_default().push((k.1, c.normal));
            }
        }
        for v in held.values_mut() {
            v.sort_unstable_by_key(|x| x.0);
        }
        // the ordered pairs (vertex block, edge block) to search, in the order of the
        // contacts
        let mut ordered = Vec::with_capacity(2 * pairs.len());
        for (a, b) in pairs {
            if model.is_fixed(a) && model.is_fixed(b) {
                continue;
            }
            if self.removed(a) || self.removed(b) {
                continue;
            }
            if !model.may_contact(a, b) {
                continue;
            }
            ordered.push((a, b));
            ordered.push((b, a));
        }
        // each block's outline, once for all its pairs (with the grid of a long one for
        // the pairs' reach: their depths are at most the search distance)
        let prm = NarrowParams::new(search);
        let outlines: Vec<Outline> = self.threads.map(nb, |i| {
            Outline::new(&polys[i], &disc.boundaries[i].loops).with_grid(&prm)
        });
        let geometry = DetectGeometry {
            disc,
            model,
            polys: &polys,
            outlines: &outlines,
            corners: &corners,
            held: &held,
            search,
            reach,
            has_midpoints,
        };
        // local work (each pair's contacts: narrow phase, tributary lengths, rows) on the
        // run's threads, then the contacts kept in order: the same on any thread count
        if self.threads.count() > 1 {
            let this = &*self;
            let found = this
                .threads
                .map(ordered.len(), |k| this.pair_contacts(&geometry, ordered[k]));
            self.keep_all_found(&geometry, density, found);
        } else {
            for &pair in &ordered {
                for c in self.pair_contacts(&geometry, pair) {
                    self.keep_found(&geometry, density, c);
                }
            }
        }
        self.corners = corners;
        if !disc.slits.is_empty() {
            self.detect_slits(disc, model, u, search, density, has_midpoints);
        }
        self.apply_dashpots();
    }

    /// The blocks' masses (kg per m of thickness; `f64::INFINITY` for a fixed block): the
    /// restitution dashpots' oscillators ([`crate::contact::restitution`]).
    pub fn set_block_masses(&mut self, masses: Vec<f64>) {
        self.block_mass = masses;
        self.apply_dashpots();
    }

    /// The time step of the coming solve (`None`: a static step, no dashpot).
    pub fn set_time_step(&mut self, dt: Option<f64>) {
        if self.step_dt != dt {
            self.step_dt = dt;
            self.apply_dashpots();
        }
    }

    /// Each contact's restitution dashpot c_N/Δt for the current time step (see
    /// [`crate::contact::restitution`]): the contact's oscillator from its normal penalty and
    /// its blocks' masses, shared among each block's contacts in proportion to their
    /// penalties (all the contacts detected for the step count).
    fn apply_dashpots(&mut self) {
        let dt = match self.step_dt {
            Some(dt) if dt > 0.0 && self.contacts.iter().any(|c| c.restitution.is_some()) => dt,
            _ => {
                for c in &mut self.contacts {
                    c.params.dashpot = 0.0;
                }
                return;
            }
        };
        let mut stiffness = vec![0.0; self.block_mass.len()];
        for c in &self.contacts {
            for b in [c.key.0, c.key.2] {
                if let Some(k) = stiffness.get_mut(b) {
                    *k += c.params.pn;
                }
            }
        }
        for c in &mut self.contacts {
            let Some(e) = c.restitution else {
                c.params.dashpot = 0.0;
                continue;
            };
            let pn = c.params.pn;
            let share = |b: usize| {
                let m = self.block_mass.get(b).copied().unwrap_or(f64::INFINITY);
                if m.is_finite() {
                    m * pn / stiffness[b]
                } else {
                    f64::INFINITY
                }
            };
            let inv = 1.0 / share(c.key.0) + 1.0 / share(c.key.2);
            if inv.is_nan() || inv <= 0.0 || !inv.is_finite() {
                c.params.dashpot = 0.0;
                continue;
            }
            let m = 1.0 / inv;
            let omega_dt = (pn / m).sqrt() * dt;
            let table = match self.dashpot_tables.iter().find(|t| t.e == e) {
                Some(t) => t.clone(),
                None => {
                    let t = std::sync::Arc::new(DashpotTable::new(e));
                    self.dashpot_tables.push(t.clone());
                    t
                }
            };
            let zeta = table.zeta(omega_dt);
            c.params.dashpot = 2.0 * zeta * (pn * m).sqrt() / dt;
        }
    }

    /// Which contact list this is: bumped whenever the contacts are replaced.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Choose each contact's branch at the iterate Δu = `du` (the law's
    /// [`super::law::FrictionLaw::iteration_branch`]; `first`: the first iterate of the
    /// step, where a contact closed at the end of the last step takes the branch it ended
    /// on instead when that prediction was the right one the last time the two differed,
    /// [`FirstChoice`]). Returns how many contacts changed branch (at the first iterate:
    /// how many are not open).
    pub fn choose_branches(&mut self, du: &[f64], first: bool) -> usize {
        let ready = !first && !self.evaluated.is_empty() && same_bits(&self.evaluated, du);
        self.evaluated.clear();
        if ready {
            // the latest true evaluation was at `du` and made this choice already
            let ((c0, u0, o0), second) = self.split_pass(&mut [], &mut [], |cs, _, _| {
                let (mut changed, mut unsymmetric, mut own) = (0, 0, true);
                for c in cs {
                    let (b, is_own, coef) = c.next;
                    own &= is_own;
                    changed += usize::from(b != c.branch);
                    c.branch = b;
                    c.coef = coef;
                    unsymmetric += usize::from(c.unsymmetric());
                }
                (changed, unsymmetric, own)
            });
            let (c1, u1, o1) = second.unwrap_or((0, 0, true));
            self.chosen_own = o0 && o1;
            self.unsymmetric = u0 + u1;
            return c0 + c1;
        }
        let prefer_last = self.prefer_last;
        let ((c0, u0, o0), second) = self.split_pass(&mut [], &mut [], |cs, _, _| {
            let (mut changed, mut unsymmetric, mut own) = (0, 0, true);
            for c in cs {
                let law = c.law.law();
                let (gn, gs) = c.gaps(du);
                let ctx = IterationContext {
                    previous: (!first).then_some(c.branch),
                    touching: c.touching,
                };
                let mut b = law.iteration_branch(&c.params, &c.history, gn, gs, ctx);
                if first {
                    // two predictions: the law's own branch at the first iterate, and the
                    // branch the contact ended the last step on; where they differ, the one
                    // that was right the last time they did ([`FirstChoice`])
                    c.first_own = b;
                    if let Some((last, record)) = c.last {
                        if last != b && record.takes_last(prefer_last) {
                            b = last;
                        }
                    }
                }
                own &= b == law.branch(&c.params, &c.history, gn, gs);
                changed += usize::from(if first {
                    b != Branch::Open
                } else {
                    b != c.branch
                });
                c.branch = b;
                c.coef = tangent4(&law.on_branch(&c.params, &c.history, gn, gs, b));
                unsymmetric += usize::from(c.unsymmetric());
            }
            (changed, unsymmetric, own)
        });
        let (c1, u1, o1) = second.unwrap_or((0, 0, true));
        self.chosen_own = o0 && o1;
        self.unsymmetric = u0 + u1;
        c0 + c1
    }

    /// Whether the last choice of branches ([`ContactSet::choose_branches`],
    /// [`ContactSet::choose_own_branches`]) put every contact on the law's own branch at
    /// its iterate: the residual on the chosen branches there is the true residual.
    pub fn chosen_are_own(&self) -> bool {
        self.chosen_own
    }

    /// Put every contact on the law's own branch at `du` (no iteration rule). Returns how
    /// many contacts changed branch.
    pub fn choose_own_branches(&mut self, du: &[f64]) -> usize {
        self.evaluated.clear();
        let ((c0, u0), second) = self.split_pass(&mut [], &mut [], |cs, _, _| {
            let (mut changed, mut unsymmetric) = (0, 0);
            for c in cs {
                let law = c.law.law();
                let (gn, gs) = c.gaps(du);
                let b = law.branch(&c.params, &c.history, gn, gs);
                changed += usize::from(b != c.branch);
                c.branch = b;
                c.coef = tangent4(&law.on_branch(&c.params, &c.history, gn, gs, b));
                unsymmetric += usize::from(c.unsymmetric());
            }
            (changed, unsymmetric)
        });
        let (c1, u1) = second.unwrap_or((0, 0));
        self.chosen_own = true;
        self.unsymmetric = u0 + u1;
        c0 + c1
    }

    /// Evaluate every contact's response at `du` on its chosen branch (`own = false`) or on
    /// the law's own branch (`own = true`, the true residual), and subtract the contact
    /// forces from `r`; with `magnitudes`, add the magnitudes of the contact forces to it
    /// componentwise (for the physical force scale of the convergence test). With `own`,
    /// returns how many contacts are on another branch than the one chosen (0: the chosen
    /// active set is consistent at `du`). One pass: each contact's law, then its scatter
    /// (local work and the ordered scatter of a half, [`ContactSet::split_pass`]).
    pub fn add_forces(
        &mut self,
        du: &[f64],
        r: &mut [f64],
        own: bool,
        magnitudes: Option<&mut [f64]>,
    ) -> usize {
        self.add_forces_along(du, None, r, own, magnitudes).0
    }

    /// [`ContactSet::add_forces`], and with `along` = Some(v) the largest relative motion
    /// of a direction v ([`ContactSet::largest_relative_motion`]) in the same pass (0
    /// without).
    pub fn add_forces_along(
        &mut self,
        du: &[f64],
        along: Option<&[f64]>,
        r: &mut [f64],
        own: bool,
        magnitudes: Option<&mut [f64]>,
    ) -> (usize, f64) {
        let mags = magnitudes.is_some();
        let w = magnitudes.unwrap_or(&mut []);
        self.evaluated.clear();
        if own {
            self.evaluated.extend_from_slice(du);
        }
        let (a, b) = self.split_pass(r, w, |cs, r, w| {
            let (mut inconsistent, mut motion) = (0, 0.0f64);
            for c in cs {
                let law = c.law.law();
                let (gn, gs) = c.gaps(du);
                if let Some(v) = along {
                    let (a, b) = c.rates(v);
                    motion = motion.max(a.abs().max(b.abs()));
                }
                let resp = if own {
                    let b = law.branch(&c.params, &c.history, gn, gs);
                    inconsistent += usize::from(b != c.branch);
                    c.response = law.on_branch(&c.params, &c.history, gn, gs, b);
                    // the choice of branches here ([`ContactSet::choose_branches`], not
                    // at the first iterate)
                    let ctx = IterationContext {
                        previous: Some(c.branch),
                        touching: c.touching,
                    };
                    let next = law.iteration_branch(&c.params, &c.history, gn, gs, ctx);
                    c.next = if next == b {
                        (b, true, tangent4(&c.response))
                    } else {
                        let r = law.on_branch(&c.params, &c.history, gn, gs, next);
                        (next, false, tangent4(&r))
                    };
                    c.response
                } else {
                    law.on_branch(&c.params, &c.history, gn, gs, c.branch)
                };
                if resp.tn == 0.0 && resp.ts == 0.0 {
                    continue;
                }
                c.scatter(-resp.tn, -resp.ts, r);
                if mags {
                    c.add_magnitudes(resp.tn, resp.ts, w);
                }
            }
            (inconsistent, motion)
        });
        // a largest value is the same whatever the split
        let (b0, b1) = b.unwrap_or((0, 0.0));
        (a.0 + b0, a.1.max(b1))
    }

    /// Run `pass` over the contacts — in two fixed halves from [`SPLIT_PRODUCT`] contacts
    /// on (at once on two threads, one after the other on one): the first half adds into
    /// `y` and `z`, the second into zeroed vectors of their sizes, added to them after —,
    /// so that every sum is the same on any number of threads. Returns each half's result
    /// (the second `None` below the split).
    fn split_pass<R: Send>(
        &mut self,
        y: &mut [f64],
        z: &mut [f64],
        pass: impl Fn(&mut [Contact], &mut [f64], &mut [f64]) -> R + Sync + Send,
    ) -> (R, Option<R>) {
        let n = self.contacts.len();
        if n < SPLIT_PRODUCT {
            return (pass(&mut self.contacts, y, z), None);
        }
        let half = &mut self.half;
        half.clear();
        half.resize(y.len() + z.len(), 0.0);
        let (hy, hz) = half.split_at_mut(y.len());
        let (first, second) = self.contacts.split_at_mut(n / 2);
        let (a, b) = self
            .threads
            .join(|| pass(first, &mut *y, &mut *z), || pass(second, hy, hz));
        let hy = &self.half[..y.len()];
        for (yi, hi) in y.iter_mut().zip(hy) {
            *yi += hi;
        }
        for (zi, hi) in z.iter_mut().zip(&self.half[y.len()..]) {
            *zi += hi;
        }
        (a, Some(b))
    }

    /// The largest |b_N · v| or |b_S · v| over the contacts: how far a direction `v` moves any
    /// contact point relative to its edge.
    pub fn largest_relative_motion(&self, v: &[f64]) -> f64 {
        let part = |cs: &[Contact]| {
            cs.iter()
                .map(|c| {
                    let (a, b) = c.rates(v);
                    a.abs().max(b.abs())
                })
                .fold(0.0, f64::max)
        };
        let cs = &self.contacts;
        if cs.len() < SPLIT_PRODUCT || self.threads.count() == 1 {
            return part(cs);
        }
        // a largest value is the same whatever the split
        let (first, second) = cs.split_at(cs.len() / 2);
        let (a, b) = self.threads.join(|| part(first), || part(second));
        a.max(b)
    }

    /// The first α in (`KINK_FLOOR`, 1] at which a contact's own branch along `du` + α `d`
    /// differs from its own branch there ([`super::law::first_kink`], just past it), 1 if
    /// none does. A contact on a boundary at `du` itself (a tie, decided by round-off) is
    /// taken on its branch just beyond, so that the kink found is one the direction
    /// reaches.
    pub fn first_kink(&self, du: &[f64], d: &[f64]) -> f64 {
        self.contacts.iter().fold(1.0, |first, c| {
            super::law::first_kink(
                c.law.law(),
                &c.params,
                &c.history,
                c.gaps(du),
                c.rates(d),
                KINK_FLOOR,
                first,
            )
            .unwrap_or(first)
        })
    }

    /// y += K_c v with the tangent of the chosen branches (matrix-free).
    pub fn apply_tangent(&self, v: &[f64], y: &mut [f64]) {
        let cs = &self.contacts;
        let pass = |cs: &[Contact], y: &mut [f64]| {
            for c in cs {
                if let Some((tn, ts)) = c.tangent_forces(v) {
                    c.scatter(tn, ts, y);
                }
            }
        };
        if cs.len() < SPLIT_PRODUCT {
            pass(cs, y);
            return;
        }
        // the second half's sum apart, added last: at once on two threads, one after the
        // other on one (the same operations in the same order on any number)
        let (first, second) = cs.split_at(cs.len() / 2);
        PRODUCT_HALF.with(|h| {
            let mut guard = h.borrow_mut();
            guard.clear();
            guard.resize(y.len(), 0.0);
            let h: &mut [f64] = &mut guard;
            self.threads
                .join(|| pass(first, &mut *y), || pass(second, &mut *h));
            for (yi, hi) in y.iter_mut().zip(h.iter()) {
                *yi += hi;
            }
        });
    }

    /// Whether the tangent of the chosen branches is symmetric (no sliding contact with the
    /// consistent, unsymmetric friction tangent).
    pub fn tangent_is_symmetric(&self) -> bool {
        self.unsymmetric == 0
    }

    /// How many contacts make the tangent of the chosen branches unsymmetric (sliding),
    /// counted when the branches were chosen (the only writers of the coefficients).
    pub fn unsymmetric_count(&self) -> usize {
        self.unsymmetric
    }

    /// The local tangent block of contact `c` on its chosen branch, row-major over its
    /// unknowns (local work: the caller scatters it), or `None` when it is zero (an open
    /// contact). `symmetric`: only its symmetric positive part — the normal spring and the
    /// stick shear spring, without the unsymmetric coupling of a sliding contact (a
    /// preconditioner).
    pub fn tangent_block(c: &Contact, symmetric: bool) -> Option<Vec<f64>> {
        let n = c.dofs.len();
        let mut k = vec![0.0; n * n];
        Self::tangent_block_into(c, symmetric, &mut k).then_some(k)
    }

    /// [`ContactSet::tangent_block`] into `k` (n² long); false (and `k` untouched) when the
    /// block is zero.
    #[inline]
    pub fn tangent_block_into(c: &Contact, symmetric: bool, k: &mut [f64]) -> bool {
        Self::block_into(c, Self::tangent_coef(c, symmetric), k)
    }

    /// The coefficients [∂t_N/∂g_N, ∂t_N/∂g_S, ∂t_S/∂g_N, ∂t_S/∂g_S] of contact `c`'s
    /// tangent block on its chosen branch; `symmetric`: without the unsymmetric coupling
    /// (see [`ContactSet::tangent_block`]).
    #[inline]
    pub fn tangent_coef(c: &Contact, symmetric: bool) -> [f64; 4] {
        let [a, b, cc, d] = c.coef;
        match symmetric {
            true => [a, 0.0, 0.0, d],
            false => [a, b, cc, d],
        }
    }

    /// The block Bᵀ C B of contact `c`'s rows B = [b_N; b_S] for the coefficients
    /// C = [[a, b], [c, d]] (`coef`), row-major over its unknowns, into `k` (n² long); false
    /// (and `k` untouched) when C is zero. The tangent block is linear in C: the block of
    /// a difference of coefficients is the difference of the blocks.
    #[inline]
    pub fn block_into(c: &Contact, coef: [f64; 4], k: &mut [f64]) -> bool {
        let [a, b, cc, d] = coef;
        if a == 0.0 && b == 0.0 && cc == 0.0 && d == 0.0 {
            return false;
        }
        #[inline(always)]
        fn fill(bn: &[f64], bs: &[f64], [a, b, cc, d]: [f64; 4], k: &mut [f64]) {
            let n = bn.len();
            for jj in 0..n {
                let vn = a * bn[jj] + b * bs[jj];
                let vs = cc * bn[jj] + d * bs[jj];
                for ii in 0..n {
                    k[ii * n + jj] = bn[ii] * vn + bs[ii] * vs;
                }
            }
        }
        match (
            c.fixed_rows(),
            <&mut [f64; CONTACT_DOFS * CONTACT_DOFS]>::try_from(&mut *k),
        ) {
            // the constant basis: arrays throughout (no bounds checks, vectorised)
            (Some((_, bn, bs)), Ok(k)) => {
                for jj in 0..CONTACT_DOFS {
                    let vn = a * bn[jj] + b * bs[jj];
                    let vs = cc * bn[jj] + d * bs[jj];
                    for ii in 0..CONTACT_DOFS {
                        k[ii * CONTACT_DOFS + jj] = bn[ii] * vn + bs[ii] * vs;
                    }
                }
            }
            _ => fill(&c.bn, &c.bs, [a, b, cc, d], k),
        }
        true
    }

    /// Counts of the chosen branches.
    pub fn counts(&self) -> BranchCounts {
        let mut n = BranchCounts::default();
        for c in &self.contacts {
            match c.branch {
                Branch::Open => n.open += 1,
                Branch::Stick => n.stick += 1,
                Branch::Slide(_) | Branch::Limit(..) => n.slide += 1,
            }
        }
        n
    }

    /// Elastic energy stored in the contact springs at the last evaluation:
    /// ½ t_N²/p_N + ½ t_S²/p_S over the closed contacts.
    pub fn spring_energy(&self) -> f64 {
        self.contacts
            .iter()
            .map(|c| {
                let r = &c.response;
                if r.status == ContactStatus::Open {
                    0.0
                } else {
                    c.params.spring_energy(c.params.spring_normal(r.tn), r.ts)
                }
            })
            .sum()
    }

    /// The energy the contacts dissipated in the last committed step (see [`StepDissipation`]).
    pub fn step_dissipation(&self) -> StepDissipation {
        self.dissipation
    }

    /// Commit the converged increment: every contact's law response becomes its history.
    pub fn commit(&mut self, du: &[f64]) {
        self.commits += 1;
        self.evaluated.clear();
        self.committed.clear();
        self.seen.clear();
        self.dissipation = StepDissipation::default();
        // local work (each contact's response, dissipation and new state) on the run's
        // threads, then the sums and the maps in contact order
        let mut dissipated = std::mem::take(&mut self.dissipated);
        dissipated.clear();
        dissipated.resize(self.contacts.len(), StepDissipation::default());
        {
            let cs = &mut self.contacts;
            let pass = |cs: &mut [Contact], ds: &mut [StepDissipation]| {
                for (c, d) in cs.iter_mut().zip(ds.iter_mut()) {
                    let law = c.law.law();
                    let (gn, gs) = c.gaps(du);
                    c.response = law.response(&c.params, &c.history, gn, gs);
                    *d = step_dissipation(c, gn, gs);
                    c.history = law.commit(&c.params, &c.history, &c.response);
                }
            };
            let n = cs.len();
            if n >= SPLIT_PRODUCT && self.threads.count() > 1 {
                let (c0, c1) = cs.split_at_mut(n / 2);
                let (d0, d1) = dissipated.split_at_mut(n / 2);
                self.threads.join(|| pass(c0, d0), || pass(c1, d1));
            } else {
                pass(cs, &mut dissipated);
            }
        }
        // the maps and sums in contact order: the committed states on one thread, the rest
        // on another (each map built as by one thread alone; 20×20 wall, 4,500 contacts:
        // 0.23 ms a step in one loop)
        let (cs, committed) = (&self.contacts, &mut self.committed);
        let (seen, lasting, sums) = (&mut self.seen, &mut self.lasting, &mut self.dissipation);
        let ((last_right, own_right), ()) = self.threads.for_items(cs.len(), SPLIT_PRODUCT).join(
            || {
                // each closed contact's state, with its record of the first iterate's
                // predictions (and the step's count of which one was right where they
                // differed)
                let (mut last_right, mut own_right) = (0usize, 0usize);
                for c in cs.iter() {
                    let first_choice = match c.last {
                        Some((last, record)) if last != c.first_own => {
                            if c.branch == last {
                                last_right += 1;
                                FirstChoice::Last
                            } else if c.branch == c.first_own {
                                own_right += 1;
                                FirstChoice::Own
                            } else {
                                record
                            }
                        }
                        Some((_, record)) => record,
                        None => FirstChoice::Unknown,
                    };
                    if c.response.status != ContactStatus::Open {
                        committed.insert(
                            c.key,
                            Committed {
                                law: c.law,
                                state: c.history,
                                normal: c.normal,
                                branch: c.branch,
                                first_choice,
                            },
                        );
                    }
                }
                (last_right, own_right)
            },
            || {
                for (c, d) in cs.iter().zip(&dissipated) {
                    seen.insert(c.key);
                    sums.friction += d.friction;
                    sums.damping += d.damping;
                    sums.algorithmic += d.algorithmic;
                    sums.start_energy += d.start_energy;
                    let h = c.history;
                    if c.law.law().lasting(&h) {
                        lasting.insert(c.key, (c.law, h));
                    } else if !lasting.is_empty() {
                        lasting.remove(&c.key);
                    }
                }
            },
        );
        if last_right + own_right > 0 {
            self.prefer_last = last_right > own_right;
        }
        self.dissipated = dissipated;
    }

    /// Bonds of the contacts under a law with bonds, as committed: (intact, among the
    /// contacts of the last step — an intact bond is never open —, and broken so far,
    /// whether detected in the last step or not). Contacts that never had a bond are in
    /// neither count.
    pub fn bond_counts(&self) -> (usize, usize) {
        let intact = self
            .committed
            .values()
            .filter(|c| c.law.law().bond(&c.state) == Some(true))
            .count();
        let broken = self
            .lasting
            .values()
            .filter(|(l, h)| l.law().bond(h) == Some(false))
            .count();
        (intact, broken)
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
                    // compression positive; a bonded contact in tension negative
                    normal_force: if r.tn > 0.0 { -r.tn } else { r.tn.abs() },
                    shear_force: r.ts,
                    weight: c.weight,
                    state: status_code(r.status),
                    bond: c.law.law().bond(&c.history),
                    first: c.key.0,
                    second: c.key.2,
                    joint: c.joint,
                }
            })
            .collect()
    }
}

/// Whether a contact of `model` may be under a law with bonds (an interface's own law or a
/// stage's `friction`): outputs then add the bonds of the contacts.
pub fn uses_bonds(model: &Model) -> bool {
    model
        .interfaces
        .iter()
        .filter_map(|i| i.law.as_ref().map(|l| l.law))
        .chain(std::iter::once(model.analysis.friction))
        .chain(model.stages.iter().map(|s| s.analysis.friction))
        .any(|l| l.law().has_bonds())
}

/// The segments of `b` (loops `loops`) whose outward normal is (nearly) `n_old`, each with
/// `p` seen from it: its index j, the arc length s of p's projection from the segment's
/// start, its length, the gap (positive outside) and its normal and tangent.
fn facing_segments<'a>(
    p: &'a Vec2,
    (b, loops): (&'a [Vec2], &'a [usize]),
    n_old: Vec2,
) -> impl Iterator<Item = (usize, f64, f64, f64, Vec2, Vec2)> + 'a {
    let m = b.len();
    (0..m).filter_map(move |j| {
        let (a, q) = (b[j], b[crate::geometry::region::loop_next(loops, m, j)]);
        let d = sub(q, a);
        let len = norm(d);
        if len == 0.0 {
            return None;
        }
        let t = [d[0] / len, d[1] / len];
        // material on the left: the outward normal is the tangent turned clockwise
        let n = [t[1], -t[0]];
        if dot(n, n_old) < 0.99 {
            return None;
        }
        let s = dot(sub(*p, a), t);
        let gap = -cross(d, sub(*p, a)) / len;
        Some((j, s, len, gap, n, t))
    })
}

/// For a bonded contact the detection did not find: the segment of `b` with the normal
/// `n_old` the contact had (within 0.99) nearest to `p`, whose strip, lengthened by
/// `reach` at both ends, holds `p` within the gap range [−`reach`, `reach`] (the
/// projection clamped to the segment).
fn held_edge(p: &Vec2, b: (&[Vec2], &[usize]), n_old: Vec2, reach: f64) -> Option<VertexEdge> {
    let mut best: Option<(f64, VertexEdge)> = None;
    for (j, s, len, gap, n, t) in facing_segments(p, b, n_old) {
        if s < -reach || s > len + reach || gap.abs() > reach {
            continue;
        }
        // distance beyond the segment's ends, then the gap: the nearest segment
        let out = (-s).max(s - len).max(0.0) + gap.abs();
        if best.as_ref().is_none_or(|(o, _)| out < *o) {
            let xi = (s / len).clamp(0.0, 1.0);
            best = Some((
                out,
                VertexEdge {
                    vertex: 0,
                    segment: j,
                    xi,
                    gap,
                    normal: n,
                    tangent: t,
                },
            ));
        }
    }
    best.map(|b| b.1)
}

/// The segment of `b` whose outward normal is (nearly) `n_old` and that still holds
/// vertex `p` (projection within the segment, gap within [−search, search]).
fn keep_edge(p: &Vec2, b: (&[Vec2], &[usize]), n_old: Vec2, search: f64) -> Option<VertexEdge> {
    let mut best: Option<VertexEdge> = None;
    for (j, s, len, gap, n, t) in facing_segments(p, b, n_old) {
        let xi = s / len;
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
        let top = keep_edge(&corner, (&b, &[]), [0.0, 1.0], 1e-3).unwrap();
        assert_eq!(top.segment, 2);
        assert_eq!(top.normal, [0.0, 1.0]);
        assert!((top.gap - 1e-6).abs() < 1e-12 && (top.xi - 0.0).abs() < 1e-12);
        let side = keep_edge(&[1.0 + 1e-6, 1.0], (&b, &[]), [1.0, 0.0], 1e-3).unwrap();
        assert_eq!(side.segment, 1);
        assert!((side.gap - 1e-6).abs() < 1e-12);
        // beyond the search distance, or past the end of the edge: nothing kept
        assert!(keep_edge(&[0.5, 1.1], (&b, &[]), [0.0, 1.0], 1e-3).is_none());
        assert!(keep_edge(&[1.5, 1.0], (&b, &[]), [0.0, 1.0], 1e-3).is_none());
    }

    #[test]
    fn polygon_faces_span_corner_to_corner() {
        // a square refined with one point per edge: vertices 0,2,4,6 are corners
        let corner = [true, false, true, false, true, false, true, false];
        let f = polygon_faces(&corner);
        assert_eq!(f[0], (0, 2));
        assert_eq!(f[1], (0, 2));
        assert_eq!(f[6], (6, 0));
        assert_eq!(f[7], (6, 0));
    }

    #[test]
    fn tributary_lengths_of_a_face_and_of_a_corner() {
        // A: the bottom face of a block, refined at x = 0.3 and 0.7, lying on B's top edge y = 0
        let a = [
            [0.0, 0.0],
            [0.3, 0.0],
            [0.7, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
        ];
        let (p0, t, n) = ([-1.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
        let w: Vec<f64> = (0..4)
            .map(|i| tributary((&a, &[]), i, 0.5, p0, t, n, -10.0, 10.0))
            .collect();
        // trapezoidal weights: half of each adjacent bottom segment; the sides face away
        let want = [0.15, 0.35, 0.35, 0.15];
        for (x, y) in w.iter().zip(want) {
            assert!((x - y).abs() < 1e-15, "{w:?}");
        }
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        // clipped to B's edge x ∈ [−1, 0.4] (s ∈ [0, 1.4]): vertex 1 keeps 0.1 of its
        // right half, vertex 2 nothing
        let c = tributary((&a, &[]), 1, 0.5, p0, t, n, 0.0, 1.4);
        assert!((c - 0.25).abs() < 1e-15, "{c}");
        assert_eq!(tributary((&a, &[]), 2, 0.5, p0, t, n, 0.0, 1.4), 0.0);
        // a corner of a square rotated 45° touching a horizontal face: both halves project
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let d = [[0.0, 0.0], [s, s], [0.0, 2.0 * s], [-s, s]];
        let c = tributary((&d, &[]), 0, 0.5, p0, t, n, -10.0, 10.0);
        assert!((c - s).abs() < 1e-15, "{c}");
    }
}
