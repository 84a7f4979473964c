//! Deleting discs from a running world ([`World::remove_discs`]), e.g. debris that has left the
//! region of interest (the common DEM practice of deleting particles that leave the model,
//! Itasca PFC `ball delete`; for cutting debris see `docs/cutting.md`, "Deleting fragments").
//!
//! The remaining discs keep their ids, state, bonds (ids, forces, status) and contact
//! histories (tangential springs, rolling moments, reference gaps): the disc arrays are
//! compacted in their current order, the neighbour list and the bond store drop the pairs and
//! bonds of deleted discs and renumber the rest (the order of the survivors is unchanged, so
//! every per-disc sum keeps its order), rigid clumps are compacted, and the neighbour list,
//! caches and time step are rebuilt at once ([`World::refresh`]'s machinery).
//!
//! Energy: what the deleted discs carry is booked as `removed` in the energy balance
//! ([`crate::energy`]), evaluated at the deletion: kinetic ½mv² + ½Iω² with the current
//! (half-step) velocities of free discs and of deleted rigid clumps, the strain of the
//! touching contacts (disc–disc and disc–wall) with a deleted disc at the current positions
//! (½k_nδ² or the Hertz 2/5·F_nδ, plus ½k_s u_s² and ½M_r²/k_r, the laws' stored energies),
//! the strain of the intact bonds dropped ([`crate::bond::Bonds::drop_discs`]) and the
//! gravity potential −m g·x. The half-step velocity instead of the step's mean makes the
//! booked kinetic energy differ from the balance's by O(F·v·Δt) of the deleted discs: nothing
//! for debris in free flight, and small against the energies of a cut (tested).

use super::World;
use crate::contact::ContactModel;
use crate::neighbors::{closest_on_wall, MinImage, Neighbors};
use crate::state::FREE;
use crate::validate::WorldError;
use serde::{Deserialize, Serialize};

/// What one call of [`World::remove_discs`] deleted (SI: kg, J).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Removed {
    pub discs: usize,
    /// Rigid clumps deleted with all their members.
    pub clumps: usize,
    /// Bonds dropped (intact and broken) with a deleted disc.
    pub bonds: usize,
    /// Touching contacts (disc–disc and disc–wall) with a deleted disc.
    pub contacts: usize,
    /// Σ m of the deleted discs (clump members: their shares of the clump mass).
    pub mass: f64,
    /// Kinetic energy of the deleted free discs and clumps (translation + rotation).
    pub kinetic: f64,
    /// Strain energy of their contacts and intact bonds.
    pub strain: f64,
    /// Their gravity potential −m g·x (0 without gravity).
    pub gravity: f64,
    /// kinetic + strain + gravity: booked as `removed` in the energy balance (when the world
    /// tracks energy and has taken a step; before the first step the balance has not started
    /// and nothing is booked).
    pub energy: f64,
}

/// Everything deleted from a world since it was built (serialized with the world, so it
/// survives checkpoints; left out while nothing was deleted).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RemovalTotals {
    /// Calls of [`World::remove_discs`] that deleted at least one disc.
    pub removals: u64,
    pub discs: u64,
    pub clumps: u64,
    pub bonds: u64,
    pub mass: f64,
    pub kinetic: f64,
    pub energy: f64,
}

impl RemovalTotals {
    /// Nothing was deleted.
    pub fn is_empty(&self) -> bool {
        self.removals == 0
    }
}

/// Elastic energy of the normal spring at overlap δ > 0: ½k_nδ² (linear) or ∫F dδ = 2/5·F_n·δ
/// (Hertz, F_n ∝ δ^{3/2}).
fn normal_energy(model: &ContactModel, r_eff: f64, delta: f64) -> f64 {
    match model {
        ContactModel::Linear(l) => 0.5 * l.kn * delta * delta,
        ContactModel::HertzMindlin(h) => 0.4 * h.spring_normal(r_eff, delta) * delta,
        ContactModel::Granular(g) => crate::contact::granular::spring_normal(g, r_eff, delta).1,
    }
}

