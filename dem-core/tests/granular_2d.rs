//! The catalogue law (`"law": "granular"`, dem-laws) on 2D discs through a scene file: a
//! two-disc impact gives the restitution the spec asks for (coeff_restitution on hooke:
//! e = exp(−γ t_n / 2m*) exactly for the linear oscillator, S2's form), and bad specs fail
//! naming the file and the field.

use dem_core::scene::{self, SceneError};
use dem_core::World;

fn scene_with(contact: serde_json::Value) -> serde_json::Value {
    serde_json::json!({
        "schema": "dem.scene/1",
        "materials": [{"name": "glass", "density": 2500}],
        "bodies": {"discs": [{"material": "glass", "discs": [[0, 0, 0.01], [0.0201, 0, 0.01]]}]},
        "contact": contact,
        "run": {"steps": 10, "dt_factor": 0.002}
    })
}

fn load(v: &serde_json::Value, name: &str) -> Result<scene::Scene, SceneError> {
    let dir = std::env::temp_dir().join(format!("dem-granular-2d-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    scene::load(&p)
}

/// Restitution of a head-on impact at ±0.5 m/s.
fn restitution(contact: serde_json::Value, name: &str) -> f64 {
    restitution_v(scene_with(contact), name)
}

fn restitution_v(v: serde_json::Value, name: &str) -> f64 {
    let s = load(&v, name).unwrap();
    let mut w: World = scene::build(&s).unwrap();
    let v0 = 0.5;
    w.state.discs.vx[0] = v0;
    w.state.discs.vx[1] = -v0;
    let gap = |w: &World| {
        let d = &w.state.discs;
        (d.x[1] - d.x[0]).abs() - d.r[0] - d.r[1]
    };
    let mut touched = false;
    for _ in 0..1_000_000 {
        w.step();
        let g = gap(&w);
        if g < 0.0 {
            touched = true;
        } else if touched {
            break;
        }
    }
    assert!(touched, "{name}: the discs never touched");
    w.run(10);
    let d = &w.state.discs;
    (d.vx[1] - d.vx[0]).abs() / (2.0 * v0)
}

#[test]
fn a_named_linear_law_gives_the_restitution_it_asks_for() {
    for e in [0.1, 0.5, 0.9, 0.99] {
        let got = restitution(
            serde_json::json!({"law": "granular", "granular": {
                "normal": {"model": "hooke", "kn": 1e6},
                "damping": {"model": "coeff_restitution", "e": e},
                "tangential": {"model": "linear_history", "kt": 5e5, "mu": 0.3}}}),
            "linear.json",
        );
        // The solver's own linear law with the same k_n and restitution: the same bits.
        let mut v = scene_with(serde_json::json!({"law": "linear_spring_dashpot"}));
        v["materials"][0]["kn"] = serde_json::json!(1e6);
        v["materials"][0]["ks"] = serde_json::json!(5e5);
        v["materials"][0]["friction"] = serde_json::json!(0.3);
        v["materials"][0]["restitution"] = serde_json::json!(e);
        let fused = restitution_v(v, "fused.json");
        eprintln!("hooke + coeff_restitution: e {e} → {got:.6} (linear_spring_dashpot {fused:.6})");
        assert_eq!(got.to_bits(), fused.to_bits());
        assert!((got / e - 1.0).abs() < 0.01, "e {e}: got {got}");
    }
}

#[test]
fn an_undamped_hertz_impact_is_elastic() {
    let got = restitution(
        serde_json::json!({"law": "granular", "granular": {
            "normal": {"model": "hertz/material", "E": 7e10, "nu": 0.3},
            "tangential": {"model": "linear_history", "kt": 1e6, "mu": 0.3}}}),
        "hertz.json",
    );
    assert!((got - 1.0).abs() < 1e-3, "e {got}");
}

#[test]
fn bad_granular_specs_name_the_file_and_field() {
    let err = |contact: serde_json::Value, name: &str| {
        let e = load(&scene_with(contact), name).unwrap_err().to_string();
        assert!(e.contains(name), "{e}");
        e
    };
    let e = err(serde_json::json!({"law": "granular"}), "missing.json");
    assert!(e.contains("contact.granular"), "{e}");
    let e = err(
        serde_json::json!({"law": "granular", "granular": {
            "normal": {"model": "hooke", "kn": 1e6},
            "damping": {"model": "coeff_restitution", "e": 1.5},
            "tangential": {"model": "linear_history", "kt": 5e5, "mu": 0.3}}}),
        "e.json",
    );
    assert!(e.contains("contact.granular.damping.e"), "{e}");
    let e = err(
        serde_json::json!({"law": "granular", "granular": {
            "normal": {"model": "hertz/material", "E": 7e10, "nu": 0.6},
            "tangential": {"model": "mindlin", "mu": 0.3}}}),
        "nu.json",
    );
    assert!(e.contains("contact.granular.normal.nu"), "{e}");
    let e = err(
        serde_json::json!({"law": "granular", "granular": {
            "normal": {"model": "hertzz", "kn": 1e6},
            "tangential": {"model": "mindlin", "mu": 0.3}}}),
        "name.json",
    );
    assert!(e.contains("contact.granular.normal"), "{e}");
    let e = err(
        serde_json::json!({"law": "granular", "granular": {
            "normal": {"model": "jkr", "E": 7e10, "nu": 0.3, "gamma": 0.1},
            "tangential": {"model": "mindlin", "mu": 0.3}}}),
        "jkr.json",
    );
    assert!(e.contains("jkr") && e.contains("3D"), "{e}");
}
