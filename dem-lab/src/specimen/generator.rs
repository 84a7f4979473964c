//! The packing of S4's procedure (Tan et al.; PFC's, Potyondy & Cundall 2004 §3.1), steps 1-3:
//!
//! 1. radii drawn (uniform or truncated normal in [r_min, r_max]) until Σπr² reaches
//!    (1 − n)·A, n the target porosity; discs placed at random at half size without overlap
//!    (random sequential addition) inside four frictionless walls stiffer than the discs;
//! 2. radii grown in small uniform steps (×1.005, each followed by 40 steps) to full size, then
//!    cycled to equilibrium; then a uniform radius change servo until the isotropic wall stress
//!    is σ0 within the tolerance (Δε = (σ0 − σ)/K with K the secant stiffness of the previous
//!    change, or the estimate K = 2E_c Z (1 − n)/π);
//! 3. floaters (fewer than 3 contacts, walls counted) are re-sized and re-centred on the
//!    circle tangent to three neighbours that fits their cage (the problem of Apollonius, the
//!    radius change closest to none), enlarged by the mean contact overlap so they carry load;
//!    three passes, each followed by equilibrium and the stress servo; floaters whose cage
//!    needs a radius outside [0.5 r, 1.5 r] or that remain after the passes are removed.
//!
//! Packing is frictionless (μ = 0, our choice: denser, isotropic packings); masses follow the
//! radii (ρ t π r²).

use super::relax::{self, DISC};
use super::rng::Rng;
use super::{Progress, RadiusDist, SpecimenError, SpecimenParams};
use dem_core::state::State;
use dem_core::World;
use serde::{Deserialize, Serialize};

/// Figures of the packing stage.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PackStats {
    pub discs_drawn: usize,
    pub floaters_resized: usize,
    pub floaters_removed: usize,
    /// The first growth jammed and the packing was grown again more slowly (issue 48 D7).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub grow_retried: bool,
    /// Floaters still counted after the last pass (left in place).
    pub floaters_left: usize,
    /// Discs with no neighbour within the bond gap at the end, removed.
    pub loose_removed: usize,
    /// Wall stress (Pa) at the end, σ_xx and σ_yy.
    pub wall_stress: [f64; 2],
    pub steps: u64,
}

/// Growth factor per increment and steps per increment.
const GROW: f64 = 1.005;
const GROW_STEPS: u64 = 40;
/// How many times more steps per increment the second growth has when the first jams.
pub const GROW_RETRY: u64 = 5;
/// Unbalanced-force ratio counted as equilibrium during packing.
pub const EQ_TOL: f64 = 2e-3;
/// Most steps spent settling between two servo changes far from the target stress.
const FAR_STEPS: u64 = 20_000;
const FLOATER_PASSES: usize = 3;

fn draw_radius(rng: &mut Rng, p: &SpecimenParams) -> f64 {
    match p.distribution {
        RadiusDist::Uniform => rng.range(p.r_min, p.r_max),
        RadiusDist::Normal => {
            if p.r_max == p.r_min {
                return p.r_min;
            }
            let (mu, sd) = (0.5 * (p.r_min + p.r_max), (p.r_max - p.r_min) / 6.0);
            loop {
                let r = mu + sd * rng.normal();
                if r >= p.r_min && r <= p.r_max {
                    return r;
                }
            }
        }
    }
}

/// Grows the placed discs from half size to `radii` in ×[`GROW`] increments, `steps_per_inc`
/// steps after each; returns the final scale (1).
fn grow(
    world: &mut World,
    radii: &[f64],
    steps_per_inc: u64,
    p: &SpecimenParams,
    stats: &mut PackStats,
    progress: &mut dyn FnMut(Progress),
) -> f64 {
    let s0: f64 = 0.5;
    let incs = ((1.0 / s0).ln() / GROW.ln()).ceil() as usize;
    let mut s = s0;
    for k in 0..incs {
        s = (s * GROW).min(1.0);
        set_radii(world, radii, s, p.density);
        world.run(steps_per_inc);
        stats.steps += steps_per_inc;
        if k % 10 == 0 {
            progress(Progress {
                stage: "grow",
                fraction: (k + 1) as f64 / incs as f64,
                message: format!("radius scale {s:.3}"),
            });
        }
    }
    s
}

