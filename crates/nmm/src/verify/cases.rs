//! The verification cases as functions: each builds its model (TOML text, so that
//! the whole path from the file format is exercised), runs it and returns the
//! figures that are compared with the closed form or independent reference.
//! The integration tests (`tests/`) call them at full size and assert; `nmm verify`
//! calls them at a quick size and writes a report.

use crate::contact::friction::ContactStatus;
use crate::model::{parse_model, Model};
use crate::simulation::{monitor_values, Simulation};
use std::path::Path;

/// Parse a generated model (a bug in the generator is reported as an error).
pub fn model(text: &str) -> Result<Model, String> {
    parse_model(text, Path::new(".")).map_err(|e| e.to_string())
}

fn simulate(text: &str) -> Result<Simulation, String> {
    Simulation::new(model(text)?)
}

fn run_to_end(sim: &mut Simulation) -> Result<Vec<usize>, String> {
    let mut its = Vec::new();
    while !sim.finished() {
        its.push(sim.advance().map_err(|e| e.to_string())?.iterations);
    }
    Ok(its)
}

/// Median of a list of counts.
pub fn median(v: &[usize]) -> usize {
    let mut s = v.to_vec();
    s.sort_unstable();
    s.get(s.len() / 2).copied().unwrap_or(0)
}

/// A TOML array of points.
pub fn poly(pts: &[[f64; 2]]) -> String {
    let items: Vec<String> = pts
        .iter()
        .map(|p| format!("[{:.17e}, {:.17e}]", p[0], p[1]))
        .collect();
    format!("[{}]", items.join(", "))
}

/// A TOML point.
pub fn point(p: [f64; 2]) -> String {
    format!("[{:.17e}, {:.17e}]", p[0], p[1])
}

/// Rotate by `angle_deg` about the origin, then translate.
pub fn place(pts: &[[f64; 2]], angle_deg: f64, offset: [f64; 2]) -> Vec<[f64; 2]> {
    let (s, c) = angle_deg.to_radians().sin_cos();
    pts.iter()
        .map(|p| {
            [
                offset[0] + c * p[0] - s * p[1],
                offset[1] + s * p[0] + c * p[1],
            ]
        })
        .collect()
}

/// Observed convergence orders from errors at successive halvings of h.
pub fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

fn material(e: f64, nu: f64, rho: f64, plane: &str) -> String {
    format!("[[material]]\nname = \"m\"\ndensity = {rho}\nyoung = {e}\npoisson = {nu}\nplane = \"{plane}\"\n")
}

// ---------------------------------------------------------------- patch test

/// Largest relative errors of a patch test.
#[derive(Debug, Clone, Copy)]
pub struct PatchErrors {
    pub stress: f64,
    pub displacement: f64,
}

/// Rotated rectangle under self-equilibrated tractions t = σ n on every edge (a uniform
/// stress σ = [2, −1, 0.5] MPa), rigid modes taken out by three point constraints that
/// carry no reaction. Exact: uniform σ and u = ε(x − a) + rotation, ε = D⁻¹σ.
pub fn patch(angle: f64, h: f64, offset: [f64; 2]) -> Result<PatchErrors, String> {
    let (e, nu) = (1.0e9, 0.25);
    let sigma = [2.0e6, -1.0e6, 0.5e6];
    let pts = place(
        &[[0.0, 0.0], [1.0, 0.0], [1.0, 0.6], [0.0, 0.6]],
        angle,
        offset,
    );
    let mut loads = String::new();
    for i in 0..4 {
        let (a, b) = (pts[i], pts[(i + 1) % 4]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let n = [(b[1] - a[1]) / len, -(b[0] - a[0]) / len];
        let t = [
            sigma[0] * n[0] + sigma[2] * n[1],
            sigma[2] * n[0] + sigma[1] * n[1],
        ];
        loads += &format!(
            "[[load]]\nblock = \"b\"\nedge = {}\ntraction = {}\n",
            poly(&[a, b]),
            point(t)
        );
    }
    let (pa, pb) = (pts[0], pts[1]);
    // the second point fixes the rotation: constrain its displacement across a→b
    let across_x = (pb[1] - pa[1]).abs() > (pb[0] - pa[0]).abs();
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1000.0\nsteps = 1\n[cover]\nsize = {h}\n{}\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = {}\n{loads}\
         [[constraint]]\nblock = \"b\"\npoint = {}\nux = 0.0\nuy = 0.0\n\
         [[constraint]]\nblock = \"b\"\npoint = {}\n{} = 0.0\n",
        material(e, nu, 2000.0, "stress"),
        poly(&pts),
        point(pa),
        point(pb),
        if across_x { "ux" } else { "uy" }
    );
    let mut sim = simulate(&text)?;
    // material points at every element vertex, located before the step
    let probes: Vec<_> = sim
        .disc
        .elements
        .iter()
        .enumerate()
        .flat_map(|(ei, el)| {
            el.polygon.iter().map(move |x| {
                (
                    *x,
                    crate::cover::MaterialPoint {
                        element: ei,
                        weights: el.weights(*x),
                    },
                )
            })
        })
        .collect();
    run_to_end(&mut sim)?;
    let eps = [
        (sigma[0] - nu * sigma[1]) / e,
        (sigma[1] - nu * sigma[0]) / e,
        2.0 * (1.0 + nu) * sigma[2] / e,
    ];
    let smax = sigma.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    let stress = sim
        .stress
        .iter()
        .flat_map(|s| (0..3).map(move |k| (s[k] - sigma[k]).abs() / smax))
        .fold(0.0, f64::max);
    let lin = |x: [f64; 2], om: f64| -> [f64; 2] {
        let d = [x[0] - pa[0], x[1] - pa[1]];
        [
            eps[0] * d[0] + 0.5 * eps[2] * d[1] - om * d[1],
            0.5 * eps[2] * d[0] + eps[1] * d[1] + om * d[0],
        ]
    };
    // rotation ω such that the constrained component of u(b) vanishes
    let om = if across_x {
        lin(pb, 0.0)[0] / (pb[1] - pa[1])
    } else {
        -lin(pb, 0.0)[1] / (pb[0] - pa[0])
    };
    let umax = pts
        .iter()
        .map(|p| lin(*p, om))
        .fold(0.0f64, |m, u| m.max(u[0].abs()).max(u[1].abs()));
    let displacement = probes
        .iter()
        .map(|(x0, mp)| {
            let u = sim.displacement_at(mp);
            let w = lin(*x0, om);
            (u[0] - w[0]).abs().max((u[1] - w[1]).abs()) / umax
        })
        .fold(0.0, f64::max);
    Ok(PatchErrors {
        stress,
        displacement,
    })
}

