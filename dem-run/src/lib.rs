//! dem-run: the run layer's files, shared by `dem sweep` (dem-cli), the report (validation)
//! and the fuzz targets, so that each names a sweep's files and reads a study one way.
//!
//! ```text
//! process  this machine's name; whether a process of it still runs (run locks, claims)
//! study  a study file (dem.study/1): a test, base flags, axes, seeds → checked, parsed values
//! claim  which process runs a case: claim files per attempt, stale claims taken over
//! case   a planned case (one line of cases.jsonl), its folder DIR/cases/<key>/ and the files
//!        there (done.json, failed.json, log.txt), the state of a case on disk
//! ```
//!
//! Each module uses only those listed before it. The planner, runner and collector are in
//! dem-cli (`dem sweep plan|run|status|collect`, docs/sweep.md).

pub mod case;
pub mod claim;
pub mod process;
pub mod study;
