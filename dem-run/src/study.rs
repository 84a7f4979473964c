//! The study file (`docs/sweep.md`): its structure ([`Study`], read with unknown fields
//! refused and errors naming the field) and its checks against the `dem test <kind>` command
//! line (every flag must be one of that test's flags; file flags must name existing files).
//!
//! Range axes: `steps` values `from + (to − from)·i/(steps − 1)`, i = 0 … steps − 1, each
//! rounded to 12 significant digits (so `0.1` steps print as `0.3`, not `0.30000000000000004`).

use crate::error::{Error, Result};
use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::Deserialize;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The lab tests a study can run (`dem test <kind>`).
pub const TESTS: [&str; 4] = ["cutting", "ucs", "brazilian", "bending"];

/// Flags `dem sweep run` sets itself (per case): a study may not give them.
pub const RESERVED: [&str; 2] = ["out", "threads"];

/// A study file (`dem sweep plan`, docs/sweep.md).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Study {
    /// Name (the Slurm job name).
    pub name: String,
    pub base: Base,
    /// Axes; none is one case (the base alone).
    #[serde(default)]
    pub axes: Vec<Axis>,
    /// `product` (every combination, first axis slowest) or `zip` (i-th value of every axis).
    #[serde(default)]
    pub combine: Combine,
    /// Outputs to collect: JSON pointers into `<test>.result.json` (`"/main_force/mean"`), or
    /// `{"name": ..., "pointer": ...}`.
    #[serde(default)]
    pub collect: Vec<CollectSpec>,
}

/// The test every case runs and the flags every case gets.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Base {
    /// `cutting`, `ucs`, `brazilian` or `bending`.
    #[schemars(extend("enum" = ["cutting", "ucs", "brazilian", "bending"]))]
    pub test: String,
    /// Flag (long name without `--`) → value as the command line takes it (`"1mm"`, `2`,
    /// `true` for a switch).
    #[serde(default)]
    #[schemars(schema_with = "flag_map_schema")]
    pub flags: std::collections::BTreeMap<String, Value>,
}

/// How the axes' values make cases.
#[derive(Debug, Default, Deserialize, Clone, Copy, PartialEq, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Combine {
    #[default]
    Product,
    Zip,
}

/// One axis: a flag and its values (a list, a range, or seeds), or named flag sets (`sets`);
/// exactly one of the four.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("oneOf" = [
    {"required": ["values"], "properties": {"values": {"type": "array"}}},
    {"required": ["range"], "properties": {"range": {"type": "object"}}},
    {"required": ["seeds"], "properties": {"seeds": {"type": ["array", "object"]}}},
    {"required": ["sets", "name"], "properties": {"sets": {"type": "array"}}}
]))]
pub struct Axis {
    /// The flag (`depth`); `seed` when `seeds` is given and this is left out. Not with `sets`.
    #[serde(default)]
    pub flag: Option<String>,
    /// A `sets` axis: its name (the column of `dem sweep collect`). Only with `sets`.
    #[serde(default)]
    pub name: Option<String>,
    /// Named flag sets: each value of the axis gives several flags at once (`{"name":
    /// "viscous", "flags": {"local-damping": 0, "contact-damping": 0.2}}`).
    #[serde(default)]
    pub sets: Option<Vec<FlagSet>>,
    /// The flag's values, as the command line takes them (`"0.5mm"`, `2`, `true`).
    #[serde(default)]
    #[schemars(schema_with = "values_schema")]
    pub values: Option<Vec<Value>>,
    /// `steps` values from `from` to `to` inclusive, `unit` appended.
    #[serde(default)]
    pub range: Option<Range>,
    /// Seeds: a list `[1, 2, 3]` or `{"from": 1, "to": 5}`. The aggregates of `dem sweep
    /// collect` are over this axis.
    #[serde(default)]
    #[schemars(schema_with = "seeds_schema")]
    pub seeds: Option<Value>,
}

