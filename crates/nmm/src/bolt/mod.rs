//! Rock bolts (`[[bolt]]`): elastic–perfectly plastic axial members between two material
//! points, in the step's Newton system with their consistent tangent.
//!
//! This module owns the bolts of a run ([`BoltSet`]): their anchors on the discretisation,
//! their committed state (installed or not, reference length, plastic elongation, force),
//! their kinematics in a step, and their local work — force, tangent block — which the
//! step's system scatters (`simulation/step.rs`). The law is [`law`].
//!
//! **Anchors.** Each end is a [`MaterialPoint`] (an element and its weights, located on the
//! initial geometry like a point monitor); its position is x₀ + u(x₀), u = Σ_a N_a U_a
//! over its element's shape functions ([`crate::cover::basis`]: at any cover order). An end
//! in a fixed block does not move.
//!
//! **Kinematics: small rotation per step, large over the run.** At a step's start the
//! anchors are at x_A, x_B (the committed displacement): length L_n = |x_B − x_A|,
//! direction e_n = (x_B − x_A)/L_n, elongation δ_n = L_n − L₀ (L₀: the length at
//! installation, so that a bolt takes nothing from the motion before it). Within the step
//! the elongation is linear in the increment Δu, as the contacts' gaps are:
//!
//!   δ(Δu) = δ_n + e_n · (Δu(x_B) − Δu(x_A)) = δ_n + bᵀ Δu,
//!
//! b = [−N_A e_n, +N_B e_n] over the unknowns of the two anchors' elements. The force on
//! the unknowns is N b (the internal force: R −= N b) and the tangent k_t b bᵀ (k_t = k
//! elastic, 0 yielding; symmetric). The direction is taken anew from the moved anchors at
//! every step, so bolts follow rotations of any size over many steps; within one step the
//! rotation of the bolt is taken as small: the elongation it leaves out is
//! |Δ(x_B − x_A)_⊥|²/(2 L), of second order in the step's transverse motion, and it enters
//! the next step's δ_n. The outputs (force, elongation) are the committed ones: N and δ of
//! the step's linearised elongation.
//!
//! **Installation.** A bolt without `stage` is installed before the first step; one with
//! `stage` at the start of that stage (before its first step): L₀ is the anchors'
//! distance then, p = −N₀/k (the pretension N₀). Its state is committed only when a step
//! converges, like the contacts'.
//!
//! **Energy** (`Energy` in `simulation/mod.rs`): stored ½ N²/k; dissipated N Δp (plastic
//! work); the scheme's share ½ k Δe² per step (e = δ − p: the force is taken at the step's
//! end, as every force of the step); the pretension's ½ N₀²/k is the work done on the
//! system at installation (external work); the difference between a step's end energy
//! and the next step's start energy (the second-order elongation above) is counted with
//! the contacts' update.

pub mod law;

use crate::cover::basis::NO_DOF;
use crate::cover::{Discretisation, MaterialPoint};
use crate::geometry::Vec2;
use crate::model::Model;
use law::{BoltBranch, BoltParams};

/// One bolt: its anchors, its committed state and its kinematics in the current step.
#[derive(Debug, Clone)]
pub struct Bolt {
    pub params: BoltParams,
    /// Force at installation N₀ (N).
    pub pretension: f64,
    /// The stage it is installed at (index into `Model::stages`; `None`: the start).
    pub stage: Option<usize>,
    /// The two anchors (A, B) and their initial positions.
    pub anchors: [MaterialPoint; 2],
    pub x0: [Vec2; 2],
    /// The unknowns of A's element then B's (`basis.element_dofs()` each; [`NO_DOF`] where
    /// none, e.g. in a fixed block).
    pub dofs: Vec<usize>,
    /// Slots of the n² tangent entries (row-major over `dofs`) in the element pattern.
    slots: Vec<u32>,
    // ---- committed state
    pub installed: bool,
    /// Anchors' distance at installation L₀ (m).
    pub length0: f64,
    /// Plastic elongation p (m).
    pub plastic: f64,
    /// Axial force N after the last step (N, tension positive).
    pub force: f64,
    /// Elongation δ after the last step (m).
    pub elongation: f64,
    /// Whether the last step ended on a yield branch.
    pub yielded: bool,
    // ---- the current step
    /// e_n, δ_n and b (over `dofs`) at the step's start.
    dir: Vec2,
    delta0: f64,
    row: Vec<f64>,
    /// The branch the Newton iteration linearises on.
    branch: BoltBranch,
}

