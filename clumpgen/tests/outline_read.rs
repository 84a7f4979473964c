//! Outline reading: formats, units, normalization and one error per kind of bad input.

use std::path::PathBuf;

use clumpgen::error::Pos;
use clumpgen::props::signed_area;
use clumpgen::{parse_outline, polygon_props, read_outline, OutlineError, ReadOptions, Units};

fn csv(text: &str) -> Result<clumpgen::Outline, OutlineError> {
    parse_outline(text, "t", "t.csv", false, &ReadOptions::default())
}

fn csv_with(text: &str, opts: ReadOptions) -> Result<clumpgen::Outline, OutlineError> {
    parse_outline(text, "t", "t.csv", false, &opts)
}

fn json(text: &str) -> Result<clumpgen::Outline, OutlineError> {
    parse_outline(text, "t", "t.json", true, &ReadOptions::default())
}

fn area(o: &clumpgen::Outline) -> f64 {
    polygon_props(&o.points).area
}

fn tmp(name: &str, contents: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("outline_read");
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, contents).unwrap();
    p
}

const SQUARE_MM: &str = "x,y\n0,0\n2,0\n2,1\n0,1\n";

#[test]
fn csv_with_header_defaults_to_mm() {
    let o = csv(SQUARE_MM).unwrap();
    assert_eq!(o.units, Units::Mm);
    assert_eq!(o.points.len(), 4);
    assert!((area(&o) - 2e-6).abs() < 1e-18);
    assert_eq!(o.origin, [1e-3, 0.5e-3]);
    assert!(o.warnings.is_empty());
    // Local frame: bounding-box centre subtracted.
    assert_eq!(o.points[0], [-1e-3, -0.5e-3]);
}

#[test]
fn whitespace_tab_and_comments() {
    let text = "# a grain\n0 0\n2\t0   # trailing comment\n\n2 \t 1\n# middle\n0   1\n";
    let o = csv(text).unwrap();
    assert_eq!(o.points.len(), 4);
    assert!((area(&o) - 2e-6).abs() < 1e-18);
}

#[test]
fn declared_units_are_honoured() {
    let text = "# gravel, UTM metres; grain 0; units: m\nx,y\n0,0\n2,0\n2,1\n0,1\n";
    let o = csv(text).unwrap();
    assert_eq!(o.units, Units::M);
    assert!((area(&o) - 2.0).abs() < 1e-15);
    let o = csv("# units: um\n0,0\n2,0\n2,1\n0,1\n").unwrap();
    assert_eq!(o.units, Units::Um);
    assert!((area(&o) - 2e-12).abs() < 1e-27);
    let o = csv("# units: px; metres_per_px: 1e-4\n0,0\n2,0\n2,1\n0,1\n").unwrap();
    assert_eq!(
        o.units,
        Units::Px {
            metres_per_px: 1e-4
        }
    );
    assert!((area(&o) - 2e-8).abs() < 1e-22);
}

#[test]
fn option_overrides_the_file_with_a_warning() {
    let text = "# units: m\n0,0\n2,0\n2,1\n0,1\n";
    let o = csv_with(
        text,
        ReadOptions {
            units: Some(Units::Mm),
            resample: None,
        },
    )
    .unwrap();
    assert_eq!(o.units, Units::Mm);
    assert!((area(&o) - 2e-6).abs() < 1e-18);
    assert_eq!(o.warnings.len(), 1);
    assert!(o.warnings[0].contains("line 1"), "{:?}", o.warnings);
    // px declared in the file, pixel size given by the option: fine, no warning.
    let o = csv_with(
        "# units: px\n0,0\n2,0\n2,1\n0,1\n",
        ReadOptions {
            units: Some(Units::Px {
                metres_per_px: 1e-4,
            }),
            resample: None,
        },
    )
    .unwrap();
    assert!(o.warnings.is_empty());
    assert!((area(&o) - 2e-8).abs() < 1e-22);
}

