//! S1 step (2): discs packed in the annulus to a target porosity n = 1 − S_discs/S_annulus.
//!
//! Radii are drawn uniformly in [r_min, r_max] until their full-size area reaches
//! (1 − n_target)·S; the discs are placed at random at half size without overlap, clear of both
//! walls (random sequential addition, as PFC and S4 do, Potyondy & Cundall 2004 §3.1). Then
//! S1's rule: with n_current the porosity of the discs as they are, every radius is multiplied
//! by m = √((1 − n_target)/(1 − n_current)), in ×1.005 increments of 40 steps each (a jump
//! would drive discs into each other), and the assembly is cycled to equilibrium
//! (frictionless, local damping 0.7; unbalanced-force ratio ≤ 1e-2, or at most
//! `max_stage_steps` steps). Discs that escaped the
//! annulus or have no neighbour within the bond gap (rattlers no bond would hold) are removed,
//! n_current measured again and the rule applied again, until |n − n_target| ≤ tolerance/2
//! with nothing removed (at most [`MAX_ROUNDS`] rounds).
//!
//! A target that cannot be reached is an error naming `porosity`: below the densest packing
//! of equal discs (1 − π/(2√3) = 0.0931) or at 0.5 and above, refused at once; otherwise when
//! the rounds do not converge, or when the packing at the target overlaps on average by more
//! than [`MAX_MEAN_OVERLAP`] of the mean radius (the discs squeezed, not packed).

use super::geometry::Walls;
use crate::specimen::relax;
use crate::specimen::rng::Rng;
use crate::LabError;
use dem_core::contact::{ContactLaws, ContactModel, LinearSpringDashpot};
use dem_core::state::{State, Wall};
use dem_core::World;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Unbalanced-force ratio counted as packed.
pub const EQ_TOL: f64 = 1e-2;
/// Most rounds of S1's radius rule.
pub const MAX_ROUNDS: usize = 8;
/// Mean overlap / mean radius above which a packing counts as squeezed.
pub const MAX_MEAN_OVERLAP: f64 = 0.02;
/// Densest packing of equal discs (hexagonal): porosity 1 − π/(2√3).
pub const HEXAGONAL_POROSITY: f64 = 1.0 - PI / (2.0 * 1.732_050_807_568_877_2);

/// What the packing needs (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct PackInput {
    pub r_min: f64,
    pub r_max: f64,
    pub porosity: f64,
    pub tolerance: f64,
    pub density: f64,
    pub thickness: f64,
    /// Disc contact normal stiffness k_n (N/m) and k_n/k_s.
    pub kn: f64,
    pub stiffness_ratio: f64,
    /// Largest gap a bond bridges (m).
    pub bond_gap: f64,
    pub seed: u64,
    /// Most steps of one equilibrium stage.
    pub max_stage_steps: u64,
}

/// Figures of the packing.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PackStats {
    pub discs_drawn: usize,
    /// Porosity of the discs as placed (at half size).
    pub porosity_placed: f64,
    /// S1's factor m of each round.
    pub factors: Vec<f64>,
    /// Discs removed (escaped or without a neighbour within the bond gap), all rounds.
    pub removed: usize,
    pub porosity_reached: f64,
    /// Mean overlap of touching pairs over the mean radius, and touching pairs per disc.
    pub mean_overlap_ratio: f64,
    pub coordination: f64,
    pub steps: u64,
}

/// Material index of the discs and walls during packing.
const DISC: u16 = 0;
const WALL: u16 = 1;

fn err(reason: String) -> LabError {
    LabError::Param {
        field: "porosity (--porosity)".into(),
        reason,
    }
}

/// The wall polylines as walls of material `material`.
pub fn wall_of(name: &str, v: &[[f64; 2]], material: u16) -> Wall {
    let mut w = Wall::new(name, v[0], v[v.len() - 1], material);
    w.via = v[1..v.len() - 1].to_vec();
    w.center = [0.0, 0.0];
    w
}

fn porosity(discs: &[[f64; 3]], area: f64) -> f64 {
    1.0 - discs.iter().map(|d| PI * d[2] * d[2]).sum::<f64>() / area
}

