//! Every class of bad input makes `nmm check` fail cleanly: non-zero exit, exactly one
//! non-empty line on stderr naming the place (table, key, block), and no panic.

use std::path::Path;
use std::process::Command;

const EXAMPLE: &str = include_str!("data/example.toml");

/// Run `nmm check FILE` and return (success, stdout, stderr).
fn check(path: &Path) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_nmm"))
        .arg("check")
        .arg(path)
        .output()
        .expect("run nmm");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Write `text` as model.toml in a fresh tempdir, check it, and assert a clean
/// one-line failure containing every fragment of `expect`.
fn assert_rejected(case: &str, text: &str, expect: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    std::fs::write(&path, text).unwrap();
    assert_fails(case, &path, expect);
}

fn assert_fails(case: &str, path: &Path, expect: &[&str]) {
    let (ok, _, stderr) = check(path);
    assert!(!ok, "{case}: accepted");
    assert!(!stderr.contains("panicked"), "{case}: panic: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{case}: stderr is not one line: {stderr:?}");
    let line = lines[0];
    assert!(
        line.starts_with("error: ") && line.len() > "error: ".len(),
        "{case}: {line}"
    );
    for e in expect {
        assert!(line.contains(e), "{case}: {line:?} does not contain {e:?}");
    }
}

/// The example with the first `from` replaced by `to`.
fn mutate(from: &str, to: &str) -> String {
    assert!(EXAMPLE.contains(from), "{from:?} is not in the example");
    EXAMPLE.replacen(from, to, 1)
}

const SLIDER: &str = "vertices = [[0.0, 1.0], [0.0, 1.5], [1.0, 1.5], [1.0, 1.0]]";

#[test]
fn the_example_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    std::fs::write(&path, EXAMPLE).unwrap();
    let (ok, stdout, stderr) = check(&path);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("blocks: 3"), "{stdout}");
}

#[test]
fn toml_syntax_error() {
    assert_rejected(
        "syntax",
        &mutate("steps = 3000", "steps = = 3000"),
        &["model.toml", "TOML syntax error at line 4"],
    );
    assert_rejected(
        "unclosed",
        &mutate("[cover]", "[cover"),
        &["TOML syntax error at line"],
    );
    assert_rejected(
        "duplicate key",
        &mutate("steps = 3000", "steps = 3000\nsteps = 4"),
        &["TOML syntax error", "steps"],
    );
}

#[test]
fn unknown_names() {
    assert_rejected(
        "material",
        &mutate(
            "name = \"slider\"\nmaterial = \"limestone\"",
            "name = \"slider\"\nmaterial = \"granite\"",
        ),
        &["[[block]] \"slider\"", "key `material`", "\"granite\""],
    );
    assert_rejected(
        "load block",
        &mutate("block = \"slider\"", "block = \"slidr\""),
        &["[[load]] #1", "key `block`", "\"slidr\""],
    );
    assert_rejected(
        "constraint block",
        &mutate("block = \"upper\"", "block = \"uper\""),
        &["[[constraint]] #1", "key `block`", "\"uper\""],
    );
    assert_rejected(
        "interface block",
        &mutate(
            "blocks = [\"base\", \"slider\"]",
            "blocks = [\"bse\", \"slider\"]",
        ),
        &["[[interface]] #2", "key `blocks`", "\"bse\""],
    );
    assert_rejected(
        "monitor block",
        &mutate(
            "interface = [\"slider\", \"base\"]",
            "interface = [\"slider\", \"bas\"]",
        ),
        &["[[monitor]] \"joint\"", "key `interface`", "\"bas\""],
    );
}

#[test]
fn duplicate_names() {
    assert_rejected(
        "block",
        &mutate("name = \"upper\"", "name = \"slider\""),
        &["[[block]] \"slider\"", "key `name`", "duplicate"],
    );
    assert_rejected(
        "material",
        &format!("{EXAMPLE}\n[[material]]\nname = \"limestone\"\ndensity = 1.0\nyoung = 1.0\npoisson = 0.2\n"),
        &["[[material]] \"limestone\"", "key `name`", "duplicate"],
    );
    assert_rejected(
        "monitor",
        &mutate("name = \"joint\"", "name = \"crest\""),
        &["[[monitor]] \"crest\"", "key `name`", "duplicate"],
    );
    assert_rejected(
        "empty",
        &mutate("name = \"upper\"", "name = \"\""),
        &["[[block]] #3", "key `name`", "empty"],
    );
}

#[test]
fn bad_polygons() {
    assert_rejected(
        "self-intersecting",
        &mutate(
            SLIDER,
            "vertices = [[0.0, 1.0], [1.0, 1.5], [0.0, 1.5], [1.0, 1.0]]",
        ),
        &["[[block]] \"slider\": key `vertices`: polygon self-intersects (edges 1 and 3)"],
    );
    assert_rejected(
        "collinear",
        &mutate(SLIDER, "vertices = [[0.0, 1.0], [0.5, 1.25], [1.0, 1.5]]"),
        &["[[block]] \"slider\": key `vertices`: degenerate polygon"],
    );
    assert_rejected(
        "repeated vertex",
        &mutate(
            SLIDER,
            "vertices = [[0.0, 1.0], [0.0, 1.5], [0.0, 1.5], [1.0, 1.5], [1.0, 1.0]]",
        ),
        &["[[block]] \"slider\": key `vertices`: degenerate polygon: vertices 2 and 3 coincide"],
    );
    assert_rejected(
        "two vertices",
        &mutate(SLIDER, "vertices = [[0.0, 1.0], [0.0, 1.5]]"),
        &[
            "[[block]] \"slider\": key `vertices`",
            "at least 3 vertices",
        ],
    );
    assert_rejected(
        "overlap",
        &mutate(
            SLIDER,
            "vertices = [[0.0, 1.0], [0.0, 1.5], [1.5, 1.5], [1.5, 1.0]]",
        ),
        &["[[block]] \"upper\": key `vertices`: overlaps block \"slider\""],
    );
}

