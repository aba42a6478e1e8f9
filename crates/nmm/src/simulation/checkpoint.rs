//! Checkpoints: every bit of the state that crosses a step, so that a run resumed from one
//! continues exactly as the uninterrupted run (the solver keeps no factorisation across
//! steps: a fresh one each step, on a pattern that follows from the reserved couplings the
//! checkpoint keeps).
//!
//! A checkpoint holds, after the step it was written at:
//! - a header: the format, the program version, a fingerprint of the whole model (resume
//!   refuses another model's) and of each part that defines the saved state (`blocks`,
//!   `joints`, `cover`, `materials`, and each stage up to the current one: `--from`
//!   compares these), the model's path and the run options;
//! - the simulation's state: step, clock (t₀ of the step grid, full steps, partial
//!   interval), stage, where the base-motion record starts, u, v, stresses, the element
//!   nodes and polygons (the geometry moves with the material), the last increment (the
//!   next step's first iterate and contact search distance), the energy balance and the
//!   committed contact states ([`SavedContacts`]: each contact's law by its name in the
//!   registry, written once, and its state's words); with `[[bolt]]`, last, each bolt's
//!   committed state ([`crate::bolt::SavedBolt`]) and the bolts' energies (a model without
//!   bolts writes nothing there: its checkpoints are what they were);
//! - (format 5) the tangent's reserved couplings, each with the step it was last used (format
//!   7: each with the key contacts find it by)
//!   (`simulation/step.rs`, `TangentPattern`): the pattern, and so the ordering and the
//!   round-off, of the next steps' factorisations follow from them. A checkpoint of an
//!   earlier format is refused with the version that wrote it;
//! - (format 8) each closed contact's last branch and its record of the first iterate's
//!   predictions, and the set's default for contacts without one
//!   ([`crate::contact::set::FirstChoice`]): the next step's first choice of branches;
//! - the run's outputs so far: the length of history.csv in bytes, the .pvd frame lists,
//!   and the run's counters for summary.json (format 6: six linear-solver counts, the
//!   unsymmetric LU factorisations added; format 9: the same layout, but history.csv's
//!   rows end with the step's `solves` and `cuts`, so that a run written before cannot be
//!   continued onto its history).
//!
//! Numbers are stored as their bits (little-endian `u64`), so nothing is lost to decimal.
//! The file ends with an FNV-1a checksum of everything before it; it is written to a
//! temporary name and renamed, so a run killed while writing leaves the previous one.

use super::{Energy, Simulation};
use crate::contact::law::Branch;
use crate::contact::law::{LawId, LawState};
use crate::contact::set::{Committed, FirstChoice, SavedContacts};
use crate::model::{Model, Stage};
use std::path::Path;
use std::time::Duration;

const MAGIC: &[u8; 8] = b"NMMCKPT\n";
/// Bumped whenever the layout below changes.
pub const FORMAT: u32 = 9;

/// The program version a checkpoint must come from.
pub fn program_version() -> String {
    format!(
        "nmm {} (checkpoint format {FORMAT})",
        env!("CARGO_PKG_VERSION")
    )
}

/// FNV-1a, 64 bits: a stable hash (std's hashers may change between releases).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn hash_debug<T: std::fmt::Debug + ?Sized>(x: &T) -> u64 {
    fnv1a(without_defaults(format!("{x:?}")).as_bytes())
}

/// The `Debug` text of a model part without the keys added later at their defaults
/// (`holes: []` of a block, `excavate: []` of a stage, `initial_stress: None`), so that
/// the fingerprints of models that do not use them are what they were.
fn without_defaults(text: String) -> String {
    if text.contains(", holes: []")
        || text.contains(", excavate: []")
        || text.contains(", initial_stress: None")
    {
        text.replace(", holes: []", "")
            .replace(", excavate: []", "")
            .replace(", initial_stress: None", "")
    } else {
        text
    }
}

/// The stages of a model as run: its `[[stage]]` tables, or `[analysis]` as one stage.
fn stages_of(model: &Model) -> Vec<Stage> {
    if model.stages.is_empty() {
        vec![Stage {
            name: String::new(),
            analysis: model.analysis.clone(),
            base_motion: true,
            excavate: Vec::new(),
        }]
    } else {
        model.stages.clone()
    }
}

