//! [`Scene`] → [`World`]: discs, rigid clumps (ORC), bonded clumps (improved ORC), automatic
//! bonds, walls, contact laws per material pair, parameters. Only what the scene uses is built:
//! no bond store without bonds, no clump pass without rigid clumps, no gravity unless set.
//!
//! Order: free discs, the rigid clumps and explicit bonds of specimen files (made of those
//! discs), then clumps in scene order (their discs get the next ids), then automatic bonds, then the world (`World::try_new` may reorder the discs in space; the bonds, built on
//! creation indices, are remapped and attached and the reference gaps of overlapping
//! bonded-clump members registered by [`world_with_bonds`]).

use super::model::{ClumpInit, NormalDamping, PairLaw, PairStiffness, Scene};
use super::schema::{Between, ClumpMode};
use super::SceneError;
use crate::bond::attach::world_with_bonds;
use crate::bond::Bonds;
use crate::bonded_clump::{place_bonded_clump_in, Placement};
use crate::contact::NormalDamping as LinDamping;
use crate::contact::{
    ContactLaws, ContactModel, HertzMindlin, LinearSpringDashpot, RollingResistance,
};
use crate::params::Params;
use crate::pipeline::World;
use crate::state::{State, Wall};
use clumpgen::Template;
use std::collections::HashMap;