/// Packs the annulus `walls`; returns the discs `[x, y, r]` and the figures.
pub fn pack(
    walls: &Walls,
    p: &PackInput,
    progress: &mut dyn FnMut(&str),
) -> Result<(Vec<[f64; 3]>, PackStats), LabError> {
    if !(p.porosity > HEXAGONAL_POROSITY && p.porosity < 0.5) {
        return Err(err(format!(
            "{}: cannot be reached; a packed 2D disc assembly has a porosity between the \
             densest packing of equal discs, {HEXAGONAL_POROSITY:.4}, and 0.5",
            p.porosity
        )));
    }
    let mut rng = Rng::new(p.seed);
    let target = (1.0 - p.porosity) * walls.area;
    let mut radii = Vec::new();
    let mut a = 0.0;
    while a < target {
        let r = rng.range(p.r_min, p.r_max);
        a += PI * r * r;
        radii.push(r);
    }
    radii.sort_by(|a, b| b.total_cmp(a));
    let r_out = walls
        .outer
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0, f64::max);
    // Random sequential addition at half size on a grid of cells 2 r_max/2 wide.
    let cell = p.r_max;
    let nc = ((2.0 * r_out / cell).ceil() as usize).max(1);
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); nc * nc];
    let idx = |x: f64, y: f64| {
        (
            (((x + r_out) / cell) as usize).min(nc - 1),
            (((y + r_out) / cell) as usize).min(nc - 1),
        )
    };
    let mut discs: Vec<[f64; 3]> = Vec::with_capacity(radii.len());
    for (k, &rf) in radii.iter().enumerate() {
        let r = 0.5 * rf;
        let mut placed = false;
        for _ in 0..100_000 {
            let (x, y) = (rng.range(-r_out, r_out), rng.range(-r_out, r_out));
            if !walls.holds([x, y], r) {
                continue;
            }
            let (cx, cy) = idx(x, y);
            let mut free = true;
            'scan: for gy in cy.saturating_sub(1)..=(cy + 1).min(nc - 1) {
                for gx in cx.saturating_sub(1)..=(cx + 1).min(nc - 1) {
                    for &j in &grid[gy * nc + gx] {
                        let d: [f64; 3] = discs[j];
                        if (d[0] - x).hypot(d[1] - y) < d[2] + r {
                            free = false;
                            break 'scan;
                        }
                    }
                }
            }
            if free {
                grid[cy * nc + cx].push(discs.len());
                discs.push([x, y, r]);
                placed = true;
                break;
            }
        }
        if !placed {
            return Err(err(format!(
                "{}: disc {k} of {} found no free place at half size in 100000 tries",
                p.porosity,
                radii.len()
            )));
        }
    }
    let mut stats = PackStats {
        discs_drawn: discs.len(),
        porosity_placed: porosity(&discs, walls.area),
        ..PackStats::default()
    };
    progress(&format!(
        "{} discs placed at half size, porosity {:.4}",
        discs.len(),
        stats.porosity_placed
    ));
    for round in 0..MAX_ROUNDS {
        let n_cur = porosity(&discs, walls.area);
        let m = ((1.0 - p.porosity) / (1.0 - n_cur)).sqrt();
        stats.factors.push(m);
        let mut world = world_of(&discs, walls, p)?;
        stats.steps += grow(&mut world, m, p)?;
        stats.steps += equilibrium(&mut world, p)?;
        let (kept, removed) = survivors(&world, walls, p.bond_gap);
        let (ov, z) = tightness(&world);
        stats.mean_overlap_ratio = ov;
        stats.coordination = z;
        discs = kept;
        stats.removed += removed;
        let n = porosity(&discs, walls.area);
        stats.porosity_reached = n;
        progress(&format!(
            "round {}: m = {m:.5}, porosity {n:.4}, {removed} removed, overlap {:.2} %, Z {z:.2}, \
             {} steps",
            round + 1,
            100.0 * ov,
            stats.steps
        ));
        if ov > MAX_MEAN_OVERLAP {
            return Err(err(format!(
                "{}: cannot be reached; at this porosity the discs overlap by {:.1} % of their \
                 mean radius on average (more than {:.0} %): they are squeezed, not packed; \
                 ask for a higher porosity",
                p.porosity,
                100.0 * ov,
                100.0 * MAX_MEAN_OVERLAP
            )));
        }
        if removed == 0 && (n - p.porosity).abs() <= 0.5 * p.tolerance {
            return Ok((discs, stats));
        }
    }
    Err(err(format!(
        "{}: cannot be reached; after {MAX_ROUNDS} rounds of the radius rule the porosity is \
         {:.4} and discs still fall out of the packing (too loose to hold together): ask for a \
         lower porosity",
        p.porosity, stats.porosity_reached
    )))
}

