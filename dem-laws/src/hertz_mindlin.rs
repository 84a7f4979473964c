//! Hertz–Mindlin (no-slip) contact with history and a damping that gives a set coefficient of
//! restitution.
//!
//! Discs are 2D cylinders, but like LAMMPS `gran/hertz/history`, LIGGGHTS `hertz` and YADE's
//! `Law2_ScGeom_MindlinPhys_Mindlin`, the law used is the 3D sphere–sphere one, applied per
//! contact (not per unit thickness):
//!
//! * normal: F_n = (4/3) E* √R* δ^{3/2} − c_n v_n (Hertz 1882; Johnson, *Contact Mechanics*
//!   1985, eq. 4.22), with 1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂ and 1/R* = 1/R₁ + 1/R₂;
//! * tangential (Mindlin 1949, no-slip): S_t = 8 G* √(R* δ), 1/G* = (2−ν₁)/G₁ + (2−ν₂)/G₂,
//!   F_t = −S_t u_s − c_t v_t with u_s the accumulated tangential displacement, limited by
//!   μ max(F_n, 0) (Coulomb);
//! * damping (Tsuji et al. 1992, Powder Technol. 71:239): c_n = η √(m* S_n), S_n = 2E*√(R*δ),
//!   c_t = η √(m* S_t). With c ∝ δ^{1/4} the restitution does not depend on the impact
//!   velocity (Antypov & Elliott 2011, EPL 94:50004); LIGGGHTS uses η = 2√(5/6) β,
//!   β = −ln e/√(ln²e + π²). Here η is found by integrating the dimensionless impact
//!   X'' = −X^{3/2} − η √(3/2) X^{1/4} X' (X(0) = 0, X'(0) = 1) and bisecting on η for the
//!   requested e ([`eta_for_restitution`]). The two agree: integrated to convergence, the
//!   LIGGGHTS η gives e within 4e-6 over e = 0.1…0.99 (the `tsuji` damping of the catalogue,
//!   `tests/catalogue.rs`; an earlier version of this note said it only approximated e).
//!
//! Undamped contact time (Johnson 1985, §11.4): t_c = 2.9432 δ_max / v₀ with
//! δ_max = (15 m* v₀² / (16 E* √R*))^{2/5}.

use crate::{ContactLaw, Kin, Out, Tangent};
use serde::{Deserialize, Serialize};

/// Parameters of the Hertz–Mindlin law for one material pair (effective values).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct HertzMindlin {
    /// Effective Young's modulus E* (Pa).
    pub e_star: f64,
    /// Effective shear modulus G* (Pa).
    pub g_star: f64,
    /// Damping constant η (see module docs), from the restitution.
    pub eta: f64,
    /// Coefficient of restitution the damping was calibrated for.
    pub restitution: f64,
    /// Coulomb friction coefficient μ.
    pub mu: f64,
}

