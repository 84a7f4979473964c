//! The run summary (`summary.json`): what ran, how fast, and where the energy went.

use super::{finite, write_atomic, OutputError};
use crate::energy::EnergyReport;
use serde::{Deserialize, Serialize};
use std::path::Path;

pub const SCHEMA: &str = "dem.summary/1";

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    pub schema: String,
    pub scene: String,
    pub name: String,
    /// `completed`, or `stopped` with the reason in `error`.
    pub status: String,
    pub error: Option<String>,
    pub restarted_from: Option<String>,
    pub active_stages: Vec<String>,
    pub threads: usize,
    pub discs: usize,
    pub clumps: usize,
    pub bonds: usize,
    pub bonds_broken: u64,
    /// Steps done by this invocation, and the world's step count at its end.
    pub steps: u64,
    pub final_step: u64,
    /// Simulated time at the end (s).
    pub time: f64,
    /// Time step at the end, and the smallest and largest used (s).
    pub dt: f64,
    pub dt_min: f64,
    pub dt_max: f64,
    /// Deepest overlap seen at the guard checks of this invocation: disc pairs over the
    /// smaller radius, disc-wall contacts over the disc radius (the guard stops a run above
    /// `run.max_overlap_fraction`). Absent (0) in summaries written before it was recorded.
    #[serde(default)]
    pub max_overlap_fraction: f64,
    pub wall_time_s: f64,
    /// CPU time of the thread that drove this invocation (s): all of its CPU when the run's
    /// rayon pool has one thread, less otherwise; `None` where the platform does not report
    /// it (see [`thread_cpu_s`]) and in summaries written before it was recorded.
    #[serde(default)]
    pub cpu_time_s: Option<f64>,
    /// The whole run, over this invocation and the earlier ones it was restarted from (equal
    /// to this invocation's figures for a run never restarted); `None` in summaries written
    /// before it was recorded.
    #[serde(default)]
    pub whole_run: Option<RunTotals>,
    /// discs × steps / wall time of the stepping (outputs excluded).
    pub particle_steps_per_s: f64,
    /// Final energies (J) and relative balance error, see [`crate::energy::EnergyReport`].
    pub energy: EnergyReport,
    /// Files written (relative to the output folder).
    pub files: Vec<String>,
    /// Figures that were not finite when a stopped run wrote its summary (a runaway load
    /// overflows the energies): written as `null` and named here. Only a `stopped` summary may
    /// have any; empty (and absent from the file) otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_finite: Vec<String>,
    /// `false` when the run wrote no checkpoints (`outputs.checkpoints` off or `dem run
    /// --no-checkpoints`): it cannot be resumed. Absent (true) otherwise.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub checkpoints: bool,
}

/// A run's figures over all its invocations: a fresh run is one invocation, each restart from
/// a checkpoint adds one. Checkpoints carry the totals up to their step, so a restarted run
/// reports its whole run time, time-step range and deepest overlap, not only its last part's.
/// (A checkpoint written before the totals were recorded starts them afresh: the earlier part
/// is then not counted, and `invocations` counts only the known ones.)
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunTotals {
    pub invocations: u32,
    /// Wall time of the invocations up to the step (s).
    pub wall_time_s: f64,
    /// CPU time of the driving threads (s; see [`RunSummary::cpu_time_s`]); `None` if any
    /// part is unknown.
    pub cpu_time_s: Option<f64>,
    /// Smallest and largest time step used (s).
    pub dt_min: f64,
    pub dt_max: f64,
    /// Deepest overlap seen at the guard checks (see [`RunSummary::max_overlap_fraction`]).
    pub max_overlap_fraction: f64,
}