/// Set every disc's radius to `scale × full[id]` and its mass to a uniform disc's.
fn set_radii(w: &mut World, full: &[f64], scale: f64, rho: f64) {
    let t = w.state.thickness;
    let d = &mut w.state.discs;
    for k in 0..d.len() {
        let r = scale * full[d.id[k] as usize];
        d.r[k] = r;
        d.m[k] = rho * t * std::f64::consts::PI * r * r;
        d.inertia[k] = 0.5 * d.m[k] * r * r;
    }
    w.refresh();
}

/// Steps 1-3: a packed, stressed, floater-free disc assembly in its walls.
pub fn pack(
    p: &SpecimenParams,
    rng: &mut Rng,
    progress: &mut dyn FnMut(Progress),
) -> Result<(World, PackStats), SpecimenError> {
    p.validate()?;
    let (w, h) = (p.width, p.height);
    let target = (1.0 - p.porosity) * w * h;
    let mut radii = Vec::new();
    let mut area = 0.0;
    while area < target {
        let r = draw_radius(rng, p);
        area += std::f64::consts::PI * r * r;
        radii.push(r);
    }
    // Largest first: random sequential addition of a size mix jams least this way.
    let mut order: Vec<usize> = (0..radii.len()).collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]).then(a.cmp(&b)));
    let radii: Vec<f64> = order.iter().map(|&k| radii[k]).collect();
    let s0 = 0.5;
    let mut st = State {
        thickness: p.thickness,
        walls: relax::box_walls(w, h),
        ..State::default()
    };
    let cell = 2.0 * s0 * p.r_max;
    let (nx, ny) = (
        ((w / cell).ceil() as usize).max(1),
        ((h / cell).ceil() as usize).max(1),
    );
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
    let idx = |x: f64, y: f64| -> (usize, usize) {
        (
            ((x / cell) as usize).min(nx - 1),
            ((y / cell) as usize).min(ny - 1),
        )
    };
    let n = radii.len();
    for (k, &rf) in radii.iter().enumerate() {
        let r = s0 * rf;
        let mut placed = false;
        for _ in 0..100_000 {
            let (x, y) = (rng.range(r, w - r), rng.range(r, h - r));
            let (cx, cy) = idx(x, y);
            let mut free = true;
            'scan: for gy in cy.saturating_sub(1)..=(cy + 1).min(ny - 1) {
                for gx in cx.saturating_sub(1)..=(cx + 1).min(nx - 1) {
                    for &j in &grid[gy * nx + gx] {
                        let d = &st.discs;
                        let (dx, dy) = (d.x[j] - x, d.y[j] - y);
                        let rr = d.r[j] + r;
                        if dx * dx + dy * dy < rr * rr {
                            free = false;
                            break 'scan;
                        }
                    }
                }
            }
            if free {
                let i = st.discs.push_uniform(x, y, r, p.density, p.thickness, DISC);
                grid[cy * nx + cx].push(i);
                placed = true;
                break;
            }
        }
        if !placed {
            return Err(SpecimenError::Placement {
                index: k,
                count: n,
                attempts: 100_000,
            });
        }
        if k % 256 == 0 {
            progress(Progress {
                stage: "place",
                fraction: k as f64 / n as f64,
                message: format!("{k} of {n} discs"),
            });
        }
    }
    let mut stats = PackStats {
        discs_drawn: n,
        ..PackStats::default()
    };
    // Growth to full size (the target porosity), then a rough equilibrium: the servo's first
    // steps only need the stress's order of magnitude. A packing whose growth jams (two discs
    // grown into each other beyond the guard's overlap before they can part: 12 × 4 mm, seed 1,
    // issue 48 D7) is grown again from the same placement GROW_RETRY times more slowly.
    // Packings that grow at the first attempt are not changed by this.
    let grown = |st: State,
                 steps_per_inc: u64,
                 stats: &mut PackStats,
                 progress: &mut dyn FnMut(Progress)| {
        let mut world = World::try_new(st, relax::params(), relax::laws(p, 0.0))?;
        let s = grow(&mut world, &radii, steps_per_inc, p, stats, progress);
        let rest = rest_energy(&world, p);
        stats.steps += relax::to_equilibrium(
            &mut world,
            "grow",
            5.0 * EQ_TOL,
            rest,
            p.max_stage_steps,
            progress,
        )?;
        Ok::<_, SpecimenError>((world, s))
    };
    let (mut world, s) = match grown(st.clone(), GROW_STEPS, &mut stats, progress) {
        Ok(g) => g,
        Err(first) => {
            stats.grow_retried = true;
            let slow = GROW_STEPS * GROW_RETRY;
            progress(Progress {
                stage: "grow",
                fraction: 0.0,
                message: format!("jammed ({first}); growing again, {slow} steps per increment"),
            });
            grown(st, slow, &mut stats, progress).map_err(|second| {
                SpecimenError::NoConvergence {
                    stage: "grow",
                    steps: stats.steps,
                    detail: format!(
                        "{first}; grown again {GROW_RETRY} times more slowly: {second}"
                    ),
                }
            })?
        }
    };
    let mut full: Vec<f64> = radii.iter().map(|r| r * s).collect();
    stats.steps += servo(&mut world, &mut full, p, progress)?;
    // Floaters: re-size those whose cage allows it, remove the others; the last pass only
    // counts.
    for pass in 0..=FLOATER_PASSES {
        let counts = relax::contact_counts(&world);
        let floaters: Vec<usize> = (0..counts.len()).filter(|&k| counts[k] < 3).collect();
        progress(Progress {
            stage: "floaters",
            fraction: pass as f64 / FLOATER_PASSES as f64,
            message: format!("pass {pass}: {} floaters", floaters.len()),
        });
        stats.floaters_left = floaters.len();
        if floaters.is_empty() || pass == FLOATER_PASSES {
            break;
        }
        let mean_overlap = mean_overlap(&world);
        let mut remove = Vec::new();
        for &k in &floaters {
            match cage_circle(&world.state, k, p) {
                Some((x, y, rho)) => {
                    let r = rho + mean_overlap;
                    let d = &mut world.state.discs;
                    d.x[k] = x;
                    d.y[k] = y;
                    full[d.id[k] as usize] = r;
                    d.r[k] = r;
                    d.m[k] = p.density * p.thickness * std::f64::consts::PI * r * r;
                    d.inertia[k] = 0.5 * d.m[k] * r * r;
                    d.vx[k] = 0.0;
                    d.vy[k] = 0.0;
                    d.omega[k] = 0.0;
                    stats.floaters_resized += 1;
                }
                None => remove.push(k),
            }
        }
        if !remove.is_empty() {
            stats.floaters_removed += remove.len();
            let (nw, nf) = without(&world, &full, &remove, p)?;
            world = nw;
            full = nf;
        } else {
            world.refresh();
        }
        stats.steps += settle(&mut world, "floaters", p, progress)?;
        stats.steps += servo(&mut world, &mut full, p, progress)?;
    }
    // Discs that no bond could reach (no disc within the bond gap) would be loose in the
    // specimen: remove them.
    let mut near = vec![false; world.state.discs.len()];
    for (i, j) in dem_core::bond::install::pairs_within_gap(&world.state, p.bond_gap) {
        near[i as usize] = true;
        near[j as usize] = true;
    }
    let loose: Vec<usize> = (0..near.len()).filter(|&k| !near[k]).collect();
    if !loose.is_empty() {
        stats.loose_removed = loose.len();
        let (nw, nf) = without(&world, &full, &loose, p)?;
        world = nw;
        full = nf;
        stats.steps += settle(&mut world, "floaters", p, progress)?;
        stats.steps += servo(&mut world, &mut full, p, progress)?;
    }
    stats.wall_stress = relax::wall_stress(&world.state);
    Ok((world, stats))
}

