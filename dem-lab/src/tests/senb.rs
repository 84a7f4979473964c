//! Fracture toughness from a virtual single-edge-notched beam (SENB) in three-point bending,
//! the form of ASTM E399's SE(B) specimen: a beam of depth W, length ℓ, thickness B = t, on
//! supports at span S = 4W, with a notch of depth a (a/W = 0.5 by default; E399 asks for
//! 0.45–0.55) cut up from the bottom at mid-length, loaded at mid-span as the bending test
//! ([`crate::tests::bending`]: polyline rollers, local damping, the run stopped after the peak).
//!
//! The notch is a slot `notch_width` wide ([`crate::specimen::cache::carve_notch`]: discs in it
//! dropped, bonds and rigid grains across its mid-line below the tip cut), so it ends in a
//! crack-like cut: the flanks may touch but carry no tension across it.
//!
//! Measured: the peak load P and K_IC = P S / (B W^{3/2}) f(a/W) (E399, after Srawley 1976;
//! [`crate::analysis::senb_toughness`]), with W the beam's extent and a the cut depth; the crack
//! mouth opening displacement (CMOD) at the peak from two position gauges at the bottom on
//! either side of the slot. Beside K_IC the result gives the bond-scale estimate S4 uses,
//! σ̄_c √(πR̄) ([`crate::analysis::fracture_toughness`] with β = 1), and their ratio: β is
//! measured here, not chosen.
//!
//! A DEM notch is one disc-scale wide and its tip is blunt on the particle scale, so K_IC
//! measured this way is an apparent toughness of the bonded material at that resolution
//! (Potyondy & Cundall 2004 §3.3 discuss the dependence on R̄); the result states a/W, the
//! slot width and the ligament in mean disc diameters so runs can be compared.

use super::bending::BendingTest;
use super::harness::{self, positive, Loading};
use crate::specimen::cache::{Shape, TestSpecimen};
use crate::{analysis, LabError, LabModel};
use dem_core::output::history::Record;
use dem_core::scene::schema::SceneFile;
use serde::{Deserialize, Serialize};

const TEST: &str = "senb";

/// A single-edge-notched beam test (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SenbTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default "senb").
    pub name: String,
    /// Beam length ℓ (m), default 22 mm; at least S = 4W plus one mean disc diameter each side.
    pub length: f64,
    /// Beam depth W (m), default 5 mm; the span is 4W (the factor of E399's K formula).
    pub height: f64,
    /// Notch depth over beam depth a/W (default 0.5; the formula holds for 0 < a/W < 1, E399
    /// accepts 0.45–0.55 for a valid K_IC; here 0.1–0.8).
    pub notch_ratio: f64,
    /// Slot width (m), default 0.25 mm (one mean disc diameter of radii 0.10–0.15 mm; `dem test
    /// senb` defaults to one nominal mean diameter of its radii).
    pub notch_width: f64,
    /// Half-width of the two CMOD gauges in mean radii (default 2).
    pub gauge_width: f64,
    /// Friction between the loading roller and the discs (`None`: the discs'), as
    /// [`BendingTest::load_friction`]; without it a first notched beam slid 60 µm sideways and
    /// the run stopped at a third of the fracture load with no bond broken.
    pub load_friction: Option<f64>,
    /// Loading; the quasi-static factor defaults to 40 (four times the plain beam's: the notched
    /// beam fails at a fraction of the deflection the speed rule estimates for a plain one).
    pub loading: Loading,
}

impl Default for SenbTest {
    fn default() -> SenbTest {
        // Four times the plain beam's quasi-static factor (see `loading`).
        let loading = Loading {
            quasi_static_factor: 40.0,
            ..Loading::default()
        };
        SenbTest {
            name: TEST.into(),
            length: 22e-3,
            height: 5e-3,
            notch_ratio: 0.5,
            notch_width: 0.25e-3,
            gauge_width: 2.0,
            load_friction: None,
            loading,
        }
    }
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SenbReport {
    /// K_IC = P S / (B W^{3/2}) f(a/W) (Pa·m^½).
    pub fracture_toughness: f64,
    /// Peak load P (N).
    pub peak_load: f64,
    /// Span S, beam depth W (the specimen's extent), notch depth a (m) and a/W.
    pub span: f64,
    pub height: f64,
    pub notch_depth: f64,
    pub notch_ratio: f64,
    /// f(a/W) (ASTM E399 SE(B)).
    pub geometry_factor: f64,
    /// Slot width (m) and the ligament W − a in mean disc diameters.
    pub notch_width: f64,
    pub ligament_diameters: f64,
    /// σ̄_c √(πR̄) (Pa·m^½): S4's bond-scale toughness with β = 1, and the measured
    /// β = K_IC / (σ̄_c √(πR̄)).
    pub bond_estimate: f64,
    pub beta: f64,
    /// Crack mouth opening at the peak (m): the change of the horizontal distance between the
    /// two gauges beside the notch mouth.
    pub cmod_at_peak: f64,
    /// Loading-roller speed (m/s), time to the peak (s) and in fundamental periods of the
    /// un-notched beam.
    pub roller_speed: f64,
    pub time_to_peak: f64,
    pub quasi_static_ratio: f64,
}

impl SenbTest {
    /// Checks every value; errors name the field (`senb.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        positive(TEST, "length", self.length)?;
        positive(TEST, "height", self.height)?;
        if 4.0 * self.height >= self.length {
            let why = format!(
                "{} m must exceed the span S = 4W = {} m",
                self.length,
                4.0 * self.height
            );
            return Err(harness::param(TEST, "length", why));
        }
        if !(self.notch_ratio >= 0.1 && self.notch_ratio <= 0.8) {
            let why = format!(
                "{} must lie in [0.1, 0.8] (ASTM E399: 0.45–0.55)",
                self.notch_ratio
            );
            return Err(harness::param(TEST, "notch_ratio", why));
        }
        positive(TEST, "notch_width", self.notch_width)?;
        if self.notch_width >= self.height {
            let why = format!(
                "{} m: a slot must be narrower than the beam depth",
                self.notch_width
            );
            return Err(harness::param(TEST, "notch_width", why));
        }
        positive(TEST, "gauge_width", self.gauge_width)?;
        harness::load_friction(TEST, self.load_friction)?;
        harness::name_and_loading(TEST, &self.name, &self.loading)
    }

