//! Normal sub-models of [`crate::GranularLaw`]: the elastic (and adhesive) normal force
//! F_ne(δ) of one contact, after LAMMPS `pair_style granular` (its `normal` keyword).
//!
//! δ is the overlap (m, > 0 in contact), R* = R₁R₂/(R₁+R₂) the effective radius,
//! a the contact radius and F > 0 repulsive. For two bodies of one material (E, ν):
//! E* = E / (2(1−ν²)), G = E / (2(1+ν)), G* = G / (2(2−ν)) (the general forms
//! 1/E* = Σ(1−νᵢ²)/Eᵢ, 1/G* = Σ(2−νᵢ)/Gᵢ, Johnson 1985, *Contact Mechanics*, ch. 4 and 7).
//!
//! | JSON `model` | force | source |
//! |---|---|---|
//! | `hooke` | F = k_n δ | Cundall & Strack 1979, Géotechnique 29:47 |
//! | `hertz` | F = k_n δ^{3/2} (LAMMPS `hertz` writes k_n a δ = k_n √R* δ^{3/2}) | Hertz 1882, J. reine angew. Math. 92:156 |
//! | `hertz/material` | F = (4/3) E* √R* δ^{3/2} | Johnson 1985, *Contact Mechanics*, eq. 4.22 |
//! | `dmt` | F = (4/3) E* √R* δ^{3/2} − 4πγR* | Derjaguin, Muller & Toporov 1975, J. Colloid Interface Sci. 53:314 |
//! | `jkr` | F = 4E*a³/(3R*) − 4√(πγE*) a^{3/2}, δ = a²/R* − 2√(πγa/E*) | Johnson, Kendall & Roberts 1971, Proc. R. Soc. Lond. A 324:301; Marshall 2009, J. Comput. Phys. 228:1541 |
//! | `walton_braun` | loading F = k₁δ, unloading/reloading F = k₂(δ − δ₀) ≥ 0 | Walton & Braun 1986, J. Rheol. 30:949 |
//!
//! **Adhesion.** γ is the surface energy of each surface (J/m²), so the work of adhesion is
//! w = 2γ, as in LAMMPS. DMT: the pull-off force (the largest tension) is 4πγR* = 2πwR*,
//! reached as δ → 0⁺; the force acts only in contact (δ > 0), as in LAMMPS.
//! JKR: with the contact radius a from δ on the stable branch, the force has its minimum
//! −3πγR* = −(3/2)πwR* (the load-controlled pull-off, Johnson et al. 1971) at
//! a³ = 9πγR*²/(4E*). Once touched the neck persists into negative overlap down to
//! δ_c = −3a_c²/R*, a_c³ = πγR*²/(4E*) (dδ/da = 0, the displacement-controlled separation,
//! Maugis 2000, *Contact, Adhesion and Rupture of Elastic Solids*, ch. 5; F(δ_c) = −(5/3)πγR*),
//! where it snaps. (LAMMPS snaps earlier, at the overlap of the load-controlled pull-off,
//! −a_po²/(3R*) with a_po³ = 9πγR*²/(4E*), i.e. −(3π²γ²R*/(16E*²))^{1/3}.) a(δ) is the largest root of x⁴/R* − c x − δ = 0, x = √a, c = 2√(πγ/E*),
//! found by Newton's method from above (the quartic is convex, so it converges monotonically).
//! Strain energy (E flag): U = ∫F dδ along the stable branch from δ = 0, in closed form
//! U(x) − U(x₀), U(x) = (8E*/15R*²)x¹⁰ − (4E*c/21R* + 4k/7R*)x⁷ + (kc/4)x⁴, k = 4√(πγE*),
//! x₀ = (cR*)^{1/3}; the well depth −U(x_c) is lost at the snap.
//!
//! **Walton–Braun.** δ_max (kept in [`NormalHistory`]) is the largest overlap of the
//! contact; while δ ≥ δ_max, F = k₁δ; below it F = k₂(δ − δ₀), δ₀ = δ_max(1 − k₁/k₂), and
//! F = 0 for δ ≤ δ₀ (a permanent set). A normal impact rebounds with e = √(k₁/k₂)
//! (Walton & Braun 1986); k₂ ≥ k₁ is required. Strain energy ½k₂(δ − δ₀)², the recoverable
//! part; the rest of the loading work, ½k₁(1 − k₁/k₂) d(δ_max²), is dissipated
//! ([`NormalForce::dissipated`]); the time-step stiffness is k₂.
//!
//! Time-step and damping stiffness S_n (N/m): hooke k_n, hertz (3/2)k_n√δ, material models
//! 2E*a (the Hertz tangent stiffness; for JKR with the JKR a), walton_braun k₂ (k₁ when
//! loading, for the damping).

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Effective elastic constants of a pair of one material (E, ν): E*, G*.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct Material {
    /// E* = E / (2(1−ν²)) (Pa).
    pub e_star: f64,
    /// G* = G / (2(2−ν)), G = E / (2(1+ν)) (Pa).
    pub g_star: f64,
}

