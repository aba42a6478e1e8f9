//! Unit tests of model parsing: the documented example, and one test per rule.

use super::*;
use std::path::Path;

/// The complete example of `docs/model-format.md`.
pub(crate) const EXAMPLE: &str = include_str!("../../../../tests/data/example.toml");

fn parse(text: &str) -> Result<Model, ModelError> {
    parse_model(text, Path::new("."))
}

/// The message without its location suffix ` (model.toml, line N)` (checked on its own
/// in `errors_name_their_line`).
fn without_line(e: String) -> String {
    match e.rfind(" (model.toml, line ") {
        Some(i) if e.ends_with(')') => e[..i].to_string(),
        _ => e,
    }
}

/// Parse `EXAMPLE` with `from` replaced by `to` (which must occur) and return the error.
fn err_with(from: &str, to: &str) -> String {
    without_line(err_with_line(from, to))
}

/// As [`err_with`], with the location.
fn err_with_line(from: &str, to: &str) -> String {
    assert!(EXAMPLE.contains(from), "{from:?} not in the example");
    match parse(&EXAMPLE.replacen(from, to, 1)) {
        Ok(_) => panic!("{from:?} -> {to:?} was accepted"),
        Err(e) => e.0,
    }
}

/// The example plus `extra` appended, and return the error.
fn err_plus(extra: &str) -> String {
    match parse(&format!("{EXAMPLE}\n{extra}")) {
        Ok(_) => panic!("{extra:?} was accepted"),
        Err(e) => without_line(e.0),
    }
}

#[test]
fn errors_name_their_line() {
    // (edit of tests/data/example.toml, expected message end)
    let cases = [
        (
            "dt = 0.001",
            "dt = -0.001",
            "got -0.001 (model.toml, line 3)",
        ),
        (
            "steps = 3000\n",
            "",
            "`steps`: missing (required) (model.toml, line 1)",
        ),
        ("size = 0.05", "size = 0.0", "got 0 (model.toml, line 10)"),
        (
            "young = 7.0e9",
            "young = -7.0e9",
            "got -7000000000 (model.toml, line 15)",
        ),
        ("poisson = 0.33", "poissons = 0.33", "(model.toml, line 16)"),
        (
            "vertices = [[0.0, 1.0], [0.0, 1.5], [1.0, 1.5], [1.0, 1.0]]",
            "vertices = [[0.0, 1.0], [1.0, 1.5], [0.0, 1.5], [1.0, 1.0]]",
            "self-intersects (edges 1 and 3) (model.toml, line 27)",
        ),
        (
            "vertices = [[1.2, 1.0], [2.0, 1.0], [2.0, 1.5], [1.2, 1.5]]",
            "vertices = [[0.9, 1.0], [2.0, 1.0], [2.0, 1.5], [0.9, 1.5]]",
            "overlaps block \"slider\" (blocks may touch but not overlap) (model.toml, line 32)",
        ),
        (
            "blocks = [\"base\", \"slider\"]",
            "blocks = [\"base\", \"slab\"]",
            "(model.toml, line 40)",
        ),
        (
            "edge = [[0.0, 1.5], [1.0, 1.5]]",
            "edge = [[0.0, 1.4], [1.0, 1.4]]",
            "(model.toml, line 48)",
        ),
        ("uy = 0.0", "uy = nan", "(model.toml, line 55)"),
        (
            "point = [1.5, 1.2]",
            "point = [1.1, 1.2]",
            "(model.toml, line 62)",
        ),
    ];
    for (from, to, end) in cases {
        let e = err_with_line(from, to);
        assert!(e.ends_with(end), "{from:?} -> {to:?}: {e}");
    }
}

