//! The cutting runs behind Table 2, the convergence study and the cutting studies, as the cases
//! of a `dem sweep` folder (dem-run, docs/sweep.md): one experiment system for the CLI and the
//! report. Each [`Job`] (specimen parameters, model, test: typed values) is written as its
//! [`Inputs`] file `<work>/inputs/<name>.json`; the study `<work>/study.json` has one axis,
//! `--inputs` over those files, and is planned into `<work>` (`cases.jsonl`, keyed by the
//! files' content); the cases not done run here ([`dem_run::runner`] with an in-process
//! executor, one case per worker thread, each on a one-thread pool: small systems run best on
//! one core, and results do not depend on the thread count), and every job's case is read
//! back by its inputs ([`crate::sweep_runs::read`]). Specimens are generated once per
//! parameter set into `<work>/specimens/`.
//!
//! **Resuming**: a case with `done.json` and its result is read back, not run again, so a long
//! report (the full Table 2 is ~120 runs) can be stopped and continued, or built up over
//! several sessions; the same folder runs with `dem sweep run <work> --jobs N` or as a Slurm
//! array (`slurm.sbatch`), each case being `dem test cutting --inputs inputs/<name>.json`.
//! A job whose inputs change (the code's defaults, say) is a new case; the old case's folder
//! stays, unplanned.

use crate::error::{Error, Result};
pub use crate::runs::{finished, key_of, key_text, Finished, Job, Missing, Outcome, Reused};
use dem_lab::cutting::{self, CuttingTest, Inputs};
use dem_lab::specimen::{self, Method, SpecimenParams};
use dem_lab::tests::harness::DtFactor;
use dem_lab::LabModel;
use dem_run::case::{self, Case, STUDY_FILE};
use dem_run::plan::{FlagInfo, Slurm, TestCommands};
use dem_run::runner::{CaseFn, Executor, Report, RunOptions, SPECIMEN_CACHE};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What to run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Plan {
    /// Specimen parameters (method and seed are set per run).
    pub specimen: SpecimenParams,
    /// The calibrated material model every run uses.
    pub model: LabModel,
    pub methods: Vec<Method>,
    pub depths_mm: Vec<f64>,
    pub speeds_m_s: Vec<f64>,
    pub seeds: Vec<u64>,
    /// Cut length L (m).
    pub length: f64,
    /// Safety factor of the automatic time step (None: the cutting test's default).
    pub dt_factor: Option<DtFactor>,
    /// Start of the steady window (× a_p) and tool stiffness (× disc k_n); None: the cutting
    /// test's defaults.
    pub window_start: Option<f64>,
    pub tool_stiffness: Option<f64>,
}

impl Plan {
    /// The cutting test of one depth (mm) and speed (m/s) under this plan.
    pub fn test(&self, depth_mm: f64, speed: f64) -> CuttingTest {
        let mut test = CuttingTest::new(depth_mm * 1e-3, speed, self.length);
        if let Some(df) = self.dt_factor {
            test.dt_factor = df;
        }
        if let Some(w) = self.window_start {
            test.window_start = w;
        }
        if let Some(k) = self.tool_stiffness {
            test.tool_stiffness = k;
        }
        test
    }

    /// One job per method, seed, depth and speed, in that order (methods outermost).
    pub fn jobs(&self) -> Vec<Job> {
        let mut jobs = vec![];
        for &m in &self.methods {
            for &s in &self.seeds {
                let mut sp = self.specimen.clone();
                sp.method = m;
                sp.seed = s;
                sp.micro = self.model.micro.clone();
                normalize_grains(&mut sp);
                for &d in &self.depths_mm {
                    for &v in &self.speeds_m_s {
                        jobs.push(Job {
                            name: format!("{}-d{d}-v{v}-s{s}", m.name()),
                            specimen: sp.clone(),
                            model: self.model.clone(),
                            test: self.test(d, v),
                        });
                    }
                }
            }
        }
        jobs
    }
}

