//! Progress of long work on stderr, wherever stderr goes.
//!
//! On a terminal, an indicatif bar (redrawn in place, cleared at the end). Anywhere else — a
//! pipe, a log file, a Slurm job's `.err`, a sweep case's `log.txt` — a bar draws nothing, so
//! a long read or generation looked hung (issue 48: a 20,000-feature GeoJSON, a 10 m specimen).
//! There a plain line is written instead, at most one every `DEM_PROGRESS_SECS` seconds
//! (default [`DEFAULT_SECS`]; `0` or `off` for none), the first after one interval, so work
//! shorter than that prints nothing, and a closing line when any was written:
//!
//! ```text
//! [  10.0 s] grow 45 %: 1234 of 25123 discs
//! [  20.0 s] 8000/20000 grains (40 %), ~30 s left
//! [  41.3 s] 20000/20000 grains: done
//! ```

use std::io::IsTerminal;
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// Seconds between two progress lines off a terminal unless `DEM_PROGRESS_SECS` says otherwise.
pub const DEFAULT_SECS: f64 = 10.0;

/// The environment variable that sets the interval of progress lines off a terminal.
pub const ENV: &str = "DEM_PROGRESS_SECS";

/// The interval of progress lines off a terminal, `None` for none; read once per process. A value
/// that is not a number of seconds is reported once and the default used.
fn interval() -> Option<Duration> {
    static EVERY: OnceLock<Option<Duration>> = OnceLock::new();
    *EVERY.get_or_init(|| {
        let Ok(v) = std::env::var(ENV) else {
            return Some(Duration::from_secs_f64(DEFAULT_SECS));
        };
        match parse_interval(&v) {
            Ok(d) => d,
            Err(why) => {
                eprintln!("warning: {ENV}={v:?}: {why}; progress lines every {DEFAULT_SECS} s");
                Some(Duration::from_secs_f64(DEFAULT_SECS))
            }
        }
    })
}

/// `DEM_PROGRESS_SECS`'s value: seconds (> 0, at most a day), or `0` / `off` for no lines.
fn parse_interval(v: &str) -> Result<Option<Duration>, String> {
    let v = v.trim();
    if v.eq_ignore_ascii_case("off") {
        return Ok(None);
    }
    let s: f64 = v
        .parse()
        .map_err(|_| "not a number of seconds (or `off`)".to_string())?;
    if s == 0.0 {
        Ok(None)
    } else if s.is_finite() && s > 0.0 && s <= 86_400.0 {
        Ok(Some(Duration::from_secs_f64(s)))
    } else {
        Err("seconds must be in (0, 86400], or 0 / `off` for no lines".to_string())
    }
}

/// What the numbers of a progress count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Stages of a generation, each with a fraction done (position in thousandths).
    Stages,
    /// Items of a known count ("grains", "steps").
    Counted(&'static str),
}

/// The off-terminal line writer's state.
#[derive(Debug)]
struct Log {
    start: Instant,
    every: Duration,
    next: Instant,
    len: u64,
    pos: u64,
    prefix: String,
    msg: String,
    printed: bool,
}

/// Progress on stderr: a bar on a terminal, a line every few seconds elsewhere (module docs).
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
    kind: Kind,
    log: Option<Mutex<Log>>,
}

impl Progress {
    /// Stages of a generation or a lab test: a prefix (the stage), its fraction done through
    /// [`Progress::set_fraction`] or a position in thousandths, and a message.
    pub fn stages() -> Self {
        Self::with(
            Kind::Stages,
            1000,
            "{elapsed:>5} {prefix:<10} {bar:30} {msg}",
        )
    }

    /// `len` items called `unit` ("grains", "steps"), with an estimate of the time left.
    pub fn counted(len: u64, unit: &'static str) -> Self {
        let template = format!(
            "{{elapsed:>5}} {{prefix}} {{bar:30}} {{pos}}/{{len}} {unit}, eta {{eta}} {{msg}}"
        );
        Self::with(Kind::Counted(unit), len, &template)
    }

    fn with(kind: Kind, len: u64, template: &str) -> Self {
        Self::on(
            std::io::stderr().is_terminal(),
            interval(),
            kind,
            len,
            template,
        )
    }

    /// `terminal`: draw a bar; otherwise write lines every `every` (none for `None`).
    fn on(terminal: bool, every: Option<Duration>, kind: Kind, len: u64, template: &str) -> Self {
        if terminal {
            let bar = ProgressBar::new(len);
            if let Ok(s) = ProgressStyle::with_template(template) {
                bar.set_style(s);
            }
            return Self {
                bar,
                kind,
                log: None,
            };
        }
        let now = Instant::now();
        let log = every.map(|every| {
            Mutex::new(Log {
                start: now,
                every,
                next: now + every,
                len,
                pos: 0,
                prefix: String::new(),
                msg: String::new(),
                printed: false,
            })
        });
        Self {
            bar: ProgressBar::hidden(),
            kind,
            log,
        }
    }

    /// Changes the total.
    pub fn set_length(&self, len: u64) {
        self.bar.set_length(len);
        self.update(|l| l.len = len);
    }

    /// Sets the position (items done, or thousandths of a stage).
    pub fn set_position(&self, pos: u64) {
        self.bar.set_position(pos);
        self.update(|l| l.pos = pos);
    }

    /// Sets a stage's fraction done, clamped to [0, 1].
    pub fn set_fraction(&self, fraction: f64) {
        self.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
    }