#[test]
fn example_parses_with_expected_values() {
    let m = parse(EXAMPLE).unwrap();
    let a = &m.analysis;
    assert_eq!(a.mode, Mode::Dynamic);
    assert_eq!((a.dt, a.steps, a.output_every), (0.001, 3000, 10));
    assert_eq!(a.gravity, [0.0, -9.81]);
    assert_eq!(a.friction.name(), "return-mapping");
    assert!(m.interfaces.iter().all(|i| i.law.is_none()));
    assert_eq!(
        (
            a.max_iterations,
            a.tolerance,
            a.max_step_cuts,
            a.constraint_penalty
        ),
        (25, 1e-9, 6, 1e6)
    );
    assert_eq!(m.cover_size, 0.05);
    assert_eq!(
        m.materials,
        vec![Material {
            name: "limestone".into(),
            density: 2243.0,
            young: 7.0e9,
            poisson: 0.33,
            plane: Plane::Strain,
            damping: Rayleigh::default(),
        }]
    );
    let names: Vec<&str> = m.blocks.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["base", "slider", "upper"]);
    assert!(m.blocks[0].fixed && !m.blocks[1].fixed && !m.blocks[2].fixed);
    // The clockwise slider is re-oriented; the others are kept as written.
    assert_eq!(
        m.blocks[0].vertices,
        vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
    );
    assert_eq!(
        m.blocks[1].vertices,
        vec![[1.0, 1.0], [1.0, 1.5], [0.0, 1.5], [0.0, 1.0]]
    );
    for b in &m.blocks {
        assert!(crate::geometry::polygon::is_ccw(&b.vertices));
    }
    assert_eq!(m.interfaces.len(), 2);
    assert_eq!(m.interfaces[0].scope, InterfaceScope::Default);
    assert_eq!(m.interfaces[0].friction_angle, 30.0);
    assert_eq!(
        m.interfaces[1].scope,
        InterfaceScope::Blocks(vec![0], vec![1])
    );
    assert_eq!(m.interfaces[1].friction_angle, 40.5);
    assert_eq!(m.interface_for(1, 0).unwrap().friction_angle, 40.5);
    assert_eq!(m.interface_for(1, 2).unwrap().friction_angle, 30.0);
    assert_eq!(
        m.loads,
        vec![Load {
            block: 1,
            kind: LoadKind::Edge {
                a: [0.0, 1.5],
                b: [1.0, 1.5],
                traction: [0.0, -1.0e6]
            }
        }]
    );
    assert_eq!(
        m.constraints,
        vec![Constraint {
            block: 2,
            geometry: ConstraintGeometry::Edge {
                a: [2.0, 1.1],
                b: [2.0, 1.2]
            },
            ux: Some(TimeFunction::Table(vec![(0.0, 0.0), (5.0, 3.0e-4)])),
            uy: Some(TimeFunction::Constant(0.0)),
        }]
    );
    assert_eq!(
        m.base_motion.as_ref().map(|b| b.axes.clone()),
        Some(BaseMotion::from_samples(&[[0.0, 0.0, 0.0], [0.01, 0.05, 0.0]]).axes)
    );
    assert_eq!(
        m.monitors,
        vec![
            Monitor {
                name: "crest".into(),
                kind: MonitorKind::Point {
                    p: [1.5, 1.2],
                    block: 2
                }
            },
            Monitor {
                name: "joint".into(),
                kind: MonitorKind::Interface {
                    first: vec![1],
                    second: vec![0]
                }
            },
        ]
    );
}

#[test]
fn minimal_model_gets_defaults() {
    let text = r#"
        [analysis]
        dt = 1
        steps = 5.0
        [cover]
        size = 0.1
        [[material]]
        name = "m"
        density = 1
        young = 1
        poisson = 0
        plane = "stress"
        [[block]]
        name = "b"
        material = "m"
        vertices = [[0, 0], [1, 0], [0, 1]]
    "#;
    let m = parse(text).unwrap();
    assert_eq!(m.analysis.mode, Mode::Dynamic);
    assert_eq!(
        (m.analysis.dt, m.analysis.steps, m.analysis.output_every),
        (1.0, 5, 1)
    );
    assert_eq!(m.analysis.gravity, [0.0, 0.0]);
    assert_eq!(m.materials[0].plane, Plane::Stress);
    assert!(m.interfaces.is_empty() && m.loads.is_empty() && m.base_motion.is_none());
}

#[test]
fn extensions_are_read() {
    let m = parse(&EXAMPLE.replacen(
        "output_every = 10",
        "output_every = 10\nmax_iterations = 40\ntolerance = 1e-6\nmax_step_cuts = 0\nconstraint_penalty = 1e4",
        1,
    )
    .replacen("mode = \"dynamic\"", "mode = \"static\"", 1)
    .replacen("friction = \"return-mapping\"", "friction = \"conventional\"", 1))
    .unwrap();
    let a = &m.analysis;
    assert_eq!((a.mode, a.friction.name()), (Mode::Static, "conventional"));
    assert_eq!(
        (
            a.max_iterations,
            a.tolerance,
            a.max_step_cuts,
            a.constraint_penalty
        ),
        (40, 1e-6, 0, 1e4)
    );
}

