//! Outlines from images (masks, labelled images) and GIS polygons (GeoJSON, WKT): the
//! templates they give against those of the CSV outlines they were made from, and every
//! bad input giving a clear error or warning that names the file and the grain.

use std::path::{Path, PathBuf};

use clumpgen::batch::{collect_inputs, run_batch, BatchOptions, SUMMARY_FILE};
use clumpgen::outline::{read_grains, GrainOptions, MaskMode};
use clumpgen::{
    make_template, polygon_props, read_outline, ClumpParams, OutlineError, ReadOptions, Template,
    Units,
};
use image::{GrayImage, ImageBuffer, Luma};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("clumpgen-img-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn outlines_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/outlines")
}

fn px(s: f64) -> ReadOptions {
    ReadOptions {
        units: Some(Units::Px { metres_per_px: s }),
        resample: None,
    }
}

fn mm() -> ReadOptions {
    ReadOptions {
        units: Some(Units::Mm),
        resample: None,
    }
}

/// A binary PNG of `rows` ('#' = 255).
fn mask_png(path: &Path, rows: &[&str]) {
    let img = GrayImage::from_fn(rows[0].len() as u32, rows.len() as u32, |x, y| {
        Luma([if rows[y as usize].as_bytes()[x as usize] == b'#' {
            255
        } else {
            0
        }])
    });
    img.save(path).unwrap();
}

const CSVS: [&str; 3] = ["equant-01.csv", "concave-02.csv", "elongated-01.csv"];

/// The three CSV outlines (metres, local frame: centroid of the polygon at props.centroid).
fn csv_outlines() -> Vec<clumpgen::Outline> {
    CSVS.iter()
        .map(|f| read_outline(&outlines_dir().join(f), &ReadOptions::default()).unwrap())
        .collect()
}

type Labels = ImageBuffer<Luma<u16>, Vec<u16>>;

/// Rasterise the polygons (metres) at `s` metres per pixel into one 16-bit label image, label
/// k+1 for polygon k, placed side by side with a margin; a pixel takes a label when its centre
/// lies inside the polygon (centre sampling: each boundary pixel is off by at most one pixel's
/// area). Returns the image and each polygon's offset (metres, y up, image bottom-left origin).
fn rasterise(polys: &[Vec<[f64; 2]>], s: f64) -> (Labels, Vec<[f64; 2]>) {
    let margin = 10.0;
    let mut offsets = Vec::new();
    let (mut x, mut hmax) = (margin, 0.0f64);
    for p in polys {
        let (lo, hi) = clumpgen::geom::bbox(p);
        offsets.push([x - lo[0] / s, margin - lo[1] / s]);
        x += (hi[0] - lo[0]) / s + margin;
        hmax = hmax.max((hi[1] - lo[1]) / s);
    }
    let (w, h) = (x.ceil() as u32, (hmax + 2.0 * margin).ceil() as u32);
    let mut img = ImageBuffer::new(w, h);
    for (k, p) in polys.iter().enumerate() {
        let o = offsets[k];
        let q: Vec<[f64; 2]> = p
            .iter()
            .map(|v| [v[0] / s + o[0], v[1] / s + o[1]])
            .collect();
        let (lo, hi) = clumpgen::geom::bbox(&q);
        for i in lo[0].floor() as u32..hi[0].ceil() as u32 {
            for yy in lo[1].floor() as u32..hi[1].ceil() as u32 {
                // Pixel (i, j) has centre (i + 0.5, H - j - 0.5) in pixel units, y up.
                if clumpgen::geom::point_in_polygon([i as f64 + 0.5, yy as f64 + 0.5], &q) {
                    img.put_pixel(i, h - 1 - yy, Luma([k as u16 + 1]));
                }
            }
        }
    }
    let off_m = offsets.iter().map(|o| [o[0] * s, o[1] * s]).collect();
    (img, off_m)
}