/// Rollers by edge penalty on the left and bottom edges, uniform tension σ on the right
/// edge (ν = 0). Returns (max relative stress error, relative error of the right edge's
/// displacement against σ w/E shifted by the stated penalty stretch +σ/p, p = factor·E/h).
pub fn roller_patch(h: f64, factor: f64) -> Result<(f64, f64), String> {
    roller_patch_sized(h, factor, 1.0, 0.5)
}

/// Cut cells: the roller patch with its right and top edges `delta`·h beyond mesh lines
/// (the mesh starts h/2 before the block's lower-left corner), so that sliver elements
/// of area ≈ delta·h² and covers with tiny supports appear along both edges.
pub fn cut_cell_patch(h: f64, delta: f64) -> Result<(f64, f64), String> {
    roller_patch_sized(h, 1e6, (10.5 + delta) * h, (5.5 + delta) * h)
}

fn roller_patch_sized(h: f64, factor: f64, w: f64, ht: f64) -> Result<(f64, f64), String> {
    let (e, sx) = (1.0e9, 1.0e6);
    let (x0, y0) = (0.031, 0.017);
    let (x1, y1) = (x0 + w, y0 + ht);
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1000.0\nsteps = 1\nconstraint_penalty = {factor}\n[cover]\nsize = {h}\n{}\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]\n\
         [[load]]\nblock = \"b\"\nedge = [[{x1}, {y0}], [{x1}, {y1}]]\ntraction = [{sx}, 0.0]\n\
         [[constraint]]\nblock = \"b\"\nedge = [[{x0}, {y0}], [{x0}, {y1}]]\nux = 0.0\n\
         [[constraint]]\nblock = \"b\"\nedge = [[{x0}, {y0}], [{x1}, {y0}]]\nuy = 0.0\n\
         [[monitor]]\nname = \"right\"\npoint = [{x1}, {ym}]\n",
        material(e, 0.0, 2000.0, "strain"),
        ym = y0 + 0.5 * ht
    );
    let mut sim = simulate(&text)?;
    run_to_end(&mut sim)?;
    let stress = sim
        .stress
        .iter()
        .map(|s| (s[0] - sx).abs().max(s[1].abs()).max(s[2].abs()) / sx)
        .fold(0.0, f64::max);
    // the left roller stretches by σ/p toward +x under its reaction
    let want = sx / e * w + sx / (sim.model.analysis.constraint_penalty * e / h);
    let u = monitor_values(&sim)[0];
    Ok((stress, ((u - want) / want).abs()))
}

// ---------------------------------------------------------------- column, cantilever

/// Self-weight column of height L = 10 m (ν = 0, static), h = L/n. Returns the relative
/// error of the top displacement against −ρ g L²/(2E).
pub fn column(n_per_length: usize) -> Result<f64, String> {
    let (l, w, e, rho, g) = (10.0, 1.0, 1.0e9, 2000.0, 9.81);
    let (x0, y0) = (0.013, 0.021);
    let h = l / n_per_length as f64;
    let (x1, y1) = (x0 + w, y0 + l);
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 100.0\nsteps = 1\ngravity = [0.0, -{g}]\n[cover]\nsize = {h}\n{}\
         [[block]]\nname = \"column\"\nmaterial = \"m\"\nvertices = [[{x0}, {y0}], [{x1}, {y0}], [{x1}, {y1}], [{x0}, {y1}]]\n\
         [[constraint]]\nblock = \"column\"\nedge = [[{x0}, {y0}], [{x1}, {y0}]]\nuy = 0.0\n\
         [[constraint]]\nblock = \"column\"\npoint = [{x0}, {y0}]\nux = 0.0\n\
         [[monitor]]\nname = \"top\"\npoint = [{xm}, {y1}]\n",
        material(e, 0.0, rho, "strain"),
        xm = x0 + 0.5 * w
    );
    let mut sim = simulate(&text)?;
    run_to_end(&mut sim)?;
    let exact = -rho * g * l * l / (2.0 * e);
    Ok(((monitor_values(&sim)[1] - exact) / exact).abs())
}

