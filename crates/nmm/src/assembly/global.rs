//! Global scatter: element and contact contributions into a fixed sparse pattern.
//!
//! Unknowns of covers that belong to fixed blocks do not exist; they appear in
//! local dof lists as [`NO_DOF`] and are skipped (their displacement is zero:
//! a fixed block is held in the frame of the base).

pub use crate::cover::basis::{element_dofs, NO_DOF};
use crate::solver::{SparseMatrix, SparsePattern};

/// The free unknowns of a local dof list.
pub fn free(dofs: &[usize]) -> Vec<usize> {
    dofs.iter().copied().filter(|&d| d != NO_DOF).collect()
}

/// Pattern of all couplings: every group's free unknowns couple with each other.
pub fn pattern(n: usize, groups: &[Vec<usize>]) -> SparsePattern {
    SparsePattern::from_groups(n, groups.iter().map(|g| g.as_slice()))
}

/// A[dofs, dofs] += k (row-major `m × m`, `m = dofs.len()`), skipping [`NO_DOF`].
pub fn scatter_matrix(a: &mut SparseMatrix, dofs: &[usize], k: &[f64]) {
    let m = dofs.len();
    for (i, &ri) in dofs.iter().enumerate() {
        if ri == NO_DOF {
            continue;
        }
        for (j, &cj) in dofs.iter().enumerate() {
            if cj == NO_DOF {
                continue;
            }
            let v = k[i * m + j];
            if v != 0.0 {
                a.add(ri, cj, v);
            }
        }
    }
}

/// f[dofs] += v, skipping [`NO_DOF`].
pub fn scatter_vector(f: &mut [f64], dofs: &[usize], v: &[f64]) {
    for (&d, &x) in dofs.iter().zip(v) {
        if d != NO_DOF {
            f[d] += x;
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