impl World {
    /// Delete the discs with ids `ids` (duplicates are ignored) from the running world: their
    /// bonds and contact histories go with them, the other discs keep their ids, state, bonds
    /// and contact histories, and the energy they carry is booked as `removed` in the energy
    /// balance (see the module doc). External loads on deleted discs and reference gaps of
    /// their pairs are dropped. A member of a rigid clump can only be deleted with all the
    /// clump's members (the clump is then deleted). On error nothing changes.
    ///
    /// Not for the hot loop: it rebuilds the neighbour list (one O(n) pass plus a build).
    pub fn remove_discs(&mut self, ids: &[u32]) -> Result<Removed, WorldError> {
        let n = self.state.discs.len();
        let mut gone = vec![false; n];
        for &id in ids {
            let k = self
                .index_of_id(id)
                .filter(|&k| k < n && self.state.discs.id[k] == id)
                .ok_or_else(|| WorldError::Disc {
                    id,
                    reason: "cannot remove it: the world has no disc with this id".into(),
                })?;
            gone[k] = true;
        }
        let cl = &self.state.clumps;
        let mut clump_gone = vec![false; cl.len()];
        for (c, g) in clump_gone.iter_mut().enumerate() {
            let mut count = 0;
            let range = cl.member_range(c);
            for &id in &cl.members[range.clone()] {
                count += usize::from(
                    self.index_of_id(id)
                        .is_some_and(|k| gone.get(k) == Some(&true)),
                );
            }
            if count > 0 && count < range.len() {
                return Err(WorldError::Clump {
                    index: c,
                    reason: format!(
                        "cannot remove {count} of its {} members: a rigid clump is removed \
                         with all its members or not at all",
                        range.len()
                    ),
                });
            }
            *g = count > 0;
        }
        let mut out = Removed {
            discs: gone.iter().filter(|&&g| g).count(),
            clumps: clump_gone.iter().filter(|&&g| g).count(),
            ..Removed::default()
        };
        if out.discs == 0 {
            return Ok(out);
        }
        self.removed_energy(&gone, &clump_gone, &mut out);
        // Compact, in the current order.
        let mut new_of_old = vec![u32::MAX; n];
        let mut order = Vec::with_capacity(n - out.discs);
        for (k, &g) in gone.iter().enumerate() {
            if !g {
                new_of_old[k] = order.len() as u32;
                order.push(k as u32);
            }
        }
        let mut removed_ids: Vec<u32> = (0..n)
            .filter(|&k| gone[k])
            .map(|k| self.state.discs.id[k])
            .collect();
        removed_ids.sort_unstable();
        let is_gone = |id: u32| removed_ids.binary_search(&id).is_ok();
        drop_pairs(&mut self.nb, &new_of_old, order.len());
        if let Some(b) = self.bonds.as_mut() {
            let (nb, e) = b.drop_discs(&new_of_old);
            out.bonds = nb;
            out.strain += e;
            out.energy += e;
        }
        self.state.discs.permute(&order);
        self.drop_clumps(&clump_gone);
        self.loads.retain(|l| !is_gone(l.id));
        self.offsets
            .retain(|&key, _| !(is_gone((key >> 32) as u32) || is_gone(key as u32)));
        if self.books_removal() {
            self.energy.removed += out.energy;
        }
        let t = &mut self.removed;
        t.removals += 1;
        t.discs += out.discs as u64;
        t.clumps += out.clumps as u64;
        t.bonds += out.bonds as u64;
        t.mass += out.mass;
        t.kinetic += out.kinetic;
        t.energy += out.energy;
        // Derived data: the next pass packs afresh; the clump angles are recomputed.
        self.ws.slots.packed_fresh = false;
        self.ws.slots.packed_current = false;
        self.ws.clump_trig.clear();
        self.rebuild_index();
        self.rebuild_requested = true;
        self.rebuild();
        Ok(out)
    }

    /// Everything deleted since the world was built.
    pub fn removal_totals(&self) -> &RemovalTotals {
        &self.removed
    }

