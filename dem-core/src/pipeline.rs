//! The World: state, parameters, contact laws, bonds, neighbour list with contact history,
//! and the step (see `docs/dem-core-design.md`).

use crate::bond::Bonds;
use crate::clump;
use crate::contact::disc_disc::{self, PassEnergy};
use crate::contact::{disc_segment, ContactLaws, ContactView};
use crate::counters::Counters;
use crate::energy::{EnergyAcc, EnergyReport};
use crate::integrate::{self, DiscCache, Kick, Moved};
use crate::neighbors::{pair_key, reorder, MinImage, Neighbors};
use crate::params::Params;
use crate::state::{State, FREE};
use crate::timestep;
use crate::validate::validate;
pub use crate::validate::WorldError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::Instant;

mod removal;
mod workspace;
pub use removal::{RemovalTotals, Removed};
use workspace::StepWorkspace;

/// The automatic step is raised only when the new estimate exceeds the current step by this
/// factor (it is lowered at once).
pub const DT_RAISE: f64 = 2.0;

/// A constant external force and torque on one disc (by stable id), applied every step
/// (e.g. a tip load, or a torque on a clump member, which acts on the whole clump). Its work
/// counts as boundary work in the energy balance.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct ExternalLoad {
    pub id: u32,
    pub force: [f64; 2],
    pub torque: f64,
}

/// The simulation: everything a checkpoint needs (all but `counters` is serialized, and a
/// deserialized World continues bit-identically).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct World {
    pub state: State,
    pub params: Params,
    pub laws: ContactLaws,
    pub bonds: Option<Bonds>,
    /// External loads applied every step (empty = none).
    pub loads: Vec<ExternalLoad>,
    #[serde(skip)]
    pub counters: Counters,
    pub(crate) nb: Neighbors,
    pub(crate) cache: DiscCache,
    /// Reference gaps g₀ keyed by [`pair_key`] of disc ids.
    pub(crate) offsets: BTreeMap<u64, f64>,
    pub(crate) index_of_id: Vec<u32>,
    pub(crate) dt: f64,
    pub(crate) dt_prev: f64,
    pub(crate) dt_crit: f64,
    pub(crate) energy: EnergyAcc,
    pub(crate) moved_too_far: bool,
    pub(crate) rebuild_requested: bool,
    /// The step's scratch ([`StepWorkspace`]): not state, left out of checkpoints.
    #[serde(skip)]
    pub(crate) ws: StepWorkspace,
    #[serde(skip)]
    pub(crate) last_good: Option<Box<State>>,
    /// Discs deleted so far ([`World::remove_discs`]); left out of checkpoints while none.
    #[serde(default, skip_serializing_if = "RemovalTotals::is_empty")]
    pub(crate) removed: RemovalTotals,
    /// What [`World::scale_inertia`] did, if it was called; left out of checkpoints while not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) mass_scaling: Option<crate::mass_scaling::MassScaling>,
}

impl World {
    /// Build a world; see [`World::try_new`] for the checks. Panics on invalid input (use
    /// `try_new` for input that comes from users).
    pub fn new(state: State, params: Params, laws: ContactLaws) -> World {
        match World::try_new(state, params, laws) {
            Ok(w) => w,
            Err(e) => panic!("World::new: {e}"),
        }
    }

    /// Build a world: validates the input, builds the neighbour list (reordering discs in
    /// space unless `params.reorder_every == 0`; use [`World::index_of_id`] to find a disc
    /// afterwards) and sets the time step.
    pub fn try_new(state: State, params: Params, laws: ContactLaws) -> Result<World, WorldError> {
        validate(&state, &params, &laws)?;
        let mut w = World {
            state,
            params,
            laws,
            bonds: None,
            loads: Vec::new(),
            counters: Counters::default(),
            nb: Neighbors::default(),
            cache: DiscCache::default(),
            offsets: BTreeMap::new(),
            index_of_id: Vec::new(),
            dt: 0.0,
            dt_prev: 0.0,
            dt_crit: 0.0,
            energy: EnergyAcc::default(),
            moved_too_far: false,
            rebuild_requested: true,
            ws: StepWorkspace::default(),
            last_good: None,
            removed: RemovalTotals::default(),
            mass_scaling: None,
        };
        w.rebuild_index();
        w.rebuild();
        if !(w.dt > 0.0 && w.dt.is_finite()) {
            return Err(WorldError::TimeStep(
                "no disc has a contact stiffness; set Params::dt_fixed".into(),
            ));
        }
        w.dt_prev = w.dt;
        Ok(w)
    }