#[test]
fn a_filled_rectangle_has_exactly_its_pixel_area_and_y_points_up() {
    let d = tmp("rect");
    let f = d.join("rect.png");
    // 7 x 3 pixels, top-left pixel (2, 1) of a 12 x 6 image.
    let mut rows = vec!["............".to_string(); 6];
    for r in rows.iter_mut().skip(1).take(3) {
        r.replace_range(2..9, "#######");
    }
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    mask_png(&f, &rows);
    let s = 1e-4;
    let fg = read_grains(&f, &px(s), &GrainOptions::default().with_min(1)).unwrap();
    assert_eq!(fg.grains.len(), 1);
    let g = &fg.grains[0];
    assert_eq!(
        (g.name.as_str(), g.label.as_str()),
        ("component-1", "component 1")
    );
    let o = g.outline.as_ref().unwrap();
    let p = polygon_props(&o.points);
    // Pixel-edge convention: area w·h·px² to rounding (the vertices are integers times px).
    assert!(
        (p.area - 21.0 * s * s).abs() <= 1e-12 * 21.0 * s * s,
        "{}",
        p.area
    );
    // Rows 1..4 of 6 (top down) are y in [2, 5] px (y up): centre y = 3.5 px; x centre 5.5 px.
    let c = [o.origin[0] + p.centroid[0], o.origin[1] + p.centroid[1]];
    assert!(
        (c[0] - 5.5 * s).abs() < 1e-15 && (c[1] - 3.5 * s).abs() < 1e-15,
        "{c:?}"
    );
    assert_eq!(o.points.len(), 4);
    assert_eq!(o.grain.as_deref(), Some("component 1"));
    assert_eq!(o.name, "rect/component-1");
    std::fs::remove_dir_all(&d).unwrap();
}

trait WithMin {
    fn with_min(self, n: usize) -> Self;
}
impl WithMin for GrainOptions {
    fn with_min(mut self, n: usize) -> Self {
        self.min_pixels = n;
        self
    }
}

/// Mask grains against the CSV templates they were drawn from: mass (area), centroid and
/// inertia within bounds of the pixel resolution.
#[test]
fn a_labelled_mask_gives_the_csv_templates_to_the_pixel_resolution() {
    let d = tmp("labels");
    let csv = csv_outlines();
    let s = 4e-6; // 4 µm pixels: 250 across a 1 mm grain radius
    let polys: Vec<Vec<[f64; 2]>> = csv
        .iter()
        .map(|o| {
            o.points
                .iter()
                .map(|p| [p[0] + o.origin[0], p[1] + o.origin[1]])
                .collect()
        })
        .collect();
    let (img, offsets) = rasterise(&polys, s);
    let f = d.join("grains.png");
    img.save(&f).unwrap();
    let fg = read_grains(&f, &px(s), &GrainOptions::default()).unwrap();
    assert_eq!(fg.grains.len(), 3, "{:?}", fg.notes);
    let params = ClumpParams::default();
    for (k, (g, o)) in fg.grains.iter().zip(&csv).enumerate() {
        assert_eq!(g.name, format!("label-{}", k + 1));
        let mo = g.outline.as_ref().unwrap();
        assert!(mo.warnings.is_empty(), "{:?}", mo.warnings);
        let a = make_template(o, &params).unwrap();
        let b = make_template(mo, &params).unwrap();
        let perim = a.shape.perimeter;
        let area = a.shape.area;
        // Largest distance of the outline from its centroid.
        let pc = polygon_props(&o.points).centroid;
        let rho = o
            .points
            .iter()
            .map(|p| (p[0] - pc[0]).hypot(p[1] - pc[1]))
            .fold(0.0, f64::max);
        // Area (and so mass): every pixel the boundary crosses is off by at most px², and the
        // boundary crosses at most 2·P/px + 4 pixels: |ΔA| ≤ (2P/px + 4)·px² ≈ 2·P·px.
        let da = (b.target.area - a.target.area).abs();
        let bound_a = (2.0 * perim / s + 4.0) * s * s;
        assert!(da <= bound_a, "{}: ΔA {da:e} > {bound_a:e}", CSVS[k]);
        let dm = (b.target.mass - a.target.mass).abs() / a.target.mass;
        assert!((dm - da / area).abs() < 1e-12);
        // Centroid: the first moment is off by at most bound_a·ρ (ρ the largest distance of
        // the outline from the centroid), and the area by bound_a: |Δc| ≤ 2·bound_a·ρ/A.
        let ca = [
            a.source.centroid_m[0] + offsets[k][0],
            a.source.centroid_m[1] + offsets[k][1],
        ];
        let dc = (b.source.centroid_m[0] - ca[0]).hypot(b.source.centroid_m[1] - ca[1]);
        let bound_c = 2.0 * bound_a * rho / area;
        assert!(dc <= bound_c, "{}: Δc {dc:e} > {bound_c:e}", CSVS[k]);
        // Polar moment about the centroid: |ΔJ| ≤ bound_a·ρ² + A·(2·ρ·Δc + Δc²).
        let dj = (b.shape.j - a.shape.j).abs();
        let r = rho;
        let bound_j = bound_a * r * r + area * (2.0 * r * dc + dc * dc);
        assert!(dj <= bound_j, "{}: ΔJ {dj:e} > {bound_j:e}", CSVS[k]);
        // The templates themselves are exact for their outlines.
        assert!(b.residuals.max() < 1e-10);
        let di = (b.achieved.inertia - a.achieved.inertia).abs() / a.achieved.inertia;
        eprintln!(
            "{}: px {s:e} m, P/px {:.0}: ΔA/A {:.2e} (bound {:.2e}), |Δc|/R_eq {:.2e} (bound \
             {:.2e}), ΔI/I {di:.2e} (bound {:.2e}), discs {} vs {}",
            CSVS[k],
            perim / s,
            da / area,
            bound_a / area,
            dc / a.shape.r_eq,
            bound_c / a.shape.r_eq,
            bound_j / a.shape.j,
            b.discs.len(),
            a.discs.len()
        );
    }
    std::fs::remove_dir_all(&d).unwrap();
}

