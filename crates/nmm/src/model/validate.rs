//! Build the validated [`Model`] from the parsed TOML tree.
//!
//! Each table is read in turn; names are resolved to indices; geometry is
//! checked with the predicates of [`crate::geometry::polygon`] at the model
//! tolerance `tol = 1e-9 × L`, where `L` is the diagonal of the bounding box
//! of all block vertices. In messages, vertices and edges of a block are
//! numbered from 1 in the order the user wrote them (edge k joins vertex k to
//! vertex k+1, the last edge closes the polygon); `[[…]] #k` counts tables of
//! one kind from 1.

// `!(x > tol)` is deliberate throughout: a NaN fails the test.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
use super::joints;
use super::lines::Doc;
use super::reader::{
    array, array_of_tables, boolean, describe, error, fmt_num, fmt_point, integer, number, pair,
    point, points, segment, string, table, Fields, R,
};
use super::*;
use crate::geometry::polygon::{degeneracy, orient_ccw, self_intersection, Degeneracy, Location};
use crate::geometry::region::{regions_overlap, Region};
use crate::geometry::{Aabb, Vec2};
use std::collections::{HashMap, HashSet};
use toml::Value;

/// Relative geometric tolerance (× model size).
pub const REL_TOL: f64 = 1e-9;

/// Default `[analysis] tolerance`: the Newton iteration stops when the residual is below
/// this fraction of the physical forces (loads, weights, inertia, stresses, reactions,
/// contact forces).
pub const DEFAULT_TOLERANCE: f64 = 1e-9;

const TOP_KEYS: &[&str] = &[
    "analysis",
    "cover",
    "material",
    "block",
    "interface",
    "load",
    "constraint",
    "base_motion",
    "monitor",
    "joint_set",
    "joint",
    "stage",
    "initial_stress",
    "bolt",
];

/// A block as drawn (or a piece): its polygon and holes.
type Shape = (Vec<Vec2>, Vec<Vec<Vec2>>);

/// What the names of blocks in the model file stand for after cutting.
pub(crate) struct Names {
    /// name → (blocks it means: one block, or every piece of a cut block; the region it
    /// names: the block as drawn for a cut block).
    map: HashMap<String, (Vec<usize>, Shape)>,
}

impl Names {
    fn new(drawn: Vec<(String, Shape)>, pieces_of: &[Vec<usize>], blocks: &[Block]) -> Names {
        let mut map = HashMap::new();
        for ((name, shape), pieces) in drawn.into_iter().zip(pieces_of) {
            map.insert(name, (pieces.clone(), shape));
        }
        for (i, b) in blocks.iter().enumerate() {
            if b.parent.is_some() {
                map.insert(
                    b.name.clone(),
                    (vec![i], (b.vertices.clone(), b.holes.clone())),
                );
            }
        }
        Names { map }
    }

    pub(crate) fn get(&self, name: &str) -> Option<(&[usize], Region<'_>)> {
        self.map.get(name).map(|(s, (p, h))| {
            (
                s.as_slice(),
                Region {
                    outer: p.as_slice(),
                    holes: h.as_slice(),
                },
            )
        })
    }
}

/// `[cover]`.
struct CoverKeys {
    size: f64,
    origin: Option<Vec2>,
    min_block_area: Option<f64>,
    max_blocks: usize,
    order: usize,
}

/// Validate the whole tree. `base_dir` resolves `[base_motion] file`.
pub(crate) fn build(root: &Doc, base_dir: &Path) -> R<Model> {
    if let Some(k) = root.keys().find(|k| !TOP_KEYS.contains(&k.as_str())) {
        return Err(error(format!(
            "top level: unknown key `{}` (allowed tables: {}){}",
            k.escape_debug(),
            TOP_KEYS.join(", "),
            root.at_top(k)
        )));
    }
    let (analysis, stages) = analysis_and_stages(root, root.contains_key("base_motion"))?;
    let cov = cover(root)?;
    let materials = materials(root)?;
    let mut blocks = blocks(root, &materials)?;
    let tol = model_tolerance(&blocks);
    check_polygons(root, &mut blocks, tol)?;
    let specs = joints::read(root, &blocks, tol)?;
    joints::check_estimate(root, &blocks, &specs, cov.max_blocks)?;
    let drawn: Vec<(String, Shape)> = blocks
        .iter()
        .map(|b| (b.name.clone(), (b.vertices.clone(), b.holes.clone())))
        .collect();
    let cutting = joints::cut(
        root,
        blocks,
        &specs,
        tol,
        (cov.size, cov.min_block_area, cov.max_blocks),
    )?;
    let blocks = cutting.blocks;
    let names = Names::new(drawn, &cutting.pieces_of, &blocks);
    let joint_list: Vec<Joint> = specs.into_iter().map(|s| s.joint).collect();
    let interfaces = interfaces(root, &blocks, &names, &joint_list)?;
    let loads = loads(root, &blocks, &names, tol)?;
    let constraints = constraints(root, &blocks, &names, tol)?;
    let base_motion = base_motion(root, base_dir)?;
    let stages = super::insitu::excavations(root, stages, &names, (&blocks, &joint_list, tol))?;
    let bolts = super::bolts::bolts(root, &blocks, &stages, tol)?;
    let monitors = monitors(
        root,
        &blocks,
        &names,
        tol,
        &bolts,
        (&joint_list, &cutting.cracks, cov.size),
    )?;
    super::insitu::check_monitors(root, &monitors, &stages)?;
    super::insitu::check_bolts(root, &bolts, &stages)?;
    let initial_stress = super::insitu::initial_stress(root)?;
    Ok(Model {
        analysis,
        cover_size: cov.size,
        cover_origin: cov.origin,
        cover_order: cov.order,
        materials,
        blocks,
        interfaces,
        loads,
        constraints,
        base_motion,
        monitors,
        joints: joint_list,
        cracks: cutting.cracks,
        merged: cutting.merged,
        enclosed: cutting.enclosed,
        kept_small: cutting.kept_small,
        min_block_area: cov.min_block_area,
        stages,
        initial_stress,
        bolts,
    })
}

/// `1e-9 ×` the bounding-box diagonal of all block vertices.
fn model_tolerance(blocks: &[Block]) -> f64 {
    let mut bb = Aabb::empty();
    for b in blocks {
        for &p in &b.vertices {
            bb.include(p);
        }
    }
    let d = bb.diagonal();
    if d.is_finite() {
        REL_TOL * d
    } else {
        0.0
    }
}

fn positive(f: &Fields, key: &str, x: f64) -> R<f64> {
    if x > 0.0 {
        Ok(x)
    } else {
        Err(f.err(key, format!("must be positive, got {}", fmt_num(x))))
    }
}

fn count(f: &Fields, key: &str, default: usize, min: i64) -> R<usize> {
    match f.opt(key, integer)? {
        None => Ok(default),
        Some(n) if n < min => Err(f.err(key, format!("must be at least {min}, got {n}"))),
        Some(n) => usize::try_from(n).map_err(|_| f.err(key, format!("out of range, got {n}"))),
    }
}

