//! Polygon properties against closed forms.

use std::f64::consts::PI;

use clumpgen::{polygon_props, synth_grain, PolygonProps, SynthParams};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

fn rect(x0: f64, y0: f64, b: f64, h: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x0 + b, y0], [x0 + b, y0 + h], [x0, y0 + h]]
}

#[test]
fn rectangle() {
    let (b, h) = (3.0_f64, 2.0_f64);
    let p = polygon_props(&rect(1.0, -2.0, b, h));
    assert!(rel(p.area, b * h) < 1e-15);
    assert!(rel(p.centroid[0], 2.5) < 1e-15 && rel(p.centroid[1], -1.0) < 1e-15);
    assert!(rel(p.ixx, b * h.powi(3) / 12.0) < 1e-14, "{}", p.ixx);
    assert!(rel(p.iyy, h * b.powi(3) / 12.0) < 1e-14, "{}", p.iyy);
    assert!(p.ixy.abs() < 1e-14);
    assert!(rel(p.j, b * h * (b * b + h * h) / 12.0) < 1e-14);
    // Long axis along x: angle 0; i_min is the moment about it, b h^3/12.
    assert!(p.principal_angle.abs() < 1e-14);
    assert!(rel(p.i_min, b * h.powi(3) / 12.0) < 1e-14);
    assert!(rel(p.i_max, h * b.powi(3) / 12.0) < 1e-14);
    assert!(rel(p.perimeter, 2.0 * (b + h)) < 1e-15);
    // Tall rectangle: long axis along y, angle +pi/2 (range is (-pi/2, pi/2]).
    let p = polygon_props(&rect(0.0, 0.0, 1.0, 5.0));
    assert!(
        (p.principal_angle - PI / 2.0).abs() < 1e-14,
        "{}",
        p.principal_angle
    );
}

#[test]
fn right_triangle() {
    // Legs b along x and h along y, right angle at the origin.
    let (b, h) = (4.0_f64, 3.0_f64);
    let tri = [[0.0, 0.0], [b, 0.0], [0.0, h]];
    let p = polygon_props(&tri);
    assert!(rel(p.area, b * h / 2.0) < 1e-15);
    assert!(rel(p.centroid[0], b / 3.0) < 1e-15 && rel(p.centroid[1], h / 3.0) < 1e-15);
    assert!(rel(p.ixx, b * h.powi(3) / 36.0) < 1e-14, "{}", p.ixx);
    assert!(rel(p.iyy, h * b.powi(3) / 36.0) < 1e-14, "{}", p.iyy);
    // Product of area about the centroid: -b^2 h^2 / 72 for this orientation.
    assert!(rel(p.ixy, -b * b * h * h / 72.0) < 1e-14, "{}", p.ixy);
    assert!(rel(p.perimeter, b + h + 5.0) < 1e-15);
}

/// Rectangle [x0, x0+b] x [y0, y0+h] as (area, centroid, ixx, iyy) about its own centroid.
fn rect_parts(x0: f64, y0: f64, b: f64, h: f64) -> (f64, [f64; 2], f64, f64) {
    (
        b * h,
        [x0 + b / 2.0, y0 + h / 2.0],
        b * h.powi(3) / 12.0,
        h * b.powi(3) / 12.0,
    )
}

#[test]
fn l_shape_by_parallel_axis_theorem() {
    // L = [0,4]x[0,1] plus [0,1]x[1,3].
    let l = [
        [0.0, 0.0],
        [4.0, 0.0],
        [4.0, 1.0],
        [1.0, 1.0],
        [1.0, 3.0],
        [0.0, 3.0],
    ];
    let parts = [
        rect_parts(0.0, 0.0, 4.0, 1.0),
        rect_parts(0.0, 1.0, 1.0, 2.0),
    ];
    let a: f64 = parts.iter().map(|q| q.0).sum();
    let cx = parts.iter().map(|q| q.0 * q.1[0]).sum::<f64>() / a;
    let cy = parts.iter().map(|q| q.0 * q.1[1]).sum::<f64>() / a;
    // Parallel-axis (Steiner) theorem: I = I_c + A d^2; product: I_xy = I_xy,c + A dx dy.
    let ixx: f64 = parts
        .iter()
        .map(|q| q.2 + q.0 * (q.1[1] - cy).powi(2))
        .sum();
    let iyy: f64 = parts
        .iter()
        .map(|q| q.3 + q.0 * (q.1[0] - cx).powi(2))
        .sum();
    let ixy: f64 = parts
        .iter()
        .map(|q| q.0 * (q.1[0] - cx) * (q.1[1] - cy))
        .sum();
    let p = polygon_props(&l);
    assert!(rel(p.area, a) < 1e-15);
    assert!(rel(p.centroid[0], cx) < 1e-14 && rel(p.centroid[1], cy) < 1e-14);
    assert!(rel(p.ixx, ixx) < 1e-14, "{} {}", p.ixx, ixx);
    assert!(rel(p.iyy, iyy) < 1e-14, "{} {}", p.iyy, iyy);
    assert!(rel(p.ixy, ixy) < 1e-14, "{} {}", p.ixy, ixy);
    assert!(ixy < 0.0); // the L's arms point along +x and +y: mass in quadrants II and IV
}