/// Timoshenko beam tip deflection of the cantilever of [`cantilever_tip`].
pub fn cantilever_reference() -> f64 {
    let (l, d, e, nu, p) = (10.0f64, 1.0f64, 1.0e9, 0.3, 1.0e3);
    let i = d.powi(3) / 12.0;
    let g = e / (2.0 * (1.0 + nu));
    p * l.powi(3) / (3.0 * e * i) + p * l / (5.0 / 6.0 * g * d)
}

/// Cantilever (plane stress) L = 10 m, d = 1 m, clamped at x = 0 by edge penalty, uniform
/// end shear of resultant P = 1 kN/m at x = L. Returns the tip deflection (positive down).
pub fn cantilever_tip(h: f64) -> Result<f64, String> {
    let (l, d, e, nu, p) = (10.0, 1.0, 1.0e9, 0.3, 1.0e3);
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 100.0\nsteps = 1\n[cover]\nsize = {h}\n{}\
         [[block]]\nname = \"beam\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [{l}, 0.0], [{l}, {d}], [0.0, {d}]]\n\
         [[constraint]]\nblock = \"beam\"\nedge = [[0.0, 0.0], [0.0, {d}]]\nux = 0.0\nuy = 0.0\n\
         [[load]]\nblock = \"beam\"\nedge = [[{l}, 0.0], [{l}, {d}]]\ntraction = [0.0, -{t}]\n\
         [[monitor]]\nname = \"tip\"\npoint = [{l}, {hd}]\n",
        material(e, nu, 2000.0, "stress"),
        t = p / d,
        hd = 0.5 * d
    );
    let mut sim = simulate(&text)?;
    run_to_end(&mut sim)?;
    Ok(-monitor_values(&sim)[1])
}

// ---------------------------------------------------------------- dynamics

/// Free fall for 1 s (dynamic, Δt = 0.01 s): returns (computed u_y, exact −½ g t²).
pub fn free_fall() -> Result<(f64, f64), String> {
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.01\nsteps = 100\ngravity = [0.0, -9.81]\n[cover]\nsize = 0.3\n{}\
         [[block]]\nname = \"b\"\nmaterial = \"m\"\nvertices = [[0.1, 0.2], [1.1, 0.25], [0.9, 1.0], [0.2, 0.8]]\n\
         [[monitor]]\nname = \"c\"\npoint = [0.5, 0.5]\n",
        material(1.0e9, 0.25, 2500.0, "strain")
    );
    let mut sim = simulate(&text)?;
    run_to_end(&mut sim)?;
    Ok((monitor_values(&sim)[1], -0.5 * 9.81))
}

/// Bar (L = 10 m, ν = 0) fixed at one end, step traction at the other, 40 steps per
/// period T = 4L/c. Returns (period measured between upward zero crossings of
/// u_tip − u_static, exact T).
pub fn bar_period() -> Result<(f64, f64), String> {
    let (l, e, rho, sx) = (10.0f64, 1.0e9f64, 2000.0f64, 1.0e6);
    let period = 4.0 * l / (e / rho).sqrt();
    let dt = period / 40.0;
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt}\nsteps = 160\n[cover]\nsize = 0.25\n{}\
         [[block]]\nname = \"bar\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [{l}, 0.0], [{l}, 0.5], [0.0, 0.5]]\n\
         [[constraint]]\nblock = \"bar\"\nedge = [[0.0, 0.0], [0.0, 0.5]]\nux = 0.0\nuy = 0.0\n\
         [[load]]\nblock = \"bar\"\nedge = [[{l}, 0.0], [{l}, 0.5]]\ntraction = [{sx}, 0.0]\n\
         [[monitor]]\nname = \"tip\"\npoint = [{l}, 0.25]\n",
        material(e, 0.0, rho, "stress")
    );
    let mut sim = simulate(&text)?;
    let u_static = sx * l / e;
    let mut hist = vec![(0.0, -u_static)];
    while !sim.finished() {
        sim.advance().map_err(|e| e.to_string())?;
        hist.push((sim.time, monitor_values(&sim)[0] - u_static));
    }
    let ups: Vec<f64> = hist
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1))
        .collect();
    if ups.len() < 3 {
        return Err(format!(
            "bar period: only {} upward zero crossings",
            ups.len()
        ));
    }
    Ok((ups[2] - ups[1], period))
}

const DAMPED_BAR_E: f64 = 1.0e9;
const DAMPED_BAR_RHO: f64 = 2500.0;

/// The closed-form first axial frequency πc/L (rad/s) of the bar of [`damped_bar`].
pub fn damped_bar_omega() -> f64 {
    std::f64::consts::PI * (DAMPED_BAR_E / DAMPED_BAR_RHO).sqrt()
}

/// What a damped free vibration of the bar of [`damped_bar`] shows.
#[derive(Debug, Clone)]
pub struct DampedBar {
    /// Closed-form angular frequency of the first axial mode of the free–free bar, πc/L.
    pub omega: f64,
    /// Δt used (s).
    pub dt: f64,
    /// ln(e_k / e_{k+1}) between successive maxima of the bar's elongation e(t).
    pub decrements: Vec<f64>,
    /// Time between the first two maxima (the damped period, s).
    pub period: f64,
}

