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
