//! # nmm — the Numerical Manifold Method in two dimensions
//!
//! Deformable blocks in contact, with Coulomb friction integrated implicitly by
//! return mapping inside a Newton-Raphson loop with the consistent (unsymmetric)
//! tangent, and Newmark (β = 0.5, γ = 1) time integration.
//!
//! Dependencies point one way:
//! `geometry ← cover ← assembly/contact ← simulation ← cli`.
//! See `ARCHITECTURE.md` for the map of the tree.

pub mod assembly;
pub mod bolt;
pub mod check;
pub mod contact;
pub mod cover;
pub mod fracture;
pub mod generate;
pub mod geometry;
pub mod material;
pub mod model;
pub mod motion;
pub mod output;
pub mod parallel;
pub mod picture;
pub mod simulation;
pub mod solver;
pub mod time;
pub mod verify;

/// Whether `a` and `b` hold the same values bit for bit (a changed value, even −0.0 for 0.0
/// or a NaN for itself, counts as a change): the test of "the same point" and "the same
/// matrix" where results must not depend on what a comparison of numbers would forgive.
pub(crate) fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}
