//! The project's generated outlines in `data/outlines/` read cleanly and match their README.

use std::path::PathBuf;

use clumpgen::props::signed_area;
use clumpgen::{polygon_props, read_outline, shape_descriptors, ReadOptions, Units};

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../data/outlines")
}

#[test]
fn all_outlines_read_without_warnings() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    assert!(files.len() >= 25, "{} files", files.len());
    let (mut concave, mut elongated) = (0, 0);
    for f in &files {
        let o = read_outline(f, &ReadOptions::default()).unwrap();
        assert_eq!(o.units, Units::Mm);
        assert!(o.warnings.is_empty(), "{}: {:?}", f.display(), o.warnings);
        assert!((60..=200).contains(&o.points.len()), "{}", f.display());
        assert!(signed_area(&o.points) > 0.0);
        let p = polygon_props(&o.points);
        let d = shape_descriptors(&o.points, &p);
        assert!(
            (1.0..=3.0 + 1e-9).contains(&d.aspect_ratio),
            "{}",
            f.display()
        );
        if d.solidity < 0.93 {
            concave += 1;
        }
        if d.aspect_ratio > 2.7 {
            elongated += 1;
        }
        if o.name != "table1-grain" {
            assert!(
                (0.5e-3 - 1e-12..=2e-3 + 1e-12).contains(&d.r_eq),
                "{}: r_eq {}",
                f.display(),
                d.r_eq
            );
        }
    }
    assert!(concave >= 4 && elongated >= 4, "{concave} {elongated}");
}

#[test]
fn table1_grain_has_the_published_area() {
    let o = read_outline(
        &data_dir().join("table1-grain.csv"),
        &ReadOptions::default(),
    )
    .unwrap();
    let a = polygon_props(&o.points).area;
    assert!((a - 2246.63e-6).abs() < 1e-12 * 2246.63e-6, "{a}");
}
