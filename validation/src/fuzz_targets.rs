//! The fuzz targets' bodies, one function per reader. Each takes any bytes and must return
//! without panicking; `fuzz/fuzz_targets/*.rs` hand them to libFuzzer (`cargo +nightly fuzz
//! run <target>`; the fuzz crate re-exports this module), and
//! `validation/tests/fuzz_regressions.rs` calls them to replay the seed corpus and every input
//! a fuzzer once crashed on (`fuzz/regressions/<target>/`) on stable Rust, in CI.
//!
//! Targets: [`outline`], [`grains`], [`template`], [`scene`], [`specimen`], [`checkpoint`],
//! [`history`], [`study`], [`sweep`].

use std::path::Path;

/// Seed inputs that the project already holds, per target, relative to the repository root
/// (`fuzz/corpus/<target>/` adds the ones it does not: checkpoints and histories). Run a
/// fuzzer with them as extra corpus folders: `cargo +nightly fuzz run outline NEW_DIR
/// ../data/outlines`.
pub const SEEDS: [(&str, &str); 6] = [
    ("outline", "data/outlines"),
    ("template", "examples/scenes/templates"),
    ("scene", "examples/scenes"),
    ("study", "data/studies"),
    ("sweep", "examples/studies"),
    ("sweep", "data/studies"),
];

/// A fuzz target's body: any bytes in, no panic.
pub type Target = fn(&[u8]);

/// The targets by name, as `fuzz_targets/` and the corpus folders name them.
pub const TARGETS: [(&str, Target); 9] = [
    ("outline", outline),
    ("grains", grains),
    ("template", template),
    ("scene", scene),
    ("specimen", specimen),
    ("checkpoint", checkpoint),
    ("history", history),
    ("study", study),
    ("sweep", sweep),
];

/// Outline text (CSV/whitespace columns, or JSON) → outline → improved-ORC template with a
/// small disc budget: an outline error, a clump error or a template whose discs are finite.
pub fn outline(data: &[u8]) {
    use clumpgen::outline::{parse_outline, ReadOptions};
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let json = text.trim_start().starts_with('{');
    let Ok(outline) = parse_outline(text, "fuzz", "fuzz.txt", json, &ReadOptions::default()) else {
        return;
    };
    template_of(&outline);
}

/// A multi-grain file: the first byte picks the kind (PNG or TIFF mask or label image at 1 µm
/// per pixel, GeoJSON or WKT in mm), the rest is the file → its grains (`read_grains`, as
/// `dem clump` reads them) → an improved-ORC template of each grain of up to 2,000 points.
pub fn grains(data: &[u8]) {
    use clumpgen::outline::{read_grains, GrainOptions, ReadOptions};
    use clumpgen::Units;
    let Some((&kind, rest)) = data.split_first() else {
        return;
    };
    let (ext, units) = match kind % 4 {
        0 => (
            "png",
            Units::Px {
                metres_per_px: 1e-6,
            },
        ),
        1 => (
            "tif",
            Units::Px {
                metres_per_px: 1e-6,
            },
        ),
        2 => ("geojson", Units::Mm),
        _ => ("wkt", Units::Mm),
    };
    let dir = std::env::temp_dir().join(format!("dem-fuzz-grains-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let file = dir.join(format!("grains.{ext}"));
    if std::fs::write(&file, rest).is_err() {
        return;
    }
    let opts = ReadOptions {
        units: Some(units),
        ..ReadOptions::default()
    };
    let Ok(found) = read_grains(&file, &opts, &GrainOptions::default()) else {
        return;
    };
    for g in found.grains {
        if let Ok(o) = g.outline {
            template_of(&o);
        }
    }
}

/// An improved-ORC template of `outline` with a small disc budget (outlines of more than
/// 2,000 points are left out: linear work the fuzzer need not repeat): its discs are finite.
fn template_of(outline: &clumpgen::Outline) {
    use clumpgen::{make_template, ClumpParams};
    if outline.points.len() > 2_000 {
        return;
    }
    let p = ClumpParams {
        max_discs: 16,
        ..ClumpParams::default()
    };
    if let Ok(t) = make_template(outline, &p) {
        for d in &t.discs {
            assert!(d.r.is_finite() && d.r > 0.0, "template disc radius {}", d.r);
            assert!(d.x.is_finite() && d.y.is_finite(), "template disc centre");
        }
    }
}

/// Template JSON → template, or an error naming the file and field.
pub fn template(data: &[u8]) {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = clumpgen::Template::from_json(text, "fuzz.json");
    }
}

/// Scene JSON → checked scene → World → three steps (scenes of up to 5,000 discs). Relative
/// paths resolve against a folder that does not exist, so file references fail cleanly.
pub fn scene(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scene) = dem_core::scene::parse(text, Path::new("/nonexistent-fuzz/scene.json")) else {
        return;
    };
    let Ok(mut world) = dem_core::scene::build(&scene) else {
        return;
    };
    if world.state.discs.len() <= 5_000 {
        for _ in 0..3 {
            world.step();
        }
    }
}

