//! The cutting runs behind Table 2 and the convergence study: specimens (generated once and
//! cached by their parameters), then one cutting test ([`dem_lab::cutting::run`]) per
//! [`Job`], one job per worker thread at a time, each on a one-thread pool (small systems run
//! best on one core; results do not depend on the thread count).
//!
//! **Resuming**: a finished run leaves `run.key.json` (specimen parameters, model and test)
//! beside its `cutting.result.json`; a later call with the same key reads the result instead of
//! running again. A long report (the full Table 2 is ~60 runs) can therefore be stopped and
//! continued, or built up over several sessions.

use crate::error::{Error, Result};
use crate::force_statistics::main_force;
use crate::table2::RunRecord;
use dem_lab::cutting::{self, CuttingResult, CuttingTest};
use dem_lab::specimen::{self, Method, SpecimenParams};
use dem_lab::LabModel;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

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
    pub dt_factor: Option<f64>,
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

/// One cutting run: a specimen (generated from its parameters), the material model and a test.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Job {
    /// Run folder name under the work folder.
    pub name: String,
    pub specimen: SpecimenParams,
    /// The model's `r_mean` sets the bond stiffness k̄_n = Ē_c/(2 r_mean): it follows the
    /// specimen's radii.
    pub model: LabModel,
    pub test: CuttingTest,
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

/// One finished run: the Table 2 record, the full result and where it is.
#[derive(Clone, Debug, Serialize)]
pub struct Finished {
    pub name: String,
    pub record: RunRecord,
    pub result_file: String,
    /// Read from an earlier run with the same key instead of run now (or from a sweep).
    pub resumed: bool,
    #[serde(skip)]
    pub result: CuttingResult,
    /// The run's folder (`<work>/<name>`, or a sweep's `cases/<key>`).
    #[serde(skip)]
    pub dir: PathBuf,
}

/// The key of a run: its specimen parameters, model and test as pretty JSON (`run.key.json`).
pub fn key_text(specimen: &SpecimenParams, model: &LabModel, test: &CuttingTest) -> Result<String> {
    serde_json::to_string_pretty(&(specimen, model, test)).map_err(Error::Serialize)
}

/// The key of a job ([`key_text`]).
pub fn key_of(j: &Job) -> String {
    key_text(&j.specimen, &j.model, &j.test).expect("job key serialises")
}

/// The record of a finished run of `job` in `dir` (its result `res`; `cpu`: CPU time, s).
pub fn finished(
    job: &Job,
    res: CuttingResult,
    dir: &Path,
    cpu: Option<f64>,
    resumed: bool,
) -> Finished {
    let hist = HistoryStats::read(dir, &res, job.specimen.grain_size);
    Finished {
        name: job.name.clone(),
        record: RunRecord {
            method: job.specimen.method.name().into(),
            depth_mm: (job.test.depth * 1e9).round() / 1e6,
            speed_m_s: job.test.speed,
            seed: job.specimen.seed,
            peak_n: res.main_force.peak,
            mean_n: res.main_force.mean,
            thickness_m: res.thickness,
            discs: res.discs,
            steps: res.run.steps,
            wall_time_s: res.run.wall_time_s,
            cpu_time_s: cpu,
            peak_avg_n: hist.peak_avg_n,
            max_overlap_fraction: res.run.max_overlap_fraction,
            broken_total: Some(res.broken_total),
            broken_intra_grain: Some(
                res.broken_bonds
                    .iter()
                    .filter(|b| b.group == "intra_grain")
                    .map(|b| b.tension + b.shear)
                    .sum(),
            ),
            median_n: hist.run.map(|s| s.median),
            top5_work_share: hist.run.and_then(|s| s.top5_work_share),
            // Runs written before the field: from their forces file.
            touching: res.touching.or_else(|| {
                main_force(&dir.join(cutting::FORCES_FILE))
                    .and_then(|(x, f)| cutting::touching_share(&x, &f, res.window))
            }),
        },
        result_file: dir.join(cutting::RESULT_FILE).display().to_string(),
        resumed,
        result: res,
        dir: dir.to_path_buf(),
    }
}

