//! `dem sweep` study files against validation's own cutting runs.
//!
//! * Equivalence: every case of `data/studies/table2.sweep.json`,
//!   `data/studies/speed-damping.sweep.json` and `examples/studies/table2-quick.sweep.json`
//!   (validation's `--quick` plan) makes `dem test cutting` (`--dry-run`: resolved,
//!   not run) build the specimen, model and test of validation's job for the same cell (Table
//!   2's plan; the study `data/studies/speed-damping.json`), compared as typed values and as
//!   the JSON of the run key, and every job has its case: results from a cluster are
//!   interchangeable with validation's own.
//! * End to end on a tiny plan (validation's quick specimens, a 1 mm cut; about a second a
//!   run): plan and run a sweep, read it back with validation (`Source::Sweep`) and get the
//!   numbers of validation running the same jobs itself: run records, seed-averaged peaks,
//!   Table 2 cells, removal figures and study rows; cases not done are listed as not run.

use dem_lab::cutting::CuttingTest;
use dem_lab::specimen::{Method, SpecimenParams};
use dem_lab::LabModel;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use validation::cutting_runs::{key_of, key_text, Job, Missing};
use validation::cutting_runs::{outcome, Source};

mod common;
use common::{dem, tmp};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ok(o: &Output) -> String {
    let t = format!(
        "{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.status.success(), "{t}");
    t
}

/// What `cutting.inputs.json` holds.
#[derive(serde::Deserialize)]
struct Inputs {
    specimen: Option<SpecimenParams>,
    model: Option<LabModel>,
    test: CuttingTest,
}

/// Plans `study` into `dir/plan` and resolves every case with `--dry-run`: (axes, inputs).
fn dry_run_cases(study: &Path, dir: &Path) -> Vec<(BTreeMap<String, String>, Inputs)> {
    let plan = dir.join("plan");
    ok(&dem(&[
        "sweep",
        "plan",
        study.to_str().unwrap(),
        "--out",
        plan.to_str().unwrap(),
    ]));
    let lines = std::fs::read_to_string(plan.join("cases.jsonl")).unwrap();
    let mut out = vec![];
    for line in lines.lines() {
        let c: Value = serde_json::from_str(line).unwrap();
        let case_out = dir.join(format!("case-{}", c["index"]));
        let mut args: Vec<String> = c["argv"]
            .as_array()
            .unwrap()
            .iter()
            .map(|a| a.as_str().unwrap().to_string())
            .collect();
        args.extend([
            "--dry-run".into(),
            "--out".into(),
            case_out.display().to_string(),
        ]);
        let o = Command::new(env!("CARGO_BIN_EXE_dem"))
            .args(&args)
            .output()
            .unwrap();
        let printed = ok(&o);
        let text = std::fs::read_to_string(case_out.join("cutting.inputs.json")).unwrap();
        assert!(printed.contains(text.trim()), "--dry-run prints the file");
        let axes = c["axes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| {
                (
                    p[0].as_str().unwrap().to_string(),
                    p[1].as_str().unwrap().to_string(),
                )
            })
            .collect();
        out.push((axes, serde_json::from_str(&text).unwrap()));
    }
    out
}

/// `1mm` → `1` (validation's run names carry a_p in mm and v in m/s).
fn mm(s: &str) -> String {
    s.trim_end_matches("mm").to_string()
}

/// Validation's name of a Table 2 case's run: `orc-d1-v2-s1`.
fn table2_name(a: &BTreeMap<String, String>) -> String {
    format!(
        "{}-d{}-v{}-s{}",
        a["method"],
        mm(&a["depth"]),
        a["speed"],
        a["seed"]
    )
}

/// Every case equals the job of its cell (typed values and key JSON), and every job has a case.
fn check(
    cases: &[(BTreeMap<String, String>, Inputs)],
    jobs: &[Job],
    name: impl Fn(&BTreeMap<String, String>) -> String,
) {
    assert_eq!(cases.len(), jobs.len());
    let mut seen = std::collections::BTreeSet::new();
    for (axes, i) in cases {
        let n = name(axes);
        let job = jobs
            .iter()
            .find(|j| j.name == n)
            .unwrap_or_else(|| panic!("no job {n} for case {axes:?}"));
        let (sp, m) = (i.specimen.as_ref().unwrap(), i.model.as_ref().unwrap());
        assert_eq!(sp, &job.specimen, "{n}: specimen");
        assert_eq!(m, &job.model, "{n}: model");
        assert_eq!(i.test, job.test, "{n}: test");
        assert_eq!(key_text(sp, m, &i.test).unwrap(), key_of(job), "{n}: key");
        assert!(seen.insert(n.clone()), "{n} twice");
    }
    assert_eq!(seen.len(), jobs.len());
}