fn choice<'a>(f: &Fields, key: &str, allowed: &[&'a str], default: &'a str) -> R<&'a str> {
    match f.opt(key, string)? {
        None => Ok(default),
        Some(s) => allowed.iter().copied().find(|a| *a == s).ok_or_else(|| {
            let list: Vec<String> = allowed.iter().map(|a| format!("\"{a}\"")).collect();
            f.err(
                key,
                format!("expected one of {}, got {s:?}", list.join(", ")),
            )
        }),
    }
}

/// The `[analysis]` keys a `[[stage]]` may also set.
const ANALYSIS_KEYS: &[&str] = &[
    "mode",
    "dt",
    "steps",
    "gravity",
    "friction",
    "output_every",
    "max_iterations",
    "tolerance",
    "max_step_cuts",
    "constraint_penalty",
];

/// The analysis keys written in one table (`[analysis]` or a `[[stage]]`), each checked.
#[derive(Default)]
struct AnalysisKeys {
    mode: Option<Mode>,
    dt: Option<f64>,
    steps: Option<usize>,
    gravity: Option<Vec2>,
    friction: Option<LawId>,
    output_every: Option<usize>,
    max_iterations: Option<usize>,
    tolerance: Option<f64>,
    max_step_cuts: Option<usize>,
    constraint_penalty: Option<f64>,
}

fn analysis_keys(f: &Fields) -> R<AnalysisKeys> {
    let opt_count = |key: &str, min: i64| -> R<Option<usize>> {
        if f.has(key) {
            count(f, key, 0, min).map(Some)
        } else {
            Ok(None)
        }
    };
    let mode = if f.has("mode") {
        Some(
            match choice(f, "mode", &["dynamic", "static"], "dynamic")? {
                "static" => Mode::Static,
                _ => Mode::Dynamic,
            },
        )
    } else {
        None
    };
    let dt = match f.opt("dt", number)? {
        Some(x) => Some(positive(f, "dt", x)?),
        None => None,
    };
    let steps = match f.opt("steps", integer)? {
        None => None,
        Some(n) if n <= 0 => return Err(f.err("steps", format!("must be positive, got {n}"))),
        Some(n) => {
            Some(usize::try_from(n).map_err(|_| f.err("steps", format!("out of range, got {n}")))?)
        }
    };
    let gravity = f.opt("gravity", pair)?;
    let friction = if f.has("friction") {
        // the laws `friction` may name: the registry's
        let names = LawId::analysis_names();
        let name = choice(f, "friction", &names, LawId::default().name())?;
        LawId::for_analysis(name)
    } else {
        None
    };
    let tolerance = f.opt("tolerance", number)?;
    if let Some(tolerance) = tolerance {
        if !(tolerance > 0.0 && tolerance < 1.0) {
            return Err(f.err(
                "tolerance",
                format!("must be in (0, 1), got {}", fmt_num(tolerance)),
            ));
        }
    }
    let constraint_penalty = match f.opt("constraint_penalty", number)? {
        Some(x) => Some(positive(f, "constraint_penalty", x)?),
        None => None,
    };
    Ok(AnalysisKeys {
        mode,
        dt,
        steps,
        gravity,
        friction,
        output_every: opt_count("output_every", 1)?,
        max_iterations: opt_count("max_iterations", 1)?,
        tolerance,
        max_step_cuts: opt_count("max_step_cuts", 0)?,
        constraint_penalty,
    })
}

/// `[analysis]`, and the `[[stage]]` tables with their keys resolved (unset: from
/// `[analysis]`, else the defaults). Without stages `[analysis]` needs `dt` and `steps`;
/// with stages, only the stages that do not set them need them there. The model's own
/// `analysis` is then the first stage's.
fn analysis_and_stages(root: &Doc, has_base_motion: bool) -> R<(Analysis, Vec<Stage>)> {
    let tables = array_of_tables(root, "stage")?;
    let t = table(root, "analysis")?;
    let base = match t {
        Some(t) => {
            let f = root.fields("[analysis]", t, "analysis", None);
            f.deny_unknown(ANALYSIS_KEYS)?;
            if tables.is_empty() {
                f.req("dt", number)?;
                f.req("steps", integer)?;
            }
            analysis_keys(&f)?
        }
        None if tables.is_empty() => {
            return Err(error(
                "[analysis]: missing table (keys `dt` and `steps` are required)",
            ))
        }
        None => AnalysisKeys::default(),
    };
    let resolve = |k: &AnalysisKeys, f: Option<&Fields>| -> R<Analysis> {
        let missing = |key: &str| match f {
            Some(f) => f.err(key, "missing (set it here or in [analysis])"),
            None => error(format!("[analysis]: key `{key}`: missing (required)")),
        };
        Ok(Analysis {
            mode: k.mode.or(base.mode).unwrap_or(Mode::Dynamic),
            dt: k.dt.or(base.dt).ok_or_else(|| missing("dt"))?,
            steps: k.steps.or(base.steps).ok_or_else(|| missing("steps"))?,
            gravity: k.gravity.or(base.gravity).unwrap_or([0.0, 0.0]),
            friction: k.friction.or(base.friction).unwrap_or_default(),
            output_every: k.output_every.or(base.output_every).unwrap_or(1),
            max_iterations: k.max_iterations.or(base.max_iterations).unwrap_or(25),
            tolerance: k.tolerance.or(base.tolerance).unwrap_or(DEFAULT_TOLERANCE),
            max_step_cuts: k.max_step_cuts.or(base.max_step_cuts).unwrap_or(6),
            constraint_penalty: k
                .constraint_penalty
                .or(base.constraint_penalty)
                .unwrap_or(1e6),
        })
    };
    let mut stages: Vec<Stage> = Vec::new();
    for (i, t) in tables.into_iter().enumerate() {
        let mut f = root.fields(format!("[[stage]] #{}", i + 1), t, "stage", Some(i));
        let name = f.name("name")?;
        f.set_place(format!("[[stage]] {name:?}"));
        let mut allowed = vec!["name", "base_motion", "excavate"];
        allowed.extend(ANALYSIS_KEYS);
        f.deny_unknown(&allowed)?;
        if let Some(k) = stages.iter().position(|s| s.name == name) {
            return Err(f.err(
                "name",
                format!("duplicate stage name (also [[stage]] #{})", k + 1),
            ));
        }
        let base_motion = f.opt("base_motion", boolean)?.unwrap_or(false);
        if base_motion && !has_base_motion {
            return Err(f.err(
                "base_motion",
                "is true but the model has no [base_motion] record",
            ));
        }
        let keys = analysis_keys(&f)?;
        let analysis = resolve(&keys, Some(&f))?;
        stages.push(Stage {
            name,
            analysis,
            base_motion,
            // resolved once the blocks are cut (`insitu::excavations`)
            excavate: Vec::new(),
        });
    }
    let analysis = match stages.first() {
        Some(s) => s.analysis.clone(),
        None => resolve(&base, None)?,
    };
    Ok((analysis, stages))
}

