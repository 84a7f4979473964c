//! Checkpoints: the serialized [`World`] (serde_json with `float_roundtrip`, so every f64 reads
//! back bit-identical), the scene's physics hash, and the output bookkeeping (history rows so far,
//! snapshot list), written atomically. A run restarted from a checkpoint continues
//! bit-identically: the same steps give the same bytes of state as an uninterrupted run.
//!
//! **Checksum.** The file opens with `{"checksum":"<SHA-256>",` followed by the rest of the
//! checkpoint's JSON; the SHA-256 (hex) is over the JSON text without that field, i.e. `{`
//! and the bytes after the comma. [`load`] recomputes it over the bytes as read, so any change
//! to the file (a digit edited, a truncated or mixed write) is refused naming the file, before
//! the world is deserialized. Checkpoints written before the checksum existed (no such field)
//! still load. A checkpoint edited on purpose loads again once its `checksum` field is removed.

use crate::output::summary::RunTotals;
use crate::output::vtk::Entry;
use crate::pipeline::World;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
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
    #[error("{file}: the checkpoint is corrupt: its checksum is {stored} but its content hashes to {computed} (changed after it was written, or a partial copy); use an earlier checkpoint, or remove the `checksum` field if you edited it on purpose")]
    Corrupt {
        file: String,
        stored: String,
        computed: String,
    },
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
    /// SHA-256 of the file without this field (see the module docs); `None` in checkpoints
    /// written before it existed.
    #[serde(default)]
    pub checksum: Option<String>,
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

/// Where the checksummed prefix of a checkpoint file starts and how long its hash is.
const CHECKSUM_PREFIX: &str = "{\"checksum\":\"";
const CHECKSUM_HEX: usize = 64;

/// SHA-256 of `bytes`, lower-case hex.
fn sha256_hex(bytes: &[&[u8]]) -> String {
    let mut h = Sha256::new();
    for b in bytes {
        h.update(b);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Puts the checksum field in front of a checkpoint's JSON text `body` (an object).
fn with_checksum(body: &str) -> String {
    let hash = sha256_hex(&[body.as_bytes()]);
    let rest = &body[1..];
    let sep = if rest.starts_with('}') { "" } else { "," };
    format!("{CHECKSUM_PREFIX}{hash}\"{sep}{rest}")
}

/// Checks the checksum of a checkpoint file's text, if it has one (the module docs).
fn verify_checksum(file: &str, text: &str) -> Result<(), CheckpointError> {
    let Some(after) = text.strip_prefix(CHECKSUM_PREFIX) else {
        return Ok(());
    };
    let stored = after.get(..CHECKSUM_HEX).unwrap_or(after);
    let rest = after
        .get(CHECKSUM_HEX..)
        .and_then(|r| r.strip_prefix('"'))
        .ok_or_else(|| CheckpointError::Format {
            file: file.to_string(),
            reason: "the checksum field is not 64 hex digits".into(),
        })?;
    let rest = rest.strip_prefix(',').unwrap_or(rest);
    let computed = sha256_hex(&[b"{", rest.as_bytes()]);
    if computed != stored {
        return Err(CheckpointError::Corrupt {
            file: file.to_string(),
            stored: stored.chars().take(12).collect(),
            computed: computed[..12].to_string(),
        });
    }
    Ok(())
}

/// Serializes a checkpoint to JSON text (compact), its checksum first.
pub fn to_json(
    world: &World,
    scene_hash: &str,
    history_rows: &str,
    snapshots: &[Entry],
    run: Option<&RunTotals>,
) -> Result<String, serde_json::Error> {
    let body = serde_json::to_string(&CheckpointRef {
        schema: SCHEMA,
        scene_hash,
        history_rows,
        snapshots,
        run,
        world,
    })?;
    Ok(with_checksum(&body))
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

/// Parses a checkpoint's JSON text, checking its checksum and schema but not the scene that
/// made it (for tools that only look at the state, e.g. `dem render`); `file` names it in
/// errors. [`load`] adds the scene check for restarts.
pub fn parse(text: &str, file: &str) -> Result<Checkpoint, CheckpointError> {
    verify_checksum(file, text)?;
    let c: Checkpoint = serde_json::from_str(text).map_err(|e| CheckpointError::Format {
        file: file.to_string(),
        reason: e.to_string(),
    })?;
    if c.schema != SCHEMA {
        return Err(CheckpointError::Format {
            file: file.to_string(),
            reason: format!("schema is {:?}, expected {SCHEMA:?}", c.schema),
        });
    }
    let mut c = c;
    c.world
        .check_restored()
        .map_err(|e| CheckpointError::Format {
            file: file.to_string(),
            reason: format!("its world is not consistent: {e}"),
        })?;
    Ok(c)
}

/// Reads a checkpoint, checks its checksum and that it was made from a scene with physics hash
/// `scene_hash`.
pub fn load(path: &Path, scene_hash: &str) -> Result<Checkpoint, CheckpointError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| CheckpointError::Io {
        file: file.clone(),
        source,
    })?;
    let c = parse(&text, &file)?;
    if c.scene_hash != scene_hash {
        return Err(CheckpointError::SceneMismatch {
            file,
            found: c.scene_hash,
            expected: scene_hash.to_string(),
        });
    }
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksum_round_trips_and_catches_one_changed_digit() {
        let body = r#"{"schema":"dem.checkpoint/1","world":{"x":[0.125,2.5]}}"#;
        let text = with_checksum(body);
        assert!(text.starts_with(CHECKSUM_PREFIX));
        // The rest is the body without its opening brace, so the hash is over the body itself.
        assert_eq!(
            &text[CHECKSUM_PREFIX.len() + CHECKSUM_HEX + 2..],
            &body[1..]
        );
        assert_eq!(
            &text[CHECKSUM_PREFIX.len()..][..CHECKSUM_HEX],
            sha256_hex(&[body.as_bytes()])
        );
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["world"]["x"][1], 2.5);
        verify_checksum("c.json", &text).unwrap();
        let bad = text.replace("2.5", "3.5");
        let e = verify_checksum("c.json", &bad).unwrap_err().to_string();
        assert!(e.starts_with("c.json: the checkpoint is corrupt"), "{e}");
        // A truncated copy is refused too; a file without the field (older) is accepted.
        assert!(verify_checksum("c.json", &text[..text.len() - 3]).is_err());
        assert!(verify_checksum("c.json", &text[..30]).is_err());
        verify_checksum("c.json", body).unwrap();
        // An empty object gets no dangling comma.
        assert!(serde_json::from_str::<serde_json::Value>(&with_checksum("{}")).is_ok());
    }
}
