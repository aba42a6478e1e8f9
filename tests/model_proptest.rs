//! Robustness of the model parser: mutated versions of a valid model (lines
//! deleted, duplicated, replaced, swapped; characters flipped; numbers changed
//! to 0, -1, nan, inf, 1e308 …; text truncated) must never make
//! `parse_model` panic. Errors must be one non-empty line; accepted models
//! must satisfy the invariants of the validated types.

use nmm::geometry::polygon::{is_ccw, polygons_overlap};
use nmm::model::{parse_model, ConstraintGeometry, InterfaceScope, LoadKind, Model, MonitorKind};
use proptest::prelude::*;
use proptest::sample::Index;
use std::path::Path;

#[path = "support/proptest_cases.rs"]
mod proptest_cases;
use proptest_cases::cases;

const EXAMPLE: &str = include_str!("data/example.toml");

/// Tables appended to the example for the jointed variant: a set cutting two blocks, a
/// fault, a crack ending inside a block, and an interface for the set.
const JOINTS: &str = r#"
[[joint_set]]
name = "bedding"
angle = 35.0
spacing = 0.3
origin = [0.05, 1.02]
blocks = ["slider", "upper"]
trace_length = 0.9
bridge = 0.2

[[joint]]
name = "fault"
points = [[0.2, 0.9], [0.8, 1.6]]
blocks = ["slider"]

[[joint]]
name = "crack"
points = [[1.3, 1.25], [1.7, 1.3]]

[[interface]]
joint = "bedding"
friction_angle = 25.0
normal_penalty = 1.0e10
shear_penalty = 1.0e7
"#;

fn jointed() -> String {
    format!("{EXAMPLE}{JOINTS}")
}

const NUMBERS: &[&str] = &[
    "0",
    "-1",
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-308",
    "0.5",
    "3",
    "99999999999999999999",
    "1.0e12",
    "\"x\"",
];
const CHARS: &[char] = &[
    '[', ']', '"', '=', ',', '.', '-', '#', '\n', ' ', 'x', '0', '{', '\'',
];

#[derive(Debug, Clone)]
enum Mutation {
    DeleteLine(Index),
    DuplicateLine(Index),
    ReplaceLine(Index, Index),
    SwapLines(Index, Index),
    FlipChar(Index, usize),
    ChangeNumber(Index, usize),
    Truncate(Index),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        2 => any::<Index>().prop_map(Mutation::DeleteLine),
        2 => any::<Index>().prop_map(Mutation::DuplicateLine),
        2 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::ReplaceLine(a, b)),
        2 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        2 => (any::<Index>(), 0..CHARS.len()).prop_map(|(a, c)| Mutation::FlipChar(a, c)),
        4 => (any::<Index>(), 0..NUMBERS.len()).prop_map(|(a, n)| Mutation::ChangeNumber(a, n)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
    ]
}

/// Byte ranges of the numeric literals in `text`.
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = (b[i].is_ascii_digit() || b[i] == b'-')
            && (i == 0
                || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.'));
        if starts {
            let mut j = i + 1;
            while j < b.len()
                && (b[j].is_ascii_digit() || matches!(b[j], b'.' | b'e' | b'E' | b'+' | b'-'))
            {
                j += 1;
            }
            if b[i..j].iter().any(u8::is_ascii_digit) {
                spans.push((i, j));
            }
            i = j;
        } else {
            i += 1;
        }
    }
    spans
}

