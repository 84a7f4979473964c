//! The removal mode of the Table 2 runs, cell by cell, held against S0's description of how
//! each specimen type is cut (Ye & Xu 2010, § results; `../shared/SOURCES.md`):
//!
//! 1. the traditional specimen gives the smoothest cut surface;
//! 2. traditional chips leave gently as single discs;
//! 3. ORC chips leave like the traditional ones;
//! 4. improved-ORC specimens leave more residual surface cracks;
//! 5. improved-ORC chips spray out fast when intra-grain bonds snap.
//!
//! Each figure is the seed mean ± SE of the runs' [`CuttingResult`] records (removal mode,
//! machined surface, residual cracks); each comparison between methods is made at two
//! standard errors ([`crate::table2::greater`]). "Single discs" (point 2) is read as: most
//! chip discs (> 50 %) leave in chips of one grain; "gently" as chips no faster on average
//! than twice the tool.

use crate::error::{Error, Result};
use crate::table2::{greater, METHODS};
use dem_lab::cutting::{CuttingResult, RESULT_FILE};
use serde::Serialize;
use std::path::Path;

/// Seed mean and standard error (sd/√n; infinite for one value).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct MeanSe {
    pub mean: f64,
    pub se: f64,
}

impl MeanSe {
    pub fn of(v: &[f64]) -> Option<MeanSe> {
        if v.is_empty() || v.iter().any(|x| !x.is_finite()) {
            return None;
        }
        let (mean, se) = crate::force_statistics::mean_se(v);
        // One run has no spread: an unknown SE resolves no comparison (as `table2::Cell`).
        let se = if v.len() > 1 { se } else { f64::INFINITY };
        Some(MeanSe { mean, se })
    }

    fn pair(self) -> (f64, f64) {
        (self.mean, self.se)
    }
}

/// One cell's removal figures (seed means ± SE; `None` where a run lacks the record).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RemovalCell {
    pub method: String,
    pub depth_mm: f64,
    pub speed_m_s: f64,
    pub seeds: usize,
    /// Share of chip discs in chips of one grain, and of at most three grains.
    pub single_grain_share: Option<MeanSe>,
    pub small_chip_share: Option<MeanSe>,
    /// Chips' mass-weighted mean speed and the fastest chip, over the tool speed.
    pub chip_speed_over_v: Option<MeanSe>,
    pub chip_speed_max_over_v: Option<MeanSe>,
    /// Machined surface: mean deviation from the nominal surface (mm, negative below) and
    /// Ra on the profile's mean line (µm; ISO 4287, `dem_lab::cutting::surface::Roughness`).
    pub surface_dev_mm: Option<MeanSe>,
    pub ra_um: Option<MeanSe>,
    /// Residual cracks below the machined surface: count and deepest (mm).
    pub cracks: MeanSe,
    pub deepest_crack_mm: MeanSe,
}

/// The removal figures of the finished runs `(folder, name)` (names as
/// [`crate::force_statistics::parse_name`] reads), one per cell in the order first seen.
pub fn cells(runs: &[(&Path, &str)]) -> Result<Vec<RemovalCell>> {
    let mut groups: Vec<((String, f64, f64), Vec<CuttingResult>)> = vec![];
    for (dir, n) in runs {
        let (m, d, v, _) =
            crate::force_statistics::parse_name(n).ok_or_else(|| Error::RunName {
                name: n.to_string(),
            })?;
        let f = dir.join(RESULT_FILE);
        let text = std::fs::read_to_string(&f).map_err(Error::io(&f))?;
        let r: CuttingResult = serde_json::from_str(&text).map_err(Error::json(&f))?;
        let key = (m, d, v);
        match groups.iter_mut().find(|g| g.0 == key) {
            Some(g) => g.1.push(r),
            None => groups.push((key, vec![r])),
        }
    }
    Ok(groups
        .into_iter()
        .map(|((method, depth_mm, speed_m_s), rs)| {
            let opt = |f: &dyn Fn(&CuttingResult) -> Option<f64>| {
                rs.iter()
                    .map(f)
                    .collect::<Option<Vec<f64>>>()
                    .and_then(|v| MeanSe::of(&v))
            };
            let all = |f: &dyn Fn(&CuttingResult) -> f64| {
                MeanSe::of(&rs.iter().map(f).collect::<Vec<_>>()).unwrap_or_default()
            };
            RemovalCell {
                method,
                depth_mm,
                speed_m_s,
                seeds: rs.len(),
                single_grain_share: opt(&|r| r.removal.as_ref().map(|m| m.single_grain_share)),
                small_chip_share: opt(&|r| r.removal.as_ref().map(|m| m.small_chip_share)),
                chip_speed_over_v: opt(&|r| {
                    r.removal.as_ref().map(|m| m.chip_speed_mean / m.tool_speed)
                }),
                chip_speed_max_over_v: opt(&|r| {
                    r.removal.as_ref().map(|m| m.chip_speed_max / m.tool_speed)
                }),
                surface_dev_mm: opt(&|r| r.surface.as_ref().map(|s| s.mean_deviation * 1e3)),
                ra_um: opt(&|r| {
                    r.surface
                        .as_ref()
                        .and_then(|s| s.roughness())
                        .map(|m| m.ra * 1e6)
                }),
                cracks: all(&|r| r.residual_cracks.count as f64),
                deepest_crack_mm: all(&|r| r.residual_cracks.deepest * 1e3),
            }
        })
        .collect())
}

