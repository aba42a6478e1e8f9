//! Turning the model's loads, constraints and monitors into vectors and penalty
//! springs on the discretisation (done once, on the initial geometry: the
//! weights of a material point do not change as the element moves).
//!
//! **Constraints are imposed by penalty** (as DDA does for fixed points): a point
//! spring k = c·E (N/m) or an edge spring p = c·E/h (N/m per m of edge), with
//! c = `[analysis] constraint_penalty` (default 1e6) and E the block's Young's
//! modulus. The error this makes is the spring's stretch: a reaction R through a
//! point spring moves the point by R/k; a uniform reaction traction t on a
//! constrained edge moves it uniformly by t/p = t h /(c E), i.e. a relative error
//! of about (t/E)(h/L)/c in the displacement and nothing in the stress.

use super::{Penalty, Simulation};
use crate::assembly::global::NO_DOF;
use crate::cover::basis::MAX_ELEMENT_SHAPES;
use crate::cover::{barycentric, CoverBasis, MaterialPoint};
use crate::geometry::{dist, Vec2};
use crate::model::{ConstraintGeometry, LoadKind, MonitorKind};

/// A piece of boundary segment inside one element: (element, weights at both ends, length).
type EdgePiece = (usize, [f64; 3], [f64; 3], f64);

fn edge_pieces(sim: &Simulation, block: usize, a: Vec2, b: Vec2) -> Result<Vec<EdgePiece>, String> {
    let pieces = sim.disc.boundary_pieces(block, a, b);
    let total: f64 = pieces.iter().map(|p| p.2).sum();
    if pieces.is_empty() || (total - dist(a, b)).abs() > 1e-6 * dist(a, b) {
        return Err(format!(
            "block \"{}\": segment [{:?}, {:?}] could not be followed along the discretised boundary (length {total} of {})",
            sim.model.blocks[block].name,
            a,
            b,
            dist(a, b)
        ));
    }
    let mut out = Vec::with_capacity(pieces.len());
    for (p1, p2, len) in pieces {
        let e = &sim.disc.elements[p1.element];
        let x2 = position(sim, &p2);
        out.push((p1.element, p1.weights, barycentric(&e.nodes, x2), len));
    }
    Ok(out)
}

/// Current position of a material point.
fn position(sim: &Simulation, p: &MaterialPoint) -> Vec2 {
    let n = &sim.disc.elements[p.element].nodes;
    let w = p.weights;
    [
        w[0] * n[0][0] + w[1] * n[1][0] + w[2] * n[2][0],
        w[0] * n[0][1] + w[1] * n[1][1] + w[2] * n[2][1],
    ]
}

fn locate(sim: &Simulation, block: usize, p: Vec2, what: &str) -> Result<MaterialPoint, String> {
    sim.disc.locate(block, p).ok_or_else(|| {
        format!(
            "{what}: point {p:?} is not inside block \"{}\"",
            sim.model.blocks[block].name
        )
    })
}

/// The global unknown of component `component` of each of `element`'s shape functions.
fn shape_dofs(sim: &Simulation, element: usize, component: usize) -> Vec<usize> {
    let d = sim.elem_dofs.of(element);
    (0..d.len() / 2).map(|a| d[2 * a + component]).collect()
}

/// The shape functions of `element` at weights `w`.
fn shapes(sim: &Simulation, element: usize, w: &[f64; 3]) -> Vec<f64> {
    let b = sim.disc.basis;
    let mut n = [0.0; MAX_ELEMENT_SHAPES];
    b.shapes(&sim.disc.elements[element], w, &mut n);
    n[..b.element_shapes()].to_vec()
}

