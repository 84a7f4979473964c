//! Checkpoints: the serialized [`World`] (serde_json with `float_roundtrip`, so every f64 reads
//! back bit-identical), the scene's physics hash, and the output bookkeeping (history rows so far,
//! snapshot list), written atomically. A run restarted from a checkpoint continues
//! bit-identically: the same steps give the same bytes of state as an uninterrupted run.
//!
//! **Checksum.** The file opens with `{"checksum":"<SHA-256>",` followed by the rest of the
//! checkpoint's JSON; the SHA-256 (hex) is over the *content* without that field, in a
//! canonical form (compact, object keys sorted, numbers in their shortest round-trip form).
//! [`load`] parses the file and recomputes it, so any change to a value (a digit edited, a
//! truncated or mixed write) is refused naming the file, before the world is deserialized,
//! whatever the spacing or key order of the file (a checkpoint re-saved by another JSON library
//! with nothing changed still loads; one space after `"checksum":` does not switch the check
//! off). Checkpoints written before the canonical form (the hash over the bytes after the
//! field) load while those bytes are unchanged; those written before the checksum existed (no
//! such field) still load. A checkpoint edited on purpose loads again once its `checksum`
//! field is removed: that is the one override.
//!
//! **Two formats, one content.** A checkpoint is written as JSON (above; `ckpt-<step>.json`,
//! the default) or in the binary format below (`ckpt-<step>.bin`, scene field
//! `outputs.checkpoint_format = "binary"` or `dem run --checkpoint-format binary`). Both hold
//! the same things (the world with its bonds, neighbour lists and contact history, the history
//! rows so far, the snapshot list, the run totals) and a restart from either continues
//! bit-identically. [`parse_bytes`] and [`load`] read either, telling them apart by the
//! binary magic (a JSON checkpoint starts with `{`).
//!
//! **Binary format, version 1.** A 136-byte header, then three sections back to back; integers
//! little-endian:
//!
//! | offset | bytes | field |
//! |-------:|------:|-------|
//! | 0 | 8 | magic `DEMCKPT\0` (`44 45 4d 43 4b 50 54 00`) |
//! | 8 | 4 | format version, u32 = 1 |
//! | 12 | 4 | number of sections, u32 = 3 |
//! | 16 | 64 | the scene's physics hash ([`crate::scene::model::Scene::physics_hash`]), 64 lower-case hex ASCII digits |
//! | 80 | 32 | SHA-256 (raw bytes) of the whole file without these 32 bytes: bytes 0..80 then 112..end |
//! | 112 | 8 | length of section 1 in bytes, u64 |
//! | 120 | 8 | length of section 2, u64 |
//! | 128 | 8 | length of section 3, u64 |
//! | 136 | … | section 1: the history CSV rows so far (UTF-8, without the header line) |
//! | … | … | section 2: bookkeeping, MessagePack map `{snapshots, run}` (the JSON checkpoint's fields of those names) |
//! | … | … | section 3: the [`World`], MessagePack |
//!
//! The sections end exactly at the end of the file. MessagePack (<https://msgpack.org>, a
//! published specification; its own numbers are big-endian) carries the same serde data model
//! as the JSON checkpoint, structs as maps with their field names, so every field the JSON
//! form has is there under the same name and optional ones may be absent as in JSON; an f64 is
//! its 8 IEEE-754 bytes, so it reads back bit-identical. It is written and read by the
//! `rmp-serde` crate: a self-describing encoding is needed because the world's serde form uses
//! internally tagged enums and skipped empty fields, which bincode-like formats cannot read
//! back. An f64 takes 9 bytes instead of JSON's ~20 characters, so a binary checkpoint is
//! about half the size of the JSON one and faster to write and read (measured figures, per
//! disc, in `docs/scene-schema.md`).
//!
//! **Reading hostile files.** [`parse_bytes`] never panics and allocates in proportion to the
//! file's size: the header is checked first (magic, version, section count), the section
//! lengths must add up to the bytes after the header exactly (a truncated or padded file is
//! refused before anything is decoded), the checksum is checked before decoding, and the
//! MessagePack decoder reads from the byte slice, refusing any length that runs past its end
//! and preallocating at most 1 MiB per container.

use crate::output::summary::RunTotals;
use crate::output::vtk::Entry;
use crate::pipeline::World;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::Path;

/// Schema identifier of a checkpoint file.
pub const SCHEMA: &str = "dem.checkpoint/1";

