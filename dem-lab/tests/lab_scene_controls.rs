//! The scene features the lab tests use: position gauges (`outputs.gauges`: mean position of
//! the discs in a region when the scene is built, the same discs after a restart) and
//! `run.stop_after_peak` (the run ends once the load has fallen below a fraction of its peak);
//! bad values name their field.

use dem_core::output::driver::{Ending, RunOptions, Simulation};
use dem_core::scene;
use dem_lab::history::Table;
use serde_json::{json, Value};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-lab-controls-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Three free discs at x = 0, 1, 2 moving at (20, 10) m/s; gauge `g` holds the first two.
fn gauge_scene() -> Value {
    json!({
        "schema": "dem.scene/1",
        "materials": [{"name": "m", "density": 1000.0, "kn": 1e5, "ks": 1e5}],
        "bodies": {"discs": [{"material": "m", "velocity": [20.0, 10.0],
                              "discs": [[0.0, 0.0, 0.1], [1.0, 0.0, 0.1], [2.0, 0.0, 0.1]]}]},
        "run": {"steps": 1000, "dt": 1e-4},
        "outputs": {"history_every": 50, "gauges": [{"name": "g", "region": [-0.5, -0.5, 1.5, 0.5]}]}
    })
}

fn load(v: &Value, dir: &std::path::Path) -> Result<scene::Scene, scene::SceneError> {
    scene::parse(&v.to_string(), &dir.join("scene.json"))
}

fn run(v: &Value, dir: &std::path::Path, opts: RunOptions) -> (Ending, Table) {
    let s = load(v, dir).unwrap();
    let mut sim = Simulation::new(s, &opts).unwrap();
    let out = sim.out_dir().to_path_buf();
    let (_, e) = sim.run(&mut |_, _| {}).unwrap();
    (e, Table::read(&out.join("history.csv")).unwrap())
}

#[test]
fn gauge_is_the_mean_of_its_discs_and_survives_a_restart() {
    let d = tmp("gauge");
    let (_, t) = run(&gauge_scene(), &d, RunOptions::default());
    let time = t.column("time", "h").unwrap();
    let gx = t.column("g_x", "h").unwrap();
    let gy = t.column("g_y", "h").unwrap();
    assert_eq!(time.len(), 20);
    for i in 0..time.len() {
        // Mean of discs 0 and 1: (0.5 + 20 t, 10 t); disc 2 is not in the gauge.
        assert!(
            (gx[i] - (0.5 + 20.0 * time[i])).abs() < 1e-9,
            "{} {}",
            gx[i],
            time[i]
        );
        assert!((gy[i] - 10.0 * time[i]).abs() < 1e-9);
    }
    // Restart at step 500 (t = 0.05 s: disc 0 is then at x = 1, disc 1 at x = 2, so a region
    // test at the restart would pick other discs): same columns and values as the full run.
    let d2 = tmp("gauge-restart");
    let (e, _) = run(
        &gauge_scene(),
        &d2,
        RunOptions {
            max_steps: Some(500),
            ..RunOptions::default()
        },
    );
    assert_eq!(e, Ending::MaxSteps);
    let ckpt = d2.join("scene.out").join("ckpt-final.json");
    let (e, t2) = run(
        &gauge_scene(),
        &d2,
        RunOptions {
            restart: Some(ckpt),
            ..RunOptions::default()
        },
    );
    assert_eq!(e, Ending::Completed);
    assert_eq!(t2.names, t.names);
    assert_eq!(t2.rows, t.rows);
}

/// A disc at 0.1 m above a fixed floor falls onto it at 1 m/s (no gravity) and bounces off:
/// the floor's force rises and falls within the contact time π√(m/k) = 0.056 s.
fn bounce_scene(stop: Value) -> Value {
    json!({
        "schema": "dem.scene/1",
        "materials": [{"name": "m", "density": 1000.0, "kn": 1e5, "ks": 1e5},
                      {"name": "w", "kn": 1e5, "ks": 1e5}],
        "bodies": {"discs": [{"material": "m", "velocity": [0.0, -1.0], "discs": [[0.0, 0.2, 0.1]]}]},
        "walls": [{"name": "floor", "a": [-1.0, 0.0], "b": [1.0, 0.0], "material": "w"},
                  {"name": "far", "a": [-1.0, 5.0], "b": [1.0, 5.0], "material": "w"}],
        "run": {"duration": 1.0, "dt": 1e-4, "stop_after_peak": stop},
        "outputs": {"history_every": 5}
    })
}

