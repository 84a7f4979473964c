//! Batches of grains (clump libraries): every grain becomes one template, in parallel (rayon);
//! a failed grain is recorded with its reason and never stops the others.
//!
//! A one-outline file (CSV, JSON, ...) is one grain, written to `<out>/<relative>.json`. A
//! multi-grain file (image, GeoJSON, WKT: [`crate::outline::MultiKind`]) gives one grain per
//! component, label or polygon, written to `<out>/<relative without extension>/<grain>.json`
//! ([`grain_template_path`]): a folder per file keeps the grain names of different files apart
//! and the file's grains together. [`plan`] reads the multi-grain files and lists every grain
//! with its template path; [`plan_clashes`] finds templates that collide (two grains of one
//! file with the same feature name, or a grain and a CSV outline for one path) before
//! anything is written; [`run_plan`] makes and writes the templates.

use crate::clump::{make_template, ClumpParams};
use crate::export::Format;
use crate::outline::{read_grains, read_outline, GrainOptions, MultiKind, Outline, ReadOptions};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// File endings read as outlines.
pub const OUTLINE_EXTENSIONS: [&str; 5] = ["csv", "txt", "xy", "dat", "json"];

/// One input and where its template goes (relative to the output folder).
#[derive(Debug, Clone)]
pub struct Input {
    pub path: PathBuf,
    pub relative: PathBuf,
}

/// Expands files and folders (recursively, sorted) into inputs. Each input keeps its place
/// below the folder common to all inputs, so no two inputs of different folders share a
/// template: one folder's files keep their path below it (`grain-000.csv`); files of one
/// folder keep their names; `coll/a/g.csv coll/b/g.csv` (or the folders `coll/a coll/b`) become
/// `a/g.csv` and `b/g.csv`. A file given twice (also through a folder) is read once. Inputs
/// that still map to one template (`g.csv` and `g.json` in one folder) are found by
/// [`clashes`].
pub fn collect_inputs(paths: &[PathBuf]) -> std::io::Result<Vec<Input>> {
    collect_inputs_except(paths, None)
}

/// [`collect_inputs`], not walking into the folder `out` (the batch's output folder) when it
/// lies inside an input folder: `dem clump dir --out dir/t`, run twice, would otherwise read
/// the first run's templates and summary back as outlines. A file inside `out` given by name
/// is still read.
pub fn collect_inputs_except(paths: &[PathBuf], out: Option<&Path>) -> std::io::Result<Vec<Input>> {
    let skip = out.and_then(|o| std::fs::canonicalize(o).ok());
    fn walk_folder(
        dir: &Path,
        base: &Path,
        prefix: &Path,
        skip: Option<&Path>,
        out: &mut Vec<Input>,
    ) -> std::io::Result<()> {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| named(dir, e))?
            .map(|e| e.map(|e| e.path()))
            .collect::<Result<_, _>>()
            .map_err(|e| named(dir, e))?;
        entries.sort();
        for p in entries {
            if p.is_dir() {
                if skip.is_some() && std::fs::canonicalize(&p).ok().as_deref() == skip {
                    continue;
                }
                walk_folder(&p, base, prefix, skip, out)?;
            } else if is_outline(&p) {
                let relative = prefix.join(p.strip_prefix(base).unwrap_or(&p));
                out.push(Input { path: p, relative });
            }
        }
        Ok(())
    }
    // Each input's folder: the folder itself, or a file's folder (canonical: `..`, `.` and
    // links resolved, so the common folder is a real one).
    let mut roots = Vec::with_capacity(paths.len());
    for p in paths {
        if !p.exists() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("{}: no such file or folder", p.display()),
            ));
        }
        let c = std::fs::canonicalize(p).map_err(|e| named(p, e))?;
        let root = if p.is_dir() {
            c
        } else {
            c.parent().map_or(c.clone(), Path::to_path_buf)
        };
        roots.push(root);
    }
    let common = common_folder(&roots);
    let mut out = Vec::new();
    for (p, root) in paths.iter().zip(&roots) {
        let prefix = root.strip_prefix(&common).unwrap_or(Path::new(""));
        if p.is_dir() {
            walk_folder(p, p, prefix, skip.as_deref(), &mut out)?;
        } else {
            let relative = prefix.join(p.file_name().unwrap_or_default());
            out.push(Input {
                path: p.clone(),
                relative,
            });
        }
    }
    // The same file twice (given twice, or as a file and within a folder): once.
    let mut seen = std::collections::HashSet::new();
    let mut unique = Vec::with_capacity(out.len());
    for i in out {
        let key = std::fs::canonicalize(&i.path).unwrap_or_else(|_| i.path.clone());
        if seen.insert(key) {
            unique.push(i);
        }
    }
    Ok(unique)
}

