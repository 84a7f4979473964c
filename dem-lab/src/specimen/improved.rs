//! Improved-ORC specimens (S0, Ye & Xu 2010): every grain cell of the tessellation
//! ([`super::grains`]) is filled with a clumpgen template (minimum-residual-area discs up to the
//! area cover, at most `template_max_discs`, masses solved so that the grain's mass, centroid and
//! inertia are exact), placed as a bonded clump ([`dem_core::bonded_clump`]: free discs carrying
//! the solved masses, intra-grain bonds in their own group, reference gaps of overlapping
//! members registered). The grains are then packed in the four walls by a wall servo to the
//! isotropic stress σ0 (PFC's servo, v = G (σ0 − σ), G = α A / (k_w N_c Δt), α = 0.5, speed
//! capped at 1e-4 r_min per step), since template radii cannot be scaled uniformly without
//! changing the grains.

use super::generator;
use super::grains::Grains;
use super::groups::{bond_groups_with, INTRA};
use super::relax::{self, DISC};
use super::{Progress, SpecimenError, SpecimenParams};
use clumpgen::{make_template, ClumpParams, Length, Method, Outline, Template, Units};
use dem_core::bond::Bonds;
use dem_core::bonded_clump::{place_bonded_clump_in, Placement};
use dem_core::state::State;
use dem_core::World;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Lower bound of the solved template masses as a fraction of the uniform-disc prior. The
/// clumpgen default (1e-3) can leave a disc 1000× lighter than its size says, which shrinks the
/// time step √(m/k) 30-fold; 0.2 keeps it within 2.2× (on 20 × 10 mm Si3N4 tessellations it
/// changed neither the disc counts nor the number of infeasible grains measurably).
pub const MASS_FLOOR: f64 = 0.2;

/// Pre-compaction stress of the improved-ORC packing, in units of σ0.
pub const PRECOMPACTION: f64 = 100.0;

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
    /// Grains whose template stops below its cover target (issue 20: reported, never
    /// changed: the specimen is the same with or without this list). Left out of the JSON when
    /// empty, so the summaries of specimens whose grains all reach the cover are unchanged.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub below_cover: Vec<GrainCover>,
}

/// A grain whose template discs stop below the area cover asked for (`template_cover`): a
/// warning, not an error. The template still has exactly the grain's mass, centroid and
/// inertia (clumpgen's [`clumpgen::template::CoverShortfall`]); only its shape is coarser than
/// asked for. Its message names the grain, the cover reached, the target and the parameter
/// (with its `dem specimen` / `dem test` flag) that changes it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GrainCover {
    /// The grain's id in the specimen (the disc group of its members).
    pub grain: u32,
    /// Area cover A_r reached and asked for.
    pub cover: f64,
    pub target: f64,
    /// Template discs placed.
    pub discs: usize,
    /// Why the fill stopped: `max_discs` (the disc cap `template_max_discs` came first) or
    /// `no_room` (no place left for a disc of radius `r_min`).
    pub stop: clumpgen::fill::StopReason,
    /// The disc cap and the smallest disc radius (m) the fill ran with (r_min may be
    /// `template_r_min` halved once or twice when the grain was too small).
    pub max_discs: usize,
    pub r_min: f64,
}

impl GrainCover {
    /// The shortfall of `t`, the template of grain `grain`, if its cover is below its target.
    pub fn of(grain: u32, t: &Template) -> Option<GrainCover> {
        let s = t.cover_shortfall()?;
        Some(GrainCover {
            grain,
            cover: s.cover,
            target: s.target,
            discs: t.discs.len(),
            stop: s.stop,
            max_discs: s.max_discs,
            r_min: s.r_min,
        })
    }
}

impl std::fmt::Display for GrainCover {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "grain {}: cover {:.4} below the target {} with {} discs; ",
            self.grain, self.cover, self.target, self.discs
        )?;
        match self.stop {
            clumpgen::fill::StopReason::MaxDiscs => write!(
                f,
                "the fill stopped at the disc cap: raise template_max_discs (--max-discs, now {})",
                self.max_discs
            ),
            _ => write!(
                f,
                "no room is left for a disc of radius {:.4} mm: lower template_r_min \
                 (--template-r-min)",
                self.r_min * 1e3
            ),
        }
    }
}

impl TemplateStats {
    /// Count one grain's template (`reduced`: its r_min had to be reduced).
    pub fn add(&mut self, t: &Template, reduced: bool) {
        let k = t.discs.len();
        self.discs_min = if self.grains == 0 {
            k
        } else {
            self.discs_min.min(k)
        };
        self.grains += 1;
        self.discs_max = self.discs_max.max(k);
        self.discs_mean += k as f64;
        self.cover_mean += t.cover.value;
        self.union_area += t.cover.union_area;
        self.max_residual = self.max_residual.max(t.residuals.max());
        self.r_min_reduced += reduced as usize;
    }

    /// [`TemplateStats::add`] for grain `grain` of a specimen, noting the grain in
    /// [`TemplateStats::below_cover`] when its template stops below its cover target.
    pub fn add_grain(&mut self, grain: u32, t: &Template, reduced: bool) {
        self.add(t, reduced);
        self.below_cover.extend(GrainCover::of(grain, t));
    }

