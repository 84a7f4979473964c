//! The run driver: steps a scene's world to its end with the scene's output cadence, runs the
//! blow-up guard at output intervals, reports progress, and writes the summary.
//!
//! Cadence (steps counted by the world, so a restarted run keeps the same rhythm): the guard
//! runs every `guard_every` steps and before every output; a history row every `history_every`
//! steps; a VTK snapshot every `vtk_every` steps (and at step 0 of a fresh run); a checkpoint
//! every `checkpoint_every` steps; `ckpt-final.json`, the break log and the summary at the end.
//! Checkpoints are `.json` or `.bin` by `outputs.checkpoint_format`; with `outputs.checkpoints`
//! off none is written (neither periodic nor final), and the summary says the run cannot be
//! resumed.
//! A [`StepHook`] set by the caller (e.g. the cutting test's fragment deletion) runs every
//! `hook.every` steps, before that step's guard and outputs.
//! When the guard fails, the run stops: the last state that passed is written to
//! `last-good-state.json`, the history (all rows passed the guard) and the summary are written,
//! and the error names the step, the disc and the likely cause. No output ever holds a NaN.

use super::history::{History, Record, Row};
use super::run_controls::{gauge_members, gauge_positions, peak_of_record, wall_load};
use super::summary::{thread_cpu_s, RunSummary, RunTotals, SCHEMA as SUMMARY_SCHEMA};
use super::vtk::{self, BondLine, Collection, Entry};
use super::{write_atomic, OutputError};
use crate::bond::BondStatus;
use crate::checkpoint::{self, CheckpointError};
use crate::guard::GuardError;
use crate::pipeline::World;
use crate::scene::model::{Scene, Stop};
use crate::scene::SceneError;
use crate::state::State;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Overrides of the scene's run and output settings (the `dem run` flags).
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output folder instead of the scene's.
    pub out_dir: Option<PathBuf>,
    /// Continue from this checkpoint.
    pub restart: Option<PathBuf>,
    /// Stop when the world reaches this step count (instead of the scene's `max_steps`).
    pub max_steps: Option<u64>,
}

/// A function run on the world between steps: every `every` steps (counted by the world, so a
/// restarted run keeps the rhythm), after the step and before the guard and the outputs of
/// that step (so they see what it did). It must be a function of the world alone for a
/// restarted run to continue bit-identically. An error stops the run ([`RunError::Hook`]).
pub struct StepHook {
    pub every: u64,
    pub run: HookFn,
    /// Asked after `run`, at the same steps: `true` ends the run there as at failure
    /// ([`Ending::Failure`], summary status `failure`, a history row and the final checkpoint
    /// written), e.g. a crushed grain's first major breakage (`dem_lab::crushing::grain`). A
    /// function of the world alone, as `run`.
    #[allow(clippy::type_complexity)]
    pub stop: Option<Box<dyn FnMut(&World) -> bool>>,
}

/// A step hook's error: the caller's own error type (dem-core does not know it), kept as the
/// source of [`RunError::Hook`].
pub type HookError = Box<dyn std::error::Error + Send + Sync>;

/// The function of a [`StepHook`].
pub type HookFn = Box<dyn FnMut(&mut World) -> Result<(), HookError>>;

/// A restart's history rows that do not read: the checkpoint's fault.
fn rows_error(checkpoint: &Option<String>, (row, reason): (usize, String)) -> CheckpointError {
    CheckpointError::Format {
        file: checkpoint.clone().unwrap_or_default(),
        reason: format!("history row {row}: {reason}"),
    }
}

/// Why a run did not complete.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    #[error("step hook at step {step}: {source}")]
    Hook {
        step: u64,
        #[source]
        source: HookError,
    },
    #[error("run stopped by the blow-up guard: {error}; the last good state (step {good_step}) is in {saved}")]
    Guard {
        error: GuardError,
        good_step: u64,
        saved: String,
    },
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// Reached the scene's duration or step count.
    Completed,
    /// Stopped at the step cap before the end.
    MaxSteps,
    /// Stopped by `run.stop_after_peak`: the load fell below the set fraction of its peak.
    Failure,
}