/// A traditional specimen has no irregular grains: its parameters carry the default grain
/// mode, so it keeps one key (and one cached specimen) whatever mode the plan gives ORC and
/// improved ORC.
pub fn normalize_grains(sp: &mut SpecimenParams) {
    if sp.method == Method::Traditional {
        sp.grains = dem_lab::specimen::GrainMode::All;
    }
}

/// FNV-1a of a string, for cache file names.
fn fnv(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Generates (or reuses) the specimen of `p` in `dir`; returns its file. The file name carries
/// the method, seed and a hash of all parameters, so different resolutions do not collide.
pub fn specimen_file(p: &SpecimenParams, dir: &Path) -> Result<PathBuf> {
    std::fs::create_dir_all(dir).map_err(Error::io(dir))?;
    let key = serde_json::to_string_pretty(p).map_err(Error::Serialize)?;
    let stem = format!(
        "{}-seed{}-{:08x}",
        p.method.name(),
        p.seed,
        fnv(&key) as u32
    );
    let file = dir.join(format!("{stem}.json"));
    let key_file = dir.join(format!("{stem}.params.json"));
    if file.exists() && std::fs::read_to_string(&key_file).ok().as_deref() == Some(key.as_str()) {
        return Ok(file);
    }
    let s = specimen::generate(p, &mut |_| {})
        .map_err(|e| Error::within(format!("specimen {stem}"), e))?;
    specimen::io::save(&s, specimen::DEFAULT_MATERIAL, &file)?;
    crate::page::write(dir, &format!("{stem}.params.json"), &key)?;
    Ok(file)
}

use dem_core::output::summary::thread_cpu_s;

/// Where the cutting runs come from.
#[derive(Clone, Copy, Debug)]
pub enum Source<'a> {
    /// Run here into the work folder ([`run_jobs`]): those not finished are run or listed.
    Here(Missing),
    /// The done cases of a `dem sweep` folder ([`crate::sweep_runs::read`]); the others are listed
    /// as not run.
    Sweep(&'a Path),
}

/// The jobs' runs from `source`: [`run_jobs`] into `work`, or read from a sweep folder.
pub fn outcome(
    jobs: &[Job],
    work: &Path,
    source: Source,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Outcome> {
    match source {
        Source::Here(m) => Ok(run_jobs(jobs, work, m, progress)),
        Source::Sweep(dir) => crate::sweep_runs::read(jobs, dir, progress),
    }
}

/// Runs the plan under `work` (specimens in `work/specimens`, runs in
/// `work/<method>-d<a_p>-v<v>-s<seed>/`); see [`run_jobs`].
pub fn run_plan(
    plan: &Plan,
    work: &Path,
    missing: Missing,
    progress: &(dyn Fn(&str) + Sync),
) -> Outcome {
    run_jobs(&plan.jobs(), work, missing, progress)
}

/// Runs `jobs` under `work` (or, with [`Missing::List`], only reads back the finished ones)
/// as the cases of a `dem sweep` folder (module docs); `progress` gets one line per finished
/// case. A failed run is reported and the others go on.
pub fn run_jobs(
    jobs: &[Job],
    work: &Path,
    missing: Missing,
    progress: &(dyn Fn(&str) + Sync),
) -> Outcome {
    match plan_and_run(jobs, work, missing, progress) {
        Ok(o) => o,
        Err(e) => Outcome {
            finished: vec![],
            errors: vec![format!("{}: {e}", work.display())],
            missing: jobs.iter().map(|j| j.name.clone()).collect(),
        },
    }
}

/// The folder of each job's inputs file (`<work>/inputs/<name>.json`).
pub const INPUTS_DIR: &str = "inputs";

/// The [`Inputs`] of a job as `dem test cutting` writes them (pretty JSON and a newline): the
/// inputs file its case runs from, and its `cutting.inputs.json`.
pub fn inputs_text(j: &Job) -> Result<String> {
    let i = Inputs {
        specimen: Some(j.specimen.clone()),
        specimen_file: None,
        model: Some(j.model.clone()),
        flat_joint: None,
        test: j.test.clone(),
    };
    Ok(serde_json::to_string_pretty(&i).map_err(Error::Serialize)? + "\n")
}

/// `dem test cutting --inputs FILE`, the one flag of the report's cases (the planner checks a
/// case against it; `dem sweep run` checks the same cases against the whole command line).
struct InputsFlag;

impl TestCommands for InputsFlag {
    fn flags(&self, kind: &str) -> dem_run::Result<BTreeMap<String, FlagInfo>> {
        if kind != "cutting" {
            return Err(dem_run::Error::input(format!(
                "the report's cases are cuts, not `dem test {kind}`"
            )));
        }
        let (file, value) = (
            FlagInfo {
                takes_value: true,
                is_file: true,
            },
            FlagInfo {
                takes_value: true,
                is_file: false,
            },
        );
        Ok([("inputs", file), ("out", value), ("threads", value)]
            .map(|(k, f)| (k.to_string(), f))
            .into())
    }

    fn check(&self, _kind: &str, _args: &[String]) -> dem_run::Result<()> {
        Ok(())
    }
}

/// Writes the jobs' inputs and study, plans the folder, runs what is not done (unless
/// [`Missing::List`]) and reads every job's case back.
fn plan_and_run(
    jobs: &[Job],
    work: &Path,
    missing: Missing,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Outcome> {
    let inputs = work.join(INPUTS_DIR);
    std::fs::create_dir_all(&inputs).map_err(Error::io(&inputs))?;
    let mut values = vec![];
    for j in jobs {
        crate::page::write(&inputs, &format!("{}.json", j.name), &inputs_text(j)?)?;
        values.push(format!("{INPUTS_DIR}/{}.json", j.name));
    }
    let name = work
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "runs".into());
    let study = serde_json::json!({
        "name": name,
        "base": {"test": "cutting"},
        "axes": [{"flag": "inputs", "values": values}],
        "collect": ["/main_force/mean", "/main_force/peak", "/run/steps"],
    });
    crate::page::write(work, STUDY_FILE, &crate::page::json(&study))?;
    let slurm = Slurm {
        throttle: None,
        cpus_per_task: 1,
        time: "24:00:00".into(),
        partition: None,
        mem: None,
    };
    let planned = dem_run::plan::replan(&work.join(STUDY_FILE), work, &slurm, &InputsFlag)
        .map_err(|e| Error::within("planning the runs", e))?;
    for (c, j) in planned.cases.iter().zip(jobs) {
        adopt_earlier(c, j, work)?;
    }
    let done_before: Vec<bool> = planned
        .cases
        .iter()
        .map(|c| matches!(case::state(c, work), case::State::Done(_)))
        .collect();
    if missing == Missing::Run && done_before.iter().any(|d| !d) {
        let spec_dir = work.join(SPECIMEN_CACHE);
        let f: Arc<CaseFn> = Arc::new(move |c, dir, _threads| run_case(c, dir, &spec_dir));
        let opts = RunOptions {
            dir: work.to_path_buf(),
            jobs: rayon::current_num_threads().max(1),
            threads: 1,
            index: None,
            // The code may have changed since a run failed: run it again.
            retry_failed: true,
            executor: Executor::InProcess(f),
        };
        dem_run::runner::run(&opts, &InputsFlag, &mut Lines(progress))
            .map_err(|e| Error::within("running the cases", e))?;
    }
    let mut out = crate::sweep_runs::read(jobs, work, progress)?;
    for f in &mut out.finished {
        // Read back: done before this call; run now: the others.
        f.resumed = jobs
            .iter()
            .position(|j| j.name == f.name)
            .is_some_and(|k| done_before[k]);
    }
    Ok(out)
}

/// The runner's lines, passed on (its progress bar is not drawn).
struct Lines<'a>(&'a (dyn Fn(&str) + Sync));

impl Report for Lines<'_> {
    fn line(&mut self, line: String) {
        (self.0)(&line)
    }
    fn progress(&mut self, _done: usize, _total: usize, _message: &str) {}
}