    /// Makes a world read back from a checkpoint safe to step: deserialisation takes any
    /// values the file holds, and a checkpoint without a checksum (older files, or one edited
    /// by hand) may hold arrays of different lengths, indices out of range or non-finite
    /// values, which the step would meet as an out-of-range index or a failed assertion
    /// ("neighbour list out of date": found by fuzzing the checkpoint reader, issue 20). Checks
    /// what [`World::try_new`] checks, then the saved derived data: the neighbour list and its
    /// contact history, the disc caches, wall pairs, time steps, loads and bonds; rebuilds the
    /// id index (a function of the ids). A consistent checkpoint is unchanged, so a restart
    /// stays bit-identical.
    pub fn check_restored(&mut self) -> Result<(), WorldError> {
        self.laws.check_table()?;
        validate(&self.state, &self.params, &self.laws)?;
        self.rebuild_index();
        let bad = |what: String| Err(WorldError::Restored(what));
        let n = self.state.discs.len();
        let c = &self.cache;
        // (The viscous coefficients are empty without viscous damping.)
        let visc = if c.visc_t.is_empty() && c.visc_r.is_empty() {
            0
        } else {
            n
        };
        for (name, len, want) in [
            ("minv_contact", c.minv_contact.len(), n),
            ("inv_m", c.inv_m.len(), n),
            ("inv_i", c.inv_i.len(), n),
            ("visc_t", c.visc_t.len(), visc),
            ("visc_r", c.visc_r.len(), visc),
            ("k_trans", c.k_trans.len(), n),
            ("k_rot", c.k_rot.len(), n),
        ] {
            if len != want {
                return bad(format!("disc cache {name} has {len} entries for {n} discs"));
            }
        }
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if ![
            &c.minv_contact,
            &c.inv_m,
            &c.inv_i,
            &c.visc_t,
            &c.visc_r,
            &c.k_trans,
            &c.k_rot,
        ]
        .iter()
        .all(|v| finite(v))
        {
            return bad("the disc cache holds a non-finite value".into());
        }
        let nb = &self.nb;
        let np = nb.nbr.len();
        let offsets_ok = |start: &[u32]| {
            start.len() == n + 1
                && start.first() == Some(&0)
                && start.windows(2).all(|w| w[0] <= w[1])
                && start[n] as usize == np
        };
        if !offsets_ok(&nb.start) || !offsets_ok(&nb.rstart) {
            return bad(format!(
                "neighbour list offsets do not fit {n} discs and {np} pairs"
            ));
        }
        if nb.us.len() != np
            || nb.mr.len() != np
            || !(nb.g0.is_empty() || nb.g0.len() == np)
            || nb.rpair.len() != np
            || nb.x0.len() != n
            || nb.y0.len() != n
        {
            return bad("neighbour list arrays have different lengths".into());
        }
        if nb.nbr.iter().any(|&j| j as usize >= n) || nb.rpair.iter().any(|&p| p as usize >= np) {
            return bad("neighbour list index out of range".into());
        }
        let lists_finite = [&nb.us, &nb.mr, &nb.g0, &nb.x0, &nb.y0]
            .iter()
            .all(|v| finite(v));
        if !lists_finite || !nb.skin.is_finite() || nb.skin < 0.0 {
            return bad("neighbour list holds a non-finite value".into());
        }
        let nw = self.state.walls.len();
        let w = &nb.walls;
        // (`wall0` of another length only forces a rebuild: `Neighbors::max_wall_disp`.)
        if w.disc.len() != w.wall.len()
            || w.us.len() != w.wall.len()
            || w.mr.len() != w.wall.len()
            || w.wall.iter().any(|&k| k as usize >= nw)
            || w.disc.iter().any(|&i| i as usize >= n)
            || !finite(&w.us)
            || !finite(&w.mr)
            || !nb.wall0.iter().flatten().all(|x| x.is_finite())
            || !nb.wall0_via.iter().flatten().all(|x| x.is_finite())
        {
            return bad(format!("wall contacts do not fit {nw} walls and {n} discs"));
        }
        for (name, dt) in [("dt", self.dt), ("dt_prev", self.dt_prev)] {
            if !(dt > 0.0 && dt.is_finite()) {
                return bad(format!("{name} = {dt} must be positive"));
            }
        }
        if self.dt_crit.is_nan() || self.dt_crit < 0.0 {
            return bad(format!("dt_crit = {} must be ≥ 0", self.dt_crit));
        }
        if self.offsets.values().any(|g| !g.is_finite()) {
            return bad("a reference gap is not finite".into());
        }
        for l in &self.loads {
            if self.index_of_id(l.id).is_none() {
                return bad(format!(
                    "external load on disc id {}, which does not exist",
                    l.id
                ));
            }
            if !(l.force.iter().all(|f| f.is_finite()) && l.torque.is_finite()) {
                return bad(format!("external load on disc id {} is not finite", l.id));
            }
        }
        if let Some(b) = &self.bonds {
            b.check_restored(n)
                .map_err(|e| WorldError::Restored(e.to_string()))?;
        }
        Ok(())
    }

