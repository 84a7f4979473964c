//! The crushable column of the "Crushable grains" section (`dem test column`,
//! `dem_lab::crushing::column`, docs/lattice.md §7): read from the committed run
//! (`<out>/crush/column/column.result.json` and a thinned `column.stress_strain.csv`), never run
//! here (the run takes tens of minutes of one core); the section says so and how to make it
//! when the files are missing.

use crate::error::{Error, Result};
use crate::page::Figure;
use crate::plot::{self, Series};
use dem_lab::crushing::column::{ColumnOutcome, Loading};
use std::path::Path;

/// The command that made the committed run (docs/lattice.md §7).
pub const COMMAND: &str = "dem test column --outlines data/outlines --out <dir> --threads 1";

/// Rows of the thinned stress–strain file: (strain, σ_top, σ_bottom) in Pa.
fn stress_strain(text: &str) -> Result<Vec<(f64, f64, f64)>> {
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let at = |n: &str| {
        head.iter()
            .position(|h| *h == n)
            .ok_or_else(|| Error::NoColumn {
                column: n.to_string(),
            })
    };
    let (e, t, b) = (at("strain")?, at("stress_top")?, at("stress_bottom")?);
    let mut out = vec![];
    for (k, l) in lines.enumerate() {
        let f: Vec<&str> = l.split(',').collect();
        let num = |i: usize| -> Result<f64> {
            f.get(i)
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or(Error::BadNumber { line: k + 2 })
        };
        out.push((num(e)?, num(t)?, num(b)?));
    }
    Ok(out)
}

/// Runs made before `relative_breakage` rounded its last bits to 0 hold −1e-16 for "no
/// breakage" (the same pieces summed in another order), which prints as −0.000.
fn tidy(o: &mut ColumnOutcome) {
    for g in &mut o.result.gradings {
        if g.relative_breakage.abs() < 1e-12 {
            g.relative_breakage = 0.0;
        }
    }
}

/// How the platen loaded the column, in words.
fn loading_words(o: &ColumnOutcome) -> String {
    match o.test.loading {
        Loading::Inertial => format!(
            "at the inertial number I = ε̇ d̄ √(ρ/σ_v) = {} throughout (its speed set from the \
             bottom platen's stress every {} steps; {:.3} m/s at the start)",
            o.test.inertial_number, o.test.history_every, o.result.platen_speed
        ),
        Loading::Ramp => format!(
            "at a constant {:.3} m/s (I = {} at the first level)",
            o.result.platen_speed, o.test.inertial_number
        ),
    }
}

