//! Run control, outputs and the periodic box of a scene file → their checked SI form.

use super::check::{dir_of, Ck};
use super::model::{Outputs, Run, Stop};
use super::schema::{OutputSpec, PeriodicSpec, RunSpec};
use super::SceneError;
use crate::state::Periodic;
use std::path::Path;

pub(crate) fn periodic(
    ck: &Ck,
    raw: Option<&PeriodicSpec>,
    u: f64,
) -> Result<Periodic, SceneError> {
    let mut p = Periodic::default();
    let Some(raw) = raw else { return Ok(p) };
    for (axis, (name, r)) in [("x", raw.x), ("y", raw.y)].into_iter().enumerate() {
        if let Some([lo, hi]) = r {
            let field = format!("periodic.{name}");
            let lo = ck.finite(&field, lo)? * u;
            let hi = ck.finite(&field, hi)? * u;
            if hi <= lo {
                return Err(ck.err(field, "needs [lo, hi] with hi > lo"));
            }
            p.lo[axis] = lo;
            p.length[axis] = Some(hi - lo);
        }
    }
    Ok(p)
}

pub(crate) fn run(ck: &Ck, r: &RunSpec, u: f64) -> Result<Run, SceneError> {
    let stop = match (r.duration, r.steps) {
        (Some(d), None) => Stop::Duration(ck.positive("run.duration", d)?),
        (None, Some(s)) => Stop::Steps(s),
        (Some(_), Some(_)) => return Err(ck.err("run.steps", "give duration or steps, not both")),
        (None, None) => return Err(ck.err("run", "needs duration (s) or steps")),
    };
    if r.dt.is_some() && r.dt_factor.is_some() {
        return Err(ck.err(
            "run.dt",
            "give dt (fixed) or dt_factor (automatic), not both",
        ));
    }
    Ok(Run {
        stop,
        dt_factor: r
            .dt_factor
            .map(|f| ck.range("run.dt_factor", f, 0.0, 1.0, true))
            .transpose()?,
        dt: r.dt.map(|d| ck.positive("run.dt", d)).transpose()?,
        max_steps: r.max_steps,
        skin: r
            .skin
            .map(|v| ck.positive("run.skin", v).map(|v| v * u))
            .transpose()?,
        max_overlap_fraction: r
            .max_overlap_fraction
            .map(|v| ck.range("run.max_overlap_fraction", v, 0.0, 1.0, true))
            .transpose()?,
        max_energy_growth: r
            .max_energy_growth
            .map(|v| ck.positive("run.max_energy_growth", v))
            .transpose()?,
    })
}

pub(crate) fn outputs(ck: &Ck, scene_path: &Path, o: &OutputSpec) -> Result<Outputs, SceneError> {
    let dir = match &o.dir {
        Some(d) => dir_of(scene_path).join(d),
        None => {
            let stem = scene_path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into());
            dir_of(scene_path).join(format!("{stem}.out"))
        }
    };
    if o.guard_every == 0 {
        return Err(ck.err("outputs.guard_every", "must be at least 1"));
    }
    Ok(Outputs {
        dir,
        history_every: o.history_every,
        vtk_every: o.vtk_every,
        checkpoint_every: o.checkpoint_every,
        guard_every: o.guard_every,
        summary: o.summary,
    })
}
