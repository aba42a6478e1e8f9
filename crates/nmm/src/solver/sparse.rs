//! Compressed sparse column storage with a fixed pattern.
//!
//! The pattern stores both triangles (the Cholesky factorisation reads only the
//! lower one); row indices are sorted and unique within each column.

use std::sync::Arc;

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SparsePattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

impl SparsePattern {
    /// The pattern of a matrix in which every dof of a group couples with every
    /// other dof of the same group (an element's dofs, a contact's dofs, ...).
    /// The diagonal is always present.
    pub fn from_groups<'a>(n: usize, groups: impl Iterator<Item = &'a [usize]>) -> Self {
        let diagonal = SparsePattern {
            n,
            col_ptr: (0..=n).collect(),
            row_idx: (0..n).collect(),
        };
        diagonal.with_groups(groups)
    }

    /// This pattern with every dof of each group coupled with every other of the same group:
    /// the same pattern as [`SparsePattern::from_groups`] of this pattern's groups and
    /// `groups`. Built column by column from the groups that hold the column, each new row
    /// marked once (a stamp per row), so only a column's distinct new rows are sorted: on
    /// a 40×40 brick wall's 15,000 contact couplings (24 unknowns each, 8.6 million pairs)
    /// 27 → 6 ms against sorting every pair.
    pub fn with_groups<'a>(&self, groups: impl Iterator<Item = &'a [usize]>) -> Self {
        let n = self.n;
        let groups: Vec<&[usize]> = groups.collect();
        // the groups that hold each column (compressed by column)
        let mut gptr = vec![0usize; n + 1];
        for g in &groups {
            for &c in *g {
                gptr[c + 1] += 1;
            }
        }
        for c in 0..n {
            gptr[c + 1] += gptr[c];
        }
        let mut gidx = vec![0u32; gptr[n]];
        let mut fill = gptr[..n].to_vec();
        for (i, g) in groups.iter().enumerate() {
            for &c in *g {
                gidx[fill[c]] = i as u32;
                fill[c] += 1;
            }
        }
        drop(fill);
        let mut stamp = vec![usize::MAX; n];
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(self.nnz() + self.nnz() / 2);
        let mut new_rows: Vec<usize> = Vec::new();
        col_ptr.push(0);
        for c in 0..n {
            let own = &self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]];
            for &r in own {
                stamp[r] = c;
            }
            new_rows.clear();
            for &gi in &gidx[gptr[c]..gptr[c + 1]] {
                for &r in groups[gi as usize] {
                    if stamp[r] != c {
                        stamp[r] = c;
                        new_rows.push(r);
                    }
                }
            }
            if new_rows.is_empty() {
                row_idx.extend_from_slice(own);
            } else {
                // merge the column's own (sorted) rows with its new ones
                new_rows.sort_unstable();
                let (mut i, mut j) = (0, 0);
                while i < own.len() || j < new_rows.len() {
                    if j == new_rows.len() || (i < own.len() && own[i] < new_rows[j]) {
                        row_idx.push(own[i]);
                        i += 1;
                    } else {
                        row_idx.push(new_rows[j]);
                        j += 1;
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
        SparsePattern {
            n,
            col_ptr,
            row_idx,
        }
    }

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Position of entry (row, col) in the value array.
    #[inline]
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[a..b].binary_search(&row).ok().map(|k| a + k)
    }
}

/// Values over a shared pattern.
#[derive(Debug, Clone)]
pub struct SparseMatrix {
    pub pattern: Arc<SparsePattern>,
    pub values: Vec<f64>,
}

