//! `validation --sweep DIR`: a folder that is not a `dem sweep` plan is an error naming its
//! `cases.jsonl`, for Table 2 (the section is written as not available) and for a study. The
//! reading of real sweep folders is tested end to end in `dem-cli/tests/sweep_validation.rs`
//! (it needs the `dem` executable).

use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-val-sweep-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data")
}

#[test]
fn a_folder_that_is_not_a_sweep_is_an_error_naming_its_case_list() {
    let dir = tmp("bad");
    let not_sweep = dir.join("nothing-here");
    let out = dir.join("report");
    let o = Command::new(env!("CARGO_BIN_EXE_validation"))
        .args(["--data", data().to_str().unwrap(), "--sweep"])
        .arg(&not_sweep)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.contains("cases.jsonl") && err.contains("table2"),
        "{err}"
    );
    // Table 2 alone was attempted (no other section ran) and its failure written down.
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    assert!(md.contains("table2: not available") && md.contains("cases.jsonl"));
    assert!(!md.contains("Table 1 (Ye & Xu 2010)"), "{md}");

    let o = Command::new(env!("CARGO_BIN_EXE_validation"))
        .args(["--data", data().to_str().unwrap(), "--study"])
        .arg(data().join("studies/speed-damping.json"))
        .arg("--sweep")
        .arg(&not_sweep)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("cases.jsonl"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
