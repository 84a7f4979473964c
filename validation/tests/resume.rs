//! Cutting runs are read back, not run again, when a run with the same parameters finished in
//! the output folder (`run.key.json`); a changed parameter runs anew.

use std::path::Path;
use std::sync::Mutex;
use validation::cutting_runs::run_plan;
use validation::table2_section::plan;

#[test]
fn finished_runs_are_read_back_and_changed_ones_rerun() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data");
    let mut p = plan(&data, true).unwrap();
    p.methods = vec![dem_core::specimen::Method::Traditional];
    p.depths_mm = vec![1.0];
    p.speeds_m_s = vec![2.0];
    p.length = 1.0e-3;
    let work = std::env::temp_dir().join(format!("dem-resume-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&work);
    let lines = Mutex::new(Vec::<String>::new());
    let log = |l: &str| lines.lock().unwrap().push(l.to_string());

    let (first, e1) = run_plan(&p, &work, &log);
    assert!(e1.is_empty(), "{e1:?}");
    assert_eq!(first.len(), 1);
    assert!(!first[0].resumed);
    assert!(lines
        .lock()
        .unwrap()
        .iter()
        .any(|l| l.starts_with("specimen")));

    lines.lock().unwrap().clear();
    let (second, e2) = run_plan(&p, &work, &log);
    assert!(e2.is_empty(), "{e2:?}");
    assert!(second[0].resumed);
    assert_eq!(second[0].record, first[0].record);
    assert!(
        !lines
            .lock()
            .unwrap()
            .iter()
            .any(|l| l.starts_with("specimen")),
        "no specimen is generated for a run read back"
    );

    // Another cut length is another run.
    p.length = 1.1e-3;
    let (third, e3) = run_plan(&p, &work, &log);
    assert!(e3.is_empty(), "{e3:?}");
    assert!(!third[0].resumed);
    let _ = std::fs::remove_dir_all(&work);
}
