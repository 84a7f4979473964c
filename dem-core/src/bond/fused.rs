//! Parallel bonds evaluated inside the disc–disc pass ("fused" bond stage).
//!
//! A bonded pair is also a listed contact pair, and the contact pass has just computed what the
//! bond needs: the centre distance, the unit normal, the contact arms and the tangential relative
//! velocity at the contact point. The pass evaluates each bond with its pair and adds its force
//! and torques to the pair's outputs before the scatter — no second gather of the discs, no
//! second geometry, no second scatter; the bond stage then only logs the breaks — when
//! (`World::step` decides at every step, from the state only):
//! - every intact bond is a parallel bond with the maximum-stress criterion (Potyondy &
//!   Cundall 2004, [`super::potyondy2004`], [`super::criteria`]) and is a listed pair;
//! - at least 95 % of the listed pairs are bonded (a bonded lattice, a grain built as a bonded
//!   lattice): a pair without a bond still costs a lane, and groups of four pairs that are not
//!   four consecutive intact bonds gather lane by lane. Measured (docs/performance.md, tenth
//!   round): the bonded benchmark lattice (every pair bonded) ~1.4× faster on one thread and
//!   ~1.5× on two; a traditional cutting specimen with 83 % of its pairs bonded 0.9× — such
//!   specimens keep the separate stage;
//! - the pass evaluates one linear spring-dashpot law without dashpot sums
//!   (`contact::disc_disc::uniform_linear`), the case of the four-lane contact kernel.
//!
//! **Results.** The law is the one of the separate bond stage (same formulas: Ā = 2R̄t,
//! Ī = (2/3)R̄³t, F̄n = −k̄nĀ(g − g₀), ΔF̄s = −k̄sĀ v_t Δt, ΔM̄ = −k̄nĪ (ω_j − ω_i) Δt, the
//! stress criterion with tension taking precedence, a breaking bond gives no force at its
//! break step), but the geometry is the contact pass's (contact point midway in the overlap:
//! a_i = r_i − h, h = (r_i + r_j − d)/2) and the bond forces are added to the pair's contact
//! forces instead of after all contacts: the same physics, rounded differently from the
//! separate stage (`Params::fuse_bonds = false` keeps that stage). The four-lane form
//! ([`four`], AVX2), the block form of the general path ([`block`]) and the one-pair form
//! ([`law`]) perform the same IEEE operations in the same order, so results do not
//! depend on the CPU, and each bond belongs to exactly one pair, so they do not depend on the
//! thread count either.
//!
//! **Orientation.** The list holds pairs (i, j) with the disc order of the list; a bond made
//! as (j, i) (discs reordered since) is evaluated in the pair's frame, where only its moment
//! changes sign (F̄n and F̄s are symmetric): its stored M̄ is negated on the way in and out,
//! exactly.

use super::criteria::{BreakMode, Criterion};
use super::kernel::{INTACT, NEW};
use super::BondModel;
use crate::contact::kernel::{Cols, PairHook};
#[cfg(target_arch = "x86_64")]
use crate::lanes::F64x4;
use crate::lanes::PAIR_BLOCK;
use crate::neighbors::MinImage;
use crate::team::SyncPtr;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Four-lane groups evaluated in registers and lane by lane (tests: both paths really run).
#[cfg(test)]
pub(crate) static FAST: AtomicUsize = AtomicUsize::new(0);
#[cfg(test)]
pub(crate) static LANES: AtomicUsize = AtomicUsize::new(0);

/// No bond on this pair.
const NONE: u32 = u32::MAX;
/// High bit of a map entry: the bond is oriented (j, i) against the pair.
const REV: u32 = 1 << 31;

/// A count of bonds broken in a fused pass, added to by the pass's parts.
#[derive(Debug, Default)]
pub(crate) struct Breaks(AtomicUsize);

impl Clone for Breaks {
    fn clone(&self) -> Breaks {
        Breaks(AtomicUsize::new(self.0.load(Ordering::Relaxed)))
    }
}

impl Breaks {
    /// The count, reset to 0.
    pub(crate) fn take(&self) -> usize {
        self.0.swap(0, Ordering::Relaxed)
    }
}

/// Per-group parameters of a fusable group: k̄n, k̄s, β̄, σ̄c, c̄, tan φ̄.
pub(crate) type GroupPar = [f64; 6];

/// The map from listed pairs to bonds, for one neighbour-list build and one set of bonds.
#[derive(Clone, Debug, Default)]
pub(crate) struct Map {
    /// The neighbour-list build and pair count it was made for.
    key: (u64, usize),
    /// Per pair: the bond index (| [`REV`] when reversed) or [`NONE`].
    bond: Vec<u32>,
    /// Per group: its parameters (every group is fusable when `ok`).
    par: Vec<GroupPar>,
    /// All bonds in one group (the kernels then take its parameters as constants).
    uniform: bool,
    /// Every group fusable, every intact bond found in the list, and at least 95 % of the
    /// listed pairs bonded.
    ok: bool,
    /// The number of bonds it was built for.
    bonds: usize,
}

