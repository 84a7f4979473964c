//! Brazilian (indirect tensile) test (S4, Tan et al.; ISRM 1978 suggested method): a disc of
//! diameter D between two flat frictionless platens moving toward each other at constant speed
//! v each, with local damping. The tensile strength is σ_t = 2F/(πDt) from the peak F of the
//! mean platen force ([`super::analysis::brazilian_strength`]).
//!
//! Quasi-static rule as the compression test ([`super::ucs`]): each platen travels the
//! estimated failure displacement ε_f D/2 in 20 P-wave transit times D √(ρ/E_c).

use super::common::{self, positive, Loading};
use super::specimens::{Shape, TestSpecimen};
use super::{analysis, LabError, LabModel};
use dem_core::output::history::Record;
use dem_core::scene::schema::{AxisName, SceneFile};
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

/// The result file `<name>.result.json`.
pub type BrazilianOutcome = common::Outcome<BrazilianTest, BrazilianReport>;

impl BrazilianTest {
    /// Checks every value; errors name the field (`brazilian.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        positive(TEST, "diameter", self.diameter)?;
        positive(TEST, "platen_length", self.platen_length)?;
        if self.name.is_empty() || self.name.contains(['/', '\\']) {
            return Err(LabError::Param {
                field: "brazilian.name".into(),
                reason: "must be a plain file stem".into(),
            });
        }
        self.loading.validate(&format!("{TEST}.loading"))
    }

    /// The geometry against the particle size: the disc of diameter `diameter` (m) made of
    /// discs of mean radius `r_mean` (m) must span [`common::MIN_DIAMETERS_ACROSS`] mean disc
    /// diameters (error field `brazilian.diameter`). [`scene`] runs it with the carved disc's
    /// height and mean radius; `dem test brazilian` also before generating.
    pub fn check_geometry(&self, diameter: f64, r_mean: f64) -> Result<(), LabError> {
        common::diameters_across(
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
        let d = spec.size()[1];
        let u_fail = 0.5 * d * common::failure_strain_estimate(model);
        self.loading
            .speed_for(u_fail, common::transit_time(model, d))
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
    s.walls = vec![
        common::wall("bottom", [xc - half, y0], [xc + half, y0], [0.0, v]),
        common::wall("top", [xc - half, y1], [xc + half, y1], [0.0, -v]),
    ];
    let m = &model.micro;
    // F at σ_t = σ̄_c would be πDtσ̄_c/2; arm the stop at 10 % of it (the
    // start-up transient, stress ρcv = E ε_f/N, is ~2.5 % of σ̄_c).
    let min_load = 0.1
        * std::f64::consts::FRAC_PI_2
        * d
        * model.thickness
        * m.boundary_tensile.min(m.boundary_cohesion);
    let u_fail = 0.5 * d * common::failure_strain_estimate(model);
    test.loading.scene_fields(
        &mut s,
        v,
        u_fail,
        &["top".into()],
        AxisName::Y,
        min_load,
        vec![],
    );
    Ok(s)
}

/// σ_t from the history of [`scene`].
pub fn analyze(
    t: &Record,
    test: &BrazilianTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<BrazilianReport, LabError> {
    let time = t.time.clone();
    let top = common::wall_series(t, "top", TEST)?.fy.clone();
    let bottom = common::wall_series(t, "bottom", TEST)?.fy.clone();
    let load: Vec<f64> = top
        .iter()
        .zip(&bottom)
        .map(|(a, b)| 0.5 * (a - b))
        .collect();
    let (ip, f) = analysis::peak(&load).ok_or_else(|| common::analysis_error(TEST, "no load"))?;
    let last = *load.last().unwrap_or(&0.0);
    if f <= 0.0 || last > 0.95 * f {
        return Err(common::analysis_error(
            TEST,
            format!(
                "no failure: the load was still {:.3} of its peak at the end; raise loading.max_travel_factor",
                last / f
            ),
        ));
    }
    let d = spec.size()[1];
    let v = test.platen_speed(model, spec);
    Ok(BrazilianReport {
        tensile_strength: analysis::brazilian_strength(f, d, model.thickness),
        peak_load: f,
        diameter: d,
        travel_at_peak: v * time[ip],
        platen_speed: v,
        time_to_peak: time[ip],
        quasi_static_ratio: time[ip] / common::transit_time(model, d),
    })
}

/// Scene beside the specimen file, run, analysis, `<name>.result.json` (atomic).
pub fn run(
    test: &BrazilianTest,
    model: &LabModel,
    spec: &TestSpecimen,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<BrazilianOutcome, LabError> {
    let s = scene(test, model, spec)?;
    common::run_test(&test.name, test, s, model, spec, progress, |h| {
        analyze(h, test, model, spec)
    })
}
