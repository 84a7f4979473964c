//! Small exact planar geometry used by the filler: point-in-polygon, distance to a polygon's
//! boundary, and an edge grid that makes repeated distance queries cheap on outlines with
//! hundreds of vertices.
//!
//! All functions take a simple polygon as a slice of vertices without a repeated closing point.

/// Axis-aligned bounding box `(lower corner, upper corner)` of a point set.
pub fn bbox(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for q in points {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (lo, hi)
}

/// Squared distance from `p` to the segment `a`–`b` (closest point clamped to the segment).
#[inline]
pub fn dist2_point_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let (wx, wy) = (p[0] - a[0], p[1] - a[1]);
    let len2 = ex * ex + ey * ey;
    let t = if len2 > 0.0 {
        ((wx * ex + wy * ey) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (dx, dy) = (wx - t * ex, wy - t * ey);
    dx * dx + dy * dy
}

/// Even–odd point-in-polygon test (crossing number). Points exactly on the boundary may go
/// either way; the filler never relies on that case (it only places discs whose distance to the
/// boundary is at least their radius).
pub fn point_in_polygon(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = poly.len();
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Exact distance from `p` to the polygon's boundary (minimum over all edges). O(n).
pub fn distance_to_boundary(p: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    let mut best = f64::INFINITY;
    for i in 0..n {
        let d2 = dist2_point_segment(p, poly[i], poly[(i + 1) % n]);
        if d2 < best {
            best = d2;
        }
    }
    best.sqrt()
}

/// A uniform grid of buckets over the polygon's edges for fast exact boundary-distance queries.
///
/// A query visits rings of cells around the query point and stops as soon as the ring's inner
/// radius exceeds the best distance found, so the answer is exact (the same value as
/// [`distance_to_boundary`], up to the order of the `min`), typically in O(1) edges.
pub struct EdgeGrid<'a> {
    poly: &'a [[f64; 2]],
    x0: f64,
    y0: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    edges: Vec<u32>,
}

impl<'a> EdgeGrid<'a> {
    /// Builds the grid with about `2·sqrt(n)` cells along the longer side.
    pub fn new(poly: &'a [[f64; 2]]) -> Self {
        let n = poly.len();
        let ([x0, y0], [x1, y1]) = bbox(poly);
        let side = (x1 - x0).max(y1 - y0).max(f64::MIN_POSITIVE);
        let k = ((2.0 * (n as f64).sqrt()).ceil() as usize).clamp(1, 256);
        let cell = side / k as f64 * (1.0 + 1e-9);
        let nx = (((x1 - x0) / cell).floor() as usize + 1).max(1);
        let ny = (((y1 - y0) / cell).floor() as usize + 1).max(1);
        // Count, then fill (CSR). An edge goes into every cell its bounding box touches.
        let mut count = vec![0u32; nx * ny + 1];
        let bbox_cells = |i: usize| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let cx0 = ((a[0].min(b[0]) - x0) / cell).floor() as usize;
            let cx1 = (((a[0].max(b[0]) - x0) / cell).floor() as usize).min(nx - 1);
            let cy0 = ((a[1].min(b[1]) - y0) / cell).floor() as usize;
            let cy1 = (((a[1].max(b[1]) - y0) / cell).floor() as usize).min(ny - 1);
            (cx0.min(nx - 1), cx1, cy0.min(ny - 1), cy1)
        };
        for i in 0..n {
            let (cx0, cx1, cy0, cy1) = bbox_cells(i);
            for cy in cy0..=cy1 {
                for cx in cx0..=cx1 {
                    count[cy * nx + cx + 1] += 1;
                }
            }
        }
        for c in 0..nx * ny {
            count[c + 1] += count[c];
        }
        let start = count.clone();
        let mut fill = count;
        let mut edges = vec![0u32; start[nx * ny] as usize];
        for i in 0..n {
            let (cx0, cx1, cy0, cy1) = bbox_cells(i);
            for cy in cy0..=cy1 {
                for cx in cx0..=cx1 {
                    let c = cy * nx + cx;
                    edges[fill[c] as usize] = i as u32;
                    fill[c] += 1;
                }
            }
        }
        EdgeGrid {
            poly,
            x0,
            y0,
            cell,
            nx,
            ny,
            start,
            edges,
        }
    }

    /// Exact distance from `p` to the polygon boundary.
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        let n = self.poly.len();
        let fx = (p[0] - self.x0) / self.cell;
        let fy = (p[1] - self.y0) / self.cell;
        let cx = fx.floor().clamp(0.0, (self.nx - 1) as f64) as i64;
        let cy = fy.floor().clamp(0.0, (self.ny - 1) as f64) as i64;
        // Distance from p to the outside of its own (clamped) cell, used to bound each ring.
        let mut best2 = f64::INFINITY;
        let max_ring = self.nx.max(self.ny) as i64;
        for ring in 0..=max_ring {
            // Cells in ring `ring` are at least (ring - 1) * cell away from p (p may lie outside
            // the grid when clamped, so we use a conservative bound from the clamped cell).
            if ring >= 1 {
                let lo = (ring - 1) as f64 * self.cell;
                let outside = ((fx - fx.clamp(0.0, self.nx as f64)).abs())
                    .max((fy - fy.clamp(0.0, self.ny as f64)).abs())
                    * self.cell;
                let lower = (lo - outside).max(0.0);
                if lower * lower > best2 {
                    break;
                }
            }
            let (x_lo, x_hi, y_lo, y_hi) = (cx - ring, cx + ring, cy - ring, cy + ring);
            let mut visit = |xx: i64, yy: i64| {
                if xx < 0 || yy < 0 || xx >= self.nx as i64 || yy >= self.ny as i64 {
                    return;
                }
                let c = yy as usize * self.nx + xx as usize;
                for &e in &self.edges[self.start[c] as usize..self.start[c + 1] as usize] {
                    let e = e as usize;
                    let d2 = dist2_point_segment(p, self.poly[e], self.poly[(e + 1) % n]);
                    if d2 < best2 {
                        best2 = d2;
                    }
                }
            };
            // Only the ring's perimeter: top and bottom rows, then the two side columns.
            for xx in x_lo..=x_hi {
                visit(xx, y_lo);
                if ring > 0 {
                    visit(xx, y_hi);
                }
            }
            for yy in (y_lo + 1)..y_hi {
                visit(x_lo, yy);
                visit(x_hi, yy);
            }
        }
        best2.sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn star(n: usize) -> Vec<[f64; 2]> {
        (0..n)
            .map(|i| {
                let t = i as f64 / n as f64 * std::f64::consts::TAU;
                let r = 1.0 + 0.3 * (5.0 * t).sin() + 0.1 * (13.0 * t).cos();
                [3.0 * r * t.cos() + 1e3, r * t.sin() - 2e3]
            })
            .collect()
    }

    #[test]
    fn square_distance_and_inside() {
        let sq = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!(point_in_polygon([1.0, 1.0], &sq));
        assert!(!point_in_polygon([3.0, 1.0], &sq));
        assert_eq!(distance_to_boundary([1.0, 1.0], &sq), 1.0);
        assert_eq!(distance_to_boundary([0.5, 1.0], &sq), 0.5);
        assert_eq!(distance_to_boundary([3.0, 3.0], &sq), 2f64.sqrt());
    }

    #[test]
    fn edge_grid_matches_brute_force() {
        let poly = star(400);
        let g = EdgeGrid::new(&poly);
        let mut s = 12345u64;
        for _ in 0..2000 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let v = (s >> 11) as f64 / (1u64 << 53) as f64;
            // Query points inside, near and well outside the bounding box.
            let p = [1e3 + (u - 0.5) * 10.0, -2e3 + (v - 0.5) * 5.0];
            let a = g.distance(p);
            let b = distance_to_boundary(p, &poly);
            assert!((a - b).abs() <= 1e-12 * b.max(1.0), "{a} vs {b} at {p:?}");
        }
    }
}
