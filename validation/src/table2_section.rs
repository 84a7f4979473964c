//! The Table 2 section of the report: the run plan (full: the paper's set-up, 5 seeds; quick:
//! coarse specimens, 1 seed, a short cut), the runs ([`crate::cutting_runs`]), the table
//! ([`crate::table2`]), a bar chart ours vs paper and the force histories of the three methods
//! at a_p = 1 mm, v = 1 m/s.

use crate::cutting_runs::{outcome, Source};
use crate::cutting_runs::{Plan, Reused};
use crate::error::{Error, Result};
use crate::page::{json, Figure, Section};
use crate::plot::{self, Series};
use crate::table2::{self, PaperTable2, METHODS};
use dem_lab::specimen::{FewGrains, GrainMode, Method, SpecimenParams};
use dem_lab::LabModel;
use std::path::Path;

/// The calibrated Si3N4 model (`data/models/si3n4.model.json`, written by `dem calibrate`).
pub fn si3n4_model(data: &Path) -> Result<LabModel> {
    let p = data.join("models/si3n4.model.json");
    let text = std::fs::read_to_string(&p).map_err(Error::io(&p))?;
    serde_json::from_str(&text).map_err(Error::json(&p))
}

/// Full: 20 × 10 mm, radii 0.175–0.285 mm (989 discs in the paper, 993 ours), grains 0.86 mm,
/// template discs from 0.08 mm, seeds 1–10 (1–5 for choosing, 6–10 to check), L = 10 mm, the cutting test's defaults. Quick (a
/// smoke test, not comparable with the paper): a 10 × 5 mm specimen, radii 0.3–0.5 mm (a
/// depth of 1 mm is 2.5 mean radii, so the tool cuts material rather than pushing single
/// discs: with radii 0.6–1.0 mm the ORC mean force was 0), grains 1.4 mm, template discs from
/// 0.15 mm, seed 1, L = 1.5 mm, steady window from 0.5 a_p, tool 3× the disc k_n.
/// Both use the calibrated micro-parameters
/// with the bond stiffness of the plan's mean radius (k̄_n = Ē_c/(2r̄)).
pub fn plan(data: &Path, quick: bool) -> Result<Plan> {
    let mut model = si3n4_model(data)?;
    let (w, h, r0, r1, grain, tmin, seeds, length) = if quick {
        (
            10e-3,
            5e-3,
            0.3e-3,
            0.5e-3,
            1.4e-3,
            0.15e-3,
            vec![1],
            1.5e-3,
        )
    } else {
        (
            20e-3,
            10e-3,
            0.175e-3,
            0.285e-3,
            0.86e-3,
            0.08e-3,
            (1..=10).collect(),
            10e-3,
        )
    };
    model.r_mean = 0.5 * (r0 + r1);
    let mut sp = SpecimenParams::new(
        Method::Traditional,
        w,
        h,
        r0,
        r1,
        model.density,
        model.micro.contact_modulus,
        model.micro.boundary_tensile,
        1,
    );
    sp.grain_size = grain;
    sp.template_r_min = tmin;
    if !quick {
        // S0's specimens: a few irregular grains in the traditional packing, as many as give
        // S0's 1576 improved-ORC discs for 989 (docs/specimen.md, "Few irregular grains").
        // The quick smoke test keeps every grain a clump (its small specimen holds few cells).
        sp.grains = GrainMode::Few(FewGrains::s0(&sp));
    }
    sp.micro = model.micro.clone();
    Ok(Plan {
        specimen: sp,
        model,
        methods: vec![Method::Orc, Method::Improved, Method::Traditional],
        depths_mm: vec![1.0, 2.0],
        speeds_m_s: vec![1.0, 2.0],
        seeds,
        length,
        dt_factor: None,
        window_start: quick.then_some(0.5),
        tool_stiffness: quick.then_some(3.0),
    })
}

/// Reads `cutting.forces.csv` (travel, time, main, vertical) as (travel mm, main kN × scale).
fn force_series(file: &Path, scale: f64) -> Option<Vec<(f64, f64)>> {
    let (x, f) = crate::force_statistics::main_force(file)?;
    Some(
        x.iter()
            .zip(&f)
            .map(|(a, b)| (a * 1e3, b * scale))
            .collect(),
    )
}

