//! The fuzz targets' bodies, one function per reader. Each takes any bytes and must return
//! without panicking; `fuzz_targets/*.rs` hand them to libFuzzer (`cargo +nightly fuzz run
//! <target>`), and `validation/tests/fuzz_regressions.rs` includes this file to replay the seed
//! corpus and every input a fuzzer once crashed on (`regressions/<target>/`) on stable Rust,
//! in CI.
//!
//! Targets: [`outline`], [`template`], [`scene`], [`checkpoint`], [`history`], [`study`].

use std::path::Path;

/// Seed inputs that the project already holds, per target, relative to the repository root
/// (`fuzz/corpus/<target>/` adds the ones it does not: checkpoints and histories). Run a
/// fuzzer with them as extra corpus folders: `cargo +nightly fuzz run outline NEW_DIR
/// ../data/outlines`.
pub const SEEDS: [(&str, &str); 4] = [
    ("outline", "data/outlines"),
    ("template", "examples/scenes/templates"),
    ("scene", "examples/scenes"),
    ("study", "data/studies"),
];

/// A fuzz target's body: any bytes in, no panic.
pub type Target = fn(&[u8]);

/// The targets by name, as `fuzz_targets/` and the corpus folders name them.
pub const TARGETS: [(&str, Target); 6] = [
    ("outline", outline),
    ("template", template),
    ("scene", scene),
    ("checkpoint", checkpoint),
    ("history", history),
    ("study", study),
];

/// Outline text (CSV/whitespace columns, or JSON) → outline → improved-ORC template with a
/// small disc budget: an outline error, a clump error or a template whose discs are finite.
pub fn outline(data: &[u8]) {
    use clumpgen::outline::{parse_outline, ReadOptions};
    use clumpgen::{make_template, ClumpParams};
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let json = text.trim_start().starts_with('{');
    let Ok(outline) = parse_outline(text, "fuzz", "fuzz.txt", json, &ReadOptions::default()) else {
        return;
    };
    if outline.points.len() > 2_000 {
        return;
    }
    let p = ClumpParams {
        max_discs: 16,
        ..ClumpParams::default()
    };
    if let Ok(t) = make_template(&outline, &p) {
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

/// Checkpoint JSON → checkpoint (checksum, schema, world) → three steps of its world. A
/// checkpoint without a checksum field is read (older files), so mutations reach the world.
pub fn checkpoint(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(c) = dem_core::checkpoint::parse(text, "fuzz.json") else {
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
        let _ = dem_core::lab::history::Table::parse(text);
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
    if let Ok(s) = validation::study::StudySpec::read(&file) {
        let _ = s.jobs(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../data"));
    }
}
