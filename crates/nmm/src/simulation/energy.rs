//! The energy balance of a run: the stored energy, the work done on the system and each
//! dissipation, from its own formula, step by step (see [`Energy`]).

use super::{step, Simulation};
use crate::assembly::global::{gather_into, NO_DOF};
use crate::cover::basis::CoverBasis;
use crate::model::Mode;

/// The energy of the whole system (J per metre of thickness) after a step, the work done on
/// it and the energy it dissipated so far.
///
/// Stored: kinetic ½ vᵀMv + elastic ½ Σ A σᵀD⁻¹σ + gravity potential (−work of gravity
/// since the start) + contact springs ½ Σ (t_N²/p_N + t_S²/p_S) + penalty springs (ghost
/// ties and constraints about their targets) + rock bolts ½ Σ N²/k = `total`.
/// `external_work` is the work of the loads and of the base motion's inertial forces (and
/// a bolt's pretension ½ N₀²/k at its installation); `constraint_work` that of the
/// prescribed (moving) constraints.
///
/// Dissipated, summed over the steps, each from its own formula:
/// * `friction`: Σ t_S Δγ over the contacts (force on the Coulomb limit × plastic slip);
/// * `damping`: Δuᵀ C v_{n+1} (Rayleigh damping, dynamic mode);
/// * `algorithmic`: what the implicit scheme dissipates by taking the forces at the step's
///   end. The scheme (β = ½, γ = 1) gives Δu = Δt (v_n + v_{n+1})/2, so the inertia force
///   does exactly the work ΔT; the elastic force f(σ_n) + KΔu does ΔU + ½ ΔuᵀKΔu, the
///   penalty springs ½ ΔuᵀPΔu more than they store, and each contact its own excess
///   ([`crate::contact::set::StepDissipation`]). These are summed;
/// * `static_reset` (static mode): Δuᵀ R(Δu), the work of the forces still out of balance
///   at the step's end (R: the static residual), which the reset of the velocity to zero
///   discards; zero, to the tolerance, for a step that reached equilibrium;
/// * `contact_update`: what the contact springs lose when the contacts are detected anew on
///   the moved geometry at each step's start (new gaps and tributary lengths): their energy
///   at the end of a step minus their energy at the start of the next (and the bolts'
///   the same, on their kinematics taken anew: [`crate::bolt`]);
/// * `bolt_plastic`: Σ N Δp over the bolts (force at the capacity × plastic elongation).
///
/// Balance: total + dissipated = initial + external work + constraint work, up to the Newton
/// tolerance and the stresses carried onto the moved elements: `balance_error`. Without external work the total can only fall:
/// `max_rise` = max over the steps of total − external work − initial total.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energy {
    pub kinetic: f64,
    pub elastic: f64,
    pub gravity: f64,
    pub contact: f64,
    pub penalty: f64,
    /// rock bolts: ½ Σ N²/k
    pub bolts: f64,
    pub external_work: f64,
    /// total at the start of the run
    pub initial: f64,
    /// largest total so far
    pub max: f64,
    /// the largest |component| seen (a scale for the rise)
    pub scale: f64,
    /// work of the prescribed (moving) constraints so far: Σ Δū ∂E/∂ū, each penalty
    /// spring's pull on its moving target at the step's end times the target's move
    pub constraint_work: f64,
    /// dissipated by friction so far
    pub friction: f64,
    /// dissipated by damping so far
    pub damping: f64,
    /// dissipated by the time integration so far
    pub algorithmic: f64,
    /// static mode: the work of the forces out of balance at each step's end, which the
    /// reset of the velocity discards (zero for steps in equilibrium)
    pub static_reset: f64,
    /// what the contact springs lost when the contacts were detected anew at each step's
    /// start (their energy at the end of a step − at the start of the next)
    pub contact_update: f64,
    /// the largest energy flow seen: |external work|, |gravity potential|, dissipated (a
    /// scale for the balance error)
    pub flow: f64,
    /// dissipated by the bolts' plastic elongation so far: Σ N Δp
    pub bolt_plastic: f64,
    /// the elastic and kinetic energy the excavated blocks had when they were removed
    pub excavated: f64,
}

