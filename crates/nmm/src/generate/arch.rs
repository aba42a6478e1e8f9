//! Masonry arches and stacks for tests and examples: a semicircular arch of `n` voussoirs
//! (radial joints) of thickness `t` on a fixed base that carries it at both springings, and
//! a stack of blocks.
//!
//! The arch's mean radius is `r`; the voussoirs span the half-circle from the right
//! springing to the left, each a quadrilateral with its two curved faces replaced by chords
//! (as DDA and UDEC models do). Under self-weight a semicircular arch stands on the
//! friction of its joints when t/r is above Heyman's minimum thickness ratio, t/r ≈ 0.1075
//! (Milankovitch's value for a continuous arch; a discrete arch of n voussoirs needs about
//! the same): thicker arches stand, thinner ones form a four-hinge mechanism and collapse.

use super::fmt_poly;
use crate::geometry::Vec2;

/// Heyman's (Milankovitch's) minimum thickness ratio t/r of a semicircular arch under its
/// own weight.
pub const ARCH_MIN_THICKNESS_RATIO: f64 = 0.1075;

/// An arch (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ArchOptions {
    /// Voussoirs.
    pub n: usize,
    /// Mean radius (m).
    pub radius: f64,
    /// Thickness (m).
    pub thickness: f64,
    /// Mathematical mesh size h (m).
    pub cover: f64,
    pub dt: f64,
    pub steps: usize,
    /// "dynamic" or "static".
    pub mode: &'static str,
    /// Friction angle of the joints (degrees).
    pub friction_angle: f64,
    /// An optional horizontal base motion: a table of (t, a_x) rows.
    pub base_motion: Option<Vec<(f64, f64)>>,
}

impl ArchOptions {
    /// A 19-voussoir arch of mean radius 2 m, t/r = 0.15, stone (2500 kg/m³, E 10 GPa),
    /// joints φ 35° with penalties 1e10 N/m, cover 0.1 m, 1 s of dynamic release.
    pub fn new() -> Self {
        ArchOptions {
            n: 19,
            radius: 2.0,
            thickness: 0.3,
            cover: 0.1,
            dt: 1e-3,
            steps: 1000,
            mode: "dynamic",
            friction_angle: 35.0,
            base_motion: None,
        }
    }
}

impl Default for ArchOptions {
    fn default() -> Self {
        Self::new()
    }
}

/// The voussoirs, from the right springing to the left, each counter-clockwise.
pub fn arch_voussoirs(o: &ArchOptions) -> Vec<Vec<Vec2>> {
    let (ri, ro) = (o.radius - 0.5 * o.thickness, o.radius + 0.5 * o.thickness);
    let base_top = 0.0;
    (0..o.n)
        .map(|k| {
            let a0 = std::f64::consts::PI * k as f64 / o.n as f64;
            let a1 = std::f64::consts::PI * (k + 1) as f64 / o.n as f64;
            let p = |r: f64, a: f64| [r * a.cos(), base_top + r * a.sin()];
            vec![p(ri, a0), p(ro, a0), p(ro, a1), p(ri, a1)]
        })
        .collect()
}

/// The arch as a model file: a fixed base under both springings (one block spanning the
/// whole span, its top at y = 0), the voussoirs, and a monitor `crown` at the crown.
pub fn arch_model(o: &ArchOptions) -> String {
    let ro = o.radius + 0.5 * o.thickness;
    let mut text = format!(
        "# A semicircular arch of {n} voussoirs, mean radius {r} m, thickness {t} m (t/r = {ratio:.4})\n\
         [analysis]\nmode = \"{mode}\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -9.81]\noutput_every = 100\n\
         [cover]\nsize = {h}\n\
         [[material]]\nname = \"stone\"\ndensity = 2500.0\nyoung = 1.0e10\npoisson = 0.2\n\
         [[interface]]\nfriction_angle = {phi}\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
         [[block]]\nname = \"base\"\nmaterial = \"stone\"\nfixed = true\nvertices = {base}\n",
        n = o.n,
        r = o.radius,
        t = o.thickness,
        ratio = o.thickness / o.radius,
        mode = o.mode,
        dt = o.dt,
        steps = o.steps,
        h = o.cover,
        phi = o.friction_angle,
        base = fmt_poly(&[
            [-ro - 0.5, -0.5],
            [ro + 0.5, -0.5],
            [ro + 0.5, 0.0],
            [-ro - 0.5, 0.0]
        ]),
    );
    for (k, v) in arch_voussoirs(o).iter().enumerate() {
        text += &format!(
            "[[block]]\nname = \"v{k}\"\nmaterial = \"stone\"\nvertices = {}\n",
            fmt_poly(v)
        );
    }
    if let Some(rows) = &o.base_motion {
        let t: Vec<String> = rows
            .iter()
            .map(|(t, a)| format!("[{t}, {a}, 0.0]"))
            .collect();
        text += &format!("[base_motion]\ntable = [{}]\n", t.join(", "));
    }
    text += &format!(
        "[[monitor]]\nname = \"crown\"\npoint = [0.0, {}]\n",
        o.radius
    );
    text
}

/// A stack of `n` blocks `w` × `hgt` on a fixed base, as a model file (dynamic release,
/// 1 s), with a monitor `top` at the top block's centre.
pub fn stack_model(n: usize, w: f64, hgt: f64, cover: f64, steps: usize) -> String {
    let mut text = format!(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = {steps}\ngravity = [0.0, -9.81]\noutput_every = 100\n\
         [cover]\nsize = {cover}\n\
         [[material]]\nname = \"stone\"\ndensity = 2500.0\nyoung = 1.0e10\npoisson = 0.2\n\
         [[interface]]\nfriction_angle = 35.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n\
         [[block]]\nname = \"base\"\nmaterial = \"stone\"\nfixed = true\nvertices = {}\n",
        fmt_poly(&[[-1.0, -0.5], [w + 1.0, -0.5], [w + 1.0, 0.0], [-1.0, 0.0]])
    );
    for k in 0..n {
        let (y0, y1) = (k as f64 * hgt, (k + 1) as f64 * hgt);
        text += &format!(
            "[[block]]\nname = \"s{k}\"\nmaterial = \"stone\"\nvertices = {}\n",
            fmt_poly(&[[0.0, y0], [w, y0], [w, y1], [0.0, y1]])
        );
    }
    text += &format!(
        "[[monitor]]\nname = \"top\"\npoint = [{}, {}]\n",
        0.5 * w,
        (n as f64 - 0.5) * hgt
    );
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arch_and_stack_models_are_valid() {
        let o = ArchOptions::new();
        let m = crate::model::parse_model(&arch_model(&o), std::path::Path::new(".")).unwrap();
        assert_eq!(m.blocks.len(), 20);
        let area: f64 = m.blocks[1..]
            .iter()
            .map(|b| crate::geometry::moments::polygon_area(&b.vertices))
            .sum();
        // the chords make it a little less than the annulus π r t
        let annulus = std::f64::consts::PI * o.radius * o.thickness;
        assert!(area < annulus && area > 0.99 * annulus, "{area} {annulus}");
        let m = crate::model::parse_model(
            &stack_model(4, 0.5, 0.3, 0.1, 10),
            std::path::Path::new("."),
        )
        .unwrap();
        assert_eq!(m.blocks.len(), 5);
    }
}
