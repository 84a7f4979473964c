//! The report's "Crushable grains" section (issue 25 item 5): single-grain crushing
//! (`dem_lab::crushing::grain`) of the synthetic outlines of `data/outlines` scaled to three sizes,
//! with a Weibull fit of the strengths per size (Weibull 1951) and the size-effect exponent of
//! the characteristic strength (`dem_lab::crushing::weibull`).
//!
//! The lattice spacing is a constant fraction of the grain's equivalent radius (S = 0.18 R_eq,
//! R_eq/S = 5.6, about 90–100 nodes a grain), so each grain's lattice is the same at every size,
//! scaled. Such a lattice has no size effect of its own: with the maximum-strain criterion the
//! strength would not depend on d at all. The energy criterion has a length scale (G_c/E):
//! a link breaks at an opening δ_c ∝ √S, so every force scales as √S and σ = F/(d t) ∝ d^(−1/2)
//! for geometrically similar grains (linear elastic fracture with a fixed G_c). The study
//! measures how closely the runs follow it (the quasi-static rule scales the platen speed with
//! the grain, so each size is the same problem, scaled), and the Weibull modulus of the
//! strengths of the 29 shapes at each size: a scatter of shape, not of flaws (the lattice is
//! regular, the criterion has no random strength).
//!
//! The results are committed (`docs/report/crush/results.json`): the section reads them back
//! when their plan matches, and runs the study (about 5 minutes on one core) otherwise.

use crate::error::{Error, Result};
use crate::page::{json, Figure, Section};
use crate::plot::{self, Series};
use clumpgen::clump::LatticeParams;
use clumpgen::{make_template, ClumpParams, Length, Method, ReadOptions};
use dem_lab::crushing::grain::{self, CrushTest, LinkCriterion};
use dem_lab::crushing::weibull::{power_law_fit, ranks, weibull_fit, PowerLaw, WeibullFit};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What the study runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Outline files (relative to the data folder), in order.
    pub grains: Vec<String>,
    /// Equivalent diameters d_eq = 2√(A/π) the outlines are scaled to (m).
    pub sizes: Vec<f64>,
    /// Lattice spacing over R_eq, and node radius fraction f.
    pub spacing_of_req: f64,
    pub node_radius: f64,
    pub test: CrushTest,
    /// Grains also run at half the platen speed (the quasi-static check).
    pub half_speed: Vec<String>,
}

/// The study's plan: every outline of `data/outlines`, d_eq = 2, 4, 8 mm, S = 0.18 R_eq, a
/// granite-like material (E 70 GPa, ν 0.2, ρ 2650 kg/m³, G_c 30 J/m²; K_IC = √(E G_c) =
/// 1.45 MPa√m), energy criterion. `quick`: two grains at 2 and 4 mm, no half-speed runs.
pub fn plan(data: &Path, quick: bool) -> Result<Plan> {
    let mut grains = csv_files(&data.join("outlines"), "outlines")?;
    if quick {
        grains.truncate(2);
    }
    let half_speed = if quick {
        vec![]
    } else {
        grains.iter().take(3).cloned().collect()
    };
    Ok(plan_of(grains, half_speed, quick))
}

/// The sorted `*.csv` files of `dir`, named `<prefix>/<file>`.
fn csv_files(dir: &Path, prefix: &str) -> Result<Vec<String>> {
    let mut grains: Vec<String> = std::fs::read_dir(dir)
        .map_err(Error::io(dir))?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .map(|n| format!("{prefix}/{n}"))
        .collect();
    grains.sort();
    Ok(grains)
}

/// The study of real outlines (issue 25 item 5, "the real gravel outlines"): `n` outlines
/// evenly spaced in the sorted `*.csv` files of `dir` (every ⌊count/n⌋-th from the first),
/// with the sizes, lattice and material of [`plan`] and no half-speed runs. The grains are
/// named `<dir's name>/<file>`, relative to `dir`'s parent (the `data` of [`run`]). Made by
/// hand (`validation/examples/crush_real.rs`); the report reads its committed results.
pub fn plan_of_folder(dir: &Path, n: usize) -> Result<Plan> {
    let name = dir
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .ok_or_else(|| Error::NoFolderName {
            dir: dir.display().to_string(),
        })?;
    let all = csv_files(dir, &name)?;
    let step = (all.len() / n.max(1)).max(1);
    let grains = all.into_iter().step_by(step).take(n).collect();
    Ok(plan_of(grains, vec![], false))
}

