//! Tangential sub-models of [`crate::GranularLaw`] (LAMMPS `pair_style granular`,
//! `tangential` keyword), generic over [`Tangent`] (a scalar along t in 2D, a vector in the
//! tangent plane in 3D).
//!
//! v_t is the tangential relative velocity, u_s the shear history (m), a the contact radius,
//! c the normal dashpot coefficient, F_c the normal load of the Coulomb limit
//! ([`crate::NormalForce::f_coulomb`], with the normal dashpot; ≥ 0) and μ the friction
//! coefficient. The limit |F_t| ≤ μF_c is applied with [`Tangent::with_length`]; when it
//! is reached the spring is reset to carry the limited force (Cundall & Strack 1979).
//!
//! | JSON `model` | force | source |
//! |---|---|---|
//! | `linear_nohistory` | F_t = −min(γ_t\|v_t\|, μF_c) v̂_t | Haff & Werner 1986, Powder Technol. 48:239; LAMMPS `linear_nohistory` |
//! | `linear_history` | u_s += v_t Δt, F_t = −k_t u_s − x_γ,t c v_t | Cundall & Strack 1979, Géotechnique 29:47; LAMMPS `linear_history` |
//! | `mindlin` | as linear_history with k_t = 8G*a (no-slip) | Mindlin 1949, J. Appl. Mech. 16:259; LAMMPS `mindlin` |
//! | `mindlin_rescale` | mindlin, u_s ← u_s a/a_prev when a shrinks | LAMMPS `mindlin_rescale` |
//! | `mindlin/force` | history F_s += −8G*a v_t Δt, F_t = F_s − x_γ,t c v_t | Thornton, Cummins & Cleary 2013, Powder Technol. 233:30 (incremental force); LAMMPS `mindlin/force` |
//! | `mindlin_rescale/force` | mindlin/force, F_s ← F_s a/a_prev when a shrinks | LAMMPS `mindlin_rescale/force` |
//! | `mindlin/deresiewicz` | dF_t = 8G*a θ du, θ from the load history (below) | Mindlin & Deresiewicz 1953, J. Appl. Mech. 20:327; Thornton 1991, J. Phys. D 24:1942; Thornton & Yin 1991, Powder Technol. 65:153 |
//!
//! **Mindlin–Deresiewicz** (partial slip at constant normal load N = F_c). With
//! T the tangential force along the loading direction and T*, T** the last turning points:
//!
//! * loading: θ³ = 1 − T/(μN);
//! * unloading (after T*): θ³ = 1 − (T* − T)/(2μN);
//! * reloading (after T**): θ³ = 1 − (T − T**)/(2μN);
//!
//! (Thornton 1991). Closed forms at constant N, with δ_s = 3μN/(16G*a) the
//! displacement to full slip (Johnson 1985, §7.2): loading
//! T = μN(1 − (1 − δ/δ_s)^{3/2}); unloading from (δ*, T*)
//! T = T* − 2μN(1 − (1 − (δ* − δ)/(2δ_s))^{3/2}). The unloading curve reaching −T* joins
//! the virgin curve in the other direction (the law switches to loading there); reloading
//! that reaches T* rejoins the virgin curve. The increment uses θ at the midpoint force
//! (a predictor–corrector step, second order in Δu). 3D: the rules act on the component of
//! du along the current force direction; the perpendicular part of du is taken with the
//! same stiffness and turns the direction (exact in 2D, where there is no perpendicular
//! part; a simplification of Thornton & Yin's 3D treatment). The change of N is felt only
//! through a and μN (Thornton's ±μΔN(1−θ) term is not included). The model has no dashpot.
//!
//! Under pure normal unloading (v_t = 0, a → a₁ < a₀) the four Mindlin variants carry
//! F_t ∝ a (mindlin: k_t ∝ a on a fixed u_s), ∝ a² (mindlin_rescale), constant
//! (mindlin/force) and ∝ a (mindlin_rescale/force).
//!
//! Energies (E flag): the strain energy of the spring ½k_t|u_s|² (mindlin/deresiewicz and
//! the force histories: |F|²/(2·8G*a), the energy an elastic unloading would return) and the
//! slip work: for the
//! spring models the trapezoid of the old and new spring force times the slip (as
//! [`crate::LinearSpringDashpot`]) for `linear_history`; for `linear_nohistory` the whole
//! F_t·v_t Δt; for `mindlin` and `mindlin/deresiewicz` the spring's work −½(F₀+F₁)·du less the
//! change of strain energy since the last step. For mindlin/deresiewicz that books the
//! micro-slip hysteresis; for mindlin it also books the energy ½Δk_t|u_s|² the no-slip spring
//! gains or loses as a changes with u_s held (a spring of varying stiffness on a stored
//! displacement is not conservative), so that the balance closes.

