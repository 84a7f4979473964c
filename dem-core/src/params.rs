//! Every tunable of the time step in one struct, with documented defaults.

use crate::damping::DampingFrame;
use serde::{Deserialize, Serialize};

/// Parameters of [`crate::World::step`]. Thread count is not here: the caller runs the world
/// inside a rayon pool of the size it wants, and results do not depend on it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Params {
    /// Safety factor f of the automatic time step dt = f · min(√(m/K), √(I/K_rot))
    /// (see [`crate::timestep`]). Default [`Params::DEFAULT_DT_FACTOR`] = 0.04, chosen so that
    /// an undamped elastic granular gas (196 discs, area fraction 0.26, ≈ 2,500 collisions)
    /// conserves energy to better than 1e-4 over 1e5 steps (`tests/gas_energy.rs`). The
    /// energy error of a collision under central differences grows as (ω dt)², so the drift
    /// over a fixed number of steps grows as f^2.5: measured worst |drift| over six seeds was
    /// 6e-5 at f = 0.04, 3e-4 at 0.07 and 6e-4 at 0.1. Runs that only need stability (e.g.
    /// damped quasi-static loading) may use larger f: the estimate is conservative (it sums
    /// every listed neighbour), and `tests/guard.rs` shows f = 2 is unstable. PFC's default
    /// of the same quantity is 0.8 (Itasca, PFC manual, "timestep determination").
    pub dt_factor: f64,
    /// Fixed time step (s); overrides the automatic one when set (the LAMMPS benchmark uses it).
    pub dt_fixed: Option<f64>,
    /// PFC local damping coefficient α: F_d = −α |F| sign(v) per component and for the torque
    /// (Cundall 1987; Potyondy & Cundall 2004 §2.2). 0 for dynamic runs, 0.7 for quasi-static.
    pub local_damping: f64,
    /// The frame local damping acts in: the lab frame (PFC; default) or each body's bonded
    /// fragment ([`crate::damping`]: leaves rigid motion alone, Galilean-invariant). Left out
    /// of the serialised parameters (checkpoints) at its default.
    #[serde(default, skip_serializing_if = "DampingFrame::is_lab")]
    pub damping_frame: DampingFrame,
    /// Global viscous damping as a fraction ζ of each body's critical damping:
    /// F_v = −2 ζ √(m K_trans) v and T_v = −2 ζ √(I K_rot) ω, with K the stiffness sums of the
    /// time-step estimate. 0 = off.
    pub viscous_damping: f64,
    /// Gravity (m/s²); `None` = no gravity pass.
    pub gravity: Option<[f64; 2]>,
    /// Verlet skin (m): pairs closer than the skin (gap < skin) are listed; the list is rebuilt
    /// when any disc or wall moved more than skin/2. `None` = 0.2 × the smallest radius.
    pub skin: Option<f64>,
    /// Reorder discs in space (cell order) every this many neighbour rebuilds (1 = at every
    /// rebuild, 0 = never). The first build always reorders unless this is 0.
    pub reorder_every: u32,
    /// Guard: largest overlap (beyond the reference gap) allowed, as a fraction of the smaller
    /// radius of the pair.
    pub max_overlap_fraction: f64,
    /// Guard: kinetic energy may not exceed this multiple of the energy supplied so far
    /// (initial total energy plus boundary work plus gravity work).
    pub max_energy_growth: f64,
    /// Track energies (kinetic, strain, dissipation, boundary work) at every step; needed by
    /// [`crate::World::energy`] and the energy-growth guard. Costs a few per cent.
    pub track_energy: bool,
    /// Hertz–Mindlin time-step estimate: the tangent stiffness is taken at the larger of the
    /// current overlap and this fraction of the effective radius R*.
    pub hertz_reference_overlap: f64,
    /// Evaluate parallel bonds (maximum-stress criterion) in the disc–disc pass, with the
    /// geometry of their pair, when every intact bond is one and is a listed pair and the
    /// scene has one linear contact law and does not track energies (see `bond::fused`):
    /// ~1.4× faster on a bonded lattice; the same physics as the separate bond stage, rounded
    /// differently. `false` always runs the separate stage.
    #[serde(default = "yes")]
    pub fuse_bonds: bool,
}

fn yes() -> bool {
    true
}

impl Params {
    /// Default safety factor of the automatic time step (see [`Params::dt_factor`]).
    pub const DEFAULT_DT_FACTOR: f64 = 0.04;
}

impl Default for Params {
    fn default() -> Params {
        Params {
            dt_factor: Params::DEFAULT_DT_FACTOR,
            dt_fixed: None,
            local_damping: 0.0,
            damping_frame: DampingFrame::Lab,
            viscous_damping: 0.0,
            gravity: None,
            skin: None,
            reorder_every: 20,
            max_overlap_fraction: 0.3,
            max_energy_growth: 2.0,
            track_energy: true,
            hertz_reference_overlap: 0.01,
            fuse_bonds: true,
        }
    }
}
