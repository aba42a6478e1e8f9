//! Assembly: local element work (`local`) and the global scatter into a fixed
//! sparse pattern (`global`), kept apart as in fenris.

pub mod global;
pub mod local;
pub mod quadratic;
