//! Synthetic grains: determinism, simplicity, requested size and aspect ratio.

use std::f64::consts::PI;

use clumpgen::props::signed_area;
use clumpgen::{
    find_self_intersection, parse_outline, polygon_props, shape_descriptors, synth_grain,
    ReadOptions, SynthParams,
};

fn params(seed: u64) -> SynthParams {
    // Spread of parameters derived from the seed.
    let f =
        |k: u64, n: u64| ((seed.wrapping_mul(2654435761).wrapping_add(k)) % n) as f64 / n as f64;
    SynthParams {
        mean_radius: 0.5e-3 + 1.5e-3 * f(1, 97),
        aspect_ratio: 1.0 + 2.0 * f(2, 89),
        roughness: 0.15 * f(3, 83),
        concavity: 0.6 * f(4, 79),
        n_points: 60 + (140.0 * f(5, 73)) as usize,
    }
}

#[test]
fn deterministic_for_a_seed() {
    let p = params(7);
    let a = synth_grain(42, &p);
    let b = synth_grain(42, &p);
    assert_eq!(a, b);
    let c = synth_grain(43, &p);
    assert_ne!(a, c);
}

#[test]
fn simple_ccw_with_requested_size_and_aspect_ratio() {
    for seed in 0..300u64 {
        let p = params(seed);
        let g = synth_grain(seed, &p);
        assert_eq!(g.len(), p.n_points);
        assert!(signed_area(&g) > 0.0, "seed {seed}: not counter-clockwise");
        assert!(
            find_self_intersection(&g).is_none(),
            "seed {seed}: self-intersecting"
        );
        let pr = polygon_props(&g);
        let a = PI * p.mean_radius * p.mean_radius;
        assert!((pr.area - a).abs() < 1e-12 * a, "seed {seed}: area");
        let r = p.mean_radius;
        assert!(pr.centroid[0].abs() < 1e-12 * r && pr.centroid[1].abs() < 1e-12 * r);
        let d = shape_descriptors(&g, &pr);
        assert!(
            (d.aspect_ratio - p.aspect_ratio).abs() < 1e-9 * p.aspect_ratio,
            "seed {seed}: aspect {} vs {}",
            d.aspect_ratio,
            p.aspect_ratio
        );
    }
}

#[test]
fn concavity_lowers_solidity_and_roughness_lowers_circularity() {
    let base = SynthParams {
        mean_radius: 1.0,
        aspect_ratio: 1.0,
        roughness: 0.0,
        concavity: 0.0,
        n_points: 200,
    };
    let mean = |p: &SynthParams, f: &dyn Fn(&clumpgen::ShapeDescriptors) -> f64| {
        (0..40u64)
            .map(|s| {
                let g = synth_grain(s, p);
                f(&shape_descriptors(&g, &polygon_props(&g)))
            })
            .sum::<f64>()
            / 40.0
    };
    let smooth = mean(&base, &|d| d.solidity);
    assert!(smooth > 0.999, "{smooth}"); // a 200-gon circle: convex
    let dented = SynthParams {
        concavity: 0.5,
        ..base
    };
    let s = mean(&dented, &|d| d.solidity);
    assert!(s < 0.97, "mean solidity with dents {s}");
    let c0 = mean(&base, &|d| d.circularity);
    let rough = SynthParams {
        roughness: 0.15,
        ..base
    };
    let c1 = mean(&rough, &|d| d.circularity);
    assert!(c0 > 0.999 && c1 < c0 - 0.02, "{c0} {c1}");
}

#[test]
fn round_trip_through_the_reader() {
    let g = synth_grain(9, &params(9));
    // Written in mm as the data generator does; Rust prints shortest round-trip decimals.
    let mut text = String::from("# units: mm\nx,y\n");
    for q in &g {
        text += &format!("{},{}\n", q[0] * 1e3, q[1] * 1e3);
    }
    let o = parse_outline(&text, "g", "g.csv", false, &ReadOptions::default()).unwrap();
    assert!(o.warnings.is_empty());
    assert_eq!(o.points.len(), g.len());
    let (a, b) = (polygon_props(&o.points), polygon_props(&g));
    assert!((a.area - b.area).abs() < 1e-12 * b.area);
    assert!((a.j - b.j).abs() < 1e-12 * b.j);
}