fn cover(root: &Doc) -> R<CoverKeys> {
    let t = table(root, "cover")?
        .ok_or_else(|| error("[cover]: missing table (key `size` is required)"))?;
    let f = root.fields("[cover]", t, "cover", None);
    f.deny_unknown(&["size", "origin", "min_block_area", "max_blocks", "order"])?;
    let size = positive(&f, "size", f.req("size", number)?)?;
    let origin = f.opt("origin", point)?;
    let min_block_area = match f.opt("min_block_area", number)? {
        Some(a) => Some(positive(&f, "min_block_area", a)?),
        None => None,
    };
    let max_blocks = count(&f, "max_blocks", joints::DEFAULT_MAX_BLOCKS, 1)?;
    let order = match f.opt("order", integer)? {
        None => 0,
        Some(n @ (0 | 1)) => n as usize,
        Some(n) => {
            return Err(f.err(
                "order",
                format!("must be 0 (constant covers) or 1 (first-order covers), got {n}"),
            ))
        }
    };
    Ok(CoverKeys {
        size,
        origin,
        min_block_area,
        max_blocks,
        order,
    })
}

fn materials(root: &Doc) -> R<Vec<Material>> {
    let mut out: Vec<Material> = Vec::new();
    for (i, t) in array_of_tables(root, "material")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[material]] #{}", i + 1), t, "material", Some(i));
        let name = f.name("name")?;
        f.set_place(format!("[[material]] {name:?}"));
        f.deny_unknown(&["name", "density", "young", "poisson", "plane", "damping"])?;
        if let Some(k) = out.iter().position(|m| m.name == name) {
            return Err(f.err(
                "name",
                format!("duplicate material name (also [[material]] #{})", k + 1),
            ));
        }
        let density = positive(&f, "density", f.req("density", number)?)?;
        let young = positive(&f, "young", f.req("young", number)?)?;
        let poisson = f.req("poisson", number)?;
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(f.err(
                "poisson",
                format!("must be in (-1, 0.5), got {}", fmt_num(poisson)),
            ));
        }
        let plane = match choice(&f, "plane", &["strain", "stress"], "strain")? {
            "stress" => Plane::Stress,
            _ => Plane::Strain,
        };
        let damping = damping(&f)?;
        out.push(Material {
            name,
            density,
            young,
            poisson,
            plane,
            damping,
        });
    }
    Ok(out)
}

/// `damping = { alpha = …, beta = … }` (either may be left out: 0) or
/// `damping = { ratio = ζ, frequencies = [f1, f2] }` (Hz), converted by [`Rayleigh::from_ratio`].
fn damping(f: &Fields) -> R<Rayleigh> {
    let table = |v: &Value| {
        match v {
        Value::Table(t) => Ok(t.clone()),
        other => Err(format!(
            "expected a table {{ alpha = …, beta = … }} or {{ ratio = …, frequencies = [f1, f2] }}, got {}",
            describe(other)
        )),
    }
    };
    let Some(t) = f.opt("damping", table)? else {
        return Ok(Rayleigh::default());
    };
    let bad = |msg: String| f.err("damping", msg);
    if let Some(k) = t
        .keys()
        .find(|k| !["alpha", "beta", "ratio", "frequencies"].contains(&k.as_str()))
    {
        return Err(bad(format!(
            "unknown key `{}` (allowed: alpha, beta, or ratio with frequencies)",
            k.escape_debug()
        )));
    }
    let num = |k: &str| -> R<Option<f64>> {
        t.get(k)
            .map(|v| number(v).map_err(|e| bad(format!("`{k}`: {e}"))))
            .transpose()
    };
    let direct = t.contains_key("alpha") || t.contains_key("beta");
    let by_ratio = t.contains_key("ratio") || t.contains_key("frequencies");
    if direct && by_ratio {
        return Err(bad(
            "give either `alpha`/`beta` or `ratio` with `frequencies`, not both".into(),
        ));
    }
    if direct {
        let mut r = Rayleigh::default();
        for (k, slot) in [("alpha", &mut r.alpha), ("beta", &mut r.beta)] {
            if let Some(x) = num(k)? {
                if !(x >= 0.0) {
                    return Err(bad(format!("`{k}` must be ≥ 0, got {}", fmt_num(x))));
                }
                *slot = x;
            }
        }
        return Ok(r);
    }
    if !by_ratio {
        return Err(bad(
            "empty table: give `alpha` and/or `beta`, or `ratio` with `frequencies`".into(),
        ));
    }
    let zeta = num("ratio")?.ok_or_else(|| bad("`ratio` is required with `frequencies`".into()))?;
    if !(0.0..=1.0).contains(&zeta) {
        return Err(bad(format!(
            "`ratio` must be in [0, 1], got {}",
            fmt_num(zeta)
        )));
    }
    let freqs = t
        .get("frequencies")
        .ok_or_else(|| bad("`frequencies = [f1, f2]` (Hz) is required with `ratio`".into()))?;
    let [f1, f2] = pair(freqs).map_err(|e| bad(format!("`frequencies`: {e}")))?;
    if !(f1 > 0.0 && f2 > 0.0) {
        return Err(bad(format!(
            "`frequencies` must be positive (Hz), got [{}, {}]",
            fmt_num(f1),
            fmt_num(f2)
        )));
    }
    Ok(Rayleigh::from_ratio(zeta, f1, f2))
}

/// Read the blocks (names, materials, vertex lists); geometry is checked later.
fn blocks(root: &Doc, materials: &[Material]) -> R<Vec<Block>> {
    let tables = array_of_tables(root, "block")?;
    if tables.is_empty() {
        return Err(error("[[block]]: the model defines no block"));
    }
    let mut out: Vec<Block> = Vec::new();
    for (i, t) in tables.into_iter().enumerate() {
        let mut f = root.fields(format!("[[block]] #{}", i + 1), t, "block", Some(i));
        let name = f.name("name")?;
        f.set_place(format!("[[block]] {name:?}"));
        f.deny_unknown(&["name", "material", "vertices", "fixed", "holes"])?;
        if let Some(k) = out.iter().position(|b| b.name == name) {
            return Err(f.err(
                "name",
                format!("duplicate block name (also [[block]] #{})", k + 1),
            ));
        }
        let mat_name = f.req("material", string)?;
        let material = materials
            .iter()
            .position(|m| m.name == mat_name)
            .ok_or_else(|| f.err("material", format!("unknown material {mat_name:?}")))?;
        let vertices = f.req("vertices", points)?;
        if vertices.len() < 3 {
            return Err(f.err(
                "vertices",
                format!(
                    "a polygon needs at least 3 vertices, got {}",
                    vertices.len()
                ),
            ));
        }
        let fixed = f.opt("fixed", boolean)?.unwrap_or(false);
        let holes = f.opt("holes", hole_list)?.unwrap_or_default();
        let edges = vertices.len() + holes.iter().map(Vec::len).sum::<usize>();
        out.push(Block {
            name,
            material,
            edge_joint: vec![None; edges],
            vertices,
            fixed,
            parent: None,
            holes,
        });
    }
    Ok(out)
}