    /// Advance one time step (see the design doc for the stage order).
    pub fn step(&mut self) {
        self.step_inner(false);
    }

    /// One step. `batch`: inside [`World::run_while`], where nothing but the step touches the
    /// discs until the next one, so the integrator may pack the moved discs for the next
    /// disc–disc pass (see `Slots::packed_fresh`).
    fn step_inner(&mut self, batch: bool) {
        let t0 = Instant::now();
        self.ws.threads = crate::team::Threads::current();
        if self.needs_rebuild() {
            self.rebuild();
            // Discs may have been reordered: pack afresh.
            self.ws.slots.packed_fresh = false;
        }
        let t1 = Counters::lap(&mut self.counters.neighbours, t0);
        let track = self.params.track_energy;
        // Dashpot sums only when some law has a dashpot (else their dissipation is exactly +0,
        // see `contact::disc_disc::Dashpot`).
        let dash = track && self.laws.has_dashpots();
        let dt = self.dt;
        let img = MinImage::new(&self.state.periodic);
        self.counters.packed_by_integrator += u64::from(self.ws.slots.packed_fresh);
        // Parallel bonds evaluated with their pairs when they all can be and the pass takes
        // the uniform linear law without dashpot sums (`bond::fused`).
        let fv = match self.bonds.as_mut() {
            Some(b)
                if self.params.fuse_bonds
                    && disc_disc::uniform_linear(&self.state.discs, &self.laws, dash) =>
            {
                let nb = &self.nb;
                b.fused_view(nb.builds, &nb.start, &nb.nbr, self.state.thickness)
            }
            _ => None,
        };
        let fuse = fv.is_some();
        self.counters.bonds_fused += u64::from(fuse);
        // (The contact pass replaces the forces: no clearing needed.)
        let mut e = disc_disc::compute(
            &mut self.state.discs,
            &mut self.nb,
            &self.cache.minv_contact,
            &self.laws,
            img,
            dt,
            track,
            dash,
            &mut self.ws.slots,
            self.ws.threads.ranges,
            fv.as_ref(),
        );
        // The records are good for one pass only (whichever path the pass took).
        self.ws.slots.packed_fresh = false;
        self.apply_loads();
        let t2 = Counters::lap(&mut self.counters.contacts, t1);
        if !self.state.walls.is_empty() {
            let ew = disc_segment::compute(
                &mut self.state.discs,
                &mut self.state.walls,
                &mut self.nb.walls,
                &self.cache.minv_contact,
                &self.laws,
                img,
                dt,
                track,
                dash,
                &mut self.ws.slots.dashpot,
            );
            e.add(&ew);
        }
        let t3 = Counters::lap(&mut self.counters.walls, t2);
        if let (true, Some(b)) = (fuse, self.bonds.as_mut()) {
            b.after_fused(&self.state);
        } else if let Some(b) = self.bonds.as_mut() {
            // The contact pass's packed records still describe the discs (AVX2 only).
            let pk: &[_] = if self.ws.slots.packed_current {
                &self.ws.slots.packed
            } else {
                &[]
            };
            b.compute_packed(&mut self.state, dt, pk, self.ws.threads.ranges);
        }
        // Whether the records hold this step's discs (radii, masses) for the integrator.
        let records_current = self.ws.slots.packed_current;
        self.ws.slots.packed_current = false;
        let t4 = Counters::lap(&mut self.counters.bonds, t3);
        // Local damping in the fragment frame: its forces now, from this step's forces and
        // the half-step velocities; the integrator adds them in place of the sign rule.
        let frame = self.params.local_damping > 0.0
            && self.params.damping_frame == crate::damping::DampingFrame::Fragment;
        if frame {
            self.ws.frag.compute(
                &self.state,
                &self.cache.inv_m,
                self.bonds.as_ref(),
                &self.index_of_id,
                self.nb.builds,
                self.params.local_damping,
                self.params.gravity.unwrap_or([0.0; 2]),
            );
        }
        let no_rel: [Vec<f64>; 3] = Default::default();
        let (rel, rel_clumps): (&[Vec<f64>; 3], &[[f64; 3]]) = if frame {
            (&self.ws.frag.disc, &self.ws.frag.clump)
        } else {
            (&no_rel, &[])
        };
        let kick = Kick {
            kick: 0.5 * (self.dt_prev + dt),
            drift: dt,
            alpha: if frame {
                0.0
            } else {
                self.params.local_damping
            },
            gravity: self.params.gravity.unwrap_or([0.0; 2]),
            track,
            dash,
            disp2_limit: 0.25 * self.nb.skin * self.nb.skin,
        };
        let w_before = if track && !self.loads.is_empty() {
            self.load_work(dt)
        } else {
            0.0
        };
        // Rigid clumps move their members after the integrator: no packing then.
        let pack = batch
            && self.state.clumps.is_empty()
            && !self.ws.slots.portable
            && crate::lanes::has_avx2();
        if pack {
            self.ws
                .slots
                .packed
                .resize(self.state.discs.len(), Default::default());
        }
        let po = pack.then_some(integrate::PackOut {
            pk: self.ws.slots.packed.as_mut_ptr(),
            len: self.ws.slots.packed.len(),
            reuse: records_current,
        });
        let mut moved = integrate::integrate_discs(
            &mut self.state.discs,
            &self.ws.slots.dashpot,
            rel,
            &self.cache,
            &self.nb.x0,
            &self.nb.y0,
            &kick,
            &mut self.ws.parts,
            po,
            self.ws.threads.workers,
        );
        self.ws.slots.packed_fresh = pack;
        if !self.state.clumps.is_empty() {
            let visc = if self.params.viscous_damping > 0.0 {
                self.clump_viscosity()
            } else {
                Vec::new()
            };
            let mc = clump::step_clumps(
                &mut self.state,
                &self.index_of_id,
                &self.ws.slots.dashpot,
                &visc,
                rel_clumps,
                &self.nb.x0,
                &self.nb.y0,
                &kick,
                &mut self.ws.clump_trig,
            );
            moved.add(&mc);
        }
        integrate::advance_walls(&mut self.state.walls, dt);
        integrate::servo_walls(&mut self.state.walls, dt, self.state.thickness);
        if track && !self.loads.is_empty() {
            // F · (v(t − dt/2) + v(t + dt/2))/2 · dt: the discrete work-energy identity of
            // central differences.
            moved.boundary_work += 0.5 * (w_before + self.load_work(dt));
        }
        self.moved_too_far = moved.exceeded;
        if track {
            self.account(&e, &moved);
        }
        self.state.time += dt;
        self.state.step += 1;
        self.dt_prev = dt;
        self.counters.steps += 1;
        Counters::lap(&mut self.counters.integrate, t4);
    }

