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
    /// discs × steps / wall time of the stepping (outputs excluded).
    pub particle_steps_per_s: f64,
    /// Final energies (J) and relative balance error, see [`crate::energy::EnergyReport`].
    pub energy: EnergyReport,
    /// Files written (relative to the output folder).
    pub files: Vec<String>,
}

impl RunSummary {
    /// Pretty JSON, refusing non-finite numbers.
    pub fn to_json(&self, path: &Path) -> Result<String, OutputError> {
        let e = &self.energy;
        for (k, v) in [
            ("time", self.time),
            ("dt", self.dt),
            ("dt_min", self.dt_min),
            ("dt_max", self.dt_max),
            ("max_overlap_fraction", self.max_overlap_fraction),
            ("wall_time_s", self.wall_time_s),
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
        ] {
            finite(path, || k.to_string(), v)?;
        }
        let mut s = serde_json::to_string_pretty(self).map_err(|e| OutputError::Io {
            file: path.display().to_string(),
            source: std::io::Error::other(e),
        })?;
        s.push('\n');
        Ok(s)
    }

    pub fn save(&self, path: &Path) -> Result<(), OutputError> {
        let s = self.to_json(path)?;
        write_atomic(path, s.as_bytes())
    }
}