#[test]
fn syntax_error_has_line_and_column() {
    let e = parse("[analysis]\ndt = 0.1\nsteps = = 3\n").unwrap_err().0;
    assert!(
        e.starts_with("model.toml: TOML syntax error at line 3, column "),
        "{e}"
    );
    assert!(!e.contains('\n'));
    let e = parse_model_named("a = \"\n", Path::new("."), "x/m.toml")
        .unwrap_err()
        .0;
    assert!(
        e.starts_with("x/m.toml: TOML syntax error at line 1"),
        "{e}"
    );
}

#[test]
fn analysis_errors() {
    assert_eq!(
        err_with("dt = 0.001", "dt = -0.001"),
        "[analysis]: key `dt`: must be positive, got -0.001"
    );
    assert_eq!(
        err_with("dt = 0.001\n", ""),
        "[analysis]: key `dt`: missing (required)"
    );
    assert_eq!(
        err_with("steps = 3000", "steps = 0"),
        "[analysis]: key `steps`: must be positive, got 0"
    );
    assert_eq!(
        err_with("steps = 3000", "steps = 2.5"),
        "[analysis]: key `steps`: expected an integer, got 2.5"
    );
    assert_eq!(
        err_with("mode = \"dynamic\"", "mode = \"quasi\""),
        "[analysis]: key `mode`: expected one of \"dynamic\", \"static\", got \"quasi\""
    );
    assert!(
        err_with("friction = \"return-mapping\"", "friction = \"coulomb\"")
            .starts_with("[analysis]: key `friction`")
    );
    assert!(err_with("output_every = 10", "output_every = 0")
        .starts_with("[analysis]: key `output_every`: must be at least 1"));
    assert!(err_with("output_every = 10", "tolerance = 1.0")
        .starts_with("[analysis]: key `tolerance`: must be in (0, 1)"));
    assert!(err_with("output_every = 10", "max_iterations = 0")
        .starts_with("[analysis]: key `max_iterations`"));
    assert!(err_with("output_every = 10", "max_step_cuts = -1")
        .starts_with("[analysis]: key `max_step_cuts`"));
    assert!(err_with("output_every = 10", "constraint_penalty = 0")
        .starts_with("[analysis]: key `constraint_penalty`"));
    assert_eq!(
        err_with("dt = 0.001", "dt = nan"),
        "[analysis]: key `dt`: NaN is not allowed"
    );
    assert!(err_with("gravity = [0.0, -9.81]", "gravity = [0.0, -inf]")
        .starts_with("[analysis]: key `gravity`: infinite"));
    assert!(err_with("gravity = [0.0, -9.81]", "gravity = [0.0]")
        .starts_with("[analysis]: key `gravity`: expected a pair"));
    assert!(err_with("dt = 0.001", "dt = \"0.001\"")
        .starts_with("[analysis]: key `dt`: expected a number, got string"));
    assert!(err_with("[analysis]", "[analysis_]").starts_with("top level: unknown key `analysis_`"));
    assert!(err_with("output_every", "outputevery")
        .starts_with("[analysis]: unknown key `outputevery`"));
}

#[test]
fn cover_and_material_errors() {
    assert_eq!(
        err_with("size = 0.05", "size = 0"),
        "[cover]: key `size`: must be positive, got 0"
    );
    assert!(err_with("[cover]\nsize = 0.05", "").starts_with("[cover]: missing table"));
    assert_eq!(
        err_with("density = 2243.0", "density = -1"),
        "[[material]] \"limestone\": key `density`: must be positive, got -1"
    );
    assert!(err_with("young = 7.0e9", "young = 0.0")
        .starts_with("[[material]] \"limestone\": key `young`: must be positive"));
    assert!(err_with("poisson = 0.33", "poisson = 0.5")
        .starts_with("[[material]] \"limestone\": key `poisson`: must be in (-1, 0.5)"));
    assert!(err_with("poisson = 0.33", "poisson = -1").contains("key `poisson`"));
    assert!(err_with("name = \"limestone\"", "name = \"\"")
        .starts_with("[[material]] #1: key `name`: must not be empty"));
    assert!(err_with("[[material]]", "[material]")
        .starts_with("[[material]]: must be an array of tables"));
    let dup = "[[material]]\nname = \"limestone\"\ndensity = 1.0\nyoung = 1.0\npoisson = 0.1\n";
    assert_eq!(
        err_plus(dup),
        "[[material]] \"limestone\": key `name`: duplicate material name (also [[material]] #1)"
    );
}