impl Material {
    /// E*, G* of two bodies of Young's modulus `e` and Poisson's ratio `nu`.
    pub fn identical(e: f64, nu: f64) -> Material {
        let g = e / (2.0 * (1.0 + nu));
        Material {
            e_star: e / (2.0 * (1.0 - nu * nu)),
            g_star: g / (2.0 * (2.0 - nu)),
        }
    }
}

/// A normal sub-model (see the module docs for the formulas).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Normal {
    /// F = k_n δ; k_n in N/m.
    Hooke { kn: f64 },
    /// F = k_n δ^{3/2}; k_n in N/m^{3/2}.
    Hertz { kn: f64 },
    /// F = (4/3)E*√R* δ^{3/2}.
    HertzMaterial(Material),
    /// Hertz − 4πγR* in contact; γ surface energy (J/m²).
    Dmt { material: Material, gamma: f64 },
    /// Johnson–Kendall–Roberts; γ surface energy (J/m²).
    Jkr { material: Material, gamma: f64 },
    /// Walton–Braun hysteretic spring; k₁ loading, k₂ ≥ k₁ unloading (N/m).
    WaltonBraun { k1: f64, k2: f64 },
}

/// What a normal sub-model carries from step to step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct NormalHistory {
    /// Largest overlap of the contact so far (Walton–Braun), m.
    pub delta_max: f64,
    /// The surfaces have touched (δ ≥ 0) and the JKR neck has not snapped.
    pub touched: bool,
}

/// The normal sub-model's answer for one overlap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NormalForce {
    /// The pair interacts (in contact, or inside a JKR neck).
    pub active: bool,
    /// Elastic + adhesive normal force F_ne (N, > 0 repulsive).
    pub f: f64,
    /// Contact radius a (m): √(R*δ), or the JKR radius.
    pub a: f64,
    /// Stiffness S_n (N/m) the damping reads (module docs).
    pub s_n: f64,
    /// Normal load for the Coulomb limit: F_ne + 2 × pull-off for dmt/jkr (Thornton 1991,
    /// J. Phys. D 24:1942; LAMMPS), otherwise F_ne.
    pub f_coulomb: f64,
    /// Strain (and adhesive) energy of the normal spring (J).
    pub energy: f64,
    /// Work dissipated by the normal model in this step (J): the plastic work of
    /// Walton–Braun loading, ½k₁(1 − k₁/k₂)(δ_max,new² − δ_max,old²); 0 otherwise.
    pub dissipated: f64,
}

/// Hertz force (4/3)E*√R* δ^{3/2} (N).
pub fn hertz_force(e_star: f64, r_eff: f64, delta: f64) -> f64 {
    let d = delta.max(0.0);
    (4.0 / 3.0) * e_star * (r_eff * d).sqrt() * d
}

/// DMT pull-off force 4πγR* (N).
pub fn dmt_pulloff(gamma: f64, r_eff: f64) -> f64 {
    4.0 * PI * gamma * r_eff
}

/// JKR pull-off force 3πγR* (N): the largest tension of the JKR curve.
pub fn jkr_pulloff(gamma: f64, r_eff: f64) -> f64 {
    3.0 * PI * gamma * r_eff
}

/// JKR overlap at contact radius `a`: δ = a²/R* − 2√(πγa/E*).
pub fn jkr_overlap(e_star: f64, gamma: f64, r_eff: f64, a: f64) -> f64 {
    a * a / r_eff - 2.0 * (PI * gamma * a / e_star).sqrt()
}