/// One value of a `sets` axis: a name and the flags it gives (as `base.flags`).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FlagSet {
    /// The value's name in the axis column (`viscous`).
    pub name: String,
    /// Flag → value, as in `base.flags`; may be empty (the test's defaults).
    #[serde(default)]
    #[schemars(schema_with = "flag_map_schema")]
    pub flags: std::collections::BTreeMap<String, Value>,
}

/// A range axis: `steps` values from `from` to `to` inclusive.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Range {
    pub from: f64,
    pub to: f64,
    /// Number of values (at least 1; 1 only when from = to).
    pub steps: usize,
    /// Appended to every value (`"mm"` gives `0.5mm`).
    #[serde(default)]
    pub unit: String,
}

/// An output to collect: a JSON pointer into `<test>.result.json` (its column is the pointer
/// with `/` as `.`), or a named one.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum CollectSpec {
    Pointer(String),
    Named {
        /// Column name.
        name: String,
        /// JSON pointer into `<test>.result.json` (`/main_force/mean`).
        pointer: String,
    },
}

/// A flag value as the command line takes it: a string, number or boolean.
fn scalar_schema() -> serde_json::Value {
    serde_json::json!({"type": ["string", "number", "boolean"]})
}

/// `base.flags`: flag name → scalar value.
fn flag_map_schema(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"type": "object", "additionalProperties": scalar_schema()})
}

/// `axes[].values`: a list of scalars (`null` is the same as leaving it out).
fn values_schema(_: &mut SchemaGenerator) -> Schema {
    json_schema!({"type": ["array", "null"], "items": scalar_schema()})
}

/// `axes[].seeds`: a list of whole numbers ≥ 0 or `{"from": a, "to": b}` (what
/// [`seed_values`] reads).
fn seeds_schema(_: &mut SchemaGenerator) -> Schema {
    let seed = serde_json::json!({"type": "integer", "minimum": 0});
    json_schema!({
        "anyOf": [
            {"type": "array", "items": seed.clone()},
            {
                "type": "object",
                "properties": {"from": seed.clone(), "to": seed},
                "required": ["from", "to"],
                "additionalProperties": false
            },
            {"type": "null"}
        ]
    })
}

/// An output to collect: column name and JSON pointer.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    pub name: String,
    pub pointer: String,
}

/// An axis with its values as command-line strings.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisValues {
    /// Long flag name (`depth`, `r-min`); a `sets` axis: its name.
    pub flag: String,
    /// The values; a `sets` axis: the sets' names.
    pub values: Vec<String>,
    /// The seed axis (aggregated over by `collect`).
    pub seed: bool,
    /// A `sets` axis: per value, its flags (long name, value as text); empty otherwise.
    pub sets: Vec<Vec<(String, String)>>,
}

impl AxisValues {
    /// The flags value `k` gives: `[(flag, value)]`, or a set's flags.
    pub fn flags_of(&self, k: usize) -> Vec<(String, String)> {
        if self.sets.is_empty() {
            vec![(self.flag.clone(), self.values[k].clone())]
        } else {
            self.sets[k].clone()
        }
    }
}

/// A study read and checked for its structure: the axes expanded to values.
#[derive(Debug)]
pub struct Parsed {
    pub study: Study,
    pub axes: Vec<AxisValues>,
    pub outputs: Vec<Output>,
}

impl Parsed {
    /// The flag of the seed axis, if the study has one (at most one: [`parse`] checks).
    pub fn seed_axis(&self) -> Option<String> {
        self.axes.iter().find(|a| a.seed).map(|a| a.flag.clone())
    }
}

/// Reads `path` and checks its structure (fields, test, axes, ranges, collect); the flags are
/// checked by `dem sweep plan` ([`crate::plan`]) against the test's command line.
pub fn read(path: &Path) -> Result<(Vec<u8>, Parsed)> {
    let bytes =
        clumpgen::io::read_input(path).map_err(|e| Error::io(path, format!("cannot read: {e}")))?;
    let parsed = parse(&bytes, path)?;
    Ok((bytes, parsed))
}

