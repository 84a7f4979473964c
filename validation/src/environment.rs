//! Where and when the report was made: commit, machine, threads, date, tool versions, run time.

use crate::cutting_runs::Reused;
use serde::Serialize;
use std::process::Command;

#[derive(Debug, Clone, Serialize)]
pub struct Environment {
    pub commit: String,
    pub dirty: bool,
    pub cpu: String,
    pub cores: usize,
    pub threads: usize,
    pub os: String,
    pub rustc: String,
    pub date_utc: String,
    pub mode: String,
    pub total_wall_time_s: f64,
    /// Finished cutting runs this call read back instead of running them, with their wall
    /// time as recorded when they ran (so a report rebuilt from finished runs states their
    /// cost too).
    pub reused: Reused,
}

/// Runs in the repository this program was built from, so that the commit is found wherever
/// the report is made (issue 48: "commit unknown" outside the repository).
fn run(cmd: &str, args: &[&str]) -> Option<String> {
    let o = Command::new(cmd)
        .args(args)
        .current_dir(crate::REPOSITORY)
        .output()
        .ok()?;
    o.status
        .success()
        .then(|| String::from_utf8_lossy(&o.stdout).trim().to_string())
}

/// Civil date (UTC) of a Unix time, `YYYY-MM-DD HH:MM:SS` (Howard Hinnant's days-from-civil
/// inverse, proleptic Gregorian).
pub fn utc_string(unix: u64) -> String {
    let days = (unix / 86400) as i64;
    let sod = unix % 86400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + (m <= 2) as i64;
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02}",
        sod / 3600,
        sod / 60 % 60,
        sod % 60
    )
}

impl Environment {
    /// Reads the environment now; `total_wall_time_s` is filled in at the end.
    pub fn capture(mode: &str) -> Environment {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|t| {
                t.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|s| s.trim().to_string())
            })
            .unwrap_or_else(|| "unknown".into());
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_secs())
            .unwrap_or(0);
        Environment {
            commit: run("git", &["rev-parse", "--short=12", "HEAD"])
                .unwrap_or_else(|| "unknown".into()),
            dirty: run("git", &["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty()),
            cpu,
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            threads: rayon::current_num_threads(),
            os: format!("{} {}", std::env::consts::OS, std::env::consts::ARCH),
            rustc: run("rustc", &["--version"]).unwrap_or_else(|| "unknown".into()),
            date_utc: utc_string(now),
            mode: mode.into(),
            total_wall_time_s: 0.0,
            reused: Reused::default(),
        }
    }

    pub fn markdown(&self) -> String {
        let reused = if self.reused.runs > 0 {
            format!(
                "| finished runs read back | {} runs, {:.0} s ({:.1} h) of wall time when they ran |\n\
                 | total with those runs | {:.0} s ({:.1} h) |\n",
                self.reused.runs,
                self.reused.wall_time_s,
                self.reused.wall_time_s / 3600.0,
                self.total_wall_time_s + self.reused.wall_time_s,
                (self.total_wall_time_s + self.reused.wall_time_s) / 3600.0
            )
        } else {
            String::new()
        };
        format!(
            "| item | value |\n|---|---|\n| commit | `{}`{} |\n| machine | {} ({} cores), {} |\n| threads | {} |\n\
             | compiler | {} |\n| date (UTC) | {} |\n| mode | {} |\n| run time of this call | {:.1} s |\n{}",
            self.commit,
            if self.dirty { " (uncommitted changes)" } else { "" },
            self.cpu,
            self.cores,
            self.os,
            self.threads,
            self.rustc,
            self.date_utc,
            self.mode,
            self.total_wall_time_s,
            reused
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates() {
        assert_eq!(utc_string(0), "1970-01-01 00:00:00");
        assert_eq!(utc_string(951_782_400), "2000-02-29 00:00:00");
        assert_eq!(utc_string(1_795_000_000), "2026-11-18 11:06:40");
    }
}