use crate::{Kin, Tangent};
use serde::{Deserialize, Serialize};

/// A tangential sub-model (module docs).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Tangential {
    /// Viscous Coulomb friction without a spring; γ_t in N·s/m.
    LinearNoHistory { gamma_t: f64, mu: f64 },
    /// Linear spring k_t (N/m) with history; tangential dashpot x_γ,t × the normal one.
    LinearHistory { kt: f64, xgammat: f64, mu: f64 },
    /// Mindlin no-slip spring k_t = 8G*a; G* in Pa. `force`: the history is the elastic
    /// force, incremented by −k_t v_t Δt (LAMMPS `mindlin/force`) instead of the displacement;
    /// `rescale`: the history is scaled by a/a_prev when the contact radius shrinks (LAMMPS
    /// `mindlin_rescale`).
    Mindlin {
        g_star: f64,
        xgammat: f64,
        mu: f64,
        force: bool,
        rescale: bool,
    },
    /// Mindlin–Deresiewicz partial slip; G* in Pa.
    MindlinDeresiewicz { g_star: f64, mu: f64 },
}

/// Loading state of the Mindlin–Deresiewicz model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum MdMode {
    /// Virgin loading (or after full slip).
    #[default]
    Loading,
    /// Unloading from the turning point T*.
    Unloading,
    /// Reloading from the turning point T**.
    Reloading,
}

/// What a tangential sub-model carries from step to step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TangentialHistory<T: Tangent> {
    /// Shear displacement u_s (m) of the spring models.
    pub us: T,
    /// Mindlin–Deresiewicz: unit loading direction (the force is `dir · s`).
    pub dir: T,
    /// Mindlin–Deresiewicz: tangential force T along `dir` (N, signed).
    pub s: f64,
    /// Mindlin–Deresiewicz: turning point T* (N).
    pub t1: f64,
    /// Mindlin–Deresiewicz: turning point T** (N).
    pub t2: f64,
    /// Mindlin–Deresiewicz: loading state.
    pub mode: MdMode,
    /// Stiffness of the last step (N/m; mindlin, mindlin/deresiewicz).
    pub k_prev: f64,
    /// Strain energy reported in the last step (J; mindlin, mindlin/deresiewicz).
    pub e_prev: f64,
    /// Contact radius of the last step (m; mindlin_rescale).
    pub a_prev: f64,
}

/// The tangential sub-model's answer for one step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TangentialForce<T: Tangent> {
    /// F_t on body j (N).
    pub f_t: T,
    /// Its dashpot part −c_t v_t.
    pub d_t: T,
    /// Strain energy of the tangential spring (J).
    pub energy: f64,
    /// Work dissipated by slip in the step (J).
    pub e_fric: f64,
}

/// θ of the Mindlin–Deresiewicz stiffness 8G*a θ for force `s` (module docs).
#[inline]
pub fn md_theta(mode: MdMode, s: f64, t1: f64, t2: f64, mu_n: f64) -> f64 {
    if mu_n <= 0.0 {
        return 0.0;
    }
    let x = match mode {
        MdMode::Loading => 1.0 - s / mu_n,
        MdMode::Unloading => 1.0 - (t1 - s) / (2.0 * mu_n),
        MdMode::Reloading => 1.0 - (s - t2) / (2.0 * mu_n),
    };
    x.clamp(0.0, 1.0).cbrt()
}

impl Tangential {
    /// Friction coefficient μ.
    pub fn mu(&self) -> f64 {
        match *self {
            Tangential::LinearNoHistory { mu, .. }
            | Tangential::LinearHistory { mu, .. }
            | Tangential::Mindlin { mu, .. }
            | Tangential::MindlinDeresiewicz { mu, .. } => mu,
        }
    }