impl Bolt {
    /// δ(Δu) = δ_n + bᵀΔu.
    fn elongation_at(&self, du: &[f64]) -> f64 {
        let mut d = self.delta0;
        for (&k, &b) in self.dofs.iter().zip(&self.row) {
            if k != NO_DOF {
                d += b * du[k];
            }
        }
        d
    }

    /// The anchors' current positions (displacement `u`).
    pub fn positions(&self, disc: &Discretisation, u: &[f64]) -> [Vec2; 2] {
        std::array::from_fn(|i| {
            let d = disc.displacement_at(&self.anchors[i], u);
            [self.x0[i][0] + d[0], self.x0[i][1] + d[1]]
        })
    }

    /// Adds `s` × b to `r`.
    fn scatter(&self, s: f64, r: &mut [f64]) {
        for (&k, &b) in self.dofs.iter().zip(&self.row) {
            if k != NO_DOF {
                r[k] += s * b;
            }
        }
    }
}

/// The energy the bolts exchanged in the last committed step (J/m).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BoltStepEnergy {
    /// Plastic work Σ N Δp.
    pub plastic: f64,
    /// The scheme's share Σ ½ k Δe².
    pub algorithmic: f64,
    /// The energy of the bolts installed before the step, on the step's start kinematics.
    pub start: f64,
    /// The energy of the bolts installed at the step's start (their pretension).
    pub installed: f64,
}

/// The bolts of a run.
#[derive(Debug, Clone, Default)]
pub struct BoltSet {
    pub bolts: Vec<Bolt>,
    step: BoltStepEnergy,
    /// Energy (pretension) of the bolts installed since the last committed step.
    pending: f64,
}

/// A bolt's state that crosses steps (checkpoints).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SavedBolt {
    pub installed: bool,
    pub length0: f64,
    pub plastic: f64,
    pub force: f64,
    pub elongation: f64,
    pub yielded: bool,
}

impl BoltSet {
    /// The model's bolts on the discretisation `disc` (element unknowns from `elem_dofs`),
    /// not yet installed. An anchor the discretisation cannot locate in its block (a point
    /// in a sliver it dropped) is an error naming the bolt.
    pub fn new(
        model: &Model,
        disc: &Discretisation,
        elem_dofs: &crate::cover::basis::ElementDofTable,
    ) -> Result<BoltSet, String> {
        let mut bolts = Vec::with_capacity(model.bolts.len());
        for b in &model.bolts {
            let mut anchors = [MaterialPoint {
                element: 0,
                weights: [0.0; 3],
            }; 2];
            let mut dofs = Vec::with_capacity(2 * elem_dofs.stride());
            for (i, anchor) in anchors.iter_mut().enumerate() {
                *anchor = disc.locate(b.blocks[i], b.points[i]).ok_or_else(|| {
                    format!(
                        "[[bolt]] \"{}\": anchor {} {:?} is not inside block \"{}\" as discretised",
                        b.name,
                        i + 1,
                        b.points[i],
                        model.blocks[b.blocks[i]].name
                    )
                })?;
                dofs.extend_from_slice(elem_dofs.of(anchor.element));
            }
            let n = dofs.len();
            bolts.push(Bolt {
                params: BoltParams {
                    stiffness: b.stiffness,
                    capacity: b.capacity,
                },
                pretension: b.pretension,
                stage: b.stage,
                anchors,
                x0: b.points,
                dofs,
                slots: Vec::new(),
                installed: false,
                length0: 0.0,
                plastic: 0.0,
                force: 0.0,
                elongation: 0.0,
                yielded: false,
                dir: [1.0, 0.0],
                delta0: 0.0,
                row: vec![0.0; n],
                branch: BoltBranch::Elastic,
            });
        }
        Ok(BoltSet {
            bolts,
            ..Default::default()
        })
    }

    pub fn is_empty(&self) -> bool {
        self.bolts.is_empty()
    }