fn plan_of(grains: Vec<String>, half_speed: Vec<String>, quick: bool) -> Plan {
    Plan {
        grains,
        sizes: if quick {
            vec![2e-3, 4e-3]
        } else {
            vec![2e-3, 4e-3, 8e-3]
        },
        spacing_of_req: 0.18,
        node_radius: 0.9,
        test: CrushTest {
            young: 70e9,
            poisson: 0.2,
            density: 2650.0,
            criterion: LinkCriterion::Energy {
                fracture_energy: 30.0,
            },
            ..CrushTest::default()
        },
        half_speed,
    }
}

/// One run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Row {
    pub grain: String,
    /// d_eq (m) the outline was scaled to, and d, the platen gap at first contact (m).
    pub d_eq: f64,
    pub d: f64,
    pub nodes: usize,
    pub links: usize,
    /// σ = F_peak/(d t) (Pa), F_peak (N), platen closure at the peak over d.
    pub strength: f64,
    pub peak_force: f64,
    pub closure_at_peak_over_d: f64,
    pub platen_speed: f64,
    pub kinetic_over_strain_at_peak: f64,
    pub balance_error: f64,
    /// Fragments after stage 1 (first major breakage) and stage 2: the d_eq (m) of every
    /// fragment of ≥ 2 nodes and of the fines, with their masses over the grain's.
    pub stage1: Pieces,
    pub stage2: Pieces,
    pub steps: u64,
    pub wall_time_s: f64,
    pub particle_steps_per_s: f64,
    /// Half platen speed (the quasi-static check).
    pub half_speed: bool,
}

/// Fragment sizes of one stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pieces {
    pub broken_links: usize,
    pub fragments: usize,
    pub fines: usize,
    pub largest_mass_fraction: f64,
    pub fines_mass_fraction: f64,
    /// d_eq of the fragments of ≥ 2 nodes (m), decreasing.
    pub d_eq: Vec<f64>,
}

/// Per size: the Weibull fit of the strengths and the mean.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SizeFit {
    pub d_eq: f64,
    pub n: usize,
    pub mean: f64,
    pub weibull: Option<WeibullFit>,
}

/// The study's results (`results.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Results {
    pub plan: Plan,
    pub rows: Vec<Row>,
    pub errors: Vec<String>,
    pub sizes: Vec<SizeFit>,
    /// σ0 against d_eq, and the mean strength against d_eq.
    pub size_effect: Option<PowerLaw>,
    pub size_effect_mean: Option<PowerLaw>,
    /// All sizes pooled after scaling each strength to 4 mm by the fitted exponent.
    pub pooled_weibull: Option<WeibullFit>,
    /// Half-speed check: (grain, d_eq, σ at the rule's speed, σ at half of it).
    pub half_speed: Vec<(String, f64, f64, f64)>,
    pub total_wall_time_s: f64,
}

fn run_one(
    plan: &Plan,
    data: &Path,
    runs: &Path,
    grain: &str,
    d_eq: f64,
    half: bool,
) -> Result<Row> {
    let ol0 = clumpgen::read_outline(&data.join(grain), &ReadOptions::default())?;
    let mut ol = ol0.clone();
    let area = std::f64::consts::PI * 0.25 * d_eq * d_eq;
    ol.points = clumpgen::scale_to_area(&ol0.points, area);
    let p = ClumpParams {
        method: Method::Lattice,
        density: plan.test.density,
        thickness: 1.0,
        lattice: Some(LatticeParams {
            spacing: Length::OfReq(plan.spacing_of_req),
            node_radius: plan.node_radius,
        }),
        ..ClumpParams::default()
    };
    let tpl = make_template(&ol, &p)?;
    let stem = Path::new(grain)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = runs.join(format!(
        "{stem}-{:.0}mm{}",
        d_eq * 1e3,
        if half { "-half" } else { "" }
    ));
    std::fs::create_dir_all(&dir).map_err(Error::io(&dir))?;
    let file = dir.join("grain.json");
    tpl.save(&file)?;
    let mut test = plan.test.clone();
    if half {
        // The rule's speed for this grain, halved.
        let probe = grain::speed_of(&test, &tpl)?;
        test.speed = Some(0.5 * probe);
    }
    let o = grain::run(&test, &file, &dir, &mut |_, _| {}).map_err(|e| Error::within(grain, e))?;
    let r = &o.result;
    let pieces = |s: &grain::StageFacts| Pieces {
        broken_links: s.broken_links,
        fragments: s.fragments.fragments,
        fines: s.fragments.fines,
        largest_mass_fraction: s.fragments.largest_mass_fraction,
        fines_mass_fraction: s.fragments.fines_mass_fraction,
        d_eq: s.fragments.d_eq.clone(),
    };
    Ok(Row {
        grain: grain.to_string(),
        d_eq,
        d: r.grain.d,
        nodes: r.grain.nodes,
        links: r.grain.links,
        strength: r.strength,
        peak_force: r.peak_force,
        closure_at_peak_over_d: r.closure_at_peak / r.grain.d,
        platen_speed: r.platen_speed,
        kinetic_over_strain_at_peak: r.kinetic_over_strain_at_peak,
        balance_error: r.balance_error,
        stage1: pieces(&r.stage1),
        stage2: pieces(&r.stage2),
        steps: o.runs[0].steps + o.runs[1].steps,
        wall_time_s: o.runs[0].wall_time_s + o.runs[1].wall_time_s,
        particle_steps_per_s: r.particle_steps_per_s,
        half_speed: half,
    })
}