/// Fingerprint of the whole model (as loaded: `analysis` is the first stage's when there
/// are stages, whatever stage a simulation is in). A key added to the model later enters
/// it only when it is not its default (`[cover] order` = 0, no `[[bolt]]`), so that the
/// checkpoints of models that do not use it are what they were.
pub fn model_fingerprint(model: &Model) -> u64 {
    let mut m = model.clone();
    if let Some(s) = m.stages.first() {
        m.analysis = s.analysis.clone();
    }
    let mut text = without_defaults(format!("{m:?}"));
    // `bolts` is the model's last field
    if let Some(t) = text.strip_suffix(", bolts: [] }") {
        text = format!("{t} }}");
    }
    if m.cover_order == 0 {
        fnv1a(text.replacen(", cover_order: 0", "", 1).as_bytes())
    } else {
        fnv1a(text.as_bytes())
    }
}

/// Fingerprints of what defines a saved state at stage `stage`: blocks, joints, cover,
/// materials and the stages up to `stage`, by name. `None` where the model has no such stage.
pub fn part_fingerprints(model: &Model, stage: usize) -> Vec<(String, Option<u64>)> {
    let blocks: Vec<_> = model
        .blocks
        .iter()
        .map(|b| (&b.name, b.material, &b.vertices, b.fixed, &b.edge_joint))
        .collect();
    let holes: Vec<_> = model.blocks.iter().map(|b| &b.holes).collect();
    let blocks_hash = if holes.iter().all(|h| h.is_empty()) {
        hash_debug(&blocks)
    } else {
        hash_debug(&(&blocks, &holes))
    };
    let mut parts = vec![
        ("blocks".to_string(), Some(blocks_hash)),
        (
            "joints".to_string(),
            Some(hash_debug(&(&model.joints, &model.cracks))),
        ),
        (
            "cover".to_string(),
            Some(if model.cover_order == 0 {
                hash_debug(&(model.cover_size, model.cover_origin, model.min_block_area))
            } else {
                hash_debug(&(
                    model.cover_size,
                    model.cover_origin,
                    model.min_block_area,
                    model.cover_order,
                ))
            }),
        ),
        ("materials".to_string(), Some(hash_debug(&model.materials))),
    ];
    if let Some(s) = &model.initial_stress {
        // the elements' stress and the contacts' in-situ offsets start from it
        parts.push(("initial stress".to_string(), Some(hash_debug(s))));
    }
    if !model.bolts.is_empty() {
        // the bolts installed by the end of `stage` (their state is saved)
        let installed: Vec<_> = model
            .bolts
            .iter()
            .filter(|b| b.stage.is_none_or(|s| s <= stage))
            .collect();
        parts.push(("bolts".to_string(), Some(hash_debug(&installed))));
    }
    let stages = stages_of(model);
    for k in 0..=stage {
        let name = match stages.get(k) {
            Some(s) if s.name.is_empty() => "[analysis]".to_string(),
            Some(s) => format!("stage {:?}", s.name),
            None => format!("stage #{}", k + 1),
        };
        parts.push((
            format!("stage #{} ({name})", k + 1),
            stages.get(k).map(hash_debug),
        ));
    }
    parts
}

/// The run options a resumed run keeps.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SavedOptions {
    /// `--friction` given on the command line.
    pub friction: Option<LawId>,
    pub vtk: bool,
    /// Checkpoint every N steps (0: only at stage ends and interrupts).
    pub checkpoint_every: usize,
}

/// The outputs of the run so far and its counters (for summary.json).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SavedOutputs {
    /// Bytes of history.csv up to and including the checkpoint's row.
    pub history_len: u64,
    pub blocks_frames: Vec<(f64, String)>,
    pub contacts_frames: Vec<(f64, String)>,
    /// The frames' stage names (empty without stages).
    pub blocks_names: Vec<String>,
    pub contacts_names: Vec<String>,
    /// The step of the last VTK frame.
    pub last_frame: usize,
    pub iterations: Vec<usize>,
    pub solves: Vec<usize>,
    pub contacts: Vec<usize>,
    pub cut_steps: Vec<(usize, usize)>,
    pub active_set_changes: usize,
    pub not_in_equilibrium: usize,
    pub last_equilibrium: bool,
    pub linear: [usize; 6],
    /// cover, assembly, contact, factorisation, solve, output (s).
    pub timings: [Duration; 6],
    /// Steps done in static mode.
    pub static_steps: usize,
    /// Wall-clock time of the whole run up to the checkpoint (s).
    pub total: Duration,
}

/// A checkpoint as read from its file.
#[derive(Debug, Clone)]
pub struct Checkpoint {
    pub version: String,
    pub model_hash: u64,
    pub parts: Vec<(String, Option<u64>)>,
    /// The model file of the run, as given (absolute when it could be made so).
    pub model_path: String,
    pub options: SavedOptions,
    /// Completed steps.
    pub step: usize,
    pub time: f64,
    /// The stage the last step belonged to, and whether that stage was complete.
    pub stage: usize,
    pub stage_finished: bool,
    pub outputs: SavedOutputs,
    state: Vec<u8>,
}

