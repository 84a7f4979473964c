//! Writes the report folder: `index.md`, a self-contained `index.html`, SVG plots and the JSON
//! behind every table and plot. Sections run in order; each is one module of this crate.

use crate::cutting_runs::Reused;
use crate::environment::Environment;
use crate::error::{Error, Result};
use crate::page::{json, write_report, Figure, Section};
use crate::plot::{self, Series};
use crate::{clump_sweep, table1};
use clumpgen::ClumpParams;
use std::path::PathBuf;
use std::time::Instant;

/// What to run and where.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// The project's `data/` folder.
    pub data: PathBuf,
    /// Output folder.
    pub out: PathBuf,
    /// Cover targets of the clump sweep.
    pub covers: Vec<f64>,
    /// Timing repeats per grain in the sweep.
    pub repeats: usize,
    /// Quick mode (CI): 1 seed, short cut, coarse specimens.
    pub quick: bool,
    /// Run only these sections ([`SECTIONS`] names); empty: all.
    pub only: Vec<String>,
    /// Part of the Table 2 plan to run (default: all of it).
    pub table2: crate::table2_section::Subset,
    /// Cutting runs (Table 2, convergence) not finished in `out` yet: run them, or only list
    /// them (a report of what is done so far).
    pub missing: crate::cutting_runs::Missing,
    /// Table 2's runs from this `dem sweep` folder instead of run here.
    pub sweep: Option<PathBuf>,
    /// The committed pictures of the specimens and cuts (`docs/pictures`, made by
    /// `scripts/cut-pictures.sh`).
    pub pictures: PathBuf,
}

/// Section names, in the order they run.
pub const SECTIONS: [&str; 10] = [
    "table1",
    "sweep",
    "table2",
    "damping",
    "table3",
    "pictures",
    "convergence",
    "stability",
    "crush",
    "chung-ooi",
];

/// What one section hands to the later ones.
#[derive(Debug, Default)]
pub struct Shared {
    /// N at the run thickness → kN at the Table 2 fitted thickness.
    pub force_scale: Option<f64>,
    /// Finished runs read back instead of run now (see [`Environment::reused`]).
    pub reused: Reused,
    /// One line per section that can say what holds, for the summary at the top.
    pub summary: Vec<String>,
}

/// The specimens and one cut of each, as pictures (committed PNGs, see [`crate::pictures`]).
/// Issue 47's contracts and trends, read from the committed studies under `<out>/studies`.
fn damping_section(o: &ReportOptions, _: &mut Shared) -> Result<Section> {
    Ok(crate::damping_studies::section(&o.out))
}

fn pictures_section(o: &ReportOptions, _: &mut Shared) -> Result<Section> {
    Ok(crate::pictures::section(&o.pictures))
}

/// Table 1 of Ye & Xu (2010).
fn table1_section(o: &ReportOptions, _: &mut Shared) -> Result<Section> {
    let t1 = table1::table1(
        &o.data.join("outlines/table1-grain.csv"),
        &o.data.join("reference/ye_xu_2010_table1.json"),
        &ClumpParams::default(),
    )?;
    Ok(Section {
        title: "Table 1 (Ye & Xu 2010): one grain by method".into(),
        markdown: strip_h1(&t1.markdown()),
        figures: vec![],
        data: vec![("table1.json".into(), json(&t1))],
    })
}