/// An I/O error with the path it concerns.
fn named(p: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("{}: {e}", p.display()))
}

/// The deepest folder containing all `paths` (absolute); `/` at worst, empty for none.
fn common_folder(paths: &[PathBuf]) -> PathBuf {
    let Some(first) = paths.first() else {
        return PathBuf::new();
    };
    let mut common = first.clone();
    for p in &paths[1..] {
        while !p.starts_with(&common) {
            if !common.pop() {
                return PathBuf::new();
            }
        }
    }
    common
}

/// The template file of a one-outline input: `<out>/<relative with .json>`.
pub fn template_path(out: &Path, input: &Input) -> PathBuf {
    out.join(input.relative.with_extension("json"))
}

/// The template file of grain `name` of a multi-grain input:
/// `<out>/<relative without extension>/<name>.json`.
pub fn grain_template_path(out: &Path, input: &Input, name: &str) -> PathBuf {
    out.join(input.relative.with_extension(""))
        .join(format!("{name}.json"))
}

/// The batch summary's file in the output folder.
pub const SUMMARY_FILE: &str = "summary.json";

/// An input whose template cannot be written: it shares its template file with another input,
/// or the template (or the batch summary) would overwrite an input file.
#[derive(Debug, Clone, PartialEq)]
pub struct Clash {
    /// The inputs (indices into the input list) not to be written.
    pub inputs: Vec<usize>,
    /// What clashes, naming the paths and the way out.
    pub message: String,
}

/// The clashes of a batch into `out` (none: every input gets its own template and no input
/// file is overwritten). [`run_batch`] writes no template of a clashing input; `dem clump`
/// refuses the whole batch.
pub fn clashes(inputs: &[Input], out: &Path) -> Vec<Clash> {
    clashes_with_exports(inputs, out, &[])
}

/// [`clashes`], and also an export ([`crate::export::Format::paths`], written beside each
/// template) that would overwrite an input file: the same rules as for templates. (Two inputs
/// never share an export unless they share a template, which is a clash already; exports never
/// end in `.json`, so no export is another input's template or the summary.)
pub fn clashes_with_exports(inputs: &[Input], out: &Path, exports: &[Format]) -> Vec<Clash> {
    let entries = input_entries(inputs, out);
    clash_core(inputs, &entries, out, exports, case_insensitive(out))
}

/// One [`Entry`] per input: its template in `out`, named by its path.
fn input_entries(inputs: &[Input], out: &Path) -> Vec<Entry> {
    inputs
        .iter()
        .enumerate()
        .map(|(k, i)| Entry {
            input: k,
            who: i.path.display().to_string(),
            dest: Some(template_path(out, i)),
        })
        .collect()
}

/// A template to be written: for input `input`, named `who` in messages.
struct Entry {
    input: usize,
    who: String,
    dest: Option<PathBuf>,
}

/// Whether the file system that holds `out` (or its nearest existing ancestor) folds case in
/// file names (macOS and Windows by default): a probe file is created there under one spelling
/// and looked up under another. False when nothing can be written there (the batch then fails
/// on its first write anyway).
fn case_insensitive(out: &Path) -> bool {
    let Some(dir) = out.ancestors().find(|a| a.is_dir()) else {
        return false;
    };
    let name = format!(".dem-case-probe-{}-Ab", std::process::id());
    let probe = dir.join(&name);
    if std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .is_err()
    {
        return false;
    }
    let folded = dir.join(name.to_lowercase()).exists();
    let _ = std::fs::remove_file(&probe);
    folded
}

