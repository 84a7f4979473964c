//! Scene → World: masses, clumps, bonds, laws and stages come out as the scene says.

use dem_core::scene::{self, Scene};
use dem_core::{ContactModel, World};
use serde_json::json;
use std::path::{Path, PathBuf};

fn templates() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes/templates")
}

fn load(v: &serde_json::Value, name: &str) -> Scene {
    let dir = std::env::temp_dir().join(format!("dem-scene-build-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, v.to_string()).unwrap();
    scene::load(&p).unwrap_or_else(|e| panic!("{e}"))
}

fn world(v: &serde_json::Value, name: &str) -> World {
    scene::build(&load(v, name)).unwrap_or_else(|e| panic!("{e}"))
}

fn base(bodies: serde_json::Value) -> serde_json::Value {
    json!({
        "schema": "dem.scene/1",
        "units": "mm",
        "thickness": 2.0,
        "materials": [
            {"name": "grain", "density": 5300, "kn": 1e5, "ks": 5e4, "friction": 0.5},
            {"name": "steel", "kn": 2e5, "ks": 1e5}
        ],
        "bond_groups": [
            {"name": "intra", "model": "parallel_potyondy2004", "criterion": "stress",
             "kn": 1e13, "ks": 4e12, "tensile_strength": 1e9, "cohesion": 1e9},
            {"name": "gb", "model": "contact_bond", "criterion": "force",
             "kn": 1e5, "ks": 5e4, "normal_strength": 1.0, "shear_strength": 1.0}
        ],
        "bodies": bodies,
        "run": {"steps": 10}
    })
}

#[test]
fn free_discs_have_uniform_masses_and_their_initial_motion() {
    let w = world(
        &base(
            json!({"discs": [{"material": "grain", "group": 3, "velocity": [100, -50], "omega": 2.0,
                                 "discs": [[0, 0, 1], [5, 0, 0.5]]}]}),
        ),
        "free.json",
    );
    let d = &w.state.discs;
    let k = w.index_of_id(1).unwrap();
    let m = 5300.0 * 2e-3 * std::f64::consts::PI * 0.25e-6;
    assert!((d.m[k] - m).abs() < 1e-12 * m);
    assert!((d.inertia[k] - 0.5 * m * 0.25e-6).abs() < 1e-12 * m * 1e-6);
    assert_eq!((d.x[k], d.r[k], d.group[k]), (5e-3, 0.5e-3, 3));
    assert_eq!((d.vx[k], d.vy[k], d.omega[k]), (0.1, -0.05, 2.0));
    assert!(
        w.bonds.is_none(),
        "bond groups without bonds build no bond stage"
    );
    assert!(!w.active_stages().contains(&"bonds") && !w.active_stages().contains(&"gravity"));
}

#[test]
fn rigid_clump_has_the_template_mass_for_the_scene_material_and_thickness() {
    let tpl = clumpgen::Template::load(&templates().join("equant-01.json")).unwrap();
    let mut v = base(
        json!({"clumps": [{"template": "", "material": "grain", "mode": "rigid",
        "placements": [{"x": 10, "y": 5, "angle": 0.5, "velocity": [0, 0], "omega": 3.0}]}]}),
    );
    v["bodies"]["clumps"][0]["template"] = templates()
        .join("equant-01.json")
        .display()
        .to_string()
        .into();
    let w = world(&v, "rigid.json");
    let cl = &w.state.clumps;
    assert_eq!(cl.len(), 1);
    // ρ 5300 vs the template's 2650, thickness 2 mm vs 1 mm: four times the mass.
    let f = (5300.0 / tpl.density) * (2e-3 / tpl.thickness);
    assert!((f - 4.0).abs() < 1e-12);
    assert!((cl.m[0] - f * tpl.achieved.mass).abs() < 1e-12 * cl.m[0]);
    assert!((cl.inertia[0] - f * tpl.achieved.inertia_own).abs() < 1e-12 * cl.inertia[0]);
    // The mass centre is the placement point plus the rotated template centroid.
    let (s, c) = 0.5f64.sin_cos();
    let [gx, gy] = tpl.achieved.centroid;
    assert!((cl.x[0] - (10e-3 + c * gx - s * gy)).abs() < 1e-15);
    assert!((cl.y[0] - (5e-3 + s * gx + c * gy)).abs() < 1e-15);
    assert_eq!(cl.omega[0], 3.0);
    // Members: the clump's group, rigid-body velocity ω × r.
    let d = &w.state.discs;
    assert_eq!(d.len(), tpl.discs.len());
    for i in 0..d.len() {
        assert_eq!(d.group[i], 0);
        let (rx, ry) = (d.x[i] - cl.x[0], d.y[i] - cl.y[0]);
        assert!((d.vx[i] + 3.0 * ry).abs() < 1e-12 && (d.vy[i] - 3.0 * rx).abs() < 1e-12);
    }
    assert!(w.active_stages().contains(&"clumps"));
}

#[test]
fn bonded_clump_is_bonded_and_starts_force_free() {
    let tpl = clumpgen::Template::load(&templates().join("elongated-01.json")).unwrap();
    let mut v = base(
        json!({"clumps": [{"template": "", "material": "grain", "mode": "bonded",
        "bond_group": "intra", "placements": [{"x": 0, "y": 0, "angle": 1.0}]}]}),
    );
    v["bodies"]["clumps"][0]["template"] = templates()
        .join("elongated-01.json")
        .display()
        .to_string()
        .into();
    let mut w = world(&v, "bonded.json");
    let n = tpl.discs.len();
    assert_eq!(w.state.discs.len(), n);
    assert!(w.state.clumps.is_empty(), "a bonded clump is free discs");
    let b = w.bonds.as_ref().expect("bond stage");
    assert!(b.len() >= n - 1, "{} bonds for {n} members", b.len());
    assert!(b.iter().all(|v| v.group == 0));
    let m: f64 = w.state.discs.m.iter().sum();
    let want = tpl.achieved.mass * 2.0 * 2.0;
    assert!((m - want).abs() < 1e-12 * want, "{m} vs {want}");
    // Overlapping members are registered with their reference gaps: nothing moves.
    w.run(200);
    let vmax = w
        .state
        .discs
        .vx
        .iter()
        .chain(&w.state.discs.vy)
        .fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(vmax < 1e-12, "members move at {vmax} m/s");
    assert!(w.check().is_ok());
}

#[test]
fn auto_bonds_follow_groups_and_materials() {
    // Four touching discs in a row: groups 0, 0, 1, 1.
    let bodies = json!({"discs": [
        {"material": "grain", "group": 0, "discs": [[0, 0, 1], [2, 0, 1]]},
        {"material": "grain", "group": 1, "discs": [[4, 0, 1], [6, 0, 1]]}
    ]});
    let count = |between: &str| {
        let mut v = base(bodies.clone());
        v["auto_bonds"] = json!([{"bond_group": "gb", "tolerance": 1e-6, "between": between}]);
        let w = world(&v, &format!("auto-{between}.json"));
        let b = w.bonds.as_ref().unwrap();
        let pairs: Vec<(u32, u32)> = b
            .iter()
            .map(|v| {
                let (a, c) = (
                    w.state.discs.id[v.i as usize],
                    w.state.discs.id[v.j as usize],
                );
                (a.min(c), a.max(c))
            })
            .collect();
        assert!(b.iter().all(|v| v.group == 1));
        pairs
    };
    assert_eq!(count("all"), vec![(0, 1), (1, 2), (2, 3)]);
    assert_eq!(count("different_groups"), vec![(1, 2)]);
    let mut same = count("same_group");
    same.sort();
    assert_eq!(same, vec![(0, 1), (2, 3)]);
    // A gap larger than the tolerance is not bonded.
    let mut v = base(json!({"discs": [{"material": "grain", "discs": [[0, 0, 1], [2.01, 0, 1]]}]}));
    v["auto_bonds"] = json!([{"bond_group": "gb", "tolerance": 0.005}]);
    assert!(world(&v, "auto-gap.json").bonds.is_none());
    v["auto_bonds"][0]["tolerance"] = 0.02.into();
    assert_eq!(world(&v, "auto-gap2.json").bonds.unwrap().len(), 1);
}

#[test]
fn laws_table_holds_each_pair_law() {
    let v = json!({
        "schema": "dem.scene/1",
        "materials": [
            {"name": "sic", "density": 3100, "youngs_modulus": 430e9, "poisson": 0.14, "friction": 0.4, "restitution": 0.5, "rolling_friction": 0.1},
            {"name": "steel", "youngs_modulus": 210e9, "poisson": 0.3, "friction": 0.2, "restitution": 0.9, "kn": 1e8, "ks": 1e8},
            {"name": "unused", "kn": 1e20, "ks": 1e20}
        ],
        "contact": {"law": "hertz_mindlin", "rolling": true,
                    "pairs": [{"materials": ["steel", "sic"], "law": "linear_spring_dashpot", "kn": 3e8, "ks": 1e8}]},
        "bodies": {"discs": [{"material": "sic", "discs": [[0, 0, 0.001], [0.003, 0, 0.001]]}]},
        "walls": [{"name": "w", "a": [-1, -0.002], "b": [1, -0.002], "material": "steel"}],
        "run": {"steps": 1}
    });
    let s = load(&v, "laws.json");
    let w = scene::build(&s).unwrap();
    match w.laws.model(0, 0) {
        ContactModel::HertzMindlin(h) => {
            let e = 1.0 / (2.0 * (1.0 - 0.14 * 0.14) / 430e9);
            assert!((h.e_star - e).abs() < 1e-6 * e);
            assert_eq!((h.restitution, h.mu), (0.5, 0.4));
        }
        m => panic!("{m:?}"),
    }
    assert!(w.laws.rolling(0, 0).is_some_and(|r| r.mu_r == 0.1));
    match w.laws.model(0, 1) {
        ContactModel::Linear(l) => assert_eq!((l.kn, l.ks, l.mu), (3e8, 1e8, 0.2)),
        m => panic!("{m:?}"),
    }
    assert!(w.laws.rolling(0, 1).is_none());
    // The unused, absurdly stiff material does not shrink the time step.
    let mut v2 = v.clone();
    v2["materials"].as_array_mut().unwrap().pop();
    let w2 = scene::build(&load(&v2, "laws2.json")).unwrap();
    assert_eq!(w.dt(), w2.dt());
}

#[test]
fn loads_push_their_disc() {
    let mut v = base(json!({"discs": [{"material": "grain", "discs": [[0, 0, 1], [10, 0, 1]]}]}));
    v["loads"] = json!([{"disc": 1, "force": [2e-3, 0], "torque": 0}]);
    v["run"] = json!({"steps": 100, "dt": 1e-5});
    let mut w = world(&v, "loads.json");
    w.run(100);
    let k = w.index_of_id(1).unwrap();
    let a = 2e-3 / w.state.discs.m[k];
    let want = a * 100.0 * 1e-5;
    assert!(
        (w.state.discs.vx[k] - want).abs() < 1e-9 * want,
        "{} vs {want}",
        w.state.discs.vx[k]
    );
    assert_eq!(w.state.discs.vx[w.index_of_id(0).unwrap()], 0.0);
    v["loads"][0]["disc"] = 2.into();
    let dir = std::env::temp_dir().join(format!("dem-scene-build-{}", std::process::id()));
    let p = dir.join("loads-bad.json");
    std::fs::write(&p, v.to_string()).unwrap();
    let e = scene::load(&p).unwrap_err().to_string();
    assert!(
        e.contains("loads[0].disc") && e.contains("no disc 2"),
        "{e}"
    );
}

/// A lattice template (S3's crushable grain, `clumpgen.template/2`) in a bonded clump set: its
/// nodes become free discs, its links the set's bonds, and the grain starts force-free.
#[test]
fn a_lattice_grain_is_bonded_along_its_links() {
    use clumpgen::clump::LatticeParams;
    use clumpgen::{make_template, ClumpParams, Length, Method, ReadOptions};
    let text = "x,y\n0,0\n3,0\n3,2\n0,2\n";
    let ol = clumpgen::outline::parse_outline(text, "g", "g.csv", false, &ReadOptions::default())
        .unwrap();
    let p = ClumpParams {
        method: Method::Lattice,
        lattice: Some(LatticeParams {
            spacing: Length::Metres(0.25e-3),
            node_radius: 1.0,
        }),
        ..ClumpParams::default()
    };
    let tpl = make_template(&ol, &p).unwrap();
    let links = tpl.lattice.as_ref().unwrap().links.len();
    let dir = std::env::temp_dir().join(format!("dem-scene-build-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("lattice-grain.json");
    tpl.save(&file).unwrap();
    let mut v = base(
        json!({"clumps": [{"template": "", "material": "grain", "mode": "bonded",
        "bond_group": "gb", "placements": [{"x": 1, "y": 2, "angle": 0.4}]}]}),
    );
    v["bodies"]["clumps"][0]["template"] = file.display().to_string().into();
    let mut w = world(&v, "lattice.json");
    assert_eq!(w.state.discs.len(), tpl.discs.len());
    let b = w.bonds.as_ref().expect("bond stage");
    assert_eq!(b.len(), links);
    assert!(b.iter().all(|v| v.group == 1));
    w.run(200);
    let vmax = w
        .state
        .discs
        .vx
        .iter()
        .chain(&w.state.discs.vy)
        .fold(0.0f64, |a, v| a.max(v.abs()));
    assert!(vmax < 1e-9, "nodes move at {vmax} m/s");
    assert_eq!(w.bonds.as_ref().unwrap().n_intact(), links);
}
