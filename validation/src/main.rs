//! `validation`: regenerates the report (Table 1, clump sweep) into a folder.

use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(about = "Reproduce the published tables and write the report")]
struct Args {
    /// The project's data folder (default: `data` here, else the repository's).
    #[arg(long)]
    data: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "report")]
    out: PathBuf,
    /// Cover targets of the clump-generation sweep.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.8,0.85,0.9,0.93,0.95,0.97,0.98"
    )]
    covers: Vec<f64>,
    /// Timing repeats per grain in the sweep (best of N).
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Quick mode (CI): 1 seed, short cut, coarse specimens, a short clump sweep.
    #[arg(long)]
    quick: bool,
    /// Run only these sections (comma-separated): table1, sweep, table2, damping, table3,
    /// pictures, convergence, stability, crush. Cutting (and Table 3's bending) runs already in the output
    /// folder with the same parameters are read back, not run again.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    /// Table 2: run only these specimen methods (traditional, orc, improved; default all).
    #[arg(long, value_delimiter = ',')]
    methods: Vec<String>,
    /// Table 2: run only these seeds (default all of the plan's).
    #[arg(long, value_delimiter = ',')]
    seeds: Vec<u64>,
    /// Table 2, Table 3, the convergence study and a `--study` use only the runs already
    /// finished in the output folder and list the others as not run (a report of the runs
    /// done so far).
    #[arg(long)]
    finished_only: bool,
    /// Run a cutting study (`data/studies/*.json`: variants of the cutting test on the Table 2
    /// specimens) into <out>/<study name>/ instead of the report; finished runs are read back.
    #[arg(long)]
    study: Option<PathBuf>,
    /// Read the cutting runs of Table 2 (or of `--study`) from the done cases of this `dem
    /// sweep` folder instead of running them (docs/sweep.md, "Table 2 on a cluster"); the runs
    /// not done there are listed as not run. Without --only, the report is Table 2 alone.
    #[arg(long)]
    sweep: Option<PathBuf>,
    /// The pictures of the specimens and cuts the report shows (PNGs made by
    /// `scripts/cut-pictures.sh`; default: `docs/pictures` here, else the repository's).
    #[arg(long)]
    pictures: Option<PathBuf>,
}

fn main() -> ExitCode {
    let mut a = Args::parse();
    let data = validation::project_path(a.data.take(), "data");
    let pictures = validation::project_path(a.pictures.take(), "docs/pictures");
    if let Some(f) = &a.study {
        let progress = |m: &str| eprintln!("{m}");
        let r = validation::study::StudySpec::read(f).and_then(|s| {
            let source = match (&a.sweep, a.finished_only) {
                (Some(d), _) => validation::sweep_runs::Source::Sweep(d),
                (None, true) => {
                    validation::sweep_runs::Source::Here(validation::cutting_runs::Missing::List)
                }
                (None, false) => {
                    validation::sweep_runs::Source::Here(validation::cutting_runs::Missing::Run)
                }
            };
            validation::study::run(&s, &data, &a.out, source, &progress).map(|r| (s, r))
        });
        return match r {
            Ok((s, (rows, errors))) => {
                eprintln!(
                    "study {}: {} runs, {} errors; {}",
                    s.name,
                    rows.len(),
                    errors.len(),
                    a.out.join(&s.name).join("study.md").display()
                );
                if errors.is_empty() {
                    ExitCode::SUCCESS
                } else {
                    ExitCode::FAILURE
                }
            }
            Err(e) => {
                eprintln!("error: {e}");
                ExitCode::from(2)
            }
        };
    }
    let mut methods = vec![];
    for m in &a.methods {
        match dem_lab::specimen::Method::parse(m) {
            Some(m) => methods.push(m),
            None => {
                eprintln!("error: --methods: unknown method `{m}` (traditional, orc, improved)");
                return ExitCode::FAILURE;
            }
        }
    }
    let o = validation::report::ReportOptions {
        data,
        out: a.out.clone(),
        covers: if a.quick { vec![0.9, 0.95] } else { a.covers },
        repeats: if a.quick { 1 } else { a.repeats },
        quick: a.quick,
        only: if a.sweep.is_some() && a.only.is_empty() {
            vec!["table2".to_string()]
        } else {
            a.only
        },
        table2: validation::table2_section::Subset {
            methods,
            seeds: a.seeds,
        },
        missing: if a.finished_only {
            validation::cutting_runs::Missing::List
        } else {
            validation::cutting_runs::Missing::Run
        },
        sweep: a.sweep,
        pictures,
    };
    match validation::report::run(&o) {
        Ok(_) => {
            eprintln!("report written to {}", a.out.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
