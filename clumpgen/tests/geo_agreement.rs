//! Where the hand-written polygon code and the `geo` crate compute the same thing, they agree:
//! area and centroid of every shipped outline, and validity (simple or self-intersecting) of
//! the shapes of the validity tests. The hand-written code stays where it gives more (the
//! polar moment J; the two meeting edges and the point) or where swapping would change the
//! last bits of every template; see the module docs of `clumpgen::outline`.

use std::path::Path;

use clumpgen::{find_self_intersection, polygon_props, read_outline, ReadOptions};
use geo::{Area, Centroid, Coord, LineString, Polygon, Validation};

fn geo_polygon(p: &[[f64; 2]]) -> Polygon<f64> {
    let ring: LineString<f64> = p.iter().map(|&[x, y]| Coord { x, y }).collect();
    Polygon::new(ring, vec![])
}

#[test]
fn area_and_centroid_agree_with_geo_on_every_outline() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/outlines");
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "csv") {
            continue;
        }
        let o = read_outline(&p, &ReadOptions::default()).unwrap();
        let ours = polygon_props(&o.points);
        let g = geo_polygon(&o.points);
        let area = g.signed_area();
        let c = g.centroid().unwrap();
        let r_eq = (ours.area / std::f64::consts::PI).sqrt();
        let da = (area - ours.area).abs() / ours.area;
        let dc = (c.x() - ours.centroid[0]).hypot(c.y() - ours.centroid[1]) / r_eq;
        worst = worst.max(da).max(dc);
        n += 1;
    }
    assert!(n >= 29, "{n} outlines");
    assert!(worst < 1e-13, "worst relative difference {worst:e}");
    eprintln!("{n} outlines: area and centroid agree with geo to {worst:.1e} (relative)");
}

#[test]
fn validity_agrees_with_geo() {
    let shapes: Vec<(&str, Vec<[f64; 2]>)> = vec![
        ("triangle", vec![[0., 0.], [1., 0.], [0., 1.]]),
        (
            "concave L",
            vec![[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]],
        ),
        ("bowtie", vec![[0., 0.], [2., 2.], [2., 0.], [0., 2.]]),
        (
            "vertex on an edge",
            vec![
                [0., 0.],
                [2., 0.],
                [2., 2.],
                [1.5, 2.0],
                [1., 0.],
                [0.5, 2.],
            ],
        ),
        (
            "figure eight",
            vec![
                [0., 0.],
                [1., 0.],
                [1., 1.],
                [2., 1.],
                [2., 2.],
                [1., 2.],
                [1., 1.],
                [0., 1.],
            ],
        ),
        (
            "slit",
            vec![
                [0., 0.],
                [3., 0.],
                [3., 1.],
                [2., 1.],
                [2., 0.],
                [1., 0.],
                [1., 1.],
                [0., 1.],
            ],
        ),
    ];
    for (name, p) in shapes {
        let ours = find_self_intersection(&p).is_none();
        let theirs = geo_polygon(&p).is_valid();
        assert_eq!(
            ours, theirs,
            "{name}: ours simple = {ours}, geo valid = {theirs}"
        );
    }
}