// ------------------------------------------------------------------ encoding

#[derive(Default)]
struct W(Vec<u8>);
impl W {
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn us(&mut self, x: usize) {
        self.u64(x as u64);
    }
    fn f(&mut self, x: f64) {
        self.u64(x.to_bits());
    }
    fn b(&mut self, x: bool) {
        self.0.push(u8::from(x));
    }
    fn s(&mut self, x: &str) {
        self.us(x.len());
        self.0.extend_from_slice(x.as_bytes());
    }
    fn fs(&mut self, x: &[f64]) {
        self.us(x.len());
        x.iter().for_each(|v| self.f(*v));
    }
    fn uss(&mut self, x: &[usize]) {
        self.us(x.len());
        x.iter().for_each(|v| self.us(*v));
    }
    fn d(&mut self, x: Duration) {
        self.u64(x.as_nanos() as u64);
    }
}

struct Rd<'a> {
    b: &'a [u8],
    at: usize,
}
type Res<T> = Result<T, String>;
impl Rd<'_> {
    fn take(&mut self, n: usize) -> Res<&[u8]> {
        if self.b.len() - self.at < n {
            return Err("truncated".into());
        }
        let s = &self.b[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }
    fn u64(&mut self) -> Res<u64> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    fn us(&mut self) -> Res<usize> {
        usize::try_from(self.u64()?).map_err(|_| "a count out of range".to_string())
    }
    /// A count of items of at least `size` bytes each that the rest of the file can hold.
    fn len(&mut self, size: usize) -> Res<usize> {
        let n = self.us()?;
        if n.saturating_mul(size) > self.b.len() - self.at {
            return Err("truncated".into());
        }
        Ok(n)
    }
    fn f(&mut self) -> Res<f64> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn b(&mut self) -> Res<bool> {
        Ok(self.take(1)?[0] != 0)
    }
    fn s(&mut self) -> Res<String> {
        let n = self.len(1)?;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| "bad text".into())
    }
    fn fs(&mut self) -> Res<Vec<f64>> {
        let n = self.len(8)?;
        (0..n).map(|_| self.f()).collect()
    }
    fn uss(&mut self) -> Res<Vec<usize>> {
        let n = self.len(8)?;
        (0..n).map(|_| self.us()).collect()
    }
    fn d(&mut self) -> Res<Duration> {
        Ok(Duration::from_nanos(self.u64()?))
    }
}

/// A law's state: its words.
fn law_state(w: &mut W, h: &LawState) {
    h.0.iter().for_each(|x| w.u64(*x));
}

/// A branch as one number: its kind in the low byte, its two small integers (a sliding
/// direction, a law's limit) in the next two.
fn branch_code(b: Branch) -> usize {
    let (kind, a, s) = match b {
        Branch::Open => (0, 0, 0),
        Branch::Stick => (1, 0, 0),
        Branch::Slide(s) => (2, 0, s),
        Branch::Limit(a, s) => (3, a, s),
    };
    kind | (usize::from(a) << 8) | (usize::from(s as u8) << 16)
}

/// The branch of [`branch_code`].
fn read_branch(code: usize) -> Res<Branch> {
    let (a, s) = (
        ((code >> 8) & 0xff) as u8,
        ((code >> 16) & 0xff) as u8 as i8,
    );
    let b = match (code & 0xff, code >> 24) {
        (0, 0) => Branch::Open,
        (1, 0) => Branch::Stick,
        (2, 0) => Branch::Slide(s),
        (3, 0) => Branch::Limit(a, s),
        _ => return Err(format!("bad contact branch {code}")),
    };
    if branch_code(b) != code {
        return Err(format!("bad contact branch {code}"));
    }
    Ok(b)
}

/// A contact's record of its first-iterate predictions ([`FirstChoice`]) as a number.
fn first_choice_code(c: FirstChoice) -> usize {
    match c {
        FirstChoice::Unknown => 0,
        FirstChoice::Last => 1,
        FirstChoice::Own => 2,
    }
}

/// The record of [`first_choice_code`].
fn read_first_choice(code: usize) -> Res<FirstChoice> {
    match code {
        0 => Ok(FirstChoice::Unknown),
        1 => Ok(FirstChoice::Last),
        2 => Ok(FirstChoice::Own),
        x => Err(format!("bad record of a contact's predictions {x}")),
    }
}

