//! Deterministic synthetic grain outlines: random star-shaped polygons with Fourier roughness,
//! Gaussian dents (concavities) and an exact inertia aspect ratio.
//!
//! Construction (in the spirit of the random Fourier-descriptor grains of G. Mollon and
//! J. Zhao, "Fourier–Voronoi-based generation of realistic samples for discrete modelling of
//! granular materials", Granular Matter 14, 621–638, 2012):
//!
//! 1. polar radius r(θ) = r_e(θ) · max(0.15, (1 + Σ_{k=3}^{K} a_k cos(kθ + φ_k)) ·
//!    Π_d (1 − δ_d exp(−((θ−θ_d)/w_d)²))), where r_e is the radius of an ellipse of semi-axes
//!    √AR and 1/√AR; K = min(n/4, 32); random phases φ_k; amplitudes a_k = g_k k^(−1.8)
//!    (g_k standard normal) rescaled so that the RMS of the series, √(Σ a_k²/2), equals
//!    `roughness`; 1 to 3 dents of depth δ_d = concavity·U(0.5, 1), half-width
//!    w_d = U(0.25, 0.6) rad at uniform random angles θ_d;
//! 2. sample it finely (16 n points at equal angles from a random start angle), then
//!    [`resample`] to n points equally spaced along the perimeter. These points lie on a
//!    star-shaped outline (positive radius) in angular order, so the polygon through them is
//!    star-shaped about the origin, hence simple;
//! 3. rotate into the principal frame, scale the axes so the second moments of area are in the
//!    ratio `aspect_ratio`² (then √(i_max/i_min) = aspect_ratio exactly; the ellipse base
//!    makes this a small correction), rotate by a random angle: an affine map, which keeps
//!    the polygon simple and counter-clockwise;
//! 4. scale about the centroid to area π·mean_radius² and put the centroid at the origin.
//!
//! The generator is SplitMix64 (G. Steele, D. Lea, C. Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014; constants as in Java's `SplittableRandom`), so a seed gives
//! the same polygon on every run. Across platforms the last bits may differ, since `sin`,
//! `cos`, `exp` and `powf` of the platform's math library are not correctly rounded.

use serde::{Deserialize, Serialize};

use crate::outline::resample;
use crate::props::polygon_props;

/// Decay exponent β of the Fourier amplitudes, a_k ∝ k^(−β).
const SPECTRAL_EXPONENT: f64 = 1.8;
/// Lower bound of the perturbation factor, so radii stay positive.
const MIN_RELATIVE_RADIUS: f64 = 0.15;

/// Parameters of [`synth_grain`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SynthParams {
    /// Equivalent radius of the result (m, or any length unit): area = π mean_radius².
    pub mean_radius: f64,
    /// Inertia aspect ratio √(i_max/i_min) of the result; values below 1 (or non-finite)
    /// are taken as 1.
    pub aspect_ratio: f64,
    /// RMS relative amplitude of the radial Fourier perturbation (harmonics 3..K); 0.02–0.05
    /// looks like a worn grain, 0.08–0.12 like a rough, irregular one.
    pub roughness: f64,
    /// Depth of the 1–3 Gaussian dents as a fraction of the radius (0 = none; 0.3–0.6 gives
    /// clear concavities, solidity ≈ 0.85–0.95).
    pub concavity: f64,
    /// Number of vertices (at least 8 are used).
    pub n_points: usize,
}

/// SplitMix64 pseudo-random generator (see module docs).
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }

    /// Standard normal (Box–Muller, one value per call).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

