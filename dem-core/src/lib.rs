//! dem-core: a 2D bonded-particle DEM solver (discs, parallel bonds, rigid clumps, walls) and
//! the virtual lab tests built on it. See `docs/dem-core-design.md` for how the parts fit.
//!
//! One step of [`World::step`]:
//!
//! ```text
//! neighbours   neighbors::Neighbors   rebuild when a disc/wall moved > skin/2 (reorder, new dt)
//! contacts     contact::disc_disc     per-pair laws (linear | Hertz–Mindlin, rolling), history
//! walls        contact::disc_segment  disc–segment contacts, wall reactions and work
//! bonds        bond::Bonds            (only when the scene has bonds)
//! clumps       clump::step_clumps     gather, integrate, place members (only with clumps)
//! integrate    integrate              central difference, local/viscous damping, gravity
//! energy       energy                 kinetic, strain, dissipation, boundary work, balance
//! ```
//! The automatic time step is [`timestep`]; the blow-up guard [`World::check`].

pub mod bench;
pub mod bond;
pub mod bonded_clump;
pub mod checkpoint;
pub mod clump;
pub mod contact;
pub mod counters;
pub mod energy;
pub mod guard;
pub mod integrate;
pub mod lab;
pub mod neighbors;
pub mod output;
pub mod params;
pub mod pipeline;
pub mod scene;
pub mod specimen;
pub mod state;
pub mod team;
pub mod timestep;
pub mod validate;

pub use contact::{ContactLaws, ContactModel, ContactView, HertzMindlin, LinearSpringDashpot};
pub use energy::EnergyReport;
pub use guard::GuardError;
pub use params::Params;
pub use pipeline::{ExternalLoad, World, WorldError};
pub use state::{Clumps, Discs, Periodic, State, Wall, FREE};