/// A law and its state written by [`law_state`], the law by its index in `laws`.
fn read_law_state(r: &mut Rd, laws: &[LawId]) -> Res<(LawId, LawState)> {
    let i = r.us()?;
    let law = *laws.get(i).ok_or_else(|| format!("bad contact law {i}"))?;
    let mut h = LawState::default();
    for x in h.0.iter_mut() {
        *x = r.u64()?;
    }
    if !law.law().valid_state(&h) {
        return Err(format!("bad contact state for law {:?}", law.name()));
    }
    Ok((law, h))
}

fn frames(w: &mut W, f: &[(f64, String)]) {
    w.us(f.len());
    for (t, name) in f {
        w.f(*t);
        w.s(name);
    }
}

fn read_frames(r: &mut Rd) -> Res<Vec<(f64, String)>> {
    let n = r.len(16)?;
    (0..n).map(|_| Ok((r.f()?, r.s()?))).collect()
}

impl Simulation {
    /// The elements that have unknowns (those of fixed blocks never move).
    fn moving_elements(&self) -> Vec<usize> {
        (0..self.disc.elements.len())
            .filter(|&i| {
                self.elem_dofs
                    .of(i)
                    .iter()
                    .any(|&d| d != crate::assembly::global::NO_DOF)
            })
            .collect()
    }

    /// The simulation's state (the part of a checkpoint after its header).
    fn encode_state(&self, w: &mut W) {
        w.us(self.step);
        w.f(self.time);
        w.us(self.stage);
        w.f(self.time_origin);
        w.u64(self.full_steps);
        w.f(self.partial);
        w.b(self.base_origin.is_some());
        w.f(self.base_origin.unwrap_or(0.0));
        w.fs(&self.u);
        w.fs(&self.v);
        // elements of fixed blocks (no unknowns) never move nor load
        let moving = self.moving_elements();
        w.us(moving.len());
        for s in moving.iter().map(|&i| &self.stress[i]) {
            s.iter().for_each(|x| w.f(*x));
        }
        // order 1: the stress at the elements' nodes (nothing at order 0)
        for &i in &moving {
            for s in self.stress_nodes.iter().skip(3 * i).take(3) {
                s.iter().for_each(|x| w.f(*x));
            }
        }
        w.us(moving.len());
        for e in moving.iter().map(|&i| &self.disc.elements[i]) {
            e.nodes.iter().flatten().for_each(|x| w.f(*x));
            w.us(e.polygon.len());
            e.polygon.iter().flatten().for_each(|x| w.f(*x));
        }
        w.fs(&self.last_du);
        w.f(self.last_dt);
        w.f(self.last_max_du);
        let e = &self.energy;
        for x in e.components().into_iter().chain([
            e.initial,
            e.max,
            e.scale,
            e.friction,
            e.damping,
            e.algorithmic,
            e.flow,
            e.constraint_work,
            e.static_reset,
            e.contact_update,
        ]) {
            w.f(x);
        }
        let c = self.contacts.saved();
        w.us(c.commits);
        // the registry's names: the contacts' laws are their indices in this list
        let laws: Vec<LawId> = LawId::all().collect();
        w.us(laws.len());
        laws.iter().for_each(|l| w.s(l.name()));
        let index = |l: &LawId| laws.iter().position(|x| x == l).unwrap_or(0);
        w.b(c.prefer_last);
        w.us(c.committed.len());
        for (k, c) in &c.committed {
            [k.0, k.1, k.2].iter().for_each(|x| w.us(*x));
            w.us(index(&c.law));
            law_state(w, &c.state);
            w.f(c.normal[0]);
            w.f(c.normal[1]);
            w.us(branch_code(c.branch));
            w.us(first_choice_code(c.first_choice));
        }
        w.us(c.lasting.len());
        for (k, l, h) in &c.lasting {
            [k.0, k.1, k.2].iter().for_each(|x| w.us(*x));
            w.us(index(l));
            law_state(w, h);
        }
        w.us(c.seen.len());
        for k in &c.seen {
            [k.0, k.1, k.2].iter().for_each(|x| w.us(*x));
        }
        // in-situ stress and excavation (format 4): the energy the excavated blocks took,
        // the contacts' in-situ offsets (the excavated blocks follow from the stage)
        w.f(e.excavated);
        let offsets = self.contacts.insitu_offsets();
        w.us(offsets.len());
        for (k, dn, gs) in &offsets {
            [k.0, k.1, k.2].iter().for_each(|x| w.us(*x));
            w.f(*dn);
            w.f(*gs);
        }
        if !self.bolts.is_empty() {
            let saved = self.bolts.saved();
            w.us(saved.len());
            for b in &saved {
                w.b(b.installed);
                for x in [b.length0, b.plastic, b.force, b.elongation] {
                    w.f(x);
                }
                w.b(b.yielded);
            }
            w.f(e.bolts);
            w.f(e.bolt_plastic);
        }
        // the tangent's reserved couplings (format 5): the pattern of the next step's
        // factorisations follows from them (simulation/step.rs, TangentPattern)
        let t = self.linear.tangent.saved();
        w.us(t.contact_dofs);
        w.us(t.reserved.len());
        for (p, k, used) in &t.reserved {
            p.iter().for_each(|d| w.us(*d));
            k.iter().for_each(|d| w.us(*d));
            w.us(*used);
        }
    }