/// Builds the world of a loaded scene.
pub fn build(scene: &Scene) -> Result<World, SceneError> {
    let file = scene.file.display().to_string();
    let fail = |what: &str, reason: String| SceneError::Build {
        file: file.clone(),
        what: what.to_string(),
        reason,
    };
    let mut st = State {
        thickness: scene.thickness,
        periodic: scene.periodic,
        ..State::default()
    };
    for d in &scene.discs {
        let (m, inertia) = d.mass.unwrap_or_else(|| {
            let m = scene.materials[d.material as usize].density.unwrap_or(0.0)
                * scene.thickness
                * std::f64::consts::PI
                * d.r
                * d.r;
            (m, 0.5 * m * d.r * d.r)
        });
        let (x, y) = (wrap(&st, 0, d.x), wrap(&st, 1, d.y));
        let k = st.discs.push(x, y, d.r, m, inertia, d.material, d.group);
        st.discs.vx[k] = d.vx;
        st.discs.vy[k] = d.vy;
        st.discs.omega[k] = d.omega;
        st.discs.fixed[k] = d.fixed;
    }
    // Rigid clumps of specimen-file discs (the scene's discs come first: index = id).
    for (k, m) in scene.rigid_clumps.iter().enumerate() {
        crate::clump::orc::make_rigid_clump(&mut st, m, "specimen").ok_or_else(|| {
            fail(
                &format!("rigid clump {k}"),
                "a member is missing or in another clump".into(),
            )
        })?;
    }
    let mut bonds = if scene.bond_groups.is_empty() {
        None
    } else {
        Some(
            Bonds::new(scene.bond_groups.clone())
                .map_err(|e| fail("bond groups", e.to_string()))?,
        )
    };
    let mut offsets = Vec::new();
    for (k, e) in scene.bonds.iter().enumerate() {
        let what = format!("specimen bond {k}");
        let b = bonds
            .as_mut()
            .ok_or_else(|| fail(&what, "no bond groups".into()))?;
        b.add(&st, e.a, e.b, e.group as u16)
            .map_err(|err| fail(&what, err.to_string()))?;
        if e.contact_offset < 0.0 {
            offsets.push((st.discs.id[e.a], st.discs.id[e.b], e.contact_offset));
        }
    }
    let mut scaled: HashMap<(usize, u16), Template> = HashMap::new();
    for (k, c) in scene.clumps.iter().enumerate() {
        let tpl = scaled
            .entry((c.template, c.material))
            .or_insert_with(|| scale_template(&scene.templates[c.template], c));
        let what = format!("clump {k} (template {})", tpl.id);
        match c.mode {
            ClumpMode::Rigid => {
                let ci = crate::clump::add_rigid_clump(&mut st, tpl, c.x, c.y, c.angle, c.material)
                    .map_err(|e| fail(&what, e.to_string()))?;
                let cl = &mut st.clumps;
                cl.vx[ci] = c.vx;
                cl.vy[ci] = c.vy;
                cl.omega[ci] = c.omega;
                let (xc, yc) = (cl.x[ci], cl.y[ci]);
                let n = st.discs.len();
                let members = n - tpl.discs.len()..n;
                set_rigid_motion(&mut st, members, [xc, yc], c);
            }
            ClumpMode::Bonded => {
                let b = bonds
                    .as_mut()
                    .ok_or_else(|| fail(&what, "no bond groups".into()))?;
                let placed = place_bonded_clump_in(
                    &mut st,
                    b,
                    tpl,
                    &Placement {
                        x: c.x,
                        y: c.y,
                        angle: c.angle,
                        material: c.material,
                        grain: c.group,
                        intra_group: c.bond_group.unwrap_or(0) as u16,
                        touch_tol: c.bond_tolerance,
                    },
                )
                .map_err(|e| fail(&what, e.to_string()))?;
                // Rigid initial motion about the grain's mass centre.
                let (s, co) = c.angle.sin_cos();
                let [gx, gy] = tpl.achieved.centroid;
                let centre = [c.x + co * gx - s * gy, c.y + s * gx + co * gy];
                set_rigid_motion(&mut st, placed.discs.iter().copied(), centre, c);
                offsets.extend(placed.offsets);
            }
        }
        if let ClumpMode::Rigid = c.mode {
            let n = st.discs.len();
            for i in n - tpl.discs.len()..n {
                st.discs.group[i] = c.group;
            }
        }
    }
    for (k, a) in scene.auto_bonds.iter().enumerate() {
        let b = bonds
            .as_mut()
            .ok_or_else(|| fail("auto_bonds", "no bond groups".into()))?;
        let d = &st.discs;
        let allowed = |i: usize| a.materials.is_empty() || a.materials.contains(&d.material[i]);
        let choose = |i: usize, j: usize| {
            let ok = allowed(i)
                && allowed(j)
                && match a.between {
                    Between::All => true,
                    Between::DifferentGroups => d.group[i] != d.group[j],
                    Between::SameGroup => d.group[i] == d.group[j],
                };
            ok.then_some(a.bond_group as u16)
        };
        b.install_within_gap(&st, a.tolerance, choose)
            .map_err(|e| fail(&format!("auto_bonds[{k}]"), e.to_string()))?;
    }
    for w in &scene.walls {
        let mut wall = Wall::new(&w.name, w.a, w.b, w.material);
        wall.via.clone_from(&w.via);
        wall.v = w.velocity;
        wall.omega = w.angular_velocity;
        wall.center = w.center;
        wall.servo = w.servo;
        st.walls.push(wall);
    }
    let (params, laws) = (params(scene), laws(scene));
    let mut world = match bonds.filter(|b| !b.is_empty()) {
        // Bonds were made on creation indices; the world may reorder the discs.
        Some(b) => world_with_bonds(st, params, laws, b, &offsets),
        None => World::try_new(st, params, laws),
    }
    .map_err(|e| fail("world", e.to_string()))?;
    world.loads = scene.loads.clone();
    if let Some(budget) = scene.run.mass_scaling {
        world.scale_inertia(budget);
    }
    Ok(world)
}

/// The template with masses for the clump's material density: masses, inertias and density
/// times ρ_material/ρ_template. (The placement functions scale by the thickness ratio.)
fn scale_template(t: &Template, c: &ClumpInit) -> Template {
    let mut t = t.clone();
    let ratio = c.density_ratio;
    t.density *= ratio;
    for d in &mut t.discs {
        d.m *= ratio;
    }
    for p in [&mut t.achieved, &mut t.target] {
        p.mass *= ratio;
        p.inertia *= ratio;
        p.inertia_own *= ratio;
    }
    t
}

