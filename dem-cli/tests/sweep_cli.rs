//! `dem sweep` end to end with the built `dem`, on tiny cutting cases (3 × 1.5 mm specimen,
//! 1 mm cut; well under a second each in the test profile): planning is stable and keyed by
//! content; a `kill -9` of `run` mid-case and a rerun give the table of an uninterrupted run,
//! the killed case resumed from its checkpoint; a failing case leaves the others done and is
//! listed with its error; `--index` runs one case; two concurrent `run`s never run a case
//! twice; the aggregates equal a hand computation; bad study files are exit code 2 naming the
//! file and the field.

use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{dem, dem_in, material, text, tmp};

/// A cutting study of tiny cases; `speed` sets the run length (10 m/s: ~60,000 steps).
fn study(name: &str, speed: &str, depths: &[&str], seeds: &[u64]) -> Value {
    json!({
        "name": name,
        "base": {"test": "cutting", "flags": {
            "width": "3mm", "height": "1.5mm", "r-min": "0.1mm", "r-max": "0.16mm",
            "material": material(), "speed": speed, "length": "1mm", "history-rows": 200
        }},
        "axes": [{"flag": "depth", "values": depths}, {"seeds": seeds}],
        "collect": ["/main_force/mean", "/main_force/peak",
                    {"name": "broken", "pointer": "/broken_total"}]
    })
}

fn write(dir: &Path, name: &str, v: &Value) -> String {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string_pretty(v).unwrap()).unwrap();
    p.display().to_string()
}

fn plan(study: &str, out: &Path) -> Output {
    dem(&["sweep", "plan", study, "--out", out.to_str().unwrap()])
}

