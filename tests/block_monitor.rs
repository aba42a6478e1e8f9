//! `[[monitor]] block = "NAME"`: history.csv columns `NAME.x, NAME.y, NAME.rotation` — the
//! displacement of the block's centroid and its mean rotation (rad). A free elastic block
//! moved by two point constraints that prescribe a rigid motion — a turn by θ = 0.02 rad
//! about its centroid and a shift d = (0.1, 0.05) m: the centroid moves by d and the
//! rotation is θ. The static step is the small-strain one: it cannot follow the rotation's
//! second-order part exactly (the two points' distance shrinks by θ²/2 in its linear
//! kinematics), which leaves a strain of order θ²/2 = 2e-4: hence the tolerances, 2e-4 m on
//! the centroid and 1e-3 relative on the rotation (a factor ½ or a sign missing in the
//! rotation, or the centroid taken unweighted, would be off by far more).

use nmm::model::parse_model;
use nmm::simulation::{history_columns, monitor_values, Simulation};
use std::path::Path;

const THETA: f64 = 0.02;
const SHIFT: [f64; 2] = [0.1, 0.05];

fn rigid(x: [f64; 2], c: [f64; 2]) -> [f64; 2] {
    let (s, co) = THETA.sin_cos();
    let d = [x[0] - c[0], x[1] - c[1]];
    [
        co * d[0] - s * d[1] - d[0] + SHIFT[0],
        s * d[0] + co * d[1] - d[1] + SHIFT[1],
    ]
}

#[test]
fn a_block_turned_rigidly_reports_its_rotation_and_a_still_centroid() {
    let c = [0.5, 0.25];
    let (a, b) = ([0.0, 0.0], [1.0, 0.0]);
    let (ua, ub) = (rigid(a, c), rigid(b, c));
    let text = format!(
        "[analysis]\nmode = \"static\"\ndt = 1.0\nsteps = 1\n\
         [cover]\nsize = 0.1\n\
         [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"slab\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]]\n\
         [[constraint]]\nblock = \"slab\"\npoint = [0.0, 0.0]\nux = [[0.0, 0.0], [1.0, {:?}]]\nuy = [[0.0, 0.0], [1.0, {:?}]]\n\
         [[constraint]]\nblock = \"slab\"\npoint = [1.0, 0.0]\nux = [[0.0, 0.0], [1.0, {:?}]]\nuy = [[0.0, 0.0], [1.0, {:?}]]\n\
         [[monitor]]\nname = \"corner\"\npoint = [1.0, 0.5]\n\
         [[monitor]]\nname = \"slab\"\nblock = \"slab\"\n",
        ua[0], ua[1], ub[0], ub[1]
    );
    let model = parse_model(&text, Path::new(".")).unwrap();
    assert_eq!(
        history_columns(&model),
        [
            "corner.ux",
            "corner.uy",
            "corner.vx",
            "corner.vy",
            "slab.x",
            "slab.y",
            "slab.rotation"
        ]
    );
    let mut sim = Simulation::new(model).unwrap();
    while !sim.finished() {
        sim.advance().unwrap();
    }
    let v = monitor_values(&sim);
    assert_eq!(v.len(), 7);
    let corner = rigid([1.0, 0.5], c);
    eprintln!(
        "corner {:?} vs {corner:?}; centroid ({}, {}), rotation {} vs {THETA}",
        &v[..2],
        v[4],
        v[5],
        v[6]
    );
    assert!((v[0] - corner[0]).abs() < 2e-4 && (v[1] - corner[1]).abs() < 2e-4);
    assert!(
        (v[4] - SHIFT[0]).abs() < 2e-4 && (v[5] - SHIFT[1]).abs() < 2e-4,
        "centroid moved {} {}",
        v[4],
        v[5]
    );
    assert!((v[6] / THETA - 1.0).abs() < 1e-3, "rotation {}", v[6]);
}

#[test]
fn a_block_monitor_names_an_existing_block_and_only_one_kind() {
    let base = "[analysis]\ndt = 1.0\nsteps = 1\n[cover]\nsize = 0.1\n\
         [[material]]\nname = \"m\"\ndensity = 2000.0\nyoung = 1.0e9\npoisson = 0.25\n\
         [[block]]\nname = \"slab\"\nmaterial = \"m\"\nvertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]]\nfixed = true\n";
    let e = nmm::model::parse_model_named(
        &format!("{base}[[monitor]]\nname = \"s\"\nblock = \"slob\"\n"),
        Path::new("."),
        "m.toml",
    )
    .unwrap_err()
    .to_string();
    assert_eq!(
        e,
        "[[monitor]] \"s\": key `block`: unknown block \"slob\" (m.toml, line 18)"
    );
    let e = nmm::model::parse_model_named(
        &format!("{base}[[monitor]]\nname = \"s\"\nblock = \"slab\"\npoint = [0.5, 0.2]\n"),
        Path::new("."),
        "m.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with(
            "[[monitor]] \"s\": key `block`: give one of `point`, `interface`, `block`, `bolt` and `crack`"
        ),
        "{e}"
    );
}
