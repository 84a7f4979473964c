//! Biaxial (confined) compression test, PFC2D's biaxial test (Potyondy & Cundall 2004,
//! "A bonded-particle model for rock", Int. J. Rock Mech. Min. Sci. 41:1329-1364, §3; Cho,
//! Martin & Sego 2007, "A clumped particle model for rock", same journal 44:997-1010): the
//! w × h specimen of the UCS test between two frictionless platens closing at constant speed v
//! each, and two frictionless side walls, longer than the specimen, whose servo
//! ([`dem_core::wall_servo`]) holds the lateral stress at the confinement σ3. Measured:
//!
//! - axial stress σ1 = F / (w t) (F the mean platen force, w the initial width, as UCS);
//! - lateral stress σ3 = F_s / (h(t) t), F_s the mean side-wall force, h(t) = h − 2 v t the
//!   current platen gap (the servo holds F_s/(h t) with the initial h: the two differ by the
//!   axial strain, ~0.5 % at the peak);
//! - strength: the peak σ1, and σ3 at that peak; E and ν from the deviator q = σ1 − σ3 and the
//!   lateral gauges over the pre-peak band of q (as UCS).
//!
//! With σ3 held from the start, the side walls close on the specimen (at up to
//! `servo_speed_factor` times the platen speed) while the platens load it: the confinement is reached at a small fraction
//! of the peak load (a UCS/E strain of ~0.5 % against σ3/E of ~0.05 %), and the analysis
//! checks that σ3 is held within `confining_tolerance` from the band's start to the peak.
//!
//! Friction angle φ and cohesion c follow from the strengths at two or more confinements by
//! the Mohr–Coulomb line σ1 = 2c cos φ/(1 − sin φ) + σ3 (1 + sin φ)/(1 − sin φ)
//! ([`crate::analysis::mohr_coulomb`]).

use super::harness::{self, positive, Loading};
use super::ucs::UcsTest;
use crate::specimen::cache::{Shape, TestSpecimen};
use crate::{analysis, LabError, LabModel};
use dem_core::output::history::Record;
use dem_core::scene::schema::{SceneFile, ServoSpec, WallSpec};
use serde::{Deserialize, Serialize};

const TEST: &str = "biaxial";

/// A biaxial test (SI): the UCS test's specimen and platens, plus the confinement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BiaxialTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default
    /// "biaxial").
    pub name: String,
    /// Specimen width w and height h (m); default 10 × 20 mm.
    pub width: f64,
    pub height: f64,
    /// Confining stress σ3 (Pa, ≥ 0).
    pub confining: f64,
    /// Platens overhang the specimen by this fraction of w on each side (default 0.25).
    pub platen_overhang: f64,
    /// Side walls overhang the specimen by this fraction of h at each end (default 0.1).
    pub side_overhang: f64,
    /// The side walls' servo relaxation factor α (default 0.5, as PFC).
    pub servo_alpha: f64,
    /// The side walls' speed limit over the platen speed (default 10: a specimen that dilates
    /// near its peak pushes them out faster than the platens close; at 2 the flat-joint SiC
    /// specimens' σ3 overshot by 12–20 % before the peak).
    pub servo_speed_factor: f64,
    /// The lateral stress must stay within this fraction of σ3 from the band's start to the
    /// peak (default 0.1).
    pub confining_tolerance: f64,
    /// Pre-peak band of the fits, fractions of the peak deviator (default [0.1, 0.5]).
    pub band: [f64; 2],
    /// Width of the lateral gauges in mean radii (default 2).
    pub gauge_width: f64,
    /// Loading; the run stops when the platen load falls below 0.8 of its peak (a confined
    /// specimen keeps more of its load after failure than an unconfined one).
    pub loading: Loading,
}

