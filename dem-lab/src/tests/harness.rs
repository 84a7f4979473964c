//! The run harness of the quasi-static lab tests (compression, biaxial, Brazilian, bending,
//! SENB): the quasi-static loading rule, the run settings of a damped quasi-static scene, the
//! platens and gauges, the checks of the parameters every test has (name, band, friction),
//! the run itself ([`QuasiStatic`], [`run`]: scene beside the specimen, run, history analysed),
//! the facts of a finished run, and the atomic result file. The crushing and cutting tests use
//! its walls, series readers and result file too.

use crate::run::{run_scene, LabRun};
use crate::specimen::cache::TestSpecimen;
use crate::{LabError, LabModel};
use dem_core::output::driver::RunOptions;
use dem_core::output::history::{GaugeSeries, GroupSeries, Record, WallSeries};
use dem_core::output::write_atomic;
use dem_core::scene::schema::{
    AxisName, GaugeSpec, OutputSpec, PlacementSpec, RunSpec, SceneFile, StopAfterPeakSpec, WallSpec,
};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Local damping of the quasi-static lab tests: PFC practice (Potyondy & Cundall 2004 §2.2,
/// α = 0.7), as the specimen generator's relaxation.
pub const LOCAL_DAMPING: f64 = 0.7;

/// Time-step safety factor of the lab tests. The engine's default 0.04 is chosen for energy
/// conservation of undamped collisions (`Params::dt_factor`); damped quasi-static loading
/// needs only stability, and the specimen generator relaxes at 0.3 (PFC runs at 0.8).
/// `tests/lab_ucs.rs` checks that halving it changes E and UCS by less than 1 %.
pub const DT_FACTOR: f64 = 0.3;

/// The safety factor f of the automatic time step dt = f · dt_crit (dem-core's
/// `Params::dt_factor`), declared once for every lab test (loading, cutting, crushing): its
/// default 0.3 (`DT_FACTOR`) and its rule, f in (0, 1] (f > 1 steps past the critical time
/// step of the stiffest contact). In files a plain number.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(transparent)]
pub struct DtFactor(pub f64);

impl Default for DtFactor {
    fn default() -> DtFactor {
        DtFactor(DT_FACTOR)
    }
}

impl DtFactor {
    /// The factor.
    pub fn get(self) -> f64 {
        self.0
    }

    /// The rule; the error names `field` (`ucs.dt_factor`, `dt_factor`).
    pub fn check(self, field: &str) -> Result<(), LabError> {
        if self.0 > 0.0 && self.0 <= 1.0 {
            return Ok(());
        }
        Err(LabError::Param {
            field: field.into(),
            reason: format!("{}: must lie in (0, 1]", self.0),
        })
    }
}

/// A command line's value (`--dt-factor 0.3`): a number under the rule.
impl std::str::FromStr for DtFactor {
    type Err = String;
    fn from_str(s: &str) -> Result<DtFactor, String> {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("{s:?} is not a number"))?;
        let f = DtFactor(v);
        f.check("dt_factor")
            .map_err(|_| format!("{v}: must lie in (0, 1]"))?;
        Ok(f)
    }
}

impl std::fmt::Display for DtFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

/// Settings every quasi-static test shares (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Loading {
    /// Speed of the moving wall(s) (m/s); `None`: the quasi-static rule of
    /// [`Loading::speed_for`].
    pub speed: Option<f64>,
    /// Quasi-static rule: the loading time to the estimated failure strain is at least this
    /// many characteristic times of the specimen (default 20).
    pub quasi_static_factor: f64,
    /// Time-step safety factor (default [`DT_FACTOR`]; [`DtFactor`]).
    pub dt_factor: DtFactor,
    /// Local damping α (default [`LOCAL_DAMPING`]).
    pub local_damping: f64,
    /// `run.stop_after_peak.below`: the run ends when the load falls below this fraction of
    /// its peak (default 0.6).
    pub stop_below: f64,
    /// The run's duration cap: the wall travel reaches this many times the estimated
    /// failure displacement (default 10).
    pub max_travel_factor: f64,
    /// History row every this many steps (default 20).
    pub history_every: u64,
}

