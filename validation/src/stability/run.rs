//! Running one case: write its files, load the scene file back as `dem run` would, step it with
//! the guard and the samples, and (for the forced case) run it once more through the output
//! driver to check that nothing non-finite is written.

use super::{CaseRecord, CaseSpec, Expect, Probe2x, StabilityError, Verdict};
use dem_core::output::driver::{RunError, RunOptions, Simulation};
use dem_core::scene::model::{Scene, Stop};
use dem_core::{State, World};
use std::path::Path;
use std::time::Instant;

fn io(file: &Path, source: std::io::Error) -> StabilityError {
    StabilityError::Io {
        file: file.display().to_string(),
        source,
    }
}

/// Running maxima and minima sampled during a run.
struct Samples {
    /// Largest |balance_error| as the engine reports it (relative to the largest energy term
    /// at that instant).
    balance: f64,
    /// Largest absolute balance error (J) and largest energy term (J) over the run.
    abs_err: f64,
    scale: f64,
    overlap: f64,
    dt: [f64; 2],
    crit: f64,
}

impl Samples {
    fn new() -> Samples {
        Samples {
            balance: 0.0,
            abs_err: 0.0,
            scale: 0.0,
            overlap: 0.0,
            dt: [f64::INFINITY, 0.0],
            crit: f64::INFINITY,
        }
    }

    fn observe_dt(&mut self, w: &World) {
        self.dt = [self.dt[0].min(w.dt()), self.dt[1].max(w.dt())];
        self.crit = self.crit.min(w.critical_dt());
    }

    /// Samples the world after at least one step. The balance terms are those of
    /// `dem_core::energy::EnergyReport::new`: error = E_now + dissipated + released − E₀ − W,
    /// scale = max(|E₀|, |E_now|, dissipated, |W|).
    /// `overlap`: the deepest overlap the guard measured on this state.
    fn observe(&mut self, w: &World, overlap: f64) {
        let e = w.energy();
        self.balance = self.balance.max(e.balance_error.abs());
        let dissipated = e.damping + e.friction;
        let err = e.total + dissipated + e.bond_break - e.initial - e.boundary_work;
        let scale = e
            .initial
            .abs()
            .max(e.total.abs())
            .max(dissipated)
            .max(e.boundary_work.abs());
        self.abs_err = self.abs_err.max(err.abs());
        self.scale = self.scale.max(scale);
        self.overlap = self.overlap.max(overlap);
    }

    /// Largest absolute balance error over the largest energy term of the run.
    fn run_balance(&self) -> f64 {
        if self.scale > 0.0 {
            self.abs_err / self.scale
        } else {
            0.0
        }
    }
}

/// Every kinematic and force value of the state is finite.
pub fn state_finite(st: &State) -> bool {
    let d = &st.discs;
    let c = &st.clumps;
    [
        &d.x, &d.y, &d.theta, &d.vx, &d.vy, &d.omega, &d.fx, &d.fy, &d.torque,
    ]
    .iter()
    .all(|v| v.iter().all(|x| x.is_finite()))
        && [&c.x, &c.y, &c.theta, &c.vx, &c.vy, &c.omega]
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()))
}