    /// Tangential dashpot coefficient (N·s/m) for the normal one `cn`: γ_t
    /// (linear_nohistory), x_γ,t c_n (linear_history, mindlin), 0 (mindlin/deresiewicz).
    pub fn dashpot(&self, cn: f64) -> f64 {
        match *self {
            Tangential::LinearNoHistory { gamma_t, .. } => gamma_t,
            Tangential::LinearHistory { xgammat, .. } | Tangential::Mindlin { xgammat, .. } => {
                xgammat * cn
            }
            Tangential::MindlinDeresiewicz { .. } => 0.0,
        }
    }

    /// Tangential stiffness (N/m) at contact radius `a` (for the time step).
    pub fn stiffness(&self, a: f64) -> f64 {
        match *self {
            Tangential::LinearNoHistory { .. } => 0.0,
            Tangential::LinearHistory { kt, .. } => kt,
            Tangential::Mindlin { g_star, .. } | Tangential::MindlinDeresiewicz { g_star, .. } => {
                8.0 * g_star * a
            }
        }
    }

    /// Tangential force for one step: `a` contact radius, `cn` normal dashpot coefficient,
    /// `f_c` Coulomb load (clamped at 0 here); the history is updated.
    pub fn force<const E: bool, T: Tangent>(
        &self,
        k: &Kin<T>,
        a: f64,
        cn: f64,
        f_c: f64,
        h: &mut TangentialHistory<T>,
    ) -> TangentialForce<T> {
        let f_max = self.mu() * f_c.max(0.0);
        match *self {
            Tangential::LinearNoHistory { gamma_t, .. } => {
                let f0 = k.vt.scale(-gamma_t);
                let f_t = if f0.norm() > f_max {
                    f0.with_length(f_max)
                } else {
                    f0
                };
                let mut out = TangentialForce {
                    f_t,
                    ..Default::default()
                };
                if E {
                    out.e_fric = -f_t.dot(k.vt) * k.dt;
                }
                out
            }
            Tangential::LinearHistory { kt, xgammat, .. } => {
                spring::<E, T>(k, kt, xgammat * cn, f_max, false, h)
            }
            Tangential::Mindlin {
                g_star,
                xgammat,
                force,
                rescale,
                ..
            } => {
                if rescale && a < h.a_prev {
                    h.us = h.us.scale(a / h.a_prev);
                }
                h.a_prev = a;
                let kt = 8.0 * g_star * a;
                if force {
                    spring_force::<E, T>(k, kt, xgammat * cn, f_max, h)
                } else {
                    spring::<E, T>(k, kt, xgammat * cn, f_max, true, h)
                }
            }
            Tangential::MindlinDeresiewicz { g_star, mu } => {
                md::<E, T>(k, 8.0 * g_star * a, mu * f_c.max(0.0), h)
            }
        }
    }
}

/// Spring–dashpot–slider step (the arithmetic of [`crate::LinearSpringDashpot`]);
/// `varying`: k_t changes with a (mindlin), so the slip work is booked as the spring's work
/// less the change of its energy since the last step.
#[inline]
fn spring<const E: bool, T: Tangent>(
    k: &Kin<T>,
    kt: f64,
    ct: f64,
    f_max: f64,
    varying: bool,
    h: &mut TangentialHistory<T>,
) -> TangentialForce<T> {
    let u0 = h.us;
    let us1 = u0.add_scaled(k.vt, k.dt);
    let ft0 = us1.scale(-kt).add_scaled(k.vt, -ct);
    let slip = ft0.norm() > f_max;
    let (f_t, us) = if slip {
        let ft_s = ft0.with_length(f_max);
        let us_s = if kt > 0.0 {
            ft_s.add_scaled(k.vt, ct).scale(-1.0 / kt)
        } else {
            T::zero()
        };
        (ft_s, us_s)
    } else {
        (ft0, us1)
    };
    h.us = us;
    let mut out = TangentialForce {
        f_t,
        ..Default::default()
    };
    if E {
        out.d_t = k.vt.scale(-ct);
        out.energy = us.scale(0.5 * kt).dot(us);
        out.e_fric = if varying {
            // W = −½(F_sp,0 + F_sp,1)·Δu, F_sp = −k_t u_s.
            let w = u0
                .scale(h.k_prev)
                .add_scaled(us, kt)
                .scale(0.5)
                .dot(k.vt.scale(k.dt));
            let e = w - (out.energy - h.e_prev);
            h.k_prev = kt;
            h.e_prev = out.energy;
            e
        } else if slip {
            u0.add_scaled(us, 1.0)
                .scale(0.5 * kt)
                .dot(us1.add_scaled(us, -1.0))
        } else {
            0.0
        };
    }
    out
}

