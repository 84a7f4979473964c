//! Single-edge-notched beam (ASTM E399 SE(B) form) of the coarse traditional lab material
//! (lab_common: radii 0.10–0.16 mm, σ̄_c = c̄ = 800 MPa): the notch lowers the peak load
//! below the plain beam's on the same span, K_IC follows the bond strength, the crack mouth
//! opens, and bad parameters name their field.

mod lab_common;

use dem_lab::tests::bending::BendingTest;
use dem_lab::tests::senb::{SenbOutcome, SenbTest};
use dem_lab::{LabError, LabModel};
use lab_common::{dir, model, specimen};

/// W = 2.8 mm (a ligament of 5.4 mean diameters at a/W = 0.5), S = 11.2 mm, ℓ = 12 mm.
fn test() -> SenbTest {
    SenbTest {
        length: 12e-3,
        height: 2.8e-3,
        notch_width: 0.26e-3,
        ..SenbTest::default()
    }
}

fn run(name: &str, m: &LabModel) -> SenbOutcome {
    let t = test();
    let d = dir(name);
    let s = specimen(t.shape(), "senb-specimen", &d);
    let o =
        dem_lab::tests::run(&t, m, &s, &mut |_, _| {}).unwrap_or_else(|e| panic!("{name}: {e}"));
    let r = &o.result;
    eprintln!(
        "{name}: K_IC {:.3} MPa·m^½ (β {:.3} of σ̄c√(πR̄) = {:.3}), P {:.4e} N, a/W {:.3}, \
         f {:.3}, ligament {:.1} d, CMOD {:.3e} m, {} discs, {} steps, {:.2} s, time to peak \
         {:.1} periods",
        r.fracture_toughness * 1e-6,
        r.beta,
        r.bond_estimate * 1e-6,
        r.peak_load,
        r.notch_ratio,
        r.geometry_factor,
        r.ligament_diameters,
        r.cmod_at_peak,
        o.run.discs,
        o.run.steps,
        o.run.wall_time_s,
        r.quasi_static_ratio
    );
    assert_eq!(o.run.status, "failure");
    assert!(o.run.bonds_broken > 0, "the load fell by fracture");
    o
}

#[test]
fn notch_lowers_the_peak_and_toughness_follows_bond_strength() {
    let m = model();
    let base = run("senb-base", &m);
    let r = &base.result;
    assert!(r.fracture_toughness.is_finite() && r.fracture_toughness > 0.0);
    assert!(
        r.cmod_at_peak > 0.0,
        "the crack mouth opens: {}",
        r.cmod_at_peak
    );
    assert!((r.span - 4.0 * r.height).abs() < 1e-12);
    // The same beam without its notch, same span: a notch to half depth leaves a quarter of
    // the section modulus, so the notched peak must lie well below the plain one.
    let t = test();
    let plain = BendingTest {
        name: "plain".into(),
        length: t.length,
        height: t.height,
        span: r.span,
        ..BendingTest::default()
    };
    let d = dir("senb-plain");
    let ps = specimen(plain.shape(), "senb-plain-specimen", &d);
    let p = dem_lab::tests::run(&plain, &m, &ps, &mut |_, _| {})
        .unwrap()
        .result;
    eprintln!(
        "plain beam: peak {:.4e} N; notched/plain {:.3}",
        p.peak_load,
        r.peak_load / p.peak_load
    );
    assert!(r.peak_load < 0.5 * p.peak_load);

    // σ̄_c and c̄ doubled: K_IC doubles within 8 % (β unchanged).
    let mut strong = m.clone();
    strong.micro.boundary_tensile *= 2.0;
    strong.micro.boundary_cohesion *= 2.0;
    let s2 = run("senb-double", &strong).result;
    let ratio = s2.fracture_toughness / r.fracture_toughness;
    assert!((ratio - 2.0).abs() < 0.16, "K_IC ratio {ratio}");
    assert!((s2.beta / r.beta - 1.0).abs() < 0.08);
}

#[test]
fn bad_parameters_name_the_field() {
    let field = |t: SenbTest| match t.validate() {
        Err(LabError::Param { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    let bad = |f: &dyn Fn(&mut SenbTest)| {
        let mut t = test();
        f(&mut t);
        field(t)
    };
    assert_eq!(bad(&|t| t.length = 10e-3), "senb.length"); // below S = 11.2 mm
    assert_eq!(bad(&|t| t.notch_ratio = 0.9), "senb.notch_ratio");
    assert_eq!(bad(&|t| t.notch_width = 3e-3), "senb.notch_width");
    assert_eq!(bad(&|t| t.notch_width = -1.0), "senb.notch_width");
    // A ligament of 3.2 mean diameters (a/W = 0.7) is below the resolution floor.
    let deep = SenbTest {
        notch_ratio: 0.7,
        ..test()
    };
    match deep.check_geometry(0.13e-3) {
        Err(LabError::Param { field, .. }) => assert_eq!(field, "senb.notch_ratio"),
        other => panic!("{other:?}"),
    }
    assert!(test().check_geometry(0.13e-3).is_ok());
}
