//! The history figure of `examples/tunnel.toml` from a run's folder:
//!
//! ```sh
//! nmm run examples/tunnel.toml --out out/tunnel
//! cargo run --release --example tunnel_figure -- out/tunnel docs/tunnel_history
//! ```
//!
//! Four panels against time (the static stages take the first 0.17 s, 0.01 s a step; the
//! shake the rest): the wall's convergence (crown and invert vertical, sidewalls
//! horizontal, relative to the base), the bolts' axial forces, the change of each bolt's
//! force during the shake (from its value at the shake's start), and the base
//! acceleration the shake stage applied. Writes `STEM.png` and `STEM.svg`.

use nmm::output::plot::{plot_panels, LineStyle, Panel, Series};
use std::path::Path;

const BOLTS: [&str; 7] = ["b1", "b2", "b3", "b4", "b5", "b6", "b7"];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [dir, stem] = args.as_slice() else {
        eprintln!("usage: tunnel_figure RUN_DIR STEM");
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
    let (t, stage) = (col("time"), col("stage"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let num = |r: &Vec<&str>, i: usize| r[i].parse::<f64>().unwrap();
    let series = |i: usize, scale: f64| -> Vec<(f64, f64)> {
        rows.iter()
            .map(|r| (num(r, t), num(r, i) * scale))
            .collect()
    };
    let start = rows
        .iter()
        .position(|r| r[stage] == "shake")
        .expect("a shake stage");
    // the shake stage starts at the end of the support stage
    let t0 = num(&rows[start - 1], t);

    let walls = Panel {
        title: "Tunnel: the wall's displacement (in situ, excavated, bolted, shaken)".into(),
        x_label: "time (s)".into(),
        y_label: "displacement (mm)".into(),
        series: [
            ("crown uy", "crown.uy"),
            ("invert uy", "invert.uy"),
            ("right wall ux", "right_wall.ux"),
            ("left wall ux", "left_wall.ux"),
        ]
        .iter()
        .enumerate()
        .map(|(k, (label, name))| Series {
            label: (*label).into(),
            points: series(col(name), 1e3),
            style: LineStyle::solid(k),
        })
        .collect(),
        hlines: vec![],
    };
    let forces = Panel {
        title: "Bolt forces (installed with 100 kN/m at the support stage's start)".into(),
        x_label: "time (s)".into(),
        y_label: "axial force (kN/m)".into(),
        series: BOLTS
            .iter()
            .enumerate()
            .map(|(k, b)| Series {
                label: (*b).into(),
                points: series(col(&format!("{b}.force")), 1e-3),
                style: LineStyle::solid(k),
            })
            .collect(),
        hlines: vec![],
    };
    let change = Panel {
        title: "Bolt force change during the shake".into(),
        x_label: "time (s)".into(),
        y_label: "force − force at the shake's start (N/m)".into(),
        series: BOLTS
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let i = col(&format!("{b}.force"));
                let f0 = num(&rows[start - 1], i);
                Series {
                    label: (*b).into(),
                    points: rows[start - 1..]
                        .iter()
                        .map(|r| (num(r, t), num(r, i) - f0))
                        .collect(),
                    style: LineStyle::solid(k),
                }
            })
            .collect(),
        hlines: vec![],
    };
    let model = nmm::model::load_model(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/tunnel.toml"
    )))
    .unwrap();
    let record = model.base_motion.expect("a record");
    let acc = Panel {
        title: "Input: base acceleration (synthetic PEER-format record, 1.0–2.5 s of it at 0.4 g)"
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
    let files = plot_panels(Path::new(stem), &[walls, forces, change, acc], 1000, 1300).unwrap();
    for f in files {
        println!("{}", f.display());
    }
}
