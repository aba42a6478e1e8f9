//! The mathematical mesh (to be written).
/// Regular triangular mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct MathMesh {
    pub origin: crate::geometry::Vec2,
    pub h: f64,
    pub nx: usize,
    pub ny: usize,
}
