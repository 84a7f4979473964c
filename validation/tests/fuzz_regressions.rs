//! Replays the fuzz targets' seeds (the project's own files, `SEEDS`, and `fuzz/corpus/<target>/`)
//! and every input a fuzzer
//! once crashed on (`fuzz/regressions/<target>/`, kept after the fix) through the targets'
//! own bodies (`validation::fuzz_targets`, which the fuzz crate re-exports, so stable `cargo
//! test` runs them in CI without libFuzzer): none may panic. docs/reliability.md, "Fuzzing".

use validation::fuzz_targets as targets;

use std::path::Path;

#[test]
fn every_seed_and_every_former_crash_is_handled() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut n = 0;
    let mut regressions = 0;
    for (name, target) in targets::TARGETS {
        let seeds = targets::SEEDS.iter().filter(|(t, _)| *t == name);
        let folders = seeds.map(|(_, d)| ("seeds", repo.join(d))).chain([
            ("corpus", repo.join("fuzz/corpus").join(name)),
            ("regressions", repo.join("fuzz/regressions").join(name)),
        ]);
        for (kind, folder) in folders {
            let Ok(dir) = std::fs::read_dir(&folder) else {
                continue;
            };
            let mut files: Vec<_> = dir
                .filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .collect();
            files.sort();
            for f in files {
                let data = std::fs::read(&f).unwrap();
                let r = std::panic::catch_unwind(|| target(&data));
                assert!(r.is_ok(), "{name}: {} panicked", f.display());
                n += 1;
                regressions += usize::from(kind == "regressions");
            }
        }
    }
    assert!(n >= 40, "only {n} inputs found: the corpus is missing");
    assert!(regressions >= 1, "the former crashes are missing");
}
