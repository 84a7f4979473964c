//! A contact law composed of sub-models, in the manner of LAMMPS `pair_style granular`
//! (doc page `pair_granular`): normal + damping + tangential (+ rolling) (+ twisting)
//! (+ van der Waals).
//!
//! One step of a contact, F > 0 repulsive:
//!
//! 1. normal ([`Normal::eval`]): F_ne, the contact radius a, the stiffness S_n;
//! 2. damping: c = [`Damping::coefficient`](m*, a, S_n), F_n = F_ne − c v_n; with
//!    `coeff_restitution` on a nonlinear normal model, or `limit_damping`,
//!    F_n ≥ min(F_ne, 0) (clipped);
//! 3. tangential ([`Tangential::force`]) with the Coulomb load F_c = F_n, or
//!    F_n + 2 × pull-off for dmt/jkr (Thornton 1991; LAMMPS);
//! 4. van der Waals ([`VanDerWaals::eval`]): F_n −= F_vdw(max(h, h_min)) for h = −δ < h_cut;
//! 5. rolling and twisting, by the solver after the force ([`GranularLaw::roll`],
//!    [`GranularLaw::twist`]), on the relative rolling rate and spin, with the moment and
//!    the twist angle kept in the history.
//!
//! Outside contact (δ < 0, no JKR neck) only van der Waals acts, and the contact history is
//! reset. [`ContactLaw::reach`] is the JKR snap-off separation or the vdW cut-off.
//!
//! Energies (E flag, [`Out`]): `e_strain` = normal strain energy (including the adhesive
//! work, negative for dmt below the Hertz energy; the JKR energy from δ = 0) + tangential
//! strain energy + vdW potential V ≤ 0; `d_n` = F_n − F_ne − F_vdw (the dashpot force
//! actually applied), `d_t` the tangential dashpot, `e_fric` the slip work plus the plastic
//! work of the normal model (Walton–Braun loading). What the springs hold when a contact
//! breaks is lost with it (the solver sees `e_strain` vanish).
//!
//! Time step: [`ContactLaw::kn`] is the normal stiffness S_n at δ (hertz: (3/2)k_n√δ,
//! material models 2E*√(R*δ), walton_braun k₂), [`ContactLaw::ks`] the tangential one.

use crate::normal::NormalHistory;
use crate::rotate_history;
use crate::tangential::TangentialHistory;
use crate::{
    ContactLaw, Damping, Kin, Normal, Out, Rolling, Tangent, Tangential, Twisting, VanDerWaals,
};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A composed contact law (module docs).
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct GranularLaw {
    pub normal: Normal,
    pub damping: Damping,
    pub tangential: Tangential,
    pub rolling: Option<Rolling>,
    pub twisting: Option<Twisting>,
    pub vdw: Option<VanDerWaals>,
    /// Clip the normal dashpot so that F_n ≥ min(F_ne, 0) whatever the damping model
    /// (LAMMPS' `limit_damping` keyword; `coeff_restitution` on a nonlinear model always
    /// clips).
    pub limit_damping: bool,
}

/// Per-contact history of a [`GranularLaw`], generic over the tangent type.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GranularHistory<T: Tangent> {
    pub normal: NormalHistory,
    pub tangential: TangentialHistory<T>,
    /// Rolling moment M_r on body i (N·m).
    pub rolling: T,
    /// Accumulated twist angle ξ_tw (rad, 3D).
    pub twist: f64,
}

impl GranularHistory<Vector3<f64>> {
    /// Bring the 3D history into the tangent plane of the current unit normal `n` (step 1 of
    /// the pipeline, [`rotate_history`]): the shear displacement, the Mindlin–Deresiewicz
    /// force direction and the rolling moment keep their lengths.
    pub fn rotate_into(&mut self, n: Vector3<f64>) {
        self.tangential.us = rotate_history(self.tangential.us, n);
        self.tangential.dir = rotate_history(self.tangential.dir, n);
        self.rolling = rotate_history(self.rolling, n);
    }
}

impl GranularLaw {
    /// Force of the pair of radii R₁, R₂ (the exact Hamaker sphere form needs both;
    /// `k.r_eff` must be R₁R₂/(R₁+R₂)). See the module docs for the steps.
    pub fn force_pair<const E: bool, T: Tangent>(
        &self,
        k: &Kin<T>,
        r1: f64,
        r2: f64,
        h: &mut GranularHistory<T>,
    ) -> Out<T> {
        let nf = self.normal.eval(k.r_eff, k.delta, &mut h.normal);
        let mut out = Out::default();
        if nf.active {
            let c = self.damping.coefficient(k.m_eff, nf.a, nf.s_n);
            let mut f_n = nf.f - c * k.vn;
            if self.limit_damping || self.damping.clips() {
                f_n = f_n.max(nf.f.min(0.0));
            }
            let f_c = nf.f_coulomb + (f_n - nf.f);
            let t = self
                .tangential
                .force::<E, T>(k, nf.a, c, f_c, &mut h.tangential);
            out.f_n = f_n;
            out.f_t = t.f_t;
            if E {
                out.d_n = f_n - nf.f;
                out.d_t = t.d_t;
                out.e_strain = nf.energy + t.energy;
                out.e_fric = t.e_fric + nf.dissipated;
            }
        } else {
            h.tangential = TangentialHistory::default();
            h.rolling = T::zero();
            h.twist = 0.0;
        }
        if let Some(v) = &self.vdw {
            let (f, pot) = v.eval(r1, r2, k.delta);
            out.f_n -= f;
            if E {
                out.e_strain += pot;
            }
        }
        out
    }

