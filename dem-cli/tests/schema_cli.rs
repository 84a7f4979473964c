//! `dem schema`: the committed docs/schema/*.schema.json equal what `dem schema <kind>` prints;
//! every shipped example (scenes, templates, studies, the cutting tests recorded in the report)
//! and the specimen and scene `dem specimen` writes validate against their schema; hand-made
//! bad files are rejected by the schema and, where it reads them at once, by `dem` itself.

use serde_json::{json, Value};
use std::path::{Path, PathBuf};

mod common;
use common::{dem, text, tmp};

const KINDS: [&str; 6] = [
    "scene",
    "template",
    "specimen",
    "study",
    "cutting-params",
    "law",
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The schema `dem schema <kind>` prints, as text.
fn printed(kind: &str) -> String {
    let o = dem(&["schema", kind]);
    assert!(o.status.success(), "dem schema {kind}: {}", text(&o));
    String::from_utf8(o.stdout).unwrap()
}

fn validator(kind: &str) -> jsonschema::Validator {
    let schema: Value = serde_json::from_str(&printed(kind)).unwrap();
    jsonschema::validator_for(&schema)
        .unwrap_or_else(|e| panic!("dem schema {kind} is not a valid JSON Schema: {e}"))
}

fn read(path: &Path) -> Value {
    let t = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&t).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The schema's complaints about `v` (file name, JSON path, message), empty when valid.
fn errors(v: &jsonschema::Validator, what: &str, instance: &Value) -> Vec<String> {
    v.iter_errors(instance)
        .map(|e| format!("{what}: at {}: {e}", e.instance_path()))
        .collect()
}

fn assert_valid(v: &jsonschema::Validator, path: &Path) {
    let e = errors(v, &path.display().to_string(), &read(path));
    assert!(e.is_empty(), "{}", e.join("\n"));
}

/// The `.json` files of a folder, sorted (at least one).
fn json_files(dir: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no .json files in {dir}");
    v
}

#[test]
fn committed_schemas_equal_what_dem_schema_prints() {
    for kind in KINDS {
        let file = root().join(format!("docs/schema/{kind}.schema.json"));
        let committed = std::fs::read_to_string(&file).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; write it with scripts/write-schemas.sh",
                file.display()
            )
        });
        let now = printed(kind);
        assert!(
            committed == now,
            "docs/schema/{kind}.schema.json differs from `dem schema {kind}` (the types changed): \
             regenerate with scripts/write-schemas.sh (or `dem schema {kind} > \
             docs/schema/{kind}.schema.json`)"
        );
        // A real schema of an object, of the draft it says, with the title naming the file.
        let s: Value = serde_json::from_str(&now).unwrap();
        assert_eq!(s["$schema"], "https://json-schema.org/draft/2020-12/schema");
        assert_eq!(s["type"], "object", "{kind}");
        assert!(s["title"].as_str().unwrap().contains(')'), "{kind}");
        jsonschema::validator_for(&s).unwrap();
    }
}

