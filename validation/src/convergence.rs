//! Error against run time for the cutting run (issue 5, item 3): the traditional specimen cut
//! at a_p = 1 mm, v = 1 m/s at several resolutions (disc radii scaled by s, so the disc count
//! goes as 1/s²: s = √2, 1, 1/√2, 1/2 give about 0.5×, 1×, 2×, 4× the paper's 989 discs) and
//! two safety factors of the automatic time step. Each point's peak and mean main force are
//! compared with the finest run (smallest s, smallest factor) and, through the thickness fitted
//! on the Table 2 cell when the report has one, with the paper's 11.4 / 7.5 kN.
//!
//! The cut is shorter than Table 2's (L is part of the sweep's plan and stated in the report):
//! the 4× run at L = 10 mm alone would take hours of one core on the development machine.

use crate::cutting_runs::{run_jobs, Job, Missing, Reused};
use crate::error::{Error, Result};
use crate::page::{json, Figure, Section};
use crate::plot::{self, Series};
use dem_lab::cutting::CuttingTest;
use dem_lab::specimen::{Method, SpecimenParams};
use dem_lab::tests::harness::DtFactor;
use dem_lab::LabModel;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// What the sweep runs.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SweepPlan {
    pub method: Method,
    /// Specimen at s = 1 (method set; radii scaled per point).
    pub specimen: SpecimenParams,
    pub model: LabModel,
    pub depth_mm: f64,
    pub speed_m_s: f64,
    /// Cut length L (m) and steady-window start (× a_p).
    pub length: f64,
    pub window_start: f64,
    /// Radius scale factors s (disc count ∝ 1/s²).
    pub scales: Vec<f64>,
    pub dt_factors: Vec<f64>,
}

/// One run of the sweep.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Point {
    pub radius_scale: f64,
    pub dt_factor: f64,
    pub discs: usize,
    pub dt_s: f64,
    pub steps: u64,
    pub wall_time_s: f64,
    /// CPU time of the run (s), where recorded (the case's `done.json`, or its result's `run.cpu_time_s`).
    #[serde(default)]
    pub cpu_time_s: Option<f64>,
    /// Forces at the run thickness (N).
    pub peak_n: f64,
    pub mean_n: f64,
    /// Relative difference from the finest run (0 for the finest itself).
    pub peak_err_vs_finest: f64,
    pub mean_err_vs_finest: f64,
    /// Relative difference from the paper's traditional 1 mm, 1 m/s cell after the Table 2
    /// thickness fit (None when the report has no Table 2 constant).
    pub peak_err_vs_paper: Option<f64>,
    pub mean_err_vs_paper: Option<f64>,
}

/// The sweep's result.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Sweep {
    pub plan: SweepPlan,
    /// The reference: the run with the smallest scale and the smallest dt factor.
    pub finest: (f64, f64),
    /// N at the run thickness → kN at the fitted thickness, if known.
    pub force_scale: Option<f64>,
    pub points: Vec<Point>,
    pub failed: Vec<String>,
    /// Runs read back from earlier calls (not in the JSON: it describes the call).
    #[serde(skip)]
    pub reused: Reused,
}

/// The paper's traditional a_p = 1 mm, v = 1 m/s cell (Ye & Xu 2010, Table 2): peak, mean (kN).
pub const PAPER_CELL: [f64; 2] = [11.4, 7.5];

/// The jobs, most expensive first (finest scale, smallest factor), so that on two workers the
/// long run starts at once.
pub fn jobs(p: &SweepPlan) -> Vec<Job> {
    let mut scales = p.scales.clone();
    scales.sort_by(f64::total_cmp);
    let mut dts = p.dt_factors.clone();
    dts.sort_by(f64::total_cmp);
    let mut out = vec![];
    for &s in &scales {
        for &f in &dts {
            let mut sp = p.specimen.clone();
            sp.method = p.method;
            sp.r_min *= s;
            sp.r_max *= s;
            sp.grain_size *= s;
            sp.template_r_min *= s;
            sp.template_r_max *= s;
            sp.micro = p.model.micro.clone();
            let mut model = p.model.clone();
            model.r_mean *= s;
            let mut test = CuttingTest::new(p.depth_mm * 1e-3, p.speed_m_s, p.length);
            test.window_start = p.window_start;
            test.dt_factor = DtFactor(f);
            out.push(Job {
                name: format!("{}-r{s:.4}-dt{f}", p.method.name()),
                specimen: sp,
                model,
                test,
            });
        }
    }
    out
}

