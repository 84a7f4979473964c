//! What a speed study finds (issue 19 item 4): per damping variant and specimen method, the
//! mean cutting force of each seed against the tool speed, the exponent n of F ∝ vⁿ, the sign
//! of the 1 → 2 m/s trend, and the quasi-static limit.
//!
//! The criteria, fixed before the full study ran (docs/cutting.md, decision log 2026-11-27):
//! - **independent of v** between two neighbouring speeds v₁ < v₂ when the ratio of the mean
//!   forces F(v₂)/F(v₁) lies in [1/1.25, 1.25] for the seed mean *and* for every seed (a
//!   ±25 % band: the seed-to-seed spread of the window mean is ±20–50 % at 2 seeds, so a
//!   narrower band would call nothing independent);
//! - the **quasi-static limit** is the highest speed v_q such that every neighbouring pair of
//!   speeds up to v_q is independent of v; none if the two lowest speeds already differ;
//! - the **exponent** n is the least-squares slope of ln F against ln v over all speeds, per
//!   seed and for the seed means (n ≈ 0: rate-independent, as a quasi-static cut should be;
//!   n ≈ 1: a force proportional to speed, as from viscous damping or momentum transfer);
//! - the **1 → 2 m/s trend** is F(2)/F(1) per seed: "rises" above 1, "falls" below.

use crate::study_row::Row;
use std::fmt::Write;

/// Ratio band within which two speeds' mean forces count as the same.
pub const SAME_FORCE_BAND: f64 = 1.25;

/// One variant × method × depth: seeds' mean force at each speed.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedSeries {
    pub variant: String,
    pub method: String,
    pub depth_mm: f64,
    /// Speeds, ascending (m/s).
    pub speeds: Vec<f64>,
    /// Seeds, ascending.
    pub seeds: Vec<u64>,
    /// `force[s][k]`: seed `seeds[s]` at `speeds[k]` (N), `None` where the run is missing.
    pub force: Vec<Vec<Option<f64>>>,
    /// Share of the window's samples in which the tool touches something, same layout.
    pub contact: Vec<Vec<Option<f64>>>,
}

