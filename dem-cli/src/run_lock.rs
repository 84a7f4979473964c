//! The run folder's lock, `<out>/run.lock` (JSON: the command, scene file, scene hash, pid,
//! host, start time). It says which scene the folder's outputs belong to and which process
//! writes them now, so two runs never mix their checkpoints, snapshots and `snapshots.pvd` in
//! one folder. `dem run` takes it in its output folder; the lab tests take it where their run
//! writes (`dem test cutting`: `--out`; `ucs`, `brazilian`, `bending`, `senb`: `<out>/<test>.out`, the
//! folder their scene `<out>/<test>.json` runs into, so `dem run` of that scene finds the same
//! lock) and `dem calibrate` in `--out`; their "scene hash" is the SHA-256 of the test's typed
//! inputs (specimen parameters, model, test), since the scene is only made after the specimen:
//!
//! * no lock: the run takes the folder;
//! * a lock of the same scene (the same hash, so run control and outputs may differ; or the
//!   same scene file, edited since or written by another command, with a note) whose process
//!   has ended: taken; a run that ended normally cleared its pid, one killed (kill -9, a
//!   crash) left it, and that stale lock is taken over with a note;
//! * a lock of another scene (another file and other physics): refused, naming the folder
//!   and the other scene, unless `--force`;
//! * a lock whose process is still running (checked on this host; a lock of another host
//!   counts as running, there is no way to tell): refused unless `--force`.
//!
//! The lock stays in the folder after the run with its pid cleared (it records whose outputs
//! the folder holds). A fresh lock is created exclusively (`create_new`), so of two runs
//! starting together one wins; taking over an existing lock is a plain atomic replace.

use serde_json::{json, Value};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock's file name in the output folder.
pub const LOCK_FILE: &str = "run.lock";
const SCHEMA: &str = "dem.run-lock/1";

/// What a lock file records.
#[derive(Clone, Debug, PartialEq)]
struct Record {
    /// The command that took the lock (`dem run`, `dem test cutting`, ...; locks written
    /// before the field existed are `dem run`'s).
    command: String,
    scene: String,
    scene_hash: String,
    /// The process writing the folder now; none once its run has ended.
    pid: Option<u32>,
    host: String,
    started: u64,
}

impl Record {
    fn to_json(&self) -> String {
        let v = json!({
            "schema": SCHEMA,
            "command": self.command,
            "scene": self.scene,
            "scene_hash": self.scene_hash,
            "pid": self.pid,
            "host": self.host,
            "started_unix_s": self.started,
        });
        serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
    }

    fn parse(text: &str) -> Result<Record, String> {
        let v: Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if v["schema"] != SCHEMA {
            return Err(format!("schema is not {SCHEMA:?}"));
        }
        let s = |k: &str| {
            v[k].as_str()
                .map(str::to_string)
                .ok_or_else(|| format!("no text field {k:?}"))
        };
        let pid = match &v["pid"] {
            Value::Null => None,
            p => Some(
                p.as_u64()
                    .and_then(|p| u32::try_from(p).ok())
                    .filter(|&p| p > 0)
                    .ok_or_else(|| format!("pid {p} is not a process id"))?,
            ),
        };
        let command = match &v["command"] {
            Value::Null => RUN.to_string(),
            c => c
                .as_str()
                .map(str::to_string)
                .ok_or_else(|| format!("command {c} is not text"))?,
        };
        Ok(Record {
            command,
            scene: s("scene")?,
            scene_hash: s("scene_hash")?,
            pid,
            host: s("host")?,
            started: v["started_unix_s"].as_u64().unwrap_or(0),
        })
    }

    /// Whether the recorded process may still be running (always, for another host).
    fn running(&self) -> bool {
        self.pid
            .is_some_and(|p| self.host != host_name() || process_alive(p))
    }

    fn who(&self) -> String {
        match self.pid {
            Some(p) => format!("pid {p} on host {}", self.host),
            None => format!("host {}", self.host),
        }
    }
}

/// A held run lock: its pid is cleared when dropped (the run has ended, however).
#[derive(Debug)]
pub struct RunLock {
    path: PathBuf,
    record: Record,
}

impl Drop for RunLock {
    fn drop(&mut self) {
        // Only if it is still ours (a `--force` run may have taken it meanwhile).
        let ours = std::fs::read_to_string(&self.path)
            .ok()
            .and_then(|t| Record::parse(&t).ok())
            .is_some_and(|r| r == self.record);
        if ours {
            let released = Record {
                pid: None,
                ..self.record.clone()
            };
            let _ = clumpgen::io::write_atomic(&self.path, released.to_json().as_bytes());
        }
    }
}

