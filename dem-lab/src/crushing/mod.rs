//! Crushable grains (`dem test crush`, `dem test column`; docs/lattice.md): lattice grains
//! (a clumpgen lattice template inside each outline, its links contact bonds that break) loaded
//! between platens, and the statistics of their strengths.
//!
//! ```text
//! grain    one grain between two platens: crushing strength σ = F/(d t), fragments after the
//!          first major breakage and after a second loading stage
//! column   many grains in a box under one-dimensional compression: stress–strain, gradings
//!          at stress levels, Hardin's relative breakage
//! lattice  what the two share: the lattice scene (materials, link bond group, damping, run),
//!          the history's energies and break counts, the energy at the end, the break log,
//!          the written files
//! weibull  Weibull modulus and characteristic strength of grain strengths, the size effect
//! ```

pub mod column;
pub mod grain;
pub mod lattice;
pub mod weibull;