/// Parses the bytes of the study file `path` (named in errors).
pub fn parse(bytes: &[u8], path: &Path) -> Result<Parsed> {
    parse_text(bytes, path).map_err(Error::input)
}

fn parse_text(bytes: &[u8], path: &Path) -> Result<Parsed, String> {
    let file = path.display();
    let text = std::str::from_utf8(bytes).map_err(|e| format!("{file}: not UTF-8: {e}"))?;
    let de = &mut serde_json::Deserializer::from_str(text);
    let study: Study = serde_path_to_error::deserialize(de).map_err(|e| {
        if e.inner().is_syntax() || e.inner().is_eof() {
            return format!("{file}: not valid JSON: {}", e.inner());
        }
        let at = e.path().to_string();
        let at = if at == "." { "(top level)".into() } else { at };
        format!("{file}: field {at}: {}", e.inner())
    })?;
    if study.name.trim().is_empty() {
        return Err(format!("{file}: field name: empty"));
    }
    if !TESTS.contains(&study.base.test.as_str()) {
        return Err(format!(
            "{file}: field base.test: {:?} is not one of {}",
            study.base.test,
            TESTS.join(", ")
        ));
    }
    let mut axes = Vec::new();
    for (i, a) in study.axes.iter().enumerate() {
        let field = format!("axes[{i}]");
        axes.push(axis_values(a, &field).map_err(|e| format!("{file}: field {e}"))?);
    }
    if axes.iter().filter(|a| a.seed).count() > 1 {
        return Err(format!("{file}: field axes: more than one seeds axis"));
    }
    for (i, a) in axes.iter().enumerate() {
        let what = if a.sets.is_empty() { "flag" } else { "name" };
        if let Some(j) = axes[..i].iter().position(|b| b.flag == a.flag) {
            return Err(format!(
                "{file}: field axes[{i}].{what}: {:?} is already axes[{j}]",
                a.flag
            ));
        }
        // A set's flags: in no other place (base, a flag axis, another sets axis).
        for (j, set) in a.sets.iter().enumerate() {
            for (f, _) in set {
                let field = format!("{file}: field axes[{i}].sets[{j}].flags.{f}");
                if study.base.flags.keys().any(|k| canonical_flag(k) == *f) {
                    return Err(format!(
                        "{field}: {f:?} is also in base.flags (give it in one place)"
                    ));
                }
                for (k, b) in axes.iter().enumerate() {
                    let clash = if b.sets.is_empty() {
                        b.flag == *f
                    } else {
                        k != i && b.sets.iter().any(|s| s.iter().any(|(g, _)| g == f))
                    };
                    if clash {
                        return Err(format!(
                            "{field}: {f:?} is also given by axes[{k}] (give it in one place)"
                        ));
                    }
                }
            }
        }
        if !a.sets.is_empty() {
            continue;
        }
        if study.base.flags.keys().any(|k| canonical_flag(k) == a.flag) {
            return Err(format!(
                "{file}: field axes[{i}].flag: {:?} is also in base.flags (give it in one place)",
                a.flag
            ));
        }
    }
    if study.combine == Combine::Zip {
        if let Some(a0) = axes.first() {
            for (i, a) in axes.iter().enumerate() {
                if a.values.len() != a0.values.len() {
                    return Err(format!(
                        "{file}: field axes[{i}]: combine \"zip\" needs axes of one length: \
                         axes[0] ({}) has {}, axes[{i}] ({}) has {}",
                        a0.flag,
                        a0.values.len(),
                        a.flag,
                        a.values.len()
                    ));
                }
            }
        }
    }
    let cases = match study.combine {
        Combine::Zip => axes.first().map_or(1, |a| a.values.len()),
        _ => axes
            .iter()
            .fold(1usize, |n, a| n.saturating_mul(a.values.len())),
    };
    if cases > MAX_CASES {
        let sizes: Vec<String> = axes.iter().map(|a| a.values.len().to_string()).collect();
        return Err(format!(
            "{file}: field axes: {} = {}",
            sizes.join(" × "),
            too_many(cases)
        ));
    }
    let mut outputs: Vec<Output> = Vec::new();
    for (i, c) in study.collect.iter().enumerate() {
        let (name, pointer) = match c {
            CollectSpec::Pointer(p) => (p.trim_start_matches('/').replace('/', "."), p.clone()),
            CollectSpec::Named { name, pointer } => (name.clone(), pointer.clone()),
        };
        if !pointer.starts_with('/') {
            return Err(format!(
                "{file}: field collect[{i}]: {pointer:?} is not a JSON pointer (starts with /)"
            ));
        }
        if name.is_empty() || outputs.iter().any(|o| o.name == name) {
            return Err(format!(
                "{file}: field collect[{i}]: name {name:?} is empty or given twice"
            ));
        }
        outputs.push(Output { name, pointer });
    }
    Ok(Parsed {
        study,
        axes,
        outputs,
    })
}