fn apply(text: &str, m: &Mutation) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let n = lines.len();
    // Earlier mutations (a truncation, deletions) may have emptied the text:
    // then there is nothing to index and the mutation is a no-op.
    let line_mutation = !matches!(
        m,
        Mutation::FlipChar(..) | Mutation::ChangeNumber(..) | Mutation::Truncate(_)
    );
    if (line_mutation && n == 0) || (matches!(m, Mutation::FlipChar(..)) && text.is_empty()) {
        return text.to_string();
    }
    match m {
        Mutation::DeleteLine(i) => {
            lines.remove(i.index(n));
        }
        Mutation::DuplicateLine(i) => {
            let k = i.index(n);
            lines.insert(k, lines[k].clone());
        }
        Mutation::ReplaceLine(i, j) => {
            let l = lines[j.index(n)].clone();
            lines[i.index(n)] = l;
        }
        Mutation::SwapLines(i, j) => lines.swap(i.index(n), j.index(n)),
        Mutation::FlipChar(i, c) => {
            let chars: Vec<char> = text.chars().collect();
            let k = i.index(chars.len());
            let mut out = chars;
            out[k] = CHARS[*c];
            return out.into_iter().collect();
        }
        Mutation::ChangeNumber(i, v) => {
            let spans = number_spans(text);
            if spans.is_empty() {
                return text.to_string();
            }
            let (a, b) = spans[i.index(spans.len())];
            return format!("{}{}{}", &text[..a], NUMBERS[*v], &text[b..]);
        }
        Mutation::Truncate(i) => {
            let chars: Vec<char> = text.chars().collect();
            return chars[..i.index(chars.len() + 1)].iter().collect();
        }
    }
    lines.join("\n")
}

/// The invariants promised by the validated model.
fn check_invariants(m: &Model) {
    let nb = m.blocks.len();
    assert!(nb >= 1);
    assert!(m.analysis.dt > 0.0 && m.analysis.steps > 0 && m.cover_size > 0.0);
    for b in &m.blocks {
        assert!(b.material < m.materials.len());
        assert_eq!(b.edge_joint.len(), b.vertices.len());
        assert!(b.edge_joint.iter().flatten().all(|&j| j < m.joints.len()));
        assert!(b.vertices.len() >= 3 && is_ccw(&b.vertices), "{b:?}");
        assert!(b.vertices.iter().flatten().all(|x| x.is_finite()));
    }
    for (i, a) in m.blocks.iter().enumerate() {
        for b in &m.blocks[i + 1..] {
            assert!(
                !polygons_overlap(&a.vertices, &b.vertices, 1e-6),
                "{} overlaps {}",
                a.name,
                b.name
            );
        }
    }
    for mat in &m.materials {
        assert!(mat.density > 0.0 && mat.young > 0.0 && mat.poisson > -1.0 && mat.poisson < 0.5);
    }
    for i in &m.interfaces {
        match &i.scope {
            InterfaceScope::Blocks(a, b) => {
                assert!(!a.is_empty() && !b.is_empty());
                assert!(a.iter().chain(b).all(|&x| x < nb));
                assert!(a == b || a.iter().all(|x| !b.contains(x)));
            }
            InterfaceScope::Joint(j) => assert!(*j < m.joints.len()),
            InterfaceScope::Default => {}
        }
        assert!(
            (0.0..90.0).contains(&i.friction_angle)
                && i.normal_penalty > 0.0
                && i.shear_penalty > 0.0
        );
    }
    for l in &m.loads {
        assert!(l.block < nb);
        match l.kind {
            LoadKind::Edge { traction, .. } => assert!(traction.iter().all(|x| x.is_finite())),
            LoadKind::Point { force, .. } => assert!(force.iter().all(|x| x.is_finite())),
        }
    }
    for c in &m.constraints {
        assert!(c.block < nb && (c.ux.is_some() || c.uy.is_some()));
        if let ConstraintGeometry::Edge { a, b } = c.geometry {
            assert!(a != b);
        }
    }
    for k in &m.cracks {
        assert!(k.block < nb && k.joint < m.joints.len() && k.points.len() >= 2);
    }
    for g in m.merged.iter().chain(&m.enclosed) {
        assert!(g.block < nb && g.area > 0.0);
    }
    if let Some(bm) = &m.base_motion {
        assert!(bm.axes.iter().any(|a| a.len() >= 2));
        for a in &bm.axes {
            assert!(a.is_empty() || a.len() >= 2);
            assert!(a.windows(2).all(|w| w[1][0] > w[0][0]));
            assert!(a.iter().flatten().all(|x| x.is_finite()));
        }
    }
    for mo in &m.monitors {
        match &mo.kind {
            MonitorKind::Point { block, .. } => assert!(*block < nb),
            MonitorKind::Block { blocks } => assert!(blocks.iter().all(|&b| b < nb)),
            MonitorKind::Interface { first, second } => {
                assert!(!first.is_empty() && !second.is_empty());
                assert!(first.iter().chain(second.iter()).all(|&x| x < nb));
                assert!(first.iter().all(|x| !second.contains(x)));
            }
            MonitorKind::Bolt { bolt } => assert!(*bolt < m.bolts.len()),
            MonitorKind::Tip {
                block,
                joint,
                radii,
                ..
            } => {
                assert!(*block < nb && *joint < m.joints.len());
                assert!(0.0 < radii[0] && radii[0] < radii[1]);
            }
        }
    }
    for b in &m.bolts {
        assert!(b.blocks.iter().all(|&x| x < nb));
        assert!(b.stiffness > 0.0 && b.capacity > 0.0);
        assert!((0.0..=b.capacity).contains(&b.pretension));
        assert!(b.stage.is_none_or(|s| s < m.stages.len()));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(500), ..ProptestConfig::default() })]

    #[test]
    fn mutated_models_never_panic(muts in prop::collection::vec(mutation(), 1..5)) {
        let mut text = EXAMPLE.to_string();
        for m in &muts {
            text = apply(&text, m);
        }
        match parse_model(&text, Path::new(".")) {
            Ok(model) => check_invariants(&model),
            Err(e) => {
                prop_assert!(!e.0.trim().is_empty());
                prop_assert!(!e.0.contains('\n'), "multi-line error: {:?}", e.0);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(200), ..ProptestConfig::default() })]

    #[test]
    fn mutated_jointed_models_never_panic(muts in prop::collection::vec(mutation(), 1..4)) {
        let mut text = jointed();
        for m in &muts {
            text = apply(&text, m);
        }
        match parse_model(&text, Path::new(".")) {
            Ok(model) => check_invariants(&model),
            Err(e) => {
                prop_assert!(!e.0.trim().is_empty());
                prop_assert!(!e.0.contains('\n'), "multi-line error: {:?}", e.0);
            }
        }
    }
}

