//! Table 2 of Ye & Xu (2010): main cutting force (peak and mean, kN) of Si3N4 for three
//! specimen types, two depths and two speeds, 5 specimens per case. This module turns the
//! per-run results into the table: seed averages and spreads, the one fitted constant, relative
//! errors against the paper, and the paper's qualitative claims checked one by one.
//!
//! The fitted constant is the disc thickness t. Every mass and every stiffness of a 2D
//! bonded-disc model is proportional to t (m = ρπr²t, k_n = 2tE_c, Ā = 2R̄t, Ī = ⅔R̄³t), so the
//! motion does not depend on t and every force is proportional to it: the runs are made at the
//! scene thickness t₀ and t is chosen afterwards so that the traditional mean force at
//! a_p = 1 mm, v = 1 m/s equals the paper's 7.5 kN. The other 23 numbers are predictions.

use serde::{Deserialize, Serialize};
use std::path::Path;

/// The three specimen types, in the paper's column order.
pub const METHODS: [&str; 3] = ["orc", "improved", "traditional"];

/// The paper's table (`data/reference/ye_xu_2010_table2.json`).
#[derive(Clone, Debug, Deserialize)]
pub struct PaperTable2 {
    pub source: String,
    pub cells: Vec<PaperCell>,
}

/// One row of the paper's table: `[peak, mean]` in kN per method.
#[derive(Clone, Debug, Deserialize)]
pub struct PaperCell {
    pub depth_mm: f64,
    pub speed_m_s: f64,
    pub orc: [f64; 2],
    pub improved: [f64; 2],
    pub traditional: [f64; 2],
}

impl PaperTable2 {
    pub fn read(path: &Path) -> Result<PaperTable2, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// `[peak, mean]` (kN) of a method at a depth and speed.
    pub fn value(&self, method: &str, depth_mm: f64, speed_m_s: f64) -> Option<[f64; 2]> {
        let c = self
            .cells
            .iter()
            .find(|c| c.depth_mm == depth_mm && c.speed_m_s == speed_m_s)?;
        match method {
            "orc" => Some(c.orc),
            "improved" => Some(c.improved),
            "traditional" => Some(c.traditional),
            _ => None,
        }
    }
}

/// One cutting run (one specimen seed), forces at the run's thickness.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    pub method: String,
    pub depth_mm: f64,
    pub speed_m_s: f64,
    pub seed: u64,
    /// Peak and mean main (horizontal) cutting force over the steady window (N).
    pub peak_n: f64,
    pub mean_n: f64,
    /// Thickness t₀ the run used (m).
    pub thickness_m: f64,
    pub discs: usize,
    pub steps: u64,
    pub wall_time_s: f64,
    /// CPU time of the run (s), where it was recorded ([`crate::cutting_runs::TIME_FILE`]).
    #[serde(default)]
    pub cpu_time_s: Option<f64>,
    /// Peak of the main force averaged over one grain of tool travel (N; see
    /// [`PEAK_AVERAGING`]), from the run's force history; `None` when it could not be read.
    #[serde(default)]
    pub peak_avg_n: Option<f64>,
    /// Deepest overlap seen at the run's guard checks (fraction of the smaller radius);
    /// `None` in results written before it was recorded.
    #[serde(default)]
    pub max_overlap_fraction: Option<f64>,
    /// Bonds broken during the run: all, and those of the intra-grain group (improved ORC's
    /// bonds inside grains; 0 for the other methods).
    #[serde(default)]
    pub broken_total: Option<u64>,
    #[serde(default)]
    pub broken_intra_grain: Option<u64>,
    /// Travel-weighted median of the main force over the window (N) and the share of the
    /// window's work done over its top 5 % of travel
    /// ([`dem_core::lab::force_stats::RunStats`]); `None` in records written before them.
    #[serde(default)]
    pub median_n: Option<f64>,
    #[serde(default)]
    pub top5_work_share: Option<f64>,
}

