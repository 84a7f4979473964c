//! A planned case (one line of `DIR/cases.jsonl`) and the files of its folder
//! `DIR/cases/<key>/`: `done.json` and `failed.json` (written atomically by `dem sweep run`),
//! `log.txt`, the claims (`claim.<g>`, [`crate::claim`]) and the test's own outputs.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub const STUDY_FILE: &str = "study.json";
pub const CASES_FILE: &str = "cases.jsonl";
pub const SBATCH_FILE: &str = "slurm.sbatch";
pub const DONE_FILE: &str = "done.json";
pub const FAILED_FILE: &str = "failed.json";
pub const LOG_FILE: &str = "log.txt";

/// One case: `dem <argv> --out DIR/cases/<key> --threads T`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    pub index: usize,
    /// Hex SHA-256 of the resolved inputs (test, flags, contents of the files named).
    pub key: String,
    /// `cutting`, `ucs`, ...
    pub test: String,
    /// This case's axis values, in axis order: `[flag, value]`.
    pub axes: Vec<(String, String)>,
    /// Arguments after `dem` (`test cutting --depth 1mm ...`), without `--out`/`--threads`.
    pub argv: Vec<String>,
}

impl Case {
    pub fn dir(&self, sweep: &Path) -> PathBuf {
        sweep.join("cases").join(&self.key)
    }

    /// `<test>.result.json` in the case folder.
    pub fn result_file(&self, sweep: &Path) -> PathBuf {
        self.dir(sweep).join(format!("{}.result.json", self.test))
    }

    /// `depth=1mm, seed=2`.
    pub fn label(&self) -> String {
        let v: Vec<String> = self.axes.iter().map(|(f, v)| format!("{f}={v}")).collect();
        if v.is_empty() {
            "base".into()
        } else {
            v.join(", ")
        }
    }
}

/// What `done.json` and `failed.json` hold (the last attempt).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Record {
    pub index: usize,
    pub key: String,
    /// Exit code; `None` when ended by a signal.
    pub exit_code: Option<i32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub signal: Option<i32>,
    /// Wall time of the attempt (s).
    pub wall_s: f64,
    /// User + system CPU time of the case's process (s; `None` where unknown).
    pub cpu_s: Option<f64>,
    pub host: String,
    /// Unix time (s) at the end.
    pub finished_unix: u64,
    /// failed.json: why, and the last lines of the log.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub log_tail: Vec<String>,
}

/// The line of a failed case's log that says why: the last `error:` line (a usage error's is
/// followed by clap's "For more information, try '--help'."), else the last line.
pub fn reason_line(tail: &[String]) -> Option<&String> {
    tail.iter()
        .rev()
        .find(|l| l.starts_with("error:"))
        .or(tail.last())
}

impl Record {
    /// Why the attempt failed: the error and the log's line that says why ("exit code 1:
    /// error: …"); `None` for a case done.
    pub fn reason(&self) -> Option<String> {
        let e = self.error.as_ref()?;
        Some(match reason_line(&self.log_tail) {
            Some(l) => format!("{e}: {l}"),
            None => e.clone(),
        })
    }
}

/// Reads `DIR/cases.jsonl`, naming the line of a bad one.
pub fn read_cases(sweep: &Path) -> Result<Vec<Case>> {
    let file = sweep.join(CASES_FILE);
    let text = clumpgen::io::read_input_string(&file).map_err(|e| {
        Error::io(
            &file,
            format!(
                "{e} (plan the sweep first: dem sweep plan STUDY --out {})",
                sweep.display()
            ),
        )
    })?;
    let mut cases = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let c: Case = serde_json::from_str(line)
            .map_err(|e| Error::input(format!("{}: line {}: {e}", file.display(), i + 1)))?;
        if c.index != cases.len() || !valid_key(&c.key) {
            return Err(Error::input(format!(
                "{}: line {}: index {} or key {:?} out of order or malformed",
                file.display(),
                i + 1,
                c.index,
                c.key
            )));
        }
        cases.push(c);
    }
    Ok(cases)
}

fn valid_key(k: &str) -> bool {
    k.len() == 64 && k.bytes().all(|b| b.is_ascii_hexdigit())
}

/// A record file of a case (`done.json` / `failed.json`), if present and readable.
pub fn read_record(path: &Path) -> Option<Record> {
    let text = std::fs::read_to_string(path).ok()?;
    serde_json::from_str(&text).ok()
}

/// The state of a case on disk.
#[derive(Debug, Clone)]
pub enum State {
    Done(Record),
    Failed(Record),
    /// Claimed by a live process: `host:pid`.
    Running(String),
    Pending,
}

impl State {
    pub fn name(&self) -> &'static str {
        match self {
            State::Done(_) => "done",
            State::Failed(_) => "failed",
            State::Running(_) => "running",
            State::Pending => "pending",
        }
    }
}

/// Done = `done.json` and the result file; failed = `failed.json`; running = a live claim.
pub fn state(c: &Case, sweep: &Path) -> State {
    let dir = c.dir(sweep);
    if let Some(r) = read_record(&dir.join(DONE_FILE)) {
        if c.result_file(sweep).is_file() {
            return State::Done(r);
        }
    }
    if let Some(h) = crate::claim::live_holder(&dir) {
        return State::Running(h);
    }
    if let Some(r) = read_record(&dir.join(FAILED_FILE)) {
        return State::Failed(r);
    }
    State::Pending
}