/// A free–free elastic bar (L = 1 m × 0.1 m, ν = 0, plane stress: c = √(E/ρ)), one block,
/// no contact, no constraint, set vibrating in its first axial mode u = cos(πx/L) by an
/// initial velocity 1 mm/s × cos(πx/L) at the cover nodes, with the material's `damping`
/// (the TOML value, e.g. `{ alpha = 10.0 }`), `steps_per_period` steps per closed-form
/// period 2π/ω for `periods` periods. The elongation e = u_x(L) − u_x(0) (insensitive to a
/// rigid drift) is sampled at every step; its maxima are located by a parabola through the
/// three samples around each.
pub fn damped_bar(damping: &str, steps_per_period: f64, periods: f64) -> Result<DampedBar, String> {
    let (l, d, e, rho) = (1.0f64, 0.1f64, DAMPED_BAR_E, DAMPED_BAR_RHO);
    let omega = damped_bar_omega();
    let dt = std::f64::consts::TAU / omega / steps_per_period;
    let steps = (periods * steps_per_period).ceil() as usize;
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt}\nsteps = {steps}\n[cover]\nsize = {h}\norigin = [0.0, 0.0]\n{}\
         damping = {damping}\n\
         [[block]]\nname = \"bar\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [{l}, 0.0], [{l}, {d}], [0.0, {d}]]\n\
         [[monitor]]\nname = \"left\"\npoint = [0.0, {hd}]\n\
         [[monitor]]\nname = \"right\"\npoint = [{l}, {hd}]\n",
        material(e, 0.0, rho, "stress"),
        h = l / 20.0,
        hd = 0.5 * d
    );
    let mut sim = simulate(&text)?;
    for c in &sim.disc.covers {
        if let Some(dof) = c.dof {
            let x = sim.disc.mesh.node(c.node);
            sim.v[dof] = 1.0e-3 * (std::f64::consts::PI * x[0] / l).cos();
        }
    }
    let elongation = |sim: &Simulation| {
        let m = monitor_values(sim);
        m[4] - m[0]
    };
    let mut hist = vec![(0.0, elongation(&sim))];
    while !sim.finished() {
        sim.advance().map_err(|e| e.to_string())?;
        hist.push((sim.time, elongation(&sim)));
    }
    let maxima: Vec<(f64, f64)> = hist
        .windows(3)
        .filter(|w| w[1].1 > w[0].1 && w[1].1 >= w[2].1 && w[1].1 > 0.0)
        .map(|w| {
            // parabola through three equally spaced samples
            let (a, b, c) = (w[0].1, w[1].1, w[2].1);
            let den = a - 2.0 * b + c;
            let s = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
            (w[1].0 + s * dt, b - 0.25 * (a - c) * s)
        })
        .collect();
    if maxima.len() < 2 {
        return Err(format!("damped bar: only {} maxima", maxima.len()));
    }
    Ok(DampedBar {
        omega,
        dt,
        decrements: maxima.windows(2).map(|p| (p[0].1 / p[1].1).ln()).collect(),
        period: maxima[1].0 - maxima[0].0,
    })
}

// ---------------------------------------------------------------- contact and friction

/// One step of the direct shear test.
#[derive(Debug, Clone)]
pub struct ShearStep {
    /// Imposed shear displacement (m).
    pub displacement: f64,
    /// Shear stress on the joint, −fx / L (Pa).
    pub tau: f64,
    /// Normal stress on the joint, fy / L (Pa): the vertical force the lower block takes,
    /// as the load cell of a shear box measures it.
    pub sigma_n: f64,
    /// Whether every closed contact of the joint slides.
    pub sliding: bool,
    /// Linear solves of the step (failed attempts included).
    pub iterations: usize,
    /// Δt cuts of the step.
    pub cuts: usize,
    pub residuals: Vec<f64>,
}

/// The paper's direct shear test (see `examples/direct_shear.toml`) with normal stress
/// `sigma_n` and friction angle `phi`: five steps of 0.06 mm.
pub fn direct_shear(sigma_n: f64, phi: f64, algorithm: &str) -> Result<Vec<ShearStep>, String> {
    direct_shear_on(sigma_n, phi, algorithm, None)
}

/// Where the joint of [`direct_shear_on`] lies relative to the mathematical mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointOnMesh {
    /// On a mesh line.
    On,
    /// 10⁻³ h from a mesh line.
    Near,
    /// Halfway between two mesh lines (the default placement of the mesh).
    Between,
}

impl JointOnMesh {
    /// The `[cover] origin` that puts the joint (y = 0.1, h = 0.025) there.
    pub fn origin(self) -> Option<[f64; 2]> {
        match self {
            JointOnMesh::On => Some([0.0, 0.0]),
            JointOnMesh::Near => Some([0.0, 0.025e-3]),
            JointOnMesh::Between => Some([0.0, 0.0125]),
        }
    }
}

