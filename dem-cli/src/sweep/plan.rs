//! `dem sweep plan STUDY --out DIR`: the study's cases, each checked against the `dem test
//! <kind>` command line, with its key; writes `DIR/study.json` (the study file's bytes),
//! `DIR/cases.jsonl` and `DIR/slurm.sbatch`.
//!
//! Case order: `product` varies the last axis fastest (case i of axes with n_1 … n_k values
//! takes value ⌊i / (n_{j+1}·…·n_k)⌋ mod n_j of axis j); `zip` takes the i-th value of every
//! axis. Key: hex SHA-256 of the compact JSON `{"flags": {flag: value, …}, "test": kind}`
//! (keys sorted; a file flag's value is `{"sha256": <hex SHA-256 of the file's bytes>}`, so the
//! key follows the file's content, not where it lies; `--out` and `--threads` are not inputs).

use super::case::{Case, CASES_FILE, SBATCH_FILE, STUDY_FILE};
use super::study::{self, canonical_flag, scalar_text, Combine, Parsed, RESERVED};
use clap::Args;
use serde_json::{json, Value};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// `dem sweep plan` flags.
#[derive(Args)]
pub struct PlanArgs {
    /// The study file (JSON, docs/sweep.md).
    pub study: PathBuf,
    /// The sweep folder: study.json, cases.jsonl, slurm.sbatch; cases/ and logs/ below it.
    #[arg(long)]
    pub out: PathBuf,
    /// Slurm: at most this many array tasks at once (`--array=0-N%T`).
    #[arg(long)]
    pub throttle: Option<usize>,
    /// Slurm: CPUs per task, also each case's worker threads.
    #[arg(long, default_value_t = 1, value_parser = crate::parse_threads)]
    pub cpus_per_task: usize,
    /// Slurm: time limit per task (`MM`, `HH:MM:SS`, `D-HH:MM:SS`).
    #[arg(long, default_value = "01:00:00")]
    pub time: String,
    /// Slurm: partition (default: the cluster's).
    #[arg(long)]
    pub partition: Option<String>,
    /// Slurm: memory per task (`2G`; default: the cluster's).
    #[arg(long)]
    pub mem: Option<String>,
}

/// What the test's command line says of one flag.
struct FlagInfo {
    takes_value: bool,
    is_file: bool,
}

/// The `dem test <kind>` flags (long name → info).
fn test_flags(kind: &str) -> Result<(clap::Command, BTreeMap<String, FlagInfo>), String> {
    use clap::Subcommand;
    let test = crate::negative_values(crate::test::TestKind::augment_subcommands(
        clap::Command::new("test"),
    ));
    let sub = test
        .find_subcommand(kind)
        .cloned()
        .ok_or_else(|| format!("`dem test {kind}` does not exist"))?;
    let mut flags = BTreeMap::new();
    for a in sub.get_arguments() {
        if let Some(long) = a.get_long() {
            flags.insert(
                long.to_string(),
                FlagInfo {
                    takes_value: a.get_action().takes_values(),
                    is_file: a.get_value_parser().type_id() == std::any::TypeId::of::<PathBuf>(),
                },
            );
        }
    }
    Ok((sub, flags))
}

/// A flag value resolved: command-line text (`None`: a switch left off) and key value.
#[derive(Clone)]
struct Resolved {
    arg: Option<String>,
    key: Value,
}

/// The inputs one axis value gives: its flags with their key values, sorted, as compact JSON
/// (two values with the same identity are one case).
/// Values are compared by what they mean ([`physical`]): `1mm`, `1.0mm`, `0.001m` and
/// `1000um` are one depth.
fn identity(v: &[(String, Resolved)]) -> String {
    let keyed: BTreeMap<&str, Value> = v
        .iter()
        .filter(|(_, r)| r.arg.is_some())
        .map(|(f, r)| {
            let k = match &r.key {
                Value::String(t) => json!(physical_of(f, t)),
                // A bare number given as a JSON number: a speed's is m/s too.
                Value::Number(n) if is_speed(f) => json!(physical_of(f, &n.to_string())),
                k => k.clone(),
            };
            (f.as_str(), k)
        })
        .collect();
    serde_json::to_string(&keyed).unwrap_or_default()
}

