//! Brazilian (indirect tensile) test (S4, Tan et al.; ISRM 1978 suggested method): a disc of
//! diameter D between two flat frictionless platens moving toward each other at constant speed
//! v each, with local damping. The tensile strength is σ_t = 2F/(πDt) from the peak F of the
//! mean platen force ([`crate::analysis::brazilian_strength`]).
//!
//! Quasi-static rule as the compression test ([`crate::tests::ucs`]): each platen travels the
//! estimated failure displacement ε_f D/2 in 20 P-wave transit times D √(ρ/E_c).

use super::harness::{self, positive, Loading};
use crate::specimen::cache::{Shape, TestSpecimen};
use crate::{analysis, LabError, LabModel};
use dem_core::output::history::Record;
use dem_core::scene::schema::SceneFile;
use serde::{Deserialize, Serialize};

const TEST: &str = "brazilian";

/// A Brazilian disc test (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BrazilianTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default
    /// "brazilian").
    pub name: String,
    /// Disc diameter D (m), default 10 mm.
    pub diameter: f64,
    /// Platen length as a fraction of D (default 1.2).
    pub platen_length: f64,
    pub loading: Loading,
}

impl Default for BrazilianTest {
    fn default() -> BrazilianTest {
        BrazilianTest {
            name: TEST.into(),
            diameter: 10e-3,
            platen_length: 1.2,
            loading: Loading::default(),
        }
    }
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BrazilianReport {
    /// Tensile strength σ_t = 2F/(πDt) (Pa), with F the peak load (N) and D the diameter of
    /// the carved specimen's extent (m, its height).
    pub tensile_strength: f64,
    pub peak_load: f64,
    pub diameter: f64,
    /// Platen travel (each) at the peak (m), speed (m/s), time to the peak (s) and its ratio
    /// to the transit time D √(ρ/E_c).
    pub travel_at_peak: f64,
    pub platen_speed: f64,
    pub time_to_peak: f64,
    pub quasi_static_ratio: f64,
}

impl BrazilianTest {
    /// Checks every value; errors name the field (`brazilian.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        for (field, v) in [
            ("diameter", self.diameter),
            ("platen_length", self.platen_length),
        ] {
            positive(TEST, field, v)?;
        }
        harness::name_and_loading(TEST, &self.name, &self.loading)
    }

    /// The geometry against the particle size: the disc of diameter `diameter` (m) made of
    /// discs of mean radius `r_mean` (m) must span [`harness::MIN_DIAMETERS_ACROSS`] mean disc
    /// diameters (error field `brazilian.diameter`). [`scene`] runs it with the carved disc's
    /// height and mean radius; `dem test brazilian` also before generating.
    pub fn check_geometry(&self, diameter: f64, r_mean: f64) -> Result<(), LabError> {
        harness::diameters_across(
            TEST,
            "diameter",
            diameter,
            r_mean,
            "across the disc for a loaded diameter that splits through discs, not along one \
             force chain",
        )
    }

    pub fn shape(&self) -> Shape {
        Shape::Disc {
            diameter: self.diameter,
        }
    }

    /// Platen speed (each, m/s): the given one, else the quasi-static rule.
    pub fn platen_speed(&self, model: &LabModel, spec: &TestSpecimen) -> f64 {
        harness::platen_speed(&self.loading, model, spec.size()[1])
    }
}

/// The test's scene: the carved disc, two platens touching its top and bottom discs.
pub fn scene(
    test: &BrazilianTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<SceneFile, LabError> {
    test.validate()?;
    test.check_geometry(spec.size()[1], spec.r_mean)?;
    let [x0, y0, x1, y1] = spec.extent;
    let d = y1 - y0;
    let xc = 0.5 * (x0 + x1);
    let half = 0.5 * test.platen_length * (x1 - x0);
    let v = test.platen_speed(model, spec);
    let mut s = model.scene_file(&test.name, &spec.file_name(), [0.0, 0.0]);
    s.description = format!(
        "Brazilian disc (dem test brazilian): D = {:.3} mm, platens at {v:.4e} m/s each",
        d * 1e3
    );
    s.walls = harness::platens(xc - half, xc + half, y0, y1, v);
    let m = &model.micro;
    // F at σ_t = σ̄_c would be πDtσ̄_c/2; arm the stop at 10 % of it (the
    // start-up transient, stress ρcv = E ε_f/N, is ~2.5 % of σ̄_c).
    let min_load = 0.1
        * std::f64::consts::FRAC_PI_2
        * d
        * model.thickness
        * m.boundary_tensile.min(m.boundary_cohesion);
    let u_fail = harness::platen_failure_travel(model, d);
    test.loading
        .platen_fields(&mut s, v, u_fail, min_load, vec![]);
    Ok(s)
}

/// σ_t from the history of [`scene`].
pub fn analyze(
    t: &Record,
    test: &BrazilianTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<BrazilianReport, LabError> {
    let d = spec.size()[1];
    let v = test.platen_speed(model, spec);
    let time = &t.time;
    let load = harness::platen_load(t, TEST)?;
    let (ip, f) = harness::failure_peak(TEST, &load, "load", "no load")?;
    Ok(BrazilianReport {
        tensile_strength: analysis::brazilian_strength(f, d, model.thickness),
        peak_load: f,
        diameter: d,
        travel_at_peak: v * time[ip],
        platen_speed: v,
        time_to_peak: time[ip],
        quasi_static_ratio: time[ip] / harness::transit_time(model, d),
    })
}

harness::quasi_static!(BrazilianTest, BrazilianReport, BrazilianOutcome);