#[test]
fn block_errors() {
    let slider = "vertices = [[0.0, 1.0], [0.0, 1.5], [1.0, 1.5], [1.0, 1.0]]";
    let e = err_with(
        slider,
        "vertices = [[0.0, 1.0], [1.0, 1.5], [0.0, 1.5], [1.0, 1.0]]",
    );
    assert_eq!(
        e,
        "[[block]] \"slider\": key `vertices`: polygon self-intersects (edges 1 and 3)"
    );
    let e = err_with(slider, "vertices = [[0.0, 1.0], [0.0, 1.5]]");
    assert_eq!(
        e,
        "[[block]] \"slider\": key `vertices`: a polygon needs at least 3 vertices, got 2"
    );
    let e = err_with(slider, "vertices = [[0.0, 1.0], [0.5, 1.25], [1.0, 1.5]]");
    assert!(
        e.starts_with("[[block]] \"slider\": key `vertices`: degenerate polygon"),
        "{e}"
    );
    let e = err_with(
        slider,
        "vertices = [[0.0, 1.0], [0.0, 1.5], [1.0, 1.5], [1.0, 1.0], [0.0, 1.0]]",
    );
    assert!(e.contains("vertices 5 and 1 coincide"), "{e}");
    let e = err_with(
        slider,
        "vertices = [[0.0, 1.0], [0.0, 1.5], [1.0, 1.5], [1.0, nan]]",
    );
    assert!(
        e.starts_with("[[block]] \"slider\": key `vertices`: point 4: NaN"),
        "{e}"
    );
    let e = err_with(
        slider,
        "vertices = [[0.0, 1.0], [0.0, 1.5], [1.0, 1.5], [1.0, 1e300]]",
    );
    assert!(e.contains("out of range"), "{e}");
    let e = err_with(
        slider,
        "vertices = [[0.0, 0.9], [0.0, 1.5], [1.0, 1.5], [1.0, 0.9]]",
    );
    assert_eq!(
        e,
        "[[block]] \"slider\": key `vertices`: overlaps block \"base\" (blocks may touch but not overlap)"
    );
    let e = err_with(
        "material = \"limestone\"\nvertices = [[0.0, 1.0]",
        "material = \"granite\"\nvertices = [[0.0, 1.0]",
    );
    assert_eq!(
        e,
        "[[block]] \"slider\": key `material`: unknown material \"granite\""
    );
    let e = err_with("name = \"upper\"", "name = \"slider\"");
    assert!(
        e.starts_with("[[block]] \"slider\": key `name`: duplicate block name"),
        "{e}"
    );
    let e = err_with("fixed = true", "fixed = 1");
    assert!(
        e.starts_with("[[block]] \"base\": key `fixed`: expected true or false"),
        "{e}"
    );
    let e = err_with("fixed = true", "fixd = true");
    assert!(
        e.starts_with("[[block]] \"base\": unknown key `fixd`"),
        "{e}"
    );
    let no_blocks = EXAMPLE.split("[[block]]").next().unwrap();
    assert_eq!(
        parse(no_blocks).unwrap_err().0,
        "[[block]]: the model defines no block"
    );
}

