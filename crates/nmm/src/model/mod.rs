//! The model file (TOML) → a validated [`Model`].
//!
//! All input errors are found here, before any computation, and reported as a
//! one-line [`ModelError`] naming the table, key and block, e.g.
//! `[[block]] "slider": key `vertices`: polygon self-intersects (edges 1 and 3)`.
//! The full format is documented in `docs/model-format.md`.
//!
//! Pipeline: the text is parsed into a generic TOML tree (syntax errors carry
//! line and column) and, for the line numbers of tables and keys in later
//! errors, into a span-keeping `toml_edit` document ([`lines`]);
//! [`reader`] gives typed, finite, located access to its
//! values and refuses unknown keys; [`validate`] checks ranges, resolves
//! names to indices, checks the geometry (simple, non-degenerate,
//! non-overlapping polygons re-oriented counter-clockwise; load and
//! constraint segments on block boundaries) at the tolerance
//! `1e-9 × (bounding-box diagonal of all blocks)`.
//!
//! A valid model that is likely to mislead (nothing holds it, lengths in mm, a normal
//! penalty far from E) gets one-line [`warnings`], never an error.

mod bolts;
mod insitu;
mod joints;
mod lines;
mod reader;
mod types;
mod validate;
pub mod warnings;
pub use joints::DEFAULT_MAX_BLOCKS;
pub use reader::MAX_COORD;
pub use types::*;
pub use validate::REL_TOL;
pub use warnings::warnings;

use std::path::Path;

/// Read and validate a model file.
pub fn load_model(path: &Path) -> Result<Model, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        reader::error(format!(
            "{}: cannot read the model file: {e}",
            path.display()
        ))
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_model_named(&text, dir, &path.display().to_string())
}

/// Parse and validate model text; `base_dir` resolves relative file names (base motion records).
/// Syntax errors are attributed to `model.toml`.
pub fn parse_model(text: &str, base_dir: &Path) -> Result<Model, ModelError> {
    parse_model_named(text, base_dir, "model.toml")
}

/// As [`parse_model`], naming the source (a file name) in TOML syntax errors.
pub fn parse_model_named(text: &str, base_dir: &Path, source: &str) -> Result<Model, ModelError> {
    let root: toml::Table =
        toml::from_str(text).map_err(|e| reader::syntax_error(source, text, &e))?;
    validate::build(&lines::Doc::new(&root, source, text), base_dir)
}

#[cfg(test)]
mod tests;