/// A speed flag (`speed`, `seat-speed`, …): one parser reads them all, a bare number in m/s
/// (`specimen::parse_speed`).
fn is_speed(flag: &str) -> bool {
    flag == "speed" || flag.ends_with("-speed")
}

/// [`physical`] for flag `flag`: a speed flag's bare number is a speed in m/s, as its parser
/// reads it (`--speed 2` and `--speed 2m/s` are one value).
fn physical_of(flag: &str, text: &str) -> String {
    match text.trim().parse::<f64>() {
        Ok(v) if is_speed(flag) && v.is_finite() => format!("{v:.11e} m/s"),
        _ => physical(text),
    }
}

/// A flag value's physical identity for the duplicate check: a number with a length, speed or
/// stress unit as its SI value (12 significant digits) and SI unit, `1.0` and `1` as one number,
/// anything else as written. (Keys stay on the text as given: folders of existing sweeps keep
/// their names.)
fn physical(text: &str) -> String {
    const UNITS: [(&str, f64, &str); 11] = [
        ("mm/s", 1e-3, "m/s"),
        ("um/s", 1e-6, "m/s"),
        ("µm/s", 1e-6, "m/s"),
        ("m/s", 1.0, "m/s"),
        ("mm", 1e-3, "m"),
        ("um", 1e-6, "m"),
        ("µm", 1e-6, "m"),
        ("GPa", 1e9, "Pa"),
        ("MPa", 1e6, "Pa"),
        ("kPa", 1e3, "Pa"),
        ("Pa", 1.0, "Pa"),
    ];
    let t = text.trim();
    let number = |n: &str| n.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    if let Some(v) = number(t) {
        return format!("{v:.11e}");
    }
    for (u, f, si) in UNITS {
        if let Some(v) = t.strip_suffix(u).and_then(number) {
            return format!("{:.11e} {si}", v * f);
        }
    }
    // Metres last: `mm` and `m/s` end in `m`/`s` too.
    match t.strip_suffix('m').and_then(number) {
        Some(v) => format!("{v:.11e} m"),
        None => text.to_string(),
    }
}

/// Checks and resolves one flag value; `field` names it in errors.
fn resolve(
    file: &Path,
    field: &str,
    flag: &str,
    text: &str,
    info: &FlagInfo,
) -> Result<Resolved, String> {
    let here = || format!("{}: field {field}", file.display());
    if !info.takes_value {
        return match text {
            "true" => Ok(Resolved {
                arg: Some(String::new()),
                key: json!(true),
            }),
            "false" => Ok(Resolved {
                arg: None,
                key: Value::Null,
            }),
            _ => Err(format!(
                "{}: --{flag} is a switch: true or false, not {text:?}",
                here()
            )),
        };
    }
    if !info.is_file {
        return Ok(Resolved {
            arg: Some(text.to_string()),
            key: json!(text),
        });
    }
    let path = study::resolve_path(file, text);
    let bytes = clumpgen::io::read_input(&path).map_err(|e| {
        format!(
            "{}: --{flag} file {text:?} ({}): {e}",
            here(),
            path.display()
        )
    })?;
    let abs = path
        .canonicalize()
        .map_err(|e| format!("{}: {}: {e}", here(), path.display()))?;
    Ok(Resolved {
        arg: Some(abs.display().to_string()),
        key: file_key(&bytes),
    })
}

/// A file flag's key value: the SHA-256 of its bytes, so the key follows content, not place.
fn file_key(bytes: &[u8]) -> Value {
    json!({ "sha256": hex(&Sha256::digest(bytes)) })
}

/// A case's key from its test and its flags' key values (module docs).
fn case_key(kind: &str, flags: BTreeMap<String, Value>) -> String {
    let key_json = json!({
        "test": kind,
        "flags": Value::Object(flags.into_iter().collect())
    })
    .to_string();
    hex(&Sha256::digest(key_json.as_bytes()))
}

