//! Number of proptest cases: `PROPTEST_CASES` from the environment when set
//! (for long local soaks, e.g. `PROPTEST_CASES=100000`), else the suite's
//! default, sized to keep `cargo test --release` quick.

pub fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}