impl Default for BiaxialTest {
    fn default() -> BiaxialTest {
        let u = UcsTest::default();
        BiaxialTest {
            name: TEST.into(),
            width: u.width,
            height: u.height,
            confining: 0.0,
            platen_overhang: u.platen_overhang,
            side_overhang: 0.1,
            servo_alpha: 0.5,
            servo_speed_factor: 10.0,
            confining_tolerance: 0.1,
            band: u.band,
            gauge_width: u.gauge_width,
            loading: Loading {
                stop_below: 0.8,
                ..Loading::default()
            },
        }
    }
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BiaxialReport {
    /// Confinement asked σ3 (Pa).
    pub confining: f64,
    /// Peak axial stress σ1 (Pa) and the lateral stress at that peak (Pa).
    pub sigma1: f64,
    pub sigma3: f64,
    /// Largest relative departure of σ3 from the confinement between the band's start and
    /// the peak (0 when σ3 = 0).
    pub confining_error: f64,
    /// Peak deviator σ1 − σ3 (Pa).
    pub deviator: f64,
    /// E and ν from the deviator and gauges over the band (Pa, —).
    pub young: f64,
    pub poisson: f64,
    pub band: [f64; 2],
    pub band_rows: usize,
    /// Axial strain at the peak.
    pub peak_strain: f64,
    /// Platen speed (each, m/s); time to the peak over the P-wave transit time h √(ρ/E).
    pub platen_speed: f64,
    pub quasi_static_ratio: f64,
}

impl BiaxialTest {
    /// The UCS test of the same specimen, platens, band and gauges (its checks and speed rule
    /// are this test's).
    fn ucs(&self) -> UcsTest {
        UcsTest {
            name: self.name.clone(),
            width: self.width,
            height: self.height,
            platen_overhang: self.platen_overhang,
            band: self.band,
            gauge_width: self.gauge_width,
            loading: self.loading.clone(),
        }
    }

    /// Checks every value; errors name the field (`biaxial.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        self.ucs()
            .validate()
            .map_err(|e| harness::renamed(e, |f| f.replacen("ucs.", "biaxial.", 1)))?;
        let bad = |f: &str, r: String| {
            Err(LabError::Param {
                field: format!("{TEST}.{f}"),
                reason: r,
            })
        };
        if !(self.confining.is_finite() && self.confining >= 0.0) {
            return bad(
                "confining",
                format!("must be finite and ≥ 0 Pa (got {})", self.confining),
            );
        }
        positive(TEST, "side_overhang", self.side_overhang)?;
        if !(self.servo_alpha > 0.0 && self.servo_alpha <= 1.0) {
            return bad(
                "servo_alpha",
                format!("must lie in (0, 1] (got {})", self.servo_alpha),
            );
        }
        positive(TEST, "confining_tolerance", self.confining_tolerance)?;
        positive(TEST, "servo_speed_factor", self.servo_speed_factor)?;
        Ok(())
    }

    /// The geometry checks of the UCS test (fields named `biaxial.*`).
    pub fn check_geometry(&self, size: [f64; 2], r_mean: f64) -> Result<(), LabError> {
        self.ucs()
            .check_geometry(size, r_mean)
            .map_err(|e| harness::renamed(e, |f| f.replacen("ucs.", "biaxial.", 1)))
    }

    /// The specimen shape.
    pub fn shape(&self) -> Shape {
        self.ucs().shape()
    }

    /// Platen speed (each platen, m/s): the UCS test's.
    pub fn platen_speed(&self, model: &LabModel, spec: &TestSpecimen) -> f64 {
        self.ucs().platen_speed(model, spec)
    }
}

