//! Weibull statistics of grain strengths and the size effect (crushable grains, issue 25).
//!
//! **Weibull fit** (Weibull 1951, "A statistical distribution function of wide applicability",
//! J. Appl. Mech. 18:293-297): the survival probability of a grain at stress σ is
//! `P_s = exp(−(σ/σ0)^m)`, so the failure probability `P = 1 − P_s` gives
//! `ln(−ln(1 − P)) = m ln σ − m ln σ0`. The n strengths sorted ascending get the median-rank-like
//! estimator `P_i = (i − 0.5)/n` (i = 1..n; the usual choice for grain crushing, e.g. McDowell &
//! Amon 2000), and m and σ0 follow from the least-squares line of `y_i = ln(−ln(1 − P_i))` on
//! `x_i = ln σ_i`: m the slope, σ0 = exp(−intercept/m) (the characteristic strength, P = 63.2 %).
//!
//! **Size effect**: a power law `σ0(d) = A·d^b` fitted by least squares on
//! `ln σ0 = ln A + b ln d`. Weibull's weakest link gives b = −2/m for a 2D grain of area ∝ d²
//! (−3/m in 3D); linear elastic fracture with a fixed fracture energy G_c gives
//! σ ∝ √(E G_c/d), b = −1/2, for geometrically similar grains (e.g. Bažant & Planas 1998).

use serde::{Deserialize, Serialize};

/// A straight line y = a + b x by least squares, with its coefficient of determination.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Line {
    pub intercept: f64,
    pub slope: f64,
    pub r2: f64,
}

/// Least squares of y on x; `None` for fewer than two points, non-finite values or all x equal.
pub fn line_fit(x: &[f64], y: &[f64]) -> Option<Line> {
    let n = x.len();
    if n < 2 || y.len() != n || !x.iter().chain(y).all(|v| v.is_finite()) {
        return None;
    }
    let nf = n as f64;
    let (mx, my) = (x.iter().sum::<f64>() / nf, y.iter().sum::<f64>() / nf);
    let sxx: f64 = x.iter().map(|v| (v - mx) * (v - mx)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let syy: f64 = y.iter().map(|v| (v - my) * (v - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    Some(Line {
        intercept: my - slope * mx,
        slope,
        r2,
    })
}

/// A Weibull fit of strengths.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WeibullFit {
    /// Weibull modulus m.
    pub modulus: f64,
    /// Characteristic strength σ0 (same unit as the strengths), P(σ0) = 1 − 1/e.
    pub sigma0: f64,
    /// R² of the regression line.
    pub r2: f64,
    pub n: usize,
}

/// The failure probabilities P_i = (i − 0.5)/n of the sorted sample (module docs).
pub fn ranks(n: usize) -> Vec<f64> {
    (1..=n).map(|i| (i as f64 - 0.5) / n as f64).collect()
}

/// Fits m and σ0 (module docs). `None` for fewer than two strengths, a strength that is not
/// positive and finite, or all strengths equal.
pub fn weibull_fit(strengths: &[f64]) -> Option<WeibullFit> {
    if strengths.len() < 2 || !strengths.iter().all(|s| s.is_finite() && *s > 0.0) {
        return None;
    }
    let mut s = strengths.to_vec();
    s.sort_by(f64::total_cmp);
    let x: Vec<f64> = s.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = ranks(s.len())
        .iter()
        .map(|p| (-(1.0 - p).ln()).ln())
        .collect();
    let l = line_fit(&x, &y)?;
    if l.slope <= 0.0 {
        return None;
    }
    Some(WeibullFit {
        modulus: l.slope,
        sigma0: (-l.intercept / l.slope).exp(),
        r2: l.r2,
        n: s.len(),
    })
}

/// A power law y = A·x^b.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PowerLaw {
    pub prefactor: f64,
    pub exponent: f64,
    /// R² of the log–log line.
    pub r2: f64,
}

/// Fits y = A·x^b on ln y = ln A + b ln x; `None` unless every value is positive and finite and
/// there are two distinct x.
pub fn power_law_fit(x: &[f64], y: &[f64]) -> Option<PowerLaw> {
    if !x.iter().chain(y).all(|v| v.is_finite() && *v > 0.0) {
        return None;
    }
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let l = line_fit(&lx, &ly)?;
    Some(PowerLaw {
        prefactor: l.intercept.exp(),
        exponent: l.slope,
        r2: l.r2,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Strengths drawn exactly at the Weibull quantiles σ_i = σ0 (−ln(1 − P_i))^(1/m) lie on
    /// the regression line: the fit gives back m and σ0.
    #[test]
    fn quantile_samples_give_back_m_and_sigma0() {
        for (m, s0, n) in [(3.0, 120e6, 29), (10.0, 2.5, 7), (1.5, 1e9, 100)] {
            let mut s: Vec<f64> = ranks(n)
                .iter()
                .map(|p: &f64| s0 * (-(1.0 - p).ln()).powf(1.0 / m))
                .collect();
            s.reverse(); // the fit sorts
            let f = weibull_fit(&s).unwrap();
            assert!((f.modulus - m).abs() <= 1e-9 * m, "{f:?}");
            assert!((f.sigma0 - s0).abs() <= 1e-9 * s0, "{f:?}");
            assert!((f.r2 - 1.0).abs() <= 1e-12);
            assert_eq!(f.n, n);
        }
    }

    #[test]
    fn weibull_refuses_bad_samples() {
        assert!(weibull_fit(&[1.0]).is_none());
        assert!(weibull_fit(&[1.0, 2.0, -1.0]).is_none());
        assert!(weibull_fit(&[1.0, f64::NAN]).is_none());
        assert!(weibull_fit(&[2.0, 2.0, 2.0]).is_none());
    }

    #[test]
    fn power_law_gives_back_the_exponent() {
        let d = [2e-3, 4e-3, 8e-3];
        let y: Vec<f64> = d.iter().map(|x: &f64| 3.0e5 * x.powf(-0.5)).collect();
        let p = power_law_fit(&d, &y).unwrap();
        assert!((p.exponent + 0.5).abs() <= 1e-12, "{p:?}");
        assert!((p.prefactor - 3.0e5).abs() <= 1e-9 * 3.0e5, "{p:?}");
        assert!(power_law_fit(&[1.0, 1.0], &[2.0, 3.0]).is_none());
        assert!(power_law_fit(&[1.0, 2.0], &[0.0, 3.0]).is_none());
        // A scattered line: R² below 1, slope by the closed form.
        let l = line_fit(&[0.0, 1.0, 2.0], &[0.0, 2.0, 1.0]).unwrap();
        assert!((l.slope - 0.5).abs() < 1e-15 && (l.intercept - 0.5).abs() < 1e-15);
        assert!((l.r2 - 0.25).abs() < 1e-15);
    }
}
