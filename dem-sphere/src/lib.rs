//! A 3D sphere DEM solver on the contact-law catalogue of `dem-laws` (issue 51, first part).
//!
//! One step ([`World::step`], velocity Verlet in its kick–drift–kick form, Swope et al. 1982,
//! J. Chem. Phys. 76:637; the scheme of LAMMPS `fix nve/sphere`):
//!
//! ```text
//! v += ½Δt (F/m + g),  ω += ½Δt T/I          half kick with the forces at x(t)
//! x += Δt v                                   drift (walls translate at their velocity)
//! broad phase  (grid.rs)    Verlet list rebuilt when a sphere has moved skin/2:
//!                           single uniform grid or Ogarko & Luding's multi-level grid;
//!                           histories carried over by their (i, j) key
//! narrow phase (contact.rs) sphere–sphere: n, δ = r_i + r_j − d, arms r − δ/2, v_rel;
//!                           sphere–plane (walls.rs): δ = r − (x − p)·n, R* = r, m* = m
//! laws         (dem-laws)   h.rotate_into(n); GranularLaw::force_pair, roll, twist
//! reduction                 contacts in parallel → per sphere, its contacts in list
//!                           order then its walls: the same bits for any thread count
//! v += ½Δt (F/m + g),  ω += ½Δt T/I          half kick with the forces at x(t + Δt)
//! ```
//!
//! Velocity-dependent forces see the half-step velocities (as LAMMPS). Periodic axes
//! ([`Periodic`], `Config::periodic`): positions stay unwrapped, pair vectors take the minimum
//! image and the grids wrap their cells. State ([`Spheres`]:
//! x, v, ω, r, m, I, species) is kept apart from the step's scratch (forces, torques,
//! dashpot parts). Time step: [`World::critical_dt`], a fraction of √(m*/k) from the laws'
//! stiffness (Cundall & Strack 1979, Géotechnique 29:47). Energy balance: [`energy`].
//! Packing scenes: [`pack`] (random sequential insertion, gravity pour, settling, packing
//! fraction in an interior window, coordination number).
//!
//! ```
//! use dem_sphere::{box_walls, Config, Laws, World};
//! use dem_laws::GranularLaw;
//! use nalgebra::Vector3;
//! let law = GranularLaw::from_json(
//!     r#"{"normal": {"model": "hooke", "kn": 1000},
//!         "damping": {"model": "coeff_restitution", "e": 0.5},
//!         "tangential": {"model": "linear_history", "kt": 800, "mu": 0.5}}"#, None)?;
//! let mut w = World::new(Config::default(), Laws::single(law, law))?;
//! for p in box_walls(Vector3::zeros(), Vector3::repeat(0.01))? { w.add_wall(p)?; }
//! w.add_sphere(Vector3::new(0.005, 0.005, 0.005), Vector3::zeros(), 1e-3, 2500.0, 0)?;
//! w.config.dt = w.critical_dt(0.1, 0.01);
//! w.run(100);
//! assert!(w.spheres.v[0].z < 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod contact;
pub mod energy;
mod error;
pub mod grid;
pub mod pack;
/// The insertion's random numbers: clumpgen's SplitMix64 (Steele, Lea & Flood 2014).
pub mod rng {
    pub use clumpgen::synth::SplitMix64;
}
mod state;
mod walls;
mod world;

pub use contact::contact_time_scale;
pub use energy::EnergyReport;
pub use error::SphereError;
pub use grid::{find_pairs, find_pairs_brute, GridKind, GridStats, Periodic};
pub use state::Spheres;
pub use walls::{box_walls, Plane};
pub use world::{Config, Counters, Laws, World};