impl HertzMindlin {
    /// Law for two materials (E₁, ν₁), (E₂, ν₂), restitution e and friction μ.
    pub fn from_materials(
        e1: f64,
        nu1: f64,
        e2: f64,
        nu2: f64,
        restitution: f64,
        mu: f64,
    ) -> HertzMindlin {
        let g1 = e1 / (2.0 * (1.0 + nu1));
        let g2 = e2 / (2.0 * (1.0 + nu2));
        HertzMindlin {
            e_star: 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2),
            g_star: 1.0 / ((2.0 - nu1) / g1 + (2.0 - nu2) / g2),
            eta: eta_for_restitution(restitution),
            restitution,
            mu,
        }
    }

    /// Tangent normal stiffness dF_n/dδ = 2 E* √(R* δ) (N/m).
    #[inline(always)]
    pub fn kn_tangent(&self, r_eff: f64, delta: f64) -> f64 {
        2.0 * self.e_star * (r_eff * delta).sqrt()
    }

    /// Tangential stiffness S_t = 8 G* √(R* δ) (N/m).
    #[inline(always)]
    pub fn kt(&self, r_eff: f64, delta: f64) -> f64 {
        8.0 * self.g_star * (r_eff * delta).sqrt()
    }

    /// Force of the pair for overlap `k.delta > 0`; `us` is the tangential displacement.
    /// Branch-free (selects only), so that the blocked force pass vectorises.
    #[inline(always)]
    pub fn force<const E: bool, T: Tangent>(&self, k: &Kin<T>, us: &mut T) -> Out<T> {
        let a = (k.r_eff * k.delta).sqrt();
        let sn = 2.0 * self.e_star * a;
        let st = 8.0 * self.g_star * a;
        let f_el = (2.0 / 3.0) * sn * k.delta; // (4/3) E* √R* δ^{3/2}
        let cn = self.eta * (k.m_eff * sn).sqrt();
        let ct = self.eta * (k.m_eff * st).sqrt();
        let f_n = f_el - cn * k.vn;
        let u0 = *us;
        let us1 = u0.add_scaled(k.vt, k.dt);
        let ft0 = us1.scale(-st).add_scaled(k.vt, -ct);
        let f_max = self.mu * f_n.max(0.0);
        let slip = ft0.norm() > f_max;
        let ft_s = ft0.with_length(f_max);
        let us_s = if st > 0.0 {
            ft_s.add_scaled(k.vt, ct).scale(-1.0).div(st)
        } else {
            T::zero()
        };
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
                    .scale(0.5 * st)
                    .dot(us1.add_scaled(us_s, -1.0))
            } else {
                0.0
            };
            out.d_n = -cn * k.vn;
            out.d_t = k.vt.scale(-ct);
            out.e_strain = 0.4 * f_el * k.delta + us.scale(0.5 * st).dot(*us);
        }
        out
    }

    /// Elastic normal force at overlap δ (for contact views).
    pub fn spring_normal(&self, r_eff: f64, delta: f64) -> f64 {
        (4.0 / 3.0) * self.e_star * (r_eff * delta.max(0.0)).sqrt() * delta.max(0.0)
    }
}

impl<T: Tangent> ContactLaw<T> for HertzMindlin {
    type History = T;
    #[inline(always)]
    fn force<const E: bool>(&self, k: &Kin<T>, us: &mut T) -> Out<T> {
        HertzMindlin::force::<E, T>(self, k, us)
    }
    #[inline(always)]
    fn kn(&self, r_eff: f64, delta: f64) -> f64 {
        self.kn_tangent(r_eff, delta)
    }
    #[inline(always)]
    fn ks(&self, r_eff: f64, delta: f64) -> f64 {
        self.kt(r_eff, delta)
    }
}

/// Restitution of the dimensionless damped Hertz impact X'' = −X^{3/2} − η√(3/2) X^{1/4} X'
/// (RK4 until X returns to 0; e = −X' at exit).
pub fn restitution_of_eta(eta: f64) -> f64 {
    let c = eta * 1.5f64.sqrt();
    let acc = |x: f64, v: f64| {
        let xp = x.max(0.0);
        -xp * xp.sqrt() - c * xp.sqrt().sqrt() * v
    };
    exit_velocity(acc, 1e-3, 200_000, 1e-9)
}

/// Exit speed of the dimensionless impact X'' = acc(X, X') from X = 0, X' = 1: RK4 with step
/// `h` until X returns to 0 (the exit velocity interpolated linearly within the last step);
/// 0 if the body comes to rest (X' ≥ 0 with X below `x_rest`) or after `steps` steps.
pub(crate) fn exit_velocity(
    acc: impl Fn(f64, f64) -> f64,
    h: f64,
    steps: usize,
    x_rest: f64,
) -> f64 {
    let (mut x, mut v) = (0.0f64, 1.0f64);
    for _ in 0..steps {
        let (k1x, k1v) = (v, acc(x, v));
        let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v));
        let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v));
        let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x, v + h * k3v));
        let xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if xn <= 0.0 {
            let s = x / (x - xn);
            return -(v + s * (vn - v));
        }
        x = xn;
        v = vn;
        if v >= 0.0 && x < x_rest {
            return 0.0;
        }
    }
    0.0
}

/// Damping constant η giving restitution `e` (bisection on [`restitution_of_eta`]).
pub fn eta_for_restitution(e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    let e = e.max(1e-3);
    let (mut lo, mut hi) = (0.0f64, 4.0f64);
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if restitution_of_eta(mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