/// The seeds that check the claims: the model was chosen on seeds 1–5 (docs/cutting.md,
/// "Decision log").
pub const CHECK_SEEDS: std::ops::RangeInclusive<u64> = 6..=10;

/// The previous model's table in the report folder (since 2026-12-02: PFC local damping in the
/// lab frame, the 10-seed runs of `table2-runs/`; git history has the ones before): its cells are
/// shown beside the new ones.
pub const PREVIOUS_FILE: &str = "table2-previous.json";

/// Writes each cell's value in the previous model's table `prev` beside it: the mean and the
/// peak *as the previous table reported it* ([`table2::Cell::peak`]: the seed-averaged peak
/// where it was computed, so the column compares the same statistic as ours, else the raw one).
pub fn set_previous(t: &mut table2::Table2, prev: &table2::Table2) {
    for c in &mut t.cells {
        if let Some(p) = prev.cell(&c.method, c.depth_mm, c.speed_m_s) {
            c.previous_mean_kN = Some(p.mean_kN);
            c.previous_peak_kN = Some(p.peak().0);
        }
    }
}

/// Which part of the plan to run: all of it by default; a subset of the methods or seeds lets
/// the full table be built up piece by piece (finished runs are read back, see
/// [`crate::cutting_runs`]).
#[derive(Clone, Debug, Default)]
pub struct Subset {
    pub methods: Vec<Method>,
    pub seeds: Vec<u64>,
}

