//! `dem clump` end to end: a batch with one bad file writes the good templates, lists the bad
//! one with its reason, and exits 1.

use std::process::Command;

mod common;
use common::{dem, text, tmp};

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

const SQUARE: &str = "x,y\n0,0\n10,0\n10,10\n0,10\n";
const TRIANGLE: &str = "0 0\n12 0\n0 9\n";

/// Two files of one name in two folders, given as files: each gets its own template, in the
/// folders below their common folder (before: one `g.json`, the second overwriting the first).
#[test]
fn same_named_files_in_two_folders_get_two_templates() {
    let dir = tmp("two-folders");
    let (a, b, out) = (dir.join("coll/a"), dir.join("coll/b"), dir.join("o"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    std::fs::write(a.join("g.csv"), SQUARE).unwrap();
    std::fs::write(b.join("g.csv"), TRIANGLE).unwrap();
    let c = std::path::Path::new("clump");
    let o = dem(&[
        c,
        &a.join("g.csv"),
        &b.join("g.csv"),
        std::path::Path::new("--out"),
        &out,
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let ta = clumpgen::Template::load(&out.join("a/g.json")).unwrap();
    let tb = clumpgen::Template::load(&out.join("b/g.json")).unwrap();
    // The square (100 mm²) and the triangle (54 mm²) each in their own template.
    assert!((ta.shape.area - 100e-6).abs() < 1e-12, "{}", ta.shape.area);
    assert!((tb.shape.area - 54e-6).abs() < 1e-12, "{}", tb.shape.area);
    assert!(!out.join("g.json").exists());
    // Two folders given as folders keep their names too.
    let out2 = dir.join("o2");
    let o = dem(&[c, &a, &b, std::path::Path::new("--out"), &out2]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(out2.join("a/g.json").exists() && out2.join("b/g.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `g.csv` and `g.json` in one folder map to one template: refused before anything is
/// written, exit 2, both inputs named.
#[test]
fn two_inputs_for_one_template_are_refused() {
    let dir = tmp("clash");
    let (input, out) = (dir.join("in"), dir.join("o"));
    std::fs::create_dir_all(&input).unwrap();
    std::fs::write(input.join("g.csv"), SQUARE).unwrap();
    std::fs::write(
        input.join("g.json"),
        r#"{"units": "mm", "points": [[0, 0], [12, 0], [0, 9]]}"#,
    )
    .unwrap();
    let o = dem(&[
        std::path::Path::new("clump"),
        &input,
        std::path::Path::new("--out"),
        &out,
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains(&input.join("g.csv").display().to_string())
            && t.contains(&input.join("g.json").display().to_string())
            && t.contains(&out.join("g.json").display().to_string()),
        "{t}"
    );
    assert_eq!(t.matches("error").count(), 1, "{t}");
    assert!(!out.join("g.json").exists() && !out.join("summary.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `dem clump dir --out dir` with JSON outlines in dir: the templates would overwrite the
/// outlines; refused, exit 2, the outline untouched.
#[test]
fn templates_never_overwrite_an_input() {
    let dir = tmp("overwrite");
    let outline = r#"{"units": "mm", "points": [[0, 0], [12, 0], [0, 9]]}"#;
    std::fs::write(dir.join("h.json"), outline).unwrap();
    std::fs::write(dir.join("k.csv"), SQUARE).unwrap();
    let o = dem(&[
        std::path::Path::new("clump"),
        &dir,
        std::path::Path::new("--out"),
        &dir,
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains(&dir.join("h.json").display().to_string()) && t.contains("overwrite"),
        "{t}"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("h.json")).unwrap(),
        outline
    );
    assert!(!dir.join("k.json").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output folder inside the input folder, run twice: the second run does not read the
/// first run's templates and summary back as outlines (before: they were read and failed).
#[test]
fn an_output_folder_inside_the_inputs_is_not_read_back() {
    let dir = tmp("out-inside");
    std::fs::write(dir.join("k.csv"), SQUARE).unwrap();
    let out = dir.join("t");
    let run = || {
        dem(&[
            std::path::Path::new("clump"),
            &dir,
            std::path::Path::new("--out"),
            &out,
        ])
    };
    let first = run();
    assert_eq!(first.status.code(), Some(0), "{}", text(&first));
    let template = std::fs::read(out.join("k.json")).unwrap();
    let second = run();
    let t = text(&second);
    assert_eq!(second.status.code(), Some(0), "{t}");
    assert!(t.contains("templates written 1"), "{t}");
    assert!(!out.join("t").exists() && !out.join("summary.json.json").exists());
    assert_eq!(std::fs::read(out.join("k.json")).unwrap(), template);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A bad global flag is one usage error (exit 2, said once), not one failure per grain.
#[test]
fn a_bad_global_flag_is_one_usage_error() {
    let dir = tmp("flags");
    let (input, out) = (dir.join("in"), dir.join("o"));
    std::fs::create_dir_all(&input).unwrap();
    for k in 0..3 {
        std::fs::write(input.join(format!("g{k}.csv")), SQUARE).unwrap();
    }
    let run = |extra: &[&str]| {
        let mut args = vec![
            "clump".to_string(),
            input.display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        Command::new(env!("CARGO_BIN_EXE_dem"))
            .args(&args)
            .output()
            .unwrap()
    };
    for (flags, flag) in [
        (&["--cover", "1.5"][..], "--cover"),
        (&["--density=-1"][..], "--density"),
        (&["--max-discs", "0"][..], "--max-discs"),
        (&["--rmin", "0.5", "--rmax", "0.1"][..], "--rmin"),
        (&["--resample", "2"][..], "--resample"),
        (&["--raster", "0"][..], "--raster"),
        (&["--units", "px"][..], "--px-scale"),
        (&["--px-scale", "1e-6"][..], "--px-scale"),
        (&["--threads", "0"][..], "--threads"),
    ] {
        let o = run(flags);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{flags:?}: {t}");
        assert_eq!(t.matches(flag).count(), 1, "{flags:?}: {t}");
        assert!(!t.contains("panicked"), "{t}");
        assert!(!out.join("summary.json").exists(), "{flags:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--export`: each format is written beside each template (several formats, as a list and by
/// repeating the flag), the LAMMPS masses add up to the template's mass, and the formats that
/// cannot carry the mass properties exactly say so in the output.
#[test]
fn exports_are_written_beside_the_templates() {
    let dir = tmp("export");
    let (input, out) = (dir.join("in"), dir.join("o"));
    std::fs::create_dir_all(input.join("sub")).unwrap();
    std::fs::write(input.join("square.csv"), SQUARE).unwrap();
    std::fs::write(input.join("sub/tri.txt"), TRIANGLE).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args([
            "clump",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args([
            "--export",
            "lammps,yade",
            "--export",
            "mercury",
            "--export",
            "pfc",
        ])
        .output()
        .unwrap();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    for stem in ["square", "sub/tri"] {
        for ending in [
            ".json",
            ".pfc.p2dat",
            ".yade.py",
            ".lammps.mol",
            ".mercury/Clump/Clump.txt",
            ".mercury/Inertia/Mass.txt",
            ".mercury/Inertia/TOI.txt",
            ".mercury/Inertia/PD.txt",
            ".mercury/README.txt",
        ] {
            let p = out.join(format!("{stem}{ending}"));
            assert!(p.is_file(), "{} missing\n{t}", p.display());
        }
    }
    // The molecule file's Masses section adds up to the template's mass.
    let tpl = clumpgen::Template::load(&out.join("square.json")).unwrap();
    let mol = std::fs::read_to_string(out.join("square.lammps.mol")).unwrap();
    let masses: Vec<f64> = mol
        .lines()
        .skip_while(|l| l.trim() != "Masses")
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(masses.len(), tpl.discs.len());
    let sum: f64 = masses.iter().sum();
    assert!((sum - tpl.target.mass).abs() <= 1e-10 * tpl.target.mass);
    // One line per format; the inexact ones say so with their figures.
    let line = |f: &str| {
        t.lines()
            .find(|l| l.starts_with(&format!("export {f}")))
            .unwrap_or_else(|| panic!("no line for {f}\n{t}"))
            .to_string()
    };
    assert!(
        line("yade").ends_with("2 grains: exact mass, centroid and inertia"),
        "{t}"
    );
    assert!(line("pfc").contains("exact mass"), "{t}");
    // The LAMMPS line gives the range of the I_z shortfall of bodies built from atoms.
    let lammps = line("lammps");
    assert!(lammps.contains("NOT EXACT"), "{t}");
    let range = lammps
        .split("I_z is low by ")
        .nth(1)
        .and_then(|r| r.split(" %").next())
        .unwrap_or_else(|| panic!("no range in {lammps}"));
    let (lo, hi) = range.split_once('-').unwrap();
    let (lo, hi): (f64, f64) = (lo.parse().unwrap(), hi.parse().unwrap());
    assert!(0.0 < lo && lo <= hi && hi < 20.0, "{lammps}");
    assert!(line("mercury").contains("NOT EXACT") && line("mercury").contains("std::stof"));
    // The summary lists the files written.
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("square.lammps.mol"), "{summary}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--export foo`: a usage error (exit 2) naming the flag and the formats, nothing written.
#[test]
fn an_unknown_export_format_is_a_usage_error() {
    let dir = tmp("export-bad");
    let (input, out) = (dir.join("in"), dir.join("o"));
    std::fs::create_dir_all(&input).unwrap();
    std::fs::write(input.join("g.csv"), SQUARE).unwrap();
    for bad in ["foo", "lammps,foo"] {
        let o = Command::new(env!("CARGO_BIN_EXE_dem"))
            .args([
                "clump",
                input.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ])
            .args(["--export", bad])
            .output()
            .unwrap();
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {t}");
        assert_eq!(t.matches("--export").count(), 1, "{bad}: {t}");
        assert!(
            t.contains("foo") && t.contains("pfc, yade, lammps, mercury"),
            "{t}"
        );
        assert!(!t.contains("panicked"), "{t}");
        assert!(!out.exists(), "{bad}: something was written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A 12-pointed star (outer radius 10 mm, inner 5 mm), drawn with straight edges.
fn star12() -> String {
    let mut s = String::from("x,y\n");
    for i in 0..24 {
        let r = if i % 2 == 0 { 10.0 } else { 5.0 };
        let t = std::f64::consts::PI * i as f64 / 12.0;
        s.push_str(&format!("{},{}\n", r * t.cos(), r * t.sin()));
    }
    s
}

/// A sliver 40 mm long and 0.6 to 1 mm thick.
const SLIVER: &str = "x,y\n0,0\n40,0\n40,1\n0,0.6\n";

/// Grains that stop at --max-discs below the --cover target: each is a warning naming the
/// grain, the cover reached, the target and the flags to change, counted in the summary;
/// `--strict` makes them failures (exit 1, not written, the other grains written). Before:
/// written with exit 0 and no word but the summary's "lowest cover".
#[test]
fn grains_below_the_cover_target_are_warned_and_counted() {
    let dir = tmp("cover");
    let input = dir.join("in");
    std::fs::create_dir_all(&input).unwrap();
    std::fs::write(input.join("star.csv"), star12()).unwrap();
    std::fs::write(input.join("sliver.csv"), SLIVER).unwrap();
    std::fs::write(input.join("square.csv"), SQUARE).unwrap();
    let run = |out: &std::path::Path, extra: &[&str]| {
        let mut args = vec![
            "clump".to_string(),
            input.display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        Command::new(env!("CARGO_BIN_EXE_dem"))
            .args(&args)
            .output()
            .unwrap()
    };
    let out = dir.join("o");
    let o = run(&out, &[]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr),
    );
    assert_eq!(o.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("below cover target 2"), "{stdout}");
    assert!(stdout.contains("templates written 3"), "{stdout}");
    for name in ["star.csv", "sliver.csv"] {
        let tpl = clumpgen::Template::load(&out.join(name).with_extension("json")).unwrap();
        assert!(tpl.cover.value < 0.95, "{name}: {}", tpl.cover.value);
        // One line per grain: its file, its cover, the target and the flags.
        let line = stderr
            .lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("no warning for {name}: {stderr}"));
        let cover = format!("cover {:.4}", tpl.cover.value);
        assert!(line.starts_with("warning: "), "{line}");
        for part in [
            cover.as_str(),
            "the target 0.95",
            "--max-discs 64",
            "--cover",
        ] {
            assert!(line.contains(part), "{name}: {part:?} not in {line:?}");
        }
    }
    assert!(!stderr.contains("square.csv"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    let warned = summary["items"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|i| i["warning"].is_string())
        .count();
    assert_eq!(warned, 2, "{summary}");

    // --strict: the two are failures, not written; the square is.
    let strict = dir.join("strict");
    let o = run(&strict, &["--strict"]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("2 of 3 grains failed") && t.contains("failures          2"),
        "{t}"
    );
    assert!(t.contains("--strict") && t.contains("cover 0."), "{t}");
    assert!(strict.join("square.json").exists());
    assert!(!strict.join("star.json").exists() && !strict.join("sliver.json").exists());
    // A target the discs reach: no warning at all.
    let o = run(&dir.join("more"), &["--cover", "0.75"]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(
        t.contains("below cover target 0") && !t.contains("warning"),
        "{t}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Work without a bound is refused before any grain is read (exit 2, once): the flag, the
/// value, the limit and why. Before: `--raster 100000` aborted allocating 9.4 GB,
/// `--resample 10000000` ran for minutes, `--max-discs` had no limit.
#[test]
fn unbounded_work_is_a_usage_error() {
    let dir = tmp("limits");
    let (input, out) = (dir.join("in"), dir.join("o"));
    std::fs::create_dir_all(&input).unwrap();
    std::fs::write(input.join("g.csv"), SQUARE).unwrap();
    for (flag, value, limit, why) in [
        (
            "--raster",
            "100000",
            "at most 1024",
            "10 bytes per cell, 1.6 TB",
        ),
        (
            "--resample",
            "10000000",
            "at most 1000000",
            "the work per grain grows",
        ),
        (
            "--max-discs",
            "5000",
            "at most 1000",
            "cube of the disc count",
        ),
    ] {
        let t0 = std::time::Instant::now();
        let o = Command::new(env!("CARGO_BIN_EXE_dem"))
            .args([
                "clump",
                input.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ])
            .args([flag, value])
            .output()
            .unwrap();
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{flag} {value}: {t}");
        assert!(t.contains(&format!("{flag} {value}: {limit}")), "{t}");
        assert!(t.contains(why), "{t}");
        assert_eq!(t.matches("error").count(), 1, "{t}");
        assert!(!out.exists(), "{flag}: something written");
        assert!(
            t0.elapsed().as_secs_f64() < 30.0,
            "{flag}: not refused at once"
        );
    }
    // At the limits the batch runs.
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args([
            "clump",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args([
            "--raster",
            "1024",
            "--max-discs",
            "1000",
            "--resample",
            "1000",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An 8-bit greyscale PNG of `rows` (`.` = 0, a digit d = label d).
fn grey_png(path: &std::path::Path, rows: &[&str]) {
    let (w, h) = (rows[0].len() as u32, rows.len() as u32);
    let data: Vec<u8> = rows
        .iter()
        .flat_map(|r| r.bytes().map(|b| if b == b'.' { 0 } else { b - b'0' }))
        .collect();
    let f = std::fs::File::create(path).unwrap();
    let mut e = png::Encoder::new(std::io::BufWriter::new(f), w, h);
    e.set_color(png::ColorType::Grayscale);
    e.set_depth(png::BitDepth::Eight);
    e.write_header().unwrap().write_image_data(&data).unwrap();
}

/// A labelled mask: one template per label in `<out>/<stem>/`, grains named in summary.json,
/// the border and hole warnings on stderr naming file and grain; a corrupt PNG fails alone.
#[test]
fn a_labelled_mask_gives_one_template_per_label() {
    let dir = tmp("mask");
    let (input, out) = (dir.join("in"), dir.join("out"));
    std::fs::create_dir_all(&input).unwrap();
    let mut rows = vec!["..........................".to_string(); 14];
    for (r, row) in rows.iter_mut().enumerate() {
        for c in 0..26 {
            let l = if (2..12).contains(&r) && (2..10).contains(&c) && !(r == 6 && c == 5) {
                '1'
            } else if (4..14).contains(&r) && (14..24).contains(&c) {
                '2'
            } else if (8..12).contains(&r) && (24..26).contains(&c) {
                '3'
            } else {
                continue;
            };
            row.replace_range(c..c + 1, &l.to_string());
        }
    }
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    grey_png(&input.join("grains.png"), &rows);
    std::fs::write(input.join("broken.png"), b"\x89PNG\r\n\x1a\n...").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args([
            "clump",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .args(["--units", "px", "--px-scale", "1e-4"])
        .output()
        .unwrap();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    let g = input.join("grains.png").display().to_string();
    assert!(
        t.contains(&format!("warning: {g}, label 2 touches the image border")),
        "{t}"
    );
    assert!(
        t.contains(&format!("warning: {g}, label 1 has 1 hole (1 px")),
        "{t}"
    );
    assert!(
        t.contains(&format!(
            "note: {g}: skipped 1 of 3 labels below --min-pixels 20"
        )),
        "{t}"
    );
    let b = input.join("broken.png").display().to_string();
    assert!(t.contains(&format!("{b}: cannot read the image")), "{t}");
    assert!(t.contains("1 of 3 grains failed"), "{t}");
    let l1 = clumpgen::Template::load(&out.join("grains/label-1.json")).unwrap();
    assert_eq!(l1.source.grain.as_deref(), Some("label 1"));
    // 10 x 8 pixels of 0.1 mm, the one-pixel hole filled: 80 px².
    assert!((l1.shape.area - 80e-8).abs() < 1e-18, "{}", l1.shape.area);
    assert!(out.join("grains/label-2.json").exists() && !out.join("grains/label-3.json").exists());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains(r#""grain": "label 2""#), "{summary}");
    // `dem render` finds the grain's outline in the image.
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .arg("render")
        .arg(out.join("grains/label-1.json"))
        .args(["--width", "200"])
        .output()
        .unwrap();
    let t = text(&o);
    assert!(
        o.status.success() && !t.contains("without the outline"),
        "{t}"
    );
    // Without the pixel size: one usage error naming the flag, nothing written.
    let out2 = dir.join("out2");
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args([
            "clump",
            input.to_str().unwrap(),
            "--out",
            out2.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("is an image") && t.contains("--px-scale M_PER_PX"),
        "{t}"
    );
    assert!(!out2.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// GeoJSON needs --units; with it, one template per feature.
#[test]
fn geojson_needs_units() {
    let dir = tmp("geojson");
    let f = dir.join("g.geojson");
    std::fs::write(
        &f,
        r#"{"type":"Feature","id":7,"properties":{},"geometry":{"type":"Polygon","coordinates":[[[0,0],[10,0],[10,10],[0,10],[0,0]]]}}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_dem"))
            .args(["clump", f.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap()
    };
    let o = run(&[]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(t.contains("g.geojson") && t.contains("--units"), "{t}");
    let o = run(&["--units", "mm"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let t = clumpgen::Template::load(&out.join("g/7.json")).unwrap();
    assert!((t.shape.area - 1e-4).abs() < 1e-16);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 48 D3: a link to `/dev/zero` named like an outline, and `/dev/zero` itself, end at once
/// with the file and its kind (before: no output while memory grew to 12 GB in 11 s; a hang);
/// a file over `--max-input-mib` is refused with the limit and the flag; a folder named like an
/// outline file is named as a folder.
#[cfg(target_os = "linux")]
#[test]
fn devices_oversized_files_and_folders_named_like_files_are_refused_by_name() {
    let dir = tmp("bounded");
    let link = dir.join("zero.csv");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let out = dir.join("o");
    for input in [link.as_path(), std::path::Path::new("/dev/zero")] {
        let t0 = std::time::Instant::now();
        let o = dem(&[std::path::Path::new("clump"), input, "--out".as_ref(), &out]);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(1), "{t}");
        assert!(
            t.contains(&format!(
                "{}: cannot read: is a character device",
                input.display()
            )),
            "{t}"
        );
        assert!(t0.elapsed().as_secs_f64() < 30.0, "not refused at once");
    }
    let big = dir.join("big.csv");
    let mut rows = String::from("x,y\n");
    while rows.len() < 2 << 20 {
        rows.push_str("0.000000,0.000000\n");
    }
    std::fs::write(&big, rows).unwrap();
    let o = dem(&[
        "--max-input-mib".as_ref(),
        "1".as_ref(),
        std::path::Path::new("clump"),
        &big,
        "--out".as_ref(),
        &out,
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("big.csv: cannot read: larger than the input limit of 1 MiB")
            && t.contains("--max-input-mib"),
        "{t}"
    );
    let folder = dir.join("x.csv");
    std::fs::create_dir_all(&folder).unwrap();
    let o = dem(&[
        std::path::Path::new("clump"),
        &folder,
        "--out".as_ref(),
        &out,
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains(&format!("in the folder {}", folder.display())),
        "{t}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 48 D11: a template that cannot be saved (here its name is taken by a folder) is
/// reported as a write failure naming the file (before: "cannot read").
#[test]
fn a_failed_save_is_reported_as_a_write() {
    let dir = tmp("write-fail");
    std::fs::write(dir.join("g.csv"), SQUARE).unwrap();
    let out = dir.join("o");
    std::fs::create_dir_all(out.join("g.json")).unwrap();
    let o = dem(&[
        std::path::Path::new("clump"),
        &dir.join("g.csv"),
        "--out".as_ref(),
        &out,
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(t.contains("g.json: cannot write"), "{t}");
    assert!(!t.contains("cannot read"), "{t}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 48 D12: a pixel size of 1e200 m is refused by the grain's size in metres, with the
/// flag to check (before: "invalid parameter: ... r_min = 0e0 m", a flag not given).
#[test]
fn an_absurd_pixel_size_names_the_size_and_the_flag() {
    let dir = tmp("px-scale");
    let png = dir.join("g.png");
    let rows = [
        ".........",
        ".1111111.",
        ".1111111.",
        ".1111111.",
        ".1111111.",
        ".........",
    ];
    grey_png(&png, &rows);
    let o = dem(&[
        std::path::Path::new("clump"),
        &png,
        "--units".as_ref(),
        "px".as_ref(),
        "--px-scale".as_ref(),
        "1e200".as_ref(),
        "--out".as_ref(),
        &dir.join("o"),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("7 x 4 px = 7e200 m") && t.contains("--px-scale"),
        "{t}"
    );
    assert!(!t.contains("r_min"), "{t}");
    std::fs::remove_dir_all(&dir).unwrap();
}
