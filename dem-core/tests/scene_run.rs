//! Scenes run: every example runs a few hundred steps and writes finite outputs; a restart
//! continues bit-identically; a blown-up run stops with the guard's message and no NaN written.

use dem_core::output::driver::{Ending, RunOptions, Simulation};
use dem_core::scene;
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-scene-run-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Every number in a text output parses as a finite float (no NaN/inf written).
fn assert_finite_text(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap();
    // Rust's f64 parser accepts NaN, inf and infinity in any case.
    for w in text.split([',', '\n', ' ', '"', '>', '<']) {
        if let Ok(v) = w.trim().parse::<f64>() {
            assert!(v.is_finite(), "{}: {w}", path.display());
        }
    }
}

#[test]
fn every_example_runs_a_few_hundred_steps() {
    for entry in std::fs::read_dir(examples()).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let name = p.file_stem().unwrap().to_string_lossy().into_owned();
        let s = scene::load(&p).unwrap();
        let out = tmp(&name);
        let opts = RunOptions {
            out_dir: Some(out.clone()),
            max_steps: Some(300),
            ..RunOptions::default()
        };
        let mut sim = Simulation::new(s, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut calls = 0;
        let (summary, ending) = sim
            .run(&mut |_, _| calls += 1)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(calls > 1);
        assert!(
            summary.steps > 0 && summary.steps <= 300,
            "{name}: {}",
            summary.steps
        );
        if summary.steps == 300 {
            assert_eq!(ending, Ending::MaxSteps);
        }
        assert!(summary.particle_steps_per_s > 0.0);
        for f in ["history.csv", "summary.json", "ckpt-final.json"] {
            assert!(out.join(f).exists(), "{name}: {f}");
        }
        assert_finite_text(&out.join("history.csv"));
        let rows = std::fs::read_to_string(out.join("history.csv"))
            .unwrap()
            .lines()
            .count();
        let every = scene::load(&p).unwrap().outputs.history_every;
        assert_eq!(
            rows as u64,
            1 + summary.steps / every,
            "{name}: history lines"
        );
        println!(
            "{name}: {} steps, stages {:?}, balance {:.2e}",
            summary.steps, summary.active_stages, summary.energy.balance_error
        );
        std::fs::remove_dir_all(&out).unwrap();
    }
}

fn run(scene_path: &Path, out: &Path, max_steps: u64, restart: Option<PathBuf>) -> Ending {
    let s = scene::load(scene_path).unwrap();
    let opts = RunOptions {
        out_dir: Some(out.to_path_buf()),
        max_steps: Some(max_steps),
        restart,
    };
    let mut sim = Simulation::new(s, &opts).unwrap();
    sim.run(&mut |_, _| {}).unwrap().1
}

#[test]
fn restart_continues_bit_identically() {
    // Rigid and bonded clumps, walls, gravity, damping: every piece of state a checkpoint holds.
    let p = examples().join("clumps-settling.json");
    let n = 400;
    let (a, b) = (tmp("restart-a"), tmp("restart-b"));
    assert_eq!(run(&p, &a, 2 * n, None), Ending::MaxSteps);
    assert_eq!(run(&p, &b, n, None), Ending::MaxSteps);
    let half = std::fs::read(b.join("ckpt-final.json")).unwrap();
    let ck = b.join("ckpt-half.json");
    std::fs::write(&ck, &half).unwrap();
    assert_eq!(run(&p, &b, 2 * n, Some(ck)), Ending::MaxSteps);
    // Everything but the run totals (wall and CPU time) is the same bytes.
    let parts = |f: &[u8]| {
        let mut v: serde_json::Value = serde_json::from_slice(f).unwrap();
        let run = v["run"].take();
        v["checksum"].take(); // over the run totals too
        (v.to_string(), run)
    };
    let fa = std::fs::read(a.join("ckpt-final.json")).unwrap();
    let fb = std::fs::read(b.join("ckpt-final.json")).unwrap();
    let ((sa, ra), (sb, rb)) = (parts(&fa), parts(&fb));
    assert_ne!(
        parts(&half).0,
        sa,
        "the second half must have moved something"
    );
    assert!(sa == sb, "final checkpoints differ after restart");
    // The totals count the invocations and carry the dt range over the restart.
    assert_eq!(ra["invocations"], 1);
    assert_eq!(rb["invocations"], 2);
    assert_eq!(ra["dt_min"], rb["dt_min"]);
    assert_eq!(ra["dt_max"], rb["dt_max"]);
    for f in ["history.csv", "breaks.csv"] {
        assert_eq!(
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
            "{f}"
        );
    }
    // The world inside is the same state, read back.
    let s = scene::load(&p).unwrap();
    let c = dem_core::checkpoint::load(&b.join("ckpt-final.json"), &s.physics_hash()).unwrap();
    assert_eq!(c.world.state.step, 2 * n);
    std::fs::remove_dir_all(&a).unwrap();
    std::fs::remove_dir_all(&b).unwrap();
}

