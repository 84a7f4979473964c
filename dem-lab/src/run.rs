//! Running a lab-test scene: the scene is written as a plain file first (so the user can edit
//! and re-run it with `dem run`), then loaded and run exactly as `dem run` would, and its
//! history read back.

use super::history::Table;
use super::LabError;
use dem_core::output::driver::{RunOptions, Simulation, StepHook};
use dem_core::output::summary::RunSummary;
use dem_core::output::write_atomic;
use dem_core::World;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// A finished lab run.
pub struct LabRun {
    /// The scene file written and run.
    pub scene_file: PathBuf,
    /// Its output folder.
    pub out_dir: PathBuf,
    pub summary: RunSummary,
    /// `history.csv` read back.
    pub history: Table,
    /// The world at the end of the run (for analyses of the final state: chips, surfaces).
    pub world: World,
}

/// A lab test that needs more steps than this is refused before it starts, as `dem run` refuses
/// one without `--yes` (issue 20, bounded work): 10⁹ steps are ~40 × the longest Table 2 cut
/// (27 M steps), about 14 core-hours for 1,000 discs at 2e7 particle-steps/s.
pub const STEP_LIMIT: u64 = 1_000_000_000;

/// Writes `scene` to `scene_file` (atomically, pretty JSON), runs it with `opts` (output folder:
/// `opts.out_dir`, else the scene's), calling `progress(done, total)` now and then.
pub fn run_scene(
    scene: &Value,
    scene_file: &Path,
    opts: &RunOptions,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<LabRun, LabError> {
    run_scene_with(scene, scene_file, opts, progress, None)
}

/// [`run_scene`] with a function run between steps (see [`StepHook`]).
pub fn run_scene_with(
    scene: &Value,
    scene_file: &Path,
    opts: &RunOptions,
    progress: &mut dyn FnMut(u64, u64),
    hook: Option<StepHook>,
) -> Result<LabRun, LabError> {
    write_scene(scene, scene_file)?;
    let loaded = dem_core::scene::load(scene_file)?;
    let mut sim = Simulation::new(loaded, opts)?;
    let steps = sim.total_steps();
    if steps > STEP_LIMIT {
        return Err(LabError::TooManySteps {
            scene: scene_file.display().to_string(),
            steps,
            dt: sim.world.dt(),
            limit: STEP_LIMIT,
        });
    }
    if let Some(h) = hook {
        sim.set_hook(h);
    }
    let out_dir = sim.out_dir().to_path_buf();
    let (summary, _) = sim.run(progress)?;
    let hist = out_dir.join("history.csv");
    let history = Table::read(&hist)?;
    Ok(LabRun {
        scene_file: scene_file.to_path_buf(),
        out_dir,
        summary,
        history,
        world: sim.world,
    })
}

/// Writes a scene JSON atomically, creating the folder.
pub fn write_scene(scene: &Value, scene_file: &Path) -> Result<(), LabError> {
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