/// [`direct_shear`] with the mathematical mesh through `origin` (`[cover] origin`).
pub fn direct_shear_on(
    sigma_n: f64,
    phi: f64,
    algorithm: &str,
    origin: Option<[f64; 2]>,
) -> Result<Vec<ShearStep>, String> {
    let origin = origin
        .map(|o| format!("origin = [{}, {}]\n", o[0], o[1]))
        .unwrap_or_default();
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 5\nfriction = \"{algorithm}\"\n[cover]\nsize = 0.025\n{origin}\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 1.0e9\npoisson = 0.0\n\
         [[block]]\nname = \"lower\"\nmaterial = \"rock\"\nvertices = [[0.0, 0.0], [0.2, 0.0], [0.2, 0.1], [0.0, 0.1]]\nfixed = true\n\
         [[block]]\nname = \"upper\"\nmaterial = \"rock\"\nvertices = [[0.05, 0.1], [0.15, 0.1], [0.15, 0.2], [0.05, 0.2]]\n\
         [[interface]]\nfriction_angle = {phi}\nnormal_penalty = 1.0e11\nshear_penalty = 1.0e11\n\
         [[load]]\nblock = \"upper\"\nedge = [[0.05, 0.2], [0.15, 0.2]]\ntraction = [0.0, -{sigma_n}]\n\
         [[constraint]]\nblock = \"upper\"\nedge = [[0.05, 0.1], [0.05, 0.2]]\nux = [[0.0, 0.0], [5.0, 3.0e-4]]\n\
         [[monitor]]\nname = \"joint\"\ninterface = [\"upper\", \"lower\"]\n"
    );
    let mut sim = simulate(&text)?;
    let mut out = Vec::new();
    while !sim.finished() {
        let rep = sim.advance().map_err(|e| e.to_string())?;
        let v = monitor_values(&sim);
        let states: Vec<_> = sim
            .contacts
            .contacts
            .iter()
            .map(|c| c.response.status)
            .collect();
        use crate::contact::ContactStatus::{Slide, Stick};
        out.push(ShearStep {
            displacement: 6.0e-5 * sim.time,
            tau: -v[0] / 0.1,
            sigma_n: v[1] / 0.1,
            sliding: states.contains(&Slide) && !states.contains(&Stick),
            iterations: rep.solves,
            cuts: rep.cuts,
            residuals: rep.residuals,
        });
    }
    Ok(out)
}

/// A block (0.5 m × 0.25 m) on a plane dipping θ, both blocks rotated so the mesh is not
/// aligned, dynamic under gravity. Returns (slip along the plane at the end, closed form
/// ½ g (sin θ − cos θ tan φ) t² (0 when φ ≥ θ), Newton iterations per step).
pub fn incline(
    theta: f64,
    phi: f64,
    dt: f64,
    steps: usize,
) -> Result<(f64, f64, Vec<usize>), String> {
    let rot = |pts: &[[f64; 2]]| place(pts, -theta, [0.0, 2.5]);
    let base = rot(&[[0.0, -0.5], [4.0, -0.5], [4.0, 0.0], [0.0, 0.0]]);
    let slider = rot(&[[0.5, 0.0], [1.0, 0.0], [1.0, 0.25], [0.5, 0.25]]);
    let c = rot(&[[0.75, 0.125]])[0];
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -9.81]\n[cover]\nsize = 0.0625\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = {}\nfixed = true\n\
         [[block]]\nname = \"slider\"\nmaterial = \"rock\"\nvertices = {}\n\
         [[interface]]\nfriction_angle = {phi}\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n\
         [[monitor]]\nname = \"c\"\npoint = {}\n",
        poly(&base),
        poly(&slider),
        point(c)
    );
    let mut sim = simulate(&text)?;
    let its = run_to_end(&mut sim)?;
    let v = monitor_values(&sim);
    let (s, co) = theta.to_radians().sin_cos();
    let slip = v[0] * co - v[1] * s;
    let t = sim.time;
    let exact = (0.5 * 9.81 * (s - co * phi.to_radians().tan()) * t * t).max(0.0);
    Ok((slip, exact, its))
}

/// One block (2.5 m × 0.5 m) cut by one persistent joint dipping θ (a `[[joint_set]]`
/// whose only trace in the block is 0.25 m above its base), rotated like [`incline`],
/// dynamic under gravity. The lower piece is held by an edge constraint on the block's
/// base (it lies on that piece only); the joint's faces take `[[interface]] joint`
/// (friction φ) while the default interface has φ = 60° > θ, so a wrong interface on
/// the joint holds the upper piece. Returns (slip of the upper piece along the joint at
/// the end, closed form ½ g (sin θ − cos θ tan φ) t² (0 when φ ≥ θ), Newton iterations
/// per step).
pub fn jointed_incline(
    theta: f64,
    phi: f64,
    dt: f64,
    steps: usize,
) -> Result<(f64, f64, Vec<usize>), String> {
    let rot = |pts: &[[f64; 2]]| place(pts, -theta, [0.0, 2.5]);
    let mass = rot(&[[0.0, -0.25], [2.5, -0.25], [2.5, 0.25], [0.0, 0.25]]);
    let base = rot(&[[0.0, -0.25], [2.5, -0.25]]);
    let origin = rot(&[[0.0, 0.0]])[0];
    let c = rot(&[[1.25, 0.125]])[0];
    let text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -9.81]\n[cover]\nsize = 0.125\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"mass\"\nmaterial = \"rock\"\nvertices = {}\n\
         [[joint_set]]\nname = \"plane\"\nangle = {}\nspacing = 100.0\norigin = {}\n\
         [[interface]]\nfriction_angle = 60.0\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n\
         [[interface]]\njoint = \"plane\"\nfriction_angle = {phi}\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n\
         [[constraint]]\nblock = \"mass\"\nedge = [{}, {}]\nux = 0.0\nuy = 0.0\n\
         [[monitor]]\nname = \"c\"\npoint = {}\n",
        poly(&mass),
        180.0 - theta,
        point(origin),
        point(base[0]),
        point(base[1]),
        point(c)
    );
    let mut sim = simulate(&text)?;
    if sim.model.blocks.len() != 2 {
        return Err(format!(
            "the joint cut the block into {} pieces, expected 2",
            sim.model.blocks.len()
        ));
    }
    let its = run_to_end(&mut sim)?;
    let v = monitor_values(&sim);
    let (s, co) = theta.to_radians().sin_cos();
    let slip = v[0] * co - v[1] * s;
    let t = sim.time;
    let exact = (0.5 * 9.81 * (s - co * phi.to_radians().tan()) * t * t).max(0.0);
    Ok((slip, exact, its))
}

