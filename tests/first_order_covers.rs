//! First-order covers (`[cover] order = 1`, issue 16): the basis, its linear dependence and
//! how it is removed, patch tests, and the cantilever against its closed forms.
//!
//! Tolerances, and why each test can fail:
//! * basis identities (partition of unity, U_k0 = the node's displacement, quadratic
//!   reproduction): 1e-13 relative — sums of a few O(1) products; a wrong shape or layout
//!   is O(1) off.
//! * nullity: eigenvalues of the diagonally scaled matrices below 1e-10 count as zero; the
//!   exact null vectors give ~1e-15, the nearest regular ones (sliver cuts) stay above 1e-8
//!   (printed), so the count is robust; a missing or extra removal changes it by ≥ 1.
//! * patch tests: 1e-10 relative — the exact field is in the approximation space and every
//!   integral is exact, so only round-off (a condition number of ~1e4 × 1e-16) remains; an
//!   inexact integral (degree too low) or a wrong tie is ≥ 1e-6 off.
//! * cantilever: within 0.5% of Timoshenko's 4.024 mm (the acceptance figure); order 0 is
//!   −47.6%, so an order-1 run that falls back to constant covers fails by 47%.

#![allow(clippy::needless_range_loop)] // dense matrices indexed as in the formulas

use nmm::cover::basis::{CoverBasis, ElementDofTable, MAX_ELEMENT_DOFS, MAX_ELEMENT_SHAPES};
use nmm::cover::{barycentric, discretise_with, Discretisation};
use nmm::geometry::Vec2;
use nmm::model::parse_model;
use nmm::simulation::Simulation;
use std::path::Path;

fn rotate(poly: &[Vec2], deg: f64, shift: Vec2) -> Vec<Vec2> {
    let (s, c) = deg.to_radians().sin_cos();
    poly.iter()
        .map(|p| {
            [
                c * p[0] - s * p[1] + shift[0],
                s * p[0] + c * p[1] + shift[1],
            ]
        })
        .collect()
}

/// A pentagon rotated by 13°: every edge cuts the mesh at arbitrary places (cut cells).
fn cut_block() -> Vec<Vec2> {
    rotate(
        &[[0.0, 0.0], [1.2, 0.0], [1.3, 0.7], [0.6, 1.1], [-0.1, 0.6]],
        13.0,
        [0.031, 0.017],
    )
}

/// A rectangle whose top edge passes 1e-3 h above a mesh line: covers of tiny support
/// (slivers) along it, held by ghost ties.
fn sliver_block(h: f64, origin: Vec2) -> Vec<Vec2> {
    let top = origin[1] + 5.0 * h + 1e-3 * h;
    let right = origin[0] + 6.0 * h + 2e-3 * h;
    vec![
        [origin[0] + 0.37 * h, origin[1] + 0.41 * h],
        [right, origin[1] + 0.41 * h],
        [right, top],
        [origin[0] + 0.37 * h, top],
    ]
}

fn disc(poly: Vec<Vec2>, h: f64, basis: CoverBasis) -> Discretisation {
    discretise_with(&[(poly, false)], h, None, basis).unwrap()
}

/// The quadratic field q(x) = (q_x, q_y) with coefficients of 1, x, y, x², xy, y².
#[derive(Clone, Copy)]
struct Quadratic([[f64; 6]; 2]);

impl Quadratic {
    fn value(&self, x: Vec2) -> Vec2 {
        let m = [1.0, x[0], x[1], x[0] * x[0], x[0] * x[1], x[1] * x[1]];
        self.0.map(|c| (0..6).map(|i| c[i] * m[i]).sum())
    }
    /// ∂q_c/∂x_j at x.
    fn grad(&self, x: Vec2) -> [Vec2; 2] {
        self.0.map(|c| {
            [
                c[1] + 2.0 * c[3] * x[0] + c[4] * x[1],
                c[2] + c[4] * x[0] + 2.0 * c[5] * x[1],
            ]
        })
    }
    /// The exact representation in the first-order basis: U_k0 = q(x_k), (U_k1, U_k2) =
    /// h ∇q(x_k / 2) (then Σ_k w_k u_k(x) = q(x) exactly: see cover/dependence.rs).
    fn cover_terms(&self, node: Vec2, h: f64) -> [Vec2; 3] {
        let v = self.value(node);
        let g = self.grad([0.5 * node[0], 0.5 * node[1]]);
        [v, [h * g[0][0], h * g[1][0]], [h * g[0][1], h * g[1][1]]]
    }
}

/// The global vector of the field's exact representation (terms removed for linear
/// dependence are set by a null vector to zero: here the solve is not involved, so the
/// vector is built on the raw numbering `all_terms`).
fn all_terms(d: &Discretisation) -> Discretisation {
    let mut raw = d.clone();
    let mut next = 0;
    for c in &mut raw.covers {
        c.dof = Some(next);
        c.terms = vec![next + 2, next + 4];
        next += 6;
    }
    raw.n_dofs = next;
    raw
}

#[test]
fn partition_of_unity_nodal_values_and_quadratic_reproduction() {
    let h = 0.3;
    let d = all_terms(&disc(cut_block(), h, CoverBasis::Linear));
    let b = d.basis;
    assert_eq!((b.cover_dofs(), b.element_dofs()), (6, 18));
    let q = Quadratic([
        [0.3, -1.0, 2.0, 0.7, -0.4, 1.1],
        [-0.2, 0.5, 0.25, -0.9, 1.3, 0.6],
    ]);
    let mut u = vec![0.0; d.n_dofs];
    for c in &d.covers {
        let x = d.mesh.node(c.node);
        let t = q.cover_terms(x, h);
        let dofs = [c.dof.unwrap(), c.terms[0], c.terms[1]];
        for j in 0..3 {
            u[dofs[j]] = t[j][0];
            u[dofs[j] + 1] = t[j][1];
        }
    }
    let table = ElementDofTable::new(&d);
    let mut n = [0.0; MAX_ELEMENT_SHAPES];
    let mut worst: f64 = 0.0;
    for (ei, e) in d.elements.iter().enumerate() {
        let mut ue = [0.0; MAX_ELEMENT_DOFS];
        for (o, &g) in ue.iter_mut().zip(table.of(ei)) {
            *o = u[g];
        }
        for w in [
            [0.2, 0.3, 0.5],
            [0.6, 0.1, 0.3],
            [1.0 / 3.0; 3],
            [-0.2, 0.7, 0.5],
        ] {
            b.shapes(e, &w, &mut n);
            // the weights are the constant terms' shapes: they sum to 1
            let pu: f64 = (0..3).map(|k| n[3 * k]).sum();
            assert!((pu - 1.0).abs() < 1e-14, "Σ w = {pu}");
            // quadratic reproduction: Σ_a N_a U_a = q(x)
            let x = [0, 1].map(|c| (0..3).map(|k| w[k] * e.nodes[k][c]).sum::<f64>());
            let (got, want) = (b.interpolate(e, &w, &ue[..18]), q.value(x));
            for c in 0..2 {
                worst = worst.max((got[c] - want[c]).abs() / (1.0 + want[c].abs()));
            }
        }
        // U_k0 is the displacement at node k: shapes at w = e_k
        for k in 0..3 {
            let mut w = [0.0; 3];
            w[k] = 1.0;
            let got = b.interpolate(e, &w, &ue[..18]);
            assert_eq!(got, [ue[6 * k], ue[6 * k + 1]], "element {ei} node {k}");
            b.shapes(e, &w, &mut n);
            for (a, &na) in n[..9].iter().enumerate() {
                assert_eq!(na, if a == 3 * k { 1.0 } else { 0.0 });
            }
        }
    }
    assert!(worst < 1e-13, "quadratic reproduction off by {worst:e}");
}