/// JKR force at contact radius `a`: 4E*a³/(3R*) − 4√(πγE*) a^{3/2}.
pub fn jkr_force_of_radius(e_star: f64, gamma: f64, r_eff: f64, a: f64) -> f64 {
    4.0 * e_star * a * a * a / (3.0 * r_eff) - 4.0 * (PI * gamma * e_star).sqrt() * a * a.sqrt()
}

/// The JKR snap-off overlap δ_c = −3a_c²/R*, a_c³ = πγR*²/(4E*) (≤ 0).
pub fn jkr_critical_overlap(e_star: f64, gamma: f64, r_eff: f64) -> f64 {
    let ac = (PI * gamma * r_eff * r_eff / (4.0 * e_star)).cbrt();
    -3.0 * ac * ac / r_eff
}

/// JKR contact radius for overlap δ ≥ δ_c on the stable branch (None below δ_c).
pub fn jkr_contact_radius(e_star: f64, gamma: f64, r_eff: f64, delta: f64) -> Option<f64> {
    if gamma == 0.0 {
        return Some((r_eff * delta.max(0.0)).sqrt());
    }
    if delta < jkr_critical_overlap(e_star, gamma, r_eff) {
        return None;
    }
    // f(x) = x⁴/R − c x − δ, x = √a; convex for x > 0; start above the largest root.
    let c = 2.0 * (PI * gamma / e_star).sqrt();
    let xc = (c * r_eff / 4.0).cbrt(); // f'(xc) = 0
    let mut x = (r_eff * delta.max(0.0)).sqrt().sqrt() + (c * r_eff).cbrt();
    for _ in 0..100 {
        let f = x * x * x * x / r_eff - c * x - delta;
        let fp = 4.0 * x * x * x / r_eff - c;
        if fp <= 0.0 {
            x = xc;
            break;
        }
        let dx = f / fp;
        x -= dx;
        if dx.abs() <= 1e-15 * x {
            break;
        }
    }
    Some(x.max(xc) * x.max(xc))
}

/// JKR strain energy along the stable branch, ∫F dδ from the touching state δ = 0 (J).
fn jkr_energy(e_star: f64, gamma: f64, r_eff: f64, a: f64) -> f64 {
    let c = 2.0 * (PI * gamma / e_star).sqrt();
    let k = 4.0 * (PI * gamma * e_star).sqrt();
    let u = |x: f64| {
        let x4 = x * x * x * x;
        let x7 = x4 * x * x * x;
        (8.0 * e_star / (15.0 * r_eff * r_eff)) * x7 * x * x * x
            - (4.0 * e_star * c / (21.0 * r_eff) + 4.0 * k / (7.0 * r_eff)) * x7
            + 0.25 * k * c * x4
    };
    u(a.sqrt()) - u((c * r_eff).cbrt())
}

impl Normal {
    /// E*, G* of a material model (hertz/material, dmt, jkr); None otherwise.
    pub fn material(&self) -> Option<Material> {
        match *self {
            Normal::HertzMaterial(m) | Normal::Dmt { material: m, .. } => Some(m),
            Normal::Jkr { material: m, .. } => Some(m),
            _ => None,
        }
    }

    /// Whether the elastic force is linear in δ (hooke): the damping calibration differs.
    pub fn is_linear(&self) -> bool {
        matches!(self, Normal::Hooke { .. })
    }

    /// Pull-off force (N, ≥ 0): 4πγR* (dmt), 3πγR* (jkr), 0 otherwise.
    pub fn pulloff(&self, r_eff: f64) -> f64 {
        match *self {
            Normal::Dmt { gamma, .. } => dmt_pulloff(gamma, r_eff),
            Normal::Jkr { gamma, .. } => jkr_pulloff(gamma, r_eff),
            _ => 0.0,
        }
    }

    /// Separation (≥ 0) down to which a touched contact persists: −δ_c for jkr, else 0.
    pub fn reach(&self, r_eff: f64) -> f64 {
        match *self {
            Normal::Jkr { material, gamma } => -jkr_critical_overlap(material.e_star, gamma, r_eff),
            _ => 0.0,
        }
    }