/// Runs the plan into `runs/` (one folder a run) and fits.
pub fn run(plan: &Plan, data: &Path, runs: &Path, progress: &dyn Fn(&str)) -> Results {
    let t0 = std::time::Instant::now();
    let mut rows = vec![];
    let mut errors = vec![];
    let mut jobs: Vec<(String, f64, bool)> = vec![];
    for &d in &plan.sizes {
        for g in &plan.grains {
            jobs.push((g.clone(), d, false));
        }
    }
    for g in &plan.half_speed {
        jobs.push((g.clone(), plan.sizes[0], true));
    }
    for (g, d, half) in jobs {
        match run_one(plan, data, runs, &g, d, half) {
            Ok(r) => {
                progress(&format!(
                    "crush {g} d_eq {:.0} mm{}: σ = {:.1} MPa, {} nodes, {:.2} s",
                    d * 1e3,
                    if half { " (half speed)" } else { "" },
                    r.strength * 1e-6,
                    r.nodes,
                    r.wall_time_s
                ));
                rows.push(r);
            }
            Err(e) => {
                progress(&format!("crush {g} d_eq {:.0} mm: {e}", d * 1e3));
                errors.push(format!("{g} at d_eq {:.0} mm: {e}", d * 1e3));
            }
        }
    }
    fit(plan.clone(), rows, errors, t0.elapsed().as_secs_f64())
}

/// [`run`] with its run folders in a temporary folder, removed after; progress on stderr.
pub fn run_in_temp(plan: &Plan, data: &Path) -> Results {
    let runs: PathBuf = std::env::temp_dir().join(format!("dem-crush-runs-{}", std::process::id()));
    let r = run(plan, data, &runs, &|l| eprintln!("  {l}"));
    let _ = std::fs::remove_dir_all(&runs);
    r
}

/// The fits of the rows (see [`Results`]).
pub fn fit(plan: Plan, rows: Vec<Row>, errors: Vec<String>, total_wall_time_s: f64) -> Results {
    let main: Vec<&Row> = rows.iter().filter(|r| !r.half_speed).collect();
    let sizes: Vec<SizeFit> = plan
        .sizes
        .iter()
        .map(|&d| {
            let s: Vec<f64> = main
                .iter()
                .filter(|r| r.d_eq == d)
                .map(|r| r.strength)
                .collect();
            SizeFit {
                d_eq: d,
                n: s.len(),
                mean: if s.is_empty() {
                    0.0
                } else {
                    s.iter().sum::<f64>() / s.len() as f64
                },
                weibull: weibull_fit(&s),
            }
        })
        .collect();
    let fitted: Vec<&SizeFit> = sizes.iter().filter(|s| s.weibull.is_some()).collect();
    let size_effect = power_law_fit(
        &fitted.iter().map(|s| s.d_eq).collect::<Vec<_>>(),
        &fitted
            .iter()
            .map(|s| s.weibull.map_or(0.0, |w| w.sigma0))
            .collect::<Vec<_>>(),
    );
    let with_mean: Vec<&SizeFit> = sizes.iter().filter(|s| s.n > 0).collect();
    let size_effect_mean = power_law_fit(
        &with_mean.iter().map(|s| s.d_eq).collect::<Vec<_>>(),
        &with_mean.iter().map(|s| s.mean).collect::<Vec<_>>(),
    );
    let pooled_weibull = size_effect.and_then(|p| {
        let s: Vec<f64> = main
            .iter()
            .map(|r| r.strength * (4e-3 / r.d_eq).powf(p.exponent))
            .collect();
        weibull_fit(&s)
    });
    let half_speed = rows
        .iter()
        .filter(|r| r.half_speed)
        .filter_map(|h| {
            main.iter()
                .find(|r| r.grain == h.grain && r.d_eq == h.d_eq)
                .map(|r| (h.grain.clone(), h.d_eq, r.strength, h.strength))
        })
        .collect();
    Results {
        plan,
        rows,
        errors,
        sizes,
        size_effect,
        size_effect_mean,
        pooled_weibull,
        half_speed,
        total_wall_time_s,
    }
}