impl SparseMatrix {
    pub fn zeros(pattern: Arc<SparsePattern>) -> Self {
        let nnz = pattern.nnz();
        SparseMatrix {
            pattern,
            values: vec![0.0; nnz],
        }
    }
    pub fn n(&self) -> usize {
        self.pattern.n
    }
    pub fn clear(&mut self) {
        self.values.iter_mut().for_each(|v| *v = 0.0);
    }
    /// A(row, col) += v. The entry must be in the pattern.
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, v: f64) {
        let s = self
            .pattern
            .slot(row, col)
            .unwrap_or_else(|| panic!("entry ({row}, {col}) is not in the sparsity pattern"));
        self.values[s] += v;
    }
    /// A[dofs, dofs] += k, with k row-major `dofs.len()²`.
    pub fn add_block(&mut self, dofs: &[usize], k: &[f64]) {
        let m = dofs.len();
        debug_assert_eq!(k.len(), m * m);
        for (j, &cj) in dofs.iter().enumerate() {
            let (a, b) = (self.pattern.col_ptr[cj], self.pattern.col_ptr[cj + 1]);
            let rows = &self.pattern.row_idx[a..b];
            for (i, &ri) in dofs.iter().enumerate() {
                let v = k[i * m + j];
                if v != 0.0 {
                    let s = a + rows
                        .binary_search(&ri)
                        .expect("entry is not in the sparsity pattern");
                    self.values[s] += v;
                }
            }
        }
    }
    /// y = A x.
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        let p = &self.pattern;
        for (c, &xc) in x.iter().enumerate() {
            if xc == 0.0 {
                continue;
            }
            for s in p.col_ptr[c]..p.col_ptr[c + 1] {
                y[p.row_idx[s]] += self.values[s] * xc;
            }
        }
    }
    /// Whether A equals its transpose to a relative tolerance.
    pub fn is_symmetric(&self, rel_tol: f64) -> bool {
        let p = &self.pattern;
        let scale = self.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for c in 0..p.n {
            for s in p.col_ptr[c]..p.col_ptr[c + 1] {
                let r = p.row_idx[s];
                if r <= c {
                    continue;
                }
                let t = p.slot(c, r).map(|k| self.values[k]).unwrap_or(0.0);
                if (self.values[s] - t).abs() > rel_tol * scale {
                    return false;
                }
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pattern_from_groups_is_sorted_unique_and_symmetric() {
        let g1 = [0usize, 2, 3];
        let g2 = [3usize, 4];
        let p = SparsePattern::from_groups(5, [&g1[..], &g2[..]].into_iter());
        assert_eq!(p.col_ptr, vec![0, 3, 4, 7, 11, 13]);
        for c in 0..5 {
            let col = &p.row_idx[p.col_ptr[c]..p.col_ptr[c + 1]];
            assert!(col.windows(2).all(|w| w[0] < w[1]));
            for &r in col {
                assert!(p.slot(c, r).is_some());
            }
        }
        assert!(p.slot(1, 4).is_none());
    }

    #[test]
    fn with_groups_is_from_groups_of_both() {
        let base: Vec<Vec<usize>> = vec![vec![0, 2, 3], vec![3, 4], vec![7, 1]];
        let more: Vec<Vec<usize>> = vec![vec![4, 1, 6], vec![0, 7], vec![2, 3], vec![5]];
        let p = SparsePattern::from_groups(8, base.iter().map(|g| &g[..]));
        let both = SparsePattern::from_groups(8, base.iter().chain(&more).map(|g| &g[..]));
        assert_eq!(p.with_groups(more.iter().map(|g| &g[..])), both);
        assert_eq!(p.with_groups(std::iter::empty()), p);
    }

    #[test]
    fn add_block_and_mul_vec_match_dense() {
        let g = [1usize, 3];
        let p = Arc::new(SparsePattern::from_groups(4, std::iter::once(&g[..])));
        let mut a = SparseMatrix::zeros(p);
        a.add_block(&g, &[2.0, -1.0, -1.0, 3.0]);
        a.add(0, 0, 5.0);
        let mut y = vec![0.0; 4];
        a.mul_vec(&[1.0, 2.0, 3.0, 4.0], &mut y);
        assert_eq!(y, vec![5.0, 0.0, 0.0, 10.0]);
        assert!(a.is_symmetric(1e-14));
    }
}