/// Eigenvalues of a symmetric matrix (cyclic Jacobi).
fn eigenvalues(mut a: Vec<Vec<f64>>) -> Vec<f64> {
    let n = a.len();
    for _sweep in 0..60 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        if off < 1e-30 {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..n {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..n {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
            }
        }
    }
    let mut e: Vec<f64> = (0..n).map(|i| a[i][i]).collect();
    e.sort_by(f64::total_cmp);
    e
}

/// Dense stiffness and mass of a discretisation (the basis's element records).
fn dense_k_m(d: &Discretisation) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let b = d.basis;
    let (nd, n) = (b.element_dofs(), d.n_dofs);
    let dm = nmm::material::elasticity_matrix(1.0e9, 0.25, nmm::model::Plane::Strain);
    let table = ElementDofTable::new(d);
    let (mut k, mut m) = (vec![vec![0.0; n]; n], vec![vec![0.0; n]; n]);
    let mut rec = vec![0.0; b.record_len()];
    for (ei, e) in d.elements.iter().enumerate() {
        let area = nmm::geometry::moments::polygon_area(&e.polygon);
        b.element_local(e, 1000.0, area, &dm, &[[0.0; 3]; 3], &mut rec);
        let dofs = table.of(ei);
        for i in 0..nd {
            for j in 0..nd {
                if dofs[i] != usize::MAX && dofs[j] != usize::MAX {
                    k[dofs[i]][dofs[j]] += rec[i * nd + j];
                    m[dofs[i]][dofs[j]] += rec[nd * nd + i * nd + j];
                }
            }
        }
    }
    (k, m)
}

/// Eigenvalues of D^{-1/2} A D^{-1/2} (D = diag A) below 1e-10, and the smallest above.
fn nullity(a: &[Vec<f64>]) -> (usize, f64) {
    let s: Vec<f64> = (0..a.len()).map(|i| 1.0 / a[i][i].sqrt()).collect();
    let scaled = (0..a.len())
        .map(|i| (0..a.len()).map(|j| a[i][j] * s[i] * s[j]).collect())
        .collect();
    let e = eigenvalues(scaled);
    let zero = e.iter().filter(|&&x| x < 1e-10).count();
    (zero, e.get(zero).copied().unwrap_or(f64::NAN))
}

#[test]
fn linear_dependence_is_six_per_block_and_removed() {
    let h = 0.25;
    let mesh_origin = [-0.125, -0.125];
    let cases: Vec<(&str, Vec<Vec2>, f64)> = vec![
        (
            "block",
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.75], [0.0, 0.75]],
            h,
        ),
        ("cut block", cut_block(), 0.3),
        ("sliver block", sliver_block(h, mesh_origin), h),
    ];
    for (name, poly, h) in cases {
        let d = if name == "sliver block" {
            let bb = nmm::geometry::Aabb::of_points(&poly);
            let mesh =
                nmm::cover::MathMesh::covering_through(&bb, h, 1 << 20, Some(mesh_origin)).unwrap();
            nmm::cover::discretise_on_mesh_with(&[(poly, false)], mesh, CoverBasis::Linear).unwrap()
        } else {
            disc(poly, h, CoverBasis::Linear)
        };
        let dep = nmm::cover::dependence::kept_terms(&d, &[false]);
        let raw = all_terms(&d);
        let (k0, m0) = dense_k_m(&raw);
        let (k1, m1) = dense_k_m(&d);
        let ((nk0, _), (nm0, _)) = (nullity(&k0), nullity(&m0));
        let ((nk1, lk1), (nm1, lm1)) = (nullity(&k1), nullity(&m1));
        let slivers = nmm::cover::stabilise::ghost_ties(&d).len();
        eprintln!(
            "{name}: {} covers ({slivers} slivers), {} unknowns raw, {} kept; nullity of M {nm0} -> {nm1} \
             (smallest scaled eigenvalue after {lm1:.1e}), of K {nk0} -> {nk1} (next {lk1:.1e})",
            d.covers.len(),
            raw.n_dofs,
            d.n_dofs
        );
        if name == "sliver block" {
            assert!(slivers > 0, "the sliver block has sliver covers");
        }
        // the raw basis: 3 null vectors per component; K has the 3 rigid modes besides
        assert_eq!((nm0, nk0), (6, 9), "{name} raw");
        assert_eq!(dep.nullity, vec![6], "{name}: the predicted null space");
        assert_eq!(raw.n_dofs - d.n_dofs, 6, "{name}: six unknowns removed");
        // after: the mass is regular, the stiffness keeps only the rigid modes
        assert_eq!((nm1, nk1), (0, 3), "{name} after");
    }
}

fn material(e: f64, nu: f64, rho: f64, plane: &str) -> String {
    format!(
        "[[material]]\nname = \"m\"\ndensity = {rho:?}\nyoung = {e:?}\npoisson = {nu:?}\nplane = \"{plane}\"\n"
    )
}

fn pt(x: Vec2) -> String {
    format!("[{:?}, {:?}]", x[0], x[1])
}

fn points(p: &[Vec2]) -> String {
    let v: Vec<String> = p
        .iter()
        .map(|x| format!("[{:?}, {:?}]", x[0], x[1]))
        .collect();
    format!("[{}]", v.join(", "))
}

/// Nodal forces of a boundary traction t(x, n) on block 0 of `sim` (on its initial
/// geometry), integrated against the shape functions by 5-point Gauss–Legendre (exact to
/// degree 9: a quadratic shape times a traction of degree ≤ 7).
fn traction_vector(sim: &Simulation, t: impl Fn(Vec2, Vec2) -> Vec2) -> Vec<f64> {
    const GL5: [(f64, f64); 5] = [
        (0.046_910_077_030_668, 0.118_463_442_528_095),
        (0.230_765_344_947_158, 0.239_314_335_249_683),
        (0.5, 0.284_444_444_444_444_4),
        (0.769_234_655_052_842, 0.239_314_335_249_683),
        (0.953_089_922_969_332, 0.118_463_442_528_095),
    ];
    let d = &sim.disc;
    let b = d.basis;
    let table = ElementDofTable::new(d);
    let mut f = vec![0.0; d.n_dofs];
    let bd = &d.boundaries[0];
    let m = bd.vertices.len();
    let mut n = [0.0; MAX_ELEMENT_SHAPES];
    for i in 0..m {
        let (pa, pb) = (bd.vertices[i].x0, bd.vertices[(i + 1) % m].x0);
        let e = &d.elements[bd.segment_elements[i]];
        let dofs = table.of(bd.segment_elements[i]);
        let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
        let normal = [(pb[1] - pa[1]) / len, -(pb[0] - pa[0]) / len];
        for (s, wq) in GL5 {
            let x = [pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])];
            let w = barycentric(&e.nodes, x);
            b.shapes(e, &w, &mut n);
            let tv = t(x, normal);
            for a in 0..b.element_shapes() {
                for c in 0..2 {
                    if dofs[2 * a + c] != usize::MAX {
                        f[dofs[2 * a + c]] += len * wq * n[a] * tv[c];
                    }
                }
            }
        }
    }
    f
}