impl Default for Loading {
    fn default() -> Loading {
        Loading {
            speed: None,
            quasi_static_factor: 20.0,
            dt_factor: DtFactor::default(),
            local_damping: LOCAL_DAMPING,
            stop_below: 0.6,
            max_travel_factor: 10.0,
            history_every: 20,
        }
    }
}

impl Loading {
    /// Checks every value; errors name the field as `<test>.<field>`.
    pub fn validate(&self, test: &str) -> Result<(), LabError> {
        let bad = |f: &str, r: &str| {
            Err(LabError::Param {
                field: format!("{test}.{f}"),
                reason: r.into(),
            })
        };
        if let Some(v) = self.speed {
            if !(v.is_finite() && v > 0.0) {
                return bad("speed", "must be positive (m/s)");
            }
        }
        if !(self.quasi_static_factor.is_finite() && self.quasi_static_factor > 0.0) {
            return bad("quasi_static_factor", "must be positive");
        }
        self.dt_factor.check(&format!("{test}.dt_factor"))?;
        if !(0.0..1.0).contains(&self.local_damping) {
            return bad("local_damping", "must lie in [0, 1)");
        }
        if !(self.stop_below > 0.0 && self.stop_below < 1.0) {
            return bad("stop_below", "must lie in (0, 1)");
        }
        if !(self.max_travel_factor.is_finite() && self.max_travel_factor > 1.0) {
            return bad("max_travel_factor", "must be above 1");
        }
        if self.history_every == 0 {
            return bad("history_every", "must be at least 1");
        }
        Ok(())
    }

    /// Wall speed: the given one, else the quasi-static rule v = u_f / (N t_c): the wall
    /// travels the estimated failure displacement `u_fail` (m) in N = `quasi_static_factor`
    /// characteristic times `t_c` (s).
    pub fn speed_for(&self, u_fail: f64, t_c: f64) -> f64 {
        self.speed
            .unwrap_or(u_fail / (self.quasi_static_factor * t_c))
    }

    /// The scene's `damping`, `run` (duration: the wall travels `max_travel_factor` × `u_fail`
    /// at `speed`; stop after the peak of the `walls`' force along `axis`, armed at
    /// `min_load`) and `outputs` (history rows, gauges) fields.
    #[allow(clippy::too_many_arguments)]
    pub fn scene_fields(
        &self,
        scene: &mut SceneFile,
        speed: f64,
        u_fail: f64,
        walls: &[String],
        axis: AxisName,
        min_load: f64,
        gauges: Vec<GaugeSpec>,
    ) {
        scene.damping.local = self.local_damping;
        scene.run = RunSpec {
            duration: Some(self.max_travel_factor * u_fail / speed),
            dt_factor: Some(self.dt_factor.get()),
            stop_after_peak: Some(StopAfterPeakSpec {
                walls: walls.to_vec(),
                axis,
                below: self.stop_below,
                min_load,
            }),
            ..RunSpec::default()
        };
        scene.outputs = OutputSpec {
            history_every: self.history_every,
            gauges,
            ..OutputSpec::default()
        };
    }
}

/// A wall of the lab's wall material from `a` to `b` (m) moving at `velocity` (m/s).
pub fn wall(name: &str, a: [f64; 2], b: [f64; 2], velocity: [f64; 2]) -> WallSpec {
    WallSpec {
        name: name.into(),
        a,
        b,
        via: Vec::new(),
        material: crate::model::WALL_MATERIAL.into(),
        velocity,
        angular_velocity: 0.0,
        center: None,
        servo: None,
    }
}