/// The committed results (`<out>/crush/results.json`) when their plan is `plan`, else a run.
pub fn results(plan: &Plan, data: &Path, out: &Path) -> Result<Results> {
    let file = out.join("crush").join("results.json");
    if let Ok(text) = std::fs::read_to_string(&file) {
        if let Ok(r) = serde_json::from_str::<Results>(&text) {
            if &r.plan == plan {
                eprintln!("  crush: results read back from {}", file.display());
                return Ok(r);
            }
        }
    }
    let r = run_in_temp(plan, data);
    std::fs::create_dir_all(out.join("crush")).map_err(Error::BareIo)?;
    crate::page::write(&out.join("crush"), "results.json", &json(&r))?;
    Ok(r)
}

fn mpa(v: f64) -> String {
    format!("{:.1}", v * 1e-6)
}

/// A size's first table cells: d_eq (mm), runs, mean σ, Weibull m, σ0 (MPa), R².
fn size_cells(s: &SizeFit) -> String {
    format!(
        "| {:.0} | {} | {} | {} | {} | {} |",
        s.d_eq * 1e3,
        s.n,
        mpa(s.mean),
        s.weibull
            .map_or("–".into(), |w| format!("{:.2}", w.modulus)),
        s.weibull.map_or("–".into(), |w| mpa(w.sigma0)),
        s.weibull.map_or("–".into(), |w| format!("{:.3}", w.r2)),
    )
}

/// Cumulative mass fraction passing against d_frag/d_eq, over the grains of size `d`.
fn grading(rows: &[&Row], stage: impl Fn(&Row) -> &Pieces) -> Vec<(f64, f64)> {
    // Pieces: (size over d_eq, mass fraction of its grain / number of grains).
    let n = rows.len().max(1) as f64;
    let mut pieces: Vec<(f64, f64)> = vec![];
    for r in rows {
        let p = stage(r);
        for &d in &p.d_eq {
            let m = (d / r.d_eq).powi(2); // area fraction = mass fraction
            pieces.push((d / r.d_eq, m / n));
        }
        if p.fines > 0 {
            // The fines: single nodes, each of size about that of one node's cell.
            let each = p.fines_mass_fraction / p.fines as f64;
            for _ in 0..p.fines {
                pieces.push((each.sqrt(), each / n));
            }
        }
    }
    pieces.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut acc = 0.0;
    pieces
        .into_iter()
        .map(|(x, m)| {
            acc += m;
            (x, acc)
        })
        .collect()
}

/// Each run's strength against its size (the main runs) and the fitted σ0 ∝ d_eq^b.
fn strength_size_svg(r: &Results, title: &str) -> Result<String> {
    let mut series = vec![];
    let mut only = vec![];
    for &d in &r.plan.sizes {
        series.push(Series {
            name: format!("σ, d_eq {:.0} mm", d * 1e3),
            points: r
                .rows
                .iter()
                .filter(|x| x.d_eq == d && !x.half_speed)
                .map(|x| (x.d, x.strength * 1e-6))
                .collect(),
        });
        only.push(true);
    }
    if let Some(p) = r.size_effect {
        series.push(Series {
            name: format!("σ0 ∝ d_eq^{:.3}", p.exponent),
            points: r
                .sizes
                .iter()
                .map(|s| (s.d_eq, p.prefactor * s.d_eq.powf(p.exponent) * 1e-6))
                .collect(),
        });
        only.push(false);
    }
    plot::scatter_and_lines(
        title,
        "d (m): platen gap at first contact; line: σ0 at d_eq",
        "σ = F/(d t) (MPa)",
        &series,
        &only,
        true,
        true,
    )
}