/// The parameters of group `g` when it is a parallel bond with the stress criterion.
pub(crate) fn group_par(
    model: &BondModel,
    criterion: &super::criteria::Compiled,
) -> Option<GroupPar> {
    match (model, criterion.criterion) {
        (
            BondModel::Parallel(p),
            Criterion::Stress {
                tensile, cohesion, ..
            },
        ) => Some([p.kn, p.ks, p.beta, tensile, cohesion, criterion.tan_phi]),
        _ => None,
    }
}

/// The bonds' arrays the map is built from.
pub(crate) struct BondsRef<'a> {
    pub i: &'a [u32],
    pub j: &'a [u32],
    pub group: &'a [u16],
    pub status: &'a [u8],
    pub par: Vec<Option<GroupPar>>,
}

impl Map {
    /// Whether this map was made for list build `builds` with `pairs` pairs.
    pub(crate) fn fits(&self, builds: u64, pairs: usize) -> bool {
        self.key == (builds, pairs) && self.bond.len() == pairs
    }

    /// Whether the pass may evaluate the bonds (see the module doc).
    pub(crate) fn ok(&self) -> bool {
        self.ok
    }

    /// Map every intact bond of `b` to its pair in the list (`start`, `nbr`: per disc, the
    /// partners of its pairs).
    pub(crate) fn build(builds: u64, start: &[u32], nbr: &[u32], b: &BondsRef) -> Map {
        let pairs = nbr.len();
        let mut m = Map {
            key: (builds, pairs),
            bond: vec![NONE; pairs],
            par: Vec::new(),
            uniform: false,
            ok: false,
            bonds: b.i.len(),
        };
        let Some(par) = b.par.iter().copied().collect::<Option<Vec<_>>>() else {
            return m;
        };
        m.par = par;
        let n = start.len().saturating_sub(1);
        let find = |o: usize, p: usize| -> Option<usize> {
            if o >= n {
                return None;
            }
            (start[o] as usize..start[o + 1] as usize).find(|&q| nbr[q] as usize == p)
        };
        for k in 0..b.i.len() {
            if b.status[k] != INTACT {
                continue;
            }
            let (i, j) = (b.i[k] as usize, b.j[k] as usize);
            let (q, rev) = match (find(i, j), find(j, i)) {
                (Some(q), _) => (q, 0),
                (None, Some(q)) => (q, REV),
                (None, None) => return m,
            };
            if m.bond[q] != NONE {
                // Two bonds on one pair: the separate stage handles them.
                return m;
            }
            m.bond[q] = k as u32 | rev;
        }
        let g0 = b.group.first().copied().unwrap_or(0);
        m.uniform = b.group.iter().all(|&g| g == g0);
        // Worth it only when nearly every listed pair is bonded (a bonded lattice, a grain
        // made of a bonded lattice): pairs without a bond cost the kernels a lane each, and
        // mixed groups gather lane by lane. Measured (docs/performance.md, tenth round): the
        // bonded lattice (every pair bonded) 1.4× faster; a traditional cutting specimen with
        // 83 % of its pairs bonded 0.9×, so specimens like it keep the separate stage.
        let bonded = m.bond.iter().filter(|&&e| e != NONE).count();
        m.ok = b.i.len() < REV as usize && 20 * bonded >= 19 * pairs;
        m
    }

    /// The view the kernels use, over the bonds' arrays (which must outlive the pass and not
    /// be accessed otherwise while it runs).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn view<'a>(
        &'a self,
        thickness: f64,
        group: &'a [u16],
        g0: &'a [f64],
        rbar: &'a [f64],
        fn_: &'a mut [f64],
        fs: &'a mut [f64],
        m: &'a mut [f64],
        status: &'a mut [u8],
        breaks: &'a Breaks,
    ) -> View<'a> {
        let n = group.len();
        assert!(g0.len() == n && rbar.len() == n && fn_.len() == n && fs.len() == n);
        assert!(m.len() == n && status.len() == n);
        // (Every map entry is a bond index below the count the map was built for.)
        assert_eq!(self.bonds, n, "the map was built for these bonds");
        View {
            bond: &self.bond,
            par: &self.par,
            uniform: self
                .uniform
                .then(|| self.par[group.first().map_or(0, |&g| g as usize)]),
            t: thickness,
            group,
            g0,
            rbar,
            fn_: SyncPtr::of(fn_),
            fs: SyncPtr::of(fs),
            m: SyncPtr::of(m),
            status: SyncPtr::of(status),
            breaks,
        }
    }
}

