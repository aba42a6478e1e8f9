//! The verification set: cases compared with closed forms or independent references
//! (`cases`), used by the integration tests at full size and by `nmm verify`.

pub mod cases;