/// Uniform radius change until the isotropic wall stress is σ0 (within the tolerance), at
/// equilibrium. `full` holds each disc's radius by id and is updated.
fn servo(
    w: &mut World,
    full: &mut [f64],
    p: &SpecimenParams,
    progress: &mut dyn FnMut(Progress),
) -> Result<u64, SpecimenError> {
    servo_with(w, p, p.iso_stress, p.iso_tolerance, progress, |w, eps| {
        for r in full.iter_mut() {
            *r *= 1.0 + eps;
        }
        set_radii(w, full, 1.0, p.density);
    })
}

/// Stress servo by uniform strain steps: `apply(world, ε)` strains the assembly by ε (radius
/// growth factor 1 + ε), then the world is cycled to equilibrium and the isotropic wall stress σ
/// read. The log-strain of the next step: from above only, aim at max(σ0, σ/2) (a geometric
/// descent that does not unjam the packing in one go); from below only, (σ0 − σ)/K, or 1e-3
/// while the assembly carries less than σ0/4 (unjammed or flowing: K means nothing there); once σ0 is bracketed, regula falsi (Illinois variant)
/// inside the middle 90 % of the bracket. K is the secant stiffness of the last step when it is sane, else
/// K = 2E_c Z (1 − n)/π (a disc packing of coordination Z under uniform radius strain, contacts
/// k_n = 2tE_c); steps are at most 1 %. Stops when |σ − σ0| ≤ `tolerance`·σ0, σ0 = `s0`.
pub fn servo_with(
    w: &mut World,
    p: &SpecimenParams,
    s0: f64,
    tolerance: f64,
    progress: &mut dyn FnMut(Progress),
    mut apply: impl FnMut(&mut World, f64),
) -> Result<u64, SpecimenError> {
    let rest = rest_energy(w, p);
    let mut steps = 0;
    let mut cur = 0.0f64; // log-strain applied so far
    let mut was_above = false;
    let mut prev: Option<(f64, f64)> = None;
    for it in 0..60 {
        let sigma = relax::iso_stress(&w.state);
        progress(Progress {
            stage: "stress",
            fraction: (it as f64 / 60.0).min(1.0),
            message: format!("σ = {:.3e} Pa (target {s0:.3e})", sigma),
        });
        if (sigma - s0).abs() <= tolerance * s0 {
            return Ok(steps);
        }
        let counts = relax::contact_counts(w);
        let z = counts.iter().map(|&c| c as f64).sum::<f64>() / counts.len().max(1) as f64;
        let k_est =
            2.0 * p.micro.contact_modulus * z.max(1.0) * (1.0 - p.porosity) / std::f64::consts::PI;
        // Secant stiffness of the last step, kept within [0.05, 20] × the estimate; a step that
        // lowered the stress it should have raised (flow) counts as soft.
        let k = match prev {
            Some((e_prev, s_prev)) if cur != e_prev => {
                let ks = (sigma - s_prev) / (cur - e_prev);
                if ks.is_finite() && ks > 0.0 {
                    ks.clamp(0.05 * k_est, 20.0 * k_est)
                } else {
                    0.05 * k_est
                }
            }
            _ => k_est,
        };
        was_above |= sigma > s0;
        let target = if sigma > s0 {
            // Geometric descent, then an under-relaxed secant step into the window.
            let aim = (0.5 * sigma).max(s0);
            let f = if aim == s0 { 0.7 } else { 1.0 };
            cur + (f * (aim - sigma) / k).max(-0.01)
        } else if sigma <= 0.25 * s0 && !was_above {
            cur + 1e-3
        } else {
            cur + (0.7 * (s0 - sigma) / k).min(0.01)
        };
        prev = Some((cur, sigma));
        apply(w, (target - cur).exp_m1());
        cur = target;
        // Far from σ0 a rough equilibrium, or FAR_STEPS steps, is enough to choose the next
        // change (a flowing assembly would take long to come to rest).
        let far = (sigma - s0).abs() > 0.5 * s0;
        let (tol, max) = if far {
            (5.0 * EQ_TOL, FAR_STEPS.min(p.max_stage_steps))
        } else {
            (EQ_TOL, p.max_stage_steps)
        };
        steps += match relax::to_equilibrium(w, "stress", tol, rest, max, progress) {
            Err(SpecimenError::NoConvergence { steps: n, .. }) if far => n,
            r => r?,
        };
    }
    Err(SpecimenError::NoConvergence {
        stage: "stress",
        steps,
        detail: format!(
            "wall stress {:.3e} Pa, target {s0:.3e} Pa after 60 strain steps",
            relax::iso_stress(&w.state)
        ),
    })
}

