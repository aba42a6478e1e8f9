//! Mathematical cover, physical covers and manifold elements.
//!
//! * **Mathematical mesh** ([`MathMesh`]): a regular triangular mesh of size h over the
//!   bounding box of all blocks. The *star* of a mesh node (its triangles) is a
//!   mathematical cover.
//! * **Physical covers** ([`PhysicalCover`]): each star intersected with each block falls
//!   apart into connected pieces; each piece is a physical cover with its own unknowns.
//! * **Manifold elements** ([`ManifoldElement`]): a mesh triangle ∩ a block, one element per
//!   connected piece (any simple polygon, possibly non-convex).
//! * **Cracks** ([`CoverCrack`], [`crack`]): traces ending inside a block split the elements
//!   they cross and the covers whose stars they separate; around a tip the covers stay
//!   connected.
//!
//! Weight functions are the triangle's linear shape functions (barycentric coordinates),
//! a partition of unity; cover functions are constants (order 0: `u(x) = Σ_k w_k(x) u_k`
//! over the element's three covers, the strain constant per element) or linear (order 1,
//! `[cover] order = 1`). The cover basis ([`basis::CoverBasis`], held by the
//! [`Discretisation`]) is the one place that knows a cover's unknowns and an element's
//! layout.

pub mod basis;
mod build;
pub mod crack;
pub mod dependence;
mod locate;
pub mod mesh;
mod removal;
pub mod slit;
pub mod stabilise;

pub use basis::CoverBasis;
pub use build::{
    discretise, discretise_cracked, discretise_on_mesh, discretise_on_mesh_cracked,
    discretise_on_mesh_with, discretise_shapes, discretise_shapes_on_mesh, discretise_through,
    discretise_with, DiscretiseError, Shape, MAX_MESH_NODES, MIN_PIECE_WIDTH,
};
pub use crack::CoverCrack;
pub use locate::{ElementIndex, LOCATE_TOL};
pub use mesh::MathMesh;
pub use slit::{Slit, SlitFace};

use crate::geometry::{cross, sub, Vec2};

/// Unknowns per physical cover of the constant basis (order 0: u_x, u_y); the
/// discretisation's own count is `Discretisation::basis.cover_dofs()`.
pub const COVER_DOFS: usize = 2;

#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalCover {
    /// Block the cover belongs to.
    pub block: usize,
    /// Mathematical mesh node whose star the cover is a piece of.
    pub node: usize,
    /// First global unknown (u_x of the constant term, U_0x; u_y is `dof + 1`), or `None`
    /// for covers of fixed blocks.
    pub dof: Option<usize>,
    /// The x unknown of each higher cover-function term (order 1: ξ, η; its y unknown is
    /// the next), [`basis::NO_DOF`] for a term removed for linear dependence
    /// ([`dependence`]); empty at order 0 and for covers of fixed blocks.
    pub terms: Vec<usize>,
    /// Area of the cover's support (sum of its elements' areas), m².
    pub support_area: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ManifoldElement {
    pub block: usize,
    /// Index of the mathematical mesh triangle.
    pub triangle: usize,
    /// Current positions of the triangle's three nodes as carried by this element
    /// (they move with the material: node k moves with cover `covers[k]`). CCW.
    pub nodes: [Vec2; 3],
    /// Physical cover (index into `Discretisation::covers`) for each triangle node.
    pub covers: [usize; 3],
    /// Current element polygon (triangle ∩ block piece), CCW.
    pub polygon: Vec<Vec2>,
}

impl ManifoldElement {
    /// Weight functions (barycentric coordinates of `x` in the element's triangle).
    pub fn weights(&self, x: Vec2) -> [f64; 3] {
        barycentric(&self.nodes, x)
    }
    /// Gradients ∇w_k of the weight functions (constant over the element).
    pub fn weight_gradients(&self) -> [Vec2; 3] {
        let [a, b, c] = self.nodes;
        let two_a = cross(sub(b, a), sub(c, a));
        [
            [(b[1] - c[1]) / two_a, (c[0] - b[0]) / two_a],
            [(c[1] - a[1]) / two_a, (a[0] - c[0]) / two_a],
            [(a[1] - b[1]) / two_a, (b[0] - a[0]) / two_a],
        ]
    }
}

