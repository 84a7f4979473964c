//! The planner (`dem sweep plan STUDY --out DIR`): the study's cases, each checked against the
//! `dem test <kind>` command line ([`TestCommands`], which the CLI gives), with its key;
//! [`write()`] writes `DIR/study.json` (the study file's bytes), `DIR/cases.jsonl` and
//! `DIR/slurm.sbatch`.
//!
//! Case order: `product` varies the last axis fastest (case i of axes with n_1 … n_k values
//! takes value ⌊i / (n_{j+1}·…·n_k)⌋ mod n_j of axis j); `zip` takes the i-th value of every
//! axis. Key: hex SHA-256 of the compact JSON `{"flags": {flag: value, …}, "test": kind}`
//! (keys sorted; a file flag's value is `{"sha256": <hex SHA-256 of the file's bytes>}`, so the
//! key follows the file's content, not where it lies; `--out` and `--threads` are not inputs).
//! In a case's command line a file is named by its absolute path, or, when it lies in the
//! sweep folder (a study planned into its own folder with its inputs, as the report's runs
//! are), relative to the folder, where the runner starts each case.

use crate::case::{Case, CASES_FILE, SBATCH_FILE, STUDY_FILE};
use crate::error::{refuse, Error, Result};
use crate::study::{self, canonical_flag, scalar_text, Combine, Parsed, RESERVED};
use serde_json::{json, Value};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What the test's command line says of one flag.
#[derive(Clone, Copy, Debug)]
pub struct FlagInfo {
    /// It takes a value (`--depth 1mm`); `false`: a switch (`--delete-fragments`).
    pub takes_value: bool,
    /// Its value is a file (keyed by the file's content).
    pub is_file: bool,
}

/// The `dem test <kind>` command lines the planner checks cases against (the CLI's parser).
pub trait TestCommands {
    /// The flags of `dem test <kind>` (long name → info); an error if there is no such test.
    fn flags(&self, kind: &str) -> Result<BTreeMap<String, FlagInfo>>;
    /// Whether `dem test <kind>` accepts `args` (the flags after the kind); the error is the
    /// parser's first line (a flag's type, a required flag missing).
    fn check(&self, kind: &str, args: &[String]) -> Result<()>;
}

