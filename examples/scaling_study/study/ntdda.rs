//! The DDA peer (ntdda, UC Berkeley's DDA code): its inputs for the same brick wall and the
//! reading of its run.
//!
//! ntdda reads a geometry file (`.geo`, DDAML: joints, fixed and measured points; it cuts the
//! blocks itself) and an analysis file (`.ana`: material, contact constants, steps). The wall is
//! the one of [`nmm::generate::wall_geometry`]: joints along every bed and head joint,
//! overshooting by 1 cm so that its cutter finds the intersections, three fixed points in the
//! base, a measured point at the `top` monitor. Contact penalty 1e10 N/m (fixed, no
//! autopenalty), φ 30°, E 7 GPa, ν 0.33, 22 kN/m³, dynamic, plane strain; the step-size limit
//! (`Maxdisplacement`) is 4 mm and `Edgenodedist` 2 mm (never below 1e-4 of the domain scale:
//! below ~4e-5 its cutter silently drops courses of bricks).

use nmm::generate::{
    fmt_g, wall_base_extent, wall_course_offset, wall_geometry, WALL_BASE_DEPTH,
    WALL_BRICK_HEIGHT as BH, WALL_BRICK_LENGTH as BW, WALL_FRICTION_ANGLE, WALL_PENALTY,
    WALL_POISSON, WALL_UNIT_WEIGHT, WALL_YOUNG,
};
use std::path::Path;

/// Joints overshoot the corners by this much (m).
const OVERSHOOT: f64 = 0.01;
const G: f64 = 9.81;

/// `%.{p}f`.
fn f(x: f64, p: usize) -> String {
    format!("{x:.p$}")
}

/// `%.{p}e` (C's form: `7.000000e+09`).
fn e(x: f64, p: usize) -> String {
    let s = format!("{x:.p$e}");
    let (m, ex) = s.split_once('e').expect("exponent form");
    let ex: i32 = ex.parse().expect("exponent");
    format!("{m}e{}{:02}", if ex < 0 { '-' } else { '+' }, ex.abs())
}

fn coords(xs: &[f64]) -> String {
    xs.iter().map(|x| f(*x, 9)).collect::<Vec<_>>().join(" ")
}

/// The `.geo` text, and the analysis scale w0 the `.ana` needs.
pub fn wall_geo(nx: usize, ny: usize) -> (String, f64) {
    let ov = OVERSHOOT;
    let w = nx as f64 * BW;
    let off: Vec<f64> = (0..ny).map(wall_course_offset).collect();
    let (xl, xr) = wall_base_extent(nx);
    let depth = WALL_BASE_DEPTH;
    let mut joints: Vec<[f64; 4]> = vec![
        [xl - ov, -depth, xr + ov, -depth],
        [xl, -depth - ov, xl, ov],
        [xr, -depth - ov, xr, ov],
        [xl - ov, 0.0, xr + ov, 0.0],
    ];
    // Bed joints: one continuous line per level above the base.
    for k in 1..=ny {
        let y = k as f64 * BH;
        let above = if k < ny { off[k] } else { off[k - 1] };
        let lo = off[k - 1].min(above);
        let hi = off[k - 1].max(above) + w;
        joints.push([lo - ov, y, hi + ov, y]);
    }
    // Head joints: short segments overshooting into the courses above and below.
    for (k, o) in off.iter().enumerate() {
        let (y0, y1) = (k as f64 * BH, (k + 1) as f64 * BH);
        for i in 0..=nx {
            let x = o + i as f64 * BW;
            joints.push([x, y0 - ov, x, y1 + ov]);
        }
    }
    let fixed = [
        [xl + 0.25, -depth / 2.0],
        [0.5 * (xl + xr), -depth / 2.0],
        [xr - 0.25, -depth / 2.0],
    ];
    let measured = [wall_geometry(nx, ny).monitor];
    let (width, height) = (xr - xl, ny as f64 * BH + depth);
    let w0 = width.max(height) / 2.0;
    let gw0 = ((height + 2.0 * ov) / 2.0).max((width + 2.0 * ov) / 2.0 / 1.3) * 1.02;
    let e00 = (0.002 / gw0).max(1e-4);
    let mut s = String::from(
        "<?xml version=\"1.0\" standalone=\"no\"?>\n\
         <!DOCTYPE DDA SYSTEM \"geometry.dtd\">\n\
         <Berkeley:DDA xmlns:Berkeley=\"http://www.tsoft.com/~bdoolin/dda\">\n\
         <Berkeley:Geometry>\n",
    );
    s += &format!("   <Berkeley:Edgenodedist distance=\"{}\"/>\n", f(e00, 10));
    s += "   <Jointlist>\n";
    for j in &joints {
        s += &format!("      <Joint type=\"1\"> {} </Joint>\n", coords(j));
    }
    s += "   </Jointlist>\n   <Fixedpointlist>\n";
    for p in &fixed {
        s += &format!("      <Point> {} </Point>\n", coords(p));
    }
    s += "   </Fixedpointlist>\n   <Measuredpointlist>\n";
    for p in &measured {
        s += &format!("      <Point> {} </Point>\n", coords(p));
    }
    s += "   </Measuredpointlist>\n</Berkeley:Geometry>\n</Berkeley:DDA>\n";
    (s, w0)
}