    /// Restore a state written by [`Simulation::encode_state`] into a simulation freshly
    /// made from the same blocks, covers and materials.
    fn decode_state(&mut self, r: &mut Rd) -> Res<()> {
        self.step = r.us()?;
        self.time = r.f()?;
        let stage = r.us()?;
        if stage >= self.model.stages.len().max(1) {
            return Err(format!("stage #{} is not in the model", stage + 1));
        }
        self.stage = stage;
        if let Some(s) = self.model.stages.get(stage) {
            self.model.analysis = s.analysis.clone();
        }
        self.scale_constraint_penalties();
        // the blocks excavated up to this stage are gone (their unknowns too)
        self.excavate_through(stage);
        // the unknowns that remain after the excavations
        let n = self.n_dofs();
        self.time_origin = r.f()?;
        self.full_steps = r.u64()?;
        self.partial = r.f()?;
        let has_base = r.b()?;
        let t0 = r.f()?;
        self.base_origin = has_base.then_some(t0);
        let sized = |v: Vec<f64>, what: &str| -> Res<Vec<f64>> {
            if v.len() == n {
                Ok(v)
            } else {
                Err(format!(
                    "{what} has {} unknowns, the model {n}: the discretisation differs",
                    v.len()
                ))
            }
        };
        self.u = sized(r.fs()?, "u")?;
        self.v = sized(r.fs()?, "v")?;
        let moving = self.moving_elements();
        if r.len(24)? != moving.len() {
            return Err("the number of manifold elements differs".into());
        }
        for &i in &moving {
            for x in self.stress[i].iter_mut() {
                *x = r.f()?;
            }
        }
        for &i in &moving {
            for s in self.stress_nodes.iter_mut().skip(3 * i).take(3) {
                for x in s.iter_mut() {
                    *x = r.f()?;
                }
            }
        }
        if r.len(48)? != moving.len() {
            return Err("the number of manifold elements differs".into());
        }
        for &i in &moving {
            let e = &mut self.disc.elements[i];
            for node in e.nodes.iter_mut() {
                node[0] = r.f()?;
                node[1] = r.f()?;
            }
            let m = r.len(16)?;
            if m != e.polygon.len() {
                return Err("a manifold element's polygon differs".into());
            }
            for x in e.polygon.iter_mut() {
                x[0] = r.f()?;
                x[1] = r.f()?;
            }
        }
        self.last_du = sized(r.fs()?, "the last increment")?;
        self.last_dt = r.f()?;
        self.last_max_du = r.f()?;
        self.energy = Energy {
            kinetic: r.f()?,
            elastic: r.f()?,
            gravity: r.f()?,
            contact: r.f()?,
            penalty: r.f()?,
            external_work: r.f()?,
            initial: r.f()?,
            max: r.f()?,
            scale: r.f()?,
            friction: r.f()?,
            damping: r.f()?,
            algorithmic: r.f()?,
            flow: r.f()?,
            constraint_work: r.f()?,
            static_reset: r.f()?,
            contact_update: r.f()?,
            excavated: 0.0,
            bolts: 0.0,
            bolt_plastic: 0.0,
        };
        let commits = r.us()?;
        let nl = r.len(8)?;
        let laws = (0..nl)
            .map(|_| {
                let name = r.s()?;
                LawId::by_name(&name).ok_or_else(|| format!("unknown contact law {name:?}"))
            })
            .collect::<Res<Vec<_>>>()?;
        let words = 8 * LawState::WORDS;
        let prefer_last = r.b()?;
        let nc = r.len(56 + words)?;
        let mut committed = Vec::with_capacity(nc);
        for _ in 0..nc {
            let k = (r.us()?, r.us()?, r.us()?);
            let (law, state) = read_law_state(r, &laws)?;
            let normal = [r.f()?, r.f()?];
            let branch = read_branch(r.us()?)?;
            let first_choice = read_first_choice(r.us()?)?;
            committed.push((
                k,
                Committed {
                    law,
                    state,
                    normal,
                    branch,
                    first_choice,
                },
            ));
        }
        let nk = r.len(32 + words)?;
        let mut lasting = Vec::with_capacity(nk);
        for _ in 0..nk {
            let k = (r.us()?, r.us()?, r.us()?);
            let (l, h) = read_law_state(r, &laws)?;
            lasting.push((k, l, h));
        }
        let ns = r.len(24)?;
        let seen = (0..ns)
            .map(|_| Ok((r.us()?, r.us()?, r.us()?)))
            .collect::<Res<Vec<_>>>()?;
        let blocks = self.model.blocks.len();
        if committed
            .iter()
            .map(|c| c.0)
            .chain(lasting.iter().map(|c| c.0))
            .chain(seen.iter().copied())
            .any(|k| k.0 >= blocks || k.2 >= blocks)
        {
            return Err("a contact names a block that is not in the model".into());
        }
        self.contacts.restore(&SavedContacts {
            commits,
            committed,
            prefer_last,
            lasting,
            seen,
        });
        self.energy.excavated = r.f()?;
        let no = r.len(40)?;
        let offsets = (0..no)
            .map(|_| Ok(((r.us()?, r.us()?, r.us()?), r.f()?, r.f()?)))
            .collect::<Res<Vec<_>>>()?;
        if offsets.iter().any(|o| o.0 .0 >= blocks || o.0 .2 >= blocks) {
            return Err("a contact names a block that is not in the model".into());
        }
        self.contacts.restore_insitu_offsets(&offsets);
        if !self.bolts.is_empty() {
            let nb = r.len(34)?;
            let saved = (0..nb)
                .map(|_| {
                    Ok(crate::bolt::SavedBolt {
                        installed: r.b()?,
                        length0: r.f()?,
                        plastic: r.f()?,
                        force: r.f()?,
                        elongation: r.f()?,
                        yielded: r.b()?,
                    })
                })
                .collect::<Res<Vec<_>>>()?;
            self.bolts.restore(&saved)?;
            self.energy.bolts = r.f()?;
            self.energy.bolt_plastic = r.f()?;
        }
        let contact_dofs = r.us()?;
        if contact_dofs > crate::contact::set::MAX_CONTACT_DOFS {
            return Err("a reserved coupling of the tangent does not fit the model".into());
        }
        let nr = r.len(8 * (2 * contact_dofs + 1))?;
        let reserved = (0..nr)
            .map(|_| {
                let p = (0..contact_dofs).map(|_| r.us()).collect::<Res<Vec<_>>>()?;
                let k = (0..contact_dofs).map(|_| r.us()).collect::<Res<Vec<_>>>()?;
                Ok((p, k, r.us()?))
            })
            .collect::<Res<Vec<_>>>()?;
        self.linear.tangent.restore(&super::step::SavedPattern {
            contact_dofs,
            reserved,
        })?;
        // the next step detects its contacts and assembles afresh, as after any step
        self.contacts_current = false;
        self.linear.step = None;
        self.solver_cm = None;
        self.solver_step = None;
        Ok(())
    }