#[test]
fn table2_and_speed_study_files_run_validations_jobs() {
    let data = root().join("data");
    let dir = tmp("equivalence");
    // Table 2: methods × depths × speeds × seeds 1–10.
    let cases = dry_run_cases(&data.join("studies/table2.sweep.json"), &dir.join("t2"));
    let jobs = validation::table2_section::plan(&data, false)
        .unwrap()
        .jobs();
    assert_eq!(jobs.len(), 120);
    check(&cases, &jobs, table2_name);
    // Few irregular grains for ORC and improved ORC, none for traditional.
    let few = |m: Method| {
        jobs.iter()
            .filter(|j| j.specimen.method == m)
            .all(|j| !j.specimen.grains.is_all())
    };
    assert!(few(Method::Orc) && few(Method::Improved));
    // The quick Table 2 (coarse specimens, a short cut; `validation --quick`).
    let cases = dry_run_cases(
        &root().join("examples/studies/table2-quick.sweep.json"),
        &dir.join("quick"),
    );
    let jobs = validation::table2_section::plan(&data, true)
        .unwrap()
        .jobs();
    assert_eq!(jobs.len(), 12);
    check(&cases, &jobs, table2_name);
    // The speed and damping study: damping sets × methods × speeds × seeds.
    let cases = dry_run_cases(
        &data.join("studies/speed-damping.sweep.json"),
        &dir.join("sd"),
    );
    let spec =
        validation::study::StudySpec::read(&data.join("studies/speed-damping.json")).unwrap();
    let jobs = spec.jobs(&data).unwrap();
    assert_eq!(jobs.len(), 90);
    check(&cases, &jobs, |a| {
        format!(
            "{}-{}-d1-v{}-s{}",
            a["damping"], a["method"], a["speed"], a["seed"]
        )
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// Table 2's test under the model of the committed runs: PFC's local damping in the lab frame.
/// The mass-scaling and two-case studies compare with those runs, so they name `damping-frame
/// lab` (and keep planning them if the cutting default changes; docs/cutting.md, "Damping and
/// the frame of reference").
fn previous_model(t: &CuttingTest) -> CuttingTest {
    CuttingTest {
        damping_frame: dem_core::DampingFrame::Lab,
        ..t.clone()
    }
}

/// The mass-scaled Table 2 studies (`data/studies/table2-mass-scaled.sweep.json`, budget
/// 0.02, and `table2-mass-scaled-b05.sweep.json`, 0.05; seeds 1–5): their ORC and traditional
/// cases are Table 2's own jobs under the previous model (inputs and keys), their improved-ORC
/// cases the same with `mass_scaling` = the budget and nothing else changed.
#[test]
fn mass_scaled_table2_differs_from_table2_only_by_the_improved_budget() {
    for (file, budget) in [
        ("table2-mass-scaled.sweep.json", 0.02),
        ("table2-mass-scaled-b05.sweep.json", 0.05),
    ] {
        mass_scaled_table2(file, budget);
    }
}

fn mass_scaled_table2(file: &str, budget: f64) {
    let data = root().join("data");
    let dir = tmp(&format!("mass-scaled-{budget}"));
    let cases = dry_run_cases(&data.join("studies").join(file), &dir.join("ms"));
    let jobs = validation::table2_section::plan(&data, false)
        .unwrap()
        .jobs();
    assert_eq!(cases.len(), 60);
    let mut seen = std::collections::BTreeSet::new();
    for (a, i) in &cases {
        let n = table2_name(a);
        let job = jobs.iter().find(|j| j.name == n).expect("a Table 2 job");
        let (sp, m) = (i.specimen.as_ref().unwrap(), i.model.as_ref().unwrap());
        assert_eq!(sp, &job.specimen, "{n}: specimen");
        assert_eq!(m, &job.model, "{n}: model");
        let mut want = previous_model(&job.test);
        let key = key_text(&job.specimen, &job.model, &want).unwrap();
        if a["method"] == "improved" {
            want.mass_scaling = budget;
            assert_ne!(key_text(sp, m, &i.test).unwrap(), key, "{n}: key");
        } else {
            assert_eq!(key_text(sp, m, &i.test).unwrap(), key, "{n}: key");
        }
        assert_eq!(i.test, want, "{n}: test");
        assert!(seen.insert(n));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The check seeds of the mass-scaling decision (`table2-mass-scaled-check.sweep.json`, budget
/// 0.02, and `table2-mass-scaled-check-b05.sweep.json`, 0.05): the 20 improved-ORC cases of
/// Table 2's seeds 6–10 with `mass_scaling` = the budget and nothing else changed, so they
/// compare with the committed unscaled runs of the same specimens.
#[test]
fn mass_scaling_check_studies_are_table2_improved_seeds_6_to_10_scaled() {
    for (file, budget) in [
        ("table2-mass-scaled-check.sweep.json", 0.02),
        ("table2-mass-scaled-check-b05.sweep.json", 0.05),
    ] {
        mass_scaling_check_study(file, budget);
    }
}

fn mass_scaling_check_study(file: &str, budget: f64) {
    let data = root().join("data");
    let dir = tmp(&format!("mass-scaled-check-{budget}"));
    let cases = dry_run_cases(&data.join("studies").join(file), &dir.join("ck"));
    let jobs = validation::table2_section::plan(&data, false)
        .unwrap()
        .jobs();
    assert_eq!(cases.len(), 20, "{file}");
    let mut seen = std::collections::BTreeSet::new();
    for (a, i) in &cases {
        let seed: u64 = a["seed"].parse().unwrap();
        assert!((6..=10).contains(&seed), "{file}: seed {seed}");
        let n = format!(
            "improved-d{}-v{}-s{}",
            mm(&a["depth"]),
            a["speed"],
            a["seed"]
        );
        let job = jobs.iter().find(|j| j.name == n).expect("a Table 2 job");
        let (sp, m) = (i.specimen.as_ref().unwrap(), i.model.as_ref().unwrap());
        assert_eq!(sp, &job.specimen, "{file} {n}: specimen");
        assert_eq!(m, &job.model, "{file} {n}: model");
        let mut want = previous_model(&job.test);
        want.mass_scaling = budget;
        assert_eq!(i.test, want, "{file} {n}: test");
        assert!(seen.insert(n));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The study of the N-core measurement (`table2-two-orc-cases.sweep.json`, docs/sweep.md): two
/// of Table 2's own cases (ORC, a_p = 1 mm, 2 m/s, seeds 1 and 2) under the previous model,
/// keys and all.
#[test]
fn two_case_study_is_two_table2_orc_cases() {
    let data = root().join("data");
    let dir = tmp("two-orc");
    let cases = dry_run_cases(
        &data.join("studies/table2-two-orc-cases.sweep.json"),
        &dir.join("two"),
    );
    let jobs = validation::table2_section::plan(&data, false)
        .unwrap()
        .jobs();
    let names: Vec<String> = cases
        .iter()
        .map(|(a, i)| {
            let n = table2_name(a);
            let job = jobs.iter().find(|j| j.name == n).expect("a Table 2 job");
            let (sp, m) = (i.specimen.as_ref().unwrap(), i.model.as_ref().unwrap());
            let want = previous_model(&job.test);
            assert_eq!(i.test, want, "{n}: test");
            assert_eq!(
                key_text(sp, m, &i.test).unwrap(),
                key_text(&job.specimen, &job.model, &want).unwrap(),
                "{n}: key"
            );
            n
        })
        .collect();
    assert_eq!(names, ["orc-d1-v2-s1", "orc-d1-v2-s2"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `(folder, name)` pairs as validation's statistics take them.
fn as_refs(d: &[(PathBuf, String)]) -> Vec<(&Path, &str)> {
    d.iter().map(|(p, n)| (p.as_path(), n.as_str())).collect()
}

/// The record fields that are not timings.
fn numbers(r: &validation::table2::RunRecord) -> Value {
    let mut v = serde_json::to_value(r).unwrap();
    let o = v.as_object_mut().unwrap();
    o.remove("wall_time_s");
    o.remove("cpu_time_s");
    v
}

#[test]
fn a_sweep_folder_gives_validations_own_numbers() {
    let data = root().join("data");
    let dir = tmp("e2e");
    // Validation's quick specimens (10 × 5 mm, radii 0.3–0.5 mm), a 1 mm cut at 2 m/s.
    let mut plan = validation::table2_section::plan(&data, true).unwrap();
    plan.methods = vec![Method::Traditional, Method::Orc];
    plan.depths_mm = vec![1.0];
    plan.speeds_m_s = vec![2.0];
    plan.seeds = vec![1, 2];
    plan.length = 1e-3;
    let jobs = plan.jobs();
    // The same runs as a study: Table 2's test ("local") and an undamped variant.
    let spec: validation::study::StudySpec = serde_json::from_value(json!({
        "name": "tiny", "length_mm": 1, "depths_mm": [1], "speeds_m_s": [2],
        "methods": ["traditional", "orc"], "seeds": [1, 2],
        "variants": [
            {"name": "local", "test": {"local_damping": 0.7, "window_start": 0.5,
                                       "tool_stiffness": 3.0}},
            {"name": "undamped", "test": {"local_damping": 0.0, "window_start": 0.5,
                                          "tool_stiffness": 3.0}}
        ]
    }))
    .unwrap();
    let model = data.join("models/si3n4.model.json");
    let study = json!({
        "name": "tiny",
        "base": {"test": "cutting", "flags": {
            "width": "10mm", "height": "5mm", "r-min": "0.3mm", "r-max": "0.5mm",
            "grain-size": "1.4mm", "template-r-min": "0.15mm",
            "model": model.display().to_string(), "specimen-from-model": true,
            "depth": "1mm", "speed": 2, "length": "1mm", "window-start": 0.5,
            "tool-stiffness": 3
        }},
        "axes": [
            {"name": "damping", "sets": [
                {"name": "local", "flags": {"local-damping": 0.7}},
                {"name": "undamped", "flags": {"local-damping": 0}}
            ]},
            {"flag": "method", "values": ["traditional", "orc"]},
            {"seeds": [1, 2]}
        ],
        "collect": ["/main_force/mean"]
    });
    let file = dir.join("tiny.json");
    std::fs::write(&file, serde_json::to_string_pretty(&study).unwrap()).unwrap();
    let sweep = dir.join("sweep");
    let s = sweep.to_str().unwrap();
    ok(&dem(&["sweep", "plan", file.to_str().unwrap(), "--out", s]));
    let quiet = |_: &str| {};

    // Nothing done: every run is listed as not run.
    let none = outcome(&jobs, &dir, Source::Sweep(&sweep), &quiet).unwrap();
    assert!(none.finished.is_empty() && none.errors.is_empty());
    assert_eq!(none.missing.len(), 4);
    // Case 0 alone (local, traditional, seed 1): one run done, three not.
    ok(&dem(&["sweep", "run", s, "--index", "0"]));
    let one = outcome(&jobs, &dir, Source::Sweep(&sweep), &quiet).unwrap();
    assert_eq!(one.finished.len(), 1, "{:?}", one.errors);
    assert_eq!(one.finished[0].name, "traditional-d1-v2-s1");
    assert_eq!(one.missing.len(), 3);
    ok(&dem(&["sweep", "run", s, "--jobs", "2"]));

    // Table 2's pieces: from the sweep and from validation running the jobs itself.
    let here = validation::cutting_runs::run_plan(&plan, &dir.join("here"), Missing::Run, &quiet);
    let there = outcome(&jobs, &dir, Source::Sweep(&sweep), &quiet).unwrap();
    assert!(
        here.errors.is_empty() && there.errors.is_empty(),
        "{:?} {:?}",
        here.errors,
        there.errors
    );
    assert!(there.missing.is_empty());
    assert_eq!(here.finished.len(), 4);
    let names = |o: &validation::cutting_runs::Outcome| -> Vec<String> {
        o.finished.iter().map(|f| f.name.clone()).collect()
    };
    assert_eq!(names(&here), names(&there));
    for (a, b) in here.finished.iter().zip(&there.finished) {
        assert_eq!(numbers(&a.record), numbers(&b.record), "{}", a.name);
        assert!(a.record.mean_n.is_finite() && a.record.peak_n.is_finite());
        assert!(
            b.record.cpu_time_s.is_some(),
            "the sweep's CPU time is the driver's"
        );
        assert_eq!(a.result.main_force, b.result.main_force);
    }
    for f in &there.finished {
        eprintln!(
            "{}: mean {:.6e} N, peak {:.6e} N, {} discs, {} steps",
            f.name, f.record.mean_n, f.record.peak_n, f.record.discs, f.record.steps
        );
    }
    // Not a comparison of zeros: the tool cut something.
    assert!(
        here.finished
            .iter()
            .filter(|f| f.record.mean_n > 0.0)
            .count()
            >= 2,
        "{:?}",
        here.finished
            .iter()
            .map(|f| (&f.name, f.record.mean_n))
            .collect::<Vec<_>>()
    );
    let dirs = |o: &validation::cutting_runs::Outcome| -> Vec<(PathBuf, String)> {
        o.finished
            .iter()
            .map(|f| (f.dir.clone(), f.name.clone()))
            .collect()
    };
    let (dh, dt) = (dirs(&here), dirs(&there));
    let sa_here = validation::force_statistics::seed_averaged(&as_refs(&dh)).unwrap();
    let sa_there = validation::force_statistics::seed_averaged(&as_refs(&dt)).unwrap();
    assert_eq!(sa_here, sa_there);
    let paper =
        validation::table2::PaperTable2::read(&data.join("reference/ye_xu_2010_table2.json"))
            .unwrap();
    let recs = |o: &validation::cutting_runs::Outcome| -> Vec<_> {
        o.finished.iter().map(|f| f.record.clone()).collect()
    };
    let t_here = validation::table2::assemble_with(&recs(&here), &paper, &sa_here).unwrap();
    let t_there = validation::table2::assemble_with(&recs(&there), &paper, &sa_there).unwrap();
    assert_eq!(t_here.cells.len(), 2);
    assert_eq!(
        serde_json::to_value(&t_here).unwrap(),
        serde_json::to_value(&t_there).unwrap()
    );
    let rm_here = validation::removal_table::cells(&as_refs(&dh)).unwrap();
    let rm_there = validation::removal_table::cells(&as_refs(&dt)).unwrap();
    assert_eq!(
        serde_json::to_value(&rm_here).unwrap(),
        serde_json::to_value(&rm_there).unwrap()
    );

    // The study: rows from the sweep equal validation's own, timings aside.
    let (rows_here, e1) = validation::study::run_on(
        &spec,
        &plan,
        &dir.join("study-here"),
        Source::Here(Missing::Run),
        &quiet,
    )
    .unwrap();
    let (rows_there, e2) = validation::study::run_on(
        &spec,
        &plan,
        &dir.join("study-there"),
        Source::Sweep(&sweep),
        &quiet,
    )
    .unwrap();
    assert!(e1.is_empty() && e2.is_empty(), "{e1:?} {e2:?}");
    assert_eq!(rows_here.len(), 8);
    let strip = |rows: &[validation::study::Row]| -> Vec<Value> {
        rows.iter()
            .map(|r| {
                let mut v = serde_json::to_value(r).unwrap();
                let o = v.as_object_mut().unwrap();
                o.remove("cpu_s");
                o.remove("wall_s");
                v
            })
            .collect()
    };
    assert_eq!(strip(&rows_here), strip(&rows_there));
    let md = std::fs::read_to_string(dir.join("study-there/tiny/study.md")).unwrap();
    assert!(
        md.contains("| undamped | orc |") && !md.contains("Not run yet"),
        "{md}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// One experiment system (issue 49): the report's own runs are the cases of a `dem sweep`
/// folder (`dem test cutting --inputs inputs/<name>.json`); `dem sweep run` runs them as child
/// processes to the same bytes as validation's in-process runner, and validation reads the
/// CLI's runs back as its own.
#[test]
fn the_reports_runs_are_a_sweep_the_cli_runs_to_the_same_bytes() {
    use validation::cutting_runs::run_plan;
    let data = root().join("data");
    let mut p = validation::table2_section::plan(&data, true).unwrap();
    p.methods = vec![Method::Traditional];
    p.depths_mm = vec![1.0];
    p.speeds_m_s = vec![2.0];
    p.seeds = vec![1];
    p.length = 1.0e-3;
    let here = tmp("report-runs-here");
    let o = run_plan(&p, &here, Missing::Run, &|_| {});
    assert!(o.errors.is_empty(), "{:?}", o.errors);
    assert_eq!(o.finished.len(), 1);
    // The same plan, written by validation without running it; its case run by the CLI.
    let there = tmp("report-runs-cli");
    let listed = run_plan(&p, &there, Missing::List, &|_| {});
    assert_eq!(listed.missing.len(), 1, "{listed:?}");
    let run = ok(&dem(&[
        "sweep".as_ref(),
        "run".as_ref(),
        there.as_os_str(),
        "--jobs".as_ref(),
        "1".as_ref(),
    ]));
    assert!(run.contains("1 done, 0 failed"), "{run}");
    let back = run_plan(&p, &there, Missing::List, &|_| {});
    assert!(
        back.errors.is_empty() && back.missing.is_empty(),
        "{back:?}"
    );
    let (a, b) = (&o.finished[0], &back.finished[0]);
    assert_eq!(a.dir.file_name(), b.dir.file_name(), "one key");
    for f in [
        "cutting.inputs.json",
        "cutting.forces.csv",
        "history.csv",
        "breaks.csv",
    ] {
        let read = |d: &Path| std::fs::read(d.join(f)).unwrap();
        assert!(read(&a.dir) == read(&b.dir), "{f} differs");
    }
    assert_eq!(numbers(&a.record), numbers(&b.record));
}
