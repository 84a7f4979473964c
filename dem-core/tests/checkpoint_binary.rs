//! Binary checkpoints (issue 20): a restart from one continues bit-identically; a flipped
//! byte, a truncated file, a wrong scene and hostile length fields are refused naming the
//! file, without a panic or a huge allocation; checkpoints can be turned off; JSON ones still
//! load and the keep logic counts both formats.

use dem_core::checkpoint::{self, Format, HEADER_LEN, MAGIC};
use dem_core::output::driver::{numbered_checkpoints, prune_checkpoints, RunOptions, Simulation};
use dem_core::scene::{self, model::Scene};
use sha2::{Digest, Sha256};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Records the largest single allocation of this test binary (hostile lengths must not ask
/// for gigabytes).
struct Largest;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every method forwards to the system allocator with the caller's arguments
// unchanged (it only records sizes), so `System`'s guarantees hold.
unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        LARGEST.fetch_max(l.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract for `alloc` is passed on unchanged.
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        // SAFETY: `p` was allocated by `System` with layout `l` (every allocation here is).
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        LARGEST.fetch_max(new, Ordering::Relaxed);
        // SAFETY: as for `dealloc`; the caller's contract for `realloc` is passed on.
        unsafe { System.realloc(p, l, new) }
    }
}

#[global_allocator]
static ALLOC: Largest = Largest;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-ckpt-bin-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The settling clumps (rigid and bonded clumps, walls, gravity, damping): every kind of state.
fn scene_with(format: Format, every: u64, keep: u32) -> Scene {
    let mut s = scene::load(&examples().join("clumps-settling.json")).unwrap();
    s.outputs.checkpoint_format = format;
    s.outputs.checkpoint_every = every;
    s.outputs.checkpoint_keep = keep;
    s
}

fn run(s: Scene, out: &Path, max_steps: u64, restart: Option<PathBuf>) {
    let opts = RunOptions {
        out_dir: Some(out.to_path_buf()),
        max_steps: Some(max_steps),
        restart,
    };
    let mut sim = Simulation::new(s, &opts).unwrap();
    sim.run(&mut |_, _| {}).unwrap();
}

/// A checkpoint's content without the run totals (wall and CPU time differ between runs).
fn content(c: &checkpoint::Checkpoint) -> String {
    format!(
        "{}|{}|{}|{}",
        c.scene_hash,
        c.history_rows,
        serde_json::to_string(&c.snapshots).unwrap(),
        serde_json::to_string(&c.world).unwrap()
    )
}

fn read(p: &Path) -> checkpoint::Checkpoint {
    checkpoint::parse_bytes(&std::fs::read(p).unwrap(), &p.display().to_string()).unwrap()
}

#[test]
fn binary_restart_continues_bit_identically_and_keep_counts_both_formats() {
    let n = 400;
    let (a, b, c) = (tmp("a"), tmp("b"), tmp("c"));
    // Uninterrupted, JSON.
    run(scene_with(Format::Json, 0, 0), &a, 2 * n, None);
    // First half in binary, a numbered checkpoint every 100 steps, the newest kept.
    run(scene_with(Format::Binary, 100, 1), &b, n, None);
    let numbered = numbered_checkpoints(&b).unwrap();
    assert_eq!(numbered.len(), 1, "{numbered:?}");
    let (step, ck) = numbered[0].clone();
    assert_eq!(step, n);
    assert!(
        ck.extension().is_some_and(|e| e == "bin"),
        "{}",
        ck.display()
    );
    assert!(b.join("ckpt-final.bin").exists() && !b.join("ckpt-final.json").exists());
    let bytes = std::fs::read(&ck).unwrap();
    assert!(bytes.starts_with(&MAGIC));
    std::fs::create_dir_all(&c).unwrap();
    std::fs::copy(&ck, c.join("half.bin")).unwrap();
    // Second half from the binary checkpoint, written as JSON (keep 1 counts both formats:
    // the older .bin goes when the first .json is written).
    run(
        scene_with(Format::Json, 100, 1),
        &b,
        2 * n,
        Some(ck.clone()),
    );
    let numbered = numbered_checkpoints(&b).unwrap();
    assert_eq!(numbered.len(), 1, "{numbered:?}");
    assert_eq!(numbered[0].0, 2 * n);
    assert!(numbered[0].1.extension().is_some_and(|e| e == "json"));
    // And from the same checkpoint in binary.
    run(
        scene_with(Format::Binary, 0, 0),
        &c,
        2 * n,
        Some(c.join("half.bin")),
    );
    let full = read(&a.join("ckpt-final.json"));
    let half = read(&c.join("half.bin"));
    assert_ne!(
        content(&half),
        content(&full),
        "the second half moved nothing"
    );
    assert!(content(&read(&b.join("ckpt-final.json"))) == content(&full));
    assert!(content(&read(&c.join("ckpt-final.bin"))) == content(&full));
    // JSON bytes of the restarted run equal the uninterrupted run's (but the totals).
    let strip = |p: &Path| {
        let mut v: serde_json::Value = serde_json::from_slice(&std::fs::read(p).unwrap()).unwrap();
        v["run"].take();
        v["checksum"].take();
        v.to_string()
    };
    assert!(strip(&a.join("ckpt-final.json")) == strip(&b.join("ckpt-final.json")));
    for f in ["history.csv", "breaks.csv"] {
        let fa = std::fs::read(a.join(f)).unwrap();
        assert_eq!(fa, std::fs::read(b.join(f)).unwrap(), "{f}");
        assert_eq!(fa, std::fs::read(c.join(f)).unwrap(), "{f}");
    }
    // The totals came through the binary checkpoint: two invocations.
    let rc = read(&c.join("ckpt-final.bin")).run.unwrap();
    assert_eq!(serde_json::to_value(rc).unwrap()["invocations"], 2);
    // The binary checkpoint of the same world is smaller.
    let json_len = std::fs::metadata(a.join("ckpt-final.json")).unwrap().len();
    let bin_len = std::fs::metadata(c.join("ckpt-final.bin")).unwrap().len();
    assert!(bin_len < json_len, "binary {bin_len} B, JSON {json_len} B");
    for d in [a, b, c] {
        std::fs::remove_dir_all(d).unwrap();
    }
}