/// `holes = [[[x, y], …], …]`: polygons of at least 3 points each.
fn hole_list(v: &Value) -> Result<Vec<Vec<Vec2>>, String> {
    let items = array(v).map_err(|_| {
        format!(
            "expected a list of polygons [[[x, y], …], …], got {}",
            describe(v)
        )
    })?;
    items
        .iter()
        .enumerate()
        .map(|(k, h)| {
            let p = points(h).map_err(|e| format!("hole {}: {e}", k + 1))?;
            if p.len() < 3 {
                return Err(format!(
                    "hole {}: a polygon needs at least 3 vertices, got {}",
                    k + 1,
                    p.len()
                ));
            }
            Ok(p)
        })
        .collect()
}

/// Check every polygon (degeneracy, self-intersection), orient it CCW (its holes CW),
/// check that each hole lies strictly inside its block and apart from the others, and
/// that no two blocks overlap.
fn check_polygons(root: &Doc, blocks: &mut [Block], tol: f64) -> R<()> {
    for (i, b) in blocks.iter_mut().enumerate() {
        // (the place is looked up only for an error: a lookup counts the lines before it)
        let err = |msg: String| {
            let at = root.at("block", Some(i), Some("vertices"));
            error(format!("[[block]] {:?}: key `vertices`: {msg}{at}", b.name))
        };
        let n = b.vertices.len();
        // A zero area is reported after self-intersection (a symmetric bow-tie has zero area).
        let degenerate = degeneracy(&b.vertices, tol);
        if !matches!(degenerate, None | Some(Degeneracy::ZeroArea))
            || self_intersection(&b.vertices, tol).is_none()
        {
            if let Some(d) = degenerate {
                return Err(err(match d {
                    Degeneracy::TooFewVertices(k) => {
                        format!("a polygon needs at least 3 vertices, got {k}")
                    }
                    Degeneracy::RepeatedVertex(i) => {
                        format!(
                            "degenerate polygon: vertices {} and {} coincide",
                            i + 1,
                            (i + 1) % n + 1
                        )
                    }
                    Degeneracy::Collinear => {
                        "degenerate polygon: all vertices are collinear".into()
                    }
                    Degeneracy::FoldBack(i) => {
                        format!(
                            "degenerate polygon: the boundary folds back on itself at vertex {}",
                            i + 1
                        )
                    }
                    Degeneracy::ZeroArea => "degenerate polygon: zero area".into(),
                }));
            }
        }
        if let Some((i, j)) = self_intersection(&b.vertices, tol) {
            return Err(err(format!(
                "polygon self-intersects (edges {} and {})",
                i + 1,
                j + 1
            )));
        }
        orient_ccw(&mut b.vertices);
        super::insitu::check_holes(root, i, b, tol)?;
    }
    let boxes: Vec<Aabb> = blocks
        .iter()
        .map(|b| Aabb::of_points(&b.vertices))
        .collect();
    for j in 0..blocks.len() {
        for i in 0..j {
            if boxes[i].overlaps(&boxes[j])
                && regions_overlap(blocks[i].region(), blocks[j].region(), tol)
            {
                return Err(error(format!(
                    "[[block]] {:?}: key `vertices`: overlaps block {:?} (blocks may touch but not overlap){}",
                    blocks[j].name,
                    blocks[i].name,
                    root.at("block", Some(j), Some("vertices"))
                )));
            }
        }
    }
    Ok(())
}

/// Resolve a block name read from `key`: the blocks it means and the polygon it names.
fn block_ref<'n>(
    f: &Fields,
    key: &str,
    name: &str,
    names: &'n Names,
) -> R<(&'n [usize], Region<'n>)> {
    names
        .get(name)
        .ok_or_else(|| f.err(key, format!("unknown block {name:?}")))
}

/// A pair of block names `["a", "b"]` as two sets of blocks. The same name twice is
/// accepted only with `same_cut` and when it names a cut block (the pairs among its
/// pieces); otherwise the sets must be disjoint.
fn block_pair(
    f: &Fields,
    key: &str,
    names: &Names,
    same_cut: bool,
) -> R<(Vec<usize>, Vec<usize>, String, String)> {
    let v = f.req(key, array)?;
    let (a, b) = match v {
        [a, b] => (
            string(a).map_err(|e| f.err(key, e))?,
            string(b).map_err(|e| f.err(key, e))?,
        ),
        _ => {
            return Err(f.err(
                key,
                format!(
                    "expected two block names [\"a\", \"b\"], got {} items",
                    v.len()
                ),
            ))
        }
    };
    let (sa, _) = block_ref(f, key, a, names)?;
    let (sb, _) = block_ref(f, key, b, names)?;
    if a == b && !(same_cut && sa.len() >= 2) {
        return Err(f.err(key, format!("the two blocks must differ, got {a:?} twice")));
    }
    if a != b && sa.iter().any(|x| sb.binary_search(x).is_ok()) {
        return Err(f.err(
            key,
            format!("{a:?} and {b:?} share a block (the name of a cut block means all its pieces)"),
        ));
    }
    Ok((sa.to_vec(), sb.to_vec(), a.to_string(), b.to_string()))
}

/// Sorted intersection of two sorted lists.
fn common(x: &[usize], y: &[usize]) -> Vec<usize> {
    x.iter()
        .copied()
        .filter(|v| y.binary_search(v).is_ok())
        .collect()
}

/// Whether two block-pair scopes share a pair of distinct blocks.
fn scopes_share(p: (&[usize], &[usize]), q: (&[usize], &[usize])) -> bool {
    let share = |x1: &[usize], x2: &[usize], y1: &[usize], y2: &[usize]| {
        let (i, j) = (common(x1, x2), common(y1, y2));
        let only_same = i.len() == 1 && j.len() == 1 && i[0] == j[0];
        !(i.is_empty() || j.is_empty() || only_same)
    };
    share(p.0, q.0, p.1, q.1) || share(p.0, q.1, p.1, q.0)
}

