//! Analyses of virtual lab tests: each reads the histories a test writes and returns the
//! macroscopic property with the formula of the standard test. Pure functions on slices, so they
//! apply equally to simulated and measured curves.

pub mod force_stats;

/// Least-squares slope and intercept of `y` against `x` (ordinary linear regression).
/// Returns `None` for fewer than two distinct `x`.
pub fn linear_fit(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len().min(y.len());
    if n < 2 {
        return None;
    }
    let mx = x[..n].iter().sum::<f64>() / n as f64;
    let my = y[..n].iter().sum::<f64>() / n as f64;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for i in 0..n {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
    }
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, my - slope * mx))
}

/// Index and value of the largest element (the first one on ties); `None` when empty or all NaN.
pub fn peak(v: &[f64]) -> Option<(usize, f64)> {
    v.iter()
        .copied()
        .enumerate()
        .filter(|(_, x)| x.is_finite())
        .fold(None, |best: Option<(usize, f64)>, (i, x)| match best {
            Some((_, b)) if b >= x => best,
            _ => Some((i, x)),
        })
}

/// Indices of the pre-peak points whose stress lies between `lo` and `hi` times the peak: the
/// "linear part" of a loading curve (ISRM practice takes the tangent or secant modulus around
/// 50 % of the peak; we fit a line over a band such as 10–50 %).
pub fn prepeak_band(stress: &[f64], lo: f64, hi: f64) -> Vec<usize> {
    let Some((ip, sp)) = peak(stress) else {
        return vec![];
    };
    (0..=ip)
        .filter(|&i| stress[i] >= lo * sp && stress[i] <= hi * sp)
        .collect()
}

/// Results of a uniaxial compression test.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct UcsResult {
    /// Young's modulus (Pa): slope of axial stress against axial strain over the band.
    pub young: f64,
    /// Poisson's ratio: −(lateral strain)/(axial strain), slope over the same band.
    pub poisson: f64,
    /// Uniaxial compressive strength (Pa): the peak axial stress.
    pub ucs: f64,
}

/// E, ν and UCS from a compression history (compression positive for stress and axial strain;
/// lateral strain positive in extension). The linear part is the pre-peak band `[lo, hi]` of the
/// peak stress.
pub fn uniaxial_compression(
    axial_strain: &[f64],
    lateral_strain: &[f64],
    stress: &[f64],
    lo: f64,
    hi: f64,
) -> Option<UcsResult> {
    let (_, ucs) = peak(stress)?;
    let band = prepeak_band(stress, lo, hi);
    let ea: Vec<f64> = band.iter().map(|&i| axial_strain[i]).collect();
    let el: Vec<f64> = band.iter().map(|&i| lateral_strain[i]).collect();
    let s: Vec<f64> = band.iter().map(|&i| stress[i]).collect();
    let (young, _) = linear_fit(&ea, &s)?;
    let (nu, _) = linear_fit(&ea, &el)?;
    Some(UcsResult {
        young,
        poisson: nu,
        ucs,
    })
}

/// The Mohr–Coulomb envelope fitted to peak strengths at several confinements.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MohrCoulomb {
    /// Friction angle φ (degrees) and cohesion c (Pa).
    pub friction_angle_deg: f64,
    pub cohesion: f64,
    /// The fitted line σ1 = intercept + slope σ3: slope = (1 + sin φ)/(1 − sin φ) (the
    /// passive coefficient), intercept = 2c cos φ/(1 − sin φ) (the envelope's UCS).
    pub slope: f64,
    pub intercept: f64,
    /// Coefficient of determination of the line (1 for two points).
    pub r2: f64,
}