/// Runs the plan (or its `subset`) into `out/table2-runs`, or reads its runs from a sweep
/// folder (`source`), and builds the section; also returns the factor that turns N at the run
/// thickness into kN at the fitted thickness, and the runs read back from earlier calls.
pub fn section(
    data: &Path,
    out: &Path,
    quick: bool,
    subset: &Subset,
    source: Source,
) -> Result<(Section, f64, Reused, Vec<String>)> {
    let mut plan = plan(data, quick)?;
    if !subset.methods.is_empty() {
        plan.methods.retain(|m| subset.methods.contains(m));
    }
    if !subset.seeds.is_empty() {
        plan.seeds.retain(|s| subset.seeds.contains(s));
    }
    if plan.methods.is_empty() || plan.seeds.is_empty() {
        return Err(Error::EmptySubset);
    }
    let paper = PaperTable2::read(&data.join("reference/ye_xu_2010_table2.json"))?;
    let work = out.join("table2-runs");
    let outcome = outcome(&plan.jobs(), &work, source, &|l| eprintln!("  {l}"))?;
    let reused = outcome.reused();
    let (runs, mut errors, not_run) = (outcome.finished, outcome.errors, outcome.missing);
    let partial = !subset.methods.is_empty() || !subset.seeds.is_empty() || !not_run.is_empty();
    let records: Vec<_> = runs.iter().map(|r| r.record.clone()).collect();
    let names: Vec<(&Path, &str)> = runs
        .iter()
        .map(|r| (r.dir.as_path(), r.name.as_str()))
        .collect();
    let seed_avg = crate::force_statistics::seed_averaged(&names).unwrap_or_else(|e| {
        errors.push(format!("seed-averaged peaks: {e}"));
        vec![]
    });
    let mut t = table2::assemble_with(&records, &paper, &seed_avg)?;
    // The claims on the check seeds (not used to choose the model), beside those on every seed.
    let check: Vec<_> = runs
        .iter()
        .filter(|r| CHECK_SEEDS.contains(&r.record.seed))
        .collect();
    if !quick && !check.is_empty() && check.len() < runs.len() {
        let recs: Vec<_> = check.iter().map(|r| r.record.clone()).collect();
        let names: Vec<(&Path, &str)> = check
            .iter()
            .map(|r| (r.dir.as_path(), r.name.as_str()))
            .collect();
        match crate::force_statistics::seed_averaged(&names)
            .and_then(|sa| table2::assemble_with(&recs, &paper, &sa))
        {
            Ok(c) => {
                t.claims_all_seeds = std::mem::replace(&mut t.claims, c.claims);
                t.claims_on = format!(
                    "the check seeds {}–{} only (not used to choose the model; the seeds \
                     1–5 were)",
                    CHECK_SEEDS.start(),
                    CHECK_SEEDS.end()
                );
            }
            Err(e) => errors.push(format!("claims on the check seeds: {e}")),
        }
    }
    // Each cell's value in the previous model's table, where it is kept.
    if let Ok(text) = std::fs::read_to_string(out.join(PREVIOUS_FILE)) {
        match serde_json::from_str::<table2::Table2>(&text) {
            Ok(prev) => set_previous(&mut t, &prev),
            Err(e) => errors.push(format!("{}: {e}", out.join(PREVIOUS_FILE).display())),
        }
    }
    let scale = t.constant.value / t.constant.run_value / 1e3;
    // Bars: mean force per case (a group) and method (a colour), ours and the paper's.
    let (cases, labels) = cases_of(t.cells.iter().map(|c| (c.depth_mm, c.speed_m_s)));
    let ours = per_method(&cases, |m, (d, v)| {
        t.cell(m, d, v).map_or(f64::NAN, |c| c.mean_kN)
    });
    let theirs = per_method(&cases, |m, (d, v)| {
        t.cell(m, d, v).map_or(f64::NAN, |c| c.paper_mean_kN)
    });
    let mean_bars: Vec<(String, Vec<f64>, Vec<f64>)> = ours
        .into_iter()
        .zip(theirs)
        .map(|((m, o), (_, p))| (m, o, p))
        .collect();
    let bars = plot::bars_against(
        "Table 2: mean main cutting force, ours (seed mean) vs Ye & Xu (2010)",
        "kN",
        &labels,
        &mean_bars,
        "paper",
    )?;
    let mut series = vec![];
    for m in METHODS {
        let name = format!("{m}-d1-v1-s{}", plan.seeds[0]);
        let f = runs
            .iter()
            .find(|r| r.name == name)
            .map(|r| r.dir.join(dem_lab::cutting::FORCES_FILE));
        if let Some(points) = f.and_then(|f| force_series(&f, scale)) {
            series.push(Series {
                name: m.into(),
                points,
            });
        }
    }
    let hist = plot::lines(
        "Main cutting force, a_p = 1 mm, v = 1 m/s (first seed)",
        "tool travel (mm)",
        "main force (kN, fitted thickness)",
        &series,
        false,
        false,
    )?;
    let total_time: f64 = records.iter().map(|r| r.wall_time_s).sum();
    let mut md = format!(
        "Plan ({}): specimens {} × {} mm, radii {:.3}–{:.3} mm, methods {}, seeds {:?}, L = {} mm, \
         calibrated Si3N4 model (`data/models/si3n4.model.json`), local damping {} in the {} \
         frame (docs/cutting.md, \"Damping and the frame of reference\"); {} runs, {:.0} s of \
         run time.\n\n",
        match (quick, partial) {
            (true, _) => "quick: coarse specimens, short cut — not comparable with the paper",
            (false, true) => "full set-up, **part of the runs**, methods and seeds below",
            (false, false) => "full",
        },
        plan.specimen.width * 1e3,
        plan.specimen.height * 1e3,
        plan.specimen.r_min * 1e3,
        plan.specimen.r_max * 1e3,
        plan.methods.iter().map(|m| m.name()).collect::<Vec<_>>().join(", "),
        plan.seeds,
        plan.length * 1e3,
        plan.test(1.0, 1.0).local_damping,
        plan.test(1.0, 1.0).damping_frame.name(),
        records.len(),
        total_time
    );
    if let Source::Sweep(d) = source {
        md += &format!(
            "The runs were made by `dem sweep` in `{}` (its done cases, matched to the plan's \
             runs by the specimen, model and test they ran: docs/sweep.md, \"Table 2 on a \
             cluster\").\n\n",
            d.display()
        );
    }
    md += &t.markdown().replacen("## Table 2", "### Table 2", 1);
    // The committed full table, read once for the section and its summary line.
    let full = quick.then(committed_full).flatten();
    if let Some((file, full)) = &full {
        md += &beside_full(&t, file, full);
    }
    // The removal mode against S0's description, and its picture.
    let (removal, removal_checks) = match crate::removal_table::cells(&names) {
        Ok(c) => {
            let k = crate::removal_table::checks(&c);
            (c, k)
        }
        Err(e) => {
            errors.push(format!("removal mode: {e}"));
            (vec![], vec![])
        }
    };
    md += "\n";
    md += &crate::removal_table::markdown(&removal, &removal_checks);
    let (cases, labels) = cases_of(removal.iter().map(|c| (c.depth_mm, c.speed_m_s)));
    let shares = per_method(&cases, |m, (d, v)| {
        crate::removal_table::find(&removal, m, d, v)
            .and_then(|c| c.single_grain_share)
            .map_or(0.0, |s| 100.0 * s.mean)
    });
    let removal_bars = plot::bars(
        "Share of the chip discs that leave in single-grain chips (seed mean)",
        "%",
        &labels,
        &shares,
    )?;
    // Where ours disagrees, the most likely cause (not for the quick mode's toy runs).
    let why = if quick {
        vec![]
    } else {
        crate::table2_why::findings(
            &records,
            &t,
            &paper,
            plan.specimen.grain_size * 1e3,
            &removal,
        )
    };
    md += "\n";
    let per_cell = crate::table2_why::per_cell(&t);
    md += &crate::table2_why::per_cell_markdown(&per_cell);
    md += &crate::table2_why::markdown(&why);
    if !not_run.is_empty() {
        let how = match source {
            Source::Sweep(d) => format!(
                "not done in the sweep `{}` yet: run them there (`dem sweep run`, or submit \
                 its `slurm.sbatch` again) and build the report again",
                d.display()
            ),
            Source::Here(_) => "a later call without `--finished-only` runs them, reading \
                                back the finished ones"
                .to_string(),
        };
        md += &format!(
            "\n**Not run yet** ({} of the plan's {} runs; {how}): {}\n",
            not_run.len(),
            plan.jobs().len(),
            not_run.join(", ")
        );
    }
    if !errors.is_empty() {
        md += "\n**Failed runs** (left out of the table):\n\n";
        for e in &errors {
            md += &format!("- {e}\n");
        }
    }
    let section = Section {
        title: "Table 2 (Ye & Xu 2010): cutting forces of Si3N4".into(),
        markdown: md,
        figures: vec![
            Figure {
                file: "table2_bars.svg".into(),
                caption: "Mean main cutting force per case and method: ours (fitted thickness) and the paper's".into(),
                svg: bars,
            },
            Figure {
                file: "table2_removal.svg".into(),
                caption: "Removal mode: share of the chip discs that leave as single-grain chips, per case and method (S0: traditional chips leave as single discs)".into(),
                svg: removal_bars,
            },
            Figure {
                file: "cutting_forces.svg".into(),
                caption: "Main cutting force against tool travel for the three specimen types, a_p = 1 mm, v = 1 m/s".into(),
                svg: hist,
            },
        ],
        data: vec![
            ("table2.json".into(), json(&t)),
            ("table2_runs.json".into(), json(&runs)),
            ("table2_not_run.json".into(), json(&not_run)),
            (
                "table2_why.json".into(),
                json(&serde_json::json!({"findings": why, "per_cell": per_cell})),
            ),
            (
                "table2_removal.json".into(),
                json(&serde_json::json!({"cells": removal, "checks": removal_checks})),
            ),
        ],
    };
    let mut summary = vec![summary_line(
        &t,
        if quick {
            ", quick smoke test: one seed, coarse specimens, not comparable with the paper"
        } else if partial {
            ", part of the runs"
        } else {
            ""
        },
    )];
    if let Some((file, full)) = &full {
        summary.push(summary_line(
            full,
            &format!(", the committed full report `{}`", file.display()),
        ));
    }
    Ok((section, scale, reused, summary))
}

