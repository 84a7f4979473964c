//! Improved-ORC specimens (S0, Ye & Xu 2010): every grain cell of the tessellation
//! ([`super::grains`]) is filled with a clumpgen template (minimum-residual-area discs up to the
//! area cover, at most `template_max_discs`, masses solved so that the grain's mass, centroid and
//! inertia are exact), placed as a bonded clump ([`crate::bonded_clump`]: free discs carrying
//! the solved masses, intra-grain bonds in their own group, reference gaps of overlapping
//! members registered). The grains are then packed in the four walls by a wall servo to the
//! isotropic stress σ0 (PFC's servo, v = G (σ0 − σ), G = α A / (k_w N_c Δt), α = 0.5, speed
//! capped at 1e-4 r_min per step), since template radii cannot be scaled uniformly without
//! changing the grains.

use super::generator;
use super::grains::Grains;
use super::methods::{bond_groups, INTRA};
use super::relax::{self, DISC};
use super::{Progress, SpecimenError, SpecimenParams};
use crate::bond::Bonds;
use crate::bonded_clump::{place_bonded_clump_in, Placement};
use crate::state::State;
use crate::World;
use clumpgen::{make_template, ClumpParams, Length, Method, Outline, Template, Units};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Lower bound of the solved template masses as a fraction of the uniform-disc prior. The
/// clumpgen default (1e-3) can leave a disc 1000× lighter than its size says, which shrinks the
/// time step √(m/k) 30-fold; 0.2 keeps it within 2.2× (on 20 × 10 mm Si3N4 tessellations it
/// changed neither the disc counts nor the number of infeasible grains measurably).
pub const MASS_FLOOR: f64 = 0.2;

/// Figures of the template stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TemplateStats {
    pub grains: usize,
    pub discs_min: usize,
    pub discs_max: usize,
    pub discs_mean: f64,
    /// Mean area cover A_r of the templates.
    pub cover_mean: f64,
    /// Σ of the exact areas of the disc unions of all grains (m²).
    pub union_area: f64,
    /// Largest relative residual of the mass fit over all grains.
    pub max_residual: f64,
    /// Grains that needed r_min halved (once or twice) to be filled.
    pub r_min_reduced: usize,
}

/// Template of one grain cell; r_min is halved (up to twice) when the cell is too small.
fn cell_template(
    gi: usize,
    cell: &[[f64; 2]],
    p: &SpecimenParams,
) -> Result<(Template, bool), SpecimenError> {
    let size = cell
        .iter()
        .map(|q| q[0].abs().max(q[1].abs()))
        .fold(0.0, f64::max);
    let mut pts: Vec<[f64; 2]> = Vec::with_capacity(cell.len());
    for &q in cell {
        let dup = |a: &[f64; 2]| (a[0] - q[0]).abs().max((a[1] - q[1]).abs()) <= 1e-12 * size;
        if !pts.last().is_some_and(dup) {
            pts.push(q);
        }
    }
    while pts.len() > 1 && (pts[0][0] - pts[pts.len() - 1][0]).abs() <= 1e-12 * size {
        if (pts[0][1] - pts[pts.len() - 1][1]).abs() > 1e-12 * size {
            break;
        }
        pts.pop();
    }
    let outline = Outline {
        name: format!("grain-{gi}"),
        source: format!("voronoi cell {gi}"),
        sha256: String::new(),
        units: Units::M,
        origin: [0.0, 0.0],
        points: pts,
        warnings: Vec::new(),
    };
    let mut r_min = p.template_r_min;
    let mut attempt = 0;
    loop {
        let cp = ClumpParams {
            method: Method::Improved,
            density: p.density,
            thickness: p.thickness,
            cover: p.template_cover,
            r_min: Length::Metres(r_min),
            r_max: Length::Metres(p.template_r_max),
            max_discs: p.template_max_discs,
            raster: 64,
            mass_floor: MASS_FLOOR,
            tolerance: 1e-10,
            max_repairs: 8,
        };
        match make_template(&outline, &cp) {
            Ok(t) => return Ok((t, attempt > 0)),
            Err(e) => {
                if attempt >= 2 {
                    return Err(SpecimenError::Template {
                        grain: gi,
                        source: e,
                    });
                }
                attempt += 1;
                r_min *= 0.5;
            }
        }
    }
}