pub fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The study's cases, checked (flags, files, the test's parser) and keyed.
pub fn cases(file: &Path, p: &Parsed) -> Result<Vec<Case>, String> {
    let kind = p.study.base.test.as_str();
    let (cmd, flags) = test_flags(kind)?;
    let lookup = |flag: &str, field: &str| -> Result<&FlagInfo, String> {
        if RESERVED.contains(&flag) {
            return Err(format!(
                "{}: field {field}: --{flag} is set by dem sweep run for each case",
                file.display()
            ));
        }
        flags.get(flag).ok_or_else(|| {
            let known: Vec<&str> = flags
                .keys()
                .map(String::as_str)
                .filter(|f| !RESERVED.contains(f) && *f != "help")
                .collect();
            format!(
                "{}: field {field}: {flag:?} is not a flag of `dem test {kind}` (its flags: {})",
                file.display(),
                known.join(", ")
            )
        })
    };
    // Base flags, sorted by name.
    let mut base: Vec<(String, Resolved)> = Vec::new();
    for (name, v) in &p.study.base.flags {
        let flag = canonical_flag(name);
        let field = format!("base.flags.{name}");
        let info = lookup(&flag, &field)?;
        let text = scalar_text(v).ok_or_else(|| {
            format!(
                "{}: field {field}: {v} is not a string, number or boolean",
                file.display()
            )
        })?;
        base.push((flag.clone(), resolve(file, &field, &flag, &text, info)?));
    }
    base.sort_by(|a, b| a.0.cmp(&b.0));
    // Axis values, resolved once each: per axis, per value, the flags it gives.
    let mut axes: Vec<Vec<Vec<(String, Resolved)>>> = Vec::new();
    for (i, a) in p.axes.iter().enumerate() {
        let mut vs = Vec::new();
        let mut seen: BTreeMap<String, usize> = BTreeMap::new();
        for j in 0..a.values.len() {
            let mut fs = Vec::new();
            for (flag, v) in a.flags_of(j) {
                let (flag_field, field) = if a.sets.is_empty() {
                    (format!("axes[{i}].flag"), format!("axes[{i}].values[{j}]"))
                } else {
                    let f = format!("axes[{i}].sets[{j}].flags.{flag}");
                    (f.clone(), f)
                };
                let info = lookup(&flag, &flag_field)?;
                let r = resolve(file, &field, &flag, &v, info)?;
                fs.push((flag, r));
            }
            // One physical case is planned once (issue 48 D5): a value whose flags resolve to
            // those of an earlier value of the axis would give cases of one key and folder,
            // run once and counted twice; or, spelt differently (`1mm`, `1.0mm`), two folders
            // of one case, counted twice.
            // (A map of the values seen: a seeds range of 100,000 values stays linear.)
            if let Some(&k) = seen.get(&identity(&fs)) {
                let at = |j: usize| {
                    if a.sets.is_empty() {
                        format!("axes[{i}].values[{j}]")
                    } else {
                        format!("axes[{i}].sets[{j}]")
                    }
                };
                return Err(format!(
                    "{}: field {}: {:?} gives the same inputs as {} ({:?}): the case would run \
                     once and count twice; list each value once",
                    file.display(),
                    at(j),
                    a.values[j],
                    at(k),
                    a.values[k]
                ));
            }
            seen.insert(identity(&fs), j);
            vs.push(fs);
        }
        axes.push(vs);
    }
    let n = match (p.study.combine, p.axes.is_empty()) {
        (_, true) => 1,
        (Combine::Zip, false) => p.axes[0].values.len(),
        (Combine::Product, false) => p.axes.iter().map(|a| a.values.len()).product(),
    };
    let mut out = Vec::with_capacity(n);
    for index in 0..n {
        // Value index of each axis for this case.
        let mut pick = vec![0usize; p.axes.len()];
        let mut rest = index;
        for (j, a) in p.axes.iter().enumerate().rev() {
            pick[j] = match p.study.combine {
                Combine::Zip => index,
                Combine::Product => {
                    let k = rest % a.values.len();
                    rest /= a.values.len();
                    k
                }
            };
        }
        let mut argv = vec!["test".to_string(), kind.to_string()];
        // Sorted by flag whatever the order given (and whatever map serde_json has).
        let mut key_flags: BTreeMap<String, Value> = BTreeMap::new();
        let mut push = |flag: &str, r: &Resolved| {
            if let Some(arg) = &r.arg {
                argv.push(format!("--{flag}"));
                if !arg.is_empty() {
                    argv.push(arg.clone());
                }
                key_flags.insert(flag.to_string(), r.key.clone());
            }
        };
        for (flag, r) in &base {
            push(flag, r);
        }
        let mut case_axes = Vec::new();
        for (j, a) in p.axes.iter().enumerate() {
            for (flag, r) in &axes[j][pick[j]] {
                push(flag, r);
            }
            case_axes.push((a.flag.clone(), a.values[pick[j]].clone()));
        }
        let case = Case {
            index,
            key: case_key(kind, key_flags),
            test: kind.to_string(),
            axes: case_axes,
            argv,
        };
        // The test's own parser: types (a seed must be a whole number) and required flags.
        let mut check = case.argv.clone();
        check.remove(0);
        check.extend(["--out".to_string(), "sweep-check".to_string()]);
        if let Err(e) = cmd.clone().try_get_matches_from(&check) {
            let msg = e.to_string();
            let first = msg.lines().next().unwrap_or_default();
            let field = if p.axes.is_empty() {
                "base.flags"
            } else {
                "axes"
            };
            return Err(format!(
                "{}: field {field}: case {index} ({}): `dem test {kind}` refuses it: {}",
                file.display(),
                case.label(),
                first.trim_start_matches("error: ")
            ));
        }
        out.push(case);
    }
    Ok(out)
}