/// Cycle to equilibrium (ratio [`EQ_TOL`] or at rest, see [`rest_energy`]).
pub fn settle(
    w: &mut World,
    stage: &'static str,
    p: &SpecimenParams,
    progress: &mut dyn FnMut(Progress),
) -> Result<u64, SpecimenError> {
    let rest = rest_energy(w, p);
    relax::to_equilibrium(w, stage, EQ_TOL, rest, p.max_stage_steps, progress)
}

/// Kinetic energy (J) below which a packing counts as at rest even when its force ratio says
/// otherwise (an unjammed packing has no contact forces to compare with): 1e-4 × N F0²/(2k_n),
/// the contact strain energy of N discs with one contact each at the target stress,
/// F0 = σ0 · 2r̄ · t.
pub fn rest_energy(w: &World, p: &SpecimenParams) -> f64 {
    let r_mean = 0.5 * (p.r_min + p.r_max);
    let f0 = p.iso_stress * 2.0 * r_mean * p.thickness;
    let kn = 2.0 * p.thickness * p.micro.contact_modulus;
    1e-4 * w.state.discs.len() as f64 * f0 * f0 / (2.0 * kn)
}

/// Mean overlap of the touching pairs (0 when none).
fn mean_overlap(w: &World) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for c in w.contacts() {
        s += c.overlap;
        n += 1;
    }
    if n == 0 {
        0.0
    } else {
        s / n as f64
    }
}