/// The summary's line for a Table 2: numbers within ±20 % and S0's claims by verdict.
fn summary_line(t: &table2::Table2, what: &str) -> String {
    let count = |v: table2::Verdict| t.claims.iter().filter(|c| c.verdict == v).count();
    format!(
        "**Table 2** (Ye & Xu 2010, Si3N4 cutting forces{what}): {} of {} numbers within ±20 % \
         of the paper's (one fitted constant, the thickness); S0's {} claims: {} hold, {} do \
         not, {} not resolved at 2 SE, {} not checked.",
        t.within_20_percent,
        t.numbers,
        t.claims.len(),
        count(table2::Verdict::Holds),
        count(table2::Verdict::DoesNotHold),
        count(table2::Verdict::NotResolved),
        count(table2::Verdict::NotChecked),
    )
}

/// The committed full report's Table 2 ([`COMMITTED_TABLE2`], found as the report finds its
/// data), which the quick report sets beside its smoke-test numbers (issue 49); `None` when it
/// is absent or does not read as a Table 2.
fn committed_full() -> Option<(std::path::PathBuf, table2::Table2)> {
    let file = crate::project_path(None, COMMITTED_TABLE2);
    let text = std::fs::read_to_string(&file).ok()?;
    let t = serde_json::from_str(&text).ok()?;
    Some((file, t))
}