impl RunTotals {
    /// These totals followed by one more invocation's figures.
    pub fn then(
        before: Option<&RunTotals>,
        wall_time_s: f64,
        cpu_time_s: Option<f64>,
        dt_range: [f64; 2],
        max_overlap_fraction: f64,
    ) -> RunTotals {
        match before {
            None => RunTotals {
                invocations: 1,
                wall_time_s,
                cpu_time_s,
                dt_min: dt_range[0],
                dt_max: dt_range[1],
                max_overlap_fraction,
            },
            Some(b) => RunTotals {
                invocations: b.invocations + 1,
                wall_time_s: b.wall_time_s + wall_time_s,
                cpu_time_s: b.cpu_time_s.zip(cpu_time_s).map(|(a, c)| a + c),
                dt_min: b.dt_min.min(dt_range[0]),
                dt_max: b.dt_max.max(dt_range[1]),
                max_overlap_fraction: b.max_overlap_fraction.max(max_overlap_fraction),
            },
        }
    }
}

/// CPU time (s) the calling thread has used so far: Linux's `/proc/thread-self/schedstat`
/// (first field, ns); `None` on other platforms or if it cannot be read.
pub fn thread_cpu_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

impl RunSummary {
    /// Pretty JSON, refusing non-finite numbers, except in a `stopped` summary: there they
    /// are written as `null` and listed in `not_finite` (the summary of a run stopped by an
    /// overflow is still written, and no NaN reaches the disk).
    pub fn to_json(&self, path: &Path) -> Result<String, OutputError> {
        let bad = self.non_finite_fields();
        if self.status != "stopped" || bad.is_empty() {
            if let Some((k, v)) = bad.first() {
                finite(path, || k.to_string(), *v)?;
            }
            return self.pretty(path);
        }
        let mut s = self.clone();
        s.not_finite = bad.iter().map(|(k, _)| k.to_string()).collect();
        s.pretty(path)
    }

    fn pretty(&self, path: &Path) -> Result<String, OutputError> {
        let mut s = serde_json::to_string_pretty(self).map_err(|e| OutputError::Io {
            file: path.display().to_string(),
            source: std::io::Error::other(e),
        })?;
        s.push('\n');
        Ok(s)
    }

    /// The figures that are not finite, by their JSON path.
    fn non_finite_fields(&self) -> Vec<(&'static str, f64)> {
        let e = &self.energy;
        let all = [
            ("time", self.time),
            ("dt", self.dt),
            ("dt_min", self.dt_min),
            ("dt_max", self.dt_max),
            ("max_overlap_fraction", self.max_overlap_fraction),
            ("wall_time_s", self.wall_time_s),
            ("cpu_time_s", self.cpu_time_s.unwrap_or(0.0)),
            (
                "whole_run.wall_time_s",
                self.whole_run.map_or(0.0, |w| w.wall_time_s),
            ),
            (
                "whole_run.cpu_time_s",
                self.whole_run.and_then(|w| w.cpu_time_s).unwrap_or(0.0),
            ),
            ("whole_run.dt_min", self.whole_run.map_or(0.0, |w| w.dt_min)),
            ("whole_run.dt_max", self.whole_run.map_or(0.0, |w| w.dt_max)),
            (
                "whole_run.max_overlap_fraction",
                self.whole_run.map_or(0.0, |w| w.max_overlap_fraction),
            ),
            ("particle_steps_per_s", self.particle_steps_per_s),
            ("energy.kinetic_translation", e.kinetic_translation),
            ("energy.kinetic_rotation", e.kinetic_rotation),
            ("energy.strain_contact", e.strain_contact),
            ("energy.strain_bond", e.strain_bond),
            ("energy.gravity_potential", e.gravity_potential),
            ("energy.boundary_work", e.boundary_work),
            ("energy.damping", e.damping),
            ("energy.friction", e.friction),
            ("energy.bond_break", e.bond_break),
            ("energy.total", e.total),
            ("energy.initial", e.initial),
            ("energy.balance_error", e.balance_error),
        ];
        all.into_iter().filter(|(_, v)| !v.is_finite()).collect()
    }

    pub fn save(&self, path: &Path) -> Result<(), OutputError> {
        let s = self.to_json(path)?;
        write_atomic(path, s.as_bytes())
    }
}

fn yes() -> bool {
    true
}

fn is_true(v: &bool) -> bool {
    *v
}
