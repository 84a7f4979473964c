//! Contact laws written once for 2D discs and 3D spheres.
//!
//! A law maps the kinematics of one touching pair ([`Kin`]: overlap δ, normal and tangential
//! relative velocity, effective mass and radius, Δt) and its tangential history to the
//! pair's force ([`Out`]). Each law is a type implementing [`ContactLaw`] over a
//! [`Tangent`]: `f64` for discs (the tangent plane is a line) and `nalgebra::Vector3<f64>`
//! for spheres, so the same code serves the 2D solver (`dem-core`) and the 3D one.
//!
//! The pipeline of a contact, as a solver drives it:
//!
//! 1. geometry (the solver): normal n, overlap δ, contact arms, relative velocity → [`Kin`];
//!    in 3D the history is first brought into the new tangent plane ([`rotate_history`]);
//! 2. law: [`ContactLaw::force`] → F_n, F_t and, with `E = true`, the energy terms;
//! 3. rolling resistance on the relative rotation ([`RollingResistance`]);
//! 4. the solver applies ±F at the contact point and the torques.
//!
//! Laws: [`LinearSpringDashpot`] (Cundall & Strack 1979) and [`HertzMindlin`] (Hertz 1882,
//! Mindlin 1949, Tsuji et al. 1992 damping calibrated for an exact restitution). Each module
//! gives its formulas and sources.

mod hertz_mindlin;
// Two-body impact integrator for the Chung & Ooi (2011) benchmark (issue 50 item 4).
mod impact;
mod kin;
mod law;
mod linear_spring_dashpot;
mod rolling;
mod tangent;

pub use hertz_mindlin::{eta_for_restitution, restitution_of_eta, HertzMindlin};
pub use kin::{Kin, Out};
pub use law::ContactLaw;
pub use linear_spring_dashpot::{LinearSpringDashpot, NormalDamping};
pub use rolling::RollingResistance;
pub use tangent::{rotate_history, Tangent};

// The two-body impact integrator (issue 50 item 4).
pub use impact::{
    run as run_impact, Body, HertzImpact, Impact, ImpactTangent, Law, Outcome, Partner, TracePoint,
    HERTZ_TIME_FACTOR,
};
