//! Deleting detached fragments during a cut (`CuttingTest::delete_fragments`): a short cut of
//! a small specimen deletes fragments, books their energy (the balance holds), gives the same
//! bytes on one and two threads, resumes bit-identically from a checkpoint, and leaves the run
//! keys of a test without deletion unchanged.

use dem_lab::cutting::{self, CuttingRunOptions, CuttingTest};
use dem_lab::LabError;
use std::path::{Path, PathBuf};

mod lab_common;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-debris-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// a_p = 0.6 mm, L = 1.5 mm, v = 10 m/s, 400 history rows (the `lab_cutting.rs` short cut).
fn short_test(delete: bool) -> CuttingTest {
    CuttingTest {
        history_rows: 400,
        window_start: 1.0,
        delete_fragments: delete,
        ..CuttingTest::new(0.6e-3, 10.0, 1.5e-3)
    }
}

fn on_threads<T: Send>(n: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .unwrap()
        .install(f)
}

fn same_files(a: &Path, b: &Path) {
    for f in [cutting::FORCES_FILE, "history.csv", "breaks.csv"] {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        assert!(x == y, "{f} differs");
    }
}

#[test]
fn a_cut_with_deletion_deletes_debris_and_is_thread_independent() {
    let dir = tmp("threads");
    let (spec, model) = lab_common::cut_specimen(&dir);
    let spec = dem_lab::cutting::SpecimenInfo::read(&spec).unwrap();
    let run = |delete: bool, threads: usize, out: &str| {
        let out = dir.join(out);
        let t = short_test(delete).check().unwrap();
        on_threads(threads, || {
            cutting::run(&t, &model, &spec, &out, &mut |_, _| {})
        })
        .unwrap()
    };
    let off = run(false, 2, "off");
    let one = run(true, 1, "one");
    let two = run(true, 2, "two");
    let d = one
        .deleted
        .clone()
        .expect("deletion on: the result says what went");
    eprintln!(
        "without deletion: main {:?} chips {:?} balance {:e}\nwith deletion: main {:?} chips \
         {:?} deleted {d:?} balance {:e} (max {:e})",
        off.main_force,
        off.chips.chips,
        off.run.balance_error_max_abs,
        one.main_force,
        one.chips.chips,
        one.run.balance_error_max_abs,
        one.run.balance_error_final
    );
    assert!(off.deleted.is_none());
    assert!(d.fragments > 0 && d.discs >= d.fragments, "{d:?}");
    assert!(
        d.mass > 0.0 && d.kinetic_energy > 0.0 && d.energy.is_finite(),
        "{d:?}"
    );
    assert_eq!(d.check_every, one.run.history_every);
    assert_eq!(one.discs as u64 + d.discs, off.discs as u64);
    // The deleted energy is booked: the balance holds as well as without deletion.
    assert!(
        one.run.balance_error_max_abs < 0.05,
        "{}",
        one.run.balance_error_max_abs
    );
    // Bond totals still count the bonds that went with the fragments.
    assert_eq!(one.broken_bonds[0].total, off.broken_bonds[0].total);
    // One and two threads: the same bytes.
    same_files(&dir.join("one"), &dir.join("two"));
    assert_eq!(one.deleted, two.deleted);
    assert_eq!(one.main_force, two.main_force);
    // The run keys of a test without deletion do not mention it.
    let j = serde_json::to_value(short_test(false)).unwrap();
    assert!(j.get("delete_fragments").is_none());
    let j = serde_json::to_value(&off).unwrap();
    assert!(j.get("deleted").is_none());
    let back: CuttingTest =
        serde_json::from_value(serde_json::to_value(short_test(true)).unwrap()).unwrap();
    assert!(back.delete_fragments);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A cut with deletion stopped part-way and run again resumes from its checkpoint (which holds
/// the world after the deletions so far) and ends with the same bytes as an uninterrupted run.
#[test]
fn an_interrupted_cut_with_deletion_resumes_bit_identically() {
    let dir = tmp("resume");
    let (spec, model) = lab_common::cut_specimen(&dir);
    let spec = dem_lab::cutting::SpecimenInfo::read(&spec).unwrap();
    let test = CuttingTest {
        history_rows: 200,
        ..short_test(true)
    }
    .check()
    .unwrap();
    let (a, b) = (dir.join("a"), dir.join("b"));
    let ra = cutting::run(&test, &model, &spec, &a, &mut |_, _| {}).unwrap();
    let stop = CuttingRunOptions {
        max_steps: Some(ra.run.steps * 2 / 3),
        ..CuttingRunOptions::default()
    };
    match cutting::run_with(&test, &model, &spec, &b, &stop, &mut |_, _| {}) {
        Err(LabError::Stopped { .. }) => {}
        other => panic!("expected a stop, got {:?}", other.map(|r| r.run)),
    }
    let rb = cutting::run(&test, &model, &spec, &b, &mut |_, _| {}).unwrap();
    assert_eq!(rb.run.invocations, 2);
    same_files(&a, &b);
    assert_eq!(ra.deleted, rb.deleted);
    assert!(ra.deleted.as_ref().unwrap().fragments > 0);
    let (x, y) = (
        std::fs::read(a.join("ckpt-final.json")).unwrap(),
        std::fs::read(b.join("ckpt-final.json")).unwrap(),
    );
    // (The checkpoints' run totals differ: wall time; the worlds must not.)
    let world = |t: &[u8]| serde_json::from_slice::<serde_json::Value>(t).unwrap()["world"].clone();
    assert!(world(&x) == world(&y), "final worlds differ");
    let _ = std::fs::remove_dir_all(&dir);
}
