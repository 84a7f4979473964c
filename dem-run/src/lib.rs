//! dem-run: the run layer. A study file becomes planned cases (a `dem test` command line each,
//! keyed by its inputs), run here N at a time or as a Slurm job array, and collected into one
//! table; `dem sweep` (dem-cli), the report (validation) and the fuzz targets use it, so each
//! names a sweep's files and reads a study one way (docs/sweep.md).
//!
//! ```text
//! error    the layer's error: its kind and a message naming the file, line or field
//! process  this machine's name; whether a process of it still runs (run locks, claims)
//! study    a study file (dem.study/1): a test, base flags, axes, seeds → checked, parsed values
//! claim    which process runs a case: claim files per attempt, stale claims taken over
//! case     a planned case (one line of cases.jsonl), its folder DIR/cases/<key>/ and the
//!          files there (done.json, failed.json, log.txt), the state of a case on disk
//! plan     study → cases checked against the test's command line (TestCommands), keyed;
//!          study.json, cases.jsonl, slurm.sbatch written
//! runner   the cases not finished, N at a time, each a child process; done.json/failed.json
//! timing   the time a sweep took: CPU, wall, busy and span, overall and per axis value
//! collect  one row per case and aggregates over seeds (CSV, JSON); the status lines
//! ```
//!
//! Each module uses only those listed before it.

pub mod case;
pub mod claim;
pub mod collect;
pub mod error;
pub mod plan;
pub mod process;
pub mod runner;
pub mod study;
pub mod timing;

pub use error::{Error, ErrorKind, Result};

/// Writes `bytes` to `path` atomically (a temporary file renamed over it).
pub(crate) fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> Result<()> {
    clumpgen::io::write_atomic(path, bytes)
        .map_err(|e| Error::io(path, format!("cannot write: {e}")))
}