    /// The notch depth a = (a/W) W (m).
    pub fn notch_depth(&self) -> f64 {
        self.notch_ratio * self.height
    }

    /// The plain three-point bending test this one loads like: span 4 × `depth`.
    fn beam(&self, depth: f64) -> BendingTest {
        BendingTest {
            name: self.name.clone(),
            length: self.length,
            height: self.height,
            span: 4.0 * depth,
            gauge_width: self.gauge_width,
            load_friction: self.load_friction,
            loading: self.loading.clone(),
            ..BendingTest::default()
        }
    }

    /// The geometry against the particle size `r_mean` (m): the beam as the bending test checks
    /// it (depth, overhang at the supports, gauges), and a ligament W − a of at least
    /// [`harness::MIN_DIAMETERS_ACROSS`] mean disc diameters (`senb.notch_ratio`).
    pub fn check_geometry(&self, r_mean: f64) -> Result<(), LabError> {
        self.beam(self.height)
            .check_geometry([self.length, self.height], r_mean)
            .map_err(|e| {
                harness::renamed(e, |f| {
                    f.replace("bending.span", "senb.length")
                        .replace("bending.", "senb.")
                })
            })?;
        harness::diameters_across(
            TEST,
            "notch_ratio",
            self.height - self.notch_depth(),
            r_mean,
            "in the ligament above the notch, which carries the bending",
        )
    }

    /// The notched beam.
    pub fn shape(&self) -> Shape {
        Shape::NotchedBeam {
            width: self.length,
            height: self.height,
            notch_depth: self.notch_depth(),
            notch_width: self.notch_width,
        }
    }
}