/// Material points at every element vertex and centroid of the initial geometry.
fn probes(d: &Discretisation) -> Vec<(usize, [f64; 3], Vec2)> {
    let mut out = Vec::new();
    for (ei, e) in d.elements.iter().enumerate() {
        let c = nmm::geometry::moments::polygon_moments(&e.polygon, e.polygon[0]).centroid();
        for x in e.polygon.iter().copied().chain([c]) {
            out.push((ei, e.weights(x), x));
        }
    }
    out
}

/// A static patch test on block `poly`: displacement field `u` with stress `sigma(x)` and
/// body force per mass `g` (as gravity), exact tractions on the whole boundary, the rigid
/// modes held at two vertices by point springs with the exact values. Returns the largest
/// displacement error at the probes relative to the largest displacement.
fn patch_error(
    poly: &[Vec2],
    h: f64,
    order: usize,
    u: impl Fn(Vec2) -> Vec2,
    sigma: impl Fn(Vec2) -> [f64; 3],
    g: Vec2,
) -> f64 {
    let (pa, pb) = (poly[0], poly[1]);
    let (ua, ub) = (u(pa), u(pb));
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\ngravity = [{:?}, {:?}]\nconstraint_penalty = 100.0\n\
         [cover]\nsize = {h:?}\norder = {order}\n{}\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = {}\n\
         [[constraint]]\nblock = \"b\"\npoint = {}\nux = {:?}\nuy = {:?}\n\
         [[constraint]]\nblock = \"b\"\npoint = {}\nuy = {:?}\n",
        g[0],
        g[1],
        material(1.0e9, 0.25, 2000.0, "strain"),
        points(poly),
        pt(pa),
        ua[0],
        ua[1],
        pt(pb),
        ub[1],
    );
    let model = parse_model(&text, Path::new(".")).unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let f = traction_vector(&sim, |x, n| {
        let s = sigma(x);
        [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]]
    });
    sim.add_load_vector(&f);
    let pr = probes(&sim.disc);
    let d0 = sim.disc.clone();
    sim.advance().unwrap();
    let (mut err, mut umax): (f64, f64) = (0.0, 0.0);
    for (e, w, x) in pr {
        let got = d0.displacement_at(
            &nmm::cover::MaterialPoint {
                element: e,
                weights: w,
            },
            &sim.u,
        );
        let want = u(x);
        for c in 0..2 {
            err = err.max((got[c] - want[c]).abs());
            umax = umax.max(want[c].abs());
        }
    }
    err / umax
}

/// Plane strain, E = 1 GPa, ν = 0.25: σ = D ε.
fn hooke(eps: [f64; 3]) -> [f64; 3] {
    let d = nmm::material::elasticity_matrix(1.0e9, 0.25, nmm::model::Plane::Strain);
    nmm::material::stress(&d, eps)
}

#[test]
fn patch_tests_linear_at_orders_0_and_1_quadratic_at_order_1() {
    let grad = [[2e-4, -1e-4], [0.5e-4, -3e-4]];
    let lin = move |x: Vec2| {
        [
            1e-4 + grad[0][0] * x[0] + grad[0][1] * x[1],
            -2e-4 + grad[1][0] * x[0] + grad[1][1] * x[1],
        ]
    };
    let lin_sigma = move |_: Vec2| hooke([grad[0][0], grad[1][1], grad[0][1] + grad[1][0]]);
    let q = Quadratic([
        [1e-4, 2e-4, -1e-4, 3e-4, -2e-4, 1e-4],
        [-1e-4, 0.5e-4, 1e-4, -1e-4, 2.5e-4, -2e-4],
    ]);
    let qs = move |x: Vec2| {
        let g = q.grad(x);
        hooke([g[0][0], g[1][1], g[0][1] + g[1][0]])
    };
    // div σ is constant: from the stress at two points per direction
    let div = {
        let (s0, sx, sy) = (qs([0.0, 0.0]), qs([1.0, 0.0]), qs([0.0, 1.0]));
        [sx[0] - s0[0] + sy[2] - s0[2], sx[2] - s0[2] + sy[1] - s0[1]]
    };
    let g = [-div[0] / 2000.0, -div[1] / 2000.0];
    let mesh_origin = [-0.125, -0.125];
    for (name, poly, h) in [
        ("rotated cut block", cut_block(), 0.23),
        ("rotated cut block, fine", cut_block(), 0.11),
        ("sliver block", sliver_block(0.25, mesh_origin), 0.25),
    ] {
        for order in [0, 1] {
            let e = patch_error(&poly, h, order, lin, lin_sigma, [0.0, 0.0]);
            eprintln!("{name} h {h}: linear field at order {order}: error {e:.1e}");
            assert!(e < 1e-10, "{name} order {order}: {e:e}");
        }
        let e = patch_error(&poly, h, 1, |x| q.value(x), qs, g);
        eprintln!("{name} h {h}: quadratic field with its body force at order 1: error {e:.1e}");
        assert!(e < 1e-10, "{name} quadratic: {e:e}");
        // and order 0 cannot: the test discriminates
        let e0 = patch_error(&poly, h, 0, |x| q.value(x), qs, g);
        eprintln!("   (order 0: {e0:.1e})");
        assert!(e0 > 1e-4);
    }
}

/// The cantilever of the issue: 10 m × 1 m, E 1 GPa, ν 0, plane stress, left edge held by
/// edge springs, 1 kN of shear on the free end; Timoshenko's tip deflection 4.024 mm.
fn cantilever_tip(h: f64, order: usize) -> (f64, usize) {
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\n[cover]\nsize = {h:?}\norder = {order}\n{}\
         [[block]]\nname = \"beam\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0]]\n\
         [[load]]\nblock = \"beam\"\nedge = [[10.0, 0.0], [10.0, 1.0]]\ntraction = [0.0, -1000.0]\n\
         [[constraint]]\nblock = \"beam\"\nedge = [[0.0, 0.0], [0.0, 1.0]]\nux = 0.0\nuy = 0.0\n\
         [[monitor]]\nname = \"tip\"\npoint = [10.0, 0.5]\n",
        material(1.0e9, 0.0, 1000.0, "stress")
    );
    let model = parse_model(&text, Path::new(".")).unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let n = sim.n_dofs();
    sim.advance().unwrap();
    let tip = nmm::simulation::monitor_values(&sim)[1];
    (tip, n)
}

#[test]
fn cantilever_at_half_depth_cover_within_half_a_percent() {
    let exact = -4.024e-3;
    let (t1, n1) = cantilever_tip(0.5, 1);
    let (t0, n0) = cantilever_tip(0.5, 0);
    let (e1, e0) = (t1 / exact - 1.0, t0 / exact - 1.0);
    eprintln!(
        "cantilever h = d/2: order 1 {:.4} mm ({:+.2}%, {n1} unknowns); order 0 {:.4} mm ({:+.1}%, {n0} unknowns)",
        t1 * 1e3,
        100.0 * e1,
        t0 * 1e3,
        100.0 * e0
    );
    assert!(e1.abs() < 0.005, "order 1: {:+.3}%", 100.0 * e1);
    assert_eq!((n0, n1), (172, 510));
    assert!(
        (e0 + 0.476).abs() < 0.005,
        "order 0 as the issue measured: {e0}"
    );
}

/// Timoshenko & Goodier's cantilever (plane stress): x from the loaded end (x = 0) to the
/// far end (x = L), y ∈ [−c, c], end load P (parabolic shear) at x = 0, the same tractions
/// the solution has at x = L; σxx = −P x y / I, σyy = 0, τxy = −P (c² − y²) / (2I).
struct Goodier {
    p: f64,
    l: f64,
    c: f64,
    e: f64,
    nu: f64,
}