/// Friction angle and cohesion from peak strengths `(σ3, σ1)` (Pa, compression positive) at
/// two or more distinct confinements: the least-squares line σ1 = a + q σ3 and
/// sin φ = (q − 1)/(q + 1), c = a (1 − sin φ)/(2 cos φ) (Jaeger, Cook & Zimmerman 2007,
/// "Fundamentals of Rock Mechanics", 4th ed., §4.5; Potyondy & Cundall 2004 §3 derive φ and c
/// of the bonded-particle model this way from biaxial tests). `None` for fewer than two
/// distinct σ3 or a slope q ≤ 1 (no friction: strength falling with confinement).
pub fn mohr_coulomb(points: &[(f64, f64)]) -> Option<MohrCoulomb> {
    let s3: Vec<f64> = points.iter().map(|p| p.0).collect();
    let s1: Vec<f64> = points.iter().map(|p| p.1).collect();
    let (q, a) = linear_fit(&s3, &s1)?;
    if q.is_nan() || q <= 1.0 {
        return None;
    }
    let sin = (q - 1.0) / (q + 1.0);
    let phi = sin.asin();
    let mean = s1.iter().sum::<f64>() / s1.len() as f64;
    let (ss_res, ss_tot) = points.iter().fold((0.0, 0.0), |(r, t), &(x, y)| {
        (r + (y - a - q * x).powi(2), t + (y - mean).powi(2))
    });
    Some(MohrCoulomb {
        friction_angle_deg: phi.to_degrees(),
        cohesion: a * (1.0 - sin) / (2.0 * phi.cos()),
        slope: q,
        intercept: a,
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            1.0
        },
    })
}

/// Brazilian (indirect tensile) strength of a disc of diameter `d` and thickness `t` failing at
/// load `f`: σ_t = 2F/(πDt) (ISRM 1978 suggested method; S4).
pub fn brazilian_strength(f: f64, d: f64, t: f64) -> f64 {
    2.0 * f / (std::f64::consts::PI * d * t)
}

/// Flexural strength of a beam in three-point bending, span `l`, width `b`, height `h`, peak load
/// `f`: σ_f = 3FL/(2bh²) (ASTM C1161; S4).
pub fn flexural_strength(f: f64, l: f64, b: f64, h: f64) -> f64 {
    3.0 * f * l / (2.0 * b * h * h)
}

/// Fracture toughness of a bonded-particle material from its bond tensile strength `sigma_c` and
/// mean particle radius `r`: K_IC = β σ̄_c √(πR) (S4, after Potyondy & Cundall 2004 §3.3).
pub fn fracture_toughness(beta: f64, sigma_c: f64, r: f64) -> f64 {
    beta * sigma_c * (std::f64::consts::PI * r).sqrt()
}

/// Geometry factor f(a/W) of the single-edge-notched beam in three-point bending with span
/// S = 4W (ASTM E399 SE(B), after Srawley 1976, Int. J. Fract. 12, 475; within 0.5 % over
/// 0 ≤ a/W ≤ 1): f(x) = 3√x [1.99 − x(1 − x)(2.15 − 3.93x + 2.7x²)] / [2(1 + 2x)(1 − x)^{3/2}].
pub fn senb_geometry_factor(x: f64) -> f64 {
    let poly = 1.99 - x * (1.0 - x) * (2.15 - 3.93 * x + 2.7 * x * x);
    3.0 * x.sqrt() * poly / (2.0 * (1.0 + 2.0 * x) * (1.0 - x).powf(1.5))
}

/// Fracture toughness from a single-edge-notched beam test (ASTM E399 SE(B), S = 4W): peak
/// load `p`, span `s`, thickness `b`, beam depth `w`, notch depth `a`:
/// K_IC = P S / (B W^{3/2}) · f(a/W) ([`senb_geometry_factor`]).
pub fn senb_toughness(p: f64, s: f64, b: f64, w: f64, a: f64) -> f64 {
    p * s / (b * w.powf(1.5)) * senb_geometry_factor(a / w)
}

/// Peak, mean and standard deviation of a force history over a window.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ForceStats {
    pub peak: f64,
    pub mean: f64,
    pub sd: f64,
    /// Samples in the window.
    pub samples: usize,
}

/// Statistics of `force` over the samples whose abscissa (time or tool travel) lies in
/// `[from, to]`; the steady part of a cut excludes the tool's entry (typically the first depth of
/// cut of travel). `None` when the window holds no sample.
pub fn force_stats(abscissa: &[f64], force: &[f64], from: f64, to: f64) -> Option<ForceStats> {
    let w: Vec<f64> = abscissa
        .iter()
        .zip(force)
        .filter(|(x, _)| **x >= from && **x <= to)
        .map(|(_, f)| *f)
        .collect();
    if w.is_empty() {
        return None;
    }
    let n = w.len() as f64;
    let mean = w.iter().sum::<f64>() / n;
    let var = w.iter().map(|f| (f - mean) * (f - mean)).sum::<f64>() / n;
    Some(ForceStats {
        peak: peak(&w)?.1,
        mean,
        sd: var.sqrt(),
        samples: w.len(),
    })
}

