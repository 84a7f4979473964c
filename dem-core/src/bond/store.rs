//! The bond store ([`Bonds`]): groups, per-bond arrays, the per-step kernel and its scatter.

use super::criteria::{check_stress, BreakMode, Compiled, Criterion, Loads};
use super::potyondy2004::Kinematics;
use super::{
    contact_bond, install, potyondy2004, BondError, BondGroup, BondModel, BondStatus, BreakEvent,
    BreakLog,
};
use crate::state::{Periodic, State, FREE};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// `status` codes: intact, broken (tension/shear), and broken in the current step (not yet
/// logged).
const INTACT: u8 = 0;
const BROKEN: u8 = 1; // + mode index
const NEW: u8 = 3; // + mode index

/// Use the two-pass parallel kernel from this many bonds on (and with more than one thread).
const PAR_MIN_BONDS: usize = 8192;
const CHUNK: usize = 2048;

/// Derived per-run data, rebuilt on demand; not part of the state (ignored by `==`).
#[derive(Clone, Debug, Default)]
struct Cache {
    compiled: Vec<Compiled>,
    /// Per-bond force on disc j (x, y) and torques on i and j, for the parallel scatter.
    scratch: Vec<[f64; 4]>,
}

impl PartialEq for Cache {
    fn eq(&self, _: &Cache) -> bool {
        true
    }
}

/// Bond groups and all bonds (structure of arrays; bond `b` joins discs `i[b]` and `j[b]`).
///
/// Disc indices are positions in [`crate::Discs`]; the pipeline calls [`Bonds::remap`] when it
/// reorders discs. Bond ids ([`BondView::id`]) are stable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bonds {
    groups: Vec<BondGroup>,
    id: Vec<u32>,
    i: Vec<u32>,
    j: Vec<u32>,
    group: Vec<u16>,
    /// Reference gap g0 (m): the gap at installation.
    g0: Vec<f64>,
    /// Bond radius R̄ (m): λ̄·min(R1,R2) for parallel bonds, min(R1,R2) for contact bonds.
    rbar: Vec<f64>,
    /// [F̄n, F̄s, M̄] (N, N, N·m).
    force: Vec<[f64; 3]>,
    status: Vec<u8>,
    next_id: u32,
    /// Disc thickness t the bonds were built with (m).
    thickness: f64,
    /// Broken bonds per group, `[tension, shear]`.
    broken: Vec<[u64; 2]>,
    /// Strain energy released at breaks, cumulative (J).
    released: f64,
    log: BreakLog,
    #[serde(skip)]
    cache: Cache,
}

/// One bond, for outputs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BondView {
    /// Stable bond id.
    pub id: u32,
    /// Current disc indices.
    pub i: u32,
    pub j: u32,
    pub group: u16,
    pub status: BondStatus,
    /// F̄n (positive in compression), F̄s (N) and M̄ (N·m).
    pub fn_: f64,
    pub fs: f64,
    pub m: f64,
    pub g0: f64,
    pub rbar: f64,
}

/// Read-only disc data the kernel needs.
struct DiscView<'a> {
    x: &'a [f64],
    y: &'a [f64],
    vx: &'a [f64],
    vy: &'a [f64],
    omega: &'a [f64],
    r: &'a [f64],
    /// Per axis (box length, 1/length), (0, 0) when not periodic.
    per: [(f64, f64); 2],
}

fn per_axes(p: &Periodic) -> [(f64, f64); 2] {
    let ax = |a: usize| match p.length[a] {
        Some(l) if l > 0.0 && l.is_finite() => (l, 1.0 / l),
        _ => (0.0, 0.0),
    };
    [ax(0), ax(1)]
}

/// Minimum-image difference `b − a` on an axis with `(l, 1/l)` (`(0, 0)`: not periodic).
/// Rounds with the 1.5·2⁵² trick (round-half-even, exact for |x| < 2⁵¹) instead of
/// `f64::round`, which is a library call on baseline x86-64.
#[inline(always)]
fn min_image(a: f64, b: f64, (l, inv): (f64, f64)) -> f64 {
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let d = b - a;
    let k = (d * inv + MAGIC) - MAGIC;
    d - l * k
}

