//! Self-intersection test for closed polygons, O(n) expected with a uniform grid.
//!
//! Edge i joins vertex i to vertex (i+1) mod n. Two edges *meet* if they share any point,
//! except that two adjacent edges may share their common vertex. So reported are: proper
//! crossings, a vertex touching another edge, collinear overlaps, a vertex visited twice, and
//! an adjacent pair folding back onto itself (a zero-width spike).
//!
//! Edges are bucketed into a uniform grid of about n cells laid over the bounding box (each
//! edge goes into every cell its bounding box covers) and only edges sharing a cell are tested,
//! each pair once. For outlines whose edges are short compared with the box (all real grain
//! outlines) this is O(n). The orientation predicate is plain f64 arithmetic, exact for the
//! integer and half-integer coordinates of pixel outlines; for other data a near-degenerate
//! configuration (|cross product| at rounding level) may be classified either way.

/// A pair of edges that meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfHit {
    /// The lower edge index (edge i joins vertices i and i+1 mod n).
    pub edge_a: usize,
    /// The higher edge index.
    pub edge_b: usize,
    /// A point common to both edges.
    pub point: [f64; 2],
}

#[inline]
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// c is on the closed segment a-b, given that a, b, c are collinear.
#[inline]
fn within(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    c[0] >= a[0].min(b[0])
        && c[0] <= a[0].max(b[0])
        && c[1] >= a[1].min(b[1])
        && c[1] <= a[1].max(b[1])
}

/// Common point of closed segments p1-p2 and p3-p4, if any.
fn segments_meet(p1: [f64; 2], p2: [f64; 2], p3: [f64; 2], p4: [f64; 2]) -> Option<[f64; 2]> {
    let d1 = orient(p3, p4, p1);
    let d2 = orient(p3, p4, p2);
    let d3 = orient(p1, p2, p3);
    let d4 = orient(p1, p2, p4);
    let opposite = |u: f64, v: f64| (u > 0.0 && v < 0.0) || (u < 0.0 && v > 0.0);
    if opposite(d1, d2) && opposite(d3, d4) {
        let t = d1 / (d1 - d2);
        return Some([p1[0] + t * (p2[0] - p1[0]), p1[1] + t * (p2[1] - p1[1])]);
    }
    if d1 == 0.0 && within(p3, p4, p1) {
        return Some(p1);
    }
    if d2 == 0.0 && within(p3, p4, p2) {
        return Some(p2);
    }
    if d3 == 0.0 && within(p1, p2, p3) {
        return Some(p3);
    }
    if d4 == 0.0 && within(p1, p2, p4) {
        return Some(p4);
    }
    None
}

/// Adjacent edges s-a and s-b (sharing vertex s) fold back onto each other: a, b collinear
/// with s and on the same side of it. Returns the end point nearer to s (on both edges).
fn fold_back(s: [f64; 2], a: [f64; 2], b: [f64; 2]) -> Option<[f64; 2]> {
    if orient(s, a, b) != 0.0 {
        return None;
    }
    let da = [a[0] - s[0], a[1] - s[1]];
    let db = [b[0] - s[0], b[1] - s[1]];
    if da[0] * db[0] + da[1] * db[1] <= 0.0 {
        return None;
    }
    let la = da[0] * da[0] + da[1] * da[1];
    let lb = db[0] * db[0] + db[1] * db[1];
    Some(if la <= lb { a } else { b })
}

/// Test edges i < j of the closed polygon `p`.
fn edge_pair(p: &[[f64; 2]], i: usize, j: usize) -> Option<[f64; 2]> {
    let n = p.len();
    let (a0, a1) = (p[i], p[(i + 1) % n]);
    let (b0, b1) = (p[j], p[(j + 1) % n]);
    if j == i + 1 {
        // Share vertex i+1 = j.
        fold_back(a1, a0, b1)
    } else if i == 0 && j == n - 1 {
        // Share vertex 0.
        fold_back(a0, a1, b0)
    } else {
        segments_meet(a0, a1, b0, b1)
    }
}

