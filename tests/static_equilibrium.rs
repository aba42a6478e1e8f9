//! docs/model-format.md, static mode: "a wall settled with Δt = 1 s in three steps ends in
//! the same equilibrium as with a thousand steps of 1 ms". The four-course running-bond
//! wall of `nmm verify` (`cases::wall_blocks`), static, under gravity: the displacements
//! of every block's top corners after 3 steps of 1 s and after 1,000 steps of 1 ms.
//!
//! Tolerance: 1e-7 of the largest displacement. Both runs solve each step to the Newton
//! tolerance (1e-9 of the forces), which bounds the difference at ~1e-9 of the
//! displacements times the system's conditioning near the solution (measured 4.5e-9; the
//! symmetric wall's joints stick, so the loading path leaves no different shear gaps).

use nmm::simulation::{monitor_values, Simulation};
use nmm::verify::cases::{model, poly, wall_blocks};

fn settled(dt: f64, steps: usize) -> Vec<f64> {
    let rect = |x0: f64, y0: f64, w: f64, h: f64| {
        poly(&[[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
    };
    let mut text = format!(
        "[analysis]\nmode = \"static\"\ndt = {dt}\nsteps = {steps}\ngravity = [0.0, -9.81]\n[cover]\nsize = 0.1\n\
         [[material]]\nname = \"brick\"\ndensity = 2000.0\nyoung = 5.0e9\npoisson = 0.2\n\
         [[block]]\nname = \"base\"\nmaterial = \"brick\"\nvertices = {}\nfixed = true\n\
         [[interface]]\nfriction_angle = 35.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e10\n",
        rect(-0.5, -0.3, 4.0, 0.3)
    );
    for (i, &(x, y, w, h)) in wall_blocks().iter().enumerate() {
        text += &format!(
            "[[block]]\nname = \"b{i}\"\nmaterial = \"brick\"\nvertices = {}\n\
             [[monitor]]\nname = \"l{i}\"\npoint = [{}, {}]\n[[monitor]]\nname = \"r{i}\"\npoint = [{}, {}]\n",
            rect(x, y, w, h),
            x,
            y + h,
            x + w,
            y + h
        );
    }
    let mut sim = Simulation::new(model(&text).unwrap()).unwrap();
    while !sim.finished() {
        sim.advance().unwrap();
    }
    // ux, uy of every monitor
    monitor_values(&sim)
        .chunks(4)
        .flat_map(|m| [m[0], m[1]])
        .collect()
}

#[test]
fn static_one_second_steps_end_where_a_thousand_millisecond_steps_do() {
    let coarse = settled(1.0, 3);
    let fine = settled(1e-3, 1000);
    let scale = fine.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = coarse
        .iter()
        .zip(&fine)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    eprintln!("largest displacement {scale:.4e} m; largest difference 3 × 1 s vs 1000 × 1 ms {diff:.3e} m ({:.2e} of it)", diff / scale);
    assert!(scale > 1e-7, "the wall did not settle: {scale}");
    assert!(diff <= 1e-7 * scale, "{diff} m vs {scale} m");
}
