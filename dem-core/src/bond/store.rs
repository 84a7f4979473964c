//! The bond store ([`Bonds`]): groups, per-bond arrays, the per-step kernel and its scatter.

use super::criteria::{BreakMode, Compiled};
use super::flat_joint::{self, FlatJointState};
use super::kernel::{self, BondsIn, BondsMut, Ctx, DiscOut, DiscView, BROKEN, INTACT, NEW};
use super::{
    contact_bond, install, potyondy2004, BondError, BondGroup, BondModel, BondStatus, BreakEvent,
    BreakLog,
};
use crate::lanes::Packed;
use crate::state::{State, FREE};
use serde::{Deserialize, Serialize};
use std::collections::HashSet;

/// Derived per-run data, rebuilt on demand; not part of the state (ignored by `==`).
#[derive(Clone, Debug, Default)]
struct Cache {
    compiled: Vec<Compiled>,
    /// Per-bond force on disc j (x, y) and torques on i and j, for the parallel scatter.
    scratch: Vec<[f64; 4]>,
    /// Work arrays of the one-thread kernel (allocated once).
    serial: Box<kernel::SerialWork>,
    /// 1 + the largest disc index of the bonds (0 without bonds), once computed; reset
    /// whenever `i` or `j` change (`add`, `remap`), so the kernel's index check is not redone
    /// every step.
    index_bound: Option<usize>,
    /// The bonds by disc, for the parallel per-disc sums; reset with `index_bound`.
    incidence: Option<super::incidence::Incidence>,
    /// The parallel path's cut into ranges (see `split`).
    split: Option<super::split::Split>,
    /// Per-bond stress parameters of parallel bonds (see [`kernel::StressParams`]); rebuilt
    /// when bonds are added or reordered.
    stress: Option<kernel::StressParams>,
    /// The map from listed pairs to bonds of the fused stage (see `fused`); reset with
    /// `index_bound`, rebuilt for each neighbour-list build.
    fused: Option<super::fused::Map>,
    /// Bonds broken in the last fused pass.
    fused_breaks: super::fused::Breaks,
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
    /// F̄n (positive in compression), F̄s (N) and M̄ (N·m).
    fn_: Vec<f64>,
    fs: Vec<f64>,
    m: Vec<f64>,
    status: Vec<u8>,
    next_id: u32,
    /// Disc thickness t the bonds were built with (m).
    thickness: f64,
    /// Broken bonds per group, `[tension, shear]`.
    broken: Vec<[u64; 2]>,
    /// Strain energy released at breaks, cumulative (J).
    released: f64,
    log: BreakLog,
    /// Bonds (intact or broken) dropped with deleted discs, per group (empty until a
    /// deletion; see [`Bonds::drop_discs`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    dropped: Vec<u64>,
    /// The interface state of each bond when a group is a flat joint (one entry per bond, in
    /// store order; a placeholder for bonds of other groups); empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    fj: Vec<FlatJointState>,
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

fn mode_of(code: u8) -> BreakMode {
    if code % 2 == 1 {
        BreakMode::Tension
    } else {
        BreakMode::Shear
    }
}

/// The checks of a bond store's groups: at most `u16::MAX`, each valid, names unique.
fn check_groups(groups: &[BondGroup]) -> Result<(), BondError> {
    if groups.len() > u16::MAX as usize {
        return Err(BondError::TooManyGroups(groups.len()));
    }
    let mut names = HashSet::new();
    for g in groups {
        g.validate()?;
        if !names.insert(g.name.as_str()) {
            return Err(BondError::DuplicateGroup(g.name.clone()));
        }
    }
    Ok(())
}

impl Bonds {
    /// An empty store with these groups (validated; names must be unique).
    pub fn new(groups: Vec<BondGroup>) -> Result<Bonds, BondError> {
        check_groups(&groups)?;
        let n = groups.len();
        Ok(Bonds {
            groups,
            id: Vec::new(),
            i: Vec::new(),
            j: Vec::new(),
            group: Vec::new(),
            g0: Vec::new(),
            rbar: Vec::new(),
            fn_: Vec::new(),
            fs: Vec::new(),
            m: Vec::new(),
            status: Vec::new(),
            next_id: 0,
            thickness: 1.0,
            broken: vec![[0; 2]; n],
            released: 0.0,
            log: BreakLog::default(),
            dropped: Vec::new(),
            fj: Vec::new(),
            cache: Cache::default(),
        })
    }