/// A scene being run: the world plus the output state.
pub struct Simulation {
    pub scene: Scene,
    pub world: World,
    out: PathBuf,
    hash: String,
    history: Option<History>,
    pvd: Option<Collection>,
    group_names: Vec<String>,
    start_step: u64,
    max_steps: Option<u64>,
    restarted_from: Option<String>,
    /// The next of `outputs.vtk_count`'s evenly spread snapshots (k of 0 … N − 1).
    snap_k: u64,
    files: BTreeSet<String>,
    dt_range: [f64; 2],
    last_flush: Instant,
    output_time: Duration,
    /// Per gauge: membership by disc id (fixed when the scene is built).
    gauges: Vec<Vec<bool>>,
    /// Largest load so far (`run.stop_after_peak`), N.
    peak_load: f64,
    /// Deepest overlap (fraction of the radius) seen at the guard checks of this invocation.
    max_overlap: f64,
    /// The run's totals up to the checkpoint this invocation restarted from.
    before: Option<RunTotals>,
    /// Start of this invocation's stepping: wall clock and the driving thread's CPU time.
    started: Instant,
    cpu_started: Option<f64>,
    /// Run between steps (see [`StepHook`]); none by default.
    hook: Option<StepHook>,
}

/// The numbered checkpoints `ckpt-<step>.json` and `ckpt-<step>.bin` (either format) in `dir`,
/// by increasing step (the last is the newest).
pub fn numbered_checkpoints(dir: &Path) -> Result<Vec<(u64, PathBuf)>, OutputError> {
    let io = |source| OutputError::Io {
        file: dir.display().to_string(),
        source,
    };
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let entry = entry.map_err(io)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let step = name
            .strip_prefix("ckpt-")
            .and_then(|r| r.strip_suffix(".json").or_else(|| r.strip_suffix(".bin")))
            .filter(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|n| n.parse::<u64>().ok());
        if let Some(step) = step {
            found.push((step, entry.path()));
        }
    }
    found.sort();
    Ok(found)
}

/// Deletes the numbered checkpoints in `dir` but the newest `keep` (0: all of them); returns
/// the deleted paths.
pub fn prune_checkpoints(dir: &Path, keep: usize) -> Result<Vec<PathBuf>, OutputError> {
    let mut numbered = numbered_checkpoints(dir)?;
    let old = numbered.len().saturating_sub(keep);
    let mut gone = Vec::with_capacity(old);
    for (_, p) in numbered.drain(..old) {
        std::fs::remove_file(&p).map_err(|source| OutputError::Io {
            file: p.display().to_string(),
            source,
        })?;
        gone.push(p);
    }
    Ok(gone)
}

/// Whether `name` is a file the driver writes.
fn is_output_name(name: &str) -> bool {
    let numbered = |pre: &str, ext: &str| {
        name.strip_prefix(pre)
            .and_then(|r| r.strip_suffix(ext))
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
    };
    numbered("snap-", ".vtp")
        || numbered("walls-", ".vtp")
        || numbered("ckpt-", ".json")
        || numbered("ckpt-", ".bin")
        || [
            "ckpt-final.json",
            "ckpt-final.bin",
            "history.csv",
            "breaks.csv",
            "summary.json",
            "snapshots.pvd",
            "last-good-state.json",
        ]
        .contains(&name)
}

/// Whether `a` and `b` name one existing file, whatever the spelling (symlinks, `..`, hard
/// links: the same device and inode on Unix, the same resolved path elsewhere). A path that
/// does not exist names no file and is nobody's twin.
///
/// ```
/// let d = std::env::temp_dir().join(format!("dem-same-file-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&d).unwrap();
/// let f = d.join("m.json");
/// std::fs::write(&f, "{}").unwrap();
/// assert!(dem_core::output::driver::same_file(&f, &d.join(".").join("m.json")));
/// assert!(!dem_core::output::driver::same_file(&f, &d.join("other.json")));
/// std::fs::remove_dir_all(&d).unwrap();
/// ```
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = (&ma, &mb);
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
    }
}

/// Refuses an input file that is one of the files a run into `out` writes (issue 48 D1: `dem
/// run sc/summary.json --out sc` replaced its own scene with the summary). The file is
/// resolved first (symlinks, `..`), so any spelling of the same file is caught; a file that
/// does not exist yet, or an output folder not made yet, cannot be overwritten and passes.
pub fn check_not_an_output(input: &Path, out: &Path) -> Result<(), OutputError> {
    let (Ok(file), Ok(dir)) = (std::fs::canonicalize(input), std::fs::canonicalize(out)) else {
        return Ok(());
    };
    let name = file.file_name().and_then(|n| n.to_str()).unwrap_or("");
    if file.parent() == Some(dir.as_path()) && is_output_name(name) {
        return Err(OutputError::InputIsOutput {
            file: input.display().to_string(),
            name: name.to_string(),
            out: out.display().to_string(),
        });
    }
    Ok(())
}

