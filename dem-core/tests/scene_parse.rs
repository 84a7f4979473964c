//! Scene files: the examples load; bad scenes fail with the file, the JSON path and the reason.

use dem_core::scene::{self, model::Stop, SceneError};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes")
}

/// A valid two-disc scene to mutate.
fn base() -> serde_json::Value {
    serde_json::json!({
        "schema": "dem.scene/1",
        "units": "mm",
        "materials": [
            {"name": "glass", "density": 2500, "kn": 1e6, "ks": 5e5, "friction": 0.3, "restitution": 0.8},
            {"name": "steel", "kn": 2e6, "ks": 1e6, "friction": 0.2, "restitution": 0.6}
        ],
        "bodies": {"discs": [{"material": "glass", "discs": [[0, 0, 1], [2.5, 0, 1]]}]},
        "walls": [{"name": "floor", "a": [-5, -1], "b": [5, -1], "material": "steel"}],
        "run": {"steps": 10}
    })
}

fn load_value(v: &serde_json::Value, name: &str) -> Result<scene::Scene, SceneError> {
    let dir = std::env::temp_dir().join(format!("dem-scene-parse-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    scene::load(&p)
}

/// Loads a mutated base scene and returns the error text, which must name the file.
fn error_of(f: impl FnOnce(&mut serde_json::Value), name: &str) -> String {
    let mut v = base();
    f(&mut v);
    let e = load_value(&v, name)
        .expect_err("scene should be rejected")
        .to_string();
    assert!(e.contains(name), "error does not name the file: {e}");
    e
}

#[test]
fn every_example_loads() {
    let mut n = 0;
    for entry in std::fs::read_dir(examples()).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "json") {
            let s = scene::load(&p).unwrap_or_else(|e| panic!("{e}"));
            assert!(s.disc_count() > 0, "{}", p.display());
            n += 1;
        }
    }
    assert!(n >= 4, "found {n} example scenes");
}

#[test]
fn lengths_convert_once_and_pairs_mix() {
    let s = load_value(&base(), "ok.json").unwrap();
    assert_eq!(s.discs[1].x, 2.5e-3);
    assert_eq!(s.discs[1].r, 1e-3);
    assert_eq!(s.walls[0].a, [-5e-3, -1e-3]);
    assert_eq!(s.walls[0].center, [0.0, -1e-3]);
    assert_eq!(
        s.thickness, 1.0,
        "default thickness is 1 m whatever the units"
    );
    assert_eq!(s.run.stop, Stop::Steps(10));
    // glass-glass and glass-steel are used; steel-steel is not.
    assert_eq!(s.pairs.len(), 2);
    let gs = s.pair(1, 0).unwrap();
    match gs.stiffness {
        scene::model::PairStiffness::Linear { kn, ks } => {
            assert!((kn - 2.0 * 1e6 * 2e6 / 3e6).abs() < 1e-6);
            assert!((ks - 2.0 * 5e5 * 1e6 / 1.5e6).abs() < 1e-6);
        }
        _ => panic!("linear expected"),
    }
    assert_eq!(gs.friction, 0.2);
    assert_eq!(gs.damping, scene::model::NormalDamping::Restitution(0.6));
    assert!(s.pair(1, 1).is_none());
}

#[test]
fn unknown_field_is_named_with_its_path() {
    let e = error_of(
        |v| v["bodies"]["discs"][0]["colour"] = "red".into(),
        "unknown.json",
    );
    assert!(
        e.contains("bodies.discs[0]") && e.contains("unknown field `colour`"),
        "{e}"
    );
    let e = error_of(|v| v["run"]["stepz"] = 3.into(), "unknown2.json");
    assert!(e.contains("run") && e.contains("stepz"), "{e}");
}

#[test]
fn wrong_type_and_bad_enum_are_named() {
    let e = error_of(
        |v| v["materials"][0]["density"] = "heavy".into(),
        "type.json",
    );
    assert!(e.contains("materials[0].density"), "{e}");
    let e = error_of(|v| v["units"] = "cm".into(), "units.json");
    assert!(e.contains("units") && e.contains("cm"), "{e}");
}

#[test]
fn negative_radius_is_named() {
    let e = error_of(
        |v| v["bodies"]["discs"][0]["discs"][1][2] = (-1.0).into(),
        "radius.json",
    );
    assert!(
        e.contains("bodies.discs[0].discs[1][2]") && e.contains("radius must be positive"),
        "{e}"
    );
}

