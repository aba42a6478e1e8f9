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
//! Outputs are written by [`run`] (`run.rs`, the driver) through `writers.rs`.

mod bolt_frames;
pub mod checkpoint;
mod energy;
mod insitu;
pub mod memory;
mod run;
mod setup;
mod stages;
mod static_step;
mod tips;
mod writers;

pub use bolt_frames::bolts_grid;
pub use energy::Energy;
pub use static_step::{STATIC_MAX_MOTION, STATIC_OUTER_ITERATIONS};

pub use run::{
    branch_start, checkpoint_name, latest_checkpoint, peak_memory_bytes, resume_start, run,
    run_observed, run_simulation, with_friction, RunError, RunObserver, RunOptions, RunStatus,
    RunSummary, Silent, Start,
};
pub use writers::{
    blocks_grid, contacts_grid, history_columns, history_header, monitor_values, write_block_table,
    HISTORY_COUNTS,
};

mod step;

use crate::assembly::global::{gather_into, NO_DOF};
use crate::contact::set::ContactSet;
use crate::cover::basis::{CoverBasis, ElementDofTable, MAX_ELEMENT_DOFS};
use crate::cover::{Discretisation, MaterialPoint};
use crate::material::{elasticity_matrix, stress as hooke, Mat3};
use crate::model::{Mode, Model, TimeFunction};
use crate::solver::{
    solve_piecewise, LinearSolver, LinearStats, NewtonOptions, Regularisation, SparseMatrix,
    SparsePattern, StageTimes, TangentSolver, MAX_REJECTIONS,
};
use crate::time;
use std::sync::Arc;
use std::time::{Duration, Instant};
use step::{StepSystem, TangentPattern};

/// A penalty spring tying one displacement component of a material point (or of
/// a piece of edge) to a prescribed value: energy ½ Σ_ij k_ij U_i U_j − ū Σ_i g_i U_i over
/// the constrained component's unknowns of the element's shape functions (n of them: 3 at
/// order 0, 9 at order 1).
#[derive(Debug, Clone)]
pub(crate) struct Penalty {
    /// The constrained component's global unknown of each of the element's shape functions.
    pub dofs: Vec<usize>,
    /// k_ij = p ∫ N_i N_j (edge) or k N_i N_j (point), n × n row-major.
    pub k: Vec<f64>,
    /// g_i = p ∫ N_i (edge) or k N_i (point).
    pub g: Vec<f64>,
    /// Index into `Simulation::functions`.
    pub function: usize,
}

impl Penalty {
    /// Its energy ½ Σ_ij k_ij (U_i U_j + ū²) − ū Σ_i g_i U_i at the displacement `u` and the
    /// prescribed value `target` (zero when the point sits on its target).
    fn energy(&self, u: &[f64], target: f64) -> f64 {
        let n = self.dofs.len();
        let mut ue = [0.0; crate::cover::basis::MAX_ELEMENT_SHAPES];
        gather_into(u, &self.dofs, &mut ue[..n]);
        let mut e = 0.0;
        for i in 0..n {
            for j in 0..n {
                e += 0.5 * self.k[i * n + j] * (ue[i] * ue[j] + target * target);
            }
            e -= target * self.g[i] * ue[i];
        }
        e
    }
}

/// A ghost tie of a tiny cover to the extrapolation of a neighbouring element
/// ([`crate::cover::stabilise`]): energy ½ Uᵀ k U over its unknowns (u_x and u_y of each
/// term: the cover's constant term and the root's three covers', 8, at order 0; at order 1
/// one tie of the constant term and the root element's 9 shapes, 20, and one of each higher
/// term and the root covers' same term, 8).
#[derive(Debug, Clone)]
pub(crate) struct Ghost {
    pub dofs: Vec<usize>,
    pub k: Vec<f64>,
}

impl Ghost {
    /// The ties of one tiny cover (one at order 0, three at order 1).
    fn ties(
        disc: &Discretisation,
        tie: &crate::cover::stabilise::GhostTie,
        stiffness: f64,
    ) -> Vec<Ghost> {
        let x_dof = |c: usize, term: usize| match (term, disc.covers[c].dof) {
            (_, None) => NO_DOF,
            (0, Some(d)) => d,
            (t, Some(_)) => disc.covers[c].terms.get(t - 1).copied().unwrap_or(NO_DOF),
        };
        // each term: u_c,term − its linear extrapolation Σ λ_j u_{r_j},term …
        let mut out: Vec<Ghost> = (0..disc.basis.terms())
            .map(|t| {
                let mut xdofs = vec![x_dof(tie.cover, t)];
                let mut a = vec![1.0];
                for j in 0..3 {
                    xdofs.push(x_dof(tie.roots[j], t));
                    a.push(-tie.lambda[j]);
                }
                Ghost::of_terms(&xdofs, &a, stiffness)
            })
            .collect();
        // … but at order 1 the constant term (the node's displacement) follows the root's
        // field: exact for every quadratic field
        if disc.basis != CoverBasis::Constant {
            let basis = disc.basis;
            let el = &disc.elements[tie.root];
            let mut d = [NO_DOF; MAX_ELEMENT_DOFS];
            basis.element_dofs_into(disc, el, &mut d);
            let mut n = [0.0; crate::cover::basis::MAX_ELEMENT_SHAPES];
            basis.shapes(el, &tie.lambda, &mut n);
            let mut xdofs = vec![x_dof(tie.cover, 0)];
            let mut a = vec![1.0];
            for s in 0..basis.element_shapes() {
                xdofs.push(d[2 * s]);
                a.push(-n[s]);
            }
            out[0] = Ghost::of_terms(&xdofs, &a, stiffness);
        }
        out
    }