    /// Whether a group is a flat joint (then every bond has a [`FlatJointState`]).
    pub fn has_flat_joints(&self) -> bool {
        self.groups
            .iter()
            .any(|g| matches!(g.model, BondModel::FlatJoint(_)))
    }

    /// The interface of bond `b` (store position) when it is a flat joint.
    pub fn flat_joint(&self, b: usize) -> Option<&FlatJointState> {
        match self.groups[self.group[b] as usize].model {
            BondModel::FlatJoint(_) => self.fj.get(b),
            _ => None,
        }
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

    /// Bonds whose cement is intact (a flat joint whose last element broke is not, even while
    /// its interface still touches).
    pub fn n_intact(&self) -> usize {
        (0..self.len())
            .filter(|&b| self.status[b] == INTACT && !self.fj.get(b).is_some_and(|f| f.logged))
            .count()
    }

    /// The disc index pairs of the intact bonds (as [`Bonds::n_intact`] counts them), in
    /// store order.
    pub fn intact_pairs(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.len())
            .filter(|&b| self.status[b] == INTACT && !self.fj.get(b).is_some_and(|f| f.logged))
            .map(|b| (self.i[b] as usize, self.j[b] as usize))
    }

    /// Broken bonds per group as `[tension, shear]`, indexed like [`Bonds::groups`].
    pub fn broken_counts(&self) -> &[[u64; 2]] {
        &self.broken
    }

    /// Flat-joint elements broken so far per group, indexed like [`Bonds::groups`]: for a
    /// flat-joint group the elements bonded at installation minus those bonded now, over its
    /// bonds in the store (partly broken interfaces count their broken elements; slit elements
    /// never count); `None` for other groups.
    pub fn elements_broken(&self) -> Vec<Option<u64>> {
        let mut out: Vec<Option<u64>> = (self.groups.iter())
            .map(|g| matches!(g.model, BondModel::FlatJoint(_)).then_some(0))
            .collect();
        for b in 0..self.len() {
            let g = self.group[b] as usize;
            if let (BondModel::FlatJoint(p), Some(f), Some(c)) =
                (&self.groups[g].model, self.fj.get(b), out[g].as_mut())
            {
                let installed = FlatJointState::installed(p, self.id[b]).bonded_count();
                *c += u64::from(installed.saturating_sub(f.bonded_count()));
            }
        }
        out
    }

    /// The crack record.
    pub fn log(&self) -> &BreakLog {
        &self.log
    }

    /// Write the crack record as CSV (atomically; see [`BreakLog::to_csv`]).
    pub fn write_breaks_csv(&self, path: &std::path::Path) -> std::io::Result<()> {
        self.log.write_csv(path, &self.group_names())
    }