/// The first pair of meeting edges (smallest edge_a, then smallest edge_b) of the closed
/// polygon `points` (no repeated closing point), or `None` if the polygon is simple.
/// Polygons with fewer than 3 points return `None`. Non-finite coordinates are not allowed.
pub fn find_self_intersection(points: &[[f64; 2]]) -> Option<SelfHit> {
    let n = points.len();
    if n < 3 {
        return None;
    }
    let (lo, hi) = crate::geom::bbox(points);
    let w = (hi[0] - lo[0]).max(f64::MIN_POSITIVE);
    let h = (hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    // About n cells, shaped like the box.
    let gx = ((n as f64 * w / h).sqrt().ceil() as usize).clamp(1, n);
    let gy = (n.div_ceil(gx)).clamp(1, n);
    let (cw, ch) = (w / gx as f64, h / gy as f64);
    let cell = |v: f64, o: f64, c: f64, g: usize| (((v - o) / c) as usize).min(g - 1);
    let range = |e: usize| {
        let (a, b) = (points[e], points[(e + 1) % n]);
        (
            cell(a[0].min(b[0]), lo[0], cw, gx),
            cell(a[0].max(b[0]), lo[0], cw, gx),
            cell(a[1].min(b[1]), lo[1], ch, gy),
            cell(a[1].max(b[1]), lo[1], ch, gy),
        )
    };
    // Compressed rows: start[c]..start[c+1] indexes `items` of cell c, edges ascending.
    let mut start = vec![0usize; gx * gy + 1];
    for e in 0..n {
        let (x0, x1, y0, y1) = range(e);
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                start[cy * gx + cx + 1] += 1;
            }
        }
    }
    for c in 0..gx * gy {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut items = vec![0usize; start[gx * gy]];
    for e in 0..n {
        let (x0, x1, y0, y1) = range(e);
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                let c = cy * gx + cx;
                items[fill[c]] = e;
                fill[c] += 1;
            }
        }
    }
    let mut stamp = vec![usize::MAX; n];
    for i in 0..n {
        let (x0, x1, y0, y1) = range(i);
        let mut best: Option<(usize, [f64; 2])> = None;
        for cy in y0..=y1 {
            for cx in x0..=x1 {
                let c = cy * gx + cx;
                for &j in &items[start[c]..start[c + 1]] {
                    if j <= i || stamp[j] == i {
                        continue;
                    }
                    stamp[j] = i;
                    if best.is_some_and(|(bj, _)| bj < j) {
                        continue;
                    }
                    if let Some(pt) = edge_pair(points, i, j) {
                        best = Some((j, pt));
                    }
                }
            }
        }
        if let Some((j, point)) = best {
            return Some(SelfHit {
                edge_a: i,
                edge_b: j,
                point,
            });
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference: test all pairs.
    fn brute(p: &[[f64; 2]]) -> Option<(usize, usize)> {
        let n = p.len();
        for i in 0..n {
            for j in i + 1..n {
                if edge_pair(p, i, j).is_some() {
                    return Some((i, j));
                }
            }
        }
        None
    }

    fn hit(p: &[[f64; 2]]) -> Option<(usize, usize)> {
        let h = find_self_intersection(p);
        assert_eq!(h.map(|h| (h.edge_a, h.edge_b)), brute(p));
        h.map(|h| (h.edge_a, h.edge_b))
    }

    #[test]
    fn simple_shapes_pass() {
        assert_eq!(hit(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), None);
        // Concave L and a U with a narrow gap.
        let l = [[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]];
        assert_eq!(hit(&l), None);
        // Collinear consecutive vertices are fine (straight angle, not a fold).
        let sq = [[0., 0.], [1., 0.], [2., 0.], [2., 2.], [0., 2.]];
        assert_eq!(hit(&sq), None);
    }

    #[test]
    fn bowtie_crossing_point() {
        let b = [[0., 0.], [2., 2.], [2., 0.], [0., 2.]];
        let h = find_self_intersection(&b).unwrap();
        assert_eq!((h.edge_a, h.edge_b), (0, 2));
        assert_eq!(h.point, [1.0, 1.0]);
    }

    #[test]
    fn vertex_touching_an_edge() {
        // Vertex 4 at (1, 0) lies on edge 0 (0,0)-(2,0).
        let p = [
            [0., 0.],
            [2., 0.],
            [2., 2.],
            [1.5, 2.0],
            [1., 0.],
            [0.5, 2.],
        ];
        let h = find_self_intersection(&p).unwrap();
        assert_eq!((h.edge_a, h.edge_b), (0, 3));
        assert_eq!(h.point, [1.0, 0.0]);
        assert_eq!(brute(&p), Some((0, 3)));
    }

    #[test]
    fn repeated_vertex_figure_eight() {
        // Two squares touching at (1,1): vertex (1,1) visited twice.
        let p = [
            [0., 0.],
            [1., 0.],
            [1., 1.],
            [2., 1.],
            [2., 2.],
            [1., 2.],
            [1., 1.],
            [0., 1.],
        ];
        let h = find_self_intersection(&p).unwrap();
        assert_eq!(h.point, [1.0, 1.0]);
        assert_eq!(hit(&p), Some((1, 5)));
    }

    #[test]
    fn collinear_overlap_of_distant_edges() {
        // Edge 0 (0,0)-(3,0); edge 4 (2,0)-(1,0) runs back along it (a slit).
        let p = [
            [0., 0.],
            [3., 0.],
            [3., 1.],
            [2., 1.],
            [2., 0.],
            [1., 0.],
            [1., 1.],
            [0., 1.],
        ];
        assert_eq!(hit(&p), Some((0, 3)));
    }

    #[test]
    fn fold_back_spike_of_adjacent_edges() {
        // Edge 1 (3,0)-(1,0) runs back along edge 0 (0,0)-(3,0): spike at vertex 1.
        let p = [[0., 0.], [3., 0.], [1., 0.], [1., 2.]];
        let h = find_self_intersection(&p).unwrap();
        assert_eq!((h.edge_a, h.edge_b), (0, 1));
        assert_eq!(h.point, [1.0, 0.0]);
        assert_eq!(hit(&p), Some((0, 1)));
        // Fold at vertex 0: closing edge (3,0)-(0,0) overlaps edge 0 (0,0)-(2,0).
        let p = [[0., 0.], [2., 0.], [2., 2.], [3., 0.]];
        let h = find_self_intersection(&p).unwrap();
        assert_eq!((h.edge_a, h.edge_b), (0, 3));
        assert_eq!(h.point, [2.0, 0.0]);
    }

    #[test]
    fn grid_matches_brute_force_on_wavy_polygons() {
        // Star polygons with and without a defect, tested against all pairs.
        for n in [7usize, 50, 333] {
            let mut p: Vec<[f64; 2]> = (0..n)
                .map(|i| {
                    let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                    let r = 1.0 + 0.3 * (7.0 * t).sin();
                    [r * t.cos(), 0.4 * r * t.sin()]
                })
                .collect();
            assert_eq!(hit(&p), None);
            // Move one vertex to outside the far side: its edges must cross the boundary.
            let q = p[n / 3];
            let d = q[0].hypot(q[1]);
            p[n / 3] = [-3.0 * q[0] / d, -3.0 * q[1] / d];
            assert!(hit(&p).is_some());
        }
    }
}
