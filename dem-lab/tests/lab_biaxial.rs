//! Biaxial (confined) compression (Potyondy & Cundall 2004 §3; PFC2D's biaxial test) on the
//! small coarse specimen of the UCS tests: the side walls' servo holds σ3, the strength rises
//! with it faster than σ3 itself (a positive friction angle), σ3 = 0 gives the UCS test's
//! strength back, and bad parameters name their field.

mod lab_common;

use dem_lab::analysis::mohr_coulomb;
use dem_lab::tests::biaxial::{BiaxialReport, BiaxialTest};
use dem_lab::tests::ucs::UcsTest;
use dem_lab::LabError;
use lab_common::{dir, model, specimen};

fn test(confining: f64, name: &str) -> BiaxialTest {
    BiaxialTest {
        name: name.into(),
        width: 2e-3,
        height: 4e-3,
        confining,
        ..BiaxialTest::default()
    }
}

fn run(d: &std::path::Path, t: &BiaxialTest) -> BiaxialReport {
    let s = specimen(t.shape(), "ucs-specimen", d);
    let o = dem_lab::tests::run(t, &model(), &s, &mut |_, _| {})
        .unwrap_or_else(|e| panic!("{}: {e}", t.name));
    let r = o.result;
    eprintln!(
        "{}: σ3 {:.1} MPa (asked {:.1}, off ≤ {:.2} %), σ1 {:.1} MPa, E {:.1} GPa, ν {:.3}, {} steps, {:.2} s",
        t.name,
        r.sigma3 * 1e-6,
        r.confining * 1e-6,
        100.0 * r.confining_error,
        r.sigma1 * 1e-6,
        r.young * 1e-9,
        r.poisson,
        o.run.steps,
        o.run.wall_time_s
    );
    assert_eq!(o.run.status, "failure");
    assert!(d.join(format!("{}.result.json", t.name)).exists());
    r
}

#[test]
fn confinement_is_held_and_raises_the_strength() {
    let d = dir("biaxial");
    let free = run(&d, &test(0.0, "biaxial-0"));
    // Unconfined: the UCS test's strength and modulus (the side walls only follow the
    // specimen at zero stress).
    let ut = UcsTest {
        width: 2e-3,
        height: 4e-3,
        ..UcsTest::default()
    };
    let s = specimen(ut.shape(), "ucs-specimen", &d);
    let u = dem_lab::tests::run(&ut, &model(), &s, &mut |_, _| {})
        .unwrap()
        .result;
    eprintln!("ucs: {:.1} MPa, E {:.1} GPa", u.ucs * 1e-6, u.young * 1e-9);
    assert!(
        (free.sigma1 / u.ucs - 1.0).abs() < 0.1,
        "σ3 = 0: σ1 {} against UCS {}",
        free.sigma1,
        u.ucs
    );
    assert!((free.young / u.young - 1.0).abs() < 0.05);

    let s3 = 0.1 * u.ucs;
    let conf = run(&d, &test(s3, "biaxial-1"));
    assert!(conf.confining_error <= 0.1, "{conf:?}");
    assert!((conf.sigma3 / s3 - 1.0).abs() <= 0.1, "{conf:?}");
    // Mohr–Coulomb: σ1 rises by q σ3 with q = (1 + sin φ)/(1 − sin φ) > 1.
    let mc = mohr_coulomb(&[(free.sigma3, free.sigma1), (conf.sigma3, conf.sigma1)])
        .unwrap_or_else(|| panic!("no envelope: σ1 {} → {}", free.sigma1, conf.sigma1));
    eprintln!(
        "φ = {:.1}°, c = {:.1} MPa",
        mc.friction_angle_deg,
        mc.cohesion * 1e-6
    );
    assert!(
        mc.friction_angle_deg > 5.0 && mc.friction_angle_deg < 70.0,
        "{mc:?}"
    );
}

#[test]
fn bad_parameters_name_their_field() {
    let field = |t: BiaxialTest| match t.validate() {
        Err(LabError::Param { field, .. }) => field,
        r => panic!("{r:?}"),
    };
    assert_eq!(field(test(-1.0, "b")), "biaxial.confining");
    assert_eq!(field(test(f64::NAN, "b")), "biaxial.confining");
    let mut t = test(1e6, "b");
    t.servo_alpha = 0.0;
    assert_eq!(field(t), "biaxial.servo_alpha");
    let mut t = test(1e6, "b");
    t.width = 0.0;
    assert_eq!(field(t), "biaxial.width");
    let mut t = test(1e6, "b");
    t.side_overhang = -0.1;
    assert_eq!(field(t), "biaxial.side_overhang");
}