fn interfaces(
    root: &Doc,
    blocks: &[Block],
    names: &Names,
    joint_list: &[Joint],
) -> R<Vec<Interface>> {
    let mut out: Vec<Interface> = Vec::new();
    let mut default_at: Option<usize> = None;
    let mut joint_at: HashMap<usize, usize> = HashMap::new();
    for (k, t) in array_of_tables(root, "interface")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[interface]] #{}", k + 1), t, "interface", Some(k));
        let mut allowed = vec![
            "blocks",
            "joint",
            "friction_angle",
            "cohesion",
            "normal_penalty",
            "shear_penalty",
            "restitution",
        ];
        // the keys of the laws an interface selects (the registry's)
        allowed.extend(LawId::interface_keys());
        f.deny_unknown(&allowed)?;
        if f.has("blocks") && f.has("joint") {
            return Err(f.err("joint", "give either `blocks` or `joint`, not both"));
        }
        let scope = if f.has("blocks") {
            let (sa, sb, a, b) = block_pair(&f, "blocks", names, true)?;
            f.set_place(format!("[[interface]] #{} (blocks {a:?}, {b:?})", k + 1));
            let first = out.iter().position(|i| match &i.scope {
                InterfaceScope::Blocks(x, y) => scopes_share((x, y), (&sa, &sb)),
                _ => false,
            });
            if let Some(first) = first {
                return Err(f.err(
                    "blocks",
                    format!(
                        "this pair already has an interface ([[interface]] #{})",
                        first + 1
                    ),
                ));
            }
            InterfaceScope::Blocks(sa, sb)
        } else if f.has("joint") {
            let name = f.req("joint", string)?;
            f.set_place(format!("[[interface]] #{} (joint {name:?})", k + 1));
            let j =
                joint_list
                    .iter()
                    .position(|j| j.name == name)
                    .ok_or_else(|| {
                        f.err(
                    "joint",
                    format!("unknown joint {name:?} (no [[joint_set]] or [[joint]] has this name)"),
                )
                    })?;
            if let Some(first) = joint_at.insert(j, k) {
                return Err(f.err(
                    "joint",
                    format!(
                        "this joint already has an interface ([[interface]] #{})",
                        first + 1
                    ),
                ));
            }
            InterfaceScope::Joint(j)
        } else {
            f.set_place(format!("[[interface]] #{} (default)", k + 1));
            if let Some(first) = default_at {
                return Err(f.fail(format!(
                    "a second default interface (without `blocks` or `joint`): [[interface]] #{} is already the default",
                    first + 1
                )));
            }
            default_at = Some(k);
            InterfaceScope::Default
        };
        let friction_angle = f.req("friction_angle", number)?;
        if !(0.0..90.0).contains(&friction_angle) {
            return Err(f.err(
                "friction_angle",
                format!(
                    "must be in [0, 90) degrees, got {}",
                    fmt_num(friction_angle)
                ),
            ));
        }
        let cohesion = f.opt("cohesion", number)?.unwrap_or(0.0);
        if cohesion < 0.0 {
            return Err(f.err(
                "cohesion",
                format!("must be zero or positive, got {}", fmt_num(cohesion)),
            ));
        }
        let normal_penalty = positive(&f, "normal_penalty", f.req("normal_penalty", number)?)?;
        let shear_penalty = positive(&f, "shear_penalty", f.req("shear_penalty", number)?)?;
        let restitution = f.opt("restitution", number)?;
        if let Some(e) = restitution {
            if e.is_nan() || e <= 0.0 || e > 1.0 {
                return Err(f.err(
                    "restitution",
                    format!(
                        "must be in (0, 1] (rebound speed / impact speed), got {}",
                        fmt_num(e)
                    ),
                ));
            }
        }
        let law = interface_law(&f, friction_angle, cohesion)?;
        out.push(Interface {
            scope,
            friction_angle,
            cohesion,
            normal_penalty,
            shear_penalty,
            restitution,
            law,
        });
    }
    if default_at.is_none() && blocks.len() >= 2 {
        // A `joint` interface covers faces, not pairs: pieces can come to touch on faces
        // no joint made, so every pair still needs its own interface or the default.
        let pairs: Vec<&Interface> = out
            .iter()
            .filter(|i| matches!(i.scope, InterfaceScope::Blocks(..)))
            .collect();
        for j in 0..blocks.len() {
            for i in 0..j {
                if !pairs.iter().any(|p| p.scope.covers_pair(i, j)) {
                    let (a, b) = (&blocks[i].name, &blocks[j].name);
                    let hint = if joint_at.is_empty() {
                        String::new()
                    } else {
                        " (a `joint` interface applies only to the faces its joint made; pieces may touch elsewhere)".into()
                    };
                    return Err(error(format!(
                        "[[interface]]: no interface for blocks {a:?} and {b:?}: add a default [[interface]] \
                         (without `blocks`) or one with blocks = [{a:?}, {b:?}]{hint}"
                    )));
                }
            }
        }
    }
    Ok(out)
}

/// The law an interface selects by its own keys (see [`crate::contact::law`]), with their
/// values checked by the law: errors at the key's line.
fn interface_law(f: &Fields, friction_angle: f64, cohesion: f64) -> R<Option<InterfaceLaw>> {
    let laws = LawId::for_interface(|k| f.has(k));
    let Some(&law) = laws.first() else {
        return Ok(None);
    };
    if let Some(other) = laws.get(1) {
        let key = other
            .keys()
            .iter()
            .find(|k| f.has(k))
            .copied()
            .unwrap_or("");
        return Err(f.err(
            key,
            format!(
                "selects the {:?} law, but this interface's other keys select the {:?} law",
                other.name(),
                law.name()
            ),
        ));
    }
    let keys = law.keys();
    let given = keys
        .iter()
        .map(|k| f.opt(k, number))
        .collect::<R<Vec<_>>>()?;
    let values = law
        .law()
        .interface_values(friction_angle, cohesion, &given)
        .map_err(|(i, msg)| f.err(keys.get(i).copied().unwrap_or(""), msg))?;
    Ok(Some(InterfaceLaw { law, values }))
}

/// Check that a segment lies on the block boundary.
fn on_boundary(
    f: &Fields,
    key: &str,
    (name, poly): (&str, Region),
    (a, b): (Vec2, Vec2),
    tol: f64,
) -> R<()> {
    if !(crate::geometry::dist(a, b) > tol) {
        return Err(f.err(
            key,
            format!(
                "segment [{},{}] has zero length",
                fmt_point(a),
                fmt_point(b)
            ),
        ));
    }
    if !poly.segment_on_boundary(a, b, tol) {
        return Err(f.err(
            key,
            format!(
                "segment [{},{}] is not on the boundary of block {:?}",
                fmt_point(a),
                fmt_point(b),
                name
            ),
        ));
    }
    Ok(())
}

/// A segment on the boundary of the blocks `set` (a cut block's pieces) split among the
/// pieces whose boundary it lies along: (block, a, b) per part.
fn split_on_pieces(
    f: &Fields,
    key: &str,
    blocks: &[Block],
    set: &[usize],
    (a, b): (Vec2, Vec2),
    tol: f64,
) -> R<Vec<(usize, Vec2, Vec2)>> {
    if let [only] = set {
        return Ok(vec![(*only, a, b)]);
    }
    let at = |t: f64| {
        if t <= 0.0 {
            a
        } else if t >= 1.0 {
            b
        } else {
            crate::geometry::lerp(a, b, t)
        }
    };
    let mut out = Vec::new();
    let mut covered = 0.0;
    for &i in set {
        for (t0, t1) in blocks[i].region().segment_boundary_intervals(a, b, tol) {
            covered += t1 - t0;
            out.push((i, at(t0), at(t1)));
        }
    }
    let len = crate::geometry::dist(a, b);
    if !((covered - 1.0).abs() * len <= tol * (1 + set.len()) as f64) {
        return Err(f.err(
            key,
            format!(
                "segment [{},{}] could not be split among the pieces of its cut block ({:.9} of its length found)",
                fmt_point(a),
                fmt_point(b),
                covered
            ),
        ));
    }
    Ok(out)
}