/// What the contact pass needs to evaluate the bonds of its pairs. Each bond is reached from
/// one pair only, so the parts of a parallel pass write disjoint bond entries.
pub(crate) struct View<'a> {
    bond: &'a [u32],
    par: &'a [GroupPar],
    /// The one group's parameters when all bonds are in one group.
    uniform: Option<GroupPar>,
    /// Disc thickness t (m).
    t: f64,
    group: &'a [u16],
    g0: &'a [f64],
    rbar: &'a [f64],
    fn_: SyncPtr<f64>,
    fs: SyncPtr<f64>,
    m: SyncPtr<f64>,
    status: SyncPtr<u8>,
    /// Bonds broken in this pass.
    breaks: &'a Breaks,
}

// SAFETY: the raw pointers are written only at the entries of the bonds of a part's pairs
// (each bond belongs to one pair, each pair to one part).
unsafe impl Sync for View<'_> {}

/// The pair geometry and kinematics the contact pass computed (see `contact::kernel::eval`):
/// centre distance `d`, r_i + r_j `rc`, unit normal (`nx`, `ny`) from i to j, arms `ai`, `aj`,
/// tangential relative velocity `vt` at the contact point, spins `wi`, `wj`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairGeom {
    pub d: f64,
    pub rc: f64,
    pub nx: f64,
    pub ny: f64,
    pub ai: f64,
    pub aj: f64,
    pub vt: f64,
    pub wi: f64,
    pub wj: f64,
}

/// New bond forces and the stress criterion's conditions (`potyondy2004::update`,
/// `criteria::stress_flags`; the operation order of [`four`]). `mp`: M̄ in the pair's frame.
/// Returns (F̄n, F̄s, M̄ in the pair's frame, tension, shear).
#[inline(always)]
fn law(
    g: &PairGeom,
    par: &GroupPar,
    t: f64,
    dt: f64,
    (rbar, g0, fs, mp): (f64, f64, f64, f64),
) -> (f64, f64, f64, bool, bool) {
    let [kn, ks, beta, sigma_c, c, tan_phi] = *par;
    // Ā = 2R̄t, Ī = (2/3)R̄³t (2D disc of thickness t).
    let a = 2.0 * rbar * t;
    let inertia = 2.0 / 3.0 * rbar * rbar * rbar * t;
    let (kn_a, ks_a, kn_i) = (kn * a, ks * a, kn * inertia);
    let gap = g.d - g.rc;
    let f0 = -kn_a * (gap - g0);
    let f1 = fs - ks_a * (g.vt * dt);
    let f2 = mp - kn_i * ((g.wj - g.wi) * dt);
    // σ̄ ≥ σ̄c as −F̄n ℓ + β̄|M̄| ≥ σ̄c Ā ℓ with ℓ = Ī/(ĀR̄) = R̄/3; τ̄ ≥ c̄ − σ tan φ̄ as
    // |F̄s| ≥ c̄Ā + F̄n tan φ̄.
    let lever = rbar * (1.0 / 3.0);
    let sal = -f0 * lever + beta * f2.abs();
    let tension = sal >= sigma_c * a * lever;
    let shear = f1.abs() >= c * a + f0 * tan_phi;
    (f0, f1, f2, tension, shear)
}

impl View<'_> {
    /// The bond on pair `p`, when intact: (index, reversed).
    #[inline(always)]
    fn bond_of(&self, p: usize) -> Option<(usize, bool)> {
        let e = self.bond[p];
        if e == NONE {
            return None;
        }
        let b = (e & !REV) as usize;
        // SAFETY: b < the bonds' count (checked when the view was made).
        let st = unsafe { *self.status.ptr().add(b) };
        (st == INTACT).then_some((b, e & REV != 0))
    }

    #[inline(always)]
    fn par_of(&self, b: usize) -> &GroupPar {
        match &self.uniform {
            Some(p) => p,
            None => &self.par[self.group[b] as usize],
        }
    }
}

/// The fused bond stage is the contact pass's per-pair hook: [`block`] on its general path,
/// [`four`] in its four-lane kernel.
impl PairHook for View<'_> {
    #[inline(always)]
    fn block<const PER: bool>(
        &self,
        img: &MinImage,
        dt: f64,
        p0: usize,
        q: usize,
        c: &Cols,
        out: [&mut [f64; PAIR_BLOCK]; 4],
    ) {
        block::<PER>(self, img, dt, p0, q, c, out)
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn four(&self, p: usize, m: usize, g: [F64x4; 9], dt: f64, f: &mut [F64x4; 4]) {
        // SAFETY: the caller's contract is `four`'s (AVX2, p + m <= the pair count).
        four(self, p, m, g, dt, f)
    }
}

