//! In-situ stress and excavation: the state of a rock mass at depth before anything moves,
//! and the removal of blocks at the start of a stage.
//!
//! **In-situ stress.** With `[initial_stress]` σ₀(y) every element starts with the stress
//! σ₀: at order 0 its value at the centroid of the element's polygon (the stress of a
//! constant-strain element; its internal force Bᵀσ A is then the exact ∫ Bᵀσ₀ dΩ of a
//! stress linear in y, B being constant), at order 1 its values at the triangle's three
//! nodes (the element's stress is linear in the weights, so a σ₀ linear in y is held
//! exactly). The step's internal force f_int(σ_n) = ∫ Bᵀσ_n dΩ then holds σ₀ from the
//! first step on: a block in equilibrium with σ₀ — tractions σ₀·n on its free edges (loads),
//! body forces with div σ₀ + ρ b = 0, contacts carrying σ₀·n (the contact set's
//! [`crate::contact::set`] in-situ offsets) — has F = f_ext − f_int = 0 and does not move.
//! Stresses then accumulate as σ = σ₀ + Σ D B Δu; the VTK's stress is that total.
//! The energy balance starts from the elastic energy of σ₀ (`initial_total`).
//!
//! **Excavation.** At the start of a stage with `excavate`, its blocks are removed: their
//! covers lose their unknowns ([`crate::cover::Discretisation::remove_blocks`]: the others
//! are numbered again, the state vectors, loads, constraint and ghost springs follow), no
//! contact with them is detected any more, their elements are dropped from the VTK frames
//! and their stress is cleared. What they carried is released at once: the contacts that
//! held the rest against them go, so the faces they touched become free surfaces loaded by
//! nothing, and the rest's internal force f_int(σ) — under in-situ stress the tractions
//! σ·n those contacts balanced — deforms it. The elastic and kinetic energy the removed
//! blocks had goes to the balance's `excavated`; their contacts' spring energy to its
//! `contact_update`, as any contact's that is not found again.

use super::Simulation;
use crate::assembly::global::NO_DOF;
use crate::cover::basis::{CoverBasis, ElementDofTable};

/// The in-situ state of a simulation.
#[derive(Debug, Clone, Default)]
pub(crate) struct State {
    /// Blocks removed by an excavation so far.
    pub excavated: Vec<bool>,
    /// The elastic energy of the in-situ stress on the initial geometry (J/m).
    pub initial_elastic: f64,
}

impl Simulation {
    /// Every element's stress at `[initial_stress]` (module doc); the contacts told.
    pub(super) fn init_insitu(&mut self) {
        self.insitu.excavated = vec![false; self.model.blocks.len()];
        let Some(s) = self.model.initial_stress else {
            return;
        };
        for (ei, e) in self.disc.elements.iter().enumerate() {
            let c = crate::geometry::moments::polygon_moments(&e.polygon, e.polygon[0]).centroid();
            self.stress[ei] = s.at(c[1]);
            if self.disc.basis != CoverBasis::Constant {
                for m in 0..3 {
                    self.stress_nodes[3 * ei + m] = s.at(e.nodes[m][1]);
                }
            }
        }
        self.contacts.set_initial_stress(Some(s));
        let all: Vec<usize> = (0..self.disc.elements.len()).collect();
        self.insitu.initial_elastic = self.elastic_energy_of(&all);
    }

    /// Whether block `b` was excavated.
    pub fn is_excavated(&self, b: usize) -> bool {
        self.insitu.excavated.get(b).copied().unwrap_or(false)
    }

    /// Excavate the blocks of the stages up to `stage` (in `model.stages`) not excavated
    /// yet: at the start of a stage, and when a checkpoint is restored.
    pub(crate) fn excavate_through(&mut self, stage: usize) {
        let blocks: Vec<usize> = self
            .model
            .stages
            .iter()
            .take(stage + 1)
            .flat_map(|s| s.excavate.iter().copied())
            .filter(|&b| !self.is_excavated(b))
            .collect();
        if !blocks.is_empty() {
            self.excavate(&blocks);
        }
    }