    /// Run `steps` steps.
    pub fn run(&mut self, steps: u64) {
        self.run_while(steps, |_| true);
    }

    /// Run at most `steps` steps, stopping after a step when `go_on` (which sees the world,
    /// read-only) returns false; returns the steps run. Same results as calling
    /// [`World::step`] that many times, faster: nothing can change the discs between the
    /// steps of a batch, so each step's integrator packs the moved discs for the next
    /// disc–disc pass while they are in cache (see `Slots::packed_fresh`).
    pub fn run_while(&mut self, steps: u64, mut go_on: impl FnMut(&World) -> bool) -> u64 {
        let mut done = 0;
        while done < steps {
            self.step_inner(true);
            done += 1;
            if !go_on(self) {
                break;
            }
        }
        // After the batch anyone may change the discs: the next pass packs them.
        self.ws.slots.packed_fresh = false;
        done
    }

    /// Current time step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// min √(m/K), √(I/K_rot) of the last estimate, before the safety factor (s).
    pub fn critical_dt(&self) -> f64 {
        self.dt_crit
    }

    /// Selective mass scaling ([`crate::mass_scaling`]): raise the mass and the moment of
    /// inertia of the free discs whose time-step bound is below the target step T, the
    /// largest T whose added mass and added spin inertia stay within `budget` (fractions of
    /// the free discs' totals), then take a fresh time-step estimate. Call it before the run,
    /// with the discs at rest (a moving disc made heavier would gain momentum). `budget` ≤ 0
    /// changes nothing. The report is kept ([`World::mass_scaling`]) and goes into
    /// checkpoints.
    pub fn scale_inertia(&mut self, budget: f64) -> crate::mass_scaling::MassScaling {
        self.refresh();
        let before = self.dt_crit;
        let c = &self.cache;
        let free: Vec<usize> = (0..c.inv_m.len()).filter(|&i| c.inv_m[i] > 0.0).collect();
        let d = &mut self.state.discs;
        let mut report = crate::mass_scaling::scale_discs(
            &mut d.m,
            &mut d.inertia,
            &c.k_trans,
            &c.k_rot,
            &free,
            budget,
        );
        if report.budget > 0.0 {
            self.refresh();
            // Before the run: the first kick uses this step, not the unscaled one.
            self.dt_prev = self.dt;
        }
        report.critical_dt_before = before;
        report.critical_dt_after = self.dt_crit;
        self.mass_scaling = Some(report.clone());
        report
    }

