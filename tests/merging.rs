//! `[cover] min_block_area` merges that cannot make keys (docs/model-format.md, Cutting).
//!
//! A jointed slope (bedding dipping 15° out of a 63° face, φ = 25°, vertical cross joints
//! that end on the bedding planes) whose face slivers (0.51 and 0.53 m²) sit between
//! persistent bedding planes, settled then shaken (0.45 g, 2.5 Hz, 1.5 s). The face wedges
//! free to slide (the layers daylighting above the toe) must move as far with
//! `min_block_area = 0.6` as without it, within 10% — the rule keeps each sliver with the
//! block behind it in its own layer instead of hooking it onto the layer above or below
//! across a bedding plane, which buttressed the face wedge behind it (with the earlier rule,
//! merging across the longest face, that wedge moved 0.037 m instead of 0.113 m). The
//! tolerance: the two models differ by the slivers' own freedom (separate blocks or part of
//! the wedge), a few % at most.

use nmm::model::parse_model;
use nmm::simulation::{monitor_values, Simulation};
use std::path::Path;

const DIP: f64 = 15.0;
const SPACING: f64 = 0.6;

fn bedding_y(k: f64, x: f64) -> f64 {
    let a = DIP.to_radians();
    (k * SPACING + a.sin() * x) / a.cos()
}

/// The slope model; `min_block_area` written when given.
fn slope(min_block_area: Option<f64>) -> String {
    let a = DIP.to_radians();
    let face_y = |k: f64| k * SPACING / (a.cos() - a.sin() / 2.0);
    let mut joints = String::new();
    let layers: [(f64, &[f64]); 5] = [
        (0.0, &[2.2, 4.6]),
        (1.0, &[1.0, 3.4, 5.8]),
        (2.0, &[2.4, 4.8]),
        (3.0, &[1.0, 3.4, 5.8]),
        (4.0, &[2.6, 5.0]),
    ];
    for (k, ds) in layers {
        let xf = if k > 0.0 { face_y(k) / 2.0 } else { 0.0 };
        for d in ds {
            let x = xf + d;
            if x >= 6.95 {
                continue;
            }
            let y0 = if k > 0.0 {
                bedding_y(k, x)
            } else {
                bedding_y(0.0, x).max(0.0)
            };
            let y1 = bedding_y(k + 1.0, x).min(3.0);
            if y1 <= y0 {
                continue;
            }
            joints.push_str(&format!(
                "[[joint]]\nname = \"c{k}_{d}\"\npoints = [[{x:?}, {y0:?}], [{x:?}, {y1:?}]]\nblocks = [\"mass\"]\n\n"
            ));
        }
    }
    let record: Vec<String> = (0..=300)
        .map(|i| {
            let t = i as f64 / 200.0;
            let a = 0.45 * 9.81 * (2.0 * std::f64::consts::PI * 2.5 * t).sin() * (t / 0.3).min(1.0);
            format!("[{t}, {a:.6}]")
        })
        .collect();
    format!(
        "[analysis]\ngravity = [0.0, -9.81]\noutput_every = 100\n\n\
         [[stage]]\nname = \"settle\"\nmode = \"static\"\ndt = 0.01\nsteps = 5\n\n\
         [[stage]]\nname = \"shake\"\nmode = \"dynamic\"\ndt = 0.001\nsteps = 1500\nbase_motion = true\n\n\
         [cover]\nsize = 0.5\n{}\n\
         [[material]]\nname = \"rock\"\ndensity = 2500.0\nyoung = 5.0e9\npoisson = 0.25\n\n\
         [[block]]\nname = \"base\"\nmaterial = \"rock\"\nvertices = [[-2.0, -1.0], [9.0, -1.0], [9.0, 0.0], [-2.0, 0.0]]\nfixed = true\n\n\
         [[block]]\nname = \"mass\"\nmaterial = \"rock\"\nvertices = [[0.0, 0.0], [7.0, 0.0], [7.0, 3.0], [1.5, 3.0]]\n\n\
         [[joint_set]]\nname = \"bedding\"\nangle = {DIP}\nspacing = {SPACING}\nblocks = [\"mass\"]\n\n{joints}\
         [[monitor]]\nname = \"f1\"\npoint = [1.0, 0.5]\n[[monitor]]\nname = \"f2\"\npoint = [2.5, 1.3]\n\
         [[monitor]]\nname = \"f3\"\npoint = [2.0, 1.9]\n[[monitor]]\nname = \"f4\"\npoint = [2.6, 2.7]\n\n\
         [[interface]]\nfriction_angle = 25.0\nnormal_penalty = 5.0e10\nshear_penalty = 5.0e9\n\n\
         [base_motion]\ntable = [{}]\n",
        min_block_area.map_or(String::new(), |a| format!("min_block_area = {a}\n")),
        record.join(", ")
    )
}

