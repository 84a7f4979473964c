//! Running a lab-test scene: the test builds the scene as a typed value (the `dem.scene/1`
//! file types), writes it as a plain file (so the user can edit and re-run it with
//! `dem run`), runs the same value exactly as `dem run` would run the file, checked in memory
//! rather than read back, and keeps its history's numbers (the driver's in-memory
//! [`Record`], series by wall, gauge and bond group).

use super::LabError;
use dem_core::output::driver::{RunOptions, Simulation, StepHook};
use dem_core::output::history::Record;
use dem_core::output::summary::RunSummary;
use dem_core::output::write_atomic;
use dem_core::scene::schema::SceneFile;
use dem_core::World;
use std::path::{Path, PathBuf};

/// A finished lab run.
pub struct LabRun {
    /// The scene file written and run.
    pub scene_file: PathBuf,
    /// Its output folder.
    pub out_dir: PathBuf,
    pub summary: RunSummary,
    /// The history's rows as numbers (what `history.csv` holds), of the whole run.
    pub history: Record,
    /// The world at the end of the run (for analyses of the final state: chips, surfaces).
    pub world: World,
}

/// A lab test that needs more steps than this is refused before it starts, as `dem run` refuses
/// one without `--yes` (issue 20, bounded work): 10⁹ steps are ~40 × the longest Table 2 cut
/// (27 M steps), about 14 core-hours for 1,000 discs at 2e7 particle-steps/s.
pub const STEP_LIMIT: u64 = 1_000_000_000;

/// Writes `scene` to `scene_file` (atomically, pretty JSON) for `dem run` to replay, and runs
/// the same value, checked in memory (not read back from the file), with `opts` (output
/// folder: `opts.out_dir`, else the scene's) and `hook` between steps (see [`StepHook`]),
/// calling `progress(done, total)` now and then.
pub fn run_scene(
    scene: &SceneFile,
    scene_file: &Path,
    opts: &RunOptions,
    progress: &mut dyn FnMut(u64, u64),
    hook: Option<StepHook>,
) -> Result<LabRun, LabError> {
    run_built(scene, scene_file, None, opts, progress, hook)
}

/// As [`run_scene`], with the world already built from `scene` when the caller has it
/// (`Some`: see [`Simulation::with_world`]; used for a fresh run only).
pub fn run_built(
    scene: &SceneFile,
    scene_file: &Path,
    built: Option<World>,
    opts: &RunOptions,
    progress: &mut dyn FnMut(u64, u64),
    hook: Option<StepHook>,
) -> Result<LabRun, LabError> {
    write_scene(scene, scene_file)?;
    let resolved = dem_core::scene::resolve(scene.clone(), scene_file)?;
    let mut sim = match built {
        Some(world) => Simulation::with_world(resolved, world, opts)?,
        None => Simulation::new(resolved, opts)?,
    };
    // The analyses read the history in memory.
    sim.keep_history()?;
    let steps = sim.total_steps();
    if steps > STEP_LIMIT {
        return Err(LabError::TooManySteps {
            scene: scene_file.display().to_string(),
            steps,
            dt: sim.world.dt(),
            limit: STEP_LIMIT,
        });
    }
    // The disk estimate `dem run` refuses on (issue 48 D4: `--snapshots 100000000` wrote a
    // snapshot every step, 453 MB in 90 s, no warning).
    let bytes = sim.output_bytes();
    if bytes > dem_core::output::driver::MAX_OUTPUT_BYTES_UNASKED {
        let o = &sim.scene.outputs;
        return Err(LabError::TooMuchOutput {
            scene: scene_file.display().to_string(),
            gb: bytes / 1e9,
            steps,
            discs: sim.world.state.discs.len(),
            snapshots: o.snapshot_plan(),
            limit_gb: dem_core::output::driver::MAX_OUTPUT_BYTES_UNASKED / 1e9,
        });
    }
    if let Some(h) = hook {
        sim.set_hook(h);
    }
    let out_dir = sim.out_dir().to_path_buf();
    let (summary, _) = sim.run(progress)?;
    let history = sim.take_history().ok_or_else(|| LabError::Param {
        field: format!("{}: outputs.history_every", scene_file.display()),
        reason: "0: a lab test analyses the history; set a positive cadence".into(),
    })?;
    Ok(LabRun {
        scene_file: scene_file.to_path_buf(),
        out_dir,
        summary,
        history,
        world: sim.world,
    })
}

/// Writes a scene atomically as pretty JSON, creating the folder.
pub fn write_scene(scene: &SceneFile, scene_file: &Path) -> Result<(), LabError> {
    if let Some(dir) = scene_file.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| LabError::Io {
            file: dir.display().to_string(),
            source,
        })?;
    }
    let text = serde_json::to_string_pretty(scene).map_err(|e| LabError::Io {
        file: scene_file.display().to_string(),
        source: std::io::Error::other(e),
    })?;
    write_atomic(scene_file, text.as_bytes())?;
    Ok(())
}
