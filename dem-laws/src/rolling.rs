//! Rolling resistance (LAMMPS `pair_style granular`, `rolling` keyword), after Ai, Chen,
//! Rotter & Ooi 2011, Powder Technol. 206:269–282. ω_rel = ω_i − ω_j is the relative
//! rolling rate (a scalar in 2D; in 3D a vector, which the solver takes in the tangent
//! plane, i.e. without the twisting part along n); M_r is the moment on body i, body j
//! receives −M_r.
//!
//! | JSON `model` | moment | source |
//! |---|---|---|
//! | `constant_torque` | M_r = −μ_r R* F_n ω̂_rel (0 when ω_rel = 0) | Ai et al. 2011, model A |
//! | `elastic_plastic` | M_r ← M_r − k_r ω_rel Δt, \|M_r\| ≤ μ_r R* F_n, k_r = c_k k_n μ_r² R*² | Ai et al. 2011, model C without dashpot (eqs. 13–16); Iwashita & Oda 1998, J. Eng. Mech. 124:285 |
//!
//! Ai et al. take c_k = 2.25; k_n is the normal stiffness (the tangent stiffness for a
//! nonlinear normal law). F_n is clamped at 0. [`RollingResistance`] is the 2D elastic–plastic
//! spring the 2D solver uses; [`Rolling`] the sub-model of [`crate::GranularLaw`], generic
//! over [`Tangent`].
//!
//! Dissipation (returned by the updates): constant torque −M_r·ω_rel Δt; elastic–plastic
//! |M_max| × the plastic rotation |trial − M_r|/k_r in a step at the limit.

use crate::Tangent;
use serde::{Deserialize, Serialize};

/// A rolling sub-model of [`crate::GranularLaw`].
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Rolling {
    /// Ai et al. 2011 model A: a constant moment μ_r R* F_n against ω_rel.
    ConstantTorque { mu_r: f64 },
    /// Ai et al. 2011 model C without dashpot (elastic–plastic spring).
    ElasticPlastic(RollingResistance),
}

impl Rolling {
    /// Update the rolling moment `mr` (on body i) for normal stiffness `kn`, normal force
    /// `f_n`, relative rolling rate `w_rel` = ω_i − ω_j over `dt`; returns the energy
    /// dissipated in the step.
    pub fn update<T: Tangent>(
        &self,
        kn: f64,
        r_eff: f64,
        f_n: f64,
        w_rel: T,
        dt: f64,
        mr: &mut T,
    ) -> f64 {
        match *self {
            Rolling::ConstantTorque { mu_r } => {
                let m_max = mu_r * r_eff * f_n.max(0.0);
                *mr = if w_rel.norm() > 0.0 {
                    w_rel.scale(-1.0).with_length(m_max)
                } else {
                    T::zero()
                };
                -mr.dot(w_rel) * dt
            }
            Rolling::ElasticPlastic(rr) => {
                let kr = rr.kr(kn, r_eff);
                let trial = mr.add_scaled(w_rel, -kr * dt);
                let m_max = rr.mu_r * r_eff * f_n.max(0.0);
                if trial.norm() > m_max {
                    *mr = trial.with_length(m_max);
                    if kr > 0.0 {
                        m_max * trial.add_scaled(*mr, -1.0).norm() / kr
                    } else {
                        0.0
                    }
                } else {
                    *mr = trial;
                    0.0
                }
            }
        }
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn generic_elastic_plastic_is_the_2d_spring() {
        let rr = RollingResistance::new(0.1);
        let law = Rolling::ElasticPlastic(rr);
        let (mut a, mut b) = (0.0f64, 0.0f64);
        for i in 0..500 {
            let w = if i < 300 { 2.0 } else { -5.0 };
            let da = rr.update(1e5, 1e-3, 3.0, w, 1e-4, &mut a);
            let db = law.update(1e5, 1e-3, 3.0, w, 1e-4, &mut b);
            assert!((a - b).abs() <= 1e-15 * a.abs().max(1e-30));
            assert!((da - db).abs() <= 1e-15 * da.abs().max(1e-30));
        }
        // 3D: the same along any axis.
        let mut m = Vector3::zeros();
        let ax = Vector3::new(0.0, 0.6, 0.8);
        let mut s = 0.0f64;
        for _ in 0..300 {
            law.update(1e5, 1e-3, 3.0, ax * 2.0, 1e-4, &mut m);
            rr.update(1e5, 1e-3, 3.0, 2.0, 1e-4, &mut s);
        }
        assert!((m - ax * s).norm() < 1e-15);
    }

    #[test]
    fn constant_torque_opposes_rolling() {
        let law = Rolling::ConstantTorque { mu_r: 0.1 };
        let mut m = 0.0f64;
        let d = law.update(0.0, 1e-3, 2.0, -3.0, 1e-3, &mut m);
        assert!((m - 2e-4).abs() < 1e-18);
        assert!((d - 6e-7).abs() < 1e-18);
        law.update(0.0, 1e-3, 2.0, 0.0, 1e-3, &mut m);
        assert_eq!(m, 0.0);
        let mut v = Vector3::zeros();
        law.update(0.0, 1e-3, 2.0, Vector3::new(0.0, 0.0, 5.0), 1e-3, &mut v);
        assert!((v - Vector3::new(0.0, 0.0, -2e-4)).norm() < 1e-18);
    }
}
