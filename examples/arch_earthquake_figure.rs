//! The figure of `examples/arch_earthquake.toml` from a run's folder:
//!
//! ```sh
//! nmm run examples/arch_earthquake.toml --out out/arch
//! cargo run --release --example arch_earthquake_figure -- out/arch docs/arch_earthquake
//! ```
//!
//! Three panels against time: the crown's displacement (relative to the base), the normal
//! forces on the two springing joints, and the base acceleration the shake stage applied
//! (the record from the stage's start). Writes `STEM.png` and `STEM.svg`.

use nmm::output::plot::{plot_panels, LineStyle, Panel, Series};
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [dir, stem] = args.as_slice() else {
        eprintln!("usage: arch_earthquake_figure RUN_DIR STEM");
        std::process::exit(2);
    };
    let text = std::fs::read_to_string(Path::new(dir).join("history.csv"))
        .unwrap_or_else(|e| panic!("{dir}/history.csv: {e}"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    };
    let (t, ux, uy) = (col("time"), col("crown.ux"), col("crown.uy"));
    let (fr, fl, stage) = (
        col("right_springing.fn"),
        col("left_springing.fn"),
        col("stage"),
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let num = |r: &Vec<&str>, i: usize| r[i].parse::<f64>().unwrap();
    let start = rows
        .iter()
        .position(|r| r[stage] == "shake")
        .expect("a shake stage");
    // the shake stage starts at the end of the settle stage
    let t0 = num(&rows[start - 1], t);
    let model = nmm::model::load_model(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/arch_earthquake.toml"
    )))
    .unwrap();
    let record = model.base_motion.expect("a record");
    // every row: the impacts at the joints last a step or two
    let series = |i: usize, scale: f64| -> Vec<(f64, f64)> {
        rows.iter()
            .map(|r| (num(r, t), num(r, i) * scale))
            .collect()
    };
    let disp = Panel {
        title: "Arch in an earthquake: crown displacement (settled statically, then shaken)".into(),
        x_label: "time (s)".into(),
        y_label: "crown displacement (mm)".into(),
        series: vec![
            Series {
                label: "horizontal ux".into(),
                points: series(ux, 1e3),
                style: LineStyle::solid(0),
            },
            Series {
                label: "vertical uy".into(),
                points: series(uy, 1e3),
                style: LineStyle::solid(1),
            },
        ],
        hlines: vec![],
    };
    let forces = Panel {
        title: "Normal force on the springing joints".into(),
        x_label: "time (s)".into(),
        y_label: "normal force (kN/m)".into(),
        series: vec![
            Series {
                label: "right springing".into(),
                points: series(fr, 1e-3),
                style: LineStyle::solid(2),
            },
            Series {
                label: "left springing".into(),
                points: series(fl, 1e-3),
                style: LineStyle::solid(4),
            },
        ],
        hlines: vec![],
    };
    let acc = Panel {
        title:
            "Input: base acceleration (synthetic PEER-format record, from the shake stage's start)"
                .into(),
        x_label: "time (s)".into(),
        y_label: "acceleration (m/s²)".into(),
        series: vec![Series {
            label: "base a_x".into(),
            points: rows
                .iter()
                .map(|r| num(r, t))
                .map(|ti| {
                    (
                        ti,
                        if ti > t0 {
                            record.accel(ti - t0)[0]
                        } else {
                            0.0
                        },
                    )
                })
                .collect(),
            style: LineStyle::solid(3),
        }],
        hlines: vec![],
    };
    let files = plot_panels(Path::new(stem), &[disp, forces, acc], 1000, 1000).unwrap();
    for f in files {
        println!("{}", f.display());
    }
}