#[test]
fn values_out_of_range() {
    let cases: &[(&str, &str, &str, &[&str])] = &[
        (
            "density",
            "density = 2243.0",
            "density = 0.0",
            &["[[material]] \"limestone\"", "key `density`", "positive"],
        ),
        (
            "young",
            "young = 7.0e9",
            "young = -7.0e9",
            &["[[material]] \"limestone\"", "key `young`", "positive"],
        ),
        (
            "dt",
            "dt = 0.001",
            "dt = -0.001",
            &["[analysis]: key `dt`: must be positive, got -0.001"],
        ),
        (
            "steps",
            "steps = 3000",
            "steps = 0",
            &["[analysis]", "key `steps`", "positive"],
        ),
        (
            "cover size",
            "size = 0.05",
            "size = 0",
            &["[cover]", "key `size`", "positive"],
        ),
        (
            "cover order 2",
            "size = 0.05",
            "size = 0.05\norder = 2",
            &[
                "[cover]: key `order`: must be 0 (constant covers) or 1 (first-order covers), got 2",
                "line 11)",
            ],
        ),
        (
            "cover order negative",
            "size = 0.05",
            "size = 0.05\norder = -1",
            &["[cover]", "key `order`", "got -1"],
        ),
        (
            "cover order not an integer",
            "size = 0.05",
            "size = 0.05\norder = 1.5",
            &["[cover]", "key `order`"],
        ),
        (
            "poisson high",
            "poisson = 0.33",
            "poisson = 0.5",
            &["[[material]] \"limestone\"", "key `poisson`"],
        ),
        (
            "poisson low",
            "poisson = 0.33",
            "poisson = -1.5",
            &["[[material]] \"limestone\"", "key `poisson`"],
        ),
        (
            "friction angle",
            "friction_angle = 40.5",
            "friction_angle = 95",
            &["[[interface]] #2", "key `friction_angle`"],
        ),
    ];
    for (case, from, to, expect) in cases {
        assert_rejected(case, &mutate(from, to), expect);
    }
}

#[test]
fn bad_damping() {
    let place = "[[material]] \"limestone\": key `damping`";
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "negative alpha",
            "{ alpha = -1.0 }",
            &["`alpha` must be ≥ 0, got -1"],
        ),
        ("nan beta", "{ beta = nan }", &["`beta`", "NaN"]),
        ("not a table", "0.05", &["expected a table", "float 0.05"]),
        ("unknown key", "{ zeta = 0.05 }", &["unknown key `zeta`"]),
        ("empty", "{}", &["empty table"]),
        (
            "both forms",
            "{ alpha = 1.0, ratio = 0.05, frequencies = [1.0, 5.0] }",
            &["not both"],
        ),
        (
            "ratio alone",
            "{ ratio = 0.05 }",
            &["`frequencies = [f1, f2]` (Hz) is required"],
        ),
        (
            "frequencies alone",
            "{ frequencies = [1.0, 5.0] }",
            &["`ratio` is required"],
        ),
        (
            "ratio too large",
            "{ ratio = 1.5, frequencies = [1.0, 5.0] }",
            &["[0, 1], got 1.5"],
        ),
        (
            "zero frequency",
            "{ ratio = 0.05, frequencies = [0.0, 5.0] }",
            &["must be positive"],
        ),
        (
            "three frequencies",
            "{ ratio = 0.05, frequencies = [1.0, 2.0, 5.0] }",
            &["`frequencies`", "3 items"],
        ),
    ];
    for (case, value, expect) in cases {
        let text = mutate(
            "poisson = 0.33",
            &format!("poisson = 0.33\ndamping = {value}"),
        );
        let mut all = vec![place, "model.toml, line 17)"];
        all.extend_from_slice(expect);
        assert_rejected(case, &text, &all);
    }
}

#[test]
fn non_finite_numbers() {
    assert_rejected(
        "nan dt",
        &mutate("dt = 0.001", "dt = nan"),
        &["[analysis]", "key `dt`", "NaN"],
    );
    assert_rejected(
        "nan vertex",
        &mutate(
            SLIDER,
            "vertices = [[0.0, 1.0], [0.0, nan], [1.0, 1.5], [1.0, 1.0]]",
        ),
        &["[[block]] \"slider\"", "key `vertices`", "NaN"],
    );
    assert_rejected(
        "inf young",
        &mutate("young = 7.0e9", "young = inf"),
        &["[[material]] \"limestone\"", "key `young`", "infinite"],
    );
    assert_rejected(
        "-inf traction",
        &mutate("traction = [0.0, -1.0e6]", "traction = [0.0, -inf]"),
        &[
            "[[load]] #1 (block \"slider\")",
            "key `traction`",
            "infinite",
        ],
    );
    assert_rejected(
        "nan table",
        &mutate("[0.01, 0.05, 0.0]", "[0.01, nan, 0.0]"),
        &["[base_motion]", "key `table`", "NaN"],
    );
}

#[test]
fn segments_off_the_boundary() {
    assert_rejected(
        "load",
        &mutate("edge = [[0.0, 1.5], [1.0, 1.5]]", "edge = [[0.0, 1.25], [1.0, 1.25]]"),
        &["[[load]] #1 (block \"slider\"): key `edge`: segment [[0,1.25],[1,1.25]] is not on the boundary of block \"slider\""],
    );
    assert_rejected(
        "constraint",
        &mutate(
            "edge = [[2.0, 1.1], [2.0, 1.2]]",
            "edge = [[2.0, 1.1], [2.0, 1.6]]",
        ),
        &[
            "[[constraint]] #1 (block \"upper\")",
            "key `edge`",
            "not on the boundary of block \"upper\"",
        ],
    );
    assert_rejected(
        "point load outside",
        &mutate(
            "edge = [[0.0, 1.5], [1.0, 1.5]]\ntraction = [0.0, -1.0e6]",
            "point = [1.5, 1.2]\nforce = [0.0, -1.0]",
        ),
        &[
            "[[load]] #1 (block \"slider\")",
            "key `point`",
            "outside block \"slider\"",
        ],
    );
}

#[test]
fn missing_files() {
    let dir = tempfile::tempdir().unwrap();
    assert_fails(
        "missing model",
        &dir.path().join("nothing.toml"),
        &["nothing.toml", "cannot read the model file"],
    );
    assert_rejected(
        "missing record",
        &mutate(
            "table = [[0.0, 0.0, 0.0], [0.01, 0.05, 0.0]]",
            "file = \"quake.csv\"",
        ),
        &["[base_motion]", "key `file`", "quake.csv"],
    );
}