/// Runs the sweep under `work`; `force_scale` turns N at the run thickness into kN at the
/// Table 2 fitted thickness.
pub fn run(
    p: &SweepPlan,
    work: &Path,
    force_scale: Option<f64>,
    missing: Missing,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Sweep> {
    let jobs = jobs(p);
    let outcome = run_jobs(&jobs, work, missing, progress);
    let reused = outcome.reused();
    let (done, failed) = (outcome.finished, outcome.errors);
    if !outcome.missing.is_empty() {
        return Err(Error::NotRun {
            runs: outcome.missing,
        });
    }
    let mut points: Vec<Point> = vec![];
    for f in &done {
        let j = jobs
            .iter()
            .find(|j| j.name == f.name)
            .ok_or(Error::NotInPlan)?;
        let s = j.specimen.r_min / p.specimen.r_min;
        points.push(Point {
            radius_scale: s,
            dt_factor: j.test.dt_factor.get(),
            discs: f.record.discs,
            dt_s: f.result.run.dt_min,
            steps: f.record.steps,
            wall_time_s: f.record.wall_time_s,
            cpu_time_s: f.record.cpu_time_s,
            peak_n: f.record.peak_n,
            mean_n: f.record.mean_n,
            peak_err_vs_finest: 0.0,
            mean_err_vs_finest: 0.0,
            peak_err_vs_paper: force_scale.map(|k| f.record.peak_n * k / PAPER_CELL[0] - 1.0),
            mean_err_vs_paper: force_scale.map(|k| f.record.mean_n * k / PAPER_CELL[1] - 1.0),
        });
    }
    // The finest run of the plan must have finished: otherwise there is no reference.
    let finest_job = &jobs[0];
    let finest = (
        finest_job.specimen.r_min / p.specimen.r_min,
        finest_job.test.dt_factor.get(),
    );
    let reference = done
        .iter()
        .find(|f| f.name == finest_job.name)
        .ok_or_else(|| Error::NoFinest {
            run: finest_job.name.clone(),
        })?;
    let (pk0, mn0) = (reference.record.peak_n, reference.record.mean_n);
    if !(pk0 > 0.0 && mn0 > 0.0) {
        return Err(Error::NoReference {
            run: finest_job.name.clone(),
            peak: pk0,
            mean: mn0,
        });
    }
    for q in &mut points {
        q.peak_err_vs_finest = q.peak_n / pk0 - 1.0;
        q.mean_err_vs_finest = q.mean_n / mn0 - 1.0;
    }
    Ok(Sweep {
        plan: p.clone(),
        finest,
        force_scale,
        points,
        failed,
        reused,
    })
}

impl Sweep {
    /// The table (Markdown).
    pub fn markdown(&self) -> String {
        let p = &self.plan;
        let mut md = format!(
            "{} specimen, a_p = {} mm, v = {} m/s, L = {} mm, steady window from {} a_p; radii \
             {:.3}–{:.3} mm at s = 1, scaled by s; reference: s = {:.3}, dt factor {}. Errors \
             are relative differences of the main force (peak, mean over the window).",
            p.method.name(),
            p.depth_mm,
            p.speed_m_s,
            p.length * 1e3,
            p.window_start,
            p.specimen.r_min * 1e3,
            p.specimen.r_max * 1e3,
            self.finest.0,
            self.finest.1
        );
        match self.force_scale {
            Some(_) => {
                md += &format!(
                    " Against the paper: forces times the thickness fitted in this report's \
                     Table 2, compared with the paper's traditional 1 mm, 1 m/s cell ({} / {} \
                     kN; the fit is on Table 2's cut length, so a shorter cut's offset is part \
                     of this error).",
                    PAPER_CELL[0], PAPER_CELL[1]
                )
            }
            None => md += " No Table 2 constant in this report, so no comparison with the paper.",
        }
        md += "\n\n| s | dt factor | discs | dt (s) | steps | wall time (s) | CPU time (s) | peak (N) | mean (N) | peak err vs finest | mean err vs finest | peak err vs paper | mean err vs paper |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
        let pct = |x: Option<f64>| x.map_or("—".to_string(), |v| format!("{:+.1} %", 100.0 * v));
        for q in &self.points {
            md += &format!(
                "| {:.3} | {} | {} | {:.3e} | {} | {:.1} | {} | {:.4e} | {:.4e} | {} | {} | {} | {} |\n",
                q.radius_scale,
                q.dt_factor,
                q.discs,
                q.dt_s,
                q.steps,
                q.wall_time_s,
                q.cpu_time_s.map_or("—".into(), |c| format!("{c:.1}")),
                q.peak_n,
                q.mean_n,
                pct(Some(q.peak_err_vs_finest)),
                pct(Some(q.mean_err_vs_finest)),
                pct(q.peak_err_vs_paper),
                pct(q.mean_err_vs_paper)
            );
        }
        if !self.failed.is_empty() {
            md += "\n**Failed runs** (left out):\n\n";
            for e in &self.failed {
                md += &format!("- {e}\n");
            }
        }
        md
    }

    /// Error of the mean force against wall time, one line per dt factor (the finest run, at
    /// zero error, is left off the log axis and named in the caption).
    pub fn plot(&self) -> Result<String> {
        // CPU time when every run recorded it (wall time overstates it on a shared machine).
        let cpu = self.points.iter().all(|q| q.cpu_time_s.is_some());
        let time = |q: &Point| {
            if cpu {
                q.cpu_time_s.unwrap_or(0.0)
            } else {
                q.wall_time_s
            }
        };
        let mut dts: Vec<f64> = self.points.iter().map(|q| q.dt_factor).collect();
        dts.sort_by(f64::total_cmp);
        dts.dedup();
        let mut series = vec![];
        for f in dts {
            for (what, pick) in [
                (
                    "mean",
                    (|q: &Point| q.mean_err_vs_finest) as fn(&Point) -> f64,
                ),
                ("peak", |q: &Point| q.peak_err_vs_finest),
            ] {
                let mut pts: Vec<(f64, f64)> = self
                    .points
                    .iter()
                    .filter(|q| q.dt_factor == f && pick(q) != 0.0)
                    .map(|q| (time(q), pick(q).abs()))
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                series.push(Series {
                    name: format!("{what} force, dt factor {f}"),
                    points: pts,
                });
            }
        }
        plot::lines(
            "Cutting force: error against run time",
            if cpu {
                "CPU time of the run (s, one thread)"
            } else {
                "wall time of the run (s, one thread)"
            },
            "|relative difference from the finest run|",
            &series,
            true,
            true,
        )
    }

    /// The report section.
    pub fn section(&self) -> Result<Section> {
        Ok(Section {
            title: "Cutting: error against run time".into(),
            markdown: self.markdown(),
            figures: vec![Figure {
                file: "cutting_error_vs_time.svg".into(),
                caption: format!(
                    "|relative difference| of the peak and mean main force from the finest run \
                     (s = {:.3}, dt factor {}) against wall time, per dt factor",
                    self.finest.0, self.finest.1
                ),
                svg: self.plot()?,
            }],
            data: vec![("cutting_convergence.json".into(), json(self))],
        })
    }
}

/// Full: the Table 2 specimen (traditional, radii 0.175–0.285 mm at s = 1), s = √2, 1, 1/√2,
/// 1/2, dt factors 0.3 (the cutting default) and 0.6, L = 3 mm, window from 1 a_p. Quick: the
/// quick Table 2 specimen (10 × 5 mm), s = √2 and 1, the same two factors, L = 3 mm, window
/// from 0.5 a_p (at 1.5 mm the finest run's window fell between two strikes under the
/// fragment-frame damping: no reference).
pub fn plan(data: &Path, quick: bool) -> Result<SweepPlan> {
    let t2 = crate::table2_section::plan(data, quick)?;
    let (scales, length, window_start) = if quick {
        (vec![std::f64::consts::SQRT_2, 1.0], 3e-3, 0.5)
    } else {
        (
            vec![
                std::f64::consts::SQRT_2,
                1.0,
                std::f64::consts::FRAC_1_SQRT_2,
                0.5,
            ],
            3e-3,
            1.0,
        )
    };
    Ok(SweepPlan {
        method: Method::Traditional,
        specimen: t2.specimen,
        model: t2.model,
        depth_mm: 1.0,
        speed_m_s: 1.0,
        length,
        window_start,
        scales,
        dt_factors: vec![0.3, 0.6],
    })
}
