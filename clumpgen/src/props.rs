//! Exact area, centroid and second moments of area of a simple polygon.
//!
//! Formulas: Green's theorem applied to the monomials 1, x, y, x², y², xy over a polygon with
//! vertices (x_i, y_i), i = 0..n-1 (closing edge implied), with the cross term
//! c_i = x_i y_{i+1} − x_{i+1} y_i (signed area of the triangle origin, i, i+1, doubled):
//!
//! * A    = ½ Σ c_i
//! * ∫x dA = ⅙ Σ (x_i + x_{i+1}) c_i,  ∫y dA = ⅙ Σ (y_i + y_{i+1}) c_i
//! * ∫x² dA = 1/12 Σ (x_i² + x_i x_{i+1} + x_{i+1}²) c_i  (and likewise ∫y² dA)
//! * ∫xy dA = 1/24 Σ (x_i y_{i+1} + 2 x_i y_i + 2 x_{i+1} y_{i+1} + x_{i+1} y_i) c_i
//!
//! (C. Steger, "On the calculation of arbitrary moments of polygons", TU München FGBV-96-05,
//! 1996, eqs. for moments up to order 2; also P. Bourke, "Calculating the area and centroid of a
//! polygon", 1988.) All sums are negated for a clockwise polygon, so the routine divides by
//! the sign of A and works for either orientation.
//!
//! Precision: pass 1 computes A and the centroid with the vertices shifted by their bounding-box
//! centre; pass 2 computes the second moments with the vertices shifted by that centroid, so no
//! parallel-axis subtraction of large numbers is needed. This keeps full relative precision for
//! georeferenced input (UTM coordinates ~1e6 m) given in any frame.
//!
//! All quantities are per the polygon (areas in m², second moments of area in m⁴); masses and
//! mass moments of inertia (× density × thickness t) are computed elsewhere.

use serde::{Deserialize, Serialize};

/// Geometric properties of a simple polygon.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PolygonProps {
    /// Enclosed area (m²), positive for either orientation.
    pub area: f64,
    /// Area centroid, in the frame of the input points.
    pub centroid: [f64; 2],
    /// ∫ y² dA about the centroid (m⁴): second moment about the x axis through the centroid.
    pub ixx: f64,
    /// ∫ x² dA about the centroid (m⁴): second moment about the y axis through the centroid.
    pub iyy: f64,
    /// Product of area ∫ x y dA about the centroid (m⁴).
    pub ixy: f64,
    /// Polar second moment of area about the centroid, `ixx + iyy` (m⁴).
    pub j: f64,
    /// Angle from +x (radians, in (−π/2, π/2]) of the major (long) axis: the centroidal axis of
    /// MINIMUM second moment of area.
    pub principal_angle: f64,
    /// Minimum centroidal second moment of area (about the long axis), m⁴.
    pub i_min: f64,
    /// Maximum centroidal second moment of area (about the short axis), m⁴.
    pub i_max: f64,
    /// Perimeter length (m), including the closing edge.
    pub perimeter: f64,
}

/// Signed area (positive for counter-clockwise) of a polygon given without a repeated closing
/// point, computed about the first vertex for precision (shoelace formula, see module docs).
pub fn signed_area(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    if n < 3 {
        return 0.0;
    }
    let o = points[0];
    let mut s = 0.0;
    for i in 1..n - 1 {
        let (a, b) = (points[i], points[i + 1]);
        s += (a[0] - o[0]) * (b[1] - o[1]) - (b[0] - o[0]) * (a[1] - o[1]);
    }
    0.5 * s
}

/// Perimeter of the closed polygon (closing edge included).
pub fn perimeter(points: &[[f64; 2]]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum()
}

fn bbox_centre(points: &[[f64; 2]]) -> [f64; 2] {
    let (lo, hi) = crate::geom::bbox(points);
    [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]
}

