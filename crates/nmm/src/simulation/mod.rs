//! The step pipeline: the only place that sees everything.
//!
//! One step (from t_n to t_{n+1} = t_n + Δt), as in the method:
//! 1. **predict**: static mode resets the velocity to zero;
//! 2. **detect contacts** on the geometry at t_n ([`ContactSet::detect`]); the
//!    contact kinematics are linear in the step's increment Δu (small displacement per step);
//! 3. **assemble** the step's linear part, once: L = K + (2/Δt²) M + (2/Δt) C + P
//!    (C = αM + βK, Rayleigh damping per material, dynamic mode only; P the constraint
//!    penalties) and F = f_ext(t_{n+1}) − f_int(σ_n) + (2/Δt) M v_n + C v_n + (penalty
//!    targets) (see [`crate::time`] for the derivation);
//! 4. **Newton-Raphson** on R(Δu) = F − L Δu − f_c(Δu): at each iterate the contacts are
//!    return-mapped from their committed state and add their force and consistent tangent;
//! 5. if Newton fails, the step is **cut** (Δt halved) and retried; the next steps then
//!    cover the rest of the interval, so that full steps end on the grid t₀ + kΔt
//!    ([`time::grid_time`]) as in a run without cuts;
//! 6. **commit**: u, v (Newmark β = ½, γ = 1), stresses σ += D B Δu, contact states;
//! 7. **update geometry**: element nodes and polygons move with the material.
//!
//! Outputs are written by [`run`] through `outputs.rs`.

mod outputs;
mod setup;

pub use outputs::{
    blocks_grid, contacts_grid, history_columns, monitor_values, peak_memory_bytes, run,
    run_observed, run_simulation, write_block_table, RunError, RunObserver, RunOptions, RunStatus,
    RunSummary, Silent,
};

use crate::assembly::global::{element_dofs, gather, scatter_matrix, scatter_vector, NO_DOF};
use crate::assembly::local;
use crate::contact::set::ContactSet;
use crate::cover::{discretise_through, Discretisation, MaterialPoint};
use crate::material::{elasticity_matrix, stress as hooke, Mat3};
use crate::model::{Mode, Model, Rayleigh, TimeFunction};
use crate::solver::{
    newton, AutoSolver, NewtonOptions, NonlinearSystem, SparseMatrix, SparsePattern, StageTimes,
};
use crate::time;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A penalty spring tying one displacement component of a material point (or of
/// a piece of edge) to a prescribed value: energy ½ Σ_ij k_ij U_i U_j − ū Σ_i g_i U_i.
#[derive(Debug, Clone)]
pub(crate) struct Penalty {
    /// The constrained component's global unknown for each of the element's covers.
    pub dofs: [usize; 3],
    /// k_ij = p ∫ w_i w_j (edge) or k w_i w_j (point).
    pub k: [f64; 9],
    /// g_i = p ∫ w_i (edge) or k w_i (point).
    pub g: [f64; 3],
    /// Index into `Simulation::functions`.
    pub function: usize,
}

/// Why a step could not be completed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    #[error("step {step} (t = {time:.6} s) did not converge after {cuts} time-step cuts (last residual {residual:.3e}){detail}")]
    NotConverged {
        step: usize,
        time: f64,
        cuts: usize,
        residual: f64,
        detail: String,
    },
}

/// What one completed step reports.
#[derive(Debug, Clone, Default)]
pub struct StepReport {
    /// Newton iterations (linear solves) of the accepted attempt.
    pub iterations: usize,
    /// How many times Δt was halved for this step.
    pub cuts: usize,
    /// Residual norms of the accepted attempt.
    pub residuals: Vec<f64>,
    /// Δt actually used.
    pub dt: f64,
}

/// Cumulative per-stage timings of a run.
#[derive(Debug, Clone, Copy, Default)]
pub struct Timings {
    pub cover: Duration,
    pub stages: StageTimes,
}