/// Geometry of a bond: unit normal from i to j, gap, arms from the disc centres to the contact
/// point. Coincident centres get the normal (1, 0).
#[inline(always)]
fn geometry(v: &DiscView, i: usize, j: usize) -> (f64, f64, f64, f64, f64) {
    let dx = min_image(v.x[i], v.x[j], v.per[0]);
    let dy = min_image(v.y[i], v.y[j], v.per[1]);
    let dist = (dx * dx + dy * dy).sqrt();
    let ok = dist > 0.0;
    let inv = 1.0 / if ok { dist } else { 1.0 };
    let nx = if ok { dx * inv } else { 1.0 };
    let ny = dy * inv;
    let gap = dist - v.r[i] - v.r[j];
    (nx, ny, gap, v.r[i] + 0.5 * gap, v.r[j] + 0.5 * gap)
}

/// Bonds per block: the kernel first computes the geometry of a block of bonds (independent,
/// branch-free work the CPU overlaps), then updates and checks them one by one.
const BLOCK: usize = 32;

/// Bond data of one block, all slices of the same length ≤ [`BLOCK`].
struct BlockIn<'a> {
    i: &'a [u32],
    j: &'a [u32],
    group: &'a [u16],
    g0: &'a [f64],
    rbar: &'a [f64],
}

/// Per-step constants of the kernel.
struct Ctx<'a> {
    v: DiscView<'a>,
    groups: &'a [BondGroup],
    compiled: &'a [Compiled],
    t: f64,
    dt: f64,
}