    /// The tie ½ k |Σ_i a_i u_i|² (both components) over the terms whose x unknowns are
    /// `xdofs` (y: the next).
    fn of_terms(xdofs: &[usize], a: &[f64], stiffness: f64) -> Ghost {
        let m = xdofs.len();
        let mut dofs = vec![NO_DOF; 2 * m];
        let mut k = vec![0.0; 4 * m * m];
        for (i, &d) in xdofs.iter().enumerate() {
            if d != NO_DOF {
                dofs[2 * i] = d;
                dofs[2 * i + 1] = d + 1;
            }
        }
        for i in 0..m {
            for j in 0..m {
                for comp in 0..2 {
                    k[(2 * i + comp) * 2 * m + 2 * j + comp] = stiffness * a[i] * a[j];
                }
            }
        }
        Ghost { dofs, k }
    }
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
    #[error("step {step} (t = {time:.6} s): out of memory ({what})")]
    OutOfMemory {
        step: usize,
        time: f64,
        what: String,
    },
}

/// What one completed step reports.
#[derive(Debug, Clone, Default)]
pub struct StepReport {
    /// Linear solves of the accepted attempt.
    pub iterations: usize,
    /// Linear solves of every attempt, failed ones included.
    pub solves: usize,
    /// How many times Δt was halved for this step.
    pub cuts: usize,
    /// Residual norms of the accepted attempt.
    pub residuals: Vec<f64>,
    /// Δt actually used.
    pub dt: f64,
    /// Branch changes of the contacts over the iterations of the accepted attempt.
    pub active_set_changes: usize,
    /// Contacts in the step.
    pub contacts: usize,
    /// Static mode: the step ended in equilibrium (always true in dynamic mode).
    pub equilibrium: bool,
    pub linear: LinearStats,
}

/// Cumulative per-stage timings of a run.
#[derive(Debug, Clone, Copy, Default)]
pub struct Timings {
    pub cover: Duration,
    pub stages: StageTimes,
}

/// The step's linear part on the element pattern, assembled through precomputed slots.
#[derive(Debug, Clone)]
struct LinearParts {
    /// Elements and penalties: the tangent pattern cache around the element pattern.
    tangent: TangentPattern,
    /// Slots of each element's n² entries (row-major, n = the basis's unknowns per element,
    /// element after element), `u32::MAX` for missing dofs.
    element_slots: Vec<u32>,
    penalty_slots: Vec<Vec<u32>>,
    ghost_slots: Vec<Vec<u32>>,
    /// Stiffness, mass and penalty values of the current step.
    k: Vec<f64>,
    m: Vec<f64>,
    p: Vec<f64>,
    /// Rayleigh damping C = αM + βK (per material; dynamic mode only), or empty.
    c: Vec<f64>,
    /// Each element's local record of the step ([`CoverBasis::element_local`]: stiffness,
    /// mass, body-force integrals ρ ∫ N_a, internal force of σ_n), element after element.
    records: Vec<f64>,
    /// The geometry step these parts were assembled for.
    step: Option<usize>,
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
    /// Stress [σ_xx, σ_yy, τ_xy] per element (order 1: at the centroid of its current
    /// polygon).
    pub stress: Vec<[f64; 3]>,
    /// Order 1: the stress of each element at its triangle's three nodes, element after
    /// element (the stress is linear in the weights); empty at order 0.
    pub stress_nodes: Vec<[f64; 3]>,
    pub contacts: ContactSet,
    /// The rock bolts ([`crate::bolt`]).
    pub bolts: crate::bolt::BoltSet,
    pub timings: Timings,
    /// The energy balance after the last step.
    pub energy: Energy,
    pub(crate) elem_dofs: ElementDofTable,
    /// Element areas on the initial geometry: the mass ρ A₀ of an element is conserved
    /// while its area changes with the strain.
    pub(crate) initial_area: Vec<f64>,
    pub(crate) d_mats: Vec<Mat3>,
    pub(crate) f_load: Vec<f64>,
    pub(crate) penalties: Vec<Penalty>,
    /// Ghost ties of the tiny covers.
    pub(crate) ghosts: Vec<Ghost>,
    pub(crate) functions: Vec<TimeFunction>,
    /// Material point of each point monitor (None for interface monitors).
    pub(crate) monitor_points: Vec<Option<MaterialPoint>>,
    linear: LinearParts,
    /// The run's threads (local work of elements and contacts).
    pub(crate) threads: crate::parallel::Threads,
    /// The linear solver (the one interface: [`LinearSolver`]).
    solver: Box<dyn LinearSolver>,
    /// The inertia coefficient of the tangent the solver's factorisation was made for, and
    /// the step it was made in.
    solver_cm: Option<f64>,
    solver_step: Option<usize>,
    /// The contacts were detected on the current geometry (for the next step).
    contacts_current: bool,
    /// Search distance of the contacts' detection of the current step (m).
    search_used: f64,
    /// Increment and Δt of the last step (the predictor of the next one).
    last_du: Vec<f64>,
    last_dt: f64,
    /// Largest nodal displacement increment of the last step (for the contact search distance).
    last_max_du: f64,
    /// t₀ of the step grid: after k full steps the time is t₀ + kΔt.
    time_origin: f64,
    /// Full steps (intervals of Δt) completed since `time_origin`.
    full_steps: u64,
    /// Time already covered in the current interval by cut steps (0 on the grid).
    partial: f64,
    /// The current `[[stage]]` (index into `model.stages`; 0 without stages). Its analysis
    /// keys are in `model.analysis`.
    stage: usize,
    /// Where the base-motion record's t = 0 is on the run's clock; `None`: no base motion
    /// in this stage.
    base_origin: Option<f64>,
    /// The constraint springs as set up with the first stage's `constraint_penalty`
    /// (`penalties` are these scaled to the current stage's factor: they are linear in it).
    penalty_base: Vec<Penalty>,
    penalty_factor: f64,
    /// In-situ stress and excavated blocks ([`insitu`]).
    pub(crate) insitu: insitu::State,
}