/// The seed-averaged moving-mean peak of one cell ([`crate::force_statistics`]), N at the
/// runs' thickness: the peak and the travel-weighted mean of the same seed-averaged history.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SeedAveraged {
    pub method: String,
    pub depth_mm: f64,
    pub speed_m_s: f64,
    pub seeds: usize,
    pub peak_n: f64,
    pub mean_n: f64,
}

/// What the averaged peak ([`RunRecord::peak_avg_n`]) averages over. Our raw peak is the
/// largest sample of the force history (one contact event, 20-40× the mean), the paper's
/// peak is 1.3-1.7× its mean: its definition is not stated. The force averaged while the tool
/// advances by one grain (S0's grain size for ORC and improved ORC, 0.86 mm; the same width
/// for every method so they stay comparable) is the load that breaks material off, fixed
/// before looking at the paper's numbers and not fitted to them.
pub const PEAK_AVERAGING: &str = "moving mean of the main force over one grain size of tool travel (the specimens' grain size, 0.86 mm in the full plan)";

/// One cell of our table (the issue's `table2.json` record).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Cell {
    pub method: String,
    pub depth_mm: f64,
    pub speed_m_s: f64,
    pub peak_kN: f64,
    pub mean_kN: f64,
    /// Sample standard deviation over the seeds (0 for one seed).
    pub peak_sd_kN: f64,
    pub mean_sd_kN: f64,
    pub seeds: usize,
    pub paper_peak_kN: f64,
    pub paper_mean_kN: f64,
    /// (ours − paper)/paper.
    pub peak_rel_err: f64,
    pub mean_rel_err: f64,
    /// Peak of the force averaged over one grain of travel ([`PEAK_AVERAGING`]): seed mean,
    /// sample sd and (ours − paper peak)/paper peak; `None` when a run of the cell lacks it.
    #[serde(default)]
    pub peak_avg_kN: Option<f64>,
    #[serde(default)]
    pub peak_avg_sd_kN: Option<f64>,
    #[serde(default)]
    pub peak_avg_rel_err: Option<f64>,
    /// Standard error of the mean over the seeds (sd/√n).
    #[serde(default)]
    pub mean_se_kN: Option<f64>,
    /// Seed mean of the runs' travel-weighted medians; `None` when a run lacks one.
    #[serde(default)]
    pub median_kN: Option<f64>,
    /// The seed-averaged moving-mean peak ([`crate::force_statistics::PEAK_STATISTIC`]), its
    /// ratio to the same averaged history's mean (beside the paper's peak/mean) and
    /// (ours − paper peak)/paper peak; `None` when not computed.
    #[serde(default)]
    pub peak_seed_avg_kN: Option<f64>,
    #[serde(default)]
    pub peak_seed_avg_over_mean: Option<f64>,
    #[serde(default)]
    pub peak_seed_avg_rel_err: Option<f64>,
}

/// The fitted constant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Constant {
    pub name: String,
    pub scales: String,
    /// Thickness the runs used and the fitted one (m).
    pub run_value: f64,
    pub value: f64,
    pub fitted_on: String,
}