/// A small binary checkpoint of the example scene, its file name and physics hash.
fn small_binary() -> (Vec<u8>, String) {
    let d = tmp("small");
    let s = scene_with(Format::Binary, 0, 0);
    let hash = s.physics_hash();
    run(s, &d, 20, None);
    let bytes = std::fs::read(d.join("ckpt-final.bin")).unwrap();
    std::fs::remove_dir_all(&d).unwrap();
    (bytes, hash)
}

/// Section lengths of a binary checkpoint.
fn lens(b: &[u8]) -> [usize; 3] {
    let l = |k: usize| u64::from_le_bytes(b[112 + 8 * k..120 + 8 * k].try_into().unwrap()) as usize;
    [l(0), l(1), l(2)]
}

/// Puts a valid checksum on `b` (to reach the checks behind it).
fn reseal(b: &mut [u8]) {
    let mut h = Sha256::new();
    h.update(&b[..80]);
    h.update(&b[112..]);
    let sum: [u8; 32] = h.finalize().into();
    b[80..112].copy_from_slice(&sum);
}

fn err(b: &[u8]) -> String {
    match checkpoint::parse_bytes(b, "run/ckpt-9.bin") {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn damaged_binary_checkpoints_are_refused_naming_the_file() {
    let (good, hash) = small_binary();
    assert!(good.len() > HEADER_LEN);
    let ok = checkpoint::parse_bytes(&good, "x").unwrap();
    assert_eq!(ok.scene_hash, hash);
    assert_eq!(ok.world.state.step, 20);
    let [l0, l1, l2] = lens(&good);
    assert_eq!(HEADER_LEN + l0 + l1 + l2, good.len());
    // One flipped bit anywhere (scene hash, each section, the last byte) is a checksum error.
    let at = [
        20,
        HEADER_LEN + l0 / 2,
        HEADER_LEN + l0 + l1 / 2,
        HEADER_LEN + l0 + l1 + l2 / 2,
        good.len() - 1,
    ];
    for i in at {
        let mut b = good.clone();
        b[i] ^= 0x10;
        let e = err(&b);
        assert!(
            e.starts_with("run/ckpt-9.bin: the checkpoint is corrupt"),
            "byte {i}: {e}"
        );
    }
    // Damaged header fields: the magic (then it is no JSON either), the version, the count.
    for (i, want) in [
        (0, "neither a binary checkpoint"),
        (8, "version"),
        (12, "sections"),
    ] {
        let mut b = good.clone();
        b[i] ^= 0x01;
        let e = err(&b);
        assert!(e.starts_with("run/ckpt-9.bin: ") && e.contains(want), "{e}");
    }
    // Truncated anywhere: refused as truncated before any decoding.
    for n in [
        9,
        HEADER_LEN - 1,
        HEADER_LEN,
        HEADER_LEN + l0 + 3,
        good.len() - 1,
    ] {
        let e = err(&good[..n]);
        assert!(
            e.starts_with("run/ckpt-9.bin: not a checkpoint: truncated"),
            "{n}: {e}"
        );
    }
    // Padded: refused.
    let mut b = good.clone();
    b.extend_from_slice(b"junk");
    assert!(err(&b).contains("4 bytes after the end"), "{}", err(&b));
    // Another scene: refused by `load` naming the file.
    let d = tmp("wrong");
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join("ckpt-final.bin");
    std::fs::write(&p, &good).unwrap();
    checkpoint::load(&p, &hash).unwrap();
    let other = "0".repeat(64);
    let e = checkpoint::load(&p, &other).err().unwrap().to_string();
    assert!(
        e.starts_with(&format!("{}: made from a different scene", p.display())),
        "{e}"
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn hostile_lengths_neither_panic_nor_allocate_gigabytes() {
    let (good, _) = small_binary();
    let [l0, l1, l2] = lens(&good);
    let mut cases: Vec<Vec<u8>> = Vec::new();
    // Section lengths that overflow or exceed the file.
    for (k, v) in [
        (0, u64::MAX),
        (1, u64::MAX - 5),
        (2, 1 << 40),
        (0, u64::MAX / 2),
    ] {
        let mut b = good.clone();
        b[112 + 8 * k..120 + 8 * k].copy_from_slice(&v.to_le_bytes());
        cases.push(b);
    }
    // Valid header and checksum, MessagePack sections claiming 4 G elements / bytes or
    // nesting a million deep.
    let body = |books: &[u8], world: &[u8]| {
        let mut b = good[..HEADER_LEN].to_vec();
        let ls = [0u64, books.len() as u64, world.len() as u64];
        for (k, l) in ls.iter().enumerate() {
            b[112 + 8 * k..120 + 8 * k].copy_from_slice(&l.to_le_bytes());
        }
        b.extend_from_slice(books);
        b.extend_from_slice(world);
        reseal(&mut b);
        b
    };
    let books = &good[HEADER_LEN + l0..HEADER_LEN + l0 + l1];
    let world = &good[HEADER_LEN + l0 + l1..HEADER_LEN + l0 + l1 + l2];
    let huge = [
        vec![0xdd, 0xff, 0xff, 0xff, 0xff, 0xcb], // array32 of 2^32 - 1
        vec![0xdf, 0xff, 0xff, 0xff, 0xff, 0xa1, b'x'], // map32
        vec![0xdb, 0xff, 0xff, 0xff, 0xf0, b'a'], // str32
        vec![0xc6, 0xff, 0xff, 0xff, 0xf0, 0],    // bin32
        vec![0x91; 1_000_000],                    // nested arrays
    ];
    for h in &huge {
        cases.push(body(h, world));
        cases.push(body(books, h));
        // As the value of an unknown field and of the first field of the world.
        let mut w = vec![0x81, 0xa2, b'z', b'z'];
        w.extend_from_slice(h);
        cases.push(body(books, &w));
        let mut w = world.to_vec();
        // The world map's first key is "state" (fixmap, fixstr 5): replace its value.
        assert_eq!(&w[1..7], b"\xa5state");
        w.truncate(7);
        w.extend_from_slice(h);
        cases.push(body(books, &w));
    }
    LARGEST.store(0, Ordering::Relaxed);
    for (k, b) in cases.iter().enumerate() {
        let r = std::panic::catch_unwind(|| checkpoint::parse_bytes(b, "h.bin"));
        let e = r
            .unwrap_or_else(|_| panic!("case {k} panicked"))
            .err()
            .unwrap_or_else(|| panic!("case {k} accepted"))
            .to_string();
        assert!(e.starts_with("h.bin: "), "case {k}: {e}");
    }
    let largest = LARGEST.load(Ordering::Relaxed);
    // Other tests of this binary run alongside; all of them stay far below this.
    assert!(largest < 256 << 20, "an allocation of {largest} bytes");
}

#[test]
fn checkpoints_off_writes_none_and_the_summary_says_so() {
    let d = tmp("off");
    let mut s = scene_with(Format::Binary, 50, 0);
    s.outputs.checkpoints = false;
    run(s, &d, 200, None);
    let names: Vec<String> = std::fs::read_dir(&d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("ckpt")), "{names:?}");
    assert!(names.iter().any(|n| n == "history.csv"), "{names:?}");
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(v["checkpoints"], false);
    assert_eq!(v["final_step"], 200);
    // On (the default): the field is left out.
    run(scene_with(Format::Json, 0, 0), &d, 10, None);
    let v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("summary.json")).unwrap()).unwrap();
    assert!(v.get("checkpoints").is_none(), "{v}");
    assert!(d.join("ckpt-final.json").exists());
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn json_checkpoints_still_load_through_parse_bytes() {
    let d = tmp("json");
    let s = scene_with(Format::Json, 0, 0);
    let hash = s.physics_hash();
    run(s, &d, 20, None);
    let p = d.join("ckpt-final.json");
    let c = checkpoint::load(&p, &hash).unwrap();
    assert_eq!(c.world.state.step, 20);
    // The same content as the binary form of the same world.
    let bin = checkpoint::to_binary(
        &c.world,
        &hash,
        &c.history_rows,
        &c.snapshots,
        c.run.as_ref(),
    )
    .unwrap();
    let b = checkpoint::parse_bytes(&bin, "b").unwrap();
    assert!(content(&b) == content(&c));
    assert_eq!(
        serde_json::to_string(&b.run).unwrap(),
        serde_json::to_string(&c.run).unwrap()
    );
    // A checkpoint in neither format names the file.
    let e = checkpoint::parse_bytes(b"\xff\xfe", "x.bin")
        .err()
        .unwrap()
        .to_string();
    assert!(e.starts_with("x.bin: not a checkpoint"), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn numbered_checkpoints_of_both_formats_are_counted_and_pruned() {
    let d = tmp("names");
    std::fs::create_dir_all(&d).unwrap();
    for n in [
        "ckpt-000000100.json",
        "ckpt-000000200.bin",
        "ckpt-000000300.json",
        "ckpt-000000400.bin",
        "ckpt-final.bin",
        "ckpt-final.json",
        "ckpt-x.bin",
        "notes.bin",
    ] {
        std::fs::write(d.join(n), "x").unwrap();
    }
    let found: Vec<u64> = numbered_checkpoints(&d)
        .unwrap()
        .iter()
        .map(|f| f.0)
        .collect();
    assert_eq!(found, [100, 200, 300, 400]);
    let gone = prune_checkpoints(&d, 1).unwrap();
    assert_eq!(gone.len(), 3);
    let left = numbered_checkpoints(&d).unwrap();
    assert_eq!(left.len(), 1);
    assert!(left[0].1.ends_with("ckpt-000000400.bin"));
    assert!(d.join("ckpt-final.json").exists() && d.join("notes.bin").exists());
    std::fs::remove_dir_all(&d).unwrap();
}

/// Measures bytes per disc and write/read times of both formats on a JSON checkpoint given in
/// `DEM_CKPT_MEASURE` (e.g. a cutting run's `ckpt-final.json`); prints the figures. Run with
/// `DEM_CKPT_MEASURE=<file> cargo test -p dem-core --test checkpoint_binary -- --ignored
/// --nocapture` (the test profile is optimized).
#[test]
#[ignore]
fn measure_formats() {
    use std::time::Instant;
    let Ok(p) = std::env::var("DEM_CKPT_MEASURE") else {
        eprintln!("set DEM_CKPT_MEASURE to a JSON checkpoint");
        return;
    };
    let c = read(Path::new(&p));
    let discs = c.world.state.discs.len();
    let d = tmp("measure");
    std::fs::create_dir_all(&d).unwrap();
    let args = (&c.world, &c.scene_hash, &c.history_rows, &c.snapshots);
    for format in [Format::Json, Format::Binary] {
        let f = d.join(format!("ckpt.{}", format.extension()));
        let reps = 5;
        let t = Instant::now();
        for _ in 0..reps {
            checkpoint::save_as(&f, format, args.0, args.1, args.2, args.3, c.run.as_ref())
                .unwrap();
        }
        let write = t.elapsed().as_secs_f64() / reps as f64;
        let t = Instant::now();
        for _ in 0..reps {
            let b = std::fs::read(&f).unwrap();
            checkpoint::parse_bytes(&b, "m").unwrap();
        }
        let read_s = t.elapsed().as_secs_f64() / reps as f64;
        let len = std::fs::metadata(&f).unwrap().len();
        println!(
            "{format:?}: {discs} discs, {len} B ({:.0} B/disc; history rows {} B), write {:.1} ms, read {:.1} ms",
            len as f64 / discs as f64,
            c.history_rows.len(),
            write * 1e3,
            read_s * 1e3
        );
        assert!(content(&read(&f)) == content(&c));
    }
    std::fs::remove_dir_all(&d).unwrap();
}