#[test]
fn bad_material_reference_is_named() {
    let e = error_of(|v| v["walls"][0]["material"] = "stee".into(), "mat.json");
    assert!(
        e.contains("walls[0].material") && e.contains("\"stee\""),
        "{e}"
    );
    // A wall material without density cannot make discs.
    let e = error_of(
        |v| v["bodies"]["discs"][0]["material"] = "steel".into(),
        "dens.json",
    );
    assert!(
        e.contains("bodies.discs[0].material") && e.contains("no density"),
        "{e}"
    );
}

#[test]
fn missing_template_is_named() {
    let e = error_of(
        |v| {
            v["bodies"]["clumps"] = serde_json::json!([{
                "template": "no/such/template.json", "material": "glass", "mode": "rigid",
                "placements": [{"x": 0, "y": 5}]
            }])
        },
        "tpl.json",
    );
    assert!(
        e.contains("bodies.clumps[0].template") && e.contains("no/such/template.json"),
        "{e}"
    );
}

#[test]
fn law_parameters_are_required_where_used() {
    let e = error_of(
        |v| v["contact"] = serde_json::json!({"law": "hertz_mindlin"}),
        "hertz.json",
    );
    assert!(
        e.contains("materials[0].youngs_modulus") && e.contains("hertz_mindlin"),
        "{e}"
    );
    let e = error_of(
        |v| {
            v["materials"][1]
                .as_object_mut()
                .unwrap()
                .remove("kn")
                .map(|_| ())
                .unwrap()
        },
        "kn.json",
    );
    assert!(e.contains("materials[1].kn"), "{e}");
}

#[test]
fn bond_group_parameters_match_model_and_criterion() {
    let group = serde_json::json!({"name": "gb", "model": "parallel_potyondy2004", "criterion": "stress",
        "kn": 1e12, "ks": 5e11, "tensile_strength": 1e7, "cohesion": 2e7});
    let mut v = base();
    v["bond_groups"] = serde_json::json!([group.clone()]);
    let s = load_value(&v, "bonds-ok.json").unwrap();
    assert_eq!(
        s.bond_groups[0].criterion,
        dem_core::bond::Criterion::Stress {
            tensile: 1e7,
            cohesion: 2e7,
            friction_angle: 0.0
        }
    );
    let e = error_of(
        |v| {
            let mut g = group.clone();
            g["friction_angle"] = 95.0.into();
            v["bond_groups"] = serde_json::json!([g]);
        },
        "bonds-phi.json",
    );
    assert!(
        e.contains("bond_groups[0].friction_angle") && e.contains("95"),
        "{e}"
    );
    let e = error_of(
        |v| {
            let mut g = group.clone();
            g.as_object_mut().unwrap().remove("cohesion");
            v["bond_groups"] = serde_json::json!([g]);
        },
        "bonds-missing.json",
    );
    assert!(
        e.contains("bond_groups[0].cohesion") && e.contains("required by criterion stress"),
        "{e}"
    );
    let e = error_of(
        |v| {
            let mut g = group.clone();
            g["fracture_energy"] = 1.0.into();
            v["bond_groups"] = serde_json::json!([g]);
        },
        "bonds-unused.json",
    );
    assert!(
        e.contains("bond_groups[0].fracture_energy") && e.contains("not used"),
        "{e}"
    );
    let e = error_of(
        |v| v["auto_bonds"] = serde_json::json!([{"bond_group": "grain_boundary"}]),
        "bonds-ref.json",
    );
    assert!(e.contains("auto_bonds[0].bond_group"), "{e}");
}

