//! `dem test crush` end to end (docs/lattice.md §4): a small disc-shaped grain from an outline
//! and `--spacing` is crushed and writes its result, force–displacement and break log; bad
//! inputs are errors naming the flag or the grain's file, never a panic.

use std::path::Path;

mod common;
use common::{dem, text, tmp};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A 48-gon of radius `r` mm.
fn disc(dir: &Path, r: f64) -> std::path::PathBuf {
    let mut t = String::from("# units: mm\nx,y\n");
    for k in 0..48 {
        let a = k as f64 * std::f64::consts::TAU / 48.0;
        t += &format!("{},{}\n", r * a.cos(), r * a.sin());
    }
    let f = dir.join("disc.csv");
    std::fs::write(&f, t).unwrap();
    f
}

#[test]
fn crush_writes_its_result_and_logs() {
    let d = tmp("run");
    let o = d.join("out");
    let outline = disc(&d, 1.0);
    let r = dem(&[
        "test",
        "crush",
        "--outline",
        s(&outline),
        "--spacing",
        "0.22",
        "--criterion",
        "energy",
        "--fracture-energy",
        "30",
        "--out",
        s(&o),
        "--threads",
        "1",
    ]);
    let all = text(&r);
    assert!(r.status.success(), "{all}");
    assert!(all.contains("σ = F/(d t) = "), "{all}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(o.join("crush.result.json")).unwrap())
            .unwrap();
    let sigma = v["result"]["strength"].as_f64().unwrap();
    assert!(sigma > 0.0, "{sigma}");
    assert!(v["result"]["stage1"]["broken_links"].as_u64().unwrap() > 0);
    let breaks = std::fs::read_to_string(o.join("crush.breaks.csv")).unwrap();
    assert!(breaks.starts_with("time,step,grain,link,node_i,node_j,criterion,mode,x,y,energy\n"));
    assert!(breaks.lines().count() > 1);
    let force = std::fs::read_to_string(o.join("crush.force.csv")).unwrap();
    assert!(force.lines().count() > 10);
    assert!(!force.contains("NaN") && !breaks.contains("NaN"));
    // The scenes run again with `dem run`: both are plain files.
    assert!(o.join("crush.json").is_file() && o.join("crush-stage2.json").is_file());
    // The run folder is locked to the test (run_lock.rs), the lock left with its pid cleared.
    let lock = std::fs::read_to_string(o.join("crush.out").join("run.lock")).unwrap();
    assert!(
        lock.contains("\"dem test crush\"") && lock.contains("\"pid\": null"),
        "{lock}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

/// Runs `dem test crush` with `extra` flags on a 1 mm disc; the output as text (it must fail).
fn fails(d: &Path, extra: &[&str]) -> String {
    let outline = disc(d, 1.0);
    let mut args = vec!["test", "crush", "--outline", s(&outline), "--out", s(d)];
    args.extend_from_slice(extra);
    let r = dem(&args);
    let all = text(&r);
    assert!(!r.status.success(), "{args:?}: {all}");
    assert!(!all.contains("panicked"), "{all}");
    all
}

#[test]
fn bad_inputs_name_the_flag_or_grain() {
    let d = tmp("bad");
    let e = ["--criterion", "energy", "--fracture-energy", "30"];
    // Spacing larger than the grain (2 mm wide).
    let all = fails(&d, &[&["--spacing", "3mm"], &e[..]].concat());
    assert!(
        all.contains("disc.csv: spacing:") && all.contains("larger than the grain"),
        "{all}"
    );
    // A grain thinner than one lattice cell: a 2 × 0.15 mm strip at S = 0.1 mm.
    std::fs::write(
        d.join("strip.csv"),
        "# units: mm\nx,y\n0,0\n2,0\n2,0.15\n0,0.15\n",
    )
    .unwrap();
    let strip = d.join("strip.csv");
    let r = dem(&[
        &[
            "test",
            "crush",
            "--outline",
            s(&strip),
            "--out",
            s(&d),
            "--spacing",
            "0.1mm",
        ][..],
        &e[..],
    ]
    .concat());
    let all = text(&r);
    assert!(!r.status.success() && !all.contains("panicked"), "{all}");
    assert!(
        all.contains("strip.csv: spacing: the grain is thinner than one lattice cell"),
        "{all}"
    );
    // A criterion without its parameter, a parameter of another criterion, stress.
    for (flags, expect) in [
        (
            &["--criterion", "energy"][..],
            "--criterion energy needs --fracture-energy",
        ),
        (
            &["--criterion", "force"],
            "--criterion force needs --link-force",
        ),
        (
            &["--criterion", "strain"],
            "--criterion strain needs --link-strain",
        ),
        (
            &[
                "--criterion",
                "force",
                "--link-force",
                "10",
                "--fracture-energy",
                "3",
            ],
            "--fracture-energy is not a parameter of --criterion force",
        ),
        (
            &["--criterion", "stress"],
            "--criterion stress needs --link-stress",
        ),
        (
            &["--criterion", "energy", "--link-stress", "5MPa"],
            "--link-stress is not a parameter of --criterion energy",
        ),
        (
            &["--criterion", "energy", "--fracture-energy", "-1"],
            "--fracture-energy -1: must be positive",
        ),
    ] {
        let all = fails(&d, &[&["--spacing", "0.2"], flags].concat());
        assert!(all.contains(expect), "{flags:?}: {all}");
    }
    // Material and test parameters.
    let all = fails(
        &d,
        &[&["--spacing", "0.2", "--poisson", "0.4"], &e[..]].concat(),
    );
    assert!(
        all.contains("--poisson: 0.4: a triangular lattice"),
        "{all}"
    );
    let all = fails(
        &d,
        &[&["--spacing", "0.2", "--major", "1.5"], &e[..]].concat(),
    );
    assert!(all.contains("--major: 1.5: must lie in (0, 1)"), "{all}");
    // The grain: neither or both, --spacing without --outline, not a lattice template.
    let r = dem(&[&["test", "crush", "--out", s(&d)][..], &e[..]].concat());
    assert!(
        text(&r).contains("give the grain: --template"),
        "{}",
        text(&r)
    );
    let all = fails(&d, &e);
    assert!(all.contains("--outline needs --spacing"), "{all}");
    std::fs::write(d.join("not-lattice.json"), "{}").unwrap();
    let r = dem(&[
        &[
            "test",
            "crush",
            "--template",
            s(&d.join("not-lattice.json")),
            "--out",
            s(&d),
        ][..],
        &e[..],
    ]
    .concat());
    let all = text(&r);
    assert!(!r.status.success() && all.contains("--template: "), "{all}");
    assert!(all.contains("not-lattice.json"), "{all}");
    std::fs::remove_dir_all(&d).unwrap();
}