/// One of S0's statements checked on one case: ✓ / ✗ / ~ (within 2 SE) and the figures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Check {
    pub statement: &'static str,
    pub case: String,
    /// `Some(true)` holds, `Some(false)` resolved against, `None` not resolved.
    pub holds: Option<bool>,
    pub figures: String,
}

/// The removal cell of method `m` at depth `d` (mm) and speed `v` (m/s).
pub(crate) fn find<'a>(
    cells: &'a [RemovalCell],
    m: &str,
    d: f64,
    v: f64,
) -> Option<&'a RemovalCell> {
    cells
        .iter()
        .find(|c| c.method == m && c.depth_mm == d && c.speed_m_s == v)
}

fn pm(x: Option<MeanSe>) -> String {
    x.map_or("—".into(), |x| crate::page::pm(x.mean, x.se, None))
}

/// Both of `a > b` and `a > c` at 2 SE: `Some(false)` if either is resolved against.
fn both(r1: Option<bool>, r2: Option<bool>) -> Option<bool> {
    match (r1, r2) {
        (Some(false), _) | (_, Some(false)) => Some(false),
        (Some(true), Some(true)) => Some(true),
        _ => None,
    }
}

/// S0's five statements on every case, each where the case has the methods it compares (see
/// the module docs).
pub fn checks(cells: &[RemovalCell]) -> Vec<Check> {
    let mut out = vec![];
    let mut cases: Vec<(f64, f64)> = cells.iter().map(|c| (c.depth_mm, c.speed_m_s)).collect();
    cases.sort_by(|a, b| a.partial_cmp(b).unwrap());
    cases.dedup();
    for (d, v) in cases {
        let case = format!("a_p {d} mm, v {v} m/s");
        let (o, i, t) = (
            find(cells, "orc", d, v),
            find(cells, "improved", d, v),
            find(cells, "traditional", d, v),
        );
        let p = |x: Option<MeanSe>| x.map(MeanSe::pair);
        let f = |c: Option<&RemovalCell>, g: fn(&RemovalCell) -> Option<MeanSe>| c.and_then(g);
        let ra = |c: &RemovalCell| c.ra_um;
        let single = |c: &RemovalCell| c.single_grain_share;
        let speed = |c: &RemovalCell| c.chip_speed_over_v;
        let cracks = |c: &RemovalCell| Some(c.cracks);
        // 1. Smoothest surface: Ra traditional below both.
        if let (Some(rt), Some(ro), Some(ri)) = (p(f(t, ra)), p(f(o, ra)), p(f(i, ra))) {
            out.push(Check {
                statement: "the traditional specimen gives the smoothest cut surface",
                case: case.clone(),
                holds: both(greater(ro, rt), greater(ri, rt)),
                figures: format!(
                    "Ra (µm) traditional {}, ORC {}, improved {}",
                    pm(f(t, ra)),
                    pm(f(o, ra)),
                    pm(f(i, ra))
                ),
            });
        }
        // 2. Traditional chips leave gently as single discs.
        if let (Some(s), Some(w)) = (p(f(t, single)), p(f(t, speed))) {
            out.push(Check {
                statement: "traditional chips leave gently as single discs",
                case: case.clone(),
                holds: both(greater(s, (0.5, 0.0)), greater((2.0, 0.0), w)),
                figures: format!(
                    "single-grain share {} (> 0.5), mean chip speed / v {} (< 2)",
                    pm(f(t, single)),
                    pm(f(t, speed))
                ),
            });
        }
        // 3. ORC chips like the traditional ones: no resolved difference in either figure.
        if let (Some(so), Some(st), Some(wo), Some(wt)) = (
            p(f(o, single)),
            p(f(t, single)),
            p(f(o, speed)),
            p(f(t, speed)),
        ) {
            let same = greater(so, st).is_none() && greater(wo, wt).is_none();
            out.push(Check {
                statement: "ORC chips leave like the traditional ones",
                case: case.clone(),
                holds: Some(same),
                figures: format!(
                    "single-grain share ORC {} vs traditional {}; chip speed / v {} vs {}",
                    pm(f(o, single)),
                    pm(f(t, single)),
                    pm(f(o, speed)),
                    pm(f(t, speed))
                ),
            });
        }
        // 4. More residual cracks in improved ORC.
        if let (Some(ci), Some(ct), Some(co)) = (p(f(i, cracks)), p(f(t, cracks)), p(f(o, cracks)))
        {
            out.push(Check {
                statement: "improved-ORC specimens leave more residual surface cracks",
                case: case.clone(),
                holds: both(greater(ci, ct), greater(ci, co)),
                figures: format!(
                    "cracks improved {}, traditional {}, ORC {}",
                    pm(f(i, cracks)),
                    pm(f(t, cracks)),
                    pm(f(o, cracks))
                ),
            });
        }
        // 5. Improved-ORC chips spray out fast.
        if let (Some(wi), Some(wt), Some(wo)) = (p(f(i, speed)), p(f(t, speed)), p(f(o, speed))) {
            out.push(Check {
                statement: "improved-ORC chips spray out fast",
                case,
                holds: both(greater(wi, wt), greater(wi, wo)),
                figures: format!(
                    "mean chip speed / v improved {}, traditional {}, ORC {}",
                    pm(f(i, speed)),
                    pm(f(t, speed)),
                    pm(f(o, speed))
                ),
            });
        }
    }
    out
}

