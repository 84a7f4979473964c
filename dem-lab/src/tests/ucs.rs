//! Uniaxial compression test (S4, Tan et al.; Potyondy & Cundall 2004 §3): a w × h specimen
//! between two frictionless platen walls, longer than the specimen, moving toward each other at
//! constant speed v each, with local damping. Measured:
//!
//! - axial stress σ_a = F / (w t), F the mean of the two platen forces (N);
//! - axial strain ε_a = 2 v t_sim / h₀ from the platen gap (the platens start touching the
//!   specimen's extreme discs);
//! - lateral strain ε_l = Δs / s₀ from two position gauges (`outputs.gauges`), bands of
//!   `gauge_width` mean radii at the left and right sides, s their mean-centre spacing;
//! - E = dσ_a/dε_a and ν = dε_l/dε_a, least-squares over the pre-peak band where
//!   σ_a ∈ [10 %, 50 %] of the peak (`band`); UCS = peak σ_a.
//!
//! Quasi-static rule: the platens travel the estimated failure displacement ε_f h/2 (ε_f from
//! [`crate::tests::harness::failure_strain_estimate`], a lower estimate) in 20 P-wave transit times
//! h √(ρ/E_c); the result reports the achieved ratio of the time to peak over h √(ρ/E) with the
//! measured E.

use super::harness::{self, positive, Loading};
use crate::specimen::cache::{Shape, TestSpecimen};
use crate::{analysis, LabError, LabModel};
use dem_core::output::history::Record;
use dem_core::scene::schema::SceneFile;
use serde::{Deserialize, Serialize};

const TEST: &str = "ucs";

/// A uniaxial compression test (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct UcsTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default "ucs").
    pub name: String,
    /// Specimen width w and height h (m); default 10 × 20 mm (2:1 tall).
    pub width: f64,
    pub height: f64,
    /// Platens overhang the specimen by this fraction of w on each side (default 0.25).
    pub platen_overhang: f64,
    /// Pre-peak band of the fits, fractions of the peak stress (default [0.1, 0.5]).
    pub band: [f64; 2],
    /// Width of the lateral gauges in mean radii (default 2).
    pub gauge_width: f64,
    pub loading: Loading,
}

impl Default for UcsTest {
    fn default() -> UcsTest {
        UcsTest {
            name: TEST.into(),
            width: 10e-3,
            height: 20e-3,
            platen_overhang: 0.25,
            band: [0.1, 0.5],
            gauge_width: 2.0,
            loading: Loading::default(),
        }
    }
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UcsReport {
    /// Young's modulus E (Pa), Poisson's ratio ν, uniaxial compressive strength (Pa).
    pub young: f64,
    pub poisson: f64,
    pub ucs: f64,
    /// The band of the fits (fractions of the peak) and the rows in it.
    pub band: [f64; 2],
    pub band_rows: usize,
    /// Axial strain at the peak.
    pub peak_strain: f64,
    /// Platen speed (each, m/s) and axial strain rate 2v/h (1/s).
    pub platen_speed: f64,
    pub strain_rate: f64,
    /// Time to the peak (s), P-wave transit time h √(ρ/E) with the measured E (s), and their
    /// ratio (quasi-static when ≫ 1; the rule aims at ≥ 20).
    pub time_to_peak: f64,
    pub transit_time: f64,
    pub quasi_static_ratio: f64,
}

impl UcsTest {
    /// Checks every value; errors name the field (`ucs.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        positive(TEST, "width", self.width)?;
        positive(TEST, "height", self.height)?;
        positive(TEST, "platen_overhang", self.platen_overhang)?;
        positive(TEST, "gauge_width", self.gauge_width)?;
        harness::prepeak_band(TEST, self.band)?;
        harness::name_and_loading(TEST, &self.name, &self.loading)
    }

