//! `dem test cutting` end to end: a small specimen generated from the specimen flags, a short
//! fast cut, the printed summary and the files; the scene it writes re-runs with `dem run`;
//! bad arguments are messages with exit code 2.

use std::path::PathBuf;

mod common;
use common::{dem, material, text, tmp};

/// The tool pushed on the specimen (a positive main force at a travel inside the cut) and
/// broke bonds; the window's figures are finite and its touching share a fraction. Not the
/// window mean's sign: with the default damping (fragment frame) a chip broken off flies clear
/// and a window of these small cuts (0.2 mm of travel) can fall between two strikes.
fn assert_tool_met_the_specimen(r: &serde_json::Value) {
    let first = r["contact_travel"].as_f64();
    let length = r["test"]["length"].as_f64().unwrap();
    assert!(
        first.is_some_and(|x| x > 0.0 && x < length),
        "{}",
        r["contact_travel"]
    );
    assert!(r["broken_total"].as_u64().unwrap() > 0);
    for k in ["peak", "mean", "sd"] {
        assert!(
            r["main_force"][k].as_f64().unwrap().is_finite(),
            "{}",
            r["main_force"]
        );
    }
    let t = r["touching"].as_f64().unwrap();
    assert!((0.0..=1.0).contains(&t), "{t}");
}