impl Simulation {
    /// Discretise a validated model and prepare loads, constraints and monitors.
    pub fn new(model: Model) -> Result<Simulation, String> {
        // refuse a model that cannot fit before any large allocation
        memory::check_fits(&model)?;
        let t0 = Instant::now();
        let blocks: Vec<_> = model
            .blocks
            .iter()
            .map(|b| crate::cover::Shape {
                outer: &b.vertices,
                holes: &b.holes,
                fixed: b.fixed,
            })
            .collect();
        // the traces that end inside their block split its covers and are contact faces
        let cracks: Vec<crate::cover::CoverCrack> = model
            .cracks
            .iter()
            .map(|c| crate::cover::CoverCrack {
                block: c.block,
                joint: c.joint,
                points: c.points.clone(),
            })
            .collect();
        let disc = crate::cover::discretise_shapes(
            &blocks,
            &cracks,
            model.cover_size,
            model.cover_origin,
            CoverBasis::from_order(model.cover_order).ok_or("[cover] order: must be 0 or 1")?,
        )
        .map_err(|e| e.to_string())?;
        let cover_time = t0.elapsed();
        let n = disc.n_dofs;
        let elem_dofs = ElementDofTable::new(&disc);
        let stress_nodes = match disc.basis {
            CoverBasis::Constant => Vec::new(),
            b => vec![[0.0; 3]; b.stress_values() * disc.elements.len()],
        };
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
        let empty = Arc::new(SparsePattern::from_groups(n, std::iter::empty()));
        let mut sim = Simulation {
            contacts: ContactSet::default(),
            bolts: Default::default(),
            energy: Energy::default(),
            step: 0,
            time: 0.0,
            u: vec![0.0; n],
            v: vec![0.0; n],
            stress: vec![[0.0; 3]; n_el],
            stress_nodes,
            timings: Timings {
                cover: cover_time,
                ..Default::default()
            },
            elem_dofs,
            initial_area,
            d_mats,
            f_load: vec![0.0; n],
            penalties: Vec::new(),
            ghosts: Vec::new(),
            functions: Vec::new(),
            monitor_points: Vec::new(),
            linear: LinearParts {
                tangent: TangentPattern::new(empty),
                element_slots: Vec::new(),
                penalty_slots: Vec::new(),
                ghost_slots: Vec::new(),
                k: Vec::new(),
                m: Vec::new(),
                p: Vec::new(),
                c: Vec::new(),
                records: Vec::new(),
                step: None,
            },
            solver: Box::new(TangentSolver::default()),
            threads: Default::default(),
            solver_cm: None,
            solver_step: None,
            contacts_current: false,
            search_used: 0.0,
            last_du: vec![0.0; n],
            last_dt: 0.0,
            last_max_du: 0.0,
            time_origin: 0.0,
            full_steps: 0,
            partial: 0.0,
            stage: 0,
            penalty_base: Vec::new(),
            penalty_factor: 0.0,
            insitu: Default::default(),
            base_origin: match model.stages.first() {
                Some(s) => s.base_motion.then_some(0.0),
                None => Some(0.0),
            },
            disc,
            model,
        };
        if let Some(s) = sim.model.stages.first() {
            sim.model.analysis = s.analysis.clone();
        }
        setup::loads(&mut sim)?;
        setup::constraints(&mut sim)?;
        sim.penalty_base = sim.penalties.clone();
        sim.penalty_factor = sim.model.analysis.constraint_penalty;
        setup::monitors(&mut sim)?;
        sim.bolts = crate::bolt::BoltSet::new(&sim.model, &sim.disc, &sim.elem_dofs)?;
        sim.install_bolts();
        sim.ghosts = crate::cover::stabilise::ghost_ties(&sim.disc)
            .iter()
            .map(|t| {
                let e = sim.model.materials[sim.model.blocks[t.block].material].young;
                Ghost::ties(&sim.disc, t, crate::cover::stabilise::GHOST_STIFFNESS * e)
            })
            .collect::<Vec<_>>()
            .concat();
        // the blocks' masses, for the restitution dashpots of the contacts
        let mut masses = vec![0.0; sim.model.blocks.len()];
        for (e, a) in sim.disc.elements.iter().zip(&sim.initial_area) {
            let b = &sim.model.blocks[e.block];
            masses[e.block] += sim.model.materials[b.material].density * a;
        }
        for (m, b) in masses.iter_mut().zip(&sim.model.blocks) {
            if b.fixed {
                *m = f64::INFINITY;
            }
        }
        sim.contacts.set_block_masses(masses);
        sim.build_element_pattern();
        sim.init_insitu();
        sim.excavate_through(0);
        Ok(sim)
    }

    /// The element pattern (elements and penalties) and the slots of every local entry.
    fn build_element_pattern(&mut self) {
        let mut groups: Vec<Vec<usize>> =
            Vec::with_capacity(self.elem_dofs.len() + self.penalties.len());
        for d in self.elem_dofs.iter() {
            groups.push(d.iter().copied().filter(|&x| x != NO_DOF).collect());
        }
        for p in &self.penalties {
            groups.push(p.dofs.iter().copied().filter(|&x| x != NO_DOF).collect());
        }
        for g in &self.ghosts {
            groups.push(g.dofs.iter().copied().filter(|&x| x != NO_DOF).collect());
        }
        groups.extend(self.bolts.groups());
        let pattern = Arc::new(SparsePattern::from_groups(
            self.n_dofs(),
            groups.iter().map(|g| g.as_slice()),
        ));
        self.bolts.bind(&pattern);
        let slot = |r: usize, c: usize| -> u32 {
            if r == NO_DOF || c == NO_DOF {
                u32::MAX
            } else {
                pattern.slot(r, c).expect("element entry in its pattern") as u32
            }
        };
        let lp = &mut self.linear;
        let group = |d: &[usize]| -> Vec<u32> {
            let n = d.len();
            (0..n * n).map(|k| slot(d[k / n], d[k % n])).collect()
        };
        lp.element_slots = self.elem_dofs.iter().flat_map(group).collect();
        lp.penalty_slots = self.penalties.iter().map(|p| group(&p.dofs)).collect();
        lp.ghost_slots = self.ghosts.iter().map(|g| group(&g.dofs)).collect();
        let nnz = pattern.nnz();
        lp.k = vec![0.0; nnz];
        lp.m = vec![0.0; nnz];
        lp.p = vec![0.0; nnz];
        let dynamic = self.model.analysis.mode == Mode::Dynamic
            || self
                .model
                .stages
                .iter()
                .any(|s| s.analysis.mode == Mode::Dynamic);
        let damped = dynamic && self.model.materials.iter().any(|m| !m.damping.is_zero());
        lp.c = if damped { vec![0.0; nnz] } else { Vec::new() };
        lp.tangent = TangentPattern::new(pattern);
        lp.step = None;
    }

