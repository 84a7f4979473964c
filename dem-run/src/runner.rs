//! The runner (`dem sweep run DIR [--jobs N] [--threads T] [--index I]`): runs the cases not
//! yet finished, N at a time, each as a child process `dem <argv> --out DIR/cases/<key>
//! --threads T` of the `dem` executable (RAYON_NUM_THREADS = T too, working folder DIR, so a
//! relative file in argv is one of the folder's), its stdout and stderr appended to the case's
//! `log.txt`; or, with [`Executor::InProcess`] (the report's runs), each as a call on a thread
//! of this process, with the same claims, records and log. A case is claimed first ([`crate::claim`]), so processes
//! sharing DIR (several `run`s, Slurm array tasks) never run one case twice.
//!
//! Ends of a case: exit code 0 with `<test>.result.json` present → `done.json`; anything else
//! → `failed.json` with the reason and the log's last lines; either written atomically, with
//! the attempt's wall time and the child's user + system CPU time (`wait4(2)`'s rusage, which
//! covers the child and the processes it waited for). On Linux each child gets
//! `PR_SET_PDEATHSIG = SIGKILL`, so a runner killed with `kill -9` takes its cases with it and a
//! rerun takes over their (stale) claims; `dem test cutting` then resumes from the checkpoints
//! in the case folder (bit-identical results, docs/cutting.md), the other tests start again.

use crate::case::{self, read_cases, Case, Record, State, DONE_FILE, FAILED_FILE, LOG_FILE};
use crate::claim::{self, Claim, HEARTBEAT};
use crate::error::{refuse, Error, Result};
use crate::plan::TestCommands;
use std::collections::VecDeque;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

/// A case run in this process: `f(case, case folder, threads)` writes the test's outputs
/// (`<test>.result.json` among them) into the case folder and gives the CPU time it measured
/// (s; `None`: the calling thread's is taken, which misses work on other threads); `Err` is
/// the reason it failed.
pub type CaseFn =
    dyn Fn(&Case, &Path, usize) -> std::result::Result<Option<f64>, String> + Send + Sync;

/// How a case runs.
#[derive(Clone)]
pub enum Executor {
    /// A child process of this `dem` executable (`dem sweep run`, a Slurm array task).
    Process(PathBuf),
    /// A call on a thread of this process (validation's report runs): its CPU time is the
    /// thread's, its error the log's last line.
    InProcess(Arc<CaseFn>),
}

impl std::fmt::Debug for Executor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Executor::Process(exe) => write!(f, "Process({})", exe.display()),
            Executor::InProcess(_) => write!(f, "InProcess"),
        }
    }
}

/// What to run (`dem sweep run` flags).
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// The sweep folder (`dem sweep plan --out DIR`).
    pub dir: PathBuf,
    /// Cases at once (at least 1).
    pub jobs: usize,
    /// Worker threads of each case (small specimens scale best one thread each).
    pub threads: usize,
    /// Run case I alone (a Slurm array task); a failed case I is run again.
    pub index: Option<usize>,
    /// Run the failed cases again too (without it they are listed and skipped).
    pub retry_failed: bool,
    /// How each case runs: the `dem` executable, or a call in this process.
    pub executor: Executor,
}

/// What the runner tells as it goes (the CLI draws a bar, or prints the lines).
pub trait Report {
    /// A line: the run's plan, a case done or failed.
    fn line(&mut self, line: String);
    /// `done` of the `total` chosen cases finished; `message`: failed, running, time left.
    fn progress(&mut self, done: usize, total: usize, message: &str);
}

/// The folder's state after a run (other processes may have run some of its cases).
#[derive(Clone, Debug)]
pub struct Summary {
    /// The cases chosen (all, or `--index`'s).
    pub chosen: usize,
    pub done: usize,
    pub failed: usize,
    /// Claimed by a live process elsewhere.
    pub running: usize,
    pub pending: usize,
    /// This run's wall time (s).
    pub wall_s: f64,
    /// A line per case running elsewhere.
    pub elsewhere: Vec<String>,
    /// Two lines per failed case: the reason, and its log.
    pub failures: Vec<String>,
}

/// A case running as a child process or on a thread.
struct Running {
    index: usize,
    claim: Claim,
    task: Task,
    /// The case folder.
    dir: PathBuf,
    started: Instant,
}

