//! Linear spring–dashpot contact with tangential spring history and Coulomb friction
//! (Cundall & Strack 1979, Géotechnique 29(1):47–65; the form of LAMMPS `gran/hooke/history`,
//! Brilliantov et al. 1996 / Silbert et al. 2001, Phys. Rev. E 64:051302).
//!
//! Normal: F_n = k_n δ − c_n v_n (positive = repulsive; not clipped, so the closed-form
//! damped-oscillator contact time π/√(k_n/m* − c_n²/(4m*²)) and restitution
//! e = exp(−π ζ/√(1−ζ²)), ζ = c_n/(2√(m* k_n)), hold exactly).
//! Tangential: the spring displacement u_s accumulates v_t dt while in contact,
//! F_t = −k_s u_s − c_t v_t, limited to |F_t| ≤ μ max(F_n, 0); when the limit is reached the
//! spring is reset so that it carries the limited force (Cundall & Strack's slip rule; LAMMPS
//! rescales the same way).

use crate::{ContactLaw, Kin, Out, Tangent};
use serde::{Deserialize, Serialize};

/// How the normal dashpot coefficient c_n is set.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum NormalDamping {
    /// c_n = 2 ζ √(m* k_n): ζ is the fraction of critical damping of the pair.
    Ratio(f64),
    /// c_n = γ m* (LAMMPS `gran/hooke` γ_n, 1/s).
    Gamma(f64),
}

impl NormalDamping {
    /// Critical-damping ratio giving the coefficient of restitution `e` for the linear
    /// oscillator: ζ = −ln e / √(π² + ln² e) (e.g. Thornton et al. 2013, Powder Technol. 233).
    pub fn from_restitution(e: f64) -> NormalDamping {
        if e >= 1.0 {
            return NormalDamping::Ratio(0.0);
        }
        let l = e.max(1e-12).ln();
        NormalDamping::Ratio(-l / (std::f64::consts::PI.powi(2) + l * l).sqrt())
    }
}

/// Parameters of the linear law for one material pair.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct LinearSpringDashpot {
    /// Normal stiffness (N/m).
    pub kn: f64,
    /// Tangential stiffness (N/m).
    pub ks: f64,
    pub damping: NormalDamping,
    /// Tangential dashpot c_t = `shear_damping` · c_n (LAMMPS default γ_t = γ_n/2 → 0.5;
    /// PFC default 0).
    pub shear_damping: f64,
    /// Coulomb friction coefficient μ.
    pub mu: f64,
}

impl LinearSpringDashpot {
    /// Undamped law with the given stiffnesses and friction.
    pub fn elastic(kn: f64, ks: f64, mu: f64) -> LinearSpringDashpot {
        LinearSpringDashpot {
            kn,
            ks,
            damping: NormalDamping::Ratio(0.0),
            shear_damping: 0.0,
            mu,
        }
    }

    /// Normal dashpot coefficient c_n (N·s/m) for effective mass m*.
    #[inline(always)]
    pub fn cn(&self, m_eff: f64) -> f64 {
        match self.damping {
            NormalDamping::Ratio(z) => {
                if z == 0.0 {
                    0.0
                } else {
                    2.0 * z * (m_eff * self.kn).sqrt()
                }
            }
            NormalDamping::Gamma(g) => g * m_eff,
        }
    }

    /// Force of the pair for overlap `k.delta > 0`; `us` is the tangential spring history.
    #[inline(always)]
    pub fn force<const E: bool, T: Tangent>(&self, k: &Kin<T>, us: &mut T) -> Out<T> {
        let cn = self.cn(k.m_eff);
        self.force_cn::<E, T>(k, cn, us)
    }

    /// [`Self::force`] with the normal dashpot coefficient given. Branch-free (selects only),
    /// so that the blocked force pass vectorises.
    #[inline(always)]
    pub fn force_cn<const E: bool, T: Tangent>(&self, k: &Kin<T>, cn: f64, us: &mut T) -> Out<T> {
        let ct = self.shear_damping * cn;
        let f_n = self.kn * k.delta - cn * k.vn;
        let u0 = *us;
        let us1 = u0.add_scaled(k.vt, k.dt);
        let ft0 = us1.scale(-self.ks).add_scaled(k.vt, -ct);
        let f_max = self.mu * f_n.max(0.0);
        let slip = ft0.norm() > f_max;
        let ft_s = ft0.with_length(f_max);
        // 1/k_s is loop-invariant: one division per block instead of one per pair.
        let inv_ks = if self.ks > 0.0 { 1.0 / self.ks } else { 0.0 };
        let us_s = ft_s.add_scaled(k.vt, ct).scale(-inv_ks);
        let f_t = if slip { ft_s } else { ft0 };
        *us = if slip { us_s } else { us1 };
        let mut out = Out {
            f_n,
            f_t,
            ..Out::default()
        };
        if E {
            // Slip work of the spring: its mean force over the step (trapezoid of the old and
            // the new spring force) times the slip u_s¹ − u_s^slip. Without slip the same
            // trapezoid equals the change of ½ k u_s², so this is what the spring energy
            // does not account for: f_max |Δu_s| in steady slip, the whole stored energy when
            // F_n drops, and possibly negative with a tangential dashpot (limiting the total
            // force makes the spring carry −c_t v_t).
            out.e_fric = if slip {
                u0.add_scaled(us_s, 1.0)
                    .scale(0.5 * self.ks)
                    .dot(us1.add_scaled(us_s, -1.0))
            } else {
                0.0
            };
            out.d_n = -cn * k.vn;
            out.d_t = k.vt.scale(-ct);
            out.e_strain = 0.5 * self.kn * k.delta * k.delta + us.scale(0.5 * self.ks).dot(*us);
        }
        out
    }

    /// Elastic normal force at overlap δ (for contact views).
    pub fn spring_normal(&self, delta: f64) -> f64 {
        self.kn * delta
    }
}

impl<T: Tangent> ContactLaw<T> for LinearSpringDashpot {
    type History = T;
    #[inline(always)]
    fn force<const E: bool>(&self, k: &Kin<T>, us: &mut T) -> Out<T> {
        LinearSpringDashpot::force::<E, T>(self, k, us)
    }
    #[inline(always)]
    fn kn(&self, _r_eff: f64, _delta: f64) -> f64 {
        self.kn
    }
    #[inline(always)]
    fn ks(&self, _r_eff: f64, _delta: f64) -> f64 {
        self.ks
    }
}
