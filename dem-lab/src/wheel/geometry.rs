//! S1 step (1): the walls of the annulus. The outer wall is a full circle, drawn as a closed
//! polygon of `outer_segments` chords with its vertices on the circle; the inner wall is a
//! ring of n1 equally spaced rectangular grooves cut into the hub (depth h1, width b) joined
//! by arcs of the inner circle (each arc a polyline of chords no longer in angle than the
//! outer polygon's), one closed polyline wall.
//!
//! Groove 1 is centred on the +x axis: its sides are the lines y = ±b/2, its mouth corners lie
//! on the inner circle at x_m = √(r_i² − b²/4), and its bottom corners at x_m − h1 (the depth is
//! measured from the mouth along the groove's axis, our reading of "depth"):
//!
//! ```text
//! c1 = (x_m, −b/2)   c2 = (x_m − h1, −b/2)   c3 = (x_m − h1, b/2)   c4 = (x_m, b/2)
//! ```
//!
//! Groove k's corners are those rotated by θ_k = 2π(k − 1)/n1 (S1). The grooves fit when every
//! groove lies in its own wedge |φ − θ_k| < π/n1 (then no two grooves overlap and every arc
//! between them has a positive length): the bottom corner c3 has the groove's largest polar
//! angle, so the test is x_m − h1 > 0 and atan2(b/2, x_m − h1) < π/n1; and b < 2 r_i.
//!
//! The annulus area S (S1's porosity denominator) is the area between the two polylines as
//! drawn (shoelace formula), so the porosity is that of the region the discs can fill.

use crate::LabError;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Dimensions of the walls (SI units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct GrooveRing {
    /// Outer radius of the wheel (m).
    pub r_outer: f64,
    /// Radius of the inner circle (the hub) (m).
    pub r_inner: f64,
    /// Number of grooves n1 (≥ 1).
    pub grooves: u32,
    /// Groove depth h1 (m), from the mouth on the inner circle towards the centre.
    pub groove_depth: f64,
    /// Groove width b (m).
    pub groove_width: f64,
    /// Chords of the outer circle (≥ 16); the inner arcs are cut as finely in angle.
    pub outer_segments: u32,
}

/// The walls as vertex lists, the groove corners and the annulus area.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Walls {
    /// Closed polyline of the inner wall (first vertex repeated last), counter-clockwise.
    pub inner: Vec<[f64; 2]>,
    /// Closed polygon of the outer wall (first vertex repeated last), counter-clockwise.
    pub outer: Vec<[f64; 2]>,
    /// The four corners c1..c4 of each groove, groove k at index k − 1.
    pub corners: Vec<[[f64; 2]; 4]>,
    /// Area between the two walls S (m²).
    pub area: f64,
}

fn err(field: &str, reason: String) -> LabError {
    LabError::Param {
        field: field.into(),
        reason,
    }
}

fn rot(p: [f64; 2], t: f64) -> [f64; 2] {
    let (s, c) = t.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

/// Shoelace area of a closed vertex list (positive counter-clockwise).
pub fn polygon_area(v: &[[f64; 2]]) -> f64 {
    let mut a = 0.0;
    for k in 0..v.len().saturating_sub(1) {
        a += v[k][0] * v[k + 1][1] - v[k + 1][0] * v[k][1];
    }
    0.5 * a
}

/// Whether `p` is inside the closed vertex list `v` (ray casting).
pub fn inside(v: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut c = false;
    for k in 0..v.len().saturating_sub(1) {
        let (a, b) = (v[k], v[k + 1]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                c = !c;
            }
        }
    }
    c
}