/// A clump placement at (`x`, `y`) (m), turned by `angle` (rad), at rest.
pub fn placement(x: f64, y: f64, angle: f64) -> PlacementSpec {
    PlacementSpec {
        x,
        y,
        angle,
        velocity: [0.0, 0.0],
        omega: 0.0,
    }
}

/// A gauge `name` over the discs whose centres are in `region` = [x0, y0, x1, y1] (m).
pub fn gauge(name: &str, region: [f64; 4]) -> GaugeSpec {
    GaugeSpec {
        name: name.into(),
        region,
    }
}

/// Lower estimate of a bonded specimen's failure strain: bond strength over bond modulus,
/// min(σ̄_c, c̄)/Ē_c (a bond of length ~2r̄ reaches its strength at this strain; the
/// specimen's failure strain is larger, so speeds from it are on the slow side).
pub fn failure_strain_estimate(m: &LabModel) -> f64 {
    let p = &m.micro;
    p.boundary_tensile.min(p.boundary_cohesion) / p.bond_modulus
}

/// P-wave transit time over `length`: t = L √(ρ/E) with the contact modulus E_c as a lower
/// estimate of the specimen's modulus (so the time is on the long side).
pub fn transit_time(m: &LabModel, length: f64) -> f64 {
    length * (m.density / m.micro.contact_modulus).sqrt()
}

/// The facts of a finished run, written into the result files.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunFacts {
    pub scene_file: PathBuf,
    pub out_dir: PathBuf,
    /// `completed`, `failure` (stopped after the peak) or `max_steps`.
    pub status: String,
    pub steps: u64,
    pub discs: usize,
    pub bonds: usize,
    pub bonds_broken: u64,
    pub dt: f64,
    pub wall_time_s: f64,
}

impl RunFacts {
    pub fn of(run: &LabRun) -> RunFacts {
        let s = &run.summary;
        RunFacts {
            scene_file: run.scene_file.clone(),
            out_dir: run.out_dir.clone(),
            status: s.status.clone(),
            steps: s.steps,
            discs: s.discs,
            bonds: s.bonds,
            bonds_broken: s.bonds_broken,
            dt: s.dt,
            wall_time_s: s.wall_time_s,
        }
    }
}

/// A test's result file `<name>.result.json`: the test, the model, the specimen, what the
/// analysis measured and the facts of the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outcome<T, R> {
    pub test: T,
    pub model: LabModel,
    pub specimen: TestSpecimen,
    pub result: R,
    pub run: RunFacts,
}

/// A quasi-static lab test: its own scene and analysis; [`run`] does the rest.
pub trait QuasiStatic: Clone + Serialize {
    /// What the analysis measured.
    type Report: Serialize;
    /// The file stem: scene `<name>.json`, outputs `<name>.out/`, result `<name>.result.json`.
    fn name(&self) -> &str;
    /// The specimen's shape.
    fn shape(&self) -> crate::specimen::cache::Shape;
    /// The test's scene (`dem.scene/1`) on `spec`, checked first.
    fn scene(&self, model: &LabModel, spec: &TestSpecimen) -> Result<SceneFile, LabError>;
    /// What the history `t` of [`QuasiStatic::scene`] measured.
    fn analyze(
        &self,
        t: &Record,
        model: &LabModel,
        spec: &TestSpecimen,
    ) -> Result<Self::Report, LabError>;
}

/// Implements [`QuasiStatic`] for `$test` (a struct with a `name` field) with the module's own
/// `scene(test, model, spec)` and `analyze(history, test, model, spec)` functions, and names
/// its result file's type `$outcome`.
macro_rules! quasi_static {
    ($test:ident, $report:ident, $outcome:ident) => {
        /// The result file `<name>.result.json`.
        pub type $outcome = $crate::tests::harness::Outcome<$test, $report>;

        impl $crate::tests::harness::QuasiStatic for $test {
            type Report = $report;
            fn name(&self) -> &str {
                &self.name
            }
            fn shape(&self) -> $crate::specimen::cache::Shape {
                <$test>::shape(self)
            }
            fn scene(
                &self,
                model: &$crate::LabModel,
                spec: &$crate::specimen::cache::TestSpecimen,
            ) -> Result<dem_core::scene::schema::SceneFile, $crate::LabError> {
                scene(self, model, spec)
            }
            fn analyze(
                &self,
                t: &dem_core::output::history::Record,
                model: &$crate::LabModel,
                spec: &$crate::specimen::cache::TestSpecimen,
            ) -> Result<$report, $crate::LabError> {
                analyze(t, self, model, spec)
            }
        }
    };
}
pub(crate) use quasi_static;

