//! Plots: both files are written, the PNG has the requested size (signature and IHDR read
//! back), the SVG carries the labels, and awkward data (empty, constant, non-finite) draws.

use nmm::output::{plot_panels, LineStyle, Panel, PlotError, Series};
use std::path::Path;

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR", "first chunk is IHDR");
    let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
    assert!(bytes.ends_with(b"IEND\xae\x42\x60\x82"), "complete PNG");
    (w, h)
}

fn slip_and_input() -> Vec<Panel> {
    let t: Vec<f64> = (0..=200).map(|k| k as f64 * 0.01).collect();
    vec![
        Panel {
            title: "Sliding block".into(),
            x_label: "time (s)".into(),
            y_label: "slip (m)".into(),
            series: vec![
                Series {
                    label: "NMM".into(),
                    points: t.iter().map(|&t| (t, 0.05 * t * t)).collect(),
                    style: LineStyle::solid(0),
                },
                Series {
                    label: "Newmark analytic".into(),
                    points: t.iter().map(|&t| (t, 0.05 * t * t * 1.01)).collect(),
                    style: LineStyle::dashed(1),
                },
                Series {
                    label: "samples".into(),
                    points: t.iter().step_by(20).map(|&t| (t, 0.05 * t * t)).collect(),
                    style: LineStyle::points(2),
                },
            ],
            hlines: vec![(0.15, "limit".into())],
        },
        Panel {
            title: "Input".into(),
            x_label: "time (s)".into(),
            y_label: "acceleration (m/s²)".into(),
            series: vec![Series {
                label: "a_x".into(),
                points: t.iter().map(|&t| (t, (6.0 * t).sin())).collect(),
                style: LineStyle::solid(3),
            }],
            hlines: vec![],
        },
    ]
}

#[test]
fn writes_png_and_svg_with_labels() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("slip_history");
    let files = plot_panels(&stem, &slip_and_input(), 800, 900).unwrap();
    assert_eq!(
        files,
        [
            dir.path().join("slip_history.png"),
            dir.path().join("slip_history.svg")
        ]
    );
    assert_eq!(png_size(&files[0]), (800, 900));
    let svg = std::fs::read_to_string(&files[1]).unwrap();
    assert!(svg.contains(r#"width="800""#) && svg.contains(r#"height="900""#));
    for label in [
        "Sliding block",
        "Input",
        "time (s)",
        "slip (m)",
        "acceleration (m/s²)",
        "NMM",
        "Newmark analytic",
        "samples",
        "limit",
        "a_x",
    ] {
        assert!(svg.contains(label), "SVG lacks {label:?}");
    }
    if let Ok(keep) = std::env::var("NMM_KEEP_PLOT") {
        std::fs::copy(&files[0], keep).unwrap();
    }
}

#[test]
fn empty_constant_and_non_finite_series_do_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let series = |label: &str, points: Vec<(f64, f64)>| Series {
        label: label.into(),
        points,
        style: LineStyle::solid(0),
    };
    let panels = vec![
        Panel {
            title: "empty".into(),
            series: vec![series("nothing", vec![])],
            ..Panel::default()
        },
        Panel {
            title: "constant".into(),
            series: vec![series("flat", vec![(1.0, 3.0), (1.0, 3.0)])],
            ..Panel::default()
        },
        Panel {
            title: "non-finite".into(),
            series: vec![series(
                "gaps",
                vec![
                    (0.0, 1.0),
                    (0.5, f64::NAN),
                    (1.0, 2.0),
                    (f64::INFINITY, 0.0),
                    (2.0, 1.5),
                ],
            )],
            hlines: vec![(f64::NAN, "bad line".into()), (0.0, "zero".into())],
            ..Panel::default()
        },
        Panel::default(),
    ];
    let files = plot_panels(&dir.path().join("odd"), &panels, 400, 800).unwrap();
    assert_eq!(png_size(&files[0]), (400, 800));
    let svg = std::fs::read_to_string(&files[1]).unwrap();
    assert!(svg.contains("gaps") && svg.contains("zero"));
}

#[test]
fn bad_requests_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("x");
    assert!(matches!(
        plot_panels(&stem, &[], 800, 600),
        Err(PlotError::NoPanels)
    ));
    let panels = slip_and_input();
    for (w, h) in [(0, 600), (800, 0), (800, 150), (100_000, 600)] {
        assert!(
            matches!(
                plot_panels(&stem, &panels, w, h),
                Err(PlotError::InvalidSize { .. })
            ),
            "{w}x{h}"
        );
    }
    assert!(!dir.path().join("x.png").exists());
    let missing = dir.path().join("no/such/dir/x");
    assert!(matches!(
        plot_panels(&missing, &panels, 800, 600),
        Err(PlotError::Draw { .. })
    ));
}

/// A map keeps true proportions: a 4 m × 1 m strip at 800 pixels wide gives a figure about
/// a quarter as high (plus the margins); polygons and lines with non-finite points draw.
#[test]
fn map_keeps_true_proportions() {
    use nmm::output::plot::{plot_map, MapLine, MapPolygon};
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("map");
    let polygons = vec![
        MapPolygon {
            points: vec![(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)],
            colour: 0,
        },
        MapPolygon {
            points: vec![(2.0, 0.0), (4.0, 0.0), (4.0, 1.0), (2.0, 1.0)],
            colour: 11,
        },
    ];
    let lines = vec![MapLine {
        points: vec![(1.0, 0.5), (3.0, 0.5), (f64::NAN, 0.0)],
        colour: 3,
        width: 3,
    }];
    let files = plot_map(&stem, "strip", &polygons, &lines, 800).unwrap();
    assert_eq!(files.len(), 2);
    let (w, h) = png_size(&files[0]);
    assert_eq!(w, 800);
    // plot area 720 px wide for 4.24 m, 1.06 m high: 180 px, plus 80 px of labels and title
    assert!((250..=270).contains(&h), "{h}");
    assert!(std::fs::read_to_string(&files[1])
        .unwrap()
        .contains("strip"));
    assert!(plot_map(&stem, "x", &polygons, &lines, 10).is_err());
}