pub struct Simulation {
    pub model: Model,
    pub disc: Discretisation,
    /// Completed steps.
    pub step: usize,
    /// Simulated time at the end of the last completed step.
    pub time: f64,
    /// Total displacement per unknown (in the frame of the base).
    pub u: Vec<f64>,
    /// Velocity per unknown.
    pub v: Vec<f64>,
    /// Stress [σ_xx, σ_yy, τ_xy] per element.
    pub stress: Vec<[f64; 3]>,
    pub contacts: ContactSet,
    pub timings: Timings,
    pub(crate) elem_dofs: Vec<[usize; 6]>,
    /// Element areas on the initial geometry: the mass ρ A₀ of an element is conserved
    /// while its area changes with the strain.
    pub(crate) initial_area: Vec<f64>,
    pub(crate) d_mats: Vec<Mat3>,
    pub(crate) f_load: Vec<f64>,
    pub(crate) penalties: Vec<Penalty>,
    pub(crate) functions: Vec<TimeFunction>,
    /// Material point of each point monitor (None for interface monitors).
    pub(crate) monitor_points: Vec<Option<MaterialPoint>>,
    solver: AutoSolver,
    pattern: Option<(Arc<SparsePattern>, Vec<Vec<usize>>)>,
    /// Largest nodal displacement increment of the last step (for the contact search distance).
    last_max_du: f64,
    /// t₀ of the step grid: after k full steps the time is t₀ + kΔt.
    time_origin: f64,
    /// Full steps (intervals of Δt) completed since `time_origin`.
    full_steps: u64,
    /// Time already covered in the current interval by cut steps (0 on the grid).
    partial: f64,
}

impl Simulation {
    /// Discretise a validated model and prepare loads, constraints and monitors.
    pub fn new(model: Model) -> Result<Simulation, String> {
        let t0 = Instant::now();
        let blocks: Vec<_> = model
            .blocks
            .iter()
            .map(|b| (b.vertices.clone(), b.fixed))
            .collect();
        let disc = discretise_through(&blocks, model.cover_size, model.cover_origin)
            .map_err(|e| e.to_string())?;
        let cover_time = t0.elapsed();
        let n = disc.n_dofs;
        let elem_dofs = disc
            .elements
            .iter()
            .map(|e| element_dofs(&disc, e))
            .collect();
        let d_mats = model
            .materials
            .iter()
            .map(|m| elasticity_matrix(m.young, m.poisson, m.plane))
            .collect();
        let n_el = disc.elements.len();
        let initial_area = disc
            .elements
            .iter()
            .map(|e| crate::geometry::moments::polygon_area(&e.polygon))
            .collect();
        let mut sim = Simulation {
            contacts: ContactSet::default(),
            step: 0,
            time: 0.0,
            u: vec![0.0; n],
            v: vec![0.0; n],
            stress: vec![[0.0; 3]; n_el],
            timings: Timings {
                cover: cover_time,
                ..Default::default()
            },
            elem_dofs,
            initial_area,
            d_mats,
            f_load: vec![0.0; n],
            penalties: Vec::new(),
            functions: Vec::new(),
            monitor_points: Vec::new(),
            solver: AutoSolver::default(),
            pattern: None,
            last_max_du: 0.0,
            time_origin: 0.0,
            full_steps: 0,
            partial: 0.0,
            disc,
            model,
        };
        setup::loads(&mut sim)?;
        setup::constraints(&mut sim)?;
        setup::monitors(&mut sim)?;
        Ok(sim)
    }

    pub fn n_dofs(&self) -> usize {
        self.disc.n_dofs
    }

    /// Unknowns of each block (0 for a fixed block).
    pub fn unknowns_per_block(&self) -> Vec<usize> {
        let mut n = vec![0; self.model.blocks.len()];
        for c in &self.disc.covers {
            if c.dof.is_some() {
                n[c.block] += crate::cover::COVER_DOFS;
            }
        }
        n
    }

