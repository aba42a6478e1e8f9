//! The validated model: what the rest of the program sees. Every name is
//! resolved to an index, every polygon is counter-clockwise, every number is
//! finite and in range.

use crate::geometry::Vec2;

/// A one-line input error: `"<place>: <reason>"`, e.g.
/// `[[block]] "slider": key `vertices`: polygon self-intersects (edges 1 and 3)`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct ModelError(pub String);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Newmark β = 0.5, γ = 1.
    Dynamic,
    /// DDA's quasi-static analysis: the velocity is reset to zero at the start of every step.
    Static,
}

/// The contact law `[analysis] friction` names (a law of the registry,
/// [`crate::contact::law::LAWS`]): `"return-mapping"` (the default: implicit return mapping
/// with the consistent tangent) or `"conventional"` (the classical open–close treatment,
/// which overshoots the strength within a step).
pub use crate::contact::law::LawId;

#[derive(Debug, Clone, PartialEq)]
pub struct Analysis {
    pub mode: Mode,
    pub dt: f64,
    pub steps: usize,
    pub gravity: Vec2,
    pub friction: LawId,
    pub output_every: usize,
    /// Extension: Newton iteration limit per step (default 25).
    pub max_iterations: usize,
    /// Extension: relative tolerance on the residual and on the increment (default 1e-9).
    pub tolerance: f64,
    /// Extension: how many times a step that does not converge may be halved (default 6).
    pub max_step_cuts: usize,
    /// Extension: penalty factor for `[[constraint]]`: point springs get
    /// `factor × E_max` (N/m), edge springs `factor × E_max / h` (N/m² per m) (default 1e6).
    pub constraint_penalty: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    Strain,
    Stress,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    pub density: f64,
    pub young: f64,
    pub poisson: f64,
    pub plane: Plane,
    /// Extension: Rayleigh damping of the material (zero: undamped).
    pub damping: Rayleigh,
}

/// Rayleigh (proportional) damping C = α M + β K of one material, in the material's own
/// elements (contact and constraint penalty springs are not damped).
///
/// A mode of angular frequency ω gets the damping ratio ζ(ω) = α/(2ω) + βω/2: the mass
/// term damps low frequencies, the stiffness term high ones.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Rayleigh {
    /// Mass-proportional coefficient α (1/s), ≥ 0.
    pub alpha: f64,
    /// Stiffness-proportional coefficient β (s), ≥ 0.
    pub beta: f64,
}

impl Rayleigh {
    /// The α, β that give the damping ratio `zeta` at the two frequencies `f1`, `f2` (Hz):
    /// with ω_i = 2π f_i, α = 2ζ ω₁ω₂/(ω₁ + ω₂) and β = 2ζ/(ω₁ + ω₂). Between the two
    /// frequencies ζ(ω) is below `zeta`, outside them above. With f₁ = f₂ = f, ζ(ω) has
    /// its minimum `zeta` at f.
    pub fn from_ratio(zeta: f64, f1: f64, f2: f64) -> Rayleigh {
        let (w1, w2) = (std::f64::consts::TAU * f1, std::f64::consts::TAU * f2);
        Rayleigh {
            alpha: 2.0 * zeta * w1 * w2 / (w1 + w2),
            beta: 2.0 * zeta / (w1 + w2),
        }
    }

    /// The damping ratio ζ(ω) = α/(2ω) + βω/2 of a mode of angular frequency `omega` (rad/s).
    pub fn ratio_at(&self, omega: f64) -> f64 {
        self.alpha / (2.0 * omega) + self.beta * omega / 2.0
    }