    /// Bond `b` (store position).
    pub fn get(&self, b: usize) -> BondView {
        let s = self.status[b];
        BondView {
            id: self.id[b],
            i: self.i[b],
            j: self.j[b],
            group: self.group[b],
            status: match self.fj.get(b) {
                // A flat joint whose cement broke, its interface still touching.
                Some(f) if s == INTACT && f.logged => {
                    BondStatus::Broken(mode_of(f.last_break.max(1)))
                }
                _ if s == INTACT => BondStatus::Intact,
                _ => BondStatus::Broken(mode_of(s)),
            },
            fn_: self.fn_[b],
            fs: self.fs[b],
            m: self.m[b],
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
            img: crate::neighbors::MinImage::new(&st.periodic),
        };
        let (i, j) = (self.i[b] as usize, self.j[b] as usize);
        let (nx, ny, _, ai, _) = v.geometry(i, j);
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
        let (dx, dy) =
            crate::state::MinImage::new(&st.periodic).delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
        if dx == 0.0 && dy == 0.0 {
            return Err(BondError::Coincident(i, j));
        }
        let rmin = d.r[i].min(d.r[j]);
        let (rbar, interface) = match &g.model {
            BondModel::Parallel(p) => (p.lambda * rmin, FlatJointState::new(0)),
            BondModel::Contact(_) => (rmin, FlatJointState::new(0)),
            BondModel::FlatJoint(p) => {
                (p.lambda * rmin, FlatJointState::installed(p, self.next_id))
            }
        };
        if self.has_flat_joints() {
            self.fj.push(interface);
        }
        self.thickness = st.thickness;
        self.id.push(self.next_id);
        self.next_id += 1;
        self.i.push(i as u32);
        self.j.push(j as u32);
        self.cache.index_bound = None;
        self.cache.incidence = None;
        self.cache.fused = None;
        self.cache.split = None;
        self.cache.stress = None;
        self.group.push(group);
        self.g0.push(install::gap(st, i, j));
        self.rbar.push(rbar);
        self.fn_.push(0.0);
        self.fs.push(0.0);
        self.m.push(0.0);
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
            self.cache.stress = None;
        }
        let n = self.group.len();
        if !self.cache.stress.as_ref().is_some_and(|s| s.fits(n)) {
            let s = kernel::StressParams::new(&self.groups, &self.cache.compiled, &self.group);
            self.cache.stress = Some(s);
        }
    }