/// Above this many bytes of snapshots and checkpoints (estimated by
/// [`Simulation::output_bytes`]) `dem run` states the figure and refuses unless `--yes`, and a
/// lab test refuses (issue 48 D4): 10 GB, an order of magnitude above the largest output of the
/// project's own runs (a 10 mm Table 2 cut, ~1,600 discs, 20 snapshots: ~30 MB).
pub const MAX_OUTPUT_BYTES_UNASKED: f64 = 10e9;

/// Bytes per disc of a VTK snapshot (with its contacts and bonds) and of a JSON and a binary
/// checkpoint, measured on an improved-ORC cutting specimen (~1,590 discs, ~3,170 bonds:
/// 0.55 MB a snapshot; 846 and 421 B per disc without the history rows; docs/reliability.md,
/// "Checkpoints").
const SNAPSHOT_BYTES_PER_DISC: f64 = 345.0;
const BINARY_SNAPSHOT_BYTES_PER_DISC: f64 = 292.0;
const JSON_CHECKPOINT_BYTES_PER_DISC: f64 = 846.0;
const BINARY_CHECKPOINT_BYTES_PER_DISC: f64 = 421.0;

/// History is rewritten at least this often while running (besides checkpoints and the end).
const FLUSH_EVERY: Duration = Duration::from_secs(5);

impl Simulation {
    /// Builds the scene's world (or loads the checkpoint) and prepares the outputs.
    pub fn new(scene: Scene, opts: &RunOptions) -> Result<Simulation, RunError> {
        Simulation::start(scene, opts, None)
    }

    /// As [`Simulation::new`], with the world the caller already built from `scene` by
    /// [`crate::scene::build()`] (to read it first: the cutting test sets its history cadence
    /// from the world's time step), so it is built once. The world must come from this scene
    /// (outputs aside: they do not enter the build). With `opts.restart` set, the checkpoint's
    /// world is used and `world` dropped.
    pub fn with_world(
        scene: Scene,
        world: World,
        opts: &RunOptions,
    ) -> Result<Simulation, RunError> {
        Simulation::start(scene, opts, Some(world))
    }

    fn start(
        scene: Scene,
        opts: &RunOptions,
        built: Option<World>,
    ) -> Result<Simulation, RunError> {
        let out = opts
            .out_dir
            .clone()
            .unwrap_or_else(|| scene.outputs.dir.clone());
        check_not_an_output(&scene.file, &out)?;
        let hash = scene.physics_hash();
        let (world, rows, snaps, restarted_from, before) = match &opts.restart {
            Some(p) => {
                let c = checkpoint::load(p, &hash)?;
                (
                    c.world,
                    c.history_rows,
                    c.snapshots,
                    Some(p.display().to_string()),
                    c.run,
                )
            }
            None => (
                match built {
                    Some(w) => w,
                    None => crate::scene::build(&scene)?,
                },
                String::new(),
                Vec::new(),
                None,
                None,
            ),
        };
        let gauges = {
            let g = &scene.outputs.gauges;
            if g.is_empty() {
                Vec::new()
            } else if opts.restart.is_none() {
                gauge_members(&scene, &world)?
            } else {
                // Same discs as the fresh run: membership from the built (initial) world.
                gauge_members(&scene, &crate::scene::build(&scene)?)?
            }
        };
        let group_names = world
            .bonds
            .as_ref()
            .map(|b| b.group_names())
            .unwrap_or_default();
        let o = &scene.outputs;
        let history = if o.history_every > 0 {
            let walls: Vec<&str> = world.state.walls.iter().map(|w| w.name.as_str()).collect();
            let groups: Vec<&str> = group_names.iter().map(String::as_str).collect();
            let gauges: Vec<&str> = o.gauges.iter().map(|g| g.name.as_str()).collect();
            let fj: Vec<&str> = (world.bonds.as_ref())
                .map(|b| {
                    (b.groups().iter())
                        .filter(|g| matches!(g.model, crate::bond::BondModel::FlatJoint(_)))
                        .map(|g| g.name.as_str())
                        .collect()
                })
                .unwrap_or_default();
            let mut h = History::with_gauges(&out.join("history.csv"), &walls, &gauges, &groups)
                .with_element_columns(&fj);
            let earlier = (h.set_rows(rows)).map_err(|e| rows_error(&restarted_from, e))?;
            Some((h, earlier))
        } else {
            None
        };
        // (A restart's peak so far, from the rows it brings.)
        let peak_load = (scene.run.stop_after_peak.as_ref())
            .zip(history.as_ref())
            .map_or(0.0, |(s, (_, earlier))| peak_of_record(earlier, s));
        let history = history.map(|(h, _)| h);
        let pvd = (o.vtk_every > 0 || o.vtk_count > 0).then(|| {
            let mut c = Collection::new(&out.join("snapshots.pvd"));
            c.entries = snaps;
            c
        });
        let dt = world.dt();
        Ok(Simulation {
            max_steps: opts.max_steps.or(scene.run.max_steps),
            start_step: world.state.step,
            snap_k: 0,
            scene,
            world,
            out,
            hash,
            history,
            pvd,
            group_names,
            restarted_from,
            files: BTreeSet::new(),
            dt_range: [dt, dt],
            last_flush: Instant::now(),
            output_time: Duration::ZERO,
            max_overlap: 0.0,
            gauges,
            peak_load,
            before,
            started: Instant::now(),
            cpu_started: thread_cpu_s(),
            hook: None,
        })
    }