/// The key `c`'s command line gives, the files it names read again; `Err` names what in the
/// command line is not a planned one. `dem sweep run` runs a case only when this is its key
/// (issue 48: any argv placed in an edited cases.jsonl ran): an edited line, or a file it names
/// that changed since planning, is refused.
pub fn key_of_argv(c: &Case) -> Result<String, String> {
    let (kind, rest) = match c.argv.as_slice() {
        [t, k, rest @ ..] if t == "test" && *k == c.test => (k.as_str(), rest),
        _ => {
            return Err(format!(
                "its command line does not start with `test {}`",
                c.test
            ))
        }
    };
    let (_, flags) = test_flags(kind)?;
    let mut key_flags: BTreeMap<String, Value> = BTreeMap::new();
    let mut it = rest.iter();
    while let Some(tok) = it.next() {
        let flag = tok
            .strip_prefix("--")
            .ok_or_else(|| format!("{tok:?} is not a flag"))?;
        let info = flags
            .get(flag)
            .filter(|_| !RESERVED.contains(&flag))
            .ok_or_else(|| format!("--{flag} is not a flag a study can set"))?;
        let key = if !info.takes_value {
            json!(true)
        } else {
            let v = it.next().ok_or_else(|| format!("--{flag} has no value"))?;
            if info.is_file {
                let bytes = clumpgen::io::read_input(Path::new(v))
                    .map_err(|e| format!("--{flag} file {v}: {e}"))?;
                file_key(&bytes)
            } else {
                json!(v)
            }
        };
        key_flags.insert(flag.to_string(), key);
    }
    Ok(case_key(kind, key_flags))
}