/// The `.ana` text: `steps` dynamic steps of `dt`, saving every step.
pub fn wall_ana(steps: usize, dt: f64, w0: f64) -> String {
    let pfactor = WALL_PENALTY / WALL_YOUNG;
    let g2 = 0.004 / w0;
    format!(
        r#"<?xml version="1.0" standalone="no"?>
<!DOCTYPE DDA SYSTEM "analysis.dtd">
<Berkeley:DDA xmlns:Berkeley="http://www.tsoft.com/~bdoolin/dda">
<!-- comment -->
<Analysis type="dynamic">
  <Analysistype type="dynamic"/>
  <Rotation type="linear"/>
  <Gravity flag="no"/>
  <Gravaccel value="{g}"/>
  <Autotimestep flag="no"/>
  <Autopenalty flag="no" pfactor="{pfactor}"/>
  <Planestrain flag="yes"/>
  <Numtimesteps timesteps="{steps}"/>
  <Maxtimestep maxtimestep="{dt}"/>
  <Maxdisplacement maxdisplacement="{g2}"/>
  <Saveinterval step="1"/>
  <AConstants>
      <Openclose value="0.000200"/>
      <Opencriteria value="0.0000002"/>
      <NormSpringPen value="0.0004"/>
      <AngleOverlap value="3.0"/>
      <ShearNormRatio value="2.5"/>
  </AConstants>
  <Blockmaterial type="1">
    <Unitmass> {rho} </Unitmass>
    <Unitweight> {uw} </Unitweight>
    <Youngsmod> {young} </Youngsmod>
    <Poissonratio> {nu} </Poissonratio>
    <Damping>0.0</Damping>
    <Istress> 0.0 0.0 0.0 </Istress>
    <Ivelocity> 0.0 0.0 0.0 </Ivelocity>
    <Istrain> 0.0 0.0 0.0 </Istrain>
  </Blockmaterial>
  <Jointproperties type="1">
    <Friction> {phi} </Friction>
    <Cohesion> 0.0 </Cohesion>
    <Tensile> 0.0 </Tensile>
  </Jointproperties>
</Analysis>
</Berkeley:DDA>
"#,
        g = f(G, 2),
        pfactor = fmt_g(pfactor, 10),
        dt = fmt_g(dt, 10),
        g2 = fmt_g(g2, 10),
        rho = f(WALL_UNIT_WEIGHT / G, 6),
        uw = f(WALL_UNIT_WEIGHT, 6),
        young = e(WALL_YOUNG, 6),
        nu = f(WALL_POISSON, 4),
        phi = f(WALL_FRICTION_ANGLE, 6),
    )
}

/// Write `wall.geo` and `wall.ana` into `dir`.
pub fn write_wall(dir: &Path, nx: usize, ny: usize, steps: usize, dt: f64) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let (geo, w0) = wall_geo(nx, ny);
    std::fs::write(dir.join("wall.geo"), geo)?;
    std::fs::write(dir.join("wall.ana"), wall_ana(steps, dt, w0))
}

/// What ntdda's stderr says about a run: the number of blocks its cutter made
/// (`nBlocks=N after ddacut`) and a glibc heap-corruption message, if any.
pub fn read_stderr(text: &str) -> (Option<usize>, Option<String>) {
    let blocks = text.lines().find_map(|l| {
        let rest = l.split("nBlocks=").nth(1)?;
        rest.split(|c: char| !c.is_ascii_digit())
            .next()?
            .parse()
            .ok()
    });
    let heap = text
        .lines()
        .find(|l| {
            [
                "munmap_chunk()",
                "free()",
                "corrupted",
                "malloc()",
                "double free",
            ]
            .iter()
            .any(|m| l.contains(m))
        })
        .map(|l| l.trim().to_string());
    (blocks, heap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn c_formats() {
        assert_eq!(e(7.0e9, 6), "7.000000e+09");
        assert_eq!(e(1.5e-3, 2), "1.50e-03");
        assert_eq!(f(22000.0 / 9.81, 6), "2242.609582");
        assert_eq!(fmt_g(1e10 / 7e9, 10), "1.428571429");
        assert_eq!(fmt_g(0.001, 10), "0.001");
    }

    #[test]
    fn wall_inputs_have_every_joint_and_point() {
        let (nx, ny) = (3, 2);
        let (geo, w0) = wall_geo(nx, ny);
        // 4 base joints, ny bed joints, (nx + 1) head joints per course.
        let joints = geo.matches("<Joint type=\"1\">").count();
        assert_eq!(joints, 4 + ny + ny * (nx + 1));
        assert_eq!(geo.matches("<Point>").count(), 4);
        // The base reaches x = -0.5 … 0.4 nx + 0.7; the wall is 0.2 ny + 0.5 high.
        assert!((w0 - (0.4 * nx as f64 + 1.2) / 2.0).abs() < 1e-12);
        assert!(geo.contains(
            "<Joint type=\"1\"> -0.510000000 -0.500000000 1.910000000 -0.500000000 </Joint>"
        ));
        // The second bed joint (y = 0.4) spans the staggered course: 0.2 … 1.4, plus overshoot.
        assert!(geo.contains(
            "<Joint type=\"1\"> 0.190000000 0.400000000 1.410000000 0.400000000 </Joint>"
        ));
        let ana = wall_ana(12, 0.001, w0);
        assert!(ana.contains("<Numtimesteps timesteps=\"12\"/>"));
        assert!(ana.contains("<Youngsmod> 7.000000e+09 </Youngsmod>"));
        assert!(ana.contains("<Autopenalty flag=\"no\" pfactor=\"1.428571429\"/>"));
    }

    #[test]
    fn stderr_is_read() {
        let (b, h) = read_stderr("x\nnBlocks=101 after ddacut\n...\n");
        assert_eq!((b, h), (Some(101), None));
        let (_, h) = read_stderr("free(): corrupted unsorted chunks\n");
        assert!(h.is_some());
    }
}
