//! Boundary deviation between a grain outline and its clump: the Hausdorff distance between the
//! outline (a closed polyline) and the boundary of the union of the discs.
//!
//! Both directed distances are evaluated on samples at spacing `h` along each boundary: from the
//! outline to the union, `d(p) = max(0, min_i (|p − c_i| − r_i))` is exact for points outside the
//! union (all outline points are, since the discs lie inside the grain); from the union's boundary
//! arcs to the outline, the exact point-to-polyline distance. Sampling can miss a maximum between
//! samples by at most `h/2` (both distance functions are 1-Lipschitz), which is the stated bound.

use crate::cover::{union_area, Circle};
use crate::geom::EdgeGrid;

/// Hausdorff distance and its sampling bound (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deviation {
    pub hausdorff: f64,
    pub bound: f64,
}

/// Deviation between `poly` and the union of `discs` (same frame), sampled at spacing `h`.
pub fn boundary_deviation(poly: &[[f64; 2]], discs: &[Circle], h: f64) -> Deviation {
    let n = poly.len();
    let mut worst: f64 = 0.0;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let k = (len / h).ceil().max(1.0) as usize;
        for s in 0..k {
            let t = s as f64 / k as f64;
            let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let d = discs
                .iter()
                .map(|c| (p[0] - c.x).hypot(p[1] - c.y) - c.r)
                .fold(f64::INFINITY, f64::min)
                .max(0.0);
            worst = worst.max(d);
        }
    }
    let grid = EdgeGrid::new(poly);
    for arc in union_area(discs).arcs {
        let c = discs[arc.disc];
        let k = ((arc.a1 - arc.a0) * c.r / h).ceil().max(1.0) as usize;
        for s in 0..=k {
            let th = arc.a0 + (arc.a1 - arc.a0) * s as f64 / k as f64;
            worst = worst.max(grid.distance([c.x + c.r * th.cos(), c.y + c.r * th.sin()]));
        }
    }
    Deviation {
        hausdorff: worst,
        bound: 0.5 * h,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inscribed_disc_of_a_square() {
        // Square of half-side 1 and its inscribed unit disc: the farthest outline points are the
        // corners, at √2 − 1 from the disc.
        let sq = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let d = boundary_deviation(
            &sq,
            &[Circle {
                x: 0.0,
                y: 0.0,
                r: 1.0,
            }],
            1e-3,
        );
        assert!((d.hausdorff - (2f64.sqrt() - 1.0)).abs() < 1e-12);
    }

    #[test]
    fn small_disc_far_from_the_outline() {
        // A disc of radius 0.2 at the centre: its boundary is 0.8 from the sides, and the
        // corners are √2 − 0.2 from it.
        let sq = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let d = boundary_deviation(
            &sq,
            &[Circle {
                x: 0.0,
                y: 0.0,
                r: 0.2,
            }],
            1e-3,
        );
        assert!((d.hausdorff - (2f64.sqrt() - 0.2)).abs() < 1e-12);
    }
}
