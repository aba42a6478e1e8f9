//! The model file (TOML) → a validated [`Model`].
//!
//! All input errors are found here, before any computation, and reported as a
//! one-line [`ModelError`] naming the table, key and block. The stable core of
//! the format is documented in `docs/model-format.md`.

mod types;
pub use types::*;
