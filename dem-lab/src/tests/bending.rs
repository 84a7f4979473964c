//! Three-point bending test (S4, Tan et al.; S0, Ye & Xu granite beams; ASTM C1161): a beam of
//! length ℓ, height h and width b = t (the disc thickness) on two supports at span L, loaded at
//! mid-span by a third roller moving down at constant speed v; local damping. S4 loads with a
//! circular wall; walls here are straight segments, so each roller is a circular arc of radius
//! R (`roller_radius`) drawn as a polyline of `roller_segments` segments over ±`roller_angle`
//! about its apex, and a roller's force is the sum of its segments' (a disc touching two
//! segments at a vertex feels both: the polyline is slightly stiffer there than the circle,
//! and the measured load is still what the beam feels).
//!
//! Measured: the load F on the loading roller (N), the flexural strength
//! σ_f = 3FL/(2bh²) from its peak ([`crate::analysis::flexural_strength`]), and the elastic
//! stiffness k = dF/dδ over the 10–50 % pre-peak band, δ the mid-span deflection of the beam's
//! bottom fibre relative to the supports (position gauges at the bottom at mid-span and above
//! each support, so roller indentation and the initial settling are excluded). Compare k with
//! [`timoshenko_stiffness`].
//!
//! Quasi-static rule: the roller travels the deflection at which the extreme fibre reaches the
//! estimated failure strain, δ_f = ε_f L²/(6h) (Euler-Bernoulli, σ = 6Ehδ/L²), in
//! `quasi_static_factor` (default 10) fundamental periods of the simply supported beam,
//! T₁ = 2π/ω₁ with ω₁ = (π/L)² √(EI/(ρA)) = (π/L)² h √(E/(12ρ)) (Euler-Bernoulli), E = E_c.

use super::harness::{self, positive, Loading};
use crate::specimen::cache::{Shape, TestSpecimen};
use crate::{analysis, LabError, LabModel};
use dem_core::output::history::Record;
use dem_core::scene::schema::{AxisName, MaterialSpec, PairSpec, SceneFile, WallSpec};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

const TEST: &str = "bending";

/// A three-point bending test (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BendingTest {
    /// Scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json` (default
    /// "bending").
    pub name: String,
    /// Beam length ℓ and height h (m); default 20 × 5 mm.
    pub length: f64,
    pub height: f64,
    /// Support span L (m), default 16 mm; below the beam length.
    pub span: f64,
    /// Roller radius R (m); default `None`: h/2.
    pub roller_radius: Option<f64>,
    /// Segments per roller (default 8) and half-angle of the arc (rad, default 0.7).
    pub roller_segments: usize,
    pub roller_angle: f64,
    /// Pre-peak band of the stiffness fit (default [0.1, 0.5]).
    pub band: [f64; 2],
    /// Width of the deflection gauges in mean radii (default 2).
    pub gauge_width: f64,
    /// Friction coefficient between the loading roller and the discs; `None` (default): the
    /// discs' own friction. The supports stay frictionless (free to let the beam spread).
    /// With every roller frictionless nothing holds the beam horizontally (a flat beam on two
    /// convex rollers is in neutral equilibrium): a few degrees of tilt in the loader's contact
    /// slid beams sideways until the load fell with no bond broken (granite beams: 47 µm of
    /// drift, a "peak" at 60 % of the fracture load). Left out of the JSON when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_friction: Option<f64>,
    pub loading: Loading,
}

impl Default for BendingTest {
    fn default() -> BendingTest {
        BendingTest {
            name: TEST.into(),
            length: 20e-3,
            height: 5e-3,
            span: 16e-3,
            roller_radius: None,
            roller_segments: 8,
            roller_angle: 0.7,
            band: [0.1, 0.5],
            gauge_width: 2.0,
            load_friction: None,
            loading: Loading {
                quasi_static_factor: 10.0,
                ..Loading::default()
            },
        }
    }
}