/// The clashes of `entries` (indices in [`Clash::inputs`] are entry indices); with
/// `fold_case`, templates whose paths differ only in case clash too (one file there).
fn clash_core(
    inputs: &[Input],
    entries: &[Entry],
    out: &Path,
    exports: &[Format],
    fold_case: bool,
) -> Vec<Clash> {
    let mut found = Vec::new();
    let canonical = |p: &Path| std::fs::canonicalize(p).ok();
    let input_files: std::collections::HashMap<PathBuf, usize> = inputs
        .iter()
        .enumerate()
        .filter_map(|(k, i)| canonical(&i.path).map(|c| (c, k)))
        .collect();
    let summary = out.join(SUMMARY_FILE);
    let mut by_template: std::collections::HashMap<PathBuf, usize> =
        std::collections::HashMap::new();
    let mut by_folded: std::collections::HashMap<PathBuf, usize> = std::collections::HashMap::new();
    for (k, en) in entries.iter().enumerate() {
        let Some(t) = en.dest.clone() else { continue };
        if let Some(&first) = by_template.get(&t) {
            found.push(Clash {
                inputs: vec![first, k],
                message: format!(
                    "{} and {} would both be written as {}: rename one of them, or clump them \
                     into different --out folders",
                    entries[first].who,
                    en.who,
                    t.display()
                ),
            });
            continue;
        }
        by_template.insert(t.clone(), k);
        if fold_case {
            let key = PathBuf::from(t.to_string_lossy().to_lowercase());
            if let Some(&first) = by_folded.get(&key) {
                found.push(Clash {
                    inputs: vec![first, k],
                    message: format!(
                        "{} and {} would be written as {} and {}, one file on this file system, \
                         which does not tell upper from lower case: rename one of them, or \
                         clump them into different --out folders",
                        entries[first].who,
                        en.who,
                        entries[first].dest.as_deref().unwrap_or(&t).display(),
                        t.display()
                    ),
                });
                continue;
            }
            by_folded.insert(key, k);
        }
        if t == summary {
            found.push(Clash {
                inputs: vec![k],
                message: format!(
                    "{}: its template would be {}, the batch summary: rename the file",
                    en.who,
                    t.display()
                ),
            });
        } else if let Some(&victim) = canonical(&t).and_then(|c| input_files.get(&c)) {
            let whose = if victim == en.input {
                "this outline itself".to_string()
            } else {
                format!("the input {}", inputs[victim].path.display())
            };
            found.push(Clash {
                inputs: vec![k],
                message: format!(
                    "{}: its template {} would overwrite {whose}: choose an --out folder that \
                     holds no outlines",
                    en.who,
                    t.display(),
                ),
            });
        }
    }
    for (k, en) in entries.iter().enumerate() {
        let Some(t) = en.dest.as_ref() else { continue };
        for f in exports {
            for e in f.paths(t) {
                if let Some(&victim) = canonical(&e).and_then(|c| input_files.get(&c)) {
                    found.push(Clash {
                        inputs: vec![k],
                        message: format!(
                            "{}: its {f} export {} would overwrite the input {}: choose an \
                             --out folder that holds no outlines",
                            en.who,
                            e.display(),
                            inputs[victim].path.display()
                        ),
                    });
                }
            }
        }
    }
    if let Some(&victim) = canonical(&summary).and_then(|c| input_files.get(&c)) {
        // Every entry of the input the summary would overwrite.
        let of_victim: Vec<usize> = (0..entries.len())
            .filter(|&k| entries[k].input == victim)
            .collect();
        found.push(Clash {
            inputs: of_victim,
            message: format!(
                "the batch summary {} would overwrite the input {}: choose another --out folder",
                summary.display(),
                inputs[victim].path.display()
            ),
        });
    }
    found
}

fn is_outline(p: &Path) -> bool {
    MultiKind::of(p).is_some()
        || p.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| OUTLINE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

/// Options of a batch.
#[derive(Debug, Clone)]
pub struct BatchOptions {
    pub read: ReadOptions,
    pub params: ClumpParams,
    pub out: PathBuf,
    /// Exports written beside each template (none: templates only).
    pub exports: Vec<Format>,
    /// A grain below the cover target fails (no template written) instead of being written
    /// with a warning (`dem clump --strict`).
    pub strict: bool,
    /// How images are read (mask mode, inverse, smallest grain).
    pub grains: GrainOptions,
}

/// The outcome for one grain.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BatchItem {
    pub input: String,
    /// The grain within a multi-grain file (`label 7`, `component 3`, `feature 2 ("g7")`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grain: Option<String>,
    /// A multi-grain file's remarks on this grain (holes, cut by the image border, an open
    /// ring), also in the template's `source.warnings`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    pub template: Option<String>,
    pub discs: usize,
    pub cover: f64,
    /// Largest of the mass, centroid and inertia residuals.
    pub residual: f64,
    pub seconds: f64,
    pub error: Option<String>,
    /// Export files written beside the template.
    #[serde(default)]
    pub exports: Vec<String>,
    /// What the exports cannot carry exactly, per format ([`crate::export::caveat`]).
    #[serde(default)]
    pub caveats: Vec<ExportCaveat>,
    /// Set when the template was written below its cover target
    /// ([`crate::template::CoverShortfall`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// A format's figure of what it does not carry exactly for one grain (see
/// [`crate::export::Caveat`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExportCaveat {
    pub format: String,
    pub rel: f64,
}

