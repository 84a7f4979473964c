//! The world: spheres, walls, laws, configuration, contact lists and the step.

use crate::contact::{self, Body, Hist, PairContact, PairOut};
use crate::energy::{EnergyAcc, EnergyReport};
use crate::error::{finite3, positive, SphereError};
use crate::grid::{find_pairs, GridKind, GridStats, Periodic};
use crate::state::{Scratch, Spheres};
use crate::walls::Plane;
use dem_laws::GranularLaw;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Laws by species: `pair[s_i * n + s_j]` (symmetric) for sphere pairs, `wall[s]` for a
/// sphere of species s on a wall.
#[derive(Clone, Debug, PartialEq)]
pub struct Laws {
    n: usize,
    pair: Vec<GranularLaw>,
    wall: Vec<GranularLaw>,
}

impl Laws {
    /// One species: `pair` between spheres, `wall` between a sphere and a wall.
    pub fn single(pair: GranularLaw, wall: GranularLaw) -> Laws {
        Laws {
            n: 1,
            pair: vec![pair],
            wall: vec![wall],
        }
    }

    /// `n` species from a full n×n table (must be symmetric) and n wall laws.
    pub fn table(pair: Vec<GranularLaw>, wall: Vec<GranularLaw>) -> Result<Laws, SphereError> {
        let n = wall.len();
        if n == 0 || n > u16::MAX as usize || pair.len() != n * n {
            return Err(SphereError::invalid(
                "laws.pair",
                format!(
                    "needs n² = {} laws for n = {n} wall laws, got {}",
                    n * n,
                    pair.len()
                ),
            ));
        }
        for a in 0..n {
            for b in 0..a {
                if pair[a * n + b] != pair[b * n + a] {
                    return Err(SphereError::invalid(
                        format!("laws.pair[{a}][{b}]"),
                        format!("must equal laws.pair[{b}][{a}] (the table is symmetric)"),
                    ));
                }
            }
        }
        Ok(Laws { n, pair, wall })
    }

    /// Number of species.
    pub fn species(&self) -> usize {
        self.n
    }

    /// Law between species a and b.
    pub fn pair(&self, a: u16, b: u16) -> &GranularLaw {
        &self.pair[a as usize * self.n + b as usize]
    }

    /// Law between a sphere of species s and a wall.
    pub fn wall(&self, s: u16) -> &GranularLaw {
        &self.wall[s as usize]
    }
}

/// Run parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Time step Δt (s); see [`World::critical_dt`].
    pub dt: f64,
    /// Gravity g (m/s²).
    pub gravity: Vector3<f64>,
    /// Verlet skin as a fraction of the smallest radius (the list is rebuilt when a sphere
    /// has moved skin/2).
    pub skin: f64,
    /// Broad phase.
    pub grid: GridKind,
    /// Track the energy balance (costs the energy terms of the laws).
    pub energy: bool,
    /// Smallest number of spheres or contacts a parallel task takes (default 512): small
    /// worlds run on one thread without the cost of waking the pool. The results are the same
    /// bits for any value and any thread count.
    pub min_par_len: usize,
    /// Periodic axes (default none). A period must exceed twice the largest contact
    /// distance 2(2 r_max + skin r_min), checked when a sphere is added.
    pub periodic: Periodic,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            dt: 1e-6,
            gravity: Vector3::new(0.0, 0.0, -9.81),
            skin: 0.2,
            grid: GridKind::default(),
            energy: false,
            min_par_len: 512,
            periodic: Periodic::none(),
        }
    }
}

/// Counters of the run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Counters {
    /// Steps taken.
    pub steps: u64,
    /// Neighbour-list builds.
    pub builds: u64,
    /// Statistics of the last build.
    pub last_build: GridStats,
}

