//! What the compression, Brazilian and bending tests share: the quasi-static loading rule, the
//! run settings of a damped quasi-static scene, the facts of a finished run, and the atomic
//! result file.

use super::run::{run_scene, LabRun};
use super::specimens::TestSpecimen;
use super::{LabError, LabModel};
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
    /// Time-step safety factor (default [`DT_FACTOR`]).
    pub dt_factor: f64,
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
            dt_factor: DT_FACTOR,
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
        if !(self.dt_factor > 0.0 && self.dt_factor <= 1.0) {
            return bad("dt_factor", "must lie in (0, 1]");
        }
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
            dt_factor: Some(self.dt_factor),
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
        material: super::model::WALL_MATERIAL.into(),
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
