//! Shared by the lab tests: small coarse traditional Si3N4-like specimens (E = 310 GPa,
//! σ̄_c = c̄ = 800 MPa, ρ = 3200 kg/m³, radii 0.10–0.16 mm, seed 1), generated once into a
//! cache folder (reused across test binaries and runs through the key file) and copied beside
//! each test's scene.

#![allow(dead_code)]

use dem_lab::specimen::cache::{self, Shape, TestSpecimen};
use dem_lab::specimen::{Method, SpecimenParams};
use dem_lab::LabModel;
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
        cache::prepare(
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

/// The cutting tests' specimen, written to `dir/small.json` (not cached): traditional, 5 × 2.5 mm, radii 0.10-0.16 mm (about 200 discs), Si3N4's density
/// and E but bonds of 3 GPa: a short test must cut fast (10 m/s), and the regime of a cut is set
/// by the impact strain v/c (c = √(E/ρ) ≈ 9.8 km/s) against the failure strain σ_t/E: with
/// 800 MPa bonds 10 m/s shatters a specimen this small (v/c ≈ 0.4 σ_t/E: 160 of 346 bonds
/// broke, the largest piece kept 60 of 198 discs), with 3 GPa it cuts (v/c ≈ 0.1 σ_t/E; the
/// full-size runs at 1 m/s and 800 MPa have 0.04).
pub fn cut_specimen(dir: &std::path::Path) -> (PathBuf, LabModel) {
    let p = SpecimenParams::new(
        Method::Traditional,
        5e-3,
        2.5e-3,
        0.10e-3,
        0.16e-3,
        3200.0,
        310e9,
        3e9,
        3,
    );
    let s = dem_lab::specimen::generate(&p, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    let path = dir.join("small.json");
    dem_lab::specimen::io::save(&s, "Si3N4", &path).unwrap();
    (path, LabModel::from_params(&p))
}