#[test]
fn a_checkpoint_whose_world_does_not_fit_is_refused_by_name() {
    // Issue 20, found by fuzzing the checkpoint reader: a checkpoint without its checksum
    // field (older files are read so) whose world had a neighbour index out of range passed
    // the reader and stopped the next step on an assertion ("neighbour list out of date").
    let p = examples().join("clumps-settling.json");
    let out = tmp("inconsistent");
    run(&p, &out, 40, None);
    let text = std::fs::read_to_string(out.join("ckpt-final.json")).unwrap();
    let mut good: serde_json::Value = serde_json::from_str(&text).unwrap();
    good.as_object_mut().unwrap().remove("checksum");
    // Unchanged but for the checksum: read, and it steps.
    let mut c = dem_core::checkpoint::parse(&good.to_string(), "c.json").unwrap();
    c.world.step();
    type Edit = fn(&mut serde_json::Value);
    let edits: [(&str, Edit); 9] = [
        ("neighbour index", |w| w["nb"]["nbr"][0] = 1_000_000.into()),
        ("neighbour offsets", |w| {
            w["nb"]["start"].as_array_mut().unwrap().pop();
        }),
        ("disc cache", |w| {
            w["cache"]["inv_m"].as_array_mut().unwrap().pop();
        }),
        ("bond disc", |w| w["bonds"]["i"][0] = 99_999.into()),
        ("bond group", |w| w["bonds"]["group"][0] = 7.into()),
        ("time step", |w| w["dt"] = (-1.0).into()),
        ("disc radius", |w| w["state"]["discs"]["r"][0] = 0.0.into()),
        ("contact law table", |w| w["laws"]["n"] = 3.into()),
        ("clump member offsets", |w| {
            w["state"]["clumps"]["offset_x"]
                .as_array_mut()
                .unwrap()
                .pop();
        }),
    ];
    for (what, edit) in edits {
        let mut v = good.clone();
        edit(&mut v["world"]);
        let e = dem_core::checkpoint::parse(&v.to_string(), "c.json")
            .err()
            .unwrap_or_else(|| panic!("{what}: must be refused"))
            .to_string();
        assert!(
            e.starts_with("c.json") && e.contains("not consistent"),
            "{what}: {e}"
        );
    }
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn restart_refuses_another_scene() {
    let p = examples().join("two-disc-impact.json");
    let out = tmp("refuse");
    run(&p, &out, 20, None);
    let other = scene::load(&examples().join("column-settling.json")).unwrap();
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        restart: Some(out.join("ckpt-final.json")),
        max_steps: None,
    };
    let e = Simulation::new(other, &opts)
        .err()
        .expect("must refuse")
        .to_string();
    assert!(
        e.contains("ckpt-final.json") && e.contains("different scene"),
        "{e}"
    );
    std::fs::remove_dir_all(&out).unwrap();
}

