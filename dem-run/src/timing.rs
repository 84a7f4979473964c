//! The time a sweep took, overall and per axis value (issue 21: "state the time per method").
//!
//! Each finished case (done or failed) has a record of its last attempt (`done.json` /
//! `failed.json`): its wall time w, its CPU time c (user + system of the case's process, when
//! known) and the Unix time f at its end (whole seconds). From the records:
//! - **CPU** = Σ c and **case wall** = Σ w, over all finished cases and over the cases of each
//!   value of every axis but the seed axis (e.g. per method);
//! - **busy** = the length of the union of the intervals [f − w, f]: the time during which at
//!   least one case was running. For one uninterrupted `dem sweep run --jobs N` it is that
//!   run's wall time (to about a second: f is whole seconds, and the runner's start before its
//!   first case is not in it); for a sweep run in several sittings it leaves out the time
//!   between them; for a job array it assumes the nodes' clocks agree;
//! - **span** = the last end − the first start (busy plus any time in which no case ran).
//!
//! Attempts before the last one (a case killed and resumed from its checkpoints) have no
//! record, so their time is in none of the figures.
//!
//! ```text
//! case A: [0, 100], case B: [50, 120], case C: [200, 230]
//! busy = (120 − 0) + (230 − 200) = 150 s, span = 230 s, case wall = 100 + 70 + 30 = 200 s
//! ```

use crate::case::{Case, Record};

/// Time summed over a set of finished cases.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sum {
    /// Finished cases (with a record).
    pub cases: usize,
    /// Σ CPU time (s) of the cases whose CPU time is known.
    pub cpu_s: f64,
    /// Cases without a CPU time (a case that could not be started, a platform without
    /// `wait4`).
    pub cpu_unknown: usize,
    /// Σ wall time (s).
    pub wall_s: f64,
}

impl Sum {
    fn add(&mut self, r: &Record) {
        self.cases += 1;
        self.wall_s += r.wall_s;
        match r.cpu_s {
            Some(c) => self.cpu_s += c,
            None => self.cpu_unknown += 1,
        }
    }
}

/// The sums of the cases sharing one value of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisSums {
    /// The axis (its flag or set name: `method`, `depth`).
    pub axis: String,
    /// Each value in the order of first appearance in the plan, with its sums.
    pub values: Vec<(String, Sum)>,
}

/// A sweep's time (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    pub all: Sum,
    /// Length of the union of the cases' run intervals (s).
    pub busy_s: f64,
    /// Last end − first start (s).
    pub span_s: f64,
    /// Per axis other than the seed axis.
    pub by_axis: Vec<AxisSums>,
}

/// Length of the union of the intervals `[a, b]` (any order; empty ones count 0).
pub fn union_length(iv: &mut [(f64, f64)]) -> f64 {
    iv.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut total = 0.0;
    let mut cur: Option<(f64, f64)> = None;
    for &(a, b) in iv.iter() {
        if b <= a {
            continue;
        }
        cur = match cur {
            Some((ca, cb)) if a <= cb => Some((ca, cb.max(b))),
            Some((ca, cb)) => {
                total += cb - ca;
                Some((a, b))
            }
            None => Some((a, b)),
        };
    }
    total + cur.map_or(0.0, |(a, b)| b - a)
}

/// The timing of `cases` from their records (`None`: not finished), or `None` when no case
/// has finished. `seed_axis`: the axis left out of the per-axis sums.
pub fn timing(
    cases: &[Case],
    records: &[Option<Record>],
    seed_axis: Option<&str>,
) -> Option<Timing> {
    let mut all = Sum::default();
    let mut by_axis: Vec<AxisSums> = Vec::new();
    let mut iv = Vec::new();
    for (c, r) in cases.iter().zip(records) {
        let Some(r) = r else { continue };
        all.add(r);
        let end = r.finished_unix as f64;
        iv.push((end - r.wall_s, end));
        for (axis, value) in &c.axes {
            if Some(axis.as_str()) == seed_axis {
                continue;
            }
            let k = match by_axis.iter().position(|a| &a.axis == axis) {
                Some(k) => k,
                None => {
                    by_axis.push(AxisSums {
                        axis: axis.clone(),
                        values: Vec::new(),
                    });
                    by_axis.len() - 1
                }
            };
            let vals = &mut by_axis[k].values;
            match vals.iter_mut().find(|(v, _)| v == value) {
                Some((_, s)) => s.add(r),
                None => {
                    let mut s = Sum::default();
                    s.add(r);
                    vals.push((value.clone(), s));
                }
            }
        }
    }
    if all.cases == 0 {
        return None;
    }
    let first = iv.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    let last = iv.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    Some(Timing {
        all,
        busy_s: union_length(&mut iv),
        span_s: last - first,
        by_axis,
    })
}