#[test]
fn flat_joint_groups_are_read_and_checked() {
    let group = serde_json::json!({"name": "fj", "model": "flat_joint_potyondy2012",
        "criterion": "stress", "kn": 1e12, "ks": 5e11, "tensile_strength": 1e7,
        "cohesion": 2e7, "friction_angle": 30, "elements": 4, "friction": 0.5});
    let mut v = base();
    v["bond_groups"] = serde_json::json!([group.clone()]);
    let s = load_value(&v, "fj-ok.json").unwrap();
    match s.bond_groups[0].model {
        dem_core::bond::BondModel::FlatJoint(p) => {
            assert_eq!((p.elements, p.friction, p.lambda), (4, 0.5, 1.0));
        }
        other => panic!("{other:?}"),
    }
    let cases: [(&str, serde_json::Value, &str, &str); 3] = [
        ("elements", 9.into(), "bond_groups[0].elements", "1 to 8"),
        (
            "friction",
            (-1.0).into(),
            "bond_groups[0].friction",
            "out of range",
        ),
        (
            "moment_factor",
            0.5.into(),
            "bond_groups[0].moment_factor",
            "not used",
        ),
    ];
    for (k, (field, value, path, why)) in cases.into_iter().enumerate() {
        let e = error_of(
            |v| {
                let mut g = group.clone();
                g[field] = value;
                v["bond_groups"] = serde_json::json!([g]);
            },
            &format!("fj-bad-{k}.json"),
        );
        assert!(e.contains(path) && e.contains(why), "{field}: {e}");
    }
    // The elements break by the stress criterion only.
    let e = error_of(
        |v| {
            let mut g = group.clone();
            let o = g.as_object_mut().unwrap();
            for k in ["tensile_strength", "cohesion", "friction_angle"] {
                o.remove(k);
            }
            g["criterion"] = "force".into();
            g["normal_strength"] = 1.0.into();
            g["shear_strength"] = 1.0.into();
            v["bond_groups"] = serde_json::json!([g]);
        },
        "fj-force.json",
    );
    assert!(
        e.contains("bond_groups[0].criterion") && e.contains("\"stress\""),
        "{e}"
    );
    // A parallel bond refuses the flat joint's fields.
    let e = error_of(
        |v| {
            let mut g = group.clone();
            g["model"] = "parallel_potyondy2004".into();
            v["bond_groups"] = serde_json::json!([g]);
        },
        "fj-on-parallel.json",
    );
    assert!(
        e.contains("bond_groups[0].elements") && e.contains("not used"),
        "{e}"
    );
}

#[test]
fn run_control_is_checked() {
    let e = error_of(
        |v| v["run"] = serde_json::json!({"steps": 10, "duration": 1.0}),
        "run.json",
    );
    assert!(e.contains("run.steps") && e.contains("not both"), "{e}");
    let e = error_of(
        |v| v["run"] = serde_json::json!({"steps": 10, "dt_factor": 1.5}),
        "dtf.json",
    );
    assert!(e.contains("run.dt_factor"), "{e}");
    let e = error_of(
        |v| v["run"] = serde_json::json!({"steps": 10, "mass_scaling": 0.7}),
        "mass.json",
    );
    assert!(
        e.contains("run.mass_scaling") && e.contains("[0, 0.5]"),
        "{e}"
    );
}

/// `run.mass_scaling` enters the physics (and so the checkpoints' scene hash) and the built
/// world is scaled: the small disc of two (m/4) sets the step until the budget raises it.
#[test]
fn mass_scaling_is_applied_when_the_world_is_built() {
    let mut v = base();
    v["bodies"]["discs"] =
        serde_json::json!([{"material": "glass", "discs": [[0, 0, 1], [1.45, 0, 0.5]]}]);
    let plain = load_value(&v, "plain.json").unwrap();
    v["run"]["mass_scaling"] = serde_json::json!(0.1);
    let scaled = load_value(&v, "scaled.json").unwrap();
    assert_eq!(scaled.run.mass_scaling, Some(0.1));
    assert_ne!(plain.physics_hash(), scaled.physics_hash());
    let (w0, w1) = (
        scene::build(&plain).unwrap(),
        scene::build(&scaled).unwrap(),
    );
    assert!(w0.mass_scaling().is_none());
    let r = w1.mass_scaling().expect("scaled");
    assert!(
        r.discs_mass >= 1 && (r.added_mass_fraction - 0.1).abs() < 1e-9,
        "{r:?}"
    );
    assert!(w1.critical_dt() > w0.critical_dt(), "{r:?}");
}