/// One case in this process, as `dem test cutting --inputs FILE --out DIR` runs it: the
/// specimen from the folder's cache (generated once per parameter set), the inputs written
/// into the case folder, the cut on a one-thread pool. Gives the CPU time of the cut.
fn run_case(c: &Case, dir: &Path, spec_dir: &Path) -> std::result::Result<Option<f64>, String> {
    let sweep = spec_dir.parent().unwrap_or(Path::new("."));
    let file = match c.argv.as_slice() {
        [_, _, flag, f] if flag == "--inputs" => sweep.join(f),
        _ => {
            return Err(format!(
                "case {}: not `test cutting --inputs FILE`",
                c.index
            ))
        }
    };
    let text = std::fs::read_to_string(&file).map_err(|e| format!("{}: {e}", file.display()))?;
    let i: Inputs = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", file.display()))?;
    let (Some(sp), Some(model)) = (&i.specimen, &i.model) else {
        return Err(format!("{}: no specimen or no model", file.display()));
    };
    let spec = one_thread(|| specimen_file(sp, spec_dir)).map_err(|e| e.to_string())?;
    crate::page::write(dir, cutting::INPUTS_FILE, &text).map_err(|e| e.to_string())?;
    let (r, cpu) = one_thread(|| {
        let c0 = thread_cpu_s();
        let r = i.test.clone().check().and_then(|test| {
            let spec = cutting::SpecimenInfo::read(&spec)?;
            cutting::run(&test, model, &spec, dir, &mut |_, _| {})
        });
        (r, thread_cpu_s().zip(c0).map(|(c1, c0)| c1 - c0))
    });
    let res = r.map_err(|e| e.to_string())?;
    // A run resumed from a checkpoint: the driver's totals over its invocations.
    Ok(if res.run.invocations > 1 {
        res.run.cpu_time_s
    } else {
        cpu
    })
}

