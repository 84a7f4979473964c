//! Shape descriptors of a grain outline: equivalent radius, aspect ratio, circularity,
//! solidity; and the convex hull they need.

use serde::{Deserialize, Serialize};

use crate::props::{signed_area, PolygonProps};

/// Dimensionless (except `r_eq`) shape descriptors of a polygon.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShapeDescriptors {
    /// Equivalent (area) radius √(A/π), m.
    pub r_eq: f64,
    /// Aspect ratio of the equivalent inertia ellipse, √(i_max / i_min) ≥ 1. An ellipse of
    /// semi-axes a ≥ b has centroidal second moments πab³/4 and πa³b/4, so this returns a/b
    /// exactly for an ellipse (inertia-based, not Feret-based: it is insensitive to single
    /// spikes and needs no rotating calipers). Infinite for a zero-width shape.
    pub aspect_ratio: f64,
    /// Circularity (isoperimetric quotient) 4πA/P², 1 for a disc, < 1 otherwise.
    pub circularity: f64,
    /// Solidity A / A_hull, 1 for a convex polygon, < 1 for a concave one.
    pub solidity: f64,
}

/// Descriptors of `points` (any orientation) given its [`PolygonProps`].
pub fn shape_descriptors(points: &[[f64; 2]], props: &PolygonProps) -> ShapeDescriptors {
    let a = props.area;
    let hull_area = signed_area(&convex_hull(points)).abs();
    ShapeDescriptors {
        r_eq: (a / std::f64::consts::PI).sqrt(),
        aspect_ratio: if props.i_min > 0.0 {
            (props.i_max / props.i_min).sqrt()
        } else {
            f64::INFINITY
        },
        circularity: if props.perimeter > 0.0 {
            4.0 * std::f64::consts::PI * a / (props.perimeter * props.perimeter)
        } else {
            0.0
        },
        solidity: if hull_area > 0.0 { a / hull_area } else { 0.0 },
    }
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// Convex hull by Andrew's monotone chain (A. M. Andrew, "Another efficient algorithm for
/// convex hulls in two dimensions", Inf. Proc. Letters 9, 1979), O(n log n).
/// Returns the hull counter-clockwise, starting at the lowest-x (then lowest-y) point, without
/// collinear points and without a repeated closing point. Fewer than 3 distinct input points
/// are returned as they are (deduplicated, sorted).
pub fn convex_hull(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p: Vec<[f64; 2]> = points.to_vec();
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut h: Vec<[f64; 2]> = Vec::with_capacity(2 * p.len());
    // Lower hull.
    for &q in &p {
        while h.len() >= 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
            h.pop();
        }
        h.push(q);
    }
    // Upper hull.
    let lower_len = h.len() + 1;
    for &q in p.iter().rev().skip(1) {
        while h.len() >= lower_len && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
            h.pop();
        }
        h.push(q);
    }
    h.pop(); // the first point again
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::props::polygon_props;

    #[test]
    fn hull_of_square_with_inner_and_edge_points() {
        let pts = [
            [0.0, 0.0],
            [0.5, 0.0], // on an edge: dropped
            [1.0, 0.0],
            [0.5, 0.5], // inside
            [1.0, 1.0],
            [0.0, 1.0],
            [0.0, 0.0], // duplicate
        ];
        let h = convex_hull(&pts);
        assert_eq!(h, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    }

    #[test]
    fn descriptors_of_rectangle_and_l_shape() {
        let rect = [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]];
        let d = shape_descriptors(&rect, &polygon_props(&rect));
        assert!((d.aspect_ratio - 3.0).abs() < 1e-12); // sqrt((h b^3)/(b h^3)) = b/h
        assert!((d.solidity - 1.0).abs() < 1e-15);
        assert!((d.circularity - 4.0 * std::f64::consts::PI * 3.0 / 64.0).abs() < 1e-15);
        assert!((d.r_eq - (3.0 / std::f64::consts::PI).sqrt()).abs() < 1e-15);
        // L: 2x2 square minus a 1x1 corner; hull area 3.5.
        let l = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ];
        let d = shape_descriptors(&l, &polygon_props(&l));
        assert!((d.solidity - 3.0 / 3.5).abs() < 1e-15);
    }

    #[test]
    fn ellipse_aspect_ratio() {
        let n = 2000;
        let pts: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                [2.5 * t.cos(), t.sin()]
            })
            .collect();
        let d = shape_descriptors(&pts, &polygon_props(&pts));
        // An inscribed polygon of an ellipse is an affine image of a regular polygon,
        // whose inertia is isotropic: the ratio is exact up to rounding.
        assert!((d.aspect_ratio - 2.5).abs() < 1e-9, "{}", d.aspect_ratio);
    }
}