#[test]
fn specimen_files_are_included_with_their_units() {
    let dir = std::env::temp_dir().join(format!("dem-scene-spec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("spec.json"),
        r#"{"schema": "dem.specimen/1", "units": "m", "discs": [{"material": "glass", "group": 4, "discs": [[0.01, 0.0, 0.002]]}]}"#,
    )
    .unwrap();
    let mut v = base();
    v["bodies"]["specimens"] = serde_json::json!([{"file": "spec.json", "offset": [100, 0]}]);
    let p = dir.join("with-spec.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let s = scene::load(&p).unwrap();
    assert_eq!(s.discs.len(), 3);
    assert!((s.discs[2].x - 0.11).abs() < 1e-15 && s.discs[2].r == 0.002 && s.discs[2].group == 4);
    // An error inside the specimen names the specimen file and its own path.
    std::fs::write(
        dir.join("spec.json"),
        r#"{"schema": "dem.specimen/1", "discs": [{"material": "glass", "discs": [[0, 0, 0]]}]}"#,
    )
    .unwrap();
    let e = scene::load(&p).unwrap_err().to_string();
    assert!(
        e.contains("spec.json") && e.contains("discs[0].discs[0][2]"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn kinematics_convert_with_units_and_random_speeds_follow_the_seed() {
    let mut v = base();
    v["gravity"] = serde_json::json!([0, -9810]);
    v["bodies"]["discs"][0]["velocity"] = serde_json::json!([100, 0]);
    v["bodies"]["discs"][0]["random_speed"] = 50.0.into();
    v["seed"] = 7.into();
    let a = load_value(&v, "seed7.json").unwrap();
    assert_eq!(a.gravity, Some([0.0, -9.81]));
    for d in &a.discs {
        let (ux, uy) = (d.vx - 0.1, d.vy);
        assert!(
            ((ux * ux + uy * uy).sqrt() - 0.05).abs() < 1e-15,
            "random part is 50 mm/s"
        );
    }
    let b = load_value(&v, "seed7b.json").unwrap();
    assert_eq!(
        (a.discs[0].vx, a.discs[1].vy),
        (b.discs[0].vx, b.discs[1].vy)
    );
    v["seed"] = 8.into();
    let c = load_value(&v, "seed8.json").unwrap();
    assert_ne!(a.discs[0].vx, c.discs[0].vx);
    assert_ne!(a.physics_hash(), c.physics_hash());
    assert_eq!(a.physics_hash(), b.physics_hash());
    // Run control and outputs do not enter the hash (a restart may extend a run).
    v["seed"] = 7.into();
    v["run"]["steps"] = 99.into();
    v["outputs"] = serde_json::json!({"history_every": 3});
    assert_eq!(
        load_value(&v, "seed7c.json").unwrap().physics_hash(),
        a.physics_hash()
    );
}

#[test]
fn hertz_takes_restitution_not_a_damping_ratio() {
    let e = error_of(
        |v| {
            v["materials"] = serde_json::json!([{"name": "glass", "density": 2500, "youngs_modulus": 60e9, "poisson": 0.2, "damping_ratio": 0.1}]);
            v["walls"] = serde_json::json!([]);
            v["contact"] = serde_json::json!({"law": "hertz_mindlin"});
        },
        "hertz-ratio.json",
    );
    assert!(
        e.contains("restitution") && e.contains("hertz_mindlin"),
        "{e}"
    );
}

#[test]
fn servo_walls_convert_and_bad_servos_are_named() {
    let servo = serde_json::json!({"stress": 2e6, "length": 4, "direction": [0, 3],
                                   "max_speed": 50});
    let mut v = base();
    v["walls"][0]["servo"] = servo.clone();
    let s = load_value(&v, "servo.json").unwrap();
    let sv = s.walls[0].servo.expect("servo");
    // Lengths and speeds in the scene's unit (mm), the direction normalised, α 0.5 by default.
    assert_eq!(
        (sv.stress, sv.length, sv.direction, sv.alpha, sv.max_speed),
        (2e6, 4e-3, [0.0, 1.0], 0.5, 50e-3)
    );
    for (field, bad, want) in [
        ("stress", serde_json::json!(-1.0), "walls[0].servo.stress"),
        ("length", serde_json::json!(0.0), "walls[0].servo.length"),
        (
            "direction",
            serde_json::json!([0, 0]),
            "walls[0].servo.direction",
        ),
        ("alpha", serde_json::json!(0.0), "walls[0].servo.alpha"),
        ("alpha", serde_json::json!(1.5), "walls[0].servo.alpha"),
        (
            "max_speed",
            serde_json::json!(-2.0),
            "walls[0].servo.max_speed",
        ),
    ] {
        let e = error_of(
            |v| {
                v["walls"][0]["servo"] = servo.clone();
                v["walls"][0]["servo"][field] = bad;
            },
            "servo.json",
        );
        assert!(e.contains(want), "{field}: {e}");
    }
    // A servo sets the wall's velocity: a prescribed one as well is refused.
    let e = error_of(
        |v| {
            v["walls"][0]["servo"] = servo.clone();
            v["walls"][0]["velocity"] = serde_json::json!([1, 0]);
        },
        "servo.json",
    );
    assert!(
        e.contains("walls[0].servo") && e.contains("velocity"),
        "{e}"
    );
}

/// `outputs.vtk_count` (N snapshots spread over the run) and `outputs.vtk_every` are two ways
/// of saying when to write: both at once is refused naming the field.
#[test]
fn vtk_count_and_vtk_every_together_are_refused() {
    let e = error_of(
        |v| {
            v["outputs"]["vtk_every"] = 10.into();
            v["outputs"]["vtk_count"] = 3.into();
        },
        "snapshots.json",
    );
    assert!(
        e.contains("outputs.vtk_count") && e.contains("not both"),
        "{e}"
    );
}
