//! Issue 4, second Done-when point: UCS, Brazilian and bending tests run on a calibrated
//! specimen and their analyses give the calibration targets. A coarse traditional specimen
//! (radii 0.4–0.6 mm: UCS 10 × 20 mm, beam 20 × 5 mm on a 16 mm span, Brazilian disc 10 mm)
//! is calibrated with `dem_lab::calibrate` (Potyondy & Cundall 2004 procedure) to
//! targets this model can reach — SiC's E = 430 GPa and flexural strength 589 MPa (S4 Table 1)
//! with ν = 0.30 (S4's 0.14 is below what this 2D packing gives at k_n/k_s ≥ 1, which the
//! calibration reports instead of hiding) — then the three tests are run again, independently,
//! with the calibrated model.
//!
//! Tolerances: E within 3 % and σ_f within 4 % (the calibration's 2 % plus the one E rescale
//! that follows the strength search), ν within 0.015 (the calibration's 0.01 plus the same).

use dem_lab::calibrate::virtual_lab::VirtualLab;
use dem_lab::calibrate::{calibrate, Options, Targets};
use dem_lab::specimen::{Method, SpecimenParams};
use dem_lab::tests::bending::BendingTest;
use dem_lab::tests::brazilian::BrazilianTest;
use dem_lab::tests::ucs::UcsTest;
use dem_lab::LabModel;

/// The coarse traditional SiC specimen of these tests (radii 0.4–0.6 mm, 10 × 20 mm).
fn coarse(seed: u64) -> SpecimenParams {
    SpecimenParams::new(
        Method::Traditional,
        10e-3,
        20e-3,
        0.4e-3,
        0.6e-3,
        3100.0,
        430e9,
        214e6,
        seed,
    )
}

#[test]
fn calibrated_specimen_gives_the_targets() {
    let dir = std::env::temp_dir().join(format!("dem-lab-calibrated-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let p = coarse(1);
    let mut lab = VirtualLab::prepare(
        &p,
        &dir,
        UcsTest::default(),
        BendingTest::default(),
        BrazilianTest::default(),
        1,
        &mut |l| eprintln!("{l}"),
    )
    .unwrap();
    let targets = Targets {
        young: 430e9,
        poisson: Some(0.30),
        flexural: Some(589e6),
        ..Targets::default()
    };
    let start = LabModel::from_params(&p);
    let c = calibrate(&mut lab, &start, &targets, &Options::default(), &mut |l| {
        eprintln!("{l}")
    })
    .unwrap();
    eprintln!("notes: {:?}", c.notes);
    assert!(
        c.notes.iter().all(|n| !n.contains("not reached")),
        "{:?}",
        c.notes
    );
    // The calibrated model moved away from the start (E_c, κ and σ̄c were all searched).
    assert!(c.model.micro.contact_modulus != start.micro.contact_modulus);
    assert!(c.model.micro.boundary_tensile != start.micro.boundary_tensile);

    // Independent runs of the three tests with the calibrated model.
    let m = &c.model;
    let u = dem_lab::tests::run(&lab.ucs[0], m, &lab.ucs_specimen[0], &mut |_, _| {}).unwrap();
    let b =
        dem_lab::tests::run(&lab.bending[0], m, &lab.bending_specimen[0], &mut |_, _| {}).unwrap();
    let z = dem_lab::tests::run(
        &lab.brazilian[0],
        m,
        &lab.brazilian_specimen[0],
        &mut |_, _| {},
    )
    .unwrap();
    let (e, nu, sf) = (u.result.young, u.result.poisson, b.result.flexural_strength);
    eprintln!(
        "calibrated: E {:.1} GPa, ν {:.3}, UCS {:.0} MPa, σ_f {:.0} MPa, σ_t {:.0} MPa",
        e * 1e-9,
        nu,
        u.result.ucs * 1e-6,
        sf * 1e-6,
        z.result.tensile_strength * 1e-6
    );
    assert!((e / 430e9 - 1.0).abs() < 0.03, "E {e}");
    assert!((nu - 0.30).abs() < 0.015, "ν {nu}");
    assert!((sf / 589e6 - 1.0).abs() < 0.04, "σ_f {sf}");
    // The Brazilian strength is reported, not fitted: positive and finite, and the same as
    // the calibration's own final run (the runs are deterministic).
    assert!(z.result.tensile_strength > 0.0);
    assert_eq!(Some(z.result.tensile_strength), c.achieved.brazilian);
    assert_eq!(e, c.achieved.young);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `dem calibrate --seeds 2`: every test runs on one specimen per seed (the second seed's
/// files and runs named `-seed2`), and what the calibration sees is the mean of the runs.
#[test]
fn two_seeds_are_two_specimens_and_the_lab_returns_their_mean() {
    use dem_lab::calibrate::Lab;
    let dir = std::env::temp_dir().join(format!("dem-lab-seeds-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let p = coarse(4);
    let mut lab = VirtualLab::prepare(
        &p,
        &dir,
        UcsTest::default(),
        BendingTest::default(),
        BrazilianTest::default(),
        2,
        &mut |l| eprintln!("{l}"),
    )
    .unwrap();
    // Seeds 4 and the next that generates (measured: the Brazilian disc of seed 5 does not
    // reach its isotropic stress, so seed 6 replaces it).
    for (k, name) in ["ucs", "bending", "brazilian"].iter().enumerate() {
        let s = &lab.seeds[k];
        assert_eq!((s.len(), s[0]), (2, 4), "{name}: {s:?}");
        assert!(s[1] > 4, "{name}: {s:?}");
        assert!(dir.join(format!("{name}-specimen.json")).exists());
        assert!(dir
            .join(format!("{name}-specimen-seed{}.json", s[1]))
            .exists());
    }
    assert_eq!(
        lab.brazilian[1].name,
        format!("brazilian-seed{}", lab.seeds[2][1])
    );
    assert_eq!(lab.ucs[0].name, "ucs");
    // Two packings of one seed each: different specimens.
    assert_ne!(lab.ucs_specimen[0].discs, 0);
    assert_ne!(
        (lab.ucs_specimen[0].discs, lab.ucs_specimen[0].bonds),
        (lab.ucs_specimen[1].discs, lab.ucs_specimen[1].bonds)
    );
    let m = LabModel::from_params(&p);
    let f = lab.bending(&m).unwrap();
    assert_eq!(lab.last.bending.len(), 2);
    assert_ne!(lab.last.bending[0], lab.last.bending[1]);
    assert_eq!(f, 0.5 * (lab.last.bending[0] + lab.last.bending[1]));
    // The first seed's run is the one-seed lab's run (same specimen file, same test).
    let one = dem_lab::tests::run(
        &lab.bending[0],
        &m,
        &lab.bending_specimen[0],
        &mut |_, _| {},
    )
    .unwrap();
    assert_eq!(one.result.flexural_strength, lab.last.bending[0]);
    let u = lab.ucs(&m).unwrap();
    let mean_e = 0.5 * (lab.last.ucs[0].young + lab.last.ucs[1].young);
    assert_eq!(u.young, mean_e);
    assert_eq!(lab.runs, 4);
    let _ = std::fs::remove_dir_all(&dir);
}