    /// Mass and energies of the discs marked `gone` (and clumps `clump_gone`) into `out`
    /// (bonds are added by the caller); takes their present energies out of the last step's
    /// sums so that [`World::energy`] is consistent until the next step.
    fn removed_energy(&mut self, gone: &[bool], clump_gone: &[bool], out: &mut Removed) {
        let st = &self.state;
        let d = &st.discs;
        let g = self.params.gravity.unwrap_or([0.0; 2]);
        let (mut kt, mut kr, mut gp, mut sc) = (0.0, 0.0, 0.0, 0.0);
        for k in (0..d.len()).filter(|&k| gone[k]) {
            out.mass += d.m[k];
            if !d.fixed[k] && d.body[k] == FREE {
                kt += 0.5 * d.m[k] * (d.vx[k] * d.vx[k] + d.vy[k] * d.vy[k]);
                kr += 0.5 * d.inertia[k] * d.omega[k] * d.omega[k];
                gp -= d.m[k] * (g[0] * d.x[k] + g[1] * d.y[k]);
            }
        }
        let cl = &st.clumps;
        for c in (0..cl.len()).filter(|&c| clump_gone[c]) {
            kt += 0.5 * cl.m[c] * (cl.vx[c] * cl.vx[c] + cl.vy[c] * cl.vy[c]);
            kr += 0.5 * cl.inertia[c] * cl.omega[c] * cl.omega[c];
            gp -= cl.m[c] * (g[0] * cl.x[c] + g[1] * cl.y[c]);
        }
        // Contacts of deleted discs at the current positions.
        let nb = &self.nb;
        let img = MinImage::new(&st.periodic);
        let laws = &self.laws;
        let rolling = |mi: u16, mj: u16, kn: f64, r_eff: f64, mr: f64| {
            laws.rolling(mi, mj).map_or(0.0, |rr| {
                let k = rr.kr(kn, r_eff);
                if k > 0.0 {
                    0.5 * mr * mr / k
                } else {
                    0.0
                }
            })
        };
        if nb.start.len() == d.len() + 1 {
            for i in 0..d.len() {
                for p in nb.start[i] as usize..nb.start[i + 1] as usize {
                    let j = nb.nbr[p] as usize;
                    if !(gone[i] || gone[j]) {
                        continue;
                    }
                    let (dx, dy) = img.delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
                    let gap = (dx * dx + dy * dy).sqrt() - d.r[i] - d.r[j];
                    let delta = nb.g0.get(p).copied().unwrap_or(0.0) - gap;
                    if delta <= 0.0 {
                        continue;
                    }
                    let r_eff = d.r[i] * d.r[j] / (d.r[i] + d.r[j]);
                    let (mi, mj) = (d.material[i], d.material[j]);
                    let model = laws.model(mi, mj);
                    sc += normal_energy(model, r_eff, delta)
                        + model.shear_energy(r_eff, delta, nb.us[p])
                        + rolling(mi, mj, model.kn(r_eff, delta), r_eff, nb.mr[p]);
                    out.contacts += 1;
                }
            }
        }
        let wp = &nb.walls;
        for q in 0..wp.wall.len() {
            let (Some(w), k) = (st.walls.get(wp.wall[q] as usize), wp.disc[q] as usize) else {
                continue;
            };
            // (Fixed discs do not touch walls, see `contact::disc_segment`.)
            if k >= d.len() || !gone[k] || d.fixed[k] {
                continue;
            }
            let (_, _, dist) = closest_on_wall(w, d.x[k], d.y[k], &img);
            let (r, delta) = (d.r[k], d.r[k] - dist);
            if delta <= 0.0 || dist <= 0.0 {
                continue;
            }
            let model = laws.model(d.material[k], w.material);
            sc += normal_energy(model, r, delta)
                + model.shear_energy(r, delta, wp.us[q])
                + rolling(d.material[k], w.material, model.kn(r, delta), r, wp.mr[q]);
            out.contacts += 1;
        }
        out.kinetic = kt + kr;
        out.strain += sc;
        out.gravity = gp;
        out.energy = kt + kr + sc + gp;
        if self.books_removal() {
            let a = &mut self.energy;
            a.kin_trans -= kt;
            a.kin_rot -= kr;
            a.strain_contact -= sc;
            a.grav_pot -= gp;
        }
    }

    /// Whether a deletion now is booked in the energy balance: it tracks energy and has
    /// started (the first step sets the initial energy).
    fn books_removal(&self) -> bool {
        self.params.track_energy && self.energy.initial.is_some()
    }