/// [`law`] over a block of pairs p0..p0 + q of the contact pass's general path: the
/// bonds' entries are gathered, the geometry (the operations of `contact::kernel::eval`) and
/// the law evaluated over the whole block without branches (vectorised like `eval`), and the
/// new bond forces, breaks and outputs written back pair by pair. The same operations as
/// [`law`] and [`four`]: the same bits. `img`: the minimum image when `PER`.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // one index over many arrays: the vectorisable form
pub(crate) fn block<const PER: bool>(
    v: &View,
    img: &MinImage,
    dt: f64,
    p0: usize,
    q: usize,
    c: &Cols,
    out: [&mut [f64; PAIR_BLOCK]; 4],
) {
    let q = q.min(PAIR_BLOCK);
    let mut idx = [usize::MAX; PAIR_BLOCK];
    let mut rev = [false; PAIR_BLOCK];
    let mut any = false;
    for k in 0..q {
        if let Some((b, r)) = v.bond_of(p0 + k) {
            (idx[k], rev[k], any) = (b, r, true);
        }
    }
    if !any {
        return;
    }
    // Bond entries per pair (zeros where there is none: finite, and ignored).
    let z = [0.0; PAIR_BLOCK];
    let (mut rbar, mut g0, mut fs, mut mp) = (z, z, z, z);
    let mut par = [[0.0; PAIR_BLOCK]; 6];
    for k in 0..q {
        let b = idx[k];
        if b == usize::MAX {
            continue;
        }
        // SAFETY: b < the bonds' count; only this pair's evaluation touches bond b.
        let (f, m) = unsafe { (*v.fs.ptr().add(b), *v.m.ptr().add(b)) };
        (rbar[k], g0[k], fs[k]) = (v.rbar[b], v.g0[b], f);
        mp[k] = if rev[k] { -m } else { m };
        let pb = v.par_of(b);
        for (a, x) in par.iter_mut().zip(pb) {
            a[k] = *x;
        }
    }
    let (mut f0, mut f1, mut f2) = (z, z, z);
    let mut o = [z; 4];
    let mut brk = [false; PAIR_BLOCK];
    let mut ten = [false; PAIR_BLOCK];
    for k in 0..PAIR_BLOCK {
        let (dx, dy) = if PER {
            img.delta_select(c.dx[k], c.dy[k])
        } else {
            (c.dx[k], c.dy[k])
        };
        let d = (dx * dx + dy * dy).sqrt();
        let inv = 1.0 / d;
        let (nx, ny) = (dx * inv, dy * inv);
        let (ri, rj, wi, wj) = (c.ri[k], c.rj[k], c.wi[k], c.wj[k]);
        let rc = ri + rj;
        let h = 0.5 * (rc - d);
        let wr = (wi * ri + wj * rj) - h * (wi + wj);
        let rvx = c.dvx[k] + wr * ny;
        let rvy = c.dvy[k] - wr * nx;
        let g = PairGeom {
            d,
            rc,
            nx,
            ny,
            ai: ri - h,
            aj: rj - h,
            vt: rvy * nx - rvx * ny,
            wi,
            wj,
        };
        let p = [
            par[0][k], par[1][k], par[2][k], par[3][k], par[4][k], par[5][k],
        ];
        let (a0, a1, a2, t, sh) = law(&g, &p, v.t, dt, (rbar[k], g0[k], fs[k], mp[k]));
        (f0[k], f1[k], f2[k], ten[k], brk[k]) = (a0, a1, a2, t, t | sh);
        o[0][k] = a0 * g.nx + a1 * -g.ny;
        o[1][k] = a0 * g.ny + a1 * g.nx;
        o[2][k] = -g.ai * a1 - a2;
        o[3][k] = -g.aj * a1 + a2;
    }
    let [fx, fy, ti, tj] = out;
    for k in 0..q {
        let b = idx[k];
        if b == usize::MAX {
            continue;
        }
        // SAFETY: as above.
        unsafe {
            *v.fn_.ptr().add(b) = f0[k];
            *v.fs.ptr().add(b) = f1[k];
            *v.m.ptr().add(b) = if rev[k] { -f2[k] } else { f2[k] };
            if brk[k] {
                let mode = if ten[k] {
                    BreakMode::Tension
                } else {
                    BreakMode::Shear
                };
                *v.status.ptr().add(b) = NEW + mode.index() as u8;
                v.breaks.0.fetch_add(1, Ordering::Relaxed);
                continue;
            }
        }
        fx[k] += o[0][k];
        fy[k] += o[1][k];
        ti[k] += o[2][k];
        tj[k] += o[3][k];
    }
}