/// The outcome of a batch, in input order.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BatchReport {
    pub items: Vec<BatchItem>,
    pub wall_seconds: f64,
    /// Remarks on whole input files (grains skipped below --min-pixels).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// One grain to clump: a one-outline input file, or one grain of a multi-grain file.
#[derive(Debug)]
pub struct Job {
    /// Index of its input file.
    pub input: usize,
    /// The grain within a multi-grain file (`label 7`); `None` for a one-outline file, and for
    /// a multi-grain file that failed as a whole.
    pub grain: Option<String>,
    /// Its template file; `None` for a multi-grain file that failed as a whole.
    pub dest: Option<PathBuf>,
    /// The outline of a multi-grain file's grain, or why the grain (or file) failed; `None`:
    /// read the one-outline file when the job runs.
    outline: Option<Result<Outline, String>>,
}

impl Job {
    /// `file` or `file, label 7`: how messages name the job.
    pub fn who(&self, inputs: &[Input]) -> String {
        let f = inputs[self.input].path.display().to_string();
        match &self.grain {
            Some(g) => format!("{f}, {g}"),
            None => f,
        }
    }
}

/// The grains of a batch, in input order (a multi-grain file's grains in its own order).
#[derive(Debug)]
pub struct Plan {
    pub jobs: Vec<Job>,
    /// Remarks on whole files (grains skipped as too small).
    pub notes: Vec<String>,
}

/// Lists the grains of `inputs`: reads the multi-grain files (in parallel on the current
/// rayon pool) and leaves the one-outline files to [`run_plan`]. A multi-grain file that
/// cannot be read at all (corrupt, an empty mask, degrees, no units) becomes one failed job.
pub fn plan(inputs: &[Input], o: &BatchOptions) -> Plan {
    let per_input: Vec<(Vec<Job>, Vec<String>)> = inputs
        .par_iter()
        .enumerate()
        .map(|(k, inp)| {
            if MultiKind::of(&inp.path).is_none() {
                let job = Job {
                    input: k,
                    grain: None,
                    dest: Some(template_path(&o.out, inp)),
                    outline: None,
                };
                return (vec![job], Vec::new());
            }
            match read_grains(&inp.path, &o.read, &o.grains) {
                Err(e) => {
                    let job = Job {
                        input: k,
                        grain: None,
                        dest: None,
                        outline: Some(Err(e.to_string())),
                    };
                    (vec![job], Vec::new())
                }
                Ok(fg) => {
                    let jobs = fg
                        .grains
                        .into_iter()
                        .map(|g| Job {
                            input: k,
                            dest: Some(grain_template_path(&o.out, inp, &g.name)),
                            grain: Some(g.label),
                            outline: Some(g.outline.map_err(|e| e.to_string())),
                        })
                        .collect();
                    (jobs, fg.notes)
                }
            }
        })
        .collect();
    let mut p = Plan {
        jobs: Vec::new(),
        notes: Vec::new(),
    };
    for (jobs, notes) in per_input {
        p.jobs.extend(jobs);
        p.notes.extend(notes);
    }
    p
}

/// [`clashes_with_exports`] for the jobs of a plan: indices in [`Clash::inputs`] are job
/// indices, and messages name the grain (`a.png, label 7 and a.png, label 7`).
pub fn plan_clashes(inputs: &[Input], p: &Plan, out: &Path, exports: &[Format]) -> Vec<Clash> {
    let entries: Vec<Entry> = p
        .jobs
        .iter()
        .map(|j| Entry {
            input: j.input,
            who: j.who(inputs),
            dest: j.dest.clone(),
        })
        .collect();
    clash_core(inputs, &entries, out, exports, case_insensitive(out))
}