#[test]
fn json_format() {
    let o = json(r#"{"units": "mm", "points": [[0, 0], [2, 0], [2, 1], [0, 1]]}"#).unwrap();
    assert_eq!(o.units, Units::Mm);
    assert!((area(&o) - 2e-6).abs() < 1e-18);
    let o = json(r#"{"name": "g", "points": [[0, 0], [2, 0], [2, 1], [0, 1], [0, 0]]}"#).unwrap();
    assert_eq!(o.points.len(), 4);
    assert_eq!(o.units, Units::Mm);
    let o = json(r#"{"units": "µm", "points": [[0, 0], [2, 0], [2, 1], [0, 1]]}"#).unwrap();
    assert_eq!(o.units, Units::Um);
    let e = json("{\n  \"points\": [[0, 0], [2, 0],\n  [2, \"a\"]]}").unwrap_err();
    assert!(matches!(e, OutlineError::Json { line: 3, .. }), "{e}");
    assert!(e.to_string().contains("t.json"), "{e}");
}

#[test]
fn clockwise_input_comes_out_counter_clockwise() {
    let cw = "0,0\n0,1\n2,1\n2,0\n";
    let o = csv(cw).unwrap();
    assert!(signed_area(&o.points) > 0.0);
    assert!((area(&o) - 2e-6).abs() < 1e-18);
    // Same vertex set as the input.
    let mut got: Vec<[f64; 2]> = o.points.clone();
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        got,
        vec![
            [-1e-3, -0.5e-3],
            [-1e-3, 0.5e-3],
            [1e-3, -0.5e-3],
            [1e-3, 0.5e-3]
        ]
    );
}

#[test]
fn duplicates_dropped_with_warning_and_closing_point_silently() {
    let text = "x,y\n0,0\n0,0\n2,0\n2,1\n2,1\n2,1\n0,1\n0,0\n";
    let o = csv(text).unwrap();
    assert_eq!(o.points.len(), 4);
    assert_eq!(
        o.warnings,
        vec!["dropped 3 consecutive duplicate points (lines 3, 6, 7)".to_string()]
    );
    // Only a closing point: no warning.
    let o = csv("0,0\n2,0\n2,1\n0,1\n0,0\n").unwrap();
    assert_eq!(o.points.len(), 4);
    assert!(o.warnings.is_empty());
}

#[test]
fn local_origin_keeps_utm_precision() {
    // Binary-exact UTM-like coordinates: a 0.125 m x 0.0625 m rectangle.
    let (x0, y0) = (339_043.937_5, 4_686_358.5);
    let text = format!(
        "# units: m\n{},{}\n{},{}\n{},{}\n{},{}\n",
        x0,
        y0,
        x0 + 0.125,
        y0,
        x0 + 0.125,
        y0 + 0.0625,
        x0,
        y0 + 0.0625
    );
    let o = csv(&text).unwrap();
    let p = polygon_props(&o.points);
    assert_eq!(p.area, 0.125 * 0.0625);
    assert_eq!(p.ixx, 0.125 * 0.0625f64.powi(3) / 12.0);
    assert_eq!(p.iyy, 0.0625 * 0.125f64.powi(3) / 12.0);
    assert_eq!(o.origin, [x0 + 0.0625, y0 + 0.03125]);
    // Input point = local + origin.
    assert_eq!(o.points[0][0] + o.origin[0], x0);
}

#[test]
fn too_few_distinct_points() {
    let e = csv("0,0\n1,1\n0,0\n1,1\n").unwrap_err();
    assert!(
        matches!(e, OutlineError::TooFewPoints { distinct: 2, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("t.csv"));
    assert!(matches!(
        csv("x,y\n").unwrap_err(),
        OutlineError::TooFewPoints { distinct: 0, .. }
    ));
}

#[test]
fn non_finite_numbers() {
    for bad in ["nan,1", "0,inf", "1e400,0", "-infinity,2"] {
        let e = csv(&format!("0,0\n1,0\n{bad}\n0,1\n")).unwrap_err();
        match &e {
            OutlineError::NonFinite { pos, text, .. } => {
                assert_eq!(*pos, Pos::Line(3));
                assert_eq!(text, bad);
            }
            _ => panic!("{bad}: {e}"),
        }
        assert!(e.to_string().contains("t.csv, line 3"), "{e}");
    }
}

#[test]
fn unparsable_line() {
    let e = csv("x,y\n0,0\n1,0\n1,abc\n0,1\n").unwrap_err();
    match &e {
        OutlineError::Unparsable { line, text, .. } => {
            assert_eq!(*line, 4);
            assert_eq!(text, "1,abc");
        }
        _ => panic!("{e}"),
    }
    let msg = e.to_string();
    assert!(
        msg.contains("t.csv, line 4") && msg.contains("1,abc"),
        "{msg}"
    );
    let e = csv("0,0\n1,0,5\n").unwrap_err();
    assert!(matches!(e, OutlineError::Unparsable { line: 2, .. }), "{e}");
}

#[test]
fn zero_area() {
    let e = csv("0,0\n1,1\n2,2\n3,3\n").unwrap_err();
    assert!(matches!(e, OutlineError::ZeroArea { .. }), "{e}");
    // Two equal loops of opposite orientation cancel exactly.
    let e = csv("0,0\n2,2\n2,0\n0,2\n").unwrap_err();
    assert!(matches!(e, OutlineError::ZeroArea { .. }), "{e}");
}

/// Issue 48 D12: coordinates of 1e200 mm (before: "signed area inf ... points collinear") or
/// 1e-200 mm (before: "signed area 0e0") are refused by their size with a hint at the units; the
/// ends of the range are read.
#[test]
fn outlines_of_no_physical_size_are_refused_by_size() {
    for (scale, size) in [("1e200", "1e197 m"), ("1e-200", "1e-203 m")] {
        let text = format!("x,y\n0,0\n{scale},0\n{scale},{scale}\n0,{scale}\n");
        let e = csv(&text).unwrap_err();
        assert!(matches!(e, OutlineError::OutOfScale { .. }), "{e}");
        let msg = e.to_string();
        assert!(msg.contains(size) && msg.contains("--units"), "{msg}");
    }
    // 1e-6 mm = 1 nm and 1e7 mm = 10 km: inside.
    for side in ["1e-6", "1e7"] {
        let text = format!("0,0\n{side},0\n{side},{side}\n0,{side}\n");
        assert!(csv(&text).is_ok(), "{side} mm");
    }
}

#[test]
fn self_intersection_names_edges_lines_and_point() {
    // Unequal bow-tie at UTM-like offsets; points on lines 3..6.
    let (x0, y0) = (339_000.0, 4_686_000.0);
    let pts = [[0.0, 0.0], [4.0, 4.0], [4.0, 0.0], [0.0, 2.0]];
    let mut text = String::from("# bow tie; units: m\nx,y\n");
    for p in pts {
        text += &format!("{},{}\n", x0 + p[0], y0 + p[1]);
    }
    let e = csv(&text).unwrap_err();
    match &e {
        OutlineError::SelfIntersection {
            a, b, point, units, ..
        } => {
            assert_eq!(a.vertices, [0, 1]);
            assert_eq!(a.pos, [Pos::Line(3), Pos::Line(4)]);
            assert_eq!(b.vertices, [2, 3]);
            assert_eq!(b.pos, [Pos::Line(5), Pos::Line(6)]);
            // Edges y = x and y = 2 - x/2 cross at (4/3, 4/3), reported in input coordinates.
            assert!((point[0] - (x0 + 4.0 / 3.0)).abs() < 1e-9, "{point:?}");
            assert!((point[1] - (y0 + 4.0 / 3.0)).abs() < 1e-9, "{point:?}");
            assert_eq!(units, "m");
        }
        _ => panic!("{e}"),
    }
    let msg = e.to_string();
    assert!(msg.contains("edge 0-1 (line 3 to line 4)"), "{msg}");
    assert!(msg.contains("edge 2-3 (line 5 to line 6)"), "{msg}");
}

#[test]
fn self_intersection_vertex_indices_count_dropped_duplicates() {
    // Vertex (1,0) touches edge (0,0)-(2,0); a duplicate before it shifts file indices.
    let text = "0,0\n2,0\n2,2\n2,2\n1.5,2\n1,0\n0.5,2\n";
    let e = csv(text).unwrap_err();
    match &e {
        OutlineError::SelfIntersection { a, b, point, .. } => {
            assert_eq!(a.vertices, [0, 1]);
            assert_eq!(b.vertices, [4, 5]);
            assert_eq!(b.pos, [Pos::Line(5), Pos::Line(6)]);
            assert_eq!(*point, [1.0, 0.0]);
        }
        _ => panic!("{e}"),
    }
}

#[test]
fn unknown_units() {
    let e = csv("# units: furlong\n0,0\n2,0\n2,1\n").unwrap_err();
    match &e {
        OutlineError::UnknownUnits { pos, text, .. } => {
            assert_eq!(*pos, Some(Pos::Line(1)));
            assert_eq!(text, "furlong");
        }
        _ => panic!("{e}"),
    }
    assert!(e.to_string().contains("t.csv, line 1"), "{e}");
    let e = json(r#"{"units": "parsec", "points": [[0, 0], [2, 0], [2, 1]]}"#).unwrap_err();
    assert!(matches!(e, OutlineError::UnknownUnits { .. }), "{e}");
}

#[test]
fn px_without_scale() {
    let e = csv("# units: px\n0,0\n2,0\n2,1\n").unwrap_err();
    assert!(
        matches!(
            e,
            OutlineError::PxWithoutScale {
                pos: Some(Pos::Line(1)),
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("t.csv"), "{e}");
    let e = csv_with(
        SQUARE_MM,
        ReadOptions {
            units: Some(Units::Px { metres_per_px: 0.0 }),
            resample: None,
        },
    )
    .unwrap_err();
    assert!(matches!(e, OutlineError::BadScale { .. }), "{e}");
}

#[test]
fn resample_option() {
    let o = csv_with(
        SQUARE_MM,
        ReadOptions {
            units: None,
            resample: Some(60),
        },
    )
    .unwrap();
    assert_eq!(o.points.len(), 60);
    assert!((area(&o) - 2e-6).abs() < 1e-18); // a rectangle with its corners on samples
    let e = csv_with(
        SQUARE_MM,
        ReadOptions {
            units: None,
            resample: Some(2),
        },
    )
    .unwrap_err();
    assert!(matches!(e, OutlineError::BadOption { .. }), "{e}");
}

/// Resampling is bounded (issue 20, item 3): 10,000,000 points are refused at once, naming
/// the file, the count and the limit (before: the outline was resampled and the fill ran for
/// minutes).
#[test]
fn resampling_beyond_the_limit_is_refused() {
    let t0 = std::time::Instant::now();
    let e = csv_with(
        SQUARE_MM,
        ReadOptions {
            units: None,
            resample: Some(10_000_000),
        },
    )
    .unwrap_err();
    assert!(matches!(e, OutlineError::BadOption { .. }), "{e}");
    let m = e.to_string();
    assert!(
        m.starts_with("t.csv: bad read option: resample to 10000000 points: at most 1000000"),
        "{m}"
    );
    assert!(t0.elapsed().as_secs_f64() < 5.0);
    let o = csv_with(
        SQUARE_MM,
        ReadOptions {
            units: None,
            resample: Some(1_000_000),
        },
    )
    .unwrap();
    assert_eq!(o.points.len(), 1_000_000);
}

#[test]
fn read_from_files() {
    let p = tmp("grain-007.csv", SQUARE_MM);
    let o = read_outline(&p, &ReadOptions::default()).unwrap();
    assert_eq!(o.name, "grain-007");
    assert_eq!(o.source, p.display().to_string());
    // sha256 of the bytes "x,y\n0,0\n2,0\n2,1\n0,1\n" (coreutils sha256sum).
    assert_eq!(
        o.sha256,
        "491d31ad89ee2ba8ccc2c5cc7cdbc2bc725c3ba847483b141d63a7207526bec2"
    );
    let pj = tmp(
        "g.JSON",
        r#"{"units": "m", "points": [[0, 0], [2, 0], [2, 1], [0, 1]]}"#,
    );
    let o = read_outline(&pj, &ReadOptions::default()).unwrap();
    assert_eq!(o.units, Units::M);
    assert_eq!(o.name, "g");
    let missing = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("no/such/file.csv");
    let e = read_outline(&missing, &ReadOptions::default()).unwrap_err();
    assert!(matches!(e, OutlineError::Io { .. }), "{e}");
    assert!(e.to_string().contains("file.csv"));
}
