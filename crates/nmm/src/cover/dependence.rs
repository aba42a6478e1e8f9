//! Linear dependence of the first-order cover basis, and the unknowns removed to end it.
//!
//! With first-order covers (u_k = U_k0 + U_k1 ξ_k + U_k2 η_k, [`super::basis`]) the
//! partition of unity reproduces every linear function, so Σ_k w_k (x − x_k) ≡ 0: on an
//! element with nodes at X_k, Y_k (units of h) the vectors
//!
//! U_k0 = 0, U_k1 = a + c Y_k, U_k2 = b − c X_k   (any a, b, c; per component)
//!
//! give u ≡ 0, and there are no others (the element's 9 scalar shape functions span the 6
//! quadratics). Elements that share two covers (an edge) share (a, b, c), so each
//! *edge-connected cluster* of a block's elements carries one triple; clusters that touch
//! only at a cover must agree there (2 equations per shared cover). The null space of a
//! block's stiffness and mass is the solution space of these equations: 3 per component
//! (6 per block) for a block whose elements are edge-connected, more for a block whose
//! pieces touch only at corners. Cholesky fails on the raw system.
//!
//! **The method: remove dependent unknowns, per block.** For the null space Z of a block
//! (dimension m per component), m higher-term unknowns whose values on Z are independent
//! are removed (fixed at zero) for each component. Any vector U differs from one with those
//! unknowns zero by a null vector, so the **approximation space is unchanged** (nothing of
//! the field is lost, exactly), and a vector of the reduced space with u ≡ 0 is a null
//! vector with those unknowns zero, i.e. zero: the reduced system is regular. The unknowns
//! are chosen by a pivoted Gram–Schmidt over the candidates' values on an orthonormal basis
//! of Z (the largest remaining component first, so the removed unknowns are far apart and
//! well determine the null space), in cover order on ties: deterministic.
//!
//! **Sliver covers.** A cover whose support weight ∫ w_c dΩ is below
//! [`super::stabilise::TINY_COVER`] h² (a block edge passing close to its node) has terms of
//! almost no norm; all of them are held by ghost ties ([`super::stabilise`]) that every
//! quadratic field and every null vector satisfy exactly (its constant term follows the root
//! element's field, its higher terms the linear extrapolation of the root covers' — the
//! higher terms of a quadratic field's and of a null vector's representation are affine in
//! the node position). So the ties change neither the null space nor the quadratic
//! reproduction, and the unknowns removed for the null space are taken at well-supported
//! covers (at a sliver's only when there are not enough others).

// index loops over small fixed blocks read as the formulas they implement
#![allow(clippy::needless_range_loop)]

use super::stabilise::{cover_weights, TINY_COVER};
use super::Discretisation;

/// The higher terms kept per cover and what was removed per block.
#[derive(Debug, Clone, PartialEq)]
pub struct Dependence {
    /// Per cover: whether its ξ and η terms keep their unknowns (covers of fixed blocks:
    /// `[false; 2]`).
    pub terms: Vec<[bool; 2]>,
    /// Per block: the dimension of the null space of the raw first-order basis (both
    /// components; 0 for a fixed block).
    pub nullity: Vec<usize>,
    /// Per block: higher-term unknowns removed for the null space (both components).
    pub dependent_removed: Vec<usize>,
}

