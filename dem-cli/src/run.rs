//! `dem run`: runs a scene file (`docs/scene-schema.md`) with a progress bar; prints the active
//! stages at the start and the summary at the end. Errors are messages (exit code 2). The
//! output folder is locked to the scene (`run_lock`): another scene's run into it is refused
//! unless `--force`.

use crate::progress::Progress;
use clap::Args;
use dem_core::output::driver::{Ending, RunOptions, Simulation, MAX_OUTPUT_BYTES_UNASKED};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct RunArgs {
    /// Scene file (JSON, schema dem.scene/1).
    scene: PathBuf,
    /// Output folder (default: the scene's `outputs.dir`, else `<scene stem>.out` beside it).
    /// It is locked to the scene (`run.lock`: scene, scene hash, pid, host).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Continue from a checkpoint written by a run of the same scene.
    #[arg(long)]
    restart: Option<PathBuf>,
    /// Worker threads, at least 1 (default: all cores); results do not depend on it.
    #[arg(long, value_parser = crate::parse_threads)]
    threads: Option<usize>,
    /// Stop when the world reaches this step (overrides the scene's run.max_steps).
    #[arg(long)]
    max_steps: Option<u64>,
    /// Run into the output folder even if it holds another scene's run, or its lock is held
    /// by a process that still runs (or runs on another host); the lock is taken over.
    #[arg(long)]
    force: bool,
    /// Run even if the scene needs more than 10⁹ steps, or its snapshots and checkpoints more
    /// than 10 GB (the step count and the estimate are stated first; without this flag such a
    /// run is refused).
    #[arg(long)]
    yes: bool,
    /// Checkpoint file format, overriding the scene's `outputs.checkpoint_format`: `json`
    /// (`ckpt-<step>.json`) or `binary` (`ckpt-<step>.bin`, about half the size). A
    /// restart reads either.
    #[arg(long, value_enum)]
    checkpoint_format: Option<CkptFormat>,
    /// VTK snapshot encoding, overriding the scene's `outputs.vtk_format`: `ascii` or
    /// `binary` (VTK's appended base64 layout: exact values, 15 % smaller mid-cut). ParaView and
    /// `dem render` read both.
    #[arg(long, value_enum)]
    vtk_format: Option<VtkFormat>,
    /// Write no checkpoints, neither periodic nor final (overrides the scene's
    /// `outputs.checkpoints` and `checkpoint_every`); the run then cannot be resumed.
    #[arg(long)]
    no_checkpoints: bool,
}

/// `--checkpoint-format` values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum CkptFormat {
    Json,
    Binary,
}

/// `--vtk-format` values.
#[derive(Clone, Copy, clap::ValueEnum)]
enum VtkFormat {
    Ascii,
    Binary,
}

/// Above this many steps `dem run` states the count and refuses unless `--yes`: 10⁹ steps of
/// a 1,500-disc cutting specimen take ~21 h on one core of the development machine (~20 M
/// particle-steps/s); a mistyped stiffness or duration easily asks for 10¹⁴.
pub const MAX_STEPS_UNASKED: u64 = dem_lab::run::STEP_LIMIT;

