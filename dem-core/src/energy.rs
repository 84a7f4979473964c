//! Energy bookkeeping (PFC's energy tracing, Itasca PFC manual "energy"; Potyondy & Cundall
//! 2004 §2.5): kinetic (translation, rotation), strain stored in contacts and bonds,
//! gravitational potential, boundary work (walls and prescribed-velocity discs), dissipation
//! by damping and friction, and strain energy released at bond breaks. The balance
//!
//! E_now + dissipated + released + removed − E_0 − W_boundary ≈ 0
//!
//! is reported relative to the largest of its terms. Values refer to time t of the last step
//! (the one before `State::time`): strain from the forces at t, kinetic from the mean of the
//! half-step velocities around t. Work and dissipation of forces at t use that same mean
//! velocity v̄ (for central differences ½m(v₊² − v₋²) = F · v̄ Δt exactly): contact dashpots
//! −F_d · v̄ Δt (per disc, `contact::disc_disc::Dashpot`), local and viscous damping
//! likewise, so the balance error is O(Δt²). Friction: the slip work of the tangential spring
//! (trapezoid of its force times the slip), plus the spring energy of contacts that open.
//! `removed` is the energy carried out by discs deleted from a running world
//! ([`crate::World::remove_discs`]): their kinetic energy, the strain of their contacts and
//! bonds and their gravity potential at the moment of deletion (a sink, like dissipation;
//! 0 and left out of the serialised forms in runs that delete nothing).

use serde::{Deserialize, Serialize};

/// Accumulated energies (J).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct EnergyAcc {
    pub kin_trans: f64,
    pub kin_rot: f64,
    pub strain_contact: f64,
    pub grav_pot: f64,
    /// Cumulative dissipation by contact dashpots.
    pub damp_contact: f64,
    /// Cumulative dissipation by local and viscous damping.
    pub damp_body: f64,
    /// Cumulative dissipation by sliding and rolling friction, including the elastic energy
    /// of the tangential (and rolling) springs of contacts that open: their histories are
    /// reset, and that energy is not returned to the discs.
    pub friction: f64,
    /// Cumulative work by prescribed-velocity (fixed) discs.
    pub fixed_work: f64,
    /// Total energy after the first step, and its gravity part.
    pub initial: Option<f64>,
    pub initial_grav: f64,
    /// Cumulative energy carried out by deleted discs (see the module doc).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub removed: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Energies of the world (J), see [`crate::World::energy`].
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct EnergyReport {
    pub kinetic_translation: f64,
    pub kinetic_rotation: f64,
    pub strain_contact: f64,
    pub strain_bond: f64,
    pub gravity_potential: f64,
    /// Work done on the discs by walls and prescribed-velocity discs.
    pub boundary_work: f64,
    pub damping: f64,
    pub friction: f64,
    pub bond_break: f64,
    /// Energy carried out by deleted discs, cumulative (J; see the module doc).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub removed: f64,
    /// Kinetic + strain + gravity potential now, and at the first step.
    pub total: f64,
    pub initial: f64,
    /// (E_now + dissipated + released + removed − E_0 − W) /
    /// max(|E_0|, |E_now|, dissipated, |W|, |removed|).
    pub balance_error: f64,
}

impl EnergyReport {
    /// Assemble the report; `wall_work` is the walls' cumulative work, bond terms from Bonds.
    pub fn new(acc: &EnergyAcc, wall_work: f64, strain_bond: f64, bond_break: f64) -> Self {
        let total = acc.kin_trans + acc.kin_rot + acc.strain_contact + strain_bond + acc.grav_pot;
        let initial = acc.initial.unwrap_or(total);
        let w = wall_work + acc.fixed_work;
        let damping = acc.damp_contact + acc.damp_body;
        let dissipated = damping + acc.friction;
        let err = total + dissipated + bond_break + acc.removed - initial - w;
        let scale = initial
            .abs()
            .max(total.abs())
            .max(dissipated)
            .max(w.abs())
            .max(acc.removed.abs())
            .max(f64::MIN_POSITIVE);
        EnergyReport {
            kinetic_translation: acc.kin_trans,
            kinetic_rotation: acc.kin_rot,
            strain_contact: acc.strain_contact,
            strain_bond,
            gravity_potential: acc.grav_pot,
            boundary_work: w,
            damping,
            friction: acc.friction,
            bond_break,
            removed: acc.removed,
            total,
            initial,
            balance_error: err / scale,
        }
    }

    pub fn kinetic(&self) -> f64 {
        self.kinetic_translation + self.kinetic_rotation
    }
}
