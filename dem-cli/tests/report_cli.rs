//! `dem report` (issue 48, item 8): the report is a `dem` subcommand that finds the project's
//! data, pictures and commit wherever it runs. Before, it was only `cargo run -p validation`
//! from the repository's root; run elsewhere it finished "without 6 section(s)" and "commit
//! unknown".

mod common;
use common::{dem_in, text, tmp};

#[test]
fn the_report_runs_from_any_folder() {
    let dir = tmp("elsewhere");
    let o = dem_in(&dir, &["report", "--only", "table1", "--out", "r"]);
    assert!(o.status.success(), "{}", text(&o));
    let md = std::fs::read_to_string(dir.join("r/index.md")).unwrap();
    assert!(md.contains("## Table 1 (Ye & Xu 2010)"), "{md}");
    assert!(
        !md.contains("commit unknown") && md.contains("| commit | `"),
        "{md}"
    );
    assert!(dir.join("r/table1.json").exists() && dir.join("r/index.html").exists());
    // The data folder the report read is the repository's, not one under the current folder.
    assert!(!dir.join("data").exists());
}

#[test]
fn an_unknown_section_is_named_and_nothing_is_written() {
    let dir = tmp("unknown");
    let o = dem_in(&dir, &["report", "--only", "tabel1", "--out", "r"]);
    assert!(!o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("unknown section `tabel1` (sections: table1,"),
        "{}",
        text(&o)
    );
    assert!(!dir.join("r/index.md").exists());
}