/// Points and weights of the 3-point Gauss–Legendre rule on [0, 1] (exact to degree 5).
const GAUSS3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// `scale` × ∫ N_a ds and ∫ N_a N_b ds (row-major) over a boundary piece of `element` of length `len`
/// whose ends have weights `w1`, `w2` (the weights are linear along it): exact, in closed
/// form for constant covers (N = w), by 3-point Gauss–Legendre for first-order covers (N
/// quadratic along the piece: products of degree 4).
fn piece_integrals(
    sim: &Simulation,
    element: usize,
    w1: &[f64; 3],
    w2: &[f64; 3],
    len: f64,
    scale: f64,
) -> (Vec<f64>, Vec<f64>) {
    match sim.disc.basis {
        CoverBasis::Constant => {
            let g = (0..3)
                .map(|i| scale * len * 0.5 * (w1[i] + w2[i]))
                .collect();
            let mut k = vec![0.0; 9];
            for i in 0..3 {
                for j in 0..3 {
                    k[i * 3 + j] = scale
                        * len
                        * (w1[i] * w1[j] / 3.0
                            + (w1[i] * w2[j] + w2[i] * w1[j]) / 6.0
                            + w2[i] * w2[j] / 3.0);
                }
            }
            (g, k)
        }
        _ => {
            let n = sim.disc.basis.element_shapes();
            let (mut g, mut k) = (vec![0.0; n], vec![0.0; n * n]);
            for (t, wq) in GAUSS3 {
                let w: [f64; 3] = std::array::from_fn(|i| (1.0 - t) * w1[i] + t * w2[i]);
                let nv = shapes(sim, element, &w);
                for a in 0..n {
                    g[a] += scale * len * wq * nv[a];
                    for b in 0..n {
                        k[a * n + b] += scale * len * wq * nv[a] * nv[b];
                    }
                }
            }
            (g, k)
        }
    }
}

pub(super) fn loads(sim: &mut Simulation) -> Result<(), String> {
    let mut f = vec![0.0; sim.n_dofs()];
    for (li, load) in sim.model.loads.clone().iter().enumerate() {
        match &load.kind {
            LoadKind::Edge { a, b, traction } => {
                for (e, w1, w2, len) in edge_pieces(sim, load.block, *a, *b)
                    .map_err(|m| format!("[[load]] #{}: {m}", li + 1))?
                {
                    let (iw, _) = piece_integrals(sim, e, &w1, &w2, len, 1.0);
                    for (k, iw) in iw.iter().enumerate() {
                        for (c, tc) in traction.iter().enumerate() {
                            let d = sim.elem_dofs.of(e)[2 * k + c];
                            if d != NO_DOF {
                                f[d] += tc * iw;
                            }
                        }
                    }
                }
            }
            LoadKind::Point { p, force } => {
                let mp = locate(sim, load.block, *p, &format!("[[load]] #{}", li + 1))?;
                for (k, nk) in shapes(sim, mp.element, &mp.weights).iter().enumerate() {
                    for (c, fc) in force.iter().enumerate() {
                        let d = sim.elem_dofs.of(mp.element)[2 * k + c];
                        if d != NO_DOF {
                            f[d] += fc * nk;
                        }
                    }
                }
            }
        }
    }
    sim.f_load = f;
    Ok(())
}