/// The four-lane form of [`law`] for pairs `p..p + m` (m ≤ 4; the other lanes are
/// ignored): the geometry comes in AVX2 registers from the four-lane contact kernel and the
/// outputs are added to its force columns `f = [fx, fy, ti, tj]` in the lanes with an intact
/// bond that does not break now. Four intact bonds stored one after the other in bond order
/// and oriented like their pairs (the common case in a bonded specimen of touching discs:
/// the store sorts bonds like the list's pairs) are loaded and stored as vectors; other
/// groups gather and store lane by lane. Both evaluate [`law4`]: the operations of
/// [`law`].
///
/// # Safety
/// The CPU must support AVX2; `p + m` must not exceed the pair count.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) unsafe fn four(
    v: &View,
    p: usize,
    m: usize,
    g: [F64x4; 9],
    dt: f64,
    f: &mut [F64x4; 4],
) {
    if m == 4 {
        let e = v.bond.as_ptr().add(p);
        let (e0, e1, e2, e3) = (*e, *e.add(1), *e.add(2), *e.add(3));
        let b0 = (e0 & !REV) as usize;
        // (REV is the top bit and bonds number fewer than 2^31: no overflow below.)
        let seq = (e1 ^ e0.wrapping_add(1)) | (e2 ^ e0.wrapping_add(2)) | (e3 ^ e0.wrapping_add(3));
        // SAFETY (status read): b0 + 4 <= the bonds' count, checked first.
        if seq | (e0 & REV) == 0
            && b0 + 4 <= v.group.len()
            && (v.status.ptr().add(b0) as *const u32).read_unaligned()
                == u32::from_ne_bytes([INTACT; 4])
        {
            #[cfg(test)]
            FAST.fetch_add(1, Ordering::Relaxed);
            // SAFETY (loads and stores at b0..b0 + 4): b0 + 4 <= the bonds' count.
            let ld = |a: *const f64| F64x4::load(a.add(b0));
            let cols = [
                ld(v.rbar.as_ptr()),
                ld(v.g0.as_ptr()),
                ld(v.fs.ptr()),
                ld(v.m.ptr()),
            ];
            let par = match &v.uniform {
                Some(u) => u.map(|x| F64x4::splat(x)),
                None => std::array::from_fn(|q| {
                    let c: [f64; 4] = std::array::from_fn(|l| v.par_of(b0 + l)[q]);
                    F64x4::load(c.as_ptr())
                }),
            };
            let all = F64x4::all_ones();
            let (f0, f1, f2, brk, ten, out) = law4(v.t, dt, cols, par, g, all);
            let st = |a: *mut f64, x: F64x4| x.store(a.add(b0));
            st(v.fn_.ptr(), f0);
            st(v.fs.ptr(), f1);
            st(v.m.ptr(), f2);
            finish(v, [b0, b0 + 1, b0 + 2, b0 + 3], all, brk, ten, out, f);
            return;
        }
    }
    four_masked(v, p, m, g, dt, f)
}

/// [`four`] for any group: the lanes' bonds gathered and stored one by one.
///
/// # Safety
/// As [`four`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline(never)]
unsafe fn four_masked(v: &View, p: usize, m: usize, g: [F64x4; 9], dt: f64, f: &mut [F64x4; 4]) {
    #[cfg(test)]
    LANES.fetch_add(1, Ordering::Relaxed);
    let mut idx = [usize::MAX; 4];
    let mut rev = [false; 4];
    let mut any = false;
    for l in 0..m.min(4) {
        if let Some((b, r)) = v.bond_of(p + l) {
            (idx[l], rev[l], any) = (b, r, true);
        }
    }
    if !any {
        return;
    }
    let full = f64::from_bits(!0);
    let mut c = [[0.0; 4]; 4];
    let mut par = [[0.0; 4]; 6];
    let (mut on, mut flip) = ([0.0; 4], [0.0; 4]);
    for l in 0..4 {
        let b = idx[l];
        if b == usize::MAX {
            continue;
        }
        // SAFETY: b < the bonds' count; only this pair's evaluation touches bond b.
        (c[0][l], c[1][l], c[2][l], c[3][l]) =
            (v.rbar[b], v.g0[b], *v.fs.ptr().add(b), *v.m.ptr().add(b));
        if v.uniform.is_none() {
            for (a, x) in par.iter_mut().zip(v.par_of(b)) {
                a[l] = *x;
            }
        }
        on[l] = full;
        if rev[l] {
            flip[l] = -0.0;
        }
    }
    let ld = |a: &[f64; 4]| F64x4::load(a.as_ptr());
    let flip = ld(&flip);
    // M̄ in the pair's frame (a sign flip, exact).
    let cols = [ld(&c[0]), ld(&c[1]), ld(&c[2]), ld(&c[3]) ^ flip];
    let on = ld(&on);
    let par = match &v.uniform {
        Some(u) => u.map(|x| F64x4::splat(x)),
        None => par.map(|a| ld(&a)),
    };
    let (f0, f1, f2, brk, ten, out) = law4(v.t, dt, cols, par, g, on);
    let mut o = [[0.0; 4]; 3];
    for (a, x) in o.iter_mut().zip([f0, f1, f2 ^ flip]) {
        x.store(a.as_mut_ptr());
    }
    for (l, &b) in idx.iter().enumerate() {
        if b != usize::MAX {
            *v.fn_.ptr().add(b) = o[0][l];
            *v.fs.ptr().add(b) = o[1][l];
            *v.m.ptr().add(b) = o[2][l];
        }
    }
    finish(v, idx, on, brk, ten, out, f);
}