/// Distance from `p` to the polyline `v`.
pub fn distance(v: &[[f64; 2]], p: [f64; 2]) -> f64 {
    let mut d = f64::INFINITY;
    for k in 0..v.len().saturating_sub(1) {
        let (a, b) = (v[k], v[k + 1]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        d = d.min((p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy));
    }
    d
}

impl GrooveRing {
    /// Groove 1's corners c1..c4 (module docs).
    pub fn first_corners(&self) -> [[f64; 2]; 4] {
        let hb = 0.5 * self.groove_width;
        let xm = (self.r_inner * self.r_inner - hb * hb).sqrt();
        let xb = xm - self.groove_depth;
        [[xm, -hb], [xb, -hb], [xb, hb], [xm, hb]]
    }

    /// Checks that the grooves fit the inner circle and do not overlap, and that the annulus
    /// is wider than `min_width` (m); errors name the field.
    pub fn validate(&self, min_width: f64) -> Result<(), LabError> {
        let pos = |f: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(err(f, format!("{v}: must be a positive length")))
            }
        };
        pos("r_outer (--r-outer)", self.r_outer)?;
        pos("r_inner (--r-inner)", self.r_inner)?;
        pos("groove_depth (--groove-depth)", self.groove_depth)?;
        pos("groove_width (--groove-width)", self.groove_width)?;
        if self.grooves == 0 {
            return Err(err(
                "grooves (--grooves)",
                "0: the inner wall needs at least one groove to turn the wheel".into(),
            ));
        }
        if self.outer_segments < 16 {
            return Err(err(
                "outer_segments (--outer-segments)",
                format!("{}: at least 16 chords", self.outer_segments),
            ));
        }
        if self.r_outer - self.r_inner < min_width {
            return Err(err(
                "r_outer (--r-outer)",
                format!(
                    "{:.4} mm: the annulus from r_inner {:.4} mm is narrower than {:.4} mm \
                     (4 largest disc diameters)",
                    self.r_outer * 1e3,
                    self.r_inner * 1e3,
                    min_width * 1e3
                ),
            ));
        }
        let hb = 0.5 * self.groove_width;
        if hb >= self.r_inner {
            return Err(err(
                "groove_width (--groove-width)",
                format!(
                    "{:.4} mm: a groove does not fit the inner circle of diameter {:.4} mm",
                    self.groove_width * 1e3,
                    2.0 * self.r_inner * 1e3
                ),
            ));
        }
        let c = self.first_corners();
        if c[1][0] <= 0.0 {
            return Err(err(
                "groove_depth (--groove-depth)",
                format!(
                    "{:.4} mm: the groove's bottom would cross the centre (at most {:.4} mm)",
                    self.groove_depth * 1e3,
                    c[0][0] * 1e3
                ),
            ));
        }
        let half = PI / self.grooves as f64;
        let phi = c[2][1].atan2(c[2][0]);
        if phi >= half {
            return Err(err(
                "grooves (--grooves)",
                format!(
                    "{} grooves {:.4} mm wide and {:.4} mm deep overlap on the inner circle of \
                     radius {:.4} mm (each needs {:.1}° of its {:.1}°): fewer, narrower or \
                     shallower grooves (--grooves, --groove-width, --groove-depth)",
                    self.grooves,
                    self.groove_width * 1e3,
                    self.groove_depth * 1e3,
                    self.r_inner * 1e3,
                    2.0 * phi.to_degrees(),
                    2.0 * half.to_degrees()
                ),
            ));
        }
        Ok(())
    }

    /// Groove k's corners (k from 1): groove 1's rotated by θ_k = 2π(k − 1)/n1.
    pub fn corners(&self, k: u32) -> [[f64; 2]; 4] {
        let t = 2.0 * PI * (k - 1) as f64 / self.grooves as f64;
        self.first_corners().map(|p| rot(p, t))
    }

    /// The wall polylines (call [`GrooveRing::validate`] first).
    pub fn walls(&self) -> Walls {
        let n = self.outer_segments as usize;
        let mut outer: Vec<[f64; 2]> = (0..n)
            .map(|k| rot([self.r_outer, 0.0], 2.0 * PI * k as f64 / n as f64))
            .collect();
        outer.push(outer[0]);
        let dmax = 2.0 * PI / n as f64;
        let corners: Vec<[[f64; 2]; 4]> = (1..=self.grooves).map(|k| self.corners(k)).collect();
        let mut inner = Vec::new();
        let g = self.grooves as usize;
        for k in 0..g {
            inner.extend_from_slice(&corners[k]);
            // Arc from this groove's c4 to the next one's c1 on the inner circle.
            let a0 = corners[k][3][1].atan2(corners[k][3][0]);
            let mut a1 = corners[(k + 1) % g][0][1].atan2(corners[(k + 1) % g][0][0]);
            while a1 <= a0 {
                a1 += 2.0 * PI;
            }
            let m = ((a1 - a0) / dmax).ceil().max(1.0) as usize;
            for j in 1..m {
                let a = a0 + (a1 - a0) * j as f64 / m as f64;
                inner.push([self.r_inner * a.cos(), self.r_inner * a.sin()]);
            }
        }
        inner.push(inner[0]);
        let area = polygon_area(&outer) - polygon_area(&inner);
        Walls {
            inner,
            outer,
            corners,
            area,
        }
    }
}

