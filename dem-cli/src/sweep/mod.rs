//! `dem sweep`: parameter studies and seed repeats as tables of cases, run here (`run`, N at
//! a time) or as a Slurm job array (`slurm.sbatch`, one task per case), then collected into one
//! table with aggregates over seeds (docs/sweep.md).
//!
//! The files come from the run layer, [`dem_run`]: [`study`] (the study file), [`claim`]
//! (which process runs a case), [`case`] (a planned case and its folder's files). Here, each
//! using only those listed before it: [`plan`], [`mod@run`], [`timing`] (the time a sweep
//! took), [`collect`] (also `status`).

pub(crate) use dem_run::{case, claim, study};

mod collect;
mod plan;
mod run;
mod timing;

use clap::Subcommand;
use std::process::ExitCode;

/// `dem sweep` commands.
#[derive(Subcommand)]
pub enum SweepCmd {
    /// Expand a study file into DIR: study.json, cases.jsonl (one case per line, keyed by a
    /// hash of its inputs) and slurm.sbatch (a job array, one task per case).
    Plan(plan::PlanArgs),
    /// Run the cases not yet finished, N at a time (or case I alone: --index I); several
    /// processes (Slurm tasks) may share DIR.
    Run(run::RunArgs),
    /// Counts, the state of each case, and the time taken (CPU and wall, overall and per axis
    /// value).
    Status(collect::StatusArgs),
    /// One row per case (axis values, collected outputs, status, times) and aggregates over
    /// seeds (n, mean, sd, SE, median) as CSV or JSON.
    Collect(collect::CollectArgs),
}

pub fn run(cmd: SweepCmd) -> Result<ExitCode, String> {
    match cmd {
        SweepCmd::Plan(a) => plan::run(a),
        SweepCmd::Run(a) => run::run(a),
        SweepCmd::Status(a) => collect::status(a),
        SweepCmd::Collect(a) => collect::collect(a),
    }
}
