//! Rock bolts (`[[bolt]]`, `crate::bolt`): the bolted block of issue 17 against its closed
//! forms, installation at a stage's start, outputs, checkpoints and `nmm resume`.
//!
//! The bolted block: the slider of the `incline` case (0.5 m × 0.25 m, ρ = 2000 kg/m³,
//! E = 1 GPa: m = 250 kg per metre) on a plane dipping θ = 30° with φ = 20° < θ, held by a
//! bolt along the slope from the slider's centre line (0.1 m inside its upslope face) to
//! an abutment of the fixed base 0.2 m upslope of it (the base's top face steps up there).
//! The model is drawn with the plane along x and rotated by −θ, so that the mathematical
//! mesh is not aligned with it.

use nmm::model::parse_model;
use nmm::simulation::{monitor_values, Simulation};
use nmm::verify::cases::{place, point, poly};
use std::path::Path;

const THETA: f64 = 30.0;
const PHI: f64 = 20.0;
const G: f64 = 9.81;
/// The slider's mass per metre: ρ × 0.5 m × 0.25 m.
const MASS: f64 = 2000.0 * 0.5 * 0.25;

/// The slope's driving force net of friction, m g (sin θ − cos θ tan φ) (N/m).
fn net_force() -> f64 {
    let (s, c) = THETA.to_radians().sin_cos();
    MASS * G * (s - c * PHI.to_radians().tan())
}

/// The bolted block (see the module docs) with `analysis` (the `[analysis]` keys and any
/// `[[stage]]`), the bolt's `bolt` keys and `[cover] extra` keys. Monitors: `c` (the
/// slider's centre), `s` (the slider as a block), `b1` (the bolt).
fn bolted_block(analysis: &str, bolt: &str, cover: &str) -> String {
    let rot = |pts: &[[f64; 2]]| place(pts, -THETA, [0.0, 2.5]);
    let base = rot(&[
        [0.0, -0.5],
        [4.0, -0.5],
        [4.0, 0.0],
        [0.3, 0.0],
        [0.3, 0.25],
        [0.0, 0.25],
    ]);
    let slider = rot(&[[0.5, 0.0], [1.0, 0.0], [1.0, 0.25], [0.5, 0.25]]);
    let anchors = rot(&[[0.6, 0.125], [0.15, 0.125]]);
    let c = rot(&[[0.75, 0.125]])[0];
    format!(
        "{analysis}\n[cover]\nsize = 0.0625\n{cover}\n\
         [[material]]\nname = \"rock\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = {}\nfixed = true\n\
         [[block]]\nname = \"slider\"\nmaterial = \"rock\"\nvertices = {}\n\
         [[interface]]\nfriction_angle = {PHI}\nnormal_penalty = 1.0e9\nshear_penalty = 1.0e9\n\
         [[bolt]]\nname = \"b1\"\npoints = [{}, {}]\n{bolt}\n\
         [[monitor]]\nname = \"c\"\npoint = {}\n\
         [[monitor]]\nname = \"s\"\nblock = \"slider\"\n\
         [[monitor]]\nname = \"b1\"\nbolt = \"b1\"\n",
        poly(&base),
        poly(&slider),
        point(anchors[0]),
        point(anchors[1]),
        point(c),
    )
}

fn simulate(text: &str) -> Simulation {
    Simulation::new(parse_model(text, Path::new(".")).unwrap()).unwrap()
}

/// The monitor values by column name after the last step.
struct Values {
    v: Vec<f64>,
}

impl Values {
    fn of(sim: &Simulation) -> Values {
        Values {
            v: monitor_values(sim),
        }
    }
    /// Columns: c.ux c.uy c.vx c.vy | s.x s.y s.rotation | b1.force b1.elongation.
    fn slip(&self) -> f64 {
        let (s, c) = THETA.to_radians().sin_cos();
        self.v[4] * c - self.v[5] * s
    }
    fn speed(&self) -> f64 {
        let (s, c) = THETA.to_radians().sin_cos();
        self.v[2] * c - self.v[3] * s
    }
    fn force(&self) -> f64 {
        self.v[7]
    }
    fn elongation(&self) -> f64 {
        self.v[8]
    }
}

/// Static: the bolt holds the block. It slides until the bolt carries what friction does
/// not, F = m g (sin θ − cos θ tan φ), by F/k. Tolerances 1% (the issue's); what is left is
/// the block's elastic distortion between the anchor and its centroid (F/E ~ 5e-7 m
/// against a slip of 4.5e-3 m) and the Newton tolerance.
#[test]
fn a_bolt_holds_the_block_with_the_force_friction_leaves() {
    for order in [0, 1] {
        let k = 1.0e5;
        let text = bolted_block(
            "[analysis]\nmode = \"static\"\ndt = 0.01\nsteps = 3\ngravity = [0.0, -9.81]",
            &format!("stiffness = {k:e}\ncapacity = 1.0e4"),
            &format!("order = {order}"),
        );
        let mut sim = simulate(&text);
        while !sim.finished() {
            let r = sim.advance().unwrap();
            assert!(r.equilibrium);
        }
        let v = Values::of(&sim);
        let f = net_force();
        eprintln!(
            "order {order}: bolt force {:.6} N vs m g (sin θ − cos θ tan φ) = {f:.6} N ({:+.4}%); \
             slip {:.6e} m vs F/k = {:.6e} m ({:+.4}%); elongation {:.6e} m",
            v.force(),
            (v.force() / f - 1.0) * 100.0,
            v.slip(),
            v.force() / k,
            (v.slip() / (v.force() / k) - 1.0) * 100.0,
            v.elongation()
        );
        assert!((v.force() / f - 1.0).abs() < 0.01);
        assert!((v.slip() / (v.force() / k) - 1.0).abs() < 0.01);
    }
}

/// Dynamic, with a capacity F_y below that force: the bolt yields and the block slides
/// with a = g (sin θ − cos θ tan φ) − F_y/m. The acceleration is measured from the
/// centre's velocity along the slope between t = 0.4 s and t = 1 s (after the bolt has
/// yielded), tolerance 1% (the issue's).
#[test]
fn a_yielding_bolt_lets_the_block_slide_with_the_reduced_acceleration() {
    let (k, fy) = (1.0e5, 200.0);
    let text = bolted_block(
        "[analysis]\nmode = \"dynamic\"\ndt = 0.001\nsteps = 1000\ngravity = [0.0, -9.81]",
        &format!("stiffness = {k:e}\ncapacity = {fy:e}"),
        "",
    );
    let mut sim = simulate(&text);
    let mut v1 = None;
    while !sim.finished() {
        sim.advance().unwrap();
        if (sim.time - 0.4).abs() < 1e-9 {
            v1 = Some(Values::of(&sim).speed());
        }
    }
    let v = Values::of(&sim);
    let a = (v.speed() - v1.unwrap()) / 0.6;
    let exact = net_force() / MASS - fy / MASS;
    eprintln!(
        "yielding bolt: a = {a:.6} m/s² vs g (sin θ − cos θ tan φ) − F_y/m = {exact:.6} ({:+.4}%); \
         force {} N, elongation {:.6} m, slip {:.6} m",
        (a / exact - 1.0) * 100.0,
        v.force(),
        v.elongation(),
        v.slip()
    );
    assert_eq!(v.force(), fy);
    assert!((a / exact - 1.0).abs() < 0.01);
}
