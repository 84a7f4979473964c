//! validation: reproduces the published tables (Ye & Xu 2010) from the project's data and writes
//! the reproducibility report. Each case is one module; `report` runs them and writes Markdown
//! and JSON.

pub mod clump_sweep;
pub mod convergence;
pub mod crush;
pub mod crush_column;
pub mod cutting_runs;
pub mod damping_studies;
pub mod environment;
pub mod error;
pub mod force_statistics;
pub mod page;
pub mod pictures;
pub mod plot;
pub mod removal_table;
pub mod report;
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
