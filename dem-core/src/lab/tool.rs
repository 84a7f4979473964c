//! Geometry of the orthogonal cutting test (S0 Ye & Xu 2010; S4 Tan et al.): the specimen in a
//! slot of three fixed frictionless walls, a tool of two wall segments moving horizontally.
//!
//! ```text
//!            rake face (rake angle γ from the vertical, positive leaning back)
//!            |
//!   tool →   |   ← specimen top y1 ─────────────────────────────┐
//!            |  a_p                                              │ right slot wall
//!   ________/E ─ ─ ─ nominal machined surface y_n = y1 − a_p ─ ─ │ (full height when
//!   clearance face (clearance angle α above the horizontal)      │  the tool never
//!   left slot wall │  (ends ½a_p below y_n)                      │  reaches it)
//!                  └──────────────── slot bottom ───────────────┘
//! ```
//!
//! The tool moves in +x at speed v. Its cutting edge E starts at height y_n with the tool's
//! foremost point `approach` × a_p before the specimen's left edge x0, and travels until E is at
//! x0 + L. Tool travel s is measured as the edge's x minus x0 (s < 0 during the approach). The
//! rake face runs from E along (−sin γ, cos γ), the clearance face from E along (−cos α, sin α);
//! wedge angle β = 90° − γ − α.

use super::cutting::CuttingTest;
use super::LabError;
use serde::{Deserialize, Serialize};

/// A wall segment by name.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    pub name: String,
    pub a: [f64; 2],
    pub b: [f64; 2],
}

/// Names of the two tool walls (history columns `<name>_fx`, `<name>_fy`).
pub const RAKE: &str = "rake";
pub const CLEARANCE: &str = "clearance";

/// Where everything is (m, s), for a test and a specimen extent `[x0, x1, y0, y1]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CutGeometry {
    pub extent: [f64; 4],
    /// Nominal machined surface y_n = y1 − a_p.
    pub nominal_y: f64,
    /// Cutting edge at t = 0.
    pub edge_start: [f64; 2],
    /// Tool walls at t = 0: rake face, clearance face (both start at the edge).
    pub tool: [Segment; 2],
    /// Fixed slot walls: bottom, left, right.
    pub slot: [Segment; 3],
    /// Travel s = edge x − x0 at t = 0 (negative) and at the end (= L).
    pub travel_start: f64,
    pub travel_end: f64,
    /// Travel at which the tool's foremost point reaches x0 (0 for γ ≥ 0).
    pub travel_entry: f64,
    /// Run duration (s) = (travel_end − travel_start) / v.
    pub duration: f64,
    /// Tool velocity (m/s).
    pub velocity: [f64; 2],
}

impl CutGeometry {
    /// The geometry of `test` on a specimen whose discs span `extent`.
    pub fn new(test: &CuttingTest, extent: [f64; 4]) -> Result<CutGeometry, LabError> {
        test.validate()?;
        let [x0, x1, y0, y1] = extent;
        if !(x1 > x0 && y1 > y0 && extent.iter().all(|v| v.is_finite())) {
            return Err(LabError::Param {
                field: "extent".into(),
                reason: format!("{extent:?} is not a box"),
            });
        }
        let ap = test.depth;
        let yn = y1 - ap;
        let side_top = yn - 0.5 * ap;
        if side_top <= y0 {
            return Err(LabError::Param {
                field: "depth".into(),
                reason: format!(
                    "a_p = {ap} m leaves no room for the slot's side walls below 1.5 a_p in a \
                     specimen {} m high",
                    y1 - y0
                ),
            });
        }
        let (sg, cg) = test.rake_angle.sin_cos();
        let (sa, ca) = test.clearance_angle.sin_cos();
        let lr = test.rake_face * ap;
        let lc = test.clearance_face * ap;
        // Foremost point ahead of the edge: the rake face's top when it leans forward (γ < 0).
        let overhang = (-sg * lr).max(0.0);
        let ex = x0 - test.approach * ap - overhang;
        let edge = [ex, yn];
        let tool = [
            Segment {
                name: RAKE.into(),
                a: edge,
                b: [ex - sg * lr, yn + cg * lr],
            },
            Segment {
                name: CLEARANCE.into(),
                a: edge,
                b: [ex - ca * lc, yn + sa * lc],
            },
        ];
        let travel_end = test.length;
        let front_end = x0 + travel_end + overhang;
        let right_top = if front_end + 0.5 * ap < x1 {
            y1
        } else {
            side_top
        };
        let pad = 0.5 * ap;
        let slot = [
            Segment {
                name: "slot_bottom".into(),
                a: [x0 - pad, y0],
                b: [x1 + pad, y0],
            },
            Segment {
                name: "slot_left".into(),
                a: [x0, y0],
                b: [x0, side_top],
            },
            Segment {
                name: "slot_right".into(),
                a: [x1, y0],
                b: [x1, right_top],
            },
        ];
        let travel_start = ex - x0;
        Ok(CutGeometry {
            extent,
            nominal_y: yn,
            edge_start: edge,
            tool,
            slot,
            travel_start,
            travel_end,
            travel_entry: -overhang,
            duration: (travel_end - travel_start) / test.speed,
            velocity: [test.speed, 0.0],
        })
    }

    /// Tool travel (m) at time `t` (s).
    pub fn travel(&self, t: f64) -> f64 {
        self.travel_start + self.velocity[0] * t
    }