    /// Run `hook` between steps (replaces an earlier one).
    pub fn set_hook(&mut self, hook: StepHook) {
        self.hook = Some(hook);
    }

    /// Stop at this world step (`None`: the scene's own `run.max_steps`); a further
    /// [`Simulation::run`] then goes on from where the previous one stopped (`dem bench
    /// cutting` runs an untimed approach, then the timed steps).
    pub fn set_max_steps(&mut self, max_steps: Option<u64>) {
        self.max_steps = max_steps.or(self.scene.run.max_steps);
    }

    /// The output folder.
    pub fn out_dir(&self) -> &Path {
        &self.out
    }

    /// Keeps the history's rows as numbers ([`Record`]) for [`Simulation::history`]; off by
    /// default (a plain run holds its history once, as text). Errors when the rows a restart
    /// brought do not read.
    pub fn keep_history(&mut self) -> Result<(), RunError> {
        if let Some(h) = self.history.as_mut() {
            (h.keep_record()).map_err(|e| rows_error(&self.restarted_from, e))?;
        }
        Ok(())
    }

    /// The record of [`Simulation::keep_history`], handed over (keeping stops).
    pub fn take_history(&mut self) -> Option<Record> {
        self.history.as_mut().and_then(History::take_record)
    }

    /// The history's rows as numbers (of the whole run: a restart brings the earlier
    /// invocations' rows from the checkpoint), if kept ([`Simulation::keep_history`]); `None`
    /// without a history (`outputs.history_every` = 0).
    pub fn history(&self) -> Option<&Record> {
        self.history.as_ref().and_then(History::record)
    }