/// The parallel-bond law of [`law`] on four lanes: columns `[R̄, g₀, F̄s, M̄ (pair frame)]`,
/// parameters `[k̄n, k̄s, β̄, σ̄c, c̄, tan φ̄]`, the pair geometry `g` (see [`four`]); the
/// lanes `on` hold a bond. Returns F̄n, F̄s, M̄ (pair frame), the breaking lanes, the
/// tension lanes and the outputs `[fx, fy, ti, tj]`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn law4(
    t: f64,
    dt: f64,
    cols: [F64x4; 4],
    par: [F64x4; 6],
    g: [F64x4; 9],
    on: F64x4,
) -> (F64x4, F64x4, F64x4, F64x4, F64x4, [F64x4; 4]) {
    let set = |v| F64x4::splat(v);
    let sign = set(-0.0);
    let neg = |a: F64x4| a ^ sign;
    let [rbar, g0, fs0, mp] = cols;
    let [kn, ks, beta, sigma_c, c, tan_phi] = par;
    let [d, rc, nx, ny, ai, aj, vt, wi, wj] = g;
    let (t, dtv) = (set(t), set(dt));
    // Ā = 2R̄t, Ī = (2/3)R̄³t; the operations of [`law`], in its order.
    let a = set(2.0) * rbar * t;
    let inertia = set(2.0 / 3.0) * rbar * rbar * rbar * t;
    let (kn_a, ks_a, kn_i) = (kn * a, ks * a, kn * inertia);
    let gap = d - rc;
    let f0 = neg(kn_a) * (gap - g0);
    let f1 = fs0 - ks_a * (vt * dtv);
    let f2 = mp - kn_i * ((wj - wi) * dtv);
    let lever = rbar * set(1.0 / 3.0);
    let (fs_abs, m_abs) = (sign.andnot(f1), sign.andnot(f2));
    let sal = neg(f0) * lever + beta * m_abs;
    let ten = on & sal.ge(sigma_c * a * lever);
    let shr = fs_abs.ge(c * a + f0 * tan_phi);
    let brk = ten | (on & shr);
    let out = [
        f0 * nx + f1 * neg(ny),
        f0 * ny + f1 * nx,
        neg(ai) * f1 - f2,
        neg(aj) * f1 + f2,
    ];
    (f0, f1, f2, brk, ten, out)
}

/// Mark the bonds of the breaking lanes (tension before shear) and add the outputs of the
/// lanes `on` that hold to `f`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn finish(
    v: &View,
    idx: [usize; 4],
    on: F64x4,
    brk: F64x4,
    ten: F64x4,
    out: [F64x4; 4],
    f: &mut [F64x4; 4],
) {
    let bm = brk.bitmask();
    if bm == 0 && on.bitmask() == 15 {
        for (fk, ok) in f.iter_mut().zip(out) {
            *fk = *fk + ok;
        }
        return;
    }
    let tm = ten.bitmask();
    for (l, &b) in idx.iter().enumerate() {
        if bm >> l & 1 == 0 {
            continue;
        }
        let mode = if tm >> l & 1 != 0 {
            BreakMode::Tension
        } else {
            BreakMode::Shear
        };
        *v.status.ptr().add(b) = NEW + mode.index() as u8;
        v.breaks.0.fetch_add(1, Ordering::Relaxed);
    }
    let keep = brk.andnot(on);
    for (fk, ok) in f.iter_mut().zip(out) {
        *fk = keep.select(*fk + ok, *fk);
    }
}

#[cfg(test)]
mod tests {
    use crate::bond::bench::{shaken_hex_lattice, KN, RADIUS};
    use crate::bond::{world_with_bonds, BondGroup, BondModel, BondStatus, Bonds, BreakMode};
    use crate::bond::{Criterion, ParallelBondParams};
    use crate::contact::{LinearSpringDashpot, NormalDamping};
    use crate::state::{Periodic, State};
    use crate::{ContactLaws, ContactModel, Params, World};

    /// A strong lattice group and a weak one (improved ORC's two groups), which breaks in
    /// tension and in shear under the shaking below.
    fn groups(t: f64) -> Vec<BondGroup> {
        crate::bond::bench::two_groups(t, 2e5, 8e4)
    }

    fn law(gamma: f64) -> ContactModel {
        ContactModel::Linear(LinearSpringDashpot {
            kn: KN,
            ks: 2.0 / 7.0 * KN,
            damping: NormalDamping::Gamma(gamma),
            shear_damping: 0.5,
            mu: 0.5,
        })
    }

