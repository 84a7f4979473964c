//! Cutting runs are read back, not run again, when a run with the same parameters finished in
//! the output folder (a `dem sweep` case of the same inputs); a changed parameter runs anew.

use std::path::Path;
use std::sync::Mutex;
use validation::cutting_runs::{run_plan, Missing, Outcome};
use validation::table2_section::plan;

#[test]
fn finished_runs_are_read_back_and_changed_ones_rerun() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data");
    let mut p = plan(&data, true).unwrap();
    p.methods = vec![dem_lab::specimen::Method::Traditional];
    p.depths_mm = vec![1.0];
    p.speeds_m_s = vec![2.0];
    p.length = 1.0e-3;
    let work = std::env::temp_dir().join(format!("dem-resume-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    let lines = Mutex::new(Vec::<String>::new());
    let log = |l: &str| lines.lock().unwrap().push(l.to_string());

    let Outcome {
        finished: first,
        errors: e1,
        ..
    } = run_plan(&p, &work, Missing::Run, &log);
    assert!(e1.is_empty(), "{e1:?}");
    assert_eq!(first.len(), 1);
    assert!(!first[0].resumed);
    let specimens = work.join("specimens");
    assert!(std::fs::read_dir(&specimens).unwrap().count() > 0);
    // Its case folder is a `dem sweep` case: done.json beside the result.
    assert!(
        first[0].dir.join("done.json").is_file(),
        "{:?}",
        first[0].dir
    );
    std::fs::remove_dir_all(&specimens).unwrap();

    lines.lock().unwrap().clear();
    let Outcome {
        finished: second,
        errors: e2,
        ..
    } = run_plan(&p, &work, Missing::Run, &log);
    assert!(e2.is_empty(), "{e2:?}");
    assert!(second[0].resumed);
    assert_eq!(second[0].record, first[0].record);
    assert!(
        !specimens.exists(),
        "no specimen is generated for a run read back"
    );

    // Another cut length is another run.
    p.length = 1.1e-3;
    let Outcome {
        finished: third,
        errors: e3,
        ..
    } = run_plan(&p, &work, Missing::Run, &log);
    assert!(e3.is_empty(), "{e3:?}");
    assert!(!third[0].resumed);

    // Listing instead of running: a finished run is read back, a new one is only named.
    p.length = 1.2e-3;
    let listed = run_plan(&p, &work, Missing::List, &log);
    assert!(listed.finished.is_empty() && listed.errors.is_empty());
    assert_eq!(listed.missing, vec!["traditional-d1-v2-s1".to_string()]);
    // ... and nothing was written for it: the 1.1 mm run is still the one read back.
    p.length = 1.1e-3;
    let back = run_plan(&p, &work, Missing::List, &log);
    assert!(back.missing.is_empty());
    assert_eq!(back.finished.len(), 1);
    assert!(back.finished[0].resumed);
    assert_eq!(back.finished[0].record, third[0].record);

    // A failed run leaves its error: listing reports the failure rather than "not run".
    p.dt_factor = Some(dem_lab::tests::harness::DtFactor(2.0));
    let failed = run_plan(&p, &work, Missing::Run, &log);
    assert!(failed.finished.is_empty());
    assert_eq!(failed.errors.len(), 1, "{:?}", failed.errors);
    let listed = run_plan(&p, &work, Missing::List, &log);
    assert!(listed.missing.is_empty(), "{:?}", listed.missing);
    assert_eq!(listed.errors.len(), 1);
    assert!(
        listed.errors[0].contains("failed") && listed.errors[0].contains("dt_factor"),
        "{:?}",
        listed.errors
    );
    let _ = std::fs::remove_dir_all(&work);
}
