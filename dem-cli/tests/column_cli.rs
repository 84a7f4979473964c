//! `dem test column` bad inputs (docs/lattice.md §7): errors name the flag or the outline
//! file, never a panic, and nothing is run.

use std::path::Path;

mod common;
use common::{dem, text, tmp};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `dem test column` on data/outlines with `extra` flags; the output as text (it must
/// fail).
fn fails(d: &Path, extra: &[&str]) -> String {
    let outlines = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/outlines");
    let mut args = vec!["test", "column", "--outlines", s(&outlines), "--out", s(d)];
    args.extend_from_slice(extra);
    let r = dem(&args);
    let all = text(&r);
    assert!(!r.status.success(), "{args:?}: {all}");
    assert!(!all.contains("panicked"), "{all}");
    all
}

#[test]
fn bad_inputs_name_the_flag_or_outline() {
    let d = tmp("column-bad");
    for (flags, expect) in [
        (vec!["--grains", "0"], "--grains"),
        (vec!["--d-max", "1mm"], "--d-max"),
        (vec!["--spacing", "-1mm"], "--spacing"),
        (vec!["--poisson", "0.4"], "--poisson"),
        (vec!["--seat-stress", "10MPa"], "--seat-stress"),
        (vec!["--stress-levels", "5MPa,2MPa"], "--stress-levels"),
        (vec!["--max-strain", "1.5"], "--max-strain"),
        (vec!["--width", "1"], "--width"),
        (vec!["--criterion", "force"], "--link-force"),
        (vec!["--criterion", "stress"], "--link-stress"),
        (
            vec!["--criterion", "stress", "--link-stress", "-5MPa"],
            "--link-stress",
        ),
        (vec!["--speed", "1m/s"], "--loading ramp"),
        (vec!["--loading", "steps"], "--loading"),
        (vec!["--inertial-number", "0"], "--inertial-number"),
    ] {
        let all = fails(&d, &flags);
        assert!(all.contains(expect), "{flags:?}: {all}");
    }
    // A spacing the thinnest outline cannot hold: the error names an outline file.
    let all = fails(&d, &["--spacing", "1.1mm"]);
    assert!(all.contains(".csv"), "{all}");
    // No outline at all.
    let empty = d.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let r = dem(&["test", "column", "--outlines", s(&empty), "--out", s(&d)]);
    let all = text(&r);
    assert!(!r.status.success() && all.contains("--outlines"), "{all}");
}