    /// The view of the fused bond stage for the neighbour list (`builds`, `start`, `nbr`: its
    /// build count and pairs), or `None` when the disc–disc pass may not evaluate the bonds
    /// (see `fused`). The map is rebuilt only for a new list or new bonds.
    pub(crate) fn fused_view(
        &mut self,
        builds: u64,
        start: &[u32],
        nbr: &[u32],
        thickness: f64,
    ) -> Option<super::fused::View<'_>> {
        if self.is_empty() {
            return None;
        }
        self.ensure_cache();
        if !self
            .cache
            .fused
            .as_ref()
            .is_some_and(|m| m.fits(builds, nbr.len()))
        {
            let par = (self.groups.iter().zip(&self.cache.compiled))
                .map(|(g, c)| super::fused::group_par(&g.model, c))
                .collect();
            let b = super::fused::BondsRef {
                i: &self.i,
                j: &self.j,
                group: &self.group,
                status: &self.status,
                par,
            };
            self.cache.fused = Some(super::fused::Map::build(builds, start, nbr, &b));
        }
        let m = self.cache.fused.as_ref().filter(|m| m.ok())?;
        self.thickness = thickness;
        Some(m.view(
            thickness,
            &self.group,
            &self.g0,
            &self.rbar,
            &mut self.fn_,
            &mut self.fs,
            &mut self.m,
            &mut self.status,
            &self.cache.fused_breaks,
        ))
    }

    /// The fused stage's map (tests).
    #[cfg(test)]
    pub(crate) fn fused_map(&self) -> Option<&super::fused::Map> {
        self.cache.fused.as_ref()
    }

    /// The bond stage after a fused pass: log the bonds that broke in it.
    pub(crate) fn after_fused(&mut self, st: &State) {
        let n = self.cache.fused_breaks.take();
        if n > 0 {
            self.log_breaks(st);
        }
    }

    /// The bond stage of a step: update every intact bond from the discs' positions (at t) and
    /// velocities (at t − dt/2), add bond forces and torques to the discs, break bonds whose
    /// criterion is met (their force vanishes from this step on) and log the breaks.
    pub fn compute(&mut self, st: &mut State, dt: f64) {
        self.compute_with(st, dt, crate::lanes::has_avx2(), &[]);
    }

    /// [`Bonds::compute`] reading the discs from `pk`, the contact pass's packed records of
    /// the current state (AVX2; see [`crate::lanes::Packed`]), when not empty:
    /// one cache line per disc instead of six arrays, same results.
    /// `ranges`: the step's thread count (see `kernel::run`).
    pub(crate) fn compute_packed(&mut self, st: &mut State, dt: f64, pk: &[Packed], ranges: usize) {
        self.compute_in(st, dt, crate::lanes::has_avx2(), pk, ranges);
    }

    /// [`Bonds::compute`] with the AVX2 build of the kernel on or off and the packed records
    /// `pk` or none (same results).
    /// The thread count is the calling rayon pool's.
    pub(crate) fn compute_with(&mut self, st: &mut State, dt: f64, avx2: bool, pk: &[Packed]) {
        self.compute_in(st, dt, avx2, pk, crate::team::Threads::current().ranges);
    }

    fn compute_in(&mut self, st: &mut State, dt: f64, avx2: bool, pk: &[Packed], ranges: usize) {
        if self.is_empty() {
            return;
        }
        self.ensure_cache();
        self.thickness = st.thickness;
        let d = &mut st.discs;
        let ctx = Ctx {
            v: DiscView {
                x: &d.x,
                y: &d.y,
                vx: &d.vx,
                vy: &d.vy,
                omega: &d.omega,
                r: &d.r,
                img: crate::neighbors::MinImage::new(&st.periodic),
            },
            // The records are read with AVX2 loads: only with AVX2 (the kernel checks that
            // there is one per disc).
            packed: if avx2 { pk } else { &[] },
            groups: &self.groups,
            compiled: &self.cache.compiled,
            stress: self.cache.stress.as_ref().expect("built by ensure_cache"),
            t: st.thickness,
            dt,
        };
        let input = BondsIn {
            i: &self.i,
            j: &self.j,
            group: &self.group,
            g0: &self.g0,
            rbar: &self.rbar,
        };
        let state = BondsMut {
            fn_: &mut self.fn_,
            fs: &mut self.fs,
            m: &mut self.m,
            status: &mut self.status,
            fj: &mut self.fj,
        };
        let out = DiscOut {
            fx: &mut d.fx,
            fy: &mut d.fy,
            tq: &mut d.torque,
        };
        let bound = *self
            .cache
            .index_bound
            .get_or_insert_with(|| kernel::index_bound(&self.i, &self.j));
        let new_breaks = kernel::run(
            &ctx,
            &input,
            state,
            out,
            &mut self.cache.scratch,
            &mut self.cache.serial,
            &mut self.cache.incidence,
            &mut self.cache.split,
            avx2,
            bound,
            ranges,
        );
        if new_breaks > 0 {
            self.log_breaks(st);
        }
    }

    /// Log the bonds broken in this step (store order), count them, release their energy and
    /// clear their forces. A flat joint whose cement broke while its interface is in contact is
    /// logged and counted now but stays in the stage (status intact, forces kept) until it opens;
    /// then it leaves without a second entry. Its energy was released element by element
    /// ([`FlatJointState::released`]): the entry reports that sum, and what the interface
    /// still holds when it leaves (0 when open) is added to the released energy then.
    fn log_breaks(&mut self, st: &State) {
        for b in 0..self.len() {
            let s = self.status[b];
            if s < NEW {
                continue;
            }
            let mode = mode_of(s);
            let fj = self.flat_joint(b).copied();
            let (log_it, leave) = match fj {
                None => (true, true),
                Some(f) => (!f.logged, self.fn_[b] == 0.0),
            };
            let g = self.group[b];
            if log_it {
                let energy = match fj {
                    None => self.bond_energy(b),
                    Some(f) => f.released,
                };
                let [x, y] = self.centre(st, b);
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
                if fj.is_none() {
                    self.released += energy;
                } else {
                    self.fj[b].logged = true;
                }
                self.broken[g as usize][mode.index()] += 1;
            }
            if !leave {
                self.status[b] = INTACT;
                continue;
            }
            if fj.is_some() {
                self.released += self.bond_energy(b);
            }
            self.fn_[b] = 0.0;
            self.fs[b] = 0.0;
            self.m[b] = 0.0;
            self.status[b] = BROKEN + mode.index() as u8;
        }
    }

    /// Strain energy held by bond `b` (J).
    pub fn bond_energy(&self, b: usize) -> f64 {
        let f = &[self.fn_[b], self.fs[b], self.m[b]];
        match &self.groups[self.group[b] as usize].model {
            BondModel::Parallel(p) => potyondy2004::energy(p, self.rbar[b], self.thickness, f),
            BondModel::Contact(p) => contact_bond::energy(p, f),
            BondModel::FlatJoint(p) => {
                flat_joint::energy(p, self.rbar[b], self.thickness, &self.fj[b])
            }
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
                    BondModel::FlatJoint(p) => flat_joint::stiffness(p, self.rbar[b], t, arm),
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

    /// Strain energy released at bond breaks since the start (J), including what flat joints
    /// gave up at element breaks and by sliding ([`FlatJointState::released`]).
    pub fn released_energy(&self) -> f64 {
        self.released + self.fj.iter().map(|s| s.released).sum::<f64>()
    }

    /// Checks a store read back from a checkpoint against `n_discs` discs: the groups as
    /// [`Bonds::new`] checks them, arrays of one length, disc indices in range and distinct,
    /// group indices that exist, known status codes, finite forces and positive radii and
    /// thickness. A hand-edited or corrupted checkpoint without a checksum gets this message
    /// instead of an out-of-range index inside the bond kernel (found by fuzzing, issue 20).
    pub fn check_restored(&self, n_discs: usize) -> Result<(), BondError> {
        let bad = |what: String| Err(BondError::Restored(what));
        check_groups(&self.groups)?;
        let n = self.id.len();
        let lens = [
            self.i.len(),
            self.j.len(),
            self.group.len(),
            self.g0.len(),
            self.rbar.len(),
            self.fn_.len(),
            self.fs.len(),
            self.m.len(),
            self.status.len(),
        ];
        if lens.iter().any(|&l| l != n) {
            return bad(format!(
                "bond arrays have different lengths ({n} ids, {lens:?})"
            ));
        }
        if self.broken.len() != self.groups.len() {
            return bad(format!(
                "{} broken counts for {} groups",
                self.broken.len(),
                self.groups.len()
            ));
        }
        if !(self.thickness > 0.0 && self.thickness.is_finite()) {
            return bad(format!("thickness {} must be positive", self.thickness));
        }
        if !self.released.is_finite() {
            return bad("released energy is not finite".into());
        }
        let fj_len = if self.has_flat_joints() { n } else { 0 };
        if self.fj.len() != fj_len {
            return bad(format!(
                "{} flat-joint states for {fj_len} bonds",
                self.fj.len()
            ));
        }
        for b in 0..n {
            let (i, j) = (self.i[b] as usize, self.j[b] as usize);
            let id = self.id[b];
            if i >= n_discs || j >= n_discs || i == j {
                return bad(format!("bond {id} joins discs {i} and {j} of {n_discs}"));
            }
            if self.group[b] as usize >= self.groups.len() {
                return bad(format!("bond {id}: group {} does not exist", self.group[b]));
            }
            if self.status[b] >= NEW {
                return bad(format!("bond {id}: status code {}", self.status[b]));
            }
            if !(self.rbar[b] > 0.0 && self.rbar[b].is_finite()) {
                return bad(format!(
                    "bond {id}: radius {} must be positive",
                    self.rbar[b]
                ));
            }
            let v = [self.g0[b], self.fn_[b], self.fs[b], self.m[b]];
            if v.iter().any(|x| !x.is_finite()) {
                return bad(format!("bond {id}: non-finite gap, force or moment"));
            }
            if id >= self.next_id {
                return bad(format!(
                    "bond id {id} is not below next_id {}",
                    self.next_id
                ));
            }
            if let Some(s) = self.fj.get(b) {
                let elements = match &self.groups[self.group[b] as usize].model {
                    BondModel::FlatJoint(p) => p.elements as u32,
                    _ => 0,
                };
                let finite = s.theta.is_finite()
                    && s.delta.is_finite()
                    && s.released.is_finite()
                    && s.fs.iter().all(|f| f.is_finite());
                if !finite || (s.bonded as u32) >> elements != 0 {
                    return bad(format!(
                        "bond {id}: flat-joint state with non-finite values or bonded elements \
                         beyond its {elements}"
                    ));
                }
            }
        }
        Ok(())
    }

    /// Follow a reordering of the discs (`new_index_of_old[old] = new`), then sort the bonds by
    /// their smaller disc index so the kernel walks the discs in memory order.
    pub fn remap(&mut self, new_index_of_old: &[u32]) {
        self.cache.index_bound = None;
        self.cache.incidence = None;
        self.cache.fused = None;
        self.cache.split = None;
        self.cache.stress = None;
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
        p(&mut self.fn_, &order);
        p(&mut self.fs, &order);
        p(&mut self.m, &order);
        p(&mut self.status, &order);
        if !self.fj.is_empty() {
            p(&mut self.fj, &order);
        }
    }
    /// Bonds dropped with deleted discs per group, indexed like [`Bonds::groups`] (all 0
    /// when nothing was deleted).
    pub fn dropped_counts(&self) -> Vec<u64> {
        let mut v = self.dropped.clone();
        v.resize(self.groups.len(), 0);
        v
    }

    /// Drop the bonds of deleted discs and renumber the others' discs: `new_of_old[old]` is
    /// the disc's new index, or `u32::MAX` when it is deleted. Bonds with a deleted disc leave
    /// the store (their ids are not reused; the crack record keeps their breaks); the others
    /// keep their ids, forces and state, in the order [`Bonds::remap`] gives. Returns the
    /// number of bonds dropped and the strain energy the intact ones held (J).
    pub fn drop_discs(&mut self, new_of_old: &[u32]) -> (usize, f64) {
        let gone = |k: u32| new_of_old.get(k as usize).is_none_or(|&n| n == u32::MAX);
        let keep: Vec<u32> = (0..self.len() as u32)
            .filter(|&b| !gone(self.i[b as usize]) && !gone(self.j[b as usize]))
            .collect();
        let n_drop = self.len() - keep.len();
        if n_drop == 0 {
            self.remap(new_of_old);
            return (0, 0.0);
        }
        self.dropped.resize(self.groups.len(), 0);
        let mut energy = 0.0;
        let mut kept = keep.iter().peekable();
        for b in 0..self.len() {
            if kept.peek() == Some(&&(b as u32)) {
                kept.next();
                continue;
            }
            if self.status[b] == INTACT {
                energy += self.bond_energy(b);
            }
            self.dropped[self.group[b] as usize] += 1;
        }
        fn p<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            let old = std::mem::take(v);
            *v = order.iter().map(|&k| old[k as usize]).collect();
        }
        p(&mut self.id, &keep);
        p(&mut self.i, &keep);
        p(&mut self.j, &keep);
        p(&mut self.group, &keep);
        p(&mut self.g0, &keep);
        p(&mut self.rbar, &keep);
        p(&mut self.fn_, &keep);
        p(&mut self.fs, &keep);
        p(&mut self.m, &keep);
        p(&mut self.status, &keep);
        if !self.fj.is_empty() {
            p(&mut self.fj, &keep);
        }
        // (`remap` resets the caches that depend on the bonds.)
        self.remap(new_of_old);
        (n_drop, energy)
    }
}
