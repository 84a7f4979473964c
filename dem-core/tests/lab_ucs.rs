//! Uniaxial compression on a small coarse traditional specimen (~200 discs).

use dem_core::lab::specimens::{self, TestSpecimen};
use dem_core::lab::ucs::{self, UcsTest};
use dem_core::lab::LabModel;
use dem_core::specimen::{Method, SpecimenParams};
use std::path::PathBuf;
use std::sync::Mutex;

static LOCK: Mutex<()> = Mutex::new(());

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-lab-ucs-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn params() -> SpecimenParams {
    SpecimenParams::new(
        Method::Traditional,
        2e-3,
        4e-3,
        0.1e-3,
        0.16e-3,
        3200.0,
        310e9,
        800e6,
        1,
    )
}

fn test() -> UcsTest {
    UcsTest {
        width: 2e-3,
        height: 4e-3,
        ..UcsTest::default()
    }
}

fn specimen(name: &str) -> TestSpecimen {
    let _g = LOCK.lock().unwrap();
    let t = test();
    let p = params();
    let d = std::env::temp_dir().join("dem-lab-ucs-specimens");
    let t0 = std::time::Instant::now();
    let s = specimens::prepare(&p, t.shape(), &d.join("ucs.specimen.json"), &mut |_| {}).unwrap();
    eprintln!(
        "specimen {} discs {:.1} s reused {}",
        s.discs,
        t0.elapsed().as_secs_f64(),
        s.reused
    );
    // Each test runs beside its own copy.
    let dd = dir(name);
    let f = dd.join("ucs.specimen.json");
    std::fs::copy(&s.file, &f).unwrap();
    TestSpecimen { file: f, ..s }
}

#[test]
fn explore() {
    let s = specimen("explore");
    let m = LabModel::from_params(&params());
    let t0 = std::time::Instant::now();
    let o = ucs::run(&test(), &m, &s, &mut |_, _| {}).unwrap();
    eprintln!(
        "{:.1} s {:#?} {:#?}",
        t0.elapsed().as_secs_f64(),
        o.result,
        o.run
    );
}
