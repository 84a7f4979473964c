//! Cutting studies: variants of the cutting test (tool model, damping, speed, ...) run on the
//! Table 2 specimens, reduced so that one command decides a model change on two cores (issue
//! 19's inner loop: e.g. L = 5 mm, a_p = 1 mm, 2 seeds). A study file
//! (`data/studies/*.json`) names the variants, each a set of [`CuttingTest`] fields (SI, as in
//! `cutting.result.json`; those left out are today's defaults) on the full Table 2 plan's
//! specimens; every variant runs on every method, depth, speed and seed. The study is typed
//! jobs, run as the cases of a `dem sweep` folder ([`crate::cutting_runs::run_jobs`]), so a
//! finished run is read back, not run again, and a failed one does not stop the others.
//!
//! Per run the study reports what the decisions need: the mean main force over the
//! steady window and over its first and second half (does the force grow along the cut?), the
//! raw peak and the peak of a moving mean over one a_p of travel, the energy split of the
//! tool's work (local/viscous damping, friction, bond breakage, kinetic energy left), the
//! machined surface and residual cracks, chips, time step, steps and CPU time.

use crate::cutting_runs::{outcome, Source};
use crate::cutting_runs::{Job, Plan};
use crate::error::{Error, Result};
use dem_lab::analysis::moving_mean_peak;
use dem_lab::cutting::{CuttingResult, CuttingTest};
use dem_lab::specimen::{Method, SpecimenParams};
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use std::fmt::Write as _;
use std::path::Path;

/// A study file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Cut length L (mm).
    pub length_mm: f64,
    pub depths_mm: Vec<f64>,
    pub speeds_m_s: Vec<f64>,
    /// traditional | orc | improved.
    pub methods: Vec<String>,
    pub seeds: Vec<u64>,
    pub variants: Vec<Variant>,
}

/// One variant: [`CuttingTest`] fields; those it leaves out are today's defaults, read as a
/// `--params` file is ([`CuttingTest::from_params`]). Depth, speed and length are the study's.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variant {
    pub name: String,
    #[serde(default)]
    pub test: Map<String, Value>,
}

impl Variant {
    /// The variant's test (depth, speed and length still to be set); an error names the study
    /// file's variant and field.
    fn test(&self, study: &str) -> Result<CuttingTest> {
        let field = |f: &str, reason: String| Error::Field {
            file: format!("study {study}"),
            field: format!(
                "variants.{}.test{}{f}",
                self.name,
                if f.is_empty() { "" } else { "." }
            ),
            reason,
        };
        for f in ["depth", "speed", "length"] {
            if self.test.contains_key(f) {
                return Err(field(
                    f,
                    "is the study's (depths_mm, speeds_m_s, length_mm)".into(),
                ));
            }
        }
        CuttingTest::from_params(&Value::Object(self.test.clone()).to_string())
            .map_err(|e| field("", e.to_string()))
    }
}

pub use crate::study_row::Row;

impl StudySpec {
    pub fn read(path: &Path) -> Result<StudySpec> {
        let text = std::fs::read_to_string(path).map_err(Error::io(path))?;
        let s: StudySpec = serde_json::from_str(&text).map_err(Error::json(path))?;
        let f = |field: &str, why: &str| {
            Err(Error::Field {
                file: path.display().to_string(),
                field: field.to_string(),
                reason: why.to_string(),
            })
        };
        if s.name.is_empty() || s.name.contains(['/', '\\']) {
            return f("name", "must be a plain folder name");
        }
        if !(s.length_mm > 0.0 && s.length_mm.is_finite()) {
            return f("length_mm", "must be positive");
        }
        for (k, v) in [
            ("depths_mm", s.depths_mm.len()),
            ("speeds_m_s", s.speeds_m_s.len()),
            ("methods", s.methods.len()),
            ("seeds", s.seeds.len()),
            ("variants", s.variants.len()),
        ] {
            if v == 0 {
                return f(k, "is empty");
            }
        }
        for m in &s.methods {
            if Method::parse(m).is_none() {
                return f("methods", &format!("unknown method {m:?}"));
            }
        }
        let mut names = std::collections::BTreeSet::new();
        for v in &s.variants {
            if !names.insert(&v.name) || v.name.contains(['/', '\\']) || v.name.is_empty() {
                return f(
                    "variants",
                    &format!("{:?}: names must be distinct folder names", v.name),
                );
            }
        }
        Ok(s)
    }