    /// Compute on `threads` (the results do not depend on their count, see
    /// [`crate::parallel`]).
    pub fn set_threads(&mut self, threads: crate::parallel::Threads) {
        self.contacts.threads = threads.clone();
        self.threads = threads;
    }

    /// Solve the steps' linear systems with `solver` instead of the [`TangentSolver`] (an
    /// iterative solver, a solver that records what it is given for a benchmark). Set it
    /// before the first step: the solver is told nothing of what came before.
    pub fn set_linear_solver(&mut self, solver: Box<dyn LinearSolver>) {
        self.solver = solver;
        self.solver_cm = None;
        self.solver_step = None;
    }

    /// The number of threads the simulation computes on.
    pub fn threads(&self) -> usize {
        self.threads.count()
    }

    pub fn n_dofs(&self) -> usize {
        self.disc.n_dofs
    }

    /// Unknowns of each block (0 for a fixed block).
    pub fn unknowns_per_block(&self) -> Vec<usize> {
        let mut n = vec![0; self.model.blocks.len()];
        for c in &self.disc.covers {
            if c.dof.is_some() {
                n[c.block] += 2 + 2 * c.terms.iter().filter(|&&t| t != NO_DOF).count();
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
        // a crack that splits no cover (it lies within the elements holding its tips) has
        // no effect on the analysis
        let idle: Vec<&crate::cover::Slit> = self
            .disc
            .slits
            .iter()
            .filter(|sl| {
                let [f0, f1] = &sl.faces;
                f0.segment_elements
                    .iter()
                    .zip(&f1.segment_elements)
                    .all(|(a, b)| a == b)
            })
            .collect();
        if let Some(first) = idle.first() {
            let c = &self.disc.cracks[first.crack];
            let len: f64 = c
                .points
                .windows(2)
                .map(|p| crate::geometry::dist(p[0], p[1]))
                .sum();
            w.push(format!(
                "{} of {} crack(s) split no physical cover at [cover] size {}: they lie within the elements holding their tips and have no effect on the analysis (a smaller cover size resolves them; the first: joint {:?} in block {:?}, {len:.6} m long, from [{}, {}])",
                idle.len(),
                self.disc.slits.len(),
                self.model.cover_size,
                self.model.joints[c.joint].name,
                self.model.blocks[c.block].name,
                c.points[0][0],
                c.points[0][1],
            ));
        }
        w
    }

    /// Advance one step, cutting Δt on non-convergence. The step covers the rest of the
    /// current interval of Δt (all of it unless an earlier step was cut). When the current
    /// stage is complete, the step is the first of the next stage.
    pub fn advance(&mut self) -> Result<StepReport, StepError> {
        // the other threads stay awake for the step's parallel loops
        self.threads.keep_warm();
        if self.stage_finished() && self.stage + 1 < self.model.stages.len() {
            self.begin_next_stage();
        }
        // 2. contacts on the geometry at t_n (once per step, whatever the cuts)
        if !self.contacts_current {
            let search = self.search_distance();
            self.detect_contacts(search, true);
        }
        self.assemble_step_parts();
        let mut dt = self.model.analysis.dt - self.partial;
        let mut last = (f64::NAN, String::new());
        let mut solves = 0;
        let mut redone = 0;
        let mut cuts = 0;
        while cuts <= self.model.analysis.max_step_cuts {
            match self.attempt(dt) {
                Ok(mut rep) => {
                    rep.cuts = cuts;
                    rep.solves = solves + rep.iterations;
                    return Ok(rep);
                }
                Err(Failure::OutOfMemory(what)) => {
                    return Err(StepError::OutOfMemory {
                        step: self.step + 1,
                        time: self.output_time(),
                        what,
                    })
                }
                Err(Failure::Outran {
                    motion,
                    iterations,
                    found,
                }) => {
                    solves += iterations;
                    if redone < OUTRUN_RETRIES {
                        // the same step again, with the contacts along its motion (already
                        // detected)
                        redone += 1;
                        continue;
                    }
                    last = (
                        f64::NAN,
                        format!(
                            ": it moves {motion:.3e} m and closes contacts beyond its search ({found} found)"
                        ),
                    );
                }
                Err(Failure::NotConverged {
                    residual,
                    detail,
                    iterations,
                }) => {
                    solves += iterations;
                    last = (residual, detail);
                }
            }
            dt *= 0.5;
            cuts += 1;
        }
        Err(StepError::NotConverged {
            step: self.step + 1,
            time: self.output_time(),
            cuts: self.model.analysis.max_step_cuts,
            residual: last.0,
            detail: last.1,
        })
    }

    /// Contacts on the geometry at t_n, searched within `search` (m); with `by_pair`, a
    /// vertex is found inside a face no deeper than the two blocks' reach
    /// ([`crate::contact::set::PenetrationReach`]), else within `search` too (the search
    /// over a step's own motion when it outran the contacts).
    fn detect_contacts(&mut self, search: f64, by_pair: bool) {
        let tc = Instant::now();
        let reach = by_pair.then(|| self.block_reach());
        let reach = reach
            .as_ref()
            .map(|r| crate::contact::set::PenetrationReach {
                blocks: r,
                floor: self.search_floor(),
            });
        self.contacts
            .detect(&self.disc, &self.model, &self.u, search, reach);
        self.timings.stages.contact += tc.elapsed();
        self.contacts_current = true;
        self.search_used = search;
    }

    /// Largest motion of a node (cover) in the increment `du` (m).
    fn largest_motion(&self, du: &[f64]) -> f64 {
        self.disc
            .covers
            .iter()
            .filter_map(|c| c.dof)
            .map(|d| crate::geometry::norm([du[d], du[d + 1]]))
            .fold(0.0, f64::max)
    }

    /// Element stiffness, mass, body-force integrals and internal forces on the geometry at
    /// t_n (independent of Δt: once per step).
    fn assemble_step_parts(&mut self) {
        if self.linear.step == Some(self.step) {
            return;
        }
        let ta = Instant::now();
        let n_el = self.disc.elements.len();
        let lp = &mut self.linear;
        lp.k.iter_mut().for_each(|v| *v = 0.0);
        lp.m.iter_mut().for_each(|v| *v = 0.0);
        lp.p.iter_mut().for_each(|v| *v = 0.0);
        lp.c.iter_mut().for_each(|v| *v = 0.0);
        let damped = !lp.c.is_empty();
        let basis = self.disc.basis;
        let (nd, rl) = (basis.element_dofs(), basis.record_len());
        let nsv = basis.stress_values();
        lp.records.resize(n_el * rl, 0.0);
        // local work on the run's threads, then the scatter in element order
        let (disc, model, elem_dofs) = (&self.disc, &self.model, &self.elem_dofs);
        let (initial_area, d_mats) = (&self.initial_area, &self.d_mats);
        let stress: &[[f64; 3]] = match basis {
            CoverBasis::Constant => &self.stress,
            _ => &self.stress_nodes,
        };
        // on the run's threads when enough elements have work (a fixed base's elements,
        // skipped, would only pay the pool's dispatch)
        let threads = self
            .threads
            .for_items(elem_dofs.free_elements(), crate::parallel::MIN_PARALLEL);
        threads.for_each_chunk_mut(&mut lp.records, rl, |ei, rec| {
            let e = &disc.elements[ei];
            if elem_dofs.of(ei).iter().all(|&d| d == NO_DOF) {
                return;
            }
            let mat = model.blocks[e.block].material;
            basis.element_local(
                e,
                model.materials[mat].density,
                initial_area[ei],
                &d_mats[mat],
                &stress[nsv * ei..nsv * (ei + 1)],
                rec,
            );
        });
        for ei in 0..n_el {
            if elem_dofs.of(ei).iter().all(|&d| d == NO_DOF) {
                continue;
            }
            let rec = &lp.records[ei * rl..(ei + 1) * rl];
            let (k, m) = (&rec[..nd * nd], &rec[nd * nd..2 * nd * nd]);
            let slots = &lp.element_slots[ei * nd * nd..(ei + 1) * nd * nd];
            for (idx, &s) in slots.iter().enumerate() {
                if s != u32::MAX {
                    lp.k[s as usize] += k[idx];
                    lp.m[s as usize] += m[idx];
                }
            }
            if damped {
                let mat = self.model.blocks[disc.elements[ei].block].material;
                let d = self.model.materials[mat].damping;
                for (idx, &s) in slots.iter().enumerate() {
                    if s != u32::MAX {
                        lp.c[s as usize] += d.alpha * m[idx] + d.beta * k[idx];
                    }
                }
            }
        }
        for (p, slots) in self.penalties.iter().zip(&lp.penalty_slots) {
            for (idx, &s) in slots.iter().enumerate() {
                if s != u32::MAX {
                    lp.p[s as usize] += p.k[idx];
                }
            }
        }
        for (g, slots) in self.ghosts.iter().zip(&lp.ghost_slots) {
            for (idx, &s) in slots.iter().enumerate() {
                if s != u32::MAX {
                    lp.p[s as usize] += g.k[idx];
                }
            }
        }
        lp.step = Some(self.step);
        // the bolts' kinematics on the geometry at t_n
        self.bolts.begin_step(&self.disc, &self.u);
        self.timings.stages.assembly += ta.elapsed();
    }

    /// The step's right-hand side F = f_ext(t1) − f_int(σ_n) + c_v M v_n + P-targets − P u_n,
    /// and the magnitudes of its physical forces per unknown (|f_ext| + |c_v M v_n| +
    /// |f_int|, for the convergence test; the penalty targets are left out), with a floor
    /// of E_max · 10⁻¹² · h.
    fn right_hand_side(&self, dt: f64, t1: f64, v_n: &[f64], f: &mut [f64], f_ext_abs: &mut [f64]) {
        let cv = time::velocity_coefficient(dt);
        let a_base = self.base_acceleration(t1);
        let g = self.model.analysis.gravity;
        // body acceleration in the frame of the base: gravity − a_base
        let b = [g[0] - a_base[0], g[1] - a_base[1]];
        f.copy_from_slice(&self.f_load);
        let floor = self
            .model
            .materials
            .iter()
            .map(|m| m.young)
            .fold(0.0, f64::max)
            * 1e-12
            * self.model.cover_size;
        for (fa, fl) in f_ext_abs.iter_mut().zip(&self.f_load) {
            *fa = fl.abs() + floor;
        }
        let lp = &self.linear;
        let nd = self.elem_dofs.stride();
        let rl = self.disc.basis.record_len();
        let mut ve = [0.0; MAX_ELEMENT_DOFS];
        for (ei, dofs) in self.elem_dofs.iter().enumerate() {
            if dofs.iter().all(|&d| d == NO_DOF) {
                continue;
            }
            let rec = &lp.records[ei * rl..(ei + 1) * rl];
            let m = &rec[nd * nd..2 * nd * nd];
            let body = &rec[2 * nd * nd..2 * nd * nd + nd / 2];
            let internal = &rec[2 * nd * nd + nd / 2..];
            gather_into(v_n, dofs, &mut ve[..nd]);
            for r in 0..nd {
                let d = dofs[r];
                if d == NO_DOF {
                    continue;
                }
                let fb = body[r / 2] * b[r % 2];
                let mv: f64 = (0..nd).map(|c| m[r * nd + c] * ve[c]).sum();
                let fi = internal[r];
                f[d] += fb + cv * mv - fi;
                // physical forces: body forces, the inertia of the motion, the stresses
                f_ext_abs[d] += fb.abs() + (cv * mv).abs() + fi.abs();
            }
        }
        if !lp.c.is_empty() && self.model.analysis.mode == Mode::Dynamic {
            // Rayleigh damping: C v_{n+1} = (2/Δt) C Δu − C v_n, so + C v_n here
            let mut cv_n = vec![0.0; f.len()];
            step::sym_mul_on(&self.threads, lp.tangent.element(), &lp.c, v_n, &mut cv_n);
            for (fi, ci) in f.iter_mut().zip(&cv_n) {
                *fi += ci;
            }
        }
        // ghost ties: their force on the displacement at the step start
        let mut ue = Vec::new();
        for g in &self.ghosts {
            let n = g.dofs.len();
            ue.resize(n, 0.0);
            gather_into(&self.u, &g.dofs, &mut ue);
            for i in 0..n {
                if g.dofs[i] != NO_DOF {
                    f[g.dofs[i]] -= (0..n).map(|j| g.k[i * n + j] * ue[j]).sum::<f64>();
                }
            }
        }
        for p in &self.penalties {
            let target = self.functions[p.function].eval(t1);
            let n = p.dofs.len();
            ue.resize(n, 0.0);
            gather_into(&self.u, &p.dofs, &mut ue);
            for i in 0..n {
                if p.dofs[i] != NO_DOF {
                    f[p.dofs[i]] +=
                        target * p.g[i] - (0..n).map(|j| p.k[i * n + j] * ue[j]).sum::<f64>();
                }
            }
        }
    }

    /// One attempt at a step of size dt; the state is changed only on success.
    ///
    /// Dynamic: Newton on the Newmark step from the previous increment scaled to Δt.
    /// Static: the equilibrium under the loads of t_{n+1}, by Newton with pseudo-transient
    /// continuation from the inertia of Δt (`solver/newton.rs`), from Δu = 0. Where that
    /// finds no equilibrium (a mechanism: a block on a plane steeper than φ, a falling
    /// block), DDA's quasi-static step is taken instead — the step with the inertia of Δt
    /// and zero initial velocity — with Δt shortened until no point moves more than
    /// [`STATIC_MAX_MOTION`] × h, and the step is reported as not in equilibrium.
    fn attempt(&mut self, dt: f64) -> Result<StepReport, Failure> {
        let a = self.model.analysis.clone();
        let n = self.n_dofs();
        let t1 = self.time + dt;
        let static_mode = a.mode == Mode::Static;
        // the contacts' restitution dashpots act over this Δt (dynamic steps only)
        self.contacts.set_time_step((!static_mode).then_some(dt));
        // 1. predict
        let v_n: Vec<f64> = if static_mode {
            vec![0.0; n]
        } else {
            self.v.clone()
        };
        let cm = time::mass_coefficient(dt);
        let ta = Instant::now();
        let mut f = vec![0.0; n];
        let mut f_ext_abs = vec![0.0; n];
        self.right_hand_side(dt, t1, &v_n, &mut f, &mut f_ext_abs);
        self.timings.stages.assembly += ta.elapsed();
        let rhs = Rhs {
            f: &f,
            f_ext_abs: &f_ext_abs,
            t1,
            dt,
        };
        let mut du = vec![0.0; n];
        let (rep, equilibrium) = if static_mode {
            self.static_step(&rhs, cm, &mut du)
        } else {
            // the first iterate: the last increment, scaled to this Δt
            if self.last_dt > 0.0 {
                let s = dt / self.last_dt;
                for (d, l) in du.iter_mut().zip(&self.last_du) {
                    *d = s * l;
                }
            }
            let rep = self.solve(
                &rhs,
                cm,
                None,
                Regularisation::None { fallback: cm },
                MAX_REJECTIONS,
                None,
                false,
                &mut du,
            );
            (rep, true)
        };
        if let Some(crate::solver::SolveError::OutOfMemory) = rep.error {
            return Err(Failure::OutOfMemory("sparse factorisation".into()));
        }
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
            return Err(Failure::NotConverged {
                residual: last,
                detail,
                iterations: rep.iterations,
            });
        }
        // A point that moved beyond the contact search: search again over the motion; if a
        // contact found that way is closed at Δu, the step is redone with it.
        let motion = self.largest_motion(&du);
        if motion > OUTRUN_FRACTION * self.search_used {
            let solved: std::collections::HashSet<_> = self
                .contacts
                .contacts
                .iter()
                .map(|c| (c.key, c.segment))
                .collect();
            self.detect_contacts((OUTRUN_SEARCH * motion).max(self.search_used), false);
            let tol = self.contacts.touch_tolerance();
            let found = self
                .contacts
                .contacts
                .iter()
                .filter(|c| !solved.contains(&(c.key, c.segment)) && c.gaps(&du).0 < -tol)
                .count();
            if found > 0 {
                return Err(Failure::Outran {
                    motion,
                    iterations: rep.iterations,
                    found,
                });
            }
        }
        // an element whose area would change sign: the step is too large
        if let Some(e) = self.inverted_element(&du) {
            return Err(Failure::NotConverged {
                residual: f64::NAN,
                detail: format!(": manifold element {e} would be inverted"),
                iterations: rep.iterations,
            });
        }
        let counts = self.contacts.counts();
        // the static step's out-of-balance work Δuᵀ R(Δu), which the velocity reset discards
        // (zero, to the tolerance, for a step in equilibrium)
        let out_of_balance = if static_mode {
            self.with_system(&rhs, 0.0, None, |sys, _| {
                let mut r = vec![0.0; du.len()];
                crate::solver::PiecewiseSystem::residual(sys, &du, &mut r);
                r.iter().zip(&du).map(|(a, b)| a * b).sum::<f64>()
            })
        } else {
            0.0
        };
        // 6. commit
        self.commit(&du, &v_n, dt, out_of_balance);
        Ok(StepReport {
            iterations: rep.iterations,
            solves: rep.iterations,
            cuts: 0,
            residuals: rep.residuals,
            dt,
            active_set_changes: rep.active_set_changes,
            contacts: counts.open + counts.stick + counts.slide,
            equilibrium,
            linear: rep.linear,
        })
    }

    /// Newton on the step's system with the linear part L = K + cm M + P, from the first
    /// iterate in `du`. With `anchor = (Δu_k, σ)` the system is the continuation's inner
    /// problem: L + σ M and F + σ M Δu_k (see [`Simulation::static_continuation`]).
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &mut self,
        rhs: &Rhs,
        cm: f64,
        anchor: Option<(&[f64], f64)>,
        regularisation: Regularisation,
        max_rejections: usize,
        tolerance: Option<f64>,
        warm: bool,
        du: &mut [f64],
    ) -> crate::solver::NewtonReport {
        let (max_iterations, tolerance) = (
            self.model.analysis.max_iterations,
            tolerance.unwrap_or(self.model.analysis.tolerance),
        );
        // the trust region: a quarter of the cover size at least (see solve_piecewise)
        let max_step = self.search_distance().max(0.25 * self.model.cover_size);
        let opts = NewtonOptions {
            max_iterations,
            tolerance,
            regularisation,
            max_rejections,
            max_step,
            warm_start: warm,
        };
        // a fresh factorisation at the first solve of every step, and when the inertia
        // coefficient or the regularisation changed (see TangentSolver)
        let invalidate = self.solver_step != Some(self.step)
            || self.solver_cm != Some(cm)
            || !matches!(regularisation, Regularisation::None { .. });
        let rep = self.with_system(rhs, cm, anchor, |sys, solver| {
            if invalidate {
                // the inertia coefficient (or the regularisation) changed
                solver.invalidate();
            }
            solve_piecewise(sys, solver, du, opts)
        });
        self.solver_cm = Some(cm);
        self.solver_step = Some(self.step);
        self.timings.stages += rep.times;
        rep
    }