/// The scene a [`specimen`] file is loaded with: the one `dem specimen` writes beside its
/// specimens (material Si3N4, its two bond groups), three steps, no outputs.
const SPECIMEN_SCENE: &str = r#"{"schema": "dem.scene/1", "name": "fuzz", "units": "m",
  "thickness": 1.0, "run": {"steps": 3}, "damping": {"local": 0.7},
  "materials": [{"name": "Si3N4", "density": 3200.0, "kn": 6.2e11, "ks": 2.48e11,
                 "friction": 0.5, "damping_ratio": 0.0}],
  "bond_groups": [
    {"name": "grain_boundary", "model": "parallel_potyondy2004", "criterion": "stress",
     "kn": 1.19e15, "ks": 4.77e14, "radius_multiplier": 1.0, "moment_factor": 1.0,
     "tensile_strength": 8e8, "cohesion": 8e8, "friction_angle": 0.0},
    {"name": "intra_grain", "model": "parallel_potyondy2004", "criterion": "stress",
     "kn": 1.19e15, "ks": 4.77e14, "radius_multiplier": 1.0, "moment_factor": 1.0,
     "tensile_strength": 1.6e9, "cohesion": 1.6e9, "friction_angle": 0.0}],
  "bodies": {"specimens": [{"file": "specimen.json"}]}}"#;

/// Specimen file (`dem.specimen/1`: disc sets, rigid clumps, bond lists with their contact
/// offsets) → the scene above loads it → World → three steps (up to 5,000 discs); and the
/// cutting test's reader of its geometry (`SpecimenInfo::read`).
pub fn specimen(data: &[u8]) {
    let dir = std::env::temp_dir().join(format!("dem-fuzz-specimen-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let (file, scene_file) = (dir.join("specimen.json"), dir.join("scene.json"));
    if std::fs::write(&file, data).is_err() || std::fs::write(&scene_file, SPECIMEN_SCENE).is_err()
    {
        return;
    }
    let _ = dem_lab::cutting::SpecimenInfo::read(&file);
    let Ok(scene) = dem_core::scene::load(&scene_file) else {
        return;
    };
    let Ok(mut world) = dem_core::scene::build(&scene) else {
        return;
    };
    if world.state.discs.len() <= 5_000 {
        for _ in 0..3 {
            world.step();
        }
    }
}

/// Checkpoint, JSON or binary (`checkpoint::parse_bytes`) → checkpoint (checksum, schema,
/// world) → three steps of its world. A JSON checkpoint without a checksum field is read
/// (older files), so mutations reach the world; a binary one (magic `DEMCKPT\0`) gets its
/// checksum (bytes 80..112: SHA-256 of the rest) recomputed here, so mutations reach its
/// section lengths and MessagePack sections instead of stopping at the checksum.
pub fn checkpoint(data: &[u8]) {
    use sha2::{Digest, Sha256};
    let mut bytes = data.to_vec();
    if bytes.starts_with(b"DEMCKPT\0") && bytes.len() >= 136 {
        let mut h = Sha256::new();
        h.update(&bytes[..80]);
        h.update(&bytes[112..]);
        let sum = h.finalize();
        bytes[80..112].copy_from_slice(&sum);
    }
    let Ok(c) = dem_core::checkpoint::parse_bytes(&bytes, "fuzz") else {
        return;
    };
    let mut world = c.world;
    if world.state.discs.len() <= 5_000 {
        for _ in 0..3 {
            world.step();
        }
    }
}

/// history.csv text → table, or an error with its line.
pub fn history(data: &[u8]) {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = dem_lab::history::Table::parse(text);
    }
}

/// validation's study file (data/studies/*.json) → checked study → its jobs (on the
/// project's data folder).
pub fn study(data: &[u8]) {
    let dir = std::env::temp_dir().join(format!("dem-fuzz-study-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let file = dir.join("study.json");
    if std::fs::write(&file, data).is_err() {
        return;
    }
    if let Ok(s) = crate::study::StudySpec::read(&file) {
        let _ = s.jobs(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../data"));
    }
}

/// `dem sweep`'s study file (examples/studies, data/studies/*.sweep.json) → checked study →
/// its axes' values (the plan's own checks against the test's flags are not reached).
pub fn sweep(data: &[u8]) {
    let _ = dem_run::study::parse(data, Path::new("fuzz.sweep.json"));
}
