//! The report's command line, shared by `dem report` and the `validation` binary: which
//! sections, which runs (here, finished only, or a `dem sweep` folder), where the data are.

use clap::Args;
use std::path::PathBuf;
use std::process::ExitCode;

/// The report's options: the same for `dem report` and the `validation` binary.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// The project's data folder (default: `data` here, else the repository's).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Output folder.
    #[arg(long, default_value = "report")]
    pub out: PathBuf,
    /// Cover targets of the clump-generation sweep.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.8,0.85,0.9,0.93,0.95,0.97,0.98"
    )]
    pub covers: Vec<f64>,
    /// Timing repeats per grain in the sweep (best of N).
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Quick mode (CI): 1 seed, short cut, coarse specimens, a short clump sweep.
    #[arg(long)]
    pub quick: bool,
    /// Run only these sections (comma-separated): table1, sweep, table2, damping, table3,
    /// pictures, convergence, stability, crush, chung-ooi. Cutting (and Table 3's bending) runs already in the output
    /// folder with the same parameters are read back, not run again.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Table 2: run only these specimen methods (traditional, orc, improved; default all).
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Table 2: run only these seeds (default all of the plan's).
    #[arg(long, value_delimiter = ',')]
    pub seeds: Vec<u64>,
    /// Table 2, Table 3, the convergence study and a `--study` use only the runs already
    /// finished in the output folder and list the others as not run (a report of the runs
    /// done so far).
    #[arg(long)]
    pub finished_only: bool,
    /// Run a cutting study (`data/studies/*.json`: variants of the cutting test on the Table 2
    /// specimens) into `<out>/<study name>/` instead of the report; finished runs are read back.
    #[arg(long)]
    pub study: Option<PathBuf>,
    /// Read the cutting runs of Table 2 (or of `--study`) from the done cases of this `dem
    /// sweep` folder instead of running them (docs/sweep.md, "Table 2 on a cluster"); the runs
    /// not done there are listed as not run. Without --only, the report is Table 2 alone.
    #[arg(long)]
    pub sweep: Option<PathBuf>,
    /// The pictures of the specimens and cuts the report shows (PNGs made by
    /// `scripts/cut-pictures.sh`; default: `docs/pictures` here, else the repository's).
    #[arg(long)]
    pub pictures: Option<PathBuf>,
}

/// Writes the report (or runs a `--study`) as `a` says; the exit code: 0 when every section
/// built, 1 when one failed, 2 for a study that could not be read.
pub fn run(mut a: ReportArgs) -> ExitCode {
    let data = crate::project_path(a.data.take(), "data");
    let pictures = crate::project_path(a.pictures.take(), "docs/pictures");
    // Runs not finished: run them, or (--finished-only) list them as not run.
    let missing = if a.finished_only {
        crate::cutting_runs::Missing::List
    } else {
        crate::cutting_runs::Missing::Run
    };
    if let Some(f) = &a.study {
        let progress = |m: &str| eprintln!("{m}");
        let r = crate::study::StudySpec::read(f).and_then(|s| {
            let source = match &a.sweep {
                Some(d) => crate::cutting_runs::Source::Sweep(d),
                None => crate::cutting_runs::Source::Here(missing),
            };
            crate::study::run(&s, &data, &a.out, source, &progress).map(|r| (s, r))
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
    let o = crate::report::ReportOptions {
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
        table2: crate::table2_section::Subset {
            methods,
            seeds: a.seeds,
        },
        missing,
        sweep: a.sweep,
        pictures,
    };
    match crate::report::run(&o) {
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
