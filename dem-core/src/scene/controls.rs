//! Run control, outputs and the periodic box of a scene file → their checked SI form.

use super::check::{dir_of, Ck};
use super::model::{Gauge, Outputs, Run, Stop, StopAfterPeak, WallInit};
use super::schema::{AxisName, OutputSpec, PeriodicSpec, RunSpec};
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

pub(crate) fn run(
    ck: &Ck,
    r: &RunSpec,
    u: f64,
    walls: &[WallInit],
    outputs: &OutputSpec,
) -> Result<Run, SceneError> {
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
        mass_scaling: r
            .mass_scaling
            .map(|v| ck.range("run.mass_scaling", v, 0.0, 0.5, true))
            .transpose()?,
        stop_after_peak: r
            .stop_after_peak
            .as_ref()
            .map(|s| stop_after_peak(ck, s, walls, outputs))
            .transpose()?,
    })
}

fn stop_after_peak(
    ck: &Ck,
    s: &super::schema::StopAfterPeakSpec,
    walls: &[WallInit],
    outputs: &OutputSpec,
) -> Result<StopAfterPeak, SceneError> {
    if s.walls.is_empty() {
        return Err(ck.err("run.stop_after_peak.walls", "name at least one wall"));
    }
    let mut idx = Vec::with_capacity(s.walls.len());
    for (k, name) in s.walls.iter().enumerate() {
        let i = walls.iter().position(|w| &w.name == name).ok_or_else(|| {
            ck.err(
                format!("run.stop_after_peak.walls[{k}]"),
                format!("no wall named {name:?}"),
            )
        })?;
        idx.push(i);
    }
    let below = ck.range("run.stop_after_peak.below", s.below, 0.0, 1.0, false)?;
    if below <= 0.0 {
        return Err(ck.err("run.stop_after_peak.below", "must be in (0, 1)"));
    }
    if outputs.history_every == 0 {
        return Err(ck.err(
            "run.stop_after_peak",
            "is checked at history rows: set outputs.history_every > 0",
        ));
    }
    Ok(StopAfterPeak {
        walls: idx,
        axis: match s.axis {
            AxisName::X => 0,
            AxisName::Y => 1,
        },
        below,
        min_load: ck.non_negative("run.stop_after_peak.min_load", s.min_load)?,
    })
}

pub(crate) fn outputs(
    ck: &Ck,
    scene_path: &Path,
    o: &OutputSpec,
    u: f64,
) -> Result<Outputs, SceneError> {
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
    if o.vtk_count > 0 && o.vtk_every > 0 {
        return Err(ck.err(
            "outputs.vtk_count",
            "give vtk_every (a snapshot every N steps) or vtk_count (N over the run), not both",
        ));
    }
    let mut gauges: Vec<Gauge> = Vec::with_capacity(o.gauges.len());
    for (i, g) in o.gauges.iter().enumerate() {
        let f = |k: &str| format!("outputs.gauges[{i}].{k}");
        if g.name.is_empty() || crate::output::history::column_name(&g.name) != g.name {
            return Err(ck.err(
                f("name"),
                format!("{:?}: use letters, digits, `_`, `-`, `.`", g.name),
            ));
        }
        if gauges.iter().any(|q| q.name == g.name) {
            return Err(ck.err(f("name"), format!("gauge {:?} is defined twice", g.name)));
        }
        let mut r = [0.0; 4];
        for (k, v) in g.region.iter().enumerate() {
            r[k] = ck.finite(&format!("{}[{k}]", f("region")), *v)? * u;
        }
        if r[2] <= r[0] || r[3] <= r[1] {
            return Err(ck.err(
                f("region"),
                "needs [x0, y0, x1, y1] with x1 > x0 and y1 > y0",
            ));
        }
        gauges.push(Gauge {
            name: g.name.clone(),
            region: r,
        });
    }
    Ok(Outputs {
        gauges,
        dir,
        history_every: o.history_every,
        vtk_every: o.vtk_every,
        vtk_count: o.vtk_count,
        vtk_format: o.vtk_format,
        checkpoint_every: o.checkpoint_every,
        checkpoint_keep: o.checkpoint_keep,
        checkpoints: o.checkpoints,
        checkpoint_format: o.checkpoint_format,
        guard_every: o.guard_every,
        summary: o.summary,
    })
}