/// A random simple counter-clockwise polygon with centroid at the origin; see module docs.
/// Deterministic for a given `seed` and parameters.
pub fn synth_grain(seed: u64, p: &SynthParams) -> Vec<[f64; 2]> {
    use std::f64::consts::PI;
    let n = p.n_points.max(8);
    let ar = if p.aspect_ratio.is_finite() && p.aspect_ratio > 1.0 {
        p.aspect_ratio
    } else {
        1.0
    };
    let mut rng = SplitMix64::new(seed);
    let phase0 = rng.range(0.0, 2.0 * PI);

    // Fourier roughness.
    let kmax = (n / 4).clamp(3, 32);
    let mut harm: Vec<(f64, f64, f64)> = (3..=kmax)
        .map(|k| {
            let k = k as f64;
            (
                k,
                rng.normal() * k.powf(-SPECTRAL_EXPONENT),
                rng.range(0.0, 2.0 * PI),
            )
        })
        .collect();
    let power: f64 = harm.iter().map(|h| 0.5 * h.1 * h.1).sum();
    if power > 0.0 {
        let f = p.roughness.max(0.0) / power.sqrt();
        for h in &mut harm {
            h.1 *= f;
        }
    }
    // Dents.
    let n_dents = 1 + (rng.uniform() * 3.0) as usize;
    let dents: Vec<(f64, f64, f64)> = (0..n_dents)
        .map(|_| {
            (
                rng.range(0.0, 2.0 * PI),
                p.concavity.max(0.0) * rng.range(0.5, 1.0),
                rng.range(0.25, 0.6),
            )
        })
        .collect();
    let final_rot = rng.range(-PI, PI);

    // Fine star-shaped polygon around an ellipse of the requested aspect ratio.
    let (ea, eb) = (ar.sqrt(), 1.0 / ar.sqrt());
    let m = 16 * n;
    let fine: Vec<[f64; 2]> = (0..m)
        .map(|i| {
            let t = phase0 + 2.0 * PI * i as f64 / m as f64;
            let (c, s) = (t.cos(), t.sin());
            let r_ell = 1.0 / ((c / ea).powi(2) + (s / eb).powi(2)).sqrt();
            let mut f = 1.0;
            for &(k, a, ph) in &harm {
                f += a * (k * t + ph).cos();
            }
            for &(dc, depth, w) in &dents {
                let d = (t - dc + PI).rem_euclid(2.0 * PI) - PI;
                f *= 1.0 - depth * (-(d / w) * (d / w)).exp();
            }
            let r = r_ell * f.max(MIN_RELATIVE_RADIUS);
            [r * c, r * s]
        })
        .collect();
    // Equal spacing along the perimeter. The samples lie on the star-shaped fine outline in
    // angular order, so the polygon through them is star-shaped too, hence simple.
    let pts = resample(&fine, n);

    // Affine correction to the exact aspect ratio, and a random orientation.
    let pr = polygon_props(&pts);
    let (c, s) = (pr.principal_angle.cos(), pr.principal_angle.sin());
    // Principal frame: u along the long axis, spread ∫u² = i_max, ∫v² = i_min.
    let fu = ar.sqrt() / pr.i_max.sqrt();
    let fv = 1.0 / (ar.sqrt() * pr.i_min.sqrt());
    let (cr, sr) = (final_rot.cos(), final_rot.sin());
    let mapped: Vec<[f64; 2]> = pts
        .iter()
        .map(|q| {
            let (x, y) = (q[0] - pr.centroid[0], q[1] - pr.centroid[1]);
            let u = (c * x + s * y) * fu;
            let v = (-s * x + c * y) * fv;
            [cr * u - sr * v, sr * u + cr * v]
        })
        .collect();
    let area = std::f64::consts::PI * p.mean_radius * p.mean_radius;
    let scaled = scale_to_area(&mapped, area);
    let cen = polygon_props(&scaled).centroid;
    scaled
        .iter()
        .map(|q| [q[0] - cen[0], q[1] - cen[1]])
        .collect()
}

/// Scale `points` about their area centroid so that the enclosed area becomes `area`
/// (uniform scale factor √(area/A)). A polygon of zero area is returned unchanged.
pub fn scale_to_area(points: &[[f64; 2]], area: f64) -> Vec<[f64; 2]> {
    let pr = polygon_props(points);
    if pr.area <= 0.0 || area.is_nan() || area < 0.0 {
        return points.to_vec();
    }
    let f = (area / pr.area).sqrt();
    let c = pr.centroid;
    points
        .iter()
        .map(|q| [c[0] + f * (q[0] - c[0]), c[1] + f * (q[1] - c[1])])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_reference_values() {
        // First outputs for seed 0 (reference implementation by S. Vigna, splitmix64.c).
        let mut r = SplitMix64::new(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        let mut r = SplitMix64::new(7);
        for _ in 0..1000 {
            let u = r.uniform();
            assert!((0.0..1.0).contains(&u));
        }
    }

    #[test]
    fn scale_to_area_keeps_centroid() {
        let sq = [[1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]];
        let s = scale_to_area(&sq, 16.0);
        let p = polygon_props(&s);
        assert!((p.area - 16.0).abs() < 1e-12);
        assert!((p.centroid[0] - 2.0).abs() < 1e-12 && (p.centroid[1] - 2.0).abs() < 1e-12);
    }
}
