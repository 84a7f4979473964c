//! Shared by the lab tests: small coarse traditional Si3N4-like specimens (E = 310 GPa,
//! σ̄_c = c̄ = 800 MPa, ρ = 3200 kg/m³, radii 0.10–0.16 mm, seed 1), generated once into a
//! cache folder (reused across test binaries and runs through the key file) and copied beside
//! each test's scene.

#![allow(dead_code)]

use dem_core::lab::specimens::{self, Shape, TestSpecimen};
use dem_core::lab::LabModel;
use dem_core::specimen::{Method, SpecimenParams};
use std::path::PathBuf;
use std::sync::Mutex;

static LOCK: Mutex<()> = Mutex::new(());

/// The specimen parameters (the test's shape replaces width and height).
pub fn params() -> SpecimenParams {
    SpecimenParams::new(
        Method::Traditional,
        2e-3,
        4e-3,
        0.10e-3,
        0.16e-3,
        3200.0,
        310e9,
        800e6,
        1,
    )
}

pub fn model() -> LabModel {
    LabModel::from_params(&params())
}

/// A fresh folder for one test.
pub fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-lab-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The specimen of `shape` (generated once, cached), copied into `dir`.
pub fn specimen(shape: Shape, stem: &str, dir: &std::path::Path) -> TestSpecimen {
    let cached = {
        let _g = LOCK.lock().unwrap_or_else(|e| e.into_inner());
        let cache = std::env::temp_dir().join("dem-lab-test-specimens");
        specimens::prepare(
            &params(),
            shape,
            &cache.join(format!("{stem}.json")),
            &mut |_| {},
        )
        .unwrap_or_else(|e| panic!("{e}"))
    };
    let file = dir.join(format!("{stem}.json"));
    std::fs::copy(&cached.file, &file).unwrap();
    TestSpecimen { file, ..cached }
}