impl Energy {
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.gravity + self.contact + self.penalty + self.bolts
    }
    /// The components (without the bolts') and the external work, in the order of the
    /// fields.
    pub fn components(&self) -> [f64; 6] {
        [
            self.kinetic,
            self.elastic,
            self.gravity,
            self.contact,
            self.penalty,
            self.external_work,
        ]
    }
    /// The largest rise of the total above its start, net of the external work.
    pub fn max_rise(&self) -> f64 {
        self.max - self.initial
    }
    /// Dissipated so far: friction + damping + algorithmic + static reset + contact update
    /// + the bolts' plastic work + what excavated blocks took with them.
    pub fn dissipated(&self) -> f64 {
        self.friction
            + self.damping
            + self.algorithmic
            + self.static_reset
            + self.contact_update
            + self.bolt_plastic
            + self.excavated
    }
    /// total + dissipated − initial − external work: zero when the balance closes.
    pub fn balance_error(&self) -> f64 {
        self.total() + self.dissipated() - self.initial - self.external_work - self.constraint_work
    }
    /// [`Energy::balance_error`] relative to the largest energy flow of the run.
    pub fn balance_error_relative(&self) -> f64 {
        if self.flow > 0.0 {
            self.balance_error() / self.flow
        } else {
            0.0
        }
    }
}