    /// The stages the world runs.
    pub fn active_stages(&self) -> Vec<&'static str> {
        self.world.active_stages()
    }

    fn ending(&self) -> Option<Ending> {
        ending_of(&self.world.state, self.scene.run.stop, self.max_steps)
    }

    /// How far the run is along its stop: time for a duration, steps for a step count.
    fn progress_value(&self) -> f64 {
        progress_of(&self.world.state, self.scene.run.stop)
    }

    /// Where snapshot k of `outputs.vtk_count` = N falls: k/(N − 1) of the stop (the last
    /// exactly at it); infinity past the last (and for k ≥ 1 when N ≤ 1).
    fn snap_target(&self, k: u64) -> f64 {
        let n = self.scene.outputs.vtk_count;
        let end = match self.scene.run.stop {
            Stop::Steps(m) => m as f64,
            Stop::Duration(d) => d,
        };
        match k {
            0 => 0.0,
            _ if k >= n || n < 2 => f64::INFINITY,
            _ if k == n - 1 => end,
            _ => end * k as f64 / (n - 1) as f64,
        }
    }

    /// The disk a run's snapshots and checkpoints will take, estimated from its step count, disc
    /// count and output intervals (the numbered checkpoints kept are bounded by
    /// `outputs.checkpoint_keep`; `ckpt-final` counts once; none with `outputs.checkpoints` off).
    pub fn output_bytes(&self) -> f64 {
        let steps = self.total_steps();
        let o = &self.scene.outputs;
        let discs = self.world.state.discs.len() as f64;
        let every = |k: u64| steps.checked_div(k).unwrap_or(0);
        let snapshots = (every(o.vtk_every) + o.vtk_count) as f64;
        let per_snapshot = match o.vtk_format {
            vtk::Format::Ascii => SNAPSHOT_BYTES_PER_DISC,
            vtk::Format::Binary => BINARY_SNAPSHOT_BYTES_PER_DISC,
        };
        let numbered = every(o.checkpoint_every);
        let kept = match o.checkpoint_keep {
            0 => numbered,
            k => numbered.min(u64::from(k)),
        };
        let checkpoints = if o.checkpoints { kept + 1 } else { 0 };
        let per_checkpoint = match o.checkpoint_format {
            checkpoint::Format::Json => JSON_CHECKPOINT_BYTES_PER_DISC,
            checkpoint::Format::Binary => BINARY_CHECKPOINT_BYTES_PER_DISC,
        };
        discs * (snapshots * per_snapshot + checkpoints as f64 * per_checkpoint)
    }

    /// Estimated total steps of this invocation (exact for a step count).
    pub fn total_steps(&self) -> u64 {
        let st = &self.world.state;
        let end = match self.scene.run.stop {
            Stop::Steps(n) => n,
            Stop::Duration(d) => {
                let left = ((d - st.time) / self.world.dt()).ceil();
                st.step
                    + if left.is_finite() && left > 0.0 {
                        left as u64
                    } else {
                        0
                    }
            }
        };
        let end = self.max_steps.map_or(end, |m| end.min(m));
        end.saturating_sub(self.start_step)
    }

    fn record(&mut self, file: &Path) {
        if let Ok(rel) = file.strip_prefix(&self.out) {
            self.files.insert(rel.display().to_string());
        }
    }

    /// Runs to the end; `progress(done, total)` is called now and then.
    pub fn run(
        &mut self,
        progress: &mut dyn FnMut(u64, u64),
    ) -> Result<(RunSummary, Ending), RunError> {
        let t0 = Instant::now();
        (self.started, self.cpu_started) = (t0, thread_cpu_s());
        let mut o = self.scene.outputs.clone();
        if !o.checkpoints {
            o.checkpoint_every = 0;
        }
        let ext = o.checkpoint_format.extension();
        std::fs::create_dir_all(&self.out).map_err(|source| OutputError::Io {
            file: self.out.display().to_string(),
            source,
        })?;
        if self.restarted_from.is_none() {
            self.clear_stale()?;
        }
        remove_dead_temporaries(&self.out);
        self.guard(t0)?;
        if self.world.state.step == 0 && (o.vtk_every > 0 || o.vtk_count > 0) {
            self.snapshot()?;
        }
        // The evenly spread snapshots still to come: those past the start (a restart goes on
        // after the last one its checkpoint's state had passed).
        let here = self.progress_value();
        self.snap_k = (1..o.vtk_count)
            .find(|&k| self.snap_target(k) > here)
            .unwrap_or(o.vtk_count.max(1));
        let mut total = self.total_steps();
        progress(0, total);
        let every = |n: u64, s: u64| n > 0 && s.is_multiple_of(n);
        let ending = loop {
            if let Some(e) = self.ending() {
                break e;
            }
            // Step to the next output event (the nearest next multiple of a cadence) in one
            // batch (`World::run_while`, faster than single steps), stopping early when the
            // run ends: the same steps and checks as stepping one at a time.
            let s0 = self.world.state.step;
            let to_next = |n: u64| s0.checked_div(n).map_or(u64::MAX, |q| (q + 1) * n - s0);
            let hook_every = self.hook.as_ref().map_or(0, |h| h.every);
            let batch = [
                o.history_every,
                o.vtk_every,
                o.checkpoint_every,
                o.guard_every,
                hook_every,
            ]
            .map(to_next)
            .into_iter()
            .min()
            .unwrap_or(1);
            let (stop, max_steps, mut dr) = (self.scene.run.stop, self.max_steps, self.dt_range);
            // The batch also stops where the next evenly spread snapshot falls.
            let snap_at = self.snap_target(self.snap_k);
            self.world.run_while(batch, |w| {
                let dt = w.dt();
                dr = [dr[0].min(dt), dr[1].max(dt)];
                ending_of(&w.state, stop, max_steps).is_none()
                    && progress_of(&w.state, stop) < snap_at
            });
            self.dt_range = dr;
            let s = self.world.state.step;
            let mut hook_stop = false;
            if let Some(h) = self.hook.as_mut().filter(|_| every(hook_every, s)) {
                (h.run)(&mut self.world).map_err(|source| RunError::Hook { step: s, source })?;
                if let Some(f) = h.stop.as_mut() {
                    hook_stop = f(&self.world);
                }
            }
            let spread = self.progress_value() >= snap_at;
            while self.progress_value() >= self.snap_target(self.snap_k) {
                self.snap_k += 1;
            }
            let (h, v, c) = (
                every(o.history_every, s) || (hook_stop && o.history_every > 0),
                every(o.vtk_every, s) || spread,
                every(o.checkpoint_every, s),
            );
            if h || v || c || hook_stop || every(o.guard_every, s) {
                let ts = Instant::now();
                self.guard(t0)?;
                let mut failed = hook_stop;
                if h {
                    self.history_row()?;
                    failed |= self.failed();
                }
                if v {
                    self.snapshot()?;
                }
                if c {
                    self.checkpoint(&self.out.join(format!("ckpt-{s:09}.{ext}")))?;
                } else if self.last_flush.elapsed() > FLUSH_EVERY {
                    self.flush()?;
                }
                self.output_time += ts.elapsed();
                if matches!(self.scene.run.stop, Stop::Duration(_)) {
                    total = self.total_steps().max(s - self.start_step);
                }
                progress(s - self.start_step, total);
                if failed {
                    break Ending::Failure;
                }
            }
        };
        self.guard(t0)?;
        if o.checkpoints {
            self.checkpoint(&self.out.join(format!("ckpt-final.{ext}")))?;
        } else {
            self.flush()?;
        }
        let steps = self.world.state.step - self.start_step;
        progress(steps, steps);
        let status = match ending {
            Ending::Completed => "completed",
            Ending::MaxSteps => "max_steps",
            Ending::Failure => "failure",
        };
        let summary = self.summary(t0, status, None)?;
        Ok((summary, ending))
    }

    /// A fresh run removes the files an earlier run left in the output folder (only names this
    /// driver writes), so snapshots and checkpoints of two runs are never mixed.
    fn clear_stale(&self) -> Result<(), OutputError> {
        let io = |source| OutputError::Io {
            file: self.out.display().to_string(),
            source,
        };
        for entry in std::fs::read_dir(&self.out).map_err(io)? {
            let entry = entry.map_err(io)?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if is_output_name(&name) && entry.file_type().map_err(io)?.is_file() {
                std::fs::remove_file(entry.path()).map_err(io)?;
            }
        }
        Ok(())
    }

    /// Runs the guard; on failure writes what is safe and returns the error.
    fn guard(&mut self, t0: Instant) -> Result<(), RunError> {
        let error = match self.world.guard() {
            Ok(deepest) => {
                self.max_overlap = self.max_overlap.max(deepest);
                return Ok(());
            }
            Err(e) => e,
        };
        let saved = self.out.join("last-good-state.json");
        let good = self
            .world
            .last_good()
            .cloned()
            .unwrap_or_else(|| self.world.state.clone());
        let text = serde_json::to_string(&good).map_err(|e| OutputError::Io {
            file: saved.display().to_string(),
            source: std::io::Error::other(e),
        })?;
        write_atomic(&saved, text.as_bytes())?;
        self.record(&saved);
        self.flush()?;
        let _ = self.summary(t0, "stopped", Some(error.to_string()));
        Err(RunError::Guard {
            error,
            good_step: good.step,
            saved: saved.display().to_string(),
        })
    }

    fn history_row(&mut self) -> Result<(), OutputError> {
        let Some(h) = self.history.as_mut() else {
            return Ok(());
        };
        let broken = self
            .world
            .bonds
            .as_ref()
            .map(|b| b.broken_counts().to_vec())
            .unwrap_or_default();
        let elements: Vec<u64> = (self.world.bonds.as_ref())
            .filter(|b| b.has_flat_joints())
            .map(|b| b.elements_broken().into_iter().flatten().collect())
            .unwrap_or_default();
        let st = &self.world.state;
        let gauges = gauge_positions(st, &self.gauges);
        h.push(&Row {
            time: st.time,
            step: st.step,
            dt: self.world.dt(),
            walls: &st.walls,
            gauges: &gauges,
            energy: &self.world.energy(),
            broken: &broken,
            elements: &elements,
        })
    }

    /// `run.stop_after_peak`: updates the peak load and tells whether the load has fallen below
    /// the set fraction of it (once the peak has reached the arming load).
    fn failed(&mut self) -> bool {
        let Some(s) = &self.scene.run.stop_after_peak else {
            return false;
        };
        let load = wall_load(&self.world.state.walls, s);
        self.peak_load = self.peak_load.max(load);
        self.peak_load > 0.0 && self.peak_load >= s.min_load && load < s.below * self.peak_load
    }

    fn snapshot(&mut self) -> Result<(), OutputError> {
        let st = &self.world.state;
        let s = st.step;
        let lines: Vec<BondLine> = self
            .world
            .bonds
            .as_ref()
            .map(|b| {
                b.iter()
                    .enumerate()
                    .map(|(k, v)| BondLine {
                        i: v.i,
                        j: v.j,
                        group: v.group as u32,
                        intact: v.status == BondStatus::Intact,
                        normal_force: v.fn_,
                        shear_force: v.fs,
                        moment: v.m,
                        bonded_elements: b.flat_joint(k).map(|s| s.bonded_count()),
                    })
                    .collect()
            })
            .unwrap_or_default();
        let name = format!("snap-{s:09}.vtp");
        let path = self.out.join(&name);
        let format = self.scene.outputs.vtk_format;
        vtk::write_discs(&path, st, &lines, format)?;
        let mut new = vec![(0, name)];
        if !st.walls.is_empty() {
            let wname = format!("walls-{s:09}.vtp");
            vtk::write_walls(&self.out.join(&wname), &st.walls, format)?;
            new.push((1, wname));
        }
        let time = st.time;
        for (part, file) in new {
            self.record(&self.out.join(&file));
            if let Some(c) = self.pvd.as_mut() {
                c.entries.push(Entry {
                    time,
                    step: s,
                    part,
                    file,
                });
            }
        }
        if let Some(c) = &self.pvd {
            c.flush()?;
            let p = c.path.clone();
            self.record(&p);
        }
        Ok(())
    }

    /// Rewrites the history and the break log.
    fn flush(&mut self) -> Result<(), OutputError> {
        if let Some(h) = &self.history {
            h.flush()?;
            let p = h.path().to_path_buf();
            self.record(&p);
        }
        if let Some(b) = &self.world.bonds {
            let p = self.out.join("breaks.csv");
            b.log()
                .write_csv(&p, &self.group_names)
                .map_err(|source| OutputError::Io {
                    file: p.display().to_string(),
                    source,
                })?;
            self.record(&p);
        }
        self.last_flush = Instant::now();
        Ok(())
    }

    /// Writes a checkpoint (with the run's totals so far); after a numbered one, deletes the
    /// older numbered checkpoints beyond `outputs.checkpoint_keep`.
    fn checkpoint(&mut self, path: &Path) -> Result<(), RunError> {
        self.flush()?;
        let rows = self.history.as_ref().map_or("", |h| h.rows());
        let snaps = self.pvd.as_ref().map_or(&[][..], |c| &c.entries[..]);
        let totals = self.totals();
        checkpoint::save_as(
            path,
            self.scene.outputs.checkpoint_format,
            &self.world,
            &self.hash,
            rows,
            snaps,
            Some(&totals),
        )?;
        self.record(path);
        let keep = self.scene.outputs.checkpoint_keep as usize;
        if keep > 0 {
            for p in prune_checkpoints(&self.out, keep)? {
                if let Ok(rel) = p.strip_prefix(&self.out) {
                    self.files.remove(&rel.display().to_string());
                }
            }
        }
        Ok(())
    }

    /// The run's totals: the restart checkpoint's plus this invocation so far.
    fn totals(&self) -> RunTotals {
        let cpu = thread_cpu_s()
            .zip(self.cpu_started)
            .map(|(c1, c0)| (c1 - c0).max(0.0));
        RunTotals::then(
            self.before.as_ref(),
            self.started.elapsed().as_secs_f64(),
            cpu,
            self.dt_range,
            self.max_overlap,
        )
    }

    fn summary(
        &mut self,
        t0: Instant,
        status: &str,
        error: Option<String>,
    ) -> Result<RunSummary, OutputError> {
        let path = self.out.join("summary.json");
        if self.scene.outputs.summary {
            self.record(&path);
        }
        let w = &self.world;
        let st = &w.state;
        let steps = st.step - self.start_step;
        let wall = t0.elapsed();
        let stepping = wall.saturating_sub(self.output_time).as_secs_f64();
        let (bonds, broken) = w.bonds.as_ref().map_or((0, 0), |b| {
            (b.len(), b.broken_counts().iter().map(|c| c[0] + c[1]).sum())
        });
        let s = RunSummary {
            schema: SUMMARY_SCHEMA.into(),
            scene: self.scene.file.display().to_string(),
            name: self.scene.name.clone(),
            status: status.into(),
            error,
            restarted_from: self.restarted_from.clone(),
            active_stages: w.active_stages().iter().map(|s| s.to_string()).collect(),
            threads: crate::team::Threads::current().ranges,
            discs: st.discs.len(),
            clumps: st.clumps.len(),
            bonds,
            bonds_broken: broken,
            steps,
            final_step: st.step,
            time: st.time,
            dt: w.dt(),
            dt_min: self.dt_range[0],
            dt_max: self.dt_range[1],
            max_overlap_fraction: self.max_overlap,
            wall_time_s: wall.as_secs_f64(),
            cpu_time_s: thread_cpu_s()
                .zip(self.cpu_started)
                .map(|(c1, c0)| (c1 - c0).max(0.0)),
            whole_run: Some(self.totals()),
            particle_steps_per_s: if stepping > 0.0 {
                st.discs.len() as f64 * steps as f64 / stepping
            } else {
                0.0
            },
            energy: w.energy(),
            files: self.files.iter().cloned().collect(),
            not_finite: vec![],
            checkpoints: self.scene.outputs.checkpoints,
        };
        if self.scene.outputs.summary {
            s.save(&path)?;
        }
        Ok(s)
    }
}