impl Goodier {
    fn i(&self) -> f64 {
        2.0 * self.c.powi(3) / 3.0
    }
    fn g(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }
    fn u(&self, x: Vec2) -> Vec2 {
        let (p, l, c, e, nu, i, g) = (self.p, self.l, self.c, self.e, self.nu, self.i(), self.g());
        let (x, y) = (x[0], x[1]);
        [
            -p * x * x * y / (2.0 * e * i) - nu * p * y.powi(3) / (6.0 * e * i)
                + p * y.powi(3) / (6.0 * i * g)
                + (p * l * l / (2.0 * e * i) - p * c * c / (2.0 * i * g)) * y,
            nu * p * x * y * y / (2.0 * e * i) + p * x.powi(3) / (6.0 * e * i)
                - p * l * l * x / (2.0 * e * i)
                + p * l.powi(3) / (3.0 * e * i),
        ]
    }
    fn sigma(&self, x: Vec2) -> [f64; 3] {
        let i = self.i();
        [
            -self.p * x[0] * x[1] / i,
            0.0,
            -self.p * (self.c * self.c - x[1] * x[1]) / (2.0 * i),
        ]
    }
}

/// Points and weights of the conical product rule on the triangle (a, b, c), 5 × 5 Gauss
/// points (exact to degree 8), weights summing to the signed area.
fn triangle_rule(a: Vec2, b: Vec2, c: Vec2) -> Vec<(Vec2, f64)> {
    const G: [(f64, f64); 5] = [
        (0.046_910_077_030_668, 0.118_463_442_528_095),
        (0.230_765_344_947_158, 0.239_314_335_249_683),
        (0.5, 0.284_444_444_444_444_4),
        (0.769_234_655_052_842, 0.239_314_335_249_683),
        (0.953_089_922_969_332, 0.118_463_442_528_095),
    ];
    let two_a = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut out = Vec::with_capacity(25);
    for (u, wu) in G {
        for (v, wv) in G {
            let (s, t) = (u * (1.0 - v), u * v);
            let x = [
                a[0] + s * (b[0] - a[0]) + t * (c[0] - a[0]),
                a[1] + s * (b[1] - a[1]) + t * (c[1] - a[1]),
            ];
            out.push((x, two_a * u * wu * wv));
        }
    }
    out
}

/// Relative L2 and energy errors of the Goodier cantilever at cover size h and order 1,
/// with the unknowns.
fn goodier_errors(h: f64, order: usize) -> (f64, f64, usize) {
    let gd = Goodier {
        p: 1000.0,
        l: 10.0,
        c: 0.5,
        e: 1.0e9,
        nu: 0.25,
    };
    let (a, b) = ([10.0, 0.0], [10.0, 0.5]);
    let (ua, ub) = (gd.u(a), gd.u(b));
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\n[cover]\nsize = {h:?}\norder = {order}\n{}\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[0.0, -0.5], [10.0, -0.5], [10.0, 0.5], [0.0, 0.5]]\n\
         [[constraint]]\nblock = \"b\"\npoint = {}\nux = {:?}\nuy = {:?}\n\
         [[constraint]]\nblock = \"b\"\npoint = {}\nux = {:?}\n",
        material(gd.e, gd.nu, 1000.0, "stress"),
        pt(a),
        ua[0],
        ua[1],
        pt(b),
        ub[0],
    );
    let model = parse_model(&text, Path::new(".")).unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let f = traction_vector(&sim, |x, n| {
        let s = gd.sigma(x);
        [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]]
    });
    sim.add_load_vector(&f);
    let d0 = sim.disc.clone();
    sim.advance().unwrap();
    let dm = nmm::material::elasticity_matrix(gd.e, gd.nu, nmm::model::Plane::Stress);
    let table = ElementDofTable::new(&d0);
    let b = d0.basis;
    let (mut l2, mut l2n, mut en, mut enn) = (0.0, 0.0, 0.0, 0.0);
    let mut ue = [0.0; MAX_ELEMENT_DOFS];
    for (ei, e) in d0.elements.iter().enumerate() {
        for (o, &g) in ue.iter_mut().zip(table.of(ei)) {
            *o = if g == usize::MAX { 0.0 } else { sim.u[g] };
        }
        let ue = &ue[..b.element_dofs()];
        let p = &e.polygon;
        for i in 1..p.len() - 1 {
            for (x, w) in triangle_rule(p[0], p[i], p[i + 1]) {
                let bw = barycentric(&e.nodes, x);
                let (uh, ex) = (b.interpolate(e, &bw, ue), gd.u(x));
                l2 += w * ((uh[0] - ex[0]).powi(2) + (uh[1] - ex[1]).powi(2));
                l2n += w * (ex[0].powi(2) + ex[1].powi(2));
                let sh = nmm::material::stress(&dm, b.strain(e, &bw, ue));
                let s = gd.sigma(x);
                let ds = [sh[0] - s[0], sh[1] - s[1], sh[2] - s[2]];
                en += w * 2.0 * nmm::material::stress_energy_density(&dm, ds);
                enn += w * 2.0 * nmm::material::stress_energy_density(&dm, s);
            }
        }
    }
    ((l2 / l2n).sqrt(), (en / enn).sqrt(), sim.n_dofs())
}

/// The least-squares slope of log e against log h.
fn rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (x, y): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// Acceptance: L2 rate ≥ 2.8 and energy rate ≥ 1.8 over h = d/2 … d/16 at order 1 (the
/// rates of quadratic shape functions are 3 and 2; order 0 gives 2 and 1, so the test fails
/// for a basis that is not quadratic). The exact solution checks itself first: its strains
/// by finite differences give its stresses.
#[test]
fn goodier_cantilever_converges_at_the_rates_of_quadratic_fields() {
    let gd = Goodier {
        p: 1000.0,
        l: 10.0,
        c: 0.5,
        e: 1.0e9,
        nu: 0.25,
    };
    let dm = nmm::material::elasticity_matrix(gd.e, gd.nu, nmm::model::Plane::Stress);
    for x in [[1.0, 0.3], [7.0, -0.45]] {
        let d = 1e-4;
        let du = |i: usize, j: usize| {
            let (mut a, mut b) = (x, x);
            a[j] += d;
            b[j] -= d;
            (gd.u(a)[i] - gd.u(b)[i]) / (2.0 * d)
        };
        let s = nmm::material::stress(&dm, [du(0, 0), du(1, 1), du(0, 1) + du(1, 0)]);
        let want = gd.sigma(x);
        for k in 0..3 {
            assert!(
                (s[k] - want[k]).abs() < 1e-6 * 6000.0,
                "{k}: {s:?} {want:?}"
            );
        }
    }
    let hs = [0.5, 0.25, 0.125, 0.0625];
    let mut rows = Vec::new();
    for &h in &hs {
        let (l2, en, n) = goodier_errors(h, 1);
        eprintln!("Goodier cantilever order 1, h = {h}: {n} unknowns, L2 error {l2:.3e}, energy error {en:.3e}");
        rows.push((l2, en));
    }
    let l2: Vec<f64> = rows.iter().map(|r| r.0).collect();
    let en: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let (rl2, ren) = (rate(&hs, &l2), rate(&hs, &en));
    eprintln!("rates over h = d/2 … d/16: L2 {rl2:.2}, energy {ren:.2}");
    assert!(rl2 >= 2.8, "L2 rate {rl2}");
    assert!(ren >= 1.8, "energy rate {ren}");
    for h in [0.5, 0.25] {
        let (l2, en, n) = goodier_errors(h, 0);
        eprintln!("   (order 0, h = {h}: {n} unknowns, L2 error {l2:.3e}, energy error {en:.3e})");
    }
}

