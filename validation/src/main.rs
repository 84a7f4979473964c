//! `validation`: regenerates the report into a folder (the same as `dem report`).

use clap::Parser;
use std::process::ExitCode;

#[derive(Parser)]
#[command(about = "Reproduce the published tables and write the report (also `dem report`)")]
struct Cli {
    #[command(flatten)]
    report: validation::cli::ReportArgs,
}

fn main() -> ExitCode {
    validation::cli::run(Cli::parse().report)
}