/// The cells' table and S0's statements checked case by case.
pub fn markdown(cells: &[RemovalCell], checks: &[Check]) -> String {
    let mut s = String::from(
        "### Removal mode against S0's description\n\n\
         Seed means ± SE of each run's figures at the end of the cut (`cutting.result.json`: \
         `removal`, `surface`, `residual_cracks`; docs/cutting.md, \"Analysis\"). Chips are \
         the fragments above the nominal surface.\n\n\
         | a_p (mm) | v (m/s) | method | seeds | single-grain share | ≤ 3-grain share | chip speed / v | fastest chip / v | surface − nominal (mm) | Ra on the mean line (µm) | residual cracks | deepest (mm) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut sorted: Vec<&RemovalCell> = cells.iter().collect();
    sorted.sort_by(|a, b| {
        (a.depth_mm, a.speed_m_s)
            .partial_cmp(&(b.depth_mm, b.speed_m_s))
            .unwrap()
            .then(
                METHODS
                    .iter()
                    .position(|m| *m == a.method)
                    .cmp(&METHODS.iter().position(|m| *m == b.method)),
            )
    });
    for c in sorted {
        s += &format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            c.depth_mm,
            c.speed_m_s,
            c.method,
            c.seeds,
            pm(c.single_grain_share),
            pm(c.small_chip_share),
            pm(c.chip_speed_over_v),
            pm(c.chip_speed_max_over_v),
            pm(c.surface_dev_mm),
            pm(c.ra_um),
            pm(Some(c.cracks)),
            pm(Some(c.deepest_crack_mm))
        );
    }
    s += "\nS0's statements, case by case (✓ holds, ✗ resolved against, ~ within 2 SE; \
          \"single discs\" read as > 50 % of chip discs in one-grain chips, \"gently\" as a \
          mean chip speed below 2 v):\n\n";
    if checks.is_empty() {
        s += "- not checked: no case has the runs they compare yet\n";
    }
    let mut statements: Vec<&str> = checks.iter().map(|c| c.statement).collect();
    statements.dedup();
    statements.sort();
    statements.dedup();
    for st in statements {
        let cs: Vec<&Check> = checks.iter().filter(|c| c.statement == st).collect();
        let n_ok = cs.iter().filter(|c| c.holds == Some(true)).count();
        let n_no = cs.iter().filter(|c| c.holds == Some(false)).count();
        s += &format!(
            "- **{st}**: holds in {n_ok}, against in {n_no}, not resolved in {} of {} cases\n",
            cs.len() - n_ok - n_no,
            cs.len()
        );
        for c in cs {
            let mark = match c.holds {
                Some(true) => "✓",
                Some(false) => "✗",
                None => "~",
            };
            s += &format!("  - {mark} {}: {}\n", c.case, c.figures);
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ms(mean: f64, se: f64) -> Option<MeanSe> {
        Some(MeanSe { mean, se })
    }

    fn cell(method: &str, single: f64, speed: f64, ra: f64, cracks: f64) -> RemovalCell {
        RemovalCell {
            method: method.into(),
            depth_mm: 1.0,
            speed_m_s: 1.0,
            seeds: 10,
            single_grain_share: ms(single, 0.02),
            small_chip_share: ms(single, 0.02),
            chip_speed_over_v: ms(speed, 0.1),
            chip_speed_max_over_v: ms(speed * 3.0, 0.3),
            surface_dev_mm: ms(-0.1, 0.01),
            ra_um: ms(ra, 1.0),
            cracks: MeanSe {
                mean: cracks,
                se: 0.2,
            },
            deepest_crack_mm: MeanSe { mean: 0.5, se: 0.1 },
        }
    }

    #[test]
    fn mean_and_se() {
        let m = MeanSe::of(&[1.0, 2.0, 3.0]).unwrap();
        assert!((m.mean - 2.0).abs() < 1e-15 && (m.se - (1.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert_eq!(MeanSe::of(&[]), None);
        assert_eq!(MeanSe::of(&[2.0]).unwrap().se, f64::INFINITY);
        assert_eq!(MeanSe::of(&[1.0, f64::NAN]), None);
    }

    /// A table that behaves as S0 describes: every statement holds; one that does not: each
    /// is marked against or unresolved.
    #[test]
    fn s0s_statements_are_checked_at_two_standard_errors() {
        let like_s0 = [
            cell("traditional", 0.8, 1.2, 10.0, 1.0),
            cell("orc", 0.78, 1.25, 20.0, 1.0),
            cell("improved", 0.4, 4.0, 25.0, 4.0),
        ];
        let c = checks(&like_s0);
        assert_eq!(c.len(), 5);
        assert!(c.iter().all(|c| c.holds == Some(true)), "{c:?}");
        let unlike = [
            cell("traditional", 0.3, 3.0, 30.0, 3.0),
            cell("orc", 0.6, 1.0, 20.0, 1.0),
            cell("improved", 0.4, 3.1, 25.0, 3.1),
        ];
        let c = checks(&unlike);
        let by = |s: &str| c.iter().find(|c| c.statement.contains(s)).unwrap().holds;
        assert_eq!(by("smoothest"), Some(false));
        assert_eq!(by("single discs"), Some(false));
        assert_eq!(by("ORC chips"), Some(false));
        assert_eq!(by("residual"), None); // 3.1 vs 3.0 ± 0.2
        assert_eq!(by("spray"), None);
        let md = markdown(&unlike, &c);
        assert!(md.contains("holds in 0, against in 1, not resolved in 0 of 1 cases"));
        assert!(md.contains("| 1 | 1 | orc | 10 | 0.60 ± 0.02 |"));
        // Without improved ORC only the statements on traditional and ORC are checked.
        let partial = checks(&unlike[..2]);
        assert_eq!(partial.len(), 2);
        assert!(partial
            .iter()
            .all(|c| !c.statement.contains("improved") && !c.statement.contains("smoothest")));
    }
}
