//! Geometry of the orthogonal cutting test (S0 Ye & Xu 2010; S4 Tan et al.): the specimen in a
//! slot of three fixed frictionless walls, a rigid tool moving horizontally.
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
//!
//! The tool ([`ToolModel::Rigid`], the default) is one rigid polyline wall `tool`: clearance
//! face end → edge → rake face end, so a disc at the edge has one contact, with the nearest
//! feature (a face or the edge). With an edge radius r_e the sharp edge E is replaced by the
//! arc of radius r_e tangent to both faces (centre E + r_e/sin(β/2) along the wedge bisector,
//! tangent points r_e/tan(β/2) from E along each face), drawn as chords of at most 10°, and
//! the tool is lowered so the arc's lowest point lies on y_n. [`ToolModel::Segments`] is the
//! earlier model: two separate wall segments `rake` and `clearance` meeting at E (a disc at
//! the edge touches both).
//!
//! This module knows shapes, not tests: [`CutGeometry::new`], which reads a
//! [`super::CuttingTest`], lives beside the test in `cutting/mod.rs` (so the geometry does
//! not import the test that imports it).

use serde::{Deserialize, Serialize};

/// A wall by name: a segment from `a` to `b`, or a polyline a → `via` → b.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Segment {
    pub name: String,
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// Inner vertices of a polyline, from `a` to `b` (empty: a segment).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub via: Vec<[f64; 2]>,
}

impl Segment {
    pub(super) fn new(name: &str, a: [f64; 2], b: [f64; 2]) -> Segment {
        Segment {
            name: name.into(),
            a,
            b,
            via: Vec::new(),
        }
    }

    /// The vertices in order: a, via, b.
    pub fn vertices(&self) -> Vec<[f64; 2]> {
        let mut v = vec![self.a];
        v.extend_from_slice(&self.via);
        v.push(self.b);
        v
    }
}

/// How the tool is modelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum ToolModel {
    /// One rigid polyline wall `tool` (one contact per disc, with the nearest feature); the
    /// tool–disc and slot-wall–disc contact stiffnesses are PFC's: the wall's and the disc's
    /// stiffness in series ([`crate::model::series_wall_stiffness`]).
    #[default]
    Rigid,
    /// The earlier model (the Table 2 runs of 2026-11-25): two separate wall segments `rake`
    /// and `clearance` (a disc at the edge touches both); tool and slot-wall contact
    /// stiffness = the factor × the disc–disc k_n directly.
    Segments,
}

impl ToolModel {
    /// The model of results and `--params` files written before the field existed.
    pub fn legacy() -> ToolModel {
        ToolModel::Segments
    }

    pub fn is_legacy(&self) -> bool {
        *self == ToolModel::Segments
    }
}

/// Names of the tool walls (history columns `<name>_fx`, `<name>_fy`): the rigid tool, and
/// the two faces of [`ToolModel::Segments`].
pub const TOOL: &str = "tool";
pub const RAKE: &str = "rake";
pub const CLEARANCE: &str = "clearance";

/// Where everything is (m, s), for a test and a specimen extent `[x0, x1, y0, y1]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CutGeometry {
    pub extent: [f64; 4],
    /// Nominal machined surface y_n = y1 − a_p.
    pub nominal_y: f64,
    /// Cutting edge at t = 0 (the faces' intersection E, also with an edge radius).
    pub edge_start: [f64; 2],
    /// Tool walls at t = 0: one polyline `tool` ([`ToolModel::Rigid`]: clearance face end,
    /// edge, rake face end), or the rake face and the clearance face, both from the edge
    /// ([`ToolModel::Segments`]).
    pub tool: Vec<Segment>,
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