    /// Builds the step's system (see [`Simulation::solve`]) and hands it to `f`.
    fn with_system<T>(
        &mut self,
        rhs: &Rhs,
        cm: f64,
        anchor: Option<(&[f64], f64)>,
        f: impl FnOnce(&mut StepSystem, &mut dyn LinearSolver) -> T,
    ) -> T {
        let lp = &mut self.linear;
        lp.tangent.step = self.step;
        // Rayleigh damping (dynamic only): (2/Δt) C
        let cd = if cm > 0.0 && !lp.c.is_empty() {
            time::damping_coefficient(rhs.dt)
        } else {
            0.0
        };
        let sigma = anchor.map_or(0.0, |a| a.1);
        let l: Vec<f64> = (0..lp.k.len())
            .map(|i| {
                let c = if cd > 0.0 { cd * lp.c[i] } else { 0.0 };
                lp.k[i] + (cm + sigma) * lp.m[i] + c + lp.p[i]
            })
            .collect();
        let mut shifted;
        let fvec: &[f64] = match anchor {
            Some((du_k, sigma)) => {
                shifted = vec![0.0; du_k.len()];
                step::sym_mul(lp.tangent.element(), &lp.m, du_k, &mut shifted);
                for (s, fi) in shifted.iter_mut().zip(rhs.f) {
                    *s = fi + sigma * *s;
                }
                &shifted
            }
            None => rhs.f,
        };
        let targets: Vec<f64> = self
            .penalties
            .iter()
            .map(|p| self.functions[p.function].eval(rhs.t1))
            .collect();
        let mut sys = StepSystem {
            l: &l,
            m: &lp.m,
            f: fvec,
            f_ext_abs: rhs.f_ext_abs,
            penalties: &self.penalties,
            targets: &targets,
            u_n: &self.u,
            contacts: &mut self.contacts,
            bolts: &mut self.bolts,
            tangent: &mut lp.tangent,
            threads: &self.threads,
            inertia: cm > 0.0,
            sigma: 0.0,
            scale: 0.0,
            work: Vec::with_capacity(rhs.f.len()),
        };
        f(&mut sys, &mut *self.solver)
    }