/// Update one block of bonds: new forces and status, and for each bond still intact the force
/// on disc j and the torques on i and j (`[fx, fy, ti, tj]`) in `out` (entries of bonds that
/// are not intact are left as they were and must not be scattered). Returns the number of
/// bonds broken now.
///
/// A block whose bonds all belong to one parallel-bond group with the stress criterion (the
/// common case) runs a copy of the loop with that group's constants hoisted; it calls the same
/// functions in the same order as the general loop, so results are identical.
#[inline(always)]
fn block(
    c: &Ctx,
    b: &BlockIn,
    force: &mut [[f64; 3]],
    status: &mut [u8],
    out: &mut [[f64; 4]],
) -> usize {
    let n = b.i.len();
    let (i_, j_, grp) = (&b.i[..n], &b.j[..n], &b.group[..n]);
    let (g0_, rbar_) = (&b.g0[..n], &b.rbar[..n]);
    let (force, status, out) = (&mut force[..n], &mut status[..n], &mut out[..n]);
    // Pass 1a: gather the pair data (all disc slices re-cut to one length so the bounds checks
    // fold into one). Entries past `n` keep harmless padding values.
    let nd = c.v.x.len();
    let (x, y, vx, vy) = (&c.v.x[..nd], &c.v.y[..nd], &c.v.vx[..nd], &c.v.vy[..nd]);
    let (omega, r) = (&c.v.omega[..nd], &c.v.r[..nd]);
    let mut dxs = [1.0f64; BLOCK];
    let mut dys = [0.0f64; BLOCK];
    let mut ris = [0.0f64; BLOCK];
    let mut rjs = [0.0f64; BLOCK];
    let mut dvx = [0.0f64; BLOCK];
    let mut dvy = [0.0f64; BLOCK];
    let mut wis = [0.0f64; BLOCK];
    let mut wjs = [0.0f64; BLOCK];
    for k in 0..n {
        let (i, j) = (i_[k] as usize, j_[k] as usize);
        if i >= nd || j >= nd {
            // Cannot happen (indices are checked when bonds are added or remapped).
            status[k] = BROKEN;
            continue;
        }
        dxs[k] = x[j] - x[i];
        dys[k] = y[j] - y[i];
        ris[k] = r[i];
        rjs[k] = r[j];
        dvx[k] = vx[j] - vx[i];
        dvy[k] = vy[j] - vy[i];
        wis[k] = omega[i];
        wjs[k] = omega[j];
    }
    // Pass 1b: geometry and kinematics, branch-free over the whole block (the compiler turns
    // it into packed SIMD arithmetic; the operations are the same IEEE ones either way).
    // Minimum image with the 1.5·2⁵² rounding trick (see `min_image`); unit normal n̂ (with
    // (1, 0) for coincident centres), gap, arms a_i = R_i + g/2, a_j = R_j + g/2; tangential
    // relative velocity of j's and i's material points at the contact point,
    // (v_j − ω_j a_j t̂) − (v_i + ω_i a_i t̂)·t̂, t̂ = (−n_y, n_x); relative spin ω_j − ω_i.
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    let [(lx, ilx), (ly, ily)] = c.v.per;
    let mut geo = [[0.0f64; BLOCK]; 7];
    {
        let [gnx, gny, ggap, gai, gaj, gvt, gdw] = &mut geo;
        for k in 0..BLOCK {
            let dx = dxs[k] - lx * ((dxs[k] * ilx + MAGIC) - MAGIC);
            let dy = dys[k] - ly * ((dys[k] * ily + MAGIC) - MAGIC);
            let dist = (dx * dx + dy * dy).sqrt();
            let ok = dist > 0.0;
            let inv = 1.0 / if ok { dist } else { 1.0 };
            let nx = if ok { dx * inv } else { 1.0 };
            let ny = dy * inv;
            let gap = dist - ris[k] - rjs[k];
            let ai = ris[k] + 0.5 * gap;
            let aj = rjs[k] + 0.5 * gap;
            gnx[k] = nx;
            gny[k] = ny;
            ggap[k] = gap;
            gai[k] = ai;
            gaj[k] = aj;
            gvt[k] = dvx[k] * -ny + dvy[k] * nx - (wjs[k] * aj + wis[k] * ai);
            gdw[k] = wjs[k] - wis[k];
        }
    }
    // Pass 2: forces, criterion, output.
    let (t, dt) = (c.t, c.dt);
    let g_first = grp.first().copied().unwrap_or(0) as usize;
    let uniform = grp.iter().all(|&g| g as usize == g_first);
    let fast = match (
        uniform,
        &c.groups[g_first].model,
        c.compiled[g_first].criterion,
    ) {
        (
            true,
            BondModel::Parallel(p),
            Criterion::Stress {
                tensile, cohesion, ..
            },
        ) => Some((*p, tensile, cohesion, c.compiled[g_first].tan_phi)),
        _ => None,
    };
    let mut broke = 0;
    macro_rules! pass2 {
        ($update:expr, $check:expr) => {
            for k in 0..n {
                if status[k] != INTACT {
                    continue;
                }
                let (nx, ny, gap) = (geo[0][k], geo[1][k], geo[2][k]);
                let (ai, aj, vt, dw) = (geo[3][k], geo[4][k], geo[5][k], geo[6][k]);
                let kin = Kinematics {
                    gap,
                    dus: vt * dt,
                    dtheta: dw * dt,
                };
                let f = &mut force[k];
                // Bond length R_i + R_j + g0 (only the strain criterion reads it).
                let length = ai + aj - gap + g0_[k];
                let loads = $update(k, rbar_[k], g0_[k], length, &kin, &mut *f);
                if let Some(mode) = $check(k, &loads) {
                    status[k] = NEW + mode.index() as u8;
                    broke += 1;
                    continue;
                }
                let (fn_, fs, m) = (f[0], f[1], f[2]);
                let (tx, ty) = (-ny, nx);
                out[k] = [
                    fn_ * nx + fs * tx,
                    fn_ * ny + fs * ty,
                    -ai * fs - m,
                    -aj * fs + m,
                ];
            }
        };
    }
    if let Some((p, tensile, cohesion, tan_phi)) = fast {
        pass2!(
            |_k, rbar, g0, len, kin: &Kinematics, f: &mut [f64; 3]| {
                potyondy2004::update(&p, rbar, t, g0, len, kin, f)
            },
            |_k, l: &Loads| check_stress(l, tensile, cohesion, tan_phi)
        );
    } else {
        pass2!(
            |k: usize, rbar, g0, len, kin: &Kinematics, f: &mut [f64; 3]| {
                match &c.groups[grp[k] as usize].model {
                    BondModel::Parallel(p) => potyondy2004::update(p, rbar, t, g0, len, kin, f),
                    BondModel::Contact(p) => contact_bond::update(p, rbar, t, g0, len, kin, f),
                }
            },
            |k: usize, l: &Loads| c.compiled[grp[k] as usize].check(l)
        );
    }
    broke
}

