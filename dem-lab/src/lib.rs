//! dem-lab: bonded-particle specimens and the virtual lab tests (uniaxial compression,
//! Brazilian, three-point bending, SE(B) fracture, biaxial, cutting, grain crushing) run on the
//! dem-core solver, with the analyses that turn their histories into material properties.
//! dem-core knows nothing of this crate; dem-cli (`dem specimen`, `dem test`, `dem calibrate`)
//! and validation use it.
//!
//! ```text
//! specimen/       the specimens (traditional, ORC, improved ORC), the dem.specimen/1 file;
//!   cache         a test's specimen (the user's parameters, the test's shape; the Brazilian
//!                 disc carved, the SENB notch cut), saved beside the scene, reused by key
//! model           LabModel: density, thickness, micro-parameters → materials, bond groups
//! run, history    the scene written as a plain file (`dem run` runs it again) and run as the
//!                 same value in memory; the history read as numbers (history.csv of old runs)
//! tests/          the quasi-static tests on a specimen, one shared harness (loading rule,
//!                 platens, run, result file): ucs (E, ν, UCS), biaxial (σ1 at σ3, φ, c),
//!                 brazilian (σ_t = 2F/(πDt)), bending (σ_f = 3FL/(2bh²)), senb (K_IC, E399)
//! cutting/        the cutting test and its parts: tool, chips, debris, surface, removal mode
//! crushing/       lattice grains that break: grain (one between platens), column (many in a
//!                 box), lattice (what they share), weibull (strength statistics)
//! analysis/       the standard formulas (E, ν, UCS, σ_t, σ_f, K_IC, Mohr–Coulomb), force
//!                 stats of cutting histories (force_stats: seed-averaged moving-mean peak)
//! wheel/          the grinding wheel of S1: grooved hub and outer circle as walls, annulus
//!                 packing to a porosity, contact bonds, grits bonded by parallel bonds
//! calibrate/      micro-parameters from target properties (Potyondy & Cundall 2004), on the
//!                 virtual_lab of UCS, bending and Brazilian tests
//!
//! pipeline: SpecimenParams ─specimen::cache::prepare→ TestSpecimen ─┐
//!           LabModel ─────────────────────────────────────────────┴─ tests::run(&UcsTest…)
//!           → scene <name>.json → run → Record → analyze → <name>.result.json (Outcome)
//! ```
//!
//! Docs: `docs/lab-tests.md`. A UCS test, as `dem test ucs` runs it: a small bonded specimen
//! (about 200 discs) generated, written and reused from a folder, compressed between two
//! platens until it fails (a fraction of a second):
//!
//! ```
//! use dem_lab::{specimen::cache, tests, LabModel, Method, SpecimenParams, UcsTest};
//!
//! let dir = std::env::temp_dir().join(format!("dem-doc-ucs-{}", std::process::id()));
//! // 2.5 x 5 mm, radii 0.10-0.15 mm, Si3N4-like: 3200 kg/m³, E = 300 GPa, σ_t = 500 MPa, seed 1.
//! let p = SpecimenParams::new(Method::Traditional, 2.5e-3, 5e-3, 0.1e-3, 0.15e-3,
//!                             3200.0, 300e9, 500e6, 1);
//! let test = UcsTest { width: 2.5e-3, height: 5e-3, ..UcsTest::default() };
//! let spec = cache::prepare(&p, test.shape(), &dir.join("ucs.specimen.json"), &mut |_| {})?;
//! let model = LabModel::from_params(&p);
//! let o = tests::run(&test, &model, &spec, &mut |_done, _total| {})?;
//! let r = &o.result;
//! assert!(r.young > 0.0 && r.ucs > 0.0 && r.poisson.is_finite());
//! assert!(dir.join("ucs.json").is_file()); // the scene, which `dem run` runs again
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod analysis;
pub mod calibrate;
pub mod crushing;
pub mod cutting;
pub mod history;
pub mod model;
pub mod run;
pub mod specimen;
pub mod tests;
pub mod wheel;

pub use calibrate::{calibrate, Calibration, MaterialFile, Targets};
pub use crushing::column::ColumnTest;
pub use crushing::grain::{CrushTest, LinkCriterion};
pub use cutting::CuttingTest;
pub use model::LabModel;
pub use specimen::cache::{Shape, TestSpecimen};
pub use specimen::{Method, SpecimenParams};
pub use tests::bending::BendingTest;
pub use tests::biaxial::BiaxialTest;
pub use tests::brazilian::BrazilianTest;
pub use tests::senb::SenbTest;
pub use tests::ucs::UcsTest;
pub use tests::{Loading, Outcome, RunFacts};

/// A JSON file of the lab's (a material, a specimen's summary or scene) read as `T` through the
/// bounded reader; an error names the file and the JSON path of the offending field.
pub(crate) fn read_json<T: serde::de::DeserializeOwned>(
    path: &std::path::Path,
) -> Result<T, LabError> {
    let file = path.display().to_string();
    let text = clumpgen::io::read_input_string(path).map_err(|source| LabError::Io {
        file: file.clone(),
        source,
    })?;
    let de = &mut serde_json::Deserializer::from_str(&text);
    serde_path_to_error::deserialize(de).map_err(|e| LabError::Param {
        field: format!("{file}: {}", e.path()),
        reason: e.inner().to_string(),
    })
}

/// Errors of the lab tests; each names the file or field at fault.
#[derive(Debug, thiserror::Error)]
pub enum LabError {
    #[error("{file}: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error(transparent)]
    Scene(#[from] dem_core::scene::SceneError),
    #[error(transparent)]
    Run(#[from] dem_core::output::driver::RunError),
    #[error(transparent)]
    Output(#[from] dem_core::output::OutputError),
    #[error(transparent)]
    History(#[from] history::HistoryError),
    #[error(transparent)]
    Specimen(#[from] crate::specimen::SpecimenError),
    #[error("{test}: {reason}")]
    Analysis { test: String, reason: String },
    #[error("{field}: {reason}")]
    Param { field: String, reason: String },
    #[error("{dir}: stopped at step {step} before the end (max_steps); run it again to continue from its last checkpoint")]
    Stopped { dir: String, step: u64 },
    #[error("{scene}: the test needs {steps} steps of dt = {dt:.3e} s, more than the {limit} a lab test runs; check the stiffness and density (dt scales with sqrt(mass/stiffness)), the loading speed and the specimen size, or run the written scene with `dem run --yes`")]
    TooManySteps {
        scene: String,
        steps: u64,
        dt: f64,
        limit: u64,
    },
    #[error("{scene}: the test's snapshots and checkpoints would take about {gb:.1} GB ({steps} steps, {discs} discs, {snapshots}), more than the {limit_gb:.0} GB a lab test writes; ask for fewer snapshots (--snapshots), or run the written scene with `dem run --yes`")]
    TooMuchOutput {
        scene: String,
        gb: f64,
        steps: u64,
        discs: usize,
        /// [`dem_core::scene::model::Outputs::snapshot_plan`].
        snapshots: String,
        limit_gb: f64,
    },
}