fn geojson_of(outlines: &[clumpgen::Outline], closed: bool, extra: &str) -> String {
    let feats: Vec<String> = outlines
        .iter()
        .enumerate()
        .map(|(k, o)| {
            let mut pts: Vec<String> = raw_points(o)
                .iter()
                .map(|p| format!("[{:?},{:?}]", p[0], p[1]))
                .collect();
            if closed {
                pts.push(pts[0].clone());
            }
            format!(
                r#"{{"type":"Feature","properties":{{"name":"g{k}"}},"geometry":{{"type":"Polygon","coordinates":[[{}]]}}}}"#,
                pts.join(",")
            )
        })
        .collect();
    format!(
        r#"{{"type":"FeatureCollection"{extra},"features":[{}]}}"#,
        feats.join(",")
    )
}

/// The file's own numbers (mm), as the CSV has them.
fn raw_points(o: &clumpgen::Outline) -> Vec<[f64; 2]> {
    let text = std::fs::read_to_string(&o.source).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#') && !l.starts_with('x'))
        .map(|l| {
            let (a, b) = l.split_once(',').unwrap();
            [a.parse().unwrap(), b.parse().unwrap()]
        })
        .collect()
}

/// The template without where it came from (file, hash, name, grain, warnings).
fn body(t: &Template) -> String {
    let mut t = t.clone();
    t.id = String::new();
    t.source.file = String::new();
    t.source.sha256 = String::new();
    t.source.grain = None;
    t.source.warnings.clear();
    serde_json::to_string(&t).unwrap()
}

