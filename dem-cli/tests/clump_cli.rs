//! `dem clump` end to end: a batch with one bad file writes the good templates, lists the bad
//! one with its reason, and exits 1.

use std::process::Command;

#[test]
fn batch_with_a_bad_file_keeps_the_others() {
    let dir = std::env::temp_dir().join(format!("dem-clump-cli-{}", std::process::id()));
    let (input, out) = (dir.join("in"), dir.join("out"));
    std::fs::create_dir_all(input.join("sub")).unwrap();
    std::fs::write(input.join("square.csv"), "x,y\n0,0\n10,0\n10,10\n0,10\n").unwrap();
    std::fs::write(input.join("sub/tri.txt"), "# units: mm\n0 0\n12 0\n0 9\n").unwrap();
    // A bow tie: edges 0-1 and 2-3 cross.
    std::fs::write(input.join("bowtie.csv"), "0 0\n10 10\n10 0\n0 10\n").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args([
            "clump",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("bowtie.csv") && stderr.contains("1 of 3 grains failed"),
        "{stderr}"
    );
    assert!(stdout.contains("templates written 2"), "{stdout}");
    let sq = clumpgen::Template::load(&out.join("square.json")).unwrap();
    assert!(sq.cover.value >= 0.95 && sq.residuals.max() <= 1e-9);
    assert!(out.join("sub/tri.json").exists());
    assert!(!out.join("bowtie.json").exists());
    assert!(out.join("summary.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