#[test]
fn unknown_keys() {
    assert_rejected(
        "top level",
        &format!("{EXAMPLE}\n[solver]\nkind = 1\n"),
        &["top level", "unknown key `solver`"],
    );
    assert_rejected(
        "analysis",
        &mutate("output_every = 10", "output_evry = 10"),
        &["[analysis]", "unknown key `output_evry`"],
    );
    assert_rejected(
        "block",
        &mutate("fixed = true", "fixed = true\ncolor = \"red\""),
        &["[[block]] \"base\"", "unknown key `color`"],
    );
    assert_rejected(
        "interface",
        &mutate("cohesion = 0.0", "cohesion = 0.0\ndilation = 0.0"),
        &["[[interface]] #2", "unknown key `dilation`"],
    );
    assert_rejected(
        "load",
        &mutate(
            "traction = [0.0, -1.0e6]",
            "traction = [0.0, -1.0e6]\nramp = 1",
        ),
        &["[[load]] #1 (block \"slider\")", "unknown key `ramp`"],
    );
    assert_rejected(
        "monitor",
        &mutate("point = [1.5, 1.2]", "point = [1.5, 1.2]\nevery = 2"),
        &["[[monitor]] \"crest\"", "unknown key `every`"],
    );
    assert_rejected(
        "base motion",
        &mutate("[base_motion]", "[base_motion]\nunits = \"g\""),
        &["[base_motion]", "unknown key `units`"],
    );
}

#[test]
fn wrong_types_and_shapes() {
    assert_rejected(
        "dt string",
        &mutate("dt = 0.001", "dt = \"fast\""),
        &["[analysis]", "key `dt`", "expected a number"],
    );
    assert_rejected(
        "single block table",
        &mutate("[[block]]\nname = \"upper\"", "[block]\nname = \"upper\""),
        &["TOML syntax error"],
    );
    assert_rejected(
        "missing analysis",
        &mutate("[analysis]", "[analysis_old]"),
        &["top level", "unknown key `analysis_old`"],
    );
    assert_rejected("pair uncovered", &mutate("[[interface]]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n", ""), &["[[interface]]", "\"base\" and \"upper\""]);
}

/// The example with a joint set cutting `slider` and `upper`, a fault across `slider`,
/// and an interface for the set's faces.
const JOINTS: &str = r#"
[[joint_set]]
name = "bedding"
angle = 35.0
spacing = 0.3
origin = [0.05, 1.02]
blocks = ["slider", "upper"]

[[joint]]
name = "fault"
points = [[0.2, 0.9], [0.8, 1.6]]
blocks = ["slider"]

[[interface]]
joint = "bedding"
friction_angle = 25.0
normal_penalty = 1.0e10
shear_penalty = 1.0e7
"#;

/// The jointed example with `from` replaced by `to` (which must occur in JOINTS).
fn jointed(from: &str, to: &str) -> String {
    assert!(JOINTS.contains(from), "{from:?} is not in JOINTS");
    format!("{EXAMPLE}{}", JOINTS.replacen(from, to, 1))
}

/// `model.toml, line N)` for the first line of `text` containing `needle`.
fn at_line(text: &str, needle: &str) -> String {
    let i = text
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not found"));
    format!("model.toml, line {})", text[..i].matches('\n').count() + 1)
}

#[test]
fn the_jointed_example_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    std::fs::write(&path, format!("{EXAMPLE}{JOINTS}")).unwrap();
    let (ok, stdout, stderr) = check(&path);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("blocks: 11 (1 fixed)"), "{stdout}");
    assert!(stdout.contains("block \"slider.6\""), "{stdout}");
}

#[test]
fn joint_errors() {
    let cases: [(&str, &str, &str, &[&str]); 12] = [
        (
            "points = [[0.2, 0.9], [0.8, 1.6]]",
            "points = [[0.2, 0.9]]",
            "points = [[0.2, 0.9]]",
            &[
                "[[joint]] \"fault\"",
                "key `points`",
                "at least 2 points, got 1",
            ],
        ),
        (
            "points = [[0.2, 0.9], [0.8, 1.6]]",
            "points = [[0.2, 0.9], [0.2, 0.9], [0.8, 1.6]]",
            "points = [[0.2, 0.9], [0.2",
            &[
                "[[joint]] \"fault\"",
                "key `points`",
                "segment 1 has zero length",
            ],
        ),
        (
            "spacing = 0.3",
            "spacing = 0.0",
            "spacing = 0.0",
            &[
                "[[joint_set]] \"bedding\"",
                "key `spacing`",
                "must be positive, got 0",
            ],
        ),
        (
            "spacing = 0.3",
            "spacing = -1.5",
            "spacing = -1.5",
            &["[[joint_set]] \"bedding\"", "key `spacing`", "got -1.5"],
        ),
        (
            "angle = 35.0",
            "angle = 180.0",
            "angle = 180.0",
            &[
                "[[joint_set]] \"bedding\"",
                "key `angle`",
                "[0, 180)",
                "got 180",
            ],
        ),
        (
            "angle = 35.0",
            "angle = -10.0",
            "angle = -10.0",
            &["[[joint_set]] \"bedding\"", "key `angle`", "got -10"],
        ),
        (
            "spacing = 0.3",
            "spacing = 0.00001",
            "spacing = 0.00001",
            &[
                "[[joint_set]] \"bedding\"",
                "key `spacing`",
                "more than `[cover] max_blocks` = 100000",
            ],
        ),
        (
            "joint = \"bedding\"",
            "joint = \"beding\"",
            "joint = \"beding\"",
            &[
                "[[interface]] #3 (joint \"beding\")",
                "key `joint`",
                "unknown joint \"beding\"",
            ],
        ),
        (
            "joint = \"bedding\"",
            "joint = \"bedding\"\nblocks = [\"slider\", \"upper\"]",
            "joint = \"bedding\"",
            &[
                "[[interface]] #3",
                "key `joint`",
                "either `blocks` or `joint`",
            ],
        ),
        (
            "blocks = [\"slider\"]",
            "blocks = [\"slidr\"]",
            "blocks = [\"slidr\"]",
            &[
                "[[joint]] \"fault\"",
                "key `blocks`",
                "unknown block \"slidr\"",
            ],
        ),
        (
            "name = \"fault\"",
            "name = \"bedding\"",
            "name = \"bedding\"\npoints",
            &[
                "[[joint]] \"bedding\"",
                "key `name`",
                "duplicate joint name",
            ],
        ),
        (
            "spacing = 0.3",
            "spacing = 0.3\ntrace_length = 0.5",
            "[[joint_set]]", // a missing key is reported at its table
            &["[[joint_set]] \"bedding\"", "key `bridge`", "missing"],
        ),
    ];
    for (from, to, needle, expect) in cases {
        let text = jointed(from, to);
        // the offending key is in the appended part
        let i = EXAMPLE.len() + text[EXAMPLE.len()..].find(needle).unwrap();
        let line = format!("model.toml, line {})", text[..i].matches('\n').count() + 1);
        let mut all: Vec<&str> = expect.to_vec();
        all.push(&line);
        assert_rejected(&format!("{from} -> {to}"), &text, &all);
    }
}