/// Spring–dashpot–slider step on a force history (`mindlin/force`): F_s += −k_t v_t Δt,
/// F_t = F_s − c_t v_t, limited to μF_c with F_s reset to carry the limited force.
fn spring_force<const E: bool, T: Tangent>(
    k: &Kin<T>,
    kt: f64,
    ct: f64,
    f_max: f64,
    h: &mut TangentialHistory<T>,
) -> TangentialForce<T> {
    let f0 = h.us;
    let du = k.vt.scale(k.dt);
    let fs1 = f0.add_scaled(du, -kt);
    let ft0 = fs1.add_scaled(k.vt, -ct);
    let (f_t, fs) = if ft0.norm() > f_max {
        let ft_s = ft0.with_length(f_max);
        (ft_s, ft_s.add_scaled(k.vt, ct))
    } else {
        (ft0, fs1)
    };
    h.us = fs;
    let mut out = TangentialForce {
        f_t,
        ..Default::default()
    };
    if E {
        out.d_t = k.vt.scale(-ct);
        out.energy = if kt > 0.0 {
            fs.dot(fs) / (2.0 * kt)
        } else {
            0.0
        };
        out.e_fric = -f0.add_scaled(fs, 1.0).scale(0.5).dot(du) - (out.energy - h.e_prev);
        h.e_prev = out.energy;
    }
    out
}

/// One Mindlin–Deresiewicz step for the scalar increment `p` (force-increasing
/// displacement along `dir`) at stiffness `k0` = 8G*a and limit `mu_n` = μN.
fn md_scalar(h: &mut TangentialHistory<impl Tangent>, p: f64, k0: f64, mu_n: f64) -> f64 {
    // Turning points.
    match h.mode {
        MdMode::Loading if p < 0.0 => {
            h.mode = MdMode::Unloading;
            h.t1 = h.s;
        }
        MdMode::Unloading if p > 0.0 => {
            h.mode = MdMode::Reloading;
            h.t2 = h.s;
        }
        MdMode::Reloading if p < 0.0 => {
            h.mode = MdMode::Unloading;
            h.t1 = h.s;
        }
        _ => {}
    }
    let th0 = md_theta(h.mode, h.s, h.t1, h.t2, mu_n);
    let s_pred = h.s + k0 * th0 * p;
    let th = md_theta(h.mode, 0.5 * (h.s + s_pred), h.t1, h.t2, mu_n);
    let mut s = h.s + k0 * th * p;
    if h.mode == MdMode::Loading && s_pred >= mu_n {
        // θ → 0 at full slip: the predictor reaching μN means full slip within the step.
        s = mu_n;
    }
    match h.mode {
        MdMode::Unloading if s <= -h.t1 => {
            // Joined the virgin curve in the other direction.
            h.mode = MdMode::Loading;
        }
        MdMode::Reloading if s >= h.t1 => h.mode = MdMode::Loading,
        _ => {}
    }
    if s.abs() >= mu_n {
        s = mu_n.copysign(s);
        h.mode = MdMode::Loading;
    }
    s
}