    /// A shaken 60 × 30-cell lattice (3,600 discs, ~10,800 bonds in two interleaved groups;
    /// with `reversed` every third bond is made as (j, i)); contacts with a normal dashpot γ.
    fn world(fuse: bool, track: bool, reversed: bool, periodic: bool, gamma: f64) -> World {
        let mut st = shaken_hex_lattice([60, 30], 99, 0.02, 20.0);
        if !periodic {
            st.periodic = Periodic::default();
        }
        // Radii 0–0.5 % below the lattice's (bond radii then differ, as in a real specimen).
        for (k, r) in st.discs.r.iter_mut().enumerate() {
            *r *= 1.0 - 0.005 * (k as f64 * 0.618_034).fract();
        }
        let mut b0 = Bonds::new(groups(st.thickness)).unwrap();
        b0.install_within_gap(&st, 1e-5, |i, j| Some(((i + j) % 2) as u16))
            .unwrap();
        let mut b = Bonds::new(groups(st.thickness)).unwrap();
        for (k, v) in b0.iter().enumerate() {
            let (i, j) = if reversed && k % 3 == 0 {
                (v.j, v.i)
            } else {
                (v.i, v.j)
            };
            b.add(&st, i as usize, j as usize, v.group).unwrap();
        }
        let params = Params {
            dt_fixed: Some(1e-7),
            track_energy: track,
            fuse_bonds: fuse,
            ..Params::default()
        };
        world_with_bonds(st, params, ContactLaws::uniform(law(gamma)), b, &[]).unwrap()
    }