pub(super) fn constraints(sim: &mut Simulation) -> Result<(), String> {
    let factor = sim.model.analysis.constraint_penalty;
    let h = sim.model.cover_size;
    for (ci, con) in sim.model.constraints.clone().iter().enumerate() {
        let young = sim.model.materials[sim.model.blocks[con.block].material].young;
        let comps: Vec<(usize, crate::model::TimeFunction)> = [(0, &con.ux), (1, &con.uy)]
            .into_iter()
            .filter_map(|(c, f)| f.clone().map(|f| (c, f)))
            .collect();
        for (c, func) in comps {
            sim.functions.push(func);
            let function = sim.functions.len() - 1;
            match &con.geometry {
                ConstraintGeometry::Point { p } => {
                    let k = factor * young;
                    let mp = locate(sim, con.block, *p, &format!("[[constraint]] #{}", ci + 1))?;
                    let w = shapes(sim, mp.element, &mp.weights);
                    let n = w.len();
                    let mut km = vec![0.0; n * n];
                    for i in 0..n {
                        for j in 0..n {
                            km[i * n + j] = k * w[i] * w[j];
                        }
                    }
                    let dofs = shape_dofs(sim, mp.element, c);
                    sim.penalties.push(Penalty {
                        dofs,
                        k: km,
                        g: w.iter().map(|wi| k * wi).collect(),
                        function,
                    });
                }
                ConstraintGeometry::Edge { a, b } => {
                    let p = factor * young / h;
                    for (e, w1, w2, len) in edge_pieces(sim, con.block, *a, *b)
                        .map_err(|m| format!("[[constraint]] #{}: {m}", ci + 1))?
                    {
                        // ∫ N_i N_j and ∫ N_i over the piece (order 0: w linear from w1 to w2,
                        // L (w1w1/3 + (w1w2+w2w1)/6 + w2w2/3) and L (w1 + w2)/2)
                        let (g, km) = piece_integrals(sim, e, &w1, &w2, len, p);
                        let dofs = shape_dofs(sim, e, c);
                        sim.penalties.push(Penalty {
                            dofs,
                            k: km,
                            g,
                            function,
                        });
                    }
                }
            }
        }
    }
    Ok(())
}