#[test]
fn geojson_and_wkt_of_the_csv_points_give_byte_identical_templates() {
    let d = tmp("gis");
    let csv = csv_outlines();
    let params = ClumpParams::default();
    let want: Vec<String> = csv
        .iter()
        .map(|o| body(&make_template(o, &params).unwrap()))
        .collect();
    let f = d.join("grains.geojson");
    std::fs::write(&f, geojson_of(&csv, true, "")).unwrap();
    let fg = read_grains(&f, &mm(), &GrainOptions::default()).unwrap();
    assert_eq!(fg.grains.len(), 3);
    for (k, g) in fg.grains.iter().enumerate() {
        assert_eq!(g.name, format!("g{k}"));
        assert_eq!(g.label, format!("feature {k} (\"g{k}\")"));
        let o = g.outline.as_ref().unwrap();
        assert!(o.warnings.is_empty(), "{:?}", o.warnings);
        assert_eq!(
            body(&make_template(o, &params).unwrap()),
            want[k],
            "{}",
            g.name
        );
    }
    // WKT, one POLYGON per line, and a MULTIPOLYGON of all three.
    let ring = |o: &clumpgen::Outline| {
        let mut p: Vec<String> = raw_points(o)
            .iter()
            .map(|p| format!("{:?} {:?}", p[0], p[1]))
            .collect();
        p.push(p[0].clone());
        format!("(({}))", p.join(", "))
    };
    let lines: Vec<String> = csv.iter().map(|o| format!("POLYGON {}", ring(o))).collect();
    let multi = format!(
        "MULTIPOLYGON ({})",
        csv.iter().map(ring).collect::<Vec<_>>().join(", ")
    );
    for (name, text) in [("lines.wkt", lines.join("\n")), ("multi.wkt", multi)] {
        let f = d.join(name);
        std::fs::write(&f, text).unwrap();
        let fg = read_grains(&f, &mm(), &GrainOptions::default()).unwrap();
        assert_eq!(fg.grains.len(), 3, "{name}");
        for (k, g) in fg.grains.iter().enumerate() {
            assert_eq!(g.name, format!("polygon-{k}"));
            let o = g.outline.as_ref().unwrap();
            assert_eq!(
                body(&make_template(o, &params).unwrap()),
                want[k],
                "{name} {k}"
            );
        }
    }
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn open_rings_are_closed_with_a_warning_and_holes_are_warned() {
    let d = tmp("open");
    let csv = csv_outlines();
    let f = d.join("open.geojson");
    std::fs::write(&f, geojson_of(&csv[..1], false, "")).unwrap();
    let fg = read_grains(&f, &mm(), &GrainOptions::default()).unwrap();
    let o = fg.grains[0].outline.as_ref().unwrap();
    assert_eq!(o.warnings.len(), 1, "{:?}", o.warnings);
    assert!(
        o.warnings[0].contains("ring not closed"),
        "{:?}",
        o.warnings
    );
    let want = body(&make_template(&csv[0], &ClumpParams::default()).unwrap());
    assert_eq!(
        body(&make_template(o, &ClumpParams::default()).unwrap()),
        want
    );
    // A square with a square hole (WKT).
    let f = d.join("holed.wkt");
    std::fs::write(
        &f,
        "POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0), (4 4, 6 4, 6 6, 4 6, 4 4))",
    )
    .unwrap();
    let fg = read_grains(&f, &mm(), &GrainOptions::default()).unwrap();
    let o = fg.grains[0].outline.as_ref().unwrap();
    assert!(
        o.warnings[0].contains("polygon 0 (line 1) has 1 hole") && o.warnings[0].contains("4.00 %"),
        "{:?}",
        o.warnings
    );
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn degrees_and_missing_units_are_refused_naming_the_file() {
    let d = tmp("crs");
    let csv = csv_outlines();
    let crs = r#","crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::4326"}}"#;
    let f = d.join("wgs84.geojson");
    std::fs::write(&f, geojson_of(&csv[..1], true, crs)).unwrap();
    let e = read_grains(&f, &mm(), &GrainOptions::default()).unwrap_err();
    let m = e.to_string();
    assert!(
        m.starts_with(&f.display().to_string()) && m.contains("geographic") && m.contains("4326"),
        "{m}"
    );
    // No units, every coordinate within ±180/±90: the error says they look like degrees.
    let f = d.join("plain.geojson");
    std::fs::write(&f, geojson_of(&csv[..1], true, "")).unwrap();
    let e = read_grains(&f, &ReadOptions::default(), &GrainOptions::default()).unwrap_err();
    let m = e.to_string();
    assert!(matches!(e, OutlineError::GisUnits { .. }), "{m}");
    assert!(m.contains("--units") && m.contains("degrees"), "{m}");
    // SRID=4326 in EWKT.
    let f = d.join("g.wkt");
    std::fs::write(&f, "SRID=4326;POLYGON ((0 0, 1 0, 1 1, 0 0))").unwrap();
    let m = read_grains(&f, &mm(), &GrainOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("g.wkt") && m.contains("geographic"), "{m}");
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn image_bad_inputs_name_the_file_and_the_grain() {
    let d = tmp("bad");
    // Empty mask.
    let f = d.join("empty.png");
    mask_png(&f, &["....", "...."]);
    let m = read_grains(&f, &px(1e-5), &GrainOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("empty.png") && m.contains("empty mask"), "{m}");
    // Missing pixel size.
    let m = read_grains(&f, &mm(), &GrainOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("empty.png") && m.contains("--px-scale"), "{m}");
    // Corrupt PNG.
    let f = d.join("corrupt.png");
    std::fs::write(&f, b"\x89PNG\r\n\x1a\nthis is not a png").unwrap();
    let e = read_grains(&f, &px(1e-5), &GrainOptions::default()).unwrap_err();
    assert!(matches!(e, OutlineError::Image { .. }), "{e}");
    assert!(e.to_string().contains("corrupt.png"), "{e}");
    // A colour image.
    let f = d.join("rgb.png");
    image::RgbImage::new(4, 4).save(&f).unwrap();
    let m = read_grains(&f, &px(1e-5), &GrainOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("rgb.png") && m.contains("greyscale"), "{m}");
    // Touching grains (sharing an edge) merge in a binary mask; grains meeting only at a corner
    // stay apart (4-connectivity); a grain on the border is warned; a hole is warned; a speck
    // below --min-pixels is skipped and counted.
    let f = d.join("mix.png");
    mask_png(
        &f,
        &[
            "..........##",
            ".####.....##",
            ".####.###...",
            "......#.#...",
            "......###.#.",
            ".........#..",
        ],
    );
    let g = GrainOptions::default().with_min(3);
    let fg = read_grains(&f, &px(1e-5), &g).unwrap();
    let names: Vec<&str> = fg.grains.iter().map(|g| g.name.as_str()).collect();
    // Components in raster order of their first pixels: the corner square (1), the two
    // touching 2x2 squares as one (2), the ring (3), the two diagonal single pixels (4, 5).
    assert_eq!(
        names,
        ["component-1", "component-2", "component-3"],
        "{:?}",
        fg.notes
    );
    assert_eq!(fg.notes.len(), 1);
    assert!(
        fg.notes[0].contains("skipped 2 of 5 components below --min-pixels 3"),
        "{:?}",
        fg.notes
    );
    let w = |k: usize| fg.grains[k].outline.as_ref().unwrap().warnings.join(" | ");
    assert!(
        w(0).contains("component 1 touches the image border"),
        "{}",
        w(0)
    );
    let merged = fg.grains[1].outline.as_ref().unwrap();
    assert!((polygon_props(&merged.points).area - 8.0 * 1e-10).abs() < 1e-22);
    assert!(w(1).is_empty(), "{}", w(1));
    assert!(w(2).contains("component 3 has 1 hole (1 px"), "{}", w(2));
    // Labels: a label in two pieces keeps the larger; --invert is for binary masks.
    let f = d.join("labels.tif");
    let img: ImageBuffer<Luma<u16>, Vec<u16>> = ImageBuffer::from_fn(8, 5, |x, y| {
        Luma([match (x, y) {
            (1..=3, 1..=3) => 300,
            (6, 1) => 300,
            (5..=6, 3..=4) => 7,
            _ => 0,
        }])
    });
    img.save(&f).unwrap();
    let fg = read_grains(&f, &px(1e-5), &GrainOptions::default().with_min(1)).unwrap();
    let names: Vec<&str> = fg.grains.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["label-7", "label-300"]);
    let o = fg.grains[1].outline.as_ref().unwrap();
    assert!(
        o.warnings[0].contains("label 300 is in 2 pieces"),
        "{:?}",
        o.warnings
    );
    assert!((polygon_props(&o.points).area - 9e-10).abs() < 1e-22);
    let inv = GrainOptions {
        invert: true,
        ..GrainOptions::default()
    };
    let m = read_grains(&f, &px(1e-5), &inv).unwrap_err().to_string();
    assert!(m.contains("--invert"), "{m}");
    // --mask binary on the same image: nonzero pixels, components.
    let bin = GrainOptions {
        mask: MaskMode::Binary,
        min_pixels: 1,
        invert: false,
        simplify: 0.0,
    };
    let fg = read_grains(&f, &px(1e-5), &bin).unwrap();
    assert_eq!(fg.grains.len(), 3);
    std::fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_batch_writes_each_grain_and_fails_a_bad_one_alone() {
    let d = tmp("batch");
    let input = d.join("in");
    std::fs::create_dir_all(&input).unwrap();
    let sq = |x: f64| {
        format!(
            "[[{x},0],[{},0],[{},10],[{x},10],[{x},0]]",
            x + 10.0,
            x + 10.0
        )
    };
    let bow = "[[0,0],[10,10],[10,0],[0,5],[0,0]]";
    let fc = format!(
        r#"{{"type":"FeatureCollection","features":[
 {{"type":"Feature","id":"a","properties":{{}},"geometry":{{"type":"Polygon","coordinates":[{}]}}}},
 {{"type":"Feature","properties":{{"name":"bow"}},"geometry":{{"type":"Polygon","coordinates":[{bow}]}}}},
 {{"type":"Feature","properties":{{}},"geometry":{{"type":"MultiPolygon","coordinates":[[{}],[{}]]}}}},
 {{"type":"Feature","properties":{{}},"geometry":{{"type":"LineString","coordinates":[[0,0],[1,1]]}}}}
]}}"#,
        sq(0.0),
        sq(20.0),
        sq(40.0)
    );
    std::fs::write(input.join("set.geojson"), fc).unwrap();
    std::fs::write(input.join("one.csv"), "0 0\n10 0\n10 10\n0 10\n").unwrap();
    let out = d.join("out");
    let o = BatchOptions {
        read: mm(),
        params: ClumpParams::default(),
        out: out.clone(),
        exports: Vec::new(),
        strict: false,
        grains: GrainOptions::default(),
    };
    let inputs = collect_inputs(std::slice::from_ref(&input)).unwrap();
    let r = run_batch(&inputs, &o, &|| {});
    let got: Vec<(Option<&str>, bool)> = r
        .items
        .iter()
        .map(|i| (i.grain.as_deref(), i.error.is_none()))
        .collect();
    assert_eq!(
        got,
        [
            (None, true),
            (Some("feature 0 (\"a\")"), true),
            (Some("feature 1 (\"bow\")"), false),
            (Some("feature 2 part 0"), true),
            (Some("feature 2 part 1"), true),
            (Some("feature 3"), false),
        ]
    );
    let set = input.join("set.geojson").display().to_string();
    let e = r.items[2].error.as_deref().unwrap();
    assert!(
        e.starts_with(&format!(
            "{set}, feature 1 (\"bow\"): outline intersects itself"
        )),
        "{e}"
    );
    let e = r.items[5].error.as_deref().unwrap();
    assert!(e.contains("feature 3") && e.contains("LineString"), "{e}");
    for f in [
        "one.json",
        "set/a.json",
        "set/feature-2-0.json",
        "set/feature-2-1.json",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    let t = Template::load(&out.join("set/a.json")).unwrap();
    assert_eq!(t.source.grain.as_deref(), Some("feature 0 (\"a\")"));
    assert_eq!(t.id, "set/a");
    r.save(&out.join(SUMMARY_FILE)).unwrap();
    let summary = std::fs::read_to_string(out.join(SUMMARY_FILE)).unwrap();
    assert!(
        summary.contains(r#""grain": "feature 2 part 1""#),
        "{summary}"
    );
    // Two features of one name: both refused by the clash check, the others written.
    let dup = r#"{"type":"FeatureCollection","features":[
 {"type":"Feature","id":"x","properties":{},"geometry":{"type":"Polygon","coordinates":[[[0,0],[1,0],[1,1],[0,0]]]}},
 {"type":"Feature","id":"x","properties":{},"geometry":{"type":"Polygon","coordinates":[[[0,0],[2,0],[2,2],[0,0]]]}},
 {"type":"Feature","id":"y","properties":{},"geometry":{"type":"Polygon","coordinates":[[[0,0],[3,0],[3,3],[0,0]]]}}]}"#;
    let f = d.join("dup.geojson");
    std::fs::write(&f, dup).unwrap();
    let inputs = collect_inputs(std::slice::from_ref(&f)).unwrap();
    let o2 = BatchOptions {
        out: d.join("out2"),
        ..o
    };
    let r = run_batch(&inputs, &o2, &|| {});
    let e = r.items[1].error.as_deref().unwrap();
    assert!(
        e.contains("would both be written as") && e.contains("feature 1 (\"x\")"),
        "{e}"
    );
    assert!(r.items[0].error.is_some() && r.items[2].error.is_none());
    assert!(!d.join("out2/dup/x.json").exists() && d.join("out2/dup/y.json").exists());
    std::fs::remove_dir_all(&d).unwrap();
}

