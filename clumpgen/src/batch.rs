//! Batches of grains (clump libraries): every input file becomes one template, in parallel
//! (rayon); a failed grain is recorded with its reason and never stops the others.

use crate::clump::{make_template, ClumpParams};
use crate::outline::{read_outline, ReadOptions};
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

/// Expands files and folders (recursively, sorted) into inputs. A folder's files keep their
/// path below it, so two folders holding `grain-000.csv` do not collide.
pub fn collect_inputs(paths: &[PathBuf]) -> std::io::Result<Vec<Input>> {
    fn walk(dir: &Path, base: &Path, out: &mut Vec<Input>) -> std::io::Result<()> {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
            .map(|e| e.map(|e| e.path()))
            .collect::<Result<_, _>>()?;
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, base, out)?;
            } else if is_outline(&p) {
                let relative = p.strip_prefix(base).unwrap_or(&p).to_path_buf();
                out.push(Input { path: p, relative });
            }
        }
        Ok(())
    }
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            walk(p, p, &mut out)?;
        } else if p.exists() {
            let relative = PathBuf::from(p.file_name().unwrap_or_default());
            out.push(Input {
                path: p.clone(),
                relative,
            });
        } else {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("{}: no such file or folder", p.display()),
            ));
        }
    }
    Ok(out)
}

fn is_outline(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| OUTLINE_EXTENSIONS.contains(&e.to_ascii_lowercase().as_str()))
}

/// Options of a batch.
#[derive(Debug, Clone)]
pub struct BatchOptions {
    pub read: ReadOptions,
    pub params: ClumpParams,
    pub out: PathBuf,
}

/// The outcome for one grain.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BatchItem {
    pub input: String,
    pub template: Option<String>,
    pub discs: usize,
    pub cover: f64,
    /// Largest of the mass, centroid and inertia residuals.
    pub residual: f64,
    pub seconds: f64,
    pub error: Option<String>,
}

/// The outcome of a batch, in input order.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BatchReport {
    pub items: Vec<BatchItem>,
    pub wall_seconds: f64,
}

/// Runs the batch on the current rayon pool. `tick` is called once per finished grain (for a
/// progress bar). Templates are written atomically as `<out>/<relative>.json`.
pub fn run_batch(inputs: &[Input], o: &BatchOptions, tick: &(dyn Fn() + Sync)) -> BatchReport {
    let t0 = Instant::now();
    let items = inputs
        .par_iter()
        .map(|inp| {
            let t = Instant::now();
            let dest = o.out.join(inp.relative.with_extension("json"));
            let result = read_outline(&inp.path, &o.read)
                .map_err(|e| e.to_string())
                .and_then(|ol| make_template(&ol, &o.params).map_err(|e| e.to_string()))
                .and_then(|tpl| {
                    tpl.save(&dest).map_err(|e| e.to_string())?;
                    Ok(tpl)
                });
            let seconds = t.elapsed().as_secs_f64();
            tick();
            let input = inp.path.display().to_string();
            match result {
                Ok(tpl) => BatchItem {
                    input,
                    template: Some(dest.display().to_string()),
                    discs: tpl.discs.len(),
                    cover: tpl.cover.value,
                    residual: tpl.residuals.max(),
                    seconds,
                    error: None,
                },
                Err(e) => BatchItem {
                    input,
                    template: None,
                    discs: 0,
                    cover: 0.0,
                    residual: 0.0,
                    seconds,
                    error: Some(e),
                },
            }
        })
        .collect();
    BatchReport {
        items,
        wall_seconds: t0.elapsed().as_secs_f64(),
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
    /// A plain-text summary: grains, failures, median discs, median and worst cover, worst
    /// residual, median time per grain.
    pub fn summary_table(&self) -> String {
        let ok: Vec<&BatchItem> = self.items.iter().filter(|i| i.error.is_none()).collect();
        let n_fail = self.items.len() - ok.len();
        let mut s = String::new();
        s.push_str(&format!("grains            {}\n", self.items.len()));
        s.push_str(&format!("templates written {}\n", ok.len()));
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

    /// Writes the report as JSON (atomically).
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::io::write_atomic(path, text.as_bytes())
    }
}