/// The rounded edge: arc points from the clearance-face tangent point to the rake-face
/// tangent point (both included), for an edge at `e` with unit face directions `uc`
/// (clearance) and `ur` (rake), radius `re` > 0; and the arc's lowest y.
pub(super) fn edge_arc(e: [f64; 2], uc: [f64; 2], ur: [f64; 2], re: f64) -> (Vec<[f64; 2]>, f64) {
    let beta = (uc[0] * ur[0] + uc[1] * ur[1]).clamp(-1.0, 1.0).acos();
    let (half_s, half_t) = ((0.5 * beta).sin(), (0.5 * beta).tan());
    let bis = [uc[0] + ur[0], uc[1] + ur[1]];
    let bl = bis[0].hypot(bis[1]);
    let c = [
        e[0] + bis[0] / bl * re / half_s,
        e[1] + bis[1] / bl * re / half_s,
    ];
    let tc = [e[0] + uc[0] * re / half_t, e[1] + uc[1] * re / half_t];
    let tr = [e[0] + ur[0] * re / half_t, e[1] + ur[1] * re / half_t];
    // Angles of the tangent points about c; the arc runs the short way round the outside
    // (through the point c − bisector · r_e), turning by π − β.
    let (a0, a1) = (
        (tc[1] - c[1]).atan2(tc[0] - c[0]),
        (tr[1] - c[1]).atan2(tr[0] - c[0]),
    );
    let mut turn = a1 - a0;
    let full = std::f64::consts::TAU;
    // The outward direction −bisector lies between a0 and a0 + turn.
    let out = (-bis[1]).atan2(-bis[0]);
    let mut rel = (out - a0).rem_euclid(full);
    turn = turn.rem_euclid(full);
    if rel > turn {
        turn -= full;
        rel -= full;
    }
    debug_assert!(rel.abs() <= turn.abs());
    let n = (turn.abs() / 10f64.to_radians()).ceil().max(1.0) as usize;
    let mut pts = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let a = a0 + turn * k as f64 / n as f64;
        pts.push([c[0] + re * a.cos(), c[1] + re * a.sin()]);
    }
    pts[0] = tc;
    pts[n] = tr;
    // Lowest point of the arc: the bottom of the circle if the arc passes it, else an end.
    let down = (-std::f64::consts::FRAC_PI_2 - a0).rem_euclid(full);
    let passes = if turn >= 0.0 {
        down <= turn
    } else {
        down - full >= turn
    };
    let low = if passes { c[1] - re } else { tc[1].min(tr[1]) };
    (pts, low)
}

impl CutGeometry {
    /// Tool travel (m) at time `t` (s).
    pub fn travel(&self, t: f64) -> f64 {
        self.travel_start + self.velocity[0] * t
    }

    /// Smallest distance (m) between any slot wall and the region the tool walls sweep over
    /// the whole run (each face of the tool translated from its start to its end position: a
    /// parallelogram). Positive means the tool never touches a slot wall.
    pub fn slot_clearance(&self) -> f64 {
        let dx = self.travel_end - self.travel_start;
        let mut best = f64::INFINITY;
        for t in &self.tool {
            for f in t.vertices().windows(2) {
                let (a, b) = (f[0], f[1]);
                let quad = [a, b, [b[0] + dx, b[1]], [a[0] + dx, a[1]]];
                for s in &self.slot {
                    best = best.min(segment_polygon_distance(s.a, s.b, &quad));
                }
            }
        }
        best
    }

    /// Lowest point of the tool at t = 0 (y, m): y_n for a sharp edge and for a rounded one.
    pub fn tool_bottom(&self) -> f64 {
        self.tool
            .iter()
            .flat_map(|t| t.vertices())
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min)
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
    use crate::cutting::CuttingTest;

