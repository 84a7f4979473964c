//! A run of the report: the [`Job`] (typed specimen parameters, model and test), its key, and
//! what a finished run gives ([`Finished`]: the Table 2 record, the result, its folder); the
//! [`Outcome`] of many. [`crate::sweep_runs`] reads them from a `dem sweep` folder and
//! [`crate::cutting_runs`] plans and runs them there.

use crate::error::{Error, Result};
use crate::force_statistics::main_force;
use crate::table2::RunRecord;
use dem_lab::cutting::{self, CuttingResult, CuttingTest};
use dem_lab::specimen::SpecimenParams;
use dem_lab::LabModel;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

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

/// The key of a run: its specimen parameters, model and test as pretty JSON (what a case's
/// `cutting.inputs.json` is matched by).
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

/// What [`crate::cutting_runs::run_jobs`] did: finished runs (run now or read back), errors and the jobs left out.
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