#[test]
fn every_number_of_the_joint_tables_can_be_replaced_without_panic() {
    let text = jointed();
    let spans: Vec<(usize, usize)> = number_spans(&text)
        .into_iter()
        .filter(|&(a, _)| a >= EXAMPLE.len())
        .collect();
    assert!(spans.len() > 15, "scanner found {} numbers", spans.len());
    for &(a, b) in &spans {
        for v in NUMBERS {
            let t = format!("{}{}{}", &text[..a], v, &text[b..]);
            match parse_model(&t, Path::new(".")) {
                Ok(m) => check_invariants(&m),
                Err(e) => assert!(!e.0.contains('\n')),
            }
        }
    }
}

#[test]
fn the_unmutated_example_is_valid() {
    let m = parse_model(EXAMPLE, Path::new(".")).unwrap();
    check_invariants(&m);
    assert_eq!(m.blocks.len(), 3);
    let m = parse_model(&jointed(), Path::new(".")).unwrap();
    check_invariants(&m);
    assert!(m.blocks.len() > 3 && !m.cracks.is_empty());
}

#[test]
fn every_number_can_be_replaced_without_panic() {
    // Exhaustive over the numeric literals and the replacement values.
    let spans = number_spans(EXAMPLE);
    assert!(spans.len() > 50, "scanner found {} numbers", spans.len());
    let mut rejected = 0;
    for &(a, b) in &spans {
        for v in NUMBERS {
            let text = format!("{}{}{}", &EXAMPLE[..a], v, &EXAMPLE[b..]);
            match parse_model(&text, Path::new(".")) {
                Ok(m) => check_invariants(&m),
                Err(e) => {
                    assert!(!e.0.contains('\n'));
                    rejected += 1;
                }
            }
        }
    }
    // nan and inf are refused wherever they go.
    assert!(rejected >= 3 * spans.len(), "only {rejected} rejections");
}