#[test]
fn cut_block_errors() {
    // a piece name that is already a block's name
    let text = format!("{EXAMPLE}{JOINTS}")
        .replacen("name = \"upper\"", "name = \"slider.2\"", 1)
        .replace(
            "blocks = [\"slider\", \"upper\"]",
            "blocks = [\"slider\", \"slider.2\"]",
        )
        .replace("block = \"upper\"", "block = \"slider.2\"");
    assert_rejected(
        "piece name clash",
        &text,
        &[
            "[[block]] \"slider\"",
            "key `name`",
            "\"slider.2\" is the name of [[block]] #3",
            &at_line(&text, "name = \"slider\""),
        ],
    );
    // a piece thinner than the mesh resolves
    let text = format!(
        "{EXAMPLE}{JOINTS}\n[[joint]]\nname = \"thin\"\npoints = [[-0.1, 1.4999999], [1.1, 1.4999999]]\nblocks = [\"slider\"]\n"
    );
    assert_rejected(
        "thin piece",
        &text,
        &[
            "[[block]] \"slider\"",
            "key `vertices`",
            "thinner than the mesh can resolve",
            "min_block_area",
            &at_line(&text, "vertices = [[0.0, 1.0], [0.0, 1.5]"),
        ],
    );
    // min_block_area and max_blocks
    assert_rejected(
        "min_block_area",
        &format!("{EXAMPLE}{JOINTS}").replacen(
            "size = 0.05",
            "size = 0.05\nmin_block_area = -1.0",
            1,
        ),
        &[
            "[cover]",
            "key `min_block_area`",
            "must be positive",
            "model.toml, line 11)",
        ],
    );
    assert_rejected(
        "max_blocks",
        &format!("{EXAMPLE}{JOINTS}").replacen("size = 0.05", "size = 0.05\nmax_blocks = 5", 1),
        &[
            "[[joint_set]] \"bedding\"",
            "key `spacing`",
            "more than `[cover] max_blocks` = 5",
        ],
    );
    // an interface pair that repeats one already covered through a cut block's name
    assert_rejected(
        "pair through pieces",
        &format!(
            "{EXAMPLE}{JOINTS}\n[[interface]]\nblocks = [\"slider.3\", \"base\"]\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n"
        ),
        &["[[interface]] #4 (blocks \"slider.3\", \"base\")", "key `blocks`", "already has an interface ([[interface]] #2)"],
    );
    // a monitor between a cut block and one of its own pieces
    assert_rejected(
        "monitor sides share a block",
        &format!("{EXAMPLE}{JOINTS}").replacen(
            "interface = [\"slider\", \"base\"]",
            "interface = [\"slider\", \"slider.1\"]",
            1,
        ),
        &["[[monitor]] \"joint\"", "key `interface`", "share a block"],
    );
    // the same joint twice in interfaces
    assert_rejected(
        "joint interface twice",
        &format!(
            "{EXAMPLE}{JOINTS}\n[[interface]]\njoint = \"bedding\"\nfriction_angle = 30.0\nnormal_penalty = 1.0e10\nshear_penalty = 1.0e7\n"
        ),
        &["[[interface]] #4 (joint \"bedding\")", "key `joint`", "already has an interface ([[interface]] #3)"],
    );
}

/// Bonded interfaces (`tensile_strength`, `residual_friction_angle`): a negative tensile
/// strength and a residual friction angle above the peak one are refused at their line;
/// `friction` names only the laws of `[analysis]`.
#[test]
fn bonded_interface_values() {
    let cases: &[(&str, &str, &str, &[&str])] = &[
        (
            "negative tensile strength",
            "cohesion = 0.0\n",
            "cohesion = 0.0\ntensile_strength = -1.0e4\n",
            &[
                "[[interface]] #2 (blocks \"base\", \"slider\"): key `tensile_strength`: must be zero or positive (Pa), got -10000",
                "model.toml, line 43)",
            ],
        ),
        (
            "residual friction above the peak",
            "cohesion = 0.0\n",
            "cohesion = 0.0\ntensile_strength = 1.0e4\nresidual_friction_angle = 45.0\n",
            &[
                "[[interface]] #2 (blocks \"base\", \"slider\"): key `residual_friction_angle`: must not exceed friction_angle = 40.5",
                "got 45",
                "model.toml, line 44)",
            ],
        ),
        (
            "residual friction alone, above the peak",
            "friction_angle = 30.0\n",
            "friction_angle = 30.0\nresidual_friction_angle = 31\n",
            &[
                "[[interface]] #1 (default): key `residual_friction_angle`: must not exceed friction_angle = 30",
                "model.toml, line 36)",
            ],
        ),
        (
            "negative residual friction",
            "cohesion = 0.0\n",
            "cohesion = 0.0\nresidual_friction_angle = -5\n",
            &["key `residual_friction_angle`: must be in [0, 90) degrees, got -5"],
        ),
        (
            "tensile strength not a number",
            "cohesion = 0.0\n",
            "cohesion = 0.0\ntensile_strength = \"strong\"\n",
            &["[[interface]] #2", "key `tensile_strength`", "expected a number"],
        ),
        (
            "friction names an interface's law",
            "friction = \"return-mapping\"",
            "friction = \"bonded\"",
            &[
                "[analysis]: key `friction`: expected one of \"return-mapping\", \"conventional\", got \"bonded\"",
            ],
        ),
    ];
    for (case, from, to, expect) in cases {
        assert_rejected(case, &mutate(from, to), expect);
    }
    // valid bonded keys are accepted
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    std::fs::write(
        &path,
        mutate(
            "cohesion = 0.0\n",
            "cohesion = 1.0e5\ntensile_strength = 5.0e4\nresidual_friction_angle = 30.0\n",
        ),
    )
    .unwrap();
    let (ok, out, err) = check(&path);
    assert!(ok, "{err}");
    assert!(
        out.contains(
            "interface #2: law \"bonded\" (tensile_strength = 50000, residual_friction_angle = 30)"
        ),
        "{out}"
    );
}

