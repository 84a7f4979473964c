//! Progress off a terminal (issue 48, item 8): a long read or generation whose stderr goes to a
//! file or a pipe wrote nothing until it ended (a 20,000-feature GeoJSON, 17 s; a 10 m specimen,
//! 25.7 s), since a progress bar draws only on a terminal. Now a line every `DEM_PROGRESS_SECS`
//! seconds (default 10) and a closing line; work shorter than one interval prints none.
//! The tests set a tiny interval so that every update writes a line.

use std::process::{Command, Output};

mod common;
use common::{text, tmp};

/// `dem` with `args` and `DEM_PROGRESS_SECS` set to `secs` (unset for `None`), stderr a pipe.
fn dem_with(secs: Option<&str>, args: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_dem"));
    c.args(args).env_remove("DEM_PROGRESS_SECS");
    if let Some(s) = secs {
        c.env("DEM_PROGRESS_SECS", s);
    }
    c.output().unwrap()
}

fn progress_lines(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| l.starts_with('[') && l.contains(" s]"))
        .map(str::to_string)
        .collect()
}

fn outlines(dir: &std::path::Path, n: usize) -> std::path::PathBuf {
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    for i in 0..n {
        let a = 10.0 + i as f64;
        std::fs::write(
            input.join(format!("g{i}.csv")),
            format!("x,y\n0,0\n{a},0\n{a},8\n0,9\n"),
        )
        .unwrap();
    }
    input
}

#[test]
fn a_batch_of_grains_says_how_far_it_is_off_a_terminal() {
    let dir = tmp("clump");
    let input = outlines(&dir, 4);
    let out = dir.join("out");
    let args = [
        "clump",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "1",
    ];
    let o = dem_with(Some("1e-6"), &args);
    assert!(o.status.success(), "{}", text(&o));
    let lines = progress_lines(&o);
    assert!(
        lines
            .iter()
            .any(|l| l.contains("/4 grains (") && l.contains("s left")),
        "{lines:?}"
    );
    assert!(
        lines
            .last()
            .is_some_and(|l| l.ends_with("4/4 grains: done")),
        "{lines:?}"
    );
    // The default interval (10 s) is longer than this batch: no lines; `off`: none either.
    for secs in [None, Some("off"), Some("0")] {
        std::fs::remove_dir_all(&out).unwrap();
        let o = dem_with(secs, &args);
        assert!(o.status.success(), "{}", text(&o));
        assert!(progress_lines(&o).is_empty(), "{secs:?}: {}", text(&o));
    }
}

#[test]
fn a_specimen_generation_says_its_stage_off_a_terminal() {
    let dir = tmp("specimen");
    let out = dir.join("s.json");
    let args = common::small_specimen_args(5, &out);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = dem_with(Some("1e-6"), &args);
    assert!(o.status.success(), "{}", text(&o));
    let lines = progress_lines(&o);
    for stage in ["grow", "relax"] {
        assert!(
            lines
                .iter()
                .any(|l| l.contains(&format!("] {stage} ")) && l.contains(" %")),
            "no {stage} line: {lines:?}"
        );
    }
    assert!(
        lines.last().is_some_and(|l| l.ends_with(" s] done")),
        "{lines:?}"
    );
}

#[test]
fn a_bad_interval_is_named_and_the_default_used() {
    let dir = tmp("bad");
    let input = outlines(&dir, 1);
    let out = dir.join("out");
    let o = dem_with(
        Some("soon"),
        &[
            "clump",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("DEM_PROGRESS_SECS=\"soon\": not a number of seconds")
            && err.contains("every 10 s"),
        "{err}"
    );
}