/// Key file of a finished run.
pub const KEY_FILE: &str = "run.key.json";

/// Run-time file of a finished run: `{"wall_time_s", "cpu_time_s"}` (CPU time of the thread
/// that stepped it; on a shared machine the wall time overstates the cost). A run resumed
/// from a checkpoint (an earlier invocation was stopped) gives the totals over its
/// invocations as the cutting driver recorded them (stepping only, without the few seconds
/// of setup and analysis the one-invocation figure includes) and `"invocations"`.
pub const TIME_FILE: &str = "run.time.json";

pub use dem_core::output::summary::thread_cpu_s;

/// Failure record of a run: `{"error", "key"}`. A later call with [`Missing::List`] reports
/// the failure instead of listing the run as not run; [`Missing::Run`] runs it again (the code
/// may have changed).
pub const FAILED_FILE: &str = "run.failed.json";

/// The error of an earlier failed run in `dir` with this key, if any.
fn earlier_failure(dir: &Path, key: &str) -> Option<String> {
    let text = std::fs::read_to_string(dir.join(FAILED_FILE)).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    (v["key"].as_str()? == key).then(|| v["error"].as_str().unwrap_or("").to_string())
}

/// CPU time recorded beside an earlier run, if any.
fn earlier_cpu(dir: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(dir.join(TIME_FILE)).ok()?;
    serde_json::from_str::<serde_json::Value>(&text).ok()?["cpu_time_s"].as_f64()
}

/// The result of an earlier run in `dir` with this key, if any.
fn earlier(dir: &Path, key: &str) -> Option<CuttingResult> {
    if std::fs::read_to_string(dir.join(KEY_FILE)).ok()? != key {
        return None;
    }
    let text = std::fs::read_to_string(dir.join(cutting::RESULT_FILE)).ok()?;
    serde_json::from_str(&text).ok()
}

/// Whether jobs with no finished run are run now or only listed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Missing {
    /// Generate their specimens and run them (the default).
    #[default]
    Run,
    /// Leave them out and list them in [`Outcome::missing`]: a report of the runs finished so
    /// far (the full Table 2 is built up over several sessions).
    List,
}

/// What [`run_jobs`] did: finished runs (run now or read back), errors and the jobs left out.
#[derive(Debug, Default)]
pub struct Outcome {
    /// In job order.
    pub finished: Vec<Finished>,
    /// One message per failed specimen or run; the others went on.
    pub errors: Vec<String>,
    /// Names of the jobs neither finished earlier nor run now ([`Missing::List`]).
    pub missing: Vec<String>,
}

/// Finished runs read back from an earlier call instead of run now, and their run time as
/// recorded when they ran: a report rebuilt from finished runs states what they cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Reused {
    pub runs: usize,
    pub wall_time_s: f64,
}

impl Reused {
    pub fn add(&mut self, o: Reused) {
        self.runs += o.runs;
        self.wall_time_s += o.wall_time_s;
    }
}