    /// The free unknowns of each bolt (a group of the element pattern: a bolt couples its
    /// two anchors' elements for the whole run).
    pub fn groups(&self) -> impl Iterator<Item = Vec<usize>> + '_ {
        self.bolts
            .iter()
            .map(|b| b.dofs.iter().copied().filter(|&d| d != NO_DOF).collect())
    }

    /// Number the bolts' unknowns again after an excavation removed some (`map`: new index
    /// of every old unknown, [`NO_DOF`] for a removed one; a bolt is never anchored in an
    /// excavated block, `model` refuses it).
    pub fn renumber(&mut self, map: &[usize]) {
        for b in &mut self.bolts {
            for d in b.dofs.iter_mut().filter(|d| **d != NO_DOF) {
                *d = map[*d];
            }
        }
    }

    /// Bind each bolt's tangent entries to their slots in the element pattern (which holds
    /// [`BoltSet::groups`]).
    pub fn bind(&mut self, pattern: &crate::solver::SparsePattern) {
        for b in &mut self.bolts {
            let n = b.dofs.len();
            b.slots = vec![u32::MAX; n * n];
            crate::assembly::global::group_slots(pattern, &b.dofs, &mut b.slots);
        }
    }

    /// Install the bolts not yet installed for which `now(stage)` holds, on the current
    /// geometry (displacement `u`): L₀ the anchors' distance, p = −N₀/k.
    pub fn install(
        &mut self,
        disc: &Discretisation,
        u: &[f64],
        now: impl Fn(Option<usize>) -> bool,
    ) {
        for b in &mut self.bolts {
            if b.installed || !now(b.stage) {
                continue;
            }
            let [xa, xb] = b.positions(disc, u);
            b.installed = true;
            b.length0 = crate::geometry::dist(xa, xb);
            b.plastic = b.params.installed_plastic(b.pretension);
            b.force = b.pretension;
            b.elongation = 0.0;
            b.yielded = false;
            self.pending += b.params.stored_energy(b.pretension);
        }
    }

    /// The kinematics of a step from the committed displacement `u` (see the module docs):
    /// e_n, δ_n and b of every installed bolt, and the energy at the step's start.
    pub fn begin_step(&mut self, disc: &Discretisation, u: &[f64]) {
        let basis = disc.basis;
        let nd = basis.element_dofs();
        let mut start = 0.0;
        for b in self.bolts.iter_mut().filter(|b| b.installed) {
            let [xa, xb] = b.positions(disc, u);
            let d = crate::geometry::sub(xb, xa);
            let len = crate::geometry::norm(d);
            if len > 0.0 {
                b.dir = [d[0] / len, d[1] / len];
            }
            b.delta0 = len - b.length0;
            for (i, sign) in [(0, -1.0), (1, 1.0)] {
                let a = &b.anchors[i];
                let out = &mut b.row[i * nd..(i + 1) * nd];
                basis.directional_row(&disc.elements[a.element], &a.weights, b.dir, out);
                out.iter_mut().for_each(|x| *x *= sign);
            }
            start += b
                .params
                .stored_energy(b.params.response(b.plastic, b.delta0).force);
        }
        // (the bolts installed at this step's start are its `installed` energy until the
        // step is committed: kinematics taken again for the same step count them once)
        self.step = BoltStepEnergy {
            installed: self.pending,
            start: start - self.pending,
            ..Default::default()
        };
    }

    /// Choose each installed bolt's branch at the iterate `du` (the law's own). Returns
    /// how many changed branch.
    pub fn choose_branches(&mut self, du: &[f64]) -> usize {
        let mut changed = 0;
        for b in self.bolts.iter_mut().filter(|b| b.installed) {
            let br = b.params.branch(b.plastic, b.elongation_at(du));
            changed += usize::from(br != b.branch);
            b.branch = br;
        }
        changed
    }

    /// Subtract the bolts' forces N b at `du` from `r`, each on its chosen branch
    /// (`own = false`) or on the law's own (`own = true`: the true residual; returns how
    /// many bolts are on another branch than the chosen one).
    pub fn add_forces(&self, du: &[f64], r: &mut [f64], own: bool) -> usize {
        let mut inconsistent = 0;
        for b in self.bolts.iter().filter(|b| b.installed) {
            let d = b.elongation_at(du);
            let resp = if own {
                let br = b.params.branch(b.plastic, d);
                inconsistent += usize::from(br != b.branch);
                b.params.on_branch(b.plastic, d, br)
            } else {
                b.params.on_branch(b.plastic, d, b.branch)
            };
            if resp.force != 0.0 {
                b.scatter(-resp.force, r);
            }
        }
        inconsistent
    }

    /// The magnitudes |N b| of the bolts' forces at `du` (law's own branch), added
    /// componentwise to `f` (the physical force scale of the convergence test).
    pub fn add_force_magnitudes(&self, du: &[f64], f: &mut [f64]) {
        for b in self.bolts.iter().filter(|b| b.installed) {
            let n = b.params.response(b.plastic, b.elongation_at(du)).force;
            for (&k, &x) in b.dofs.iter().zip(&b.row) {
                if k != NO_DOF {
                    f[k] += (n * x).abs();
                }
            }
        }
    }

    /// y += K_b v with the tangent of the chosen branches: k b (bᵀv) for elastic bolts.
    pub fn apply_tangent(&self, v: &[f64], y: &mut [f64]) {
        for b in self.bolts.iter().filter(|b| b.installed) {
            if b.branch != BoltBranch::Elastic {
                continue;
            }
            let mut s = 0.0;
            for (&k, &x) in b.dofs.iter().zip(&b.row) {
                if k != NO_DOF {
                    s += x * v[k];
                }
            }
            b.scatter(b.params.stiffness * s, y);
        }
    }

    /// values += the bolts' tangent blocks k b bᵀ (elastic bolts), through their element-
    /// pattern slots mapped into the tangent's pattern by `map`.
    pub fn assemble(&self, values: &mut [f64], map: &[u32]) {
        for b in self.bolts.iter().filter(|b| b.installed) {
            if b.branch != BoltBranch::Elastic {
                continue;
            }
            let n = b.dofs.len();
            let k = b.params.stiffness;
            for i in 0..n {
                for j in 0..n {
                    let s = b.slots[i * n + j];
                    if s != u32::MAX {
                        values[map[s as usize] as usize] += k * b.row[i] * b.row[j];
                    }
                }
            }
        }
    }

    /// Commit the converged increment `du`: each installed bolt's return mapping becomes
    /// its state; the step's plastic work and the scheme's share are kept for the energy
    /// balance ([`BoltSet::step_energy`]).
    pub fn commit(&mut self, du: &[f64]) {
        let (mut plastic, mut algorithmic) = (0.0, 0.0);
        for b in self.bolts.iter_mut().filter(|b| b.installed) {
            let d = b.elongation_at(du);
            let r = b.params.response(b.plastic, d);
            plastic += r.force * (r.plastic - b.plastic);
            let de = (d - r.plastic) - (b.delta0 - b.plastic);
            algorithmic += 0.5 * b.params.stiffness * de * de;
            b.plastic = r.plastic;
            b.force = r.force;
            b.elongation = d;
            b.yielded = r.branch.yielding();
        }
        self.step.plastic = plastic;
        self.step.algorithmic = algorithmic;
        self.pending = 0.0;
    }

    /// The energy the bolts exchanged in the last committed step.
    pub fn step_energy(&self) -> BoltStepEnergy {
        self.step
    }

    /// Stored elastic energy ½ N²/k of the installed bolts after the last step.
    pub fn energy(&self) -> f64 {
        self.bolts
            .iter()
            .filter(|b| b.installed)
            .map(|b| b.params.stored_energy(b.force))
            .sum()
    }

    /// The committed state of every bolt (for checkpoints).
    pub fn saved(&self) -> Vec<SavedBolt> {
        self.bolts
            .iter()
            .map(|b| SavedBolt {
                installed: b.installed,
                length0: b.length0,
                plastic: b.plastic,
                force: b.force,
                elongation: b.elongation,
                yielded: b.yielded,
            })
            .collect()
    }

    /// Restore the committed states written by [`BoltSet::saved`] (one per bolt).
    pub fn restore(&mut self, saved: &[SavedBolt]) -> Result<(), String> {
        if saved.len() != self.bolts.len() {
            return Err(format!(
                "{} bolts saved, the model has {}",
                saved.len(),
                self.bolts.len()
            ));
        }
        for (b, s) in self.bolts.iter_mut().zip(saved) {
            b.installed = s.installed;
            b.length0 = s.length0;
            b.plastic = s.plastic;
            b.force = s.force;
            b.elongation = s.elongation;
            b.yielded = s.yielded;
        }
        self.pending = 0.0;
        Ok(())
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use crate::model::parse_model;
    use crate::simulation::Simulation;
    use std::path::Path;

    /// A free unit square (cover `h`, `[cover] order`) with a bolt inside it from (0.2, 0.3)
    /// to (0.8, 0.6) (L = √0.45), k = 1e6 N/m, capacity `fy`.
    fn square(order: usize, fy: f64) -> Simulation {
        let text = format!(
            "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = 1\n\
             [cover]\nsize = 0.3\norder = {order}\n\
             [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = 1e9\npoisson = 0.25\n\
             [[block]]\nname = \"b\"\nmaterial = \"m\"\n\
             vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n\
             [[bolt]]\nname = \"b1\"\npoints = [[0.2, 0.3], [0.8, 0.6]]\nstiffness = 1.0e6\ncapacity = {fy:e}\n"
        );
        Simulation::new(parse_model(&text, Path::new(".")).unwrap()).unwrap()
    }

    /// The displacement vector of the linear field u(x) = A (x − c) (the covers' constant
    /// terms at the nodes, the higher terms zero: exact at both orders).
    fn linear_field(sim: &Simulation, a: [[f64; 2]; 2], c: Vec2) -> Vec<f64> {
        let mut u = vec![0.0; sim.n_dofs()];
        for e in &sim.disc.elements {
            for k in 0..3 {
                if let Some(d) = sim.disc.covers[e.covers[k]].dof {
                    let x = [e.nodes[k][0] - c[0], e.nodes[k][1] - c[1]];
                    u[d] = a[0][0] * x[0] + a[0][1] * x[1];
                    u[d + 1] = a[1][0] * x[0] + a[1][1] * x[1];
                }
            }
        }
        u
    }

    fn rotation(t: f64) -> [[f64; 2]; 2] {
        let (s, c) = t.sin_cos();
        [[c - 1.0, -s], [s, c - 1.0]]
    }

    /// A rigid rotation of 90° in 1° steps: at every step's start the bolt's elongation
    /// from the moved anchors is zero (to round-off), the committed one is the linearised
    /// −L (1 − cos Δθ) (second order in the step's rotation, not carried over), and after
    /// the quarter turn a dilation ε along the turned bolt stretches it by exactly ε L: its
    /// direction followed the rotation.
    #[test]
    fn a_bolt_follows_a_rigid_rotation_of_any_size() {
        for order in [0, 1] {
            let mut sim = square(order, 1.0e9);
            let c = [0.5, 0.5];
            let len = 0.45f64.sqrt();
            let step = 1f64.to_radians();
            let mut bolts = sim.bolts.clone();
            let mut u = vec![0.0; sim.n_dofs()];
            for k in 0..90 {
                bolts.begin_step(&sim.disc, &u);
                let b = &bolts.bolts[0];
                assert!(b.delta0.abs() < 1e-12 * len, "step {k}: δ_n {}", b.delta0);
                let next = linear_field(&sim, rotation(step * (k + 1) as f64), c);
                let du: Vec<f64> = next.iter().zip(&u).map(|(a, b)| a - b).collect();
                bolts.commit(&du);
                let want = -len * (1.0 - step.cos());
                let b = &bolts.bolts[0];
                assert!(
                    (b.elongation - want).abs() < 1e-9 * len,
                    "order {order} step {k}: {} vs {want}",
                    b.elongation
                );
                u = next;
            }
            bolts.begin_step(&sim.disc, &u);
            let d0 = [0.6 / len, 0.3 / len];
            let dir = bolts.bolts[0].dir;
            assert!(
                (dir[0] + d0[1]).abs() < 1e-12 && (dir[1] - d0[0]).abs() < 1e-12,
                "{dir:?}"
            );
            // a dilation ε about c of the turned square: Δu = ε (x − c) on the current
            // positions x − c = R (x₀ − c), a linear field of the initial ones
            let eps = 1.0e-4;
            let r = rotation(90f64.to_radians());
            let a = [
                [eps * (r[0][0] + 1.0), eps * r[0][1]],
                [eps * r[1][0], eps * (r[1][1] + 1.0)],
            ];
            let rotated = linear_field(&sim, a, c);
            bolts.commit(&rotated);
            let b = &bolts.bolts[0];
            assert!(
                (b.elongation - eps * len).abs() < 1e-12 * len,
                "order {order}: {} vs {}",
                b.elongation,
                eps * len
            );
            assert!((b.force - 1.0e6 * eps * len).abs() < 1e-6, "{}", b.force);
            sim.bolts = bolts;
        }
    }

    /// The bolts' force N b and their tangent k_t b bᵀ: the tangent (applied, and
    /// assembled) against central differences of the force on the chosen branch, elastic
    /// and yielding, at both orders.
    #[test]
    fn the_tangent_is_the_derivative_of_the_bolt_forces() {
        for order in [0, 1] {
            for (fy, scale) in [(1.0e9, 1.0e-4), (10.0, 1.0e-3)] {
                let sim = square(order, fy);
                let mut bolts = sim.bolts.clone();
                let n = sim.n_dofs();
                let u = linear_field(&sim, rotation(0.3), [0.5, 0.5]);
                bolts.begin_step(&sim.disc, &u);
                // an increment with a stretch and some noise, and a direction
                let mut du = linear_field(&sim, [[scale, 0.2 * scale], [0.0, scale]], [0.1, 0.0]);
                let v: Vec<f64> = (0..n)
                    .map(|i| ((i * 7919 % 101) as f64 / 101.0 - 0.5) * 1e-3)
                    .collect();
                for (i, d) in du.iter_mut().enumerate() {
                    *d += 1e-6 * scale * ((i * 31 % 17) as f64 - 8.0);
                }
                bolts.choose_branches(&du);
                let yielding = bolts.bolts[0].branch != BoltBranch::Elastic;
                assert_eq!(yielding, fy < 1e3, "order {order}, F_y {fy}");
                let h = 1e-7;
                let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
                let plus: Vec<f64> = du.iter().zip(&v).map(|(a, b)| a + h * b).collect();
                let minus: Vec<f64> = du.iter().zip(&v).map(|(a, b)| a - h * b).collect();
                bolts.add_forces(&plus, &mut rp, false);
                bolts.add_forces(&minus, &mut rm, false);
                let mut kv = vec![0.0; n];
                bolts.apply_tangent(&v, &mut kv);
                // assembled on the bolts' own pattern (map = identity)
                let groups: Vec<Vec<usize>> = bolts.groups().collect();
                let p = crate::solver::SparsePattern::from_groups(
                    n,
                    groups.iter().map(|g| g.as_slice()),
                );
                bolts.bind(&p);
                let mut values = vec![0.0; p.nnz()];
                let map: Vec<u32> = (0..p.nnz() as u32).collect();
                bolts.assemble(&mut values, &map);
                let mut kv2 = vec![0.0; n];
                for col in 0..n {
                    for k in p.col_ptr[col]..p.col_ptr[col + 1] {
                        kv2[p.row_idx[k]] += values[k] * v[col];
                    }
                }
                let kmax = kv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for i in 0..n {
                    // R = −f: −(R(+) − R(−))/2h = K v
                    let fd = -(rp[i] - rm[i]) / (2.0 * h);
                    assert!(
                        (fd - kv[i]).abs() <= 1e-6 * (kmax + 1.0),
                        "order {order}, F_y {fy}, dof {i}: {fd} vs {}",
                        kv[i]
                    );
                    assert!((kv2[i] - kv[i]).abs() <= 1e-9 * (kmax + 1.0));
                }
                if yielding {
                    assert_eq!(kmax, 0.0);
                    // the force on the yield branch is the capacity along the bolt
                    let mut r = vec![0.0; n];
                    bolts.add_forces(&du, &mut r, true);
                    let sum: f64 = r.iter().map(|x| x.abs()).sum();
                    assert!(sum > 0.0);
                } else {
                    assert!(kmax > 0.0);
                }
            }
        }
    }
}