/// First bytes of a binary checkpoint (see the module docs).
pub const MAGIC: [u8; 8] = *b"DEMCKPT\0";
/// Version of the binary format this build writes and reads.
pub const BINARY_VERSION: u32 = 1;
/// Sections of a version-1 binary checkpoint: history rows, bookkeeping, world.
const SECTIONS: usize = 3;
/// Bytes before the first section of a binary checkpoint.
pub const HEADER_LEN: usize = 16 + HASH_HEX + 32 + 8 * SECTIONS;
/// Offset of the SHA-256 checksum in the binary header.
const SUM_AT: usize = 16 + HASH_HEX;
/// Hex digits of a scene physics hash.
const HASH_HEX: usize = 64;

/// The file format of a checkpoint: scene field `outputs.checkpoint_format`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// JSON text with a SHA-256 checksum field (`ckpt-<step>.json`); the default.
    #[default]
    Json,
    /// The documented binary format (`ckpt-<step>.bin`, see the module docs): about half the
    /// size, and faster to write and read.
    Binary,
}

impl Format {
    /// File extension of this format's checkpoints (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Json => "json",
            Format::Binary => "bin",
        }
    }

    /// `true` for the default, JSON (to leave the field out of written scenes).
    pub fn is_json(&self) -> bool {
        *self == Format::Json
    }
}

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
    #[error("{file}: the checkpoint is corrupt: its checksum is {stored} but its content hashes to {computed} (changed after it was written, or a partial copy); use an earlier checkpoint (or, for a JSON checkpoint edited on purpose, remove its `checksum` field)")]
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

/// Why a world could not be encoded as a checkpoint.
#[derive(Debug, thiserror::Error)]
pub enum EncodeError {
    #[error("the scene hash {0:?} is not {HASH_HEX} hex digits")]
    SceneHash(String),
    #[error("bookkeeping: {0}")]
    Books(rmp_serde::encode::Error),
    #[error("world: {0}")]
    World(rmp_serde::encode::Error),
    #[error("{0}")]
    Json(serde_json::Error),
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

/// The bookkeeping section of a binary checkpoint (borrowed for writing).
#[derive(Serialize)]
struct BooksRef<'a> {
    snapshots: &'a [Entry],
    #[serde(skip_serializing_if = "Option::is_none")]
    run: Option<&'a RunTotals>,
}

/// The bookkeeping section of a binary checkpoint, read back.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Books {
    snapshots: Vec<Entry>,
    #[serde(default)]
    run: Option<RunTotals>,
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

/// Feeds the canonical form of `v` to `h`: compact JSON with every object's keys sorted
/// (byte order), numbers as serde_json prints them (shortest round-trip form), strings
/// escaped as serde_json escapes them. Two texts of the same content (other spacing, key
/// order or number spelling, as a re-save by another JSON library gives) have one canonical
/// form; any change of a value changes it. `skip` leaves out one key of the top object
/// (the checksum itself), so the content is hashed without copying it.
fn canonical(v: &serde_json::Value, skip: Option<&str>, h: &mut Sha256) {
    use serde_json::Value;
    match v {
        Value::Null => h.update(b"null"),
        Value::Bool(b) => h.update(if *b { &b"true"[..] } else { &b"false"[..] }),
        Value::Number(n) => h.update(n.to_string().as_bytes()),
        Value::String(s) => h.update(quoted(s).as_bytes()),
        Value::Array(a) => {
            h.update(b"[");
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    h.update(b",");
                }
                canonical(x, None, h);
            }
            h.update(b"]");
        }
        Value::Object(m) => {
            let mut keys: Vec<&String> = m.keys().filter(|k| Some(k.as_str()) != skip).collect();
            keys.sort();
            h.update(b"{");
            for (i, k) in keys.into_iter().enumerate() {
                if i > 0 {
                    h.update(b",");
                }
                h.update(quoted(k).as_bytes());
                h.update(b":");
                canonical(&m[k], None, h);
            }
            h.update(b"}");
        }
    }
}

/// `s` as a JSON string literal, escaped as serde_json escapes it (no copy of `s` first).
fn quoted(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_default()
}

