//! The collector: `dem sweep status DIR` ([`status`]) and `dem sweep collect DIR --out
//! table.csv|table.json` ([`write()`]).
//!
//! The table has one row per case: index, key, the axis values, status, the collected outputs
//! (the JSON values at the study's pointers in `<test>.result.json`, done cases only), exit
//! code, wall and CPU time (`done.json`/`failed.json`). Aggregates are over the seed axis: the
//! cases that share every other axis value form a group, and for each output its numeric
//! values over the group's done cases give n, mean x̄ = Σx/n, sd = √(Σ(x − x̄)²/(n − 1)),
//! SE = sd/√n and the median (the middle value, or the mean of the two middle ones). sd and SE
//! need n ≥ 2; a figure that does not exist is null in JSON and an empty cell in CSV, never
//! NaN. CSV writes the aggregates beside the table as `<stem>.aggregates.csv`. With the timing
//! columns, JSON also holds the sweep's time, overall and per axis value ([`crate::timing`]),
//! which `status` prints. Files are written atomically.

use crate::case::{self, read_cases, State, STUDY_FILE};
use crate::error::{refuse, Error, Result};
use crate::study;
use crate::timing::{self, Sum, Timing};
use serde_json::{json, Map, Value};
use std::path::Path;

/// n, mean, sd (n − 1), SE and median of `x`; `None` where undefined.
#[derive(Debug, PartialEq)]
pub struct Stats {
    pub n: usize,
    pub mean: Option<f64>,
    pub sd: Option<f64>,
    pub se: Option<f64>,
    pub median: Option<f64>,
}

pub fn stats(x: &[f64]) -> Stats {
    let n = x.len();
    let fin = |v: f64| v.is_finite().then_some(v);
    if n == 0 {
        return Stats {
            n,
            mean: None,
            sd: None,
            se: None,
            median: None,
        };
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let sd = (n >= 2)
        .then(|| (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt());
    let mut s = x.to_vec();
    s.sort_by(f64::total_cmp);
    let median = if n % 2 == 1 {
        s[n / 2]
    } else {
        (s[n / 2 - 1] + s[n / 2]) / 2.0
    };
    Stats {
        n,
        mean: fin(mean),
        sd: sd.and_then(fin),
        se: sd.and_then(|sd| fin(sd / (n as f64).sqrt())),
        median: fin(median),
    }
}

fn num(v: Option<f64>) -> Value {
    v.and_then(serde_json::Number::from_f64)
        .map(Value::Number)
        .unwrap_or(Value::Null)
}

/// A group of cases: the axis values they share (all but the seed) and their indices.
type Group = (Vec<(String, String)>, Vec<usize>);

/// The seed axis of the sweep in `dir` (`None` when its study has none or cannot be read:
/// `status` then sums over every axis).
fn seed_axis(dir: &Path) -> Option<String> {
    study::read(&dir.join(STUDY_FILE)).ok()?.1.seed_axis()
}

/// The table as JSON (see the module doc).
pub fn table(dir: &Path, timing: bool) -> Result<Value> {
    let file = dir.join(STUDY_FILE);
    let bytes = clumpgen::io::read_input(&file).map_err(|e| Error::io(&file, e))?;
    let p = study::parse(&bytes, &file)?;
    let cases = read_cases(dir)?;
    let seed = p.seed_axis();
    let mut rows = Vec::new();
    let mut groups: Vec<Group> = Vec::new();
    let mut records = Vec::new();
    for c in &cases {
        let st = case::state(c, dir);
        let mut outs = Map::new();
        let result: Option<Value> = match &st {
            State::Done(_) => std::fs::read_to_string(c.result_file(dir))
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok()),
            _ => None,
        };
        for o in &p.outputs {
            let v = result
                .as_ref()
                .and_then(|r| r.pointer(&o.pointer))
                .cloned()
                .unwrap_or(Value::Null);
            outs.insert(o.name.clone(), v);
        }
        let rec = match &st {
            State::Done(r) | State::Failed(r) => Some(r),
            _ => None,
        };
        let mut row = Map::new();
        row.insert("index".into(), json!(c.index));
        row.insert("key".into(), json!(c.key));
        row.insert(
            "axes".into(),
            Value::Object(c.axes.iter().map(|(f, v)| (f.clone(), json!(v))).collect()),
        );
        row.insert("status".into(), json!(st.name()));
        row.insert("outputs".into(), Value::Object(outs));
        row.insert("exit_code".into(), json!(rec.and_then(|r| r.exit_code)));
        if let State::Failed(r) = &st {
            row.insert("error".into(), json!(r.error));
        }
        if timing {
            row.insert("wall_s".into(), num(rec.map(|r| r.wall_s)));
            row.insert("cpu_s".into(), num(rec.and_then(|r| r.cpu_s)));
        }
        records.push(rec.cloned());
        rows.push(Value::Object(row));
        if seed.is_some() {
            let g: Vec<(String, String)> = c
                .axes
                .iter()
                .filter(|(f, _)| Some(f) != seed.as_ref())
                .cloned()
                .collect();
            match groups.iter_mut().find(|(k, _)| *k == g) {
                Some((_, v)) => v.push(c.index),
                None => groups.push((g, vec![c.index])),
            }
        }
    }
    let mut aggs = Vec::new();
    for (g, members) in &groups {
        let mut outs = Map::new();
        for o in &p.outputs {
            let x: Vec<f64> = members
                .iter()
                .filter_map(|&i| rows[i]["outputs"][&o.name].as_f64())
                .collect();
            let s = stats(&x);
            outs.insert(
                o.name.clone(),
                json!({"n": s.n, "mean": num(s.mean), "sd": num(s.sd), "se": num(s.se),
                       "median": num(s.median)}),
            );
        }
        let done = members
            .iter()
            .filter(|&&i| rows[i]["status"] == "done")
            .count();
        aggs.push(json!({
            "group": Value::Object(g.iter().map(|(f, v)| (f.clone(), json!(v))).collect()),
            "cases": members.len(),
            "done": done,
            "outputs": Value::Object(outs),
        }));
    }
    let mut t = json!({
        "study": p.study.name,
        "test": p.study.base.test,
        "axes": p.axes.iter().map(|a| a.flag.clone()).collect::<Vec<_>>(),
        "seed_axis": seed,
        "outputs": p.outputs.iter().map(|o| json!({"name": o.name, "pointer": o.pointer}))
            .collect::<Vec<_>>(),
        "cases": rows,
        "aggregates": aggs,
    });
    if timing {
        t["timing"] = timing::timing(&cases, &records, seed.as_deref())
            .map_or(Value::Null, |t| timing_json(&t));
    }
    Ok(t)
}

/// [`Timing`] as JSON.
fn timing_json(t: &Timing) -> Value {
    let sum = |s: &Sum| {
        json!({"cases": s.cases, "cpu_s": num(Some(s.cpu_s)), "cpu_unknown": s.cpu_unknown,
               "wall_s": num(Some(s.wall_s))})
    };
    let mut v = sum(&t.all);
    v["busy_s"] = num(Some(t.busy_s));
    v["span_s"] = num(Some(t.span_s));
    v["by_axis"] = t
        .by_axis
        .iter()
        .map(|a| {
            let values: Vec<Value> = a
                .values
                .iter()
                .map(|(val, s)| {
                    let mut o = sum(s);
                    o["value"] = json!(val);
                    o
                })
                .collect();
            json!({"axis": a.axis, "values": values})
        })
        .collect();
    v
}

fn cell(v: &Value) -> String {
    let s = match v {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        v => v.to_string(),
    };
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s
    }
}