/// What the test measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BendingReport {
    /// σ_f = 3FL/(2bh²) (Pa) from the peak load F (N); b = t, h the beam's extent height (m).
    pub flexural_strength: f64,
    pub peak_load: f64,
    pub span: f64,
    pub height: f64,
    /// Elastic stiffness dF/dδ (N/m) over the band, and the rows in it.
    pub stiffness: f64,
    pub band_rows: usize,
    /// Mid-span deflection at the peak (m).
    pub deflection_at_peak: f64,
    /// Roller speed (m/s), time to the peak (s), and its ratio to the beam's fundamental
    /// period T₁ with E_c.
    pub roller_speed: f64,
    pub time_to_peak: f64,
    pub quasi_static_ratio: f64,
}

/// Mid-span stiffness F/δ of a simply supported beam of span L under a central load,
/// Timoshenko: δ = FL³/(48EI) + FL/(4κGA), I = bh³/12, A = bh, G = E/(2(1+ν)), κ = 5/6
/// (rectangular section; Timoshenko & Gere, Mechanics of Materials). `shear = false` gives
/// Euler-Bernoulli (bending term only).
pub fn timoshenko_stiffness(e: f64, nu: f64, span: f64, b: f64, h: f64, shear: bool) -> f64 {
    let i = b * h * h * h / 12.0;
    let g = e / (2.0 * (1.0 + nu));
    let bend = span.powi(3) / (48.0 * e * i);
    let sh = if shear {
        span / (4.0 * (5.0 / 6.0) * g * b * h)
    } else {
        0.0
    };
    1.0 / (bend + sh)
}

impl BendingTest {
    /// Checks every value; errors name the field (`bending.<field>`).
    pub fn validate(&self) -> Result<(), LabError> {
        positive(TEST, "length", self.length)?;
        positive(TEST, "height", self.height)?;
        positive(TEST, "span", self.span)?;
        if self.span >= self.length {
            let why = format!(
                "{} m must be below the beam length {} m",
                self.span, self.length
            );
            return Err(harness::param(TEST, "span", why));
        }
        if let Some(r) = self.roller_radius {
            positive(TEST, "roller_radius", r)?;
        }
        if self.roller_segments == 0 || self.roller_segments > 64 {
            return Err(harness::param(
                TEST,
                "roller_segments",
                "must lie in 1..=64",
            ));
        }
        if !(self.roller_angle > 0.0 && self.roller_angle < 0.5 * PI) {
            return Err(harness::param(
                TEST,
                "roller_angle",
                "must lie in (0, π/2) rad",
            ));
        }
        positive(TEST, "gauge_width", self.gauge_width)?;
        harness::load_friction(TEST, self.load_friction)?;
        harness::prepeak_band(TEST, self.band)?;
        harness::name_and_loading(TEST, &self.name, &self.loading)
    }

