//! Lattice fill: a grain outline filled with the nodes of a triangular lattice (hexagonal
//! cells), the first step of crushable grains (S3, the patent "DEM for crushing particles of
//! arbitrary shape": a periodic hexagonal lattice of nodes joined by springs inside the scanned
//! outline; see docs/lattice.md).
//!
//! Nodes sit at `o + i·a₁ + j·a₂` with `a₁ = (S, 0)`, `a₂ = (S/2, S·√3/2)` (spacing `S`, one
//! node per hexagonal cell of area `A_c = (√3/2)·S²`, six neighbours at distance `S`). Each
//! node is a disc of radius `r = f·S/2` (`f` in (0, 1], 1 = neighbours touch). A node is kept
//! when its centre is inside the outline and its disc is too: `dist(centre, outline) ≥ r`
//! (exact distance, [`crate::geom::EdgeGrid`]), so the boundary nodes stay inside the grain and
//! the node count is about `A_r/A_c`, `A_r` the outline's area eroded by `r` (Steiner, for a
//! convex grain: `A − P·r + π·r²`).
//!
//! The lattice offset `o` is chosen among the 16 points `(u·a₁ + v·a₂)`, `u, v ∈ {0, ¼, ½, ¾}`
//! (the origin is the grain centroid): the most nodes win, then the node centroid nearest the
//! grain centroid, then the first; so the result is deterministic. The lattice axis `a₁` is +x
//! of the grain's centroid frame.
//!
//! Links join two kept nodes that are lattice neighbours (index steps `(1, 0)`, `(0, 1)`,
//! `(−1, 1)`: the three link directions 0°, 60°, 120°, the "three kinds of central springs" of
//! S3) when the segment between them lies inside the outline (always so for `f = 1`: the two
//! touching discs cover it; otherwise checked exactly).

use crate::geom::{bbox, point_in_polygon, EdgeGrid};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// The most lattice nodes one grain may have. The placement and the closed-form mass fit are
/// `O(n)` (0.5 s for 9661 nodes on a 720-gon), but the active-set fallback of the mass fit costs
/// up to `O(n²)` (5.9 s on the same grain); a spacing that gives more is refused, naming
/// `spacing`.
pub const MAX_LATTICE_NODES: usize = 10_000;

/// The direction of a lattice link (from its first node to its second): 0°, 60° or 120° from
/// the lattice axis (+x). S3's three kinds of central springs of a hexagonal cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum LinkKind {
    /// Along `a₁ = (S, 0)`.
    #[serde(rename = "d0")]
    D0,
    /// Along `a₂ = (S/2, S√3/2)`.
    #[serde(rename = "d60")]
    D60,
    /// Along `a₂ − a₁ = (−S/2, S√3/2)`.
    #[serde(rename = "d120")]
    D120,
}

impl LinkKind {
    /// The lattice index step `(Δi, Δj)` of the link.
    pub fn step(self) -> (i64, i64) {
        match self {
            LinkKind::D0 => (1, 0),
            LinkKind::D60 => (0, 1),
            LinkKind::D120 => (-1, 1),
        }
    }
}

/// A lattice link between nodes (discs) `i < j` of a template, at distance `spacing`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Link {
    pub i: usize,
    pub j: usize,
    pub kind: LinkKind,
}

/// The nodes and links of one grain's lattice, in the grain's centroid frame.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeFill {
    /// Node centres (m), ordered by lattice row `j`, then `i`.
    pub nodes: Vec<[f64; 2]>,
    /// Lattice indices `(i, j)` of the nodes.
    pub index: Vec<(i64, i64)>,
    pub links: Vec<Link>,
    /// The lattice offset `o` (m).
    pub offset: [f64; 2],
    /// Node disc radius `r = f·S/2` (m).
    pub radius: f64,
}

/// Why no lattice could be built (`field` names the parameter at fault).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {reason}")]
pub struct LatticeError {
    pub field: &'static str,
    pub reason: String,
}

fn bad(field: &'static str, reason: String) -> LatticeError {
    LatticeError { field, reason }
}

/// The largest distance between two points of the outline (its largest width, m).
pub fn diameter(poly: &[[f64; 2]]) -> f64 {
    let h = crate::descriptors::convex_hull(poly);
    let mut d2: f64 = 0.0;
    for (k, p) in h.iter().enumerate() {
        for q in &h[k + 1..] {
            d2 = d2.max((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2));
        }
    }
    d2.sqrt()
}