/// The study of real outlines ([`plan_of_folder`]) read from `<out>/crush/real/results.json`
/// when committed there (never run here: its outlines are not the project's): per size the
/// runs, mean, Weibull fit; the size exponent; the pooled modulus; a strength–size plot.
fn real_part(out: &Path) -> Result<(String, Vec<Figure>)> {
    let file = out.join("crush").join("real").join("results.json");
    let Ok(text) = std::fs::read_to_string(&file) else {
        return Ok((String::new(), vec![]));
    };
    let r: Results = serde_json::from_str(&text).map_err(Error::json(&file))?;
    let folder = r
        .plan
        .grains
        .first()
        .and_then(|g| g.split('/').next())
        .unwrap_or("?")
        .to_string();
    let mut md = format!(
        "\n### Real gravel outlines\n\nThe same study on {} real gravel outlines (evenly spaced \
         in the sorted files of the `{}` folder of the project's shared test outlines: grains segmented from field \
         photographs by segmenteverygrain, Apache-2.0; not copied into the project, so the \
         study is made by hand with `validation/examples/crush_real.rs` and its results \
         committed in `crush/real/results.json`): d_eq = {} mm, the lattice, material and \
         speed rule above. {} runs, {} errors, {:.0} s.\n\n\
         | d_eq (mm) | runs | mean σ (MPa) | Weibull m | σ0 (MPa) | R² |\n|---|---|---|---|---|---|\n",
        r.plan.grains.len(),
        folder,
        r.plan
            .sizes
            .iter()
            .map(|d| format!("{:.0}", d * 1e3))
            .collect::<Vec<_>>()
            .join(", "),
        r.rows.len(),
        r.errors.len(),
        r.total_wall_time_s
    );
    for s in &r.sizes {
        md += &format!("{}\n", size_cells(s));
    }
    if let (Some(p), Some(q)) = (r.size_effect, r.size_effect_mean) {
        md += &format!(
            "\nSize effect: σ0 ∝ d^{:.3} (R² {:.4}), mean σ ∝ d^{:.3} (R² {:.4}).",
            p.exponent, p.r2, q.exponent, q.r2
        );
    }
    if let Some(w) = r.pooled_weibull {
        md += &format!(
            " All {} strengths scaled to 4 mm by that exponent: Weibull m = {:.2} (R² {:.3}).",
            w.n, w.modulus, w.r2
        );
    }
    md += "\n";
    if !r.errors.is_empty() {
        md += &format!(
            "\nRuns that failed (the reasons in `crush/real/results.json`): {}.\n",
            r.errors
                .iter()
                .map(|e| e.split(':').next().unwrap_or(e).to_string())
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    let svg = strength_size_svg(
        &r,
        &format!(
            "Crushing strength against grain size ({} real gravel outlines)",
            r.plan.grains.len()
        ),
    )?;
    Ok((
        md,
        vec![Figure {
            file: "crush_real_strength_size.svg".into(),
            caption: "Crushing strength of real gravel outlines against their size, and the fitted σ0 ∝ d^b".into(),
            svg,
        }],
    ))
}

/// The section.
pub fn section(data: &Path, out: &Path, quick: bool) -> Result<Section> {
    let plan = plan(data, quick)?;
    let r = results(&plan, data, out)?;
    let main: Vec<&Row> = r.rows.iter().filter(|x| !x.half_speed).collect();
    let mut md = String::new();
    md +=
        &format!(
        "Single-grain crushing between two platens (`dem test crush`, docs/lattice.md §4): the \
         {} synthetic outlines of `data/outlines` scaled to d_eq = {} mm, each filled with a \
         lattice of spacing S = {} R_eq (R_eq/S = {:.1}; nodes of radius {} S/2), E = {} GPa, \
         ν = {}, ρ = {} kg/m³, energy criterion G_c = 30 J/m², platens with friction {}, speed \
         by the quasi-static rule (factor {}). σ = F_peak/(d·t) with d the platen gap at first \
         contact; F_peak the largest platen force before the first major breakage (the largest \
         fragment below {} % of the mass). {} runs, {} errors, {:.0} s in all on this 2-core VM \
         (one core).\n\n",
        plan.grains.len(),
        plan.sizes.iter().map(|d| format!("{:.0}", d * 1e3)).collect::<Vec<_>>().join(", "),
        plan.spacing_of_req,
        1.0 / plan.spacing_of_req,
        plan.node_radius,
        plan.test.young * 1e-9,
        plan.test.poisson,
        plan.test.density,
        plan.test.platen_friction,
        plan.test.quasi_static_factor,
        plan.test.major * 100.0,
        r.rows.len(),
        r.errors.len(),
        r.total_wall_time_s
    );
    md += "| d_eq (mm) | runs | mean σ (MPa) | Weibull m | σ0 (MPa) | R² | mean nodes | mean steps | mean run time (s) | particle-steps/s |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for s in &r.sizes {
        let rs: Vec<&&Row> = main.iter().filter(|x| x.d_eq == s.d_eq).collect();
        let n = rs.len().max(1) as f64;
        let mean = |f: &dyn Fn(&Row) -> f64| rs.iter().map(|x| f(x)).sum::<f64>() / n;
        md += &format!(
            "{} {:.0} | {:.0} | {:.2} | {:.2e} |\n",
            size_cells(s),
            mean(&|x| x.nodes as f64),
            mean(&|x| x.steps as f64),
            mean(&|x| x.wall_time_s),
            mean(&|x| x.particle_steps_per_s)
        );
    }
    if let (Some(p), Some(q)) = (r.size_effect, r.size_effect_mean) {
        md += &format!(
            "\nSize effect: σ0 ∝ d^{:.3} (R² {:.4}), mean σ ∝ d^{:.3} (R² {:.4}); the energy \
             criterion on geometrically similar lattices predicts −1/2 exactly (module docs \
             of `validation/src/crush.rs`).",
            p.exponent, p.r2, q.exponent, q.r2
        );
    }
    if let Some(w) = r.pooled_weibull {
        md += &format!(
            " All {} strengths scaled to 4 mm by that exponent: Weibull m = {:.2} (R² {:.3}). \
             This m is the scatter of the 29 shapes (and of the crushing path each takes), not \
             of flaws: the lattice is regular and the criterion has no random strength.\n",
            w.n, w.modulus, w.r2
        );
    }
    if !r.half_speed.is_empty() {
        md += "\nQuasi-static check, the rule's platen speed against half of it:\n\n| grain | d_eq (mm) | σ (MPa) | σ at half speed (MPa) | change |\n|---|---|---|---|---|\n";
        for (g, d, a, b) in &r.half_speed {
            md += &format!(
                "| {g} | {:.0} | {} | {} | {:+.1} % |\n",
                d * 1e3,
                mpa(*a),
                mpa(*b),
                100.0 * (b / a - 1.0)
            );
        }
        let ks = main
            .iter()
            .map(|x| x.kinetic_over_strain_at_peak)
            .fold(0.0, f64::max);
        let be = main
            .iter()
            .map(|x| x.balance_error.abs())
            .fold(0.0, f64::max);
        md += &format!(
            "\nKinetic over strain energy at the peak: at most {ks:.2e} over the runs; largest \
             energy-balance error at the end of a run {be:.2e} (relative to the work).\n"
        );
    }
    md += "\nFragments (mass fractions over the grains of each size): stage 1 = at the first \
           major breakage, stage 2 = loaded on to twice stage 1's platen closure.\n\n\
           | d_eq (mm) | stage | mean fragments (≥ 2 nodes) | mean fines | mean largest fragment | mean fines mass |\n|---|---|---|---|---|---|\n";
    for &d in &plan.sizes {
        let rs: Vec<&&Row> = main.iter().filter(|x| x.d_eq == d).collect();
        let n = rs.len().max(1) as f64;
        for (k, st) in [(1, 0), (2, 1)] {
            let p = |x: &Row| -> Pieces {
                if st == 0 {
                    x.stage1.clone()
                } else {
                    x.stage2.clone()
                }
            };
            md += &format!(
                "| {:.0} | {k} | {:.2} | {:.2} | {:.3} | {:.3} |\n",
                d * 1e3,
                rs.iter().map(|x| p(x).fragments as f64).sum::<f64>() / n,
                rs.iter().map(|x| p(x).fines as f64).sum::<f64>() / n,
                rs.iter().map(|x| p(x).largest_mass_fraction).sum::<f64>() / n,
                rs.iter().map(|x| p(x).fines_mass_fraction).sum::<f64>() / n,
            );
        }
    }
    if !r.errors.is_empty() {
        md += "\nRuns that failed:\n\n";
        for e in &r.errors {
            md += &format!("- {e}\n");
        }
    }
    // Strength against size.
    let size_svg = strength_size_svg(
        &r,
        &format!(
            "Crushing strength against grain size ({} shapes, three sizes)",
            plan.grains.len()
        ),
    )?;
    // Weibull plot.
    let mut wseries = vec![];
    for &d in &plan.sizes {
        let mut s: Vec<f64> = main
            .iter()
            .filter(|x| x.d_eq == d)
            .map(|x| x.strength)
            .collect();
        s.sort_by(f64::total_cmp);
        let p = ranks(s.len());
        wseries.push(Series {
            name: format!("d_eq {:.0} mm", d * 1e3),
            points: s
                .iter()
                .zip(&p)
                .map(|(v, p)| ((v * 1e-6).ln(), (-(1.0 - p).ln()).ln()))
                .collect(),
        });
    }
    let weibull_svg = plot::lines(
        "Weibull plot: ln(−ln(1 − P_i)) against ln σ_i, P_i = (i − 0.5)/n",
        "ln(σ / 1 MPa)",
        "ln(−ln(1 − P))",
        &wseries,
        false,
        false,
    )?;
    // Fragment grading.
    let mut gseries = vec![];
    for &d in &plan.sizes {
        let rs: Vec<&Row> = main.iter().filter(|x| x.d_eq == d).copied().collect();
        for (k, name) in [(1, "stage 1"), (2, "stage 2")] {
            let pts = if k == 1 {
                grading(&rs, |x| &x.stage1)
            } else {
                grading(&rs, |x| &x.stage2)
            };
            gseries.push(Series {
                name: format!("d_eq {:.0} mm, {name}", d * 1e3),
                points: pts,
            });
        }
    }
    let grading_svg = plot::lines(
        "Fragment grading: mass fraction finer than d_frag/d_eq",
        "d_frag / d_eq",
        "cumulative mass fraction",
        &gseries,
        true,
        false,
    )?;
    // Real outlines, from their committed results.
    let (real_md, real_figures) = real_part(out)?;
    md += &real_md;
    // The crushable column, from its committed run.
    let (column_md, column_figures) = crate::crush_column::part(out)?;
    md += &column_md;
    let mut figures = vec![
            Figure {
                file: "crush_strength_size.svg".into(),
                caption: "Crushing strength of each grain against its size, and the fitted σ0 ∝ d^b".into(),
                svg: size_svg,
            },
            Figure {
                file: "crush_weibull.svg".into(),
                caption: "Weibull plot of the strengths at each size".into(),
                svg: weibull_svg,
            },
            Figure {
                file: "crush_fragments.svg".into(),
                caption: "Fragment grading after the first major breakage (stage 1) and after the second loading stage".into(),
                svg: grading_svg,
            },
        ];
    figures.extend(real_figures);
    figures.extend(column_figures);
    Ok(Section {
        title: "Crushable grains: single-grain crushing, Weibull modulus, size effect".into(),
        markdown: md,
        figures,
        data: vec![],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Evenly spaced outlines of a folder, named relative to its parent; the report leaves
    /// the real-outline part out when no results are committed.
    #[test]
    fn a_folder_plan_samples_evenly_and_names_by_folder() {
        let dir = std::env::temp_dir().join(format!("crush-plan-{}", std::process::id()));
        let grains = dir.join("gravel");
        std::fs::create_dir_all(&grains).unwrap();
        for i in 0..10 {
            std::fs::write(grains.join(format!("g-{i:02}.csv")), "x,y\n").unwrap();
        }
        std::fs::write(grains.join("notes.txt"), "not an outline").unwrap();
        let p = plan_of_folder(&grains, 3).unwrap();
        assert_eq!(
            p.grains,
            vec!["gravel/g-00.csv", "gravel/g-03.csv", "gravel/g-06.csv"]
        );
        assert!(p.half_speed.is_empty());
        assert_eq!(p.sizes, vec![2e-3, 4e-3, 8e-3]);
        assert_eq!(plan_of_folder(&grains, 50).unwrap().grains.len(), 10);
        assert!(plan_of_folder(&dir.join("none"), 3)
            .unwrap_err()
            .to_string()
            .contains("none"));
        let (md, figures) = real_part(&dir).unwrap();
        assert!(md.is_empty() && figures.is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