/// `12,345.6 s (3.43 h)` for long times, `95.2 s` for short ones.
pub fn secs(s: f64) -> String {
    let tenths = (s.max(0.0) * 10.0).round() as u64;
    let mut digits = (tenths / 10).to_string();
    let mut grouped = String::new();
    while digits.len() > 3 {
        let tail = digits.split_off(digits.len() - 3);
        grouped = format!(",{tail}{grouped}");
    }
    let text = format!("{digits}{grouped}.{} s", tenths % 10);
    if s >= 3600.0 {
        format!("{text} ({:.2} h)", s / 3600.0)
    } else {
        text
    }
}

/// The lines `dem sweep status` prints: the total, then the sums per value of each axis with
/// more than one value.
pub fn lines(t: &Timing) -> Vec<String> {
    let sum = |s: &Sum| {
        let unknown = if s.cpu_unknown > 0 {
            format!(" ({} without a CPU time)", s.cpu_unknown)
        } else {
            String::new()
        };
        format!(
            "{} case{}, CPU {}{unknown}, wall {}",
            s.cases,
            if s.cases == 1 { "" } else { "s" },
            secs(s.cpu_s),
            secs(s.wall_s)
        )
    };
    let mut out = vec![format!(
        "time of the finished cases (last attempts): {}; busy (some case running) {}, \
         first start to last end {}",
        sum(&t.all),
        secs(t.busy_s),
        secs(t.span_s)
    )];
    // (Axes with one value repeat the total.)
    for a in t.by_axis.iter().filter(|a| a.values.len() > 1) {
        for (v, s) in &a.values {
            out.push(format!("  {}={v}: {}", a.axis, sum(s)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(end: u64, wall: f64, cpu: Option<f64>) -> Record {
        Record {
            index: 0,
            key: String::new(),
            exit_code: Some(0),
            signal: None,
            wall_s: wall,
            cpu_s: cpu,
            host: "h".into(),
            finished_unix: end,
            error: None,
            log_tail: Vec::new(),
        }
    }

    fn case(method: &str, seed: &str) -> Case {
        Case {
            index: 0,
            key: String::new(),
            test: "cutting".into(),
            axes: vec![
                ("method".into(), method.into()),
                ("seed".into(), seed.into()),
            ],
            argv: Vec::new(),
        }
    }

    #[test]
    fn union_of_overlapping_touching_nested_and_empty_intervals() {
        // [0,100] ∪ [50,120] = [0,120]; [120,130] touches it; [125,126] is inside;
        // [200,230] apart; [300,300] and [400,350] are empty.
        let mut iv = [
            (200.0, 230.0),
            (50.0, 120.0),
            (300.0, 300.0),
            (0.0, 100.0),
            (125.0, 126.0),
            (400.0, 350.0),
            (120.0, 130.0),
        ];
        assert_eq!(union_length(&mut iv), 130.0 + 30.0);
        assert_eq!(union_length(&mut []), 0.0);
    }

    #[test]
    fn sums_per_axis_value_and_busy_time_by_hand() {
        // The module doc's example: A [0,100], B [50,120], C [200,230] (ends 1000 s later),
        // and a pending case D.
        let cases = [
            case("orc", "1"),
            case("improved", "1"),
            case("orc", "2"),
            case("orc", "3"),
        ];
        let (a, b, c) = (
            rec(1100, 100.0, Some(90.0)),
            rec(1120, 70.0, Some(60.5)),
            rec(1230, 30.0, None),
        );
        let recs = [Some(a.clone()), Some(b), Some(c), None];
        let t = timing(&cases, &recs, Some("seed")).unwrap();
        assert_eq!(t.all.cases, 3);
        assert_eq!(t.all.wall_s, 200.0);
        assert_eq!(t.all.cpu_s, 150.5);
        assert_eq!(t.all.cpu_unknown, 1);
        assert_eq!(t.busy_s, 150.0);
        assert_eq!(t.span_s, 230.0);
        assert_eq!(t.by_axis.len(), 1, "the seed axis is left out");
        assert_eq!(t.by_axis[0].axis, "method");
        let v = &t.by_axis[0].values;
        assert_eq!(v[0].0, "orc");
        assert_eq!(
            (v[0].1.cases, v[0].1.wall_s, v[0].1.cpu_s),
            (2, 130.0, 90.0)
        );
        assert_eq!(v[0].1.cpu_unknown, 1);
        assert_eq!(v[1].0, "improved");
        assert_eq!((v[1].1.cases, v[1].1.wall_s, v[1].1.cpu_s), (1, 70.0, 60.5));
        // Without a seed axis every axis is summed; nothing finished: no timing.
        assert_eq!(
            timing(&cases, &[Some(a), None, None, None], None)
                .unwrap()
                .by_axis
                .len(),
            2
        );
        assert_eq!(
            timing(&cases, &[None, None, None, None], Some("seed")),
            None
        );
    }

    #[test]
    fn seconds_are_grouped_and_long_ones_in_hours() {
        assert_eq!(secs(95.24), "95.2 s");
        assert_eq!(secs(12345.64), "12,345.6 s (3.43 h)");
        assert_eq!(secs(1234567.0), "1,234,567.0 s (342.94 h)");
        assert_eq!(secs(0.0), "0.0 s");
        assert_eq!(secs(999.96), "1,000.0 s");
    }
}
