//! `dem`: the command line of the workspace. Argument parsing, progress and messages only; the
//! work is done by the libraries.

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

mod bench;
mod calibrate;
mod clump;
mod lab_args;
mod progress;
mod render;
mod run;
mod run_lock;
mod schema;
mod specimen;
mod sweep;
mod test;
mod test_column;
mod test_crush;
mod test_cutting;

#[derive(Parser)]
#[command(name = "dem", version, about = "2D DEM of brittle-material machining")]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Largest input file or stream any command reads, in MiB (default 1024; also the
    /// environment variable DEM_MAX_INPUT_MIB). Devices and folders are refused whatever the size.
    #[arg(long, global = true, value_name = "MiB", value_parser = clap::value_parser!(u64).range(1..))]
    max_input_mib: Option<u64>,
}

// Parsed once per process: the size of the largest variant is of no account.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Grain outlines (files or folders) to disc-clump templates (improved ORC or ORC).
    Clump(clump::ClumpArgs),
    /// Run a scene file (JSON, docs/scene-schema.md) with its outputs.
    Run(run::RunArgs),
    /// Build a relaxed bonded specimen (traditional, ORC or improved ORC) as a specimen file.
    Specimen(specimen::SpecimenArgs),
    /// Virtual lab tests (uniaxial compression, Brazilian, three-point bending, notched-beam
    /// fracture toughness) on a generated specimen: scene file, run, analysis,
    /// `<test>.result.json`.
    #[command(subcommand)]
    Test(test::TestKind),
    /// Calibrate micro-parameters against a material's measured properties (UCS, bending and
    /// Brazilian tests): writes model.json (for `dem test --model`) and the calibration table.
    Calibrate(calibrate::CalibrateArgs),
    /// Draw a checkpoint, last-good-state.json, specimen file, clump template or VTK snapshot
    /// as a PNG picture (discs coloured by grain, bond group, speed or material; bonds, walls,
    /// tool), or a snapshots.pvd series as an animated GIF (or MP4 through ffmpeg).
    Render(render::RenderArgs),
    /// Speed benchmarks; the last line printed is the figure.
    #[command(subcommand)]
    Bench(bench::BenchKind),
    /// Parameter studies and seed repeats: plan a study file into cases, run them here or as
    /// a Slurm job array, collect one table (docs/sweep.md).
    #[command(subcommand)]
    Sweep(sweep::SweepCmd),
    /// Print the JSON Schema of a file kind (scene, template, specimen, study, cutting-params),
    /// derived from the program's own types; `--list` lists them (docs/schema/).
    Schema(schema::SchemaArgs),
    /// Reproduce the published tables and write the reproducibility report (Markdown, HTML,
    /// JSON, plots) into a folder; finds the project's data wherever it runs (docs/guide.md,
    /// "The report"). The same as the `validation` binary.
    Report(validation::cli::ReportArgs),
}

/// Every option that takes one value takes it even when it starts with `-`, so `--width -5mm`
/// reaches the length parser and is refused there by name ("--width -5mm: must be positive")
/// instead of clap's "unexpected argument '-5' found". Applied to every subcommand, and by
/// `dem sweep plan` to the test commands it checks cases against.
pub(crate) fn negative_values(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        let one = a
            .get_num_args()
            .is_none_or(|r| r.min_values() == 1 && r.max_values() == 1);
        if !a.is_positional() && a.get_action().takes_values() && one {
            a.allow_hyphen_values(true)
        } else {
            a
        }
    })
    .mut_subcommands(negative_values)
}

fn main() -> ExitCode {
    default_sigpipe();
    let cli = match Cli::from_arg_matches(&negative_values(Cli::command()).get_matches()) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    if let Some(mib) = cli.max_input_mib {
        clumpgen::io::set_input_limit(mib.saturating_mul(1 << 20));
        // The cases `dem sweep run` starts read their inputs under the same limit. (Set before
        // any thread is started.)
        std::env::set_var(clumpgen::io::INPUT_LIMIT_ENV, mib.to_string());
    }
    let result = match cli.command {
        Command::Clump(a) => clump::run(a),
        Command::Run(a) => run::run(a),
        Command::Specimen(a) => specimen::run(a),
        Command::Test(k) => test::run(k),
        Command::Calibrate(a) => calibrate::run(a),
        Command::Render(a) => render::run(a),
        Command::Bench(k) => bench::run(k),
        Command::Sweep(c) => sweep::run(c),
        Command::Schema(a) => schema::run(a),
        Command::Report(a) => return validation::cli::run(a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `--threads N`: a count of at least 1 (leaving the flag out means all cores; 0 used to
/// mean that too, silently).
pub(crate) fn parse_threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(0) => Err("must be at least 1 (leave the flag out for all cores)".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(format!("{e} (a count of worker threads, at least 1)")),
    }
}

/// A standard output closed early (`dem bench dense | head -1`) ends the program quietly, as it
/// does `cat`: Rust programs ignore SIGPIPE, so `println!` would panic on the broken pipe.
#[cfg(unix)]
fn default_sigpipe() {
    // SAFETY: sets the disposition of one signal to the default; called first in `main`,
    // before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn default_sigpipe() {}