/// A qualitative claim of the paper and whether our table shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Claim {
    pub claim: String,
    pub holds: bool,
    /// Each comparison made, with ✓/✗.
    pub details: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Table2 {
    pub source: String,
    pub cells: Vec<Cell>,
    pub constant: Constant,
    pub claims: Vec<Claim>,
    /// Cells (peak and mean counted separately, 24 in all) within ±20 % of the paper.
    pub within_20_percent: usize,
    pub numbers: usize,
    /// What the averaged peak is ([`PEAK_AVERAGING`]) and how many averaged peaks are within
    /// ±20 % of the paper's peaks (of how many cells have one).
    #[serde(default)]
    pub peak_averaging: String,
    #[serde(default)]
    pub peak_avg_within_20_percent: usize,
    #[serde(default)]
    pub peak_avg_numbers: usize,
    /// What the seed-averaged peak is, and how many are within ±20 % of the paper's peaks
    /// (of how many cells have one).
    #[serde(default)]
    pub peak_statistic: String,
    #[serde(default)]
    pub peak_seed_avg_within_20_percent: usize,
    #[serde(default)]
    pub peak_seed_avg_numbers: usize,
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let sd = if v.len() > 1 {
        (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    (m, sd)
}

/// Builds the table from the runs, without seed-averaged peaks ([`assemble_with`]).
pub fn assemble(runs: &[RunRecord], paper: &PaperTable2) -> Result<Table2, String> {
    assemble_with(runs, paper, &[])
}

/// Builds the table from the runs and the cells' seed-averaged peaks (`seed_avg`, N at the
/// runs' thickness; cells without one have none). Fails when the fitting cell (traditional,
/// 1 mm, 1 m/s) has no run or a non-positive mean force, or the runs use different
/// thicknesses.
pub fn assemble_with(
    runs: &[RunRecord],
    paper: &PaperTable2,
    seed_avg: &[SeedAveraged],
) -> Result<Table2, String> {
    let t0 = runs.first().ok_or("no cutting runs")?.thickness_m;
    if runs.iter().any(|r| r.thickness_m != t0) {
        return Err("runs with different thicknesses cannot share one fitted constant".into());
    }
    if let Some(r) = runs
        .iter()
        .find(|r| !(r.peak_n.is_finite() && r.mean_n.is_finite()))
    {
        return Err(format!(
            "run {} a_p {} mm v {} m/s seed {}: non-finite force",
            r.method, r.depth_mm, r.speed_m_s, r.seed
        ));
    }
    let pick = |m: &str, d: f64, v: f64| -> Vec<&RunRecord> {
        runs.iter()
            .filter(|r| r.method == m && r.depth_mm == d && r.speed_m_s == v)
            .collect()
    };
    let fit = pick("traditional", 1.0, 1.0);
    if fit.is_empty() {
        return Err("no traditional run at a_p = 1 mm, v = 1 m/s to fit the constant on".into());
    }
    let fit_mean = mean_sd(&fit.iter().map(|r| r.mean_n).collect::<Vec<_>>()).0;
    let paper_fit = paper
        .value("traditional", 1.0, 1.0)
        .ok_or("the paper's table has no traditional 1 mm, 1 m/s cell")?[1];
    if fit_mean <= 0.0 {
        return Err(format!(
            "traditional mean force at 1 mm, 1 m/s is {fit_mean} N: cannot fit the thickness"
        ));
    }
    let t = t0 * paper_fit * 1e3 / fit_mean;
    let scale = t / t0 / 1e3; // N at t₀ → kN at t
    let mut cells = Vec::new();
    for pc in &paper.cells {
        for m in METHODS {
            let rs = pick(m, pc.depth_mm, pc.speed_m_s);
            if rs.is_empty() {
                continue;
            }
            let (pk, pk_sd) = mean_sd(&rs.iter().map(|r| r.peak_n * scale).collect::<Vec<_>>());
            let (mn, mn_sd) = mean_sd(&rs.iter().map(|r| r.mean_n * scale).collect::<Vec<_>>());
            let p = paper
                .value(m, pc.depth_mm, pc.speed_m_s)
                .expect("method known");
            let avg: Option<Vec<f64>> =
                rs.iter().map(|r| r.peak_avg_n.map(|v| v * scale)).collect();
            let avg = avg.map(|a| mean_sd(&a));
            let median: Option<Vec<f64>> =
                rs.iter().map(|r| r.median_n.map(|v| v * scale)).collect();
            let sa = seed_avg.iter().find(|a| {
                a.method == m && a.depth_mm == pc.depth_mm && a.speed_m_s == pc.speed_m_s
            });
            cells.push(Cell {
                method: m.into(),
                depth_mm: pc.depth_mm,
                speed_m_s: pc.speed_m_s,
                peak_kN: pk,
                mean_kN: mn,
                peak_sd_kN: pk_sd,
                mean_sd_kN: mn_sd,
                seeds: rs.len(),
                paper_peak_kN: p[0],
                paper_mean_kN: p[1],
                peak_rel_err: pk / p[0] - 1.0,
                mean_rel_err: mn / p[1] - 1.0,
                peak_avg_kN: avg.map(|a| a.0),
                peak_avg_sd_kN: avg.map(|a| a.1),
                peak_avg_rel_err: avg.map(|a| a.0 / p[0] - 1.0),
                mean_se_kN: Some(mn_sd / (rs.len() as f64).sqrt()),
                median_kN: median.map(|v| mean_sd(&v).0),
                peak_seed_avg_kN: sa.map(|a| a.peak_n * scale),
                peak_seed_avg_over_mean: sa.filter(|a| a.mean_n > 0.0).map(|a| a.peak_n / a.mean_n),
                peak_seed_avg_rel_err: sa.map(|a| a.peak_n * scale / p[0] - 1.0),
            });
        }
    }
    let numbers = 2 * cells.len();
    let within = cells
        .iter()
        .map(|c| (c.peak_rel_err.abs() <= 0.2) as usize + (c.mean_rel_err.abs() <= 0.2) as usize)
        .sum();
    let avg_errs: Vec<f64> = cells.iter().filter_map(|c| c.peak_avg_rel_err).collect();
    let sa_errs: Vec<f64> = cells
        .iter()
        .filter_map(|c| c.peak_seed_avg_rel_err)
        .collect();
    let claims = claims(&cells);
    Ok(Table2 {
        source: paper.source.clone(),
        cells,
        constant: Constant {
            name: "thickness".into(),
            scales: "every force (masses and stiffnesses are ∝ t, so the motion is independent of t and forces ∝ t)".into(),
            run_value: t0,
            value: t,
            fitted_on: "traditional, a_p = 1 mm, v = 1 m/s, mean force = 7.5 kN".into(),
        },
        claims,
        within_20_percent: within,
        numbers,
        peak_averaging: PEAK_AVERAGING.into(),
        peak_avg_within_20_percent: avg_errs.iter().filter(|e| e.abs() <= 0.2).count(),
        peak_avg_numbers: avg_errs.len(),
        peak_statistic: if sa_errs.is_empty() {
            String::new()
        } else {
            crate::force_statistics::PEAK_STATISTIC.into()
        },
        peak_seed_avg_within_20_percent: sa_errs.iter().filter(|e| e.abs() <= 0.2).count(),
        peak_seed_avg_numbers: sa_errs.len(),
    })
}

fn find<'a>(cells: &'a [Cell], m: &str, d: f64, v: f64) -> Option<&'a Cell> {
    cells
        .iter()
        .find(|c| c.method == m && c.depth_mm == d && c.speed_m_s == v)
}