    /// The first element whose triangle or polygon would change orientation under `du`.
    fn inverted_element(&self, du: &[f64]) -> Option<usize> {
        let basis = self.disc.basis;
        let nd = self.elem_dofs.stride();
        let mut ue = [0.0; MAX_ELEMENT_DOFS];
        for (ei, e) in self.disc.elements.iter().enumerate() {
            let ue = &mut ue[..nd];
            gather_into(du, self.elem_dofs.of(ei), ue);
            if ue.iter().all(|&x| x == 0.0) {
                continue;
            }
            let moved: [crate::geometry::Vec2; 3] = std::array::from_fn(|k| {
                let d = basis.node_displacement(ue, k);
                [e.nodes[k][0] + d[0], e.nodes[k][1] + d[1]]
            });
            let a0 = crate::geometry::cross(
                crate::geometry::sub(e.nodes[1], e.nodes[0]),
                crate::geometry::sub(e.nodes[2], e.nodes[0]),
            );
            let a1 = crate::geometry::cross(
                crate::geometry::sub(moved[1], moved[0]),
                crate::geometry::sub(moved[2], moved[0]),
            );
            if a1 <= 0.0 || a1 < 1e-6 * a0 {
                return Some(ei);
            }
        }
        None
    }

    /// Add the nodal forces `f` (one per unknown, N per metre of thickness; constant in
    /// time) to the model's loads: for loads the model file cannot state, such as the exact
    /// tractions of a verification case integrated against the shape functions.
    pub fn add_load_vector(&mut self, f: &[f64]) {
        assert_eq!(f.len(), self.f_load.len(), "one force per unknown");
        for (a, b) in self.f_load.iter_mut().zip(f) {
            *a += b;
        }
    }

