//! dem-core: a 2D bonded-particle DEM solver (discs, parallel bonds, rigid clumps, walls) and
//! the virtual lab tests built on it. See `docs/dem-core-design.md` for how the parts fit.

pub mod bond;
pub mod bonded_clump;
pub mod lab;
pub mod output;
pub mod scene;
pub mod state;

pub use state::{Clumps, Discs, Periodic, State, Wall, FREE};
