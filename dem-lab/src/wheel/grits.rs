//! S1 step (3): abrasive grits on the rim, each a cluster of overlapping discs of radius r_g.
//!
//! Layouts, in the grit's own frame (x tangential, y radial outwards, rows from the base up):
//!
//! * **triangle** (S1): row 1 has N discs one radius r_g apart; each next row is shifted half a
//!   radius in x and one radius in y and has one disc fewer. S1's example says "6 rows, the
//!   first of 5 discs", which is not consistent (rows of 5, 4, 3, 2, 1 discs end after 5
//!   rows; a 6th would be empty). We read the rule, not the count: `rows` = N discs in the
//!   first row, N rows, N(N + 1)/2 discs (5 rows: 15 discs; 6 rows: 21);
//! * **square**: N rows of N discs, one radius apart both ways;
//! * **round**: the discs of a hexagonal lattice of pitch r_g whose centres lie within
//!   (N − 1) r_g/2 of the grit's centre: a disc-packed circle N discs across.
//!
//! Adjacent discs of a grit overlap (centres one radius apart), so a grit is a solid body; it is
//! written as one rigid clump (ORC: mass and inertia the members' sums). Grits are placed
//! around the rim, the base towards the wheel, their outermost point `protrusion` beyond the
//! outer radius; their centres uniformly spaced in angle, or at random with gaps of at least
//! `min_gap` between neighbouring grits (arc length at the outer radius). The wheel discs a
//! grit disc overlaps are removed.

use crate::specimen::rng::Rng;
use crate::LabError;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Grit shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum GritShape {
    Triangle,
    Square,
    Round,
}

impl GritShape {
    pub fn parse(s: &str) -> Option<GritShape> {
        match s {
            "triangle" => Some(GritShape::Triangle),
            "square" => Some(GritShape::Square),
            "round" => Some(GritShape::Round),
            _ => None,
        }
    }
}

/// How the grits are spaced round the rim.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum GritSpacing {
    Uniform,
    Random,
}

/// The grits' parameters (SI units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct GritParams {
    pub shape: GritShape,
    /// Discs in the first row (triangle), per side (square), across (round); ≥ 1.
    pub rows: u32,
    /// Radius of the grit discs r_g (m); also their pitch.
    pub radius: f64,
    /// Number of grits (≥ 0).
    pub count: u32,
    pub spacing: GritSpacing,
    /// Smallest gap between neighbouring grits along the rim (m).
    pub min_gap: f64,
    /// How far the grit's outermost point lies beyond the outer radius (m).
    pub protrusion: f64,
}

fn err(field: &str, reason: String) -> LabError {
    LabError::Param {
        field: field.into(),
        reason,
    }
}

/// Disc centres of one grit in its own frame (x tangential, y radial, base row at y = 0).
pub fn layout(shape: GritShape, rows: u32, r: f64) -> Vec<[f64; 2]> {
    let n = rows as usize;
    let mut v = Vec::new();
    match shape {
        GritShape::Triangle => {
            for row in 0..n {
                for k in 0..n - row {
                    v.push([(k as f64 + 0.5 * row as f64) * r, row as f64 * r]);
                }
            }
        }
        GritShape::Square => {
            for row in 0..n {
                for k in 0..n {
                    v.push([k as f64 * r, row as f64 * r]);
                }
            }
        }
        GritShape::Round => {
            let rad = 0.5 * (n as f64 - 1.0) * r;
            let dy = r * 3f64.sqrt() / 2.0;
            let m = (rad / dy).floor() as i64 + 1;
            for j in -m..=m {
                let shift = if j.rem_euclid(2) == 1 { 0.5 * r } else { 0.0 };
                let kmax = (rad / r).ceil() as i64 + 1;
                for k in -kmax..=kmax {
                    let (x, y) = (k as f64 * r + shift, j as f64 * dy);
                    if x.hypot(y) <= rad + 1e-12 * r {
                        v.push([x + rad, y + rad]);
                    }
                }
            }
        }
    }
    // Centre in x, base row's discs at y = 0.
    let (x0, x1) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p[0]), a.1.max(p[0]))
    });
    let y0 = v.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let xc = 0.5 * (x0 + x1);
    v.iter().map(|p| [p[0] - xc, p[1] - y0]).collect()
}

/// Tangential width and radial height of a layout's discs (m), outer edges included.
pub fn extent(v: &[[f64; 2]], r: f64) -> (f64, f64) {
    let f = |k: usize| {
        v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.min(p[k]), a.1.max(p[k]))
        })
    };
    let (x, y) = (f(0), f(1));
    (x.1 - x.0 + 2.0 * r, y.1 - y.0 + 2.0 * r)
}