/// The circle tangent to three neighbours of disc `k` that overlaps no other disc, stays in the
/// box and has the radius closest to disc k's, within [0.5 r, 1.5 r].
fn cage_circle(st: &State, k: usize, p: &SpecimenParams) -> Option<(f64, f64, f64)> {
    let d = &st.discs;
    let (x0, y0, r0) = (d.x[k], d.y[k], d.r[k]);
    let reach = r0 + 4.0 * p.r_max;
    // Neighbours in relative coordinates, nearest surfaces first.
    let mut nb: Vec<(f64, [f64; 3])> = (0..d.len())
        .filter(|&j| j != k)
        .filter_map(|j| {
            let (dx, dy) = (d.x[j] - x0, d.y[j] - y0);
            let dist = dx.hypot(dy);
            (dist < reach + d.r[j]).then_some((dist - d.r[j], [dx, dy, d.r[j]]))
        })
        .collect();
    nb.sort_by(|a, b| a.0.total_cmp(&b.0));
    let near: Vec<[f64; 3]> = nb.iter().take(8).map(|e| e.1).collect();
    let mut best: Option<(f64, f64, f64)> = None;
    for a in 0..near.len() {
        for b in a + 1..near.len() {
            for c in b + 1..near.len() {
                for (x, y, rho) in apollonius(near[a], near[b], near[c]) {
                    if !(rho >= 0.5 * r0 && rho <= 1.5 * r0) {
                        continue;
                    }
                    // The centre must lie inside the triangle of the three centres, so the
                    // three contact normals span the plane and hold the disc in place.
                    if !inside_triangle([x, y], near[a], near[b], near[c]) {
                        continue;
                    }
                    let (ax, ay) = (x + x0, y + y0);
                    if ax - rho < 0.0 || ay - rho < 0.0 || ax + rho > p.width || ay + rho > p.height
                    {
                        continue;
                    }
                    let tol = 1e-9 * rho;
                    let clear = nb
                        .iter()
                        .all(|(_, q)| (q[0] - x).hypot(q[1] - y) - q[2] - rho >= -tol);
                    let closer = match best {
                        None => true,
                        Some(bb) => (rho - r0).abs() < (bb.2 - r0).abs(),
                    };
                    if clear && closer {
                        best = Some((ax, ay, rho));
                    }
                }
            }
        }
    }
    best
}

/// Whether `q` lies strictly inside the triangle of the centres of `a`, `b`, `c`.
fn inside_triangle(q: [f64; 2], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let cross =
        |p: [f64; 3], r: [f64; 3]| (r[0] - p[0]) * (q[1] - p[1]) - (r[1] - p[1]) * (q[0] - p[0]);
    let (s1, s2, s3) = (cross(a, b), cross(b, c), cross(c, a));
    (s1 > 0.0 && s2 > 0.0 && s3 > 0.0) || (s1 < 0.0 && s2 < 0.0 && s3 < 0.0)
}