    fn run(w: &mut World, steps: usize, threads: usize) {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| (0..steps).for_each(|_| w.step()));
    }

    fn breaks(w: &World) -> Vec<(u64, u32, BreakMode)> {
        let b = w.bonds.as_ref().unwrap();
        b.log()
            .events
            .iter()
            .map(|e| (e.step, e.bond, e.mode))
            .collect()
    }

    fn max_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    }

    fn max_abs(a: &[f64]) -> f64 {
        a.iter().fold(0.0, |m, x| m.max(x.abs()))
    }

    /// The fused stage is the separate bond stage (itself checked against the closed forms in
    /// `tests/bond_parallel.rs`) up to rounding: after 300 steps of the shaken lattice, with
    /// contacts acting and bonds breaking in both modes, the same bonds broke at the same
    /// steps in the same modes, and positions, velocities and bond forces agree to 1e-9 of
    /// their scale — periodic with reversed bonds, and bounded.
    #[test]
    fn fused_stage_agrees_with_the_separate_stage() {
        for (periodic, reversed) in [(true, true), (false, false)] {
            let (mut f, mut s) = (
                world(true, false, reversed, periodic, 100.0),
                world(false, false, reversed, periodic, 100.0),
            );
            run(&mut f, 300, 1);
            run(&mut s, 300, 1);
            assert_eq!(f.counters.bonds_fused, 300);
            assert_eq!(s.counters.bonds_fused, 0);
            let (bf, bs) = (breaks(&f), breaks(&s));
            let mut modes = [0; 2];
            bf.iter().for_each(|e| modes[e.2.index()] += 1);
            eprintln!("periodic {periodic}: breaks by mode {modes:?}");
            assert!(modes[0] > 0 && modes[1] > 0, "breaks by mode {modes:?}");
            assert_eq!(bf, bs);
            let (df, ds) = (&f.state.discs, &s.state.discs);
            assert_eq!(df.id, ds.id);
            for (a, b) in [(&df.x, &ds.x), (&df.y, &ds.y)] {
                assert!(max_diff(a, b) < 1e-9 * RADIUS, "{}", max_diff(a, b));
            }
            for (a, b) in [(&df.vx, &ds.vx), (&df.vy, &ds.vy), (&df.omega, &ds.omega)] {
                assert!(max_diff(a, b) < 1e-9 * max_abs(b), "{}", max_diff(a, b));
            }
            let (vf, vs): (Vec<_>, Vec<_>) = (
                f.bonds.as_ref().unwrap().iter().collect(),
                s.bonds.as_ref().unwrap().iter().collect(),
            );
            let fields: [fn(&crate::bond::BondView) -> f64; 3] = [|v| v.fn_, |v| v.fs, |v| v.m];
            for q in fields {
                let (a, b): (Vec<f64>, Vec<f64>) =
                    (vf.iter().map(q).collect(), vs.iter().map(q).collect());
                assert!(
                    max_diff(&a, &b) < 1e-9 * max_abs(&b),
                    "{}",
                    max_diff(&a, &b)
                );
            }
        }
    }

    /// The fused stage's results are the same bits on 1, 2 and 3 threads, on the portable
    /// path (the general kernel path with the block form instead of the four-lane kernels) and
    /// with energy tracking (contacts without dashpots): disc state, bond forces and status,
    /// the break log and the energies after 200 steps, with reversed bonds and breaks; both
    /// four-lane forms (in registers, lane by lane) ran. With dashpots and energy tracking
    /// (dashpot sums) the separate bond stage runs.
    #[test]
    fn fused_bits_do_not_depend_on_threads_path_or_energy_tracking() {
        let go = |threads: usize, portable: bool, track: bool, gamma: f64| {
            let mut w = world(true, track, true, true, gamma);
            w.ws.slots.portable = portable;
            run(&mut w, 200, threads);
            let b = w.bonds.clone().unwrap();
            let e = format!("{:?}", track.then(|| w.energy()));
            (
                serde_json::to_string(&w.state).unwrap(),
                b,
                w.counters.bonds_fused,
                e,
            )
        };
        assert_eq!(go(1, false, true, 100.0).2, 0);
        for track in [false, true] {
            let one = go(1, false, track, 0.0);
            assert_eq!(one.2, 200);
            assert!(!one.1.log().events.is_empty());
            let map = one.1.fused_map().unwrap();
            assert!(map
                .bond
                .iter()
                .any(|&e| e != super::NONE && e & super::REV != 0));
            #[cfg(target_arch = "x86_64")]
            if crate::lanes::has_avx2() {
                use std::sync::atomic::Ordering::Relaxed;
                assert!(super::FAST.load(Relaxed) > 0 && super::LANES.load(Relaxed) > 0);
            }
            for (threads, portable) in [(2, false), (3, false), (1, true), (2, true)] {
                let other = go(threads, portable, track, 0.0);
                let what = format!("{threads} threads, portable {portable}, energy {track}");
                assert!(other.0 == one.0, "state, {what}");
                assert!(other.1 == one.1, "bonds, {what}");
                assert_eq!(other.2, 200, "{what}");
                assert!(
                    other.3 == one.3,
                    "energies, {what}: {} vs {}",
                    other.3,
                    one.3
                );
            }
        }
    }

    /// Two discs joined at contact and pulled apart by δ (at rest): one step gives
    /// F̄n = −k̄n Ā δ with Ā = 2R̄t (Potyondy & Cundall 2004, 2D disc of thickness t), F̄s = M̄ = 0;
    /// pulled to k̄n δ = 1.01 σ̄c the bond breaks in tension in that step, is logged, and the
    /// discs (no longer touching) get no force.
    #[test]
    fn fused_bond_force_and_tension_break_are_the_closed_form() {
        let (r, t, kn, sigma_c) = (1e-3, 0.5e-3, 2e12, 5e6);
        let pulled = |delta: f64| {
            let mut st = State {
                thickness: t,
                ..State::default()
            };
            st.discs.push_uniform(0.0, 0.0, r, 2500.0, t, 0);
            st.discs.push_uniform(2.0 * r, 0.0, r, 2500.0, t, 0);
            let g = BondGroup {
                name: "pb".into(),
                model: BondModel::Parallel(ParallelBondParams {
                    kn,
                    ks: 0.5 * kn,
                    lambda: 1.0,
                    beta: 1.0,
                }),
                criterion: Criterion::Stress {
                    tensile: sigma_c,
                    cohesion: 1e9,
                    friction_angle: 0.5,
                },
            };
            let mut b = Bonds::new(vec![g]).unwrap();
            b.add(&st, 0, 1, 0).unwrap();
            let params = Params {
                dt_fixed: Some(1e-9),
                skin: Some(0.2 * r),
                track_energy: false,
                ..Params::default()
            };
            let mut w =
                world_with_bonds(st, params, ContactLaws::uniform(law(100.0)), b, &[]).unwrap();
            let k = w.index_of_id(1).unwrap();
            w.state.discs.x[k] += delta;
            w.step();
            assert_eq!(w.counters.bonds_fused, 1);
            w
        };
        let area = 2.0 * r * t;
        let delta = 1e-6;
        let w = pulled(delta);
        let v = w.bonds.as_ref().unwrap().get(0);
        assert_eq!(v.status, BondStatus::Intact);
        let expect = -kn * area * delta;
        assert!(
            (v.fn_ - expect).abs() <= 1e-12 * expect.abs(),
            "{} vs {expect}",
            v.fn_
        );
        assert_eq!((v.fs, v.m), (0.0, 0.0));
        // The force pulls the discs together: +|F̄n| on the left disc.
        let d = &w.state.discs;
        let left = w.index_of_id(0).unwrap();
        assert!((d.fx[left] + expect).abs() <= 1e-12 * expect.abs());
        let w = pulled(1.01 * sigma_c / kn);
        let b = w.bonds.as_ref().unwrap();
        assert!(matches!(
            b.get(0).status,
            BondStatus::Broken(BreakMode::Tension)
        ));
        assert_eq!(b.log().len(), 1);
        assert!(w.state.discs.fx.iter().all(|&f| f == 0.0));
    }
}
