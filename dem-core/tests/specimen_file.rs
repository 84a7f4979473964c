//! The specimen-file additions (`groups`, `mass_factors`, `rigid_clumps`, `bonds` with
//! `contact_offsets`) as a scene loads them, on a hand-written file; and bad files are errors
//! naming the field.

use dem_core::scene;
use serde_json::json;
use std::path::PathBuf;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-specimen-file-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene_with(spec: serde_json::Value, name: &str) -> Result<dem_core::World, String> {
    let d = dir(name);
    std::fs::write(d.join("spec.json"), spec.to_string()).unwrap();
    let sc = json!({
        "schema": "dem.scene/1",
        "units": "mm",
        "thickness": 2.0,
        "materials": [{"name": "Si3N4", "density": 3200, "kn": 1e6, "ks": 4e5, "friction": 0.5}],
        "bond_groups": [
            {"name": "grain_boundary", "model": "parallel_potyondy2004", "criterion": "stress",
             "kn": 1e15, "ks": 4e14, "tensile_strength": 1e9, "cohesion": 1e9},
            {"name": "intra_grain", "model": "parallel_potyondy2004", "criterion": "stress",
             "kn": 1e15, "ks": 4e14, "tensile_strength": 2e9, "cohesion": 2e9}
        ],
        "bodies": {"specimens": [{"file": "spec.json", "offset": [1, 0]}]},
        "run": {"steps": 10}
    });
    let p = d.join("scene.json");
    std::fs::write(&p, sc.to_string()).unwrap();
    let s = scene::load(&p).map_err(|e| e.to_string())?;
    scene::build(&s).map_err(|e| e.to_string())
}

/// Four discs (mm): 0 and 1 a rigid ORC grain, 2 and 3 overlapping members of a bonded grain.
fn spec() -> serde_json::Value {
    json!({
        "schema": "dem.specimen/1",
        "units": "mm",
        "discs": [{
            "material": "Si3N4",
            "discs": [[0, 0, 1], [1.5, 0, 0.5], [4, 0, 1], [5.5, 0, 0.8]],
            "groups": [7, 7, 8, 8],
            "mass_factors": [1, 1, 0.6, 1.7]
        }],
        "rigid_clumps": [[0, 1]],
        "bonds": [
            {"bond_group": "grain_boundary", "pairs": [[1, 2]]},
            {"bond_group": "intra_grain", "pairs": [[2, 3]], "contact_offsets": [-0.3]}
        ]
    })
}

#[test]
fn groups_masses_rigid_clumps_bonds_and_offsets_load() {
    let w = scene_with(spec(), "ok").unwrap_or_else(|e| panic!("{e}"));
    let d = &w.state.discs;
    let k = |id: u32| w.index_of_id(id).unwrap();
    let uniform = |r: f64| 3200.0 * 2e-3 * std::f64::consts::PI * r * r;
    // Groups and mass factors (× ρ t π r²), inertia m r²/2; positions shifted by the offset.
    assert_eq!(d.group[k(0)], 7);
    assert_eq!(d.group[k(3)], 8);
    assert!((d.m[k(2)] - 0.6 * uniform(1e-3)).abs() <= 1e-12 * d.m[k(2)]);
    assert!((d.m[k(3)] - 1.7 * uniform(0.8e-3)).abs() <= 1e-12 * d.m[k(3)]);
    assert!((d.inertia[k(3)] - 0.5 * d.m[k(3)] * 0.64e-6).abs() <= 1e-12 * d.inertia[k(3)]);
    assert!((d.x[k(2)] - 5e-3).abs() < 1e-15);
    // The rigid clump has the ORC sums of its two members.
    let cl = &w.state.clumps;
    assert_eq!(cl.len(), 1);
    let (m0, m1) = (uniform(1e-3), uniform(0.5e-3));
    assert!((cl.m[0] - (m0 + m1)).abs() <= 1e-12 * cl.m[0]);
    let xc = (m0 * 1e-3 + m1 * 2.5e-3) / (m0 + m1);
    let i = 0.5 * m0 * 1e-6
        + m0 * (1e-3 - xc).powi(2)
        + 0.5 * m1 * 0.25e-6
        + m1 * (2.5e-3 - xc).powi(2);
    assert!((cl.x[0] - xc).abs() < 1e-15 && (cl.inertia[0] - i).abs() <= 1e-12 * i);
    // Two bonds, one per group; the overlapping members' reference gap is registered, so their
    // 0.3 mm overlap exerts no contact force.
    let b = w.bonds.as_ref().unwrap();
    assert_eq!(b.len(), 2);
    let names = b.group_names();
    let groups: Vec<&str> = b.iter().map(|v| names[v.group as usize].as_str()).collect();
    assert!(groups.contains(&"grain_boundary") && groups.contains(&"intra_grain"));
    let members: Vec<f64> = w
        .contacts()
        .filter(|c| (c.id_i.min(c.id_j), c.id_i.max(c.id_j)) == (2, 3))
        .map(|c| c.overlap)
        .collect();
    for overlap in members {
        assert!(overlap < 1e-9, "overlap beyond the reference gap {overlap}");
    }
}

#[test]
fn bad_specimen_files_name_the_field() {
    let cases = [
        ("/bonds/0/pairs/0/1", json!(9), "bonds[0].pairs[0][1]"),
        (
            "/discs/0/mass_factors",
            json!([1, 1]),
            "discs[0].mass_factors",
        ),
        ("/discs/0/groups", json!([1]), "discs[0].groups"),
        (
            "/rigid_clumps",
            json!([[0, 1], [1, 2]]),
            "rigid_clumps[1][0]",
        ),
        (
            "/bonds/1/contact_offsets",
            json!([-0.3, 0]),
            "bonds[1].contact_offsets",
        ),
        (
            "/bonds/0/bond_group",
            json!("cement"),
            "bonds[0].bond_group",
        ),
        ("/bonds/0/pairs/0", json!([2, 2]), "bonds[0].pairs[0]"),
        (
            "/discs/0/mass_factors/1",
            json!(-1),
            "discs[0].mass_factors[1]",
        ),
    ];
    for (k, (ptr, value, field)) in cases.into_iter().enumerate() {
        let mut s = spec();
        *s.pointer_mut(ptr).unwrap() = value;
        let e = scene_with(s, &format!("bad{k}"))
            .err()
            .unwrap_or_else(|| panic!("{ptr} accepted"));
        assert!(e.contains(field) && e.contains("spec.json"), "{ptr}: {e}");
    }
}