/// Templates for every cell (in parallel, collected in cell order), placed as bonded clumps in
/// the box walls. Returns the world (bond groups of [`bond_groups`], intra bonds installed),
/// the registered contact offsets and the template figures.
#[allow(clippy::type_complexity)]
pub fn build(
    p: &SpecimenParams,
    g: &Grains,
    progress: &mut dyn FnMut(Progress),
) -> Result<(World, Vec<(u32, u32, f64)>, TemplateStats), SpecimenError> {
    let n = g.cells.len();
    let mut templates = Vec::with_capacity(n);
    let chunk = 32;
    for lo in (0..n).step_by(chunk) {
        let hi = (lo + chunk).min(n);
        let part: Vec<Result<(Template, bool), SpecimenError>> = (lo..hi)
            .into_par_iter()
            .map(|gi| cell_template(gi, &g.cells[gi], p))
            .collect();
        for t in part {
            templates.push(t?);
        }
        progress(Progress {
            stage: "templates",
            fraction: hi as f64 / n.max(1) as f64,
            message: format!("{hi} of {n} grains"),
        });
    }
    let mut st = State {
        thickness: p.thickness,
        walls: relax::box_walls(p.width, p.height),
        ..State::default()
    };
    let mut bonds = Bonds::new(bond_groups(p))?;
    let mut offsets = Vec::new();
    let mut ts = TemplateStats {
        grains: n,
        discs_min: usize::MAX,
        ..TemplateStats::default()
    };
    for (gi, (t, reduced)) in templates.iter().enumerate() {
        let [cx, cy] = t.source.centroid_m;
        let placed = place_bonded_clump_in(
            &mut st,
            &mut bonds,
            t,
            &Placement {
                x: cx,
                y: cy,
                angle: 0.0,
                material: DISC,
                grain: gi as u32,
                intra_group: INTRA,
                touch_tol: 0.0,
            },
        )?;
        offsets.extend(placed.offsets);
        let k = t.discs.len();
        ts.discs_min = ts.discs_min.min(k);
        ts.discs_max = ts.discs_max.max(k);
        ts.discs_mean += k as f64;
        ts.cover_mean += t.cover.value;
        ts.union_area += t.cover.union_area;
        ts.max_residual = ts.max_residual.max(t.residuals.max());
        ts.r_min_reduced += *reduced as usize;
    }
    if n > 0 {
        ts.discs_mean /= n as f64;
        ts.cover_mean /= n as f64;
    }
    let mut w = World::try_new(st, relax::params(), relax::laws(p, 0.0))?;
    let nd = w.state.discs.len();
    let new_of_old: Vec<u32> = (0..nd as u32)
        .map(|id| w.index_of_id(id).map_or(u32::MAX, |k| k as u32))
        .collect();
    bonds.remap(&new_of_old);
    w.bonds = Some(bonds);
    for &(a, b, g0) in &offsets {
        w.set_contact_offset(a, b, g0);
    }
    w.refresh();
    Ok((w, offsets, ts))
}

/// Move the four walls along their normals until each carries σ0 (within the tolerance) with
/// the assembly in equilibrium (PFC's servo, v = G (σ0 − σ), G = α A / (k_w N_c Δt),
/// α = 0.5, speed capped at 1e-4 r_min per step). Returns the steps taken.
#[allow(clippy::manual_is_multiple_of)] // rust-version 1.80
pub fn wall_servo(
    w: &mut World,
    p: &SpecimenParams,
    progress: &mut dyn FnMut(Progress),
) -> Result<u64, SpecimenError> {
    let s0 = p.iso_stress;
    let kw = 2.0 * p.thickness * p.micro.contact_modulus * p.micro.wall_stiffness_factor;
    let r_min = w
        .state
        .discs
        .r
        .iter()
        .cloned()
        .fold(f64::INFINITY, f64::min);
    // (name, axis, inward direction)
    let walls = [
        ("left", 0usize, 1.0f64),
        ("right", 0, -1.0),
        ("bottom", 1, 1.0),
        ("top", 1, -1.0),
    ];
    let mut steps = 0u64;
    let mut counts = [0usize; 4];
    // Wall stresses averaged over ~100 steps (exponential moving average): the instantaneous
    // ones rattle with every impact.
    let mut ema = [0.0f64; 4];
    loop {
        let Some(b) = relax::box_of_walls(&w.state) else {
            return Ok(steps);
        };
        if steps % 50 == 0 {
            for (k, (name, _, _)) in walls.iter().enumerate() {
                counts[k] = w
                    .state
                    .walls
                    .iter()
                    .find(|x| x.name == *name)
                    .map_or(0, |wall| {
                        let d = &w.state.discs;
                        (0..d.len())
                            .filter(|&i| relax::disc_touches_wall(d.x[i], d.y[i], d.r[i], wall))
                            .count()
                    });
            }
        }
        let dt = w.dt();
        let vmax = 1e-4 * r_min / dt;
        let mut worst: f64 = 0.0;
        for (k, (name, axis, dir)) in walls.iter().enumerate() {
            let len = if *axis == 0 { b[3] - b[2] } else { b[1] - b[0] };
            let Some(wall) = w.state.walls.iter_mut().find(|x| x.name == *name) else {
                continue;
            };
            let sigma = -dir * wall.force[*axis] / (len * p.thickness);
            ema[k] += 0.01 * (sigma - ema[k]);
            let err = s0 - sigma;
            worst = worst.max((s0 - ema[k]).abs() / s0);
            let gain = 0.5 * len * p.thickness / (kw * counts[k].max(1) as f64 * dt);
            let v = if counts[k] == 0 && err > 0.0 {
                vmax
            } else {
                (gain * err).clamp(-vmax, vmax)
            };
            wall.v = [0.0; 2];
            wall.v[*axis] = dir * v;
        }
        if steps % 500 == 0 {
            progress(Progress {
                stage: "servo",
                fraction: (steps as f64 / p.max_stage_steps as f64).min(1.0),
                message: format!(
                    "largest wall stress error {:.1} %, box {:.4} x {:.4} mm",
                    100.0 * worst,
                    (b[1] - b[0]) * 1e3,
                    (b[3] - b[2]) * 1e3,
                ),
            });
        }
        if worst <= 0.5 * p.iso_tolerance && steps % 100 == 0 {
            // Close: hold the walls, let the assembly settle roughly (ratio 1e-2; the bonded
            // specimen is relaxed fully later), and accept if σ0 holds there.
            for wall in &mut w.state.walls {
                wall.v = [0.0; 2];
            }
            let rest = generator::rest_energy(w, p);
            steps += relax::to_equilibrium(w, "servo", 1e-2, rest, p.max_stage_steps, progress)?;
            let s = relax::wall_stress(&w.state);
            if s.iter().all(|&x| (x - s0).abs() <= p.iso_tolerance * s0) {
                return Ok(steps);
            }
            ema = [0.5 * (s[0] + s[1]); 4];
        }
        if steps >= p.max_stage_steps {
            return Err(SpecimenError::NoConvergence {
                stage: "servo",
                steps,
                detail: format!("largest wall stress error {:.1} %", 100.0 * worst),
            });
        }
        w.step();
        steps += 1;
    }
}