    /// Whether the material is damped at all.
    pub fn is_zero(&self) -> bool {
        self.alpha == 0.0 && self.beta == 0.0
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// The `[[block]]` name, or `NAME.k` for the k-th piece of a block cut by joints.
    pub name: String,
    /// Index into `Model::materials`.
    pub material: usize,
    /// Simple polygon, counter-clockwise (re-oriented if given clockwise).
    pub vertices: Vec<Vec2>,
    pub fixed: bool,
    /// Per polygon edge (edge i joins vertex i to vertex i+1 mod n): the joint (index into
    /// `Model::joints`) whose trace made this face, `None` for a face of the block as drawn.
    pub edge_joint: Vec<Option<usize>>,
    /// For a piece of a cut block: the name of the `[[block]]` it was cut from.
    pub parent: Option<String>,
    /// Holes (`[[block]] holes`, or left by a closed loop of joint traces that cut out the
    /// pieces inside it): simple polygons, clockwise (the material on the left of every
    /// loop, [`crate::geometry::region`]). `edge_joint` goes on over their edges, hole after
    /// hole, after the outer polygon's.
    pub holes: Vec<Vec<Vec2>>,
}

impl Block {
    /// The block as a region: its polygon and its holes.
    pub fn region(&self) -> crate::geometry::region::Region<'_> {
        crate::geometry::region::Region {
            outer: &self.vertices,
            holes: &self.holes,
        }
    }

    /// The edges (a, b) over all loops, in the order of `edge_joint`.
    pub fn edges(&self) -> impl Iterator<Item = (Vec2, Vec2)> + '_ {
        self.region()
            .loops()
            .flat_map(|l| (0..l.len()).map(move |k| (l[k], l[(k + 1) % l.len()])))
    }

    /// Area, m² (the holes' taken out).
    pub fn area(&self) -> f64 {
        if self.holes.is_empty() {
            crate::geometry::polygon::signed_area(&self.vertices)
        } else {
            self.region().area()
        }
    }
}

/// `[initial_stress]`: the stress of every block before the first step (tension
/// positive, as in the VTK output), σ(y) = `stress` + (y − `y_ref`) `gradient`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InitialStress {
    /// [σxx, σyy, τxy] at y = `y_ref`, Pa.
    pub stress: [f64; 3],
    /// d[σxx, σyy, τxy]/dy, Pa/m.
    pub gradient: [f64; 3],
    pub y_ref: f64,
}

impl InitialStress {
    /// [σxx, σyy, τxy] at height `y`.
    pub fn at(&self, y: f64) -> [f64; 3] {
        let dy = y - self.y_ref;
        std::array::from_fn(|k| self.stress[k] + dy * self.gradient[k])
    }
}

/// A `[[joint_set]]` or a `[[joint]]`, after validation. Its index in `Model::joints`
/// (the sets in file order, then the joints in file order) is its id in
/// `Block::edge_joint`, cracks and outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
}

#[derive(Debug, Clone, PartialEq)]
pub enum JointKind {
    /// Parallel traces: lines at `angle` (degrees from +x, counter-clockwise, in [0, 180)),
    /// `spacing` apart (normal distance), one through `origin`.
    Set {
        angle: f64,
        spacing: f64,
        origin: Vec2,
        /// Non-persistent traces: `(trace_length, bridge)` along each line, the first
        /// trace starting at the foot of `origin` on the line.
        pattern: Option<(f64, f64)>,
    },
    /// One mapped joint: a polyline.
    Polyline { points: Vec<Vec2> },
}

/// A part of one trace that ends inside a block (it does not split it). Kept as data:
/// the analysis does not model cracks yet.
#[derive(Debug, Clone, PartialEq)]
pub struct Crack {
    /// Index into `Model::blocks`.
    pub block: usize,
    /// Index into `Model::joints`.
    pub joint: usize,
    /// The crack as a polyline (at least two points).
    pub points: Vec<Vec2>,
}

/// A piece smaller than `[cover] min_block_area` that was merged into a neighbour, or a
/// region enclosed by a loop of traces that would pinch the block around it (kept as part
/// of that block; its loop is a crack).
#[derive(Debug, Clone, PartialEq)]
pub struct MergedPiece {
    /// The block (index into `Model::blocks`) it is now part of.
    pub block: usize,
    pub area: f64,
    pub centroid: Vec2,
    /// For a merge: the joint (index into `Model::joints`) it bridges — a joint face it
    /// crossed goes on past it as a face of other blocks —, if any.
    pub bridges: Option<usize>,
}

/// Which contacts an interface applies to.
#[derive(Debug, Clone, PartialEq)]
pub enum InterfaceScope {
    /// Every pair of blocks without its own interface (no `blocks`, no `joint`).
    Default,
    /// `blocks = ["a", "b"]`: every pair of distinct blocks (x, y), x in the first set and
    /// y in the second (either order). A set holds one block, or all pieces of a cut
    /// block. Sorted indices into `Model::blocks`.
    Blocks(Vec<usize>, Vec<usize>),
    /// `joint = "name"`: faces made by this joint (index into `Model::joints`).
    Joint(usize),
}

