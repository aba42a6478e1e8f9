//! Base motion records (to be written): CSV, PEER NGA `.AT2`, K-NET/KiK-net ASCII.
use std::path::Path;

/// Read a record file into samples `(t, ax, ay)` in m/s² (scale factors of the
/// record's own header applied; the user's `scale` is applied by the caller).
/// `format`: `Some("csv" | "peer" | "knet")`, or `None` to infer from the file.
/// `component`: which axis a single-component record drives (`"x"` or `"y"`).
pub fn read_record(
    path: &Path,
    _format: Option<&str>,
    _component: &str,
) -> Result<Vec<[f64; 3]>, String> {
    Err(format!(
        "{}: record reading is not yet written",
        path.display()
    ))
}
