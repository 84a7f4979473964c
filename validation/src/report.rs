//! Writes the report folder: Markdown and the JSON behind every table.

use crate::{clump_sweep, table1};
use clumpgen::ClumpParams;
use std::path::{Path, PathBuf};

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
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    clumpgen::io::write_atomic(path, text.as_bytes())
        .map_err(|e| format!("{}: {e}", path.display()))
}

fn json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string_pretty(v).expect("report data serialises") + "\n"
}

/// Runs Table 1 and the clump sweep; returns the Markdown index.
pub fn run(o: &ReportOptions) -> Result<String, String> {
    let base = ClumpParams::default();
    let t1 = table1::table1(
        &o.data.join("outlines/table1-grain.csv"),
        &o.data.join("reference/ye_xu_2010_table1.json"),
        &base,
    )?;
    write(&o.out.join("table1.md"), &t1.markdown())?;
    write(&o.out.join("table1.json"), &json(&t1))?;
    let sw = clump_sweep::sweep(&o.data.join("outlines"), &o.covers, &base, o.repeats)?;
    write(&o.out.join("clump_sweep.md"), &sw.markdown())?;
    write(&o.out.join("clump_sweep.json"), &json(&sw))?;
    let index = format!("{}\n{}", t1.markdown(), sw.markdown());
    write(&o.out.join("index.md"), &index)?;
    Ok(index)
}