/// The Slurm resources of the batch script (`dem sweep plan` flags).
#[derive(Clone, Debug)]
pub struct Slurm {
    /// At most this many array tasks at once (`--array=0-N%T`).
    pub throttle: Option<usize>,
    /// CPUs per task, also each case's worker threads.
    pub cpus_per_task: usize,
    /// Time limit per task (`MM`, `HH:MM:SS`, `D-HH:MM:SS`).
    pub time: String,
    /// Partition (default: the cluster's).
    pub partition: Option<String>,
    /// Memory per task (`2G`; default: the cluster's).
    pub mem: Option<String>,
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
fn resolve(file: &Path, field: &str, flag: &str, text: &str, info: &FlagInfo) -> Result<Resolved> {
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
            _ => Err(refuse!(
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
        refuse!(
            "{}: --{flag} file {text:?} ({}): {e}",
            here(),
            path.display()
        )
    })?;
    let abs = path
        .canonicalize()
        .map_err(|e| refuse!("{}: {}: {e}", here(), path.display()))?;
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
pub fn cases(file: &Path, p: &Parsed, tests: &dyn TestCommands) -> Result<Vec<Case>> {
    let kind = p.study.base.test.as_str();
    let flags = tests.flags(kind)?;
    let lookup = |flag: &str, field: &str| -> Result<&FlagInfo> {
        if RESERVED.contains(&flag) {
            return Err(refuse!(
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
            refuse!(
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
            refuse!(
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
                return Err(refuse!(
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
        let mut check = case.argv[2..].to_vec();
        check.extend(["--out".to_string(), "sweep-check".to_string()]);
        if let Err(e) = tests.check(kind, &check) {
            let msg = e.to_string();
            let first = msg.lines().next().unwrap_or_default();
            let field = if p.axes.is_empty() {
                "base.flags"
            } else {
                "axes"
            };
            return Err(refuse!(
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
/// that changed since planning, is refused. A relative file in the command line is one of the
/// sweep folder `sweep` (where the runner starts the case).
pub fn key_of_argv(c: &Case, sweep: &Path, tests: &dyn TestCommands) -> Result<String> {
    let (kind, rest) = match c.argv.as_slice() {
        [t, k, rest @ ..] if t == "test" && *k == c.test => (k.as_str(), rest),
        _ => {
            return Err(refuse!(
                "its command line does not start with `test {}`",
                c.test
            ))
        }
    };
    let flags = tests.flags(kind)?;
    let mut key_flags: BTreeMap<String, Value> = BTreeMap::new();
    let mut it = rest.iter();
    while let Some(tok) = it.next() {
        let flag = tok
            .strip_prefix("--")
            .ok_or_else(|| refuse!("{tok:?} is not a flag"))?;
        let info = flags
            .get(flag)
            .filter(|_| !RESERVED.contains(&flag))
            .ok_or_else(|| refuse!("--{flag} is not a flag a study can set"))?;
        let key = if !info.takes_value {
            json!(true)
        } else {
            let v = it.next().ok_or_else(|| refuse!("--{flag} has no value"))?;
            if info.is_file {
                let bytes = clumpgen::io::read_input(&sweep.join(v))
                    .map_err(|e| refuse!("--{flag} file {v}: {e}"))?;
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
fn sbatch(a: &Slurm, name: &str, n: usize, dir: &Path, exe: &Path) -> String {
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

/// A plan written ([`write()`]): the sweep folder (canonical), the study and its cases.
pub struct Planned {
    pub dir: PathBuf,
    pub study: Parsed,
    pub cases: Vec<Case>,
}

impl Planned {
    /// The axes as `2 × depth, 3 × seed` (`zipped with` for a zip study).
    pub fn axes_line(&self) -> String {
        self.study
            .axes
            .iter()
            .map(|x| format!("{} × {}", x.values.len(), x.flag))
            .collect::<Vec<_>>()
            .join(if self.study.study.combine == Combine::Zip {
                " zipped with "
            } else {
                ", "
            })
    }
}

/// Plans the study file `study` into the folder `out`: its cases, and the Slurm script whose
/// tasks run `exe sweep run`. Another study in the folder is refused, never overwritten; the
/// files are written atomically.
pub fn write(
    study: &Path,
    out: &Path,
    slurm: &Slurm,
    tests: &dyn TestCommands,
    exe: &Path,
) -> Result<Planned> {
    let exe = exe
        .canonicalize()
        .map_err(|e| Error::io(exe, format!("the dem executable's path: {e}")))?;
    write_plan(study, out, slurm, tests, &exe, false)
}

/// Plans the study file `study` into the folder `out`, which is the caller's own (validation's
/// report runs): a plan already there is replaced. Cases whose inputs did not change keep their
/// key, so their folders (and their results) stay theirs; the others are new cases. The Slurm
/// script runs `dem` from the PATH.
pub fn replan(
    study: &Path,
    out: &Path,
    slurm: &Slurm,
    tests: &dyn TestCommands,
) -> Result<Planned> {
    write_plan(study, out, slurm, tests, Path::new("dem"), true)
}

fn write_plan(
    study: &Path,
    out: &Path,
    slurm: &Slurm,
    tests: &dyn TestCommands,
    exe: &Path,
    replace: bool,
) -> Result<Planned> {
    if !valid_time(&slurm.time) {
        return Err(refuse!(
            "--time {:?}: a Slurm time limit (MM, HH:MM:SS or D-HH:MM:SS)",
            slurm.time
        ));
    }
    if slurm.throttle == Some(0) {
        return Err(refuse!("--throttle: at least 1"));
    }
    let (bytes, parsed) = study::read(study)?;
    let mut cases = cases(study, &parsed, tests)?;
    // A file in the folder is named relative to it (the runner starts cases there), so the
    // folder can be moved or committed with its inputs; other files keep their absolute path.
    std::fs::create_dir_all(out).map_err(|e| Error::io(out, e))?;
    let dir = out.canonicalize().map_err(|e| Error::io(out, e))?;
    for c in &mut cases {
        for a in &mut c.argv {
            if let Ok(rel) = Path::new(a.as_str()).strip_prefix(&dir) {
                *a = rel.display().to_string();
            }
        }
    }
    let mut lines = String::new();
    for c in &cases {
        lines += &serde_json::to_string(c).map_err(|e| Error::io(&out.join(CASES_FILE), e))?;
        lines.push('\n');
    }
    // Another study in the folder is refused, never overwritten (unless it is to be replaced).
    for (name, new) in [(STUDY_FILE, &bytes[..]), (CASES_FILE, lines.as_bytes())] {
        if replace {
            break;
        }
        let path = out.join(name);
        if let Ok(old) = std::fs::read(&path) {
            if old != new {
                return Err(refuse!(
                    "{}: the folder holds another plan ({name} differs: another study, or \
                     files it names have changed); plan into a new folder, or remove this one",
                    out.display()
                ));
            }
        }
    }
    for sub in ["cases", "logs"] {
        std::fs::create_dir_all(out.join(sub)).map_err(|e| Error::io(&out.join(sub), e))?;
    }
    let write = |name: &str, b: &[u8]| crate::write_atomic(&dir.join(name), b);
    write(STUDY_FILE, &bytes)?;
    write(CASES_FILE, lines.as_bytes())?;
    let script = sbatch(slurm, &parsed.study.name, cases.len(), &dir, exe);
    write(SBATCH_FILE, script.as_bytes())?;
    Ok(Planned {
        dir,
        study: parsed,
        cases,
    })
}

#[cfg(test)]
mod tests {
    //! The planner with a command line of its own (dem-cli's tests use `dem test`'s).
    use super::*;

    /// `dem test ucs` with `--width` (a value, required), `--strict` (a switch) and `--seed`
    /// (a whole number).
    struct Fake;

    impl TestCommands for Fake {
        fn flags(&self, kind: &str) -> Result<BTreeMap<String, FlagInfo>> {
            if kind != "ucs" {
                return Err(refuse!("`dem test {kind}` does not exist"));
            }
            let v = FlagInfo {
                takes_value: true,
                is_file: false,
            };
            let s = FlagInfo {
                takes_value: false,
                is_file: false,
            };
            Ok([("width", v), ("seed", v), ("strict", s), ("out", v)]
                .map(|(k, f)| (k.to_string(), f))
                .into())
        }

        fn check(&self, _kind: &str, args: &[String]) -> Result<()> {
            if !args.iter().any(|a| a == "--width") {
                return Err(refuse!(
                    "the following required arguments were not provided"
                ));
            }
            match args.iter().position(|a| a == "--seed") {
                Some(i) if args[i + 1].parse::<u64>().is_err() => {
                    Err(refuse!("invalid value '{}' for '--seed'", args[i + 1]))
                }
                _ => Ok(()),
            }
        }
    }

    fn plan(text: &str) -> Result<Vec<Case>> {
        let f = Path::new("s.json");
        cases(f, &study::parse(text.as_bytes(), f)?, &Fake)
    }

    #[test]
    fn cases_argv_keys_and_the_parser_s_word() {
        let c = plan(
            r#"{"name":"u","base":{"test":"ucs","flags":{"width":"2mm","strict":true}},
                "axes":[{"seeds":[1,2]}]}"#,
        )
        .unwrap();
        assert_eq!(c.len(), 2);
        assert_eq!(
            c[1].argv,
            ["test", "ucs", "--strict", "--width", "2mm", "--seed", "2"].map(String::from)
        );
        assert_ne!(c[0].key, c[1].key);
        // The key follows the inputs: the same case planned again has the same key, and its
        // command line gives it back.
        assert_eq!(key_of_argv(&c[1], Path::new("."), &Fake).unwrap(), c[1].key);
        let e = plan(r#"{"name":"u","base":{"test":"ucs","flags":{"seed":1}}}"#).unwrap_err();
        assert_eq!(e.kind(), crate::ErrorKind::Input);
        assert!(
            e.to_string().contains("refuses it: the following required"),
            "{e}"
        );
        let e = plan(r#"{"name":"u","base":{"test":"ucs","flags":{"out":"x","width":"1mm"}}}"#)
            .unwrap_err();
        assert!(
            e.to_string()
                .contains("field base.flags.out: --out is set by"),
            "{e}"
        );
        let e = plan(
            r#"{"name":"u","base":{"test":"ucs","flags":{"width":"1mm"}},
                "axes":[{"flag":"seed","values":["x"]}]}"#,
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("invalid value 'x' for '--seed'"),
            "{e}"
        );
    }
}
