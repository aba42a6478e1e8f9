//! The verification set: cases compared with closed forms or independent references
//! (`cases`), used by the integration tests at full size and by `nmm verify`.

pub mod cases;
pub mod report;

/// The independent rigid-block reference (Newmark 1965), shared with the tests: it uses
/// no `nmm` code.
pub mod newmark_sliding;
