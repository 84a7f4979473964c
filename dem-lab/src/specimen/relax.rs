//! World helpers shared by the specimen stages: contact laws and walls of the generation box,
//! wall stresses, the unbalanced-force ratio, cycling to equilibrium and relaxing.

use super::{Progress, SpecimenError, SpecimenParams};
use dem_core::contact::{ContactLaws, ContactModel, LinearSpringDashpot};
use dem_core::params::Params;
use dem_core::state::{State, Wall, FREE};
use dem_core::World;

/// Material index of the discs and of the box walls.
pub const DISC: u16 = 0;
pub const WALL: u16 = 1;
/// PFC's local damping coefficient for quasi-static stages (Potyondy & Cundall 2004 §2.2).
pub const LOCAL_DAMPING: f64 = 0.7;
/// Time-step safety factor of the quasi-static stages: local damping removes the energy error
/// the engine's accurate default (0.1) guards against, and PFC runs at 0.8.
pub const DT_FACTOR: f64 = 0.3;

/// Linear contact laws of the generation: discs k_n = 2tE_c, k_s = k_n/ratio, friction `mu`;
/// walls frictionless with k_n × `wall_stiffness_factor`, no shear stiffness.
pub fn laws(p: &SpecimenParams, mu: f64) -> ContactLaws {
    let m = &p.micro;
    let kn = 2.0 * p.thickness * m.contact_modulus;
    let mut laws = ContactLaws::new(
        2,
        ContactModel::Linear(LinearSpringDashpot::elastic(kn, kn / m.stiffness_ratio, mu)),
    );
    laws.set(
        DISC,
        WALL,
        ContactModel::Linear(LinearSpringDashpot::elastic(
            kn * m.wall_stiffness_factor,
            0.0,
            0.0,
        )),
    );
    laws
}

/// Global viscous damping ζ of the quasi-static stages: local damping acts only on bodies
/// that feel a force, so discs flying free in an unjammed packing would keep their speed.
pub const VISCOUS_DAMPING: f64 = 0.1;

/// Quasi-static step parameters: local damping [`LOCAL_DAMPING`] and viscous damping
/// [`VISCOUS_DAMPING`], [`DT_FACTOR`], energy tracked. The guard's
/// energy-growth check is off: radius changes put energy in that no boundary work accounts for
/// (the overlap and finiteness checks stay on).
pub fn params() -> Params {
    Params {
        local_damping: LOCAL_DAMPING,
        viscous_damping: VISCOUS_DAMPING,
        dt_factor: DT_FACTOR,
        max_energy_growth: f64::INFINITY,
        ..Params::default()
    }
}

/// The four walls of the box `[0, w] × [0, h]`, named left, right, bottom, top.
pub fn box_walls(w: f64, h: f64) -> Vec<Wall> {
    vec![
        Wall::new("left", [0.0, h], [0.0, 0.0], WALL),
        Wall::new("right", [w, 0.0], [w, h], WALL),
        Wall::new("bottom", [0.0, 0.0], [w, 0.0], WALL),
        Wall::new("top", [w, h], [0.0, h], WALL),
    ]
}

/// The box `[x0, x1, y0, y1]` spanned by the walls named left, right, bottom, top.
pub fn box_of_walls(st: &State) -> Option<[f64; 4]> {
    let f = |name: &str| st.walls.iter().find(|w| w.name == name);
    Some([
        f("left")?.a[0],
        f("right")?.a[0],
        f("bottom")?.a[1],
        f("top")?.a[1],
    ])
}

/// Mean normal stresses on the walls (σ_xx, σ_yy; Pa, compression positive): the forces the
/// discs exert on the left and right walls over the box height × t, likewise bottom and top
/// over the box width × t. Zero without the four walls.
pub fn wall_stress(st: &State) -> [f64; 2] {
    let Some(b) = box_of_walls(st) else {
        return [0.0; 2];
    };
    let t = st.thickness;
    let f = |name: &str| {
        st.walls
            .iter()
            .find(|w| w.name == name)
            .map_or([0.0; 2], |w| w.force)
    };
    // Discs push the low wall towards −axis and the high wall towards +axis.
    let sxx = 0.5 * (f("right")[0] - f("left")[0]) / ((b[3] - b[2]) * t);
    let syy = 0.5 * (f("top")[1] - f("bottom")[1]) / ((b[1] - b[0]) * t);
    [sxx, syy]
}

/// Mean of the two wall stresses.
pub fn iso_stress(st: &State) -> f64 {
    let s = wall_stress(st);
    0.5 * (s[0] + s[1])
}