#[test]
fn interface_errors() {
    let e = err_with(
        "blocks = [\"base\", \"slider\"]",
        "blocks = [\"base\", \"slab\"]",
    );
    assert_eq!(e, "[[interface]] #2: key `blocks`: unknown block \"slab\"");
    let e = err_with(
        "blocks = [\"base\", \"slider\"]",
        "blocks = [\"base\", \"base\"]",
    );
    assert!(e.contains("must differ"), "{e}");
    let e = err_with("blocks = [\"base\", \"slider\"]", "");
    assert!(
        e.starts_with("[[interface]] #2 (default): a second default interface"),
        "{e}"
    );
    let e = err_with("friction_angle = 40.5", "friction_angle = 90");
    assert!(e.starts_with("[[interface]] #2 (blocks \"base\", \"slider\"): key `friction_angle`: must be in [0, 90)"), "{e}");
    assert!(err_with("cohesion = 0.0", "cohesion = -1.0").contains("key `cohesion`"));
    assert!(err_with(
        "normal_penalty = 1.0e10\nshear_penalty = 1.0e7\n\n[[interface]]",
        "normal_penalty = 0\nshear_penalty = 1.0e7\n\n[[interface]]"
    )
    .contains("key `normal_penalty`: must be positive"));
    let second = "[[interface]]\nblocks = [\"slider\", \"base\"]\nfriction_angle = 1\nnormal_penalty = 1\nshear_penalty = 1\n";
    assert!(err_plus(second).contains("this pair already has an interface ([[interface]] #2)"));
    // Without a default, every pair needs its own interface.
    let e = err_with(
        "[[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n",
        "",
    );
    assert!(
        e.starts_with("[[interface]]: no interface for blocks \"base\" and \"upper\""),
        "{e}"
    );
}

#[test]
fn load_and_constraint_errors() {
    let e = err_with(
        "edge = [[0.0, 1.5], [1.0, 1.5]]",
        "edge = [[0.0, 1.4], [1.0, 1.4]]",
    );
    assert_eq!(e, "[[load]] #1 (block \"slider\"): key `edge`: segment [[0,1.4],[1,1.4]] is not on the boundary of block \"slider\"");
    let e = err_with(
        "edge = [[0.0, 1.5], [1.0, 1.5]]",
        "edge = [[0.5, 1.5], [0.5, 1.5]]",
    );
    assert!(e.contains("has zero length"), "{e}");
    let e = err_with("block = \"slider\"\nedge", "block = \"slid\"\nedge");
    assert_eq!(
        e,
        "[[load]] #1 (block \"slid\"): key `block`: unknown block \"slid\""
    );
    let e = err_with("traction = [0.0, -1.0e6]", "force = [0.0, -1.0e6]");
    assert!(e.contains("key `force`"), "{e}");
    let e = err_with(
        "edge = [[0.0, 1.5], [1.0, 1.5]]\ntraction",
        "point = [5.0, 5.0]\ntraction",
    );
    assert!(e.contains("key `traction`: belongs to an edge load"), "{e}");
    let e = err_with(
        "edge = [[0.0, 1.5], [1.0, 1.5]]\ntraction = [0.0, -1.0e6]",
        "point = [5.0, 5.0]\nforce = [0.0, 1.0]",
    );
    assert_eq!(
        e,
        "[[load]] #1 (block \"slider\"): key `point`: point [5,5] is outside block \"slider\""
    );
    assert!(parse(&EXAMPLE.replacen(
        "edge = [[0.0, 1.5], [1.0, 1.5]]\ntraction = [0.0, -1.0e6]",
        "point = [1.0, 1.2]\nforce = [0.0, 1.0]",
        1
    ))
    .is_ok());
    let e = err_with(
        "edge = [[2.0, 1.1], [2.0, 1.2]]",
        "edge = [[2.0, 1.1], [2.1, 1.2]]",
    );
    assert!(
        e.starts_with("[[constraint]] #1 (block \"upper\"): key `edge`: segment"),
        "{e}"
    );
    let e = err_with(
        "ux = [[0.0, 0.0], [5.0, 3.0e-4]]",
        "ux = [[0.0, 0.0], [0.0, 3.0e-4]]",
    );
    assert!(
        e.contains("key `ux`: row 2: times must be strictly increasing"),
        "{e}"
    );
    let e = err_with("ux = [[0.0, 0.0], [5.0, 3.0e-4]]\nuy = 0.0", "");
    assert!(
        e.contains("key `ux`: missing: give `ux`, `uy` or both"),
        "{e}"
    );
    let e = err_with("ux = [[0.0, 0.0], [5.0, 3.0e-4]]", "ux = \"free\"");
    assert!(e.contains("key `ux`: expected a number or a table"), "{e}");
    let e = err_with("block = \"upper\"", "block = \"uper\"");
    assert!(e.contains("unknown block \"uper\""), "{e}");
}