/// The loading-rate check: the committed runs of a smaller column in `dir` (`*.result.json`),
/// B_r at each level against the loading, and each run's largest relative difference of B_r
/// from the slowest inertial run's (at the levels where that one's B_r is at least 0.02).
/// Empty when there are none; a result file that does not read or parse is an error naming it
/// (a committed run is never left out silently).
fn rate_check(dir: &Path) -> Result<String> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(String::new());
    };
    let mut files: Vec<std::path::PathBuf> = entries
        .map(|e| e.map(|e| e.path()).map_err(Error::io(dir)))
        .collect::<Result<_>>()?;
    files.retain(|p| p.to_string_lossy().ends_with(".result.json"));
    files.sort();
    let mut runs = Vec::with_capacity(files.len());
    for p in &files {
        let text = std::fs::read_to_string(p).map_err(Error::io(p))?;
        let mut o: ColumnOutcome = serde_json::from_str(&text).map_err(Error::json(p))?;
        tidy(&mut o);
        runs.push(o);
    }
    // Ramps first, then by falling I; the reference is the last (the slowest inertial run).
    runs.sort_by(|a, b| {
        (a.test.loading == Loading::Inertial)
            .cmp(&(b.test.loading == Loading::Inertial))
            .then(b.test.inertial_number.total_cmp(&a.test.inertial_number))
    });
    let Some(reference) = runs.last() else {
        return Ok(String::new());
    };
    let levels = |o: &ColumnOutcome| {
        o.result.gradings[1..]
            .iter()
            .map(|g| format!("{:.0}", g.level * 1e-6))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut md = format!(
        "\nLoading-rate check (docs/lattice.md §7; {} grains, H0 = {:.1} mm, the same deposit): \
         B_r at {} MPa, and the largest difference from the run at I = {} where its B_r ≥ 0.02\n\n\
         | loading | I | B_r | largest difference | loading steps | wall time (s) |\n\
         |---|---|---|---|---|---|\n",
        reference.result.grains,
        reference.result.height * 1e3,
        levels(reference),
        reference.test.inertial_number
    );
    let by_level = |o: &ColumnOutcome, level: f64| {
        o.result
            .gradings
            .iter()
            .find(|g| g.level == level)
            .map(|g| g.relative_breakage)
    };
    for c in &runs {
        let worst = reference.result.gradings[1..]
            .iter()
            .filter(|g| g.relative_breakage >= 0.02)
            .filter_map(|g| Some((by_level(c, g.level)? / g.relative_breakage - 1.0).abs()))
            .fold(0.0, f64::max);
        md += &format!(
            "| {} | {} | {} | {:.0} % | {} | {:.0} |\n",
            match c.test.loading {
                Loading::Inertial => "inertial",
                Loading::Ramp => "ramp (I at the first level)",
            },
            c.test.inertial_number,
            c.result.gradings[1..]
                .iter()
                .map(|g| format!("{:.3}", g.relative_breakage))
                .collect::<Vec<_>>()
                .join(", "),
            100.0 * worst,
            c.run.steps,
            c.run.wall_time_s
        );
    }
    let i_ref = reference.test.inertial_number;
    if let Some(near) = runs.iter().find(|c| {
        c.test.loading == Loading::Inertial
            && c.test.inertial_number != i_ref
            && (c.test.inertial_number / i_ref - 1.0).abs() <= 0.2
    }) {
        md += &format!(
            "\nThe run at I = {} is the reference's loading changed by {:.0} %: its difference is \
             the scatter of one realization of this small column (a granular assembly's path is \
             chaotic: any change of the loading gives another realization). A difference of \
             another run below it is not a rate effect.\n",
            near.test.inertial_number,
            100.0 * (near.test.inertial_number / i_ref - 1.0).abs()
        );
    }
    Ok(md)
}