/// Whether the open segment `p`–`q` crosses or touches an edge of the polygon.
fn segment_hits_boundary(p: [f64; 2], q: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    let n = poly.len();
    (0..n).any(|k| {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        let (d1, d2) = (orient(a, b, p), orient(a, b, q));
        let (d3, d4) = (orient(p, q, a), orient(p, q, b));
        (d1 * d2 <= 0.0) && (d3 * d4 <= 0.0)
    })
}

/// Whether some three nodes are linked pairwise (one triangular cell of the lattice): for a
/// `d0` link from `(i, j)` to `(i+1, j)`, the node `(i, j+1)` above or `(i+1, j−1)` below,
/// linked to both. (So at least 3 nodes and 3 links; a single row of nodes has none.)
fn has_cell(index: &[(i64, i64)], at: &HashMap<(i64, i64), usize>, links: &[Link]) -> bool {
    let linked: std::collections::HashSet<(usize, usize)> =
        links.iter().map(|l| (l.i, l.j)).collect();
    let pair = |a: usize, b: usize| linked.contains(&(a.min(b), a.max(b)));
    links.iter().filter(|l| l.kind == LinkKind::D0).any(|l| {
        let ((i0, j0), (i1, j1)) = (index[l.i], index[l.j]);
        let (a, b) = if i0 < i1 { (l.i, l.j) } else { (l.j, l.i) };
        let (i, j) = (i0.min(i1), j0.min(j1));
        [(i, j + 1), (i + 1, j - 1)]
            .iter()
            .any(|ij| at.get(ij).is_some_and(|&c| pair(a, c) && pair(b, c)))
    })
}