    /// The checked test's geometry on a 20 × 10 mm specimen.
    fn geometry(t: &CuttingTest) -> CutGeometry {
        CutGeometry::new(&t.clone().check().unwrap(), [0.0, 20e-3, 0.0, 10e-3]).unwrap()
    }

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
        // The faces as separate segments (the earlier model) show each face's geometry.
        let t = CuttingTest {
            tool: ToolModel::Segments,
            ..Default::default()
        };
        let g = geometry(&t);
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
        let g = geometry(&t);
        assert!(g.slot[2].b[1] < g.nominal_y);
        assert!(g.travel_entry < 0.0);
        assert!(g.slot_clearance() > 0.0);
        // A right wall of full height would be hit: the check sees it.
        let mut h = g.clone();
        h.slot[2].b[1] = 10e-3;
        assert_eq!(h.slot_clearance(), 0.0);
    }

    #[test]
    fn the_rigid_tool_is_one_polyline_through_the_edge() {
        let t = CuttingTest::default();
        let g = geometry(&t);
        assert_eq!(g.tool.len(), 1);
        let v = g.tool[0].vertices();
        assert_eq!(v.len(), 3);
        assert_eq!(v[1], g.edge_start);
        assert_eq!(g.tool_bottom(), g.nominal_y);
        // Clearance end behind and above the edge at α, rake end straight up (γ = 0).
        let (c, r) = (v[0], v[2]);
        assert!(((c[1] - v[1][1]) / (v[1][0] - c[0]) - t.clearance_angle.tan()).abs() < 1e-12);
        assert!((r[0] - v[1][0]).abs() < 1e-18 && (r[1] - v[1][1] - 3e-3).abs() < 1e-15);
    }

    #[test]
    fn a_rounded_edge_is_an_arc_tangent_to_both_faces_cutting_at_y_n() {
        for rake in [0.0f64, 10.0, -10.0] {
            let t = CuttingTest {
                rake_angle: rake.to_radians(),
                edge_radius: 0.05,
                ..Default::default()
            };
            let g = geometry(&t);
            let v = g.tool[0].vertices();
            let re = 0.05 * t.depth;
            // The arc turns by π − β = 90° + γ + α in chords of at most 10°.
            let turn = 90.0 + rake + 7.0;
            let n = (turn / 10.0f64).ceil() as usize;
            assert_eq!(v.len(), n + 3, "rake {rake}");
            // All arc points lie on one circle of radius r_e; the first and last chords are
            // continued by the faces (tangency: the face direction is perpendicular to the
            // radius at the tangent point).
            let arc = &v[1..v.len() - 1];
            let (p0, p1) = (arc[0], arc[arc.len() - 1]);
            // Centre from the tangent points and the face normals.
            let uc = [v[0][0] - p0[0], v[0][1] - p0[1]];
            let ul = uc[0].hypot(uc[1]);
            let uc = [uc[0] / ul, uc[1] / ul];
            let c = [p0[0] - uc[1] * re, p0[1] + uc[0] * re];
            let c = if (c[0] - p1[0]).hypot(c[1] - p1[1]) > 1.5 * re {
                [p0[0] + uc[1] * re, p0[1] - uc[0] * re]
            } else {
                c
            };
            for p in arc {
                assert!(((p[0] - c[0]).hypot(p[1] - c[1]) - re).abs() < 1e-12 * t.depth);
            }
            let ur = [v[v.len() - 1][0] - p1[0], v[v.len() - 1][1] - p1[1]];
            let rad = [p1[0] - c[0], p1[1] - c[1]];
            assert!((ur[0] * rad[0] + ur[1] * rad[1]).abs() < 1e-9 * t.depth * re);
            // The lowest point of the true arc is y_n; the chords lie inside the arc, at most
            // the sagitta r_e (1 − cos 5°) higher.
            let low = g.tool_bottom();
            assert!(
                low >= g.nominal_y - 1e-15
                    && low - g.nominal_y <= re * (1.0 - 5f64.to_radians().cos()) + 1e-15
            );
            assert!((c[1] - re - g.nominal_y).abs() < 1e-12 * t.depth);
        }
        let bad = CuttingTest {
            edge_radius: 0.05,
            tool: ToolModel::Segments,
            ..Default::default()
        };
        assert!(bad
            .validate()
            .unwrap_err()
            .to_string()
            .contains("edge_radius"));
    }

    #[test]
    fn too_deep_a_cut_is_an_error() {
        // A window that starts early enough for the test itself to be valid: the depth error is
        // the geometry's (1.5 a_p = 10.5 mm in a 10 mm high specimen).
        let t = CuttingTest {
            depth: 7e-3,
            window_start: 1.0,
            ..Default::default()
        };
        let err = CutGeometry::new(&t.check().unwrap(), [0.0, 20e-3, 0.0, 10e-3]).unwrap_err();
        assert!(err.to_string().contains("depth"), "{err}");
    }
}