impl SpeedSeries {
    /// Seed mean at each speed (over the seeds that ran; `None` if none did).
    pub fn seed_mean(&self) -> Vec<Option<f64>> {
        (0..self.speeds.len())
            .map(|k| {
                let v: Vec<f64> = self.force.iter().filter_map(|f| f[k]).collect();
                (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
            })
            .collect()
    }

    /// Whether the force is independent of v between speeds k and k + 1 (module doc); `None`
    /// when a seed's run is missing at either speed.
    pub fn independent(&self, k: usize) -> Option<bool> {
        let within = |a: f64, b: f64| {
            let r = b / a;
            r.is_finite() && (1.0 / SAME_FORCE_BAND..=SAME_FORCE_BAND).contains(&r)
        };
        let mut all = true;
        for f in &self.force {
            all &= within(f[k]?, f[k + 1]?);
        }
        let m = self.seed_mean();
        Some(all && within(m[k]?, m[k + 1]?))
    }

    /// The quasi-static limit (module doc): `Some(v_q)`, or `None` when the two lowest speeds
    /// already differ (or are missing).
    pub fn quasi_static_limit(&self) -> Option<f64> {
        let mut vq = None;
        for k in 0..self.speeds.len().saturating_sub(1) {
            if self.independent(k) == Some(true) {
                vq = Some(self.speeds[k + 1]);
            } else {
                break;
            }
        }
        vq
    }

    /// Least-squares slope of ln F on ln v over the speeds where `f` is positive.
    pub fn exponent(&self, f: &[Option<f64>]) -> Option<f64> {
        let pts: Vec<(f64, f64)> = self
            .speeds
            .iter()
            .zip(f)
            .filter_map(|(v, f)| f.filter(|f| *f > 0.0).map(|f| (v.ln(), f.ln())))
            .collect();
        if pts.len() < 2 {
            return None;
        }
        let n = pts.len() as f64;
        let (mx, my) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        (sxx > 0.0).then(|| sxy / sxx)
    }

    /// F(2 m/s)/F(1 m/s) per seed, where both ran with a positive mean force (a mean ≤ 0,
    /// a tool pulled more than pushed over the window, has no trend ratio).
    pub fn trend_1_to_2(&self) -> Vec<(u64, f64)> {
        let at = |v: f64| self.speeds.iter().position(|s| *s == v);
        let (Some(a), Some(b)) = (at(1.0), at(2.0)) else {
            return vec![];
        };
        self.seeds
            .iter()
            .zip(&self.force)
            .filter_map(|(s, f)| {
                let (fa, fb) = (f[a]?, f[b]?);
                (fa > 0.0 && fb > 0.0).then_some((*s, fb / fa))
            })
            .collect()
    }
}

/// The series of `rows`, in the order their variant, method and depth first appear.
pub fn series(rows: &[Row]) -> Vec<SpeedSeries> {
    let mut out: Vec<SpeedSeries> = vec![];
    for r in rows {
        let same = |s: &SpeedSeries| {
            s.variant == r.variant && s.method == r.method && s.depth_mm == r.depth_mm
        };
        if !out.iter().any(same) {
            let mine = rows
                .iter()
                .filter(|q| q.variant == r.variant && q.method == r.method)
                .filter(|q| q.depth_mm == r.depth_mm);
            let mut speeds: Vec<f64> = mine.clone().map(|q| q.speed_m_s).collect();
            speeds.sort_by(f64::total_cmp);
            speeds.dedup();
            let mut seeds: Vec<u64> = mine.clone().map(|q| q.seed).collect();
            seeds.sort_unstable();
            seeds.dedup();
            let grid = |f: &dyn Fn(&Row) -> f64| -> Vec<Vec<Option<f64>>> {
                seeds
                    .iter()
                    .map(|s| {
                        speeds
                            .iter()
                            .map(|v| {
                                mine.clone()
                                    .find(|q| q.seed == *s && q.speed_m_s == *v)
                                    .map(f)
                            })
                            .collect()
                    })
                    .collect()
            };
            out.push(SpeedSeries {
                variant: r.variant.clone(),
                method: r.method.clone(),
                depth_mm: r.depth_mm,
                force: grid(&|q| q.mean_n),
                contact: grid(&|q| q.contact_share),
                speeds,
                seeds,
            });
        }
    }
    out
}

/// The findings as Markdown: a table of forces per seed and speed for each series, then one
/// line per series with the exponent, the 1 → 2 m/s trend and the quasi-static limit. A series
/// that lacks one of the study's `planned` speeds gets its table and a line naming the speeds
/// not run yet, but no verdicts: with a speed missing, the speeds either side of it are not
/// neighbours.
pub fn markdown(rows: &[Row], planned: &[f64]) -> String {
    let all = series(rows);
    let mut s = String::from(
        "## Findings: force against speed\n\nCriteria (fixed before the study ran; \
         `validation/src/study_findings.rs`): two neighbouring speeds give *the same force* when \
         the ratio of their mean forces is within ×/÷ 1.25 for the seed mean and for every \
         seed; the *quasi-static limit* is the highest speed up to which every neighbouring \
         pair gives the same force; n is the least-squares slope of ln F against ln v. Forces \
         in N (scene thickness); in brackets the share of the window in which the tool touches \
         anything (a cut where a detached layer runs ahead of the tool touches little).\n\n",
    );
    for x in all.iter().filter(|x| x.speeds.len() > 1) {
        let _ = writeln!(
            s,
            "### variant `{}`, {}, a_p = {} mm\n",
            x.variant, x.method, x.depth_mm
        );
        let head: Vec<String> = x.speeds.iter().map(|v| format!("{v} m/s")).collect();
        let _ = writeln!(s, "| seed | {} | n |", head.join(" | "));
        let _ = writeln!(s, "|---{}|---|", "|---".repeat(x.speeds.len()));
        let cell = |f: Option<f64>, c: Option<f64>| match (f, c) {
            (Some(f), Some(c)) if c.is_finite() => format!("{f:.0} ({:.0} %)", 100.0 * c),
            (Some(f), _) => format!("{f:.0}"),
            _ => "–".into(),
        };
        let exp = |n: Option<f64>| n.map_or("–".into(), |n| format!("{n:.2}"));
        for (k, seed) in x.seeds.iter().enumerate() {
            let cells: Vec<String> = (0..x.speeds.len())
                .map(|j| cell(x.force[k][j], x.contact[k][j]))
                .collect();
            let _ = writeln!(
                s,
                "| {seed} | {} | {} |",
                cells.join(" | "),
                exp(x.exponent(&x.force[k]))
            );
        }
        let m = x.seed_mean();
        let cells: Vec<String> = m.iter().map(|f| cell(*f, None)).collect();
        let _ = writeln!(
            s,
            "| mean | {} | {} |\n",
            cells.join(" | "),
            exp(x.exponent(&m))
        );
        let missing: Vec<String> = planned
            .iter()
            .filter(|v| !x.speeds.contains(v))
            .map(|v| format!("{v}"))
            .collect();
        if !missing.is_empty() {
            let _ = writeln!(
                s,
                "Incomplete: no run yet at {} m/s, so no verdict on neighbouring speeds, the \
                 quasi-static limit or the 1 → 2 m/s trend.\n",
                missing.join(", ")
            );
            continue;
        }
        let same: Vec<String> = (0..x.speeds.len() - 1)
            .map(|k| {
                let verdict = match x.independent(k) {
                    Some(true) => "same",
                    Some(false) => "differ",
                    None => "not run",
                };
                format!("{}→{}: {verdict}", x.speeds[k], x.speeds[k + 1])
            })
            .collect();
        let vq = match x.quasi_static_limit() {
            Some(v) => format!("up to {v} m/s"),
            None => format!("not reached at or above {} m/s", x.speeds[0]),
        };
        let trend = x.trend_1_to_2();
        let rises = trend.iter().filter(|t| t.1 > 1.0).count();
        let ratios: Vec<String> = trend
            .iter()
            .map(|(seed, r)| format!("seed {seed} ×{r:.2}"))
            .collect();
        let _ = writeln!(
            s,
            "Neighbouring speeds: {}. Quasi-static limit: {vq}. 1 → 2 m/s: rises in {rises} \
             of {} seeds with a positive mean at both ({}).\n",
            same.join(", "),
            trend.len(),
            ratios.join(", ")
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(variant: &str, seed: u64, v: f64, f: f64) -> Row {
        Row {
            variant: variant.into(),
            method: "traditional".into(),
            depth_mm: 1.0,
            speed_m_s: v,
            seed,
            mean_n: f,
            contact_share: 0.9,
            ..Row::default()
        }
    }

    #[test]
    fn a_rate_independent_force_is_quasi_static_everywhere() {
        let speeds = [0.25, 0.5, 1.0, 2.0, 4.0];
        let rows: Vec<Row> = speeds
            .iter()
            .flat_map(|&v| [row("local", 1, v, 100.0), row("local", 2, v, 110.0)])
            .collect();
        let s = &series(&rows)[0];
        assert_eq!(s.speeds, speeds);
        assert_eq!(s.quasi_static_limit(), Some(4.0));
        assert!(s.exponent(&s.seed_mean()).unwrap().abs() < 1e-12);
        assert_eq!(s.trend_1_to_2(), vec![(1, 1.0), (2, 1.0)]);
    }

    #[test]
    fn a_force_proportional_to_speed_has_exponent_one_and_no_limit() {
        let rows: Vec<Row> = [0.25, 0.5, 1.0, 2.0]
            .iter()
            .flat_map(|&v| [row("local", 1, v, 100.0 * v), row("local", 2, v, 90.0 * v)])
            .collect();
        let s = &series(&rows)[0];
        assert!((s.exponent(&s.force[0]).unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(s.quasi_static_limit(), None);
        assert_eq!(s.independent(0), Some(false));
        let md = markdown(&rows, &[0.25, 0.5, 1.0, 2.0]);
        assert!(md.contains("rises in 2 of 2 seeds"), "{md}");
        assert!(md.contains("not reached at or above 0.25 m/s"), "{md}");
    }

    #[test]
    fn the_limit_is_where_the_force_starts_to_grow_and_each_seed_must_agree() {
        // Flat up to 1 m/s, then doubling: the limit is 1 m/s.
        let f = |v: f64| if v <= 1.0 { 100.0 } else { 100.0 * v };
        let rows: Vec<Row> = [0.25, 0.5, 1.0, 2.0, 4.0]
            .iter()
            .flat_map(|&v| [row("viscous", 1, v, f(v)), row("viscous", 2, v, f(v))])
            .collect();
        assert_eq!(series(&rows)[0].quasi_static_limit(), Some(1.0));
        // One seed jumping ×1.5 between the two lowest speeds (the mean moves less than
        // ×1.25): no limit.
        let mut rows = rows;
        rows[3].mean_n = 150.0; // seed 2 at 0.5 m/s
        let s = &series(&rows)[0];
        assert_eq!(s.independent(0), Some(false));
        assert_eq!(s.quasi_static_limit(), None);
    }

    #[test]
    fn variants_and_missing_runs_are_kept_apart() {
        let rows = vec![
            row("local", 1, 1.0, 100.0),
            row("local", 1, 2.0, 80.0),
            row("undamped", 1, 1.0, 50.0),
        ];
        let all = series(&rows);
        assert_eq!(all.len(), 2);
        assert_eq!(all[0].trend_1_to_2(), vec![(1, 0.8)]);
        assert_eq!(all[1].speeds, vec![1.0]);
        let md = markdown(&rows, &[1.0, 2.0]);
        assert!(md.contains("rises in 0 of 1 seeds"), "{md}");
        // With a planned speed missing from a series: its table, no verdicts.
        let md = markdown(&rows, &[1.0, 2.0, 4.0]);
        assert!(md.contains("Incomplete: no run yet at 4 m/s"), "{md}");
        assert!(!md.contains("Quasi-static limit"), "{md}");
        assert!(
            !md.contains("undamped damping"),
            "one speed: no series table\n{md}"
        );
    }

    #[test]
    fn a_negative_mean_has_no_trend_ratio_or_exponent_point() {
        let rows = vec![
            row("undamped", 1, 1.0, 900.0),
            row("undamped", 1, 2.0, -500.0),
            row("undamped", 2, 1.0, 100.0),
            row("undamped", 2, 2.0, 300.0),
        ];
        let s = &series(&rows)[0];
        assert_eq!(s.trend_1_to_2(), vec![(2, 3.0)]);
        assert_eq!(s.exponent(&s.force[0]), None);
        assert_eq!(s.independent(0), Some(false));
    }
}
