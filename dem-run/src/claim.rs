//! Claims: which process runs a case. A claim is a file `claim.<g>` in the case folder
//! (g = 0, 1, 2, …) holding the claimant's host, pid and process start time; the case belongs
//! to the claimant of the highest g, until it releases it (the case ended). Each claim file is created whole and exclusively (written
//! to a temporary file, then `link(2)`ed to its name, which fails if the name exists: atomic,
//! also on NFS), so of two processes that want a case only one gets it. A claim is stale when
//! its process has ended: on this host, its pid is gone or belongs to a later process (start
//! time differs); of another host, its file has not been touched (the runner touches its
//! claims every [`HEARTBEAT`]) for [`STALE_AFTER`]. A stale claim g is taken over by creating
//! claim g + 1, with the same exclusivity. Released claims are kept (the case's run history); a claim taken for a case found finished
//! is removed.

use crate::error::{Error, Result};
use crate::process::host;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

/// How often a runner touches the claims it holds.
pub const HEARTBEAT: Duration = Duration::from_secs(60);
/// A claim of another host untouched this long is stale.
pub const STALE_AFTER: Duration = Duration::from_secs(600);

#[derive(Debug, Serialize, Deserialize, PartialEq)]
struct Holder {
    host: String,
    pid: u32,
    /// Start time of the process (clock ticks since boot, `/proc/<pid>/stat` field 22).
    start: Option<u64>,
    /// Set when the holder finished with the case: the claim is history, not held.
    #[serde(default)]
    released: bool,
}

/// A claim held by this process.
#[derive(Debug)]
pub struct Claim {
    pub path: PathBuf,
}

impl Claim {
    /// Marks the claim released (the case ended; kept as its run history).
    pub fn release(self) {
        let mut h = me();
        h.released = true;
        if let Ok(text) = serde_json::to_string(&h) {
            let _ = clumpgen::io::write_atomic(&self.path, text.as_bytes());
        }
    }

    /// Gives up a claim taken for nothing (the case turned out finished): removes it.
    pub fn drop_unused(self) {
        let _ = std::fs::remove_file(&self.path);
    }

    /// The heartbeat: sets the claim file's modification time to now.
    pub fn touch(&self) {
        if let Ok(f) = std::fs::OpenOptions::new().append(true).open(&self.path) {
            let _ = f.set_modified(SystemTime::now());
        }
    }
}

/// Start time of process `pid` (Linux: `/proc/<pid>/stat` field 22), `None` elsewhere or if gone.
fn start_time(pid: u32) -> Option<u64> {
    let s = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // Fields after the command name, which is in parentheses and may hold spaces.
    let rest = &s[s.rfind(')')? + 1..];
    rest.split_whitespace().nth(19)?.parse().ok()
}

fn me() -> Holder {
    let pid = std::process::id();
    Holder {
        host: host(),
        pid,
        start: start_time(pid),
        released: false,
    }
}

/// The claims in a case folder, highest generation last.
fn claims(dir: &Path) -> Vec<(u64, PathBuf)> {
    let mut v: Vec<(u64, PathBuf)> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let g = name.strip_prefix("claim.")?.parse().ok()?;
            Some((g, e.path()))
        })
        .collect();
    v.sort();
    v
}

/// Whether the claim file `path` is held by a live process; `Some(holder)` if so.
fn live(path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(path).ok();
    let holder: Option<Holder> = text.and_then(|t| serde_json::from_str(&t).ok());
    let age = std::fs::metadata(path)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| SystemTime::now().duration_since(t).ok())
        .unwrap_or_default();
    match holder {
        Some(h) if h.released => None,
        Some(h) if h.host == host() => {
            let alive =
                crate::process::alive(h.pid) && (h.start.is_none() || start_time(h.pid) == h.start);
            alive.then(|| format!("{}:{}", h.host, h.pid))
        }
        Some(h) => (age < STALE_AFTER).then(|| format!("{}:{}", h.host, h.pid)),
        // (Cannot happen for files this module writes: they appear whole.)
        None => (age < STALE_AFTER).then(|| "unknown".to_string()),
    }
}

/// The live holder (`host:pid`) of the case in `dir`, if any.
pub fn live_holder(dir: &Path) -> Option<String> {
    let (_, path) = claims(dir).pop()?;
    live(&path)
}