/// A bolt from the slider to the base (accepted), and its bad-input lines.
const BOLT: &str = "\n[[bolt]]\nname = \"b1\"\npoints = [[0.5, 1.25], [0.5, 0.5]]\nstiffness = 1.0e8\ncapacity = 2.0e5\n";

/// The example with a bolt whose `from` is replaced by `to` (which must occur in BOLT),
/// and `extra` after it.
fn bolted(from: &str, to: &str, extra: &str) -> String {
    assert!(BOLT.contains(from), "{from:?} is not in BOLT");
    format!("{EXAMPLE}{}{extra}", BOLT.replacen(from, to, 1))
}

#[test]
fn the_bolted_example_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    let stage = "\n[[stage]]\nname = \"support\"\n";
    let text = bolted(
        "capacity = 2.0e5",
        "capacity = 2.0e5\npretension = 2.0e5\nstage = \"support\"",
        &format!("{stage}\n[[monitor]]\nname = \"b\"\nbolt = \"b1\"\n"),
    );
    std::fs::write(&path, text).unwrap();
    let (ok, stdout, stderr) = check(&path);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("blocks: 3"), "{stdout}");
    assert!(
        stdout.contains("bolt \"b1\": [0.5, 1.25] in block \"slider\" to [0.5, 0.5] in block \"base\", stiffness 100000000 N/m, capacity 200000 N, pretension 200000 N, installed at the start of stage \"support\""),
        "{stdout}"
    );
}

/// Every bad `[[bolt]]` (and a monitor of a bolt that does not exist): one line naming the
/// bolt, the key, the reason and the file and line.
#[test]
fn bolt_errors() {
    let stages = "\n[[stage]]\nname = \"settle\"\n[[stage]]\nname = \"shake\"\n";
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        (
            bolted("capacity = 2.0e5", "capacity = 2.0e5\nstage = \"support\"", ""),
            "stage = \"support\"",
            vec!["[[bolt]] \"b1\"", "key `stage`", "unknown stage \"support\" (the model has no [[stage]])"],
        ),
        (
            bolted("capacity = 2.0e5", "capacity = 2.0e5\nstage = \"support\"", stages),
            "stage = \"support\"",
            vec!["[[bolt]] \"b1\"", "key `stage`", "unknown stage \"support\" (stages: \"settle\", \"shake\")"],
        ),
        (
            bolted("[0.5, 0.5]]", "[3.0, 0.5]]", ""),
            "points = ",
            vec!["[[bolt]] \"b1\"", "key `points`", "point 2 [3,0.5] is not inside any block"],
        ),
        (
            bolted("[[0.5, 1.25]", "[[-0.5, 1.25]", ""),
            "points = ",
            vec!["[[bolt]] \"b1\"", "key `points`", "point 1 [-0.5,1.25] is not inside any block"],
        ),
        (
            format!("{EXAMPLE}{BOLT}{BOLT}"),
            "name = \"b1\"\npoints = [[0.5, 1.25], [0.5, 0.5]]\nstiffness = 1.0e8\ncapacity = 2.0e5\n\n[[bolt]]\nname",
            vec!["[[bolt]] \"b1\"", "key `name`", "duplicate bolt name (also [[bolt]] #1)"],
        ),
        (
            bolted("stiffness = 1.0e8", "stiffness = 0.0", ""),
            "stiffness = 0.0",
            vec!["[[bolt]] \"b1\"", "key `stiffness`", "must be positive, got 0"],
        ),
        (
            bolted("stiffness = 1.0e8", "stiffness = -1.0e8", ""),
            "stiffness = -1.0e8",
            vec!["[[bolt]] \"b1\"", "key `stiffness`", "must be positive, got -100000000"],
        ),
        (
            bolted("capacity = 2.0e5", "capacity = 0", ""),
            "capacity = 0",
            vec!["[[bolt]] \"b1\"", "key `capacity`", "must be positive, got 0"],
        ),
        (
            bolted("capacity = 2.0e5", "capacity = -5.0", ""),
            "capacity = -5.0",
            vec!["[[bolt]] \"b1\"", "key `capacity`", "must be positive, got -5"],
        ),
        (
            bolted("capacity = 2.0e5", "capacity = 2.0e5\npretension = 3.0e5", ""),
            "pretension = 3.0e5",
            vec!["[[bolt]] \"b1\"", "key `pretension`", "300000 is above the capacity 200000"],
        ),
        (
            bolted("capacity = 2.0e5", "capacity = 2.0e5\npretension = -1.0", ""),
            "pretension = -1.0",
            vec!["[[bolt]] \"b1\"", "key `pretension`", "must be zero or positive"],
        ),
        (
            bolted("[[0.5, 1.25], [0.5, 0.5]]", "[[0.5, 1.25]]", ""),
            "points = ",
            vec!["[[bolt]] \"b1\"", "key `points`", "expected its two anchors [[x1, y1], [x2, y2]], got 1 items"],
        ),
        (
            bolted("[0.5, 0.5]]", "[0.5, 1.25]]", ""),
            "points = ",
            vec!["[[bolt]] \"b1\"", "key `points`", "the two anchors coincide at [0.5,1.25]"],
        ),
        (
            bolted("stiffness = 1.0e8", "stiffness = \"stiff\"", ""),
            "stiffness = \"stiff\"",
            vec!["[[bolt]] \"b1\"", "key `stiffness`", "expected a number, got string \"stiff\""],
        ),
        (
            bolted("capacity = 2.0e5", "capacity = 2.0e5\nyield = 1.0", ""),
            "yield = 1.0",
            vec!["[[bolt]] \"b1\"", "unknown key `yield`"],
        ),
        (
            bolted("", "", "\n[[monitor]]\nname = \"b\"\nbolt = \"b2\"\n"),
            "bolt = \"b2\"",
            vec!["[[monitor]] \"b\"", "key `bolt`", "unknown bolt \"b2\""],
        ),
        (
            bolted("", "", "\n[[monitor]]\nname = \"b\"\nbolt = \"b1\"\npoint = [0.5, 0.5]\n"),
            "bolt = \"b1\"",
            vec!["[[monitor]] \"b\"", "key `bolt`", "not several"],
        ),
    ];
    for (text, line_of, expect) in cases {
        let mut expect = expect.clone();
        let at = if line_of == "name = \"b1\"\npoints = [[0.5, 1.25], [0.5, 0.5]]\nstiffness = 1.0e8\ncapacity = 2.0e5\n\n[[bolt]]\nname" {
            // the second table's name
            let first = text.find(line_of).unwrap();
            let second = first + line_of.len() - "name".len();
            format!("model.toml, line {})", text[..second].matches('\n').count() + 1)
        } else {
            at_line(&text, line_of)
        };
        expect.push(&at);
        assert_rejected(expect[2], &text, &expect);
    }
}

