//! Global scatter: element and contact contributions into a fixed sparse pattern.
//!
//! Unknowns of covers that belong to fixed blocks do not exist; they appear in
//! local dof lists as [`NO_DOF`] and are skipped (their displacement is zero:
//! a fixed block is held in the frame of the base).

pub use crate::cover::basis::{element_dofs, NO_DOF};
use crate::solver::SparsePattern;

/// The slots in `pattern` of every entry (row, col) of a dof group, row-major over
/// `dofs` (`dofs.len()²` of them), `u32::MAX` where either dof is [`NO_DOF`]. Every coupling
/// of the group must be in the pattern.
pub fn group_slots(pattern: &SparsePattern, dofs: &[usize], out: &mut [u32]) {
    let m = dofs.len();
    for (j, &col) in dofs.iter().enumerate() {
        for (i, &row) in dofs.iter().enumerate() {
            out[i * m + j] = if row == NO_DOF || col == NO_DOF {
                u32::MAX
            } else {
                pattern
                    .slot(row, col)
                    .expect("a coupling of the group is missing from the pattern")
                    as u32
            };
        }
    }
}

/// values[slots] += local: the ordered scatter of one local block (entries at `u32::MAX`
/// are skipped). Local blocks may be computed in any order, on any thread; scattering them
/// in a fixed order makes the sums the same whatever the thread count.
#[inline]
pub fn scatter(values: &mut [f64], slots: &[u32], local: &[f64]) {
    for (&s, &v) in slots.iter().zip(local) {
        if s != u32::MAX {
            values[s as usize] += v;
        }
    }
}

/// Gather the local values of a global vector (zero for [`NO_DOF`]).
pub fn gather<const N: usize>(x: &[f64], dofs: &[usize; N]) -> [f64; N] {
    let mut out = [0.0; N];
    for (o, &d) in out.iter_mut().zip(dofs) {
        if d != NO_DOF {
            *o = x[d];
        }
    }
    out
}
