//! `dem render` on VTK output: a disc snapshot of a tiny run drawn as a PNG (size, colours at
//! the disc centres, the wall), the run's `snapshots.pvd` as an animated GIF (decoded: three
//! frames of one size), and bad snapshots and series ending with exit code 2 naming the file.

use image::AnimationDecoder;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{dem, text, tmp};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Column and row of (x, y) mm from `dem render`'s `S px/mm, (0, 0) mm at column C, row R`.
fn frame(out: &str) -> impl Fn(f64, f64) -> (u32, u32) {
    let num = |after: &str, until: char| -> f64 {
        let i = out
            .find(after)
            .unwrap_or_else(|| panic!("{after:?} in {out}"))
            + after.len();
        out[i..]
            .split(until)
            .next()
            .unwrap()
            .trim()
            .parse()
            .unwrap()
    };
    let c0 = num("at column ", ',');
    let r0 = num(", row ", '\n');
    let i = out.find(" px/mm").unwrap();
    let sc: f64 = out[..i].rsplit(' ').next().unwrap().parse().unwrap();
    move |x, y| ((c0 + sc * x).floor() as u32, (r0 - sc * y).floor() as u32)
}

const PALETTE0: [u8; 3] = [0x1f, 0x77, 0xb4];
const PALETTE1: [u8; 3] = [0xff, 0x7f, 0x0e];
const VIRIDIS_LOW: [u8; 3] = [0x44, 0x01, 0x54];
const VIRIDIS_HIGH: [u8; 3] = [0xfd, 0xe7, 0x25];
const WHITE: [u8; 3] = [255, 255, 255];