/// Fills `poly` (centroid frame, simple polygon) with a triangular lattice of spacing `s` (m)
/// and node radius `frac·s/2`. Errors name `spacing` (too large for the grain, too small for
/// [`MAX_LATTICE_NODES`], a grain thinner than one lattice cell: no three nodes linked in a
/// triangle, so also fewer than 3 nodes or no link) or `node-radius` (not in (0, 1]).
pub fn lattice_fill(poly: &[[f64; 2]], s: f64, frac: f64) -> Result<LatticeFill, LatticeError> {
    if !(s.is_finite() && s > 0.0) {
        return Err(bad(
            "spacing",
            format!("{s} m: must be positive and finite"),
        ));
    }
    if !(frac.is_finite() && frac > 0.0 && frac <= 1.0) {
        return Err(bad(
            "node-radius",
            format!("{frac}: a fraction of S/2 in (0, 1]"),
        ));
    }
    let width = diameter(poly);
    if s > width {
        return Err(bad(
            "spacing",
            format!(
                "{s:e} m is larger than the grain (its largest width is {width:e} m); \
                 lower --spacing"
            ),
        ));
    }
    let h = s * 3f64.sqrt() / 2.0;
    let cell = s * h;
    let ([x0, y0], [x1, y1]) = bbox(poly);
    let estimate = (x1 - x0 + s) * (y1 - y0 + h) / cell;
    if estimate > 4.0 * MAX_LATTICE_NODES as f64 {
        return Err(bad(
            "spacing",
            format!(
                "{s:e} m gives about {estimate:.0} lattice points over the grain's bounding box, \
                 more than the {MAX_LATTICE_NODES} nodes a grain may have; raise --spacing"
            ),
        ));
    }
    let r = frac * s / 2.0;
    let grid = EdgeGrid::new(poly);
    let nodes_at = |o: [f64; 2]| -> (Vec<[f64; 2]>, Vec<(i64, i64)>) {
        let mut nodes = Vec::new();
        let mut index = Vec::new();
        let j0 = ((y0 - o[1]) / h).ceil() as i64;
        let j1 = ((y1 - o[1]) / h).floor() as i64;
        for j in j0..=j1 {
            let y = o[1] + j as f64 * h;
            let xs = o[0] + j as f64 * s / 2.0;
            let i0 = ((x0 - xs) / s).ceil() as i64;
            let i1 = ((x1 - xs) / s).floor() as i64;
            for i in i0..=i1 {
                let p = [xs + i as f64 * s, y];
                if point_in_polygon(p, poly) && grid.distance(p) >= r {
                    nodes.push(p);
                    index.push((i, j));
                }
            }
        }
        (nodes, index)
    };
    // (node count, node centroid distance from the grain centroid, offset, nodes, indices)
    type Candidate = (usize, f64, [f64; 2], Vec<[f64; 2]>, Vec<(i64, i64)>);
    let mut best: Option<Candidate> = None;
    for u in 0..4 {
        for v in 0..4 {
            let (fu, fv) = (u as f64 / 4.0, v as f64 / 4.0);
            let o = [fu * s + fv * s / 2.0, fv * h];
            let (nodes, index) = nodes_at(o);
            let n = nodes.len();
            let off = if n == 0 {
                f64::INFINITY
            } else {
                let cx = nodes.iter().map(|p| p[0]).sum::<f64>() / n as f64;
                let cy = nodes.iter().map(|p| p[1]).sum::<f64>() / n as f64;
                cx.hypot(cy)
            };
            let better = match &best {
                None => true,
                Some((bn, boff, ..)) => n > *bn || (n == *bn && off < *boff),
            };
            if better {
                best = Some((n, off, o, nodes, index));
            }
        }
    }
    let (n, _, offset, nodes, index) = best.expect("16 offsets tried");
    if n > MAX_LATTICE_NODES {
        return Err(bad(
            "spacing",
            format!(
                "{s:e} m gives {n} lattice nodes, more than the {MAX_LATTICE_NODES} a grain may \
                 have; raise --spacing"
            ),
        ));
    }
    let at: HashMap<(i64, i64), usize> = index.iter().enumerate().map(|(k, &ij)| (ij, k)).collect();
    let mut links = Vec::new();
    for (a, &(i, j)) in index.iter().enumerate() {
        for kind in [LinkKind::D0, LinkKind::D60, LinkKind::D120] {
            let (di, dj) = kind.step();
            let Some(&b) = at.get(&(i + di, j + dj)) else {
                continue;
            };
            let (p, q) = (nodes[a], nodes[b]);
            // Balls of radius dist(·) around both ends and the midpoint lie inside the
            // outline; they cover the segment when each end's ball and the midpoint's reach
            // half the spacing. Otherwise test the segment against every edge.
            let mid = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
            let covered = r + grid.distance(mid) >= s / 2.0;
            if covered || !segment_hits_boundary(p, q, poly) {
                let (i, j) = if a < b { (a, b) } else { (b, a) };
                links.push(Link { i, j, kind });
            }
        }
    }
    links.sort_by_key(|l| (l.i, l.j));
    if !has_cell(&index, &at, &links) {
        return Err(bad(
            "spacing",
            format!(
                "the grain is thinner than one lattice cell: {n} node(s) of radius {r:e} m and \
                 {} link(s) fit at spacing {s:e} m, and no three nodes are linked in a triangle \
                 (a lattice needs at least one cell); lower --spacing",
                links.len()
            ),
        ));
    }
    Ok(LatticeFill {
        nodes,
        index,
        links,
        offset,
        radius: r,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(l: f64) -> Vec<[f64; 2]> {
        vec![
            [-l / 2.0, -l / 2.0],
            [l / 2.0, -l / 2.0],
            [l / 2.0, l / 2.0],
            [-l / 2.0, l / 2.0],
        ]
    }

    #[test]
    fn segments_crossing_a_notch_are_not_linked() {
        // A U shape: two prongs 1 apart across a gap.
        let u = vec![
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 3.0],
            [2.0, 3.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ];
        assert!(segment_hits_boundary([0.5, 2.0], [2.5, 2.0], &u));
        assert!(!segment_hits_boundary([0.5, 0.5], [2.5, 0.5], &u));
        // Small nodes (f = 0.2) across the gap are never linked.
        let f = lattice_fill(&u, 0.3, 0.2).unwrap();
        for l in &f.links {
            assert!(!segment_hits_boundary(f.nodes[l.i], f.nodes[l.j], &u));
        }
    }

    #[test]
    fn bad_spacings_name_the_field() {
        let sq = square(1.0);
        for s in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(lattice_fill(&sq, s, 1.0).unwrap_err().field, "spacing");
        }
        let e = lattice_fill(&sq, 2.0, 1.0).unwrap_err();
        assert!(e.reason.contains("larger than the grain"), "{e}");
        let e = lattice_fill(&sq, 1e-4, 1.0).unwrap_err();
        assert!(e.reason.contains("more than the 10000"), "{e}");
        let e = lattice_fill(&sq, 0.9, 1.0).unwrap_err();
        assert!(e.reason.contains("thinner than one lattice cell"), "{e}");
        for f in [0.0, 1.5, f64::NAN] {
            assert_eq!(lattice_fill(&sq, 0.1, f).unwrap_err().field, "node-radius");
        }
    }
}