    /// The model's warnings ([`crate::model::warnings`]) and those about its cover
    /// ([`crate::model::warnings::cover_warnings`]), one line each.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = crate::model::warnings(&self.model);
        w.extend(crate::model::warnings::cover_warnings(
            &self.model,
            &self.unknowns_per_block(),
        ));
        w
    }

    /// End time of the analysis.
    pub fn end_time(&self) -> f64 {
        let a = &self.model.analysis;
        time::grid_time(self.time_origin, a.steps as u64, a.dt)
    }

    /// Whether the analysis has reached its end time (completed all its full steps).
    pub fn finished(&self) -> bool {
        self.full_steps >= self.model.analysis.steps as u64
    }

    fn material_of_element(&self, e: usize) -> usize {
        self.model.blocks[self.disc.elements[e].block].material
    }

    /// Advance one step, cutting Δt on non-convergence. The step covers the rest of the
    /// current interval of Δt (all of it unless an earlier step was cut).
    pub fn advance(&mut self) -> Result<StepReport, StepError> {
        let mut dt = self.model.analysis.dt - self.partial;
        let mut last = (f64::NAN, String::new());
        for cuts in 0..=self.model.analysis.max_step_cuts {
            match self.attempt(dt) {
                Ok(mut rep) => {
                    rep.cuts = cuts;
                    return Ok(rep);
                }
                Err(e) => last = e,
            }
            dt *= 0.5;
        }
        Err(StepError::NotConverged {
            step: self.step + 1,
            time: self.time,
            cuts: self.model.analysis.max_step_cuts,
            residual: last.0,
            detail: last.1,
        })
    }

    /// One attempt at a step of size dt; the state is changed only on success.
    fn attempt(&mut self, dt: f64) -> Result<StepReport, (f64, String)> {
        let a = self.model.analysis.clone();
        let n = self.n_dofs();
        let t1 = self.time + dt;
        // 1. predict
        let v_n: Vec<f64> = match a.mode {
            Mode::Static => vec![0.0; n],
            Mode::Dynamic => self.v.clone(),
        };
        // 2. detect contacts on the geometry at t_n
        let tc = Instant::now();
        let search = self.search_distance();
        self.contacts
            .detect(&self.disc, &self.model, &self.u, search);
        self.timings.stages.contact += tc.elapsed();
        // 3. assemble the linear part
        let ta = Instant::now();
        let pattern = self.pattern_for_step();
        let mut l = SparseMatrix::zeros(pattern.clone());
        let mut f = vec![0.0; n];
        self.assemble_linear(dt, t1, &v_n, &mut l, &mut f);
        self.timings.stages.assembly += ta.elapsed();
        // 4. Newton
        let mut du = vec![0.0; n];
        let mut jac = SparseMatrix::zeros(pattern);
        let reference = norm(&f).max(self.force_scale());
        let mut sys = StepSystem {
            l: &l,
            f: &f,
            contacts: &mut self.contacts,
            reference,
            changed: true,
            first: true,
        };
        let opts = NewtonOptions {
            max_iterations: a.max_iterations,
            tolerance: a.tolerance,
        };
        let rep = newton(&mut sys, &mut jac, &mut self.solver, &mut du, opts);
        self.timings.stages += rep.times;
        if !rep.converged {
            let last = rep.residuals.last().copied().unwrap_or(f64::NAN);
            let tail: Vec<String> = rep
                .residuals
                .iter()
                .rev()
                .take(4)
                .rev()
                .map(|r| format!("{r:.2e}"))
                .collect();
            let detail = match &rep.error {
                Some(e) => format!(": {e}"),
                None => format!(" (residuals ... {})", tail.join(", ")),
            };
            return Err((last, detail));
        }
        // 6. commit
        self.commit(&du, &v_n, dt);
        Ok(StepReport {
            iterations: rep.iterations,
            cuts: 0,
            residuals: rep.residuals,
            dt,
        })
    }

    /// The linear part of the next step's system (L, F) on the current state, with
    /// the sparsity pattern of the current contact set: for benchmarks and tests.
    pub fn linear_system(&mut self) -> (SparseMatrix, Vec<f64>) {
        let dt = self.model.analysis.dt;
        let v_n = match self.model.analysis.mode {
            Mode::Static => vec![0.0; self.n_dofs()],
            Mode::Dynamic => self.v.clone(),
        };
        let pattern = self.pattern_for_step();
        let mut l = SparseMatrix::zeros(pattern);
        let mut f = vec![0.0; self.n_dofs()];
        self.assemble_linear(dt, self.time + dt, &v_n, &mut l, &mut f);
        (l, f)
    }

    /// Contact search distance: three times the largest displacement of the last
    /// step, and at least 2% of the mesh size.
    fn search_distance(&self) -> f64 {
        (3.0 * self.last_max_du).max(0.02 * self.model.cover_size)
    }

    /// A force scale for the relative residual test when the step's load vanishes:
    /// the largest element stiffness times 1e-9 of the model size.
    fn force_scale(&self) -> f64 {
        let e = self
            .model
            .materials
            .iter()
            .map(|m| m.young)
            .fold(0.0, f64::max);
        e * 1e-12 * self.model.cover_size
    }

    /// The sparsity pattern of this step: elements, penalties and contacts. Reused
    /// (with its symbolic factorisation) while the contact couplings are unchanged.
    fn pattern_for_step(&mut self) -> Arc<SparsePattern> {
        let contact_groups = self.contacts.dof_groups();
        if let Some((p, g)) = &self.pattern {
            if *g == contact_groups {
                return p.clone();
            }
        }
        let mut groups: Vec<Vec<usize>> =
            Vec::with_capacity(self.elem_dofs.len() + self.penalties.len() + contact_groups.len());
        for d in &self.elem_dofs {
            groups.push(d.iter().copied().filter(|&x| x != NO_DOF).collect());
        }
        for p in &self.penalties {
            groups.push(p.dofs.iter().copied().filter(|&x| x != NO_DOF).collect());
        }
        groups.extend(contact_groups.iter().cloned());
        let p = Arc::new(crate::assembly::global::pattern(self.n_dofs(), &groups));
        self.pattern = Some((p.clone(), contact_groups));
        p
    }

    /// L = K + (2/Δt²) M + (2/Δt) C + P and
    /// F = f_ext(t1) − f_int(σ_n) + (2/Δt) M v_n + C v_n + P-targets − P u_n.
    fn assemble_linear(&self, dt: f64, t1: f64, v_n: &[f64], l: &mut SparseMatrix, f: &mut [f64]) {
        let cm = time::mass_coefficient(dt);
        let cv = time::velocity_coefficient(dt);
        let cd = time::damping_coefficient(dt);
        let a_base = self
            .model
            .base_motion
            .as_ref()
            .map(|b| b.accel(t1))
            .unwrap_or([0.0, 0.0]);
        let g = self.model.analysis.gravity;
        // body acceleration in the frame of the base: gravity − a_base
        let b = [g[0] - a_base[0], g[1] - a_base[1]];
        for (ei, e) in self.disc.elements.iter().enumerate() {
            let dofs = &self.elem_dofs[ei];
            if dofs.iter().all(|&d| d == NO_DOF) {
                continue;
            }
            let mat = self.material_of_element(ei);
            let it = local::element_integrals(e);
            // conserved mass: the current density is ρ₀ A₀ / A
            let rho = self.model.materials[mat].density * self.initial_area[ei] / it.area;
            let mut k = local::stiffness(it.area, &it.grads, &self.d_mats[mat]);
            let m = local::mass(rho, &it.int_ww, 1.0);
            // Rayleigh damping C = αM + βK: (2/Δt) C on the matrix, C v_n on the right
            let damping = match self.model.analysis.mode {
                Mode::Dynamic => self.model.materials[mat].damping,
                Mode::Static => Rayleigh::default(),
            };
            let mut fe = local::body_force(rho, &it.int_w, b);
            let fi = local::internal_force(it.area, &it.grads, &self.stress[ei]);
            let ve: [f64; 6] = gather(v_n, dofs);
            for r in 0..6 {
                let mv: f64 = (0..6).map(|c| m[r * 6 + c] * ve[c]).sum();
                let kv: f64 = (0..6).map(|c| k[r * 6 + c] * ve[c]).sum();
                fe[r] += (cv + damping.alpha) * mv + damping.beta * kv - fi[r];
            }
            let (ck, cmass) = (1.0 + cd * damping.beta, cm + cd * damping.alpha);
            for (kv, mv) in k.iter_mut().zip(&m) {
                *kv = ck * *kv + cmass * mv;
            }
            scatter_matrix(l, dofs, &k);
            scatter_vector(f, dofs, &fe);
        }
        for (fi, li) in f.iter_mut().zip(&self.f_load) {
            *fi += li;
        }
        for p in &self.penalties {
            scatter_matrix(l, &p.dofs, &p.k);
            let target = self.functions[p.function].eval(t1);
            let ue: [f64; 3] = gather(&self.u, &p.dofs);
            let fp: [f64; 3] = std::array::from_fn(|i| {
                target * p.g[i] - (0..3).map(|j| p.k[i * 3 + j] * ue[j]).sum::<f64>()
            });
            scatter_vector(f, &p.dofs, &fp);
        }
    }

    /// Commit a converged increment: kinematics, stresses, contacts, geometry.
    fn commit(&mut self, du: &[f64], v_n: &[f64], dt: f64) {
        for i in 0..du.len() {
            self.u[i] += du[i];
            self.v[i] = time::velocity_update(du[i], v_n[i], dt);
        }
        self.contacts.commit(du);
        let mut max_du = 0.0f64;
        for (ei, e) in self.disc.elements.iter_mut().enumerate() {
            let dofs = &self.elem_dofs[ei];
            let ue: [f64; 6] = gather(du, dofs);
            if ue.iter().all(|&x| x == 0.0) {
                continue;
            }
            let mat = self.model.blocks[e.block].material;
            let g = e.weight_gradients();
            let ds = hooke(&self.d_mats[mat], local::strain(&g, &ue));
            let s = &mut self.stress[ei];
            for k in 0..3 {
                s[k] += ds[k];
            }
            // geometry: polygon vertices move by Σ w_k Δu_k (weights on the old triangle), then the nodes
            for x in e.polygon.iter_mut() {
                let w = crate::cover::barycentric(&e.nodes, *x);
                x[0] += w[0] * ue[0] + w[1] * ue[2] + w[2] * ue[4];
                x[1] += w[0] * ue[1] + w[1] * ue[3] + w[2] * ue[5];
            }
            for k in 0..3 {
                e.nodes[k][0] += ue[2 * k];
                e.nodes[k][1] += ue[2 * k + 1];
                max_du = max_du.max(ue[2 * k].hypot(ue[2 * k + 1]));
            }
        }
        self.last_max_du = max_du;
        self.advance_clock(dt);
        self.step += 1;
    }

    /// The clock after a committed step of `dt`: a step that covered the rest of its
    /// interval ends on the grid, t = t₀ + kΔt; a cut one ends at t₀ + kΔt + (time covered).
    fn advance_clock(&mut self, dt: f64) {
        let step = self.model.analysis.dt;
        // `dt` is the remainder itself (same expression as in `advance`) or a half of it
        if dt >= step - self.partial {
            self.full_steps += 1;
            self.partial = 0.0;
        } else {
            self.partial += dt;
        }
        self.time = time::grid_time(self.time_origin, self.full_steps, step) + self.partial;
    }

    /// Displacement (in the frame of the base) at a material point.
    pub fn displacement_at(&self, p: &MaterialPoint) -> [f64; 2] {
        self.disc.displacement_at(p, &self.u)
    }

    /// Velocity at a material point.
    pub fn velocity_at(&self, p: &MaterialPoint) -> [f64; 2] {
        self.disc.displacement_at(p, &self.v)
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// The step's nonlinear system for Newton: R(Δu) = F − L Δu − f_c(Δu).
struct StepSystem<'a> {
    l: &'a SparseMatrix,
    f: &'a [f64],
    contacts: &'a mut ContactSet,
    reference: f64,
    changed: bool,
    /// No evaluation yet: the next one (at Δu = 0) is the closed-contact predictor,
    /// see `ContactSet::evaluate`.
    first: bool,
}

impl NonlinearSystem for StepSystem<'_> {
    fn evaluate(
        &mut self,
        x: &[f64],
        r: &mut [f64],
        j: &mut SparseMatrix,
        times: &mut StageTimes,
    ) -> bool {
        j.values.copy_from_slice(&self.l.values);
        self.l.mul_vec(x, r);
        for (ri, fi) in r.iter_mut().zip(self.f) {
            *ri = fi - *ri;
        }
        let t = Instant::now();
        let predictor = std::mem::replace(&mut self.first, false);
        let (symmetric, changed) = self.contacts.evaluate(x, r, j, predictor);
        times.contact += t.elapsed();
        self.changed = changed;
        symmetric
    }
    fn reference_norm(&self) -> f64 {
        self.reference
    }
    fn active_set_changed(&self) -> bool {
        self.changed
    }
}
