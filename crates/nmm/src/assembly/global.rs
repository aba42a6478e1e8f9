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

/// No place in a group's key ([`scatter_through`]).
pub const NO_PLACE: u8 = u8::MAX;

/// values[slots] += local for a block over unknowns that are a part of a group's: `places`
/// gives each of the block's unknowns its place in the group (or [`NO_PLACE`]: skipped),
/// `slots` the group's slots (m² row-major, m = `places.len()`, as [`group_slots`]). Groups
/// shared by several blocks (contacts between the same two elements) keep one set of slots.
#[inline]
pub fn scatter_through(values: &mut [f64], slots: &[u32], places: &[u8], local: &[f64]) {
    // (into the whole, no slot is another part's)
    debug_assert!(slots
        .iter()
        .all(|&s| s == u32::MAX || (s as usize) < values.len()));
    scatter_through_part(values, 0, slots, places, local);
}

/// [`scatter_through`] into one part of the values: `part` holds the slots `lo ..
/// lo + part.len()` of the whole, and the block's entries in other slots (another part's)
/// are skipped. Every slot a part holds receives the same sums in the same order as from
/// [`scatter_through`] into the whole.
#[inline]
pub fn scatter_through_part(
    part: &mut [f64],
    lo: usize,
    slots: &[u32],
    places: &[u8],
    local: &[f64],
) {
    let m = places.len();
    let len = part.len();
    for (i, &pi) in places.iter().enumerate() {
        if pi == NO_PLACE {
            continue;
        }
        let row = &slots[pi as usize * m..(pi as usize + 1) * m];
        let lrow = &local[i * m..(i + 1) * m];
        for (&pj, &v) in places.iter().zip(lrow) {
            if pj == NO_PLACE {
                continue;
            }
            let s = row[pj as usize];
            // (u32::MAX, no slot, is beyond every part)
            let o = (s as usize).wrapping_sub(lo);
            if s != u32::MAX && o < len {
                part[o] += v;
            }
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

/// Gather the local values of a global vector into `out` (zero for [`NO_DOF`]; `out` as
/// long as `dofs`).
#[inline]
pub fn gather_into(x: &[f64], dofs: &[usize], out: &mut [f64]) {
    for (o, &d) in out.iter_mut().zip(dofs) {
        *o = if d != NO_DOF { x[d] } else { 0.0 };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two groups {0, 1} and {2, 3} of four dofs: columns 0..3 hold rows {0,1}, {0,1},
    /// {2,3}, {2,3}, so the slots are (0,0)=0, (1,0)=1, (0,1)=2, (1,1)=3, (2,2)=4, (3,2)=5,
    /// (2,3)=6, (3,3)=7.
    fn pattern() -> SparsePattern {
        let groups: [&[usize]; 2] = [&[0, 1], &[2, 3]];
        let p = SparsePattern::from_groups(4, groups.into_iter());
        assert_eq!(p.col_ptr, [0, 2, 4, 6, 8]);
        assert_eq!(p.row_idx, [0, 1, 0, 1, 2, 3, 2, 3]);
        p
    }

    const X: u32 = u32::MAX;

    #[test]
    fn group_slots_are_the_pattern_positions_row_major_with_no_dof_skipped() {
        let p = pattern();
        let mut out = [0u32; 9];
        // rows and columns in the order of the group: dof 1, a fixed cover, dof 0
        group_slots(&p, &[1, NO_DOF, 0], &mut out);
        assert_eq!(out, [3, X, 1, X, X, X, 2, X, 0]);
        let mut out = [0u32; 4];
        group_slots(&p, &[3, 2], &mut out);
        assert_eq!(out, [7, 5, 6, 4]);
    }

    #[test]
    #[should_panic(expected = "missing from the pattern")]
    fn a_coupling_missing_from_the_pattern_panics() {
        let mut out = [0u32; 4];
        // 0 and 2 are in different groups: (0, 2) is not in the pattern
        group_slots(&pattern(), &[0, 2], &mut out);
    }

    #[test]
    fn scatter_adds_a_local_block_at_its_slots_and_skips_no_dof_entries() {
        let p = pattern();
        let mut slots = [0u32; 9];
        group_slots(&p, &[1, NO_DOF, 0], &mut slots);
        let local = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
        let mut values = vec![0.0; p.nnz()];
        values[4] = 0.5;
        scatter(&mut values, &slots, &local);
        // (1,1) += 1, (1,0) += 3, (0,1) += 7, (0,0) += 9; the NO_DOF row and column dropped
        assert_eq!(values, [9.0, 3.0, 7.0, 1.0, 0.5, 0.0, 0.0, 0.0]);
        // scattering adds (a second block on the same dofs accumulates)
        scatter(&mut values, &slots, &local);
        assert_eq!(values, [18.0, 6.0, 14.0, 2.0, 0.5, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn gather_reads_the_dofs_and_gives_zero_for_no_dof() {
        let x = [10.0, 20.0, 30.0, 40.0];
        assert_eq!(gather(&x, &[3, NO_DOF, 0]), [40.0, 0.0, 10.0]);
        assert_eq!(gather(&x, &[NO_DOF; 2]), [0.0, 0.0]);
    }
}
