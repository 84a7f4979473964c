//! The one interface every contact law implements, in 2D and 3D alike.

use crate::{Kin, Out, Tangent};

/// A contact law: the force of one pair from its kinematics and tangential history, and the
/// stiffnesses the time step and rolling resistance read.
///
/// `E` switches on the energy terms of [`Out`] (a compile-time flag, so the force pass without
/// energy tracking carries no energy arithmetic).
pub trait ContactLaw<T: Tangent> {
    /// Force for overlap `k.delta > 0`; `us` is the tangential history, updated in place.
    fn force<const E: bool>(&self, k: &Kin<T>, us: &mut T) -> Out<T>;
    /// Normal (tangent) stiffness dF_n/dδ at overlap `delta` (N/m).
    fn kn(&self, r_eff: f64, delta: f64) -> f64;
    /// Tangential stiffness at overlap `delta` (N/m).
    fn ks(&self, r_eff: f64, delta: f64) -> f64;
}