/// Files of a run made by the report's runner before its runs were `dem sweep` cases
/// (2026-12-03): `run.key.json` held the job's key, `run.time.json` its wall and CPU time.
const EARLIER_KEY_FILE: &str = "run.key.json";
const EARLIER_TIME_FILE: &str = "run.time.json";

/// A finished run of the earlier layout (`<work>/<name>/` with `run.key.json` equal to the
/// job's key and its result) becomes the job's case: its folder moved to `cases/<key>/`, its
/// inputs and a `done.json` from its recorded times written. Its result is what the cache
/// of that runner read back for the same key; nothing is run again.
fn adopt_earlier(c: &Case, j: &Job, work: &Path) -> Result<()> {
    let old = work.join(&j.name);
    let new = c.dir(work);
    if new.exists()
        || std::fs::read_to_string(old.join(EARLIER_KEY_FILE)).ok() != Some(key_of(j))
        || !old.join(cutting::RESULT_FILE).is_file()
    {
        return Ok(());
    }
    let times: serde_json::Value = std::fs::read_to_string(old.join(EARLIER_TIME_FILE))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default();
    let finished_unix = std::fs::metadata(old.join(cutting::RESULT_FILE))
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_secs());
    std::fs::rename(&old, &new).map_err(Error::io(&old))?;
    crate::page::write(&new, cutting::INPUTS_FILE, &inputs_text(j)?)?;
    let rec = case::Record {
        index: c.index,
        key: c.key.clone(),
        exit_code: Some(0),
        signal: None,
        wall_s: times["wall_time_s"].as_f64().unwrap_or(0.0),
        cpu_s: times["cpu_time_s"].as_f64(),
        host: "unknown (a run of the report's earlier runner, adopted)".into(),
        finished_unix,
        error: None,
        log_tail: vec![],
    };
    crate::page::write(&new, case::DONE_FILE, &crate::page::json(&rec))?;
    for f in [EARLIER_KEY_FILE, EARLIER_TIME_FILE] {
        let _ = std::fs::remove_file(new.join(f));
    }
    Ok(())
}

/// Runs `f` on a one-thread rayon pool (the engine's inner parallel loops then run serially).
fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}