    /// The geometry against the particle size, for a beam of `size` = [ℓ, h] (m) made of
    /// discs of mean radius `r_mean` (m): the height must span
    /// [`harness::MIN_DIAMETERS_ACROSS`] mean disc diameters (`bending.height`); the beam must
    /// overhang each support by at least one mean disc diameter, so the supports bear on discs
    /// inside the beam and not on its end discs (`bending.span`); the deflection gauges (bands
    /// of half-width `gauge_width` r̄ at the bottom fibre) must hold a disc (`gauge_width` ≥ 1),
    /// stay in the lower half of the beam (`gauge_width` r̄ ≤ h/2, `bending.gauge_width`), and
    /// the mid-span gauge must not overlap the support gauges (span ≥ 4 `gauge_width` r̄,
    /// `bending.span`). [`scene`] runs it with the specimen's extent and mean radius; `dem test
    /// bending` also before generating. Call [`BendingTest::validate`] first (span < ℓ).
    pub fn check_geometry(&self, size: [f64; 2], r_mean: f64) -> Result<(), LabError> {
        let [l, h] = size;
        let d = 2.0 * r_mean;
        harness::diameters_across(
            TEST,
            "height",
            h,
            r_mean,
            "through the beam's height for tension and compression sides about its neutral axis",
        )?;
        let overhang = 0.5 * (l - self.span);
        if overhang.is_nan() || overhang < d {
            return Err(harness::param(
                TEST,
                "span",
                format!(
                    "{:.4} mm on a {:.4} mm beam leaves {:.4} mm ({:.1} mean disc diameters) \
                     beyond each support; at least one mean disc diameter ({:.4} mm) is needed \
                     so the supports bear on discs inside the beam, not on its end discs: \
                     the span may be at most {:.4} mm",
                    self.span * 1e3,
                    l * 1e3,
                    overhang * 1e3,
                    overhang / d,
                    d * 1e3,
                    (l - 2.0 * d) * 1e3
                ),
            ));
        }
        harness::gauge_holds_a_disc(TEST, self.gauge_width, r_mean)?;
        let g = self.gauge_width * r_mean;
        if g > 0.5 * h {
            return Err(harness::param(
                TEST,
                "gauge_width",
                format!(
                    "{} mean radii: the deflection gauges reach {:.4} mm up into a {:.4} mm \
                     high beam, past its neutral axis; at most {:.2} (half the height)",
                    self.gauge_width,
                    g * 1e3,
                    h * 1e3,
                    0.5 * h / r_mean
                ),
            ));
        }
        if self.span < 4.0 * g {
            return Err(harness::param(
                TEST,
                "span",
                format!(
                    "{:.4} mm: the mid-span and support gauges (bands of ±{:.4} mm, \
                     gauge_width {} mean radii) overlap below a span of {:.4} mm and would \
                     average the same discs; lengthen the span or lower gauge_width",
                    self.span * 1e3,
                    g * 1e3,
                    self.gauge_width,
                    4.0 * g * 1e3
                ),
            ));
        }
        Ok(())
    }

    pub fn shape(&self) -> Shape {
        Shape::Rectangle {
            width: self.length,
            height: self.height,
        }
    }

    /// Loading-roller speed (m/s): the given one, else the quasi-static rule.
    pub fn roller_speed(&self, model: &LabModel, spec: &TestSpecimen) -> f64 {
        let h = spec.size()[1];
        self.loading
            .speed_for(self.failure_deflection(model, h), self.period(model, h))
    }

    /// δ_f = ε_f L²/(6h).
    fn failure_deflection(&self, model: &LabModel, h: f64) -> f64 {
        harness::failure_strain_estimate(model) * self.span * self.span / (6.0 * h)
    }

    /// Fundamental period of the simply supported beam of height `h` (s):
    /// T₁ = 2π/ω₁, ω₁ = (π/L)² h √(E_c/(12ρ)).
    pub fn period(&self, model: &LabModel, h: f64) -> f64 {
        let c = (model.micro.contact_modulus / (12.0 * model.density)).sqrt();
        2.0 * PI / ((PI / self.span).powi(2) * h * c)
    }
}

/// The polyline vertices of a roller arc of radius `r` about `centre`, apex direction `up`
/// (+1: apex on top).
fn roller_points(centre: [f64; 2], r: f64, up: f64, test: &BendingTest) -> Vec<[f64; 2]> {
    let n = test.roller_segments;
    let apex = up * 0.5 * PI;
    (0..=n)
        .map(|k| {
            let a = apex - test.roller_angle + 2.0 * test.roller_angle * k as f64 / n as f64;
            [centre[0] + r * a.cos(), centre[1] + r * a.sin()]
        })
        .collect()
}

/// Distance from point `p` to segment `a`–`b`.
fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (sx, sy) = (b[0] - a[0], b[1] - a[1]);
    let t = (((p[0] - a[0]) * sx + (p[1] - a[1]) * sy) / (sx * sx + sy * sy)).clamp(0.0, 1.0);
    (p[0] - a[0] - t * sx).hypot(p[1] - a[1] - t * sy)
}

/// A roller: polyline walls `<name>_<k>` on the arc of radius `r` about `centre`, apex
/// direction `up` (+1: apex on top, a support; −1: apex below, the loader).
fn roller(
    name: &str,
    centre: [f64; 2],
    r: f64,
    up: f64,
    test: &BendingTest,
    velocity: [f64; 2],
) -> Vec<WallSpec> {
    let p = roller_points(centre, r, up, test);
    (0..test.roller_segments)
        .map(|k| harness::wall(&format!("{name}_{k}"), p[k], p[k + 1], velocity))
        .collect()
}

