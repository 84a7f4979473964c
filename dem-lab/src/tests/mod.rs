//! The quasi-static virtual lab tests on a bonded specimen (`dem test ucs|biaxial|brazilian|
//! bending|senb`, docs/lab-tests.md). Each file keeps only what is its own: the test's
//! parameters, its geometry (scene) and its analysis formula with the citation; the
//! [`harness`] does the rest, the same for all:
//!
//! ```text
//! harness    loading rule (quasi-static speed, damping, dt factor, stop after the peak),
//!            platens/walls/gauges, parameter checks, the run (scene written beside the
//!            specimen, run, history read back as numbers), the result file
//! ucs        uniaxial compression: E, ν (10–50 % pre-peak band), UCS
//! biaxial    confined compression (servo side walls): σ1 at σ3, Mohr–Coulomb φ and c
//! brazilian  Brazilian disc: σ_t = 2F/(πDt)
//! bending    three-point bending: σ_f = 3FL/(2bh²), elastic stiffness (vs Timoshenko)
//! senb       single-edge-notched beam (ASTM E399 SE(B)): K_IC, measured β of β σ̄_c √(πR̄)
//! ```
//!
//! Every test runs the same way, [`run`]: its scene written as `<name>.json` beside the
//! specimen file, run (outputs `<name>.out/`), analysed, `<name>.result.json` written.

pub mod bending;
pub mod biaxial;
pub mod brazilian;
pub mod harness;
pub mod senb;
pub mod ucs;

pub use harness::{run, Loading, Outcome, QuasiStatic, RunFacts};