    /// Update the rolling moment (history) for the relative rolling rate `w_rel` = ω_i − ω_j
    /// and the normal force `f_n` of this step; returns (M_r on body i, energy dissipated).
    /// No rolling model, or no contact: (0, 0).
    pub fn roll<T: Tangent>(
        &self,
        k: &Kin<T>,
        f_n: f64,
        w_rel: T,
        h: &mut GranularHistory<T>,
    ) -> (T, f64) {
        match &self.rolling {
            None => (T::zero(), 0.0),
            Some(_) if !h.normal.touched => {
                h.rolling = T::zero();
                (T::zero(), 0.0)
            }
            Some(r) => {
                let kn = self.normal.stiffness(k.r_eff, k.delta);
                let d = r.update(kn, k.r_eff, f_n, w_rel, k.dt, &mut h.rolling);
                (h.rolling, d)
            }
        }
    }

    /// Update the twisting moment (history) for the relative spin `w_twist` = (ω_i − ω_j)·n
    /// (3D) and the normal force `f_n` of this step; returns (M_tw on body i about n, energy
    /// dissipated). No twisting model, or no contact: (0, 0).
    pub fn twist<T: Tangent>(
        &self,
        k: &Kin<T>,
        f_n: f64,
        w_twist: f64,
        h: &mut GranularHistory<T>,
    ) -> (f64, f64) {
        let Some(tw) = &self.twisting else {
            return (0.0, 0.0);
        };
        if !h.normal.touched {
            h.twist = 0.0;
            return (0.0, 0.0);
        }
        let a = self.radius(k.r_eff, k.delta);
        let cn = self
            .damping
            .coefficient(k.m_eff, a, self.normal.stiffness(k.r_eff, k.delta));
        let t = &self.tangential;
        let coef = tw.coefficients(a, t.stiffness(a), t.dashpot(cn), t.mu());
        let f_c = f_n + 2.0 * self.normal.pulloff(k.r_eff);
        Twisting::update(coef, f_c, w_twist, k.dt, &mut h.twist)
    }

    /// Contact radius at overlap δ without history (√(R*δ); JKR radius for jkr).
    fn radius(&self, r_eff: f64, delta: f64) -> f64 {
        match self.normal {
            Normal::Jkr { material, gamma } => {
                crate::normal::jkr_contact_radius(material.e_star, gamma, r_eff, delta)
                    .unwrap_or(0.0)
            }
            _ => (r_eff * delta.max(0.0)).sqrt(),
        }
    }
}

impl<T: Tangent> ContactLaw<T> for GranularLaw {
    type History = GranularHistory<T>;

    /// [`GranularLaw::force_pair`] with R₁ = R₂ = 2R* (exact for equal spheres).
    fn force<const E: bool>(&self, k: &Kin<T>, h: &mut GranularHistory<T>) -> Out<T> {
        self.force_pair::<E, T>(k, 2.0 * k.r_eff, 2.0 * k.r_eff, h)
    }

    fn kn(&self, r_eff: f64, delta: f64) -> f64 {
        self.normal.stiffness(r_eff, delta)
    }

    fn ks(&self, r_eff: f64, delta: f64) -> f64 {
        self.tangential.stiffness(self.radius(r_eff, delta))
    }

    fn reach(&self, r_eff: f64) -> f64 {
        let v = self.vdw.map_or(0.0, |v| v.cutoff);
        self.normal.reach(r_eff).max(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rotated_3d_history_stays_tangent() {
        let mut h = GranularHistory::<Vector3<f64>>::default();
        h.tangential.us = Vector3::new(1e-6, 2e-6, 0.0);
        h.tangential.dir = Vector3::new(0.0, 1.0, 0.0);
        h.rolling = Vector3::new(0.0, 3e-3, 4e-3);
        let n = Vector3::new(0.0, 0.6, 0.8);
        h.rotate_into(n);
        for v in [h.tangential.us, h.tangential.dir, h.rolling] {
            assert!(Vector3::dot(&v, &n).abs() < 1e-15 * v.norm().max(1e-300));
        }
        assert!((h.tangential.dir.norm() - 1.0).abs() < 1e-15);
        assert!((h.tangential.us.norm() - 5e-12f64.sqrt()).abs() < 1e-20);
    }
}