/// Largest mean of `force` over a stretch of `width` of the abscissa (a moving average of
/// width `width`), over the stretches that lie wholly inside `[from, to]`; each stretch starts
/// at a sample and holds the samples in `[x, x + width]`. A measured force peak depends on how
/// the force is filtered: the largest single sample of a DEM force history is one contact
/// event, while the force averaged over the time the tool takes to advance by one grain is the
/// load that breaks off material. `None` when no stretch fits or `width` is not positive.
///
/// ```
/// use dem_lab::analysis::moving_mean_peak;
/// let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
/// let f = [0.0, 0.0, 9.0, 3.0, 0.0, 0.0];
/// assert_eq!(moving_mean_peak(&x, &f, 0.0, 5.0, 0.0), None);
/// assert_eq!(moving_mean_peak(&x, &f, 0.0, 5.0, 1.0), Some(6.0)); // samples 2 and 3
/// assert_eq!(moving_mean_peak(&x, &f, 0.0, 5.0, 2.0), Some(4.0)); // samples 1..=3 or 2..=4
/// ```
pub fn moving_mean_peak(
    abscissa: &[f64],
    force: &[f64],
    from: f64,
    to: f64,
    width: f64,
) -> Option<f64> {
    if width.is_nan() || width <= 0.0 {
        return None;
    }
    let pts: Vec<(f64, f64)> = abscissa
        .iter()
        .zip(force)
        .filter(|(x, _)| **x >= from && **x <= to)
        .map(|(x, f)| (*x, *f))
        .collect();
    let mut best: Option<f64> = None;
    let (mut end, mut sum) = (0usize, 0.0f64);
    for start in 0..pts.len() {
        let x0 = pts[start].0;
        if x0 + width > to {
            break;
        }
        end = end.max(start);
        while end < pts.len() && pts[end].0 <= x0 + width {
            sum += pts[end].1;
            end += 1;
        }
        let m = sum / (end - start) as f64;
        best = Some(best.map_or(m, |b| b.max(m)));
        sum -= pts[start].1;
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Strengths on an exact Mohr–Coulomb line give back φ and c; the envelope's intercept is
    /// its UCS 2c cos φ/(1 − sin φ).
    #[test]
    fn mohr_coulomb_recovers_the_friction_angle_and_cohesion() {
        for (phi_deg, c) in [(30.0_f64, 10e6), (52.0, 230e6), (5.0, 1e6)] {
            let phi = phi_deg.to_radians();
            let q = (1.0 + phi.sin()) / (1.0 - phi.sin());
            let ucs = 2.0 * c * phi.cos() / (1.0 - phi.sin());
            let pts: Vec<(f64, f64)> = [0.0, 20e6, 50e6, 100e6]
                .iter()
                .map(|&s3| (s3, ucs + q * s3))
                .collect();
            let m = mohr_coulomb(&pts).unwrap();
            assert!((m.friction_angle_deg - phi_deg).abs() < 1e-9, "{m:?}");
            assert!((m.cohesion / c - 1.0).abs() < 1e-9, "{m:?}");
            assert!((m.intercept / ucs - 1.0).abs() < 1e-9 && (m.r2 - 1.0).abs() < 1e-12);
            // Two points are enough.
            let m2 = mohr_coulomb(&pts[1..3]).unwrap();
            assert!((m2.friction_angle_deg - phi_deg).abs() < 1e-9, "{m2:?}");
        }
        // Strength falling with confinement, or one confinement only: no envelope.
        assert!(mohr_coulomb(&[(0.0, 100e6), (50e6, 90e6)]).is_none());
        assert!(mohr_coulomb(&[(10e6, 100e6), (10e6, 120e6)]).is_none());
        assert!(mohr_coulomb(&[(10e6, 100e6)]).is_none());
    }

    #[test]
    #[allow(clippy::approx_constant)] // 3.14 is E399's tabulated f(0.55), not π
    fn senb_factor_matches_astm_e399_table() {
        // ASTM E399 tabulates f(a/W) for SE(B) with S/W = 4: 0.45 → 2.29, 0.50 → 2.66,
        // 0.55 → 3.14 (three figures).
        for (x, f) in [(0.45, 2.29), (0.50, 2.66), (0.55, 3.14)] {
            let g = senb_geometry_factor(x);
            assert!((g - f).abs() < 0.006, "f({x}) = {g}, table {f}");
        }
        // K = P S f / (B W^1.5): 1 kN on a 20 mm span, 1 m thick, 5 mm deep, a/W = 0.5.
        let k = senb_toughness(1e3, 20e-3, 1.0, 5e-3, 2.5e-3);
        let want = 1e3 * 20e-3 / (5e-3f64).powf(1.5) * senb_geometry_factor(0.5);
        assert!((k - want).abs() < 1e-9 * want);
        assert!((k / 1e6 - 0.1506).abs() < 1e-3, "{k}"); // ≈ 0.1506 MPa·m^½
    }

    #[test]
    fn linear_fit_recovers_a_line() {
        let x: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| 3.0 * v - 2.0).collect();
        let (a, b) = linear_fit(&x, &y).unwrap();
        assert!((a - 3.0).abs() < 1e-12 && (b + 2.0).abs() < 1e-12);
        assert!(linear_fit(&[1.0, 1.0], &[0.0, 1.0]).is_none());
    }

    #[test]
    fn ucs_of_an_elastic_softening_curve() {
        // Linear to 100 MPa at E = 50 GPa and ν = 0.25, then softening.
        let (e, nu) = (50e9, 0.25);
        let mut ea = vec![];
        let mut el = vec![];
        let mut s = vec![];
        for i in 0..=300 {
            let eps = i as f64 * 1e-5;
            let sig = if eps <= 2e-3 {
                e * eps
            } else {
                100e6 - 20e9 * (eps - 2e-3)
            };
            ea.push(eps);
            el.push(nu * eps);
            s.push(sig);
        }
        let r = uniaxial_compression(&ea, &el, &s, 0.1, 0.5).unwrap();
        assert!((r.young / e - 1.0).abs() < 1e-9);
        assert!((r.poisson - nu).abs() < 1e-9);
        assert!((r.ucs - 100e6).abs() < 1e-3);
    }

    #[test]
    fn standard_formulas() {
        assert!((brazilian_strength(PI, 2.0, 0.5) - 2.0).abs() < 1e-15);
        // 3·F·L/(2·b·h²) with F = 2, L = 3, b = 1, h = 1: 9.
        assert!((flexural_strength(2.0, 3.0, 1.0, 1.0) - 9.0).abs() < 1e-15);
        assert!((fracture_toughness(1.0, 1.0, 1.0 / PI) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn moving_mean_peak_of_a_spike_and_a_plateau() {
        // Travel in mm at 0.25 mm spacing (exact in binary); one spike of 1 MN on 10 kN.
        let x: Vec<f64> = (0..4001).map(|i| i as f64 * 0.25).collect();
        let mut f = vec![1e4; x.len()];
        f[2000] = 1e6;
        // Raw peak: the spike. Averaged over 10 mm (41 samples): the spike shares its window.
        let raw = force_stats(&x, &f, 0.0, 1000.0).unwrap().peak;
        assert_eq!(raw, 1e6);
        let avg = moving_mean_peak(&x, &f, 0.0, 1000.0, 10.0).unwrap();
        let expect = 1e4 + (1e6 - 1e4) / 41.0;
        assert!((avg / expect - 1.0).abs() < 1e-12, "{avg} vs {expect}");
        // A window wider than the range has no full stretch; a constant force is itself.
        assert_eq!(moving_mean_peak(&x, &f, 0.0, 1000.0, 2000.0), None);
        let c = vec![5.0; x.len()];
        let m = moving_mean_peak(&x, &c, 200.0, 1000.0, 86.0).unwrap();
        assert!((m - 5.0).abs() < 1e-12);
        // Only stretches inside [from, to]: the spike before `from` is not seen.
        let m = moving_mean_peak(&x, &f, 600.0, 1000.0, 10.0).unwrap();
        assert!((m - 1e4).abs() < 1e-6);
    }

    #[test]
    fn force_stats_over_a_window() {
        let x: Vec<f64> = (0..100).map(|i| i as f64).collect();
        let f: Vec<f64> = x
            .iter()
            .map(|v| {
                if *v < 10.0 {
                    100.0
                } else {
                    5.0 + (*v as i64 % 2) as f64
                }
            })
            .collect();
        let s = force_stats(&x, &f, 10.0, 99.0).unwrap();
        assert_eq!(s.samples, 90);
        assert_eq!(s.peak, 6.0);
        assert!((s.mean - 5.5).abs() < 1e-12 && (s.sd - 0.5).abs() < 1e-12);
        assert!(force_stats(&x, &f, 200.0, 300.0).is_none());
    }
}