/// Runs a quasi-static test: writes its scene `<name>.json` beside the specimen file, runs it
/// (outputs `<name>.out/`), analyses the history and writes `<name>.result.json` there
/// (atomically); `progress(done, total)` now and then.
pub fn run<T: QuasiStatic>(
    test: &T,
    model: &LabModel,
    spec: &TestSpecimen,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<Outcome<T, T::Report>, LabError> {
    let s = test.scene(model, spec)?;
    run_test(test.name(), test, s, model, spec, progress, |h| {
        test.analyze(h, model, spec)
    })
}

/// What every quasi-static test's `run` does: writes `scene` as `<name>.json` beside the
/// specimen file, runs it (outputs `<name>.out/`), analyses the history with `analyze` and
/// writes `<name>.result.json` there (atomically).
pub fn run_test<T: Clone + Serialize, R: Serialize>(
    name: &str,
    test: &T,
    scene: SceneFile,
    model: &LabModel,
    spec: &TestSpecimen,
    progress: &mut dyn FnMut(u64, u64),
    analyze: impl FnOnce(&Record) -> Result<R, LabError>,
) -> Result<Outcome<T, R>, LabError> {
    let dir = spec.file.parent().unwrap_or(Path::new("."));
    let r = run_scene(
        &scene,
        &dir.join(format!("{name}.json")),
        &RunOptions::default(),
        progress,
        None,
    )?;
    let out = Outcome {
        test: test.clone(),
        model: model.clone(),
        specimen: spec.clone(),
        result: analyze(&r.history)?,
        run: RunFacts::of(&r),
    };
    write_result(&dir.join(format!("{name}.result.json")), &out)?;
    Ok(out)
}

/// Writes `value` as pretty JSON to `path` atomically.
pub fn write_result<T: Serialize>(path: &Path, value: &T) -> Result<(), LabError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| LabError::Io {
        file: path.display().to_string(),
        source: std::io::Error::other(e),
    })?;
    write_atomic(path, text.as_bytes())?;
    Ok(())
}

/// Checks a length-like test parameter.
pub fn positive(test: &str, field: &str, v: f64) -> Result<f64, LabError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(LabError::Param {
            field: format!("{test}.{field}"),
            reason: format!("must be positive (got {v})"),
        })
    }
}

/// The fewest mean disc diameters across a lab test's resolving dimension (the compression
/// specimen's width and height, the Brazilian disc's diameter, the beam's height); the bound
/// and its source: [`crate::specimen::MIN_DIAMETERS_ACROSS`].
pub use crate::specimen::MIN_DIAMETERS_ACROSS;

/// `<test>.<field>`, a length `value` (m) that must span at least [`MIN_DIAMETERS_ACROSS`]
/// mean disc diameters 2 `r_mean`; `why` says what the test needs it for. The error names the
/// field, the value, the number of diameters, the bound and the reason.
pub fn diameters_across(
    test: &str,
    field: &str,
    value: f64,
    r_mean: f64,
    why: &str,
) -> Result<(), LabError> {
    let d = 2.0 * r_mean;
    let n = value / d;
    if n.is_finite() && n >= MIN_DIAMETERS_ACROSS {
        return Ok(());
    }
    Err(LabError::Param {
        field: format!("{test}.{field}"),
        reason: format!(
            "{:.4} mm is {n:.1} mean disc diameters ({:.4} mm); at least {MIN_DIAMETERS_ACROSS} \
             are needed {why} (resolution floor, docs/lab-tests.md; Potyondy & Cundall 2004, \
             Ding et al. 2014)",
            value * 1e3,
            d * 1e3
        ),
    })
}