/// SHA-256 (hex) of the canonical form of a checkpoint's content without its `checksum`.
fn content_hash(v: &serde_json::Value) -> String {
    let mut h = Sha256::new();
    canonical(v, Some("checksum"), &mut h);
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// Puts the checksum field in front of a checkpoint's JSON text `body` (an object): the
/// SHA-256 of the body's canonical form ([`canonical`]).
fn with_checksum(body: &str) -> String {
    let hash = match serde_json::from_str::<serde_json::Value>(body) {
        Ok(v) => content_hash(&v),
        // (Not reached for the bodies `to_json` serialises; hash the text as it is.)
        Err(_) => sha256_hex(&[body.as_bytes()]),
    };
    let rest = &body[1..];
    let sep = if rest.starts_with('}') { "" } else { "," };
    format!("{CHECKSUM_PREFIX}{hash}\"{sep}{rest}")
}

/// Checks the checksum of a checkpoint file's text, if it has a `checksum` field (the module
/// docs): on the parsed content, so that neither spacing nor key order nor a re-save can turn
/// the check off, and any edited value is refused. Files written before the canonical form
/// (their hash is over their own bytes after the field) are accepted while those bytes are
/// unchanged.
fn verify_checksum(file: &str, text: &str) -> Result<(), CheckpointError> {
    let format = |reason: String| CheckpointError::Format {
        file: file.to_string(),
        reason,
    };
    let v: serde_json::Value =
        serde_json::from_str(text).map_err(|e| format(format!("not JSON: {e}")))?;
    let Some(field) = v.get("checksum") else {
        return Ok(());
    };
    let stored = field
        .as_str()
        .filter(|s| s.len() == CHECKSUM_HEX && s.bytes().all(|b| b.is_ascii_hexdigit()))
        .ok_or_else(|| format("the checksum field is not 64 hex digits".into()))?;
    // Written before the canonical form: the hash of the bytes after the field.
    let legacy = text
        .strip_prefix(CHECKSUM_PREFIX)
        .and_then(|a| a.get(CHECKSUM_HEX..))
        .and_then(|r| r.strip_prefix('"'))
        .map(|r| sha256_hex(&[b"{", r.strip_prefix(',').unwrap_or(r).as_bytes()]));
    if legacy.as_deref() == Some(stored) {
        return Ok(());
    }
    let computed = content_hash(&v);
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

/// Serializes a checkpoint in the binary format (the module docs), its header first.
pub fn to_binary(
    world: &World,
    scene_hash: &str,
    history_rows: &str,
    snapshots: &[Entry],
    run: Option<&RunTotals>,
) -> Result<Vec<u8>, EncodeError> {
    if scene_hash.len() != HASH_HEX || !scene_hash.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(EncodeError::SceneHash(scene_hash.to_string()));
    }
    let mut buf = Vec::with_capacity(HEADER_LEN + history_rows.len() + 64 * 1024);
    buf.extend_from_slice(&MAGIC);
    buf.extend_from_slice(&BINARY_VERSION.to_le_bytes());
    buf.extend_from_slice(&(SECTIONS as u32).to_le_bytes());
    buf.extend_from_slice(scene_hash.as_bytes());
    buf.resize(HEADER_LEN, 0);
    let mut lens = [0u64; SECTIONS];
    let mut start = buf.len();
    buf.extend_from_slice(history_rows.as_bytes());
    lens[0] = (buf.len() - start) as u64;
    start = buf.len();
    rmp_serde::encode::write_named(&mut buf, &BooksRef { snapshots, run })
        .map_err(EncodeError::Books)?;
    lens[1] = (buf.len() - start) as u64;
    start = buf.len();
    rmp_serde::encode::write_named(&mut buf, world).map_err(EncodeError::World)?;
    lens[2] = (buf.len() - start) as u64;
    for (k, l) in lens.iter().enumerate() {
        let at = SUM_AT + 32 + 8 * k;
        buf[at..at + 8].copy_from_slice(&l.to_le_bytes());
    }
    let sum = binary_checksum(&buf);
    buf[SUM_AT..SUM_AT + 32].copy_from_slice(&sum);
    Ok(buf)
}

/// SHA-256 of a binary checkpoint without its checksum field (`bytes` holds at least the
/// header).
fn binary_checksum(bytes: &[u8]) -> [u8; 32] {
    let mut h = Sha256::new();
    h.update(&bytes[..SUM_AT]);
    h.update(&bytes[SUM_AT + 32..]);
    h.finalize().into()
}

/// Deepest nesting of MessagePack containers a checkpoint section may have (a world nests about
/// 8 deep); deeper input is refused before it can exhaust the stack.
const MAX_DEPTH: usize = 64;

/// Decodes one MessagePack section, refusing nesting deeper than [`MAX_DEPTH`].
fn decode<'de, T: Deserialize<'de>>(bytes: &'de [u8]) -> Result<T, rmp_serde::decode::Error> {
    let mut de = rmp_serde::Deserializer::from_read_ref(bytes);
    de.set_max_depth(MAX_DEPTH);
    T::deserialize(&mut de)
}

/// Lower-case hex of `bytes`.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Writes a JSON checkpoint atomically (see [`save_as`] for either format).
pub fn save(
    path: &Path,
    world: &World,
    scene_hash: &str,
    history_rows: &str,
    snapshots: &[Entry],
    run: Option<&RunTotals>,
) -> Result<(), CheckpointError> {
    save_as(
        path,
        Format::Json,
        world,
        scene_hash,
        history_rows,
        snapshots,
        run,
    )
}

/// Writes a checkpoint in `format` atomically.
pub fn save_as(
    path: &Path,
    format: Format,
    world: &World,
    scene_hash: &str,
    history_rows: &str,
    snapshots: &[Entry],
    run: Option<&RunTotals>,
) -> Result<(), CheckpointError> {
    let file = path.display().to_string();
    let bytes = match format {
        Format::Json => to_json(world, scene_hash, history_rows, snapshots, run)
            .map(String::into_bytes)
            .map_err(EncodeError::Json),
        Format::Binary => to_binary(world, scene_hash, history_rows, snapshots, run),
    }
    .map_err(|e| CheckpointError::Format {
        file: file.clone(),
        reason: e.to_string(),
    })?;
    clumpgen::io::write_atomic(path, &bytes).map_err(|source| CheckpointError::Io { file, source })
}

/// Parses a checkpoint in either format (binary when `bytes` start with [`MAGIC`], JSON
/// otherwise), checking its checksum, its format and its world's consistency but not the scene
/// that made it; `file` names it in errors. Never panics, and allocates in proportion to
/// `bytes.len()` whatever they hold (the entry for fuzzing).
pub fn parse_bytes(bytes: &[u8], file: &str) -> Result<Checkpoint, CheckpointError> {
    if bytes.starts_with(&MAGIC) {
        return parse_binary(bytes, file);
    }
    let text = std::str::from_utf8(bytes).map_err(|e| CheckpointError::Format {
        file: file.to_string(),
        reason: format!("neither a binary checkpoint (no magic) nor UTF-8 JSON text: {e}"),
    })?;
    parse(text, file)
}

/// Parses a binary checkpoint (the module docs); see [`parse_bytes`].
fn parse_binary(bytes: &[u8], file: &str) -> Result<Checkpoint, CheckpointError> {
    let bad = |reason: String| CheckpointError::Format {
        file: file.to_string(),
        reason,
    };
    if bytes.len() < HEADER_LEN {
        return Err(bad(format!(
            "truncated binary checkpoint: {} bytes, its header alone has {HEADER_LEN}",
            bytes.len()
        )));
    }
    let u32_at =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let version = u32_at(8);
    if version != BINARY_VERSION {
        return Err(bad(format!(
            "binary checkpoint version {version}; this build reads version {BINARY_VERSION}"
        )));
    }
    let sections = u32_at(12);
    if sections as usize != SECTIONS {
        return Err(bad(format!(
            "the header gives {sections} sections; version {BINARY_VERSION} has {SECTIONS}"
        )));
    }
    let mut lens = [0usize; SECTIONS];
    let mut total: u64 = 0;
    let after = (bytes.len() - HEADER_LEN) as u64;
    for (k, len) in lens.iter_mut().enumerate() {
        let at = SUM_AT + 32 + 8 * k;
        let mut b = [0u8; 8];
        b.copy_from_slice(&bytes[at..at + 8]);
        let l = u64::from_le_bytes(b);
        total = total.saturating_add(l);
        if total > after {
            return Err(bad(format!(
                "truncated binary checkpoint: its sections need at least {total} bytes after \
                 the header, the file has {after}"
            )));
        }
        *len = l as usize;
    }
    if total != after {
        return Err(bad(format!(
            "{} bytes after the end of its last section (a damaged or mixed file)",
            after - total
        )));
    }
    let stored = &bytes[SUM_AT..SUM_AT + 32];
    let computed = binary_checksum(bytes);
    if stored != computed {
        return Err(CheckpointError::Corrupt {
            file: file.to_string(),
            stored: hex(&stored[..6]),
            computed: hex(&computed[..6]),
        });
    }
    let hash = &bytes[16..SUM_AT];
    if !hash.iter().all(|b| b.is_ascii_hexdigit()) {
        return Err(bad("the scene hash in the header is not hex digits".into()));
    }
    let scene_hash = String::from_utf8_lossy(hash).into_owned();
    let (rows, rest) = bytes[HEADER_LEN..].split_at(lens[0]);
    let (books, world) = rest.split_at(lens[1]);
    let history_rows = std::str::from_utf8(rows)
        .map_err(|e| bad(format!("section 1 (history rows) is not UTF-8: {e}")))?
        .to_string();
    let books: Books = decode(books).map_err(|e| bad(format!("section 2 (bookkeeping): {e}")))?;
    let mut world: World = decode(world).map_err(|e| bad(format!("section 3 (world): {e}")))?;
    world
        .check_restored()
        .map_err(|e| bad(format!("its world is not consistent: {e}")))?;
    Ok(Checkpoint {
        checksum: Some(hex(stored)),
        schema: SCHEMA.to_string(),
        scene_hash,
        history_rows,
        snapshots: books.snapshots,
        run: books.run,
        world,
    })
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

/// Reads a checkpoint in either format, checks its checksum and that it was made from a scene
/// with physics hash `scene_hash`.
pub fn load(path: &Path, scene_hash: &str) -> Result<Checkpoint, CheckpointError> {
    let file = path.display().to_string();
    let bytes = clumpgen::io::read_input(path).map_err(|source| CheckpointError::Io {
        file: file.clone(),
        source,
    })?;
    let c = parse_bytes(&bytes, &file)?;
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
        assert_eq!(content_hash(&v), sha256_hex(&[body.as_bytes()]));
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

    /// Issue 48 D6: the check is on the content. One space after `"checksum":` (or any other
    /// spacing, key order, or a re-save by another JSON writer) neither turns it off nor
    /// trips it; an edited value is refused in every spelling; a checksum written over the
    /// file's bytes (before the canonical form) still verifies; a malformed field is refused.
    #[test]
    fn checksum_is_checked_on_the_content_in_any_spelling() {
        let body = r#"{"schema":"dem.checkpoint/1","world":{"v":[1e-5,-0.3],"id":7,"s":"a\"b"}}"#;
        let text = with_checksum(body);
        let spaced = text.replacen("\"checksum\":", "\"checksum\": ", 1);
        verify_checksum("c.json", &spaced).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let pretty = serde_json::to_string_pretty(&v).unwrap();
        verify_checksum("c.json", &pretty).unwrap();
        // Keys in another order, a number spelled otherwise (as Python's json.dump writes it).
        let python = format!(
            r#"{{"world": {{"s": "a\"b", "id": 7, "v": [1e-05, -0.3]}}, "checksum": "{}", "schema": "dem.checkpoint/1"}}"#,
            v["checksum"].as_str().unwrap()
        );
        verify_checksum("c.json", &python).unwrap();
        for edited in [
            spaced.replace("-0.3", "-0.4"),
            pretty.replace("-0.3", "-0.4"),
            python.replace("-0.3", "-0.4"),
        ] {
            let e = verify_checksum("c.json", &edited).unwrap_err().to_string();
            assert!(e.contains("corrupt"), "{e}");
        }
        // The override: without the field it loads (and says nothing).
        let mut m = v.as_object().unwrap().clone();
        m.remove("checksum");
        let edited = serde_json::Value::Object(m)
            .to_string()
            .replace("-0.3", "-0.4");
        verify_checksum("c.json", &edited).unwrap();
        // A checkpoint of before the canonical form: its hash over the bytes after the field.
        let legacy = format!(
            "{CHECKSUM_PREFIX}{}\",{}",
            sha256_hex(&[b"{\"world\":{\"id\":7},\"schema\":\"x\"}"]),
            "\"world\":{\"id\":7},\"schema\":\"x\"}"
        );
        verify_checksum("c.json", &legacy).unwrap();
        assert!(verify_checksum("c.json", &legacy.replace("\"id\":7", "\"id\":8")).is_err());
        let e = verify_checksum("c.json", r#"{"checksum": "abc", "schema": "x"}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("not 64 hex digits"), "{e}");
    }
}