/// An in-process case's outcome (the CPU time it measured, or why it failed) and its thread's
/// CPU time.
type Called = (std::result::Result<Option<f64>, String>, Option<f64>);

enum Task {
    Child(Child),
    Thread(JoinHandle<Called>),
    /// A thread joined (its outcome taken).
    Done,
}

/// How a child ended: exit code or signal, and its CPU time.
struct Ended {
    code: Option<i32>,
    signal: Option<i32>,
    cpu_s: Option<f64>,
}

/// How the case ended, or `None` while it runs.
fn poll(r: &mut Running) -> Result<Option<Ended>> {
    let handle = match &mut r.task {
        Task::Child(child) => return poll_child(child, r.index),
        Task::Thread(h) if !h.is_finished() => return Ok(None),
        Task::Thread(_) => {
            let Task::Thread(h) = std::mem::replace(&mut r.task, Task::Done) else {
                unreachable!("matched above")
            };
            h
        }
        Task::Done => return Ok(None),
    };
    let (outcome, thread_cpu) = handle
        .join()
        .unwrap_or_else(|_| (Err("the case's thread panicked".into()), None));
    let cpu_s = match &outcome {
        Ok(Some(cpu)) => Some(*cpu),
        _ => thread_cpu,
    };
    if let Err(e) = &outcome {
        // The reason, as a child's `error:` line (the failure record quotes it).
        let log = r.dir.join(LOG_FILE);
        if let Ok(mut f) = std::fs::OpenOptions::new().append(true).open(&log) {
            let _ = writeln!(f, "error: {e}");
        }
    }
    Ok(Some(Ended {
        code: Some(if outcome.is_ok() { 0 } else { 1 }),
        signal: None,
        cpu_s,
    }))
}

#[cfg(unix)]
fn poll_child(child: &mut Child, index: usize) -> Result<Option<Ended>> {
    let pid = child.id() as libc::pid_t;
    let mut status: libc::c_int = 0;
    // SAFETY: rusage is plain data, zeroed is a valid value; wait4 writes both outputs.
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: pid is our own unreaped child; the pointers are valid for the call.
    let got = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut ru) };
    if got == 0 {
        return Ok(None);
    }
    if got < 0 {
        return Err(Error::process(format!(
            "wait4 of case {} (pid {pid}): {}",
            index,
            std::io::Error::last_os_error()
        )));
    }
    let t = |v: libc::timeval| v.tv_sec as f64 + v.tv_usec as f64 * 1e-6;
    let cpu = t(ru.ru_utime) + t(ru.ru_stime);
    Ok(Some(Ended {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        signal: libc::WIFSIGNALED(status).then(|| libc::WTERMSIG(status)),
        cpu_s: Some(cpu),
    }))
}

#[cfg(not(unix))]
fn poll_child(child: &mut Child, index: usize) -> Result<Option<Ended>> {
    match child.try_wait() {
        Ok(None) => Ok(None),
        Ok(Some(s)) => Ok(Some(Ended {
            code: s.code(),
            signal: None,
            cpu_s: None,
        })),
        Err(e) => Err(Error::process(format!("case {index}: {e}"))),
    }
}

fn unix_now() -> u64 {
    SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0)
}

/// The log's last `n` non-empty lines of the latest attempt.
fn log_tail(log: &Path, n: usize) -> Vec<String> {
    let text = std::fs::read_to_string(log).unwrap_or_default();
    let attempt = text.rsplit_once(HEADER).map(|(_, t)| t).unwrap_or(&text);
    let lines: Vec<&str> = attempt
        .lines()
        .skip(1) // the rest of the header line
        .filter(|l| !l.trim().is_empty())
        .collect();
    lines[lines.len().saturating_sub(n)..]
        .iter()
        .map(|l| l.to_string())
        .collect()
}

/// The folder of `DIR` where cutting cases keep the specimens they generate
/// (`dem test cutting --specimen-cache`).
pub const SPECIMEN_CACHE: &str = "specimens";

/// Starts each attempt's lines in `log.txt` (tests count them).
pub const HEADER: &str = "=== dem sweep run: attempt";