    /// The linear part of the next step's system (L, F) on the current state, over the
    /// element pattern: for benchmarks and tests.
    pub fn linear_system(&mut self) -> (SparseMatrix, Vec<f64>) {
        let dt = self.model.analysis.dt;
        let n = self.n_dofs();
        let v_n = match self.model.analysis.mode {
            Mode::Static => vec![0.0; n],
            Mode::Dynamic => self.v.clone(),
        };
        self.linear.step = None;
        self.assemble_step_parts();
        let cm = time::mass_coefficient(dt);
        let lp = &self.linear;
        let values = (0..lp.k.len())
            .map(|i| lp.k[i] + cm * lp.m[i] + lp.p[i])
            .collect();
        let l = SparseMatrix {
            pattern: lp.tangent.element().clone(),
            values,
        };
        let mut f = vec![0.0; n];
        let mut fa = vec![0.0; n];
        self.right_hand_side(dt, self.time + dt, &v_n, &mut f, &mut fa);
        (l, f)
    }

    /// Contact search distance: three times the largest displacement of the last
    /// step, and at least 2% of the mesh size.
    fn search_distance(&self) -> f64 {
        (SEARCH_MOTIONS * self.last_max_du).max(self.search_floor())
    }

    /// The least contact search distance: 2% of the mesh size.
    fn search_floor(&self) -> f64 {
        0.02 * self.model.cover_size
    }