impl Outcome {
    /// The finished runs that were read back, not run now.
    pub fn reused(&self) -> Reused {
        let back = self.finished.iter().filter(|f| f.resumed);
        Reused {
            runs: back.clone().count(),
            wall_time_s: back.map(|f| f.record.wall_time_s).sum(),
        }
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

/// Runs `jobs` under `work` (or, with [`Missing::List`], only reads back the finished ones);
/// `progress` gets one line per finished item. A failed run is reported and the others go on.
pub fn run_jobs(
    jobs: &[Job],
    work: &Path,
    missing: Missing,
    progress: &(dyn Fn(&str) + Sync),
) -> Outcome {
    let errors = Mutex::new(Vec::new());
    // Runs finished earlier with the same key need no specimen.
    let before: Vec<Option<CuttingResult>> = jobs
        .iter()
        .map(|j| earlier(&work.join(&j.name), &key_of(j)))
        .collect();
    let mut not_run = vec![];
    let (jobs, before): (Vec<&Job>, Vec<Option<CuttingResult>>) = match missing {
        Missing::Run => (jobs.iter().collect(), before),
        Missing::List => jobs
            .iter()
            .zip(before)
            .filter(|(j, b)| {
                if b.is_none() {
                    match earlier_failure(&work.join(&j.name), &key_of(j)) {
                        Some(e) => errors
                            .lock()
                            .unwrap()
                            .push(format!("{}: failed in an earlier call: {e}", j.name)),
                        None => not_run.push(j.name.clone()),
                    }
                }
                b.is_some()
            })
            .unzip(),
    };
    // Specimens: each distinct parameter set still to run once, two at a time.
    let mut specs: Vec<SpecimenParams> = vec![];
    for (j, b) in jobs.iter().zip(&before) {
        if b.is_none() && !specs.contains(&j.specimen) {
            specs.push(j.specimen.clone());
        }
    }
    let spec_dir = work.join("specimens");
    let files: Vec<Option<PathBuf>> = parallel_map(&specs, |p| {
        let t0 = Instant::now();
        let r = one_thread(|| specimen_file(p, &spec_dir));
        let what = format!(
            "specimen {} seed {} (r {:.3}-{:.3} mm)",
            p.method.name(),
            p.seed,
            p.r_min * 1e3,
            p.r_max * 1e3
        );
        match r {
            Ok(f) => {
                progress(&format!("{what}: {:.1} s", t0.elapsed().as_secs_f64()));
                Some(f)
            }
            Err(e) => {
                errors.lock().unwrap().push(e.to_string());
                progress(&format!("{what}: FAILED: {e}"));
                None
            }
        }
    });
    // (job, specimen file to run on | result of the earlier run)
    let runnable: Vec<(&Job, std::result::Result<PathBuf, CuttingResult>)> = jobs
        .into_iter()
        .zip(before)
        .filter_map(|(j, b)| match b {
            Some(res) => Some((j, Err(res))),
            None => {
                let k = specs.iter().position(|p| *p == j.specimen)?;
                files[k].clone().map(|f| (j, Ok(f)))
            }
        })
        .collect();
    let total = runnable.len();
    let done = Mutex::new(0usize);
    let out: Vec<Option<Finished>> = parallel_map(&runnable, |(job, what)| {
        let dir = work.join(&job.name);
        let key = key_of(job);
        let t0 = Instant::now();
        let (r, resumed, cpu) = match what {
            Err(res) => (Ok(res.clone()), true, earlier_cpu(&dir)),
            Ok(f) => {
                // The run steps on the one-thread pool's worker: its CPU time is the run's.
                let (r, cpu) = one_thread(|| {
                    let c0 = thread_cpu_s();
                    let r = job
                        .test
                        .clone()
                        .check()
                        .and_then(|test| {
                            let spec = cutting::SpecimenInfo::read(f)?;
                            cutting::run(&test, &job.model, &spec, &dir, &mut |_, _| {})
                        })
                        .map_err(|e| e.to_string());
                    (r, thread_cpu_s().zip(c0).map(|(c1, c0)| c1 - c0))
                });
                // A resumed run: the driver's totals over all its invocations.
                let cpu = match &r {
                    Ok(res) if res.run.invocations > 1 => res.run.cpu_time_s,
                    _ => cpu,
                };
                if let Ok(res) = &r {
                    let _ = std::fs::remove_file(dir.join(FAILED_FILE));
                    let mut time = serde_json::json!({
                        "wall_time_s": res.run.wall_time_s,
                        "cpu_time_s": cpu,
                    });
                    if res.run.invocations > 1 {
                        time["invocations"] = serde_json::json!(res.run.invocations);
                    }
                    for (file, text) in [
                        (
                            TIME_FILE,
                            serde_json::to_string_pretty(&time).unwrap_or_default(),
                        ),
                        (KEY_FILE, key.clone()),
                    ] {
                        if let Err(e) = crate::page::write(&dir, file, &text) {
                            errors.lock().unwrap().push(e.to_string());
                        }
                    }
                }
                (r, false, cpu)
            }
        };
        let mut n = done.lock().unwrap();
        *n += 1;
        match r {
            Ok(res) => {
                progress(&format!(
                    "[{}/{total}] {}: peak {:.4e} N, mean {:.4e} N, {} steps, {:.1} s{}",
                    *n,
                    job.name,
                    res.main_force.peak,
                    res.main_force.mean,
                    res.run.steps,
                    if resumed {
                        res.run.wall_time_s
                    } else {
                        t0.elapsed().as_secs_f64()
                    },
                    if resumed {
                        " (earlier run)".to_string()
                    } else if res.run.invocations > 1 {
                        format!(
                            " (resumed from a checkpoint; {} invocations, {:.1} s in all)",
                            res.run.invocations, res.run.wall_time_s
                        )
                    } else {
                        String::new()
                    }
                ));
                Some(finished(job, res, &dir, cpu, resumed))
            }
            Err(e) => {
                let record = serde_json::json!({ "error": e, "key": key });
                if let Err(w) = crate::page::write(
                    &dir,
                    FAILED_FILE,
                    &serde_json::to_string_pretty(&record).unwrap_or_default(),
                ) {
                    errors.lock().unwrap().push(w.to_string());
                }
                let msg = format!("{}: {e}", job.name);
                progress(&format!("[{}/{total}] FAILED {msg}", *n));
                errors.lock().unwrap().push(msg);
                None
            }
        }
    });
    Outcome {
        finished: out.into_iter().flatten().collect(),
        errors: errors.into_inner().unwrap(),
        missing: not_run,
    }
}

/// Statistics of a run's main-force history (`cutting.forces.csv`) over its steady window.
#[derive(Clone, Copy, Debug, Default)]
struct HistoryStats {
    /// Peak of the force averaged over one grain of tool travel
    /// ([`crate::table2::PEAK_AVERAGING`]).
    peak_avg_n: Option<f64>,
    /// Travel-weighted mean, median, raw and moving-mean peak, top-5 % work share on the
    /// [`crate::force_statistics`] grid and width.
    run: Option<dem_lab::analysis::force_stats::RunStats>,
}

impl HistoryStats {
    /// `None` fields where the file cannot be read or the window holds no sample.
    fn read(dir: &Path, res: &CuttingResult, grain: f64) -> HistoryStats {
        let Some((x, f)) = main_force(&dir.join(cutting::FORCES_FILE)) else {
            return HistoryStats::default();
        };
        let [from, to] = res.window;
        HistoryStats {
            peak_avg_n: dem_lab::analysis::moving_mean_peak(&x, &f, from, to, grain),
            run: dem_lab::analysis::force_stats::run_stats(
                (&x, &f),
                res.window,
                crate::force_statistics::GRID_STEP_M,
                crate::force_statistics::PEAK_WIDTH_AP * res.test.depth,
            )
            .ok()
            .flatten(),
        }
    }
}

/// Runs `f` on a one-thread rayon pool (the engine's inner parallel loops then run serially).
fn one_thread<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    match rayon::ThreadPoolBuilder::new().num_threads(1).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}

/// `f` over `items` on as many scoped threads as rayon's pool has (each item whole on one
/// thread, taken in order), results in item order. Plain threads rather than nested rayon
/// pools: a rayon worker blocked in another pool's `install` steals more outer items, which
/// interleaves runs and makes their wall times meaningless.
fn parallel_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let slots: Vec<Mutex<Option<R>>> = items.iter().map(|_| Mutex::new(None)).collect();
    let workers = rayon::current_num_threads().clamp(1, items.len().max(1));
    std::thread::scope(|sc| {
        for _ in 0..workers {
            sc.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= items.len() {
                    break;
                }
                let r = f(&items[k]);
                *slots[k].lock().unwrap() = Some(r);
            });
        }
    });
    slots
        .into_iter()
        .map(|m| m.into_inner().unwrap().expect("every item ran"))
        .collect()
}