/// A 3D sphere world (the pipeline is in the crate docs).
#[derive(Clone, Debug)]
pub struct World {
    /// Sphere state.
    pub spheres: Spheres,
    /// Plane walls.
    pub walls: Vec<Plane>,
    /// Laws by species.
    pub laws: Laws,
    /// Run parameters (change `dt`, `gravity` freely; `skin` and `grid` apply at the next
    /// build).
    pub config: Config,
    /// Time (s).
    pub time: f64,
    /// Counters.
    pub counters: Counters,
    contacts: Vec<PairContact>,
    outs: Vec<PairOut>,
    released: Vec<f64>,
    /// Per sphere: incident contacts, index·2 + (0: sphere is i, 1: sphere is j).
    inc_start: Vec<u32>,
    inc: Vec<u32>,
    /// Wall contact histories, [sphere · walls + wall], and their last strain energies.
    wall_hist: Vec<Hist>,
    wall_eprev: Vec<f64>,
    wall_released: Vec<f64>,
    scratch: Scratch,
    energy: EnergyAcc,
    /// Forces of the current positions are in the scratch.
    forces_valid: bool,
    list_valid: bool,
    reach_max: f64,
    old_walls: usize,
}

impl World {
    /// An empty world.
    pub fn new(config: Config, laws: Laws) -> Result<World, SphereError> {
        positive("config.dt", config.dt)?;
        finite3("config.gravity", &config.gravity)?;
        if !(config.skin.is_finite() && config.skin >= 0.0) {
            return Err(SphereError::invalid(
                "config.skin",
                format!("must be a finite number ≥ 0, got {}", config.skin),
            ));
        }
        if let GridKind::MultiLevel { ratio } = config.grid {
            if !(ratio.is_finite() && ratio > 1.0) {
                return Err(SphereError::invalid(
                    "config.grid.ratio",
                    format!("must be a finite number > 1, got {ratio}"),
                ));
            }
        }
        Ok(World {
            spheres: Spheres::default(),
            walls: Vec::new(),
            laws,
            config,
            time: 0.0,
            counters: Counters::default(),
            contacts: Vec::new(),
            outs: Vec::new(),
            released: Vec::new(),
            inc_start: vec![0],
            inc: Vec::new(),
            wall_hist: Vec::new(),
            wall_eprev: Vec::new(),
            wall_released: Vec::new(),
            scratch: Scratch::default(),
            energy: EnergyAcc::default(),
            forces_valid: false,
            list_valid: false,
            reach_max: 0.0,
            old_walls: 0,
        })
    }

    /// Add a sphere of radius `r` and density `rho` at `x` with velocity `v`; returns its
    /// index. Refuses a non-positive or non-finite radius or density, an unknown species,
    /// and a sphere that does not fit between the walls.
    pub fn add_sphere(
        &mut self,
        x: Vector3<f64>,
        v: Vector3<f64>,
        r: f64,
        rho: f64,
        species: u16,
    ) -> Result<usize, SphereError> {
        finite3("sphere.x", &x)?;
        finite3("sphere.v", &v)?;
        positive("sphere.radius", r)?;
        positive("sphere.density", rho)?;
        if species as usize >= self.laws.species() {
            return Err(SphereError::invalid(
                "sphere.species",
                format!(
                    "must be < {} (the species of the law table), got {species}",
                    self.laws.species()
                ),
            ));
        }
        for (k, a) in self.walls.iter().enumerate() {
            for b in &self.walls[..k] {
                // Opposite parallel walls closer than the diameter cannot hold the sphere.
                if a.normal.dot(&b.normal) < -1.0 + 1e-12 {
                    let gap = (a.point - b.point).dot(&b.normal);
                    if gap < 2.0 * r {
                        return Err(SphereError::invalid(
                            "sphere.radius",
                            format!(
                                "the diameter {} exceeds the gap {gap} between walls",
                                2.0 * r
                            ),
                        ));
                    }
                }
            }
        }
        for k in 0..3 {
            if let Some(l) = self.config.periodic.len[k] {
                let need = 2.0 * (2.0 * r + self.config.skin * r);
                if !(l.is_finite() && l >= need) {
                    return Err(SphereError::invalid(
                        format!("config.periodic.len[{k}]"),
                        format!("must be ≥ 2 (2r + skin·r) = {need} for a sphere of radius {r}, got {l}"),
                    ));
                }
            }
        }
        let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
        self.spheres.push(x, v, r, m, species);
        self.changed();
        Ok(self.spheres.len() - 1)
    }