/// Add one bond's contribution to its discs (the only place disc sums are formed). The three
/// slices have one length (so one bounds check covers them).
#[inline(always)]
fn scatter(fx: &mut [f64], fy: &mut [f64], tq: &mut [f64], i: usize, j: usize, o: &[f64; 4]) {
    let n = fx.len();
    let (fx, fy, tq) = (&mut fx[..n], &mut fy[..n], &mut tq[..n]);
    fx[i] -= o[0];
    fy[i] -= o[1];
    tq[i] += o[2];
    fx[j] += o[0];
    fy[j] += o[1];
    tq[j] += o[3];
}

fn mode_of(code: u8) -> BreakMode {
    if code % 2 == 1 {
        BreakMode::Tension
    } else {
        BreakMode::Shear
    }
}

impl Bonds {
    /// An empty store with these groups (validated; names must be unique).
    pub fn new(groups: Vec<BondGroup>) -> Result<Bonds, BondError> {
        if groups.len() > u16::MAX as usize {
            return Err(BondError::TooManyGroups(groups.len()));
        }
        let mut names = HashSet::new();
        for g in &groups {
            g.validate()?;
            if !names.insert(g.name.as_str()) {
                return Err(BondError::DuplicateGroup(g.name.clone()));
            }
        }
        let n = groups.len();
        Ok(Bonds {
            groups,
            id: Vec::new(),
            i: Vec::new(),
            j: Vec::new(),
            group: Vec::new(),
            g0: Vec::new(),
            rbar: Vec::new(),
            force: Vec::new(),
            status: Vec::new(),
            next_id: 0,
            thickness: 1.0,
            broken: vec![[0; 2]; n],
            released: 0.0,
            log: BreakLog::default(),
            cache: Cache::default(),
        })
    }

    pub fn groups(&self) -> &[BondGroup] {
        &self.groups
    }

    pub fn group_names(&self) -> Vec<String> {
        self.groups.iter().map(|g| g.name.clone()).collect()
    }

    /// Index of the group called `name`.
    pub fn group_index(&self, name: &str) -> Result<u16, BondError> {
        self.groups
            .iter()
            .position(|g| g.name == name)
            .map(|k| k as u16)
            .ok_or_else(|| BondError::UnknownGroupName(name.to_string()))
    }

    /// Number of bonds (intact and broken).
    pub fn len(&self) -> usize {
        self.i.len()
    }

    pub fn is_empty(&self) -> bool {
        self.i.is_empty()
    }

    pub fn n_intact(&self) -> usize {
        self.status.iter().filter(|&&s| s == INTACT).count()
    }

    /// Broken bonds per group as `[tension, shear]`, indexed like [`Bonds::groups`].
    pub fn broken_counts(&self) -> &[[u64; 2]] {
        &self.broken
    }

    /// The crack record.
    pub fn log(&self) -> &BreakLog {
        &self.log
    }

    /// Bond `b` (store position).
    pub fn get(&self, b: usize) -> BondView {
        let s = self.status[b];
        BondView {
            id: self.id[b],
            i: self.i[b],
            j: self.j[b],
            group: self.group[b],
            status: if s == INTACT {
                BondStatus::Intact
            } else {
                BondStatus::Broken(mode_of(s))
            },
            fn_: self.force[b][0],
            fs: self.force[b][1],
            m: self.force[b][2],
            g0: self.g0[b],
            rbar: self.rbar[b],
        }
    }

