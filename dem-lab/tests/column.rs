//! The crushable column (`dem_lab::crushing::column`, docs/lattice.md §7) on a small
//! configuration: 16 grains of three outlines, a coarse lattice, two stress levels.
//!
//! - a grading is recorded at each level, when both platens carry it; with inertial loading
//!   (the default) the platen's speed keeps the inertial number near its target at every
//!   level, with a ramp the speed is constant and I falls as 1/√σ;
//! - breakage is irreversible: pieces only split, so Hardin's breakage potential can only
//!   fall and B_r rises (or stays) from level to level, within [0, 1];
//! - every grading's mass sums to the column's (the largest sieve passes everything);
//! - the break log has one line per broken link;
//! - the energy balance through breakage (work = strain + kinetic + damping + friction +
//!   released at breaks) within 1 % of the work;
//! - the outputs are written and hold no NaN; a bad value is refused naming its field.

use dem_lab::crushing::column::{self, ColumnTest, Loading};
use dem_lab::LabError;
use std::path::PathBuf;

fn outlines() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/outlines");
    ["equant-01.csv", "concave-02.csv", "elongated-02.csv"]
        .iter()
        .map(|f| dir.join(f))
        .collect()
}

fn small() -> ColumnTest {
    ColumnTest {
        grains: 16,
        width: 5.0,
        d_min: 1.2e-3,
        d_max: 1.6e-3,
        size_classes: 2,
        spacing: 0.3e-3,
        stress_levels: vec![5e6, 20e6],
        seat_stress: 1e6,
        // Ten times the quasi-static default: a test, not a study.
        inertial_number: 1e-2,
        ..ColumnTest::default()
    }
}

#[test]
fn a_small_column_crushes_with_rising_relative_breakage() {
    let dir = std::env::temp_dir().join(format!("dem-column-test-{}", std::process::id()));
    let test = small();
    let o = column::run(&test, &outlines(), &dir, &mut |_, _| {}).unwrap();
    let r = &o.result;
    assert_eq!(r.grains, 16);
    assert!(
        r.levels_not_reached.is_empty(),
        "{:?}",
        r.levels_not_reached
    );
    assert_eq!(r.gradings.len(), 3);
    let mut last = 0.0;
    for g in &r.gradings[1..] {
        // Recorded when both platens carried the level, at the target inertial number
        // (the speed is set from the bottom platen's stress every history row).
        assert!(g.stress >= g.level, "{} < {}", g.stress, g.level);
        let ratio = g.inertial_number / test.inertial_number;
        assert!(
            (0.7..1.3).contains(&ratio),
            "I {} at {} Pa",
            g.inertial_number,
            g.level
        );
        assert!(
            g.relative_breakage >= last - 1e-12 && g.relative_breakage <= 1.0,
            "B_r {} after {last}",
            g.relative_breakage
        );
        last = g.relative_breakage;
        assert!((g.passing.last().unwrap() - 1.0).abs() < 1e-9);
    }
    assert_eq!(r.gradings[0].relative_breakage, 0.0);
    // The initial grading: the grains themselves, none finer than the fines cutoff.
    assert!(r.gradings[0].breakage_potential > 0.0);
    // Links broke (the second level is near the grains' strength) and the log lists them.
    let broken = r.gradings[2].broken_links;
    assert!(
        broken > 0 && last > 0.0,
        "no breakage: {broken} links, B_r {last}"
    );
    let log = std::fs::read_to_string(dir.join("column.breaks.csv")).unwrap();
    assert_eq!(log.lines().count() - 1, o.run.bonds_broken as usize);
    // Energy balance through breakage.
    let sum = r.strain_energy + r.kinetic_energy + r.damping + r.friction + r.released;
    assert!(r.released > 0.0);
    assert!(
        (sum - r.work).abs() <= 0.01 * r.work,
        "work {} vs {sum}",
        r.work
    );
    for f in [
        "column.stress_strain.csv",
        "column.gradings.csv",
        "column.result.json",
    ] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(!text.contains("NaN") && !text.contains("inf"), "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Ramp loading: each grading the first time both platens carry the level; the platen moves
/// at its constant speed, so the strain is the speed times the time over H0.
#[test]
fn a_ramp_records_each_level_when_both_platens_first_carry_it() {
    let dir = std::env::temp_dir().join(format!("dem-column-ramp-{}", std::process::id()));
    let test = ColumnTest {
        loading: Loading::Ramp,
        ..small()
    };
    let o = column::run(&test, &outlines(), &dir, &mut |_, _| {}).unwrap();
    let r = &o.result;
    assert_eq!(r.gradings.len(), 3);
    for g in &r.gradings[1..] {
        assert!(g.stress >= g.level, "{} < {}", g.stress, g.level);
        // Constant speed: I falls as 1/√σ from its value at the first level.
        let i1 = r.gradings[1].inertial_number;
        let expect = i1 * (r.gradings[1].stress / g.stress).sqrt();
        assert!(
            (g.inertial_number / expect - 1.0).abs() < 0.3,
            "{} vs {expect}",
            g.inertial_number
        );
        let strain = r.platen_speed * g.time / r.height;
        assert!(
            (g.strain - strain).abs() <= 1e-9 * strain,
            "{} vs {strain}",
            g.strain
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_inputs_are_refused_naming_the_field() {
    let dir = std::env::temp_dir().join(format!("dem-column-bad-{}", std::process::id()));
    let t = ColumnTest {
        seat_stress: 10e6,
        ..small()
    };
    match column::run(&t, &outlines(), &dir, &mut |_, _| {}) {
        Err(LabError::Param { field, .. }) => assert_eq!(field, "column.seat_stress"),
        other => panic!("{:?}", other.map(|_| ())),
    }
    // An outline the lattice cannot fill at this spacing: the error names the file.
    let t = ColumnTest {
        spacing: 1.1e-3,
        ..small()
    };
    match column::run(&t, &outlines(), &dir, &mut |_, _| {}) {
        Err(LabError::Param { field, reason }) => {
            assert_eq!(field, "outlines");
            assert!(reason.contains(".csv"), "{reason}");
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
    let missing = vec![dir.join("no-such-outline.csv")];
    assert!(column::run(&small(), &missing, &dir, &mut |_, _| {}).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