    /// Remove `blocks` (module doc).
    fn excavate(&mut self, blocks: &[usize]) {
        for &b in blocks {
            self.insitu.excavated[b] = true;
        }
        let gone: Vec<usize> = (0..self.disc.elements.len())
            .filter(|&ei| self.is_excavated(self.disc.elements[ei].block))
            .collect();
        // the energy they take with them: elastic, and kinetic ½ vᵀMv of their unknowns
        // (zero before the first step and after a static one), on the mass matrix of the
        // current geometry: assembled here (once per step: the next step's own if nothing
        // is excavated), so that a run resumed from a checkpoint at a stage's end, whose
        // solver has assembled nothing yet, books the same as the run that went on
        let mut taken = self.elastic_energy_of(&gone);
        if self.v.iter().any(|&x| x != 0.0) {
            self.assemble_step_parts();
        }
        let lp = &self.linear;
        if lp.m.len() == lp.tangent.element().nnz() && self.v.iter().any(|&x| x != 0.0) {
            let mut removed = vec![false; self.v.len()];
            for c in self
                .disc
                .covers
                .iter()
                .filter(|c| self.is_excavated(c.block))
            {
                for d in c.dof.into_iter().chain(c.terms.iter().copied()) {
                    if d != NO_DOF {
                        removed[d] = true;
                        removed[d + 1] = true;
                    }
                }
            }
            let kept: Vec<f64> = (0..self.v.len())
                .map(|d| if removed[d] { 0.0 } else { self.v[d] })
                .collect();
            let kinetic = |v: &[f64]| {
                let mut mv = vec![0.0; v.len()];
                super::step::sym_mul(lp.tangent.element(), &lp.m, v, &mut mv);
                0.5 * mv.iter().zip(v).map(|(a, b)| a * b).sum::<f64>()
            };
            taken += kinetic(&self.v) - kinetic(&kept);
        }
        for &ei in &gone {
            self.stress[ei] = [0.0; 3];
            for s in self.stress_nodes.iter_mut().skip(3 * ei).take(3) {
                *s = [0.0; 3];
            }
        }
        let map = self.disc.remove_blocks(&self.insitu.excavated);
        let n = self.disc.n_dofs;
        let remap = |old: &[f64]| {
            let mut new = vec![0.0; n];
            for (i, &x) in old.iter().enumerate() {
                if map[i] != NO_DOF {
                    new[map[i]] = x;
                }
            }
            new
        };
        self.u = remap(&self.u);
        self.v = remap(&self.v);
        self.last_du = remap(&self.last_du);
        self.f_load = remap(&self.f_load);
        let dof = |d: &mut usize| {
            if *d != NO_DOF {
                *d = map[*d];
            }
        };
        for p in self
            .penalties
            .iter_mut()
            .chain(self.penalty_base.iter_mut())
        {
            p.dofs.iter_mut().for_each(dof);
        }
        for g in &mut self.ghosts {
            g.dofs.iter_mut().for_each(dof);
        }
        self.bolts.renumber(&map);
        self.elem_dofs = ElementDofTable::new(&self.disc);
        self.contacts
            .set_removed_blocks(self.insitu.excavated.clone());
        self.contacts_current = false;
        self.build_element_pattern();
        self.solver_cm = None;
        self.solver_step = None;
        self.energy.excavated += taken;
    }

    /// ½ ∫ σᵀD⁻¹σ over the elements `elements` (their current polygons).
    fn elastic_energy_of(&self, elements: &[usize]) -> f64 {
        elements
            .iter()
            .map(|&ei| {
                let e = &self.disc.elements[ei];
                let d = &self.d_mats[self.model.blocks[e.block].material];
                match self.disc.basis {
                    CoverBasis::Constant => {
                        crate::geometry::moments::polygon_area(&e.polygon)
                            * crate::material::stress_energy_density(d, self.stress[ei])
                    }
                    _ => {
                        let s = &self.stress_nodes[3 * ei..3 * ei + 3];
                        let ww = crate::assembly::quadratic::weight_products(e);
                        let mut en = 0.0;
                        for m in 0..3 {
                            for k in 0..3 {
                                en += ww[m][k]
                                    * crate::material::stress_energy_product(d, s[m], s[k]);
                            }
                        }
                        en
                    }
                }
            })
            .sum()
    }
}