/// The first block of `set` containing `p` (inside or on its boundary).
fn piece_at(blocks: &[Block], set: &[usize], p: Vec2, tol: f64) -> usize {
    set.iter()
        .copied()
        .find(|&i| blocks[i].region().locate(p, tol) != Location::Outside)
        .unwrap_or(set[0])
}

/// Check that a point lies inside or on the block.
fn in_block(f: &Fields, key: &str, (name, poly): (&str, Region), p: Vec2, tol: f64) -> R<()> {
    if poly.locate(p, tol) == Location::Outside {
        return Err(f.err(
            key,
            format!("point {} is outside block {:?}", fmt_point(p), name),
        ));
    }
    Ok(())
}

/// Read `block` and rename the place `[[KIND]] #k (block "name")`: (name, blocks it
/// means, polygon it names).
fn owner_block<'n>(
    f: &mut Fields,
    kind: &str,
    k: usize,
    names: &'n Names,
) -> R<(String, &'n [usize], Region<'n>)> {
    let name = f.req("block", string)?;
    f.set_place(format!("[[{kind}]] #{} (block {name:?})", k + 1));
    let (set, poly) = block_ref(f, "block", name, names)?;
    Ok((name.to_string(), set, poly))
}

fn loads(root: &Doc, blocks: &[Block], names: &Names, tol: f64) -> R<Vec<Load>> {
    let mut out = Vec::new();
    for (k, t) in array_of_tables(root, "load")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[load]] #{}", k + 1), t, "load", Some(k));
        let (name, set, poly) = owner_block(&mut f, "load", k, names)?;
        f.deny_unknown(&["block", "edge", "traction", "point", "force"])?;
        let named = (name.as_str(), poly);
        match (f.has("edge"), f.has("point")) {
            (true, true) => {
                return Err(f.err(
                    "point",
                    "give either `edge` (with `traction`) or `point` (with `force`), not both",
                ))
            }
            (false, false) => {
                return Err(f.err(
                    "edge",
                    "missing: give either `edge` with `traction`, or `point` with `force`",
                ))
            }
            (true, false) => {
                if f.has("force") {
                    return Err(f.err(
                        "force",
                        "belongs to a point load; an edge load takes `traction` (Pa)",
                    ));
                }
                let (a, b) = f.req("edge", segment)?;
                on_boundary(&f, "edge", named, (a, b), tol)?;
                let traction = f.req("traction", pair)?;
                for (block, a, b) in split_on_pieces(&f, "edge", blocks, set, (a, b), tol)? {
                    out.push(Load {
                        block,
                        kind: LoadKind::Edge { a, b, traction },
                    });
                }
            }
            (false, true) => {
                if f.has("traction") {
                    return Err(f.err(
                        "traction",
                        "belongs to an edge load; a point load takes `force` (N/m)",
                    ));
                }
                let p = f.req("point", point)?;
                in_block(&f, "point", named, p, tol)?;
                let force = f.req("force", pair)?;
                out.push(Load {
                    block: piece_at(blocks, set, p, tol),
                    kind: LoadKind::Point { p, force },
                });
            }
        }
    }
    Ok(out)
}

/// A prescribed displacement: a number, or rows `[[t, u], …]` with strictly increasing t.
fn time_function(v: &Value) -> Result<TimeFunction, String> {
    if let Value::Array(rows) = v {
        if rows.is_empty() {
            return Err("the table [[t, u], …] has no rows".into());
        }
        let mut out: Vec<(f64, f64)> = Vec::with_capacity(rows.len());
        for (i, r) in rows.iter().enumerate() {
            let [t, u] =
                pair(r).map_err(|e| format!("row {}: {}", i + 1, e.replace("[x, y]", "[t, u]")))?;
            if let Some(&(t0, _)) = out.last() {
                if !(t > t0) {
                    return Err(format!(
                        "row {}: times must be strictly increasing, got {} after {}",
                        i + 1,
                        fmt_num(t),
                        fmt_num(t0)
                    ));
                }
            }
            out.push((t, u));
        }
        Ok(TimeFunction::Table(out))
    } else {
        number(v).map(TimeFunction::Constant).map_err(|_| {
            format!(
                "expected a number or a table [[t, u], …], got {}",
                super::reader::describe(v)
            )
        })
    }
}

fn constraints(root: &Doc, blocks: &[Block], names: &Names, tol: f64) -> R<Vec<Constraint>> {
    let mut out = Vec::new();
    for (k, t) in array_of_tables(root, "constraint")?.into_iter().enumerate() {
        let mut f = root.fields(
            format!("[[constraint]] #{}", k + 1),
            t,
            "constraint",
            Some(k),
        );
        let (name, set, poly) = owner_block(&mut f, "constraint", k, names)?;
        f.deny_unknown(&["block", "edge", "point", "ux", "uy"])?;
        let named = (name.as_str(), poly);
        let parts: Vec<(usize, ConstraintGeometry)> = match (f.has("edge"), f.has("point")) {
            (true, true) => return Err(f.err("point", "give either `edge` or `point`, not both")),
            (false, false) => return Err(f.err("edge", "missing: give either `edge` or `point`")),
            (true, false) => {
                let (a, b) = f.req("edge", segment)?;
                on_boundary(&f, "edge", named, (a, b), tol)?;
                split_on_pieces(&f, "edge", blocks, set, (a, b), tol)?
                    .into_iter()
                    .map(|(block, a, b)| (block, ConstraintGeometry::Edge { a, b }))
                    .collect()
            }
            (false, true) => {
                let p = f.req("point", point)?;
                in_block(&f, "point", named, p, tol)?;
                vec![(
                    piece_at(blocks, set, p, tol),
                    ConstraintGeometry::Point { p },
                )]
            }
        };
        let ux = f.opt("ux", time_function)?;
        let uy = f.opt("uy", time_function)?;
        if ux.is_none() && uy.is_none() {
            return Err(f.err("ux", "missing: give `ux`, `uy` or both"));
        }
        for (block, geometry) in parts {
            out.push(Constraint {
                block,
                geometry,
                ux: ux.clone(),
                uy: uy.clone(),
            });
        }
    }
    Ok(out)
}

/// The keys of one record: in `[base_motion]` itself, or in its `x` / `y` tables.
const RECORD_KEYS: &[&str] = &[
    "table", "file", "format", "scale", "pga", "start", "duration",
];

