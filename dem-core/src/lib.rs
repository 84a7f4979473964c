//! dem-core: a 2D bonded-particle DEM solver (discs, parallel bonds, rigid clumps, walls) and
//! its scene files and outputs. Specimens and the virtual lab tests built on it are the
//! `dem-lab` crate. See `docs/dem-core-design.md` for how the parts fit.
//!
//! One step of [`World::step`]:
//!
//! ```text
//! neighbours   neighbors::Neighbors   rebuild when a disc/wall moved > skin/2 (reorder, new dt)
//! contacts     contact::disc_disc     per-pair laws (linear | Hertz–Mindlin, rolling), history
//! walls        contact::disc_segment  disc–segment contacts, wall reactions and work
//! bonds        bond::Bonds            (only when the scene has bonds)
//! clumps       clump::step_clumps     gather, integrate, place members (only with clumps)
//! damping      damping                local damping in the fragment frame (only when chosen)
//! integrate    integrate              central difference, local/viscous damping, gravity
//! energy       energy                 kinetic, strain, dissipation, boundary work, balance
//! ```
//! The automatic time step is [`timestep`]; the blow-up guard [`World::check`].
//!
//! A scene (`dem.scene/1`, docs/scene-schema.md) loaded and run, as `dem run` does: two glass
//! discs collide head-on, and a linear spring-dashpot with restitution e = 0.7 leaves them
//! e² = 49 % of their kinetic energy.
//!
//! ```
//! use dem_core::{RunOptions, Simulation};
//!
//! let dir = std::env::temp_dir().join(format!("dem-doc-{}", std::process::id()));
//! let scene = r#"{
//!   "schema": "dem.scene/1", "name": "collide", "units": "mm",
//!   "materials": [{"name": "glass", "density": 2500, "kn": 1e5, "ks": 5e4,
//!                  "friction": 0.3, "restitution": 0.7}],
//!   "bodies": {"discs": [
//!     {"material": "glass", "velocity": [500, 0], "discs": [[-2, 0, 1]]},
//!     {"material": "glass", "velocity": [-500, 0], "discs": [[2, 0, 1]]}]},
//!   "run": {"steps": 400},
//!   "outputs": {"history_every": 0, "summary": false, "checkpoints": false}
//! }"#;
//! let scene = dem_core::scene::parse(scene, &dir.join("collide.json"))?;
//! let mut sim = Simulation::new(scene, &RunOptions::default())?;
//! let before = sim.world.energy().kinetic();
//! let (summary, _ending) = sim.run(&mut |_done, _total| {})?;
//! assert_eq!(summary.final_step, 400);
//! let ratio = sim.world.energy().kinetic() / before;
//! assert!((ratio - 0.49).abs() < 0.01, "{ratio}");
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// The solver's public modules: the state, the laws, the step and its files.
pub mod bond;
pub mod bonded_clump;
pub mod checkpoint;
pub mod clump;
pub mod contact;
pub mod damping;
pub mod energy;
pub mod fragments;
pub mod mass_scaling;
pub mod neighbors;
pub mod output;
pub mod params;
pub mod pipeline;
pub mod scene;
pub mod state;
pub mod timestep;
pub mod wall_servo;

// The step's machinery, private: the hot path's lanes (AVX2 check, block sizes, packed
// records), the workers of the parallel stages, the integrator, input checks, blow-up guard
// and stage counters are reached through `World`. (So are the contact pass's kernels and the
// cell grid: `contact` and `neighbors` keep them crate-private.)
mod counters;
mod guard;
mod integrate;
mod lanes;
mod team;
mod validate;

// In-memory benchmark scenes (`dem bench`) and the lattice fixtures the tests share; built
// only for tests and with the `bench` feature, which `dem` turns on.
#[cfg(any(test, feature = "bench"))]
pub mod bench;

// What most users need, at the root: scene files in, the driver, its outputs and errors,
// the world and its state, the laws and bonds. (Everything else stays at its module path.)
pub use bond::{BondGroup, BondModel, Bonds, Criterion};
pub use contact::{ContactLaws, ContactModel, ContactView, HertzMindlin, LinearSpringDashpot};
pub use damping::DampingFrame;
/// The contact-law catalogue the solver's laws come from (written once for discs and spheres).
pub use dem_laws as laws;
pub use energy::EnergyReport;
pub use guard::GuardError;
pub use output::driver::{Ending, HookError, RunError, RunOptions, Simulation, StepHook};
pub use params::Params;
pub use pipeline::{ExternalLoad, World, WorldError};
pub use scene::schema::{SceneFile, SpecimenFile};
pub use scene::{Scene, SceneError};
pub use state::{Clumps, Discs, Periodic, State, Wall, FREE};
