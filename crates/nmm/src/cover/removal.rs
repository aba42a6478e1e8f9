//! Removing blocks from a discretisation (an excavation): their covers lose their
//! unknowns, as the covers of a fixed block have none, and the unknowns of the other
//! covers are numbered again in the same order (covers block by block, node by node,
//! each cover's constant term then its higher terms), so that the system keeps no row
//! for a removed block and the bandwidth of the others is what it was.

use super::basis::NO_DOF;
use super::Discretisation;

impl Discretisation {
    /// Remove the unknowns of the covers of the blocks with `removed[b]`; returns the new
    /// index of every old unknown ([`NO_DOF`] for a removed one). Elements and boundaries
    /// stay (an element without unknowns neither moves nor loads, as a fixed block's).
    pub fn remove_blocks(&mut self, removed: &[bool]) -> Vec<usize> {
        let mut map = vec![NO_DOF; self.n_dofs];
        let mut next = 0;
        for c in &mut self.covers {
            let Some(d) = c.dof else { continue };
            if removed.get(c.block).copied().unwrap_or(false) {
                c.dof = None;
                c.terms.clear();
                continue;
            }
            map[d] = next;
            map[d + 1] = next + 1;
            c.dof = Some(next);
            next += 2;
            for t in c.terms.iter_mut().filter(|t| **t != NO_DOF) {
                map[*t] = next;
                map[*t + 1] = next + 1;
                *t = next;
                next += 2;
            }
        }
        self.n_dofs = next;
        map
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cover::{discretise_with, CoverBasis};

    #[test]
    fn the_other_blocks_keep_their_order() {
        let a = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let b = vec![[0.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
        let c = vec![[0.0, 2.0], [1.0, 2.0], [1.0, 3.0], [0.0, 3.0]];
        for basis in [CoverBasis::Constant, CoverBasis::Linear] {
            let mut d = discretise_with(
                &[(a.clone(), false), (b.clone(), false), (c.clone(), false)],
                0.3,
                None,
                basis,
            )
            .unwrap();
            let before = d.clone();
            let map = d.remove_blocks(&[false, true, false]);
            let kept = |blk: usize| {
                before
                    .covers
                    .iter()
                    .filter(|c| c.block == blk)
                    .map(|c| 2 + 2 * c.terms.iter().filter(|&&t| t != NO_DOF).count())
                    .sum::<usize>()
            };
            assert_eq!(d.n_dofs, kept(0) + kept(2));
            for (old, new) in before.covers.iter().zip(&d.covers) {
                if old.block == 1 {
                    assert!(new.dof.is_none() && new.terms.is_empty());
                    assert_eq!(map[old.dof.unwrap()], NO_DOF);
                } else {
                    assert_eq!(new.dof, Some(map[old.dof.unwrap()]));
                    for (t0, t1) in old.terms.iter().zip(&new.terms) {
                        if *t0 != NO_DOF {
                            assert_eq!(*t1, map[*t0]);
                        }
                    }
                }
            }
            // block 0 unchanged, block 2 shifted down past block 1's unknowns
            let first = |dd: &Discretisation, blk: usize| {
                dd.covers
                    .iter()
                    .find(|c| c.block == blk)
                    .unwrap()
                    .dof
                    .unwrap()
            };
            assert_eq!(first(&d, 0), 0);
            assert_eq!(first(&d, 2), kept(0));
            let mut used: Vec<usize> = map.iter().copied().filter(|&m| m != NO_DOF).collect();
            used.sort_unstable();
            assert_eq!(used, (0..d.n_dofs).collect::<Vec<_>>());
        }
    }
}