#[test]
fn cutting_generates_cuts_and_reports() {
    let dir = tmp("ok");
    let out = dir.join("cut");
    let o = dem(&[
        "test",
        "cutting",
        "--width",
        "3mm",
        "--height",
        "1.5mm",
        "--r-min",
        "0.1mm",
        "--r-max",
        "0.16mm",
        "--material",
        &material(),
        "--seed",
        "2",
        "--depth",
        "0.4mm",
        "--speed",
        "10m/s",
        "--length",
        "1mm",
        "--history-rows",
        "200",
        "--threads",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    for k in [
        "main force (kN)",
        "vertical force (kN)",
        "chips",
        "broken grain_boundary",
        "surface",
        "residual cracks",
        "cutting.result.json",
    ] {
        assert!(t.contains(k), "missing {k:?} in\n{t}");
    }
    for f in [
        "specimen.json",
        "specimen.summary.json",
        "specimen.scene.json",
        "cutting.scene.json",
        "history.csv",
        "cutting.forces.csv",
        "cutting.result.json",
        "cutting.inputs.json",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    // The inputs: the generated specimen's parameters, its own model (no --model), the test.
    let i: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cutting.inputs.json")).unwrap())
            .unwrap();
    assert_eq!(i["specimen"]["seed"], 2);
    assert_eq!(i["specimen"]["r_min"].as_f64().unwrap(), 0.1e-3);
    assert!(i["model"]["micro"]["contact_modulus"].as_f64().unwrap() > 0.0);
    assert_eq!(i["test"]["depth"].as_f64().unwrap(), 0.4e-3);
    assert!(i["specimen_file"].is_null());
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cutting.result.json")).unwrap())
            .unwrap();
    assert_tool_met_the_specimen(&r);
    assert_eq!(r["test"]["depth"].as_f64().unwrap(), 0.4e-3);
    assert_eq!(r["test"]["speed"].as_f64().unwrap(), 10.0);
    // The scene is plain: `dem run` loads and starts it (capped at 200 steps).
    let o = dem(&[
        "run",
        out.join("cutting.scene.json").to_str().unwrap(),
        "--max-steps",
        "200",
        "--out",
        dir.join("rerun").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_are_messages() {
    let dir = tmp("bad");
    let out = dir.join("cut");
    let o = dem(&[
        "test",
        "cutting",
        "--out",
        out.to_str().unwrap(),
        "--depth",
        "1mm",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("--specimen"), "{}", text(&o));
    let o = dem(&[
        "test",
        "cutting",
        "--specimen",
        dir.join("missing.json").to_str().unwrap(),
        "--speed",
        "fast",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("--speed"), "{}", text(&o));
    let o = dem(&[
        "test",
        "cutting",
        "--specimen",
        dir.join("missing.json").to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("missing.json"), "{}", text(&o));
    // --specimen-from-model: needs --model, refuses a material and a given specimen.
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/models/si3n4.model.json"
    );
    let gen = ["test", "cutting", "--r-min", "0.1mm", "--r-max", "0.16mm"];
    for (extra, want) in [
        (
            vec!["--specimen-from-model"],
            "--specimen-from-model needs --model",
        ),
        (
            vec![
                "--specimen-from-model",
                "--model",
                model,
                "--material",
                &material(),
            ],
            "--material",
        ),
        (
            vec![
                "--specimen-from-model",
                "--model",
                model,
                "--specimen",
                "s.json",
            ],
            "leave out --specimen",
        ),
        (
            vec!["--irregular", "some", "--material", &material()],
            "--irregular",
        ),
    ] {
        let mut args: Vec<&str> = gen.to_vec();
        args.extend(extra.iter().copied());
        let o_dir = out.to_str().unwrap();
        args.extend(["--out", o_dir]);
        let o = dem(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(text(&o).contains(want), "{args:?}: {}", text(&o));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--dry-run` resolves and writes the inputs, runs nothing; `--specimen-from-model` takes
/// the model's micro-parameters and sets its r_mean to the specimen's radii; `--irregular few`
/// is kept for ORC and dropped for traditional; `--window-start` sets the window.
#[test]
fn dry_run_writes_the_inputs_and_runs_nothing() {
    let dir = tmp("dry");
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/models/si3n4.model.json"
    );
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(model).unwrap()).unwrap();
    for method in ["orc", "traditional"] {
        let out = dir.join(method);
        let o = dem(&[
            "test",
            "cutting",
            "--method",
            method,
            "--r-min",
            "0.175mm",
            "--r-max",
            "0.285mm",
            "--grain-size",
            "0.86mm",
            "--irregular",
            "few",
            "--model",
            model,
            "--specimen-from-model",
            "--window-start",
            "1.5",
            "--dry-run",
            "--out",
            out.to_str().unwrap(),
        ]);
        let t = text(&o);
        assert!(o.status.success(), "{t}");
        let file = std::fs::read_to_string(out.join("cutting.inputs.json")).unwrap();
        assert!(t.contains(file.trim()), "printed: {t}");
        assert!(!out.join("specimen.json").exists() && !out.join("cutting.scene.json").exists());
        let i: serde_json::Value = serde_json::from_str(&file).unwrap();
        assert_eq!(i["specimen"]["micro"], m["micro"]);
        assert_eq!(i["specimen"]["density"], m["density"]);
        assert_eq!(
            i["specimen"]["iso_stress"].as_f64().unwrap(),
            0.01 * m["micro"]["boundary_tensile"].as_f64().unwrap()
        );
        assert_eq!(
            i["model"]["r_mean"].as_f64().unwrap(),
            0.5 * (0.175e-3 + 0.285e-3)
        );
        assert_eq!(i["test"]["window_start"].as_f64().unwrap(), 1.5);
        // Few irregular grains for ORC; a traditional specimen has none.
        assert_eq!(
            i["specimen"]["grains"].get("few").is_some(),
            method == "orc",
            "{file}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--delete-fragments`: the test records it, the summary and the result say what went.
#[test]
fn cutting_with_deleted_fragments_reports_them() {
    let dir = tmp("delete");
    let out = dir.join("cut");
    let o = small_cut(
        &out,
        &[
            "--seed",
            "2",
            "--speed",
            "10m/s",
            "--history-rows",
            "200",
            "--delete-fragments",
        ],
    );
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(t.contains("deleted fragments"), "{t}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cutting.result.json")).unwrap())
            .unwrap();
    assert_eq!(r["test"]["delete_fragments"], serde_json::json!(true));
    let d = &r["deleted"];
    for k in ["fragments", "discs", "bonds", "check_every"] {
        assert!(d[k].is_u64(), "deleted.{k}: {d}");
    }
    assert!(d["mass"].as_f64().unwrap() >= 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--mass-scaling`: an improved-ORC cut records the budget in its test, the summary prints
/// what was added and the result's `run.mass_scaling` holds it, within the budget.
#[test]
fn cutting_with_mass_scaling_reports_it() {
    let dir = tmp("mass-scaling");
    let out = dir.join("cut");
    let o = small_cut(
        &out,
        &[
            "--method",
            "improved",
            "--irregular",
            "few",
            "--grain-size",
            "0.5mm",
            "--seed",
            "2",
            "--speed",
            "10m/s",
            "--history-rows",
            "100",
            "--mass-scaling",
            "0.02",
        ],
    );
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(t.contains("mass scaling       budget 0.02"), "{t}");
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("cutting.result.json")).unwrap())
            .unwrap();
    assert_eq!(r["test"]["mass_scaling"], serde_json::json!(0.02));
    let m = &r["run"]["mass_scaling"];
    let f = |k: &str| m[k].as_f64().unwrap_or_else(|| panic!("{k}: {m}"));
    assert!(
        f("added_mass_fraction") <= 0.02 + 1e-12 && f("added_inertia_fraction") <= 0.02 + 1e-12
    );
    assert!(f("critical_dt_after") > f("critical_dt_before"), "{m}");
    assert!(m["discs_mass"].as_u64().unwrap() + m["discs_inertia"].as_u64().unwrap() > 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--specimen-cache`: the first cut generates the specimen and keeps it, the second (another
/// speed) takes it from the cache; the files are the same (the summary's generation wall time
/// aside) and the cut's result equals that of a run without the cache.
#[test]
fn specimen_cache_gives_the_generated_specimen() {
    let dir = tmp("specimen-cache");
    let cache = dir.join("cache");
    let cut = |name: &str, speed: &str, cached: bool| {
        let out = dir.join(name);
        let c = cache.display().to_string();
        let mut args = vec![
            "--method",
            "orc",
            "--irregular",
            "few",
            "--grain-size",
            "0.5mm",
            "--seed",
            "3",
            "--history-rows",
            "50",
            "--speed",
            speed,
        ];
        if cached {
            args.extend(["--specimen-cache", c.as_str()]);
        }
        let o = small_cut(&out, &args);
        let t = text(&o);
        assert!(o.status.success(), "{t}");
        (out, t)
    };
    let (first, t1) = cut("first", "10m/s", true);
    assert!(!t1.contains("from the cache"), "{t1}");
    assert_eq!(std::fs::read_dir(&cache).unwrap().count(), 1, "one entry");
    let (second, t2) = cut("second", "20m/s", true);
    assert!(t2.contains("from the cache"), "{t2}");
    let (plain, _) = cut("plain", "20m/s", false);
    for f in [
        "specimen.json",
        "specimen.summary.json",
        "specimen.scene.json",
    ] {
        let read = |d: &std::path::Path| {
            let mut v: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(d.join(f)).unwrap()).unwrap();
            // (A generation's own wall time differs from run to run.)
            if let Some(o) = v.as_object_mut() {
                o.remove("wall_time_s");
            }
            v.to_string()
        };
        assert!(read(&first) == read(&second), "{f}: cached copy differs");
        assert!(
            read(&plain) == read(&second),
            "{f}: differs from a generation"
        );
    }
    let result = |d: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("cutting.result.json")).unwrap())
            .unwrap()
    };
    let (a, b) = (result(&second), result(&plain));
    assert_eq!(a["main_force"], b["main_force"]);
    assert_eq!(a["broken_total"], b["broken_total"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--flat-joint 2` (Potyondy 2012) on the smallest cut of these tests: the scene's bond groups
/// are flat joints of those elements, the tool meets the specimen and breaks
/// interfaces (cement all gone), and reports the element figures; the inputs record the
/// option and the model it ran with carries it.
#[test]
fn cutting_with_flat_joints_runs_and_counts_broken_interfaces() {
    let dir = tmp("flat-joint");
    let out = dir.join("cut");
    let o = small_cut(
        &out,
        &[
            "--seed",
            "2",
            "--speed",
            "10m/s",
            "--history-rows",
            "200",
            "--flat-joint",
            "2",
            "--joint-friction",
            "0.5",
        ],
    );
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(
        t.contains("flat joints (Potyondy 2012) of 2 elements"),
        "{t}"
    );
    assert!(t.contains("flat-joint interfaces"), "{t}");
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(out.join(f)).unwrap()).unwrap()
    };
    let scene = read("cutting.scene.json");
    let groups = scene["bond_groups"].as_array().unwrap();
    assert_eq!(groups.len(), 2);
    for g in groups {
        assert_eq!(g["model"], "flat_joint_potyondy2012", "{g}");
        assert_eq!(g["elements"], 2, "{g}");
        assert_eq!(g["friction"], 0.5, "{g}");
    }
    let i = read("cutting.inputs.json");
    assert_eq!(i["flat_joint"]["elements"], 2);
    assert_eq!(i["model"]["flat_joint"]["elements"], 2);
    assert_eq!(i["model"]["flat_joint"]["friction"], 0.5);
    let r = read("cutting.result.json");
    assert_tool_met_the_specimen(&r);
    let broken = r["broken_total"].as_u64().unwrap();
    assert!(broken >= 1, "{}", r["broken_bonds"]);
    let mut sum = 0;
    for b in r["broken_bonds"].as_array().unwrap() {
        let n = |k: &str| b[k].as_u64().unwrap_or_else(|| panic!("{k}: {b}"));
        sum += n("tension") + n("shear");
        // Each broken interface lost every one of its bonded elements (1 or 2).
        assert!(n("elements_broken") >= n("tension") + n("shear"), "{b}");
        assert!(n("elements_broken") <= n("elements_bonded"), "{b}");
        assert!(n("tension") + n("shear") <= n("total"), "{b}");
        assert_eq!(n("slit"), 0, "{b}");
    }
    assert_eq!(sum, broken);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `dem test cutting` generating a 3 × 1.5 mm Si3N4 specimen (radii 0.1–0.16 mm) and cutting
/// 1 mm of it 0.4 mm deep, with the flags `extra` (seed, speed, history rows, ...), into `out`.
fn small_cut(out: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let (m, o) = (material(), out.display().to_string());
    let mut args = vec![
        "test",
        "cutting",
        "--width",
        "3mm",
        "--height",
        "1.5mm",
        "--r-min",
        "0.1mm",
        "--r-max",
        "0.16mm",
        "--depth",
        "0.4mm",
        "--length",
        "1mm",
        "--material",
        &m,
        "--out",
        &o,
    ];
    args.extend_from_slice(extra);
    dem(&args)
}

/// A 3 × 1.5 mm specimen file of 18 discs (no summary beside it: the geometry is checked
/// before the model is read).
fn small_specimen(dir: &std::path::Path) -> PathBuf {
    let mut discs = Vec::new();
    for i in 0..6 {
        for j in 0..3 {
            discs.push([0.25 + 0.5 * i as f64, 0.25 + 0.5 * j as f64, 0.25]);
        }
    }
    let spec = serde_json::json!({
        "schema": "dem.specimen/1",
        "units": "mm",
        "discs": [{"material": "si3n4", "discs": discs}]
    });
    let p = dir.join("small.json");
    std::fs::write(&p, spec.to_string()).unwrap();
    p
}

/// A cut longer than the specimen, or deeper than it allows, is an error naming the flag, the
/// value and the specimen's extent (exit 2), before any run (before: a run of a 100 mm cut on
/// a 5 mm specimen with a meaningless "steady window").
#[test]
fn cut_geometry_outside_the_specimen_is_refused() {
    let dir = tmp("geometry");
    let out = dir.join("cut");
    let spec = small_specimen(&dir);
    let (s, o) = (spec.to_str().unwrap(), out.to_str().unwrap());
    let r = dem(&[
        "test",
        "cutting",
        "--specimen",
        s,
        "--length",
        "100mm",
        "--out",
        o,
    ]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(
        t.contains("--length 100mm") && t.contains("3 mm wide") && t.contains("small.json"),
        "{t}"
    );
    let r = dem(&[
        "test",
        "cutting",
        "--specimen",
        s,
        "--depth",
        "1.2mm",
        "--length",
        "2.5mm",
        "--out",
        o,
    ]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(
        t.contains("--depth 1.2mm") && t.contains("1.5 mm high"),
        "{t}"
    );
    // The default length (10 mm) is named as the default.
    let r = dem(&["test", "cutting", "--specimen", s, "--out", o]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(t.contains("--length") && t.contains("default"), "{t}");
    // A specimen to be generated is checked against --width/--height before generating it.
    let r = dem(&[
        "test",
        "cutting",
        "--width",
        "3mm",
        "--height",
        "1.5mm",
        "--r-min",
        "0.1mm",
        "--r-max",
        "0.16mm",
        "--material",
        &material(),
        "--length",
        "5mm",
        "--out",
        o,
    ]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(t.contains("--length 5mm") && t.contains("--width"), "{t}");
    assert!(!out.join("specimen.json").exists());
    // Issue 48 D8: a specimen too coarse for its height is refused as `dem specimen` refuses it,
    // before generating (before: the generator failed in `grow`).
    let r = dem(&[
        "test",
        "cutting",
        "--width",
        "4mm",
        "--height",
        "2mm",
        "--r-min",
        "0.3mm",
        "--r-max",
        "0.5mm",
        "--material",
        &material(),
        "--depth",
        "0.5mm",
        "--length",
        "2mm",
        "--out",
        o,
    ]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(
        t.contains("--height 2mm: 2 mm is 2.5 mean disc diameters") && t.contains("at least 5"),
        "{t}"
    );
    assert!(!t.contains("grow"), "{t}");
    assert!(!out.join("specimen.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The lab tests lock the folder their run writes (issue 20): `dem test cutting` its `--out`
/// (keyed on its inputs: a rerun, or the run after a `--dry-run`, of the same cut is allowed,
/// other inputs are allowed with a note), a quasi-static test `<out>/<test>.out`; a folder
/// locked by a live process or by another scene's run is refused before anything is written,
/// unless `--force`.
#[test]
fn lab_tests_lock_their_run_folder() {
    let dir = tmp("lock");
    let out = dir.join("cut");
    let model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../data/models/si3n4.model.json"
    );
    let cut = |speed: &str, extra: &[&str]| {
        let mut args = vec![
            "test",
            "cutting",
            "--method",
            "traditional",
            "--r-min",
            "0.175mm",
            "--r-max",
            "0.285mm",
            "--model",
            model,
            "--specimen-from-model",
            "--speed",
            speed,
            "--dry-run",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        dem(&args)
    };
    let lock_file = out.join("run.lock");
    let read_lock = || -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(&lock_file).unwrap()).unwrap()
    };
    let o = cut("1", &[]);
    assert!(o.status.success(), "{}", text(&o));
    let lock = read_lock();
    assert_eq!(lock["command"], "dem test cutting", "{lock}");
    assert!(lock["pid"].is_null(), "released: {lock}");
    assert!(lock["scene"]
        .as_str()
        .unwrap()
        .ends_with("cutting.scene.json"));
    // The same cut again: no note. Other inputs: allowed, with a note, and the hash changes.
    let o = cut("1", &[]);
    assert!(
        o.status.success() && !text(&o).contains("note:"),
        "{}",
        text(&o)
    );
    let o = cut("2", &[]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("changed since its run"), "{}", text(&o));
    assert_ne!(read_lock()["scene_hash"], lock["scene_hash"]);
    // A live process holds the folder (this test's pid on this host): refused, nothing written.
    let mut held = read_lock();
    held["pid"] = serde_json::json!(std::process::id());
    std::fs::write(&lock_file, held.to_string()).unwrap();
    std::fs::remove_file(out.join("cutting.inputs.json")).unwrap();
    let o = cut("2", &[]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("being run into this folder now") && t.contains("`dem test cutting`"),
        "{t}"
    );
    assert!(!out.join("cutting.inputs.json").exists(), "nothing written");
    // The folder of another scene (a `dem run`, the lock's older form without `command`).
    let other = serde_json::json!({"schema": "dem.run-lock/1", "scene": "/elsewhere/other.json",
        "scene_hash": "ab".repeat(32), "pid": null, "host": "h", "started_unix_s": 1});
    std::fs::write(&lock_file, other.to_string()).unwrap();
    let o = cut("2", &[]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let t = text(&o);
    assert!(
        t.contains("another scene, /elsewhere/other.json by `dem run`") && t.contains("--force"),
        "{t}"
    );
    let o = cut("2", &["--force"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("note: --force"), "{}", text(&o));
    assert_eq!(read_lock()["command"], "dem test cutting");
    // A quasi-static test locks `<out>/ucs.out`: held by a live process, it is refused before
    // its specimen is generated.
    let lab = dir.join("lab");
    std::fs::create_dir_all(lab.join("ucs.out")).unwrap();
    held["scene"] = serde_json::json!(lab.join("ucs.json").display().to_string());
    held["command"] = serde_json::json!("dem test ucs");
    std::fs::write(lab.join("ucs.out/run.lock"), held.to_string()).unwrap();
    let o = dem(&[
        "test",
        "ucs",
        "--r-min",
        "0.1mm",
        "--r-max",
        "0.16mm",
        "--material",
        &material(),
        "--out",
        lab.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("`dem test ucs`"), "{}", text(&o));
    assert!(!lab.join("ucs.specimen.json").exists(), "nothing generated");
    std::fs::remove_dir_all(&dir).ok();
}

/// Improved-ORC grains whose templates stop below their cover target: warnings naming the
/// specimen file and the grain, and with --strict a failure before the specimen is written
/// (issue 20's cover rule, as in `dem specimen` and the other lab tests).
#[test]
fn grains_below_cover_warn_and_strict_refuses_the_cut() {
    let dir = tmp("cover");
    let out = dir.join("cut");
    let m = material();
    let args = |strict: bool| {
        let mut v = vec![
            "test",
            "cutting",
            "--method",
            "improved",
            "--width",
            "4mm",
            "--height",
            "2mm",
            "--r-min",
            "0.1mm",
            "--r-max",
            "0.16mm",
            "--grain-size",
            "0.5mm",
            "--template-r-min",
            "0.1mm",
            "--material",
            &m,
            "--length",
            "1mm",
            "--depth",
            "0.3mm",
            "--speed",
            "10",
            "--threads",
            "1",
            "--out",
            out.to_str().unwrap(),
        ];
        if strict {
            v.push("--strict");
        }
        v.iter().map(|s| s.to_string()).collect::<Vec<String>>()
    };
    let o = dem(&args(true));
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("--strict: ")
            && t.contains("grains of the specimen are below their cover target")
            && t.contains("specimen.json: grain ")
            && t.contains("--template-r-min"),
        "{t}"
    );
    assert!(!out.join("specimen.json").exists() && !out.join("cutting.result.json").exists());
    let o = dem(&args(false));
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(
        t.contains("warning: ")
            && t.contains("specimen.json: grain ")
            && t.contains("grains below their cover target (warnings above"),
        "{t}"
    );
    assert!(out.join("cutting.result.json").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// Issue 48: `--snapshots 3` wrote 4 (an interval of the planned steps: the start and three
/// more); a step-interval fix wrote 2 here, where the step grows during the cut. Now N
/// snapshots spread over the duration are N, the last at the end of the cut.
#[test]
fn snapshots_n_writes_n() {
    let dir = tmp("snapshots");
    for n in [1usize, 3, 7] {
        let out = dir.join(format!("cut{n}"));
        let o = small_cut(
            &out,
            &[
                "--speed",
                "10m/s",
                "--history-rows",
                "200",
                "--snapshots",
                &n.to_string(),
            ],
        );
        assert!(o.status.success(), "{}", text(&o));
        let pvd = std::fs::read_to_string(out.join("snapshots.pvd")).unwrap();
        let mut steps: Vec<&str> = pvd
            .split("file=\"snap-")
            .skip(1)
            .filter_map(|t| t.split('.').next())
            .collect();
        steps.dedup();
        assert_eq!(steps.len(), n, "{pvd}");
        assert_eq!(steps[0], "000000000");
        if n > 1 {
            let r: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(out.join("cutting.result.json")).unwrap(),
            )
            .unwrap();
            let last: u64 = steps[n - 1].parse().unwrap();
            assert_eq!(
                Some(last),
                r["run"]["steps"].as_u64(),
                "the last at the end"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
