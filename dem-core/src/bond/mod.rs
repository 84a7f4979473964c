//! Bonds between discs: bond groups (each with its own model, parameters and breakage
//! criterion) and a structure-of-arrays store of the bonds, the stage the pipeline calls once per
//! step ([`Bonds::compute`]).
//!
//! Models: the parallel bond of Potyondy & Cundall 2004 ([`potyondy2004`]) and the contact bond
//! ([`contact_bond`]), and the flat-joint interface of Potyondy 2012 ([`flat_joint`]), whose
//! elements break one by one. Criteria: maximum stress, force, strain or energy ([`criteria`]). Every
//! break is logged ([`breaks`]).
//!
//! **Parallelism and determinism.** Each bond's new forces depend only on its own history and on
//! the two discs' positions and velocities, so they are computed per bond (in parallel with rayon
//! when there are many bonds and more than one thread) into per-bond slots; the per-disc sums are
//! then gathered, in parallel over discs, each disc adding its bonds in bond-store order
//! (`incidence`). With one thread the two passes are fused into a scatter in bond order, the
//! same arithmetic in the same order. Results are bit-identical for any thread count.

pub mod attach;
#[cfg(any(test, feature = "bench"))]
pub mod bench;
pub mod breaks;
pub mod contact_bond;
pub mod criteria;
pub mod flat_joint;
pub(crate) mod fused;
mod incidence;
pub mod install;
mod kernel;
#[cfg(target_arch = "x86_64")]
mod parallel4;
pub mod potyondy2004;
mod split;
mod store;

pub use attach::{attach, world_with_bonds};
pub use breaks::{BreakEvent, BreakLog};
pub use contact_bond::ContactBondParams;
pub use criteria::{BreakMode, Criterion};
pub use flat_joint::{FlatJointParams, FlatJointState};
pub use potyondy2004::ParallelBondParams;
pub use store::{BondView, Bonds};

use serde::{Deserialize, Serialize};

/// Bond model of a group.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum BondModel {
    /// Parallel bond (force and moment), Potyondy & Cundall 2004.
    Parallel(ParallelBondParams),
    /// Contact bond (force only, at the contact point).
    Contact(ContactBondParams),
    /// Flat joint (an interface of elements that break one by one), Potyondy 2012; its
    /// elements' strength is the group's stress criterion.
    FlatJoint(FlatJointParams),
}

/// A bond group: a name (written to outputs and the break log), a model and a criterion.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BondGroup {
    pub name: String,
    pub model: BondModel,
    pub criterion: Criterion,
}

impl BondGroup {
    pub fn validate(&self) -> Result<(), BondError> {
        if self.name.is_empty() {
            return Err(BondError::EmptyName);
        }
        let parallel = match &self.model {
            BondModel::Parallel(p) => {
                p.validate(&self.name)?;
                true
            }
            BondModel::Contact(p) => {
                p.validate(&self.name)?;
                false
            }
            BondModel::FlatJoint(p) => {
                p.validate(&self.name)?;
                if !matches!(self.criterion, Criterion::Stress { .. }) {
                    return Err(BondError::FlatJointNeedsStress(self.name.clone()));
                }
                true
            }
        };
        self.criterion.validate(&self.name, parallel)
    }
}

/// State of a bond.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BondStatus {
    Intact,
    Broken(BreakMode),
}

/// Errors building bonds (bad parameters or indices). The stepping itself cannot fail.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BondError {
    #[error("bond group `{group}`: `{field}` = {value} is out of range")]
    Parameter {
        group: String,
        field: String,
        value: f64,
    },
    #[error("bond group `{0}`: the stress criterion needs a parallel bond (a contact bond has no cross-section); use the force criterion")]
    StressOnContactBond(String),
    #[error("bond group `{0}`: a flat joint's elements break by the stress criterion (tensile strength, cohesion, friction angle); use criterion stress")]
    FlatJointNeedsStress(String),
    #[error("a bond group has an empty name")]
    EmptyName,
    #[error("bond group name `{0}` is used twice")]
    DuplicateGroup(String),
    #[error("too many bond groups ({0}; at most 65535)")]
    TooManyGroups(usize),
    #[error("bonds read back from a checkpoint: {0}")]
    Restored(String),
    #[error("bond group index {0} does not exist")]
    UnknownGroup(usize),
    #[error("bond group `{0}` does not exist")]
    UnknownGroupName(String),
    #[error("disc index {index} out of range ({len} discs)")]
    DiscIndex { index: usize, len: usize },
    #[error("cannot bond disc {0} to itself")]
    SelfBond(usize),
    #[error("discs {0} and {1} have coincident centres; a bond needs a direction")]
    Coincident(usize, usize),
    #[error("bond between discs {i} and {j}: non-finite or non-positive radius or position")]
    BadDisc { i: usize, j: usize },
    #[error("the world has no bond stage (create it with bond groups first)")]
    NoBondStage,
    #[error("clump template `{id}`: {what}")]
    Template { id: String, what: String },
}