#[test]
fn base_motion_and_monitor_errors() {
    let table = "table = [[0.0, 0.0, 0.0], [0.01, 0.05, 0.0]]";
    let e = err_with(table, "table = [[0.0, 0.0, 0.0], [0.0, 0.05, 0.0]]");
    assert!(
        e.starts_with("[base_motion]: key `table`: sample 2: times must be strictly increasing"),
        "{e}"
    );
    let e = err_with(table, "table = [[0.0, 0.0, 0.0]]");
    assert!(e.contains("at least 2 samples"), "{e}");
    let e = err_with(table, "table = [[0.0, 0.0, 0.0], [1.0, 0.0]]");
    assert!(e.contains("same length"), "{e}");
    let e = err_with(table, "file = \"no-such-record.csv\"");
    assert!(
        e.starts_with("[base_motion]: key `file`: cannot read \"no-such-record.csv\""),
        "{e}"
    );
    let e = err_with(table, "file = \"x.csv\"\ntable = []");
    assert!(e.contains("not both"), "{e}");
    let e = err_with(table, "table = [[0.0, 1.0], [1.0, 2.0]]\nformat = \"csv\"");
    assert!(e.contains("key `format`: applies only with `file`"), "{e}");
    let e = err_with(
        table,
        "table = [[0.0, 1.0], [1.0, 2.0]]\nscale = 1e308\ncomponent = \"y\"",
    );
    assert!(e.contains("key `scale`"), "{e}");
    let m = parse(&EXAMPLE.replacen(
        table,
        "table = [[0.0, 1.0], [1.0, 2.0]]\nscale = 2\ncomponent = \"y\"",
        1,
    ))
    .unwrap();
    let b = m.base_motion.unwrap();
    assert!(b.axes[0].is_empty());
    assert_eq!(b.axes[1], vec![[0.0, 2.0], [1.0, 4.0]]);

    let e = err_with("point = [1.5, 1.2]", "point = [1.1, 1.2]");
    assert_eq!(
        e,
        "[[monitor]] \"crest\": key `point`: point [1.1,1.2] is not inside any block"
    );
    let e = err_with("name = \"joint\"", "name = \"crest\"");
    assert_eq!(
        e,
        "[[monitor]] \"crest\": key `name`: duplicate monitor name"
    );
    let e = err_with(
        "interface = [\"slider\", \"base\"]",
        "interface = [\"slider\", \"bas\"]",
    );
    assert_eq!(
        e,
        "[[monitor]] \"joint\": key `interface`: unknown block \"bas\""
    );
    let e = err_with("name = \"joint\"", "name = \"a,b\"");
    assert!(e.contains("commas"), "{e}");
    // A monitor on the shared edge belongs to the first block that contains it.
    let m = parse(&EXAMPLE.replacen("point = [1.5, 1.2]", "point = [0.5, 1.0]", 1)).unwrap();
    assert_eq!(
        m.monitors[0].kind,
        MonitorKind::Point {
            p: [0.5, 1.0],
            block: 0
        }
    );
}

#[test]
fn errors_are_one_line() {
    let e = err_with("name = \"joint\"", "name = \"a\\nb\"");
    assert!(!e.contains('\n'), "{e}");
}

#[test]
fn damping_in_both_forms() {
    let with = |value: &str| {
        parse(&EXAMPLE.replacen(
            "poisson = 0.33",
            &format!("poisson = 0.33\ndamping = {value}"),
            1,
        ))
        .unwrap()
        .materials[0]
            .damping
    };
    assert_eq!(
        with("{ alpha = 0.5 }"),
        Rayleigh {
            alpha: 0.5,
            beta: 0.0
        }
    );
    assert_eq!(
        with("{ beta = 1e-3 }"),
        Rayleigh {
            alpha: 0.0,
            beta: 1e-3
        }
    );
    let r = with("{ ratio = 0.05, frequencies = [2.0, 20.0] }");
    for f in [2.0, 20.0] {
        let z = r.ratio_at(std::f64::consts::TAU * f);
        assert!((z - 0.05).abs() < 1e-14, "{z}");
    }
    assert!(r.ratio_at(std::f64::consts::TAU * 6.0) < 0.05);
    // equal frequencies: the minimum ζ is at f
    let r = with("{ ratio = 0.02, frequencies = [5.0, 5.0] }");
    let w = std::f64::consts::TAU * 5.0;
    assert!((r.ratio_at(w) - 0.02).abs() < 1e-15);
    assert!(r.ratio_at(0.9 * w) > 0.02 && r.ratio_at(1.1 * w) > 0.02);
    // a sub-table works too, and no damping is zero damping
    let sub = EXAMPLE.replacen(
        "poisson = 0.33",
        "poisson = 0.33\n[material.damping]\nalpha = 2.0",
        1,
    );
    assert_eq!(parse(&sub).unwrap().materials[0].damping.alpha, 2.0);
    assert!(parse(EXAMPLE).unwrap().materials[0].damping.is_zero());
}

