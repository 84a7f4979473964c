//! The machined surface of a cut specimen: the upper envelope of the workpiece's discs in bins
//! along the cut, its depth relative to the nominal machined surface (the specimen top minus the
//! depth of cut), and its roughness on the profile's mean line.
//!
//! Profile: in bin `[a, b]` the height z is the highest point of any workpiece disc over that
//! interval (a disc centred at x with radius r reaches y + r if a ≤ x ≤ b, else
//! y + √(r² − d²) at the bin end nearest to it, d < r the distance). With e_b = z_b − y_n the
//! deviation from the nominal surface y_n:
//! - depth: mean deviation = mean e_b (negative: the surface lies below the nominal one), and
//!   the highest and lowest e_b;
//! - roughness ([`Roughness`], ISO 4287:1997 definitions on the binned profile): about the
//!   mean line m(x), the least-squares straight line through (x_b, e_b) (§3.1.8.1, the mean
//!   line of the primary profile by least squares of the nominal form, a straight cut here; no
//!   λc filter: the evaluated length is a few sampling lengths at most), with p_b = e_b − m(x_b):
//!   Ra = mean |p_b| (§4.2.1), Rq = √(mean p_b²) (§4.2.2) and Rz = max p_b − min p_b, the
//!   peak-to-valley height over the evaluated length (ISO's Rt, §4.1.3; with one sampling
//!   length Rz and Rt coincide).
//!
//! Files written before the mean line (2026-12) hold `ra`/`rz` measured from the nominal line;
//! [`Surface::roughness`] computes the mean-line figures from their stored profile.

use serde::{Deserialize, Serialize};

/// The binned surface profile and its roughness (m).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Surface {
    /// Nominal machined surface y_n (m).
    pub nominal_y: f64,
    /// Evaluated length `[x_from, x_to]` (m) and bin width (m).
    pub x_from: f64,
    pub x_to: f64,
    pub bin_width: f64,
    /// Mean |z − y_n| from the nominal line (m): not ISO's Ra (which is on the mean line,
    /// [`Surface::roughness`]); kept as written by earlier versions.
    pub ra: f64,
    /// max(z) − min(z) (m); for a straight cut with no tilt, the Rz of [`Surface::roughness`].
    pub rz: f64,
    /// Mean of z − y_n (m): positive when material was left above the nominal surface.
    pub mean_deviation: f64,
    /// Highest and lowest deviation z − y_n (m).
    pub max_deviation: f64,
    pub min_deviation: f64,
    /// Bin centres and deviations z − y_n (m).
    pub profile: Vec<[f64; 2]>,
    /// Roughness on the mean line (absent in files written before it: see
    /// [`Surface::roughness`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_line: Option<Roughness>,
}

/// Roughness of a profile on its mean line (ISO 4287; module docs), in metres.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Roughness {
    /// Arithmetic mean deviation Ra = mean |p| (m).
    pub ra: f64,
    /// Root-mean-square deviation Rq = √(mean p²) (m).
    pub rq: f64,
    /// Peak-to-valley height Rz = max p − min p over the evaluated length (m).
    pub rz: f64,
    /// Slope of the mean line (m/m): a tilted machined surface.
    pub slope: f64,
}