fn base_motion(root: &Doc, base_dir: &Path) -> R<Option<BaseMotion>> {
    let Some(t) = table(root, "base_motion")? else {
        return Ok(None);
    };
    let f = root.fields("[base_motion]", t, "base_motion", None);
    let window = (
        f.opt("start", number)?.unwrap_or(0.0),
        f.opt("duration", number)?,
    );
    check_window(&f, window)?;
    let mut axes: [Vec<[f64; 2]>; 2] = [Vec::new(), Vec::new()];
    let mut records = Vec::new();
    if !(f.has("x") || f.has("y")) {
        let mut allowed = RECORD_KEYS.to_vec();
        allowed.push("component");
        f.deny_unknown(&allowed)?;
        let component = choice(&f, "component", &["x", "y"], "x")?;
        let (samples, info) = record(&f, base_dir, component, window, false)?;
        for (k, axis) in ["x", "y"].into_iter().enumerate() {
            if info.axis.contains(axis) {
                axes[k] = samples.iter().map(|s| [s[0], s[k + 1]]).collect();
            }
        }
        records.push(info);
    } else {
        if let Some(k) = t
            .keys()
            .find(|k| !["x", "y", "start", "duration"].contains(&k.as_str()))
        {
            return Err(f.err(
                k,
                "with `x` / `y` component records, give each record's keys in its own table \
                 (x = { file = \"…\", pga = 0.3 }); only `start` and `duration` may be shared",
            ));
        }
        for (k, axis) in [(0usize, "x"), (1, "y")] {
            let Some(v) = t.get(axis) else { continue };
            let toml::Value::Table(sub) = v else {
                return Err(f.err(
                    axis,
                    format!(
                        "must be a table such as {{ file = \"record.AT2\", pga = 0.3 }}, got {}",
                        describe(v)
                    ),
                ));
            };
            let g = root
                .fields(format!("[base_motion.{axis}]"), sub, "base_motion", None)
                .within(axis);
            g.deny_unknown(RECORD_KEYS)?;
            let own = (
                g.opt("start", number)?.unwrap_or(window.0),
                g.opt("duration", number)?.or(window.1),
            );
            check_window(&g, own)?;
            let (samples, info) = record(&g, base_dir, axis, own, true)?;
            axes[k] = samples.iter().map(|s| [s[0], s[k + 1]]).collect();
            records.push(info);
        }
    }
    Ok(Some(BaseMotion { axes, records }))
}

/// `start` ≥ 0 and `duration` > 0 where given.
fn check_window(f: &Fields, (start, duration): (f64, Option<f64>)) -> R<()> {
    if f.has("start") && !(start >= 0.0) {
        return Err(f.err(
            "start",
            format!("must be at least 0 s, got {}", fmt_num(start)),
        ));
    }
    if let Some(d) = duration.filter(|_| f.has("duration")) {
        positive(f, "duration", d)?;
    }
    Ok(())
}

/// One record (`table` or `file`) read, windowed and scaled: its samples `(t, ax, ay)`
/// as applied and what it was. `single`: a component record (`[base_motion.x]`), which
/// must have one acceleration column.
fn record(
    f: &Fields,
    base_dir: &Path,
    component: &str,
    (start, duration): (f64, Option<f64>),
    single: bool,
) -> R<(Vec<[f64; 3]>, RecordInfo)> {
    let (key, source, raw, two_axes) = match (f.has("table"), f.has("file")) {
        (true, true) => return Err(f.err("file", "give either `table` or `file`, not both")),
        (false, false) => return Err(f.err("table", "missing: give either `table` or `file`")),
        (true, false) => {
            if f.has("format") {
                return Err(f.err("format", "applies only with `file`"));
            }
            let raw = f.req("table", |v| motion_table(v, component))?;
            let three = f.req("table", |v| {
                Ok(array(v)?
                    .first()
                    .and_then(|r| r.as_array())
                    .is_some_and(|r| r.len() == 3))
            })?;
            if single && three {
                return Err(f.err(
                    "table",
                    format!("a component record's rows are [t, a] (it drives {component} only)"),
                ));
            }
            ("table", "table".to_string(), raw, three)
        }
        (false, true) => {
            let format = choice(f, "format", &["csv", "peer", "knet"], "")?;
            let format = (!format.is_empty()).then_some(format);
            let file = f.req("file", string)?;
            if file.trim().is_empty() {
                return Err(f.err("file", "must not be empty"));
            }
            let path = base_dir.join(file);
            if let Err(e) = std::fs::metadata(&path) {
                return Err(f.err(
                    "file",
                    format!("cannot read {file:?} ({}): {e}", path.display()),
                ));
            }
            let samples = crate::motion::read_record(&path, format, component)
                .map_err(|e| f.err("file", e))?;
            let other = if component == "y" { 1 } else { 2 };
            let two = samples.iter().any(|s| s[other] != 0.0);
            if single && two {
                return Err(f.err(
                    "file",
                    format!(
                        "{file:?} has two acceleration columns; a component record has one (t,a)"
                    ),
                ));
            }
            ("file", file.to_string(), samples, two)
        }
    };
    check_samples(&raw).map_err(|e| f.err(key, e))?;
    let axis = if two_axes {
        "x, y".to_string()
    } else {
        component.to_string()
    };
    let pga_read = crate::motion::peaks(&raw);
    let windowed = crate::motion::window(&raw, start, duration).map_err(|e| {
        f.err(
            if f.has("duration") {
                "duration"
            } else if f.has("start") {
                "start"
            } else {
                key
            },
            e,
        )
    })?;
    let peak_used = crate::motion::peaks(&windowed);
    let scale = match (f.opt("scale", number)?, f.opt("pga", number)?) {
        (Some(_), Some(_)) => return Err(f.err("pga", "give either `scale` or `pga`, not both")),
        (Some(s), None) => s,
        (None, Some(p)) => {
            if !(p > 0.0) {
                return Err(f.err(
                    "pga",
                    format!("must be positive (in g), got {}", fmt_num(p)),
                ));
            }
            let peak = peak_used[0].max(peak_used[1]);
            if !(peak > 0.0) {
                return Err(f.err(
                    "pga",
                    "the part of the record used has no acceleration to scale (all zero)",
                ));
            }
            p * crate::motion::G / peak
        }
        (None, None) => 1.0,
    };
    let samples: Vec<[f64; 3]> = windowed
        .iter()
        .map(|s| [s[0], scale * s[1], scale * s[2]])
        .collect();
    if samples
        .iter()
        .any(|s| !(s[1].is_finite() && s[2].is_finite()))
    {
        let k = if f.has("pga") { "pga" } else { "scale" };
        return Err(f.err(
            k,
            format!("scaled accelerations overflow (scale = {})", fmt_num(scale)),
        ));
    }
    let info = RecordInfo {
        axis,
        source,
        samples: raw.len(),
        dt: crate::motion::intervals(&raw),
        span: (raw[0][0], raw[raw.len() - 1][0]),
        pga_read,
        start,
        duration: samples[samples.len() - 1][0],
        scale,
        pga_applied: crate::motion::peaks(&samples),
    };
    Ok((samples, info))
}