/// Barycentric coordinates of `x` in triangle `t` (sum to 1; linear in x).
pub fn barycentric(t: &[Vec2; 3], x: Vec2) -> [f64; 3] {
    let [a, b, c] = *t;
    let two_a = cross(sub(b, a), sub(c, a));
    let w0 = cross(sub(b, x), sub(c, x)) / two_a;
    let w1 = cross(sub(c, x), sub(a, x)) / two_a;
    [w0, w1, 1.0 - w0 - w1]
}

/// A material point: an element and its (fixed) weights. Weights are invariant
/// under the element's affine motion, so the point's displacement is
/// `Σ_k w_k u_{covers[k]}` at every step (order 0; at order 1 the cover functions are
/// taken on the element's reference triangle, so the weights are all a point needs too:
/// [`basis`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialPoint {
    pub element: usize,
    pub weights: [f64; 3],
}

/// A vertex of a block's boundary, refined where the boundary crosses mesh edges,
/// so that each boundary segment lies in one manifold element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryVertex {
    /// Initial position.
    pub x0: Vec2,
    /// The vertex as a material point (any element that contains it).
    pub at: MaterialPoint,
    /// Whether this vertex is a corner of the block polygon (not a refinement point).
    pub corner: bool,
    /// Whether this vertex is the midpoint of a refined segment (first-order covers: the
    /// contacts integrate the interface by Simpson's rule, exact for their quadratic shape
    /// functions; see `contact/set.rs`).
    pub midpoint: bool,
}

/// A block's boundary: one or more loops of refined vertices, each with the material on
/// its left — the outer loop counter-clockwise, then one clockwise loop per hole
/// ([`crate::geometry::region`]) —, stored one after the other in `vertices`, loop `k`
/// starting at `loops[k]`. Segment i goes from vertex i to the next vertex of its loop
/// ([`BlockBoundary::next`]), lies in element `segment_elements[i]` and is a part of the
/// block's edge `segment_edges[i]` (edges numbered over the loops as `Block::edge_joint`:
/// edge k of the outer polygon joins its vertex k to k+1 mod n, then the holes' edges).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockBoundary {
    pub vertices: Vec<BoundaryVertex>,
    pub segment_elements: Vec<usize>,
    pub segment_edges: Vec<usize>,
    /// First vertex of each loop (`[0]` for a block without holes).
    pub loops: Vec<usize>,
}

impl BlockBoundary {
    /// The vertex after `i` on its loop.
    #[inline]
    pub fn next(&self, i: usize) -> usize {
        crate::geometry::region::loop_next(&self.loops, self.vertices.len(), i)
    }

    /// The vertex before `i` on its loop.
    #[inline]
    pub fn prev(&self, i: usize) -> usize {
        crate::geometry::region::loop_prev(&self.loops, self.vertices.len(), i)
    }
}

/// The NMM discretisation of a whole model.
#[derive(Debug, Clone, PartialEq)]
pub struct Discretisation {
    pub mesh: MathMesh,
    pub covers: Vec<PhysicalCover>,
    pub elements: Vec<ManifoldElement>,
    /// Elements of each block.
    pub block_elements: Vec<Vec<usize>>,
    /// Boundary of each block.
    pub boundaries: Vec<BlockBoundary>,
    /// Number of global unknowns.
    pub n_dofs: usize,
    /// The cover functions (`[cover] order`): the layout of every element's unknowns.
    pub basis: CoverBasis,
    /// Distance within which every point of a block has an element of that block:
    /// `LOCATE_TOL · h` plus the largest *reach* of a dropped piece (how far a dropped
    /// piece extends from the triangle edges through which it joins the rest of the
    /// block; ≤ its width for a sliver along a mesh line, a few 1e-5 h for the tip of a
    /// block corner just across a mesh line). Point searches accept elements this close.
    pub locate_tol: f64,
    /// The cracks that split the covers (empty for a model without cracks).
    pub cracks: Vec<CoverCrack>,
    /// The faces of every crack ([`slit`]), block by block: contact faces of a block with
    /// itself.
    pub slits: Vec<Slit>,
}
