//! Helpers the `dem` command-line tests share: a fresh temporary folder per test, the `dem`
//! binary run with arguments, its output as text, the shipped Si3N4 material file.
//!
//! Each test file includes this module (`mod common;`) and uses a part of it.
#![allow(dead_code)]

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// An empty folder `dem-<test binary>-<pid>-<name>` in the system's temporary folder (emptied
/// if an earlier run left it).
pub fn tmp(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let stem = exe.file_stem().and_then(|s| s.to_str()).unwrap_or("test");
    // Cargo names test binaries `<file>-<hash>`.
    let suite = stem.rsplit_once('-').map_or(stem, |(s, _)| s);
    let d = std::env::temp_dir().join(format!("dem-{suite}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `dem` with `args` in the test's working folder.
pub fn dem<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dem"))
        .args(args)
        .output()
        .unwrap()
}

/// Runs `dem` with `args` in `dir`.
pub fn dem_in<S: AsRef<OsStr>>(dir: &Path, args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_dem"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

/// Standard output, a newline, standard error.
pub fn text(o: &Output) -> String {
    format!(
        "{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// The repository's root folder.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The shipped Si3N4 material file (`data/materials/si3n4.json`).
pub fn material() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../data/materials/si3n4.json").to_string()
}

/// `dem specimen` of the small Si3N4 specimen the tests share (3 × 1.5 mm, radii 0.1–0.16 mm,
/// the shipped material), seed `seed`, into `out`: about 60 discs, under a second.
pub fn small_specimen_args(seed: u64, out: &Path) -> Vec<String> {
    [
        "specimen", "--width", "3mm", "--height", "1.5mm", "--r-min", "0.1mm", "--r-max", "0.16mm",
        "--seed",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([
        seed.to_string(),
        "--material".into(),
        material(),
        "--out".into(),
        out.display().to_string(),
    ])
    .collect()
}
