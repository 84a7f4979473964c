//! What a law reads of one touching pair and what it returns.

use crate::Tangent;

/// Kinematics of one touching pair, input to a law. `T` is the tangent type: `f64` for 2D
/// discs (components along t = (−n_y, n_x)), `nalgebra::Vector3<f64>` for 3D spheres.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kin<T: Tangent> {
    /// Overlap δ (m), positive in contact.
    pub delta: f64,
    /// Normal relative velocity v_n = (v_j − v_i)·n (m/s), positive when separating.
    pub vn: f64,
    /// Tangential relative velocity of j's contact point with respect to i's (m/s).
    pub vt: T,
    /// Effective mass m* = m_i m_j / (m_i + m_j) (kg).
    pub m_eff: f64,
    /// Effective radius R* = r_i r_j / (r_i + r_j) (m).
    pub r_eff: f64,
    /// Time step Δt (s).
    pub dt: f64,
}

/// The force of a law on disc/sphere j (i receives the opposite), and with energy tracking
/// the terms the energy balance books.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Out<T: Tangent> {
    /// Normal force F_n (N), positive = repulsive.
    pub f_n: f64,
    /// Tangential force F_t (N).
    pub f_t: T,
    /// Elastic energy stored in the contact after the step (J).
    pub e_strain: f64,
    /// Dashpot part of F_n (−c_n v_n): its dissipation is booked with the mean of the
    /// half-step velocities by the integrator.
    pub d_n: f64,
    /// Dashpot part of F_t (−c_t v_t).
    pub d_t: T,
    /// Work dissipated by Coulomb slip in this step (J).
    pub e_fric: f64,
}
