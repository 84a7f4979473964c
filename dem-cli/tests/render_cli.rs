//! `dem render` end to end: a checkpoint of a tiny run, its last good state, a specimen file
//! and a clump template drawn as PNGs (decoded here: size, the colour at disc centres, the
//! background in a corner, bonds); bad inputs end with exit code 2 naming the file or flag.

use serde_json::Value;
use std::path::{Path, PathBuf};

mod common;
use common::{dem, text, tmp};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A decoded RGB image.
struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Image {
    fn read(path: &Path) -> Image {
        let file = std::fs::File::open(path).unwrap();
        let mut decoder = png::Decoder::new(file);
        // Palette images (the default) are expanded to RGB.
        decoder.set_transformations(png::Transformations::EXPAND);
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
        assert_eq!(info.bit_depth, png::BitDepth::Eight);
        buf.truncate(info.buffer_size());
        Image {
            width: info.width,
            height: info.height,
            rgb: buf,
        }
    }

    fn at(&self, col: f64, row: f64) -> [u8; 3] {
        let (c, r) = (col.floor() as usize, row.floor() as usize);
        assert!(
            c < self.width as usize && r < self.height as usize,
            "({c}, {r}) outside"
        );
        let k = 3 * (r * self.width as usize + c);
        [self.rgb[k], self.rgb[k + 1], self.rgb[k + 2]]
    }
}

/// The `(0, 0) mm at column C, row R` and `S px/mm` of `dem render`'s report: a point (x, y)
/// in mm is at column C + S·x, row R − S·y.
fn frame(out: &str) -> impl Fn(f64, f64) -> (f64, f64) {
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
    let s: f64 = out[..i].rsplit(' ').next().unwrap().parse().unwrap();
    move |x, y| (c0 + s * x, r0 - s * y)
}

const PALETTE0: [u8; 3] = [0x1f, 0x77, 0xb4];
const PALETTE1: [u8; 3] = [0xff, 0x7f, 0x0e];
const VIRIDIS_LOW: [u8; 3] = [0x44, 0x01, 0x54];
const VIRIDIS_HIGH: [u8; 3] = [0xfd, 0xe7, 0x25];
const WHITE: [u8; 3] = [255, 255, 255];