/// What [`settle`] measures.
#[derive(Debug, Clone)]
pub struct Settled {
    /// Total downward force on the fixed base from all blocks.
    pub base_force: f64,
    pub weight: f64,
    pub max_velocity: f64,
    /// Largest contact penetration −t_N/p_N.
    pub max_penetration: f64,
    pub iterations: Vec<usize>,
}

/// Rectangular blocks `(x, y, w, h)` on a fixed base, settled under gravity in static
/// mode (DDA's quasi-static analysis: the velocity is reset every step) with Δt = 10 ms.
/// Static mode is how a model is brought to rest: in dynamic mode the β = ½, γ = 1
/// scheme damps the displacement of very stiff (penalty) modes in a step but leaves their
/// velocity flipping sign from step to step (see `time::amplification`).
pub fn settle(blocks: &[(f64, f64, f64, f64)], steps: usize) -> Result<Settled, String> {
    settle_with(blocks, steps, "static", 0.01)
}

/// [`settle`] with a chosen mode and time step.
pub fn settle_with(
    blocks: &[(f64, f64, f64, f64)],
    steps: usize,
    mode: &str,
    dt: f64,
) -> Result<Settled, String> {
    let (rho, g, pn) = (2000.0, 9.81, 1.0e10);
    let rect = |x0: f64, y0: f64, w: f64, h: f64| {
        poly(&[[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
    };
    let mut text = format!(
        "[analysis]\nmode = \"{mode}\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -{g}]\n[cover]\nsize = 0.1\n\
         [[material]]\nname = \"brick\"\ndensity = {rho}\nyoung = 5.0e9\npoisson = 0.2\n\
         [[block]]\nname = \"base\"\nmaterial = \"brick\"\nvertices = {}\nfixed = true\n\
         [[interface]]\nfriction_angle = 35.0\nnormal_penalty = {pn}\nshear_penalty = {pn}\n",
        rect(-0.5, -0.3, 4.0, 0.3)
    );
    let mut weight = 0.0;
    for (i, &(x, y, w, h)) in blocks.iter().enumerate() {
        text += &format!(
            "[[block]]\nname = \"b{i}\"\nmaterial = \"brick\"\nvertices = {}\n",
            rect(x, y, w, h)
        );
        weight += rho * g * w * h;
    }
    let mut sim = simulate(&text)?;
    let iterations = run_to_end(&mut sim)?;
    let fy: f64 = (1..=blocks.len())
        .map(|b| sim.contacts.interface_force(0, b).fy)
        .sum();
    Ok(Settled {
        base_force: -fy,
        weight,
        max_velocity: sim.v.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        max_penetration: sim
            .contacts
            .contacts
            .iter()
            .map(|c| -c.response.tn / c.params.pn)
            .fold(0.0f64, f64::max),
        iterations,
    })
}

/// A stack of three blocks.
pub fn stack_blocks() -> Vec<(f64, f64, f64, f64)> {
    vec![
        (0.0, 0.0, 1.0, 0.4),
        (0.1, 0.4, 0.8, 0.4),
        (0.2, 0.8, 0.6, 0.4),
    ]
}

/// A wall of four courses of 0.6 m × 0.25 m bricks in running bond (half bricks at the
/// ends of the odd courses), 2.4 m long.
pub fn wall_blocks() -> Vec<(f64, f64, f64, f64)> {
    wall_courses(4)
}

/// A running-bond wall of `courses` courses (see [`wall_blocks`]).
pub fn wall_courses(courses: usize) -> Vec<(f64, f64, f64, f64)> {
    let (bw, bh) = (0.6, 0.25);
    let mut bricks = Vec::new();
    for course in 0..courses {
        let y = course as f64 * bh;
        if course % 2 == 0 {
            for k in 0..4 {
                bricks.push((k as f64 * bw, y, bw, bh));
            }
        } else {
            bricks.push((0.0, y, 0.5 * bw, bh));
            for k in 0..3 {
                bricks.push((0.5 * bw + k as f64 * bw, y, bw, bh));
            }
            bricks.push((3.5 * bw, y, 0.5 * bw, bh));
        }
    }
    bricks
}

// ---------------------------------------------------------------- shaken slope

/// A shaking-table input: a sinusoid whose amplitude ramps linearly to `amplitude`
/// (m/s²) over `ramp` seconds, for `duration` seconds.
#[derive(Debug, Clone, Copy)]
pub struct SineMotion {
    pub amplitude: f64,
    pub frequency: f64,
    pub ramp: f64,
    pub duration: f64,
}

impl SineMotion {
    pub fn accel(&self, t: f64) -> f64 {
        let ramp = if self.ramp > 0.0 {
            (t / self.ramp).min(1.0)
        } else {
            1.0
        };
        self.amplitude * ramp * (2.0 * std::f64::consts::PI * self.frequency * t).sin()
    }
    /// Samples every `step` seconds, as a shaking-table record would give them.
    pub fn samples(&self, step: f64) -> Vec<[f64; 3]> {
        let n = (self.duration / step).round() as usize;
        (0..=n)
            .map(|i| i as f64 * step)
            .map(|t| [t, self.accel(t), 0.0])
            .collect()
    }
}

/// The ramped 5 Hz motion of `examples/shaking_table_slope.toml` (0 → 0.4 g over 10 s).
pub const RAMPED_5HZ: SineMotion = SineMotion {
    amplitude: 0.4 * 9.81,
    frequency: 5.0,
    ramp: 10.0,
    duration: 10.0,
};
/// A 2 Hz motion of 0.25 g reached after a 1 s ramp, 4 s long.
pub const STEADY_2HZ: SineMotion = SineMotion {
    amplitude: 0.25 * 9.81,
    frequency: 2.0,
    ramp: 1.0,
    duration: 4.0,
};

/// The two-block slope of `examples/shaking_table_slope.toml` (the paper's limestone and
/// joint) for a plane dipping `theta` degrees toward +x, as TOML.
pub fn slope_model(theta: f64, motion: &SineMotion, algorithm: &str, dt: f64) -> String {
    let th = theta.to_radians();
    let (l, h) = (3.0, 2.5);
    let d = [th.cos(), -th.sin()];
    let n = [th.sin(), th.cos()];
    let (s0, a, b) = (0.5, 0.6, 0.3);
    let p0 = [s0 * d[0], h + s0 * d[1]];
    let p1 = [p0[0] + a * d[0], p0[1] + a * d[1]];
    let p2 = [p1[0] + b * n[0], p1[1] + b * n[1]];
    let p3 = [p0[0] + b * n[0], p0[1] + b * n[1]];
    let c = [0.5 * (p0[0] + p2[0]), 0.5 * (p0[1] + p2[1])];
    let table: Vec<String> = motion
        .samples(0.005)
        .iter()
        .map(|r| format!("[{}, {:.9}, 0.0]", r[0], r[1]))
        .collect();
    format!(
        "[analysis]\nmode = \"dynamic\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -9.81]\nfriction = \"{algorithm}\"\n\
         [cover]\nsize = 0.1\n\
         [[material]]\nname = \"limestone\"\ndensity = 2242.6\nyoung = 7.0e9\npoisson = 0.33\n\
         [[block]]\nname = \"base\"\nmaterial = \"limestone\"\nvertices = {}\nfixed = true\n\
         [[block]]\nname = \"slider\"\nmaterial = \"limestone\"\nvertices = {}\n\
         [[interface]]\nfriction_angle = 40.5\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n\
         [base_motion]\ntable = [{}]\n\
         [[monitor]]\nname = \"slider\"\npoint = {}\n",
        poly(&[[0.0, 0.0], [l, 0.0], [l, h - l * th.tan()], [0.0, h]]),
        poly(&[p0, p1, p2, p3]),
        table.join(", "),
        point(c),
        steps = (motion.duration / dt).round() as usize
    )
}

/// What [`shaken_slope`] measures.
#[derive(Debug, Clone)]
pub struct ShakenSlope {
    /// (t, base acceleration a_x, slip along the plane (+ downslope)) of the NMM run.
    pub history: Vec<(f64, f64, f64)>,
    /// (t, slip) of the Newmark rigid-block reference under the same record.
    pub reference: Vec<(f64, f64)>,
    /// Onset of sliding: the first step at the end of which the whole joint slides
    /// (every closed contact in the slide state). A definition fixed without reference to
    /// the comparison (issue 19): the former one, slip above a threshold, had its
    /// threshold raised from 2e-4 m to 1 mm until the comparison passed — the elastic
    /// block's lightly loaded part of the joint slips at the record's peaks before the
    /// whole joint yields and the block creeps by ~1.5e-4 m, which a rigid block cannot.
    pub onset: Option<f64>,
    /// The reference's onset: the first time its slip is above zero.
    pub onset_reference: Option<f64>,
    pub final_slip: f64,
    pub final_reference: f64,
    /// g tan(φ − θ).
    pub yield_acceleration: f64,
    pub iterations: Vec<usize>,
}

/// The shaken two-block slope with the NMM and with the Newmark reference.
pub fn shaken_slope(
    theta: f64,
    motion: &SineMotion,
    algorithm: &str,
) -> Result<ShakenSlope, String> {
    let dt = 1e-3;
    let model = model(&slope_model(theta, motion, algorithm, dt))?;
    let record = model.base_motion.clone().ok_or("no base motion")?;
    let mut sim = Simulation::new(model)?;
    let (s, c) = theta.to_radians().sin_cos();
    let mut history = Vec::new();
    let mut iterations = Vec::new();
    let mut onset = None;
    while !sim.finished() {
        iterations.push(sim.advance().map_err(|e| e.to_string())?.iterations);
        let v = monitor_values(&sim);
        history.push((sim.time, record.accel(sim.time)[0], v[0] * c - v[1] * s));
        let closed = sim
            .contacts
            .contacts
            .iter()
            .filter(|k| k.response.status != ContactStatus::Open);
        let (mut n, mut sliding) = (0, 0);
        for k in closed {
            n += 1;
            sliding += usize::from(k.response.status == ContactStatus::Slide);
        }
        if onset.is_none() && n > 0 && sliding == n {
            onset = Some(sim.time);
        }
    }
    // the reference slope dips toward −x: mirror the horizontal acceleration
    let accel = |t: f64| (-record.accel(t)[0], 0.0);
    let reference: Vec<(f64, f64)> =
        super::newmark_sliding::slide(theta, 40.5, 9.81, dt, &accel, motion.duration)
            .iter()
            .map(|r| (r.0, r.1))
            .collect();
    let onset_reference = reference.iter().find(|h| h.1 > 0.0).map(|h| h.0);
    Ok(ShakenSlope {
        final_slip: history.last().map(|h| h.2).unwrap_or(0.0),
        final_reference: reference.last().map(|h| h.1).unwrap_or(0.0),
        history,
        reference,
        onset,
        onset_reference,
        yield_acceleration: super::newmark_sliding::yield_acceleration(theta, 40.5, 9.81),
        iterations,
    })
}

/// Steps of the static settle stage of [`staged_slope_model`] (Δt = 0.01 s).
pub const STAGED_SETTLE_STEPS: usize = 20;

/// The shaken-slope model (θ, the steady 2 Hz record, return mapping, Δt = 1 ms) with a
/// static `settle` stage of [`STAGED_SETTLE_STEPS`] steps before a dynamic `shake` stage
/// whose record starts at the stage's start; `order` is the cover order.
pub fn staged_slope_model(theta: f64, order: usize) -> String {
    let dt = 1e-3;
    let shake = (STEADY_2HZ.duration / dt).round() as usize;
    let mut text = slope_model(theta, &STEADY_2HZ, "return-mapping", dt);
    if order != 0 {
        text = text.replacen("[cover]\n", &format!("[cover]\norder = {order}\n"), 1);
    }
    format!(
        "{text}\n[[stage]]\nname = \"settle\"\nmode = \"static\"\ndt = 0.01\nsteps = {STAGED_SETTLE_STEPS}\n\
         [[stage]]\nname = \"shake\"\nmode = \"dynamic\"\ndt = {dt}\nsteps = {shake}\nbase_motion = true\n"
    )
}

/// A staged run of a block on a plane: every step's (time, slip along the plane
/// (+ downslope), settlement into the plane) and stage name.
pub struct StagedSlope {
    pub history: Vec<(f64, f64, f64)>,
    pub stages: Vec<String>,
}

impl StagedSlope {
    /// The state at the end of the settle stage.
    pub fn settled(&self) -> (f64, f64, f64) {
        self.history[STAGED_SETTLE_STEPS - 1]
    }
    /// The slip during the shaking.
    pub fn shake_slip(&self) -> f64 {
        self.history.last().map_or(0.0, |h| h.1) - self.settled().1
    }
    /// The largest settlement beyond the settled one over the first `steps` steps of the
    /// shaking (absolute value).
    pub fn extra_settlement(&self, steps: usize) -> f64 {
        let s = self.settled().2;
        self.history[STAGED_SETTLE_STEPS..STAGED_SETTLE_STEPS + steps]
            .iter()
            .map(|r| (r.2 - s).abs())
            .fold(0.0, f64::max)
    }
}

/// Runs a model of a block on a plane dipping θ toward +x (as [`slope_model`] writes it,
/// staged or not; its first monitor on the block) to its end.
pub fn run_staged_slope(text: &str, theta: f64) -> Result<StagedSlope, String> {
    let mut sim = simulate(text)?;
    let (s, c) = theta.to_radians().sin_cos();
    let (mut history, mut stages) = (Vec::new(), Vec::new());
    while !sim.finished() {
        sim.advance().map_err(|e| e.to_string())?;
        let v = monitor_values(&sim);
        // the plane dips toward +x: down-slope (c, −s), outward normal (s, c)
        history.push((sim.time, v[0] * c - v[1] * s, -(v[0] * s + v[1] * c)));
        stages.push(sim.stage_name().unwrap_or("").to_string());
    }
    Ok(StagedSlope { history, stages })
}

/// The Newmark (1965) rigid block's slip (φ = 40.5°) under the record of the staged model
/// `text` (θ), from the shake stage's start.
pub fn staged_newmark_slip(text: &str, theta: f64) -> Result<f64, String> {
    let record = model(text)?.base_motion.ok_or("no base motion")?;
    let accel = |t: f64| (-record.accel(t)[0], 0.0);
    let reference =
        super::newmark_sliding::slide(theta, 40.5, 9.81, 1e-3, &accel, STEADY_2HZ.duration);
    Ok(reference.last().map_or(0.0, |r| r.1))
}
