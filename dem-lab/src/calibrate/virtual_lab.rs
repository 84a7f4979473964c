//! The virtual laboratory the calibration drives ([`crate::calibrate::Lab`]): the UCS, bending
//! and Brazilian tests on specimens generated once from the user's specimen parameters (the
//! geometry does not change while micro-parameters are searched), each run writing its scene,
//! outputs and result beside its specimen.
//!
//! With several seeds every test runs on one specimen per seed and the calibration sees the
//! mean over them (the searches' linearity — E ∝ E_c, strengths ∝ σ̄_c — holds for a mean as
//! for one run); [`VirtualLab::last`] keeps each seed's value of the latest run for the scatter
//! the report states. A bonded packing's strength varies from seed to seed by more than the
//! calibration's tolerance (SiC at R̄ 9.6 µm: σ_f 588 and 351 MPa on seeds 1 and 2 of a
//! 486-disc beam), so one seed calibrates that specimen, not the material.

use crate::analysis::UcsResult;
use crate::calibrate::Lab;
use crate::specimen::cache::{prepare, Shape, TestSpecimen};
use crate::specimen::SpecimenParams;
use crate::tests::bending::BendingTest;
use crate::tests::brazilian::BrazilianTest;
use crate::tests::harness::Outcome;
use crate::tests::ucs::UcsTest;
use crate::{LabError, LabModel};
use std::path::Path;

/// The three tests and their specimens, one per seed.
pub struct VirtualLab {
    /// One test per seed (names `ucs`, `ucs-seed<k>`, …: each run writes beside its specimen).
    pub ucs: Vec<UcsTest>,
    pub bending: Vec<BendingTest>,
    pub brazilian: Vec<BrazilianTest>,
    pub ucs_specimen: Vec<TestSpecimen>,
    pub bending_specimen: Vec<TestSpecimen>,
    pub brazilian_specimen: Vec<TestSpecimen>,
    /// The seeds of each test's specimens (a seed whose specimen failed to generate is
    /// replaced by the next unused one; see [`VirtualLab::prepare`]).
    pub seeds: [Vec<u64>; 3],
    /// Each seed's result of the latest run of each test.
    pub last: LastRuns,
    /// Runs made so far (one per specimen).
    pub runs: usize,
    /// Wall time of the runs (s).
    pub wall_time_s: f64,
}

/// Per-seed results of the latest run of each test, in the order of [`VirtualLab::seeds`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LastRuns {
    pub ucs: Vec<UcsResult>,
    pub bending: Vec<f64>,
    pub brazilian: Vec<f64>,
}

/// The specimen file of `name` for the `k`-th seed: `<name>-specimen.json` for the first,
/// `<name>-specimen-seed<s>.json` for the others, so a one-seed calibration keeps its names.
fn specimen_name(name: &str, k: usize, seed: u64) -> String {
    if k == 0 {
        format!("{name}-specimen.json")
    } else {
        format!("{name}-specimen-seed{seed}.json")
    }
}

/// The test name of the `k`-th seed (`ucs`, `ucs-seed2`, …).
pub fn test_name(name: &str, k: usize, seed: u64) -> String {
    if k == 0 {
        name.to_string()
    } else {
        format!("{name}-seed{seed}")
    }
}

/// Prepares `n` specimens of `shape` from seeds `base.seed`, `base.seed + 1`, …; a seed whose
/// packing fails to generate (e.g. the stress servo does not converge) is reported through
/// `progress` and replaced by the next seed, at most `n` replacements. Returns the specimens
/// and their seeds.
pub fn prepare_seeds(
    base: &SpecimenParams,
    dir: &Path,
    name: &str,
    shape: Shape,
    n: usize,
    progress: &mut dyn FnMut(&str),
) -> Result<(Vec<TestSpecimen>, Vec<u64>), LabError> {
    let (mut specs, mut seeds) = (Vec::new(), Vec::new());
    let mut failures = Vec::new();
    let mut seed = base.seed;
    while specs.len() < n {
        let k = specs.len();
        let file = dir.join(specimen_name(name, k, seed));
        progress(&format!(
            "{name} specimen (seed {seed}): {}",
            file.display()
        ));
        let mut p = base.clone();
        p.seed = seed;
        match prepare(&p, shape, &file, &mut |_| {}) {
            Ok(s) => {
                progress(&format!(
                    "{name} specimen (seed {seed}): {} discs, {} bonds{}",
                    s.discs,
                    s.bonds,
                    if s.reused { " (reused)" } else { "" }
                ));
                specs.push(s);
                seeds.push(seed);
            }
            Err(e) => {
                progress(&format!(
                    "warning: {name} specimen, seed {seed}: {e}; the next seed replaces it"
                ));
                failures.push(format!("seed {seed}: {e}"));
                if failures.len() > n {
                    return Err(LabError::Param {
                        field: format!("{name} specimen"),
                        reason: format!(
                            "{} seeds failed to generate: {}",
                            failures.len(),
                            failures.join("; ")
                        ),
                    });
                }
            }
        }
        seed += 1;
    }
    Ok((specs, seeds))
}