/// The Slurm batch script of `n` cases.
fn sbatch(a: &PlanArgs, name: &str, n: usize, dir: &Path, exe: &Path) -> String {
    let job: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    let throttle = a.throttle.map(|t| format!("%{t}")).unwrap_or_default();
    let q = |p: &Path| shell_quote(&p.display().to_string());
    let mut s = String::new();
    s += "#!/bin/bash\n";
    s += &format!("# dem sweep: {n} cases of the study {name:?}; one array task per case.\n");
    s += "# Submit: sbatch slurm.sbatch (add --wait to block). Re-plan to change the resources.\n";
    s += &format!("#SBATCH --job-name={job}\n");
    s += &format!("#SBATCH --array=0-{}{throttle}\n", n.saturating_sub(1));
    s += "#SBATCH --ntasks=1\n";
    s += &format!("#SBATCH --cpus-per-task={}\n", a.cpus_per_task);
    s += &format!("#SBATCH --time={}\n", a.time);
    if let Some(p) = &a.partition {
        s += &format!("#SBATCH --partition={p}\n");
    }
    if let Some(m) = &a.mem {
        s += &format!("#SBATCH --mem={m}\n");
    }
    s += &format!(
        "#SBATCH --output={}\n",
        dir.join("logs").join("%A_%a.out").display()
    );
    s += &format!(
        "exec {} sweep run {} --index \"$SLURM_ARRAY_TASK_ID\" --threads {}\n",
        q(exe),
        q(dir),
        a.cpus_per_task
    );
    s
}

