//! Rolling resistance: the elastic–plastic spring model ("type C" without dashpot) of
//! Ai, Chen, Rotter & Ooi 2011, Powder Technol. 206:269–282, eqs. (13)–(16), after
//! Iwashita & Oda 1998 (J. Eng. Mech. 124:285):
//!
//! k_r = c_k k_n μ_r² R*² (Ai et al. take c_k = 2.25), relative rotation increment
//! Δθ_r = (ω_i − ω_j) Δt, moment on disc i M_r ← M_r − k_r Δθ_r, limited to
//! |M_r| ≤ μ_r R* F_n (full mobilisation); disc j receives −M_r.

use serde::{Deserialize, Serialize};

/// Rolling-resistance parameters of one material pair.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct RollingResistance {
    /// Rolling friction coefficient μ_r (dimensionless).
    pub mu_r: f64,
    /// Stiffness factor c_k of k_r = c_k k_n μ_r² R*² (Ai et al. 2011: 2.25).
    pub stiffness_factor: f64,
}

impl RollingResistance {
    pub fn new(mu_r: f64) -> RollingResistance {
        RollingResistance {
            mu_r,
            stiffness_factor: 2.25,
        }
    }

    /// Rolling stiffness k_r (N·m/rad) for normal stiffness k_n and effective radius R*.
    #[inline(always)]
    pub fn kr(&self, kn: f64, r_eff: f64) -> f64 {
        self.stiffness_factor * kn * self.mu_r * self.mu_r * r_eff * r_eff
    }

    /// Update the rolling moment `mr` (on disc i) for the relative rotation rate `w_rel` =
    /// ω_i − ω_j over `dt`; returns the energy dissipated by plastic rolling in this step.
    #[inline(always)]
    pub fn update(&self, kn: f64, r_eff: f64, f_n: f64, w_rel: f64, dt: f64, mr: &mut f64) -> f64 {
        let kr = self.kr(kn, r_eff);
        let trial = *mr - kr * w_rel * dt;
        let m_max = self.mu_r * r_eff * f_n.max(0.0);
        if trial.abs() > m_max {
            *mr = m_max.copysign(trial);
            if kr > 0.0 {
                m_max * ((trial - *mr) / kr).abs()
            } else {
                0.0
            }
        } else {
            *mr = trial;
            0.0
        }
    }
}