/// Removes the temporary files (`.<output name>.<pid>.tmp`, see [`write_atomic`]) that a run
/// killed during a write left in `dir`: those of this driver's outputs whose process is gone
/// (Linux: no `/proc/<pid>`; elsewhere nothing is removed). Best effort: errors are ignored.
pub fn remove_dead_temporaries(dir: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(inner) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
            continue;
        };
        let Some((file, pid)) = inner.rsplit_once('.') else {
            continue;
        };
        let Ok(pid) = pid.parse::<u32>() else {
            continue;
        };
        let dead = pid != std::process::id() && !Path::new("/proc").join(pid.to_string()).exists();
        if dead && is_output_name(file) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Time (a duration stop) or steps (a step-count stop) run so far.
fn progress_of(st: &State, stop: Stop) -> f64 {
    match stop {
        Stop::Steps(_) => st.step as f64,
        Stop::Duration(_) => st.time,
    }
}

/// How a run at `st` ends, if it has: the scene's stop reached, or the invocation's step limit.
fn ending_of(st: &State, stop: Stop, max_steps: Option<u64>) -> Option<Ending> {
    let done = match stop {
        Stop::Steps(n) => st.step >= n,
        Stop::Duration(d) => st.time >= d,
    };
    if done {
        Some(Ending::Completed)
    } else if max_steps.is_some_and(|m| st.step >= m) {
        Some(Ending::MaxSteps)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::{is_output_name, remove_dead_temporaries};

    #[test]
    fn only_driver_names_are_outputs() {
        for n in [
            "snap-000000100.vtp",
            "walls-1.vtp",
            "ckpt-000000200.json",
            "ckpt-000000200.bin",
            "ckpt-final.json",
            "ckpt-final.bin",
            "history.csv",
        ] {
            assert!(is_output_name(n), "{n}");
        }
        for n in [
            "snap-.vtp",
            "snap-12a.vtp",
            "notes.txt",
            "ckpt-half.json",
            "ckpt-half.bin",
            "ckpt-1.bin.bak",
            "history.csv.bak",
            "scene.json",
        ] {
            assert!(!is_output_name(n), "{n}");
        }
    }

    /// Issue 20: temporaries of a killed run's writes go at the next start; those of live
    /// processes (this one) and of files the driver does not write stay.
    #[cfg(target_os = "linux")]
    #[test]
    fn dead_runs_temporaries_are_removed() {
        let dir = std::env::temp_dir().join(format!("dem-driver-tmp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // A pid that is not running: above the kernel's pid_max (at most 2^22).
        let dead = 4_194_304 + 17;
        let me = std::process::id();
        let names = [
            format!(".ckpt-000000200.json.{dead}.tmp"),
            format!(".history.csv.{dead}.tmp"),
            format!(".ckpt-000000300.json.{me}.tmp"),
            format!(".notes.txt.{dead}.tmp"),
            ".ckpt-final.json.abc.tmp".to_string(),
        ];
        for n in &names {
            std::fs::write(dir.join(n), "partial").unwrap();
        }
        remove_dead_temporaries(&dir);
        let mut left: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        let mut want = names[2..].to_vec();
        want.sort();
        assert_eq!(left, want);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