/// Runs the batch on the current rayon pool: [`plan`], then [`run_plan`].
pub fn run_batch(inputs: &[Input], o: &BatchOptions, tick: &(dyn Fn() + Sync)) -> BatchReport {
    let t0 = Instant::now();
    let p = plan(inputs, o);
    let mut r = run_plan(inputs, p, o, tick);
    r.wall_seconds = t0.elapsed().as_secs_f64();
    r
}

/// `file: reason` of a grain's error as `file, grain: reason` (errors of the clump stage name
/// the file only).
fn name_grain(e: String, file: &str, grain: Option<&str>) -> String {
    match grain {
        Some(g) => match e.strip_prefix(&format!("{file}: ")) {
            Some(rest) => format!("{file}, {g}: {rest}"),
            None => e,
        },
        None => e,
    }
}

/// Makes and writes the templates of a plan. `tick` is called once per finished grain (for a
/// progress bar). Templates are written atomically to each job's path ([`template_path`],
/// [`grain_template_path`]), then each of `o.exports` beside it ([`crate::export::write`],
/// file by file atomically); a job in one of the plan's [`plan_clashes`] fails with the
/// clash's message and nothing is written for it. An export that cannot be written fails its
/// grain (its template stays). A template below its cover target is written with a warning, or
/// with [`BatchOptions::strict`] fails and is not written.
pub fn run_plan(
    inputs: &[Input],
    p: Plan,
    o: &BatchOptions,
    tick: &(dyn Fn() + Sync),
) -> BatchReport {
    let t0 = Instant::now();
    let mut refused: Vec<Option<String>> = vec![None; p.jobs.len()];
    for c in plan_clashes(inputs, &p, &o.out, &o.exports) {
        for k in c.inputs {
            refused[k].get_or_insert_with(|| c.message.clone());
        }
    }
    let items = p
        .jobs
        .into_par_iter()
        .zip(refused)
        .map(|(job, refused)| {
            let t = Instant::now();
            let inp = &inputs[job.input];
            let file = inp.path.display().to_string();
            let grain = job.grain.clone();
            let mut notes = Vec::new();
            let result = refused
                .map_or(Ok(()), Err)
                .and_then(|()| match job.outline {
                    Some(r) => r,
                    None => read_outline(&inp.path, &o.read).map_err(|e| e.to_string()),
                })
                .and_then(|ol| {
                    if grain.is_some() {
                        notes.clone_from(&ol.warnings);
                    }
                    make_template(&ol, &o.params).map_err(|e| e.to_string())
                })
                .and_then(|tpl| {
                    let dest = job.dest.as_ref().ok_or("no template path")?;
                    let short = tpl.cover_shortfall();
                    if let Some(s) = short.as_ref().filter(|_| o.strict) {
                        return Err(format!("{s} (a failure with --strict)"));
                    }
                    tpl.save(dest).map_err(|e| e.to_string())?;
                    let mut files = Vec::new();
                    for &f in &o.exports {
                        let w = crate::export::write(&tpl, f, dest).map_err(|e| e.to_string())?;
                        files.extend(w.iter().map(|p| p.display().to_string()));
                    }
                    Ok((tpl, files, short.map(|s| s.to_string())))
                });
            let seconds = t.elapsed().as_secs_f64();
            tick();
            let g = grain.as_deref();
            match result {
                Ok((tpl, exports, warning)) => BatchItem {
                    input: file.clone(),
                    grain: grain.clone(),
                    notes,
                    template: job.dest.as_ref().map(|d| d.display().to_string()),
                    discs: tpl.discs.len(),
                    cover: tpl.cover.value,
                    residual: tpl.residuals.max(),
                    seconds,
                    error: None,
                    exports,
                    caveats: o
                        .exports
                        .iter()
                        .filter_map(|&f| crate::export::caveat(&tpl, f))
                        .map(|c| ExportCaveat {
                            format: c.format.name().to_string(),
                            rel: c.rel,
                        })
                        .collect(),
                    warning: warning.map(|w| name_grain(w, &file, g)),
                },
                Err(e) => BatchItem {
                    input: file.clone(),
                    grain: grain.clone(),
                    notes,
                    template: None,
                    discs: 0,
                    cover: 0.0,
                    residual: 0.0,
                    seconds,
                    error: Some(name_grain(e, &file, g)),
                    exports: Vec::new(),
                    caveats: Vec::new(),
                    warning: None,
                },
            }
        })
        .collect();
    BatchReport {
        items,
        wall_seconds: t0.elapsed().as_secs_f64(),
        notes: p.notes,
    }
}