/// Rigid-body initial velocity v + ω × (x − centre) and spin ω for the discs `members`.
fn set_rigid_motion(
    st: &mut State,
    members: impl IntoIterator<Item = usize>,
    centre: [f64; 2],
    c: &ClumpInit,
) {
    let d = &mut st.discs;
    for i in members {
        let (rx, ry) = (d.x[i] - centre[0], d.y[i] - centre[1]);
        d.vx[i] = c.vx - c.omega * ry;
        d.vy[i] = c.vy + c.omega * rx;
        d.omega[i] = c.omega;
    }
}

fn wrap(st: &State, axis: usize, x: f64) -> f64 {
    let p = &st.periodic;
    match p.length[axis] {
        Some(l) if x < p.lo[axis] || x >= p.lo[axis] + l => p.wrap(axis, x),
        _ => x,
    }
}

/// Step parameters from the scene (engine defaults where the scene is silent).
pub fn params(scene: &Scene) -> Params {
    let d = Params::default();
    let r = &scene.run;
    Params {
        dt_factor: r.dt_factor.unwrap_or(d.dt_factor),
        dt_fixed: r.dt,
        local_damping: scene.damping.local,
        damping_frame: scene.damping.frame,
        viscous_damping: scene.damping.viscous,
        gravity: scene.gravity,
        skin: r.skin,
        max_overlap_fraction: r.max_overlap_fraction.unwrap_or(d.max_overlap_fraction),
        max_energy_growth: r.max_energy_growth.unwrap_or(d.max_energy_growth),
        ..d
    }
}

/// The engine's model of one pair law.
fn model(p: &PairLaw) -> ContactModel {
    match p.stiffness {
        PairStiffness::Granular(g) => ContactModel::Granular(g),
        PairStiffness::Hertz { e_star, g_star } => {
            // Hertz pairs carry a restitution (a non-zero damping ratio is refused at load).
            let e = match p.damping {
                NormalDamping::Restitution(e) => e,
                NormalDamping::Ratio(_) => 1.0,
            };
            ContactModel::HertzMindlin(HertzMindlin {
                e_star,
                g_star,
                eta: crate::contact::eta_for_restitution(e),
                restitution: e,
                mu: p.friction,
            })
        }
        PairStiffness::Linear { kn, ks } => ContactModel::Linear(LinearSpringDashpot {
            kn,
            ks,
            damping: match p.damping {
                NormalDamping::Restitution(e) => LinDamping::from_restitution(e),
                NormalDamping::Ratio(z) => LinDamping::Ratio(z),
            },
            shear_damping: 0.0,
            mu: p.friction,
        }),
    }
}

/// The contact-law table: every pair that can touch gets its law; pairs that never touch get
/// the law of the first material's own pair (they only enter the time-step floor, which takes
/// the stiffest law a disc's material has, so they must not be stiffer than a real pair).
pub fn laws(scene: &Scene) -> ContactLaws {
    let n = scene.materials.len();
    let Some(first) = scene.pairs.first() else {
        return ContactLaws::new(
            n,
            ContactModel::Linear(LinearSpringDashpot::elastic(1.0, 1.0, 0.0)),
        );
    };
    let mut laws = ContactLaws::new(n, model(first));
    // Unused pairs (a, b): a's own law if a makes discs, else b's, else the first pair's.
    for a in 0..n as u16 {
        for b in a..n as u16 {
            if scene.pair(a, b).is_some() {
                continue;
            }
            if let Some(p) = scene.pair(a, a).or_else(|| scene.pair(b, b)) {
                laws.set(a, b, model(p));
            }
        }
    }
    for p in &scene.pairs {
        laws.set(p.a, p.b, model(p));
        if let Some(mu_r) = p.rolling {
            laws.set_rolling(p.a, p.b, Some(RollingResistance::new(mu_r)));
        }
    }
    laws
}
