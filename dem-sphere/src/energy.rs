//! Energy balance (the terms of PFC's energy tracing and `dem-core`'s `EnergyReport`).
//!
//! E = K_t + K_r + V_g + U, with K_t = Σ ½m v², K_r = Σ ½I ω², V_g = −Σ m g·x and U the
//! strain energy the laws report (`Out::e_strain`: normal + tangential springs, vdW
//! potential). The balance
//!
//! E_now + D_dashpot + D_friction − E_0 − W_walls ≈ 0
//!
//! is reported relative to max(|E_0|, |E_now|, D, |W|). Bookkeeping in velocity Verlet: each
//! half kick Δv = F Δt/(2m) changes ½mv² by exactly F·(v_before + v_after)/2 · Δt/2, so
//! the dashpot part of the force (`Out::d_n`, `d_t`) is booked with that mean velocity
//! (exact for the kinetic energy it removes); D_friction sums the laws' slip work
//! (`e_fric`, rolling and twisting dissipation) and the strain energy a contact holds when it
//! breaks (lost with it, as in `dem-core`); W_walls = Σ F_wall·u Δt for walls translating
//! at u. The remaining error is that of the integrator on the conservative forces, O(Δt²)
//! and bounded (it does not accumulate). Rolling-spring energy is not in U (the tests run
//! without rolling resistance).

/// Cumulative energy terms (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct EnergyAcc {
    pub damping: f64,
    pub friction: f64,
    pub wall_work: f64,
    pub initial: Option<f64>,
}

/// Energies of the world (J), [`crate::World::energy`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyReport {
    pub kinetic_translation: f64,
    pub kinetic_rotation: f64,
    /// −Σ m g·x.
    pub gravity_potential: f64,
    /// Strain energy of the contacts (sphere pairs and walls).
    pub strain: f64,
    /// Cumulative dashpot dissipation.
    pub damping: f64,
    /// Cumulative slip (and rolling, twisting) dissipation and energy lost at breaks.
    pub friction: f64,
    /// Cumulative work of the walls on the spheres.
    pub wall_work: f64,
    /// E now and at the first step.
    pub total: f64,
    pub initial: f64,
    /// (E_now + D − E_0 − W) / max(|E_0|, |E_now|, D, |W|).
    pub balance_error: f64,
}

impl EnergyReport {
    pub(crate) fn new(kt: f64, kr: f64, pot: f64, strain: f64, acc: &EnergyAcc) -> EnergyReport {
        let total = kt + kr + pot + strain;
        let initial = acc.initial.unwrap_or(total);
        let d = acc.damping + acc.friction;
        let err = total + d - initial - acc.wall_work;
        let scale = initial
            .abs()
            .max(total.abs())
            .max(d)
            .max(acc.wall_work.abs())
            .max(f64::MIN_POSITIVE);
        EnergyReport {
            kinetic_translation: kt,
            kinetic_rotation: kr,
            gravity_potential: pot,
            strain,
            damping: acc.damping,
            friction: acc.friction,
            wall_work: acc.wall_work,
            total,
            initial,
            balance_error: err / scale,
        }
    }

    /// K_t + K_r.
    pub fn kinetic(&self) -> f64 {
        self.kinetic_translation + self.kinetic_rotation
    }
}
