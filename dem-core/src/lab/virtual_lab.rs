//! The virtual laboratory the calibration drives ([`super::calibrate::Lab`]): the UCS, bending
//! and Brazilian tests on specimens generated once from the user's specimen parameters (the
//! geometry does not change while micro-parameters are searched), each run writing its scene,
//! outputs and result beside its specimen.

use super::analysis::UcsResult;
use super::bending::{self, BendingTest};
use super::brazilian::{self, BrazilianTest};
use super::calibrate::Lab;
use super::specimens::{prepare, Shape, TestSpecimen};
use super::ucs::{self, UcsTest};
use super::{LabError, LabModel};
use crate::specimen::SpecimenParams;
use std::path::Path;

/// The three tests and their specimens.
pub struct VirtualLab {
    pub ucs: UcsTest,
    pub bending: BendingTest,
    pub brazilian: BrazilianTest,
    pub ucs_specimen: TestSpecimen,
    pub bending_specimen: TestSpecimen,
    pub brazilian_specimen: TestSpecimen,
    /// Runs made so far.
    pub runs: usize,
    /// Wall time of the runs (s).
    pub wall_time_s: f64,
}

impl VirtualLab {
    /// Prepares (generates or reuses) the three specimens of `base` in `dir`:
    /// `ucs-specimen.json` (the UCS test's width × height), `bending-specimen.json` (length ×
    /// height) and `brazilian-specimen.json` (a disc of the test's diameter). `progress` gets
    /// a line per specimen.
    pub fn prepare(
        base: &SpecimenParams,
        dir: &Path,
        ucs: UcsTest,
        bending: BendingTest,
        brazilian: BrazilianTest,
        progress: &mut dyn FnMut(&str),
    ) -> Result<VirtualLab, LabError> {
        let mut one = |name: &str, shape: Shape| -> Result<TestSpecimen, LabError> {
            let file = dir.join(format!("{name}-specimen.json"));
            progress(&format!("{name} specimen: {}", file.display()));
            let s = prepare(base, shape, &file, &mut |_| {})?;
            progress(&format!(
                "{name} specimen: {} discs, {} bonds{}",
                s.discs,
                s.bonds,
                if s.reused { " (reused)" } else { "" }
            ));
            Ok(s)
        };
        let ucs_specimen = one(
            "ucs",
            Shape::Rectangle {
                width: ucs.width,
                height: ucs.height,
            },
        )?;
        let bending_specimen = one(
            "bending",
            Shape::Rectangle {
                width: bending.length,
                height: bending.height,
            },
        )?;
        let brazilian_specimen = one(
            "brazilian",
            Shape::Disc {
                diameter: brazilian.diameter,
            },
        )?;
        Ok(VirtualLab {
            ucs,
            bending,
            brazilian,
            ucs_specimen,
            bending_specimen,
            brazilian_specimen,
            runs: 0,
            wall_time_s: 0.0,
        })
    }
}

impl Lab for VirtualLab {
    fn ucs(&mut self, model: &LabModel) -> Result<UcsResult, LabError> {
        let o = ucs::run(&self.ucs, model, &self.ucs_specimen, &mut |_, _| {})?;
        self.runs += 1;
        self.wall_time_s += o.run.wall_time_s;
        Ok(UcsResult {
            young: o.result.young,
            poisson: o.result.poisson,
            ucs: o.result.ucs,
        })
    }

    fn bending(&mut self, model: &LabModel) -> Result<f64, LabError> {
        let o = bending::run(&self.bending, model, &self.bending_specimen, &mut |_, _| {})?;
        self.runs += 1;
        self.wall_time_s += o.run.wall_time_s;
        Ok(o.result.flexural_strength)
    }

    fn brazilian(&mut self, model: &LabModel) -> Result<f64, LabError> {
        let o = brazilian::run(
            &self.brazilian,
            model,
            &self.brazilian_specimen,
            &mut |_, _| {},
        )?;
        self.runs += 1;
        self.wall_time_s += o.run.wall_time_s;
        Ok(o.result.tensile_strength)
    }
}