    /// The jobs: variants × methods × depths × speeds × seeds, on the full Table 2 plan's
    /// specimens and model.
    pub fn jobs(&self, data: &Path) -> Result<Vec<Job>> {
        self.jobs_on(&crate::table2_section::plan(data, false)?)
    }

    /// The jobs on `plan`'s specimen and model (its methods, depths, speeds, seeds and test
    /// are not used: the study gives its own).
    pub fn jobs_on(&self, plan: &Plan) -> Result<Vec<Job>> {
        let mut jobs = vec![];
        for v in &self.variants {
            for m in &self.methods {
                let method = Method::parse(m).expect("checked by read");
                for &d in &self.depths_mm {
                    for &sp in &self.speeds_m_s {
                        for &seed in &self.seeds {
                            let mut spec: SpecimenParams = plan.specimen.clone();
                            spec.method = method;
                            spec.seed = seed;
                            crate::cutting_runs::normalize_grains(&mut spec);
                            let mut test = v.test(&self.name)?;
                            test.depth = d * 1e-3;
                            test.speed = sp;
                            test.length = self.length_mm * 1e-3;
                            test.validate()
                                .map_err(|e| Error::within(format!("variant {}", v.name), e))?;
                            jobs.push(Job {
                                name: format!(
                                    "{}-{}-d{}-v{}-s{seed}",
                                    v.name,
                                    method.name(),
                                    d,
                                    sp
                                ),
                                specimen: spec,
                                model: plan.model.clone(),
                                test,
                            });
                        }
                    }
                }
            }
        }
        Ok(jobs)
    }
}

/// Mean of `f` over samples with abscissa in [a, b].
fn window_mean(x: &[f64], f: &[f64], a: f64, b: f64) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for (xi, fi) in x.iter().zip(f) {
        if *xi >= a && *xi <= b {
            s += fi;
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        s / n as f64
    }
}

/// The row of one finished run in `dir`.
pub fn row(variant: &str, job: &Job, res: &CuttingResult, dir: &Path, cpu: Option<f64>) -> Row {
    let (x, f) = crate::force_statistics::main_force(&dir.join(dem_lab::cutting::FORCES_FILE))
        .unwrap_or_default();
    let [a, b] = res.window;
    let mid = 0.5 * (a + b);
    let energy = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .map(|v| v["energy"].clone())
        .unwrap_or(Value::Null);
    let e = |k: &str| energy[k].as_f64().unwrap_or(f64::NAN);
    Row {
        variant: variant.into(),
        method: job.specimen.method.name().into(),
        depth_mm: job.test.depth * 1e3,
        speed_m_s: job.test.speed,
        seed: job.specimen.seed,
        discs: res.discs,
        mean_n: res.main_force.mean,
        mean_first_half_n: window_mean(&x, &f, a, mid),
        mean_second_half_n: window_mean(&x, &f, mid, b),
        contact_share: window_mean(
            &x,
            &f.iter()
                .map(|v| f64::from(u8::from(*v != 0.0)))
                .collect::<Vec<_>>(),
            a,
            b,
        ),
        peak_raw_n: res.main_force.peak,
        peak_ap_n: moving_mean_peak(&x, &f, a, b, job.test.depth),
        work_j: e("boundary_work"),
        damping_j: e("damping"),
        friction_j: e("friction"),
        bond_break_j: e("bond_break"),
        kinetic_j: e("kinetic_translation") + e("kinetic_rotation"),
        broken_bonds: res.broken_total,
        chips: res.chips.chips.count,
        chip_discs: res.chips.chips.discs,
        loose_below: res.chips.loose_below_surface.count,
        surface_mean_dev_m: res.surface.as_ref().map(|s| s.mean_deviation),
        surface_ra_m: res
            .surface
            .as_ref()
            .and_then(|s| s.roughness())
            .map(|m| m.ra),
        residual_cracks: res.residual_cracks.count,
        deepest_crack_m: res.residual_cracks.deepest,
        single_grain_share: res.removal.as_ref().map(|m| m.single_grain_share),
        chip_speed_mean: res.removal.as_ref().map(|m| m.chip_speed_mean),
        chip_speed_max: res.removal.as_ref().map(|m| m.chip_speed_max),
        max_overlap_fraction: res.run.max_overlap_fraction,
        dt_s: res.run.dt,
        steps: res.run.steps,
        cpu_s: cpu,
        wall_s: res.run.wall_time_s,
    }
}