/// Writes the case's files, loads its scene file, runs it; `out` is the suite's output folder
/// (scene paths in the record are relative to it).
pub fn run_case(spec: &CaseSpec, dir: &Path, out: &Path) -> Result<CaseRecord, StabilityError> {
    let file = spec.write(dir)?;
    let scene = dem_core::scene::load(&file)?;
    let planned = match scene.run.stop {
        Stop::Steps(n) => n,
        Stop::Duration(_) => {
            return Err(StabilityError::Setup {
                case: spec.name.clone(),
                reason: "the suite's scenes give a step count".into(),
            })
        }
    };
    let mut w = dem_core::scene::build(&scene)?;
    let bonds0 = w.bonds.as_ref().map_or(0, |b| b.n_intact());
    let t0 = Instant::now();
    let mut s = Samples::new();
    let mut guard_message = None;
    let mut finite = true;
    s.observe_dt(&w);
    w.guard().map_err(|e| StabilityError::Setup {
        case: spec.name.clone(),
        reason: format!("the initial state fails the guard: {e}"),
    })?;
    while w.state.step < planned {
        w.run(spec.sample_every.min(planned - w.state.step));
        s.observe_dt(&w);
        match w.guard() {
            Ok(overlap) => s.observe(&w, overlap),
            Err(e) => {
                guard_message = Some(e.to_string());
                finite = w.last_good().is_some_and(state_finite);
                break;
            }
        }
    }
    let wall_time_s = t0.elapsed().as_secs_f64();
    let broken = w.bonds.as_ref().map_or(0, |b| bonds0 - b.n_intact());
    let stable = guard_message.is_none() && state_finite(&w.state) && s.run_balance() < spec.bound;
    let outputs_finite = match spec.expect {
        Expect::Stable => None,
        Expect::Caught => Some(finite && driver_outputs_finite(&file)?),
    };
    let at_2x = match spec.expect {
        Expect::Stable => Some(probe_2x(&scene, planned.min(PROBE_STEPS), spec.bound)?),
        Expect::Caught => None,
    };
    let passed = match spec.expect {
        Expect::Stable => stable,
        Expect::Caught => guard_message.is_some() && outputs_finite == Some(true),
    };
    Ok(CaseRecord {
        name: spec.name.clone(),
        stresses: spec.stresses.clone(),
        scene_file: file
            .strip_prefix(out)
            .unwrap_or(&file)
            .display()
            .to_string(),
        discs: w.state.discs.len(),
        rigid_clumps: w.state.clumps.len(),
        bonds: bonds0,
        dt_factor: scene.run.dt.is_none().then_some(w.params.dt_factor),
        dt_min_s: s.dt[0].min(s.dt[1]),
        dt_max_s: s.dt[1],
        critical_dt_s: s.crit,
        steps: w.state.step,
        steps_planned: planned,
        simulated_time_s: w.state.time,
        wall_time_s,
        max_balance_error: s.balance,
        balance_error_run: s.run_balance(),
        balance_bound: spec.bound,
        sample_every: spec.sample_every,
        max_overlap_fraction: s.overlap,
        bonds_broken: broken,
        expected: spec.expect,
        verdict: if stable {
            Verdict::Stable
        } else {
            Verdict::Unstable
        },
        guard_message,
        outputs_finite,
        at_2x,
        passed,
    })
}

/// Runs the scene as `dem run` does (output driver, outputs into `<scene stem>.out`); expects
/// the guard to stop it, then checks the files it wrote: `last-good-state.json` reloads as a
/// state whose values are all finite, and every number in `history.csv` is finite.
fn driver_outputs_finite(file: &Path) -> Result<bool, StabilityError> {
    let scene = dem_core::scene::load(file)?;
    let mut sim =
        Simulation::new(scene, &RunOptions::default()).map_err(|e| StabilityError::Setup {
            case: file.display().to_string(),
            reason: e.to_string(),
        })?;
    let out = sim.out_dir().to_path_buf();
    match sim.run(&mut |_, _| {}) {
        Err(RunError::Guard { .. }) => {}
        Ok(_) => return Ok(false),
        Err(e) => {
            return Err(StabilityError::Setup {
                case: file.display().to_string(),
                reason: e.to_string(),
            })
        }
    }
    let good = out.join("last-good-state.json");
    let text = std::fs::read_to_string(&good).map_err(|e| io(&good, e))?;
    let Ok(st) = serde_json::from_str::<State>(&text) else {
        return Ok(false);
    };
    let hist = out.join("history.csv");
    let rows = std::fs::read_to_string(&hist).map_err(|e| io(&hist, e))?;
    let numbers_finite = rows.lines().skip(1).all(|l| {
        l.split(',')
            .all(|f| f.trim().parse::<f64>().is_ok_and(f64::is_finite))
    });
    Ok(state_finite(&st) && numbers_finite)
}

/// Steps of the 2× probe (or the case's step count when smaller).
pub const PROBE_STEPS: u64 = 5000;

/// Re-runs a case at a fixed step of 2× its critical step (as built), the guard every 10 steps:
/// does the guard stop it, and is the energy balance error of the run above the bound?
fn probe_2x(scene: &Scene, steps: u64, bound: f64) -> Result<Probe2x, StabilityError> {
    let mut w = dem_core::scene::build(scene)?;
    let crit = w.critical_dt();
    w.params.dt_fixed = Some(2.0 * crit);
    w.refresh();
    let mut s = Samples::new();
    let mut guard_message = w.guard().err().map(|e| e.to_string());
    while guard_message.is_none() && w.state.step < steps {
        w.run(10.min(steps - w.state.step));
        match w.guard() {
            Ok(overlap) => s.observe(&w, overlap),
            Err(e) => guard_message = Some(e.to_string()),
        }
    }
    let balance_error_run = s.run_balance();
    let detected_by = if guard_message.is_some() {
        "guard"
    } else if balance_error_run >= bound {
        "balance"
    } else {
        "none"
    };
    Ok(Probe2x {
        dt_s: w.dt(),
        critical_dt_s: crit,
        steps: w.state.step,
        guard_message,
        balance_error_run,
        detected_by: detected_by.into(),
    })
}