/// Starts case `c` (claimed): the attempt's header in its log, then the executor's task.
fn start(c: &Case, dir: &Path, executor: &Executor, threads: usize) -> Result<Task> {
    let cdir = c.dir(dir);
    let _ = std::fs::remove_file(cdir.join(DONE_FILE));
    let _ = std::fs::remove_file(cdir.join(FAILED_FILE));
    let log_path = cdir.join(LOG_FILE);
    let mut log = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&log_path)
        .map_err(|e| Error::io(&log_path, e))?;
    writeln!(
        log,
        "{HEADER} by pid {} on {}, unix time {}, {} threads: dem {} --out {} ===",
        std::process::id(),
        crate::process::host(),
        unix_now(),
        threads,
        c.argv.join(" "),
        cdir.display()
    )
    .map_err(|e| Error::io(&log_path, e))?;
    match executor {
        Executor::Process(exe) => start_child(c, dir, exe, threads, log).map(Task::Child),
        Executor::InProcess(f) => {
            let index = c.index;
            let (f, c, cdir) = (Arc::clone(f), c.clone(), cdir.clone());
            std::thread::Builder::new()
                .name(format!("case {index}"))
                .spawn(move || {
                    let c0 = crate::process::thread_cpu_s();
                    let r = f(&c, &cdir, threads);
                    let cpu = crate::process::thread_cpu_s()
                        .zip(c0)
                        .map(|(c1, c0)| c1 - c0);
                    (r, cpu)
                })
                .map(Task::Thread)
                .map_err(|e| Error::process(format!("cannot start a thread for case {index}: {e}")))
        }
    }
}

/// Starts case `c` as a child process of `exe`, its output appended to `log`.
fn start_child(
    c: &Case,
    dir: &Path,
    exe: &Path,
    threads: usize,
    log: std::fs::File,
) -> Result<Child> {
    let log_path = c.dir(dir).join(LOG_FILE);
    // The child starts in the sweep folder, so the folders it is given must not be relative
    // to ours (`dem sweep run dir` once wrote to dir/dir/cases/…).
    let dir = &std::path::absolute(dir).map_err(|e| Error::io(dir, e))?;
    let cdir = c.dir(dir);
    let err = log.try_clone().map_err(|e| Error::io(&log_path, e))?;
    let mut cmd = Command::new(exe);
    cmd.args(&c.argv).current_dir(dir);
    if matches!(c.argv.as_slice(), [t, k, ..] if t == "test" && k == "cutting")
        && !c.argv.iter().any(|a| a == "--specimen")
    {
        // The cases of one specimen (a seed's depths and speeds) generate it once.
        cmd.arg("--specimen-cache").arg(dir.join(SPECIMEN_CACHE));
    }
    cmd.arg("--out")
        .arg(&cdir)
        .arg("--threads")
        .arg(threads.to_string())
        .env("RAYON_NUM_THREADS", threads.to_string())
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(err);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: getpid is async-signal-safe.
        let parent = unsafe { libc::getpid() };
        // SAFETY: the closure runs in the forked child before exec and calls only the
        // async-signal-safe prctl and getppid.
        unsafe {
            cmd.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL, 0, 0, 0) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                if libc::getppid() != parent {
                    return Err(std::io::Error::other("the runner has ended"));
                }
                Ok(())
            });
        }
    }
    cmd.spawn()
        .map_err(|e| Error::process(format!("cannot start {}: {e}", exe.display())))
}

/// Refuses the run when a case's command line does not give its key
/// ([`crate::plan::key_of_argv`]): cases.jsonl was edited, or a file it names changed after
/// planning. `index`: only that case is checked.
fn verify_keys(
    dir: &Path,
    cases: &[Case],
    index: Option<usize>,
    tests: &dyn TestCommands,
) -> Result<()> {
    let file = dir.join(crate::case::CASES_FILE);
    for c in cases.iter().filter(|c| index.is_none_or(|i| i == c.index)) {
        let why = match crate::plan::key_of_argv(c, dir, tests) {
            Ok(k) if k == c.key => continue,
            Ok(_) => "its command line does not give its key".to_string(),
            Err(e) => e.to_string(),
        };
        return Err(refuse!(
            "{}: line {}: case {} ({}): {why}: the line was edited, or a file it names changed \
             after planning; only what the study plans runs: plan the study again (into a new \
             folder if the inputs changed)",
            file.display(),
            c.index + 1,
            c.index,
            c.label()
        ));
    }
    Ok(())
}

