//! The fuzz targets' bodies live in the project's workspace, `validation::fuzz_targets`, so
//! that stable `cargo test` replays their seeds and former crashes (validation/tests/
//! fuzz_regressions.rs) without including this crate's files; `fuzz_targets/*.rs` call them.

pub use validation::fuzz_targets::*;