/// Material of the loading roller's segments: the walls' stiffness, friction μ.
pub const LOAD_MATERIAL: &str = "load_roller";

/// Gives the loading roller (`walls` named `load_*`) its own material [`LOAD_MATERIAL`]: the
/// wall material of scene `s` with friction `mu`, and its disc pair likewise.
fn load_roller_material(
    s: &mut SceneFile,
    walls: &mut [WallSpec],
    mu: f64,
) -> Result<(), LabError> {
    let wall = crate::model::WALL_MATERIAL;
    let layout = || harness::analysis_error(TEST, "the lab scene's materials changed layout");
    let roller = MaterialSpec {
        name: LOAD_MATERIAL.into(),
        friction: mu,
        ..(s.materials.iter().find(|m| m.name == wall))
            .cloned()
            .ok_or_else(layout)?
    };
    let pair = PairSpec {
        materials: [crate::model::DISC_MATERIAL.into(), LOAD_MATERIAL.into()],
        friction: Some(mu),
        ..s.contact.pairs.first().cloned().ok_or_else(layout)?
    };
    s.materials.push(roller);
    s.contact.pairs.push(pair);
    for w in walls.iter_mut().filter(|w| w.name.starts_with("load_")) {
        w.material = LOAD_MATERIAL.into();
    }
    Ok(())
}

/// Bonds and flat-joint elements broken by the end of a history (the sum of its `broken_*`
/// columns' last row: whole bonds by mode, and `broken_<group>_elements` for flat-joint
/// groups, whose beams can lose their load while every interface keeps some cement).
fn bonds_broken(t: &Record) -> f64 {
    t.broken_at_end() as f64
}

/// The row and value of the peak of the roller `load` of history `t`, if the beam fractured:
/// the load fell below 95 % of its peak by the end, and with at least one bond (or flat-joint
/// element) broken (a drop with none is a sliding or ringing beam, or a roller pressing a loose
/// grain). Errors name `test`.
pub fn fracture_peak(t: &Record, load: &[f64], test: &str) -> Result<(usize, f64), LabError> {
    let (ip, f) = harness::failure_peak(test, load, "load", "no load")?;
    let last = *load.last().unwrap_or(&0.0);
    if bonds_broken(t) < 1.0 {
        return Err(harness::analysis_error(
            test,
            format!(
                "the load fell to {:.3} of its peak with no bond broken: not a fracture (the beam \
                 slid or rang, or the roller pressed a loose grain); lower the speed or raise \
                 load_friction",
                last / f
            ),
        ));
    }
    Ok((ip, f))
}