    /// Tangent stiffness (N/m) for the time step at overlap δ (module docs).
    pub fn stiffness(&self, r_eff: f64, delta: f64) -> f64 {
        let d = delta.max(0.0);
        match *self {
            Normal::Hooke { kn } => kn,
            Normal::Hertz { kn } => 1.5 * kn * d.sqrt(),
            Normal::HertzMaterial(m) | Normal::Dmt { material: m, .. } => {
                2.0 * m.e_star * (r_eff * d).sqrt()
            }
            Normal::Jkr { material, gamma } => {
                let a = jkr_contact_radius(material.e_star, gamma, r_eff, delta).unwrap_or(0.0);
                2.0 * material.e_star * a
            }
            Normal::WaltonBraun { k2, .. } => k2,
        }
    }

    /// Elastic normal force at overlap `delta`, updating the history (module docs).
    pub fn eval(&self, r_eff: f64, delta: f64, h: &mut NormalHistory) -> NormalForce {
        if delta >= 0.0 {
            h.touched = true;
        }
        if let Normal::Jkr { material, gamma } = *self {
            if !h.touched {
                return NormalForce::default();
            }
            let e = material.e_star;
            let Some(a) = jkr_contact_radius(e, gamma, r_eff, delta) else {
                *h = NormalHistory::default();
                return NormalForce::default();
            };
            let f = jkr_force_of_radius(e, gamma, r_eff, a);
            return NormalForce {
                active: true,
                f,
                a,
                s_n: 2.0 * e * a,
                f_coulomb: f + 2.0 * jkr_pulloff(gamma, r_eff),
                energy: jkr_energy(e, gamma, r_eff, a),
                dissipated: 0.0,
            };
        }
        if delta <= 0.0 {
            *h = NormalHistory::default();
            return NormalForce::default();
        }
        let a = (r_eff * delta).sqrt();
        let mut dissipated = 0.0;
        let (f, s_n, energy, f_coulomb) = match *self {
            Normal::Hooke { kn } => {
                let f = kn * delta;
                (f, kn, 0.5 * f * delta, f)
            }
            Normal::Hertz { kn } => {
                let f = kn * delta * delta.sqrt();
                (f, 1.5 * kn * delta.sqrt(), 0.4 * f * delta, f)
            }
            Normal::HertzMaterial(m) => {
                let f = hertz_force(m.e_star, r_eff, delta);
                (f, 2.0 * m.e_star * a, 0.4 * f * delta, f)
            }
            Normal::Dmt { material, gamma } => {
                let fh = hertz_force(material.e_star, r_eff, delta);
                let p = dmt_pulloff(gamma, r_eff);
                (
                    fh - p,
                    2.0 * material.e_star * a,
                    0.4 * fh * delta - p * delta,
                    fh + p,
                )
            }
            Normal::WaltonBraun { k1, k2 } => {
                if delta >= h.delta_max {
                    dissipated = 0.5 * k1 * (1.0 - k1 / k2) * (delta * delta - h.delta_max.powi(2));
                    h.delta_max = delta;
                }
                let d0 = h.delta_max * (1.0 - k1 / k2);
                let loading = delta >= h.delta_max;
                let f = if loading {
                    k1 * delta
                } else {
                    (k2 * (delta - d0)).max(0.0)
                };
                let x = (delta - d0).max(0.0);
                (f, if loading { k1 } else { k2 }, 0.5 * k2 * x * x, f)
            }
            Normal::Jkr { .. } => unreachable!("handled above"),
        };
        NormalForce {
            active: true,
            f,
            a,
            s_n,
            f_coulomb,
            energy,
            dissipated,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    const R: f64 = 1e-3;

    fn jkr() -> (Normal, Material, f64) {
        let m = Material::identical(7e10, 0.33);
        let gamma = 0.5;
        (Normal::Jkr { material: m, gamma }, m, gamma)
    }

    #[test]
    fn material_constants() {
        let m = Material::identical(2.0, 0.0);
        assert_relative_eq!(m.e_star, 1.0);
        assert_relative_eq!(m.g_star, 0.25);
    }

    #[test]
    fn jkr_radius_inverts_the_overlap() {
        let (_, m, g) = jkr();
        let dc = jkr_critical_overlap(m.e_star, g, R);
        for &d in &[1e-6, 1e-8, 0.0, 0.5 * dc, 0.999 * dc] {
            let a = jkr_contact_radius(m.e_star, g, R, d).unwrap();
            assert_relative_eq!(jkr_overlap(m.e_star, g, R, a), d, epsilon = 1e-12 * R);
        }
        assert!(jkr_contact_radius(m.e_star, g, R, 1.001 * dc).is_none());
        // F(δ_c) = −(5/3)πγR* (displacement-controlled separation).
        let ac = jkr_contact_radius(m.e_star, g, R, dc).unwrap();
        assert_relative_eq!(
            jkr_force_of_radius(m.e_star, g, R, ac),
            -5.0 / 3.0 * PI * g * R,
            max_relative = 1e-6
        );
    }

    #[test]
    fn jkr_pulloff_is_3_pi_gamma_r() {
        // Unload a touched contact from δ = 1e-6 m down to snap-off; the largest tension
        // on the way is the pull-off force.
        let (law, m, g) = jkr();
        let mut h = NormalHistory::default();
        let dc = jkr_critical_overlap(m.e_star, g, R);
        let n = 200_000;
        let (d0, mut f_min) = (1e-6, f64::INFINITY);
        let mut snapped_at = None;
        for i in 0..=n {
            let d = d0 - (d0 - 1.01 * dc) * i as f64 / n as f64;
            let nf = law.eval(R, d, &mut h);
            if !nf.active {
                snapped_at.get_or_insert(d);
                continue;
            }
            f_min = f_min.min(nf.f);
        }
        let err = (-f_min - jkr_pulloff(g, R)).abs() / jkr_pulloff(g, R);
        assert!(err < 1e-8, "JKR pull-off error {err:e}");
        let s = snapped_at.unwrap();
        assert!(
            (s - dc).abs() < (d0 - 1.01 * dc) / n as f64 * 1.01,
            "snap at {s:e}, δc {dc:e}"
        );
        // A new contact does not feel the neck before it touches.
        let mut h = NormalHistory::default();
        assert!(!law.eval(R, 0.5 * dc, &mut h).active);
    }

    #[test]
    fn jkr_energy_is_the_integral_of_the_force() {
        let (law, m, g) = jkr();
        let mut h = NormalHistory::default();
        let (d1, d2) = (0.3 * jkr_critical_overlap(m.e_star, g, R), 2e-7);
        law.eval(R, 0.0, &mut h); // touch
        let e1 = law.eval(R, d1, &mut h).energy;
        let e2 = law.eval(R, d2, &mut h).energy;
        // Simpson's rule on F(δ).
        let n = 2000;
        let hs = (d2 - d1) / n as f64;
        let mut s = 0.0;
        for i in 0..=n {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            s += w * law.eval(R, d1 + i as f64 * hs, &mut h).f;
        }
        assert_relative_eq!(e2 - e1, s * hs / 3.0, max_relative = 1e-9);
        assert_relative_eq!(law.eval(R, 0.0, &mut h).energy, 0.0, epsilon = 1e-24);
    }

    #[test]
    fn dmt_pulloff_is_4_pi_gamma_r() {
        let m = Material::identical(7e10, 0.33);
        let law = Normal::Dmt {
            material: m,
            gamma: 0.5,
        };
        let mut h = NormalHistory::default();
        let f = law.eval(R, 1e-300, &mut h).f;
        assert_relative_eq!(-f, 4.0 * PI * 0.5 * R, max_relative = 1e-12);
        assert_relative_eq!(law.pulloff(R), 4.0 * PI * 0.5 * R);
        assert!(!law.eval(R, -1e-12, &mut h).active);
    }

    #[test]
    fn walton_braun_unloads_along_k2() {
        let law = Normal::WaltonBraun { k1: 1e5, k2: 4e5 };
        let mut h = NormalHistory::default();
        assert_relative_eq!(law.eval(R, 1e-4, &mut h).f, 10.0);
        assert_relative_eq!(h.delta_max, 1e-4);
        // δ₀ = δ_max (1 − k1/k2) = 0.75e-4.
        assert_relative_eq!(
            law.eval(R, 0.9e-4, &mut h).f,
            4e5 * 0.15e-4,
            max_relative = 1e-12
        );
        assert_eq!(law.eval(R, 0.7e-4, &mut h).f, 0.0);
        // Reloading follows k2 back to the loading line, then k1 again.
        assert_relative_eq!(law.eval(R, 1.1e-4, &mut h).f, 11.0, max_relative = 1e-12);
    }
}