/// The clump-generation sweep: cover, discs and time per grain against the cover target.
fn sweep_section(o: &ReportOptions, _: &mut Shared) -> Result<Section> {
    let sw = clump_sweep::sweep(
        &o.data.join("outlines"),
        &o.covers,
        &ClumpParams::default(),
        o.repeats,
    )?;
    let cover_discs = plot::lines(
        "Clump generation: cover against discs per grain",
        "median discs per grain",
        "median area cover",
        &[Series {
            name: "median over grains".into(),
            points: sw
                .rows
                .iter()
                .map(|r| (r.median_discs, r.median_cover))
                .collect(),
        }],
        false,
        false,
    )?;
    let time = plot::lines(
        "Clump generation: boundary error against time per grain",
        "median time per grain (ms, one thread)",
        "median Hausdorff distance / R_eq",
        &[Series {
            name: "one point per cover target".into(),
            points: sw
                .rows
                .iter()
                .map(|r| (r.median_ms_per_grain, r.median_hausdorff_over_req))
                .collect(),
        }],
        false,
        true,
    )?;
    Ok(Section {
        title: "Clump generation: error against run time".into(),
        markdown: strip_h1(&sw.markdown()),
        figures: vec![
            Figure {
                file: "clump_cover_vs_discs.svg".into(),
                caption: "Area cover against the number of discs per grain (median over the outlines in data/outlines), one point per cover target".into(),
                svg: cover_discs,
            },
            Figure {
                file: "clump_error_vs_time.svg".into(),
                caption: "Boundary deviation against generation time per grain, one point per cover target".into(),
                svg: time,
            },
        ],
        data: vec![("clump_sweep.json".into(), json(&sw))],
    })
}

/// The stability suite: stiff and extreme scenes at the automatic time step, and one forced
/// above the critical step that the guard must stop.
fn stability_section(o: &ReportOptions, _: &mut Shared) -> Result<Section> {
    let st = crate::stability::run_suite(&o.out, o.quick, &mut |l| eprintln!("  {l}"))?;
    Ok(Section {
        title: "Numerical stability on stiff and extreme cases".into(),
        markdown: strip_h1(&st.to_markdown())
            + "\nThe scenes are in `stability/` (each runs with `dem run`); details and the \
               choice of bounds: `docs/stability.md`.\n",
        figures: vec![],
        data: vec![("stability.json".into(), json(&st))],
    })
}

/// Table 2: the cutting runs, the table, its plots.
fn table2_section(o: &ReportOptions, sh: &mut Shared) -> Result<Section> {
    let source = match &o.sweep {
        Some(d) => crate::cutting_runs::Source::Sweep(d),
        None => crate::cutting_runs::Source::Here(o.missing),
    };
    let (s, scale, reused, summary) =
        crate::table2_section::section(&o.data, &o.out, o.quick, &o.table2, source)?;
    sh.force_scale = Some(scale);
    sh.reused.add(reused);
    sh.summary.extend(summary);
    Ok(s)
}

/// Table 3: the granites' flexural strength ([`crate::table3`]).
fn table3_section(o: &ReportOptions, sh: &mut Shared) -> Result<Section> {
    let (s, summary) = crate::table3::section(&o.data, &o.out, o.quick, o.missing)?;
    sh.summary.push(summary);
    Ok(s)
}

/// Error against run time of the cutting run ([`crate::convergence`]).
fn convergence_section(o: &ReportOptions, sh: &mut Shared) -> Result<Section> {
    let p = crate::convergence::plan(&o.data, o.quick)?;
    let sw = crate::convergence::run(
        &p,
        &o.out.join("convergence-runs"),
        sh.force_scale,
        o.missing,
        &|l| eprintln!("  {l}"),
    )?;
    sh.reused.add(sw.reused);
    sw.section()
}

/// Crushable grains: single-grain crushing, Weibull fit, size effect ([`crate::crush`]).
fn crush_section(o: &ReportOptions, _: &mut Shared) -> Result<Section> {
    crate::crush::section(&o.data, &o.out, o.quick)
}

/// The Chung & Ooi (2011) impact benchmark ([`crate::chung_ooi`]): runs in about a second.
fn chung_ooi_section(o: &ReportOptions, sh: &mut Shared) -> Result<Section> {
    let (s, summary) = crate::chung_ooi::section(&o.data)?;
    sh.summary.push(summary);
    Ok(s)
}