/// `--r_min`, `r_min`, `r-min` → `r-min`.
pub fn canonical_flag(f: &str) -> String {
    f.trim().trim_start_matches("--").replace('_', "-")
}

/// A JSON scalar as the command line writes it (`1`, `0.5`, `"1mm"`); `None` for others.
pub fn scalar_text(v: &Value) -> Option<String> {
    match v {
        Value::String(s) => Some(s.clone()),
        Value::Number(n) => Some(n.to_string()),
        Value::Bool(b) => Some(b.to_string()),
        _ => None,
    }
}

fn axis_values(a: &Axis, field: &str) -> Result<AxisValues, String> {
    let given = [
        a.values.is_some(),
        a.range.is_some(),
        a.seeds.is_some(),
        a.sets.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err(format!(
            "{field}: give exactly one of values, range, seeds, sets"
        ));
    }
    if let Some(sets) = &a.sets {
        return sets_values(a, sets, field);
    }
    if a.name.is_some() {
        return Err(format!(
            "{field}.name: only a sets axis has a name (this axis is named by its flag)"
        ));
    }
    let flag = match (&a.flag, &a.seeds) {
        (Some(f), _) => canonical_flag(f),
        (None, Some(_)) => "seed".to_string(),
        (None, None) => return Err(format!("{field}.flag: missing")),
    };
    if flag.is_empty() {
        return Err(format!("{field}.flag: empty"));
    }
    let values = if let Some(vs) = &a.values {
        if vs.is_empty() {
            return Err(format!("{field}.values: empty list"));
        }
        let mut out = Vec::new();
        for (j, v) in vs.iter().enumerate() {
            out.push(scalar_text(v).ok_or_else(|| {
                format!("{field}.values[{j}]: {v} is not a string, number or boolean")
            })?);
        }
        out
    } else if let Some(r) = &a.range {
        range_values(r).map_err(|e| format!("{field}.range: {e}"))?
    } else {
        seed_values(a.seeds.as_ref().unwrap_or(&Value::Null))
            .map_err(|e| format!("{field}.seeds: {e}"))?
    };
    Ok(AxisValues {
        flag,
        values,
        seed: a.seeds.is_some(),
        sets: Vec::new(),
    })
}

