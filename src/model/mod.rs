//! The model file (TOML) → a validated [`Model`].
//!
//! All input errors are found here, before any computation, and reported as a
//! one-line [`ModelError`] naming the table, key and block. The stable core of
//! the format is documented in `docs/model-format.md`.

mod types;
pub use types::*;

use std::path::Path;

/// Read and validate a model file.
pub fn load_model(path: &Path) -> Result<Model, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        ModelError(format!(
            "{}: cannot read the model file: {e}",
            path.display()
        ))
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    parse_model(&text, dir)
}

/// Parse and validate model text; `base_dir` resolves relative file names (base motion records).
pub fn parse_model(_text: &str, _base_dir: &Path) -> Result<Model, ModelError> {
    Err(ModelError("model parsing is not yet written".into()))
}