/// The four observations of S0 (§ results), each over every case the table holds, on the peak
/// and the mean force.
pub fn claims(cells: &[Cell]) -> Vec<Claim> {
    let mut cases: Vec<(f64, f64)> = cells.iter().map(|c| (c.depth_mm, c.speed_m_s)).collect();
    cases.sort_by(|a, b| a.partial_cmp(b).unwrap());
    cases.dedup();
    let depths: Vec<f64> = {
        let mut d: Vec<f64> = cases.iter().map(|c| c.0).collect();
        d.dedup();
        d.sort_by(f64::total_cmp);
        d.dedup();
        d
    };
    let speeds: Vec<f64> = {
        let mut s: Vec<f64> = cases.iter().map(|c| c.1).collect();
        s.sort_by(f64::total_cmp);
        s.dedup();
        s
    };
    let mark = |ok: bool| if ok { "✓" } else { "✗" };
    let q = |c: &Cell, k: usize| if k == 0 { c.peak_kN } else { c.mean_kN };
    let kind = ["peak", "mean"];
    let mut out = Vec::new();

    // 1. ORC > improved > traditional in every case.
    let mut det = vec![];
    let mut ok = true;
    for &(d, v) in &cases {
        if let (Some(o), Some(i), Some(t)) = (
            find(cells, "orc", d, v),
            find(cells, "improved", d, v),
            find(cells, "traditional", d, v),
        ) {
            for (k, kind) in kind.iter().enumerate() {
                let h = q(o, k) > q(i, k) && q(i, k) > q(t, k);
                ok &= h;
                det.push(format!(
                    "{} a_p {d} mm, v {v} m/s, {}: ORC {:.2} > improved {:.2} > traditional {:.2}",
                    mark(h),
                    kind,
                    q(o, k),
                    q(i, k),
                    q(t, k)
                ));
            }
        }
    }
    out.push(Claim {
        claim: "force order ORC > improved ORC > traditional in every case".into(),
        holds: ok && !det.is_empty(),
        details: det,
    });

    // 2. The ORC–improved gap grows with depth.
    let mut det = vec![];
    let mut ok = true;
    for &v in &speeds {
        for w in depths.windows(2) {
            let gap = |d: f64, k: usize| {
                Some(q(find(cells, "orc", d, v)?, k) - q(find(cells, "improved", d, v)?, k))
            };
            for (k, kind) in kind.iter().enumerate() {
                if let (Some(g1), Some(g2)) = (gap(w[0], k), gap(w[1], k)) {
                    let h = g2 > g1;
                    ok &= h;
                    det.push(format!(
                        "{} v {v} m/s, {}: ORC − improved {:.2} at {} mm → {:.2} at {} mm",
                        mark(h),
                        kind,
                        g1,
                        w[0],
                        g2,
                        w[1]
                    ));
                }
            }
        }
    }
    out.push(Claim {
        claim: "the ORC–improved ORC gap is small at small depth and grows with depth".into(),
        holds: ok && !det.is_empty(),
        details: det,
    });

    // 3. Force grows with depth; 4. force falls with speed.
    for (claim, across_depth) in [
        ("force grows with the depth of cut", true),
        ("force falls with the cutting speed", false),
    ] {
        let mut det = vec![];
        let mut ok = true;
        for m in METHODS {
            let (outer, inner) = if across_depth {
                (&speeds, &depths)
            } else {
                (&depths, &speeds)
            };
            for &o in outer {
                for w in inner.windows(2) {
                    let get = |x: f64| {
                        if across_depth {
                            find(cells, m, x, o)
                        } else {
                            find(cells, m, o, x)
                        }
                    };
                    if let (Some(a), Some(b)) = (get(w[0]), get(w[1])) {
                        for (k, kind) in kind.iter().enumerate() {
                            let h = if across_depth {
                                q(b, k) > q(a, k)
                            } else {
                                q(b, k) < q(a, k)
                            };
                            ok &= h;
                            let (unit, other) = if across_depth {
                                ("mm", format!("v {o} m/s"))
                            } else {
                                ("m/s", format!("a_p {o} mm"))
                            };
                            det.push(format!(
                                "{} {m}, {other}, {}: {:.2} at {} {unit} → {:.2} at {} {unit}",
                                mark(h),
                                kind,
                                q(a, k),
                                w[0],
                                q(b, k),
                                w[1]
                            ));
                        }
                    }
                }
            }
        }
        out.push(Claim {
            claim: claim.into(),
            holds: ok && !det.is_empty(),
            details: det,
        });
    }
    out
}