/// Median of a sample (the mean of the two middle values for an even count; 0 when empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

impl BatchReport {
    /// A plain-text summary: grains, templates written, those below the cover target,
    /// failures, median discs, median and worst cover, worst residual, median time per grain.
    pub fn summary_table(&self) -> String {
        let ok: Vec<&BatchItem> = self.items.iter().filter(|i| i.error.is_none()).collect();
        let n_fail = self.items.len() - ok.len();
        let mut s = String::new();
        s.push_str(&format!("grains            {}\n", self.items.len()));
        s.push_str(&format!("templates written {}\n", ok.len()));
        s.push_str(&format!("below cover target {}\n", self.warnings().count()));
        s.push_str(&format!("failures          {n_fail}\n"));
        if !ok.is_empty() {
            let discs = median(ok.iter().map(|i| i.discs as f64).collect());
            let cover = median(ok.iter().map(|i| i.cover).collect());
            let worst_cover = ok.iter().map(|i| i.cover).fold(f64::INFINITY, f64::min);
            let worst_res = ok.iter().map(|i| i.residual).fold(0.0, f64::max);
            let t = median(ok.iter().map(|i| i.seconds).collect());
            s.push_str(&format!("median discs      {discs}\n"));
            s.push_str(&format!("median cover      {cover:.4}\n"));
            s.push_str(&format!("lowest cover      {worst_cover:.4}\n"));
            s.push_str(&format!("worst residual    {worst_res:.2e}\n"));
            s.push_str(&format!("median time/grain {:.3} ms\n", t * 1e3));
        }
        s.push_str(&format!("wall time         {:.3} s", self.wall_seconds));
        s
    }

    /// The grains written below their cover target, with their warnings.
    pub fn warnings(&self) -> impl Iterator<Item = (&BatchItem, &str)> {
        self.items
            .iter()
            .filter_map(|i| i.warning.as_deref().map(|w| (i, w)))
    }

