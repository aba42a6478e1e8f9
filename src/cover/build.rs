//! Building the discretisation (to be written).
use super::Discretisation;
use crate::geometry::Vec2;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct DiscretiseError(pub String);

/// Discretise blocks `(vertices CCW, fixed)` with a mathematical mesh of size `h`.
pub fn discretise(
    _blocks: &[(Vec<Vec2>, bool)],
    _h: f64,
) -> Result<Discretisation, DiscretiseError> {
    Err(DiscretiseError("not yet written".into()))
}