/// Runs a study into `out/<name>/` (or reads its runs from a sweep folder: `source`) and
/// writes `study.json` (rows) and `study.md` (per variant, method, depth and speed: seed means
/// and standard errors). Returns the rows and the errors.
pub fn run(
    spec: &StudySpec,
    data: &Path,
    out: &Path,
    source: Source,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<(Vec<Row>, Vec<String>)> {
    let plan = crate::table2_section::plan(data, false)?;
    run_on(spec, &plan, out, source, progress)
}

/// [`run`] on `plan`'s specimen and model ([`StudySpec::jobs_on`]).
pub fn run_on(
    spec: &StudySpec,
    plan: &Plan,
    out: &Path,
    source: Source,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<(Vec<Row>, Vec<String>)> {
    let jobs = spec.jobs_on(plan)?;
    let dir = out.join(&spec.name);
    let work = dir.join("runs");
    progress(&format!(
        "study {}: {} runs into {}",
        spec.name,
        jobs.len(),
        work.display()
    ));
    let o = outcome(&jobs, &work, source, progress)?;
    let mut rows = vec![];
    for fin in &o.finished {
        let Some(job) = jobs.iter().find(|j| j.name == fin.name) else {
            continue;
        };
        let variant = spec
            .variants
            .iter()
            .find(|v| fin.name.starts_with(&format!("{}-", v.name)))
            .map_or("?", |v| v.name.as_str());
        rows.push(row(
            variant,
            job,
            &fin.result,
            &fin.dir,
            fin.record.cpu_time_s,
        ));
    }
    let json = serde_json::to_string_pretty(&serde_json::json!({
        "study": spec, "rows": rows, "errors": o.errors, "not_run": o.missing}))
    .map_err(Error::Serialize)?;
    crate::page::write(&dir, "study.json", &json)?;
    let mut md = markdown(spec, &rows, &o.errors);
    if !o.missing.is_empty() {
        let _ = writeln!(
            md,
            "\n**Not run yet** ({} of the study's {} runs{}): {}",
            o.missing.len(),
            jobs.len(),
            match source {
                Source::Sweep(d) => format!("; not done in the sweep `{}`", d.display()),
                Source::Here(_) => String::new(),
            },
            o.missing.join(", ")
        );
    }
    md.push('\n');
    md.push_str(&crate::study_findings::markdown(&rows, &spec.speeds_m_s));
    let dir_of = |name: &str| {
        o.finished
            .iter()
            .find(|f| f.name == name)
            .map(|f| f.dir.clone())
    };
    for (file, svg) in plots(spec, &rows, &dir_of)? {
        crate::page::write(&dir, &file, &svg)?;
        let _ = writeln!(md, "\n![{file}]({file})");
    }
    crate::page::write(&dir, "study.md", &md)?;
    Ok((rows, o.errors))
}

/// Moving mean of `f` over `w` of travel, centred, at every sample (for readable plots).
fn smooth(x: &[f64], f: &[f64], w: f64) -> Vec<(f64, f64)> {
    let (mut lo, mut hi, mut sum) = (0usize, 0usize, 0.0);
    let mut out = Vec::with_capacity(x.len());
    for k in 0..x.len() {
        while hi < x.len() && x[hi] <= x[k] + 0.5 * w {
            sum += f[hi];
            hi += 1;
        }
        while x[lo] < x[k] - 0.5 * w {
            sum -= f[lo];
            lo += 1;
        }
        out.push((x[k], sum / (hi - lo) as f64));
    }
    out
}

/// The study's pictures: per method, depth and speed the main force of the first seed
/// against travel (moving mean over a_p), one line per variant (`forces-<method>-d<a_p>-v<v>.svg`);
/// with several speeds, the seed-mean window force against speed, one line per variant and
/// method (`speed.svg`).
pub fn plots(
    spec: &StudySpec,
    rows: &[Row],
    dir_of: &dyn Fn(&str) -> Option<std::path::PathBuf>,
) -> Result<Vec<(String, String)>> {
    use crate::plot::{lines, Series};
    let mut out = vec![];
    let seed = spec.seeds[0];
    for m in &spec.methods {
        let Some(method) = Method::parse(m) else {
            continue;
        };
        for &d in &spec.depths_mm {
            for &v in &spec.speeds_m_s {
                let mut series = vec![];
                for var in &spec.variants {
                    let run = format!("{}-{}-d{}-v{}-s{seed}", var.name, method.name(), d, v);
                    let file = dir_of(&run).map(|d| d.join(dem_lab::cutting::FORCES_FILE));
                    if let Some((x, f)) = file.and_then(|f| crate::force_statistics::main_force(&f))
                    {
                        let pts = smooth(&x, &f, d * 1e-3)
                            .into_iter()
                            .map(|(a, b)| (a * 1e3, b * 1e-3))
                            .collect();
                        series.push(Series {
                            name: var.name.clone(),
                            points: pts,
                        });
                    }
                }
                if series.is_empty() {
                    continue;
                }
                let title = format!(
                    "{}: {}, a_p = {d} mm, v = {v} m/s, seed {seed} (moving mean over a_p)",
                    spec.name,
                    method.name()
                );
                let svg = lines(
                    &title,
                    "tool travel (mm)",
                    "main force (kN/m)",
                    &series,
                    false,
                    false,
                )?;
                out.push((format!("forces-{}-d{d}-v{v}.svg", method.name()), svg));
            }
        }
    }
    if spec.speeds_m_s.len() > 1 {
        let mut series = vec![];
        for var in &spec.variants {
            for m in &spec.methods {
                let Some(method) = Method::parse(m) else {
                    continue;
                };
                let mut pts = vec![];
                for &v in &spec.speeds_m_s {
                    let g: Vec<f64> = rows
                        .iter()
                        .filter(|r| {
                            r.variant == var.name && r.method == method.name() && r.speed_m_s == v
                        })
                        .map(|r| r.mean_n * 1e-3)
                        .collect();
                    if !g.is_empty() {
                        pts.push((v, g.iter().sum::<f64>() / g.len() as f64));
                    }
                }
                if !pts.is_empty() {
                    series.push(Series {
                        name: format!("{} {}", var.name, method.name()),
                        points: pts,
                    });
                }
            }
        }
        let svg = lines(
            &format!(
                "{}: mean main force against cutting speed (seed mean)",
                spec.name
            ),
            "cutting speed (m/s)",
            "mean main force (kN/m)",
            &series,
            true,
            false,
        )?;
        out.push(("speed.svg".into(), svg));
    }
    Ok(out)
}

/// Mean and standard error of the mean.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    if v.len() < 2 {
        return (m, f64::NAN);
    }
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// The study's table: one line per variant, method, depth and speed.
pub fn markdown(spec: &StudySpec, rows: &[Row], errors: &[String]) -> String {
    let mut s = format!(
        "# Study `{}`\n\n{}\n\nL = {} mm; seeds {:?}. Forces in N at the runs' thickness (the \
         calibrated model's t, 1 m: N per metre of thickness; Table 2's fitted t scales them \
         afterwards). Energies as shares of the walls' work W (tool and slot). Means over the \
         seeds ± standard error.\n\n",
        spec.name, spec.description, spec.length_mm, spec.seeds
    );
    s.push_str(
        "| variant | method | a_p | v | runs | mean (N) | 2nd/1st half | raw peak/mean | \
         a_p-peak/mean | damping/W | friction/W | breakage/W | kinetic/W | broken | surface \
         dev (mm) | Ra (mm) | cracks | single-grain chip share | chip speed / v | max overlap | \
         dt (ns) | steps (M) | CPU (s) |\n",
    );
    s.push_str(&"|---".repeat(23));
    s.push_str("|\n");
    let mut keys: Vec<(String, String, f64, f64)> = vec![];
    for r in rows {
        let k = (r.variant.clone(), r.method.clone(), r.depth_mm, r.speed_m_s);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    for (v, m, d, sp) in keys {
        let g: Vec<&Row> = rows
            .iter()
            .filter(|r| r.variant == v && r.method == m && r.depth_mm == d && r.speed_m_s == sp)
            .collect();
        let col = |f: &dyn Fn(&Row) -> f64| -> Vec<f64> {
            g.iter().map(|r| f(r)).filter(|x| x.is_finite()).collect()
        };
        let ms = |f: &dyn Fn(&Row) -> f64, scale: f64, digits: usize| {
            let v = col(f);
            if v.is_empty() {
                return "–".to_string();
            }
            let (m, se) = mean_se(&v);
            if se.is_finite() {
                format!("{:.*} ± {:.*}", digits, m * scale, digits, se * scale)
            } else {
                format!("{:.*}", digits, m * scale)
            }
        };
        let _ = writeln!(
            s,
            "| {v} | {m} | {d} | {sp} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            g.len(),
            ms(&|r| r.mean_n, 1.0, 0),
            ms(&|r| r.mean_second_half_n / r.mean_first_half_n, 1.0, 2),
            ms(&|r| r.peak_raw_n / r.mean_n, 1.0, 1),
            ms(&|r| r.peak_ap_n.unwrap_or(f64::NAN) / r.mean_n, 1.0, 2),
            ms(&|r| r.damping_j / r.work_j, 1.0, 2),
            ms(&|r| r.friction_j / r.work_j, 1.0, 2),
            ms(&|r| r.bond_break_j / r.work_j, 1.0, 3),
            ms(&|r| r.kinetic_j / r.work_j, 1.0, 3),
            ms(&|r| r.broken_bonds as f64, 1.0, 0),
            ms(&|r| r.surface_mean_dev_m.unwrap_or(f64::NAN), 1e3, 2),
            ms(&|r| r.surface_ra_m.unwrap_or(f64::NAN), 1e3, 2),
            ms(&|r| r.residual_cracks as f64, 1.0, 1),
            ms(&|r| r.single_grain_share.unwrap_or(f64::NAN), 1.0, 2),
            ms(&|r| r.chip_speed_mean.unwrap_or(f64::NAN) / r.speed_m_s, 1.0, 2),
            ms(&|r| r.max_overlap_fraction.unwrap_or(f64::NAN), 1.0, 3),
            ms(&|r| r.dt_s, 1e9, 2),
            ms(&|r| r.steps as f64, 1e-6, 2),
            ms(&|r| r.cpu_s.unwrap_or(f64::NAN), 1.0, 0),
        );
    }
    if !errors.is_empty() {
        s.push_str("\nErrors:\n\n");
        for e in errors {
            let _ = writeln!(s, "- {e}");
        }
    }
    s
}