    /// Add a plane wall.
    pub fn add_wall(&mut self, p: Plane) -> Result<usize, SphereError> {
        let p = Plane::new(p.point, p.normal)?.moving(p.velocity);
        finite3("plane.velocity", &p.velocity)?;
        self.walls.push(p);
        self.changed();
        Ok(self.walls.len() - 1)
    }

    fn changed(&mut self) {
        let n = self.spheres.len();
        let nw = self.walls.len();
        if self.wall_hist.len() != n * nw {
            // Re-lay the wall histories out as [sphere · walls + wall], keeping each
            // (sphere, wall) pair's history (spheres and walls are only ever appended).
            let old_n = self
                .wall_eprev
                .len()
                .checked_div(self.old_walls)
                .unwrap_or(0);
            let mut h = vec![Hist::default(); n * nw];
            let mut e = vec![0.0; n * nw];
            for i in 0..old_n.min(n) {
                for k in 0..self.old_walls.min(nw) {
                    h[i * nw + k] = self.wall_hist[i * self.old_walls + k];
                    e[i * nw + k] = self.wall_eprev[i * self.old_walls + k];
                }
            }
            self.wall_hist = h;
            self.wall_eprev = e;
        }
        self.old_walls = nw;
        self.wall_released.resize(n * nw, 0.0);
        self.scratch.resize(n);
        self.forces_valid = false;
        self.list_valid = false;
    }

    /// Suggested time step: `fraction` × the smallest √(m*/k) over the sphere pairs and
    /// sphere–wall contacts the sizes allow (the smallest sphere with itself and with a wall),
    /// k the laws' stiffness at overlap `delta_rel` × the smallest radius (the Hertz stiffness
    /// grows with δ: take the largest overlap expected). Cundall & Strack 1979 take
    /// Δt ≈ 0.1–0.2 √(m/k); the Hertz contact time is ≈ 3.2 √(m*/k(δ_max)).
    pub fn critical_dt(&self, fraction: f64, delta_rel: f64) -> f64 {
        let s = &self.spheres;
        let mut t = f64::INFINITY;
        for i in 0..s.len() {
            // Each species' smallest sphere suffices; O(N·species) is cheap.
            let (r, m, sp) = (s.r[i], s.m[i], s.species[i]);
            let d = delta_rel * r;
            t = t.min(contact::contact_time_scale(self.laws.wall(sp), m, r, d));
            for b in 0..self.laws.species() as u16 {
                t = t.min(contact::contact_time_scale(
                    self.laws.pair(sp, b),
                    0.5 * m,
                    0.5 * r,
                    d,
                ));
            }
        }
        fraction * t
    }

    /// Advance one step of velocity Verlet (crate docs): half kick, drift, broad phase when
    /// the skin is used up, narrow phase + laws, half kick.
    pub fn step(&mut self) {
        if !self.forces_valid {
            self.compute_forces();
            if self.config.energy && self.energy.initial.is_none() {
                let e = self.energy();
                self.energy.initial = Some(e.kinetic() + e.gravity_potential + e.strain);
            }
        }
        let dt = self.config.dt;
        self.kick(0.5 * dt);
        self.drift(dt);
        self.compute_forces();
        self.kick(0.5 * dt);
        self.time += dt;
        self.counters.steps += 1;
    }

