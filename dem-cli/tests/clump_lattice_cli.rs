//! `dem clump --method lattice --spacing S` end to end (docs/lattice.md): a square and a thin
//! strip in one batch: the square is written as a `clumpgen.template/2` lattice template, the
//! strip fails naming its file and `spacing`; the template validates against the JSON Schema;
//! bad flags are usage errors naming the flag.

use std::path::Path;

mod common;
use common::{dem, text, tmp};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn lattice_batch_writes_version_2_templates_and_names_thin_grains() {
    let d = tmp("batch");
    let (input, out) = (d.join("in"), d.join("out"));
    std::fs::create_dir_all(&input).unwrap();
    std::fs::write(input.join("square.csv"), "x,y\n0,0\n10,0\n10,10\n0,10\n").unwrap();
    std::fs::write(input.join("strip.csv"), "x,y\n0,0\n40,0\n40,1.5\n0,1.5\n").unwrap();
    let o = dem(&[
        "clump",
        s(&input),
        "--out",
        s(&out),
        "--method",
        "lattice",
        "--spacing",
        "1mm",
    ]);
    let all = text(&o);
    assert_eq!(o.status.code(), Some(1), "{all}");
    assert!(
        all.contains("strip.csv: spacing: the grain is thinner than one lattice cell"),
        "{all}"
    );
    let t = clumpgen::Template::load(&out.join("square.json")).unwrap();
    assert_eq!(t.schema, "clumpgen.template/2");
    let l = t.lattice.as_ref().unwrap();
    assert_eq!(l.spacing, 1e-3);
    assert!(
        t.discs.len() >= 70 && !l.links.is_empty(),
        "{}",
        t.discs.len()
    );
    assert!(t.residuals.max() <= 1e-10);
    // The template validates against `dem schema template` (docs/schema/template.schema.json).
    let o = dem(&["schema", "template"]);
    let schema: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let v = jsonschema::validator_for(&schema).unwrap();
    let file: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("square.json")).unwrap()).unwrap();
    let errs: Vec<String> = v.iter_errors(&file).map(|e| e.to_string()).collect();
    assert!(errs.is_empty(), "{errs:?}");
    // No cover warning: a lattice has no cover target.
    assert!(!all.contains("below the target"), "{all}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn bad_lattice_flags_are_usage_errors_naming_the_flag() {
    let d = tmp("flags");
    std::fs::write(d.join("square.csv"), "x,y\n0,0\n10,0\n10,10\n0,10\n").unwrap();
    let out = d.join("out");
    let run = |extra: &[&str]| {
        let mut a = vec!["clump", s(&d), "--out", s(&out)];
        a.extend_from_slice(extra);
        let o = dem(&a);
        (o.status.code(), text(&o))
    };
    for (extra, want) in [
        (
            &["--method", "lattice"][..],
            "--method lattice needs --spacing",
        ),
        (
            &["--spacing", "0.1"][..],
            "--spacing is for --method lattice",
        ),
        (
            &["--method", "lattice", "--spacing", "0"][..],
            "--spacing 0: must be positive and finite",
        ),
        (
            &["--method", "lattice", "--spacing=-1mm"][..],
            "--spacing -1mm: must be positive and finite",
        ),
        (
            &["--method", "lattice", "--spacing", "nan"][..],
            "--spacing nan: must be positive and finite",
        ),
        (
            &[
                "--method",
                "lattice",
                "--spacing",
                "0.1",
                "--node-radius",
                "2",
            ][..],
            "--node-radius 2: a fraction of S/2 in (0, 1]",
        ),
    ] {
        let (code, all) = run(extra);
        assert_eq!(code, Some(2), "{extra:?}: {all}");
        assert!(all.contains(want), "{extra:?}: {all}");
    }
    assert!(!out.join("square.json").exists());
    std::fs::remove_dir_all(&d).unwrap();
}