/// The test's scene: the UCS scene's platens, gauges and run control, and the two servo side
/// walls `side_left`, `side_right`.
pub fn scene(
    test: &BiaxialTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<SceneFile, LabError> {
    test.validate()?;
    test.check_geometry(spec.size(), spec.r_mean)?;
    let mut s = super::ucs::scene(&test.ucs(), model, spec)?;
    let [x0, y0, x1, y1] = spec.extent;
    let h = y1 - y0;
    let v = test.platen_speed(model, spec);
    let oh = test.side_overhang * h;
    let side = |name: &str, x: f64, dir: f64| WallSpec {
        servo: Some(ServoSpec {
            stress: test.confining,
            length: h,
            direction: [dir, 0.0],
            alpha: test.servo_alpha,
            max_speed: test.servo_speed_factor * v,
        }),
        ..harness::wall(name, [x, y0 - oh], [x, y1 + oh], [0.0, 0.0])
    };
    s.walls.push(side("side_left", x0, 1.0));
    s.walls.push(side("side_right", x1, -1.0));
    s.description = format!(
        "Biaxial compression (dem test biaxial): confinement {:.4} MPa held by servo side walls; platens at {v:.4e} m/s each; specimen {:.3} x {:.3} mm",
        test.confining * 1e-6,
        (x1 - x0) * 1e3,
        h * 1e3
    );
    Ok(s)
}

/// σ1, σ3, E and ν from the history of [`scene`].
pub fn analyze(
    t: &Record,
    test: &BiaxialTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<BiaxialReport, LabError> {
    let time = &t.time;
    let load = harness::platen_load(t, TEST)?;
    let (sl, sr) = (
        &harness::wall_series(t, "side_left", TEST)?.fx,
        &harness::wall_series(t, "side_right", TEST)?.fx,
    );
    harness::enough_rows(t, TEST)?;
    let [w, h] = spec.size();
    let th = model.thickness;
    let v = test.platen_speed(model, spec);
    let sigma1: Vec<f64> = load.iter().map(|f| f / (w * th)).collect();
    // Discs push the right wall to +x and the left one to −x.
    let sigma3: Vec<f64> = (0..time.len())
        .map(|i| 0.5 * (sr[i] - sl[i]) / ((h - 2.0 * v * time[i]) * th))
        .collect();
    let q: Vec<f64> = sigma1.iter().zip(&sigma3).map(|(a, b)| a - b).collect();
    let (axial, lateral) = harness::compression_strains(t, TEST, v, h)?;
    let (ip, peak) = harness::failure_peak(TEST, &sigma1, "axial load", "no stress")?;
    let [lo, hi] = test.band;
    let band = harness::band_rows(TEST, &q, test.band, true)?;
    let confining_error = if test.confining > 0.0 {
        (band[0]..=ip)
            .map(|i| (sigma3[i] / test.confining - 1.0).abs())
            .fold(0.0, f64::max)
    } else {
        0.0
    };
    if confining_error > test.confining_tolerance {
        return Err(harness::analysis_error(
            TEST,
            format!(
                "the side walls did not hold σ3 = {:.4} MPa: off by {:.1} % between the band's start and the peak (tolerance {:.0} %); lower the platen speed or raise servo_speed_factor",
                test.confining * 1e-6,
                100.0 * confining_error,
                100.0 * test.confining_tolerance
            ),
        ));
    }
    let r = analysis::uniaxial_compression(&axial, &lateral, &q, lo, hi)
        .ok_or_else(|| harness::analysis_error(TEST, "cannot fit the pre-peak band"))?;
    let transit = h * (model.density / r.young).sqrt();
    Ok(BiaxialReport {
        confining: test.confining,
        sigma1: peak,
        sigma3: sigma3[ip],
        confining_error,
        deviator: peak - sigma3[ip],
        young: r.young,
        poisson: r.poisson,
        band: test.band,
        band_rows: band.len(),
        peak_strain: axial[ip],
        platen_speed: v,
        quasi_static_ratio: time[ip] / transit,
    })
}

harness::quasi_static!(BiaxialTest, BiaxialReport, BiaxialOutcome);

/// Biaxial tests at several confinements on one specimen, and their Mohr–Coulomb envelope.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BiaxialSeries {
    /// The test the series varies the confinement of (its name is the series' stem).
    pub test: BiaxialTest,
    pub model: LabModel,
    pub specimen: TestSpecimen,
    /// One report per confinement, in the order given (run `<name>-<k>`).
    pub results: Vec<BiaxialReport>,
    /// φ and c from the strengths (σ3 measured at each peak, σ1); `None` for one
    /// confinement or strengths that do not rise with it.
    pub mohr_coulomb: Option<analysis::MohrCoulomb>,
    /// Steps and wall time of all runs (s).
    pub steps: u64,
    pub wall_time_s: f64,
}

/// Runs `test` at each of `confinements` (Pa) on `spec` (runs `<name>-0`, `<name>-1`, … beside
/// the specimen), fits the envelope and writes `<name>.result.json` (atomically).
/// `progress(done, total)` counts over the whole series.
pub fn run_series(
    test: &BiaxialTest,
    confinements: &[f64],
    model: &LabModel,
    spec: &TestSpecimen,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<BiaxialSeries, LabError> {
    if confinements.is_empty() {
        return Err(harness::param(
            TEST,
            "confining",
            "give at least one confinement",
        ));
    }
    let n = confinements.len() as u64;
    let mut results = Vec::new();
    let (mut steps, mut wall) = (0, 0.0);
    for (k, &s3) in confinements.iter().enumerate() {
        let t = BiaxialTest {
            name: format!("{}-{k}", test.name),
            confining: s3,
            ..test.clone()
        };
        let o = harness::run(&t, model, spec, &mut |d, total| {
            progress(k as u64 * total + d, n * total)
        })?;
        steps += o.run.steps;
        wall += o.run.wall_time_s;
        results.push(o.result);
    }
    let pts: Vec<(f64, f64)> = results.iter().map(|r| (r.sigma3, r.sigma1)).collect();
    let series = BiaxialSeries {
        test: test.clone(),
        model: model.clone(),
        specimen: spec.clone(),
        mohr_coulomb: analysis::mohr_coulomb(&pts),
        results,
        steps,
        wall_time_s: wall,
    };
    let dir = spec.file.parent().unwrap_or(std::path::Path::new("."));
    harness::write_result(&dir.join(format!("{}.result.json", test.name)), &series)?;
    Ok(series)
}