/// `nmm run` of the shipped example `name` with `[cover] order = 1` added; its history as
/// (header, rows), and the energy balance's relative error from summary.json.
fn run_example_order_1(name: &str) -> (Vec<String>, Vec<Vec<f64>>, f64) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let text = std::fs::read_to_string(root.join(name)).unwrap();
    assert!(text.contains("[cover]\n"), "{name} has a [cover] table");
    let text = text.replacen("[cover]\n", "[cover]\norder = 1\n", 1);
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join(name);
    std::fs::write(&model, text).unwrap();
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
        .args([
            "run",
            model.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--no-vtk", "--quiet"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let hist = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let mut lines = hist.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let key = "\"balance_error_relative\": ";
    let at = summary
        .find(key)
        .expect("the energy balance in summary.json")
        + key.len();
    let rest = &summary[at..];
    let end = rest.find([',', '\n', '}']).unwrap();
    (header, rows, rest[..end].trim().parse().unwrap())
}

fn col(h: &[String], rows: &[Vec<f64>], name: &str) -> Vec<f64> {
    let k = h.iter().position(|x| x == name).unwrap();
    rows.iter().map(|r| r[k]).collect()
}

/// The incline example at order 1: slip ½ g (sin θ − cos θ tan φ) t² within 0.1% (the
/// acceptance; measured 0.0001%, as at order 0: the block slides as a rigid body), and the
/// energy balance closes (relative error below 1e-8, as at order 0; measured 1e-10: the
/// elastic energy of the linear stress, the kinetic energy of the consistent mass and the
/// friction work of the Simpson contacts account for the gravity work).
#[test]
fn incline_at_order_1_slides_as_the_closed_form() {
    let (h, rows, balance) = run_example_order_1("incline.toml");
    eprintln!("incline, order 1: energy balance error {balance:e} (relative)");
    assert!(balance.abs() < 1e-8, "{balance}");
    let (s, c) = 30f64.to_radians().sin_cos();
    let t = *col(&h, &rows, "time").last().unwrap();
    let ux = *col(&h, &rows, "c.ux").last().unwrap();
    let uy = *col(&h, &rows, "c.uy").last().unwrap();
    let slip = ux * c - uy * s;
    let exact = 0.5 * 9.81 * (s - c * 20f64.to_radians().tan()) * t * t;
    eprintln!(
        "incline, order 1: slip {slip:.6} m vs {exact:.6} m ({:+.4}%)",
        100.0 * (slip / exact - 1.0)
    );
    assert!((slip / exact - 1.0).abs() < 1e-3);
}

/// The paper's direct shear at order 1: the joint's shear stress never above the strength
/// 577.35 kPa (× 1.001) and at it within 0.1% once the whole joint slides. The upper block
/// is more flexible at order 1 than with constant covers (which are too stiff), so the
/// first two 0.06 mm steps go partly into its elastic shear (measured 441 and 569 kPa;
/// order 0: 495 and 577.3) and the joint slides from the third step on.
#[test]
fn direct_shear_at_order_1_stays_at_the_strength() {
    let strength = 1.0e6 * 30f64.to_radians().tan();
    let (h, rows, _) = run_example_order_1("direct_shear.toml");
    let tau: Vec<f64> = col(&h, &rows, "joint.fx")
        .iter()
        .map(|f| -f / 0.1)
        .collect();
    eprintln!("direct shear, order 1: τ {tau:?} Pa (strength {strength:.1})");
    assert_eq!(tau.len(), 5);
    for t in &tau {
        assert!(*t <= strength * 1.001, "{t} above {strength}");
    }
    for t in &tau[2..] {
        assert!((t / strength - 1.0).abs() < 1e-3, "{t} vs {strength}");
    }
}

/// Checkpoints at order 1 carry the whole state (the stress at the elements' nodes, the
/// moved geometry, the contacts): a run of the shaken slope at order 1 branched from its own
/// checkpoint at the end of the settling stage writes the shaking's rows of the
/// uninterrupted run, byte for byte.
#[test]
fn order_1_checkpoints_are_exact() {
    use nmm::verify::cases::{slope_model, SineMotion};
    let motion = SineMotion {
        amplitude: 0.5 * 9.81,
        frequency: 5.0,
        ramp: 0.0,
        duration: 0.15,
    };
    let text = slope_model(30.0, &motion, "return-mapping", 1e-3)
        .replace("[cover]\nsize = 0.1\n", "[cover]\nsize = 0.1\norder = 1\n");
    assert!(text.contains("order = 1"));
    let text = format!(
        "{text}[[stage]]\nname = \"settle\"\nmode = \"static\"\ndt = 0.01\nsteps = 5\n\
         [[stage]]\nname = \"shake\"\ndt = 0.001\nsteps = 150\nbase_motion = true\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    std::fs::write(&model, text).unwrap();
    let run = |out: &Path, extra: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_nmm"))
            .args([
                "run",
                model.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
                "--quiet",
            ])
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out.join("history.csv")).unwrap()
    };
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let fresh = run(&a, &[]);
    let ckpt = a.join("checkpoints").join("step_00000005.ckpt");
    assert!(ckpt.exists());
    let branch = run(&b, &["--from", ckpt.to_str().unwrap()]);
    let (f, br): (Vec<&str>, Vec<&str>) = (fresh.lines().collect(), branch.lines().collect());
    assert_eq!(f.len(), 1 + 5 + 150);
    assert_eq!(br[0], f[0]);
    assert_eq!(
        &br[1..],
        &f[6..],
        "the branch's rows are the shaking's of the fresh run"
    );
    // it slid: the state carried over matters
    let k = f[0].split(',').position(|c| c == "slider.ux").unwrap();
    let ux: f64 = f
        .last()
        .unwrap()
        .split(',')
        .nth(k)
        .unwrap()
        .parse()
        .unwrap();
    eprintln!("order-1 shaken slope: slider.ux {ux:e} m after 0.15 s");
}

/// Unknowns, nonzeros per row of the element pattern and wall time per step (ms, the
/// median of `reps` alternations of `steps` steps; one thread) of a model.
fn cost(text: &str, steps: usize, reps: usize) -> (usize, f64, f64) {
    let mut times = Vec::new();
    let mut out = (0, 0.0);
    for _ in 0..reps {
        let model = parse_model(text, Path::new(".")).unwrap();
        let mut sim = Simulation::new(model).unwrap();
        sim.set_threads(nmm::parallel::Threads::new(1).unwrap());
        let (l, _) = sim.linear_system();
        out = (sim.n_dofs(), l.pattern.nnz() as f64 / sim.n_dofs() as f64);
        sim.advance().unwrap(); // the first step: symbolic analyses, first contacts
        let t0 = std::time::Instant::now();
        for _ in 0..steps {
            sim.advance().unwrap();
        }
        times.push(t0.elapsed().as_secs_f64() * 1e3 / steps as f64);
    }
    times.sort_by(f64::total_cmp);
    (out.0, out.1, times[times.len() / 2])
}