#[test]
fn stop_after_peak_ends_at_the_first_row_below_the_fraction() {
    let d = tmp("stop");
    let (e, t) = run(
        &bounce_scene(json!({"walls": ["floor", "far"], "axis": "y", "below": 0.5})),
        &d,
        RunOptions::default(),
    );
    assert_eq!(e, Ending::Failure);
    let summary = std::fs::read_to_string(d.join("scene.out/summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"failure\""), "{summary}");
    let f: Vec<f64> = t
        .column("floor_fy", "h")
        .unwrap()
        .iter()
        .map(|v| v.abs())
        .collect();
    let time = t.column("time", "h").unwrap();
    let n = f.len();
    let peak = f.iter().copied().fold(0.0, f64::max);
    // Contact from t = 0.1 s, peak near 0.128 s; stopped during the unloading.
    assert!(time[n - 1] > 0.13 && time[n - 1] < 0.16, "{}", time[n - 1]);
    assert!(f[n - 1] < 0.5 * peak, "last {} peak {peak}", f[n - 1]);
    let ip = f.iter().position(|&v| v == peak).unwrap();
    assert!(
        f[ip..n - 1].iter().all(|&v| v >= 0.5 * peak),
        "not the first row below"
    );

    // A restart after the peak (step 1400, t = 0.14 s, load still above half the peak) takes the
    // peak from the history rows it continues, and stops at the same row.
    let stop = json!({"walls": ["floor", "far"], "axis": "y", "below": 0.5});
    let d2 = tmp("stop-restart");
    let (e, _) = run(
        &bounce_scene(stop.clone()),
        &d2,
        RunOptions {
            max_steps: Some(1400),
            ..RunOptions::default()
        },
    );
    assert_eq!(e, Ending::MaxSteps);
    let (e, t2) = run(
        &bounce_scene(stop),
        &d2,
        RunOptions {
            restart: Some(d2.join("scene.out/ckpt-final.json")),
            ..RunOptions::default()
        },
    );
    assert_eq!(e, Ending::Failure);
    assert_eq!(t2.rows, t.rows);

    // Armed only once the peak reaches min_load: above the peak, the run completes.
    let d = tmp("stop-unarmed");
    let (e, t) = run(
        &bounce_scene(json!({"walls": ["floor"], "axis": "y", "below": 0.5,
                             "min_load": 10.0 * peak})),
        &d,
        RunOptions::default(),
    );
    assert_eq!(e, Ending::Completed);
    assert!(*t.column("time", "h").unwrap().last().unwrap() > 0.999);
}

fn field_of(v: &Value) -> String {
    let d = tmp("bad");
    let err = match load(v, &d) {
        Err(e) => e,
        Ok(s) => match Simulation::new(s, &RunOptions::default()) {
            Err(e) => return e.to_string(),
            Ok(_) => panic!("accepted: {v}"),
        },
    };
    err.to_string()
}

#[test]
fn bad_values_name_their_field() {
    let mut v = bounce_scene(json!({"walls": ["nope"], "axis": "y", "below": 0.5}));
    assert!(
        field_of(&v).contains("run.stop_after_peak.walls[0]"),
        "{}",
        field_of(&v)
    );
    v = bounce_scene(json!({"walls": ["floor"], "axis": "y", "below": 1.5}));
    assert!(field_of(&v).contains("run.stop_after_peak.below"));
    v = bounce_scene(json!({"walls": ["floor"], "axis": "z", "below": 0.5}));
    assert!(
        field_of(&v).contains("run.stop_after_peak.axis"),
        "{}",
        field_of(&v)
    );
    v = bounce_scene(json!({"walls": ["floor"], "axis": "y", "below": 0.5}));
    v["outputs"]["history_every"] = json!(0);
    assert!(
        field_of(&v).contains("field run.stop_after_peak:"),
        "{}",
        field_of(&v)
    );

    let mut g = gauge_scene();
    g["outputs"]["gauges"][0]["region"] = json!([5.0, 5.0, 6.0, 6.0]);
    let e = field_of(&g);
    assert!(
        e.contains("outputs.gauges[0].region") && e.contains("no disc"),
        "{e}"
    );
    g["outputs"]["gauges"][0]["region"] = json!([1.0, 0.0, 0.0, 1.0]);
    assert!(field_of(&g).contains("outputs.gauges[0].region"));
    g = gauge_scene();
    g["outputs"]["gauges"] = json!([{"name": "a", "region": [0, 0, 1, 1]},
                                    {"name": "a", "region": [0, 0, 1, 1]}]);
    assert!(field_of(&g).contains("outputs.gauges[1].name"));
    g["outputs"]["gauges"] = json!([{"name": "a b", "region": [0, 0, 1, 1]}]);
    assert!(field_of(&g).contains("outputs.gauges[0].name"));
}