    /// One more item done.
    pub fn inc(&self, n: u64) {
        self.bar.inc(n);
        self.update(|l| l.pos += n);
    }

    /// The stage or the name of the work.
    pub fn set_prefix(&self, prefix: impl Into<String>) {
        let prefix = prefix.into();
        self.bar.set_prefix(prefix.clone());
        self.update(|l| l.prefix = prefix);
    }

    /// A short status.
    pub fn set_message(&self, msg: impl Into<String>) {
        let msg = msg.into();
        self.bar.set_message(msg.clone());
        self.update(|l| l.msg = msg);
    }

    /// A line above the bar; off a terminal nothing (the caller prints its lines itself:
    /// [`Progress::is_hidden`]).
    pub fn println(&self, line: &str) {
        self.bar.println(line);
    }

    /// True when no bar is drawn (stderr is not a terminal).
    pub fn is_hidden(&self) -> bool {
        self.bar.is_hidden()
    }

    /// Clears the bar; off a terminal, a closing line when any progress line was written.
    pub fn finish_and_clear(&self) {
        self.bar.finish_and_clear();
        if let Some(log) = &self.log {
            let l = log.lock().unwrap_or_else(|p| p.into_inner());
            if l.printed {
                eprintln!("{}", self.line(&l, l.start.elapsed(), true));
            }
        }
    }

    fn update(&self, f: impl FnOnce(&mut Log)) {
        let Some(log) = &self.log else { return };
        let mut l = log.lock().unwrap_or_else(|p| p.into_inner());
        f(&mut l);
        let now = Instant::now();
        if now >= l.next {
            l.next = now + l.every;
            l.printed = true;
            eprintln!("{}", self.line(&l, now - l.start, false));
        }
    }

    /// One progress line: elapsed time, what, how far, and for counted work the time left.
    fn line(&self, l: &Log, elapsed: Duration, done: bool) -> String {
        let t = elapsed.as_secs_f64();
        let mut s = format!("[{t:>6.1} s]");
        // The closing line of stages says "done", not the last stage's name.
        let closing_stages = done && self.kind == Kind::Stages;
        if !closing_stages && !l.prefix.is_empty() {
            s.push(' ');
            s.push_str(&l.prefix);
        }
        match self.kind {
            Kind::Stages if done => s.push_str(" done"),
            Kind::Stages => s.push_str(&format!(" {:.0} %", l.pos as f64 / 10.0)),
            Kind::Counted(unit) => {
                s.push_str(&format!(" {}/{} {unit}", l.pos, l.len));
                if done {
                    s.push_str(": done");
                } else if l.len > 0 {
                    let f = l.pos as f64 / l.len as f64;
                    s.push_str(&format!(" ({:.0} %)", 100.0 * f));
                    if f > 0.0 {
                        s.push_str(&format!(", ~{:.0} s left", t * (1.0 - f) / f));
                    }
                }
            }
        }
        if !done && !l.msg.is_empty() {
            s.push_str(": ");
            s.push_str(&l.msg);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn log_of(p: &Progress) -> std::sync::MutexGuard<'_, Log> {
        p.log
            .as_ref()
            .expect("off-terminal progress")
            .lock()
            .unwrap()
    }

    #[test]
    fn interval_values() {
        assert_eq!(parse_interval("off"), Ok(None));
        assert_eq!(parse_interval("0"), Ok(None));
        assert_eq!(
            parse_interval(" 2.5 "),
            Ok(Some(Duration::from_millis(2500)))
        );
        assert!(parse_interval("abc").unwrap_err().contains("not a number"));
        assert!(parse_interval("-1").unwrap_err().contains("(0, 86400]"));
        assert!(parse_interval("inf").is_err());
        assert!(parse_interval("NaN").is_err());
    }

    #[test]
    fn lines_say_how_far_and_how_long() {
        let p = Progress::on(
            false,
            Some(Duration::from_secs(3600)),
            Kind::Counted("grains"),
            20,
            "",
        );
        p.inc(5);
        let l = log_of(&p);
        assert!(!l.printed, "no line before one interval");
        let s = p.line(&l, Duration::from_secs(10), false);
        assert_eq!(s, "[  10.0 s] 5/20 grains (25 %), ~30 s left");
        assert_eq!(
            p.line(&l, Duration::from_secs(40), true),
            "[  40.0 s] 5/20 grains: done"
        );
        drop(l);

        let p = Progress::on(false, Some(Duration::ZERO), Kind::Stages, 1000, "");
        p.set_prefix("grow");
        p.set_message("300 discs");
        p.set_fraction(0.456);
        let l = log_of(&p);
        assert!(l.printed, "a zero interval writes at every update");
        assert_eq!(
            p.line(&l, Duration::from_secs(12), false),
            "[  12.0 s] grow 46 %: 300 discs"
        );
        assert_eq!(
            p.line(&l, Duration::from_millis(13_240), true),
            "[  13.2 s] done"
        );
    }

    #[test]
    fn no_lines_when_off_and_a_bar_only_on_a_terminal() {
        let p = Progress::on(false, None, Kind::Stages, 1000, "");
        assert!(p.log.is_none() && p.is_hidden());
        p.set_fraction(0.5);
        let p = Progress::on(true, Some(Duration::ZERO), Kind::Stages, 1000, "{bar}");
        assert!(p.log.is_none());
    }
}