    /// Each block's reach in the last step: [`SEARCH_MOTIONS`] times the largest motion of
    /// its covers in the last increment (0 for a block that did not move).
    fn block_reach(&self) -> Vec<f64> {
        let mut reach = vec![0.0f64; self.disc.boundaries.len()];
        if self.last_du.is_empty() {
            return reach;
        }
        for c in &self.disc.covers {
            if let Some(d) = c.dof {
                let m = crate::geometry::norm([self.last_du[d], self.last_du[d + 1]]);
                reach[c.block] = reach[c.block].max(SEARCH_MOTIONS * m);
            }
        }
        reach
    }

    /// Commit a converged increment: kinematics, stresses, contacts, geometry.
    fn commit(&mut self, du: &[f64], v_n: &[f64], dt: f64, out_of_balance: f64) {
        for i in 0..du.len() {
            self.u[i] += du[i];
            self.v[i] = time::velocity_update(du[i], v_n[i], dt);
        }
        if self.model.analysis.mode == Mode::Static {
            // a static step ends at rest
            self.v.iter_mut().for_each(|x| *x = 0.0);
        }
        self.contacts.commit(du);
        self.bolts.commit(du);
        let mut max_du = 0.0f64;
        let basis = self.disc.basis;
        let nd = self.elem_dofs.stride();
        let mut ue = [0.0; MAX_ELEMENT_DOFS];
        let mut moves: Vec<crate::geometry::Vec2> = Vec::new();
        for (ei, e) in self.disc.elements.iter_mut().enumerate() {
            let ue = &mut ue[..nd];
            gather_into(du, self.elem_dofs.of(ei), ue);
            if ue.iter().all(|&x| x == 0.0) {
                continue;
            }
            let mat = self.model.blocks[e.block].material;
            let d_mat = &self.d_mats[mat];
            match basis {
                CoverBasis::Constant => {
                    let ds = hooke(d_mat, basis.strain(e, &[0.0; 3], ue));
                    let s = &mut self.stress[ei];
                    for k in 0..3 {
                        s[k] += ds[k];
                    }
                }
                _ => {
                    // the stress is linear in the weights: its increments at the nodes
                    for m in 0..3 {
                        let mut w = [0.0; 3];
                        w[m] = 1.0;
                        let ds = hooke(d_mat, basis.strain(e, &w, ue));
                        let s = &mut self.stress_nodes[3 * ei + m];
                        for k in 0..3 {
                            s[k] += ds[k];
                        }
                    }
                }
            }
            // geometry: polygon vertices move by Δu (weights on the old triangle), then the nodes
            moves.clear();
            let er: &crate::cover::ManifoldElement = e;
            moves.extend(er.polygon.iter().map(|x| {
                let w = crate::cover::barycentric(&er.nodes, *x);
                basis.interpolate(er, &w, ue)
            }));
            for (x, d) in e.polygon.iter_mut().zip(&moves) {
                x[0] += d[0];
                x[1] += d[1];
            }
            for k in 0..3 {
                let d = basis.node_displacement(ue, k);
                e.nodes[k][0] += d[0];
                e.nodes[k][1] += d[1];
                max_du = max_du.max(crate::geometry::norm(d));
            }
            if basis != CoverBasis::Constant {
                // the stress written out: at the centroid of the moved polygon
                let c =
                    crate::geometry::moments::polygon_moments(&e.polygon, e.polygon[0]).centroid();
                let w = crate::cover::barycentric(&e.nodes, c);
                let sn = &self.stress_nodes[3 * ei..3 * ei + 3];
                self.stress[ei] =
                    std::array::from_fn(|k| w[0] * sn[0][k] + w[1] * sn[1][k] + w[2] * sn[2][k]);
            }
        }
        self.last_max_du = max_du;
        self.last_du.copy_from_slice(du);
        self.last_dt = dt;
        self.contacts_current = false;
        self.update_energy(du, v_n, dt, out_of_balance);
        self.advance_clock(dt);
        self.step += 1;
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

/// The right-hand side of a step attempt.
struct Rhs<'a> {
    f: &'a [f64],
    f_ext_abs: &'a [f64],
    t1: f64,
    dt: f64,
}

/// Why an attempt at a step failed.
enum Failure {
    NotConverged {
        residual: f64,
        detail: String,
        iterations: usize,
    },
    /// The converged increment moves a point farther than the contacts were searched for
    /// at the start of the step allows ([`OUTRUN_FRACTION`]), and a contact found by a
    /// search over its motion is closed at the increment: a vertex passed through an edge
    /// that was never looked at.
    Outran {
        motion: f64,
        iterations: usize,
        /// contacts the wider search added
        found: usize,
    },
    OutOfMemory(String),
}

/// A step may move no point farther than this fraction of the contact search distance
/// used at its start: two blocks approaching each other close the distance twice as fast.
pub const OUTRUN_FRACTION: f64 = 0.5;
/// The contact search distance in motions of the last step ([`Simulation::search_distance`]).
const SEARCH_MOTIONS: f64 = 3.0;

/// Times a step that outran its contact search (and closed a contact found by a search
/// over [`OUTRUN_SEARCH`] × its motion) is redone with those contacts before Δt is cut.
const OUTRUN_RETRIES: usize = 3;
/// Search distance of a redone step, as a multiple of the motion that outran the search.
const OUTRUN_SEARCH: f64 = 3.0;
