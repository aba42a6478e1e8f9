//! Stage control: the sequence of `[[stage]]`s, each with its analysis keys, its step grid
//! and its base-motion clock, and the run's clock across stages.
//!
//! A stage begins at the first step after the previous one completed its full steps
//! ([`Simulation::advance`] calls [`Simulation::begin_next_stage`]): its `[analysis]` keys
//! replace the current ones, its step grid starts at the current time, the record (if the
//! stage asks for base motion) starts at the stage's start, and the constraint springs take
//! the stage's `constraint_penalty`, and the stage's `[[bolt]]`s are installed (on the
//! current geometry: [`crate::bolt`]). Displacements, stresses and contact states carry
//! over.

use super::Simulation;
use crate::model::Mode;
use crate::time;

impl Simulation {
    /// End time of the analysis (of its last stage).
    pub fn end_time(&self) -> f64 {
        let a = &self.model.analysis;
        let mut t = time::grid_time(self.time_origin, a.steps as u64, a.dt);
        for s in self.model.stages.iter().skip(self.stage + 1) {
            t = time::grid_time(t, s.analysis.steps as u64, s.analysis.dt);
        }
        t
    }

    /// Whether the analysis has reached its end time (completed all the full steps of its
    /// last stage).
    pub fn finished(&self) -> bool {
        self.stage_finished() && self.stage + 1 >= self.model.stages.len()
    }

    /// Whether the current stage (the whole analysis without stages) has completed its
    /// full steps.
    pub fn stage_finished(&self) -> bool {
        self.full_steps >= self.model.analysis.steps as u64
    }

    /// The index of the current stage in `model.stages` (0 without stages).
    pub fn stage_index(&self) -> usize {
        self.stage
    }

    /// The current stage's name (`None` without `[[stage]]`). After a step, the stage that
    /// step belonged to: the next stage begins with the next step.
    pub fn stage_name(&self) -> Option<&str> {
        self.model.stages.get(self.stage).map(|s| s.name.as_str())
    }

    /// Full steps of the whole analysis (every stage), for progress reports.
    pub fn total_steps(&self) -> usize {
        if self.model.stages.is_empty() {
            self.model.analysis.steps
        } else {
            self.model.stages.iter().map(|s| s.analysis.steps).sum()
        }
    }

    /// Full steps of the stages before the current one plus those done in it.
    pub fn full_steps_done(&self) -> usize {
        let before: usize = self
            .model
            .stages
            .iter()
            .take(self.stage)
            .map(|s| s.analysis.steps)
            .sum();
        before + self.full_steps as usize
    }

    /// The base acceleration at time `t` of the run's clock: the record at `t` − the
    /// start of the stage that applies it (the record from t = 0 without stages), zero in a
    /// stage without base motion.
    pub fn base_acceleration(&self, t: f64) -> crate::geometry::Vec2 {
        match (&self.model.base_motion, self.base_origin) {
            (Some(b), Some(t0)) => b.accel(t - t0),
            _ => [0.0, 0.0],
        }
    }

    /// Begin the next stage: its analysis keys, a step grid from the current time, the
    /// base-motion record from its start if it asks for it. Displacements, stresses and
    /// contact states carry over; after a static stage the velocity is zero (a static step
    /// ends at rest) and the next stage's first iterate starts from zero.
    pub(super) fn begin_next_stage(&mut self) {
        let was_static = self.model.analysis.mode == Mode::Static;
        self.stage += 1;
        let s = &self.model.stages[self.stage];
        self.model.analysis = s.analysis.clone();
        self.base_origin = s.base_motion.then_some(self.time);
        self.time_origin = self.time;
        self.full_steps = 0;
        self.partial = 0.0;
        self.scale_constraint_penalties();
        self.excavate_through(self.stage);
        self.install_bolts();
        if was_static {
            self.v.iter_mut().for_each(|x| *x = 0.0);
            self.last_du.iter_mut().for_each(|x| *x = 0.0);
            self.last_dt = 0.0;
        }
        // the friction law and the inertia coefficient may change with the stage
        self.contacts_current = false;
        self.linear.step = None;
    }

    /// Install the bolts of the stages begun so far (those without a stage at the start)
    /// on the current geometry ([`crate::bolt`]).
    pub(super) fn install_bolts(&mut self) {
        let stage = self.stage;
        self.bolts
            .install(&self.disc, &self.u, |s| s.is_none_or(|s| s <= stage));
    }

    /// The constraint springs for the current stage's `constraint_penalty`: those set up
    /// with the first stage's factor, scaled (each spring is linear in the factor).
    pub(super) fn scale_constraint_penalties(&mut self) {
        let s = self.model.analysis.constraint_penalty / self.penalty_factor;
        for (p, b) in self.penalties.iter_mut().zip(&self.penalty_base) {
            if s == 1.0 {
                p.k.clone_from(&b.k);
                p.g.clone_from(&b.g);
            } else {
                p.k = b.k.iter().map(|x| x * s).collect();
                p.g = b.g.iter().map(|x| x * s).collect();
            }
        }
        self.linear.step = None;
    }

    /// The time the outputs write for the clock: the same point, but inside a cut step the
    /// double nearest its decimal ([`time::cut_time`]: 1.481, not 1.4809999999999999). The
    /// clock itself ([`Simulation::time`]) keeps the sum the loads were evaluated at (a few
    /// roundings apart at most), so that the numerics of a cut step are those they were.
    pub fn output_time(&self) -> f64 {
        match self.partial {
            0.0 => self.time,
            p => time::cut_time(self.time_origin, self.full_steps, self.model.analysis.dt, p),
        }
    }

    /// The clock after a committed step of `dt`: a step that covered the rest of its
    /// interval ends on the grid, t = t₀ + kΔt; a cut one ends at t₀ + kΔt + (time covered).
    pub(super) fn advance_clock(&mut self, dt: f64) {
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
}