    /// A checkpoint of the current state as bytes (see the module docs).
    pub fn checkpoint_bytes(
        &self,
        model_path: &str,
        options: &SavedOptions,
        outputs: &SavedOutputs,
    ) -> Vec<u8> {
        let mut w = W::default();
        w.0.extend_from_slice(MAGIC);
        w.s(&program_version());
        w.u64(model_fingerprint(&self.model));
        let parts = part_fingerprints(&self.model, self.stage);
        w.us(parts.len());
        for (name, h) in &parts {
            w.s(name);
            w.u64(h.unwrap_or(0));
        }
        w.s(model_path);
        w.s(options.friction.map_or("", LawId::name));
        w.b(options.vtk);
        w.us(options.checkpoint_every);
        w.us(self.step);
        w.f(self.time);
        w.us(self.stage);
        w.b(self.stage_finished());
        let o = outputs;
        w.u64(o.history_len);
        frames(&mut w, &o.blocks_frames);
        frames(&mut w, &o.contacts_frames);
        for names in [&o.blocks_names, &o.contacts_names] {
            w.us(names.len());
            names.iter().for_each(|n| w.s(n));
        }
        w.us(o.last_frame);
        w.uss(&o.iterations);
        w.uss(&o.solves);
        w.uss(&o.contacts);
        w.us(o.cut_steps.len());
        for (s, c) in &o.cut_steps {
            w.us(*s);
            w.us(*c);
        }
        w.us(o.active_set_changes);
        w.us(o.not_in_equilibrium);
        w.b(o.last_equilibrium);
        o.linear.iter().for_each(|x| w.us(*x));
        o.timings.iter().for_each(|x| w.d(*x));
        w.us(o.static_steps);
        w.d(o.total);
        let mut state = W::default();
        self.encode_state(&mut state);
        w.us(state.0.len());
        w.0.extend_from_slice(&state.0);
        let sum = fnv1a(&w.0);
        w.u64(sum);
        w.0
    }