impl Simulation {
    /// The energy balance after a committed step of `du` over `dt` (see [`Energy`]).
    pub(super) fn update_energy(&mut self, du: &[f64], v_n: &[f64], dt: f64, out_of_balance: f64) {
        let t1 = self.time + dt;
        let lp = &self.linear;
        let g = self.model.analysis.gravity;
        let a_base = self.base_acceleration(t1);
        // work of gravity and of the base's inertial force over the step (body forces of the
        // step's geometry), and of the loads
        let (mut w_grav, mut w_ext) = (0.0, 0.0);
        let nd = self.elem_dofs.stride();
        let rl = self.disc.basis.record_len();
        for (ei, dofs) in self.elem_dofs.iter().enumerate() {
            if dofs.iter().all(|&d| d == NO_DOF) {
                continue;
            }
            let body = &lp.records[ei * rl + 2 * nd * nd..ei * rl + 2 * nd * nd + nd / 2];
            for r in 0..nd {
                if dofs[r] != NO_DOF {
                    let x = du[dofs[r]] * body[r / 2];
                    w_grav += x * g[r % 2];
                    w_ext -= x * a_base[r % 2];
                }
            }
        }
        w_ext += self.f_load.iter().zip(du).map(|(f, d)| f * d).sum::<f64>();
        let mut mv = vec![0.0; self.v.len()];
        step::sym_mul_on(&self.threads, lp.tangent.element(), &lp.m, &self.v, &mut mv);
        let kinetic = 0.5 * mv.iter().zip(&self.v).map(|(a, b)| a * b).sum::<f64>();
        let initial_kinetic = if self.step == 0 {
            step::sym_mul_on(&self.threads, lp.tangent.element(), &lp.m, v_n, &mut mv);
            0.5 * mv.iter().zip(v_n).map(|(a, b)| a * b).sum::<f64>()
        } else {
            0.0
        };
        let elastic: f64 = match self.disc.basis {
            CoverBasis::Constant => self
                .disc
                .elements
                .iter()
                .zip(&self.stress)
                .map(|(e, s)| {
                    let mat = self.model.blocks[e.block].material;
                    crate::geometry::moments::polygon_area(&e.polygon)
                        * crate::material::stress_energy_density(&self.d_mats[mat], *s)
                })
                .sum(),
            _ => self
                .disc
                .elements
                .iter()
                .zip(self.stress_nodes.chunks_exact(3))
                .map(|(e, s)| {
                    if s.iter().all(|x| *x == [0.0; 3]) {
                        return 0.0;
                    }
                    let mat = self.model.blocks[e.block].material;
                    let ww = crate::assembly::quadratic::weight_products(e);
                    let mut en = 0.0;
                    for m in 0..3 {
                        for n in 0..3 {
                            en += ww[m][n]
                                * crate::material::stress_energy_product(
                                    &self.d_mats[mat],
                                    s[m],
                                    s[n],
                                );
                        }
                    }
                    en
                })
                .sum(),
        };
        // the penalty springs' energy; the work their moving targets did over the step,
        // Δū ∂E/∂ū at the step's end (the force the spring pulls its target with, taken at
        // the end like every force of the step); and the scheme's share of a moving target,
        // −Δū gᵀΔu + ½ Δū² Σk (with ½ ΔuᵀkΔu, added below: ½ [Δu, Δū]ᵀ H [Δu, Δū] ≥ 0 for the
        // energy's Hessian H)
        let (mut penalty, mut w_constraints, mut moving) = (0.0, 0.0, 0.0);
        let (mut ue, mut due) = (Vec::new(), Vec::new());
        for p in &self.penalties {
            let f = &self.functions[p.function];
            let (target0, target1) = (f.eval(self.time), f.eval(t1));
            penalty += p.energy(&self.u, target1);
            let dt_target = target1 - target0;
            if dt_target != 0.0 {
                let n = p.dofs.len();
                ue.resize(n, 0.0);
                due.resize(n, 0.0);
                gather_into(&self.u, &p.dofs, &mut ue);
                gather_into(du, &p.dofs, &mut due);
                let ksum: f64 = p.k.iter().sum();
                let gu: f64 = (0..n).map(|i| p.g[i] * ue[i]).sum();
                let gdu: f64 = (0..n).map(|i| p.g[i] * due[i]).sum();
                w_constraints += dt_target * (target1 * ksum - gu);
                moving += -dt_target * gdu + 0.5 * dt_target * dt_target * ksum;
            }
        }
        for gh in &self.ghosts {
            let n = gh.dofs.len();
            ue.resize(n, 0.0);
            gather_into(&self.u, &gh.dofs, &mut ue);
            for i in 0..n {
                for j in 0..n {
                    penalty += 0.5 * gh.k[i * n + j] * ue[i] * ue[j];
                }
            }
        }
        // dissipation of the step: damping Δuᵀ C v_{n+1}; the scheme's ½ Δuᵀ (K + P) Δu of
        // the elements and penalty springs, and the contacts' own (see [`Energy`])
        let mut y = vec![0.0; du.len()];
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut damping = 0.0;
        if !lp.c.is_empty() && self.model.analysis.mode == Mode::Dynamic {
            step::sym_mul_on(&self.threads, lp.tangent.element(), &lp.c, &self.v, &mut y);
            damping = dot(du, &y);
        }
        step::sym_mul_on(&self.threads, lp.tangent.element(), &lp.k, du, &mut y);
        let mut algorithmic = 0.5 * dot(du, &y) + moving;
        step::sym_mul_on(&self.threads, lp.tangent.element(), &lp.p, du, &mut y);
        algorithmic += 0.5 * dot(du, &y);
        let contacts = self.contacts.step_dissipation();
        algorithmic += contacts.algorithmic;
        let first = self.step == 0;
        // the contact springs' energy at this step's start, on the contacts detected anew
        // on the moved geometry, against what the last step left in them
        let redetection = self.energy.contact - contacts.start_energy;
        let e = &mut self.energy;
        e.gravity -= w_grav;
        e.external_work += w_ext;
        e.constraint_work += w_constraints;
        e.friction += contacts.friction;
        e.damping += damping + contacts.damping;
        e.algorithmic += algorithmic;
        e.static_reset += out_of_balance;
        e.contact_update += redetection;
        e.flow = e
            .flow
            .max(e.external_work.abs())
            .max(e.constraint_work.abs())
            .max(e.gravity.abs())
            .max(e.dissipated().abs());
        e.kinetic = kinetic;
        e.elastic = elastic;
        e.contact = self.contacts.spring_energy();
        e.penalty = penalty;
        if !self.bolts.is_empty() {
            // the bolts: stored ½N²/k, plastic work, the scheme's share, the pretension of
            // those installed at the step's start (work done on the system) and the
            // change of their energy between the last step's end and this one's start
            let b = self.bolts.step_energy();
            e.external_work += b.installed;
            e.bolt_plastic += b.plastic;
            e.algorithmic += b.algorithmic;
            e.contact_update += e.bolts - b.start;
            e.bolts = self.bolts.energy();
            e.flow = e.flow.max(e.external_work.abs()).max(e.dissipated().abs());
        }
        if first {
            // the state before the first step: unstressed (or at the in-situ stress), no
            // springs stretched, moving only if a velocity was set (½ v₀ᵀMv₀)
            e.initial = initial_kinetic + self.insitu.initial_elastic;
            e.max = e.initial;
        }
        let net = e.total() - e.external_work;
        e.max = e.max.max(net);
        for c in e.components() {
            e.scale = e.scale.max(c.abs());
        }
        e.scale = e.scale.max(e.bolts.abs());
    }
}
