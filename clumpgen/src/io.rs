//! File input and output helpers shared by the workspace.
//!
//! Output: [`write_atomic`]. Input: [`read_input`] and [`read_input_string`], which every
//! reader of a user's file goes through, so that no input can take unbounded memory or time: a
//! special file (`/dev/zero`, a device, a socket) or a folder is refused by name, and a file or
//! stream longer than [`input_limit`] is refused as soon as the limit is passed, with the limit
//! and how to raise it in the message (`dem --max-input-mib`, or the environment variable
//! [`INPUT_LIMIT_ENV`] for the library and Python).

use std::io::{Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// Default [`input_limit`]: 1 GiB, above any outline, template, scene, checkpoint or study this
/// project writes for a 2D specimen (a 10-million-disc checkpoint is ~0.6 GB).
pub const DEFAULT_INPUT_LIMIT: u64 = 1 << 30;

/// Environment variable that sets [`input_limit`] in MiB when [`set_input_limit`] was not called.
pub const INPUT_LIMIT_ENV: &str = "DEM_MAX_INPUT_MIB";

/// 0: not set by [`set_input_limit`] (the environment or the default applies).
static INPUT_LIMIT: AtomicU64 = AtomicU64::new(0);

/// Sets the largest input, in bytes, that [`read_input`] accepts for the rest of the process
/// (`dem --max-input-mib N`). 0 restores the default.
pub fn set_input_limit(bytes: u64) {
    INPUT_LIMIT.store(bytes, Ordering::Relaxed);
}

/// The largest input, in bytes, [`read_input`] accepts: the value of [`set_input_limit`], else
/// [`INPUT_LIMIT_ENV`] (MiB) when it parses as a positive integer, else [`DEFAULT_INPUT_LIMIT`].
pub fn input_limit() -> u64 {
    match INPUT_LIMIT.load(Ordering::Relaxed) {
        0 => std::env::var(INPUT_LIMIT_ENV)
            .ok()
            .and_then(|v| v.trim().parse::<u64>().ok())
            .filter(|&m| m > 0)
            .map_or(DEFAULT_INPUT_LIMIT, |m| m.saturating_mul(1 << 20)),
        b => b,
    }
}

fn too_large(limit: u64) -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::InvalidData,
        format!(
            "larger than the input limit of {} MiB; raise it with `dem --max-input-mib N` or \
             the environment variable {INPUT_LIMIT_ENV}",
            limit.div_ceil(1 << 20)
        ),
    )
}

/// Reads a whole input file, bounded: folders and special files other than pipes (devices such as
/// `/dev/zero`, sockets) are refused by their kind; a regular file larger than [`input_limit`] is
/// refused before it is read, and a pipe as soon as it passes the limit. The error carries no
/// path: callers add the file they were reading, as for any other I/O error.
pub fn read_input(path: &Path) -> std::io::Result<Vec<u8>> {
    read_limited(path, input_limit())
}

fn read_limited(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if let Some(kind) = special_kind(&meta) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("is {kind}, not a regular file"),
        ));
    }
    if meta.len() > limit {
        return Err(too_large(limit));
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(limit));
    }
    Ok(bytes)
}

/// [`read_input`] as UTF-8 text (an `InvalidData` error otherwise).
pub fn read_input_string(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read_input(path)?)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e))
}

/// What kind of non-regular file `meta` describes, or `None` for a regular file or a pipe.
fn special_kind(meta: &std::fs::Metadata) -> Option<&'static str> {
    let t = meta.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a folder");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return None;
        }
        if t.is_char_device() {
            return Some("a character device");
        }
        if t.is_block_device() {
            return Some("a block device");
        }
        if t.is_socket() {
            return Some("a socket");
        }
    }
    Some("a special file")
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder is written and
/// renamed over `path`, so readers never see a half-written file and a failed run leaves the old
/// file intact. Parent folders are created. (No fsync: atomic against readers and crashes of the
/// program, not durable against power loss; an fsync per template tripled batch time.)
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    // On any failure (a full disk: ENOSPC while writing, or at the rename) the temporary file
    // goes too: nothing partial is left, and the target keeps its earlier content.
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes))
        .and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

