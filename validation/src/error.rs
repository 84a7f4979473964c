//! The errors of the validation crate: [`Error`] for the report's cases and studies,
//! [`StabilityError`] for the stability suite. Each variant says what failed and carries its
//! data (the file, field, run or cell at fault); its `Display` is the message the report, the
//! `validation` binary and the failure records print. A leaf module: it names no other module of
//! the crate (they import it).

use std::path::Path;

/// The result of the crate's fallible functions.
pub type Result<T> = std::result::Result<T, Error>;

/// Errors of the report's cases, studies and their inputs and outputs.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A file or folder could not be read, written, listed or created.
    #[error("{file}: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    /// An I/O error printed without a file name (listing the input outlines, creating the
    /// crush results folder).
    #[error(transparent)]
    BareIo(std::io::Error),
    /// A JSON file could not be parsed as the type expected.
    #[error("{file}: {source}")]
    Json {
        file: String,
        source: serde_json::Error,
    },
    /// A value could not be turned into (or read from) JSON; no file involved.
    #[error(transparent)]
    Serialize(serde_json::Error),
    /// `cases.jsonl` of a `--sweep` folder could not be read.
    #[error("{file}: {source} (--sweep takes a `dem sweep plan` folder)")]
    NotASweep {
        file: String,
        source: std::io::Error,
    },
    /// A line of a JSON-lines file could not be parsed (`line` counts from 1).
    #[error("{file}: line {line}: {source}")]
    JsonLine {
        file: String,
        line: usize,
        source: serde_json::Error,
    },
    /// A line of a sweep's `cases.jsonl` whose key is not a case key (hex digits).
    #[error("{file}: line {line}: key {key:?} is not a case key")]
    BadCaseKey {
        file: String,
        line: usize,
        key: String,
    },
    /// A field that a file must have is absent.
    #[error("{file}: no {field}")]
    Missing { file: String, field: String },
    /// A field of a file has a value that is not allowed.
    #[error("{file}: {field}: {reason}")]
    Field {
        file: String,
        field: String,
        reason: String,
    },
    /// A result file without its `window` (the steady window of a cutting run).
    #[error("window")]
    NoWindow,
    /// A force history that could not be read.
    #[error("{file}: unreadable")]
    Unreadable { file: String },
    /// A run folder whose path has no (UTF-8) last component.
    #[error("{dir}: no folder name")]
    NoFolderName { dir: String },
    /// A run name that is not `<method>-d<a_p>-v<v>-s<seed>`.
    #[error("{name}: not <method>-d<a_p>-v<v>-s<seed>")]
    RunName { name: String },
    /// A file that should be a PNG has no PNG signature and IHDR chunk.
    #[error("{file}: not a PNG file (no PNG signature and IHDR)")]
    NotPng { file: String },
    /// A PNG with an empty width or height.
    #[error("{file}: PNG of {width} x {height} px")]
    PngSize {
        file: String,
        width: u32,
        height: u32,
    },
    /// The crushable column's stress–strain file lacks a column.
    #[error("column.stress_strain.csv: no column {column}")]
    NoColumn { column: String },
    /// A value of the crushable column's stress–strain file that is not a finite number
    /// (`line` counts from 1, the header being line 1).
    #[error("column.stress_strain.csv line {line}: bad number")]
    BadNumber { line: usize },
    /// A plot could not be drawn (plotters' message).
    #[error("plot: {0}")]
    Plot(String),
    /// A lab test (cutting, bending, crushing) or its inputs failed.
    #[error(transparent)]
    Lab(#[from] dem_lab::LabError),
    /// The run layer refused a plan or could not run its cases.
    #[error(transparent)]
    Run(#[from] dem_run::Error),
    /// A specimen could not be generated or saved.
    #[error(transparent)]
    Specimen(#[from] dem_lab::specimen::SpecimenError),
    /// A grain outline could not be read.
    #[error(transparent)]
    Outline(#[from] clumpgen::OutlineError),
    /// A clump template could not be made.
    #[error(transparent)]
    Clump(#[from] clumpgen::ClumpError),
    /// A clump template could not be written.
    #[error(transparent)]
    Template(#[from] clumpgen::template::TemplateError),
    /// The stability suite failed.
    #[error(transparent)]
    Stability(#[from] StabilityError),
    /// The force statistics of a run or cell (named by `what`) failed.
    #[error("{what}: {source}")]
    ForceStats {
        what: String,
        source: dem_lab::analysis::force_stats::ForceStatsError,
    },
    /// A cell of force statistics given no runs.
    #[error("a cell without runs")]
    EmptyCell,
    /// A run with no force samples in its window.
    #[error("{run}: empty window")]
    EmptyWindow { run: String },
    /// No stretch of the peak width (m) fits the common window of a cell's runs.
    #[error("{cell}: no stretch of {width} m fits the common window")]
    NoStretch { cell: String, width: f64 },
    /// No traditional run in the cell the force scale is fitted on.
    #[error("no traditional run at a_p = 1 mm, v = 1 m/s")]
    NoScaleRun,
    /// The paper's table lacks the cell the force scale is fitted on.
    #[error("the paper has no traditional 1 mm, 1 m/s cell")]
    NoPaperCell,
    /// The mean force (N) of the fitting cell is not positive.
    #[error("traditional 1 mm 1 m/s mean {mean} N")]
    BadScaleMean { mean: f64 },
    /// Table 2 given no cutting runs.
    #[error("no cutting runs")]
    NoRuns,
    /// Table 2's runs have different thicknesses.
    #[error("runs with different thicknesses cannot share one fitted constant")]
    MixedThickness,
    /// A run whose peak or mean force is not finite.
    #[error("run {method} a_p {depth_mm} mm v {speed_m_s} m/s seed {seed}: non-finite force")]
    NonFinite {
        method: String,
        depth_mm: f64,
        speed_m_s: f64,
        seed: u64,
    },
    /// No traditional run in any of the paper's cells to fit Table 2's thickness on.
    #[error("no traditional run of the paper's cells to fit the constant on")]
    NoFitRuns,
    /// The traditional mean forces give no positive least-squares thickness (Σ m·p and
    /// Σ m², kN²).
    #[error("traditional mean forces give Σ m·p = {mp}, Σ m² = {mm}: cannot fit the thickness")]
    CannotFit { mp: f64, mm: f64 },
    /// A Table 2 subset (methods, seeds) that selects nothing of the plan.
    #[error("the Table 2 subset selects no method or no seed of the plan")]
    EmptySubset,
    /// Runs of a study not run yet (called with `--finished-only`).
    #[error(
        "not run yet: {} (a call without --finished-only runs them)",
        runs.join(", ")
    )]
    NotRun { runs: Vec<String> },
    /// A finished run that is not one of the plan's jobs.
    #[error("finished run not in the plan")]
    NotInPlan,
    /// The finest run of the convergence sweep (its reference) did not finish.
    #[error("the finest run {run} did not finish")]
    NoFinest { run: String },
    /// The finest run's peak or mean force (N) is not positive.
    #[error("the finest run {run} has peak {peak} N, mean {mean} N: no reference to compare with")]
    NoReference { run: String, peak: f64, mean: f64 },
    /// A report section asked for that does not exist (`known`: the sections there are).
    #[error("unknown section `{name}` (sections: {})", known.join(", "))]
    UnknownSection { name: String, known: Vec<String> },
    /// The report was written without the sections that failed (`failed`: "name: error").
    #[error(
        "report written to {out} without {} section(s): {}",
        failed.len(),
        failed.join("; ")
    )]
    SectionsFailed { out: String, failed: Vec<String> },
    /// The error an earlier failed run recorded (read back as its text).
    #[error("{0}")]
    EarlierFailure(String),
    /// `source` in the context `what` (a variant, grain or specimen).
    #[error("{what}: {source}")]
    In { what: String, source: Box<Error> },
    /// A `--seeds` value that is not an integer (the `force_stats` example).
    #[error("--seeds `{text}`: {source}")]
    SeedArg {
        text: String,
        source: std::num::ParseIntError,
    },
    /// A message of free text (a command-line usage error of an example).
    #[error("{0}")]
    Other(String),
}

impl Error {
    /// `map_err` for I/O on `file`: [`Error::Io`] naming it.
    pub fn io(file: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
        move |source| Error::Io {
            file: file.display().to_string(),
            source,
        }
    }

    /// `map_err` for parsing the JSON of `file`: [`Error::Json`] naming it.
    pub fn json(file: &Path) -> impl FnOnce(serde_json::Error) -> Error + '_ {
        move |source| Error::Json {
            file: file.display().to_string(),
            source,
        }
    }

    /// `e` in the context `what` ([`Error::In`]: "what: e").
    pub fn within(what: impl Into<String>, e: impl Into<Error>) -> Error {
        Error::In {
            what: what.into(),
            source: Box::new(e.into()),
        }
    }
}

/// Errors of the stability suite (`crate::stability`).
#[derive(Debug, thiserror::Error)]
pub enum StabilityError {
    /// A case file could not be written or read.
    #[error("{file}: {source}")]
    Io {
        file: String,
        source: std::io::Error,
    },
    /// A case's scene could not be loaded or built.
    #[error(transparent)]
    Scene(#[from] dem_core::scene::SceneError),
    /// A case could not be set up or run as planned.
    #[error("case {case}: {reason}")]
    Setup { case: String, reason: String },
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The messages are the texts the `String` errors had (the report, the failure records
    /// and the binary print them).
    #[test]
    fn messages_are_the_former_texts() {
        let io = || std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        let cases: Vec<(Error, &str)> = vec![
            (Error::io(Path::new("a/b.json"))(io()), "a/b.json: gone"),
            (Error::BareIo(io()), "gone"),
            (
                Error::NotASweep {
                    file: "s/cases.jsonl".into(),
                    source: io(),
                },
                "s/cases.jsonl: gone (--sweep takes a `dem sweep plan` folder)",
            ),
            (
                Error::BadCaseKey {
                    file: "c".into(),
                    line: 3,
                    key: "x y".into(),
                },
                "c: line 3: key \"x y\" is not a case key",
            ),
            (
                Error::Field {
                    file: "s.json".into(),
                    field: "name".into(),
                    reason: "must be a plain folder name".into(),
                },
                "s.json: name: must be a plain folder name",
            ),
            (
                Error::NotRun {
                    runs: vec!["a".into(), "b".into()],
                },
                "not run yet: a, b (a call without --finished-only runs them)",
            ),
            (
                Error::NoReference {
                    run: "r".into(),
                    peak: 1.5,
                    mean: 0.0,
                },
                "the finest run r has peak 1.5 N, mean 0 N: no reference to compare with",
            ),
            (
                Error::NonFinite {
                    method: "orc".into(),
                    depth_mm: 1.0,
                    speed_m_s: 2.0,
                    seed: 4,
                },
                "run orc a_p 1 mm v 2 m/s seed 4: non-finite force",
            ),
            (
                Error::CannotFit { mp: -1.0, mm: 2.5 },
                "traditional mean forces give Σ m·p = -1, Σ m² = 2.5: cannot fit the thickness",
            ),
            (
                Error::UnknownSection {
                    name: "x".into(),
                    known: vec!["table1".into(), "sweep".into()],
                },
                "unknown section `x` (sections: table1, sweep)",
            ),
            (
                Error::SectionsFailed {
                    out: "report".into(),
                    failed: vec!["a: e1".into(), "b: e2".into()],
                },
                "report written to report without 2 section(s): a: e1; b: e2",
            ),
            (
                Error::within("variant v: test", Error::Plot("bad".into())),
                "variant v: test: plot: bad",
            ),
            (
                Error::BadNumber { line: 2 },
                "column.stress_strain.csv line 2: bad number",
            ),
        ];
        for (e, text) in cases {
            assert_eq!(e.to_string(), text);
        }
    }
}
