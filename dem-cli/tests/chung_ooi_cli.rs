//! `dem bench chung-ooi` (issue 50 item 4): the table, the exit status, the files of --out,
//! the committed LAMMPS peer beside ours.

use std::process::{Command, Output};

fn dem(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dem"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn bench_chung_ooi_passes_and_writes_its_results() {
    let out = std::env::temp_dir().join(format!("dem-chung-ooi-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let o = dem(&[
        "bench",
        "chung-ooi",
        "--steps-per-contact",
        "500",
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(stdout
        .lines()
        .last()
        .unwrap()
        .starts_with("worst asserted error: "));
    assert!(stdout.contains("LAMMPS: LAMMPS "), "{stdout}");
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("chung_ooi.json")).unwrap())
            .unwrap();
    assert_eq!(j["schema"], "dem.chung-ooi/1");
    assert_eq!(j["failed"], 0);
    assert!(out.join("chung_ooi_test1_force.svg").is_file());
    assert!(out.join("chung_ooi_test8_recoil.svg").is_file());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bench_chung_ooi_refuses_a_coarse_step() {
    let o = dem(&["bench", "chung-ooi", "--steps-per-contact", "10"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--steps-per-contact"));
}
