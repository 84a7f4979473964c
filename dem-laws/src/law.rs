//! The one interface every contact law implements, in 2D and 3D alike.

use crate::{Kin, Out, Tangent};

/// A contact law: the force of one pair from its kinematics and per-contact history, and the
/// stiffnesses the time step and rolling resistance read.
///
/// `E` switches on the energy terms of [`Out`] (a compile-time flag, so the force pass without
/// energy tracking carries no energy arithmetic).
pub trait ContactLaw<T: Tangent> {
    /// What the law carries from step to step for one contact: the tangential spring `T` for
    /// [`crate::LinearSpringDashpot`] and [`crate::HertzMindlin`], a struct for
    /// [`crate::GranularLaw`] (maximum overlap, JKR neck, Mindlin–Deresiewicz turning
    /// points, rolling moment). A new contact starts from `Default`.
    type History: Copy + Default + core::fmt::Debug;
    /// Force for overlap `k.delta` (> 0 in contact; an adhesive law also acts for
    /// −[`Self::reach`] < δ ≤ 0); the history is updated in place.
    fn force<const E: bool>(&self, k: &Kin<T>, h: &mut Self::History) -> Out<T>;
    /// Normal (tangent) stiffness dF_n/dδ at overlap `delta` (N/m), for the time step.
    fn kn(&self, r_eff: f64, delta: f64) -> f64;
    /// Tangential stiffness at overlap `delta` (N/m).
    fn ks(&self, r_eff: f64, delta: f64) -> f64;
    /// Separation (m, ≥ 0) up to which the law still acts on a pair of effective radius
    /// `r_eff` — a JKR neck or a van der Waals cut-off; 0 for a law acting only in contact.
    /// A solver keeps a pair in its contact list while δ > −reach.
    fn reach(&self, _r_eff: f64) -> f64 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{HertzMindlin, LinearSpringDashpot};
    use nalgebra::Vector3;

    fn through_trait<L: ContactLaw<T>, T: Tangent>(l: &L, k: &Kin<T>) -> (Out<T>, L::History) {
        let mut h = L::History::default();
        (l.force::<true>(k, &mut h), h)
    }

    #[test]
    fn the_two_solver_laws_keep_t_as_their_history() {
        let lsd = LinearSpringDashpot::elastic(1e5, 4e4, 0.3);
        let hm = HertzMindlin::from_materials(7e10, 0.33, 7e10, 0.33, 0.5, 0.3);
        let k = Kin {
            delta: 1e-6,
            vn: -0.1,
            vt: 0.2,
            m_eff: 1e-3,
            r_eff: 1e-3,
            dt: 1e-6,
        };
        let (o, h) = through_trait(&lsd, &k);
        let mut us = 0.0;
        assert_eq!(o, lsd.force::<true, f64>(&k, &mut us));
        assert_eq!(h, us);
        let k3 = Kin {
            vt: Vector3::new(0.0, 0.2, 0.0),
            delta: k.delta,
            vn: k.vn,
            m_eff: k.m_eff,
            r_eff: k.r_eff,
            dt: k.dt,
        };
        let (o, h) = through_trait(&hm, &k3);
        let mut us = Vector3::zeros();
        assert_eq!(o, hm.force::<true, Vector3<f64>>(&k3, &mut us));
        assert_eq!(h, us);
        assert_eq!(<HertzMindlin as ContactLaw<f64>>::reach(&hm, 1e-3), 0.0);
    }
}