fn csv(header: &[String], rows: &[Vec<Value>]) -> String {
    let mut s = header
        .iter()
        .map(|h| cell(&json!(h)))
        .collect::<Vec<_>>()
        .join(",");
    s.push('\n');
    for r in rows {
        s += &r.iter().map(cell).collect::<Vec<_>>().join(",");
        s.push('\n');
    }
    s
}

/// The case table and the aggregates table as CSV.
fn to_csv(t: &Value, timing: bool) -> (String, String) {
    let strs = |v: &Value| -> Vec<String> {
        v.as_array()
            .map(|a| {
                a.iter()
                    .filter_map(|x| x.as_str().map(String::from))
                    .collect()
            })
            .unwrap_or_default()
    };
    let axes = strs(&t["axes"]);
    let outputs: Vec<String> = t["outputs"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|o| o["name"].as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    let mut h: Vec<String> = vec!["index".into(), "key".into()];
    h.extend(axes.iter().cloned());
    h.push("status".into());
    h.extend(outputs.iter().cloned());
    h.push("exit_code".into());
    if timing {
        h.extend(["wall_s".into(), "cpu_s".into()]);
    }
    let empty = Vec::new();
    let rows: Vec<Vec<Value>> = t["cases"]
        .as_array()
        .unwrap_or(&empty)
        .iter()
        .map(|c| {
            let mut r = vec![c["index"].clone(), c["key"].clone()];
            r.extend(axes.iter().map(|a| c["axes"][a].clone()));
            r.push(c["status"].clone());
            r.extend(outputs.iter().map(|o| c["outputs"][o].clone()));
            r.push(c["exit_code"].clone());
            if timing {
                r.extend([c["wall_s"].clone(), c["cpu_s"].clone()]);
            }
            r
        })
        .collect();
    let seed = t["seed_axis"].as_str().unwrap_or_default();
    let group: Vec<String> = axes.iter().filter(|a| *a != seed).cloned().collect();
    let mut ah = group.clone();
    ah.extend(["cases".into(), "done".into()]);
    for o in &outputs {
        for s in ["n", "mean", "sd", "se", "median"] {
            ah.push(format!("{o}.{s}"));
        }
    }
    let arows: Vec<Vec<Value>> = t["aggregates"]
        .as_array()
        .unwrap_or(&empty)
        .iter()
        .map(|g| {
            let mut r: Vec<Value> = group.iter().map(|a| g["group"][a].clone()).collect();
            r.extend([g["cases"].clone(), g["done"].clone()]);
            for o in &outputs {
                for s in ["n", "mean", "sd", "se", "median"] {
                    r.push(g["outputs"][o][s].clone());
                }
            }
            r
        })
        .collect();
    (csv(&h, &rows), csv(&ah, &arows))
}

/// What [`write()`] wrote.
pub struct Written {
    /// The files, as `table.csv and table.aggregates.csv`.
    pub files: String,
    pub cases: usize,
    pub done: usize,
    pub groups: usize,
    /// The seed axis, if the study has one.
    pub seed_axis: Option<String>,
}

/// Writes the table of the sweep in `dir` to `out` (`.json`, or `.csv` with
/// `<stem>.aggregates.csv` beside it), with the timing columns if `timing`.
pub fn write(dir: &Path, out: &Path, timing: bool) -> Result<Written> {
    let t = table(dir, timing)?;
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("");
    let files = match ext {
        "json" => {
            let mut s = serde_json::to_string_pretty(&t).map_err(|e| Error::io(out, e))?;
            s.push('\n');
            crate::write_atomic(out, s.as_bytes())?;
            out.display().to_string()
        }
        "csv" => {
            let (cases, aggs) = to_csv(&t, timing);
            let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("table");
            let agg = out.with_file_name(format!("{stem}.aggregates.csv"));
            crate::write_atomic(out, cases.as_bytes())?;
            crate::write_atomic(&agg, aggs.as_bytes())?;
            format!("{} and {}", out.display(), agg.display())
        }
        _ => {
            return Err(refuse!(
                "--out {}: give a .csv or .json file",
                out.display()
            ))
        }
    };
    let rows = t["cases"].as_array();
    Ok(Written {
        files,
        cases: rows.map_or(0, Vec::len),
        done: rows.map_or(0, |c| c.iter().filter(|r| r["status"] == "done").count()),
        groups: t["aggregates"].as_array().map_or(0, Vec::len),
        seed_axis: t["seed_axis"].as_str().map(String::from),
    })
}

/// The lines `dem sweep status` prints: the counts, a line per case, the time taken.
pub fn status(dir: &Path) -> Result<Vec<String>> {
    let cases = read_cases(dir)?;
    let mut counts = std::collections::BTreeMap::<&str, usize>::new();
    let mut lines = Vec::new();
    let mut records = Vec::new();
    for c in &cases {
        let st = case::state(c, dir);
        records.push(match &st {
            State::Done(r) | State::Failed(r) => Some(r.clone()),
            _ => None,
        });
        *counts.entry(st.name()).or_default() += 1;
        let extra = match &st {
            State::Done(r) => format!(
                "{:.1} s{}",
                r.wall_s,
                r.cpu_s
                    .map(|c| format!(", {c:.1} s CPU"))
                    .unwrap_or_default()
            ),
            State::Failed(r) => r.error.clone().unwrap_or_default(),
            State::Running(h) => format!("in {h}"),
            State::Pending => String::new(),
        };
        lines.push(format!(
            "{:>5} {}  {:<8} {}  {extra}",
            c.index,
            &c.key[..12],
            st.name(),
            c.label()
        ));
    }
    let count = |k: &str| counts.get(k).copied().unwrap_or(0);
    let mut out = vec![format!(
        "{}: {} cases: {} done, {} failed, {} running, {} pending",
        dir.display(),
        cases.len(),
        count("done"),
        count("failed"),
        count("running"),
        count("pending")
    )];
    out.extend(lines);
    if let Some(t) = timing::timing(&cases, &records, seed_axis(dir).as_deref()) {
        out.extend(timing::lines(&t));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::stats;

    #[test]
    fn stats_by_hand() {
        let s = stats(&[4.0, 1.0, 2.0]);
        assert_eq!(s.n, 3);
        assert!((s.mean.unwrap() - 7.0 / 3.0).abs() < 1e-15);
        // Σ(x − 7/3)² = (25 + 16 + 1)/9 = 42/9; / (n − 1) = 7/3.
        assert!((s.sd.unwrap() - (7.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((s.se.unwrap() - (7.0f64 / 9.0).sqrt()).abs() < 1e-15);
        assert_eq!(s.median, Some(2.0));
        assert_eq!(stats(&[1.0, 3.0, 10.0, 2.0]).median, Some(2.5));
        let one = stats(&[5.0]);
        assert_eq!((one.sd, one.se, one.median), (None, None, Some(5.0)));
        assert_eq!(stats(&[]).mean, None);
    }
}