    /// Writes the report as JSON (atomically).
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::io::write_atomic(path, text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("clumpgen-batch-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    const SQUARE: &str = "0 0\n10 0\n10 10\n0 10\n";

    #[test]
    fn inputs_keep_their_place_below_the_common_folder() {
        let d = tmp("common");
        for f in ["a/g.csv", "b/g.csv", "b/sub/h.csv", "one.csv"] {
            std::fs::create_dir_all(d.join(f).parent().unwrap()).unwrap();
            std::fs::write(d.join(f), SQUARE).unwrap();
        }
        let rel = |paths: &[PathBuf]| -> Vec<String> {
            collect_inputs(paths)
                .unwrap()
                .iter()
                .map(|i| i.relative.display().to_string())
                .collect()
        };
        // One folder, or files of one folder: paths below it, as before.
        assert_eq!(rel(&[d.join("b")]), ["g.csv", "sub/h.csv"]);
        assert_eq!(rel(&[d.join("a/g.csv")]), ["g.csv"]);
        // Files or folders of several folders: below their common folder.
        assert_eq!(
            rel(&[d.join("a/g.csv"), d.join("b/g.csv")]),
            ["a/g.csv", "b/g.csv"]
        );
        assert_eq!(
            rel(&[d.join("a"), d.join("b"), d.join("one.csv")]),
            ["a/g.csv", "b/g.csv", "b/sub/h.csv", "one.csv"]
        );
        // A file also reached through its folder is read once.
        assert_eq!(
            rel(&[d.join("b"), d.join("b/g.csv")]),
            ["g.csv", "sub/h.csv"]
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn the_output_folder_inside_an_input_folder_is_not_read_back() {
        let d = tmp("out-inside");
        std::fs::write(d.join("g.csv"), SQUARE).unwrap();
        let out = d.join("t");
        let o = BatchOptions {
            read: ReadOptions::default(),
            params: ClumpParams::default(),
            out: out.clone(),
            exports: Vec::new(),
            strict: false,
            grains: GrainOptions::default(),
        };
        let inputs = collect_inputs_except(std::slice::from_ref(&d), Some(&out)).unwrap();
        assert_eq!(inputs.len(), 1);
        let r = run_batch(&inputs, &o, &|| {});
        assert!(r.items[0].error.is_none(), "{:?}", r.items[0].error);
        r.save(&out.join(SUMMARY_FILE)).unwrap();
        // The second run: the template and the summary in `t` are outlines to a plain walk...
        let all = collect_inputs(std::slice::from_ref(&d)).unwrap();
        assert_eq!(all.len(), 3, "{all:?}");
        // ...but not when `t` is the output folder; a file in it named explicitly still is.
        let again = collect_inputs_except(std::slice::from_ref(&d), Some(&out)).unwrap();
        assert_eq!(again.len(), 1, "{again:?}");
        assert!(clashes(&again, &out).is_empty());
        let named = collect_inputs_except(&[d.clone(), out.join("g.json")], Some(&out)).unwrap();
        assert_eq!(named.len(), 2, "{named:?}");
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// A 12-pointed star (radii 10 and 5 mm): 64 discs reach a cover of about 0.92 < 0.95.
    fn star12() -> String {
        (0..24)
            .map(|i| {
                let r = if i % 2 == 0 { 10.0 } else { 5.0 };
                let t = std::f64::consts::PI * i as f64 / 12.0;
                format!("{} {}\n", r * t.cos(), r * t.sin())
            })
            .collect()
    }

    #[test]
    fn grains_below_the_cover_target_are_warned_or_fail_with_strict() {
        let d = tmp("cover");
        std::fs::write(d.join("star.csv"), star12()).unwrap();
        std::fs::write(d.join("square.csv"), SQUARE).unwrap();
        let inputs = collect_inputs(&[d.join("star.csv"), d.join("square.csv")]).unwrap();
        let mut o = BatchOptions {
            read: ReadOptions::default(),
            params: ClumpParams::default(),
            out: d.join("out"),
            exports: Vec::new(),
            strict: false,
            grains: GrainOptions::default(),
        };
        let r = run_batch(&inputs, &o, &|| {});
        let star = &r.items[0];
        assert!(star.error.is_none() && star.cover < 0.95, "{star:?}");
        let w = star.warning.as_deref().expect("a warning for the star");
        assert!(
            w.starts_with(&format!("{}: cover 0.9", d.join("star.csv").display())),
            "{w}"
        );
        for part in [
            "below the target 0.95",
            "--max-discs 64",
            "raise --max-discs",
            "--cover",
        ] {
            assert!(w.contains(part), "{part:?} not in {w:?}");
        }
        assert!(r.items[1].warning.is_none() && r.items[1].error.is_none());
        assert!(d.join("out/star.json").exists());
        assert!(
            r.summary_table().contains("below cover target 1"),
            "{}",
            r.summary_table()
        );
        // --strict: the star fails and is not written; the square is.
        o.out = d.join("strict");
        o.strict = true;
        let r = run_batch(&inputs, &o, &|| {});
        let e = r.items[0].error.as_deref().expect("a failure with strict");
        assert!(
            e.contains("below the target 0.95") && e.contains("--strict"),
            "{e}"
        );
        assert!(r.items[0].warning.is_none() && r.items[1].error.is_none());
        assert!(!d.join("strict/star.json").exists() && d.join("strict/square.json").exists());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn clashing_inputs_are_not_written() {
        let d = tmp("clash");
        std::fs::write(d.join("g.csv"), SQUARE).unwrap();
        std::fs::write(d.join("g.txt"), SQUARE).unwrap();
        std::fs::write(d.join("k.csv"), SQUARE).unwrap();
        let inputs = collect_inputs(std::slice::from_ref(&d)).unwrap();
        let out = d.join("out");
        let c = clashes(&inputs, &out);
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].inputs, [0, 1]);
        let o = BatchOptions {
            read: ReadOptions::default(),
            params: ClumpParams::default(),
            out: out.clone(),
            exports: Vec::new(),
            strict: false,
            grains: GrainOptions::default(),
        };
        let r = run_batch(&inputs, &o, &|| {});
        assert!(r.items[0]
            .error
            .as_deref()
            .unwrap()
            .contains("both be written"));
        assert!(r.items[1].error.is_some() && r.items[2].error.is_none());
        assert!(!out.join("g.json").exists() && out.join("k.json").exists());
        // Into the input folder itself: k.json is then an input that its template overwrites.
        std::fs::remove_file(d.join("g.txt")).unwrap();
        std::fs::rename(out.join("k.json"), d.join("g.json")).unwrap();
        std::fs::remove_file(d.join("g.csv")).unwrap();
        let inputs = collect_inputs(std::slice::from_ref(&d)).unwrap();
        let c = clashes(&inputs, &d);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!(
            c[0].message.contains("overwrite this outline itself"),
            "{c:?}"
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    /// `G.csv` and `g.csv` get `G.json` and `g.json`: two files on Linux, one on a file system
    /// that folds case (macOS, Windows), where the second would silently replace the first.
    #[test]
    fn names_differing_only_in_case_clash_where_case_is_folded() {
        let d = tmp("case");
        std::fs::write(d.join("G.csv"), SQUARE).unwrap();
        std::fs::write(d.join("g.csv"), SQUARE).unwrap();
        let inputs = collect_inputs(std::slice::from_ref(&d)).unwrap();
        let out = d.join("out");
        let entries = input_entries(&inputs, &out);
        assert!(clash_core(&inputs, &entries, &out, &[], false).is_empty());
        let c = clash_core(&inputs, &entries, &out, &[], true);
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].inputs, [0, 1]);
        assert!(
            c[0].message.contains("upper from lower case") && c[0].message.contains("G.json"),
            "{c:?}"
        );
        // This machine's /tmp tells case apart (a Linux file system): no clash in a batch.
        assert!(!case_insensitive(&out));
        assert!(clashes(&inputs, &out).is_empty());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn exports_are_written_beside_templates_and_never_over_an_input() {
        let d = tmp("exports");
        std::fs::create_dir_all(d.join("sub")).unwrap();
        std::fs::write(d.join("sub/g.csv"), SQUARE).unwrap();
        let out = d.join("out");
        let o = BatchOptions {
            read: ReadOptions::default(),
            params: ClumpParams::default(),
            out: out.clone(),
            exports: vec![Format::Lammps, Format::Mercury],
            strict: false,
            grains: GrainOptions::default(),
        };
        let inputs = collect_inputs(std::slice::from_ref(&d)).unwrap();
        let r = run_batch(&inputs, &o, &|| {});
        let item = &r.items[0];
        assert!(item.error.is_none(), "{:?}", item.error);
        assert_eq!(item.exports.len(), 6, "{:?}", item.exports);
        assert!(out.join("sub/g.lammps.mol").exists());
        assert!(out.join("sub/g.mercury/Inertia/TOI.txt").exists());
        assert!(!out.join("sub/g.yade.py").exists());
        let formats: Vec<&str> = item.caveats.iter().map(|c| c.format.as_str()).collect();
        assert_eq!(formats, ["lammps", "mercury"]);
        assert!(item.caveats[0].rel > 0.0 && item.caveats[0].rel < 0.2);
        // Into the input folder, where an outline sits where an export goes (MercuryDPM's
        // Clump.txt is an outline file name): refused, named, the outline untouched.
        let sub = d.join("sub");
        let victim = sub.join("g.mercury/Clump/Clump.txt");
        std::fs::create_dir_all(victim.parent().unwrap()).unwrap();
        std::fs::write(&victim, SQUARE).unwrap();
        let inputs = collect_inputs(std::slice::from_ref(&sub)).unwrap();
        assert_eq!(inputs.len(), 2);
        assert!(clashes(&inputs, &sub).is_empty());
        assert!(clashes_with_exports(&inputs, &sub, &[Format::Lammps]).is_empty());
        let c = clashes_with_exports(&inputs, &sub, &o.exports);
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].inputs.len(), 1);
        assert_eq!(inputs[c[0].inputs[0]].path, sub.join("g.csv"));
        assert!(
            c[0].message.contains("mercury export") && c[0].message.contains("would overwrite"),
            "{c:?}"
        );
        let o2 = BatchOptions {
            out: sub.clone(),
            ..o.clone()
        };
        let r = run_batch(&inputs, &o2, &|| {});
        let failed: Vec<_> = r.items.iter().filter(|i| i.error.is_some()).collect();
        assert_eq!(failed.len(), 1);
        assert!(failed[0]
            .error
            .as_deref()
            .unwrap()
            .contains("would overwrite"));
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), SQUARE);
        assert!(!sub.join("g.json").exists());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