/// `<test>.gauge_width` (in mean radii) of a position gauge: the band of half-width
/// `gauge_width` r̄ about its line must be at least one mean disc diameter wide (else it may hold
/// no disc centre), i.e. `gauge_width` ≥ 1.
pub fn gauge_holds_a_disc(test: &str, gauge_width: f64, r_mean: f64) -> Result<(), LabError> {
    if gauge_width >= 1.0 {
        return Ok(());
    }
    Err(LabError::Param {
        field: format!("{test}.gauge_width"),
        reason: format!(
            "{gauge_width} mean radii: a gauge band {:.4} mm wide is narrower than a mean disc \
             ({:.4} mm) and may hold no disc centre; at least 1",
            2.0 * gauge_width * r_mean * 1e3,
            2.0 * r_mean * 1e3
        ),
    })
}

/// An analysis error of `test`.
pub fn analysis_error(test: &str, reason: impl Into<String>) -> LabError {
    LabError::Analysis {
        test: test.into(),
        reason: reason.into(),
    }
}

/// The history's series of wall `name`, or an analysis error of `test` naming it.
pub fn wall_series<'a>(r: &'a Record, name: &str, test: &str) -> Result<&'a WallSeries, LabError> {
    found(r.wall(name), "wall", name, test)
}

/// The history's series of gauge `name`, or an analysis error of `test` naming it.
pub fn gauge_series<'a>(
    r: &'a Record,
    name: &str,
    test: &str,
) -> Result<&'a GaugeSeries, LabError> {
    found(r.gauge(name), "gauge", name, test)
}

/// The history's series of bond group `name`, or an analysis error of `test` naming it.
pub fn group_series<'a>(
    r: &'a Record,
    name: &str,
    test: &str,
) -> Result<&'a GroupSeries, LabError> {
    found(r.group(name), "bond group", name, test)
}

fn found<'a, T>(s: Option<&'a T>, kind: &str, name: &str, test: &str) -> Result<&'a T, LabError> {
    s.ok_or_else(|| analysis_error(test, format!("the history has no {kind} `{name}`")))
}

/// Element-wise sum of two series (kinetic = translation + rotation, and the like).
pub fn sum2(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(p, q)| p + q).collect()
}

/// A count series (broken bonds) as numbers.
pub fn counts(v: &[u64]) -> Vec<f64> {
    v.iter().map(|&c| c as f64).collect()
}

/// A parameter error of `test`'s `field` (`<test>.<field>`).
pub fn param(test: &str, field: &str, reason: impl Into<String>) -> LabError {
    LabError::Param {
        field: format!("{test}.{field}"),
        reason: reason.into(),
    }
}

/// `<test>.name`: a plain file stem (no folder).
pub fn plain_name(test: &str, name: &str) -> Result<(), LabError> {
    if name.is_empty() || name.contains(['/', '\\']) {
        return Err(LabError::Param {
            field: format!("{test}.name"),
            reason: "must be a plain file stem".into(),
        });
    }
    Ok(())
}

/// The checks every quasi-static test ends with: `<test>.name` a plain file stem, and the
/// loading (`<test>.loading.<field>`).
pub fn name_and_loading(test: &str, name: &str, loading: &Loading) -> Result<(), LabError> {
    plain_name(test, name)?;
    loading.validate(&format!("{test}.loading"))
}

/// `<test>.band`: a pre-peak band [lo, hi] of fractions of the peak, 0 ≤ lo < hi < 1.
pub fn prepeak_band(test: &str, [lo, hi]: [f64; 2]) -> Result<(), LabError> {
    if !(lo >= 0.0 && lo < hi && hi < 1.0) {
        return Err(LabError::Param {
            field: format!("{test}.band"),
            reason: format!("needs 0 ≤ lo < hi < 1 (got [{lo}, {hi}])"),
        });
    }
    Ok(())
}