    /// Delete the clumps marked `gone` (their members are already gone) and renumber the
    /// others in the discs' `body`.
    fn drop_clumps(&mut self, gone: &[bool]) {
        if !gone.iter().any(|&g| g) {
            return;
        }
        let cl = &mut self.state.clumps;
        let keep: Vec<u32> = (0..cl.len() as u32)
            .filter(|&c| !gone[c as usize])
            .collect();
        let mut new_of_old = vec![FREE; cl.len()];
        for (new, &c) in keep.iter().enumerate() {
            new_of_old[c as usize] = new as u32;
        }
        fn p<T: Clone>(v: &mut Vec<T>, order: &[u32]) {
            let old = std::mem::take(v);
            *v = order.iter().map(|&k| old[k as usize].clone()).collect();
        }
        let (mut members, mut ox, mut oy) = (Vec::new(), Vec::new(), Vec::new());
        let mut start = vec![0u32];
        for &c in &keep {
            let r = cl.member_range(c as usize);
            members.extend_from_slice(&cl.members[r.clone()]);
            ox.extend_from_slice(&cl.offset_x[r.clone()]);
            oy.extend_from_slice(&cl.offset_y[r]);
            start.push(members.len() as u32);
        }
        (cl.members, cl.offset_x, cl.offset_y, cl.member_start) = (members, ox, oy, start);
        for v in [
            &mut cl.x,
            &mut cl.y,
            &mut cl.theta,
            &mut cl.vx,
            &mut cl.vy,
            &mut cl.omega,
            &mut cl.m,
            &mut cl.inertia,
            &mut cl.fx,
            &mut cl.fy,
            &mut cl.torque,
        ] {
            p(v, &keep);
        }
        p(&mut cl.template, &keep);
        for b in &mut self.state.discs.body {
            if *b != FREE {
                *b = new_of_old[*b as usize];
            }
        }
    }
}

/// Drop the pairs (disc–disc and disc–wall) of deleted discs from the list and renumber the
/// others (`new_of_old[old]` = new index or `u32::MAX`; survivors keep their order, so the
/// list stays sorted), keeping their histories and reference gaps. `n_new` discs remain. The
/// positions at the last build are cleared: the caller rebuilds the list.
fn drop_pairs(nb: &mut Neighbors, new_of_old: &[u32], n_new: usize) {
    const GONE: u32 = u32::MAX;
    let n = new_of_old.len();
    if nb.start.len() == n + 1 {
        let has_g0 = !nb.g0.is_empty();
        let mut start = vec![0u32; n_new + 1];
        let mut w = 0;
        for (i, &a) in new_of_old.iter().enumerate() {
            for p in nb.start[i] as usize..nb.start[i + 1] as usize {
                let b = new_of_old.get(nb.nbr[p] as usize).copied().unwrap_or(GONE);
                if a == GONE || b == GONE {
                    continue;
                }
                nb.nbr[w] = b;
                nb.us[w] = nb.us[p];
                nb.mr[w] = nb.mr[p];
                if has_g0 {
                    nb.g0[w] = nb.g0[p];
                }
                start[a as usize + 1] += 1;
                w += 1;
            }
        }
        nb.nbr.truncate(w);
        nb.us.truncate(w);
        nb.mr.truncate(w);
        if has_g0 {
            nb.g0.truncate(w);
        }
        for i in 0..n_new {
            start[i + 1] += start[i];
        }
        nb.start = start;
    } else {
        // No list for these discs: the rebuild starts a fresh one.
        nb.start.clear();
        nb.nbr.clear();
        nb.us.clear();
        nb.mr.clear();
        nb.g0.clear();
    }
    let wp = &mut nb.walls;
    let mut w = 0;
    for q in 0..wp.wall.len() {
        let k = wp.disc[q] as usize;
        let Some(&new) = new_of_old.get(k).filter(|&&v| v != GONE) else {
            continue;
        };
        wp.wall[w] = wp.wall[q];
        wp.disc[w] = new;
        wp.us[w] = wp.us[q];
        wp.mr[w] = wp.mr[q];
        w += 1;
    }
    wp.wall.truncate(w);
    wp.disc.truncate(w);
    wp.us.truncate(w);
    wp.mr.truncate(w);
    nb.rstart.clear();
    nb.rpair.clear();
    nb.owner.clear();
    nb.x0.clear();
    nb.y0.clear();
    nb.verified = false;
}