impl InterfaceScope {
    /// Whether the scope is a block pair covering blocks `a` and `b` (a ≠ b).
    pub fn covers_pair(&self, a: usize, b: usize) -> bool {
        match self {
            InterfaceScope::Blocks(x, y) => {
                a != b
                    && ((x.binary_search(&a).is_ok() && y.binary_search(&b).is_ok())
                        || (x.binary_search(&b).is_ok() && y.binary_search(&a).is_ok()))
            }
            _ => false,
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Interface {
    pub scope: InterfaceScope,
    pub friction_angle: f64,
    pub cohesion: f64,
    pub normal_penalty: f64,
    pub shear_penalty: f64,
    /// Restitution of impacts e (rebound speed / impact speed, 0 < e ≤ 1): a normal dashpot
    /// calibrated against the time integration ([`crate::contact::restitution`]); `None`:
    /// no dashpot (the impacts lose only what the time integration takes).
    pub restitution: Option<f64>,
    /// The law this interface selects by its own keys (e.g. `tensile_strength`: the bonded
    /// law), with their values; `None`: the analysis' `friction`.
    pub law: Option<InterfaceLaw>,
}

/// A law an `[[interface]]` selects by setting its own keys, with the values of those keys
/// (checked and defaulted by the law, in the order of its keys).
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceLaw {
    pub law: LawId,
    pub values: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq)]
pub enum LoadKind {
    /// Traction (Pa) on a segment of the block's boundary.
    Edge { a: Vec2, b: Vec2, traction: Vec2 },
    /// Point force (N per metre of thickness).
    Point { p: Vec2, force: Vec2 },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    pub block: usize,
    pub kind: LoadKind,
}

/// A prescribed displacement component as a function of time.
#[derive(Debug, Clone, PartialEq)]
pub enum TimeFunction {
    Constant(f64),
    /// Rows `(t, value)`, strictly increasing t, linear in between, constant outside.
    Table(Vec<(f64, f64)>),
}

impl TimeFunction {
    pub fn eval(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant(v) => *v,
            TimeFunction::Table(rows) => interpolate(rows, t),
        }
    }
}

/// Piecewise-linear interpolation in rows `(t, v)` sorted by t; constant outside.
pub fn interpolate(rows: &[(f64, f64)], t: f64) -> f64 {
    match rows.len() {
        0 => 0.0,
        1 => rows[0].1,
        _ => {
            if t <= rows[0].0 {
                return rows[0].1;
            }
            if t >= rows[rows.len() - 1].0 {
                return rows[rows.len() - 1].1;
            }
            let i = rows.partition_point(|r| r.0 <= t).max(1) - 1;
            let (t0, v0) = rows[i];
            let (t1, v1) = rows[i + 1];
            v0 + (v1 - v0) * (t - t0) / (t1 - t0)
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum ConstraintGeometry {
    Edge { a: Vec2, b: Vec2 },
    Point { p: Vec2 },
}

#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    pub block: usize,
    pub geometry: ConstraintGeometry,
    /// `None`: that component is free.
    pub ux: Option<TimeFunction>,
    pub uy: Option<TimeFunction>,
}

/// The base acceleration: per axis (x, y), samples `(t, a)` in m/s² as applied (window,
/// `scale` or `pga`), t from the motion's t = 0, strictly increasing; an empty axis has
/// no motion. Each axis is linear between its samples and zero outside them.
#[derive(Debug, Clone, PartialEq)]
pub struct BaseMotion {
    pub axes: [Vec<[f64; 2]>; 2],
    /// What each record was as read and as applied (`nmm check`).
    pub records: Vec<RecordInfo>,
}

/// One base-motion record as read and as applied.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordInfo {
    /// The axes it drives: "x", "y" or "x, y".
    pub axis: String,
    /// The file as written in the model, or "table".
    pub source: String,
    /// Samples as read.
    pub samples: usize,
    /// Smallest and largest interval between samples as read, s.
    pub dt: (f64, f64),
    /// Times of the first and last sample as read, s.
    pub span: (f64, f64),
    /// Peak |a| as read (the record's own units converted, before `scale`/`pga`), m/s²,
    /// per axis [x, y].
    pub pga_read: [f64; 2],
    /// The window used: from `start` (the motion's t = 0), `duration` long, s.
    pub start: f64,
    pub duration: f64,
    /// The factor applied (`scale`, or the one `pga` asks for).
    pub scale: f64,
    /// Peak |a| of the part used, as applied, m/s², per axis [x, y].
    pub pga_applied: [f64; 2],
}

impl BaseMotion {
    /// A motion from samples `(t, ax, ay)` driving both axes (no record information).
    pub fn from_samples(samples: &[[f64; 3]]) -> BaseMotion {
        BaseMotion {
            axes: [
                samples.iter().map(|s| [s[0], s[1]]).collect(),
                samples.iter().map(|s| [s[0], s[2]]).collect(),
            ],
            records: Vec::new(),
        }
    }

    /// Base acceleration at time t: per axis linear between samples, zero outside them.
    pub fn accel(&self, t: f64) -> Vec2 {
        [axis_at(&self.axes[0], t), axis_at(&self.axes[1], t)]
    }
}

fn axis_at(s: &[[f64; 2]], t: f64) -> f64 {
    if s.is_empty() || t < s[0][0] || t > s[s.len() - 1][0] {
        return 0.0;
    }
    let i = s.partition_point(|r| r[0] <= t);
    if i == 0 {
        return s[0][1];
    }
    if i >= s.len() {
        return s[s.len() - 1][1];
    }
    let (a, b) = (s[i - 1], s[i]);
    a[1] + (t - a[0]) / (b[0] - a[0]) * (b[1] - a[1])
}

#[derive(Debug, Clone, PartialEq)]
pub enum MonitorKind {
    /// A material point, in block `block` (the first block that contains it).
    Point { p: Vec2, block: usize },
    /// Total contact force on the blocks `first` from the blocks `second` (sorted, disjoint
    /// sets of indices: one block, or all pieces of a cut block).
    Interface {
        first: Vec<usize>,
        second: Vec<usize>,
    },
    /// A block (or every piece of a cut block): the displacement of its centroid and its
    /// mean rotation.
    Block { blocks: Vec<usize> },
    /// A rock bolt (index into `Model::bolts`): its axial force and elongation.
    Bolt { bolt: usize },
    /// A crack tip: the stress intensity factors K_I, K_II by the interaction integral
    /// over the ring `radii[0] < r < radii[1]` of block `block`'s elements around `tip`
    /// ([`crate::fracture`]); `dir` is the crack's unit direction at the tip, pointing ahead
    /// of it; `joint` the joint whose crack it is.
    Tip {
        block: usize,
        joint: usize,
        tip: Vec2,
        dir: Vec2,
        radii: [f64; 2],
    },
}

/// Default inner and outer radii of a crack-tip monitor's integration ring, × the cover
/// size h (`[[monitor]] radii` overrides them).
pub const TIP_RADII: [f64; 2] = [3.0, 8.0];

#[derive(Debug, Clone, PartialEq)]
pub struct Monitor {
    pub name: String,
    pub kind: MonitorKind,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub analysis: Analysis,
    /// Mathematical mesh size h (m).
    pub cover_size: f64,
    /// `[cover] origin`: a point the mathematical mesh passes through (a mesh node);
    /// `None`: the default placement (h/2 below and left of the model's box).
    pub cover_origin: Option<Vec2>,
    /// `[cover] order`: the polynomial order of the cover functions, 0 (constant, the
    /// default) or 1 (first-order covers: 6 unknowns per cover).
    pub cover_order: usize,
    pub materials: Vec<Material>,
    pub blocks: Vec<Block>,
    pub interfaces: Vec<Interface>,
    pub loads: Vec<Load>,
    pub constraints: Vec<Constraint>,
    pub base_motion: Option<BaseMotion>,
    pub monitors: Vec<Monitor>,
    /// `[[joint_set]]` then `[[joint]]` tables, in file order.
    pub joints: Vec<Joint>,
    /// Traces that end inside a block (phase A: data only).
    pub cracks: Vec<Crack>,
    /// Pieces merged because they were smaller than `[cover] min_block_area`.
    pub merged: Vec<MergedPiece>,
    /// Regions enclosed by loops of traces that would pinch the block around them (a loop
    /// hanging from the rest by one vertex, or touching another loop at one): they stay
    /// part of that block; their loops are cracks. (A loop that touches nothing else cuts
    /// out the pieces inside it.)
    pub enclosed: Vec<MergedPiece>,
    /// Pieces smaller than `[cover] min_block_area` kept as they are because every merge
    /// would have bridged a joint (`block` is the piece itself).
    pub kept_small: Vec<MergedPiece>,
    /// `[cover] min_block_area` (m²), if given.
    pub min_block_area: Option<f64>,
    /// `[[stage]]` tables in file order (empty: the model is one stage, `analysis`).
    pub stages: Vec<Stage>,
    /// `[initial_stress]`, if given.
    pub initial_stress: Option<InitialStress>,
    /// `[[bolt]]` tables in file order (the last field: see
    /// `simulation::checkpoint::model_fingerprint`).
    pub bolts: Vec<Bolt>,
}

/// A `[[bolt]]`: an elastic–perfectly plastic axial member between two material points
/// ([`crate::bolt`] has its law). Forces per metre of thickness, like every force of the
/// model.
#[derive(Debug, Clone, PartialEq)]
pub struct Bolt {
    pub name: String,
    /// Its two anchors as written (initial positions).
    pub points: [Vec2; 2],
    /// The block of each anchor (index into `Model::blocks`: the first that holds it).
    pub blocks: [usize; 2],
    /// Axial stiffness k, N/m (> 0).
    pub stiffness: f64,
    /// Yield force F_y, N (> 0), in tension and in compression.
    pub capacity: f64,
    /// The force at installation, N (0 ≤ N₀ ≤ F_y).
    pub pretension: f64,
    /// The stage at whose start it is installed (index into `Model::stages`); `None`: from
    /// the start of the analysis.
    pub stage: Option<usize>,
}

/// One `[[stage]]`: a part of the analysis with its own keys (those it does not set come
/// from `[analysis]`). `step` and `time` continue across stages.
#[derive(Debug, Clone, PartialEq)]
pub struct Stage {
    pub name: String,
    /// The stage's analysis keys, resolved.
    pub analysis: Analysis,
    /// The base-motion record applies in this stage, its t = 0 at the stage's start.
    pub base_motion: bool,
    /// `excavate`: the blocks (indices into `Model::blocks`, sorted) removed at the start
    /// of this stage.
    pub excavate: Vec<usize>,
}

impl Model {
    /// The interface properties for a pair of blocks: the pair's own, else the default.
    pub fn interface_for(&self, a: usize, b: usize) -> Option<&Interface> {
        self.interfaces
            .iter()
            .find(|i| i.scope.covers_pair(a, b))
            .or_else(|| {
                self.interfaces
                    .iter()
                    .find(|i| i.scope == InterfaceScope::Default)
            })
    }

    /// The interface for a contact of a vertex of block `vertex_block` against a face of
    /// block `edge_block` made by joint `edge_joint` (`None`: a face of the block as
    /// drawn). Precedence: the joint's interface, else the pair's, else the default.
    pub fn interface_for_face(
        &self,
        vertex_block: usize,
        edge_block: usize,
        edge_joint: Option<usize>,
    ) -> Option<&Interface> {
        edge_joint
            .and_then(|j| {
                self.interfaces
                    .iter()
                    .find(|i| i.scope == InterfaceScope::Joint(j))
            })
            .or_else(|| self.interface_for(vertex_block, edge_block))
    }

    /// Whether some interface can apply to contacts between blocks `a` and `b`.
    pub fn may_contact(&self, a: usize, b: usize) -> bool {
        self.interface_for(a, b).is_some()
            || (self
                .interfaces
                .iter()
                .any(|i| matches!(i.scope, InterfaceScope::Joint(_)))
                && (self.blocks[a].edge_joint.iter().any(Option::is_some)
                    || self.blocks[b].edge_joint.iter().any(Option::is_some)))
    }
}