fn shell_quote(s: &str) -> String {
    if s.chars()
        .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

fn valid_time(t: &str) -> bool {
    !t.is_empty()
        && t.chars()
            .all(|c| c.is_ascii_digit() || c == ':' || c == '-')
        && t.starts_with(|c: char| c.is_ascii_digit())
        && t.ends_with(|c: char| c.is_ascii_digit())
}

pub fn run(a: PlanArgs) -> Result<ExitCode, String> {
    if !valid_time(&a.time) {
        return Err(format!(
            "--time {:?}: a Slurm time limit (MM, HH:MM:SS or D-HH:MM:SS)",
            a.time
        ));
    }
    if a.throttle == Some(0) {
        return Err("--throttle: at least 1".into());
    }
    let (bytes, parsed) = study::read(&a.study)?;
    let cases = cases(&a.study, &parsed)?;
    let mut lines = String::new();
    for c in &cases {
        lines += &serde_json::to_string(c).map_err(|e| e.to_string())?;
        lines.push('\n');
    }
    // Another study in the folder is refused, never overwritten.
    for (name, new) in [(STUDY_FILE, &bytes[..]), (CASES_FILE, lines.as_bytes())] {
        let path = a.out.join(name);
        if let Ok(old) = std::fs::read(&path) {
            if old != new {
                return Err(format!(
                    "{}: the folder holds another plan ({name} differs: another study, or \
                     files it names have changed); plan into a new folder, or remove this one",
                    a.out.display()
                ));
            }
        }
    }
    for sub in ["cases", "logs"] {
        std::fs::create_dir_all(a.out.join(sub))
            .map_err(|e| format!("{}: {e}", a.out.join(sub).display()))?;
    }
    let dir = a
        .out
        .canonicalize()
        .map_err(|e| format!("{}: {e}", a.out.display()))?;
    let exe = std::env::current_exe()
        .and_then(|p| p.canonicalize())
        .map_err(|e| format!("the dem executable's path: {e}"))?;
    let write = |name: &str, b: &[u8]| {
        dem_core::output::write_atomic(&dir.join(name), b).map_err(|e| e.to_string())
    };
    write(STUDY_FILE, &bytes)?;
    write(CASES_FILE, lines.as_bytes())?;
    let script = sbatch(&a, &parsed.study.name, cases.len(), &dir, &exe);
    write(SBATCH_FILE, script.as_bytes())?;
    println!(
        "planned {} cases of `dem test {}` ({}) into {}",
        cases.len(),
        parsed.study.base.test,
        parsed
            .axes
            .iter()
            .map(|x| format!("{} × {}", x.values.len(), x.flag))
            .collect::<Vec<_>>()
            .join(if parsed.study.combine == Combine::Zip {
                " zipped with "
            } else {
                ", "
            }),
        dir.display()
    );
    println!(
        "run here: dem sweep run {0} --jobs N; on Slurm: sbatch {0}/{SBATCH_FILE}",
        dir.display()
    );
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(text: &str) -> Result<Vec<Case>, String> {
        let f = Path::new("s.json");
        cases(f, &study::parse(text.as_bytes(), f)?)
    }

    #[test]
    fn zip_switches_and_keys() {
        let z =
            plan(r#"{"name":"z","base":{"test":"cutting","flags":{"specimen-x":1}}}"#).unwrap_err();
        assert!(
            z.contains("base.flags.specimen-x") && z.contains("not a flag"),
            "{z}"
        );
        let c = plan(
            r#"{"name":"z","base":{"test":"cutting","flags":{"r_min":"0.1mm","r-max":"0.2mm"}},
                "combine":"zip","axes":[{"flag":"depth","values":["1mm","2mm"]},
                {"flag":"delete-fragments","values":[true,false]}]}"#,
        )
        .unwrap();
        assert_eq!(c.len(), 2);
        let a: Vec<String> = ["test", "cutting", "--r-max", "0.2mm", "--r-min", "0.1mm"]
            .map(String::from)
            .to_vec();
        let mut a0 = a.clone();
        a0.extend(["--depth", "1mm", "--delete-fragments"].map(String::from));
        let mut a1 = a.clone();
        a1.extend(["--depth", "2mm"].map(String::from));
        assert_eq!((c[0].argv.clone(), c[1].argv.clone()), (a0, a1));
        assert_eq!(c[1].axes[1], ("delete-fragments".into(), "false".into()));
        // The key is the inputs': the same flags given in another order or spelling agree.
        let d = plan(
            r#"{"name":"other","base":{"test":"cutting","flags":{"r-max":"0.2mm"}},
                "axes":[{"flag":"r-min","values":["0.1mm"]},{"flag":"depth","values":["2mm"]}]}"#,
        )
        .unwrap();
        assert_eq!(d[0].key, c[1].key);
        assert_ne!(c[0].key, c[1].key);
        let e = plan(
            r#"{"name":"z","base":{"test":"cutting"},"axes":[{"flag":"delete-fragments","values":["yes"]}]}"#,
        )
        .unwrap_err();
        assert!(
            e.contains("axes[0].values[0]") && e.contains("switch"),
            "{e}"
        );
    }

    #[test]
    fn sets_axes_give_several_flags_per_value() {
        let c = plan(
            r#"{"name":"s","base":{"test":"cutting","flags":{"r-min":"0.1mm","r-max":"0.2mm"}},
                "axes":[{"name":"damping","sets":[
                    {"name":"local","flags":{"local-damping":0.7}},
                    {"name":"viscous","flags":{"local_damping":0,"contact-damping":0.2}},
                    {"name":"none"}]},
                  {"flag":"depth","values":["1mm","2mm"]}]}"#,
        )
        .unwrap();
        assert_eq!(c.len(), 6);
        assert_eq!(
            c[2].axes,
            vec![
                ("damping".to_string(), "viscous".to_string()),
                ("depth".to_string(), "1mm".to_string())
            ]
        );
        let tail: Vec<&str> = c[2].argv[6..].iter().map(String::as_str).collect();
        assert_eq!(
            tail,
            [
                "--contact-damping",
                "0.2",
                "--local-damping",
                "0",
                "--depth",
                "1mm"
            ]
        );
        assert_eq!(c[4].argv[6..], ["--depth", "1mm"].map(String::from));
        // The key is the flags': a set giving the base's flags is the same case.
        let d = plan(
            r#"{"name":"t","base":{"test":"cutting","flags":{"r-min":"0.1mm","r-max":"0.2mm",
                "depth":"1mm"}},"axes":[{"name":"x","sets":[{"name":"a","flags":{
                "contact-damping":0.2,"local-damping":0}}]}]}"#,
        )
        .unwrap();
        assert_eq!(d[0].key, c[2].key);
        let bad = |axes: &str, want: &[&str]| {
            let e = plan(&format!(
                r#"{{"name":"s","base":{{"test":"cutting","flags":{{"depth":"1mm"}}}},"axes":{axes}}}"#
            ))
            .unwrap_err();
            for w in want {
                assert!(e.contains(w), "{axes}: {e}");
            }
        };
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"depth":"2mm"}}]}]"#,
            &["axes[0].sets[0].flags.depth", "base.flags"],
        );
        bad(
            r#"[{"flag":"speed","values":[1]},{"name":"d","sets":[{"name":"a","flags":{"speed":2}}]}]"#,
            &["axes[1].sets[0].flags.speed", "axes[0]"],
        );
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"tool-friction":0.1}}]},
                {"name":"e","sets":[{"name":"b","flags":{"tool-friction":0.2}}]}]"#,
            &["axes[0].sets[0].flags.tool-friction", "axes[1]"],
        );
        bad(
            r#"[{"flag":"d","sets":[{"name":"a"}]}]"#,
            &["axes[0].flag", "name"],
        );
        bad(r#"[{"sets":[{"name":"a"}]}]"#, &["axes[0].name", "missing"]);
        bad(r#"[{"name":"d","sets":[]}]"#, &["axes[0].sets", "empty"]);
        bad(
            r#"[{"name":"d","sets":[{"name":"a"},{"name":"a"}]}]"#,
            &["axes[0].sets[1].name", "twice"],
        );
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"speeed":2}}]}]"#,
            &["axes[0].sets[0].flags.speeed", "not a flag"],
        );
        bad(
            r#"[{"name":"d","sets":[{"name":"a","flags":{"speed":[2]}}]}]"#,
            &["axes[0].sets[0].flags.speed", "not a string"],
        );
        bad(
            r#"[{"name":"d","values":[1]}]"#,
            &["axes[0].name", "only a sets axis"],
        );
    }

    /// Issue 48 D5: a value listed twice in an axis (seeds, values, or sets giving the same
    /// flags) is refused, naming both places, instead of planning two cases of one key.
    #[test]
    fn a_value_listed_twice_is_refused() {
        let base = r#"{"name":"d","base":{"test":"cutting","flags":{"r-min":"0.1mm"}},"axes":"#;
        let e = plan(&format!(r#"{base}[{{"seeds":[1,1,2]}}]}}"#)).unwrap_err();
        assert!(
            e.contains("axes[0].values[1]") && e.contains("axes[0].values[0]"),
            "{e}"
        );
        assert!(e.contains("count twice"), "{e}");
        let e = plan(&format!(
            r#"{base}[{{"flag":"depth","values":["1mm","2mm","1mm"]}}]}}"#
        ))
        .unwrap_err();
        assert!(
            e.contains("axes[0].values[2]") && e.contains("axes[0].values[0]"),
            "{e}"
        );
        let e = plan(&format!(
            r#"{base}[{{"flag":"depth","values":["1mm"]}},{{"name":"damping","sets":[
                {{"name":"a","flags":{{"local-damping":0.7}}}},
                {{"name":"b","flags":{{"local-damping":0.7}}}}]}}]}}"#
        ))
        .unwrap_err();
        assert!(
            e.contains("axes[1].sets[1]") && e.contains("axes[1].sets[0]"),
            "{e}"
        );
        // One depth spelt four ways is one value; a speed in two units likewise.
        for (flag, spellings) in [
            ("depth", ["1mm", "1.0mm", "0.001m", "1000um"]),
            ("speed", ["2m/s", "2000mm/s", "2.0m/s", "2e3mm/s"]),
            // A bare speed is m/s (one parser for every speed flag).
            ("speed", ["2", "2m/s", "2000mm/s", "2.0"]),
        ] {
            for k in 1..spellings.len() {
                let e = plan(&format!(
                    r#"{base}[{{"flag":"{flag}","values":["{}","{}"]}}]}}"#,
                    spellings[0], spellings[k]
                ))
                .unwrap_err();
                assert!(
                    e.contains("axes[0].values[1]") && e.contains("count twice"),
                    "{e}"
                );
            }
        }
        // Distinct values plan as before.
        let ok = plan(&format!(r#"{base}[{{"seeds":[1,2,3]}}]}}"#)).unwrap();
        assert_eq!(ok.len(), 3);
        let ok = plan(&format!(
            r#"{base}[{{"flag":"depth","values":["1mm","1.5mm","1m"]}}]}}"#
        ))
        .unwrap();
        assert_eq!(ok.len(), 3);
    }
}