#[test]
fn rotated_rectangle() {
    let (b, h) = (4.0_f64, 1.0_f64);
    let (ixx0, iyy0) = (b * h.powi(3) / 12.0, h * b.powi(3) / 12.0);
    for alpha in [0.3_f64, -1.1, 2.0, PI / 2.0] {
        let (c, s) = (alpha.cos(), alpha.sin());
        let pts: Vec<[f64; 2]> = rect(-b / 2.0, -h / 2.0, b, h)
            .iter()
            .map(|q| [5.0 + c * q[0] - s * q[1], -7.0 + s * q[0] + c * q[1]])
            .collect();
        let p = polygon_props(&pts);
        // Second-moment tensor [[∫x², ∫xy], [∫xy, ∫y²]] = R diag(iyy0, ixx0) Rᵀ.
        let ex2 = iyy0 * c * c + ixx0 * s * s;
        let ey2 = iyy0 * s * s + ixx0 * c * c;
        let exy = (iyy0 - ixx0) * s * c;
        assert!((p.iyy - ex2).abs() < 1e-13 * iyy0, "{alpha}");
        assert!((p.ixx - ey2).abs() < 1e-13 * iyy0, "{alpha}");
        assert!((p.ixy - exy).abs() < 1e-13 * iyy0, "{alpha}");
        assert!(rel(p.i_min, ixx0) < 1e-12 && rel(p.i_max, iyy0) < 1e-12);
        // Long axis at alpha, as an axis (modulo pi), and reported in (-pi/2, pi/2].
        let d = (p.principal_angle - alpha).rem_euclid(PI);
        assert!(d.min(PI - d) < 1e-12, "{alpha}: {}", p.principal_angle);
        assert!(p.principal_angle > -PI / 2.0 && p.principal_angle <= PI / 2.0);
        assert!(rel(p.centroid[0], 5.0) < 1e-14 && rel(p.centroid[1], -7.0) < 1e-14);
    }
}

#[test]
fn regular_720_gon_and_disc() {
    let (n, r) = (720usize, 0.37_f64);
    let pts: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let t = 2.0 * PI * i as f64 / n as f64;
            [r * t.cos(), r * t.sin()]
        })
        .collect();
    let p = polygon_props(&pts);
    let alpha = 2.0 * PI / n as f64;
    // Exact regular-polygon formulas (n triangles of apex angle alpha and sides R; a
    // triangle O,P1,P2 has polar moment A_t (|P1|²+|P2|²+P1·P2)/6 about O).
    let a_exact = n as f64 * r * r * alpha.sin() / 2.0;
    let j_exact = a_exact * r * r * (2.0 + alpha.cos()) / 6.0;
    assert!(rel(p.area, a_exact) < 1e-12, "{}", rel(p.area, a_exact));
    assert!(rel(p.j, j_exact) < 1e-12, "{}", rel(p.j, j_exact));
    assert!(p.centroid[0].abs() < 1e-14 * r && p.centroid[1].abs() < 1e-14 * r);
    assert!(rel(p.ixx, p.iyy) < 1e-12 && p.ixy.abs() < 1e-12 * p.j);
    // Against the disc: A/(pi R²) = sin(a)/a ≈ 1 - a²/6 and J/(pi R⁴/2) ≈ 1 - a²/3.
    let ea = (PI * r * r - p.area) / (PI * r * r);
    let ej = (PI * r.powi(4) / 2.0 - p.j) / (PI * r.powi(4) / 2.0);
    assert!(ea > 0.0 && ea < 1.001 * alpha * alpha / 6.0, "{ea}");
    assert!(ej > 0.0 && ej < 1.001 * alpha * alpha / 3.0, "{ej}");
    assert!(ea > 0.99 * alpha * alpha / 6.0 && ej > 0.99 * alpha * alpha / 3.0);
}

fn assert_same_props(a: &PolygonProps, b: &PolygonProps, shift: [f64; 2], tol: f64) {
    assert!(rel(a.area, b.area) < tol, "area {}", rel(a.area, b.area));
    assert!(rel(a.ixx, b.ixx) < tol, "ixx {}", rel(a.ixx, b.ixx));
    assert!(rel(a.iyy, b.iyy) < tol, "iyy {}", rel(a.iyy, b.iyy));
    assert!((a.ixy - b.ixy).abs() < tol * b.j, "ixy");
    assert!(rel(a.j, b.j) < tol, "j");
    assert!(rel(a.perimeter, b.perimeter) < tol, "perimeter");
    let size = b.area.sqrt();
    for (k, sh) in shift.iter().enumerate() {
        let d = (a.centroid[k] - sh - b.centroid[k]).abs();
        assert!(d < tol * size, "centroid {k}: {}", d / size);
    }
}

#[test]
fn translation_invariance_at_utm_offsets() {
    let base = synth_grain(
        3,
        &SynthParams {
            mean_radius: 5.0,
            aspect_ratio: 2.0,
            roughness: 0.08,
            concavity: 0.4,
            n_points: 300,
        },
    );
    let p0 = polygon_props(&base);
    for shift in [[1e6, 1e6], [339_043.9, 4_686_358.5], [-1e6, 3e5]] {
        let moved: Vec<[f64; 2]> = base
            .iter()
            .map(|q| [q[0] + shift[0], q[1] + shift[1]])
            .collect();
        let p1 = polygon_props(&moved);
        // The shifted coordinates are themselves rounded to ~1e-10 (ulp of 1e6), which for a
        // grain of size ~10 is ~1e-11 relative: 1e-9 leaves room only for a sound algorithm.
        assert_same_props(&p1, &p0, shift, 1e-9);
    }
}

#[test]
fn clockwise_gives_the_same_properties() {
    let mut pts = synth_grain(
        11,
        &SynthParams {
            mean_radius: 1e-3,
            aspect_ratio: 1.5,
            roughness: 0.1,
            concavity: 0.5,
            n_points: 120,
        },
    );
    let a = polygon_props(&pts);
    pts.reverse();
    let b = polygon_props(&pts);
    assert!(a.area > 0.0);
    assert_same_props(&b, &a, [0.0, 0.0], 1e-13);
    assert!((a.principal_angle - b.principal_angle).abs() < 1e-12);
}