/// A `sets` axis: its name, the sets' names and their flags (canonical long names).
fn sets_values(a: &Axis, sets: &[FlagSet], field: &str) -> Result<AxisValues, String> {
    if a.flag.is_some() {
        return Err(format!(
            "{field}.flag: a sets axis gives its flags in sets[].flags; name it with name"
        ));
    }
    let name = a.name.as_deref().map(str::trim).unwrap_or_default();
    if name.is_empty() {
        return Err(format!(
            "{field}.name: missing or empty (a sets axis needs a name: its column)"
        ));
    }
    if sets.is_empty() {
        return Err(format!("{field}.sets: empty list"));
    }
    let (mut values, mut flags) = (Vec::new(), Vec::new());
    for (j, s) in sets.iter().enumerate() {
        let n = s.name.trim();
        if n.is_empty() || values.iter().any(|v| v == n) {
            return Err(format!(
                "{field}.sets[{j}].name: {:?} is empty or given twice",
                s.name
            ));
        }
        values.push(n.to_string());
        let mut fs = Vec::new();
        for (f, v) in &s.flags {
            let text = scalar_text(v).ok_or_else(|| {
                format!("{field}.sets[{j}].flags.{f}: {v} is not a string, number or boolean")
            })?;
            let flag = canonical_flag(f);
            if flag.is_empty() || fs.iter().any(|(g, _): &(String, String)| *g == flag) {
                return Err(format!("{field}.sets[{j}].flags.{f}: empty or given twice"));
            }
            fs.push((flag, text));
        }
        fs.sort();
        flags.push(fs);
    }
    Ok(AxisValues {
        flag: name.to_string(),
        values,
        seed: false,
        sets: flags,
    })
}

/// The most cases a study may plan (a range's steps, a seed range, the axes' product): a study
/// of more is a typo (a seed range to 10¹¹ asked for 800 GB before this bound). 100,000 cases
/// are ~50 MB of `cases.jsonl` (~0.5 KB per case), 100 × Slurm's default `MaxArraySize`
/// (1001); at a second per case, a day of one core.
pub const MAX_CASES: usize = 100_000;

fn too_many(n: impl std::fmt::Display) -> String {
    format!("{n} values: a study has at most {MAX_CASES} cases (split it into several studies)")
}

fn range_values(r: &Range) -> Result<Vec<String>, String> {
    if !(r.from.is_finite() && r.to.is_finite()) {
        return Err("from and to must be finite".into());
    }
    if r.steps > MAX_CASES {
        return Err(format!("steps {}", too_many(r.steps)));
    }
    match r.steps {
        0 => Err("empty: steps is 0".into()),
        1 if r.from != r.to => Err(format!(
            "steps 1 with from {} ≠ to {} (give steps ≥ 2, or from = to)",
            r.from, r.to
        )),
        1 => Ok(vec![format!("{}{}", round12(r.from), r.unit)]),
        n => Ok((0..n)
            .map(|i| {
                let v = r.from + (r.to - r.from) * i as f64 / (n - 1) as f64;
                format!("{}{}", round12(v), r.unit)
            })
            .collect()),
    }
}