/// Two bonded discs of material `a` at rest, a disc of material `b` moving, a floor wall; 20
/// steps with a VTK snapshot every 10 (steps 0, 10, 20). Returns the output folder.
fn tiny_run(dir: &Path) -> PathBuf {
    let scene = serde_json::json!({
        "schema": "dem.scene/1",
        "name": "render-vtk",
        "units": "mm",
        "materials": [
            {"name": "a", "density": 2500, "kn": 1e5, "ks": 5e4, "friction": 0.3},
            {"name": "b", "density": 2500, "kn": 1e5, "ks": 5e4, "friction": 0.3}
        ],
        "bond_groups": [{"name": "glue", "model": "parallel_potyondy2004", "criterion": "stress",
                         "kn": 1e9, "ks": 1e9, "radius_multiplier": 1.0,
                         "tensile_strength": 1e9, "cohesion": 1e9, "friction_angle": 30}],
        "bodies": {"discs": [
            {"material": "a", "discs": [[0, 0, 1], [2, 0, 1]]},
            {"material": "b", "velocity": [50, 0], "discs": [[6, 0, 1.5]]}
        ]},
        "auto_bonds": [{"bond_group": "glue", "tolerance": 0.01}],
        "walls": [{"name": "floor", "a": [-2, -2], "b": [9, -2], "material": "a"}],
        "run": {"steps": 20},
        "outputs": {"vtk_every": 10, "checkpoint_every": 10}
    });
    let p = dir.join("scene.json");
    std::fs::write(&p, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    let out = dir.join("out");
    let o = dem(&["run", s(&p), "--out", s(&out), "--threads", "1"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    out
}

/// Disc centres (mm) and materials of the final checkpoint (= the last snapshot's state).
fn centres(ck: &Path) -> Vec<(f64, f64, u64)> {
    let v: Value = serde_json::from_str(&std::fs::read_to_string(ck).unwrap()).unwrap();
    let d = &v["world"]["state"]["discs"];
    (0..d["x"].as_array().unwrap().len())
        .map(|k| {
            (
                d["x"][k].as_f64().unwrap() * 1e3,
                d["y"][k].as_f64().unwrap() * 1e3,
                d["material"][k].as_u64().unwrap(),
            )
        })
        .collect()
}

fn rgb_at(img: &image::RgbaImage, c: u32, r: u32) -> [u8; 3] {
    let p = img.get_pixel(c, r).0;
    [p[0], p[1], p[2]]
}

#[test]
fn a_snapshot_is_drawn_and_a_series_animated() {
    let dir = tmp("ok");
    let out = tiny_run(&dir);
    let snap = out.join("snap-000000020.vtp");
    assert!(snap.is_file() && out.join("walls-000000020.vtp").is_file());
    let discs = centres(&out.join("ckpt-final.json"));
    assert_eq!(discs.len(), 3);

    // By material: each disc centre has its material's colour, the corner is background.
    let png = dir.join("snap.png");
    let o = dem(&[
        "render",
        s(&snap),
        "--width",
        "400",
        "--color",
        "material",
        "--out",
        s(&png),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(t.contains(": 400 x "), "{t}");
    let img = image::open(&png).unwrap().to_rgba8();
    assert_eq!(img.width(), 400);
    let at = frame(&t);
    for &(x, y, m) in &discs {
        let (c, r) = at(x, y);
        let want = if m == 0 { PALETTE0 } else { PALETTE1 };
        assert_eq!(
            rgb_at(&img, c, r),
            want,
            "disc at ({x}, {y}) mm, material {m}"
        );
    }
    assert_eq!(rgb_at(&img, 399, 0), WHITE);
    // The floor (from walls-*.vtp) is drawn: grey at y = -2 mm between the discs.
    let (c, r) = at(4.0, -2.0);
    let px = rgb_at(&img, c, r);
    assert!(
        px.iter().all(|&v| v < 0xa0) && px[0] == px[1],
        "floor pixel {px:?}"
    );

    // By speed (from `velocity`): the discs at rest low on the scale, the moving one at the top.
    let o = dem(&[
        "render",
        s(&snap),
        "--width",
        "400",
        "--color",
        "speed",
        "--out",
        s(&png),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    // The caption has the step and the time from snapshots.pvd beside it.
    let img = image::open(&png).unwrap().to_rgba8();
    let at = frame(&t);
    for &(x, y, m) in &discs {
        let (c, r) = at(x, y);
        let want = if m == 0 { VIRIDIS_LOW } else { VIRIDIS_HIGH };
        assert_eq!(rgb_at(&img, c, r), want, "disc at ({x}, {y}) mm");
    }
    // Bonds from the line cells: a point on the bond inside disc 0 turns dark with --bonds.
    let (bx, by) = (0.75 * discs[0].0 + 0.25 * discs[1].0, discs[0].1);
    let o = dem(&[
        "render",
        s(&snap),
        "--width",
        "400",
        "--bonds",
        "--out",
        s(&png),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let img = image::open(&png).unwrap().to_rgba8();
    let (c, r) = frame(&t)(bx, by);
    let px = rgb_at(&img, c, r);
    assert!(px.iter().all(|&v| v < 100), "bond pixel {px:?}");

    // The series: 3 snapshots (steps 0, 10, 20) → a GIF of 3 frames, all one size.
    let pvd = out.join("snapshots.pvd");
    let gif = dir.join("cut.gif");
    let o = dem(&[
        "render",
        s(&pvd),
        "--out",
        s(&gif),
        "--fps",
        "5",
        "--width",
        "300",
        "--color",
        "speed",
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(t.contains("3 frames of 300 x "), "{t}");
    let dec = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).unwrap(),
    ))
    .unwrap();
    let frames = dec.into_frames().collect_frames().unwrap();
    assert_eq!(frames.len(), 3);
    let (w, h) = frames[0].buffer().dimensions();
    assert_eq!(w, 300);
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (w, h));
        assert_eq!(f.delay().numer_denom_ms(), (200, 1), "5 fps");
    }
    // The frames differ (the caption's step and time at least).
    assert_ne!(frames[0].buffer(), frames[2].buffer());
    // Kept for looking at: the last frame as a PNG.
    frames[2]
        .buffer()
        .save(dir.join("cut-frame-3.png"))
        .unwrap();
    // Default output beside the series: snapshots.gif.
    let o = dem(&["render", s(&pvd), "--width", "200"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(out.join("snapshots.gif").is_file());
}

#[test]
fn bad_snapshots_and_series_are_usage_errors_naming_the_file() {
    let dir = tmp("bad");
    let fail = |args: &[&str], want: &[&str]| {
        let o = dem(args);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {t}");
        for w in want {
            assert!(t.contains(w), "{args:?}: {w:?} not in {t}");
        }
        assert!(!t.contains("panicked"), "{t}");
    };
    let good = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\">\n  <PolyData>\n    \
        <Piece NumberOfPoints=\"2\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n      \
        <PointData Scalars=\"radius\">\n        <DataArray type=\"Float64\" Name=\"radius\" NumberOfComponents=\"1\" format=\"ascii\">\n0.001 0.001\n        </DataArray>\n      </PointData>\n      \
        <Points>\n        <DataArray type=\"Float64\" Name=\"points\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 0 0.003 0 0\n        </DataArray>\n      </Points>\n    \
        </Piece>\n  </PolyData>\n</VTKFile>\n";
    // The hand-written snapshot itself is fine (no velocity: a note, speeds 0).
    let ok = dir.join("snap-000000005.vtp");
    std::fs::write(&ok, good).unwrap();
    let o = dem(&["render", s(&ok), "--width", "100"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let trunc = dir.join("snap-truncated.vtp");
    std::fs::write(&trunc, &good[..good.len() / 2]).unwrap();
    fail(&["render", s(&trunc)], &[s(&trunc), "truncated"]);
    let norad = dir.join("snap-norad.vtp");
    std::fs::write(&norad, good.replace("Name=\"radius\"", "Name=\"size\"")).unwrap();
    fail(&["render", s(&norad)], &[s(&norad), "\"radius\""]);
    let short = dir.join("snap-short.vtp");
    std::fs::write(&short, good.replace("0.001 0.001", "0.001")).unwrap();
    fail(
        &["render", s(&short)],
        &[s(&short), "\"radius\"", "expected 2"],
    );
    // Arrays that say binary but hold text: the base64 is refused naming the array.
    let binary = dir.join("snap-binary.vtp");
    std::fs::write(
        &binary,
        good.replace("format=\"ascii\"", "format=\"binary\""),
    )
    .unwrap();
    fail(
        &["render", s(&binary)],
        &[s(&binary), "\"radius\"", "bad base64"],
    );
    let grid = dir.join("grid.vtp");
    std::fs::write(
        &grid,
        good.replace("PolyData\" version", "UnstructuredGrid\" version"),
    )
    .unwrap();
    fail(&["render", s(&grid)], &[s(&grid), "UnstructuredGrid"]);
    // A series naming a missing file, and an animation written as a PNG.
    let pvd = dir.join("run.pvd");
    std::fs::write(
        &pvd,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n    \
         <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"snap-000000005.vtp\"/>\n    \
         <DataSet timestep=\"0.001\" group=\"\" part=\"0\" file=\"snap-gone.vtp\"/>\n  </Collection>\n</VTKFile>\n",
    )
    .unwrap();
    fail(
        &["render", s(&pvd)],
        &[s(&pvd), "snap-gone.vtp", "does not exist"],
    );
    fail(
        &["render", s(&pvd), "--out", s(&dir.join("x.png"))],
        &["x.png", ".gif"],
    );
    // A bad snapshot inside a series names both files.
    std::fs::write(
        dir.join("run2.pvd"),
        std::fs::read_to_string(&pvd)
            .unwrap()
            .replace("snap-gone.vtp", "snap-norad.vtp"),
    )
    .unwrap();
    fail(
        &["render", s(&dir.join("run2.pvd"))],
        &["run2.pvd", s(&norad), "\"radius\""],
    );
    // An MP4 without ffmpeg on PATH names ffmpeg.
    let o = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args(["render", s(&pvd), "--out", s(&dir.join("x.mp4"))])
        .env("PATH", "")
        .output()
        .unwrap();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(t.contains("ffmpeg") && t.contains("x.mp4"), "{t}");
    // --fps bounds.
    fail(&["render", s(&pvd), "--fps", "0"], &["--fps", "1 to 100"]);
    // Nothing was written by the failures.
    for f in ["x.png", "x.mp4", "run.gif", "run2.gif"] {
        assert!(!dir.join(f).exists(), "{f}");
    }
}