    /// The geometry against the particle size: the specimen of `size` = [w, h] (m) made of
    /// discs of mean radius `r_mean` (m) must span [`harness::MIN_DIAMETERS_ACROSS`] mean disc
    /// diameters in width and height, and each lateral gauge band (half-width `gauge_width`
    /// r̄ about a side) must hold a disc (`gauge_width` ≥ 1) and stay in its half of the
    /// specimen (`gauge_width` r̄ ≤ w/2, else the two gauges average the same discs). Errors
    /// name the field (`ucs.width`, `ucs.height`, `ucs.gauge_width`). [`scene`] runs it with
    /// the specimen's extent and mean radius; `dem test ucs` also before generating.
    pub fn check_geometry(&self, size: [f64; 2], r_mean: f64) -> Result<(), LabError> {
        let [w, h] = size;
        harness::diameters_across(
            TEST,
            "width",
            w,
            r_mean,
            "across the width for an interior between the lateral gauges",
        )?;
        harness::diameters_across(
            TEST,
            "height",
            h,
            r_mean,
            "along the loading axis for a strain measured over more than a few contacts",
        )?;
        harness::gauge_holds_a_disc(TEST, self.gauge_width, r_mean)?;
        let g = self.gauge_width * r_mean;
        if g > 0.5 * w {
            return Err(harness::param(
                TEST,
                "gauge_width",
                format!(
                    "{} mean radii: each lateral gauge reaches {:.4} mm into a {:.4} mm wide \
                     specimen, so the two overlap and average the same discs; at most {:.2} \
                     (half the width)",
                    self.gauge_width,
                    g * 1e3,
                    w * 1e3,
                    0.5 * w / r_mean
                ),
            ));
        }
        Ok(())
    }

    /// The specimen shape.
    pub fn shape(&self) -> Shape {
        Shape::Rectangle {
            width: self.width,
            height: self.height,
        }
    }

    /// Platen speed (each platen, m/s): the given one, else the quasi-static rule.
    pub fn platen_speed(&self, model: &LabModel, spec: &TestSpecimen) -> f64 {
        harness::platen_speed(&self.loading, model, spec.size()[1])
    }
}

/// The test's scene (`dem.scene/1`): the specimen file (by its file name: the scene is written
/// beside it), two platens, left/right gauges, local damping, stop after the peak.
pub fn scene(test: &UcsTest, model: &LabModel, spec: &TestSpecimen) -> Result<SceneFile, LabError> {
    test.validate()?;
    test.check_geometry(spec.size(), spec.r_mean)?;
    let [x0, y0, x1, y1] = spec.extent;
    let (w, h) = (x1 - x0, y1 - y0);
    let v = test.platen_speed(model, spec);
    let ov = test.platen_overhang * w;
    let mut s = model.scene_file(&test.name, &spec.file_name(), [0.0, 0.0]);
    s.description = format!(
        "Uniaxial compression (dem test ucs): platens at {v:.4e} m/s each; specimen {:.3} x {:.3} mm",
        w * 1e3,
        h * 1e3
    );
    s.walls = harness::platens(x0 - ov, x1 + ov, y0, y1, v);
    let gauges = harness::side_gauges(spec.extent, test.gauge_width * spec.r_mean);
    let m = &model.micro;
    // Arm the stop at 10 % of σ̄_c w t (the start-up transient, stress ρcv = E ε_f/N, is
    // ~2.5 % of σ̄_c).
    let min_load = 0.1 * m.boundary_tensile.min(m.boundary_cohesion) * w * model.thickness;
    let u_fail = harness::platen_failure_travel(model, h);
    test.loading
        .platen_fields(&mut s, v, u_fail, min_load, gauges);
    Ok(s)
}

/// E, ν and UCS from the history of [`scene`].
pub fn analyze(
    t: &Record,
    test: &UcsTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<UcsReport, LabError> {
    let time = &t.time;
    let load = harness::platen_load(t, TEST)?;
    harness::enough_rows(t, TEST)?;
    let [w, h] = spec.size();
    let v = test.platen_speed(model, spec);
    let area = w * model.thickness;
    let stress: Vec<f64> = load.iter().map(|f| f / area).collect();
    let (axial, lateral) = harness::compression_strains(t, TEST, v, h)?;
    let (ip, _) = harness::failure_peak(TEST, &stress, "load", "no stress")?;
    let [lo, hi] = test.band;
    let rows = harness::band_rows(TEST, &stress, test.band, true)?.len();
    let r = analysis::uniaxial_compression(&axial, &lateral, &stress, lo, hi)
        .ok_or_else(|| harness::analysis_error(TEST, "cannot fit the pre-peak band"))?;
    let transit = h * (model.density / r.young).sqrt();
    Ok(UcsReport {
        young: r.young,
        poisson: r.poisson,
        ucs: r.ucs,
        band: test.band,
        band_rows: rows,
        peak_strain: axial[ip],
        platen_speed: v,
        strain_rate: 2.0 * v / h,
        time_to_peak: time[ip],
        transit_time: transit,
        quasi_static_ratio: time[ip] / transit,
    })
}

harness::quasi_static!(UcsTest, UcsReport, UcsOutcome);