/// Claims the case in `dir` (created if needed) for this process: `Ok(Some)` if this process
/// now holds it, `Ok(None)` if a live process does.
pub fn try_claim(dir: &Path) -> Result<Option<Claim>> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let me = me();
    let text = serde_json::to_string(&me).map_err(|e| Error::io(dir, e))?;
    let nanos = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let tmp = dir.join(format!(".claim.tmp.{}.{nanos}", me.pid));
    std::fs::write(&tmp, &text).map_err(|e| Error::io(&tmp, e))?;
    let result = (|| {
        // Bounded: each failed link means another process made progress.
        for _ in 0..1000 {
            let next = match claims(dir).pop() {
                None => 0,
                Some((g, path)) => {
                    if live(&path).is_some() {
                        return Ok(None);
                    }
                    g + 1
                }
            };
            let path = dir.join(format!("claim.{next}"));
            match std::fs::hard_link(&tmp, &path) {
                Ok(()) => return Ok(Some(Claim { path })),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(Error::io(&path, format!("cannot claim: {e}"))),
            }
        }
        Err(Error::io(dir, "claim contended 1000 times"))
    })();
    let _ = std::fs::remove_file(&tmp);
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_claim_then_stale_takeover() {
        let dir = std::env::temp_dir().join(format!("dem-claim-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let c = try_claim(&dir).unwrap().expect("first claim");
        assert!(c.path.ends_with("claim.0"));
        // Held by this (live) process: a second claim fails.
        assert!(try_claim(&dir).unwrap().is_none());
        assert!(live_holder(&dir).is_some());
        // A claim of a dead process of this host (pid beyond pid_max) is taken over.
        let dead = Holder {
            host: host(),
            pid: 999_999_999,
            start: None,
            released: false,
        };
        std::fs::write(dir.join("claim.1"), serde_json::to_string(&dead).unwrap()).unwrap();
        assert!(live_holder(&dir).is_none());
        let c = try_claim(&dir).unwrap().expect("takeover");
        assert!(c.path.ends_with("claim.2"));
        // Released: free for the next claimant, kept as history.
        c.release();
        assert!(live_holder(&dir).is_none());
        let c = try_claim(&dir).unwrap().expect("after release");
        assert!(c.path.ends_with("claim.3"));
        c.drop_unused();
        assert!(!dir.join("claim.3").exists() && dir.join("claim.2").exists());
        // Another host's claim: live while its heartbeat is fresh, stale after STALE_AFTER.
        let other = Holder {
            host: format!("{}-other", host()),
            pid: 1,
            start: None,
            released: false,
        };
        let p = dir.join("claim.3");
        std::fs::write(&p, serde_json::to_string(&other).unwrap()).unwrap();
        assert!(live_holder(&dir).is_some_and(|h| h.ends_with("-other:1")));
        assert!(try_claim(&dir).unwrap().is_none());
        let old = SystemTime::now() - STALE_AFTER - Duration::from_secs(1);
        let f = std::fs::OpenOptions::new().append(true).open(&p).unwrap();
        f.set_modified(old).unwrap();
        assert!(live_holder(&dir).is_none());
        let c = try_claim(&dir)
            .unwrap()
            .expect("stale claim of another host");
        assert!(c.path.ends_with("claim.4"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A claim whose process ended but was not reaped (a zombie: a case killed with its
    /// runner) is stale. Before [`crate::process`], `kill(pid, 0)` alone counted it as live,
    /// so its case read as running until init reaped it.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_zombie_holds_no_claim() {
        let dir = std::env::temp_dir().join(format!("dem-claim-z-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        // A child that exits at once and is not waited for: a zombie until `wait`.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        while !crate::process::zombie(pid) {
            std::thread::sleep(Duration::from_millis(5));
        }
        let z = Holder {
            host: host(),
            pid,
            start: start_time(pid),
            released: false,
        };
        std::fs::write(dir.join("claim.0"), serde_json::to_string(&z).unwrap()).unwrap();
        assert!(live_holder(&dir).is_none(), "a zombie's claim is stale");
        assert!(try_claim(&dir).unwrap().is_some());
        child.wait().unwrap();
        let _ = std::fs::remove_dir_all(&dir);
    }
}
