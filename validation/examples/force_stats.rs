//! Force statistics of finished Table 2 runs, read back (no run is made):
//! `cargo run --release -p validation --example force_stats -- [runs dir] [data dir]`
//! (defaults `docs/report/table2-runs-2026-11-25`, `data`). Prints the width study on the a_p = 1 mm
//! cells (the rule of `force_statistics::choose_width`), the same study on a_p = 2 mm as a check,
//! and the cell table at the chosen width (kN at the thickness fitted as Table 2 does), as
//! markdown; `--json FILE` also writes the figures as JSON; `--seeds 6,7,8,9,10` uses only
//! those seeds (the width is chosen on seeds 1–5 and checked on fresh ones).

use std::path::PathBuf;
use std::process::ExitCode;
use validation::error::{Error, Result};
use validation::force_statistics as fs;
use validation::table2::PaperTable2;

/// Prints an error as `main` did when it returned its error as a `String`: `Error: "<message>"`,
/// exit code 1.
fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("Error: {:?}", e.to_string());
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let json = match args.iter().position(|a| a == "--json") {
        Some(i) if i + 1 < args.len() => {
            let f = args.remove(i + 1);
            args.remove(i);
            Some(PathBuf::from(f))
        }
        Some(_) => return Err(Error::Other("--json needs a file".into())),
        None => None,
    };
    let seeds: Option<Vec<u64>> = match args.iter().position(|a| a == "--seeds") {
        Some(i) if i + 1 < args.len() => {
            let list = args.remove(i + 1);
            args.remove(i);
            Some(
                list.split(',')
                    .map(|x| {
                        x.trim().parse().map_err(|source| Error::SeedArg {
                            text: x.to_string(),
                            source,
                        })
                    })
                    .collect::<Result<_>>()?,
            )
        }
        Some(_) => return Err(Error::Other("--seeds needs a list".into())),
        None => None,
    };
    let dir = PathBuf::from(
        args.first()
            .map_or("docs/report/table2-runs-2026-11-25", |s| s.as_str()),
    );
    let data = PathBuf::from(args.get(1).map_or("data", |s| s.as_str()));
    let paper = PaperTable2::read(&data.join("reference/ye_xu_2010_table2.json"))?;
    let mut runs = fs::load_runs(&dir)?;
    if let Some(keep) = &seeds {
        runs.retain(|r| keep.contains(&r.seed));
    }
    let scale = fs::force_scale(&runs, &paper)?;
    let cells = fs::cells(&runs);
    let study = |d: f64| -> Result<Vec<fs::WidthRow>> {
        cells
            .iter()
            .filter(|c| c[0].depth_mm == d)
            .map(|c| fs::width_row(c))
            .collect()
    };
    let rows1 = study(1.0)?;
    let (chosen, med1) = fs::choose_width(&rows1);
    let rows2 = study(2.0)?;
    let (check, med2) = fs::choose_width(&rows2);
    let stats: Vec<fs::CellStats> = cells
        .iter()
        .map(|c| fs::cell_stats(c, fs::PEAK_WIDTH_AP))
        .collect::<Result<_>>()?;
    println!(
        "{} runs from {} (seeds {}); kN per N at the runs' thickness: {scale:.4e}\n",
        runs.len(),
        dir.display(),
        seeds.map_or("all".to_string(), |s| format!("{s:?}"))
    );
    println!("## a_p = 1 mm (choosing)\n");
    println!("{}", fs::width_markdown(&rows1, "the a_p = 1 mm cells"));
    println!("## a_p = 2 mm (check, not used to choose)\n");
    println!("{}", fs::width_markdown(&rows2, "the a_p = 2 mm cells"));
    println!(
        "## Cells at w = {} a_p (PEAK_WIDTH_AP)\n",
        fs::PEAK_WIDTH_AP
    );
    println!("{}", fs::cells_markdown(&stats, scale, &paper));
    if let Some(f) = json {
        let v = serde_json::json!({
            "statistic": fs::PEAK_STATISTIC,
            "runs_dir": dir.display().to_string(),
            "kn_per_n": scale,
            "width_study_ap1": rows1, "median_drop_ap1": med1, "chosen_by_rule_ap_x": chosen,
            "width_study_ap2": rows2, "median_drop_ap2": med2, "rule_on_ap2_ap_x": check,
            "peak_width_ap": fs::PEAK_WIDTH_AP,
            "cells": stats,
        });
        std::fs::write(
            &f,
            serde_json::to_string_pretty(&v).map_err(Error::Serialize)?,
        )
        .map_err(Error::io(&f))?;
    }
    Ok(())
}