#[test]
fn list_and_unknown_kind() {
    let o = dem(&["schema", "--list"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = String::from_utf8(o.stdout).unwrap();
    let names: Vec<&str> = out
        .lines()
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(names, KINDS, "{out}");

    let o = dem(&["schema", "scenery"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("scenery"), "{err}");
    for kind in KINDS {
        assert!(err.contains(kind), "the usage error names {kind}: {err}");
    }
    let o = dem(&["schema"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

#[test]
fn shipped_examples_validate() {
    let scene = validator("scene");
    for f in json_files("examples/scenes") {
        assert_valid(&scene, &f);
    }
    let template = validator("template");
    for f in json_files("examples/scenes/templates") {
        assert_valid(&template, &f);
    }
    let study = validator("study");
    for f in json_files("examples/studies") {
        assert_valid(&study, &f);
    }
    // The cutting tests recorded in the report's results (`test`: a CuttingTest as written),
    // the cases of its convergence folder.
    let cutting = validator("cutting-params");
    let runs = root().join("docs/report/convergence-runs/cases");
    let mut n = 0;
    for d in std::fs::read_dir(&runs).unwrap() {
        let f = d.unwrap().path().join("cutting.result.json");
        if f.exists() {
            let e = errors(&cutting, &f.display().to_string(), &read(&f)["test"]);
            assert!(e.is_empty(), "{}", e.join("\n"));
            n += 1;
        }
    }
    assert!(n > 0, "no cutting.result.json under {}", runs.display());
}

#[test]
fn files_dem_specimen_writes_validate() {
    let dir = tmp("specimen");
    let material = root().join("data/materials/si3n4.json");
    let out = dir.join("spec.json");
    let o = dem(&[
        "specimen",
        "--method",
        "traditional",
        "--width",
        "3mm",
        "--height",
        "1.5mm",
        "--r-min",
        "0.1mm",
        "--r-max",
        "0.16mm",
        "--seed",
        "3",
        "--material",
        material.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let spec = read(&out);
    assert!(!spec["discs"][0]["discs"].as_array().unwrap().is_empty());
    assert_valid(&validator("specimen"), &out);
    assert_valid(&validator("scene"), &dir.join("spec.scene.json"));
    // A specimen is not a scene, and the other way round.
    assert!(!validator("scene").is_valid(&spec));
    assert!(!validator("specimen").is_valid(&read(&dir.join("spec.scene.json"))));
    std::fs::remove_dir_all(&dir).ok();
}

/// A small scene `dem run` accepts, with every top-level object present.
fn good_scene() -> Value {
    json!({
        "schema": "dem.scene/1",
        "units": "mm",
        "thickness": null,
        "materials": [{"name": "glass", "density": 2500.0, "kn": 1e6, "ks": 1e6,
                       "restitution": 0.9}],
        "contact": {"law": "linear_spring_dashpot"},
        "bodies": {"discs": [{"material": "glass", "discs": [[0.0, 0.0, 1.0], [3.0, 0.0, 1.0]],
                              "velocity": [1.0, 0.0]}]},
        "walls": [{"name": "floor", "a": [-5.0, -2.0], "b": [5.0, -2.0], "material": "glass"}],
        "damping": {"local": 0.1},
        "run": {"steps": 3, "stop_after_peak": {"walls": ["floor"], "axis": "y", "below": 0.5}},
        "outputs": {"history_every": 1, "summary": false, "gauges":
                    [{"name": "g", "region": [-1.0, -1.0, 1.0, 1.0]}]}
    })
}

/// Writes `v` as `<dir>/<name>` and returns the path.
fn write(dir: &Path, name: &str, v: &Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    p
}

#[test]
fn bad_scenes_are_rejected_by_schema_and_dem() {
    let scene = validator("scene");
    let dir = tmp("scenes");
    let good = good_scene();
    assert!(errors(&scene, "good", &good).is_empty());
    let ok = dem(&["run", write(&dir, "good.json", &good).to_str().unwrap()]);
    assert!(ok.status.success(), "{}", text(&ok));

    // (case, edit, JSON path the schema names, text `dem run` names)
    type Edit = fn(&mut Value);
    let cases: [(&str, Edit, &str, &str); 6] = [
        (
            "unknown-top",
            |v| v["colour"] = json!("red"),
            "",
            "unknown field `colour`",
        ),
        (
            "unknown-nested",
            |v| v["bodies"]["discs"][0]["colour"] = json!("red"),
            "/bodies/discs/0",
            "bodies.discs[0]",
        ),
        (
            "wrong-type",
            |v| v["thickness"] = json!("5mm"),
            "/thickness",
            "thickness",
        ),
        (
            "disc-of-two",
            |v| v["bodies"]["discs"][0]["discs"][1] = json!([3.0, 0.0]),
            "/bodies/discs/0/discs/1",
            "bodies.discs[0].discs[1]",
        ),
        ("bad-enum", |v| v["units"] = json!("cm"), "/units", "units"),
        (
            "wrong-schema",
            |v| v["schema"] = json!("dem.specimen/1"),
            "/schema",
            "expected \"dem.scene/1\"",
        ),
    ];
    for (name, edit, at, says) in cases {
        let mut v = good.clone();
        edit(&mut v);
        let e = errors(&scene, name, &v);
        assert!(!e.is_empty(), "{name}: the schema accepts it");
        assert!(
            e.iter()
                .any(|m| m.starts_with(&format!("{name}: at {at}:"))),
            "{name}: expected an error at {at:?}: {e:?}"
        );
        let p = write(&dir, &format!("{name}.json"), &v);
        let o = dem(&["run", p.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{name}: dem run: {}", text(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&format!("{name}.json")) && err.contains(says),
            "{name}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn templates_specimens_and_cutting_params_bad_and_good() {
    let template = validator("template");
    let shipped = read(&root().join("examples/scenes/templates/equant-01.json"));
    for (name, edit) in [
        (
            "mass as text",
            json!({"discs": [{"x": 0.0, "y": 0.0, "r": 1e-4, "m": "1g"}]}),
        ),
        ("no discs", json!({"discs": null})),
        ("unknown method", json!({"method": "voronoi"})),
        ("other schema", json!({"schema": "clumpgen.template/3"})),
    ] {
        let mut v = shipped.clone();
        for (k, x) in edit.as_object().unwrap() {
            v[k] = x.clone();
        }
        assert!(!template.is_valid(&v), "template with {name} accepted");
    }
    // Templates are read without refusing unknown fields, and so is their schema.
    let mut extra = shipped.clone();
    extra["note"] = json!("hand-added");
    assert!(template.is_valid(&extra));

    let specimen = validator("specimen");
    let good = json!({"schema": "dem.specimen/1", "units": "mm",
        "discs": [{"material": "m", "discs": [[0.0, 0.0, 0.1], [0.2, 0.0, 0.1]],
                   "groups": [1, 2], "mass_factors": [1.0, 0.9]}],
        "rigid_clumps": [[0, 1]],
        "bonds": [{"bond_group": "b", "pairs": [[0, 1]], "contact_offsets": [-0.01]}]});
    assert!(errors(&specimen, "specimen", &good).is_empty());
    for (name, at, edit) in [
        (
            "negative index",
            "/rigid_clumps/0/0",
            json!({"rigid_clumps": [[-1, 1]]}),
        ),
        (
            "unknown field",
            "/bonds/0",
            json!({"bonds": [{"bond_group": "b", "pairs": [], "gaps": []}]}),
        ),
        (
            "pair of three",
            "/bonds/0/pairs/0",
            json!({"bonds": [{"bond_group": "b", "pairs": [[0, 1, 2]]}]}),
        ),
    ] {
        let mut v = good.clone();
        for (k, x) in edit.as_object().unwrap() {
            v[k] = x.clone();
        }
        let e = errors(&specimen, name, &v);
        assert!(
            e.iter()
                .any(|m| m.starts_with(&format!("{name}: at {at}:"))),
            "{name}: {e:?}"
        );
    }

    let cutting = validator("cutting-params");
    assert!(cutting.is_valid(&json!({})), "every field has a default");
    assert!(cutting.is_valid(&json!({"depth": 5e-4, "tool": "segments", "delete_fragments": true})));
    for (name, v) in [
        ("unknown field", json!({"depht": 5e-4})),
        ("unit-bearing length", json!({"depth": "0.5mm"})),
        ("unknown tool", json!({"tool": "round"})),
        ("negative count", json!({"history_rows": -1})),
    ] {
        assert!(
            !cutting.is_valid(&v),
            "cutting params with {name} accepted: {v}"
        );
    }
}

#[test]
fn study_files_bad_and_good() {
    let study = validator("study");
    let dir = tmp("studies");
    let shipped = read(&root().join("examples/studies/cutting-demo.json"));
    // The shipped study files of Table 2 and the speed study (a `sets` axis).
    for f in [
        "data/studies/table2.sweep.json",
        "data/studies/table2-mass-scaled.sweep.json",
        "data/studies/table2-mass-scaled-check.sweep.json",
        "data/studies/table2-mass-scaled-b05.sweep.json",
        "data/studies/table2-mass-scaled-check-b05.sweep.json",
        "data/studies/table2-two-orc-cases.sweep.json",
        "data/studies/speed-damping.sweep.json",
    ] {
        let v = read(&root().join(f));
        assert!(
            errors(&study, f, &v).is_empty(),
            "{f}: {:?}",
            errors(&study, f, &v)
        );
    }
    // Forms the reader takes: a range, a seed range, `null` for an absent list, zip.
    let mut good = shipped.clone();
    good["combine"] = json!("zip");
    good["axes"] = json!([
        {"flag": "depth", "range": {"from": 0.3, "to": 0.4, "steps": 2, "unit": "mm"},
         "values": null},
        {"seeds": {"from": 1, "to": 2}}
    ]);
    assert!(
        errors(&study, "good", &good).is_empty(),
        "{:?}",
        errors(&study, "good", &good)
    );

    let cases: [(&str, Value, &str); 6] = [
        (
            "unknown-field",
            json!({"comment": "x"}),
            "unknown field `comment`",
        ),
        (
            "unknown-test",
            json!({"base": {"test": "shear", "flags": {}}}),
            "base.test",
        ),
        (
            "list-flag",
            json!({"base": {"test": "cutting", "flags": {"width": ["3mm"]}}}),
            "width",
        ),
        (
            "two-kinds",
            json!({"axes": [{"flag": "depth", "values": ["1mm"], "seeds": [1]}]}),
            "give exactly one of values, range, seeds",
        ),
        (
            "seed-range-field",
            json!({"axes": [{"seeds": {"from": 1, "to": 2, "by": 1}}]}),
            "unknown field `by`",
        ),
        (
            "negative-seed",
            json!({"axes": [{"seeds": [1, -2]}]}),
            "not a seed",
        ),
    ];
    for (name, edit, says) in cases {
        let mut v = shipped.clone();
        for (k, x) in edit.as_object().unwrap() {
            v[k] = x.clone();
        }
        assert!(!study.is_valid(&v), "{name}: the schema accepts {v}");
        // The study names its material relative to its own folder: keep that working.
        v["base"]["flags"]["material"] = json!(root().join("data/materials/si3n4.json"));
        let p = write(&dir, &format!("{name}.json"), &v);
        let o = dem(&[
            "sweep",
            "plan",
            p.to_str().unwrap(),
            "--out",
            dir.join(name).to_str().unwrap(),
        ]);
        assert_eq!(
            o.status.code(),
            Some(2),
            "{name}: dem sweep plan: {}",
            text(&o)
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&format!("{name}.json")) && err.contains(says),
            "{name}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