    /// Write a checkpoint to `path` (through a temporary file and a rename).
    pub fn write_checkpoint(
        &self,
        path: &Path,
        model_path: &str,
        options: &SavedOptions,
        outputs: &SavedOutputs,
    ) -> std::io::Result<()> {
        let bytes = self.checkpoint_bytes(model_path, options, outputs);
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        {
            use std::io::Write;
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(&bytes)?;
            f.sync_all()?;
        }
        std::fs::rename(&tmp, path)
    }

    /// Restore the state of `ckpt` into this simulation, made by [`Simulation::new`] from a
    /// model whose saved-state parts match (see [`Checkpoint::differences`]).
    pub fn restore(&mut self, ckpt: &Checkpoint) -> Result<(), String> {
        let mut r = Rd {
            b: &ckpt.state,
            at: 0,
        };
        self.decode_state(&mut r)
            .map_err(|e| format!("checkpoint does not fit the model: {e}"))?;
        if r.at != ckpt.state.len() {
            return Err("checkpoint does not fit the model: trailing state".into());
        }
        Ok(())
    }
}

impl Checkpoint {
    /// Read a checkpoint file. Errors are one line: not a checkpoint, another program
    /// version, damaged.
    pub fn read(path: &Path) -> Result<Checkpoint, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Checkpoint::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub fn from_bytes(bytes: &[u8]) -> Result<Checkpoint, String> {
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err("not an nmm checkpoint".into());
        }
        let mut r = Rd {
            b: bytes,
            at: MAGIC.len(),
        };
        let damaged = |e: String| format!("damaged checkpoint ({e})");
        let version = r.s().map_err(damaged)?;
        if version != program_version() {
            return Err(format!(
                "checkpoint written by {version}, this is {}: resume it with that version",
                program_version()
            ));
        }
        if bytes.len() < r.at + 8 {
            return Err(damaged("truncated".into()));
        }
        let body = &bytes[..bytes.len() - 8];
        let sum = u64::from_le_bytes(bytes[bytes.len() - 8..].try_into().unwrap());
        if fnv1a(body) != sum {
            return Err(damaged("checksum mismatch".into()));
        }
        let mut r = Rd { b: body, at: r.at };
        (|| -> Res<Checkpoint> {
            let model_hash = r.u64()?;
            let np = r.len(16)?;
            let parts = (0..np)
                .map(|_| Ok((r.s()?, Some(r.u64()?))))
                .collect::<Res<Vec<_>>>()?;
            let model_path = r.s()?;
            let friction = match r.s()?.as_str() {
                "" => None,
                name => Some(
                    LawId::for_analysis(name)
                        .ok_or_else(|| format!("unknown friction law {name:?}"))?,
                ),
            };
            let options = SavedOptions {
                friction,
                vtk: r.b()?,
                checkpoint_every: r.us()?,
            };
            let step = r.us()?;
            let time = r.f()?;
            let stage = r.us()?;
            let stage_finished = r.b()?;
            let history_len = r.u64()?;
            let blocks_frames = read_frames(&mut r)?;
            let contacts_frames = read_frames(&mut r)?;
            let mut names = Vec::new();
            for _ in 0..2 {
                let n = r.len(8)?;
                names.push((0..n).map(|_| r.s()).collect::<Res<Vec<_>>>()?);
            }
            let contacts_names = names.pop().unwrap_or_default();
            let blocks_names = names.pop().unwrap_or_default();
            let last_frame = r.us()?;
            let iterations = r.uss()?;
            let solves = r.uss()?;
            let contacts = r.uss()?;
            let ncut = r.len(16)?;
            let cut_steps = (0..ncut)
                .map(|_| Ok((r.us()?, r.us()?)))
                .collect::<Res<Vec<_>>>()?;
            let outputs = SavedOutputs {
                history_len,
                blocks_frames,
                contacts_frames,
                blocks_names,
                contacts_names,
                last_frame,
                iterations,
                solves,
                contacts,
                cut_steps,
                active_set_changes: r.us()?,
                not_in_equilibrium: r.us()?,
                last_equilibrium: r.b()?,
                linear: [r.us()?, r.us()?, r.us()?, r.us()?, r.us()?, r.us()?],
                timings: [r.d()?, r.d()?, r.d()?, r.d()?, r.d()?, r.d()?],
                static_steps: r.us()?,
                total: r.d()?,
            };
            let n = r.len(1)?;
            let state = r.take(n)?.to_vec();
            if r.at != body.len() {
                return Err("trailing bytes".into());
            }
            Ok(Checkpoint {
                version,
                model_hash,
                parts,
                model_path,
                options,
                step,
                time,
                stage,
                stage_finished,
                outputs,
                state,
            })
        })()
        .map_err(damaged)
    }

    /// Whether `model` (with the checkpoint's `--friction`, if any, applied) is the model
    /// the checkpoint was written from.
    pub fn is_of_model(&self, model: &Model) -> bool {
        model_fingerprint(model) == self.model_hash
    }

    /// What differs between the saved state's defining parts and `model`'s (empty: the
    /// model can start from this checkpoint), by part name: the parts other than stages by
    /// their names (a part that one side has and the other not differs), then the stages in
    /// order.
    pub fn differences(&self, model: &Model) -> Vec<String> {
        let mine = part_fingerprints(model, self.stage);
        let is_stage = |p: &&(String, Option<u64>)| p.0.starts_with("stage #");
        let mut out: Vec<String> = Vec::new();
        for (name, h) in self.parts.iter().filter(|p| !is_stage(p)) {
            match mine.iter().find(|p| p.0 == *name) {
                Some(p) if p.1 == *h => {}
                Some(_) => out.push(name.clone()),
                None => out.push(format!("{name} (the new model has none)")),
            }
        }
        for (name, _) in mine.iter().filter(|p| !is_stage(p)) {
            if !self.parts.iter().any(|p| p.0 == *name) {
                out.push(format!("{name} (the saved run had none)"));
            }
        }
        let theirs = self.parts.iter().filter(is_stage);
        let ours = mine.iter().filter(is_stage);
        out.extend(theirs.zip(ours).filter(|(a, b)| a.1 != b.1).map(|(a, b)| {
            if b.1.is_none() {
                format!("{} (the new model has no such stage)", a.0)
            } else if a.0 != b.0 {
                format!("{} (now {})", a.0, b.0)
            } else {
                a.0.clone()
            }
        }));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every branch a law can take is written as a number and read back as itself; a
    /// number no branch writes is refused.
    #[test]
    fn branches_are_read_back_as_written() {
        let mut all = vec![Branch::Open, Branch::Stick];
        for s in [-1i8, 0, 1, i8::MIN, i8::MAX] {
            all.push(Branch::Slide(s));
            for a in [0u8, 1, 2, u8::MAX] {
                all.push(Branch::Limit(a, s));
            }
        }
        for b in all {
            assert_eq!(read_branch(branch_code(b)), Ok(b), "{b:?}");
        }
        for bad in [4usize, 1 << 8, 1 | (1 << 16), 1 << 24, usize::MAX] {
            assert!(read_branch(bad).is_err(), "{bad}");
        }
    }

    /// So is every record of a contact's first-iterate predictions.
    #[test]
    fn first_choices_are_read_back_as_written() {
        for c in [FirstChoice::Unknown, FirstChoice::Last, FirstChoice::Own] {
            assert_eq!(read_first_choice(first_choice_code(c)), Ok(c), "{c:?}");
        }
        for bad in [3usize, usize::MAX] {
            assert!(read_first_choice(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn fnv_is_the_reference_hash() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn a_damaged_checkpoint_is_refused() {
        assert_eq!(
            Checkpoint::from_bytes(b"hello").unwrap_err(),
            "not an nmm checkpoint"
        );
        let mut w = W::default();
        w.0.extend_from_slice(MAGIC);
        w.s("nmm 0.0.0 (checkpoint format 0)");
        let e = Checkpoint::from_bytes(&w.0).unwrap_err();
        assert!(e.starts_with("checkpoint written by nmm 0.0.0"), "{e}");
        let mut w = W::default();
        w.0.extend_from_slice(MAGIC);
        w.s(&program_version());
        w.u64(7);
        w.u64(0);
        let e = Checkpoint::from_bytes(&w.0).unwrap_err();
        assert!(e.contains("checksum mismatch"), "{e}");
    }
}
