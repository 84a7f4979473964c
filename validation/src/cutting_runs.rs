//! The cutting runs behind Table 2: specimens of the three types for every seed (generated once
//! and cached by their parameters), then a cutting test per depth and speed
//! ([`dem_core::lab::cutting::run`]), one run per worker thread at a time, each on a one-thread
//! pool (small systems run best on one core; results do not depend on the thread count).

use crate::table2::RunRecord;
use dem_core::lab::cutting::{self, CuttingTest};
use dem_core::lab::LabModel;
use dem_core::specimen::{self, Method, SpecimenParams};
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

/// Generates (or reuses) the specimen of `p` in `dir`; returns its file.
pub fn specimen_file(p: &SpecimenParams, dir: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let stem = format!("{}-seed{}", p.method.name(), p.seed);
    let file = dir.join(format!("{stem}.json"));
    let key_file = dir.join(format!("{stem}.params.json"));
    let key = serde_json::to_string_pretty(p).map_err(|e| e.to_string())?;
    if file.exists() && std::fs::read_to_string(&key_file).ok().as_deref() == Some(key.as_str()) {
        return Ok(file);
    }
    let s = specimen::generate(p, &mut |_| {}).map_err(|e| format!("specimen {stem}: {e}"))?;
    specimen::io::save(&s, specimen::DEFAULT_MATERIAL, &file).map_err(|e| e.to_string())?;
    crate::page::write(dir, &format!("{stem}.params.json"), &key)?;
    Ok(file)
}

/// One finished run: the Table 2 record and the full result.
#[derive(Clone, Debug, Serialize)]
pub struct Finished {
    pub record: RunRecord,
    pub result_file: String,
}

/// Runs the plan under `work` (specimens in `work/specimens`, runs in
/// `work/<method>-d<a_p>-v<v>-s<seed>/`); `progress` gets one line per finished item. A failed
/// run is reported and the others go on; the error list is returned beside the records.
pub fn run_plan(
    plan: &Plan,
    work: &Path,
    progress: &(dyn Fn(&str) + Sync),
) -> (Vec<Finished>, Vec<String>) {
    let errors = Mutex::new(Vec::new());
    // Specimens: one per method and seed, two at a time.
    let specs: Vec<(Method, u64)> = plan
        .methods
        .iter()
        .flat_map(|&m| plan.seeds.iter().map(move |&s| (m, s)))
        .collect();
    let spec_dir = work.join("specimens");
    let files: Vec<Option<PathBuf>> = parallel_map(&specs, |&(m, s)| {
        let mut p = plan.specimen.clone();
        p.method = m;
        p.seed = s;
        p.micro = plan.model.micro.clone();
        let t0 = Instant::now();
        let r = one_thread(|| specimen_file(&p, &spec_dir));
        match r {
            Ok(f) => {
                progress(&format!(
                    "specimen {} seed {s}: {:.1} s",
                    m.name(),
                    t0.elapsed().as_secs_f64()
                ));
                Some(f)
            }
            Err(e) => {
                errors.lock().unwrap().push(e.clone());
                progress(&format!("specimen {} seed {s}: FAILED: {e}", m.name()));
                None
            }
        }
    });
    // Runs.
    let mut jobs = vec![];
    for (k, &(m, s)) in specs.iter().enumerate() {
        let Some(f) = &files[k] else { continue };
        for &d in &plan.depths_mm {
            for &v in &plan.speeds_m_s {
                jobs.push((m, s, d, v, f.clone()));
            }
        }
    }
    let total = jobs.len();
    let done = Mutex::new(0usize);
    let out: Vec<Option<Finished>> = parallel_map(&jobs, |(m, s, d, v, f)| {
        let mut test = CuttingTest::new(d * 1e-3, *v, plan.length);
        if let Some(df) = plan.dt_factor {
            test.dt_factor = df;
        }
        if let Some(w) = plan.window_start {
            test.window_start = w;
        }
        if let Some(k) = plan.tool_stiffness {
            test.tool_stiffness = k;
        }
        let dir = work.join(format!("{}-d{d}-v{v}-s{s}", m.name()));
        let t0 = Instant::now();
        let r = one_thread(|| {
            cutting::run(&test, &plan.model, f, &dir, &mut |_, _| {}).map_err(|e| e.to_string())
        });
        let mut n = done.lock().unwrap();
        *n += 1;
        match r {
            Ok(res) => {
                progress(&format!(
                        "[{}/{total}] {} a_p {d} mm v {v} m/s seed {s}: peak {:.4e} N, mean {:.4e} N, {} steps, {:.1} s",
                        *n,
                        m.name(),
                        res.main_force.peak,
                        res.main_force.mean,
                        res.run.steps,
                        t0.elapsed().as_secs_f64()
                    ));
                Some(Finished {
                    record: RunRecord {
                        method: m.name().into(),
                        depth_mm: *d,
                        speed_m_s: *v,
                        seed: *s,
                        peak_n: res.main_force.peak,
                        mean_n: res.main_force.mean,
                        thickness_m: res.thickness,
                        discs: res.discs,
                        steps: res.run.steps,
                        wall_time_s: res.run.wall_time_s,
                    },
                    result_file: dir.join(cutting::RESULT_FILE).display().to_string(),
                })
            }
            Err(e) => {
                let msg = format!("{} a_p {d} mm v {v} m/s seed {s}: {e}", m.name());
                progress(&format!("[{}/{total}] FAILED {msg}", *n));
                errors.lock().unwrap().push(msg);
                None
            }
        }
    });
    (
        out.into_iter().flatten().collect(),
        errors.into_inner().unwrap(),
    )
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
