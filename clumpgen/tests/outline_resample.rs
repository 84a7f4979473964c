//! Resampling along the perimeter.

use std::f64::consts::PI;

use clumpgen::{polygon_props, resample, synth_grain, SynthParams};

/// Arc-length position (from vertex 0) of a point that lies on the closed polygon `p`.
fn arc_position(p: &[[f64; 2]], q: [f64; 2]) -> (f64, f64) {
    let n = p.len();
    let mut cum = 0.0;
    let mut best = (f64::INFINITY, 0.0);
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let t = (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0);
        let foot = [a[0] + t * d[0], a[1] + t * d[1]];
        let dist = (q[0] - foot[0]).hypot(q[1] - foot[1]);
        if dist < best.0 {
            best = (dist, cum + t * len2.sqrt());
        }
        cum += len2.sqrt();
    }
    best
}

fn grain() -> Vec<[f64; 2]> {
    synth_grain(
        5,
        &SynthParams {
            mean_radius: 1.2e-3,
            aspect_ratio: 2.2,
            roughness: 0.12,
            concavity: 0.5,
            n_points: 150,
        },
    )
}

#[test]
fn equal_spacing_along_the_perimeter() {
    let g = grain();
    let perim = polygon_props(&g).perimeter;
    for n in [3usize, 17, 64, 150, 1000] {
        let r = resample(&g, n);
        assert_eq!(r.len(), n);
        assert_eq!(r[0], g[0]);
        let step = perim / n as f64;
        let mut prev = 0.0;
        for (k, q) in r.iter().enumerate() {
            let (dist, s) = arc_position(&g, *q);
            assert!(
                dist < 1e-12 * perim,
                "point {k} is off the outline by {dist}"
            );
            // A point at vertex 0 may be found at arc length P instead of 0.
            let s = if k == 0 { 0.0 } else { s };
            if k > 0 {
                assert!(
                    ((s - prev) - step).abs() < 1e-9 * step,
                    "n {n} k {k}: spacing {} vs {step}",
                    s - prev
                );
            }
            prev = s;
        }
        // The closing gap too.
        assert!(((perim - prev) - step).abs() < 1e-9 * step);
    }
}

#[test]
fn regular_polygon_resampled_to_its_vertices_and_midpoints() {
    let n = 12;
    let p: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = 2.0 * PI * i as f64 / n as f64;
            [t.cos(), t.sin()]
        })
        .collect();
    let r = resample(&p, n);
    for (a, b) in r.iter().zip(&p) {
        assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
    }
    let r2 = resample(&p, 2 * n);
    for i in 0..n {
        let mid = [
            0.5 * (p[i][0] + p[(i + 1) % n][0]),
            0.5 * (p[i][1] + p[(i + 1) % n][1]),
        ];
        assert!((r2[2 * i][0] - p[i][0]).abs() < 1e-12);
        assert!((r2[2 * i + 1][0] - mid[0]).abs() < 1e-12);
        assert!((r2[2 * i + 1][1] - mid[1]).abs() < 1e-12);
    }
}

#[test]
fn area_converges_quadratically_on_a_smooth_outline() {
    let m = 4000;
    let ell: Vec<[f64; 2]> = (0..m)
        .map(|i| {
            let t = 2.0 * PI * i as f64 / m as f64;
            [3.0 * t.cos(), t.sin()]
        })
        .collect();
    let a0 = polygon_props(&ell).area;
    let errs: Vec<f64> = [25usize, 50, 100, 200]
        .iter()
        .map(|&n| (polygon_props(&resample(&ell, n)).area - a0).abs() / a0)
        .collect();
    for w in errs.windows(2) {
        // Chords cut the curve: error ~ 1/n², so doubling n divides it by ~4.
        assert!(w[1] < w[0] / 3.0, "{errs:?}");
    }
    assert!(errs[3] < 1e-3, "{errs:?}");
}

#[test]
fn degenerate_requests() {
    assert!(resample(&grain(), 0).is_empty());
    assert!(resample(&[], 5).is_empty());
    assert_eq!(resample(&[[1.0, 2.0]], 3), vec![[1.0, 2.0]; 3]);
}