/// Two bonded discs of material `a` at rest and a disc of material `b` moving, above a floor
/// wall; a short run writes `ckpt-final.json`. Returns the checkpoint.
fn tiny_checkpoint(dir: &Path) -> PathBuf {
    let scene = serde_json::json!({
        "schema": "dem.scene/1",
        "name": "render",
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
        "outputs": {"checkpoint_every": 10}
    });
    let p = dir.join("render.json");
    std::fs::write(&p, serde_json::to_string_pretty(&scene).unwrap()).unwrap();
    let out = dir.join("out");
    let o = dem(&["run", s(&p), "--out", s(&out), "--threads", "1"]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let ck = out.join("ckpt-final.json");
    assert!(ck.exists());
    ck
}

/// Disc centres (mm) of a checkpoint, in the state's order, and their materials.
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

#[test]
fn checkpoint_pictures_have_the_width_disc_colours_and_background() {
    let dir = tmp("ckpt");
    let ck = tiny_checkpoint(&dir);
    let discs = centres(&ck);
    assert_eq!(discs.len(), 3);

    // By material, default output beside the input.
    let o = dem(&["render", s(&ck), "--width", "400", "--color", "material"]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let png = ck.with_extension("png");
    assert!(
        t.contains(&format!("wrote {}: 400 x ", png.display())),
        "{t}"
    );
    let img = Image::read(&png);
    assert_eq!(img.width, 400);
    let at = frame(&t);
    for &(x, y, m) in &discs {
        let (c, r) = at(x, y);
        let want = if m == 0 { PALETTE0 } else { PALETTE1 };
        assert_eq!(img.at(c, r), want, "disc at ({x}, {y}) mm, material {m}");
    }
    assert_eq!(img.at(399.0, 0.0), WHITE, "top right corner");
    assert_eq!(img.at(0.0, 0.0), WHITE, "top left corner");
    // The image is wider than tall: the content is 11 x 3.5 mm.
    assert!(img.height < img.width, "{} x {}", img.width, img.height);

    // A palette PNG by default; --rgb gives the same colours in 24 bits.
    let raw = |p: &Path| {
        let r = png::Decoder::new(std::fs::File::open(p).unwrap())
            .read_info()
            .unwrap();
        r.info().color_type
    };
    assert_eq!(raw(&png), png::ColorType::Indexed);
    let full = dir.join("full.png");
    let o = dem(&[
        "render",
        s(&ck),
        "--width",
        "400",
        "--color",
        "material",
        "--rgb",
        "--out",
        s(&full),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert_eq!(raw(&full), png::ColorType::Rgb);
    assert_eq!(Image::read(&full).rgb, img.rgb);

    // By speed: the discs at rest at the bottom of the scale, the moving one at the top.
    let out = dir.join("speed.png");
    let o = dem(&[
        "render",
        s(&ck),
        "--width",
        "400",
        "--color",
        "speed",
        "--out",
        s(&out),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let img = Image::read(&out);
    let at = frame(&t);
    for &(x, y, m) in &discs {
        let (c, r) = at(x, y);
        let want = if m == 0 { VIRIDIS_LOW } else { VIRIDIS_HIGH };
        assert_eq!(img.at(c, r), want, "disc at ({x}, {y}) mm");
    }

    // By grain (the default; each disc is a grain here): the touching discs differ.
    let out = dir.join("grain.png");
    let o = dem(&["render", s(&ck), "--width", "400", "--out", s(&out)]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let img = Image::read(&out);
    let at = frame(&t);
    let colour = |k: usize| {
        let (c, r) = at(discs[k].0, discs[k].1);
        img.at(c, r)
    };
    assert_ne!(colour(0), colour(1));
    assert!(![colour(0), colour(1), colour(2)].contains(&WHITE));

    // Bonds: a point on the bond between discs 0 and 1, inside disc 0, turns dark with
    // --bonds and keeps the disc's colour without.
    let (x0, x1) = (discs[0].0, discs[1].0);
    let (bx, by) = (0.75 * x0 + 0.25 * x1, discs[0].1);
    let plain = {
        let (c, r) = at(bx, by);
        img.at(c, r)
    };
    assert_eq!(plain, colour(0));
    let out = dir.join("bonds.png");
    let o = dem(&[
        "render",
        s(&ck),
        "--width",
        "400",
        "--bonds",
        "--out",
        s(&out),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let img = Image::read(&out);
    let (c, r) = frame(&t)(bx, by);
    let px = img.at(c, r);
    assert!(px.iter().all(|&v| v < 100), "bond pixel {px:?}");

    // The same state as a last-good-state.json (a bare state, no schema).
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&ck).unwrap()).unwrap();
    let state = dir.join("last-good-state.json");
    std::fs::write(&state, v["world"]["state"].to_string()).unwrap();
    let o = dem(&["render", s(&state), "--width", "300", "--color", "material"]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let img = Image::read(&dir.join("last-good-state.png"));
    assert_eq!(img.width, 300);
    let (c, r) = frame(&t)(discs[2].0, discs[2].1);
    assert_eq!(img.at(c, r), PALETTE1);
}

#[test]
fn specimen_files_draw_bonds_by_group() {
    let dir = tmp("specimen");
    let spec = serde_json::json!({
        "schema": "dem.specimen/1",
        "description": "three discs",
        "units": "mm",
        "discs": [{"material": "rock", "discs": [[0, 0, 1], [2, 0, 1], [6, 0, 1]],
                   "groups": [1, 1, 2]}],
        "bonds": [{"bond_group": "intra", "pairs": [[0, 1]]}]
    });
    let p = dir.join("spec.json");
    std::fs::write(&p, spec.to_string()).unwrap();
    let out = dir.join("spec-group.png");
    let o = dem(&[
        "render",
        s(&p),
        "--color",
        "group",
        "--width",
        "500",
        "--out",
        s(&out),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    let img = Image::read(&out);
    assert_eq!(img.width, 500);
    let at = frame(&t);
    // On the bond: the first group's colour (darkened a little); the unbonded disc: grey.
    let (c, r) = at(0.5, 0.0);
    let px = img.at(c, r);
    assert!(
        px[2] > px[0] + 60 && px[2] > px[1],
        "bond pixel {px:?} is not the first group's blue"
    );
    let (c, r) = at(6.0, 0.0);
    assert_eq!(img.at(c, r), [0x9a, 0x9a, 0x9a]);
    assert_eq!(img.at(499.0, 0.0), WHITE);
    // Wrong bond indices name the field.
    let bad = serde_json::json!({
        "schema": "dem.specimen/1",
        "discs": [{"material": "rock", "discs": [[0, 0, 1]]}],
        "bonds": [{"bond_group": "intra", "pairs": [[0, 5]]}]
    });
    std::fs::write(&p, bad.to_string()).unwrap();
    let o = dem(&["render", s(&p), "--out", s(&out)]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(t.contains("spec.json: field bonds[0].pairs[0]"), "{t}");
}

#[test]
fn templates_are_drawn_over_their_outline() {
    let dir = tmp("template");
    // A 4 x 2 mm rectangle: centroid (2, 1) mm, so in the template frame it spans ±2, ±1 mm.
    let csv = dir.join("brick.csv");
    std::fs::write(&csv, "x,y\n0,0\n4,0\n4,2\n0,2\n").unwrap();
    let tdir = dir.join("t");
    let o = dem(&["clump", s(&csv), "--out", s(&tdir)]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let tpl = tdir.join("brick.json");
    let o = dem(&["render", s(&tpl), "--width", "500"]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(!t.contains("note:"), "{t}");
    let img = Image::read(&tdir.join("brick.png"));
    assert_eq!(img.width, 500);
    let at = frame(&t);
    let dark = |x: f64, y: f64| {
        let (c, r) = at(x, y);
        (-1..=1).any(|d| img.at(c + d as f64, r).iter().all(|&v| v < 100))
    };
    assert!(dark(0.0, 0.0), "the centroid mark");
    assert!(dark(-2.0, 0.0) && dark(2.0, 0.5), "the outline's sides");
    assert_eq!(img.at(499.0, 0.0), WHITE);

    // The outline file gone: drawn without it, with a note saying how to give it.
    let moved = dir.join("moved.csv");
    std::fs::rename(&csv, &moved).unwrap();
    let o = dem(&["render", s(&tpl), "--width", "300"]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(
        t.contains("note: ") && t.contains("brick.csv") && t.contains("--outline"),
        "{t}"
    );
    let o = dem(&["render", s(&tpl), "--width", "300", "--outline", s(&moved)]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(0), "{t}");
    assert!(!t.contains("note:"), "{t}");
}

#[test]
fn bad_inputs_are_usage_errors_naming_the_file_or_flag() {
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
    let not_json = dir.join("notes.json");
    std::fs::write(&not_json, "hello").unwrap();
    fail(&["render", s(&not_json)], &[s(&not_json), "not a JSON"]);
    let unknown = dir.join("other.json");
    std::fs::write(&unknown, r#"{"schema": "someone.else/3", "discs": []}"#).unwrap();
    fail(
        &["render", s(&unknown)],
        &[s(&unknown), "someone.else/3", "dem.checkpoint/1"],
    );
    let scene = dir.join("scene.json");
    std::fs::write(&scene, r#"{"schema": "dem.scene/1"}"#).unwrap();
    fail(&["render", s(&scene)], &[s(&scene), "dem run"]);
    let none = dir.join("plain.json");
    std::fs::write(&none, r#"{"points": [[0, 0]]}"#).unwrap();
    fail(&["render", s(&none)], &[s(&none), "no `schema` field"]);
    fail(
        &["render", s(&dir.join("missing.json"))],
        &["missing.json", "cannot read"],
    );
    let bad_ckpt = dir.join("ckpt-000000010.json");
    std::fs::write(&bad_ckpt, r#"{"schema": "dem.checkpoint/1", "world": 3}"#).unwrap();
    fail(
        &["render", s(&bad_ckpt)],
        &[s(&bad_ckpt), "not a checkpoint"],
    );
    // Flags.
    fail(
        &["render", s(&unknown), "--width", "0"],
        &["--width", "1 to 6000"],
    );
    fail(&["render", s(&unknown), "--width", "-3"], &["--width"]);
    fail(
        &["render", s(&unknown), "--color", "mood"],
        &["--color", "grain, group"],
    );
    fail(
        &["render", s(&unknown), "--view", "1,2,3"],
        &["--view", "four"],
    );
    fail(
        &["render", s(&unknown), "--view", "5,1,0,1"],
        &["--view", "XMIN < XMAX"],
    );
    // The output may not be the input, however it is spelled.
    let alias = dir.join("sub").join("..").join("other.json");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    fail(
        &["render", s(&unknown), "--out", s(&alias)],
        &["--out", "is the input"],
    );
    let png_named = dir.join("pic.png");
    std::fs::write(&png_named, "{}").unwrap();
    fail(&["render", s(&png_named)], &["--out", "is the input"]);
    assert_eq!(std::fs::read_to_string(&png_named).unwrap(), "{}");
    // Nothing was written for any of them.
    let pngs: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "png") && e.path() != png_named)
        .collect();
    assert!(pngs.is_empty(), "{pngs:?}");
}
