//! Checkpoints: the serialized [`World`] (serde_json with `float_roundtrip`, so every f64 reads
//! back bit-identical), the scene's physics hash, and the output bookkeeping (history rows so far,
//! snapshot list), written atomically. A run restarted from a checkpoint continues
//! bit-identically: the same steps give the same bytes of state as an uninterrupted run.

use crate::output::summary::RunTotals;
use crate::output::vtk::Entry;
use crate::pipeline::World;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Schema identifier of a checkpoint file.
pub const SCHEMA: &str = "dem.checkpoint/1";

/// Errors saving or loading a checkpoint.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{file}: cannot read or write: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    #[error("{file}: not a checkpoint: {reason}")]
    Format { file: String, reason: String },
    #[error("{file}: made from a different scene (physics hash {found}, the scene has {expected}); restart with the scene that wrote it")]
    SceneMismatch {
        file: String,
        found: String,
        expected: String,
    },
}

/// What a checkpoint holds (borrowed for writing).
#[derive(Serialize)]
struct CheckpointRef<'a> {
    schema: &'a str,
    scene_hash: &'a str,
    history_rows: &'a str,
    snapshots: &'a [Entry],
    #[serde(skip_serializing_if = "Option::is_none")]
    run: Option<&'a RunTotals>,
    world: &'a World,
}

/// A loaded checkpoint.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Checkpoint {
    pub schema: String,
    pub scene_hash: String,
    /// History CSV rows written up to the checkpoint (without the header).
    pub history_rows: String,
    /// VTK snapshots written up to the checkpoint.
    pub snapshots: Vec<Entry>,
    /// The run's totals up to the checkpoint (run time, dt range, deepest overlap, over all
    /// invocations); `None` in checkpoints written before they were recorded.
    #[serde(default)]
    pub run: Option<RunTotals>,
    pub world: World,
}

/// Serializes a checkpoint to JSON text (compact).
pub fn to_json(
    world: &World,
    scene_hash: &str,
    history_rows: &str,
    snapshots: &[Entry],
    run: Option<&RunTotals>,
) -> Result<String, serde_json::Error> {
    serde_json::to_string(&CheckpointRef {
        schema: SCHEMA,
        scene_hash,
        history_rows,
        snapshots,
        run,
        world,
    })
}

/// Writes a checkpoint atomically.
pub fn save(
    path: &Path,
    world: &World,
    scene_hash: &str,
    history_rows: &str,
    snapshots: &[Entry],
    run: Option<&RunTotals>,
) -> Result<(), CheckpointError> {
    let file = path.display().to_string();
    let text = to_json(world, scene_hash, history_rows, snapshots, run).map_err(|e| {
        CheckpointError::Format {
            file: file.clone(),
            reason: e.to_string(),
        }
    })?;
    clumpgen::io::write_atomic(path, text.as_bytes())
        .map_err(|source| CheckpointError::Io { file, source })
}

/// Reads a checkpoint and checks that it was made from a scene with physics hash `scene_hash`.
pub fn load(path: &Path, scene_hash: &str) -> Result<Checkpoint, CheckpointError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| CheckpointError::Io {
        file: file.clone(),
        source,
    })?;
    let c: Checkpoint = serde_json::from_str(&text).map_err(|e| CheckpointError::Format {
        file: file.clone(),
        reason: e.to_string(),
    })?;
    if c.schema != SCHEMA {
        return Err(CheckpointError::Format {
            file,
            reason: format!("schema is {:?}, expected {SCHEMA:?}", c.schema),
        });
    }
    if c.scene_hash != scene_hash {
        return Err(CheckpointError::SceneMismatch {
            file,
            found: c.scene_hash,
            expected: scene_hash.to_string(),
        });
    }
    Ok(c)
}