/// The cost of order 1 against order 0 (a benchmark for the note, not a check: run with
/// `cargo test --release --test first_order_covers cost -- --ignored --nocapture`): the
/// cantilever at equal accuracy (order 1 at h = d/2 against order 0 refined until it is as
/// accurate) and the 20×20 wall at equal h (dynamic, contacts).
#[test]
#[ignore]
fn cost_of_order_1() {
    let cant = |h: f64, order: usize| {
        format!(
            "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 100\n[cover]\nsize = {h:?}\norder = {order}\n{}\
             [[block]]\nname = \"beam\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0]]\n\
             [[load]]\nblock = \"beam\"\nedge = [[10.0, 0.0], [10.0, 1.0]]\ntraction = [0.0, -1000.0]\n\
             [[constraint]]\nblock = \"beam\"\nedge = [[0.0, 0.0], [0.0, 1.0]]\nux = 0.0\nuy = 0.0\n",
            material(1.0e9, 0.0, 1000.0, "stress")
        )
    };
    eprintln!("| model | order | h | unknowns | nonzeros/row | ms/step | tip error |");
    eprintln!("|---|---|---|---|---|---|---|");
    for (h, order) in [
        (0.5, 1),
        (0.25, 1),
        (0.0625, 0),
        (0.03125, 0),
        (0.015625, 0),
    ] {
        let (n, nnz, ms) = cost(&cant(h, order), 5, 3);
        let (tip, _) = cantilever_tip(h, order);
        eprintln!(
            "| cantilever | {order} | {h} | {n} | {nnz:.1} | {ms:.2} | {:+.2}% |",
            100.0 * (tip / -4.024e-3 - 1.0)
        );
    }
    for order in [0, 1] {
        let mut o = nmm::generate::WallOptions::new(20, 20);
        o.steps = 100;
        let text = nmm::generate::brick_wall_model(&o).replacen(
            "[cover]\n",
            &format!("[cover]\norder = {order}\n"),
            1,
        );
        let (n, nnz, ms) = cost(&text, 10, 3);
        eprintln!("| wall 20×20 | {order} | 0.2 | {n} | {nnz:.1} | {ms:.1} | |");
    }
}

/// The first eigenfrequency (Hz) of the clamped cantilever's discrete system K x = ω² M x
/// (K with the clamp's edge springs), by inverse iteration on a sparse Cholesky factor; K
/// and M from the step's linear part L = K + (2/Δt²) M at two Δt.
fn cantilever_frequency(h: f64, order: usize) -> (f64, usize) {
    let text = |dt: f64| {
        format!(
            "[analysis]\nmode = \"dynamic\"\ndt = {dt:?}\nsteps = 1\n[cover]\nsize = {h:?}\norder = {order}\n{}\
             [[block]]\nname = \"beam\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0]]\n\
             [[constraint]]\nblock = \"beam\"\nedge = [[0.0, 0.0], [0.0, 1.0]]\nux = 0.0\nuy = 0.0\n",
            material(1.0e9, 0.0, 1000.0, "stress")
        )
    };
    let system = |dt: f64| {
        let mut sim = Simulation::new(parse_model(&text(dt), Path::new(".")).unwrap()).unwrap();
        sim.linear_system().0
    };
    let (la, lb) = (system(1.0), system(0.5));
    let (ca, cb) = (2.0, 8.0);
    let m: Vec<f64> = la
        .values
        .iter()
        .zip(&lb.values)
        .map(|(a, b)| (b - a) / (cb - ca))
        .collect();
    let k: Vec<f64> = la.values.iter().zip(&m).map(|(a, m)| a - ca * m).collect();
    let p = la.pattern.clone();
    let n = p.n;
    let mul = |a: &[f64], x: &[f64]| {
        let mut y = vec![0.0; n];
        for c in 0..n {
            for s in p.col_ptr[c]..p.col_ptr[c + 1] {
                y[p.row_idx[s]] += a[s] * x[c];
            }
        }
        y
    };
    let kmat = nmm::solver::SparseMatrix {
        pattern: p.clone(),
        values: k.clone(),
    };
    let mut chol = nmm::solver::Cholesky::default();
    chol.factorize(&kmat).unwrap();
    let mut x: Vec<f64> = (0..n).map(|i| 1.0 + 0.001 * (i % 7) as f64).collect();
    let mut lambda = 0.0;
    for _ in 0..200 {
        let mut y = mul(&m, &x);
        chol.solve_in_place(&mut y).unwrap();
        let (ky, my) = (mul(&k, &y), mul(&m, &y));
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let l = dot(&y, &ky) / dot(&y, &my);
        let norm = dot(&y, &my).sqrt();
        x = y.iter().map(|v| v / norm).collect();
        if (l - lambda).abs() < 1e-14 * l {
            lambda = l;
            break;
        }
        lambda = l;
    }
    (lambda.sqrt() / (2.0 * std::f64::consts::PI), n)
}

/// Acceptance: the first bending frequency at h = d/2 within 0.3% at order 1. References: the
/// same discretisation converged (h = d/16 at order 1; the differences fall as h⁴, printed),
/// and Timoshenko's beam (κ = 5/6, rotary inertia; first-order correction of
/// Euler–Bernoulli). The frequency is the discrete system's (K x = ω² M x), which a free
/// vibration under Newmark β = ½, γ = 1 reproduces to O((ωΔt)²). Order 0 at d/2 (38% too
/// stiff) shows that the test can fail.
#[test]
fn cantilever_first_frequency_at_half_depth_cover() {
    let mut rows = Vec::new();
    for h in [0.5, 0.25, 0.125, 0.0625] {
        let (f, n) = cantilever_frequency(h, 1);
        rows.push((h, f, n));
    }
    let reference = rows.last().unwrap().1;
    for &(h, f, n) in &rows {
        eprintln!(
            "cantilever order 1, h = {h}: {n} unknowns, f1 = {f:.6} Hz ({:+.3}% of h = d/16)",
            100.0 * (f / reference - 1.0)
        );
    }
    // Euler–Bernoulli with Timoshenko's first-order correction for shear and rotary inertia
    let (e, rho, l, i, a): (f64, f64, f64, f64, f64) = (1.0e9, 1000.0, 10.0, 1.0 / 12.0, 1.0);
    let f_eb = 1.875_104_f64.powi(2) * (e * i / (rho * a * l.powi(4))).sqrt()
        / (2.0 * std::f64::consts::PI);
    let r2 = i / (a * l * l);
    let f_t = f_eb * (1.0 - 0.5 * 1.875_104_f64.powi(2) * r2 * (1.0 + e / (5.0 / 6.0 * e / 2.0)));
    eprintln!("   Euler–Bernoulli {f_eb:.5} Hz, with Timoshenko's correction ≈ {f_t:.5} Hz");
    let (f0, n0) = cantilever_frequency(0.5, 0);
    eprintln!(
        "   order 0, h = 0.5: {n0} unknowns, f1 = {f0:.5} Hz ({:+.1}%)",
        100.0 * (f0 / reference - 1.0)
    );
    let e1 = rows[0].1 / reference - 1.0;
    assert!(e1.abs() < 3e-3, "order 1 at d/2: {e1:+e}");
    // and against the beam theory (its first-order correction is itself good to ~0.05% at
    // L/d = 10): the independent model's −0.14%
    let et = rows[0].1 / f_t - 1.0;
    eprintln!(
        "   order 1 at d/2 against Timoshenko's beam: {:+.3}%",
        100.0 * et
    );
    assert!(et.abs() < 3e-3, "against the beam theory: {et:+e}");
    assert!(
        (rows[2].1 / reference - 1.0).abs() < 1e-4,
        "converged: d/8 against d/16"
    );
    assert!(f0 / reference - 1.0 > 0.1, "order 0 is far too stiff");
}