/// The example in two stages, `settle` and `dig`, `dig` excavating `upper` (its
/// constraint goes with it); the monitor `crest` moved from `upper` to the base (at
/// [1, 0.8], outside CAVE).
const DIG: &str =
    "\n[[stage]]\nname = \"settle\"\n\n[[stage]]\nname = \"dig\"\nexcavate = [\"upper\"]\n";

/// The excavated example with `from` replaced by `to` (which must occur in DIG), and
/// `extra` after it; `base` replaces the example.
fn dug_from(base: &str, from: &str, to: &str, extra: &str) -> String {
    assert!(DIG.contains(from), "{from:?} is not in DIG");
    let base = base.replacen("point = [1.5, 1.2]", "point = [1.0, 0.8]", 1);
    format!("{base}{}{extra}", DIG.replacen(from, to, 1))
}

fn dug(from: &str, to: &str, extra: &str) -> String {
    dug_from(EXAMPLE, from, to, extra)
}

/// `model.toml, line N)` for the last line of `text` containing `needle`.
fn at_last_line(text: &str, needle: &str) -> String {
    let i = text
        .rfind(needle)
        .unwrap_or_else(|| panic!("{needle:?} not found"));
    format!("model.toml, line {})", text[..i].matches('\n').count() + 1)
}

/// A closed `[[joint]]` loop "cave" in the base (which it cuts: `blocks`), cutting out
/// its region.
const CAVE: &str = "\n[[joint]]\nname = \"cave\"\npoints = [[1.3, 0.2], [1.8, 0.2], [1.8, 0.6], [1.3, 0.6], [1.3, 0.2]]\nblocks = [\"base\"]\n";

#[test]
fn the_excavated_example_is_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("model.toml");
    for (case, text, lines) in [
        ("a block", dug("", "", ""), &["blocks: 3 (1 fixed)"][..]),
        (
            "pieces and a joint loop",
            dug_from(
                &format!("{EXAMPLE}{JOINTS}{CAVE}"),
                "[\"upper\"]",
                "[\"upper.1\", \"slider.2\", \"cave\"]",
                "",
            )
            .replacen("interface = [\"slider\", \"base\"]", "interface = [\"slider.1\", \"base.2\"]", 1),
            &["blocks: 12 (2 fixed)"][..],
        ),
        (
            "a hole, its plug and in-situ stress",
            dug(
                "[\"upper\"]",
                "[\"plug\"]",
                "\n[initial_stress]\nstress = [-1.0e6, -2.0e6, 0.0]\ngradient = [1.0e4, 2.0e4, 0.0]\ny_ref = 1.5\n\
                 \n[[block]]\nname = \"plug\"\nmaterial = \"limestone\"\nvertices = [[1.3, 0.2], [1.8, 0.2], [1.8, 0.6], [1.3, 0.6]]\n",
            )
            .replacen(
                "fixed = true",
                "fixed = true\nholes = [[[1.3, 0.2], [1.3, 0.6], [1.8, 0.6], [1.8, 0.2]]]",
                1,
            ),
            &[
                "blocks: 4 (1 fixed)",
                // nmm check says what the model holds: the in-situ stress, the hole, what a
                // stage excavates
                "initial stress: [-1000000.0, -2000000.0, 0.0] Pa at y = 1.5 m, gradient [10000.0, 20000.0, 0.0] Pa/m",
                ", 1 hole, fixed",
                ", excavates \"plug\"",
            ][..],
        ),
    ] {
        std::fs::write(&path, &text).unwrap();
        let (ok, stdout, stderr) = check(&path);
        assert!(ok, "{case}: {stderr}");
        for l in lines {
            assert!(stdout.contains(l), "{case}: {l:?} in {stdout}");
        }
    }
}

