//! The machined surface of a cut specimen: the upper envelope of the workpiece's discs in bins
//! along the cut, and its roughness relative to the nominal machined surface (the specimen top
//! minus the depth of cut).
//!
//! Profile: in bin `[a, b]` the height z is the highest point of any workpiece disc over that
//! interval (a disc centred at x with radius r reaches y + r if a ≤ x ≤ b, else
//! y + √(r² − d²) at the bin end nearest to it, d < r the distance). Roughness, with
//! e_b = z_b − y_n the deviation from the nominal surface y_n (ISO 4287 definitions applied to
//! the binned profile, measured from the nominal line instead of the mean line, so a uniform
//! over- or under-cut shows up):
//! Ra = mean |e_b|, Rz = max e_b − min e_b (peak-to-valley over the evaluated length, i.e.
//! ISO's Rt; with one sampling length Rz and Rt coincide), mean deviation = mean e_b.

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
    /// Arithmetic mean deviation Ra = mean |z − y_n| (m).
    pub ra: f64,
    /// Peak-to-valley height Rz = max(z) − min(z) (m).
    pub rz: f64,
    /// Mean of z − y_n (m): positive when material was left above the nominal surface.
    pub mean_deviation: f64,
    /// Highest and lowest deviation z − y_n (m).
    pub max_deviation: f64,
    pub min_deviation: f64,
    /// Bin centres and deviations z − y_n (m).
    pub profile: Vec<[f64; 2]>,
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
        profile: env.iter().zip(&e).map(|(p, v)| [p[0], *v]).collect(),
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
    }
}