/// The test's scene: the beam, two supports and the loading roller (polylines), gauges
/// `mid` (bottom, mid-span), `sup_left`, `sup_right` (bottom, above the supports).
pub fn scene(
    test: &BendingTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<SceneFile, LabError> {
    test.validate()?;
    let [x0, y0, x1, y1] = spec.extent;
    let (l, h) = (x1 - x0, y1 - y0);
    if test.span >= l {
        return Err(harness::param(
            TEST,
            "span",
            format!("{} m must be below the specimen's length {l} m", test.span),
        ));
    }
    test.check_geometry([l, h], spec.r_mean)?;
    let xc = 0.5 * (x0 + x1);
    let r = test.roller_radius.unwrap_or(0.5 * h);
    let v = test.roller_speed(model, spec);
    let (xl, xr) = (xc - 0.5 * test.span, xc + 0.5 * test.span);
    // Each roller just touches the beam (no gap to close first): the polyline's height is
    // found by bisection between the circle's touching height and two sagittas beyond it.
    let discs = spec.discs()?;
    let sagitta = r * (1.0 - (test.roller_angle / test.roller_segments as f64).cos());
    let place = |x: f64, side: f64| -> Result<f64, LabError> {
        let near: Vec<[f64; 3]> = discs
            .iter()
            .filter(|d| (d[0] - x).abs() < r + d[2])
            .copied()
            .collect();
        // side +1: roller above the beam (centre above the highest touching point).
        let circle = near
            .iter()
            .map(|d| side * (d[1] + side * ((r + d[2]).powi(2) - (d[0] - x).powi(2)).sqrt()))
            .fold(f64::NEG_INFINITY, f64::max)
            * side;
        if !circle.is_finite() {
            return Err(harness::param(
                TEST,
                "span",
                format!("no disc under the roller at x = {x} m"),
            ));
        }
        let gap = |yc: f64| {
            let pts = roller_points([x, yc], r, -side, test);
            near.iter()
                .flat_map(|d| {
                    pts.windows(2)
                        .map(move |w| seg_dist([d[0], d[1]], w[0], w[1]) - d[2])
                })
                .fold(f64::INFINITY, f64::min)
        };
        // At the circle's height the gap is ≥ 0, two sagittas into the beam it is < 0.
        let (mut out, mut inn) = (circle, circle - side * 2.0 * sagitta);
        for _ in 0..60 {
            let mid = 0.5 * (out + inn);
            if gap(mid) > 0.0 {
                out = mid;
            } else {
                inn = mid;
            }
        }
        Ok(out)
    };
    let (yl, yr, yc) = (place(xl, -1.0)?, place(xr, -1.0)?, place(xc, 1.0)?);
    let mut walls = roller("support_left", [xl, yl], r, 1.0, test, [0.0, 0.0]);
    walls.extend(roller("support_right", [xr, yr], r, 1.0, test, [0.0, 0.0]));
    walls.extend(roller("load", [xc, yc], r, -1.0, test, [0.0, -v]));
    let load_walls: Vec<String> = (0..test.roller_segments)
        .map(|k| format!("load_{k}"))
        .collect();
    let mut s = model.scene_file(&test.name, &spec.file_name(), [0.0, 0.0]);
    load_roller_material(
        &mut s,
        &mut walls,
        test.load_friction.unwrap_or(model.micro.friction),
    )?;
    s.description = format!(
        "Three-point bending (dem test bending): beam {:.3} x {:.3} mm, span {:.3} mm, roller R {:.3} mm at {v:.4e} m/s",
        l * 1e3,
        h * 1e3,
        test.span * 1e3,
        r * 1e3
    );
    s.walls = walls;
    let g = test.gauge_width * spec.r_mean;
    let band = |x: f64| [x - g, y0 - g, x + g, y0 + g];
    let gauges = vec![
        harness::gauge("mid", band(xc)),
        harness::gauge("sup_left", band(xl)),
        harness::gauge("sup_right", band(xr)),
    ];
    let m = &model.micro;
    // F at σ_f = σ̄_c would be 2σ̄_c t h²/(3L); arm the stop at 15 % of it (the start-up
    // transient of the free beam hit by the roller is ~6 % of the peak).
    let min_load =
        0.15 * 2.0 * m.boundary_tensile.min(m.boundary_cohesion) * model.thickness * h * h
            / (3.0 * test.span);
    test.loading.scene_fields(
        &mut s,
        v,
        test.failure_deflection(model, h),
        &load_walls,
        AxisName::Y,
        min_load,
        gauges,
    );
    Ok(s)
}

/// The loading roller's vertical force per history row: the sum of its `segments` segments'
/// `load_<k>_fy` columns (errors name `test`).
pub fn roller_load(t: &Record, segments: usize, test: &str) -> Result<Vec<f64>, LabError> {
    let mut load = vec![0.0; t.len()];
    for k in 0..segments {
        for (f, v) in load
            .iter_mut()
            .zip(&harness::wall_series(t, &format!("load_{k}"), test)?.fy)
        {
            *f += v;
        }
    }
    Ok(load)
}

/// σ_f and the elastic stiffness from the history of [`scene`].
pub fn analyze(
    t: &Record,
    test: &BendingTest,
    model: &LabModel,
    spec: &TestSpecimen,
) -> Result<BendingReport, LabError> {
    let time = t.time.clone();
    let load = roller_load(t, test.roller_segments, TEST)?;
    let mid = harness::gauge_series(t, "mid", TEST)?.y.clone();
    let sl = harness::gauge_series(t, "sup_left", TEST)?.y.clone();
    let sr = harness::gauge_series(t, "sup_right", TEST)?.y.clone();
    let defl: Vec<f64> = (0..time.len())
        .map(|i| {
            let d = |k: usize| 0.5 * (sl[k] + sr[k]) - mid[k];
            d(i) - d(0)
        })
        .collect();
    let (ip, f) = fracture_peak(t, &load, TEST)?;
    let band = harness::band_rows(TEST, &load, test.band, false)?;
    let bx: Vec<f64> = band.iter().map(|&i| defl[i]).collect();
    let by: Vec<f64> = band.iter().map(|&i| load[i]).collect();
    let (k, _) = analysis::linear_fit(&bx, &by)
        .ok_or_else(|| harness::analysis_error(TEST, "cannot fit the pre-peak band"))?;
    let h = spec.size()[1];
    Ok(BendingReport {
        flexural_strength: analysis::flexural_strength(f, test.span, model.thickness, h),
        peak_load: f,
        span: test.span,
        height: h,
        stiffness: k,
        band_rows: band.len(),
        deflection_at_peak: defl[ip],
        roller_speed: test.roller_speed(model, spec),
        time_to_peak: time[ip],
        quasi_static_ratio: time[ip] / test.period(model, h),
    })
}

harness::quasi_static!(BendingTest, BendingReport, BendingOutcome);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests::harness::fixtures;
    use dem_core::output::history::{GaugeSeries, GroupSeries, WallSeries};

    #[test]
    fn a_load_drop_without_a_broken_bond_is_refused() {
        // The load rises to 1 kN and falls to half (a "peak"), the beam deflects, no bond
        // breaks: a sliding beam, not a fracture.
        let loads = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 0.5];
        let n = loads.len();
        let at_end = |v: u64| (0..n).map(|i| if i == 9 { v } else { 0 }).collect();
        let gauge = |name: &str, y: Vec<f64>| GaugeSeries {
            name: name.into(),
            x: vec![0.0; n],
            y,
        };
        let table = |broken: u64, elements: u64| Record {
            time: (0..n).map(|i| i as f64 * 1e-5).collect(),
            walls: (0..8)
                .map(|k| WallSeries {
                    name: format!("load_{k}"),
                    fy: loads.iter().map(|f| f * 1e3 / 8.0).collect(),
                    ..WallSeries::default()
                })
                .collect(),
            gauges: vec![
                gauge("mid", (0..n).map(|i| -1e-6 * i as f64).collect()),
                gauge("sup_left", vec![0.0; n]),
                gauge("sup_right", vec![0.0; n]),
            ],
            groups: vec![GroupSeries {
                name: "grain_boundary".into(),
                tension: at_end(broken),
                shear: vec![0; n],
                elements: Some(at_end(elements)),
            }],
            ..Record::default()
        };
        let spec = fixtures::specimen("b.json", 20e-3, 5e-3, 500, 900);
        let (t, m) = (BendingTest::default(), fixtures::model(20e-3, 5e-3));
        match analyze(&table(0, 0), &t, &m, &spec) {
            Err(LabError::Analysis { reason, .. }) => assert!(reason.contains("no bond broken")),
            other => panic!("{other:?}"),
        }
        let r = analyze(&table(2, 0), &t, &m, &spec).unwrap();
        assert!((r.peak_load - 1e3).abs() < 1e-9);
        // Flat joints: elements broken, every interface still partly cemented — a fracture.
        let r = analyze(&table(0, 3), &t, &m, &spec).unwrap();
        assert!((r.peak_load - 1e3).abs() < 1e-9);
        // The JSON of the default test is unchanged by the new field (run keys, locks).
        let v = serde_json::to_value(&t).unwrap();
        assert!(v.get("load_friction").is_none());
    }
}