/// What holds and what does not, first on the page (issue 48): the verdict line of each
/// section that has one, then the sections built and those that failed.
fn summary_section(
    quick: bool,
    lines: &[String],
    failed: &[String],
    steps: &[(&str, impl Sized)],
) -> Section {
    let mut md = String::new();
    if quick {
        md += "**Quick mode: a smoke test of the chain** (one seed, coarse specimens, short \
               cuts, a short clump sweep): it shows that every stage runs, not what the model \
               predicts. The reproduction is the committed full report, \
               `docs/report/index.md`; its Table 2 is set beside the quick one below.\n\n";
    }
    for l in lines {
        md += &format!("- {l}\n");
    }
    let built: Vec<&str> = steps
        .iter()
        .map(|(n, _)| *n)
        .filter(|n| !failed.iter().any(|f| f.starts_with(&format!("{n}:"))))
        .collect();
    md += &format!("- Sections built: {}.\n", built.join(", "));
    if !failed.is_empty() {
        md += &format!(
            "- **Sections that could not be built**: {}.\n",
            failed.join("; ")
        );
    }
    md += "\nEach section below gives its numbers, their source and how they were obtained.\n";
    Section {
        title: "Summary".into(),
        markdown: md,
        figures: vec![],
        data: vec![],
    }
}

/// Drops a leading `# ...` title line (sections get their own `##` title).
fn strip_h1(md: &str) -> String {
    match md.strip_prefix("# ") {
        Some(rest) => rest
            .split_once('\n')
            .map_or("", |x| x.1)
            .trim_start()
            .to_string(),
        None => md.to_string(),
    }
}

/// Runs every section, printing progress on stderr; writes the report; returns the Markdown.
pub fn run(o: &ReportOptions) -> Result<String> {
    let t0 = Instant::now();
    let mode = if o.quick { "quick" } else { "full" };
    let mut env = Environment::capture(mode);
    let mut sections = Vec::new();
    type Builder = fn(&ReportOptions, &mut Shared) -> Result<Section>;
    let all: [Builder; 10] = [
        table1_section,
        sweep_section,
        table2_section,
        damping_section,
        table3_section,
        pictures_section,
        convergence_section,
        stability_section,
        crush_section,
        chung_ooi_section,
    ];
    if let Some(bad) = o.only.iter().find(|n| !SECTIONS.contains(&n.as_str())) {
        return Err(Error::UnknownSection {
            name: bad.clone(),
            known: SECTIONS.iter().map(|s| s.to_string()).collect(),
        });
    }
    let steps: Vec<(&str, Builder)> = SECTIONS
        .iter()
        .zip(all)
        .filter(|(n, _)| o.only.is_empty() || o.only.iter().any(|m| m == *n))
        .map(|(n, f)| (*n, f))
        .collect();
    let mut shared = Shared::default();
    let mut failed = vec![];
    for (i, (name, f)) in steps.iter().enumerate() {
        eprintln!("[{}/{}] {name} ...", i + 1, steps.len());
        let ts = Instant::now();
        // A failed section is written as such and the others go on; the call fails at the end.
        match f(o, &mut shared) {
            Ok(s) => sections.push(s),
            Err(e) => {
                eprintln!("[{}/{}] {name}: FAILED: {e}", i + 1, steps.len());
                sections.push(Section {
                    title: format!("{name}: not available"),
                    markdown: format!("This section could not be built: {e}\n"),
                    figures: vec![],
                    data: vec![],
                });
                failed.push(format!("{name}: {e}"));
                continue;
            }
        }
        eprintln!(
            "[{}/{}] {name}: {:.1} s",
            i + 1,
            steps.len(),
            ts.elapsed().as_secs_f64()
        );
    }
    env.total_wall_time_s = t0.elapsed().as_secs_f64();
    env.reused = shared.reused;
    sections.insert(
        0,
        Section {
            title: "Environment".into(),
            markdown: env.markdown(),
            figures: vec![],
            data: vec![("environment.json".into(), json(&env))],
        },
    );
    sections.insert(
        0,
        summary_section(o.quick, &shared.summary, &failed, &steps),
    );
    let md = write_report(
        &o.out,
        "Reproducibility report: DEM of brittle-material cutting",
        &sections,
    )?;
    if failed.is_empty() {
        Ok(md)
    } else {
        Err(Error::SectionsFailed {
            out: o.out.display().to_string(),
            failed,
        })
    }
}