/// `<test>.load_friction`: a finite coefficient ≥ 0 when given.
pub fn load_friction(test: &str, mu: Option<f64>) -> Result<(), LabError> {
    match mu {
        Some(mu) if !(mu.is_finite() && mu >= 0.0) => Err(LabError::Param {
            field: format!("{test}.load_friction"),
            reason: format!("{mu} must be a finite coefficient ≥ 0"),
        }),
        _ => Ok(()),
    }
}

/// Each platen's travel to the estimated failure of a specimen `length` long (m) along the
/// loading axis, both platens closing: ε_f L/2 ([`failure_strain_estimate`]).
pub fn platen_failure_travel(model: &LabModel, length: f64) -> f64 {
    0.5 * length * failure_strain_estimate(model)
}

/// Platen speed (each, m/s) on a specimen `length` long (m) along the loading axis: the given
/// one, else the quasi-static rule over the travel [`platen_failure_travel`] and the P-wave
/// transit time of `length` ([`transit_time`]).
pub fn platen_speed(loading: &Loading, model: &LabModel, length: f64) -> f64 {
    loading.speed_for(
        platen_failure_travel(model, length),
        transit_time(model, length),
    )
}

/// Two flat platens `bottom` (at `y0`) and `top` (at `y1`) from x = `xa` to `xb` (m), closing
/// at `v` (m/s) each.
pub fn platens(xa: f64, xb: f64, y0: f64, y1: f64, v: f64) -> Vec<WallSpec> {
    vec![
        wall("bottom", [xa, y0], [xb, y0], [0.0, v]),
        wall("top", [xa, y1], [xb, y1], [0.0, -v]),
    ]
}

impl Loading {
    /// [`Loading::scene_fields`] of the two-platen tests: stop after the peak of the `top`
    /// platen's y force.
    pub fn platen_fields(
        &self,
        scene: &mut SceneFile,
        speed: f64,
        u_fail: f64,
        min_load: f64,
        gauges: Vec<GaugeSpec>,
    ) {
        self.scene_fields(
            scene,
            speed,
            u_fail,
            &["top".into()],
            AxisName::Y,
            min_load,
            gauges,
        );
    }
}

/// The mean platen force per history row, 0.5 (F_top − F_bottom) (N): discs push the top platen
/// up (+y) and the bottom one down. Errors name `test`.
pub fn platen_load(t: &Record, test: &str) -> Result<Vec<f64>, LabError> {
    let top = &wall_series(t, "top", test)?.fy;
    let bottom = &wall_series(t, "bottom", test)?.fy;
    Ok(top.iter().zip(bottom).map(|(a, b)| 0.5 * (a - b)).collect())
}

/// At least 10 history rows, else an analysis error of `test`.
pub fn enough_rows(t: &Record, test: &str) -> Result<(), LabError> {
    if t.time.len() < 10 {
        return Err(analysis_error(
            test,
            format!("{} history rows: too few", t.time.len()),
        ));
    }
    Ok(())
}

/// The row and value of the peak of `load` (the `what` of `test`: `load`, `axial load`) if the
/// specimen failed: the peak is positive and the load fell below 95 % of it by the end. `none`:
/// the error when `load` has no peak.
pub fn failure_peak(
    test: &str,
    load: &[f64],
    what: &str,
    none: &str,
) -> Result<(usize, f64), LabError> {
    let (ip, f) = crate::analysis::peak(load).ok_or_else(|| analysis_error(test, none))?;
    let last = *load.last().unwrap_or(&0.0);
    if f <= 0.0 || last > 0.95 * f {
        return Err(analysis_error(
            test,
            format!(
                "no failure: the {what} was still {:.3} of its peak at the end; raise loading.max_travel_factor",
                last / f
            ),
        ));
    }
    Ok((ip, f))
}