/// Where the committed full report keeps its Table 2, relative to the repository.
pub const COMMITTED_TABLE2: &str = "docs/report/table2.json";

/// The quick report's Table 2 beside the committed full one: each quick cell's mean (one seed)
/// with the full table's seed mean ± SE and the paper's, then the full table's claims.
fn beside_full(quick: &table2::Table2, file: &Path, full: &table2::Table2) -> String {
    let mut md = format!(
        "\n### Beside the committed full Table 2\n\nThe numbers above are a smoke test of the \
         chain (one seed, coarse specimens, a short cut): they show that it runs, not what the \
         model predicts. The committed full report (`{}`, {} cells, constant {} = {:.4e} m) \
         gives, for the same cells:\n\n\
         | a_p (mm) | v (m/s) | method | quick mean (kN, n = 1) | full mean ± SE (kN) | seeds \
         | paper (kN) |\n|---|---|---|---|---|---|---|\n",
        file.display(),
        full.cells.len(),
        full.constant.name,
        full.constant.value,
    );
    for c in &quick.cells {
        let Some(f) = full.cell(&c.method, c.depth_mm, c.speed_m_s) else {
            continue;
        };
        md += &format!(
            "| {} | {} | {} | {} | {} | {} | {} |\n",
            c.depth_mm,
            c.speed_m_s,
            c.method,
            crate::page::fixed(c.mean_kN, 2),
            crate::page::pm(f.mean_kN, f.mean_se_kN.unwrap_or(f64::NAN), None),
            f.seeds,
            f.paper_mean_kN
        );
    }
    md += &format!("\nThe full table's claims, on {}:\n\n", full.claims_on);
    for c in &full.claims {
        md += &format!("- **{}**: {}\n", c.claim, c.verdict.text());
    }
    md
}

/// The (a_p, v) cases among `keys`, sorted, each once, and their labels for a chart.
fn cases_of(keys: impl Iterator<Item = (f64, f64)>) -> (Vec<(f64, f64)>, Vec<String>) {
    let mut cases: Vec<(f64, f64)> = keys.collect();
    cases.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    cases.dedup();
    let labels = cases
        .iter()
        .map(|(d, v)| format!("a_p {d} mm, v {v} m/s"))
        .collect();
    (cases, labels)
}

/// One chart series per method of [`METHODS`]: `value(method, case)` for each case.
fn per_method(
    cases: &[(f64, f64)],
    value: impl Fn(&str, (f64, f64)) -> f64,
) -> Vec<(String, Vec<f64>)> {
    METHODS
        .iter()
        .map(|m| (m.to_string(), cases.iter().map(|&k| value(m, k)).collect()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The previous column compares like with like: the previous table's seed-averaged peak
    /// (8.11 kN for ORC at 1 mm, 1 m/s), not its raw peak (150.3 kN).
    #[test]
    fn the_previous_peak_is_the_statistic_the_previous_table_reported() {
        let text = include_str!("../../docs/report/table2-previous.json");
        let prev: table2::Table2 = serde_json::from_str(text).unwrap();
        let mut t = prev.clone();
        set_previous(&mut t, &prev);
        for (c, p) in t.cells.iter().zip(&prev.cells) {
            let shown = c.previous_peak_kN.unwrap();
            assert_eq!(Some(shown), p.peak_seed_avg_kN);
            assert_ne!(shown, p.peak_kN);
            assert_eq!(c.previous_mean_kN, Some(p.mean_kN));
        }
    }
}