/// Every bad `excavate` (and a monitor or a bolt anchor on an excavated block): one line
/// naming the stage (or the monitor, the bolt), the key, the reason and the file and line.
#[test]
fn excavation_errors() {
    let no_joint_monitor = |t: String| {
        t.replacen(
            "\n[[monitor]]\nname = \"joint\"\ninterface = [\"slider\", \"base\"]\n",
            "\n",
            1,
        )
    };
    let two_stages = dug(
        "name = \"settle\"",
        "name = \"settle\"\nexcavate = [\"upper\"]",
        "",
    );
    let block_monitor = dug(
        "",
        "",
        "\n[[monitor]]\nname = \"heap\"\nblock = \"upper\"\n",
    );
    let cases: Vec<(String, String, Vec<&str>)> = vec![
        (
            dug("[\"upper\"]", "[\"upper\", \"slider\", \"upper\"]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: block \"upper\" is excavated twice (also in this list)"],
        ),
        (
            two_stages.clone(),
            at_last_line(&two_stages, "excavate = "),
            vec!["[[stage]] \"dig\": key `excavate`: block \"upper\" is excavated twice (also by [[stage]] \"settle\")"],
        ),
        (
            dug_from(&format!("{EXAMPLE}{JOINTS}"), "[\"upper\"]", "[\"upper.2\", \"upper\"]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: \"upper\" names a block excavated twice: \"upper.2\" (also in this list) means it too"],
        ),
        (
            dug_from(&format!("{EXAMPLE}{CAVE}"), "[\"upper\"]", "[\"cave\", \"base.1\"]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\"", "key `excavate`", "\"base.1\" names a block excavated twice: \"cave\" (also in this list) means it too"],
        ),
        (
            dug("[\"upper\"]", "[\"uper\"]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: unknown block \"uper\" (nor a closed [[joint]] loop of that name)"],
        ),
        (
            dug_from(&format!("{EXAMPLE}{JOINTS}"), "[\"upper\"]", "[\"fault\"]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: no block is named \"fault\", and [[joint]] \"fault\" is not a closed loop"],
        ),
        (
            dug_from(&format!("{EXAMPLE}{}", CAVE.replace("blocks = [\"base\"]\n", "")), "[\"upper\"]", "[\"cave\"]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: the closed joint loop \"cave\" encloses no block", "by default every block that is not fixed"],
        ),
        (
            dug("[\"upper\"]", "\"upper\"", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: expected an array, got string \"upper\""],
        ),
        (
            dug("[\"upper\"]", "[1]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: expected a string, got integer 1"],
        ),
        (
            dug("[\"upper\"]", "[[\"upper\"]]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: expected a string, got an array of 1 items"],
        ),
        (
            dug("[\"upper\"]", "{ block = \"upper\" }", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: expected an array, got a table"],
        ),
        (
            dug("[\"upper\"]", "[]", ""),
            "excavate = ".into(),
            vec!["[[stage]] \"dig\": key `excavate`: must name at least one block"],
        ),
        (
            format!("{}{DIG}", EXAMPLE.replacen("output_every = 10", "output_every = 10\nexcavate = [\"upper\"]", 1)),
            "excavate = ".into(),
            vec!["[analysis]: unknown key `excavate`"],
        ),
        (
            format!("{EXAMPLE}{DIG}"),
            "point = [1.5, 1.2]".into(),
            vec!["[[monitor]] \"crest\": key `point`: it is on a block that [[stage]] \"dig\" excavates (a monitor on an excavated block is not allowed"],
        ),
        (
            dug("[\"upper\"]", "[\"slider\"]", ""),
            "interface = [\"slider\", \"base\"]".into(),
            vec!["[[monitor]] \"joint\": key `interface`: it is on a block that [[stage]] \"dig\" excavates"],
        ),
        (
            block_monitor.clone(),
            at_last_line(&block_monitor, "block = \"upper\""),
            vec!["[[monitor]] \"heap\": key `block`: it is on a block that [[stage]] \"dig\" excavates"],
        ),
        (
            no_joint_monitor(dug("[\"upper\"]", "[\"slider\"]", BOLT)),
            "points = [[0.5, 1.25]".into(),
            vec!["[[bolt]] \"b1\": key `points`: anchor 1 is in a block that [[stage]] \"dig\" excavates (anchor bolts in the rock that stays)"],
        ),
        (
            // `base` means its pieces, the loop's among them
            dug_from(&format!("{EXAMPLE}{CAVE}"), "[\"upper\"]", "[\"cave\"]", ""),
            "interface = [\"slider\", \"base\"]".into(),
            vec!["[[monitor]] \"joint\": key `interface`: it is on a block that [[stage]] \"dig\" excavates"],
        ),
        (
            no_joint_monitor(dug_from(
                &format!("{EXAMPLE}{CAVE}"),
                "[\"upper\"]",
                "[\"cave\"]",
                &BOLT.replace("[[0.5, 1.25], [0.5, 0.5]]", "[[1.5, 1.25], [1.5, 0.4]]"),
            )),
            "points = [[1.5, 1.25]".into(),
            vec!["[[bolt]] \"b1\": key `points`: anchor 2 is in a block that [[stage]] \"dig\" excavates"],
        ),
    ];
    for (text, line_of, expect) in cases {
        let mut expect = expect.clone();
        let at = if line_of.starts_with("model.toml") {
            line_of
        } else {
            at_line(&text, &line_of)
        };
        expect.push(&at);
        assert_rejected(expect[0], &text, &expect);
    }
}

/// Every bad `[initial_stress]`: one line naming the table, the key, the reason and the
/// file and line.
#[test]
fn initial_stress_errors() {
    const IS: &str = "\n[initial_stress]\nstress = [-1.0e6, -2.0e6, 0.0]\ngradient = [0.0, 2.0e4, 0.0]\ny_ref = 1.5\n";
    let with = |from: &str, to: &str| {
        assert!(IS.contains(from), "{from:?} is not in IS");
        format!("{EXAMPLE}{}", IS.replacen(from, to, 1))
    };
    let cases: Vec<(String, &str, Vec<&str>)> = vec![
        (
            with("[-1.0e6, -2.0e6, 0.0]", "[-1.0e6, -2.0e6]"),
            "stress = ",
            vec!["[initial_stress]: key `stress`: expected three numbers [σxx, σyy, τxy], got 2 items"],
        ),
        (
            with("[-1.0e6, -2.0e6, 0.0]", "[-1.0e6, -2.0e6, 0.0, 0.0]"),
            "stress = ",
            vec!["[initial_stress]: key `stress`: expected three numbers [σxx, σyy, τxy], got 4 items"],
        ),
        (
            with("[0.0, 2.0e4, 0.0]", "[2.0e4]"),
            "gradient = ",
            vec!["[initial_stress]: key `gradient`: expected three numbers [σxx, σyy, τxy], got 1 items"],
        ),
        (
            with("[0.0, 2.0e4, 0.0]", "[0.0, 2.0e4, 0.0, 0.0]"),
            "gradient = ",
            vec!["[initial_stress]: key `gradient`: expected three numbers [σxx, σyy, τxy], got 4 items"],
        ),
        (
            with("-2.0e6", "\"deep\""),
            "stress = ",
            vec!["[initial_stress]: key `stress`: expected a number, got string \"deep\""],
        ),
        (
            with("2.0e4", "nan"),
            "gradient = ",
            vec!["[initial_stress]: key `gradient`: NaN is not allowed"],
        ),
        (
            with("-1.0e6", "-inf"),
            "stress = ",
            vec!["[initial_stress]: key `stress`: infinite values are not allowed, got -inf"],
        ),
        (
            with("[-1.0e6, -2.0e6, 0.0]", "-2.0e6"),
            "stress = ",
            vec!["[initial_stress]: key `stress`: expected an array, got float -2000000"],
        ),
        (
            with("y_ref = 1.5", "y_ref = \"top\""),
            "y_ref = ",
            vec!["[initial_stress]: key `y_ref`: expected a number, got string \"top\""],
        ),
        (
            with("y_ref = 1.5", "y_ref = 1.5\nk0 = 0.5"),
            "k0 = ",
            vec!["[initial_stress]: unknown key `k0` (allowed: stress, gradient, y_ref)"],
        ),
        (
            with("stress = [-1.0e6, -2.0e6, 0.0]\n", ""),
            "[initial_stress]",
            vec!["[initial_stress]: key `stress`: missing (required)"],
        ),
        (
            with("[initial_stress]", "[[initial_stress]]"),
            "[[initial_stress]]",
            vec!["[initial_stress]: must be a single table (write [initial_stress], not [[initial_stress]])"],
        ),
        (
            format!("initial_stress = -1.0e6\n{EXAMPLE}"),
            "initial_stress = ",
            vec!["[initial_stress]: must be a table, got float -1000000"],
        ),
    ];
    for (text, line_of, expect) in cases {
        let mut expect = expect.clone();
        let at = at_line(&text, line_of);
        expect.push(&at);
        assert_rejected(expect[0], &text, &expect);
    }
}

/// Every bad `[[block]] holes`: one line naming the block, the key, the hole, the reason
/// and the file and line (that of `holes`).
#[test]
fn hole_errors() {
    let place = "[[block]] \"base\": key `holes`: ";
    let cases: &[(&str, &str)] = &[
        (
            "[[[2.2, 0.2], [2.6, 0.2], [2.6, 0.6], [2.2, 0.6]]]",
            "hole 1 is not strictly inside the block's polygon (a hole may not touch or cross the block's boundary)",
        ),
        (
            "[[[1.8, 0.2], [2.6, 0.2], [2.6, 0.6], [1.8, 0.6]]]",
            "hole 1 is not strictly inside the block's polygon",
        ),
        (
            "[[[0.0, 0.2], [0.6, 0.2], [0.6, 0.6], [0.0, 0.6]]]",
            "hole 1 is not strictly inside the block's polygon",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6], [0.2, 0.6]], [[-0.5, -0.5], [2.5, -0.5], [2.5, 1.5], [-0.5, 1.5]]]",
            "hole 2 is not strictly inside the block's polygon",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6], [0.2, 0.6]], [[0.5, 0.3], [0.9, 0.3], [0.9, 0.7], [0.5, 0.7]]]",
            "holes 1 and 2 overlap or touch",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6], [0.2, 0.6]], [[0.3, 0.3], [0.4, 0.3], [0.4, 0.4], [0.3, 0.4]]]",
            "holes 1 and 2 overlap or touch",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6], [0.2, 0.6]], [[0.6, 0.3], [0.9, 0.3], [0.9, 0.4], [0.6, 0.4]]]",
            "holes 1 and 2 overlap or touch",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6], [0.2, 0.6]], [[0.2, 0.2], [0.4, 0.4], [0.6, 0.6]]]",
            "hole 2: degenerate polygon: all vertices are collinear",
        ),
        (
            "[[[0.2, 0.2], [0.2, 0.6], [0.2, 0.6], [0.6, 0.2]]]",
            "hole 1: degenerate polygon: vertices 2 and 3 coincide",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.4, 0.2], [0.4, 0.5]]]",
            "hole 1: degenerate polygon: the boundary folds back on itself at vertex 2",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.6], [0.2, 0.6], [0.6, 0.2]]]",
            "hole 1: polygon self-intersects (edges 1 and 3)",
        ),
        (
            "[[[0.2, 0.2], [0.2, 0.6]]]",
            "hole 1: a polygon needs at least 3 vertices, got 2",
        ),
        ("[[]]", "hole 1: a polygon needs at least 3 vertices, got 0"),
        (
            "5",
            "expected a list of polygons [[[x, y], …], …], got integer 5",
        ),
        (
            "[[0.2, 0.2], [0.6, 0.2], [0.6, 0.6]]",
            "hole 1: point 1: expected a pair [x, y], got float 0.2",
        ),
        ("[\"tunnel\"]", "hole 1: expected an array, got string \"tunnel\""),
        (
            "[[[0.2, 0.2], [0.6, nan], [0.6, 0.6]]]",
            "hole 1: point 2: NaN is not allowed",
        ),
        (
            "[[[0.2, 0.2], [0.6, 0.2], [0.6, 2.0e12]]]",
            "hole 1: point 3: coordinate out of range",
        ),
    ];
    for (holes, msg) in cases {
        let text = mutate("fixed = true", &format!("fixed = true\nholes = {holes}"));
        let at = at_line(&text, "holes = ");
        let first = format!("{place}{msg}");
        assert_rejected(holes, &text, &[&first, &at]);
    }
    // a block that crosses the hole's boundary overlaps the block with the hole
    let text = mutate(
        "fixed = true",
        "fixed = true\nholes = [[[1.3, 0.2], [1.8, 0.2], [1.8, 0.6], [1.3, 0.6]]]",
    ) + "\n[[block]]\nname = \"plug\"\nmaterial = \"limestone\"\nvertices = [[1.3, 0.2], [1.9, 0.2], [1.9, 0.6], [1.3, 0.6]]\n";
    assert_rejected(
        "plug across the hole",
        &text,
        &[
            "[[block]] \"plug\": key `vertices`: overlaps block \"base\" (blocks may touch but not overlap)",
            &at_line(&text, "vertices = [[1.3, 0.2]"),
        ],
    );
}
