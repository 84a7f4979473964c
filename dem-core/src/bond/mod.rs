//! Placeholder of the bond stage (the bonds helper replaces this file with the real one).
//! It holds no bonds; it only fixes the interface the pipeline calls
//! (see `docs/dem-core-design.md`, "Bonds ↔ pipeline").

use crate::state::State;
use serde::{Deserialize, Serialize};

/// Bond groups and bonds (none in this placeholder).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Bonds {}

impl Bonds {
    /// Adds bond forces and torques, breaks bonds, logs breaks (no bonds here).
    pub fn compute(&mut self, _st: &mut State, _dt: f64) {}

    /// Adds each disc's bond stiffness for the time step (no bonds here).
    pub fn add_stiffness(&self, _st: &State, _k_trans: &mut [f64], _k_rot: &mut [f64]) {}

    /// Strain energy stored in intact bonds (J).
    pub fn strain_energy(&self) -> f64 {
        0.0
    }

    /// Cumulative strain energy released at breaks (J).
    pub fn released_energy(&self) -> f64 {
        0.0
    }

    /// Renumber disc indices after a spatial reordering.
    pub fn remap(&mut self, _new_index_of_old: &[u32]) {}
}