fn laws(p: &PackInput) -> ContactLaws {
    let mut laws = ContactLaws::new(
        2,
        ContactModel::Linear(LinearSpringDashpot::elastic(
            p.kn,
            p.kn / p.stiffness_ratio,
            0.0,
        )),
    );
    laws.set(
        DISC,
        WALL,
        ContactModel::Linear(LinearSpringDashpot::elastic(p.kn, 0.0, 0.0)),
    );
    laws
}

fn world_of(discs: &[[f64; 3]], walls: &Walls, p: &PackInput) -> Result<World, LabError> {
    let mut st = State {
        thickness: p.thickness,
        walls: vec![
            wall_of("inner", &walls.inner, WALL),
            wall_of("outer", &walls.outer, WALL),
        ],
        ..State::default()
    };
    for d in discs {
        st.discs
            .push_uniform(d[0], d[1], d[2], p.density, p.thickness, DISC);
    }
    World::try_new(st, relax::params(), laws(p)).map_err(|e| LabError::Param {
        field: "wheel".into(),
        reason: e.to_string(),
    })
}

fn set_scale(w: &mut World, base: &[f64], s: f64, rho: f64) {
    let t = w.state.thickness;
    let d = &mut w.state.discs;
    for k in 0..d.len() {
        let r = s * base[d.id[k] as usize];
        d.r[k] = r;
        d.m[k] = rho * t * PI * r * r;
        d.inertia[k] = 0.5 * d.m[k] * r * r;
    }
    w.refresh();
}

fn guard(w: &World, stage: &str) -> Result<(), LabError> {
    w.check().map_err(|e| LabError::Param {
        field: "porosity (--porosity)".into(),
        reason: format!("the packing blew up while {stage}: {e}; try another --seed"),
    })
}

/// Radii ×`m` in ×1.005 increments (÷ when m < 1), 40 steps each.
fn grow(w: &mut World, m: f64, p: &PackInput) -> Result<u64, LabError> {
    let d = &w.state.discs;
    let mut base = vec![0.0; d.len()];
    for k in 0..d.len() {
        base[d.id[k] as usize] = d.r[k];
    }
    let incs = (m.ln().abs() / 1.005f64.ln()).ceil().max(1.0) as u64;
    for k in 1..=incs {
        set_scale(w, &base, m.powf(k as f64 / incs as f64), p.density);
        w.run(40);
        guard(w, "growing the discs")?;
    }
    Ok(40 * incs)
}

/// Cycle until the unbalanced-force ratio is at most [`EQ_TOL`], or the kinetic energy 1e-6 of the
/// strain energy, or the stage's cap (then the packing is taken as it is).
fn equilibrium(w: &mut World, p: &PackInput) -> Result<u64, LabError> {
    let mut steps = 0;
    while steps < p.max_stage_steps {
        w.run(200);
        steps += 200;
        guard(w, "settling")?;
        let (ke, u) = relax::energies(w);
        if relax::unbalanced_ratio(w) <= EQ_TOL || ke <= 1e-6 * u {
            break;
        }
    }
    Ok(steps)
}

/// The discs (by id order) whose centre is in the annulus and that have a neighbour disc
/// within `gap`; and how many were dropped.
fn survivors(w: &World, walls: &Walls, gap: f64) -> (Vec<[f64; 3]>, usize) {
    let d = &w.state.discs;
    let mut near = vec![false; d.len()];
    for (i, j) in dem_core::bond::install::pairs_within_gap(&w.state, gap) {
        near[i as usize] = true;
        near[j as usize] = true;
    }
    let mut order: Vec<usize> = (0..d.len()).collect();
    order.sort_by_key(|&k| d.id[k]);
    let kept: Vec<[f64; 3]> = order
        .iter()
        .filter(|&&k| near[k] && walls.contains([d.x[k], d.y[k]]))
        .map(|&k| [d.x[k], d.y[k], d.r[k]])
        .collect();
    let removed = d.len() - kept.len();
    (kept, removed)
}

/// Mean overlap / mean radius of the touching disc pairs, and touching pairs per disc.
fn tightness(w: &World) -> (f64, f64) {
    let d = &w.state.discs;
    let r_mean = d.r.iter().sum::<f64>() / d.len().max(1) as f64;
    let (mut s, mut n) = (0.0, 0usize);
    for c in w.contacts() {
        if c.overlap > 0.0 {
            s += c.overlap;
            n += 1;
        }
    }
    let ov = if n == 0 { 0.0 } else { s / n as f64 / r_mean };
    (ov, 2.0 * n as f64 / d.len().max(1) as f64)
}