#[cfg(test)]
mod tests {
    /// Issue 48 D3: `/dev/zero` (directly or through a link named like an outline) is refused by
    /// its kind at once instead of being read until memory runs out; a folder likewise.
    #[cfg(target_os = "linux")]
    #[test]
    fn special_files_and_folders_are_refused_by_kind() {
        let e = super::read_input(std::path::Path::new("/dev/zero")).expect_err("a device");
        assert_eq!(e.to_string(), "is a character device, not a regular file");
        let dir = std::env::temp_dir().join(format!("clumpgen-io-dev-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let link = dir.join("zero.csv");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        let e = super::read_input(&link).expect_err("a link to a device");
        assert!(e.to_string().contains("character device"), "{e}");
        let e = super::read_input(&dir).expect_err("a folder");
        assert_eq!(e.to_string(), "is a folder, not a regular file");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Issue 48 D3: a file or a pipe longer than the limit is refused with the limit and the way
    /// to raise it; at the limit it is read whole.
    #[cfg(target_os = "linux")]
    #[test]
    fn inputs_over_the_limit_are_refused_with_the_flag_to_raise_it() {
        let dir = std::env::temp_dir().join(format!("clumpgen-io-cap-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("big.csv");
        std::fs::write(&p, vec![b'1'; 3 << 20]).unwrap();
        let e = super::read_limited(&p, 2 << 20).expect_err("3 MiB over a 2 MiB limit");
        let msg = e.to_string();
        assert!(msg.contains("input limit of 2 MiB"), "{msg}");
        assert!(msg.contains("--max-input-mib") && msg.contains(super::INPUT_LIMIT_ENV));
        assert_eq!(super::read_limited(&p, 3 << 20).unwrap().len(), 3 << 20);
        // A stream: its length is unknown until read, so the limit stops the read.
        let fifo = dir.join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        assert!(made.is_ok_and(|s| s.success()), "mkfifo");
        let mut writer = std::process::Command::new("sh")
            .arg("-c")
            .arg(format!("head -c 3145728 /dev/zero > {}", fifo.display()))
            .spawn()
            .unwrap();
        let e = super::read_limited(&fifo, 2 << 20).expect_err("a 3 MiB stream");
        assert!(e.to_string().contains("input limit of 2 MiB"), "{e}");
        let _ = writer.wait();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The limit set by `dem --max-input-mib` is the one read back (a value above the default,
    /// so that tests running beside this one are not affected).
    #[test]
    fn the_set_limit_is_the_limit() {
        super::set_input_limit(5 << 30);
        assert_eq!(super::input_limit(), 5 << 30);
        super::set_input_limit(0);
    }

    #[test]
    fn atomic_write_replaces_content_and_leaves_no_temp() {
        let dir = std::env::temp_dir().join(format!("clumpgen-io-{}", std::process::id()));
        let p = dir.join("sub/a.json");
        super::write_atomic(&p, b"one").unwrap();
        super::write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        let left: Vec<_> = std::fs::read_dir(p.parent().unwrap()).unwrap().collect();
        assert_eq!(left.len(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A full disk (issue 20): the temporary file is a link to /dev/full, so writing it fails
    /// with ENOSPC as on a full file system. The error is returned, the earlier file is kept
    /// and no temporary file is left (before: the partial temporary file stayed).
    #[cfg(target_os = "linux")]
    #[test]
    fn a_full_disk_leaves_the_old_file_and_no_temporary() {
        let dir = std::env::temp_dir().join(format!("clumpgen-io-full-{}", std::process::id()));
        let p = dir.join("a.json");
        super::write_atomic(&p, b"old").unwrap();
        let tmp = dir.join(format!(".a.json.{}.tmp", std::process::id()));
        std::os::unix::fs::symlink("/dev/full", &tmp).unwrap();
        let e = super::write_atomic(&p, b"new").expect_err("no space");
        assert_eq!(e.raw_os_error(), Some(28), "{e}");
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("a.json")]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
