//! Cutting runs from a `dem sweep` folder (docs/sweep.md, "Table 2 on a cluster"): the runs
//! of Table 2 or of a study made elsewhere (a Slurm job array) as `dem sweep` cases, read
//! instead of run here.
//!
//! A case is matched to a [`Job`] by what it ran, not by its axes: `dem test cutting` writes
//! `cutting.inputs.json` (the generated specimen's parameters, the model and the test) into
//! its folder `DIR/cases/<key>/` before it starts, and a case whose three values serialise
//! to the job's key ([`crate::cutting_runs::key_of`]) is that job's run (the report's own
//! runs are such a folder too, [`crate::cutting_runs`]). A done case (`done.json` and `cutting.result.json`, as `dem sweep
//! status` counts it) is read as a finished run; a failed one (`failed.json`) is an error
//! naming it; a job without a done or failed case is listed as not run, as `--finished-only`
//! lists the runs not made yet.
//!
//! The report's own runs are such a folder too ([`crate::cutting_runs`]).

use crate::error::{Error, Result};
use crate::runs::{finished, key_of, key_text, Job, Outcome};
use dem_lab::cutting::{CuttingResult, Inputs, RESULT_FILE};
use serde::Deserialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The sweep's file names and the cut's inputs file, as `dem sweep` and `dem test cutting`
/// write them.
pub use dem_lab::cutting::INPUTS_FILE;
pub use dem_run::case::{CASES_FILE, DONE_FILE, FAILED_FILE};

/// One line of `cases.jsonl` (the fields read here).
#[derive(Deserialize)]
struct CaseLine {
    index: usize,
    key: String,
    test: String,
}

/// What a case's folder says.
enum CaseState {
    Done,
    Failed(String),
    NotDone,
}

/// A case whose inputs are known.
struct Found {
    index: usize,
    dir: PathBuf,
    state: CaseState,
}

/// The runs of `jobs` among the cases of the sweep folder `sweep` (see the module docs).
/// Errors: `cases.jsonl` unreadable or malformed (naming the file and line). A case whose
/// inputs or result cannot be read is an error of the outcome; the others go on.
pub fn read(jobs: &[Job], sweep: &Path, progress: &(dyn Fn(&str) + Sync)) -> Result<Outcome> {
    let file = sweep.join(CASES_FILE);
    let text = std::fs::read_to_string(&file).map_err(|source| Error::NotASweep {
        file: file.display().to_string(),
        source,
    })?;
    let mut out = Outcome::default();
    let mut by_key: HashMap<String, Found> = HashMap::new();
    let mut cases = 0usize;
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let c: CaseLine = serde_json::from_str(line).map_err(|source| Error::JsonLine {
            file: file.display().to_string(),
            line: i + 1,
            source,
        })?;
        if c.key.is_empty() || !c.key.bytes().all(|b| b.is_ascii_hexdigit()) {
            return Err(Error::BadCaseKey {
                file: file.display().to_string(),
                line: i + 1,
                key: c.key,
            });
        }
        cases += 1;
        if c.test != "cutting" {
            continue;
        }
        let dir = sweep.join("cases").join(&c.key);
        let inputs = dir.join(INPUTS_FILE);
        let Ok(text) = std::fs::read_to_string(&inputs) else {
            // Not started: nothing says what it runs.
            continue;
        };
        let key = match serde_json::from_str::<Inputs>(&text) {
            Ok(Inputs {
                specimen: Some(sp),
                model: Some(m),
                test,
                ..
            }) => key_text(&sp, &m, &test)?,
            Ok(_) => {
                // A cut of a given specimen file, or a model not known yet: no job's.
                continue;
            }
            Err(e) => {
                out.errors
                    .push(format!("case {} ({}): {e}", c.index, inputs.display()));
                continue;
            }
        };
        let state = if dir.join(DONE_FILE).is_file() && dir.join(RESULT_FILE).is_file() {
            CaseState::Done
        } else if dir.join(FAILED_FILE).is_file() {
            let why = dem_run::case::read_record(&dir.join(FAILED_FILE))
                .and_then(|r| r.reason())
                .unwrap_or_else(|| "failed".into());
            CaseState::Failed(why)
        } else {
            CaseState::NotDone
        };
        // Two cases with one key (a study that lists a value twice): the done one counts.
        let keep = match by_key.get(&key) {
            Some(f) => !matches!(f.state, CaseState::Done),
            None => true,
        };
        if keep {
            by_key.insert(
                key,
                Found {
                    index: c.index,
                    dir,
                    state,
                },
            );
        }
    }
    let mut used = 0usize;
    for job in jobs {
        let Some(f) = by_key.get(&key_of(job)) else {
            out.missing.push(job.name.clone());
            continue;
        };
        used += 1;
        match &f.state {
            CaseState::Done => {
                let rf = f.dir.join(RESULT_FILE);
                let res = std::fs::read_to_string(&rf)
                    .map_err(|e| e.to_string())
                    .and_then(|t| {
                        serde_json::from_str::<CuttingResult>(&t).map_err(|e| e.to_string())
                    });
                match res {
                    Ok(res) => {
                        let cpu = res.run.cpu_time_s;
                        out.finished.push(finished(job, res, &f.dir, cpu, true));
                    }
                    Err(e) => out.errors.push(format!(
                        "{}: sweep case {} ({}): {e}",
                        job.name,
                        f.index,
                        rf.display()
                    )),
                }
            }
            CaseState::Failed(why) => out.errors.push(format!(
                "{}: failed in the sweep (case {}, {}): {why}",
                job.name,
                f.index,
                f.dir.join(FAILED_FILE).display()
            )),
            CaseState::NotDone => out.missing.push(job.name.clone()),
        }
    }
    progress(&format!(
        "sweep {}: {cases} cases; of the {} runs {} done there, {} not done, {} errors; {} \
         cases are other runs or not started",
        sweep.display(),
        jobs.len(),
        out.finished.len(),
        out.missing.len(),
        out.errors.len(),
        cases - used.min(cases),
    ));
    Ok(out)
}