/// The example with `slider` and `upper` cut by a joint set and `slider` by a fault.
fn jointed_example() -> String {
    format!(
        "{EXAMPLE}\n[[joint_set]]\nname = \"bedding\"\nangle = 35.0\nspacing = 0.3\norigin = [0.05, 1.02]\nblocks = [\"slider\", \"upper\"]\n\
         [[joint]]\nname = \"fault\"\npoints = [[0.2, 0.9], [0.8, 1.6]]\nblocks = [\"slider\"]\n\
         [[interface]]\njoint = \"bedding\"\nfriction_angle = 25.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n"
    )
}

#[test]
fn models_without_joints_are_unchanged_by_cutting() {
    let m = parse(EXAMPLE).unwrap();
    assert!(m.joints.is_empty() && m.cracks.is_empty() && m.merged.is_empty());
    for b in &m.blocks {
        assert_eq!(b.edge_joint, vec![None; b.vertices.len()]);
        assert_eq!(b.parent, None);
    }
}

#[test]
fn cut_blocks_are_named_tagged_and_referenced() {
    let m = parse(&jointed_example()).unwrap();
    let names: Vec<&str> = m.blocks.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "base", "slider.1", "slider.2", "slider.3", "slider.4", "slider.5", "slider.6",
            "upper.1", "upper.2", "upper.3", "upper.4"
        ]
    );
    assert_eq!(m.joints.len(), 2);
    assert_eq!(m.joints[0].name, "bedding");
    assert!(matches!(m.joints[1].kind, JointKind::Polyline { .. }));
    // pieces keep material and flags; areas add up; centroids ordered bottom to top
    let area = |i: usize| crate::geometry::polygon::signed_area(&m.blocks[i].vertices);
    let slider: f64 = (1..=6).map(area).sum();
    let upper: f64 = (7..=10).map(area).sum();
    assert!((slider - 0.5).abs() < 1e-12 && (upper - 0.4).abs() < 1e-12);
    for b in &m.blocks[1..] {
        assert!(!b.fixed && b.material == 0);
        assert_eq!(b.edge_joint.len(), b.vertices.len());
    }
    assert_eq!(m.blocks[1].parent.as_deref(), Some("slider"));
    let tags: Vec<Option<usize>> = m.blocks[1..]
        .iter()
        .flat_map(|b| b.edge_joint.iter().copied())
        .collect();
    assert!(tags.contains(&Some(0)) && tags.contains(&Some(1)) && tags.contains(&None));
    let cy = |i: usize| {
        let v = &m.blocks[i].vertices;
        crate::geometry::moments::polygon_moments(v, v[0]).centroid()[1]
    };
    for i in 1..6 {
        assert!(
            cy(i) <= cy(i + 1) + 1e-9,
            "{} above {}",
            names[i],
            names[i + 1]
        );
    }
    // the interfaces: the pair "base"–"slider" means every piece of slider
    assert_eq!(
        m.interfaces[1].scope,
        InterfaceScope::Blocks(vec![0], vec![1, 2, 3, 4, 5, 6])
    );
    assert_eq!(m.interfaces[2].scope, InterfaceScope::Joint(0));
    // precedence: joint > pair > default
    let phi = |i: Option<&Interface>| i.map(|i| i.friction_angle);
    assert_eq!(phi(m.interface_for_face(0, 3, Some(0))), Some(25.0));
    assert_eq!(phi(m.interface_for_face(0, 3, None)), Some(40.5));
    assert_eq!(phi(m.interface_for_face(2, 3, Some(1))), Some(30.0));
    assert_eq!(phi(m.interface_for_face(2, 3, None)), Some(30.0));
    assert_eq!(phi(m.interface_for_face(8, 2, Some(0))), Some(25.0));
    // the edge load on slider's top is split among the pieces along it, length kept
    let length: f64 = m
        .loads
        .iter()
        .map(|l| match l.kind {
            LoadKind::Edge { a, b, traction } => {
                assert_eq!(traction, [0.0, -1.0e6]);
                assert!((1..=6).contains(&l.block));
                assert!(crate::geometry::polygon::segment_on_boundary(
                    &m.blocks[l.block].vertices,
                    a,
                    b,
                    1e-9
                ));
                crate::geometry::dist(a, b)
            }
            _ => panic!("{l:?}"),
        })
        .sum();
    assert!(m.loads.len() >= 2);
    assert!((length - 1.0).abs() < 1e-12, "{length}");
    // the edge constraint on upper's right side goes to the pieces it lies on
    let c_len: f64 = m
        .constraints
        .iter()
        .map(|c| match c.geometry {
            ConstraintGeometry::Edge { a, b } => {
                assert!((7..=10).contains(&c.block));
                crate::geometry::dist(a, b)
            }
            _ => panic!(),
        })
        .sum();
    assert!((c_len - 0.1).abs() < 1e-12);
    // monitors: the point goes to the piece containing it, the interface to every piece
    match &m.monitors[0].kind {
        MonitorKind::Point { p, block } => {
            assert!((7..=10).contains(block));
            assert_ne!(
                crate::geometry::polygon::point_in_polygon(&m.blocks[*block].vertices, *p, 1e-9),
                crate::geometry::polygon::Location::Outside
            );
        }
        k => panic!("{k:?}"),
    }
    assert_eq!(
        m.monitors[1].kind,
        MonitorKind::Interface {
            first: vec![1, 2, 3, 4, 5, 6],
            second: vec![0]
        }
    );
}