impl Roughness {
    /// The roughness of deviations `profile` (x, e) about their least-squares line; `None`
    /// for an empty profile.
    pub fn of(profile: &[[f64; 2]]) -> Option<Roughness> {
        let n = profile.len() as f64;
        if profile.is_empty() {
            return None;
        }
        let xm = profile.iter().map(|p| p[0]).sum::<f64>() / n;
        let em = profile.iter().map(|p| p[1]).sum::<f64>() / n;
        let sxx: f64 = profile.iter().map(|p| (p[0] - xm) * (p[0] - xm)).sum();
        let sxe: f64 = profile.iter().map(|p| (p[0] - xm) * (p[1] - em)).sum();
        let slope = if sxx > 0.0 { sxe / sxx } else { 0.0 };
        let p: Vec<f64> = profile
            .iter()
            .map(|q| q[1] - em - slope * (q[0] - xm))
            .collect();
        let max = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = p.iter().copied().fold(f64::INFINITY, f64::min);
        Some(Roughness {
            ra: p.iter().map(|v| v.abs()).sum::<f64>() / n,
            rq: (p.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
            rz: max - min,
            slope,
        })
    }
}

impl Surface {
    /// Ra, Rq, Rz on the mean line: as stored, or from the profile for a file written before.
    pub fn roughness(&self) -> Option<Roughness> {
        self.mean_line.or_else(|| Roughness::of(&self.profile))
    }
}

/// Upper envelope of discs `(x, y, r)` in bins of width ≈ `bin` over `[x_from, x_to]` (the
/// count is rounded so the bins tile the interval exactly). A bin no disc reaches gets
/// `floor`. Returns bin centres and heights.
pub fn envelope(
    discs: impl Iterator<Item = [f64; 3]> + Clone,
    x_from: f64,
    x_to: f64,
    bin: f64,
    floor: f64,
) -> Vec<[f64; 2]> {
    if !(x_to > x_from && bin > 0.0) {
        return Vec::new();
    }
    let n = ((x_to - x_from) / bin).round().max(1.0) as usize;
    let w = (x_to - x_from) / n as f64;
    let mut z = vec![floor; n];
    for [x, y, r] in discs {
        // Bins the disc's x-range [x − r, x + r] touches.
        let lo = (((x - r - x_from) / w).floor().max(0.0)) as usize;
        let hi = ((x + r - x_from) / w).floor();
        if hi < 0.0 || lo >= n {
            continue;
        }
        let hi = (hi as usize).min(n - 1);
        for (b, zb) in z.iter_mut().enumerate().take(hi + 1).skip(lo) {
            let (a, c) = (x_from + b as f64 * w, x_from + (b + 1) as f64 * w);
            let d = if x < a {
                a - x
            } else if x > c {
                x - c
            } else {
                0.0
            };
            if d < r {
                *zb = zb.max(y + (r * r - d * d).sqrt());
            }
        }
    }
    z.iter()
        .enumerate()
        .map(|(b, &h)| [x_from + (b as f64 + 0.5) * w, h])
        .collect()
}

/// Roughness of the envelope of `discs` over `[x_from, x_to]` relative to `nominal_y`;
/// `floor` is the height of a bin no disc reaches (e.g. the slot bottom).
pub fn measure(
    discs: impl Iterator<Item = [f64; 3]> + Clone,
    x_from: f64,
    x_to: f64,
    bin: f64,
    nominal_y: f64,
    floor: f64,
) -> Option<Surface> {
    let env = envelope(discs, x_from, x_to, bin, floor);
    if env.is_empty() {
        return None;
    }
    let e: Vec<f64> = env.iter().map(|p| p[1] - nominal_y).collect();
    let n = e.len() as f64;
    let max = e.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = e.iter().copied().fold(f64::INFINITY, f64::min);
    let profile: Vec<[f64; 2]> = env.iter().zip(&e).map(|(p, v)| [p[0], *v]).collect();
    Some(Surface {
        nominal_y,
        x_from,
        x_to,
        bin_width: (x_to - x_from) / n,
        ra: e.iter().map(|v| v.abs()).sum::<f64>() / n,
        rz: max - min,
        mean_deviation: e.iter().sum::<f64>() / n,
        max_deviation: max,
        min_deviation: min,
        mean_line: Roughness::of(&profile),
        profile,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn envelope_of_a_row_of_discs() {
        // Discs of radius 1 at x = 0, 2, 4, ..., 10, all at y = 0; bins [2k, 2k + 2] over
        // [0, 10] each hold two disc centres (on their ends): top = 1 everywhere.
        let discs: Vec<[f64; 3]> = (0..6).map(|k| [2.0 * k as f64, 0.0, 1.0]).collect();
        let env = envelope(discs.iter().copied(), 0.0, 10.0, 2.0, -5.0);
        assert_eq!(env.len(), 5);
        for p in &env {
            assert!((p[1] - 1.0).abs() < 1e-15);
        }
        // Narrow bins between centres: bin [0.5, 1.5] sees disc 0 at d = 0.5 and disc 1 (x = 2)
        // at d = 0.5: √(1 − 0.25).
        let env = envelope(discs.iter().copied(), 0.5, 1.5, 1.0, -5.0);
        assert_eq!(env.len(), 1);
        assert!((env[0][1] - 0.75f64.sqrt()).abs() < 1e-15);
        // A bin no disc reaches gets the floor.
        let env = envelope(discs.iter().copied(), 20.0, 21.0, 1.0, -5.0);
        assert_eq!(env[0][1], -5.0);
    }

    #[test]
    fn roughness_of_a_step_profile() {
        // Left half at height 1 (discs r = 0.5 at y = 0.5), right half at height 2: bins of 1
        // over [0, 4], nominal 1: deviations 0, 0, 1, 1.
        let mut discs = vec![];
        for k in 0..4 {
            let x = 0.5 + k as f64;
            let y = if k < 2 { 0.5 } else { 1.5 };
            discs.push([x, y, 0.5]);
        }
        // Bins [0,1],[1,2],[2,3],[3,4]: each disc lies in its own bin and only touches the
        // neighbour bins' edges (d = r, height y, below their own discs' tops).
        let s = measure(discs.iter().copied(), 0.0, 4.0, 1.0, 1.0, 0.0).unwrap();
        let dev: Vec<f64> = s.profile.iter().map(|p| p[1]).collect();
        assert_eq!(dev, vec![0.0, 0.0, 1.0, 1.0]);
        assert!((s.ra - 0.5).abs() < 1e-15);
        assert!((s.rz - 1.0).abs() < 1e-15);
        assert!((s.mean_deviation - 0.5).abs() < 1e-15);
        assert_eq!((s.max_deviation, s.min_deviation), (1.0, 0.0));
        assert!(measure(discs.iter().copied(), 1.0, 1.0, 1.0, 0.0, 0.0).is_none());
        // On the mean line: the least-squares line through (0.5, 0), (1.5, 0), (2.5, 1),
        // (3.5, 1) has slope 0.4 and passes through (2, 0.5); residuals −0.1, 0.3, −0.3, 0.1.
        let m = s.mean_line.unwrap();
        assert!((m.slope - 0.4).abs() < 1e-15);
        assert!((m.ra - 0.2).abs() < 1e-15, "{m:?}");
        assert!((m.rq - 0.05f64.sqrt()).abs() < 1e-15);
        assert!((m.rz - 0.6).abs() < 1e-15);
        assert_eq!(s.roughness(), Some(m));
    }

    /// Issue 48: a flat surface cut 0.25 mm too deep has Ra 250 µm from the nominal line but
    /// none on its mean line; the depth is its own figure. A file without `mean_line` (written
    /// before) gets it from its profile.
    #[test]
    fn a_uniform_undercut_is_depth_not_roughness() {
        let discs: Vec<[f64; 3]> = (0..11).map(|k| [k as f64, -0.25, 0.5]).collect();
        let s = measure(discs.iter().copied(), 0.0, 10.0, 1.0, 0.5, -5.0).unwrap();
        assert!(
            (s.mean_deviation + 0.25).abs() < 1e-12,
            "{}",
            s.mean_deviation
        );
        assert!((s.ra - 0.25).abs() < 1e-12);
        let m = s.roughness().unwrap();
        assert!(m.ra < 1e-12 && m.rz < 1e-12, "{m:?}");
        let mut old = serde_json::to_value(&s).unwrap();
        old.as_object_mut().unwrap().remove("mean_line");
        let old: Surface = serde_json::from_value(old).unwrap();
        assert_eq!(old.mean_line, None);
        assert_eq!(old.roughness(), Some(m));
    }

    /// A tilted straight surface has no roughness on its mean line, only a slope.
    #[test]
    fn a_tilted_line_is_slope_not_roughness() {
        let profile: Vec<[f64; 2]> = (0..10).map(|k| [k as f64, 0.01 * k as f64]).collect();
        let m = Roughness::of(&profile).unwrap();
        assert!((m.slope - 0.01).abs() < 1e-15);
        assert!(m.ra < 1e-15 && m.rz < 1e-15, "{m:?}");
        assert!(Roughness::of(&[]).is_none());
    }
}