impl GritParams {
    /// Checks the grits against a rim of radius `r_outer` (m); errors name the field.
    pub fn validate(&self, r_outer: f64) -> Result<(), LabError> {
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(err(
                "grit radius (--grit-radius)",
                format!("{}: must be a positive length", self.radius),
            ));
        }
        if self.rows == 0 {
            return Err(err("grit rows (--grit-rows)", "0: at least 1".into()));
        }
        if !(self.min_gap.is_finite() && self.min_gap >= 0.0) {
            return Err(err(
                "grit min_gap (--grit-gap)",
                format!("{}: must be a length >= 0", self.min_gap),
            ));
        }
        let v = layout(self.shape, self.rows, self.radius);
        let (w, h) = extent(&v, self.radius);
        if !(self.protrusion.is_finite() && self.protrusion >= 0.0) {
            return Err(err(
                "grit protrusion (--protrusion)",
                format!("{}: must be a length >= 0", self.protrusion),
            ));
        }
        if self.protrusion > h - self.radius {
            return Err(err(
                "grit protrusion (--protrusion)",
                format!(
                    "{:.4} mm: a grit {:.4} mm high would not reach into the wheel; at most {:.4} \
                     mm (its height less one disc radius)",
                    self.protrusion * 1e3,
                    h * 1e3,
                    (h - self.radius) * 1e3
                ),
            ));
        }
        if self.count > 0 {
            let spacing = 2.0 * PI * r_outer / self.count as f64;
            if w + self.min_gap > spacing {
                return Err(err(
                    "grits (--grits)",
                    format!(
                        "{} grits {:.4} mm wide (plus the gap {:.4} mm) are wider than their \
                         spacing {:.4} mm on the rim of radius {:.4} mm: fewer grits (--grits), \
                         smaller ones (--grit-rows, --grit-radius) or a smaller --grit-gap",
                        self.count,
                        w * 1e3,
                        self.min_gap * 1e3,
                        spacing * 1e3,
                        r_outer * 1e3
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The polar angle of each grit's centre line (rad).
    pub fn angles(&self, r_outer: f64, rng: &mut Rng) -> Vec<f64> {
        let n = self.count as usize;
        let step = 2.0 * PI / n.max(1) as f64;
        match self.spacing {
            GritSpacing::Uniform => (0..n).map(|k| k as f64 * step).collect(),
            GritSpacing::Random => {
                // Gaps = the minimum (width + min_gap, as an angle) plus a random share of the
                // slack.
                let v = layout(self.shape, self.rows, self.radius);
                let w = extent(&v, self.radius).0;
                let least = (w + self.min_gap) / r_outer;
                let slack = (2.0 * PI - n as f64 * least).max(0.0);
                let share: Vec<f64> = (0..n).map(|_| rng.uniform()).collect();
                let sum: f64 = share.iter().sum::<f64>().max(1e-300);
                let start = rng.range(0.0, 2.0 * PI);
                let mut a = start;
                let mut out = Vec::with_capacity(n);
                for s in &share {
                    out.push(a);
                    a += least + slack * s / sum;
                }
                out
            }
        }
    }

    /// Every grit's discs `[x, y]` in the wheel frame (radius `self.radius`).
    pub fn place(&self, r_outer: f64, rng: &mut Rng) -> Vec<Vec<[f64; 2]>> {
        let v = layout(self.shape, self.rows, self.radius);
        let (_, h) = extent(&v, self.radius);
        // The base row's centres at radius r_base: the top edge at r_outer + protrusion.
        let r_base = r_outer + self.protrusion - h + self.radius;
        self.angles(r_outer, rng)
            .into_iter()
            .map(|a| {
                let (s, c) = a.sin_cos();
                v.iter()
                    .map(|p| {
                        // Radial direction (c, s), tangential (−s, c).
                        let rr = r_base + p[1];
                        [rr * c - p[0] * s, rr * s + p[0] * c]
                    })
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Done when: each grit's disc layout as S1 describes (triangle rows of N, N − 1, …, 1
    /// discs one radius apart, each row half a radius across and one radius up).
    #[test]
    fn triangle_is_s1s_layout() {
        let r = 0.1e-3;
        let v = layout(GritShape::Triangle, 5, r);
        assert_eq!(v.len(), 15);
        let mut k = 0;
        for row in 0..5usize {
            let first = v[k];
            for j in 0..5 - row {
                let p = v[k + j];
                assert!((p[1] - row as f64 * r).abs() < 1e-15, "row {row} y");
                if j > 0 {
                    assert!((p[0] - v[k + j - 1][0] - r).abs() < 1e-15, "spacing");
                }
            }
            if row > 0 {
                let prev = v[k - (5 - row + 1)];
                assert!((first[0] - prev[0] - 0.5 * r).abs() < 1e-15, "shift");
            }
            k += 5 - row;
        }
        assert_eq!(layout(GritShape::Triangle, 6, r).len(), 21);
        assert_eq!(layout(GritShape::Square, 4, r).len(), 16);
        let round = layout(GritShape::Round, 5, r);
        // A hexagonal patch within 2 r of the centre: 19 discs (1 + 6 + 12).
        assert_eq!(round.len(), 19, "{round:?}");
    }

    #[test]
    fn grits_wider_than_their_spacing_are_refused() {
        let g = GritParams {
            shape: GritShape::Triangle,
            rows: 5,
            radius: 0.1e-3,
            count: 60,
            spacing: GritSpacing::Uniform,
            min_gap: 0.0,
            protrusion: 0.2e-3,
        };
        // 60 grits 0.6 mm wide on a 5 mm rim: spacing 0.52 mm.
        match g.validate(5e-3) {
            Err(LabError::Param { field, .. }) => assert!(field.starts_with("grits"), "{field}"),
            other => panic!("{other:?}"),
        }
        assert!(GritParams {
            count: 20,
            ..g.clone()
        }
        .validate(5e-3)
        .is_ok());
        match (GritParams {
            protrusion: 1e-3,
            count: 20,
            ..g
        })
        .validate(5e-3)
        {
            Err(LabError::Param { field, .. }) => assert!(field.contains("protrusion")),
            other => panic!("{other:?}"),
        }
    }
}