impl Walls {
    /// Whether a disc at `p` of radius `r` lies in the annulus, clear of both walls.
    pub fn holds(&self, p: [f64; 2], r: f64) -> bool {
        inside(&self.outer, p)
            && !inside(&self.inner, p)
            && distance(&self.outer, p) >= r
            && distance(&self.inner, p) >= r
    }

    /// Whether the centre `p` lies between the walls.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        inside(&self.outer, p) && !inside(&self.inner, p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    pub fn ring() -> GrooveRing {
        GrooveRing {
            r_outer: 5e-3,
            r_inner: 2e-3,
            grooves: 6,
            groove_depth: 0.5e-3,
            groove_width: 0.6e-3,
            outer_segments: 120,
        }
    }

    /// Done when: groove corners equal groove 1's rotated by θ_k to round-off, and the
    /// polyline holds them in order.
    #[test]
    fn groove_corners_are_groove_one_rotated() {
        let g = ring();
        g.validate(1e-3).unwrap();
        let w = g.walls();
        let c1 = g.first_corners();
        let mut worst = 0.0f64;
        for k in 1..=g.grooves {
            let t = 2.0 * PI * (k - 1) as f64 / g.grooves as f64;
            let c = w.corners[k as usize - 1];
            for (p, q) in c.iter().zip(c1.iter()) {
                // Rotated back by θ_k, each corner is groove 1's.
                let back = rot(*p, -t);
                worst = worst.max((back[0] - q[0]).hypot(back[1] - q[1]));
                assert!(w.inner.contains(p));
            }
            // Mouth corners on the inner circle, bottoms h1 deeper along the groove axis.
            assert!((c[0][0].hypot(c[0][1]) - g.r_inner).abs() < 1e-15);
            let depth = (c[0][0] - c[1][0]).hypot(c[0][1] - c[1][1]);
            let width = (c[1][0] - c[2][0]).hypot(c[1][1] - c[2][1]);
            assert!(
                (depth - g.groove_depth).abs() < 1e-15 && (width - g.groove_width).abs() < 1e-15
            );
        }
        eprintln!("groove corners: worst distance from groove 1's rotated {worst:.2e} m");
        assert!(worst < 1e-15, "{worst}");
        // The area: outer polygon minus the grooved hub.
        let hub = PI * g.r_inner * g.r_inner;
        assert!(w.area > PI * (g.r_outer * g.r_outer) * 0.99 - hub);
        assert!(w.area < PI * g.r_outer * g.r_outer - hub + 6.0 * 0.6e-3 * 0.6e-3);
        assert_eq!(w.inner.first(), w.inner.last());
    }

    /// Bad input: grooves that overlap or do not fit name the field.
    #[test]
    fn bad_grooves_name_the_field() {
        let cases = [
            (
                GrooveRing {
                    grooves: 40,
                    ..ring()
                },
                "grooves",
            ),
            (
                GrooveRing {
                    groove_width: 4.5e-3,
                    ..ring()
                },
                "groove_width",
            ),
            (
                GrooveRing {
                    groove_depth: 2.5e-3,
                    ..ring()
                },
                "groove_depth",
            ),
            (
                GrooveRing {
                    grooves: 0,
                    ..ring()
                },
                "grooves",
            ),
            (
                GrooveRing {
                    r_outer: 2.5e-3,
                    ..ring()
                },
                "r_outer",
            ),
        ];
        for (g, field) in cases {
            match g.validate(1e-3) {
                Err(LabError::Param { field: f, reason }) => {
                    assert!(f.starts_with(field), "{f} ({reason}) for {field}")
                }
                other => panic!("{field}: {other:?}"),
            }
        }
    }
}