fn md<const E: bool, T: Tangent>(
    k: &Kin<T>,
    k0: f64,
    mu_n: f64,
    h: &mut TangentialHistory<T>,
) -> TangentialForce<T> {
    let du = k.vt.scale(k.dt);
    let f0 = h.dir.scale(h.s);
    if h.dir.norm() == 0.0 {
        h.dir = du.scale(-1.0).with_length(1.0);
        if du.norm() == 0.0 {
            h.dir = T::zero();
        }
    }
    let p = -du.dot(h.dir);
    let q = du.scale(-1.0).add_scaled(h.dir, -p); // perpendicular part of −du
    let s0 = h.s;
    let s = md_scalar(h, p, k0, mu_n);
    let th = md_theta(h.mode, 0.5 * (s0 + s), h.t1, h.t2, mu_n);
    let mut f1 = h.dir.scale(s).add_scaled(q, k0 * th);
    if f1.norm() > mu_n {
        f1 = f1.with_length(mu_n);
    }
    // Keep s ≥ 0 in loading so the loading rule reads |T|; carry the sign into dir.
    let l = f1.norm();
    if l > 0.0 {
        let sign = if s < 0.0 && h.mode != MdMode::Loading {
            -1.0
        } else {
            1.0
        };
        h.dir = f1.with_length(1.0).scale(sign);
        h.s = sign * l;
    } else {
        h.s = 0.0;
    }
    if h.mode == MdMode::Loading && h.s < 0.0 {
        h.s = -h.s;
        h.dir = h.dir.scale(-1.0);
    }
    let mut out = TangentialForce {
        f_t: f1,
        ..Default::default()
    };
    if E {
        out.energy = if k0 > 0.0 {
            f1.dot(f1) / (2.0 * k0)
        } else {
            0.0
        };
        out.e_fric = -f0.add_scaled(f1, 1.0).scale(0.5).dot(du) - (out.energy - h.e_prev);
        h.e_prev = out.energy;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn kin<T: Tangent>(vt: T, dt: f64) -> Kin<T> {
        Kin {
            delta: 1e-6,
            vn: 0.0,
            vt,
            m_eff: 1e-3,
            r_eff: 1e-3,
            dt,
        }
    }

    /// Drive the MD model at constant N along a displacement path; returns (δ, T) pairs.
    fn md_path<T: Tangent>(dir: T, path: &[f64], n: usize) -> Vec<(f64, f64)> {
        let law = Tangential::MindlinDeresiewicz {
            g_star: 1e10,
            mu: 0.3,
        };
        let (a, fc) = (1e-5, 10.0);
        let mut h = TangentialHistory::<T>::default();
        let mut x = 0.0;
        let mut out = vec![];
        for w in path.windows(2) {
            let dx = (w[1] - w[0]) / n as f64;
            for _ in 0..n {
                // F_t opposes u_s: T = −F_t·dir for u along dir.
                let k = kin(dir.scale(dx), 1.0);
                let f = law.force::<false, T>(&k, a, 0.0, fc, &mut h);
                x += dx;
                out.push((x, -f.f_t.dot(dir)));
            }
        }
        out
    }

    fn md_closed_form(path_max: f64, x: f64, unloading: bool) -> f64 {
        let (mu_n, k0) = (3.0, 8.0 * 1e10 * 1e-5);
        let ds = 1.5 * mu_n / k0; // 3μN/(16G*a) = 1.5 μN / (8G*a)
        let load = |x: f64| mu_n * (1.0 - (1.0 - x / ds).max(0.0).powf(1.5));
        if !unloading {
            load(x)
        } else {
            let t1 = load(path_max);
            t1 - 2.0 * mu_n * (1.0 - (1.0 - (path_max - x) / (2.0 * ds)).max(0.0).powf(1.5))
        }
    }

    fn check_md<T: Tangent>(dir: T) -> (f64, f64) {
        let ds = 1.5 * 3.0 / (8.0 * 1e10 * 1e-5);
        let xm = 0.6 * ds;
        let n = 2000;
        let p = md_path(dir, &[0.0, xm, -xm], n);
        let (mut e_load, mut e_unl) = (0.0f64, 0.0f64);
        for (i, &(x, t)) in p.iter().enumerate() {
            if i < n {
                e_load = e_load.max((t - md_closed_form(xm, x, false)).abs());
            } else {
                e_unl = e_unl.max((t - md_closed_form(xm, x, true)).abs());
            }
        }
        // Ends at −T* on the virgin curve of the other direction.
        let t_end = p.last().unwrap().1;
        assert!((t_end + md_closed_form(xm, xm, false)).abs() < 1e-5 * 3.0);
        (e_load / 3.0, e_unl / 3.0)
    }

    #[test]
    fn mindlin_deresiewicz_loading_and_unloading_match_the_closed_forms() {
        let (l, u) = check_md(1.0f64);
        println!("MD 2D: max |T − T_closed|/μN loading {l:.2e}, unloading {u:.2e}");
        assert!(l < 1e-6 && u < 1e-6, "{l:e} {u:e}");
        let (l3, u3) = check_md(Vector3::new(0.6, 0.8, 0.0));
        println!("MD 3D: max |T − T_closed|/μN loading {l3:.2e}, unloading {u3:.2e}");
        assert!(l3 < 1e-6 && u3 < 1e-6, "{l3:e} {u3:e}");
    }

    #[test]
    fn mindlin_deresiewicz_reloading_matches_the_closed_form() {
        // Load to δ* = 0.6δ_s, unload to δ** = −0.2δ_s, reload: T = T** + 2μN(1 − (1 −
        // (δ − δ**)/(2δ_s))^{3/2}) (Johnson 1985, §7.2), which meets T* at δ*.
        let (mu_n, k0) = (3.0, 8.0 * 1e10 * 1e-5);
        let ds = 1.5 * mu_n / k0;
        let (x1, x2) = (0.6 * ds, -0.2 * ds);
        let n = 2000;
        let p = md_path(1.0f64, &[0.0, x1, x2, x1], n);
        let t2 = md_closed_form(x1, x2, true);
        let mut worst: f64 = 0.0;
        for &(x, t) in &p[2 * n..] {
            let c = t2 + 2.0 * mu_n * (1.0 - (1.0 - (x - x2) / (2.0 * ds)).powf(1.5));
            worst = worst.max((t - c).abs() / mu_n);
        }
        println!("MD reloading: max |T − T_closed|/μN {worst:.2e}");
        assert!(worst < 1e-6, "{worst:e}");
        let t_star = md_closed_form(x1, x1, false);
        assert!((p.last().unwrap().1 - t_star).abs() < 1e-6 * mu_n);
    }

    #[test]
    fn mindlin_deresiewicz_slips_at_mu_n() {
        let ds = 1.5 * 3.0 / (8.0 * 1e10 * 1e-5);
        let p = md_path(-1.0f64, &[0.0, 2.0 * ds], 1000);
        let t = p.last().unwrap().1;
        assert!((t - 3.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn nohistory_is_viscous_below_the_limit_and_coulomb_above() {
        let law = Tangential::LinearNoHistory {
            gamma_t: 2.0,
            mu: 0.5,
        };
        let mut h = TangentialHistory::default();
        let f = law.force::<true, f64>(&kin(0.1, 1e-3), 0.0, 0.0, 10.0, &mut h);
        assert_eq!(f.f_t, -0.2);
        let f = law.force::<true, f64>(&kin(-100.0, 1e-3), 0.0, 0.0, 10.0, &mut h);
        assert_eq!(f.f_t, 5.0);
        assert!((f.e_fric - 0.5).abs() < 1e-12);
        let v = Vector3::new(30.0, 40.0, 0.0);
        let mut h3 = TangentialHistory::default();
        let f = law.force::<false, Vector3<f64>>(&kin(v, 1e-3), 0.0, 0.0, 10.0, &mut h3);
        assert!((f.f_t - Vector3::new(-3.0, -4.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn linear_history_matches_the_linear_spring_dashpot() {
        let lsd = crate::LinearSpringDashpot {
            kn: 1e5,
            ks: 4e4,
            damping: crate::NormalDamping::Ratio(0.0),
            shear_damping: 0.5,
            mu: 0.3,
        };
        let law = Tangential::LinearHistory {
            kt: 4e4,
            xgammat: 0.5,
            mu: 0.3,
        };
        let cn = 3.0;
        let mut h = TangentialHistory::<f64>::default();
        let mut us = 0.0;
        for i in 0..200 {
            let k = Kin {
                vn: 0.0,
                ..kin(if i < 120 { 0.2 } else { -0.3 }, 1e-5)
            };
            let a = lsd.force_cn::<true, f64>(&k, cn, &mut us);
            let b = law.force::<true, f64>(&k, 0.0, cn, a.f_n, &mut h);
            assert_eq!(a.f_t, b.f_t);
            assert_eq!(us, h.us);
            assert!((a.e_fric - b.e_fric).abs() <= 1e-15 * a.e_fric.abs().max(1e-30));
        }
    }
}