/// Circles (x, y, ρ), ρ > 0, externally tangent to three circles `[x, y, r]` (the problem of
/// Apollonius, all-external case): |c − c_k| = ρ + r_k. Subtracting the first equation from
/// the others gives x, y linear in ρ; the first then gives a quadratic in ρ.
pub fn apollonius(c1: [f64; 3], c2: [f64; 3], c3: [f64; 3]) -> Vec<(f64, f64, f64)> {
    let row = |c: [f64; 3]| {
        (
            2.0 * (c[0] - c1[0]),
            2.0 * (c[1] - c1[1]),
            c[0] * c[0] + c[1] * c[1] - c1[0] * c1[0] - c1[1] * c1[1] - c[2] * c[2] + c1[2] * c1[2],
            -2.0 * (c[2] - c1[2]),
        )
    };
    // a x + b y = e + f ρ
    let (a2, b2, e2, f2) = row(c2);
    let (a3, b3, e3, f3) = row(c3);
    let det = a2 * b3 - a3 * b2;
    let scale = (a2.abs() + b2.abs()) * (a3.abs() + b3.abs());
    if det.abs() <= 1e-12 * scale || scale == 0.0 {
        return Vec::new();
    }
    let x0 = (e2 * b3 - e3 * b2) / det;
    let x1 = (f2 * b3 - f3 * b2) / det;
    let y0 = (a2 * e3 - a3 * e2) / det;
    let y1 = (a2 * f3 - a3 * f2) / det;
    let (px, py) = (x0 - c1[0], y0 - c1[1]);
    let qa = x1 * x1 + y1 * y1 - 1.0;
    let qb = 2.0 * (px * x1 + py * y1 - c1[2]);
    let qc = px * px + py * py - c1[2] * c1[2];
    let mut roots = Vec::new();
    if qa.abs() < 1e-14 {
        if qb != 0.0 {
            roots.push(-qc / qb);
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let s = disc.sqrt();
            // Numerically stable pair of roots.
            let q = -0.5 * (qb + s.copysign(qb));
            if q != 0.0 {
                roots.push(q / qa);
                roots.push(qc / q);
            } else {
                roots.push(0.0);
            }
        }
    }
    roots
        .into_iter()
        .filter(|&r| r > 0.0 && r.is_finite())
        .map(|r| (x0 + x1 * r, y0 + y1 * r, r))
        .collect()
}

/// A new world without the discs at indices `remove`, ids renumbered in id order; returns it
/// and the full radii by new id.
fn without(
    w: &World,
    full: &[f64],
    remove: &[usize],
    p: &SpecimenParams,
) -> Result<(World, Vec<f64>), SpecimenError> {
    let d = &w.state.discs;
    let mut gone = vec![false; d.len()];
    for &k in remove {
        gone[k] = true;
    }
    let mut keep: Vec<usize> = (0..d.len()).filter(|&k| !gone[k]).collect();
    keep.sort_by_key(|&k| d.id[k]);
    let mut st = State {
        thickness: w.state.thickness,
        walls: w.state.walls.clone(),
        ..State::default()
    };
    let mut nf = Vec::with_capacity(keep.len());
    for &k in &keep {
        let i = st.discs.push(
            d.x[k],
            d.y[k],
            d.r[k],
            d.m[k],
            d.inertia[k],
            d.material[k],
            0,
        );
        st.discs.vx[i] = d.vx[k];
        st.discs.vy[i] = d.vy[k];
        st.discs.omega[i] = d.omega[k];
        nf.push(full[d.id[k] as usize]);
    }
    let nw = World::try_new(st, w.params.clone(), relax::laws(p, 0.0))?;
    Ok((nw, nf))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn apollonius_circle_is_tangent_to_all_three() {
        let cs = [[0.0, 0.0, 1.0], [3.0, 0.2, 0.7], [1.2, 2.9, 1.3]];
        let sols = apollonius(cs[0], cs[1], cs[2]);
        assert!(!sols.is_empty());
        for (x, y, r) in sols {
            for c in &cs {
                let g = (x - c[0]).hypot(y - c[1]) - c[2] - r;
                assert!(g.abs() < 1e-12, "gap {g}");
            }
        }
        // Three unit circles at the corners of an equilateral triangle of side 2: the inner
        // circle has radius 2/√3 − 1.
        let s = 3f64.sqrt();
        let sols = apollonius([0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [1.0, s, 1.0]);
        let inner = sols.iter().map(|s| s.2).fold(f64::INFINITY, f64::min);
        assert!((inner - (2.0 / s - 1.0)).abs() < 1e-12, "{inner}");
    }
}