/// Writes done.json or failed.json for a case that ended; the failure reason if it failed.
fn finish(
    c: &Case,
    dir: &Path,
    started: Instant,
    end: &Ended,
    not_started: Option<&str>,
) -> Result<Option<String>> {
    let cdir = c.dir(dir);
    let result = c.result_file(dir);
    let error = match (end.code, end.signal) {
        _ if not_started.is_some() => not_started.map(String::from),
        (Some(0), _) if result.is_file() => None,
        (Some(0), _) => Some(format!("exit code 0 but no {}", result.display())),
        (Some(code), _) => Some(format!("exit code {code}")),
        (None, Some(sig)) => Some(format!("killed by signal {sig}")),
        (None, None) => Some("ended without an exit code".into()),
    };
    let tail = if error.is_some() {
        log_tail(&cdir.join(LOG_FILE), 10)
    } else {
        Vec::new()
    };
    let rec = Record {
        index: c.index,
        key: c.key.clone(),
        exit_code: end.code,
        signal: end.signal,
        wall_s: started.elapsed().as_secs_f64(),
        cpu_s: end.cpu_s,
        host: crate::process::host(),
        finished_unix: unix_now(),
        error: error.clone(),
        log_tail: tail,
    };
    let name = if error.is_none() {
        DONE_FILE
    } else {
        FAILED_FILE
    };
    let path = cdir.join(name);
    let text = serde_json::to_string_pretty(&rec).map_err(|e| Error::io(&path, e))?;
    crate::write_atomic(&path, text.as_bytes())?;
    Ok(rec.reason())
}

/// A duration as `4.2s`, `35s`, `12m05s`, `3h07m`.
pub fn fmt_secs(s: f64) -> String {
    if s < 10.0 {
        return format!("{:.1}s", s.max(0.0));
    }
    let s = s.round() as u64;
    if s >= 3600 {
        format!("{}h{:02}m", s / 3600, s % 3600 / 60)
    } else if s >= 60 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{s}s")
    }
}