/// The test's scene: the bending test's rollers on span S = 4W (W the specimen's extent), and
/// gauges `mouth_left`, `mouth_right`: bands of half-width `gauge_width` r̄ at the bottom
/// holding the discs nearest the notch on each side.
pub fn scene(
    test: &SenbTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<SceneFile, LabError> {
    test.validate()?;
    let [x0, y0, x1, _] = spec.extent;
    let w = spec.size()[1];
    let beam = test.beam(w);
    let mut s = super::bending::scene(&beam, model, spec)?;
    let xc = 0.5 * (x0 + x1);
    let g = test.gauge_width * spec.r_mean;
    // The discs of the bottom band nearest the slot on each side.
    let discs = spec.discs()?;
    let band: Vec<f64> = discs
        .iter()
        .filter(|d| d[1] < y0 + g)
        .map(|d| d[0])
        .collect();
    let left = band
        .iter()
        .copied()
        .filter(|&x| x < xc)
        .fold(f64::NAN, f64::max);
    let right = band
        .iter()
        .copied()
        .filter(|&x| x > xc)
        .fold(f64::NAN, f64::min);
    if !(left.is_finite() && right.is_finite()) {
        return Err(harness::analysis_error(
            TEST,
            "no disc at the bottom on one side of the notch (is the specimen a notched beam?)",
        ));
    }
    let e = 0.25 * spec.r_mean;
    s.outputs.gauges = vec![
        harness::gauge("mouth_left", [left - 2.0 * g, y0 - g, left + e, y0 + g]),
        harness::gauge("mouth_right", [right - e, y0 - g, right + 2.0 * g, y0 + g]),
    ];
    // The plain beam's stop is armed at 15 % of its estimated peak; the notched beam's peak
    // scales with the ligament squared, (1 − a/W)².
    let lig = 1.0 - test.notch_ratio;
    if let Some(stop) = s.run.stop_after_peak.as_mut() {
        // (Written (arm × lig) × lig, the order of the earlier JSON edit: the same bits.)
        stop.min_load = stop.min_load * lig * lig;
    }
    let (slot, a) = (test.notch_width, test.notch_depth());
    s.description = format!(
        "Single-edge-notched beam (dem test senb): {:.3} x {:.3} mm, span {:.3} mm, notch {:.3} mm deep (a/W = {:.2}), slot {:.3} mm",
        (x1 - x0) * 1e3,
        w * 1e3,
        4.0 * w * 1e3,
        a * 1e3,
        a / w,
        slot * 1e3
    );
    Ok(s)
}

/// K_IC and the CMOD from the history of [`scene`].
pub fn analyze(
    t: &Record,
    test: &SenbTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<SenbReport, LabError> {
    let w = spec.size()[1];
    let beam = test.beam(w);
    let time = t.time.clone();
    let load = super::bending::roller_load(t, beam.roller_segments, TEST)?;
    let (ip, p) = super::bending::fracture_peak(t, &load, TEST)?;
    let xl = harness::gauge_series(t, "mouth_left", TEST)?.x.clone();
    let xr = harness::gauge_series(t, "mouth_right", TEST)?.x.clone();
    let cmod = (xr[ip] - xl[ip]) - (xr[0] - xl[0]);
    let (slot, a) = (test.notch_width, test.notch_depth());
    let span = beam.span;
    let kic = analysis::senb_toughness(p, span, model.thickness, w, a);
    let bond = analysis::fracture_toughness(1.0, model.micro.boundary_tensile, spec.r_mean);
    Ok(SenbReport {
        fracture_toughness: kic,
        peak_load: p,
        span,
        height: w,
        notch_depth: a,
        notch_ratio: a / w,
        geometry_factor: analysis::senb_geometry_factor(a / w),
        notch_width: slot,
        ligament_diameters: (w - a) / (2.0 * spec.r_mean),
        bond_estimate: bond,
        beta: kic / bond,
        cmod_at_peak: cmod,
        time_to_peak: time[ip],
        quasi_static_ratio: time[ip] / beam.period(model, w),
        roller_speed: beam.roller_speed(model, spec),
    })
}

harness::quasi_static!(SenbTest, SenbReport, SenbOutcome);

#[cfg(test)]
mod tests {
    use dem_core::output::history::{GaugeSeries, GroupSeries, WallSeries};

    use super::*;
    use crate::tests::harness::fixtures;

    /// A synthetic history: the load rises to `peak` and falls to half, the mouth opens by
    /// 1 µm at the peak, `broken` bonds at the end.
    fn table(peak: f64, broken: u64) -> Record {
        let loads = [0.0, 0.5, 1.0, 0.5];
        let n = loads.len();
        let gauge = |name: &str, x: Vec<f64>| GaugeSeries {
            name: name.into(),
            y: vec![0.0; n],
            x,
        };
        let open = |i: usize| if i >= 2 { 1e-6 } else { 0.0 };
        Record {
            time: (0..n).map(|i| i as f64 * 1e-4).collect(),
            walls: (0..8)
                .map(|k| WallSeries {
                    name: format!("load_{k}"),
                    fy: loads.iter().map(|f| f * peak / 8.0).collect(),
                    ..WallSeries::default()
                })
                .collect(),
            gauges: vec![
                gauge("mouth_left", vec![1e-3; n]),
                gauge("mouth_right", (0..n).map(|i| 2e-3 + open(i)).collect()),
            ],
            groups: vec![GroupSeries {
                name: "grain_boundary".into(),
                tension: (0..n).map(|i| if i == 3 { broken } else { 0 }).collect(),
                shear: vec![0; n],
                elements: None,
            }],
            ..Record::default()
        }
    }

    fn setup() -> (SenbTest, LabModel, TestSpecimen) {
        let spec = fixtures::specimen("senb.specimen.json", 22e-3, 5e-3, 1800, 3500);
        (SenbTest::default(), fixtures::model(22e-3, 5e-3), spec)
    }

    #[test]
    fn toughness_from_the_peak_and_cmod_from_the_gauges() {
        let (t, m, spec) = setup();
        let r = analyze(&table(1e5, 3), &t, &m, &spec).unwrap();
        // S = 4W = 20 mm, W = 5 mm, a = 2.5 mm, B = t = 1 m: K = P S f(0.5) / (B W^1.5).
        let want = 1e5 * 20e-3 / (5e-3f64).powf(1.5) * analysis::senb_geometry_factor(0.5);
        assert!((r.fracture_toughness - want).abs() < 1e-9 * want);
        assert!((r.span - 20e-3).abs() < 1e-15 && (r.notch_ratio - 0.5).abs() < 1e-12);
        assert!((r.cmod_at_peak - 1e-6).abs() < 1e-15);
        assert!((r.ligament_diameters - 10.0).abs() < 1e-9);
        let bond = 800e6 * (std::f64::consts::PI * 0.125e-3).sqrt();
        assert!((r.beta - want / bond).abs() < 1e-9);
    }

    #[test]
    fn a_drop_without_a_broken_bond_is_refused() {
        let (t, m, spec) = setup();
        match analyze(&table(1e5, 0), &t, &m, &spec) {
            Err(LabError::Analysis { reason, .. }) => assert!(reason.contains("no bond broken")),
            other => panic!("{other:?}"),
        }
    }
}