/// Unbalanced-force ratio (PFC's "mechanical ratio", averaged): mean |net force| of the free
/// bodies (free discs and rigid clumps) over the mean normal force of the touching pairs
/// (bonds are left out: force-free intra-grain bonds would dilute the mean). Uses the forces of
/// the last step. Infinite when nothing touches and something is pushed.
pub fn unbalanced_ratio(w: &World) -> f64 {
    let d = &w.state.discs;
    let (mut sum, mut n) = (0.0, 0usize);
    for i in 0..d.len() {
        if d.body[i] == FREE && !d.fixed[i] {
            sum += d.fx[i].hypot(d.fy[i]);
            n += 1;
        }
    }
    let cl = &w.state.clumps;
    for c in 0..cl.len() {
        sum += cl.fx[c].hypot(cl.fy[c]);
        n += 1;
    }
    let (mut fc, mut nc) = (0.0, 0usize);
    for c in w.contacts() {
        fc += c.f_n.abs();
        nc += 1;
    }
    if n == 0 {
        return 0.0;
    }
    let mean_f = sum / n as f64;
    if nc == 0 || fc == 0.0 {
        return if mean_f == 0.0 { 0.0 } else { f64::INFINITY };
    }
    mean_f / (fc / nc as f64)
}

/// Kinetic and stored strain energy (J).
pub fn energies(w: &World) -> (f64, f64) {
    let e = w.energy();
    (e.kinetic(), e.strain_contact + e.strain_bond)
}

/// Step until `done(world)` holds (checked every `every` steps) or `max` steps; returns the
/// steps taken. Errors with the stage name when the cap is reached.
pub fn cycle_until(
    w: &mut World,
    stage: &'static str,
    every: u64,
    max: u64,
    progress: &mut dyn FnMut(Progress),
    mut done: impl FnMut(&World) -> (bool, String),
) -> Result<u64, SpecimenError> {
    let mut steps = 0;
    let every = every.max(1);
    loop {
        w.run(every);
        steps += every;
        if let Err(e) = w.check() {
            // The engine's advice names a scene's time-step settings, which `dem specimen` does
            // not have (issue 48 D7); the generator's step is the engine's automatic one.
            let cause = format!(
                "discs driven into each other faster than they part at this stage (time step \
                 {:.3e} s, {:.2} of the critical step, the generator's fixed factor); try \
                 another --seed, and report this seed with its flags",
                w.dt(),
                w.dt() / w.critical_dt()
            );
            return Err(SpecimenError::NoConvergence {
                stage,
                steps,
                detail: format!("the blow-up guard stopped it: {}", e.with_cause(cause)),
            });
        }
        let (ok, msg) = done(w);
        progress(Progress {
            stage,
            fraction: (steps as f64 / max as f64).min(1.0),
            message: msg.clone(),
        });
        if ok {
            return Ok(steps);
        }
        if steps >= max {
            return Err(SpecimenError::NoConvergence {
                stage,
                steps,
                detail: msg,
            });
        }
    }
}

/// Step until the unbalanced-force ratio is at most `tol` or the kinetic energy at most
/// `rest_ke` (J).
pub fn to_equilibrium(
    w: &mut World,
    stage: &'static str,
    tol: f64,
    rest_ke: f64,
    max: u64,
    progress: &mut dyn FnMut(Progress),
) -> Result<u64, SpecimenError> {
    cycle_until(w, stage, 100, max, progress, |w| {
        let r = unbalanced_ratio(w);
        let ke = energies(w).0;
        (
            r <= tol || ke <= rest_ke,
            format!("unbalanced-force ratio {r:.2e} (target {tol:.0e}), KE {ke:.2e} J"),
        )
    })
}

/// Step until the kinetic energy is at most `ratio` × the strain energy at three checks in a
/// row, 200 steps apart (so a momentary zero crossing of the velocities does not count);
/// returns steps, KE and strain energy.
pub fn relax(
    w: &mut World,
    ratio: f64,
    max: u64,
    progress: &mut dyn FnMut(Progress),
) -> Result<(u64, f64, f64), SpecimenError> {
    let mut below = 0;
    let steps = cycle_until(w, "relax", 200, max, progress, |w| {
        let (ke, u) = energies(w);
        if ke <= ratio * u {
            below += 1;
        } else {
            below = 0;
        }
        (
            below >= 3,
            format!("KE/U = {:.2e} (target {ratio:.0e})", ke / u.max(1e-300)),
        )
    })?;
    let (ke, u) = energies(w);
    Ok((steps, ke, u))
}

/// Number of touching disc-disc pairs plus disc-wall contacts of every disc, indexed like
/// `w.state.discs`. Pairs inside one rigid clump are never listed, so they do not count.
pub fn contact_counts(w: &World) -> Vec<u32> {
    let d = &w.state.discs;
    let mut n = vec![0u32; d.len()];
    for c in w.contacts() {
        n[c.i as usize] += 1;
        n[c.j as usize] += 1;
    }
    for wall in &w.state.walls {
        for (i, k) in n.iter_mut().enumerate() {
            if disc_touches_wall(d.x[i], d.y[i], d.r[i], wall) {
                *k += 1;
            }
        }
    }
    n
}

/// Whether a disc overlaps a wall segment.
pub fn disc_touches_wall(x: f64, y: f64, r: f64, w: &Wall) -> bool {
    let (ax, ay, bx, by) = (w.a[0], w.a[1], w.b[0], w.b[1]);
    let (dx, dy) = (bx - ax, by - ay);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((x - ax) * dx + (y - ay) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (px, py) = (ax + t * dx, ay + t * dy);
    (x - px).hypot(y - py) < r
}
