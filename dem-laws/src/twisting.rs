//! Twisting resistance of [`crate::GranularLaw`] (LAMMPS `pair_style granular`, `twisting`
//! keyword): a moment about the contact normal against the relative spin
//! Ω_tw = (ω_i − ω_j)·n. 3D only: a 2D disc spins about the axis normal to the plane, which
//! is perpendicular to every contact normal, so Ω_tw = 0 for discs.
//!
//! Spring–dashpot–slider on the accumulated twist angle ξ_tw (history):
//! ξ_tw += Ω_tw Δt, M_tw = −k_tw ξ_tw − η_tw Ω_tw, limited to |M_tw| ≤ μ_tw F_c with the
//! spring reset to carry the limited moment (as the tangential slider).
//!
//! | JSON `model` | k_tw (N·m/rad), η_tw (N·m·s/rad), μ_tw (m) | source |
//! |---|---|---|
//! | `marshall` | k_tw = ½ k_t a², η_tw = ½ η_t a², μ_tw = (2/3) a μ_t, from the tangential model (k_t its stiffness, η_t its dashpot, μ_t its friction) | Marshall 2009, J. Comput. Phys. 228:1541–1561; LAMMPS `marshall` |
//! | `sds` | given: `k_tw`, `eta_tw`, `mu_tw` | LAMMPS `sds` |
//!
//! Dissipation (returned): the slip work |M_max| |Δξ_slip| plus the dashpot η_tw Ω_tw² Δt.

use serde::{Deserialize, Serialize};

/// A twisting sub-model.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub enum Twisting {
    /// Coefficients from the tangential model and the contact radius (Marshall 2009).
    Marshall,
    /// Given spring k_tw (N·m/rad), dashpot η_tw (N·m·s/rad), friction μ_tw (m).
    Sds { k_tw: f64, eta_tw: f64, mu_tw: f64 },
}

impl Twisting {
    /// (k_tw, η_tw, μ_tw) for contact radius `a` and the tangential model's stiffness `kt`,
    /// dashpot `eta_t` and friction `mu_t`.
    pub fn coefficients(&self, a: f64, kt: f64, eta_t: f64, mu_t: f64) -> (f64, f64, f64) {
        match *self {
            Twisting::Marshall => (0.5 * kt * a * a, 0.5 * eta_t * a * a, 2.0 / 3.0 * a * mu_t),
            Twisting::Sds {
                k_tw,
                eta_tw,
                mu_tw,
            } => (k_tw, eta_tw, mu_tw),
        }
    }

    /// Update the twist angle `xi` for the relative spin `w` over `dt` with coefficients
    /// (k, η, μ) and Coulomb load `f_c`; returns (M_tw on body i, energy dissipated).
    pub fn update(coef: (f64, f64, f64), f_c: f64, w: f64, dt: f64, xi: &mut f64) -> (f64, f64) {
        let (k, eta, mu) = coef;
        let xi1 = *xi + w * dt;
        let m0 = -k * xi1 - eta * w;
        let m_max = mu * f_c.max(0.0);
        let mut dissipated = eta * w * w * dt;
        let m = if m0.abs() > m_max {
            let m = m_max.copysign(m0);
            let xs = if k > 0.0 { -(m + eta * w) / k } else { 0.0 };
            dissipated += m_max * (xi1 - xs).abs();
            *xi = xs;
            m
        } else {
            *xi = xi1;
            m0
        };
        (m, dissipated)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marshall_coefficients_and_slip() {
        let c = Twisting::Marshall.coefficients(1e-4, 1e5, 2.0, 0.3);
        assert_eq!(
            c,
            (0.5 * 1e5 * 1e-8, 0.5 * 2.0 * 1e-8, 2.0 / 3.0 * 1e-4 * 0.3)
        );
        let mut xi = 0.0;
        // Elastic: M = −k ξ.
        let (m, d) = Twisting::update((2.0, 0.0, 1.0), 10.0, 0.5, 1.0, &mut xi);
        assert_eq!((m, d, xi), (-1.0, 0.0, 0.5));
        // Slip at μ F_c = 10: the spring carries −10, ξ = 5.
        let (m, d) = Twisting::update((2.0, 0.0, 1.0), 10.0, 10.0, 1.0, &mut xi);
        assert_eq!((m, xi), (-10.0, 5.0));
        assert!((d - 10.0 * 5.5).abs() < 1e-12);
    }
}