/// The column's markdown and figures.
pub fn part(out: &Path) -> Result<(String, Vec<Figure>)> {
    let dir = out.join("crush").join("column");
    let file = dir.join("column.result.json");
    let Ok(text) = std::fs::read_to_string(&file) else {
        return Ok((
            format!(
                "\n### Crushable column\n\nNo committed run in `{}`: make it with `{COMMAND}` and copy \
                 `column.result.json` and `column.stress_strain.csv` there.\n",
                dir.display()
            ),
            vec![],
        ));
    };
    let mut o: ColumnOutcome = serde_json::from_str(&text).map_err(Error::json(&file))?;
    tidy(&mut o);
    let ss_file = dir.join("column.stress_strain.csv");
    let ss = stress_strain(&std::fs::read_to_string(&ss_file).map_err(Error::io(&ss_file))?)?;
    let (t, r) = (&o.test, &o.result);
    let mut md = String::from("\n### Crushable column (one-dimensional compression)\n\n");
    md += &format!(
        "`dem test column` (docs/lattice.md §7): {} lattice grains from the {} outlines of \
         `data/outlines`, scaled to d_eq = {} mm (one size class drawn per grain), one lattice \
         spacing S = {:.3} mm (R_eq/S = {:.1}–{:.1}; {} nodes, {} links), the material of the \
         single-grain study (E = {} GPa, ν = {}, energy criterion G_c = 30 J/m²), friction {} \
         between nodes and {} at the platens, smooth side walls. Deposited (seed {}) into a box \
         {:.1} mm wide ({:.1} mm high, solid fraction {:.3}), seated as rigid grains at {:.1} MPa \
         ({:.1} mm, {:.3}), then loaded by the top platen {}. σ_v is the smaller of the two \
         platens' stresses F/(W t); the grading is taken the first time σ_v reaches each \
         level. Hardin's (1985) relative \
         breakage B_r = B_t/B_p, with b_p = log10(d/d_f) and the fines cutoff d_f = {:.3} mm \
         (two lattice cells: a single node is below it).\n\n",
        r.grains,
        o.outlines.len(),
        t.sizes()
            .iter()
            .map(|d| format!("{:.2}", d * 1e3))
            .collect::<Vec<_>>()
            .join(", "),
        t.spacing * 1e3,
        0.5 * t.d_min / t.spacing,
        0.5 * t.d_max / t.spacing,
        r.nodes,
        r.links,
        t.young * 1e-9,
        t.poisson,
        t.friction,
        t.platen_friction,
        t.seed,
        r.width * 1e3,
        r.deposit_height * 1e3,
        r.deposit_solid_fraction,
        t.seat_stress * 1e-6,
        r.height * 1e3,
        r.initial_solid_fraction,
        loading_words(&o),
        r.fines_cutoff * 1e3
    );
    md += "| level (MPa) | σ_v (MPa) | ε_v | broken links | pieces (≥ 2 nodes) | fines | fines mass | B_p | B_r | I | E_k/E_s | unbalanced |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for g in &r.gradings {
        md += &format!(
            "| {:.0} | {:.2} | {:.4} | {} | {} | {} | {:.4} | {:.4} | {:.4} | {:.1e} | {:.3} | {:.1e} |\n",
            g.level * 1e-6,
            g.stress * 1e-6,
            g.strain,
            g.broken_links,
            g.fragments,
            g.fines,
            g.fines_mass_fraction,
            g.breakage_potential,
            g.relative_breakage,
            g.inertial_number,
            g.kinetic_over_strain,
            g.unbalanced_ratio
        );
    }
    if !r.levels_not_reached.is_empty() {
        md += &format!(
            "\nNot reached within ε_v = {}: {:?} MPa.\n",
            t.max_strain,
            r.levels_not_reached
                .iter()
                .map(|s| s * 1e-6)
                .collect::<Vec<_>>()
        );
    }
    // Quasi-static honesty: the bottom platen's mean stress over the top one's while loaded.
    let first = t.stress_levels.first().copied().unwrap_or(0.0);
    let loaded: Vec<&(f64, f64, f64)> = ss.iter().filter(|x| x.1 >= first).collect();
    let top_sum: f64 = loaded.iter().map(|x| x.1).sum();
    let ratio = if top_sum > 0.0 {
        loaded.iter().map(|x| x.2).sum::<f64>() / top_sum
    } else {
        0.0
    };
    let seat_ps = if o.seat.wall_time_s > 0.0 {
        o.seat.discs as f64 * o.seat.steps as f64 / o.seat.wall_time_s
    } else {
        0.0
    };
    md += &format!(
        "\nRun times (this 2-core VM, shared; one thread): seating {} steps in {:.0} s (rigid \
         grains, dt {:.2e} s, {:.2e} particle-steps/s), loading {} steps in {:.0} s (dt {:.2e} \
         s): **{:.2e} particle-steps/s** for the lattice column (nodes × steps / wall time). \
         Energy balance at the end: work {:.3e} J, released at breaks {:.3e} J, error {:.1e} of \
         the work; local damping took {:.0} % of the work, friction {:.0} %. While σ_top ≥ \
         {:.0} MPa the bottom platen carried on average **{:.2}** of the top one's stress (mean \
         over mean; smooth side walls, so 1 at equilibrium).\n",
        o.seat.steps,
        o.seat.wall_time_s,
        o.seat.dt,
        seat_ps,
        o.run.steps,
        o.run.wall_time_s,
        o.run.dt,
        r.particle_steps_per_s,
        r.work,
        r.released,
        r.balance_error,
        100.0 * r.damping / r.work,
        100.0 * r.friction / r.work,
        first * 1e-6,
        ratio
    );
    md += &rate_check(&dir.join("rate-check"))?;
    // Gradings.
    let gseries: Vec<Series> = r
        .gradings
        .iter()
        .map(|g| Series {
            name: if g.level == 0.0 {
                "initial".into()
            } else {
                format!("{:.0} MPa (B_r {:.3})", g.level * 1e-6, g.relative_breakage)
            },
            points: r
                .sieves
                .iter()
                .zip(&g.passing)
                .map(|(s, p)| (s * 1e3, *p))
                .collect(),
        })
        .collect();
    let grading_svg = plot::lines(
        "Crushable column: grading at each vertical stress",
        "sieve size d (mm)",
        "mass fraction finer than d",
        &gseries,
        true,
        false,
    )?;
    let br_svg = plot::lines(
        "Crushable column: Hardin's relative breakage and fines against vertical stress",
        "σ_v (MPa): the smaller (bottom) platen's stress",
        "fraction",
        &[
            Series {
                name: "B_r (Hardin 1985)".into(),
                points: r
                    .gradings
                    .iter()
                    .map(|g| (g.stress * 1e-6, g.relative_breakage))
                    .collect(),
            },
            Series {
                name: "fines (single nodes) mass fraction".into(),
                points: r
                    .gradings
                    .iter()
                    .map(|g| (g.stress * 1e-6, g.fines_mass_fraction))
                    .collect(),
            },
        ],
        false,
        false,
    )?;
    let ss_svg = plot::lines(
        "Crushable column: vertical stress against vertical strain",
        "ε_v = platen travel / H0",
        "σ (MPa)",
        &[
            Series {
                name: "top platen".into(),
                points: ss.iter().map(|x| (x.0, x.1 * 1e-6)).collect(),
            },
            Series {
                name: "bottom platen".into(),
                points: ss.iter().map(|x| (x.0, x.2 * 1e-6)).collect(),
            },
        ],
        false,
        false,
    )?;
    Ok((
        md,
        vec![
            Figure {
                file: "crush_column_gradings.svg".into(),
                caption: "Crushable column: grading curves (mass fraction finer than each sieve size) initially and at each vertical stress level".into(),
                svg: grading_svg,
            },
            Figure {
                file: "crush_column_breakage.svg".into(),
                caption: "Crushable column: Hardin's relative breakage B_r and the fines' mass fraction against the vertical stress".into(),
                svg: br_svg,
            },
            Figure {
                file: "crush_column_stress_strain.svg".into(),
                caption: "Crushable column: top and bottom platen stress against the vertical strain".into(),
                svg: ss_svg,
            },
        ],
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stress_strain_rows_and_bad_numbers() {
        let ok = "time,platen_travel,strain,stress_top,stress_bottom\n0,0,0.1,2e6,1e6\n";
        assert_eq!(stress_strain(ok).unwrap(), vec![(0.1, 2e6, 1e6)]);
        let bad = "strain,stress_top,stress_bottom\n0.1,NaN,1\n";
        assert!(stress_strain(bad)
            .unwrap_err()
            .to_string()
            .contains("line 2"));
        assert!(stress_strain("a,b\n")
            .unwrap_err()
            .to_string()
            .contains("strain"));
    }

    /// The rate check reads every committed result: none is nothing to report, a result that
    /// does not parse is an error naming its file (it used to be left out silently).
    #[test]
    fn rate_check_names_a_bad_result_file() {
        let dir = std::env::temp_dir().join(format!("rate-check-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(rate_check(&dir.join("absent")).unwrap(), "");
        std::fs::write(dir.join("notes.txt"), "not a result").unwrap();
        assert_eq!(rate_check(&dir).unwrap(), "");
        std::fs::write(dir.join("i0.001.result.json"), "{\"test\": 1}").unwrap();
        let e = rate_check(&dir).unwrap_err().to_string();
        assert!(e.contains("i0.001.result.json"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