    /// Turn the sums of [`TemplateStats::add`] into means.
    pub fn finish(&mut self) {
        if self.grains > 0 {
            self.discs_mean /= self.grains as f64;
            self.cover_mean /= self.grains as f64;
        }
    }
}

/// Template of one grain cell; r_min is halved (up to twice) when the cell is too small.
fn cell_template(
    gi: usize,
    cell: &[[f64; 2]],
    p: &SpecimenParams,
) -> Result<(Template, bool), SpecimenError> {
    cell_template_with(gi, cell, p, MASS_FLOOR)
}

/// `cell_template` with another lower bound of the solved masses (a fraction of the
/// uniform-disc prior), for studies of the time step (`examples/template_dt.rs`). Returns the
/// template and whether r_min had to be reduced.
pub fn cell_template_with(
    gi: usize,
    cell: &[[f64; 2]],
    p: &SpecimenParams,
    mass_floor: f64,
) -> Result<(Template, bool), SpecimenError> {
    outline_template(gi, cell, format!("voronoi cell {gi}"), p, mass_floor)
}

/// Template of grain `gi` with the outline `cell` (m, in the box) described as `source`;
/// r_min is halved (up to twice) when the outline is too small. Returns the template and
/// whether r_min had to be reduced.
pub fn outline_template(
    gi: usize,
    cell: &[[f64; 2]],
    source: String,
    p: &SpecimenParams,
    mass_floor: f64,
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
        source,
        sha256: String::new(),
        units: Units::M,
        origin: [0.0, 0.0],
        points: pts,
        warnings: Vec::new(),
        grain: None,
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
            mass_floor,
            tolerance: 1e-10,
            max_repairs: 8,
            // A specimen's seed must give the specimen its run keys were made with: no rescue
            // of failed fits (it would turn some failed or retried templates into others).
            rescue: false,
            lattice: None,
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
/// the box walls. Returns the world (bond groups of [`super::methods::bond_groups`], intra bonds installed),
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
    let mut bonds = Bonds::new(bond_groups_with(p, true))?;
    let mut offsets = Vec::new();
    let mut ts = TemplateStats::default();
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
        ts.add_grain(gi as u32, t, *reduced);
    }
    ts.finish();
    let w = dem_core::bond::attach::world_with_bonds(
        st,
        relax::params(),
        relax::laws(p, 0.0),
        bonds,
        &offsets,
    )?;
    Ok((w, offsets, ts))
}

/// Pack the grains to the isotropic stress σ0: affine contraction of the grain mass centres
/// and of the walls about the box centre (x ↦ c + (x − c)/(1 + ε), for the gaps between
/// grains the same as a radius growth ε, while every grain keeps its template), driven by the
/// stress servo [`generator::servo_with`]: first to [`PRECOMPACTION`] × σ0 (±50 %), then down
/// to σ0. At σ0 alone (~1e-5 E) the frictionless grains keep flowing into the gaps left by the
/// templates' cover for millions of steps; under the higher stress they settle at once, and
/// the unloading is nearly elastic (the same path the disc packing takes from its jammed
/// state). Returns the steps taken.
pub fn compact(
    w: &mut World,
    p: &SpecimenParams,
    progress: &mut dyn FnMut(Progress),
) -> Result<u64, SpecimenError> {
    let high = PRECOMPACTION * p.iso_stress;
    let mut steps = generator::servo_with(w, p, high, 0.5, progress, |w, eps| {
        contract(w, 1.0 / (1.0 + eps))
    })?;
    steps += compact_to(w, p, p.iso_stress, progress)?;
    Ok(steps)
}

/// The servo of [`compact`] to the stress `s0` alone (tolerance `iso_tolerance`). Returns the
/// steps taken.
pub fn compact_to(
    w: &mut World,
    p: &SpecimenParams,
    s0: f64,
    progress: &mut dyn FnMut(Progress),
) -> Result<u64, SpecimenError> {
    generator::servo_with(w, p, s0, p.iso_tolerance, progress, |w, eps| {
        contract(w, 1.0 / (1.0 + eps))
    })
}

/// Scale grain mass-centre positions and the walls by `f` about the centre of the walls' box.
fn contract(w: &mut World, f: f64) {
    let Some(b) = relax::box_of_walls(&w.state) else {
        return;
    };
    let c = [0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])];
    let d = &mut w.state.discs;
    let mut acc: std::collections::BTreeMap<u32, [f64; 3]> = Default::default();
    for k in 0..d.len() {
        let e = acc.entry(d.group[k]).or_default();
        e[0] += d.m[k] * d.x[k];
        e[1] += d.m[k] * d.y[k];
        e[2] += d.m[k];
    }
    for k in 0..d.len() {
        let e = acc[&d.group[k]];
        let (gx, gy) = (e[0] / e[2], e[1] / e[2]);
        d.x[k] += (f - 1.0) * (gx - c[0]);
        d.y[k] += (f - 1.0) * (gy - c[1]);
    }
    for wall in &mut w.state.walls {
        for q in [&mut wall.a, &mut wall.b, &mut wall.center] {
            q[0] = c[0] + f * (q[0] - c[0]);
            q[1] = c[1] + f * (q[1] - c[1]);
        }
    }
    w.refresh();
}