/// Runs the sweep's cases (module docs) and returns the folder's state at the end. An error:
/// the folder cannot be read, `index` is out of range, or a case's command line does not give
/// its key; a case that fails is recorded (`failed.json`) and counted, not an error.
pub fn run(a: &RunOptions, tests: &dyn TestCommands, report: &mut dyn Report) -> Result<Summary> {
    let t_run = Instant::now();
    let dir = a.dir.clone();
    let cases = read_cases(&dir)?;
    if let Some(i) = a.index {
        if i >= cases.len() {
            return Err(refuse!(
                "--index {i}: {} has {} cases (0-{})",
                dir.display(),
                cases.len(),
                cases.len().saturating_sub(1)
            ));
        }
    }
    let retry = a.retry_failed || a.index.is_some();
    // Only what was planned runs: each case to run gives its key again from its command line.
    verify_keys(&dir, &cases, a.index, tests)?;
    let chosen: Vec<usize> = match a.index {
        Some(i) => vec![i],
        None => (0..cases.len()).collect(),
    };
    let mut queue: VecDeque<usize> = chosen
        .iter()
        .copied()
        .filter(|&i| match case::state(&cases[i], &dir) {
            State::Done(_) | State::Running(_) => false,
            State::Failed(_) => retry,
            State::Pending => true,
        })
        .collect();
    let done0 = chosen
        .iter()
        .filter(|&&i| matches!(case::state(&cases[i], &dir), State::Done(_)))
        .count();
    report.line(format!(
        "sweep {}: {} cases, {} done, {} to run, {} at a time, {} thread(s) each",
        dir.display(),
        chosen.len(),
        done0,
        queue.len(),
        a.jobs,
        a.threads
    ));
    report.progress(done0, chosen.len(), "");
    let (mut done, mut failed, mut walls) = (done0, 0usize, Vec::<f64>::new());
    let mut running: Vec<Running> = Vec::new();
    let mut beat = Instant::now();
    loop {
        while running.len() < a.jobs {
            let Some(i) = queue.pop_front() else { break };
            let c = &cases[i];
            let claim = match claim::try_claim(&c.dir(&dir)) {
                Ok(Some(cl)) => cl,
                Ok(None) => continue, // another process runs it
                Err(e) => {
                    report.line(format!("case {i} ({}): {e}", c.label()));
                    failed += 1;
                    continue;
                }
            };
            // Finished by another process between the listing and the claim?
            match case::state(c, &dir) {
                State::Done(_) => {
                    claim.drop_unused();
                    continue;
                }
                State::Failed(_) if !retry => {
                    claim.drop_unused();
                    continue;
                }
                _ => {}
            }
            let started = Instant::now();
            match start(c, &dir, &a.executor, a.threads) {
                Ok(task) => running.push(Running {
                    index: i,
                    claim,
                    task,
                    dir: c.dir(&dir),
                    started,
                }),
                Err(e) => {
                    // Recorded like a case that failed (exit code none, the reason).
                    let end = Ended {
                        code: None,
                        signal: None,
                        cpu_s: None,
                    };
                    let _ = finish(c, &dir, started, &end, Some(&e.to_string()));
                    claim.release();
                    report.line(format!("case {i} ({}): {e}", c.label()));
                    failed += 1;
                }
            }
        }
        if running.is_empty() {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
        let mut k = 0;
        while k < running.len() {
            let Some(end) = poll(&mut running[k])? else {
                k += 1;
                continue;
            };
            let r = running.swap_remove(k);
            let c = &cases[r.index];
            let wall = r.started.elapsed().as_secs_f64();
            let fin = finish(c, &dir, r.started, &end, None);
            r.claim.release();
            match fin {
                // (A record that cannot be written, a full disk say, fails this case only.)
                Err(e) => {
                    failed += 1;
                    report.line(format!("case {} ({}): {e}", c.index, c.label()));
                }
                Ok(None) => {
                    done += 1;
                    walls.push(wall);
                    report.line(format!(
                        "case {} ({}) done in {}{}",
                        c.index,
                        c.label(),
                        fmt_secs(wall),
                        end.cpu_s
                            .map(|s| format!(" ({} CPU)", fmt_secs(s)))
                            .unwrap_or_default()
                    ));
                }
                Ok(Some(e)) => {
                    failed += 1;
                    report.line(format!("case {} ({}) failed: {e}", c.index, c.label()));
                }
            }
        }
        if beat.elapsed() >= HEARTBEAT {
            running.iter().for_each(|r| r.claim.touch());
            beat = Instant::now();
        }
        let eta = if walls.is_empty() {
            "?".to_string()
        } else {
            let mean = walls.iter().sum::<f64>() / walls.len() as f64;
            fmt_secs(mean * (queue.len() + running.len()) as f64 / a.jobs as f64)
        };
        let message = format!("{failed} failed, {} running, eta {eta}", running.len());
        report.progress(done, chosen.len(), &message);
    }
    // The final word is the folder's state (other processes may have run some cases).
    let mut counts = [0usize; 4];
    let mut failures = Vec::new();
    let mut elsewhere = Vec::new();
    for &i in &chosen {
        let c = &cases[i];
        match case::state(c, &dir) {
            State::Done(_) => counts[0] += 1,
            State::Failed(r) => {
                counts[1] += 1;
                failures.push(format!(
                    "  case {i} ({}): {}{}\n    log: {}",
                    c.label(),
                    r.error.unwrap_or_default(),
                    r.log_tail
                        .last()
                        .map(|l| format!(": {l}"))
                        .unwrap_or_default(),
                    c.dir(&dir).join(LOG_FILE).display()
                ));
            }
            State::Running(h) => {
                counts[2] += 1;
                elsewhere.push(format!("  case {i} ({}): running in {h}", c.label()));
            }
            State::Pending => counts[3] += 1,
        }
    }
    Ok(Summary {
        chosen: chosen.len(),
        done: counts[0],
        failed: counts[1],
        running: counts[2],
        pending: counts[3],
        wall_s: t_run.elapsed().as_secs_f64(),
        elsewhere,
        failures,
    })
}

#[cfg(test)]
mod tests {
    /// Issue 48: a case ended by a usage error was summarised by clap's last line, "For more
    /// information, try '--help'."; the `error:` line is the reason.
    #[test]
    fn the_reason_is_the_error_line_not_the_help_hint() {
        let tail: Vec<String> = [
            "error: unexpected argument '--bogus' found",
            "",
            "Usage: dem test cutting [OPTIONS] --out <OUT>",
            "For more information, try '--help'.",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(
            crate::case::reason_line(&tail).unwrap(),
            "error: unexpected argument '--bogus' found"
        );
        let plain = vec!["step 10".to_string(), "killed".to_string()];
        assert_eq!(crate::case::reason_line(&plain).unwrap(), "killed");
    }
}