pub(super) fn monitors(sim: &mut Simulation) -> Result<(), String> {
    let mut pts = Vec::new();
    for m in sim.model.monitors.clone() {
        pts.push(match m.kind {
            MonitorKind::Point { p, block } => Some(locate(
                sim,
                block,
                p,
                &format!("[[monitor]] \"{}\"", m.name),
            )?),
            MonitorKind::Interface { .. }
            | MonitorKind::Block { .. }
            | MonitorKind::Bolt { .. }
            | MonitorKind::Tip { .. } => None,
        });
    }
    sim.monitor_points = pts;
    Ok(())
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // 3×3 blocks indexed as in the code under test
mod tests {
    use super::*;
    use crate::model::parse_model;
    use std::path::Path;

    const E: f64 = 2.0e9;
    const C: f64 = 1.0e4;
    const H: f64 = 0.25;

    /// A free unit square (E = 2 GPa, h = 0.25, constraint penalty 1e4) with `extra` keys.
    fn sim(extra: &str) -> Simulation {
        let text = format!(
            "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 1\ngravity = [0.0, 0.0]\n\
             constraint_penalty = {C:?}\n\
             [cover]\nsize = {H:?}\n\
             [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = {E:?}\npoisson = 0.25\n\
             [[block]]\nname = \"b\"\nmaterial = \"m\"\n\
             vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n{extra}"
        );
        let model = parse_model(&text, Path::new(".")).unwrap();
        Simulation::new(model).unwrap()
    }

    /// The mesh node (position) of each cover's x dof.
    fn node_of_dof(sim: &Simulation) -> Vec<Option<Vec2>> {
        let mut out = vec![None; sim.n_dofs()];
        for e in &sim.disc.elements {
            for k in 0..3 {
                if let Some(d) = sim.disc.covers[e.covers[k]].dof {
                    out[d] = Some(e.nodes[k]);
                }
            }
        }
        out
    }

    /// Σ f_x, Σ f_y and the moments Σ f_y·x_node, Σ f_x·y_node of a nodal force vector.
    fn resultants(sim: &Simulation, f: &[f64]) -> [f64; 4] {
        let nodes = node_of_dof(sim);
        let mut r = [0.0; 4];
        for (d, x) in nodes.iter().enumerate() {
            if let Some(x) = x {
                r[0] += f[d];
                r[1] += f[d + 1];
                r[2] += f[d + 1] * x[0];
                r[3] += f[d] * x[1];
            }
        }
        r
    }

    // Tolerances: the nodal sums are sums of a few dozen products of O(1) weights, so
    // 1e-12 relative is ~100 ulp; any wrong weight, missing piece or doubled piece is O(1).
    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-12 * scale
    }

    #[test]
    fn an_edge_tractions_nodal_forces_are_its_resultant_and_moment() {
        // traction (2e5, −1e6) Pa on the top edge from x = 0.2 to 0.9 (length 0.7, through
        // three elements): resultant t·L, and, the cover functions reproducing x, a moment
        // ∫ t_y x ds = t_y (0.9² − 0.2²)/2 about the origin
        let s = sim("[[load]]\nblock = \"b\"\nedge = [[0.2, 1.0], [0.9, 1.0]]\ntraction = [2.0e5, -1.0e6]\n");
        let r = resultants(&s, &s.f_load);
        let (tx, ty, l) = (2.0e5, -1.0e6, 0.7);
        assert!(close(r[0], tx * l, 1e6), "{r:?}");
        assert!(close(r[1], ty * l, 1e6), "{r:?}");
        assert!(close(r[2], ty * (0.81 - 0.04) / 2.0, 1e6), "{r:?}");
        assert!(close(r[3], tx * l * 1.0, 1e6), "{r:?}");
        // only covers whose support touches the loaded stretch of the edge are loaded
        let nodes = node_of_dof(&s);
        for (d, x) in nodes.iter().enumerate() {
            if let Some(x) = x {
                if s.f_load[d] != 0.0 || s.f_load[d + 1] != 0.0 {
                    assert!(x[1] > 1.0 - H - 1e-9, "load on a cover at {x:?}");
                    assert!(x[0] > 0.2 - H - 1e-9 && x[0] < 0.9 + H + 1e-9, "{x:?}");
                }
            }
        }
    }

    #[test]
    fn a_point_load_lands_on_the_covers_of_its_element_with_its_barycentric_weights() {
        let p = [0.3, 0.6];
        let force = [1.0e3, -2.0e3];
        let s = sim("[[load]]\nblock = \"b\"\npoint = [0.3, 0.6]\nforce = [1.0e3, -2.0e3]\n");
        let mp = s.disc.locate(0, p).unwrap();
        let e = &s.disc.elements[mp.element];
        // the weights are p's barycentric coordinates in the element's triangle
        let w = mp.weights;
        assert!(
            w.iter().all(|&wk| (-1e-12..=1.0 + 1e-12).contains(&wk)),
            "{w:?}"
        );
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        for c in 0..2 {
            let x: f64 = (0..3).map(|k| w[k] * e.nodes[k][c]).sum();
            assert!((x - p[c]).abs() < 1e-12, "{x} vs {}", p[c]);
        }
        // f = force · w_k on the three covers' dofs, nothing anywhere else
        let mut expected = vec![0.0; s.n_dofs()];
        for k in 0..3 {
            let d = s.disc.covers[e.covers[k]].dof.unwrap();
            expected[d] += force[0] * w[k];
            expected[d + 1] += force[1] * w[k];
        }
        assert_eq!(s.f_load, expected);
        let r = resultants(&s, &s.f_load);
        assert!(
            close(r[0], force[0], 1e3) && close(r[1], force[1], 1e3),
            "{r:?}"
        );
        // and its moment is the force's: the weights reproduce the point
        assert!(close(r[2], force[1] * p[0], 1e3), "{r:?}");
    }

    #[test]
    fn a_point_constraint_is_a_spring_k_equal_c_e_at_the_point() {
        let s = sim("[[constraint]]\nblock = \"b\"\npoint = [0.3, 0.6]\nux = 1.0e-3\n");
        // one component constrained: one spring, on the x dofs
        assert_eq!(s.penalties.len(), 1);
        let pen = &s.penalties[0];
        let mp = s.disc.locate(0, [0.3, 0.6]).unwrap();
        let e = &s.disc.elements[mp.element];
        let k = C * E;
        for i in 0..3 {
            assert_eq!(pen.dofs[i], s.disc.covers[e.covers[i]].dof.unwrap());
            assert!(close(pen.g[i], k * mp.weights[i], k));
            for j in 0..3 {
                assert!(close(
                    pen.k[i * 3 + j],
                    k * mp.weights[i] * mp.weights[j],
                    k
                ));
            }
        }
        // a rigid shift u of the element stretches the spring by u: force k u, target g·u0
        let ksum: f64 = pen.k.iter().sum();
        assert!(close(ksum, k, k), "{ksum} vs {k}");
        assert!(close(pen.g.iter().sum::<f64>(), k, k));
        assert_eq!(s.functions[pen.function].eval(0.5), 1.0e-3);
    }

    #[test]
    fn an_edge_constraint_is_a_distributed_spring_c_e_over_h_per_metre() {
        // uy held on the left edge (length 1, four elements): p = c E / h N/m per m
        let s = sim("[[constraint]]\nblock = \"b\"\nedge = [[0.0, 0.0], [0.0, 1.0]]\nuy = [[0.0, 0.0], [1.0, 2.0e-3]]\n");
        let p = C * E / H;
        assert!(s.penalties.len() >= 4, "{}", s.penalties.len());
        let nodes = node_of_dof(&s);
        let (mut ksum, mut gsum, mut moment) = (0.0, 0.0, 0.0);
        for pen in &s.penalties {
            // y components only (dof of a cover + 1), covers at the left edge
            for &d in &pen.dofs {
                let x = nodes[d - 1].expect("a y dof");
                assert!(x[0] < H, "{x:?}");
            }
            ksum += pen.k.iter().sum::<f64>();
            gsum += pen.g.iter().sum::<f64>();
            moment += (0..3)
                .map(|i| pen.g[i] * nodes[pen.dofs[i] - 1].unwrap()[1])
                .sum::<f64>();
            // symmetric, positive semidefinite 3×3 (a Gram matrix of the weights)
            for i in 0..3 {
                assert!(pen.k[i * 4] >= 0.0);
                for j in 0..3 {
                    assert_eq!(pen.k[i * 3 + j], pen.k[j * 3 + i]);
                }
            }
            assert_eq!(s.functions[pen.function].eval(0.5), 1.0e-3);
        }
        // a rigid shift: total stiffness p·L; the target forces p·L and their moment p ∫ y dy
        assert!(close(ksum, p, p), "{ksum} vs {p}");
        assert!(close(gsum, p, p), "{gsum} vs {p}");
        assert!(close(moment, p * 0.5, p), "{moment} vs {}", p * 0.5);
    }

    #[test]
    fn monitors_and_bad_points() {
        let s = sim("[[monitor]]\nname = \"m\"\npoint = [0.7, 0.2]\n");
        let mp = s.monitor_points[0].unwrap();
        let e = &s.disc.elements[mp.element];
        for c in 0..2 {
            let x: f64 = (0..3).map(|k| mp.weights[k] * e.nodes[k][c]).sum();
            assert!((x - [0.7, 0.2][c]).abs() < 1e-12);
        }
        let text = "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 1\n[cover]\nsize = 0.25\n\
                    [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = 1e9\npoisson = 0.25\n\
                    [[block]]\nname = \"b\"\nmaterial = \"m\"\n\
                    vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]\n\
                    [[load]]\nblock = \"b\"\npoint = [0.5, 0.5]\nforce = [1.0, 0.0]\n";
        let mut s = Simulation::new(parse_model(text, Path::new(".")).unwrap()).unwrap();
        // a point outside the block (as a load would be after the block moved): one line
        if let LoadKind::Point { p, .. } = &mut s.model.loads[0].kind {
            *p = [1.5, 0.5];
        }
        let err = loads(&mut s).unwrap_err();
        assert!(
            err.starts_with("[[load]] #1: point [1.5, 0.5] is not inside block \"b\""),
            "{err}"
        );
    }
}