/// The rows of `series` in its pre-peak `band` ([`crate::analysis::prepeak_band`]), at least 5,
/// else an analysis error of `test` (`named`: the band's bounds in the message).
pub fn band_rows(
    test: &str,
    series: &[f64],
    [lo, hi]: [f64; 2],
    named: bool,
) -> Result<Vec<usize>, LabError> {
    let band = crate::analysis::prepeak_band(series, lo, hi);
    if band.len() < 5 {
        let which = if named {
            format!(" {lo}-{hi}")
        } else {
            String::new()
        };
        return Err(analysis_error(
            test,
            format!(
                "{} history rows in the{which} pre-peak band: lower loading.history_every or the speed",
                band.len()
            ),
        ));
    }
    Ok(band)
}

/// The compression tests' (UCS, biaxial) strains per row: axial ε_a = 2 v t / h from the platen
/// gap (platens at `v` each, specimen height `h`), lateral ε_l = Δs/s₀ from the mean-centre
/// spacing s of the `left` and `right` gauges. Errors name `test`.
pub fn compression_strains(
    t: &Record,
    test: &str,
    v: f64,
    h: f64,
) -> Result<(Vec<f64>, Vec<f64>), LabError> {
    let left = &gauge_series(t, "left", test)?.x;
    let right = &gauge_series(t, "right", test)?.x;
    let axial: Vec<f64> = t.time.iter().map(|t| 2.0 * v * t / h).collect();
    let s0 = right[0] - left[0];
    let lateral: Vec<f64> = (left.iter().zip(right))
        .map(|(l, r)| (r - l - s0) / s0)
        .collect();
    Ok((axial, lateral))
}

/// The lateral gauges `left` and `right` of the compression tests: bands of half-width `g` (m)
/// about the sides x0 and x1 of the specimen's extent [x0, y0, x1, y1].
pub fn side_gauges([x0, y0, x1, y1]: [f64; 4], g: f64) -> Vec<GaugeSpec> {
    vec![
        gauge("left", [x0 - g, y0 - g, x0 + g, y1 + g]),
        gauge("right", [x1 - g, y0 - g, x1 + g, y1 + g]),
    ]
}

/// `e` with its field renamed by `rename` if it is a parameter error (a test that checks
/// another's parameters names its own fields: `ucs.width` → `biaxial.width`).
pub fn renamed(e: LabError, rename: impl Fn(&str) -> String) -> LabError {
    match e {
        LabError::Param { field, reason } => LabError::Param {
            field: rename(&field),
            reason,
        },
        e => e,
    }
}

/// Fixtures of the tests' unit tests: a Si3N4-like model and a specimen record.
#[cfg(test)]
pub(crate) mod fixtures {
    use crate::specimen::cache::TestSpecimen;
    use crate::specimen::{Method, SpecimenParams};
    use crate::LabModel;

    /// The model of a traditional `w` × `h` (m) specimen, radii 0.10–0.15 mm, 3200 kg/m³,
    /// E = 310 GPa, σ_t = 800 MPa, seed 1.
    pub fn model(w: f64, h: f64) -> LabModel {
        let p = SpecimenParams::new(
            Method::Traditional,
            w,
            h,
            0.1e-3,
            0.15e-3,
            3200.0,
            310e9,
            800e6,
            1,
        );
        LabModel::from_params(&p)
    }

    /// A specimen `file` of `w` × `h` (m) at the origin, mean radius 0.125 mm.
    pub fn specimen(file: &str, w: f64, h: f64, discs: usize, bonds: usize) -> TestSpecimen {
        TestSpecimen {
            file: file.into(),
            extent: [0.0, 0.0, w, h],
            discs,
            bonds,
            r_mean: 0.125e-3,
            reused: false,
            below_cover: vec![],
        }
    }
}