/// Area, centroid, centroidal second moments of area, principal axes and perimeter of a simple
/// polygon (either orientation, no repeated closing point). A polygon with fewer than 3 points
/// or zero area gives zero area and moments and the vertex mean as centroid (the outline reader
/// rejects such input before it gets here).
pub fn polygon_props(points: &[[f64; 2]]) -> PolygonProps {
    let n = points.len();
    let perim = perimeter(points);
    let mean = if n == 0 {
        [0.0, 0.0]
    } else {
        let s = points
            .iter()
            .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
        [s[0] / n as f64, s[1] / n as f64]
    };
    let degenerate = PolygonProps {
        area: 0.0,
        centroid: mean,
        ixx: 0.0,
        iyy: 0.0,
        ixy: 0.0,
        j: 0.0,
        principal_angle: 0.0,
        i_min: 0.0,
        i_max: 0.0,
        perimeter: perim,
    };
    if n < 3 {
        return degenerate;
    }
    // Pass 1: area and first moments about the bounding-box centre.
    let o = bbox_centre(points);
    let (mut a2, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (points[i], points[(i + 1) % n]);
        let (x0, y0, x1, y1) = (p[0] - o[0], p[1] - o[1], q[0] - o[0], q[1] - o[1]);
        let c = x0 * y1 - x1 * y0;
        a2 += c;
        sx += (x0 + x1) * c;
        sy += (y0 + y1) * c;
    }
    if a2 == 0.0 || !a2.is_finite() {
        return degenerate;
    }
    let area_signed = 0.5 * a2;
    let cx = sx / (6.0 * area_signed);
    let cy = sy / (6.0 * area_signed);
    let centroid = [o[0] + cx, o[1] + cy];
    // Pass 2: second moments directly about the centroid.
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (points[i], points[(i + 1) % n]);
        let x0 = (p[0] - o[0]) - cx;
        let y0 = (p[1] - o[1]) - cy;
        let x1 = (q[0] - o[0]) - cx;
        let y1 = (q[1] - o[1]) - cy;
        let c = x0 * y1 - x1 * y0;
        sxx += (x0 * x0 + x0 * x1 + x1 * x1) * c;
        syy += (y0 * y0 + y0 * y1 + y1 * y1) * c;
        sxy += (x0 * y1 + 2.0 * x0 * y0 + 2.0 * x1 * y1 + x1 * y0) * c;
    }
    let sign = area_signed.signum();
    let iyy = sign * sxx / 12.0; // ∫ x² dA
    let ixx = sign * syy / 12.0; // ∫ y² dA
    let ixy = sign * sxy / 24.0; // ∫ x y dA
    let (i_min, i_max, principal_angle) = principal(ixx, iyy, ixy);
    PolygonProps {
        area: area_signed.abs(),
        centroid,
        ixx,
        iyy,
        ixy,
        j: ixx + iyy,
        principal_angle,
        i_min,
        i_max,
        perimeter: perim,
    }
}

/// Principal second moments and the angle of the long axis.
///
/// The second moment about a centroidal axis of direction (cos θ, sin θ) is
/// I(θ) = ixx cos²θ + iyy sin²θ − 2 ixy sinθ cosθ (distance to the axis is −x sinθ + y cosθ).
/// It is minimal at θ = ½ atan2(2 ixy, iyy − ixx) (the long axis), with the extreme values
/// (ixx+iyy)/2 ∓ √(((ixx−iyy)/2)² + ixy²) (Mohr's circle; e.g. Gere & Goodno, Mechanics of
/// Materials, §12.8).
fn principal(ixx: f64, iyy: f64, ixy: f64) -> (f64, f64, f64) {
    let mean = 0.5 * (ixx + iyy);
    let rad = (0.5 * (ixx - iyy)).hypot(ixy);
    let mut theta = 0.5 * (2.0 * ixy).atan2(iyy - ixx);
    if theta <= -std::f64::consts::FRAC_PI_2 {
        theta += std::f64::consts::PI;
    }
    (mean - rad, mean + rad, theta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_square_both_orientations() {
        let ccw = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mut cw = ccw;
        cw.reverse();
        for pts in [&ccw[..], &cw[..]] {
            let p = polygon_props(pts);
            assert!((p.area - 1.0).abs() < 1e-15);
            assert!((p.centroid[0] - 0.5).abs() < 1e-15 && (p.centroid[1] - 0.5).abs() < 1e-15);
            assert!((p.ixx - 1.0 / 12.0).abs() < 1e-15);
            assert!((p.iyy - 1.0 / 12.0).abs() < 1e-15);
            assert!(p.ixy.abs() < 1e-15);
            assert!((p.perimeter - 4.0).abs() < 1e-15);
        }
        assert!(signed_area(&ccw) > 0.0 && signed_area(&cw) < 0.0);
    }

    #[test]
    fn principal_angle_range_and_sign() {
        // Long axis along y: angle must be +pi/2 (not -pi/2).
        let (_, _, t) = principal(1.0, 0.1, -0.0);
        assert!((t - std::f64::consts::FRAC_PI_2).abs() < 1e-15, "{t}");
        // Mass along y = -x: ixy < 0, long axis at -45 degrees.
        let (_, _, t) = principal(1.0, 1.0, -0.5);
        assert!((t + std::f64::consts::FRAC_PI_4).abs() < 1e-15, "{t}");
    }

    #[test]
    fn degenerate_input_gives_zeros() {
        let p = polygon_props(&[[0.0, 0.0], [1.0, 1.0]]);
        assert_eq!(p.area, 0.0);
        let p = polygon_props(&[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]);
        assert_eq!(p.area, 0.0);
        assert!(p.j == 0.0 && p.centroid[0].is_finite());
    }
}