/// Rounded to 12 significant digits, printed shortest.
fn round12(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

fn seed_values(v: &Value) -> Result<Vec<String>, String> {
    let seed = |x: &Value| -> Result<u64, String> {
        x.as_u64()
            .ok_or_else(|| format!("{x} is not a seed (a whole number ≥ 0)"))
    };
    let seeds: Vec<u64> = match v {
        Value::Array(xs) => xs.iter().map(seed).collect::<Result<_, _>>()?,
        Value::Object(m) => {
            if let Some(k) = m.keys().find(|k| *k != "from" && *k != "to") {
                return Err(format!("unknown field `{k}`, expected `from` and `to`"));
            }
            let get = |k: &str| m.get(k).ok_or_else(|| format!("missing field `{k}`"));
            let (from, to) = (seed(get("from")?)?, seed(get("to")?)?);
            if to < from {
                return Err(format!("empty: to {to} < from {from}"));
            }
            if to - from >= MAX_CASES as u64 {
                return Err(format!("from {from} to {to}: {}", too_many(to - from + 1)));
            }
            (from..=to).collect()
        }
        _ => return Err("a list of seeds or {\"from\": a, \"to\": b}".into()),
    };
    if seeds.is_empty() {
        return Err("empty list".into());
    }
    Ok(seeds.iter().map(|s| s.to_string()).collect())
}

/// A path in the study, relative to the study file's folder.
pub fn resolve_path(study_file: &Path, value: &str) -> PathBuf {
    let p = Path::new(value);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        study_file
            .parent()
            .unwrap_or_else(|| Path::new("."))
            .join(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Result<Parsed, String> {
        parse_text(text.as_bytes(), Path::new("s.json"))
    }

    #[test]
    fn ranges_seeds_and_errors() {
        let s = p(r#"{"name":"x","base":{"test":"ucs"},"axes":[
            {"flag":"porosity","range":{"from":0.1,"to":0.3,"steps":3}},
            {"seeds":{"from":3,"to":5}}]}"#)
        .unwrap();
        assert_eq!(s.axes[0].values, ["0.1", "0.2", "0.3"]);
        assert_eq!(s.axes[1].values, ["3", "4", "5"]);
        assert!(s.axes[1].seed && !s.axes[0].seed);
        let e = p(r#"{"name":"x","base":{"test":"ucs"},"axes":[{"flag":"a","range":{"from":1,"to":2,"steps":0}}]}"#)
            .unwrap_err();
        assert!(
            e.contains("s.json") && e.contains("axes[0].range") && e.contains("empty"),
            "{e}"
        );
        let e = p(r#"{"name":"x","base":{"test":"ucs"},"axis":[]}"#).unwrap_err();
        assert!(e.contains("unknown field `axis`"), "{e}");
        let e = p(r#"{"name":"x","base":{"test":"ucs","flag":{}}}"#).unwrap_err();
        assert!(
            e.contains("base") && e.contains("unknown field `flag`"),
            "{e}"
        );
        let e = p(r#"{"name":"x","base":{"test":"milling"}}"#).unwrap_err();
        assert!(e.contains("base.test"), "{e}");
        let e = p(
            r#"{"name":"x","base":{"test":"ucs"},"combine":"zip","axes":[
            {"flag":"a","values":[1,2]},{"flag":"b","values":[1]}]}"#,
        )
        .unwrap_err();
        assert!(e.contains("axes[1]") && e.contains("zip"), "{e}");
    }

    /// A seed range, a range or a product of axes above [`MAX_CASES`] is refused naming the
    /// field (a seed range to 10¹¹ aborted `dem sweep plan` allocating 800 GB).
    #[test]
    fn more_cases_than_the_bound_are_refused() {
        let e = p(
            r#"{"name":"x","base":{"test":"ucs"},"axes":[{"seeds":{"from":0,"to":100000000000}}]}"#,
        )
        .unwrap_err();
        assert!(
            e.contains("axes[0]") && e.contains("at most 100000 cases"),
            "{e}"
        );
        let e = p(r#"{"name":"x","base":{"test":"ucs"},"axes":[{"flag":"a","range":{"from":1,"to":2,"steps":1000000000000}}]}"#)
            .unwrap_err();
        assert!(e.contains("axes[0].range") && e.contains("at most"), "{e}");
        let e = p(r#"{"name":"x","base":{"test":"ucs"},"axes":[
            {"flag":"a","range":{"from":1,"to":2,"steps":1000}},
            {"flag":"b","range":{"from":1,"to":2,"steps":1000}}]}"#)
        .unwrap_err();
        assert!(
            e.contains("field axes: 1000 × 1000 = 1000000 values"),
            "{e}"
        );
        let ok = p(r#"{"name":"x","base":{"test":"ucs"},"axes":[
            {"flag":"a","range":{"from":1,"to":2,"steps":100}},
            {"seeds":{"from":1,"to":1000}}]}"#);
        assert!(ok.is_ok(), "{ok:?}");
    }
}
