//! One finished run of a study, as its figures: written by [`crate::study`], read by
//! [`crate::study_findings`] (kept apart so that the two import one way).

use serde::{Deserialize, Serialize};

/// One finished run of a study.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Row {
    pub variant: String,
    pub method: String,
    pub depth_mm: f64,
    pub speed_m_s: f64,
    pub seed: u64,
    pub discs: usize,
    /// Mean main force over the window, and over its first and second half (N, scene t).
    pub mean_n: f64,
    pub mean_first_half_n: f64,
    pub mean_second_half_n: f64,
    /// Share of the window's force samples in which the tool touches anything (main force
    /// not 0): low when a detached layer runs ahead of the tool.
    pub contact_share: f64,
    /// Largest sample, and the largest moving mean over one a_p of travel (N).
    pub peak_raw_n: f64,
    pub peak_ap_n: Option<f64>,
    /// Energies at the end (J): the walls' work on the discs (tool and slot), local and
    /// viscous damping, friction, bond breakage, kinetic energy left.
    pub work_j: f64,
    pub damping_j: f64,
    pub friction_j: f64,
    pub bond_break_j: f64,
    pub kinetic_j: f64,
    pub broken_bonds: u64,
    pub chips: usize,
    pub chip_discs: usize,
    pub loose_below: usize,
    /// Machined surface: mean deviation from y_n, and Ra on the mean line (ISO 4287) (m).
    pub surface_mean_dev_m: Option<f64>,
    pub surface_ra_m: Option<f64>,
    pub residual_cracks: usize,
    pub deepest_crack_m: f64,
    /// Removal mode: share of chip discs in single-grain chips, chips' mean and largest
    /// mass-centre speed (m/s) ([`dem_lab::cutting::removal`]).
    pub single_grain_share: Option<f64>,
    pub chip_speed_mean: Option<f64>,
    pub chip_speed_max: Option<f64>,
    pub max_overlap_fraction: Option<f64>,
    pub dt_s: f64,
    pub steps: u64,
    pub cpu_s: Option<f64>,
    pub wall_s: f64,
}