fn cases(dir: &Path) -> Vec<Value> {
    std::fs::read_to_string(dir.join("cases.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn case_dir(dir: &Path, c: &Value) -> PathBuf {
    dir.join("cases").join(c["key"].as_str().unwrap())
}

/// Attempts recorded in a case's log (one header line per start).
fn attempts(dir: &Path, c: &Value) -> usize {
    std::fs::read_to_string(case_dir(dir, c).join("log.txt"))
        .unwrap_or_default()
        .lines()
        .filter(|l| l.starts_with("=== dem sweep run: attempt"))
        .count()
}

fn collect(dir: &Path, out: &Path, extra: &[&str]) -> String {
    let mut a = vec![
        "sweep",
        "collect",
        dir.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    a.extend_from_slice(extra);
    let o = dem(&a);
    assert!(o.status.success(), "{}", text(&o));
    std::fs::read_to_string(out).unwrap()
}

#[test]
fn same_study_same_cases_and_keys_by_content() {
    let d = tmp("plan");
    let s = write(
        &d,
        "s.json",
        &study("p", "10m/s", &["0.3mm", "0.4mm"], &[1, 2, 3]),
    );
    let (a, b) = (d.join("a"), d.join("b"));
    let files = |dir: &Path| {
        ["study.json", "cases.jsonl", "slurm.sbatch"].map(|f| std::fs::read(dir.join(f)).unwrap())
    };
    for out in [&a, &b] {
        let o = plan(&s, out);
        assert!(o.status.success(), "{}", text(&o));
    }
    let first = files(&a);
    // Re-planning into the same folder: byte-identical files.
    let o = plan(&s, &a);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(files(&a), first);
    // Another folder: the same study copy and cases (slurm.sbatch names its folder).
    assert_eq!(files(&b)[..2], first[..2]);
    let ca = cases(&a);
    assert_eq!(ca.len(), 6);
    // Product order: the seed (last axis) fastest.
    assert_eq!(ca[1]["axes"], json!([["depth", "0.3mm"], ["seed", "2"]]));
    assert_eq!(ca[3]["axes"], json!([["depth", "0.4mm"], ["seed", "1"]]));
    let keys: std::collections::BTreeSet<&str> =
        ca.iter().map(|c| c["key"].as_str().unwrap()).collect();
    assert_eq!(keys.len(), 6, "keys differ between cases");
    let sb = std::fs::read_to_string(a.join("slurm.sbatch")).unwrap();
    assert!(
        sb.contains("#SBATCH --array=0-5\n")
            && sb.contains("--index \"$SLURM_ARRAY_TASK_ID\"")
            && sb.contains(&format!(
                "{}/logs/%A_%a.out",
                a.canonicalize().unwrap().display()
            )),
        "{sb}"
    );
    // Another study into the same folder is refused, nothing overwritten.
    let s2 = write(
        &d,
        "s2.json",
        &study("p", "10m/s", &["0.3mm", "0.5mm"], &[1, 2, 3]),
    );
    let o = plan(&s2, &a);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("another plan"), "{}", text(&o));
    assert_eq!(cases(&a), ca);
    // Keys follow the inputs, not the position or the file's place: depth 0.3 mm keeps its
    // keys in the new study, 0.5 mm gets new ones; the material copied elsewhere keeps them.
    let o = plan(&s2, &d.join("c"));
    assert!(o.status.success(), "{}", text(&o));
    let cc = cases(&d.join("c"));
    assert_eq!(cc[..3], ca[..3]);
    assert!(cc[3..]
        .iter()
        .all(|c| !keys.contains(c["key"].as_str().unwrap())));
    let m = d.join("m.json");
    std::fs::copy(material(), &m).unwrap();
    let mut moved = study("p", "10m/s", &["0.3mm", "0.4mm"], &[1, 2, 3]);
    moved["base"]["flags"]["material"] = json!("m.json"); // relative to the study file
    let s3 = write(&d, "s3.json", &moved);
    let o = plan(&s3, &d.join("e"));
    assert!(o.status.success(), "{}", text(&o));
    let ce = cases(&d.join("e"));
    assert!(ca.iter().zip(&ce).all(|(x, y)| x["key"] == y["key"]));
    assert!(ce[0]["argv"].to_string().contains(&m.display().to_string()));
    // The shipped example plans.
    let ex = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/studies/cutting-demo.json"
    );
    let o = plan(ex, &d.join("ex"));
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(cases(&d.join("ex")).len(), 4);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn kill_9_then_rerun_gives_the_uninterrupted_table() {
    let d = tmp("kill");
    // 3 m/s: ~200,000 steps a case, about 2 s; 20 checkpoints over each.
    let s = write(&d, "s.json", &study("k", "3m/s", &["0.4mm"], &[1, 2]));
    let (reference, killed) = (d.join("ref"), d.join("killed"));
    for out in [&reference, &killed] {
        assert!(plan(&s, out).status.success());
    }
    let o = dem(&["sweep", "run", reference.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));

    // Kill the runner once case 1 has written a numbered checkpoint.
    let cs = cases(&killed);
    let mut child = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args(["sweep", "run", killed.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let c1 = case_dir(&killed, &cs[1]);
    let t0 = Instant::now();
    let has_ckpt = || {
        std::fs::read_dir(&c1)
            .into_iter()
            .flatten()
            .flatten()
            .any(|e| {
                let n = e.file_name().to_string_lossy().into_owned();
                n.starts_with("ckpt-0") && n.ends_with(".json")
            })
    };
    while !has_ckpt() {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "no checkpoint of case 1"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    // The case's process follows its runner (PR_SET_PDEATHSIG): none is left running in
    // the folder to race the rerun.
    #[cfg(target_os = "linux")]
    {
        let alive = || {
            std::fs::read_dir("/proc").unwrap().flatten().any(|e| {
                std::fs::read(e.path().join("cmdline"))
                    .map(|c| String::from_utf8_lossy(&c).contains(c1.to_str().unwrap()))
                    .unwrap_or(false)
            })
        };
        let t0 = Instant::now();
        while alive() {
            assert!(
                t0.elapsed() < Duration::from_secs(1),
                "case 1 outlived its runner"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }
    assert!(!c1.join("done.json").exists());
    let st = dem(&["sweep", "status", killed.to_str().unwrap()]);
    assert!(
        text(&st).contains("1 done, 0 failed, 0 running, 1 pending"),
        "{}",
        text(&st)
    );

    let o = dem(&["sweep", "run", killed.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(
        (attempts(&killed, &cs[0]), attempts(&killed, &cs[1])),
        (1, 2)
    );
    // Case 1 went on from its checkpoint: two invocations of one run.
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(c1.join("cutting.result.json")).unwrap())
            .unwrap();
    assert_eq!(r["run"]["invocations"], 2, "{}", r["run"]);
    // ... and said so in its second attempt's log (issue 48: only "took over the stale lock").
    let log = std::fs::read_to_string(c1.join("log.txt")).unwrap();
    let second = log.rsplit("=== dem sweep run: attempt").next().unwrap();
    assert!(
        second.contains("resuming the interrupted run of this cut from")
            && second.contains("ckpt-0"),
        "{second}"
    );
    for ext in ["csv", "json"] {
        let a = collect(&reference, &d.join(format!("ref.{ext}")), &["--no-timing"]);
        let b = collect(&killed, &d.join(format!("killed.{ext}")), &["--no-timing"]);
        assert_eq!(a, b, "{ext}");
        assert!(!a.contains("NaN"));
    }
    let a = std::fs::read_to_string(d.join("ref.csv")).unwrap();
    assert_eq!(a.lines().count(), 3, "{a}");
    assert!(a.lines().skip(1).all(|l| l.contains(",done,")), "{a}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_failing_case_is_listed_and_index_runs_one_case() {
    let d = tmp("fail");
    // 5 mm is deeper than the 1.5 mm specimen allows: `dem test cutting` refuses it.
    let s = write(
        &d,
        "s.json",
        &study("f", "10m/s", &["0.3mm", "5mm"], &[1, 2]),
    );
    let dir = d.join("sw");
    assert!(plan(&s, &dir).status.success());
    let cs = cases(&dir);
    // --index 1 runs case 1 alone.
    let o = dem(&["sweep", "run", dir.to_str().unwrap(), "--index", "1"]);
    assert!(o.status.success(), "{}", text(&o));
    let ran: Vec<usize> = cs.iter().map(|c| attempts(&dir, c)).collect();
    assert_eq!(ran, [0, 1, 0, 0]);
    assert!(case_dir(&dir, &cs[1]).join("done.json").exists());
    let o = dem(&["sweep", "run", dir.to_str().unwrap(), "--index", "4"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    // The rest: cases 2 and 3 fail, case 0 is done, case 1 is not run again.
    let o = dem(&["sweep", "run", dir.to_str().unwrap(), "--jobs", "2"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let t = text(&o);
    assert!(t.contains("2 done, 2 failed"), "{t}");
    for i in [2, 3] {
        // The case's own error (`dem test cutting` exits 2 with a message) is listed.
        assert!(
            t.contains(&format!(
                "case {i} (depth=5mm, seed={}): exit code 2: error: ",
                i - 1
            )),
            "{t}"
        );
        let f: Value = serde_json::from_str(
            &std::fs::read_to_string(case_dir(&dir, &cs[i]).join("failed.json")).unwrap(),
        )
        .unwrap();
        assert_eq!(f["exit_code"], 2);
        assert!(f["log_tail"].to_string().contains("error: "), "{f}");
        assert_eq!(f["error"], "exit code 2");
    }
    let ran: Vec<usize> = cs.iter().map(|c| attempts(&dir, c)).collect();
    assert_eq!(ran, [1, 1, 1, 1]);
    // Failed cases are skipped by a rerun, run again with --retry-failed.
    let o = dem(&["sweep", "run", dir.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(attempts(&dir, &cs[2]), 1);
    let o = dem(&["sweep", "run", dir.to_str().unwrap(), "--retry-failed"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(attempts(&dir, &cs[2]), 2);
    let table = collect(&dir, &d.join("t.csv"), &[]);
    let rows: Vec<&str> = table.lines().collect();
    assert_eq!(
        rows[0],
        "index,key,depth,seed,status,main_force.mean,main_force.peak,broken,exit_code,wall_s,cpu_s"
    );
    assert!(rows[3].contains(",5mm,1,failed,,,,2,"), "{}", rows[3]);
    assert!(!table.contains("NaN"));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn two_runs_on_one_folder_never_run_a_case_twice_and_aggregates_are_right() {
    let d = tmp("two");
    let s = write(
        &d,
        "s.json",
        &study("t", "10m/s", &["0.3mm", "0.4mm"], &[1, 2, 3]),
    );
    let dir = d.join("sw");
    assert!(plan(&s, &dir).status.success());
    let spawn = || {
        Command::new(env!("CARGO_BIN_EXE_dem"))
            .args(["sweep", "run", dir.to_str().unwrap()])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (a, b) = (spawn(), spawn());
    let (a, b) = (a.wait_with_output().unwrap(), b.wait_with_output().unwrap());
    assert!(
        a.status.success() && b.status.success(),
        "{}{}",
        text(&a),
        text(&b)
    );
    let cs = cases(&dir);
    for c in &cs {
        assert_eq!(attempts(&dir, c), 1, "case {}", c["index"]);
        let claims = std::fs::read_dir(case_dir(&dir, c))
            .unwrap()
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().starts_with("claim."))
            .count();
        assert_eq!(claims, 1, "case {}", c["index"]);
        assert!(case_dir(&dir, c).join("done.json").exists());
    }
    // The two depths of a seed share its specimen: three kept in `specimens/` (each entry
    // renamed into place whole, even when both processes generated it), no partial entry.
    let kept: Vec<String> = std::fs::read_dir(dir.join("specimens"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(kept.len(), 3, "{kept:?}");
    assert!(kept.iter().all(|k| !k.starts_with('.')), "{kept:?}");
    // Both processes ran some (each prints a line per case it finished).
    let n = |o: &Output| {
        String::from_utf8_lossy(&o.stderr)
            .matches(") done in")
            .count()
    };
    assert_eq!(n(&a) + n(&b), 6, "{}{}", text(&a), text(&b));
    assert!(
        n(&a) > 0 && n(&b) > 0,
        "one process ran all: {}{}",
        text(&a),
        text(&b)
    );

    // Aggregates over seeds by hand, from the per-case values.
    collect(&dir, &d.join("t.json"), &[]);
    let t: Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("t.json")).unwrap()).unwrap();
    assert_eq!(t["seed_axis"], "seed");
    let aggs = t["aggregates"].as_array().unwrap();
    assert_eq!(aggs.len(), 2);
    for (g, depth) in aggs.iter().zip(["0.3mm", "0.4mm"]) {
        assert_eq!(g["group"], json!({ "depth": depth }));
        for out in ["main_force.mean", "main_force.peak", "broken"] {
            let x: Vec<f64> = t["cases"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|c| c["axes"]["depth"] == depth)
                .map(|c| c["outputs"][out].as_f64().unwrap())
                .collect();
            assert_eq!(x.len(), 3);
            let mean = (x[0] + x[1] + x[2]) / 3.0;
            let sd = (((x[0] - mean).powi(2) + (x[1] - mean).powi(2) + (x[2] - mean).powi(2))
                / 2.0)
                .sqrt();
            let mut s = x.clone();
            s.sort_by(f64::total_cmp);
            let a = &g["outputs"][out];
            let close = |v: &Value, w: f64| {
                let v = v.as_f64().unwrap();
                assert!(
                    (v - w).abs() <= 1e-12 * w.abs().max(1e-300),
                    "{out}: {v} vs {w}"
                );
            };
            assert_eq!(a["n"], 3);
            close(&a["mean"], mean);
            close(&a["sd"], sd);
            close(&a["se"], sd / 3f64.sqrt());
            close(&a["median"], s[1]);
        }
    }
    // The sweep's time: sums over all cases and per depth equal the per-case columns; the
    // time some case was running lies between the longest case and the sum of the cases.
    let rows = t["cases"].as_array().unwrap();
    let total = |key: &str, depth: Option<&str>| -> f64 {
        rows.iter()
            .filter(|c| depth.is_none_or(|d| c["axes"]["depth"] == d))
            .map(|c| c[key].as_f64().unwrap())
            .sum()
    };
    let tm = &t["timing"];
    let near = |v: &Value, w: f64| (v.as_f64().unwrap() - w).abs() <= 1e-9 * w.max(1.0);
    assert_eq!(tm["cases"], 6, "{tm}");
    assert!(near(&tm["cpu_s"], total("cpu_s", None)), "{tm}");
    assert!(near(&tm["wall_s"], total("wall_s", None)), "{tm}");
    assert_eq!(
        tm["by_axis"].as_array().unwrap().len(),
        1,
        "no seed sums: {tm}"
    );
    assert_eq!(tm["by_axis"][0]["axis"], "depth");
    for (v, depth) in tm["by_axis"][0]["values"]
        .as_array()
        .unwrap()
        .iter()
        .zip(["0.3mm", "0.4mm"])
    {
        assert_eq!((&v["value"], &v["cases"]), (&json!(depth), &json!(3)));
        assert!(near(&v["cpu_s"], total("cpu_s", Some(depth))), "{v}");
        assert!(near(&v["wall_s"], total("wall_s", Some(depth))), "{v}");
    }
    let longest = rows
        .iter()
        .map(|c| c["wall_s"].as_f64().unwrap())
        .fold(0.0, f64::max);
    let (busy, span) = (
        tm["busy_s"].as_f64().unwrap(),
        tm["span_s"].as_f64().unwrap(),
    );
    // (Case ends are whole seconds: up to 1 s either way.)
    assert!(busy >= longest - 1.0 && busy <= span + 1e-9, "{tm}");
    assert!(busy <= total("wall_s", None) + 1.0, "{tm}");
    let st = Command::new(env!("CARGO_BIN_EXE_dem"))
        .args(["sweep", "status", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(
        text(&st).contains("time of the finished cases (last attempts): 6 cases")
            && text(&st).contains("  depth=0.4mm: 3 cases, CPU "),
        "{}",
        text(&st)
    );
    collect(&dir, &d.join("u.json"), &["--no-timing"]);
    let u = std::fs::read_to_string(d.join("u.json")).unwrap();
    assert!(!u.contains("timing"), "{u}");

    // The CSV form of the same aggregates.
    collect(&dir, &d.join("t.csv"), &[]);
    let agg = std::fs::read_to_string(d.join("t.aggregates.csv")).unwrap();
    assert!(
        agg.starts_with("depth,cases,done,main_force.mean.n,main_force.mean.mean,"),
        "{agg}"
    );
    assert!(
        agg.lines().nth(1).unwrap().starts_with("0.3mm,3,3,3,"),
        "{agg}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_study_files_name_the_file_and_field() {
    let d = tmp("bad");
    let good = study("b", "10m/s", &["0.3mm"], &[1]);
    let cases: Vec<(&str, Value, &[&str])> = vec![
        (
            "unknown-axis.json",
            {
                let mut s = good.clone();
                s["axes"][0]["flag"] = json!("dept");
                s
            },
            &[
                "axes[0].flag",
                "\"dept\" is not a flag of `dem test cutting`",
                "depth",
            ],
        ),
        (
            "empty-range.json",
            {
                let mut s = good.clone();
                s["axes"][0] = json!({"flag": "depth", "range": {"from": 0.2, "to": 0.4, "steps": 0, "unit": "mm"}});
                s
            },
            &["axes[0].range", "empty"],
        ),
        (
            "empty-list.json",
            {
                let mut s = good.clone();
                s["axes"][0]["values"] = json!([]);
                s
            },
            &["axes[0].values", "empty"],
        ),
        (
            "empty-seeds.json",
            {
                let mut s = good.clone();
                s["axes"][1] = json!({"seeds": {"from": 5, "to": 2}});
                s
            },
            &["axes[1].seeds", "empty"],
        ),
        (
            "missing-file.json",
            {
                let mut s = good.clone();
                s["base"]["flags"]["material"] = json!("no-such-material.json");
                s
            },
            &["base.flags.material", "no-such-material.json"],
        ),
        (
            "unknown-field.json",
            {
                let mut s = good.clone();
                s["colect"] = json!([]);
                s
            },
            &["unknown field `colect`"],
        ),
        (
            "reserved.json",
            {
                let mut s = good.clone();
                s["base"]["flags"]["out"] = json!("x");
                s
            },
            &["base.flags.out", "set by dem sweep run"],
        ),
        (
            "bad-seed.json",
            {
                let mut s = good.clone();
                s["axes"][0] = json!({"flag": "snapshots", "values": ["many"]});
                s
            },
            &["axes", "case 0", "--snapshots"],
        ),
    ];
    for (name, s, want) in cases {
        let f = write(&d, name, &s);
        let o = plan(&f, &d.join("out"));
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {t}");
        assert!(t.contains(name), "{name}: {t}");
        for w in want {
            assert!(t.contains(w), "{name}: want {w:?} in {t}");
        }
        assert!(!t.contains("panicked"), "{t}");
    }
    assert!(!d.join("out").join("cases.jsonl").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 48: `sweep run` ran whatever argv an edited cases.jsonl held. Now a line whose command
/// line does not give its key (a value changed by hand, a flag added), or whose named file
/// changed after planning, stops the run before any case starts, naming the line.
#[test]
fn an_edited_plan_or_a_changed_input_is_refused_before_running() {
    let d = tmp("edited");
    let mat = d.join("mat.json");
    std::fs::copy(material(), &mat).unwrap();
    let mut st = study("edited", "10m/s", &["0.3mm"], &[1, 2]);
    st["base"]["flags"]["material"] = json!(mat.display().to_string());
    let s = write(&d, "study.json", &st);
    let dir = d.join("sweep");
    assert!(plan(&s, &dir).status.success());
    let original = std::fs::read_to_string(dir.join("cases.jsonl")).unwrap();
    let run = || dem(&["sweep", "run", dir.to_str().unwrap(), "--jobs", "1"]);
    for (edit, why) in [
        (
            original.replacen("\"0.3mm\"", "\"0.9mm\"", 2),
            "does not give its key",
        ),
        (
            original.replacen("\"--seed\",", "\"--speed\",\"1000m/s\",\"--seed\",", 1),
            "does not give its key",
        ),
        (
            original.replacen("\"--seed\",", "\"--out\",\"/tmp/x\",\"--seed\",", 1),
            "--out is not a flag a study can set",
        ),
    ] {
        assert_ne!(edit, original);
        std::fs::write(dir.join("cases.jsonl"), &edit).unwrap();
        let o = run();
        let t = text(&o);
        assert_eq!(o.status.code(), Some(2), "{t}");
        assert!(
            t.contains("cases.jsonl: line 1: case 0") && t.contains(why),
            "{t}"
        );
        assert!(t.contains("only what the study plans runs"), "{t}");
        assert!(!dir.join("cases").read_dir().unwrap().any(|e| e
            .unwrap()
            .path()
            .join("log.txt")
            .exists()));
    }
    // The plan as written, but its material edited after planning: refused too.
    std::fs::write(dir.join("cases.jsonl"), &original).unwrap();
    let text0 = std::fs::read_to_string(&mat).unwrap();
    std::fs::write(&mat, text0.replacen('{', "{\n", 1)).unwrap();
    let o = run();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(2), "{t}");
    assert!(
        t.contains("line 1") && t.contains("does not give its key"),
        "{t}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// A sweep folder named relative to the working directory: the cases (which start in the
/// sweep folder) still write into its cases/ (they once wrote to sw/sw/cases/… and every case
/// failed with "exit code 0 but no …result.json").
#[test]
fn a_relative_sweep_folder_runs() {
    let d = tmp("relative");
    write(&d, "s.json", &study("r", "10m/s", &["0.3mm"], &[1]));
    let o = dem_in(&d, &["sweep", "plan", "s.json", "--out", "sw"]);
    assert!(o.status.success(), "{}", text(&o));
    let o = dem_in(&d, &["sweep", "run", "sw"]);
    assert!(o.status.success(), "{}", text(&o));
    let cs = cases(&d.join("sw"));
    assert!(case_dir(&d.join("sw"), &cs[0]).join("done.json").exists());
    assert!(!d.join("sw/sw").exists());
    let _ = std::fs::remove_dir_all(&d);
}
