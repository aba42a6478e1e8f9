//! Contact between blocks: broad phase, vertex–edge detection and friction laws.
//!
//! This module owns the *pure* parts of contact, each usable and tested alone:
//! * [`broad`]: which blocks may touch (sweep and prune on bounding boxes);
//! * [`narrow`]: which vertex of one boundary polyline touches which segment of
//!   another, with the signed gap (negative = penetration), the outward normal of
//!   the segment and its tangent;
//! * [`friction`]: the penalty normal law and Coulomb friction, by implicit
//!   return mapping (with the consistent, unsymmetric tangent) or by the
//!   conventional DDA rule, as pure functions of numbers;
//! * [`bonded`]: the bonded joint that breaks (Mohr–Coulomb with a tension cut-off,
//!   then residual friction), a pure function of numbers;
//! * [`law`]: the interface every law implements and the one registry of their names;
//! * [`generate`]: seeded geometry generators for benchmarks and tests.
//!
//! Sign conventions shared by all parts: `g_N < 0` is penetration,
//! `t_N = p_N g_N ≤ 0` is compression (`t_N > 0`, tension, only on a bonded
//! contact, [`bonded`]), normals point out of the block that owns the segment. The kinematics on the NMM covers and the contact set carried
//! over Newton iterations are built on top of these parts.

pub mod bonded;
pub mod broad;
pub mod friction;
pub mod generate;
pub mod law;
pub mod narrow;
pub mod restitution;
pub mod set;

pub use broad::sweep_and_prune;

/// What contact detection needs of a model — a narrow view, so that `contact` depends on
/// the interfaces and not on the whole model: which blocks are fixed, the joint that made
/// each face, the interface of a face, and the analysis' friction law. [`crate::model::Model`]
/// implements it.
pub trait InterfaceView: Sync {
    /// Whether block `b` is fixed.
    fn is_fixed(&self, b: usize) -> bool;
    /// Whether some interface can apply to contacts between blocks `a` and `b`.
    fn may_contact(&self, a: usize, b: usize) -> bool;
    /// The joint that made edge `edge` of block `b` (edges numbered over its loops), if any.
    fn face_joint(&self, b: usize, edge: usize) -> Option<usize>;
    /// The interface of a contact of a vertex of `vertex_block` on a face of `edge_block`
    /// made by `joint`: the joint's, else the pair's, else the default (`None`: no contact).
    fn interface_for_face(
        &self,
        vertex_block: usize,
        edge_block: usize,
        joint: Option<usize>,
    ) -> Option<&crate::model::Interface>;
    /// The analysis' friction law (an interface without its own law uses it).
    fn default_law(&self) -> law::LawId;
}

impl InterfaceView for crate::model::Model {
    fn is_fixed(&self, b: usize) -> bool {
        self.blocks[b].fixed
    }
    fn may_contact(&self, a: usize, b: usize) -> bool {
        crate::model::Model::may_contact(self, a, b)
    }
    fn face_joint(&self, b: usize, edge: usize) -> Option<usize> {
        self.blocks[b].edge_joint.get(edge).copied().flatten()
    }
    fn interface_for_face(
        &self,
        vertex_block: usize,
        edge_block: usize,
        joint: Option<usize>,
    ) -> Option<&crate::model::Interface> {
        crate::model::Model::interface_for_face(self, vertex_block, edge_block, joint)
    }
    fn default_law(&self) -> law::LawId {
        self.analysis.friction
    }
}
pub use friction::{
    commit_conventional, commit_return_mapping, conventional, return_mapping, ContactStatus,
    FrictionParams, LawResponse, ShearHistory,
};
pub use generate::brick_wall;
pub use law::{Branch, FrictionLaw, IterationContext, LawId, LawState, LAWS};
pub use narrow::{
    corner_flags, vertex_edge_contacts, vertex_edge_contacts_with, NarrowParams, VertexEdge,
};
