//! File output helpers shared by the workspace.

use std::io::Write;
use std::path::Path;

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
