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
///
/// Two prunings keep queries far from the boundary cheap on dense outlines (a 200,000-point
/// circle): rings nearer than the nearest non-empty cell are skipped (each cell stores its
/// Chebyshev distance, in cells, to the nearest cell holding an edge: two-pass chamfer transform
/// with unit weights, exact for the Chebyshev metric; Rosenfeld & Pfaltz, "Sequential operations
/// in digital picture processing", J. ACM 13, 1966), and a cell is skipped when its box is
/// farther than the best distance found. Neither changes the set of edges that can be nearest,
/// so the answer is the same. The stored distance also gives a lower bound on the distance
/// without any edge ([`EdgeGrid::lower_bound`]).
pub struct EdgeGrid<'a> {
    poly: &'a [[f64; 2]],
    x0: f64,
    y0: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    edges: Vec<u32>,
    /// Chebyshev distance (cells) from each cell to the nearest cell that holds an edge.
    empty_rings: Vec<u32>,
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
        // Chamfer transform (forward and backward pass, 8-neighbourhood, unit weights).
        let big = u32::MAX / 2;
        let mut d: Vec<u32> = (0..nx * ny)
            .map(|c| if start[c + 1] > start[c] { 0 } else { big })
            .collect();
        for cy in 0..ny {
            for cx in 0..nx {
                let mut v = d[cy * nx + cx];
                if cx > 0 {
                    v = v.min(d[cy * nx + cx - 1] + 1);
                }
                if cy > 0 {
                    for xx in cx.saturating_sub(1)..=(cx + 1).min(nx - 1) {
                        v = v.min(d[(cy - 1) * nx + xx] + 1);
                    }
                }
                d[cy * nx + cx] = v;
            }
        }
        for cy in (0..ny).rev() {
            for cx in (0..nx).rev() {
                let mut v = d[cy * nx + cx];
                if cx + 1 < nx {
                    v = v.min(d[cy * nx + cx + 1] + 1);
                }
                if cy + 1 < ny {
                    for xx in cx.saturating_sub(1)..=(cx + 1).min(nx - 1) {
                        v = v.min(d[(cy + 1) * nx + xx] + 1);
                    }
                }
                d[cy * nx + cx] = v;
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
            empty_rings: d,
        }
    }

    /// The (clamped) cell of `p` and `p` in cell units.
    fn locate(&self, p: [f64; 2]) -> (f64, f64, i64, i64) {
        let fx = (p[0] - self.x0) / self.cell;
        let fy = (p[1] - self.y0) / self.cell;
        let cx = fx.floor().clamp(0.0, (self.nx - 1) as f64) as i64;
        let cy = fy.floor().clamp(0.0, (self.ny - 1) as f64) as i64;
        (fx, fy, cx, cy)
    }

    /// A lower bound on the distance from `p` to the boundary, without visiting any edge: every
    /// point of every edge lies in a cell that lists the edge, and those cells are at least
    /// `k` cells (Chebyshev) from `p`'s cell, so at least `(k − 1)·cell` from `p`.
    pub fn lower_bound(&self, p: [f64; 2]) -> f64 {
        let (_, _, cx, cy) = self.locate(p);
        let k = self.empty_rings[cy as usize * self.nx + cx as usize];
        k.saturating_sub(1) as f64 * self.cell
    }

    /// Exact distance from `p` to the polygon boundary.
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        let n = self.poly.len();
        let (fx, fy, cx, cy) = self.locate(p);
        // Distance from p to the outside of its own (clamped) cell, used to bound each ring.
        let mut best2 = f64::INFINITY;
        let max_ring = self.nx.max(self.ny) as i64;
        // Rings nearer than the nearest cell with an edge hold no edge.
        let first = self.empty_rings[cy as usize * self.nx + cx as usize] as i64;
        for ring in first.min(max_ring)..=max_ring {
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
                let cell_edges = &self.edges[self.start[c] as usize..self.start[c + 1] as usize];
                if cell_edges.is_empty() {
                    return;
                }
                // The cell's box farther than the best so far: none of its edges is nearer
                // (an edge's nearest point lies in a cell that lists it, never skipped). The
                // margin keeps a rounding of the box's corners from skipping a tie.
                let bx = (self.x0 + xx as f64 * self.cell - p[0])
                    .max(p[0] - (self.x0 + (xx + 1) as f64 * self.cell))
                    .max(0.0);
                let by = (self.y0 + yy as f64 * self.cell - p[1])
                    .max(p[1] - (self.y0 + (yy + 1) as f64 * self.cell))
                    .max(0.0);
                if bx * bx + by * by > best2 * (1.0 + 1e-9) {
                    return;
                }
                for &e in cell_edges {
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
    fn edge_grid_is_exact_and_its_bound_is_useful_on_a_dense_circle() {
        // 20,000 points: the centre is far from every edge cell, the bound says so without
        // visiting an edge, and the exact distance is still the brute-force one.
        let n = 20_000;
        let poly: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let t = i as f64 / n as f64 * std::f64::consts::TAU;
                [t.cos(), t.sin()]
            })
            .collect();
        let g = EdgeGrid::new(&poly);
        for p in [
            [0.0, 0.0],
            [0.3, -0.2],
            [0.7, 0.69],
            [-0.99, 0.0],
            [1.5, 0.2],
        ] {
            let b = distance_to_boundary(p, &poly);
            assert!((g.distance(p) - b).abs() <= 1e-12, "{p:?}");
            assert!(g.lower_bound(p) <= b, "{p:?}");
        }
        // Chebyshev rings: the nearest edge cells lie on the diagonals, 1/√2 away.
        assert!(g.lower_bound([0.0, 0.0]) > 0.69);
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
            assert!(
                g.lower_bound(p) <= b,
                "bound {} above {b}",
                g.lower_bound(p)
            );
        }
    }
}