    /// All bonds in store order.
    pub fn iter(&self) -> impl Iterator<Item = BondView> + '_ {
        (0..self.len()).map(|b| self.get(b))
    }

    /// Bond centre (the contact point x_i + (R_i + g/2) n̂), wrapped into a periodic box.
    pub fn centre(&self, st: &State, b: usize) -> [f64; 2] {
        let d = &st.discs;
        let v = DiscView {
            x: &d.x,
            y: &d.y,
            vx: &d.vx,
            vy: &d.vy,
            omega: &d.omega,
            r: &d.r,
            per: per_axes(&st.periodic),
        };
        let (i, j) = (self.i[b] as usize, self.j[b] as usize);
        let (nx, ny, _, ai, _) = geometry(&v, i, j);
        [
            st.periodic.wrap(0, d.x[i] + ai * nx),
            st.periodic.wrap(1, d.y[i] + ai * ny),
        ]
    }

    /// Bond discs `i` and `j` with a bond of group `group`; returns the bond's store position.
    /// The reference gap g0 is the current gap, so the bond starts force-free (across a gap or
    /// an overlap). R̄ = λ̄·min(R_i, R_j) (parallel) or min(R_i, R_j) (contact bond).
    /// Does not check for an existing bond between the pair (the `install_*` functions do).
    pub fn add(&mut self, st: &State, i: usize, j: usize, group: u16) -> Result<usize, BondError> {
        let n = st.discs.len();
        for k in [i, j] {
            if k >= n {
                return Err(BondError::DiscIndex { index: k, len: n });
            }
        }
        if i == j {
            return Err(BondError::SelfBond(i));
        }
        let g = self
            .groups
            .get(group as usize)
            .ok_or(BondError::UnknownGroup(group as usize))?;
        let d = &st.discs;
        let ok = |k: usize| {
            d.r[k] > 0.0 && d.r[k].is_finite() && d.x[k].is_finite() && d.y[k].is_finite()
        };
        if !(ok(i) && ok(j) && st.thickness > 0.0 && st.thickness.is_finite()) {
            return Err(BondError::BadDisc { i, j });
        }
        let dx = st.periodic.delta(0, d.x[i], d.x[j]);
        let dy = st.periodic.delta(1, d.y[i], d.y[j]);
        if dx == 0.0 && dy == 0.0 {
            return Err(BondError::Coincident(i, j));
        }
        let rmin = d.r[i].min(d.r[j]);
        let rbar = match &g.model {
            BondModel::Parallel(p) => p.lambda * rmin,
            BondModel::Contact(_) => rmin,
        };
        self.thickness = st.thickness;
        self.id.push(self.next_id);
        self.next_id += 1;
        self.i.push(i as u32);
        self.j.push(j as u32);
        self.group.push(group);
        self.g0.push(install::gap(st, i, j));
        self.rbar.push(rbar);
        self.force.push([0.0; 3]);
        self.status.push(INTACT);
        Ok(self.len() - 1)
    }

    /// Bond every pair with gap ≤ `tol` (touching, overlapping or nearly touching discs) whose
    /// group `choose(i, j)` returns (None: leave the pair unbonded). Pairs already bonded and
    /// pairs inside one rigid clump are skipped. Returns the number of bonds added.
    pub fn install_within_gap(
        &mut self,
        st: &State,
        tol: f64,
        mut choose: impl FnMut(usize, usize) -> Option<u16>,
    ) -> Result<usize, BondError> {
        let pairs = install::pairs_within_gap(st, tol);
        self.install_pairs(
            st,
            pairs.into_iter().filter_map(|(i, j)| {
                let (i, j) = (i as usize, j as usize);
                choose(i, j).map(|g| (i, j, g))
            }),
        )
    }

    /// Bond every pair within gap `tol` with a bond of `group` (see
    /// [`Bonds::install_within_gap`]).
    pub fn install_at_contacts(
        &mut self,
        st: &State,
        tol: f64,
        group: u16,
    ) -> Result<usize, BondError> {
        self.install_within_gap(st, tol, |_, _| Some(group))
    }

    /// Bond the given pairs `(i, j, group)`, skipping pairs already bonded (either order) and
    /// pairs inside one rigid clump. Returns the number added.
    pub fn install_pairs(
        &mut self,
        st: &State,
        pairs: impl IntoIterator<Item = (usize, usize, u16)>,
    ) -> Result<usize, BondError> {
        let mut have: HashSet<(u32, u32)> = self
            .i
            .iter()
            .zip(&self.j)
            .map(|(&a, &b)| (a.min(b), a.max(b)))
            .collect();
        let body = &st.discs.body;
        let mut added = 0;
        for (i, j, g) in pairs {
            if i < body.len() && j < body.len() && body[i] != FREE && body[i] == body[j] {
                continue;
            }
            let key = (i.min(j) as u32, i.max(j) as u32);
            if have.contains(&key) {
                continue;
            }
            self.add(st, i, j, g)?;
            have.insert(key);
            added += 1;
        }
        Ok(added)
    }

    fn ensure_cache(&mut self) {
        if self.cache.compiled.len() != self.groups.len() {
            self.cache.compiled = self.groups.iter().map(|g| g.criterion.compile()).collect();
        }
    }

    /// The bond stage of a step: update every intact bond from the discs' positions (at t) and
    /// velocities (at t − dt/2), add bond forces and torques to the discs, break bonds whose
    /// criterion is met (their force vanishes from this step on) and log the breaks.
    pub fn compute(&mut self, st: &mut State, dt: f64) {
        let nb = self.len();
        if nb == 0 {
            return;
        }
        self.ensure_cache();
        self.thickness = st.thickness;
        let t = st.thickness;
        let parallel = nb >= PAR_MIN_BONDS && rayon::current_num_threads() > 1;
        if parallel && self.cache.scratch.len() != nb {
            self.cache.scratch.resize(nb, [0.0; 4]);
        }
        let Bonds {
            groups,
            i: bi,
            j: bj,
            group,
            g0,
            rbar,
            force,
            status,
            cache,
            ..
        } = self;
        let per = per_axes(&st.periodic);
        let d = &mut st.discs;
        let v = DiscView {
            x: &d.x,
            y: &d.y,
            vx: &d.vx,
            vy: &d.vy,
            omega: &d.omega,
            r: &d.r,
            per,
        };
        let ctx = Ctx {
            v,
            groups,
            compiled: &cache.compiled[..],
            t,
            dt,
        };
        let input = |r: std::ops::Range<usize>| BlockIn {
            i: &bi[r.clone()],
            j: &bj[r.clone()],
            group: &group[r.clone()],
            g0: &g0[r.clone()],
            rbar: &rbar[r],
        };
        let mut new_breaks = 0usize;
        if parallel {
            new_breaks = force
                .par_chunks_mut(CHUNK)
                .zip(status.par_chunks_mut(CHUNK))
                .zip(cache.scratch.par_chunks_mut(CHUNK))
                .enumerate()
                .map(|(c, ((f, s), out))| {
                    let base = c * CHUNK;
                    let mut nb = 0;
                    for k in (0..f.len()).step_by(BLOCK) {
                        let e = (k + BLOCK).min(f.len());
                        nb += block(
                            &ctx,
                            &input(base + k..base + e),
                            &mut f[k..e],
                            &mut s[k..e],
                            &mut out[k..e],
                        );
                    }
                    nb
                })
                .sum();
            let nd = d.fx.len();
            let (fx, fy, tq) = (&mut d.fx[..nd], &mut d.fy[..nd], &mut d.torque[..nd]);
            for (b, o) in cache.scratch.iter().enumerate() {
                if status[b] == INTACT {
                    scatter(fx, fy, tq, bi[b] as usize, bj[b] as usize, o);
                }
            }
        } else {
            let nd = d.fx.len();
            let (fx, fy, tq) = (&mut d.fx[..nd], &mut d.fy[..nd], &mut d.torque[..nd]);
            let mut out = [[0.0f64; 4]; BLOCK];
            for k in (0..nb).step_by(BLOCK) {
                let e = (k + BLOCK).min(nb);
                new_breaks += block(
                    &ctx,
                    &input(k..e),
                    &mut force[k..e],
                    &mut status[k..e],
                    &mut out[..e - k],
                );
                for b in k..e {
                    if status[b] == INTACT {
                        scatter(fx, fy, tq, bi[b] as usize, bj[b] as usize, &out[b - k]);
                    }
                }
            }
        }
        if new_breaks > 0 {
            self.log_breaks(st);
        }
    }

    /// Log the bonds broken in this step (store order), count them, release their energy and
    /// clear their forces.
    fn log_breaks(&mut self, st: &State) {
        for b in 0..self.len() {
            let s = self.status[b];
            if s < NEW {
                continue;
            }
            let mode = mode_of(s);
            let energy = self.bond_energy(b);
            let [x, y] = self.centre(st, b);
            let g = self.group[b];
            self.log.push(BreakEvent {
                time: st.time,
                step: st.step,
                x,
                y,
                group: g,
                mode,
                id_i: st.discs.id[self.i[b] as usize],
                id_j: st.discs.id[self.j[b] as usize],
                bond: self.id[b],
                energy,
            });
            self.released += energy;
            self.broken[g as usize][mode.index()] += 1;
            self.force[b] = [0.0; 3];
            self.status[b] = BROKEN + mode.index() as u8;
        }
    }

    /// Strain energy held by bond `b` (J).
    pub fn bond_energy(&self, b: usize) -> f64 {
        let f = &self.force[b];
        match &self.groups[self.group[b] as usize].model {
            BondModel::Parallel(p) => potyondy2004::energy(p, self.rbar[b], self.thickness, f),
            BondModel::Contact(p) => contact_bond::energy(p, f),
        }
    }

    /// Per-disc stiffness of the intact bonds for the time-step estimate (added to `k_trans`
    /// and `k_rot`, indexed by disc): see [`potyondy2004::stiffness`] and
    /// [`contact_bond::stiffness`]; the arm is R_k + g0/2.
    pub fn add_stiffness(&self, st: &State, k_trans: &mut [f64], k_rot: &mut [f64]) {
        let t = st.thickness;
        let r = &st.discs.r;
        for b in 0..self.len() {
            if self.status[b] != INTACT {
                continue;
            }
            let g0 = self.g0[b];
            for k in [self.i[b] as usize, self.j[b] as usize] {
                let arm = r[k] + 0.5 * g0;
                let (kt, kr) = match &self.groups[self.group[b] as usize].model {
                    BondModel::Parallel(p) => potyondy2004::stiffness(p, self.rbar[b], t, arm),
                    BondModel::Contact(p) => contact_bond::stiffness(p, arm),
                };
                k_trans[k] += kt;
                k_rot[k] += kr;
            }
        }
    }

    /// Strain energy stored in the intact bonds (J).
    pub fn strain_energy(&self) -> f64 {
        (0..self.len())
            .filter(|&b| self.status[b] == INTACT)
            .map(|b| self.bond_energy(b))
            .sum()
    }

    /// Strain energy released at bond breaks since the start (J).
    pub fn released_energy(&self) -> f64 {
        self.released
    }

    /// Follow a reordering of the discs (`new_index_of_old[old] = new`), then sort the bonds by
    /// their smaller disc index so the kernel walks the discs in memory order.
    pub fn remap(&mut self, new_index_of_old: &[u32]) {
        for k in self.i.iter_mut().chain(self.j.iter_mut()) {
            *k = new_index_of_old[*k as usize];
        }
        let mut order: Vec<u32> = (0..self.len() as u32).collect();
        order.sort_by_key(|&b| {
            let (i, j) = (self.i[b as usize], self.j[b as usize]);
            (i.min(j), i.max(j), self.id[b as usize])
        });
        if order.iter().enumerate().all(|(k, &b)| k as u32 == b) {
            return;
        }
        fn p<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            let old = std::mem::take(v);
            *v = order.iter().map(|&k| old[k as usize]).collect();
        }
        p(&mut self.id, &order);
        p(&mut self.i, &order);
        p(&mut self.j, &order);
        p(&mut self.group, &order);
        p(&mut self.g0, &order);
        p(&mut self.rbar, &order);
        p(&mut self.force, &order);
        p(&mut self.status, &order);
    }
}
