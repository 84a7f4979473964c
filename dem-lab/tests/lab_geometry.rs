//! Issue 20, bounded work: the lab tests and the specimen refuse geometry that the particle
//! size makes meaningless (fewer than `MIN_DIAMETERS_ACROSS` mean disc diameters across, gauges
//! narrower than a disc or overlapping, a span that leaves no room for the supports), with
//! errors naming the field, the value and the bound; valid defaults and the coarse regression
//! geometries still pass. Before, every case below was accepted.

use dem_lab::specimen::{Method, SpecimenError, SpecimenParams};
use dem_lab::tests::bending::BendingTest;
use dem_lab::tests::brazilian::BrazilianTest;
use dem_lab::tests::harness::MIN_DIAMETERS_ACROSS;
use dem_lab::tests::ucs::UcsTest;
use dem_lab::LabError;

/// Mean radius of the coarse regression specimens (0.10–0.16 mm).
const R: f64 = 0.13e-3;

fn field(r: Result<(), LabError>) -> (String, String) {
    match r {
        Err(LabError::Param { field, reason }) => (field, reason),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_bound_is_five_mean_disc_diameters() {
    assert_eq!(MIN_DIAMETERS_ACROSS, 5.0);
}

#[test]
fn valid_defaults_and_the_coarse_regression_geometries_pass() {
    // Defaults (10 × 20 mm, D 10 mm, 20 × 5 mm beam on 16 mm) with the test discs.
    UcsTest::default()
        .check_geometry([10e-3, 20e-3], R)
        .unwrap();
    BrazilianTest::default().check_geometry(10e-3, R).unwrap();
    BendingTest::default()
        .check_geometry([20e-3, 5e-3], R)
        .unwrap();
    // The small grid of the regression tests: UCS 2 × 4 mm, disc 3 mm, beam 6 × 1.5 mm on 5 mm.
    UcsTest::default().check_geometry([2e-3, 4e-3], R).unwrap();
    BrazilianTest::default().check_geometry(3e-3, R).unwrap();
    let beam = BendingTest {
        length: 6e-3,
        height: 1.5e-3,
        span: 5e-3,
        ..BendingTest::default()
    };
    beam.check_geometry([6e-3, 1.5e-3], R).unwrap();
}

#[test]
fn ucs_too_narrow_or_too_short_is_refused() {
    // 0.1 mm wide of 0.2 mm discs: 0.5 diameters.
    let (f, r) = field(UcsTest::default().check_geometry([0.1e-3, 20e-3], 0.1e-3));
    assert_eq!(f, "ucs.width");
    assert!(
        r.contains("0.1000 mm")
            && r.contains("0.5 mean disc diameters")
            && r.contains("at least 5"),
        "{r}"
    );
    // Just below the bound (4.9 diameters) is refused, at it passes.
    let d = 2.0 * R;
    assert_eq!(
        field(UcsTest::default().check_geometry([4.9 * d, 20e-3], R)).0,
        "ucs.width"
    );
    UcsTest::default()
        .check_geometry([5.01 * d, 20e-3], R)
        .unwrap();
    assert_eq!(
        field(UcsTest::default().check_geometry([10e-3, 4.0 * d], R)).0,
        "ucs.height"
    );
}

#[test]
fn ucs_gauge_narrower_than_a_disc_or_wider_than_the_specimen_is_refused() {
    let narrow = UcsTest {
        gauge_width: 0.5,
        ..UcsTest::default()
    };
    let (f, r) = field(narrow.check_geometry([10e-3, 20e-3], R));
    assert_eq!(f, "ucs.gauge_width");
    assert!(r.contains("narrower than a mean disc"), "{r}");
    // 2 mm wide, gauges reaching 30 r̄ = 3.9 mm into each side: they overlap.
    let wide = UcsTest {
        gauge_width: 30.0,
        ..UcsTest::default()
    };
    let (f, r) = field(wide.check_geometry([2e-3, 4e-3], R));
    assert_eq!(f, "ucs.gauge_width");
    assert!(r.contains("overlap"), "{r}");
    // The same gauges run through scene() too (validate alone accepts them).
    wide.validate().unwrap();
}

#[test]
fn brazilian_disc_of_a_few_particles_is_refused() {
    let (f, r) = field(BrazilianTest::default().check_geometry(1e-3, R));
    assert_eq!(f, "brazilian.diameter");
    assert!(r.contains("3.8 mean disc diameters"), "{r}");
}

#[test]
fn bending_beam_too_shallow_or_span_without_room_is_refused() {
    let t = |length: f64, height: f64, span: f64| BendingTest {
        length,
        height,
        span,
        ..BendingTest::default()
    };
    // 1 mm high beam of 0.26 mm discs: 3.8 diameters.
    let (f, r) = field(t(6e-3, 1e-3, 5e-3).check_geometry([6e-3, 1e-3], R));
    assert_eq!(f, "bending.height");
    assert!(r.contains("3.8 mean disc diameters"), "{r}");
    // 5.8 mm span on a 6 mm beam: 0.1 mm beyond each support, less than a disc.
    let (f, r) = field(t(6e-3, 1.5e-3, 5.8e-3).check_geometry([6e-3, 1.5e-3], R));
    assert_eq!(f, "bending.span");
    assert!(
        r.contains("beyond each support") && r.contains("5.4800 mm"),
        "{r}"
    );
    // 0.8 mm span: the mid-span and support gauges (±0.26 mm) overlap.
    let (f, r) = field(t(6e-3, 1.5e-3, 0.8e-3).check_geometry([6e-3, 1.5e-3], R));
    assert_eq!(f, "bending.span");
    assert!(r.contains("gauges") && r.contains("overlap"), "{r}");
    // Gauges narrower than a disc, or reaching past the neutral axis.
    let mut g = t(6e-3, 1.5e-3, 5e-3);
    g.gauge_width = 0.9;
    assert_eq!(
        field(g.check_geometry([6e-3, 1.5e-3], R)).0,
        "bending.gauge_width"
    );
    g.gauge_width = 6.0;
    let (f, r) = field(g.check_geometry([6e-3, 1.5e-3], R));
    assert_eq!(f, "bending.gauge_width");
    assert!(r.contains("neutral axis"), "{r}");
}

#[test]
fn specimen_resolution_names_the_smaller_side() {
    let p = |w: f64, h: f64| {
        SpecimenParams::new(
            Method::Traditional,
            w,
            h,
            0.1e-3,
            0.16e-3,
            3200.0,
            310e9,
            800e6,
            1,
        )
    };
    p(3e-3, 1.5e-3).check_resolution().unwrap();
    match p(3e-3, 1e-3).check_resolution() {
        Err(SpecimenError::Geometry { field, reason }) => {
            assert_eq!(field, "height");
            assert!(reason.contains("3.8 mean disc diameters"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    match p(1e-3, 3e-3).check_resolution() {
        Err(SpecimenError::Geometry { field, .. }) => assert_eq!(field, "width"),
        other => panic!("{other:?}"),
    }
    // validate() (which generate runs) does not refuse it: existing parameter sets still
    // generate.
    p(3e-3, 1e-3).validate().unwrap();
}