/// The crown's largest |displacement| over `steps` steps of the arch `o` at order 1, and the
/// step cuts.
fn arch_crown_order_1(o: &nmm::generate::ArchOptions, steps: usize) -> (f64, usize) {
    let text = nmm::generate::arch_model(o).replacen("[cover]\n", "[cover]\norder = 1\n", 1);
    assert!(text.contains("order = 1"));
    let mut sim = Simulation::new(parse_model(&text, Path::new(".")).unwrap()).unwrap();
    let (mut worst, mut cuts) = (0.0f64, 0);
    for _ in 0..steps {
        let r = sim.advance().unwrap();
        cuts += r.cuts;
        let v = nmm::simulation::monitor_values(&sim);
        worst = worst.max(v[0].hypot(v[1]));
    }
    (worst, cuts)
}

/// Contact at order 1 in a structure: the 19-voussoir arch at t/r = 0.15, above its minimum
/// thickness (0.1075), stands under gravity (the crown settles by less than 1 mm, elastic:
/// measured 0.18 mm in 0.3 s); at t/r = 0.09 it collapses (the crown falls by more than
/// 0.1 m within 0.6 s: measured 0.59 m). Either failing — a stiff mode blowing the thick arch apart, or contacts holding
/// the thin one up — fails the test.
#[test]
fn arch_at_order_1_stands_above_its_minimum_thickness_and_collapses_below() {
    let mut o = nmm::generate::ArchOptions::new();
    let (thick, cuts) = arch_crown_order_1(&o, 300);
    eprintln!("arch t/r 0.15 at order 1: crown moves {thick:.3e} m in 0.3 s, {cuts} cuts");
    assert!(thick < 1e-3, "{thick}");
    o.thickness = 0.09 * o.radius;
    let (thin, cuts) = arch_crown_order_1(&o, 600);
    eprintln!("arch t/r 0.09 at order 1: crown moves {thin:.3e} m in 0.6 s, {cuts} cuts");
    assert!(thin > 0.1, "{thin}");
}

/// Walls at order 1: a 5×5 running-bond wall with closers (cover 0.2 m) stands for 0.3 s of
/// dynamic release with no step cut (largest brick motion < 1 mm, elastic settlement).
#[test]
fn wall_at_order_1_stands_without_cuts() {
    let mut o = nmm::generate::WallOptions::new(5, 5);
    o.closers = true;
    o.steps = 300;
    let text = nmm::generate::brick_wall_model(&o).replacen("[cover]\n", "[cover]\norder = 1\n", 1);
    assert!(text.contains("order = 1"));
    let mut sim = Simulation::new(parse_model(&text, Path::new(".")).unwrap()).unwrap();
    let (mut worst, mut cuts) = (0.0f64, 0);
    for _ in 0..300 {
        cuts += sim.advance().unwrap().cuts;
        let v = nmm::simulation::monitor_values(&sim);
        worst = worst.max(v[0].hypot(v[1]));
    }
    eprintln!(
        "wall 5×5 at order 1: {} unknowns, top moves {worst:.3e} m, {cuts} cuts",
        sim.n_dofs()
    );
    assert_eq!(cuts, 0);
    assert!(worst < 1e-3, "{worst}");
}

/// Kirsch's plate: a circular hole of radius a in an infinite plate under σ0 along x (plane
/// strain, E, ν): stresses and displacements in polar coordinates about the hole's centre.
struct Kirsch {
    a: f64,
    s0: f64,
    e: f64,
    nu: f64,
}

impl Kirsch {
    fn sigma(&self, x: Vec2) -> [f64; 3] {
        let (r, t) = (x[0].hypot(x[1]), x[1].atan2(x[0]));
        let (a2, a4) = ((self.a / r).powi(2), (self.a / r).powi(4));
        let s0 = self.s0;
        [
            s0 * (1.0 - a2 * (1.5 * (2.0 * t).cos() + (4.0 * t).cos())
                + 1.5 * a4 * (4.0 * t).cos()),
            s0 * (-a2 * (0.5 * (2.0 * t).cos() - (4.0 * t).cos()) - 1.5 * a4 * (4.0 * t).cos()),
            s0 * (-a2 * (0.5 * (2.0 * t).sin() + (4.0 * t).sin()) + 1.5 * a4 * (4.0 * t).sin()),
        ]
    }
    fn u(&self, x: Vec2) -> Vec2 {
        let (r, t) = (x[0].hypot(x[1]), x[1].atan2(x[0]));
        let mu = self.e / (2.0 * (1.0 + self.nu));
        let k = 3.0 - 4.0 * self.nu;
        let (a, c) = (self.a, self.s0 * self.a / (8.0 * mu));
        [
            c * ((r / a) * (k + 1.0) * t.cos()
                + 2.0 * (a / r) * ((1.0 + k) * t.cos() + (3.0 * t).cos())
                - 2.0 * (a / r).powi(3) * (3.0 * t).cos()),
            c * ((r / a) * (k - 3.0) * t.sin()
                + 2.0 * (a / r) * ((1.0 - k) * t.sin() + (3.0 * t).sin())
                - 2.0 * (a / r).powi(3) * (3.0 * t).sin()),
        ]
    }
}

/// The quarter plate [0, L]² less the hole (its arc a polygon of `arc` chords), Kirsch's
/// tractions on its four straight edges (the symmetry lines included), its rigid modes held
/// by three point springs at points where the exact displacement is zero; order 1 at cover
/// h.
/// Returns the relative energy error, σxx at the hole's top (the hoop stress, 3 σ0 exact) and
/// the unknowns.
fn kirsch_errors(h: f64, arc: usize) -> (f64, f64, usize) {
    let k = Kirsch {
        a: 1.0,
        s0: 1.0e6,
        e: 1.0e9,
        nu: 0.25,
    };
    let l = 4.0;
    let mut poly = vec![[k.a, 0.0], [l, 0.0], [l, l], [0.0, l], [0.0, k.a]];
    for i in 1..arc {
        let t = std::f64::consts::FRAC_PI_2 * (1.0 - i as f64 / arc as f64);
        poly.push([k.a * t.cos(), k.a * t.sin()]);
    }
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\n[cover]\nsize = {h:?}\norder = 1\n{}\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = {}\n\
         [[constraint]]\nblock = \"b\"\npoint = [0.0, {l:?}]\nux = 0.0\n\
         [[constraint]]\nblock = \"b\"\npoint = [{l:?}, 0.0]\nuy = 0.0\n\
         [[constraint]]\nblock = \"b\"\npoint = [0.0, {a:?}]\nux = 0.0\n",
        material(k.e, k.nu, 1000.0, "strain"),
        points(&poly),
        a = k.a,
    );
    let model = parse_model(&text, Path::new(".")).unwrap();
    let mut sim = Simulation::new(model).unwrap();
    let tol = 1e-9;
    let f = traction_vector(&sim, |x, n| {
        if (x[0] - l).abs() < tol || (x[1] - l).abs() < tol || x[0].abs() < tol || x[1].abs() < tol
        {
            let s = k.sigma(x);
            [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]]
        } else {
            [0.0, 0.0]
        }
    });
    sim.add_load_vector(&f);
    let d0 = sim.disc.clone();
    let top = d0.locate(0, [0.0, k.a]).unwrap();
    sim.advance().unwrap();
    let dm = nmm::material::elasticity_matrix(k.e, k.nu, nmm::model::Plane::Strain);
    let table = ElementDofTable::new(&d0);
    let b = d0.basis;
    let (mut en, mut enn, mut near) = (0.0, 0.0, 0.0);
    let mut ue = [0.0; MAX_ELEMENT_DOFS];
    let fill = |ei: usize, ue: &mut [f64; MAX_ELEMENT_DOFS]| {
        for (o, &g) in ue.iter_mut().zip(table.of(ei)) {
            *o = if g == usize::MAX { 0.0 } else { sim.u[g] };
        }
    };
    for (ei, e) in d0.elements.iter().enumerate() {
        fill(ei, &mut ue);
        let p = &e.polygon;
        for i in 1..p.len() - 1 {
            for (x, w) in triangle_rule(p[0], p[i], p[i + 1]) {
                let bw = barycentric(&e.nodes, x);
                let sh = nmm::material::stress(&dm, b.strain(e, &bw, &ue[..18]));
                let s = k.sigma(x);
                let ds = [sh[0] - s[0], sh[1] - s[1], sh[2] - s[2]];
                en += w * 2.0 * nmm::material::stress_energy_density(&dm, ds);
                enn += w * 2.0 * nmm::material::stress_energy_density(&dm, s);
                if x[0].hypot(x[1]) < 1.2 * k.a {
                    near += w * 2.0 * nmm::material::stress_energy_density(&dm, ds);
                }
            }
        }
    }
    eprintln!(
        "   near the hole (r < 1.2 a): {:.3e} of the energy error²",
        near / en
    );
    fill(top.element, &mut ue);
    let hoop = nmm::material::stress(
        &dm,
        b.strain(&d0.elements[top.element], &top.weights, &ue[..18]),
    )[0];
    ((en / enn).sqrt(), hoop, sim.n_dofs())
}