/// The bedding layer index (n · x / spacing) of a point.
fn layer(p: [f64; 2]) -> f64 {
    let a = DIP.to_radians();
    (-a.sin() * p[0] + a.cos() * p[1]) / SPACING
}

#[test]
fn no_merge_crosses_a_bedding_plane() {
    let m = parse_model(&slope(Some(0.6)), Path::new(".")).unwrap();
    assert_eq!(m.merged.len(), 6, "{:?}", m.merged);
    assert!(m.kept_small.is_empty());
    assert!(m.merged.iter().all(|g| g.bridges.is_none()));
    // the face slivers (the merges of more than 0.5 m² next to the face) went into the
    // block behind them in their own bedding layer (the earlier rule put both into the
    // block of another layer, across the bedding plane they share with it)
    let slivers: Vec<_> = m
        .merged
        .iter()
        .filter(|g| g.area > 0.5 && g.centroid[0] < 2.0)
        .collect();
    assert_eq!(slivers.len(), 2, "{:?}", m.merged);
    for g in slivers {
        let b = &m.blocks[g.block];
        let c = nmm::geometry::moments::polygon_moments(&b.vertices, b.vertices[0]).centroid();
        assert_eq!(
            layer(c).floor(),
            layer(g.centroid).floor(),
            "the sliver at {:?} went into block {} of another bedding layer",
            g.centroid,
            b.name
        );
    }
    // the two face slivers went into the block behind them, in their own layer
    let unmerged = parse_model(&slope(None), Path::new(".")).unwrap();
    assert_eq!(unmerged.blocks.len(), m.blocks.len() + 6);
    assert!(
        nmm::model::warnings(&m).is_empty(),
        "{:?}",
        nmm::model::warnings(&m)
    );
}

/// |displacement| of the monitors f1 … f4 at the end of the run.
fn run(text: &str) -> Vec<f64> {
    let mut sim = Simulation::new(parse_model(text, Path::new(".")).unwrap()).unwrap();
    while !sim.finished() {
        sim.advance().unwrap();
    }
    let v = monitor_values(&sim);
    (0..4).map(|k| v[4 * k].hypot(v[4 * k + 1])).collect()
}

#[test]
fn face_wedges_move_alike_with_and_without_min_block_area() {
    let without = run(&slope(None));
    let with = run(&slope(Some(0.6)));
    for k in 0..4 {
        eprintln!(
            "f{}: {:.4} m without merging, {:.4} m with min_block_area = 0.6 ({:+.1}%)",
            k + 1,
            without[k],
            with[k],
            (with[k] / without[k] - 1.0) * 100.0
        );
    }
    // f1 is the face block of the lowest layer, held at the toe by the base: it barely
    // moves either way. f2 … f4 are the face wedges that slide along the bedding.
    for k in 1..4 {
        assert!(without[k] > 0.05, "f{} slides", k + 1);
        assert!(
            (with[k] - without[k]).abs() < 0.1 * without[k],
            "f{}: {} vs {}",
            k + 1,
            with[k],
            without[k]
        );
    }
    assert!(with[0] < 0.05 && without[0] < 0.05);
}