    /// The report of [`World::scale_inertia`], if the world's discs were scaled.
    pub fn mass_scaling(&self) -> Option<&crate::mass_scaling::MassScaling> {
        self.mass_scaling.as_ref()
    }

    /// Every body's time-step bound of the last estimate, smallest first
    /// ([`crate::timestep::bounds`]): which discs set the step, by mass or by inertia.
    pub fn dt_bounds(&self) -> Vec<crate::timestep::DtBound> {
        crate::timestep::bounds(&self.state, &self.cache, &self.index_of_id)
    }

    /// Energies at the time of the last step (see [`crate::energy`]). Before the first step
    /// (no step has accounted anything yet) the kinetic energy and the gravity potential are
    /// those of the state as given, ½mv² + ½Iω² and −m g·x over the free discs and the
    /// clumps; contact strain is 0 then (no contact pass has run) and bond strain is the
    /// bonds' own.
    pub fn energy(&self) -> EnergyReport {
        let wall_work: f64 = self.state.walls.iter().map(|w| w.work).sum();
        let (sb, rb) = self
            .bonds
            .as_ref()
            .map_or((0.0, 0.0), |b| (b.strain_energy(), b.released_energy()));
        if self.energy.initial.is_some() {
            return EnergyReport::new(&self.energy, wall_work, sb, rb);
        }
        let mut acc = self.energy.clone();
        let [gx, gy] = self.params.gravity.unwrap_or([0.0, 0.0]);
        let d = &self.state.discs;
        for i in 0..d.len() {
            if d.body[i] == FREE && !d.fixed[i] {
                acc.kin_trans += 0.5 * d.m[i] * (d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i]);
                acc.kin_rot += 0.5 * d.inertia[i] * d.omega[i] * d.omega[i];
                acc.grav_pot -= d.m[i] * (gx * d.x[i] + gy * d.y[i]);
            }
        }
        let c = &self.state.clumps;
        for k in 0..c.len() {
            acc.kin_trans += 0.5 * c.m[k] * (c.vx[k] * c.vx[k] + c.vy[k] * c.vy[k]);
            acc.kin_rot += 0.5 * c.inertia[k] * c.omega[k] * c.omega[k];
            acc.grav_pot -= c.m[k] * (gx * c.x[k] + gy * c.y[k]);
        }
        EnergyReport::new(&acc, wall_work, sb, rb)
    }

    /// Names of the stages this world runs, in order.
    pub fn active_stages(&self) -> Vec<&'static str> {
        let mut s = vec!["neighbours", "contacts"];
        if !self.state.walls.is_empty() {
            s.push("walls");
        }
        if self.bonds.is_some() {
            s.push("bonds");
        }
        if !self.state.clumps.is_empty() {
            s.push("clumps");
        }
        if self.params.gravity.is_some() {
            s.push("gravity");
        }
        if self.params.local_damping > 0.0 {
            s.push("local damping");
        }
        if self.params.viscous_damping > 0.0 {
            s.push("viscous damping");
        }
        s.push("integrate");
        if self.params.track_energy {
            s.push("energy");
        }
        s
    }

    /// Register the reference gap g₀ (≤ 0, clamped) of the pair of discs with ids `id_a`,
    /// `id_b`: the contact then acts on δ = g₀ − gap. Takes effect at the next step.
    pub fn set_contact_offset(&mut self, id_a: u32, id_b: u32, g0: f64) {
        self.offsets.insert(pair_key(id_a, id_b), g0.min(0.0));
        self.rebuild_requested = true;
    }

    /// Rebuild the neighbour list and take a fresh time-step estimate (without the raise
    /// hysteresis) now: call after editing positions, radii, masses, fixed flags or materials
    /// of discs, or the time-step parameters, directly.
    pub fn refresh(&mut self) {
        self.rebuild_index();
        self.dt = 0.0;
        self.rebuild();
    }

    /// Current index of the disc with stable id `id`.
    pub fn index_of_id(&self, id: u32) -> Option<usize> {
        self.index_of_id
            .get(id as usize)
            .filter(|&&k| k != u32::MAX)
            .map(|&k| k as usize)
    }

    /// Number of listed (potential contact) pairs.
    pub fn n_pairs(&self) -> usize {
        self.nb.n_pairs()
    }

    /// Touching pairs (overlap beyond the reference gap > 0).
    pub fn contacts(&self) -> impl Iterator<Item = ContactView> + '_ {
        self.near_pairs(f64::NEG_INFINITY)
            .filter(|c| c.overlap > 0.0)
    }

    /// Listed pairs whose gap (|x_j − x_i| − r_i − r_j) is at most `max_gap`, plus touching
    /// pairs when `max_gap` is −∞ (used with a filter by [`World::contacts`]).
    pub fn near_pairs(&self, max_gap: f64) -> impl Iterator<Item = ContactView> + '_ {
        let st = &self.state;
        let d = &st.discs;
        let img = MinImage::new(&st.periodic);
        let nb = &self.nb;
        let n = if nb.start.len() == d.len() + 1 {
            d.len()
        } else {
            0
        };
        (0..n).flat_map(move |i| {
            (nb.start[i] as usize..nb.start[i + 1] as usize).filter_map(move |p| {
                let j = nb.nbr[p] as usize;
                let (dx, dy) = img.delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
                let dist = (dx * dx + dy * dy).sqrt();
                let gap = dist - d.r[i] - d.r[j];
                let g0 = nb.g0.get(p).copied().unwrap_or(0.0);
                let overlap = g0 - gap;
                if !(max_gap == f64::NEG_INFINITY || gap <= max_gap) || dist <= 0.0 {
                    return None;
                }
                let (nx, ny) = (dx / dist, dy / dist);
                let r_eff = d.r[i] * d.r[j] / (d.r[i] + d.r[j]);
                let model = self.laws.model(d.material[i], d.material[j]);
                let (f_n, f_t) = if overlap > 0.0 {
                    model.spring_forces(r_eff, overlap, nb.us[p])
                } else {
                    (0.0, 0.0)
                };
                // Midway in the geometric overlap (the force pass's contact point).
                let s = d.r[i] - 0.5 * (-gap).max(0.0);
                Some(ContactView {
                    i: i as u32,
                    j: j as u32,
                    id_i: d.id[i],
                    id_j: d.id[j],
                    gap,
                    overlap,
                    normal: [nx, ny],
                    point: [d.x[i] + s * nx, d.y[i] + s * ny],
                    f_n,
                    f_t,
                })
            })
        })
    }

    fn apply_loads(&mut self) {
        let d = &mut self.state.discs;
        for l in &self.loads {
            if let Some(&i) = self.index_of_id.get(l.id as usize) {
                let i = i as usize;
                if i < d.len() {
                    d.fx[i] += l.force[0];
                    d.fy[i] += l.force[1];
                    d.torque[i] += l.torque;
                }
            }
        }
    }

    /// F · v · dt of the external loads with the current velocities.
    fn load_work(&self, dt: f64) -> f64 {
        let d = &self.state.discs;
        let mut w = 0.0;
        for l in &self.loads {
            if let Some(&i) = self.index_of_id.get(l.id as usize) {
                let i = i as usize;
                if i < d.len() {
                    w += (l.force[0] * d.vx[i] + l.force[1] * d.vy[i] + l.torque * d.omega[i]) * dt;
                }
            }
        }
        w
    }

    fn needs_rebuild(&self) -> bool {
        let half = 0.5 * self.nb.skin;
        self.rebuild_requested
            || self.nb.x0.len() != self.state.discs.len()
            || self.moved_too_far
            || self.nb.max_wall_disp(&self.state.walls) > half
    }

    fn rebuild_index(&mut self) {
        let ids = &self.state.discs.id;
        let m = ids.iter().map(|&i| i as usize + 1).max().unwrap_or(0);
        self.index_of_id.clear();
        self.index_of_id.resize(m, u32::MAX);
        for (k, &id) in ids.iter().enumerate() {
            self.index_of_id[id as usize] = k as u32;
        }
    }

    /// Wrap periodic positions, reorder (when due), rebuild the list, caches and time step.
    pub(crate) fn rebuild(&mut self) {
        self.counters.rebuilds += 1;
        self.wrap_periodic();
        let every = self.params.reorder_every as u64;
        let due = every > 0 && self.nb.builds.is_multiple_of(every);
        if due {
            if let Some((order, new_of_old)) = reorder::spatial_order(&self.state) {
                self.state.discs.permute(&order);
                self.nb.remap(&new_of_old);
                if let Some(b) = self.bonds.as_mut() {
                    b.remap(&new_of_old);
                }
                self.rebuild_index();
                self.counters.reorders += 1;
            }
        }
        let skin = self.skin();
        self.nb.rebuild(&self.state, skin, &self.offsets);
        self.fill_cache();
        timestep::disc_stiffness(
            &self.state,
            &self.nb,
            &self.laws,
            &self.params,
            self.bonds.as_ref(),
            &mut self.cache,
        );
        self.dt_crit = timestep::critical_dt(&self.state, &self.cache, &self.index_of_id)
            .unwrap_or(f64::INFINITY);
        self.dt = match self.params.dt_fixed {
            Some(dt) => dt,
            None => {
                // Decrease at once; increase only by a clear margin, so that the step does not
                // flip at every rebuild (leapfrog with a varying step is not symplectic).
                let want = self.params.dt_factor * self.dt_crit;
                if self.dt <= 0.0 || want < self.dt || want > DT_RAISE * self.dt {
                    want
                } else {
                    self.dt
                }
            }
        };
        if self.params.viscous_damping > 0.0 {
            let z = 2.0 * self.params.viscous_damping;
            let d = &self.state.discs;
            self.cache.visc_t = (0..d.len())
                .map(|i| z * (d.m[i] * self.cache.k_trans[i]).sqrt())
                .collect();
            self.cache.visc_r = (0..d.len())
                .map(|i| z * (d.inertia[i] * self.cache.k_rot[i]).sqrt())
                .collect();
        } else {
            self.cache.visc_t.clear();
            self.cache.visc_r.clear();
        }
        self.moved_too_far = false;
        self.rebuild_requested = false;
    }

    fn skin(&self) -> f64 {
        self.params.skin.unwrap_or_else(|| {
            let rmin = self
                .state
                .discs
                .r
                .iter()
                .cloned()
                .fold(f64::INFINITY, f64::min);
            if rmin.is_finite() {
                0.2 * rmin
            } else {
                0.0
            }
        })
    }

    fn fill_cache(&mut self) {
        let d = &self.state.discs;
        let c = &mut self.cache;
        c.minv_contact = (0..d.len())
            .map(|i| if d.fixed[i] { 0.0 } else { 1.0 / d.m[i] })
            .collect();
        let free = |i: usize| !d.fixed[i] && d.body[i] == FREE;
        c.inv_m = (0..d.len())
            .map(|i| if free(i) { 1.0 / d.m[i] } else { 0.0 })
            .collect();
        c.inv_i = (0..d.len())
            .map(|i| if free(i) { 1.0 / d.inertia[i] } else { 0.0 })
            .collect();
    }

    fn clump_viscosity(&self) -> Vec<[f64; 2]> {
        let z = 2.0 * self.params.viscous_damping;
        let cl = &self.state.clumps;
        timestep::clump_stiffness(&self.state, &self.cache, &self.index_of_id)
            .iter()
            .enumerate()
            .map(|(c, k)| {
                [
                    z * (cl.m[c] * k[0]).sqrt(),
                    z * (cl.inertia[c] * k[1]).sqrt(),
                ]
            })
            .collect()
    }

    fn wrap_periodic(&mut self) {
        let p = self.state.periodic;
        if p.length == [None, None] {
            return;
        }
        let d = &mut self.state.discs;
        for i in 0..d.len() {
            if d.body[i] == FREE {
                d.x[i] = wrap(&p, 0, d.x[i]);
                d.y[i] = wrap(&p, 1, d.y[i]);
            }
        }
        let cl = &mut self.state.clumps;
        let mut moved = false;
        for c in 0..cl.len() {
            let (x, y) = (wrap(&p, 0, cl.x[c]), wrap(&p, 1, cl.y[c]));
            moved |= x != cl.x[c] || y != cl.y[c];
            cl.x[c] = x;
            cl.y[c] = y;
        }
        if moved {
            clump::place_members(&mut self.state, &self.index_of_id);
        }
    }

    fn account(&mut self, e: &PassEnergy, m: &Moved) {
        let a = &mut self.energy;
        a.kin_trans = m.ke_trans;
        a.kin_rot = m.ke_rot;
        a.strain_contact = e.strain;
        a.grav_pot = m.grav_pot;
        a.damp_contact += e.damp + m.damp_contact;
        a.damp_body += m.damp;
        a.friction += e.fric;
        a.fixed_work += m.boundary_work;
        if a.initial.is_none() {
            let sb = self.bonds.as_ref().map_or(0.0, |b| b.strain_energy());
            a.initial = Some(a.kin_trans + a.kin_rot + a.strain_contact + sb + a.grav_pot);
            a.initial_grav = a.grav_pot;
        }
    }
}

/// Wrap a coordinate into the periodic box only when it is outside (keeps bits otherwise).
fn wrap(p: &crate::state::Periodic, axis: usize, x: f64) -> f64 {
    match p.length[axis] {
        Some(l) if x < p.lo[axis] || x >= p.lo[axis] + l => p.wrap(axis, x),
        _ => x,
    }
}