/// The area error of a rasterised grain against its pixel size: always below P·px (half the
/// worst-case bound), and much smaller in practice (errors of boundary pixels cancel).
#[test]
fn mask_area_error_against_pixel_size() {
    let o = &csv_outlines()[0];
    let poly: Vec<[f64; 2]> = o.points.clone();
    let p = polygon_props(&poly);
    let perim = clumpgen::props::perimeter(&poly);
    let d = tmp("conv");
    for s in [32e-6, 16e-6, 8e-6, 4e-6, 2e-6] {
        let (img, _) = rasterise(std::slice::from_ref(&poly), s);
        let f = d.join("g.png");
        img.save(&f).unwrap();
        let fg = read_grains(&f, &px(s), &GrainOptions::default().with_min(1)).unwrap();
        let mo = fg.grains[0].outline.as_ref().unwrap();
        let a = polygon_props(&mo.points).area;
        let da = (a - p.area).abs();
        assert!(
            da <= perim * s,
            "px {s:e}: ΔA {da:e} > P·px {:e}",
            perim * s
        );
        eprintln!(
            "equant-01 at {:>4.0} µm/px: ΔA/A {:.2e}, ΔA/(P·px) {:.2e}",
            s * 1e6,
            da / p.area,
            da / (perim * s)
        );
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// `simplify` (geo's Ramer-Douglas-Peucker) drops staircase corners: far fewer vertices, the
/// area within tolerance × perimeter of the exact pixel outline's, still a valid template.
#[test]
fn simplified_pixel_outlines_stay_within_the_tolerance() {
    let o = &csv_outlines()[1];
    let s = 4e-6;
    let (img, _) = rasterise(std::slice::from_ref(&o.points), s);
    let d = tmp("simplify");
    let f = d.join("g.png");
    img.save(&f).unwrap();
    let exact = read_grains(&f, &px(s), &GrainOptions::default()).unwrap();
    let exact = exact.grains[0].outline.as_ref().unwrap();
    let tol = 1.0;
    let g = GrainOptions {
        simplify: tol,
        ..GrainOptions::default()
    };
    let simple = read_grains(&f, &px(s), &g).unwrap();
    let simple = simple.grains[0].outline.as_ref().unwrap();
    let (a0, a1) = (
        polygon_props(&exact.points).area,
        polygon_props(&simple.points).area,
    );
    let perim = clumpgen::props::perimeter(&exact.points);
    assert!((a1 - a0).abs() <= tol * s * perim, "{a0:e} {a1:e}");
    assert!(simple.points.len() * 3 < exact.points.len());
    let t = make_template(simple, &ClumpParams::default()).unwrap();
    assert!(t.residuals.max() < 1e-10);
    eprintln!(
        "concave-02 at 4 µm/px: {} corners, {} after simplify {tol} px; area {:.2e} relative",
        exact.points.len(),
        simple.points.len(),
        (a1 - a0).abs() / a0
    );
    std::fs::remove_dir_all(&d).unwrap();
}
