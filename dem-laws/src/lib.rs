//! Contact laws written once for 2D discs and 3D spheres.
//!
//! A law maps the kinematics of one touching pair ([`Kin`]: overlap δ, normal and tangential
//! relative velocity, effective mass and radius, Δt) and its per-contact history
//! ([`ContactLaw::History`]) to the pair's force ([`Out`]). Each law is a type implementing [`ContactLaw`] over a
//! [`Tangent`]: `f64` for discs (the tangent plane is a line) and `nalgebra::Vector3<f64>`
//! for spheres, so the same code serves the 2D solver (`dem-core`) and the 3D one.
//!
//! The pipeline of a contact, as a solver drives it:
//!
//! 1. geometry (the solver): normal n, overlap δ, contact arms, relative velocity → [`Kin`];
//!    in 3D the history is first brought into the new tangent plane ([`rotate_history`]);
//! 2. law: [`ContactLaw::force`] → F_n, F_t and, with `E = true`, the energy terms; a pair
//!    stays in the contact list while δ > −[`ContactLaw::reach`] (JKR neck, van der Waals);
//! 3. rolling resistance on the relative rotation ([`RollingResistance`], or
//!    [`GranularLaw::roll`]) and, in 3D, twisting ([`GranularLaw::twist`]);
//! 4. the solver applies ±F at the contact point and the torques.
//!
//! Laws: [`LinearSpringDashpot`] (Cundall & Strack 1979) and [`HertzMindlin`] (Hertz 1882,
//! Mindlin 1949, Tsuji et al. 1992 damping calibrated for an exact restitution), the two the
//! 2D solver runs; and the catalogue [`GranularLaw`], composed like LAMMPS
//! `pair_style granular` of a [`Normal`] (hooke, hertz, hertz/material, dmt, jkr,
//! walton_braun), a [`Damping`] (none, velocity, mass_velocity, viscoelastic, tsuji,
//! coeff_restitution), a [`Tangential`] (linear_nohistory, linear_history, mindlin,
//! mindlin_rescale, mindlin/force, mindlin_rescale/force, mindlin/deresiewicz), an optional
//! [`Rolling`] (constant_torque, elastic_plastic), an optional [`Twisting`] (marshall, sds)
//! and an optional [`VanDerWaals`] attraction, read by name from JSON ([`GranularSpec`],
//! [`GranularLaw::from_json`]). Each module gives its formulas and sources;
//! `docs/laws.md` tabulates them.

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

// The contact-law catalogue (LAMMPS `pair_style granular` sub-models).
mod damping;
mod error;
mod granular;
mod normal;
mod spec;
mod tangential;
mod twisting;
mod vdw;

pub use damping::{beta_of_restitution, eta_clipped_for_restitution, restitution_clipped, Damping};
pub use error::LawError;
pub use granular::{GranularHistory, GranularLaw};
pub use normal::{
    dmt_pulloff, hertz_force, jkr_contact_radius, jkr_critical_overlap, jkr_force_of_radius,
    jkr_overlap, jkr_pulloff, Material, Normal, NormalForce, NormalHistory,
};
pub use rolling::Rolling;
pub use spec::{
    DampingSpec, GranularSpec, NormalSpec, RollingSpec, TangentialSpec, TwistingSpec, VdwSpec,
};
pub use tangential::{md_theta, MdMode, Tangential, TangentialForce, TangentialHistory};
pub use twisting::Twisting;
pub use vdw::{
    cylinders_force_per_length, cylinders_potential_per_length, sphere_sphere_force,
    sphere_sphere_force_near, sphere_sphere_potential, sphere_wall_force, sphere_wall_potential,
    VanDerWaals, H_MIN_DEFAULT,
};

// The two-body impact integrator (issue 50 item 4).
pub use impact::{
    run as run_impact, Body, HertzImpact, Impact, ImpactTangent, Law, Outcome, Partner, TracePoint,
    HERTZ_TIME_FACTOR,
};