impl VirtualLab {
    /// Prepares (generates or reuses) the three tests' specimens of `base` in `dir`, `seeds`
    /// of each: `ucs-specimen.json` (the UCS test's width × height), `bending-specimen.json`
    /// (length × height) and `brazilian-specimen.json` (a disc of the test's diameter), then
    /// `…-specimen-seed<s>.json` for the further seeds. `progress` gets a line per specimen.
    pub fn prepare(
        base: &SpecimenParams,
        dir: &Path,
        ucs: UcsTest,
        bending: BendingTest,
        brazilian: BrazilianTest,
        seeds: usize,
        progress: &mut dyn FnMut(&str),
    ) -> Result<VirtualLab, LabError> {
        let n = seeds.max(1);
        let rect = |width, height| Shape::Rectangle { width, height };
        let (ucs_specimen, s_ucs) =
            prepare_seeds(base, dir, "ucs", rect(ucs.width, ucs.height), n, progress)?;
        let (bending_specimen, s_bend) = prepare_seeds(
            base,
            dir,
            "bending",
            rect(bending.length, bending.height),
            n,
            progress,
        )?;
        let (brazilian_specimen, s_braz) = prepare_seeds(
            base,
            dir,
            "brazilian",
            Shape::Disc {
                diameter: brazilian.diameter,
            },
            n,
            progress,
        )?;
        let named = |seeds: &[u64], name: &str| -> Vec<String> {
            (seeds.iter().enumerate())
                .map(|(k, &s)| test_name(name, k, s))
                .collect()
        };
        Ok(VirtualLab {
            ucs: (named(&s_ucs, &ucs.name).into_iter())
                .map(|name| UcsTest {
                    name,
                    ..ucs.clone()
                })
                .collect(),
            bending: (named(&s_bend, &bending.name).into_iter())
                .map(|name| BendingTest {
                    name,
                    ..bending.clone()
                })
                .collect(),
            brazilian: (named(&s_braz, &brazilian.name).into_iter())
                .map(|name| BrazilianTest {
                    name,
                    ..brazilian.clone()
                })
                .collect(),
            ucs_specimen,
            bending_specimen,
            brazilian_specimen,
            seeds: [s_ucs, s_bend, s_braz],
            last: LastRuns::default(),
            runs: 0,
            wall_time_s: 0.0,
        })
    }
}

/// The arithmetic mean (the inputs are never empty: at least one seed).
fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// Runs one test on each of its seeds' specimens with `run`, counting the runs and their wall
/// time; the per-seed results in seed order.
fn run_each<T, R>(
    tests: &[T],
    specimens: &[TestSpecimen],
    runs: &mut usize,
    wall_time_s: &mut f64,
    run: impl Fn(&T, &TestSpecimen) -> Result<Outcome<T, R>, LabError>,
) -> Result<Vec<R>, LabError> {
    let mut all = Vec::new();
    for (t, s) in tests.iter().zip(specimens) {
        let o = run(t, s)?;
        *runs += 1;
        *wall_time_s += o.run.wall_time_s;
        all.push(o.result);
    }
    Ok(all)
}

impl Lab for VirtualLab {
    fn ucs(&mut self, model: &LabModel) -> Result<UcsResult, LabError> {
        let all: Vec<UcsResult> = run_each(
            &self.ucs,
            &self.ucs_specimen,
            &mut self.runs,
            &mut self.wall_time_s,
            |t, s| crate::tests::run(t, model, s, &mut |_, _| {}),
        )?
        .into_iter()
        .map(|r| UcsResult {
            young: r.young,
            poisson: r.poisson,
            ucs: r.ucs,
        })
        .collect();
        let m = |f: fn(&UcsResult) -> f64| mean(&all.iter().map(f).collect::<Vec<_>>());
        let r = UcsResult {
            young: m(|r| r.young),
            poisson: m(|r| r.poisson),
            ucs: m(|r| r.ucs),
        };
        self.last.ucs = all;
        Ok(r)
    }

    fn bending(&mut self, model: &LabModel) -> Result<f64, LabError> {
        let all: Vec<f64> = run_each(
            &self.bending,
            &self.bending_specimen,
            &mut self.runs,
            &mut self.wall_time_s,
            |t, s| crate::tests::run(t, model, s, &mut |_, _| {}),
        )?
        .into_iter()
        .map(|r| r.flexural_strength)
        .collect();
        let r = mean(&all);
        self.last.bending = all;
        Ok(r)
    }

    fn brazilian(&mut self, model: &LabModel) -> Result<f64, LabError> {
        let all: Vec<f64> = run_each(
            &self.brazilian,
            &self.brazilian_specimen,
            &mut self.runs,
            &mut self.wall_time_s,
            |t, s| crate::tests::run(t, model, s, &mut |_, _| {}),
        )?
        .into_iter()
        .map(|r| r.tensile_strength)
        .collect();
        let r = mean(&all);
        self.last.brazilian = all;
        Ok(r)
    }
}