impl Table2 {
    /// Our table beside the paper's, relative errors, seed spread, the constant and the claims.
    pub fn markdown(&self) -> String {
        let mut s =
            String::from("## Table 2: main cutting force (kN), Si3N4, ours vs Ye & Xu (2010)\n\n");
        s += &format!(
            "Fitted constant: {} = {:.4e} m (runs at {} m), fitted on {}; it scales {}. \
             The other numbers are predictions.\n\n",
            self.constant.name,
            self.constant.value,
            self.constant.run_value,
            self.constant.fitted_on,
            self.constant.scales
        );
        s += "| a_p (mm) | v (m/s) | method | peak ours ± sd | peak paper | err | mean ours ± sd | mean paper | err | seeds |\n";
        s += "|---|---|---|---|---|---|---|---|---|---|\n";
        for c in &self.cells {
            s += &format!(
                "| {} | {} | {} | {:.2} ± {:.2} | {:.1} | {:+.0} % | {:.2} ± {:.2} | {:.1} | {:+.0} % | {} |\n",
                c.depth_mm,
                c.speed_m_s,
                c.method,
                c.peak_kN,
                c.peak_sd_kN,
                c.paper_peak_kN,
                100.0 * c.peak_rel_err,
                c.mean_kN,
                c.mean_sd_kN,
                c.paper_mean_kN,
                100.0 * c.mean_rel_err,
                c.seeds
            );
        }
        s += &format!(
            "\n{} of {} numbers within ±20 % of the paper (the fitted cell's mean is exact by construction).\n\n",
            self.within_20_percent, self.numbers
        );
        if self.cells.iter().any(|c| c.peak_avg_kN.is_some()) {
            s += &format!(
                "**Averaged peak** ({}): the paper does not say how its peak was taken; ours \
                 above is the largest single sample of the history.\n\n",
                self.peak_averaging
            );
            s += "| a_p (mm) | v (m/s) | method | averaged peak ours ± sd | peak paper | err | averaged peak / mean |\n";
            s += "|---|---|---|---|---|---|---|\n";
            for c in &self.cells {
                let (Some(a), Some(sd), Some(e)) =
                    (c.peak_avg_kN, c.peak_avg_sd_kN, c.peak_avg_rel_err)
                else {
                    continue;
                };
                s += &format!(
                    "| {} | {} | {} | {a:.2} ± {sd:.2} | {:.1} | {:+.0} % | {:.1} |\n",
                    c.depth_mm,
                    c.speed_m_s,
                    c.method,
                    c.paper_peak_kN,
                    100.0 * e,
                    a / c.mean_kN
                );
            }
            s += &format!(
                "\n{} of {} averaged peaks within ±20 % of the paper's peaks (the paper's peak/mean \
                 is 1.3–1.7).\n\n",
                self.peak_avg_within_20_percent, self.peak_avg_numbers
            );
        }
        if self.cells.iter().any(|c| c.peak_seed_avg_kN.is_some()) {
            s += &format!(
                "**Force statistics** (S0 does not define its peak; ours are stated before \
                 comparing, docs/cutting.md \"Force statistics\"). Raw peak: the seed mean of \
                 each run's largest sample. Seed-averaged peak: {}. Its ratio is to the \
                 mean of the same averaged history.\n\n",
                self.peak_statistic
            );
            s += "| a_p (mm) | v (m/s) | method | mean ± SE | median | raw peak | seed-avg peak | peak paper | err | raw peak / mean | seed-avg peak / mean | paper peak / mean |\n";
            s += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
            let o = |x: Option<f64>, d: usize| x.map_or("—".to_string(), |v| format!("{v:.d$}"));
            for c in &self.cells {
                s += &format!(
                    "| {} | {} | {} | {:.2} ± {} | {} | {:.1} | {} | {:.1} | {} | {:.1} | {} | {:.2} |\n",
                    c.depth_mm,
                    c.speed_m_s,
                    c.method,
                    c.mean_kN,
                    o(c.mean_se_kN, 2),
                    o(c.median_kN, 2),
                    c.peak_kN,
                    o(c.peak_seed_avg_kN, 2),
                    c.paper_peak_kN,
                    c.peak_seed_avg_rel_err
                        .map_or("—".to_string(), |e| format!("{:+.0} %", 100.0 * e)),
                    c.peak_kN / c.mean_kN,
                    o(c.peak_seed_avg_over_mean, 2),
                    c.paper_peak_kN / c.paper_mean_kN
                );
            }
            s += &format!(
                "\n{} of {} seed-averaged peaks within ±20 % of the paper's peaks.\n\n",
                self.peak_seed_avg_within_20_percent, self.peak_seed_avg_numbers
            );
        }
        s += "### The paper's claims\n\n";
        for c in &self.claims {
            let verdict = match (c.details.is_empty(), c.holds) {
                (true, _) => "not checked: the table lacks the runs it compares",
                (false, true) => "holds",
                (false, false) => "does not hold",
            };
            s += &format!("- **{}**: {verdict}\n", c.claim);
            for d in &c.details {
                s += &format!("  - {d}\n");
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> PaperTable2 {
        let text = include_str!("../../data/reference/ye_xu_2010_table2.json");
        serde_json::from_str(text).unwrap()
    }

    /// Runs that reproduce the paper's numbers at t = 2 × t₀ with ±5 % seed scatter.
    fn runs_like_paper(seeds: u64) -> Vec<RunRecord> {
        let p = paper();
        let mut v = vec![];
        for c in &p.cells {
            for m in METHODS {
                let [pk, mn] = p.value(m, c.depth_mm, c.speed_m_s).unwrap();
                for s in 0..seeds {
                    let f = 1.0 + 0.05 * ((s as f64) - (seeds as f64 - 1.0) / 2.0);
                    v.push(RunRecord {
                        method: m.into(),
                        depth_mm: c.depth_mm,
                        speed_m_s: c.speed_m_s,
                        seed: s,
                        peak_n: pk * 500.0 * f,
                        mean_n: mn * 500.0 * f,
                        thickness_m: 1.0,
                        discs: 1000,
                        steps: 1,
                        wall_time_s: 1.0,
                        cpu_time_s: None,
                        peak_avg_n: Some(pk * 450.0 * f),
                        max_overlap_fraction: None,
                        broken_total: None,
                        broken_intra_grain: None,
                        median_n: Some(mn * 400.0 * f),
                        top5_work_share: None,
                    });
                }
            }
        }
        v
    }

    #[test]
    fn reproduces_the_paper_when_the_runs_do() {
        let t = assemble(&runs_like_paper(5), &paper()).unwrap();
        assert_eq!(t.cells.len(), 12);
        assert!((t.constant.value - 2.0).abs() < 1e-12);
        assert_eq!(t.within_20_percent, 24);
        for c in &t.cells {
            assert!(c.mean_rel_err.abs() < 1e-12 && c.peak_rel_err.abs() < 1e-12);
            assert_eq!(c.seeds, 5);
            assert!(c.mean_sd_kN > 0.0);
            // Averaged peaks at 0.9 of the paper's peaks.
            assert!((c.peak_avg_rel_err.unwrap() + 0.1).abs() < 1e-12);
        }
        assert_eq!((t.peak_avg_within_20_percent, t.peak_avg_numbers), (12, 12));
        assert!(t.markdown().contains("12 of 12 averaged peaks"));
        // A run without an averaged peak leaves its cell without one.
        let mut runs = runs_like_paper(2);
        runs[0].peak_avg_n = None;
        let t = assemble(&runs, &paper()).unwrap();
        assert_eq!(
            t.cells.iter().filter(|c| c.peak_avg_kN.is_none()).count(),
            1
        );
        assert_eq!(t.peak_avg_numbers, 11);
        // The paper's own numbers: the order, depth and speed claims hold; the gap claim
        // holds too (ORC − improved: 0.3 → 3.1 kN peak at 1 m/s).
        for c in &t.claims {
            assert!(c.holds, "{}: {:?}", c.claim, c.details);
        }
    }

    /// Seed-averaged peaks at 1.1 × the paper's peaks, over a history whose mean is the
    /// paper's mean: errors +10 %, ratio 1.1 × the paper's; medians and SEs per cell.
    #[test]
    fn seed_averaged_peaks_beside_the_raw_ones() {
        let p = paper();
        let pr = &p;
        let runs = runs_like_paper(5);
        // t = 2 t₀: kN at t = N at t₀ / 500.
        let sa: Vec<SeedAveraged> = p
            .cells
            .iter()
            .flat_map(|c| {
                METHODS.iter().map(move |m| {
                    let [pk, mn] = pr.value(m, c.depth_mm, c.speed_m_s).unwrap();
                    SeedAveraged {
                        method: (*m).into(),
                        depth_mm: c.depth_mm,
                        speed_m_s: c.speed_m_s,
                        seeds: 5,
                        peak_n: 1.1 * pk * 500.0,
                        mean_n: mn * 500.0,
                    }
                })
            })
            .filter(|a| a.method != "orc" || a.depth_mm == 1.0)
            .collect();
        let t = assemble_with(&runs, &p, &sa).unwrap();
        for c in &t.cells {
            let paper_ratio = c.paper_peak_kN / c.paper_mean_kN;
            match c.peak_seed_avg_rel_err {
                Some(e) => {
                    assert!((e - 0.1).abs() < 1e-12);
                    assert!((c.peak_seed_avg_over_mean.unwrap() / paper_ratio - 1.1).abs() < 1e-12);
                }
                None => assert!(c.method == "orc" && c.depth_mm == 2.0),
            }
            // Medians at 0.8 of the means; SE = sd/√5.
            assert!((c.median_kN.unwrap() / c.mean_kN - 0.8).abs() < 1e-12);
            assert!((c.mean_se_kN.unwrap() - c.mean_sd_kN / 5f64.sqrt()).abs() < 1e-12);
            // The raw peak is untouched.
            assert!(c.peak_rel_err.abs() < 1e-12);
        }
        assert_eq!(
            (t.peak_seed_avg_within_20_percent, t.peak_seed_avg_numbers),
            (10, 10)
        );
        assert!(t.peak_statistic.contains("moving mean over w = 1 a_p"));
        let md = t.markdown();
        assert!(md.contains("10 of 10 seed-averaged peaks"));
        assert!(md.contains("| 2 | 1 | orc |") && md.contains("| — | 22.7 | — |"));
        // Without them: no statistic, no table.
        let t = assemble(&runs, &p).unwrap();
        assert!(t.peak_statistic.is_empty() && t.cells[0].peak_seed_avg_kN.is_none());
        assert!(!t.markdown().contains("seed-averaged peaks within"));
    }

    /// The committed table (written before the seed-averaged peak) still loads.
    #[test]
    fn the_committed_table_loads() {
        let t: Table2 =
            serde_json::from_str(include_str!("../../docs/report/table2.json")).unwrap();
        assert_eq!(t.cells.len(), 12);
        assert!(t.cells.iter().all(|c| c.peak_seed_avg_kN.is_none()));
        assert_eq!(t.peak_seed_avg_numbers, 0);
    }

    #[test]
    fn a_broken_order_is_reported() {
        let mut runs = runs_like_paper(1);
        for r in runs.iter_mut().filter(|r| r.method == "traditional") {
            r.peak_n *= 3.0;
            r.mean_n *= 3.0;
        }
        let t = assemble(&runs, &paper()).unwrap();
        assert!(!t.claims[0].holds);
        assert!(t.claims[0].details.iter().any(|d| d.starts_with('✗')));
        assert!(t.markdown().contains("does not hold"));
    }

    #[test]
    fn bad_runs_are_errors() {
        assert!(assemble(&[], &paper()).is_err());
        let mut runs = runs_like_paper(1);
        runs[0].mean_n = f64::NAN;
        assert!(assemble(&runs, &paper())
            .unwrap_err()
            .contains("non-finite"));
        let runs: Vec<RunRecord> = runs_like_paper(1)
            .into_iter()
            .filter(|r| r.method != "traditional")
            .collect();
        assert!(assemble(&runs, &paper())
            .unwrap_err()
            .contains("traditional"));
    }

    /// A table of traditional runs alone: the claims that compare methods are not checked
    /// (and say so), the depth and speed claims are.
    #[test]
    fn a_partial_table_marks_what_it_cannot_check() {
        let runs: Vec<RunRecord> = runs_like_paper(1)
            .into_iter()
            .filter(|r| r.method == "traditional")
            .collect();
        let t = assemble(&runs, &paper()).unwrap();
        assert_eq!(t.cells.len(), 4);
        assert_eq!(t.numbers, 8);
        assert!(t.claims[0].details.is_empty() && !t.claims[0].holds);
        assert!(t.claims[1].details.is_empty());
        assert!(t.claims[2].holds && t.claims[3].holds);
        let md = t.markdown();
        assert_eq!(md.matches("not checked").count(), 2);
    }
}