/// Rows `[t, ax, ay]` or `[t, a]` (the latter drives `component`).
fn motion_table(v: &Value, component: &str) -> Result<Vec<[f64; 3]>, String> {
    let rows = array(v)?;
    let mut width = None;
    let mut out = Vec::with_capacity(rows.len());
    for (i, r) in rows.iter().enumerate() {
        let items = array(r).map_err(|e| format!("row {}: {e}", i + 1))?;
        let nums: Vec<f64> = items
            .iter()
            .map(number)
            .collect::<Result<_, _>>()
            .map_err(|e| format!("row {}: {e}", i + 1))?;
        out.push(match nums.as_slice() {
            [t, ax, ay] => [*t, *ax, *ay],
            [t, a] if component == "y" => [*t, 0.0, *a],
            [t, a] => [*t, *a, 0.0],
            _ => {
                return Err(format!(
                    "row {}: expected [t, ax, ay] or [t, a], got {} numbers",
                    i + 1,
                    nums.len()
                ))
            }
        });
        if *width.get_or_insert(nums.len()) != nums.len() {
            return Err(format!("row {}: all rows must have the same length", i + 1));
        }
    }
    Ok(out)
}

/// At least two finite samples with strictly increasing times.
fn check_samples(s: &[[f64; 3]]) -> Result<(), String> {
    if s.len() < 2 {
        return Err(format!(
            "the record needs at least 2 samples, got {}",
            s.len()
        ));
    }
    for (i, r) in s.iter().enumerate() {
        if r.iter().any(|x| !x.is_finite()) {
            return Err(format!("sample {}: non-finite value", i + 1));
        }
        if i > 0 && !(r[0] > s[i - 1][0]) {
            return Err(format!(
                "sample {}: times must be strictly increasing, got {} after {}",
                i + 1,
                fmt_num(r[0]),
                fmt_num(s[i - 1][0])
            ));
        }
    }
    Ok(())
}

fn monitors(
    root: &Doc,
    blocks: &[Block],
    names: &Names,
    tol: f64,
    bolts: &[Bolt],
    (joints, cracks, h): (&[Joint], &[Crack], f64),
) -> R<Vec<Monitor>> {
    let mut out: Vec<Monitor> = Vec::new();
    let mut seen: HashSet<String> = HashSet::new();
    for (k, t) in array_of_tables(root, "monitor")?.into_iter().enumerate() {
        let mut f = root.fields(format!("[[monitor]] #{}", k + 1), t, "monitor", Some(k));
        let name = f.name("name")?;
        f.set_place(format!("[[monitor]] {name:?}"));
        f.deny_unknown(&[
            "name",
            "point",
            "interface",
            "block",
            "bolt",
            "crack",
            "tip",
            "radii",
        ])?;
        if name.chars().any(|c| c == ',' || c == '"' || c.is_control()) {
            return Err(f.err("name", "must not contain commas, quotes or control characters (it heads history.csv columns)"));
        }
        if !seen.insert(name.clone()) {
            return Err(f.err("name", "duplicate monitor name"));
        }
        let given = ["point", "interface", "block", "bolt", "crack"]
            .into_iter()
            .filter(|k| f.has(k))
            .collect::<Vec<_>>();
        if given.len() > 1 {
            return Err(f.err(
                given[1],
                "give one of `point`, `interface`, `block`, `bolt` and `crack`, not several",
            ));
        }
        for k in ["tip", "radii"] {
            if f.has(k) && !f.has("crack") {
                return Err(f.err(k, "belongs to a crack-tip monitor: give `crack` too"));
            }
        }
        let kind = match (f.has("point"), f.has("interface")) {
            _ if f.has("crack") => tip_monitor(&f, blocks, tol, (joints, cracks, h))?,
            _ if f.has("bolt") => {
                let name = f.req("bolt", string)?;
                let bolt = bolts
                    .iter()
                    .position(|b| b.name == name)
                    .ok_or_else(|| f.err("bolt", format!("unknown bolt {name:?}")))?;
                MonitorKind::Bolt { bolt }
            }
            _ if f.has("block") => {
                let name = f.req("block", string)?;
                let (set, _) = names
                    .get(name)
                    .ok_or_else(|| f.err("block", format!("unknown block {name:?}")))?;
                MonitorKind::Block {
                    blocks: set.to_vec(),
                }
            }
            (true, true) => unreachable!("refused above"),
            (false, false) => {
                return Err(f.err(
                    "point",
                    "missing: give one of `point`, `interface`, `block`, `bolt` and `crack`",
                ))
            }
            (true, false) => {
                let p = f.req("point", point)?;
                let block = blocks
                    .iter()
                    .position(|b| b.region().locate(p, tol) != Location::Outside)
                    .ok_or_else(|| {
                        f.err(
                            "point",
                            format!("point {} is not inside any block", fmt_point(p)),
                        )
                    })?;
                MonitorKind::Point { p, block }
            }
            (false, true) => {
                let (first, second, _, _) = block_pair(&f, "interface", names, false)?;
                MonitorKind::Interface { first, second }
            }
        };
        out.push(Monitor { name, kind });
    }
    Ok(out)
}

/// A crack-tip monitor: `crack` names the joint, `tip` a point within the cover size of one
/// of its crack tips (an end inside a block; a crack's mouth on a block edge is not a tip),
/// `radii` (optional, m) the integration ring (default [`TIP_RADII`] × h).
fn tip_monitor(
    f: &super::reader::Fields,
    blocks: &[Block],
    tol: f64,
    (joints, cracks, h): (&[Joint], &[Crack], f64),
) -> R<MonitorKind> {
    let jname = f.req("crack", string)?;
    let joint = joints
        .iter()
        .position(|j| j.name == jname)
        .ok_or_else(|| f.err("crack", format!("unknown joint {jname:?}")))?;
    let p = f.req("tip", point)?;
    let mut best: Option<(f64, usize, Vec2, Vec2)> = None;
    for c in cracks.iter().filter(|c| c.joint == joint) {
        let n = c.points.len();
        for (end, before) in [
            (c.points[0], c.points[1]),
            (c.points[n - 1], c.points[n - 2]),
        ] {
            if blocks[c.block].region().locate(end, tol) != Location::Inside {
                continue; // a mouth on the block's boundary
            }
            let d = crate::geometry::dist(end, p);
            if best.is_none_or(|b| d < b.0) {
                let t = crate::geometry::sub(end, before);
                let l = crate::geometry::norm(t);
                best = Some((d, c.block, end, [t[0] / l, t[1] / l]));
            }
        }
    }
    let Some((d, block, tip, dir)) = best else {
        return Err(f.err(
            "crack",
            format!("joint {jname:?} has no crack tip inside a block (its traces cut blocks through, or it ends on block edges)"),
        ));
    };
    if d > h {
        return Err(f.err(
            "tip",
            format!(
                "no tip of joint {jname:?} within the cover size {} of {}: the nearest is {}",
                fmt_num(h),
                fmt_point(p),
                fmt_point(tip)
            ),
        ));
    }
    let radii = match f.opt("radii", point)? {
        None => [TIP_RADII[0] * h, TIP_RADII[1] * h],
        Some(r) => {
            if !(r[0] > 0.0 && r[1] > r[0] && r[1].is_finite()) {
                return Err(f.err(
                    "radii",
                    format!(
                        "[r_in, r_out] must satisfy 0 < r_in < r_out, got {}",
                        fmt_point(r)
                    ),
                ));
            }
            r
        }
    };
    Ok(MonitorKind::Tip {
        block,
        joint,
        tip,
        dir,
        radii,
    })
}
