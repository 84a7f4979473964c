//! validation: reproduces the published tables (Ye & Xu 2010) from the project's data and writes
//! the reproducibility report. Each case is one module; `report` runs them and writes Markdown
//! and JSON. It also holds the fuzz targets' bodies (`fuzz_targets`: every reader of a user's
//! file fed any bytes), which the fuzz crate hands to libFuzzer and a test replays in CI.

/// The repository this crate was built in (its data, pictures and git history): the report's
/// defaults when it runs outside it.
pub const REPOSITORY: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// `given` if the user named it; else `default` relative to the current folder when it exists
/// there, else relative to [`REPOSITORY`] (issue 48: run from another folder, the report
/// finished "without 6 section(s)").
pub fn project_path(given: Option<std::path::PathBuf>, default: &str) -> std::path::PathBuf {
    given.unwrap_or_else(|| {
        let here = std::path::PathBuf::from(default);
        if here.exists() {
            here
        } else {
            let there = std::path::Path::new(REPOSITORY).join(default);
            there.canonicalize().unwrap_or(there)
        }
    })
}

pub mod chung_ooi;
pub mod cli;
pub mod clump_sweep;
pub mod convergence;
pub mod crush;
pub mod crush_column;
pub mod cutting_runs;
pub mod damping_studies;
pub mod environment;
pub mod error;
pub mod force_statistics;
pub mod fuzz_targets;
pub mod page;
pub mod pictures;
pub mod plot;
pub mod removal_table;
pub mod report;
pub mod runs;
pub mod stability;
pub mod study;
pub mod study_findings;
pub mod study_row;
pub mod sweep_runs;
pub mod table1;
pub mod table2;
pub mod table2_section;
pub mod table2_why;
pub mod table3;
