//! Contact bond (PFC; Potyondy & Cundall 2004, the contact-bond model; S1 uses it to hold a
//! grinding wheel's discs, S4 describes it as acting at the contact point only).
//!
//! A contact bond glues two discs at a point: it carries a normal force Fn (positive in
//! compression) and a shear force Fs at the contact point and no moment, so the bonded discs can
//! still roll over each other. Its springs have stiffness kn, ks in N/m:
//!
//! ```text
//! Fn = −kn (g − g0)        (total form of Fn -= kn Δδn; g0 = gap at installation)
//! Fs -= ks Δδs             (Δδs: relative shear displacement at the contact point)
//! ```
//!
//! with the same kinematics, contact point and force application as the parallel bond
//! ([`super::potyondy2004`]). Strengths are in force units (normal, shear; PFC's contact-bond
//! strengths) through [`super::criteria::Criterion::Force`]; the strain and energy criteria apply
//! too with bond length L = R1 + R2 + g0 and area 2·min(R1,R2)·t.
//!
//! Difference from PFC: in PFC the contact bond is a state of the contact's own linear springs
//! (they then carry tension and do not slip). Here the bond is a separate pair of springs acting
//! in parallel with the contact law, so in compression the contact and the bond stiffness add.
//! To reproduce PFC, give the contact law only what the bond does not (or equal stiffness to both
//! and halve them).

use super::criteria::Loads;
use super::potyondy2004::Kinematics;
use super::BondError;
use serde::{Deserialize, Serialize};

/// Contact-bond parameters of a bond group.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactBondParams {
    /// Normal stiffness (N/m).
    pub kn: f64,
    /// Shear stiffness (N/m).
    pub ks: f64,
}

impl ContactBondParams {
    pub fn validate(&self, group: &str) -> Result<(), BondError> {
        for (f, v) in [("kn", self.kn), ("ks", self.ks)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(BondError::Parameter {
                    group: group.to_string(),
                    field: f.to_string(),
                    value: v,
                });
            }
        }
        Ok(())
    }
}

/// `f = [Fn, Fs, 0]` after one step, and the loads. `rbar` = min(R1, R2) defines the nominal
/// area 2·rbar·t used only by the energy criterion.
#[inline(always)]
pub(crate) fn update(
    p: &ContactBondParams,
    rbar: f64,
    t: f64,
    g0: f64,
    length: f64,
    k: &Kinematics,
    f: [f64; 3],
) -> ([f64; 3], Loads) {
    let f = [-p.kn * (k.gap - g0), f[1] - p.ks * k.dus, 0.0];
    let l = Loads {
        fn_: f[0],
        fs_abs: f[1].abs(),
        m_abs: 0.0,
        area: 2.0 * rbar * t,
        lever: 1.0,
        beta: 0.0,
        kn_a: p.kn,
        ks_a: p.ks,
        kn_i: 0.0,
        length,
    };
    (f, l)
}

/// Strain energy Fn²/(2kn) + Fs²/(2ks) (J).
#[inline]
pub fn energy(p: &ContactBondParams, f: &[f64; 3]) -> f64 {
    f[0] * f[0] / (2.0 * p.kn) + f[1] * f[1] / (2.0 * p.ks)
}

/// Stiffness seen by one disc for the time step: translational max(kn, ks), rotational
/// ks·arm² (the shear spring at the contact point).
#[inline]
pub fn stiffness(p: &ContactBondParams, arm: f64) -> (f64, f64) {
    (p.kn.max(p.ks), p.ks * arm * arm)
}