/// Acceptance: the plate with a circular hole (Kirsch, exact tractions on the outer
/// polygon) at order 1: energy-error rate ≥ 1.7, fitted over h = a/4 … a/32 (measured 1.83;
/// the halvings give 1.43, 1.71, 1.84, 1.92 from a/2: a/2 is not yet asymptotic), and the
/// hoop stress at the hole within 5% at the finest size (measured +0.03%). The hole is a
/// polygon of 512 chords (5e-6 a from the circle, below the finest error); the exact field
/// first checks itself (Hooke on its finite-difference strains).
///
/// Measured and kept out: with the symmetry lines held by edge constraints (`ux = 0` on
/// x = 0, `uy = 0` on y = 0: penalty springs c E/h on edges that cut the mesh's cells)
/// instead of their exact tractions, the rate fell to 1.21 and the hoop stress to +3.4% at
/// a/16: a stiff penalty on a cut edge constrains the quadratic trace of first-order covers
/// too much (a known limitation of penalty Dirichlet conditions on cut cells).
#[test]
fn kirsch_plate_with_a_hole_at_order_1() {
    let k = Kirsch {
        a: 1.0,
        s0: 1.0e6,
        e: 1.0e9,
        nu: 0.25,
    };
    let dm = nmm::material::elasticity_matrix(k.e, k.nu, nmm::model::Plane::Strain);
    for x in [[1.3, 0.4], [0.2, 2.5], [3.0, 3.0]] {
        let d = 1e-5;
        let du = |i: usize, j: usize| {
            let (mut p, mut m) = (x, x);
            p[j] += d;
            m[j] -= d;
            (k.u(p)[i] - k.u(m)[i]) / (2.0 * d)
        };
        let s = nmm::material::stress(&dm, [du(0, 0), du(1, 1), du(0, 1) + du(1, 0)]);
        let want = k.sigma(x);
        for c in 0..3 {
            assert!((s[c] - want[c]).abs() < 1e-5 * k.s0, "{c}: {s:?} {want:?}");
        }
    }
    let hs = [0.5, 0.25, 0.125, 0.0625, 0.03125];
    let mut errs = Vec::new();
    let mut hoop = 0.0;
    for &h in &hs {
        let (e, s, n) = kirsch_errors(h, 512);
        eprintln!(
            "Kirsch order 1, h = {h}: {n} unknowns, energy error {e:.3e}, hoop stress {:.4} σ0",
            s / k.s0
        );
        errs.push(e);
        hoop = s;
    }
    let r = rate(&hs[1..], &errs[1..]);
    eprintln!(
        "energy rate over h = a/4 … a/32: {r:.2} (a/2 … a/32: {:.2})",
        rate(&hs, &errs)
    );
    assert!(r >= 1.7, "energy rate {r}");
    assert!((hoop / (3.0 * k.s0) - 1.0).abs() < 0.05, "hoop {hoop}");
}

/// The first bending frequency in a dynamic free vibration (the acceptance's "free
/// vibration, dynamic"): the clamped cantilever at order 1, h = d/2, set moving by an initial
/// velocity v_y = 1 mm/s × (x/L)² on the covers' constant terms (close to the first mode),
/// integrated by the solver's Newmark step at 1000 steps per period for 4 periods; the
/// frequency from the tip's upward zero crossings (linear interpolation between steps).
/// Within 0.3% of Timoshenko's beam (as the eigenvalue test above) and within 0.1% of the
/// discrete eigenfrequency (the scheme's period error at ωΔt = 2π/1000 is ~1e-5; the second
/// mode's share of the initial field moves the crossings by less).
#[test]
fn cantilever_free_vibration_frequency_at_order_1() {
    let (f_eig, _) = cantilever_frequency(0.5, 1);
    let period = 1.0 / f_eig;
    let dt = period / 1000.0;
    let steps = 4000;
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt:?}\nsteps = {steps}\n[cover]\nsize = 0.5\norder = 1\n{}\
         [[block]]\nname = \"beam\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0]]\n\
         [[constraint]]\nblock = \"beam\"\nedge = [[0.0, 0.0], [0.0, 1.0]]\nux = 0.0\nuy = 0.0\n\
         [[monitor]]\nname = \"tip\"\npoint = [10.0, 0.5]\n",
        material(1.0e9, 0.0, 1000.0, "stress")
    );
    let mut sim = Simulation::new(parse_model(&text, Path::new(".")).unwrap()).unwrap();
    for c in &sim.disc.covers {
        if let Some(d) = c.dof {
            let x = sim.disc.mesh.node(c.node);
            sim.v[d + 1] = 1.0e-3 * (x[0] / 10.0).powi(2);
        }
    }
    let mut series = vec![(0.0, 0.0)];
    while !sim.finished() {
        sim.advance().unwrap();
        let m = nmm::simulation::monitor_values(&sim);
        series.push((sim.time, m[1]));
    }
    let crossings: Vec<f64> = series
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1))
        .collect();
    assert!(crossings.len() >= 3, "{} crossings", crossings.len());
    let f_dyn = (crossings.len() - 1) as f64 / (crossings[crossings.len() - 1] - crossings[0]);
    // Timoshenko's beam, as in the eigenvalue test
    let (e, rho, l, i, a): (f64, f64, f64, f64, f64) = (1.0e9, 1000.0, 10.0, 1.0 / 12.0, 1.0);
    let f_eb = 1.875_104_f64.powi(2) * (e * i / (rho * a * l.powi(4))).sqrt()
        / (2.0 * std::f64::consts::PI);
    let r2 = i / (a * l * l);
    let f_t = f_eb * (1.0 - 0.5 * 1.875_104_f64.powi(2) * r2 * (1.0 + e / (5.0 / 6.0 * e / 2.0)));
    eprintln!(
        "free vibration at order 1, h = 0.5: f1 = {f_dyn:.6} Hz; eigenvalue {f_eig:.6} ({:+.4}%), Timoshenko {f_t:.6} ({:+.3}%)",
        100.0 * (f_dyn / f_eig - 1.0),
        100.0 * (f_dyn / f_t - 1.0)
    );
    assert!((f_dyn / f_eig - 1.0).abs() < 1e-3);
    assert!((f_dyn / f_t - 1.0).abs() < 3e-3);
}