#[test]
fn a_cut_block_named_twice_means_the_pairs_of_its_pieces() {
    let text = format!(
        "{}\n[[interface]]\nblocks = [\"slider\", \"slider\"]\nfriction_angle = 20.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n",
        jointed_example()
    );
    let m = parse(&text).unwrap();
    let i = m.interface_for(1, 4).unwrap();
    assert_eq!(i.friction_angle, 20.0);
    assert_eq!(m.interface_for(7, 8).unwrap().friction_angle, 30.0);
    // an uncut block cannot pair with itself
    let e = err_plus("[[interface]]\nblocks = [\"base\", \"base\"]\nfriction_angle = 20.0\nnormal_penalty = 1.0\nshear_penalty = 1.0\n");
    assert!(e.contains("must differ"), "{e}");
}

#[test]
fn cracks_and_small_pieces_are_reported() {
    // a trace ending inside `upper` is a crack; min_block_area merges small pieces
    let text = jointed_example().replacen(
        "[[interface]]\njoint",
        "[[joint]]\nname = \"crack\"\npoints = [[1.0, 1.25], [1.6, 1.25]]\nblocks = [\"upper\"]\n[[interface]]\njoint",
        1,
    );
    let m = parse(&text).unwrap();
    assert!(!m.cracks.is_empty());
    let k = m.cracks.iter().find(|k| k.joint == 2).unwrap();
    assert!(m.blocks[k.block].name.starts_with("upper."));
    let x_end = k.points.iter().map(|p| p[0]).fold(f64::NAN, f64::max);
    assert_eq!(x_end, 1.6, "{:?}", k.points);
    let small = m
        .blocks
        .iter()
        .map(|b| crate::geometry::polygon::signed_area(&b.vertices))
        .fold(f64::INFINITY, f64::min);
    assert!(small < 0.01, "{small}");
    let merged =
        parse(&text.replacen("size = 0.05", "size = 0.05\nmin_block_area = 0.01", 1)).unwrap();
    assert!(!merged.merged.is_empty());
    assert_eq!(merged.min_block_area, Some(0.01));
    for b in &merged.blocks[1..] {
        assert!(
            crate::geometry::polygon::signed_area(&b.vertices) >= 0.01,
            "{}",
            b.name
        );
    }
    assert!(merged.blocks.len() < m.blocks.len());
    let total = |m: &Model| -> f64 {
        m.blocks
            .iter()
            .map(|b| crate::geometry::polygon::signed_area(&b.vertices))
            .sum()
    };
    assert!((total(&merged) - total(&m)).abs() < 1e-12);
}