/// The command of `dem run`.
pub const RUN: &str = "dem run";

/// Who asks for a folder: the command, the scene file its run runs, and the hash that says
/// whether two runs are the same (`Scene::physics_hash` for `dem run`; the SHA-256 of the
/// typed inputs, [`inputs_hash`], for the lab tests).
pub struct Claim<'a> {
    pub command: &'a str,
    pub scene: &'a Path,
    pub hash: &'a str,
}

/// [`acquire`], with its notes (a stale lock taken over, a rerun) printed to stderr: what every
/// command that runs into a locked folder does.
pub fn acquire_noted(out: &Path, claim: Claim<'_>, force: bool) -> Result<RunLock, String> {
    let (lock, notes) = acquire(out, claim, force)?;
    for n in notes {
        eprintln!("note: {n}");
    }
    Ok(lock)
}

/// SHA-256 (hex) of `value`'s JSON: the identity of a lab test's inputs in its lock.
pub fn inputs_hash<T: serde::Serialize>(value: &T) -> String {
    use sha2::{Digest, Sha256};
    let text = serde_json::to_string(value).unwrap_or_default();
    Sha256::digest(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Takes the lock of the output folder `out` (created if missing) for `claim`; `force` takes
/// it in every case. Returns the lock and notes to print (a stale lock taken over, a forced
/// take-over, a changed scene). The error names the folder and, for a lock of another scene
/// or a running one, that scene, its command and its process.
pub fn acquire(
    out: &Path,
    claim: Claim<'_>,
    force: bool,
) -> Result<(RunLock, Vec<String>), String> {
    let Claim {
        command,
        scene,
        hash,
    } = claim;
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create the output folder: {e}", out.display()))?;
    let path = out.join(LOCK_FILE);
    let scene = std::fs::canonicalize(scene).unwrap_or_else(|_| scene.to_path_buf());
    let me = Record {
        command: command.to_string(),
        scene: scene.display().to_string(),
        scene_hash: hash.to_string(),
        pid: Some(std::process::id()),
        host: host_name(),
        started: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
    };
    let lock = RunLock {
        path: path.clone(),
        record: me.clone(),
    };
    let text = match std::fs::read_to_string(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    f.write_all(me.to_json().as_bytes()).map_err(|e| {
                        format!("{}: cannot write the run lock: {e}", path.display())
                    })?;
                    return Ok((lock, Vec::new()));
                }
                // Another run created it since: read what it wrote.
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    std::fs::read_to_string(&path)
                        .map_err(|e| format!("{}: cannot read the run lock: {e}", path.display()))?
                }
                Err(e) => {
                    return Err(format!(
                        "{}: cannot write the run lock: {e}",
                        path.display()
                    ))
                }
            }
        }
        Err(e) => return Err(format!("{}: cannot read the run lock: {e}", path.display())),
        Ok(t) => t,
    };
    let mut notes = Vec::new();
    match Record::parse(&text) {
        Err(reason) if !force => {
            return Err(format!(
                "{}: not a run lock ({reason}); if no run writes into {} now, remove it or use \
                 --force",
                path.display(),
                out.display()
            ))
        }
        Err(reason) => notes.push(format!(
            "--force: replacing {}, which is not a run lock ({reason})",
            path.display()
        )),
        Ok(old) => {
            let running = old.running();
            // One scene file however it was spelled (issue 48 D15: `cc/cutting.scene.json` and
            // `./cc/cutting.scene.json` were "another scene").
            let same_scene = old.scene == me.scene
                || dem_core::output::driver::same_file(
                    std::path::Path::new(&old.scene),
                    std::path::Path::new(&me.scene),
                );
            if same_scene && old.command != me.command {
                // The same scene file, run by another command (a lab test's scene run by
                // `dem run`, or the other way round).
                notes.push(format!(
                    "{} held the run of {} by `{}`; its outputs are replaced",
                    out.display(),
                    old.scene,
                    old.command
                ));
            } else if old.scene_hash != hash && same_scene {
                // The same scene file, edited (or a lab test with other inputs): a fresh run
                // replaces its outputs.
                notes.push(format!(
                    "{} changed since its run in {}; that run's outputs are replaced",
                    old.scene,
                    out.display()
                ));
            }
            if old.scene_hash != hash && !same_scene {
                let now = if running {
                    format!(", being run now by {}", old.who())
                } else {
                    String::new()
                };
                if !force {
                    return Err(format!(
                        "{}: the folder holds the run of another scene, {} by `{}` (scene hash \
                         {}){now}; give another --out, or --force to replace its outputs",
                        out.display(),
                        old.scene,
                        old.command,
                        old.scene_hash.chars().take(12).collect::<String>()
                    ));
                }
                notes.push(format!(
                    "--force: {} held the run of {}{now}; its outputs are replaced",
                    out.display(),
                    old.scene
                ));
            } else if running {
                if !force {
                    return Err(format!(
                        "{}: scene {} is being run into this folder now by `{}`, {}; wait for \
                         it to end, or use --force if that process is gone",
                        out.display(),
                        old.scene,
                        old.command,
                        old.who()
                    ));
                }
                notes.push(format!(
                    "--force: took the lock of {} from {}",
                    out.display(),
                    old.who()
                ));
            } else if old.pid.is_some() {
                notes.push(format!(
                    "{}: took over the stale lock of {} (no such process: that run was \
                     stopped before its end)",
                    out.display(),
                    old.who()
                ));
            }
        }
    }
    clumpgen::io::write_atomic(&path, me.to_json().as_bytes())
        .map_err(|e| format!("{}: cannot write the run lock: {e}", path.display()))?;
    Ok((lock, notes))
}