pub fn run(a: RunArgs) -> Result<ExitCode, String> {
    let mut scene = dem_core::scene::load(&a.scene).map_err(|e| e.to_string())?;
    // Run control, not physics: neither changes the scene's physics hash.
    if let Some(f) = a.checkpoint_format {
        scene.outputs.checkpoint_format = match f {
            CkptFormat::Json => dem_core::checkpoint::Format::Json,
            CkptFormat::Binary => dem_core::checkpoint::Format::Binary,
        };
    }
    if let Some(f) = a.vtk_format {
        scene.outputs.vtk_format = match f {
            VtkFormat::Ascii => dem_core::output::vtk::Format::Ascii,
            VtkFormat::Binary => dem_core::output::vtk::Format::Binary,
        };
    }
    if a.no_checkpoints {
        scene.outputs.checkpoints = false;
    }
    // (The folder `Simulation::new` writes into.)
    let out = a.out.clone().unwrap_or_else(|| scene.outputs.dir.clone());
    let (file, hash) = (scene.file.clone(), scene.physics_hash());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| e.to_string())?;
    let opts = RunOptions {
        out_dir: Some(out.clone()),
        restart: a.restart,
        max_steps: a.max_steps,
    };
    pool.install(|| {
        // Built (or loaded) before the lock: nothing is written yet, and a refused run leaves
        // the folder as it was.
        let mut sim = Simulation::new(scene, &opts).map_err(|e| e.to_string())?;
        check_step_count(&sim, a.yes)?;
        check_output_size(&sim, a.yes)?;
        let _lock = crate::run_lock::acquire_noted(
            &out,
            crate::run_lock::Claim {
                command: crate::run_lock::RUN,
                scene: &file,
                hash: &hash,
            },
            a.force,
        )?;
        let st = &sim.world.state;
        println!(
            "scene {}: {} discs, {} rigid clumps, {} bonds, {} walls; dt {:.4e} s",
            sim.scene.file.display(),
            st.discs.len(),
            st.clumps.len(),
            sim.world.bonds.as_ref().map_or(0, |b| b.len()),
            st.walls.len(),
            sim.world.dt()
        );
        if let Some(r) = &opts.restart {
            println!("restart from {} at step {}", r.display(), st.step);
        }
        println!("active stages: {}", sim.active_stages().join(", "));
        println!("output: {}", sim.out_dir().display());
        if !sim.scene.outputs.checkpoints {
            println!("checkpoints: off (this run writes none and cannot be resumed)");
        }
        let bar = Progress::counted(sim.total_steps(), "steps");
        let result = sim.run(&mut |done, total| {
            bar.set_length(total);
            bar.set_position(done);
        });
        bar.finish_and_clear();
        let (s, ending) = result.map_err(|e| e.to_string())?;
        if ending == Ending::MaxSteps {
            println!("stopped at the step cap ({} steps) before the end of the scene", s.final_step);
        }
        println!(
            "{}: {} steps to step {} (t = {:.6e} s) in {:.2} s on {} threads: {:.4e} particle-steps/s",
            s.status, s.steps, s.final_step, s.time, s.wall_time_s, s.threads, s.particle_steps_per_s
        );
        println!(
            "dt {:.4e} s (min {:.4e}, max {:.4e}); bonds {} ({} broken); energy balance error {:.3e} (relative)",
            s.dt, s.dt_min, s.dt_max, s.bonds, s.bonds_broken, s.energy.balance_error
        );
        // Numbered series (snapshots, checkpoints) are counted, the rest named.
        let series = |p: &str| s.files.iter().filter(|f| f.starts_with(p)).count();
        let named: Vec<&str> = s
            .files
            .iter()
            .map(String::as_str)
            .filter(|f| !(f.starts_with("snap-") || f.starts_with("walls-") || f.starts_with("ckpt-0")))
            .collect();
        println!(
            "files: {}; {} snapshots, {} periodic checkpoints",
            named.join(", "),
            series("snap-"),
            series("ckpt-0")
        );
        if !s.checkpoints {
            println!("no checkpoints written (checkpoints off): this run cannot be resumed");
        }
        Ok(ExitCode::SUCCESS)
    })
}

/// States a run's step count before it starts and refuses one above [`MAX_STEPS_UNASKED`]
/// unless `yes` (issue 20: a stiffness of 1e30 asked for ~1.6e14 steps at dt = 6e-17 s and ran
/// silently).
fn check_step_count(sim: &Simulation, yes: bool) -> Result<(), String> {
    let steps = sim.total_steps();
    let dt = sim.world.dt();
    if steps <= MAX_STEPS_UNASKED || yes {
        return Ok(());
    }
    let discs = sim.world.state.discs.len().max(1) as f64;
    // At ~20 M particle-steps/s on one core (docs/performance.md), the order of magnitude.
    let hours = steps as f64 * discs / 2e7 / 3600.0;
    Err(format!(
        "{}: the run needs {steps} steps of dt = {dt:.3e} s (from run.duration or \
         run.steps; about {hours:.1e} core-hours for {} discs at 2e7 particle-steps/s), more \
         than the {MAX_STEPS_UNASKED} steps run without asking. Check run.duration, run.dt / \
         run.dt_factor and the materials' stiffness (the time step scales with \
         sqrt(mass/stiffness)); cap the run with run.max_steps or --max-steps, or give --yes \
         to run it as it is",
        sim.scene.file.display(),
        discs as u64
    ))
}

/// Refuses a run whose outputs would fill more than [`MAX_OUTPUT_BYTES_UNASKED`] (the
/// estimate is [`Simulation::output_bytes`], the one every run path uses) unless `yes`
/// (issue 20: VTK output grew ~48 MB/min with no warning), naming the scene fields to change.
fn check_output_size(sim: &Simulation, yes: bool) -> Result<(), String> {
    let bytes = sim.output_bytes();
    if bytes <= MAX_OUTPUT_BYTES_UNASKED || yes {
        return Ok(());
    }
    let o = &sim.scene.outputs;
    Err(format!(
        "{}: the run's snapshots and checkpoints would take about {:.1} GB ({} steps, {} \
         discs, {}, a checkpoint every {} steps \
         (outputs.checkpoint_every), {} kept (outputs.checkpoint_keep, 0 = all)), more than \
         the {:.0} GB written without asking. Raise the intervals, or give --yes to run it \
         as it is",
        sim.scene.file.display(),
        bytes / 1e9,
        sim.total_steps(),
        sim.world.state.discs.len(),
        o.snapshot_plan(),
        o.checkpoint_every,
        o.checkpoint_keep,
        MAX_OUTPUT_BYTES_UNASKED / 1e9
    ))
}
