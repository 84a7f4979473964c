//! `dem run` end to end: a tiny scene writes history, snapshots and summary; bad scenes and
//! bad restarts are messages naming the file and field, with exit code 2 and no panic.

use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{dem, text, tmp};

/// Issue 20 (bounded work): a run whose snapshots and checkpoints would fill more than 10 GB
/// (here 10⁸ steps of two discs with a snapshot every step: ~70 GB) is refused before anything
/// is written, naming the estimate and the scene fields; `--max-steps` caps it.
#[test]
fn a_run_that_would_fill_the_disk_is_refused_unless_asked() {
    let dir = tmp("disk");
    let scene = tiny_scene(&dir);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    v["run"] = serde_json::json!({"steps": 100_000_000u64});
    v["outputs"]["vtk_every"] = 1.into();
    let p = dir.join("chatty.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let out = dir.join("chatty.out");
    let o = dem(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("chatty.json") && t.contains("69.8 GB") && t.contains("outputs.vtk_every"),
        "{t}"
    );
    assert!(t.contains("--yes") && !t.contains("MAX_"), "{t}");
    assert!(!out.exists(), "a refused run writes nothing");
    // Snapshots spread over the run are named as such (not "a snapshot every 0 steps").
    let mut w = v.clone();
    w["outputs"]["vtk_every"] = 0.into();
    w["outputs"]["vtk_count"] = 100_000_000u64.into();
    let q = dir.join("spread.json");
    std::fs::write(&q, w.to_string()).unwrap();
    let o = dem(&["run", q.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("100000000 snapshots over the run (outputs.vtk_count)")
            && !t.contains("every 0"),
        "{t}"
    );
    assert!(!out.exists(), "a refused run writes nothing");
    let o = dem(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--max-steps",
        "10",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Two discs meeting head-on between two walls, with every output on.
fn tiny_scene(dir: &Path) -> PathBuf {
    let scene = serde_json::json!({
        "schema": "dem.scene/1",
        "name": "tiny",
        "units": "mm",
        "materials": [{"name": "glass", "density": 2500, "kn": 1e5, "ks": 5e4, "friction": 0.3, "restitution": 0.7}],
        "bodies": {"discs": [
            {"material": "glass", "velocity": [500, 0], "discs": [[-2, 0, 1]]},
            {"material": "glass", "velocity": [-500, 0], "discs": [[2, 0, 1]]}
        ]},
        "walls": [{"name": "floor", "a": [-10, -1.5], "b": [10, -1.5], "material": "glass"}],
        "run": {"steps": 400},
        "outputs": {"history_every": 20, "vtk_every": 100, "checkpoint_every": 200}
    });
    let p = dir.join("tiny.json");
    std::fs::write(&p, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    p
}

#[test]
fn run_writes_history_snapshots_and_summary() {
    let dir = tmp("ok");
    let scene = tiny_scene(&dir);
    let out = dir.join("out");
    // Leftovers of an earlier run are cleared; other files are kept.
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("snap-000999999.vtp"), "old").unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let o = dem(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(
        t.contains("active stages: neighbours, contacts, walls, integrate"),
        "{t}"
    );
    assert!(t.contains("completed: 400 steps"), "{t}");
    let hist = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let lines: Vec<&str> = hist.lines().collect();
    assert_eq!(lines.len(), 1 + 400 / 20, "{hist}");
    assert!(lines[0].starts_with("time,step,dt,floor_fx,floor_fy,floor_moment,ek_trans"));
    // The discs collide: kinetic energy drops below its start and comes back to ~e² of it.
    let ek: Vec<f64> = lines[1..]
        .iter()
        .map(|l| l.split(',').nth(6).unwrap().parse().unwrap())
        .collect();
    assert!(ek.iter().all(|v| v.is_finite()));
    let ratio = ek.last().unwrap() / ek[0];
    assert!(
        (ratio - 0.49).abs() < 0.01,
        "rebound energy ratio {ratio}, expected e² = 0.49"
    );
    for k in [0, 100, 200, 300, 400] {
        let p = out.join(format!("snap-{k:09}.vtp"));
        let v = std::fs::read_to_string(&p).unwrap_or_else(|_| panic!("{}", p.display()));
        assert!(v.contains("NumberOfPoints=\"2\"") && v.contains("Name=\"radius\""));
    }
    assert!(!out.join("snap-000999999.vtp").exists() && out.join("notes.txt").exists());
    let pvd = std::fs::read_to_string(out.join("snapshots.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 10, "{pvd}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["status"], "completed");
    assert_eq!(s["steps"], 400);
    assert!(s["particle_steps_per_s"].as_f64().unwrap() > 0.0);
    assert!(out.join("ckpt-000000200.json").exists() && out.join("ckpt-final.json").exists());

    // Restart from the step-200 checkpoint into another folder: the same final state.
    let out2 = dir.join("out2");
    let ck = out.join("ckpt-000000200.json");
    let o = dem(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out2.to_str().unwrap(),
        "--restart",
        ck.to_str().unwrap(),
        "--threads",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(
        text(&o).contains("completed: 200 steps to step 400"),
        "{}",
        text(&o)
    );
    // The same bytes of state; only the run totals (wall and CPU time, invocations) differ.
    let ckpt = |d: &std::path::Path| {
        let mut v: serde_json::Value =
            serde_json::from_slice(&std::fs::read(d.join("ckpt-final.json")).unwrap()).unwrap();
        let run = v["run"].take();
        v["checksum"].take(); // over the run totals too
        (v.to_string(), run)
    };
    let ((a, ra), (b, rb)) = (ckpt(&out), ckpt(&out2));
    assert!(a == b, "final checkpoints differ after the restart");
    assert_eq!(
        (ra["invocations"].clone(), rb["invocations"].clone()),
        (1.into(), 2.into())
    );
    assert_eq!(
        hist,
        std::fs::read_to_string(out2.join("history.csv")).unwrap()
    );

    // One digit of a disc's position changed: the restart is refused, naming the file.
    let raw = std::fs::read_to_string(&ck).unwrap();
    let at = raw
        .find("\"x\":[")
        .expect("disc positions in the checkpoint")
        + 6;
    let digit = raw[at..].find(|c: char| c.is_ascii_digit()).unwrap() + at;
    let mut bytes = raw.into_bytes();
    bytes[digit] = if bytes[digit] == b'9' {
        b'1'
    } else {
        bytes[digit] + 1
    };
    let bad = dir.join("ckpt-edited.json");
    std::fs::write(&bad, &bytes).unwrap();
    let o = dem(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        dir.join("out3").to_str().unwrap(),
        "--restart",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("ckpt-edited.json: the checkpoint is corrupt"),
        "{}",
        text(&o)
    );
    // Issue 48 D6: the same edit with one space after `"checksum":` is refused too (it used to
    // switch the check off), and so is the edit in a copy re-saved by another JSON writer
    // (pretty-printed, keys sorted).
    let edited = String::from_utf8(bytes).unwrap();
    let spaced = edited.replacen("\"checksum\":", "\"checksum\": ", 1);
    let pretty = {
        let v: serde_json::Value = serde_json::from_str(&edited).unwrap();
        serde_json::to_string_pretty(&v).unwrap()
    };
    for (name, t) in [("ckpt-spaced.json", spaced), ("ckpt-resaved.json", pretty)] {
        let bad = dir.join(name);
        std::fs::write(&bad, t).unwrap();
        let o = dem(&[
            "run",
            scene.to_str().unwrap(),
            "--out",
            dir.join("out4").to_str().unwrap(),
            "--restart",
            bad.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", text(&o));
        assert!(
            text(&o).contains(&format!("{name}: the checkpoint is corrupt")),
            "{}",
            text(&o)
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_scenes_are_messages_with_exit_code_2() {
    let dir = tmp("bad");
    let scene = tiny_scene(&dir);
    let good = std::fs::read_to_string(&scene).unwrap();
    // An unknown field (a typo of "friction").
    let p = dir.join("bad-field.json");
    std::fs::write(&p, good.replace("\"friction\"", "\"frikshun\"")).unwrap();
    let o = dem(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        dir.join("o").to_str().unwrap(),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("bad-field.json")
            && t.contains("materials[0].frikshun")
            && t.contains("unknown field"),
        "{t}"
    );
    assert!(!t.contains("panicked"), "{t}");
    // Structured edits for the rest.
    let mut v: serde_json::Value = serde_json::from_str(&good).unwrap();
    v["bodies"]["discs"][1]["discs"][0][2] = (-1.0).into();
    v["walls"][0]["material"] = "steel".into();
    let p = dir.join("bad-radius.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let o = dem(&["run", p.to_str().unwrap()]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("bad-radius.json")
            && t.contains("bodies.discs[1].discs[0][2]")
            && t.contains("radius must be positive"),
        "{t}"
    );
    v["bodies"]["discs"][1]["discs"][0][2] = 1.0.into();
    std::fs::write(&p, v.to_string()).unwrap();
    let t = text(&dem(&["run", p.to_str().unwrap()]));
    assert!(
        t.contains("walls[0].material") && t.contains("no material named \"steel\""),
        "{t}"
    );
    // Missing file, and a restart file that is not a checkpoint.
    let o = dem(&["run", dir.join("nope.json").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("nope.json"));
    let o = dem(&[
        "run",
        scene.to_str().unwrap(),
        "--restart",
        scene.to_str().unwrap(),
        "--out",
        dir.join("o").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("not a checkpoint"), "{}", text(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bench_prints_the_figure_last() {
    for kind in ["dense", "bonded"] {
        let o = dem(&["bench", kind, "--steps", "3", "--threads", "1"]);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(0), "{t}");
        let stdout = String::from_utf8_lossy(&o.stdout);
        let last = stdout.lines().last().unwrap();
        let v: f64 = last
            .strip_prefix("particle-steps/s: ")
            .unwrap_or_else(|| panic!("{last}"))
            .parse()
            .unwrap();
        assert!(v > 0.0 && v.is_finite(), "{last}");
        assert!(stdout.contains("46000 discs"), "{stdout}");
    }
    let o = dem(&["bench", "dense", "--steps", "0"]);
    assert_eq!(o.status.code(), Some(2));
}

/// The run folder's lock: a second scene into the same folder is refused (naming the folder
/// and the other scene) unless `--force`; the same scene again is allowed; a lock left by a
/// process that is gone (same host) is taken over with a note; a live one is refused.
#[test]
fn run_folder_is_locked_to_its_scene() {
    let dir = tmp("lock");
    let scene = tiny_scene(&dir);
    let out = dir.join("out");
    let (s, o) = (scene.to_str().unwrap(), out.to_str().unwrap());
    let first = dem(&["run", s, "--out", o, "--threads", "1"]);
    assert_eq!(first.status.code(), Some(0), "{}", text(&first));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();

    // Another scene (the discs faster) into the same folder: refused, nothing touched.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    v["bodies"]["discs"][0]["velocity"] = serde_json::json!([600, 0]);
    let other = dir.join("other.json");
    std::fs::write(&other, v.to_string()).unwrap();
    let ot = other.to_str().unwrap();
    let r = dem(&["run", ot, "--out", o, "--threads", "1"]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(
        t.contains(o) && t.contains("tiny.json") && t.contains("--force"),
        "{t}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("summary.json")).unwrap(),
        summary
    );

    let read_lock = || -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(out.join("run.lock")).unwrap()).unwrap()
    };
    let lock = read_lock();
    assert!(lock["scene_hash"].as_str().unwrap().len() == 64, "{lock}");
    assert!(
        lock["host"].as_str().is_some_and(|h| !h.is_empty()),
        "{lock}"
    );
    assert!(lock["pid"].is_null(), "released after the run: {lock}");
    assert!(
        lock["scene"].as_str().unwrap().ends_with("tiny.json"),
        "{lock}"
    );

    // The same scene again, and a restart of it into the folder: allowed.
    let r = dem(&["run", s, "--out", o, "--threads", "1"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r));
    let ck = out.join("ckpt-000000200.json");
    let r = dem(&["run", s, "--out", o, "--restart", ck.to_str().unwrap()]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r));

    // A lock held by a live process (this test's) on this host: refused even for the scene.
    let mut held = read_lock();
    held["pid"] = std::process::id().into();
    std::fs::write(out.join("run.lock"), held.to_string()).unwrap();
    let r = dem(&["run", s, "--out", o, "--threads", "1"]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(2), "{t}");
    assert!(
        t.contains(&std::process::id().to_string()) && t.contains(o),
        "{t}"
    );

    // A lock of a process that has ended (kill -9 of a run): taken over with a note.
    let mut child = Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    held["pid"] = dead.into();
    std::fs::write(out.join("run.lock"), held.to_string()).unwrap();
    let r = dem(&["run", s, "--out", o, "--threads", "1"]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(0), "{t}");
    assert!(t.contains("stale") && t.contains(&dead.to_string()), "{t}");

    // --force: the other scene replaces this one.
    let r = dem(&["run", ot, "--out", o, "--threads", "1", "--force"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r));
    assert_ne!(read_lock()["scene_hash"], lock["scene_hash"]);
    assert!(read_lock()["scene"]
        .as_str()
        .unwrap()
        .ends_with("other.json"));
    // The same scene file, edited (its physics changed): a fresh run, with a note.
    v["bodies"]["discs"][0]["velocity"] = serde_json::json!([700, 0]);
    std::fs::write(&other, v.to_string()).unwrap();
    let r = dem(&["run", ot, "--out", o, "--threads", "1"]);
    let t = text(&r);
    assert_eq!(r.status.code(), Some(0), "{t}");
    assert!(t.contains("other.json changed since its run"), "{t}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--threads 0` is a usage error (exit 2), not "all cores" in silence.
#[test]
fn threads_zero_is_a_usage_error() {
    let dir = tmp("threads");
    let scene = tiny_scene(&dir);
    let out = dir.join("out");
    let o = dem(&[
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "0",
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(t.contains("--threads") && t.contains("at least 1"), "{t}");
    assert!(!out.join("summary.json").exists());
    let o = dem(&[
        "specimen",
        "--method",
        "traditional",
        "--width",
        "1mm",
        "--height",
        "1mm",
        "--r-min",
        "0.1mm",
        "--r-max",
        "0.16mm",
        "--out",
        dir.join("s.json").to_str().unwrap(),
        "--threads",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--threads"), "{}", text(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 20: a run of 0 steps reports the scene's energies (it reported 0 J), and a run
/// stopped by a runaway load (gravity 1e300 m/s²) still writes its summary, with the figures
/// that overflowed written as null and named, and no NaN on disk.
#[test]
fn zero_steps_and_runaway_loads_write_honest_summaries() {
    let dir = tmp("summaries");
    let scene = tiny_scene(&dir);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    v["run"]["steps"] = 0.into();
    let p = dir.join("zero.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let out = dir.join("zero.out");
    let o = dem(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    // Two glass discs (r = 1 mm, t = 1 m, 2500 kg/m³) at 0.5 m/s: 2 · ½ m v².
    let m = 2500.0 * std::f64::consts::PI * 1e-6;
    let ke = 2.0 * 0.5 * m * 0.25;
    let got = s["energy"]["kinetic_translation"].as_f64().unwrap();
    assert!((got / ke - 1.0).abs() < 1e-12, "{got} vs {ke}");
    assert_eq!(s["energy"]["total"].as_f64(), Some(got));

    v["run"]["steps"] = 400.into();
    v["gravity"] = serde_json::json!([0, -1e300]);
    let p = dir.join("runaway.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let out = dir.join("runaway.out");
    let o = dem(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    let file = std::fs::read_to_string(out.join("summary.json")).expect("a summary");
    assert!(!file.contains("NaN") && !file.contains("inf"), "{file}");
    let s: serde_json::Value = serde_json::from_str(&file).unwrap();
    assert_eq!(s["status"], "stopped", "{file}");
    assert!(s["error"].as_str().unwrap().contains("speed"), "{file}");
    assert!(out.join("last-good-state.json").exists());
    let bad = s["not_finite"].as_array().expect("the energies overflowed");
    assert!(bad.iter().any(|k| k == "energy.total"), "{file}");
    for k in bad {
        let path: Vec<&str> = k.as_str().unwrap().split('.').collect();
        let mut x = &s;
        for p in &path {
            x = &x[*p];
        }
        assert!(x.is_null(), "{k}: {x}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 20: a scene asking for more steps than `dem run` runs unasked (a stiffness of 1e30
/// made dt = 6e-17 s and ~1.6e14 steps, run silently) is refused before anything is written,
/// naming the count and the fields to check; `--max-steps` or `--yes` lets it run.
#[test]
fn a_run_of_too_many_steps_is_refused_unless_asked() {
    let dir = tmp("steps");
    let scene = tiny_scene(&dir);
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    v["materials"][0]["kn"] = 1e30.into();
    v["materials"][0]["ks"] = 5e29.into();
    v["run"] = serde_json::json!({"duration": 1.0});
    let p = dir.join("stiff.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let out = dir.join("stiff.out");
    let o = dem(&["run", p.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("stiff.json") && t.contains("steps") && t.contains("--yes"),
        "{t}"
    );
    assert!(t.contains("run.duration") && t.contains("stiffness"), "{t}");
    assert!(!out.exists(), "a refused run writes nothing");
    // Capped, it runs.
    let o = dem(&[
        "run",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--max-steps",
        "10",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 20: `--checkpoint-format binary` writes `.bin` checkpoints that `--restart` reads
/// (the same final state as a JSON run); `--no-checkpoints` writes none and says the run cannot
/// be resumed.
#[test]
fn binary_checkpoints_and_the_off_switch() {
    let dir = tmp("binary");
    let scene = tiny_scene(&dir);
    let s = scene.to_str().unwrap();
    let (json, bin, bin2, off) = (
        dir.join("json"),
        dir.join("bin"),
        dir.join("bin2"),
        dir.join("off"),
    );
    let o = dem(&["run", s, "--out", json.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = dem(&[
        "run",
        s,
        "--out",
        bin.to_str().unwrap(),
        "--checkpoint-format",
        "binary",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("2 periodic checkpoints"), "{}", text(&o));
    let ck = bin.join("ckpt-000000200.bin");
    assert!(ck.exists() && bin.join("ckpt-final.bin").exists());
    assert!(!bin.join("ckpt-final.json").exists());
    let o = dem(&[
        "run",
        s,
        "--out",
        bin2.to_str().unwrap(),
        "--restart",
        ck.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("completed: 200 steps to step 400"));
    let world = |p: &Path| {
        let c = dem_core::checkpoint::parse_bytes(&std::fs::read(p).unwrap(), "c").unwrap();
        serde_json::to_string(&c.world).unwrap()
    };
    let w = world(&json.join("ckpt-final.json"));
    assert!(w == world(&bin.join("ckpt-final.bin")));
    assert!(w == world(&bin2.join("ckpt-final.json")));
    // A corrupted binary checkpoint is refused naming it.
    let mut b = std::fs::read(&ck).unwrap();
    let n = b.len();
    b[n / 2] ^= 1;
    let bad = dir.join("bad.bin");
    std::fs::write(&bad, &b).unwrap();
    let o = dem(&[
        "run",
        s,
        "--out",
        off.to_str().unwrap(),
        "--restart",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("bad.bin: the checkpoint is corrupt"),
        "{}",
        text(&o)
    );
    // Off: no checkpoint files, and it says so.
    let o = dem(&["run", s, "--out", off.to_str().unwrap(), "--no-checkpoints"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("cannot be resumed"), "{}", text(&o));
    let names: Vec<String> = std::fs::read_dir(&off)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with("ckpt")), "{names:?}");
    assert!(names.iter().any(|n| n == "summary.json"), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--vtk-format binary` writes appended base64 snapshots that `dem render` draws like the
/// ASCII ones of the same run.
#[test]
fn binary_vtk_snapshots_render_like_ascii() {
    let dir = tmp("vtkbin");
    let scene = tiny_scene(&dir);
    let s = scene.to_str().unwrap();
    // One folder name for both: the picture's caption names it.
    let (ascii, bin) = (dir.join("a").join("run"), dir.join("b").join("run"));
    let o = dem(&["run", s, "--out", ascii.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = dem(&[
        "run",
        s,
        "--out",
        bin.to_str().unwrap(),
        "--vtk-format",
        "binary",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let snap = |d: &Path| d.join("snap-000000200.vtp");
    let b = std::fs::read_to_string(snap(&bin)).unwrap();
    assert!(b.contains("<AppendedData encoding=\"base64\">") && !b.contains("\"ascii\""));
    let picture = |d: &Path| {
        let png = d.join("s.png");
        let o = dem(&[
            "render",
            snap(d).to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
        std::fs::read(png).unwrap()
    };
    assert!(
        picture(&ascii) == picture(&bin),
        "the two snapshots draw differently"
    );
    let o = dem(&[
        "run",
        s,
        "--out",
        dir.join("x").to_str().unwrap(),
        "--vtk-format",
        "raw",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

/// Issue 48 D1: a scene that is one of the files the run writes into its --out folder (its
/// summary, history or final checkpoint, by any spelling: `..`, a symlink) is refused before
/// anything is written, and stays as it was; `--force` changes nothing.
#[test]
fn a_scene_that_is_one_of_the_runs_outputs_is_refused() {
    let dir = tmp("input-is-output");
    let scene = tiny_scene(&dir);
    let text_of_scene = std::fs::read_to_string(&scene).unwrap();
    let sc = dir.join("sc1");
    std::fs::create_dir_all(&sc).unwrap();
    for name in [
        "summary.json",
        "history.csv",
        "ckpt-final.json",
        "ckpt-000000200.json",
    ] {
        let p = sc.join(name);
        std::fs::write(&p, &text_of_scene).unwrap();
        let spelled = dir.join("sc1/../sc1").join(name);
        for (s, force) in [(&p, false), (&spelled, false), (&p, true)] {
            let mut args = vec!["run", s.to_str().unwrap(), "--out", sc.to_str().unwrap()];
            if force {
                args.push("--force");
            }
            let o = dem(&args);
            assert_eq!(o.status.code(), Some(2), "{name}: {}", text(&o));
            assert!(
                text(&o).contains(&format!("the run's own output `{name}`")),
                "{}",
                text(&o)
            );
            assert_eq!(
                std::fs::read_to_string(&p).unwrap(),
                text_of_scene,
                "{name}"
            );
        }
        std::fs::remove_file(&p).unwrap();
    }
    #[cfg(unix)]
    {
        let p = sc.join("summary.json");
        std::fs::write(&p, &text_of_scene).unwrap();
        let link = dir.join("link.json");
        std::os::unix::fs::symlink(&p, &link).unwrap();
        let o = dem(&["run", link.to_str().unwrap(), "--out", sc.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert_eq!(std::fs::read_to_string(&p).unwrap(), text_of_scene);
    }
    // The same scene under its own name in that folder runs.
    let own = sc.join("scene.json");
    std::fs::write(&own, &text_of_scene).unwrap();
    let o = dem(&["run", own.to_str().unwrap(), "--out", sc.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    std::fs::remove_dir_all(&dir).unwrap();
}