struct UnionFind(Vec<usize>);
impl UnionFind {
    fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// The null space (columns, orthonormal) of the dense matrix `a` (rows of length `n`),
/// by Gauss–Jordan elimination with partial pivoting (pivots below `tol` count as zero).
fn null_space(a: &[Vec<f64>], n: usize, tol: f64) -> Vec<Vec<f64>> {
    let mut m: Vec<Vec<f64>> = a.to_vec();
    let mut pivots: Vec<usize> = Vec::new();
    let mut row = 0;
    for col in 0..n {
        if row >= m.len() {
            break;
        }
        let (best, val) = (row..m.len())
            .map(|r| (r, m[r][col].abs()))
            .fold((row, -1.0), |acc, x| if x.1 > acc.1 { x } else { acc });
        if val <= tol {
            continue;
        }
        m.swap(row, best);
        let p = m[row][col];
        for x in m[row].iter_mut() {
            *x /= p;
        }
        for r in 0..m.len() {
            if r != row && m[r][col] != 0.0 {
                let f = m[r][col];
                for c in 0..n {
                    m[r][c] -= f * m[row][c];
                }
            }
        }
        pivots.push(col);
        row += 1;
    }
    let free: Vec<usize> = (0..n).filter(|c| !pivots.contains(c)).collect();
    let mut basis: Vec<Vec<f64>> = free
        .iter()
        .map(|&f| {
            let mut v = vec![0.0; n];
            v[f] = 1.0;
            for (r, &pc) in pivots.iter().enumerate() {
                v[pc] = -m[r][f];
            }
            v
        })
        .collect();
    orthonormalise(&mut basis);
    basis
}

/// Modified Gram–Schmidt, twice (the vectors are independent).
fn orthonormalise(v: &mut [Vec<f64>]) {
    for _ in 0..2 {
        for i in 0..v.len() {
            for j in 0..i {
                let d: f64 = v[i].iter().zip(&v[j]).map(|(a, b)| a * b).sum();
                let vj = v[j].clone();
                for (x, y) in v[i].iter_mut().zip(&vj) {
                    *x -= d * y;
                }
            }
            let nrm = v[i].iter().map(|x| x * x).sum::<f64>().sqrt();
            v[i].iter_mut().for_each(|x| *x /= nrm);
        }
    }
}

/// The higher terms each cover keeps (see the module docs); `fixed[b]`: block b is fixed.
pub fn kept_terms(d: &Discretisation, fixed: &[bool]) -> Dependence {
    let nb = d.block_elements.len();
    let mut out = Dependence {
        terms: vec![[false; 2]; d.covers.len()],
        nullity: vec![0; nb],
        dependent_removed: vec![0; nb],
    };
    let h2 = d.mesh.h * d.mesh.h;
    let weights = cover_weights(d);
    let nx1 = d.mesh.nx + 1;
    for b in 0..nb {
        if fixed[b] {
            continue;
        }
        let elems = &d.block_elements[b];
        // clusters: elements sharing two covers
        let mut uf = UnionFind((0..elems.len()).collect());
        let mut by_pair: std::collections::HashMap<(usize, usize), usize> = Default::default();
        for (le, &e) in elems.iter().enumerate() {
            let c = d.elements[e].covers;
            for (i, j) in [(0, 1), (1, 2), (0, 2)] {
                let key = (c[i].min(c[j]), c[i].max(c[j]));
                match by_pair.get(&key) {
                    Some(&other) => uf.union(le, other),
                    None => {
                        by_pair.insert(key, le);
                    }
                }
            }
        }
        let mut cluster_id = vec![usize::MAX; elems.len()];
        let mut ncl = 0;
        for le in 0..elems.len() {
            let r = uf.find(le);
            if cluster_id[r] == usize::MAX {
                cluster_id[r] = ncl;
                ncl += 1;
            }
            cluster_id[le] = cluster_id[r];
        }
        // the block's covers (in index order) with their clusters
        let mut clusters_of: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for (le, &e) in elems.iter().enumerate() {
            for &c in &d.elements[e].covers {
                let v = clusters_of.entry(c).or_default();
                if !v.contains(&cluster_id[le]) {
                    v.push(cluster_id[le]);
                }
            }
        }
        let Some(&first) = clusters_of.keys().next() else {
            continue;
        };
        let origin = d.covers[first].node;
        let (i0, j0) = ((origin % nx1) as f64, (origin / nx1) as f64);
        let xy = |c: usize| {
            let n = d.covers[c].node;
            ((n % nx1) as f64 - i0, (n / nx1) as f64 - j0)
        };
        let np = 3 * ncl;
        // functional of term t (0: ξ, 1: η) of cover c seen from cluster k
        let functional = |c: usize, t: usize, k: usize| {
            let (x, y) = xy(c);
            let mut f = vec![0.0; np];
            if t == 0 {
                f[3 * k] = 1.0;
                f[3 * k + 2] = y;
            } else {
                f[3 * k + 1] = 1.0;
                f[3 * k + 2] = -x;
            }
            f
        };
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for (&c, cl) in &clusters_of {
            for &k in &cl[1..] {
                for t in 0..2 {
                    let mut f = functional(c, t, cl[0]);
                    for (x, y) in f.iter_mut().zip(functional(c, t, k)) {
                        *x -= y;
                    }
                    rows.push(f);
                }
            }
        }
        let tol = 1e-9;
        let z = null_space(&rows, np, tol);
        let m = z.len();
        out.nullity[b] = 2 * m;
        for &c in clusters_of.keys() {
            out.terms[c] = [true; 2];
        }
        if m == 0 {
            continue;
        }
        // candidates' values on the null space: well-supported covers first, then slivers
        let tiny = |c: usize| weights[c] < TINY_COVER * h2;
        let cands: Vec<(usize, usize, Vec<f64>)> = [false, true]
            .into_iter()
            .flat_map(|sliver| clusters_of.iter().filter(move |(&c, _)| tiny(c) == sliver))
            .flat_map(|(&c, cl)| (0..2).map(move |t| (c, t, cl[0])))
            .map(|(c, t, k)| {
                let f = functional(c, t, k);
                let v: Vec<f64> = z
                    .iter()
                    .map(|zc| zc.iter().zip(&f).map(|(a, b)| a * b).sum())
                    .collect();
                (c, t, v)
            })
            .collect();
        let mut chosen: Vec<Vec<f64>> = Vec::new();
        for _ in 0..m {
            let mut best: Option<(f64, usize, Vec<f64>)> = None;
            for (i, (c, _, v)) in cands.iter().enumerate() {
                if tiny(*c) && best.as_ref().is_some_and(|(bn, _, _)| *bn > 1e-3) {
                    break; // a well-supported cover determines the rest well enough
                }
                let mut r = v.clone();
                for q in &chosen {
                    let dq: f64 = r.iter().zip(q).map(|(a, b)| a * b).sum();
                    for (x, y) in r.iter_mut().zip(q) {
                        *x -= dq * y;
                    }
                }
                let nrm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
                if best
                    .as_ref()
                    .is_none_or(|(bn, _, _)| nrm > *bn * (1.0 + 1e-12))
                {
                    best = Some((nrm, i, r));
                }
            }
            let Some((nrm, i, mut r)) = best else { break };
            if nrm <= tol {
                break;
            }
            r.iter_mut().for_each(|x| *x /= nrm);
            chosen.push(r);
            let (c, t, _) = cands[i];
            out.terms[c][t] = false;
            out.dependent_removed[b] += 2;
        }
    }
    out
}