#[test]
fn blow_up_stops_with_the_guard_and_writes_no_nan() {
    // A packed, overlapping cluster at twice the critical time step 2·sqrt(m/k)... and more.
    let dir = tmp("blowup");
    std::fs::create_dir_all(&dir).unwrap();
    let mut discs = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            discs.push(serde_json::json!([i as f64 * 1.9, j as f64 * 1.9, 1.0]));
        }
    }
    // m = 1000·π ≈ 3142 kg, k = 1e6 N/m: sqrt(m/k) ≈ 0.056 s; dt = 0.15 s is unstable.
    let scene = serde_json::json!({
        "schema": "dem.scene/1",
        "materials": [{"name": "a", "density": 1000, "kn": 1e6, "ks": 1e6}],
        "bodies": {"discs": [{"material": "a", "discs": discs}]},
        "run": {"steps": 2000, "dt": 0.15},
        "outputs": {"history_every": 5, "vtk_every": 5, "guard_every": 5}
    });
    let p = dir.join("blowup.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    let s = scene::load(&p).unwrap();
    let out = dir.join("out");
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        ..RunOptions::default()
    };
    let mut sim = Simulation::new(s, &opts).unwrap();
    let e = sim.run(&mut |_, _| {}).expect_err("must blow up");
    let msg = e.to_string();
    assert!(
        matches!(e, dem_core::output::driver::RunError::Guard { .. }),
        "{msg}"
    );
    assert!(
        msg.contains("step ") && msg.contains("disc") && msg.contains("likely cause"),
        "{msg}"
    );
    assert!(out.join("last-good-state.json").exists());
    let good: dem_core::State =
        serde_json::from_str(&std::fs::read_to_string(out.join("last-good-state.json")).unwrap())
            .unwrap();
    assert!(good
        .discs
        .x
        .iter()
        .chain(&good.discs.vx)
        .all(|v| v.is_finite()));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"stopped\""), "{summary}");
    for entry in std::fs::read_dir(&out).unwrap() {
        let f = entry.unwrap().path();
        if f.extension()
            .is_some_and(|e| e == "csv" || e == "vtp" || e == "json" || e == "pvd")
        {
            assert_finite_text(&f);
        }
    }
    // serde_json would write a NaN as null: the JSON outputs read back into their f64 fields.
    let s: dem_core::output::summary::RunSummary =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(s.steps > 0 && s.steps < 2000 && s.error.is_some());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn broken_bonds_reach_the_history_and_the_break_log() {
    let dir = tmp("breaks");
    std::fs::create_dir_all(&dir).unwrap();
    // Two touching discs bonded by a contact bond, pulled apart: it breaks in tension.
    let scene = serde_json::json!({
        "schema": "dem.scene/1",
        "units": "mm",
        "materials": [{"name": "a", "density": 2500, "kn": 1e5, "ks": 5e4}],
        "bond_groups": [{"name": "glue", "model": "contact_bond", "criterion": "force",
                          "kn": 1e5, "ks": 5e4, "normal_strength": 0.01, "shear_strength": 0.01}],
        "bodies": {"discs": [
            {"material": "a", "velocity": [-100, 0], "discs": [[-1, 0, 1]]},
            {"material": "a", "velocity": [100, 0], "discs": [[1, 0, 1]]}
        ]},
        "auto_bonds": [{"bond_group": "glue"}],
        "run": {"steps": 200},
        "outputs": {"history_every": 10}
    });
    let p = dir.join("pull.json");
    std::fs::write(&p, scene.to_string()).unwrap();
    let out = dir.join("out");
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        ..RunOptions::default()
    };
    let (s, _) = Simulation::new(scene::load(&p).unwrap(), &opts)
        .unwrap()
        .run(&mut |_, _| {})
        .unwrap();
    assert_eq!((s.bonds, s.bonds_broken), (1, 1));
    let hist = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let head: Vec<&str> = hist.lines().next().unwrap().split(',').collect();
    let col = head
        .iter()
        .position(|h| *h == "broken_glue_tension")
        .unwrap();
    let last: Vec<&str> = hist.lines().last().unwrap().split(',').collect();
    assert_eq!((last[col], last[col + 1]), ("1", "0"));
    let breaks = std::fs::read_to_string(out.join("breaks.csv")).unwrap();
    let lines: Vec<&str> = breaks.lines().collect();
    assert_eq!(lines.len(), 2, "{breaks}");
    assert!(lines[1].contains(",glue,tension,"), "{breaks}");
    std::fs::remove_dir_all(&dir).unwrap();
}