    /// Smallest distance (m) between any slot wall and the region the tool walls sweep over
    /// the whole run (each tool segment translated from its start to its end position: a
    /// parallelogram). Positive means the tool never touches a slot wall.
    pub fn slot_clearance(&self) -> f64 {
        let dx = self.travel_end - self.travel_start;
        let mut best = f64::INFINITY;
        for t in &self.tool {
            let quad = [t.a, t.b, [t.b[0] + dx, t.b[1]], [t.a[0] + dx, t.a[1]]];
            for s in &self.slot {
                best = best.min(segment_polygon_distance(s.a, s.b, &quad));
            }
        }
        best
    }
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Distance from point p to segment ab.
fn point_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let e = sub(b, a);
    let l2 = e[0] * e[0] + e[1] * e[1];
    let s = if l2 > 0.0 {
        (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + s * e[0] - p[0], a[1] + s * e[1] - p[1]];
    (q[0] * q[0] + q[1] * q[1]).sqrt()
}

/// Whether segments ab and cd cross or touch.
fn segments_intersect(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let d1 = cross(sub(b, a), sub(c, a));
    let d2 = cross(sub(b, a), sub(d, a));
    let d3 = cross(sub(d, c), sub(a, c));
    let d4 = cross(sub(d, c), sub(b, c));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    point_segment(c, a, b) == 0.0
        || point_segment(d, a, b) == 0.0
        || point_segment(a, c, d) == 0.0
        || point_segment(b, c, d) == 0.0
}

/// Whether p lies inside (or on) the convex polygon `poly` (either orientation; a degenerate
/// polygon of zero area contains nothing beyond its edges, which the caller tests).
fn inside_convex(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let (mut pos, mut neg) = (false, false);
    for k in 0..poly.len() {
        let c = cross(sub(poly[(k + 1) % poly.len()], poly[k]), sub(p, poly[k]));
        pos |= c > 0.0;
        neg |= c < 0.0;
    }
    !(pos && neg)
}

/// Distance between segment ab and the convex polygon `poly` (0 when they meet).
pub fn segment_polygon_distance(a: [f64; 2], b: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    let area2: f64 = (0..poly.len())
        .map(|k| cross(poly[k], poly[(k + 1) % poly.len()]))
        .sum();
    if area2.abs() > 0.0 && (inside_convex(a, poly) || inside_convex(b, poly)) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for k in 0..poly.len() {
        let (c, d) = (poly[k], poly[(k + 1) % poly.len()]);
        if segments_intersect(a, b, c, d) {
            return 0.0;
        }
        best = best
            .min(point_segment(a, c, d))
            .min(point_segment(b, c, d))
            .min(point_segment(c, a, b))
            .min(point_segment(d, a, b));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_polygon_distances() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(segment_polygon_distance([2.0, 0.0], [2.0, 1.0], &sq), 1.0);
        assert_eq!(segment_polygon_distance([0.5, -1.0], [0.5, 2.0], &sq), 0.0);
        assert_eq!(segment_polygon_distance([0.2, 0.2], [0.3, 0.3], &sq), 0.0);
        let d = segment_polygon_distance([2.0, 2.0], [3.0, 2.0], &sq);
        assert!((d - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn default_tool_clears_the_slot_and_starts_outside() {
        let t = CuttingTest::default();
        let g = CutGeometry::new(&t, [0.0, 20e-3, 0.0, 10e-3]).unwrap();
        assert!((g.nominal_y - 9e-3).abs() < 1e-15);
        // Edge starts approach·a_p before x0; 0° rake: the rake face is vertical.
        assert!((g.edge_start[0] + t.approach * t.depth).abs() < 1e-15);
        assert!((g.tool[0].b[0] - g.edge_start[0]).abs() < 1e-15);
        assert!((g.tool[0].b[1] - (9e-3 + t.rake_face * t.depth)).abs() < 1e-15);
        // The clearance face rises back at α.
        let [a, b] = [g.tool[1].a, g.tool[1].b];
        assert!(((b[1] - a[1]) / (a[0] - b[0]) - t.clearance_angle.tan()).abs() < 1e-12);
        // Travel and duration.
        assert!((g.duration - (t.length + t.approach * t.depth) / t.speed).abs() < 1e-15);
        assert!((g.travel(g.duration) - t.length).abs() < 1e-15);
        // Right wall full height (the tool stops 10 mm short of it), left wall below the cut.
        assert_eq!(g.slot[2].b[1], 10e-3);
        assert!(g.slot[1].b[1] < g.nominal_y);
        assert!(g.slot_clearance() > 0.4e-3);
    }

    #[test]
    fn a_cut_through_the_whole_specimen_lowers_the_far_wall() {
        let mut t = CuttingTest {
            rake_angle: (-10f64).to_radians(),
            ..Default::default()
        };
        t.length = 25e-3;
        let g = CutGeometry::new(&t, [0.0, 20e-3, 0.0, 10e-3]).unwrap();
        assert!(g.slot[2].b[1] < g.nominal_y);
        assert!(g.travel_entry < 0.0);
        assert!(g.slot_clearance() > 0.0);
        // A right wall of full height would be hit: the check sees it.
        let mut h = g.clone();
        h.slot[2].b[1] = 10e-3;
        assert_eq!(h.slot_clearance(), 0.0);
    }

    #[test]
    fn too_deep_a_cut_is_an_error() {
        let t = CuttingTest {
            depth: 7e-3,
            ..Default::default()
        };
        assert!(CutGeometry::new(&t, [0.0, 20e-3, 0.0, 10e-3]).is_err());
    }
}
