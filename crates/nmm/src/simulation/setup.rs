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
use crate::cover::{barycentric, MaterialPoint};
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

fn cover_dof(sim: &Simulation, element: usize, k: usize, component: usize) -> usize {
    let c = sim.disc.elements[element].covers[k];
    match sim.disc.covers[c].dof {
        Some(d) => d + component,
        None => NO_DOF,
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
                    for k in 0..3 {
                        let iw = 0.5 * len * (w1[k] + w2[k]);
                        for (c, tc) in traction.iter().enumerate() {
                            let d = cover_dof(sim, e, k, c);
                            if d != NO_DOF {
                                f[d] += tc * iw;
                            }
                        }
                    }
                }
            }
            LoadKind::Point { p, force } => {
                let mp = locate(sim, load.block, *p, &format!("[[load]] #{}", li + 1))?;
                for k in 0..3 {
                    for (c, fc) in force.iter().enumerate() {
                        let d = cover_dof(sim, mp.element, k, c);
                        if d != NO_DOF {
                            f[d] += fc * mp.weights[k];
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
                    let w = mp.weights;
                    let mut km = [0.0; 9];
                    for i in 0..3 {
                        for j in 0..3 {
                            km[i * 3 + j] = k * w[i] * w[j];
                        }
                    }
                    let dofs = [0, 1, 2].map(|kk| cover_dof(sim, mp.element, kk, c));
                    sim.penalties.push(Penalty {
                        dofs,
                        k: km,
                        g: [k * w[0], k * w[1], k * w[2]],
                        function,
                    });
                }
                ConstraintGeometry::Edge { a, b } => {
                    let p = factor * young / h;
                    for (e, w1, w2, len) in edge_pieces(sim, con.block, *a, *b)
                        .map_err(|m| format!("[[constraint]] #{}: {m}", ci + 1))?
                    {
                        // ∫ w_i w_j over the piece, w linear from w1 to w2: L (w1w1/3 + (w1w2+w2w1)/6 + w2w2/3)
                        let mut km = [0.0; 9];
                        for i in 0..3 {
                            for j in 0..3 {
                                km[i * 3 + j] = p
                                    * len
                                    * (w1[i] * w1[j] / 3.0
                                        + (w1[i] * w2[j] + w2[i] * w1[j]) / 6.0
                                        + w2[i] * w2[j] / 3.0);
                            }
                        }
                        let g = [0, 1, 2].map(|i| p * len * 0.5 * (w1[i] + w2[i]));
                        let dofs = [0, 1, 2].map(|kk| cover_dof(sim, e, kk, c));
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
            MonitorKind::Interface { .. } | MonitorKind::Block { .. } => None,
        });
    }
    sim.monitor_points = pts;
    Ok(())
}