use dem_run::process::host as host_name;
#[cfg(test)]
use dem_run::process::zombie;

/// Whether process `pid` of this host still runs ([`dem_run::process::alive`]); this
/// process's own pid: no, since the recorded process has ended if the id is ours now.
fn process_alive(pid: u32) -> bool {
    pid != std::process::id() && dem_run::process::alive(pid)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip_and_bad_ones_are_named() {
        let r = Record {
            command: RUN.into(),
            scene: "/a/s.json".into(),
            scene_hash: "ab".repeat(32),
            pid: Some(7),
            host: "h".into(),
            started: 3,
        };
        assert_eq!(Record::parse(&r.to_json()).unwrap(), r);
        let released = Record { pid: None, ..r };
        assert_eq!(Record::parse(&released.to_json()).unwrap(), released);
        assert!(Record::parse("{}").unwrap_err().contains("schema"));
        // A lock written before the command was recorded is `dem run`'s.
        let old = released
            .to_json()
            .replace("  \"command\": \"dem run\",\n", "");
        assert!(!old.contains("command"), "{old}");
        assert_eq!(Record::parse(&old).unwrap(), released);
        let bad = released.to_json().replace("\"dem run\"", "3");
        assert!(
            Record::parse(&bad).unwrap_err().contains("command"),
            "{bad}"
        );
        let zero = released.to_json().replace("null", "0");
        assert!(Record::parse(&zero).unwrap_err().contains("pid"), "{zero}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_zombie_is_not_a_running_process() {
        // A child that has exited and is not yet waited for is a zombie.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let pid = child.id();
        let t0 = std::time::Instant::now();
        while !zombie(pid) {
            assert!(t0.elapsed().as_secs() < 10, "the child never exited");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(!process_alive(pid));
        child.wait().unwrap();
        assert!(!zombie(std::process::id()));
        assert!(process_alive(1));
    }

    /// Issue 48 D15: a lock taken before its scene existed keeps the path as spelled; the
    /// same file reached by another spelling is the same scene (a rerun with a note), not
    /// "another scene". A different file still is.
    #[test]
    fn the_same_scene_spelled_otherwise_is_not_another_scene() {
        let dir = std::env::temp_dir().join(format!("dem-lock-spelling-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let out = dir.join("out");
        let spelled = dir.join("sub").join("..").join("s.json");
        fn claim<'a>(scene: &'a Path, command: &'a str, hash: &'a str) -> Claim<'a> {
            Claim {
                command,
                scene,
                hash,
            }
        }
        // The lab test takes the folder before writing its scene: the path stays as given.
        let (lock, _) = acquire(&out, claim(&spelled, "dem test cutting", "aa"), false).unwrap();
        drop(lock);
        std::fs::write(dir.join("s.json"), "{}").unwrap();
        let (lock, notes) = acquire(&out, claim(&dir.join("s.json"), RUN, "bb"), false).unwrap();
        assert!(
            notes.iter().any(|n| n.contains("outputs are replaced")),
            "{notes:?}"
        );
        drop(lock);
        std::fs::write(dir.join("other.json"), "{}").unwrap();
        let e = acquire(&out, claim(&dir.join("other.json"), RUN, "cc"), false)
            .err()
            .unwrap();
        assert!(e.contains("another scene"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn own_pid_is_not_a_running_other_process() {
        assert!(!process_alive(std::process::id()));
        #[cfg(unix)]
        assert!(process_alive(1), "init runs");
    }
}