    /// Run `n` steps.
    pub fn run(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    fn kick(&mut self, h: f64) {
        let g = self.config.gravity;
        let energy = self.config.energy;
        let min_len = self.config.min_par_len.max(1);
        let s = &mut self.spheres;
        let sc = &mut self.scratch;
        let (diss, work): (Vec<f64>, Vec<f64>) = (s.v.par_iter_mut(), s.w.par_iter_mut())
            .into_par_iter()
            .enumerate()
            .with_min_len(min_len)
            .map(|(i, (v, w))| {
                let (v0, w0) = (*v, *w);
                *v += (sc.f[i] / s.m[i] + g) * h;
                *w += sc.t[i] * (h / s.inertia[i]);
                if energy {
                    let d = -(sc.df[i].dot(&(v0 + *v)) + sc.dt[i].dot(&(w0 + *w))) * 0.5 * h;
                    (d, sc.wall_power[i] * h)
                } else {
                    (0.0, 0.0)
                }
            })
            .unzip();
        if energy {
            // Serial sums: the same bits for any thread count.
            self.energy.damping += diss.iter().sum::<f64>();
            self.energy.wall_work += work.iter().sum::<f64>();
        }
    }

    fn drift(&mut self, dt: f64) {
        let min_len = self.config.min_par_len.max(1);
        let s = &mut self.spheres;
        s.x.par_iter_mut()
            .zip(s.v.par_iter())
            .with_min_len(min_len)
            .for_each(|(x, v)| *x += v * dt);
        for p in &mut self.walls {
            p.point += p.velocity * dt;
        }
    }

    /// Rebuild the Verlet list if needed (a sphere moved more than skin/2 since the last
    /// build), carrying every history over by its (i, j) key.
    fn broad_phase(&mut self) {
        let s = &self.spheres;
        let (r_min, r_max) = s.radius_range();
        let skin = self.config.skin * r_min;
        let min_len = self.config.min_par_len.max(1);
        if self.list_valid {
            let xb = &self.scratch.x_build;
            let moved =
                s.x.par_iter()
                    .zip(xb.par_iter())
                    .with_min_len(min_len)
                    .map(|(a, b)| (a - b).norm_squared())
                    .reduce(|| 0.0, f64::max);
            if moved.sqrt() <= 0.5 * skin {
                return;
            }
        }
        let mut reach = 0.0f64;
        for a in 0..self.laws.species() as u16 {
            for b in 0..self.laws.species() as u16 {
                reach = reach.max(contact::reach(self.laws.pair(a, b), 0.5 * r_max));
            }
            reach = reach.max(contact::reach(self.laws.wall(a), r_max));
        }
        self.reach_max = reach;
        let (pairs, stats) = find_pairs(
            self.config.grid,
            &self.config.periodic,
            &s.x,
            &s.r,
            skin + reach,
        );
        // Merge-join with the old sorted list: histories follow their pair.
        let old = std::mem::take(&mut self.contacts);
        let mut out = Vec::with_capacity(pairs.len());
        let mut k = 0;
        // A pair leaving the list (possible while touching only with a zero skin) loses what
        // its springs held: booked as dissipated, as when the law sees it open.
        let mut dropped = 0.0;
        for (i, j) in pairs {
            while k < old.len() && (old[k].i, old[k].j) < (i, j) {
                dropped += old[k].e_prev;
                k += 1;
            }
            if k < old.len() && (old[k].i, old[k].j) == (i, j) {
                out.push(old[k]);
                k += 1;
            } else {
                out.push(PairContact {
                    i,
                    j,
                    ..Default::default()
                });
            }
        }
        for c in &old[k.min(old.len())..] {
            dropped += c.e_prev;
        }
        self.energy.friction += dropped;
        self.contacts = out;
        // Incidence (CSR), contacts in list order for each sphere.
        let n = s.len();
        let mut start = vec![0u32; n + 1];
        for c in &self.contacts {
            start[c.i as usize + 1] += 1;
            start[c.j as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut inc = vec![0u32; 2 * self.contacts.len()];
        for (k, c) in self.contacts.iter().enumerate() {
            for (b, role) in [(c.i, 0), (c.j, 1)] {
                inc[fill[b as usize] as usize] = 2 * k as u32 + role;
                fill[b as usize] += 1;
            }
        }
        self.inc_start = start;
        self.inc = inc;
        self.scratch.x_build.clone_from(&s.x);
        self.list_valid = true;
        self.counters.builds += 1;
        self.counters.last_build = stats;
    }

    /// Broad phase, narrow phase and laws, and the per-sphere reduction of the forces at
    /// the current positions (the velocities are the half-step ones, as in LAMMPS).
    pub fn compute_forces(&mut self) {
        self.broad_phase();
        if self.config.energy {
            self.force_pass::<true>();
        } else {
            self.force_pass::<false>();
        }
        self.forces_valid = true;
    }

    fn force_pass<const E: bool>(&mut self) {
        let dt = self.config.dt;
        let reach = self.reach_max;
        let per = &self.config.periodic;
        let min_len = self.config.min_par_len.max(1);
        let s = &self.spheres;
        let laws = &self.laws;
        let body = |i: usize| Body {
            x: s.x[i],
            v: s.v[i],
            w: s.w[i],
            r: s.r[i],
            m: s.m[i],
        };
        // 1. Contacts in parallel, each writing its own output.
        self.outs.resize(self.contacts.len(), PairOut::default());
        self.released.resize(self.contacts.len(), 0.0);
        self.contacts
            .par_iter_mut()
            .zip(self.outs.par_iter_mut())
            .zip(self.released.par_iter_mut())
            .with_min_len(min_len)
            .for_each(|((c, o), rel)| {
                let law = laws.pair(s.species[c.i as usize], s.species[c.j as usize]);
                let (out, released) = contact::sphere_sphere::<E>(
                    law,
                    reach,
                    per,
                    &body(c.i as usize),
                    &body(c.j as usize),
                    dt,
                    c,
                );
                *o = out;
                *rel = released;
            });
        // 2. Per sphere, in a fixed order: its contacts in list order, then its walls.
        let nw = self.walls.len();
        let walls = &self.walls;
        let outs = &self.outs;
        let inc = &self.inc;
        let inc_start = &self.inc_start;
        let sc = &mut self.scratch;
        let wall_hist = &mut self.wall_hist;
        let wall_eprev = &mut self.wall_eprev;
        let wall_released = &mut self.wall_released;
        let chunks = wall_hist
            .par_chunks_mut(nw.max(1))
            .zip(wall_eprev.par_chunks_mut(nw.max(1)))
            .zip(wall_released.par_chunks_mut(nw.max(1)));
        let per_sphere =
            sc.f.par_iter_mut()
                .zip(sc.t.par_iter_mut())
                .zip(sc.df.par_iter_mut())
                .zip(sc.dt.par_iter_mut())
                .zip(sc.wall_power.par_iter_mut())
                .zip(sc.wall_strain.par_iter_mut())
                .zip(sc.wall_fric.par_iter_mut())
                .enumerate();
        let sum_pairs = |i: usize| {
            let (mut f, mut t, mut df, mut dtq) = (
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
            );
            for &e in &inc[inc_start[i] as usize..inc_start[i + 1] as usize] {
                let o = &outs[(e >> 1) as usize];
                if e & 1 == 0 {
                    f -= o.f;
                    t += o.ti;
                    if E {
                        df -= o.df;
                        dtq += o.dti;
                    }
                } else {
                    f += o.f;
                    t += o.tj;
                    if E {
                        df += o.df;
                        dtq += o.dtj;
                    }
                }
            }
            (f, t, df, dtq)
        };
        if nw == 0 {
            per_sphere.for_each(|(i, ((((((f, t), df), dtq), _), _), _))| {
                let (a, b, c, d) = sum_pairs(i);
                (*f, *t, *df, *dtq) = (a, b, c, d);
            });
        } else {
            per_sphere.zip(chunks).for_each(
                |((i, ((((((f, t), df), dtq), pw), ws), wf)), ((hist, ep), rel))| {
                    let (mut a, mut b, mut c, mut d) = sum_pairs(i);
                    let (mut p, mut es, mut ef) = (0.0, 0.0, 0.0);
                    let bi = body(i);
                    let law = laws.wall(s.species[i]);
                    let wreach = contact::reach(law, bi.r);
                    for (k, w) in walls.iter().enumerate() {
                        let (o, released) = contact::sphere_plane::<E>(
                            law,
                            wreach,
                            w,
                            &bi,
                            dt,
                            &mut hist[k],
                            &mut ep[k],
                        );
                        a += o.f;
                        b += o.tj;
                        if E {
                            c += o.df;
                            d += o.dtj;
                            p += o.f.dot(&w.velocity);
                            es += o.e_strain;
                            ef += o.e_fric;
                            rel[k] = released;
                        }
                    }
                    (*f, *t, *df, *dtq) = (a, b, c, d);
                    (*pw, *ws, *wf) = (p, es, ef);
                },
            );
        }
        if E {
            // Serial sums in list order: the same bits for any thread count.
            let mut fric = 0.0;
            for (o, r) in self.outs.iter().zip(&self.released) {
                fric += o.e_fric + r;
            }
            for (f, r) in self
                .scratch
                .wall_fric
                .iter()
                .zip(self.wall_released.chunks(nw.max(1)))
            {
                fric += f + r.iter().sum::<f64>();
            }
            self.energy.friction += fric;
        }
    }

    /// Energies now (module docs of [`crate::energy`]). The strain energy and the balance
    /// terms (dissipation, wall work, the initial energy) are tracked only with
    /// `config.energy`; kinetic and gravity terms always.
    pub fn energy(&self) -> EnergyReport {
        let s = &self.spheres;
        let g = self.config.gravity;
        let (mut kt, mut kr, mut pot) = (0.0, 0.0, 0.0);
        for i in 0..s.len() {
            kt += 0.5 * s.m[i] * s.v[i].norm_squared();
            kr += 0.5 * s.inertia[i] * s.w[i].norm_squared();
            pot -= s.m[i] * g.dot(&s.x[i]);
        }
        let mut strain = 0.0;
        for o in &self.outs {
            strain += o.e_strain;
        }
        for e in &self.scratch.wall_strain {
            strain += e;
        }
        EnergyReport::new(kt, kr, pot, strain, &self.energy)
    }

    /// Sphere–sphere contacts at the last force pass: (i, j, overlap δ) for the pairs whose
    /// law acts.
    pub fn contacts(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.contacts
            .iter()
            .zip(&self.outs)
            .filter(|(_, o)| o.active)
            .map(|(c, o)| (c.i as usize, c.j as usize, o.delta))
    }

    /// Sphere–wall overlaps at the current positions: (sphere, wall, δ) for δ > 0.
    pub fn wall_contacts(&self) -> Vec<(usize, usize, f64)> {
        let mut v = Vec::new();
        for i in 0..self.spheres.len() {
            for (k, w) in self.walls.iter().enumerate() {
                let d = self.spheres.r[i] - w.gap(&self.spheres.x[i]);
                if d > 0.0 {
                    v.push((i, k, d));
                }
            }
        }
        v
    }

    /// Contact force and torque on each sphere at the last force pass (gravity excluded).
    pub fn forces(&self) -> (&[Vector3<f64>], &[Vector3<f64>]) {
        (&self.scratch.f, &self.scratch.t)
    }

    /// Tangential force on j of each listed pair at the last force pass: (i, j, F_n, |F_t|).
    pub fn pair_forces(&self) -> Vec<(usize, usize, f64, f64)> {
        self.contacts
            .iter()
            .zip(&self.outs)
            .map(|(c, o)| {
                let n = self
                    .config
                    .periodic
                    .delta(self.spheres.x[c.j as usize] - self.spheres.x[c.i as usize])
                    .normalize();
                let fnn = o.f.dot(&n);
                (c.i as usize, c.j as usize, fnn, (o.f - n * fnn).norm())
            })
            .collect()
    }

    /// Force a neighbour-list build at the next force pass (benchmarks; histories are kept).
    pub fn invalidate_list(&mut self) {
        self.list_valid = false;
    }

    /// Mark the state as edited (positions or velocities set by hand): forces are recomputed
    /// and the neighbour list rebuilt at the next step. Histories are kept.
    pub fn touch(&mut self) {
        self.forces_valid = false;
        self.list_valid = false;
    }
}
