//! Disc–disc force pass over the neighbour list.
//!
//! Pairs are computed in blocks of [`BLOCK`]: a gather loop copies the pair data into small
//! local arrays, a branch-free loop evaluates the law for the whole block (so the compiler can
//! vectorise it), and a scatter loop adds the forces to the discs in pair order. Discs are
//! grouped in fixed chunks of [`CHUNK`] discs (independent of the thread count). One thread:
//! forces are scattered pair by pair in list order. Several threads: chunks run in parallel
//! and write per-pair slots, then every disc gathers its partner-side slots (increasing pair
//! order) and adds its own pairs' sum — the same sequence of floating-point additions as the
//! serial scatter, so results are bit-identical for any thread count. Energies are summed in
//! pair order within a chunk and the chunk sums added in chunk order.

use super::{ContactLaws, ContactModel, HertzMindlin, LinearSpringDashpot, NormalDamping};
use super::{PairKin, PairOut};
use crate::neighbors::{MinImage, Neighbors};
use crate::state::Discs;
use rayon::prelude::*;

/// Discs per work chunk (fixed so that reductions do not depend on the thread count).
pub const CHUNK: usize = 2048;
/// Pairs per block of the kernel.
pub const BLOCK: usize = 64;

/// Energies of one force pass: strain (stored, at this step), dissipated in dashpots and
/// friction during this step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassEnergy {
    pub strain: f64,
    pub damp: f64,
    pub fric: f64,
}

impl PassEnergy {
    pub fn add(&mut self, o: &PassEnergy) {
        self.strain += o.strain;
        self.damp += o.damp;
        self.fric += o.fric;
    }
}

/// Per-pair force slots for the parallel pass (fx, fy on j; torques on i and j).
#[derive(Clone, Debug, Default)]
pub struct Slots {
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub ti: Vec<f64>,
    pub tj: Vec<f64>,
    pub chunk_energy: Vec<PassEnergy>,
}

/// A contact law as the force pass sees it: the uniform laws skip the material lookup and
/// have branch-free bodies.
pub trait PairLaw: Sync {
    /// Whether the law depends on the materials (table lookup).
    const MATERIAL: bool;
    /// Whether rolling resistance may apply.
    const ROLLING: bool;
    fn force<const E: bool>(&self, mi: u16, mj: u16, k: &PairKin, us: &mut f64) -> PairOut;
    /// Rolling moment on i after the update, dissipated and stored energy
    /// (see [`super::RollingResistance::update`]).
    #[inline(always)]
    fn rolling(
        &self,
        _mi: u16,
        _mj: u16,
        _k: &PairKin,
        _f_n: f64,
        _w: f64,
        _mr: &mut f64,
    ) -> [f64; 3] {
        [0.0; 3]
    }
}

/// Linear law with c_n = γ m*.
pub struct LinearGamma(pub LinearSpringDashpot, pub f64);
/// Linear law with c_n = 2ζ√(m* k_n).
pub struct LinearRatio(pub LinearSpringDashpot, pub f64);

impl PairLaw for LinearGamma {
    const MATERIAL: bool = false;
    const ROLLING: bool = false;
    #[inline(always)]
    fn force<const E: bool>(&self, _: u16, _: u16, k: &PairKin, us: &mut f64) -> PairOut {
        self.0.force_cn::<E>(k, self.1 * k.m_eff, us)
    }
}

impl PairLaw for LinearRatio {
    const MATERIAL: bool = false;
    const ROLLING: bool = false;
    #[inline(always)]
    fn force<const E: bool>(&self, _: u16, _: u16, k: &PairKin, us: &mut f64) -> PairOut {
        self.0
            .force_cn::<E>(k, 2.0 * self.1 * (k.m_eff * self.0.kn).sqrt(), us)
    }
}

impl PairLaw for HertzMindlin {
    const MATERIAL: bool = false;
    const ROLLING: bool = false;
    #[inline(always)]
    fn force<const E: bool>(&self, _: u16, _: u16, k: &PairKin, us: &mut f64) -> PairOut {
        HertzMindlin::force::<E>(self, k, us)
    }
}

impl PairLaw for ContactLaws {
    const MATERIAL: bool = true;
    const ROLLING: bool = true;
    #[inline(always)]
    fn force<const E: bool>(&self, mi: u16, mj: u16, k: &PairKin, us: &mut f64) -> PairOut {
        self.model(mi, mj).force::<E>(k, us)
    }
    #[inline(always)]
    fn rolling(&self, mi: u16, mj: u16, k: &PairKin, f_n: f64, w: f64, mr: &mut f64) -> [f64; 3] {
        let Some(rr) = self.rolling(mi, mj) else {
            return [0.0; 3];
        };
        let kn = self.model(mi, mj).kn(k.r_eff, k.delta);
        let diss = rr.update(kn, k.r_eff, f_n, w, k.dt, mr);
        let kr = rr.kr(kn, k.r_eff);
        let strain = if kr > 0.0 { 0.5 * *mr * *mr / kr } else { 0.0 };
        [*mr, diss, strain]
    }
}

/// Read-only data of the pass.
struct Ctx<'a, L: PairLaw> {
    x: &'a [f64],
    y: &'a [f64],
    vx: &'a [f64],
    vy: &'a [f64],
    w: &'a [f64],
    r: &'a [f64],
    mat: &'a [u16],
    minv: &'a [f64],
    start: &'a [u32],
    nbr: &'a [u32],
    g0: &'a [f64],
    law: &'a L,
    img: MinImage,
    dt: f64,
}

/// Unchecked read; [`compute`] validates all indices once per call ([`valid`]).
macro_rules! at {
    ($s:expr, $i:expr) => {
        // SAFETY: see `valid`: every disc index in the list is < n and every pair index is
        // < the slot length.
        unsafe { *$s.get_unchecked($i) }
    };
}

/// Working arrays of one block (inputs gathered per pair, outputs per pair).
#[derive(Clone)]
pub struct Scratch {
    dx: [f64; BLOCK],
    dy: [f64; BLOCK],
    reach: [f64; BLOCK],
    wr: [f64; BLOCK],
    wrel: [f64; BLOCK],
    dvx: [f64; BLOCK],
    dvy: [f64; BLOCK],
    ms: [f64; BLOCK],
    ri: [f64; BLOCK],
    rj: [f64; BLOCK],
    mi: [u16; BLOCK],
    mj: [u16; BLOCK],
    us: [f64; BLOCK],
    mr: [f64; BLOCK],
    fx: [f64; BLOCK],
    fy: [f64; BLOCK],
    ti: [f64; BLOCK],
    tj: [f64; BLOCK],
    es: [f64; BLOCK],
    ed: [f64; BLOCK],
    ef: [f64; BLOCK],
}

impl Default for Scratch {
    fn default() -> Scratch {
        let z = [0.0; BLOCK];
        Scratch {
            dx: z,
            dy: z,
            reach: z,
            wr: z,
            wrel: z,
            dvx: z,
            dvy: z,
            ms: z,
            ri: z,
            rj: z,
            mi: [0; BLOCK],
            mj: [0; BLOCK],
            us: z,
            mr: z,
            fx: z,
            fy: z,
            ti: z,
            tj: z,
            es: z,
            ed: z,
            ef: z,
        }
    }
}

/// Gather pairs p0..p0+q (q ≤ BLOCK) into the scratch arrays, disc by disc (`gi` is the
/// disc owning pair p0 or an earlier disc; it is advanced). The history is read from `us`,
/// `mr` (indexed by pair).
#[inline(always)]
fn gather<L: PairLaw>(
    c: &Ctx<L>,
    p0: usize,
    q: usize,
    gi: &mut usize,
    us: &[f64],
    mr: &[f64],
    s: &mut Scratch,
) {
    debug_assert!(q <= BLOCK);
    let (mut p, end) = (p0, p0 + q);
    let mut k = 0;
    while p < end {
        while at!(c.start, *gi + 1) as usize <= p {
            *gi += 1;
        }
        let i = *gi;
        let b = (at!(c.start, i + 1) as usize).min(end);
        let (xi, yi, ri, wi) = (at!(c.x, i), at!(c.y, i), at!(c.r, i), at!(c.w, i));
        let (vxi, vyi, mvi) = (at!(c.vx, i), at!(c.vy, i), at!(c.minv, i));
        let wri = wi * ri;
        let mati = if L::MATERIAL { at!(c.mat, i) } else { 0 };
        while p < b {
            let j = at!(c.nbr, p) as usize;
            let (ddx, ddy) = c.img.delta(at!(c.x, j) - xi, at!(c.y, j) - yi);
            s.dx[k] = ddx;
            s.dy[k] = ddy;
            let rj = at!(c.r, j);
            s.ri[k] = ri;
            s.rj[k] = rj;
            let g0 = if c.g0.is_empty() { 0.0 } else { at!(c.g0, p) };
            s.reach[k] = ri + rj + g0;
            let wj = at!(c.w, j);
            s.wr[k] = wri + wj * rj;
            s.dvx[k] = at!(c.vx, j) - vxi;
            s.dvy[k] = at!(c.vy, j) - vyi;
            s.ms[k] = mvi + at!(c.minv, j);
            s.us[k] = at!(us, p);
            if L::ROLLING {
                s.wrel[k] = wi - wj;
                s.mr[k] = at!(mr, p);
            }
            if L::MATERIAL {
                s.mi[k] = mati;
                s.mj[k] = at!(c.mat, j);
            }
            k += 1;
            p += 1;
        }
    }
    // Entries q..BLOCK keep stale but finite data (or zeros) and are ignored.
}

/// Evaluate the law for all BLOCK entries (branch-free, fixed trip count: vectorisable).
#[inline(always)]
fn eval<const E: bool, L: PairLaw>(law: &L, dt: f64, s: &mut Scratch) {
    for k in 0..BLOCK {
        let (dx, dy) = (s.dx[k], s.dy[k]);
        let d2 = dx * dx + dy * dy;
        let rc = s.reach[k];
        let touch = d2 < rc * rc && rc > 0.0 && s.ms[k] > 0.0;
        let d = d2.sqrt();
        let inv = 1.0 / d;
        let (nx, ny) = (dx * inv, dy * inv);
        let rvx = s.dvx[k] + s.wr[k] * ny;
        let rvy = s.dvy[k] - s.wr[k] * nx;
        let (ri, rj) = (s.ri[k], s.rj[k]);
        let kin = PairKin {
            delta: rc - d,
            vn: rvx * nx + rvy * ny,
            vt: rvy * nx - rvx * ny,
            m_eff: 1.0 / s.ms[k],
            r_eff: ri * rj / (ri + rj),
            dt,
        };
        let mut u = s.us[k];
        let o = law.force::<E>(s.mi[k], s.mj[k], &kin, &mut u);
        let mut m = s.mr[k];
        let roll = if L::ROLLING && touch {
            law.rolling(s.mi[k], s.mj[k], &kin, o.f_n, s.wrel[k], &mut m)
        } else {
            [0.0; 3]
        };
        s.us[k] = if touch { u } else { 0.0 };
        s.mr[k] = if touch { m } else { 0.0 };
        // t = (−n_y, n_x): F = F_n n + F_t t.
        let fx = o.f_n * nx - o.f_t * ny;
        let fy = o.f_n * ny + o.f_t * nx;
        let ti = -ri * o.f_t + roll[0];
        let tj = -rj * o.f_t - roll[0];
        s.fx[k] = if touch { fx } else { 0.0 };
        s.fy[k] = if touch { fy } else { 0.0 };
        s.ti[k] = if touch { ti } else { 0.0 };
        s.tj[k] = if touch { tj } else { 0.0 };
        if E {
            s.es[k] = if touch { o.e_strain + roll[2] } else { 0.0 };
            s.ed[k] = if touch { o.e_damp } else { 0.0 };
            s.ef[k] = if touch { o.e_fric + roll[1] } else { 0.0 };
        }
    }
}

/// [`eval`] compiled for AVX2 (4 lanes). Only selects, +, −, ×, ÷ and √ are used, all
/// correctly rounded in IEEE 754, and no FMA contraction happens, so the results are the same
/// bits as the baseline build.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn eval_avx2<const E: bool, L: PairLaw>(law: &L, dt: f64, s: &mut Scratch) {
    eval::<E, L>(law, dt, s)
}

/// Evaluate one gathered block with the best instruction set available.
#[inline(always)]
fn eval_best<const E: bool, L: PairLaw>(law: &L, dt: f64, s: &mut Scratch, avx2: bool) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is true only when the CPU reports AVX2 (see `has_avx2`).
        unsafe { eval_avx2::<E, L>(law, dt, s) };
        return;
    }
    let _ = avx2;
    eval::<E, L>(law, dt, s)
}

fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Evaluate pairs p0..p0+q: gather, evaluate, write the rolling history back and add the
/// energies in pair order. Forces and the new `us` stay in the scratch [..q]; the caller
/// writes `us` back.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn block<const E: bool, L: PairLaw>(
    c: &Ctx<L>,
    p0: usize,
    gi: &mut usize,
    us: &mut [f64],
    mr: &mut [f64],
    s: &mut Scratch,
    e: &mut PassEnergy,
    avx2: bool,
) {
    let q = us.len();
    gather(c, p0, q, gi, us, mr, s);
    eval_best::<E, L>(c.law, c.dt, s, avx2);
    if L::ROLLING {
        mr.copy_from_slice(&s.mr[..q]);
    }
    if E {
        for k in 0..q {
            e.strain += s.es[k];
            e.damp += s.ed[k];
            e.fric += s.ef[k];
        }
    }
}

/// Whether the list is consistent with `n` discs (checked before unchecked indexing).
fn valid(d: &Discs, nb: &Neighbors, minv: &[f64]) -> bool {
    let n = d.len();
    let np = nb.nbr.len();
    nb.start.len() == n + 1
        && nb.start[n] as usize == np
        && nb.us.len() == np
        && nb.mr.len() == np
        && (nb.g0.is_empty() || nb.g0.len() == np)
        && nb.rstart.len() == n + 1
        && nb.rpair.len() == np
        && minv.len() == n
        && [
            d.y.len(),
            d.vx.len(),
            d.vy.len(),
            d.omega.len(),
            d.r.len(),
            d.material.len(),
        ]
        .iter()
        .all(|&l| l == n)
        && [d.fx.len(), d.fy.len(), d.torque.len()]
            .iter()
            .all(|&l| l == n)
        && (nb.nbr.iter().fold(0u32, |m, &j| m.max(j)) as usize) < n.max(1)
        && (nb.rpair.iter().fold(0u32, |m, &p| m.max(p)) as usize) < np.max(1)
        && nb.start.windows(2).all(|w| w[0] <= w[1])
}

/// Compute disc–disc contact forces, adding them to `d.fx, d.fy, d.torque` (which the caller
/// has cleared). Returns the pass energies (zero unless `track_energy`).
#[allow(clippy::too_many_arguments)]
pub fn compute(
    d: &mut Discs,
    nb: &mut Neighbors,
    minv: &[f64],
    laws: &ContactLaws,
    img: MinImage,
    dt: f64,
    track_energy: bool,
    slots: &mut Slots,
) -> PassEnergy {
    assert!(valid(d, nb, minv), "neighbour list out of date");
    let uniform = laws.n_materials() == 1 && !laws.any_rolling();
    let a = (d, nb, minv, img, dt, track_energy, slots);
    match (uniform, laws.models()[0]) {
        (true, ContactModel::Linear(l)) => match l.damping {
            NormalDamping::Gamma(g) => run(a, &LinearGamma(l, g)),
            NormalDamping::Ratio(z) => run(a, &LinearRatio(l, z)),
        },
        (true, ContactModel::HertzMindlin(h)) => run(a, &h),
        _ => run(a, laws),
    }
}

type Args<'a> = (
    &'a mut Discs,
    &'a mut Neighbors,
    &'a [f64],
    MinImage,
    f64,
    bool,
    &'a mut Slots,
);

fn run<L: PairLaw>(a: Args, law: &L) -> PassEnergy {
    let (d, nb, minv, img, dt, track, slots) = a;
    let parallel = rayon::current_num_threads() > 1 && d.len() > 2 * CHUNK;
    match (track, parallel) {
        (true, false) => serial::<true, L>(d, nb, minv, law, img, dt),
        (false, false) => serial::<false, L>(d, nb, minv, law, img, dt),
        (true, true) => parallel_pass::<true, L>(d, nb, minv, law, img, dt, slots),
        (false, true) => parallel_pass::<false, L>(d, nb, minv, law, img, dt, slots),
    }
}

fn serial<const E: bool, L: PairLaw>(
    d: &mut Discs,
    nb: &mut Neighbors,
    minv: &[f64],
    law: &L,
    img: MinImage,
    dt: f64,
) -> PassEnergy {
    let n = d.len();
    let Discs {
        x,
        y,
        vx,
        vy,
        omega,
        r,
        material,
        fx,
        fy,
        torque,
        ..
    } = d;
    let c = Ctx {
        x,
        y,
        vx,
        vy,
        w: omega,
        r,
        mat: material,
        minv,
        start: &nb.start,
        nbr: &nb.nbr,
        g0: &nb.g0,
        law,
        img,
        dt,
    };
    let (us, mr) = (&mut nb.us, &mut nb.mr);
    let mut sc = Box::<Scratch>::default();
    let avx2 = has_avx2();
    let mut total = PassEnergy::default();
    let mut lo = 0;
    while lo < n {
        let hi = (lo + CHUNK).min(n);
        let mut e = PassEnergy::default();
        let (mut i, mut ax, mut ay, mut at) = (lo, 0.0, 0.0, 0.0);
        let mut gi = lo;
        let (mut p, pend) = (c.start[lo] as usize, c.start[hi] as usize);
        while p < pend {
            let q = BLOCK.min(pend - p);
            let (u, m) = (&mut us[p..p + q], &mut mr[p..p + q]);
            block::<E, L>(&c, p, &mut gi, u, m, &mut sc, &mut e, avx2);
            for k in 0..q {
                let pp = p + k;
                while at!(c.start, i + 1) as usize <= pp {
                    fx[i] += ax;
                    fy[i] += ay;
                    torque[i] += at;
                    (ax, ay, at) = (0.0, 0.0, 0.0);
                    i += 1;
                }
                // Pairs not in contact add zeros, exactly as the parallel gather does.
                let (f0, f1, f2, f3) = (sc.fx[k], sc.fy[k], sc.ti[k], sc.tj[k]);
                ax -= f0;
                ay -= f1;
                at += f2;
                let j = at!(c.nbr, pp) as usize;
                // SAFETY: j < n and pp < np (see `valid`).
                unsafe {
                    *fx.get_unchecked_mut(j) += f0;
                    *fy.get_unchecked_mut(j) += f1;
                    *torque.get_unchecked_mut(j) += f3;
                    *us.get_unchecked_mut(pp) = sc.us[k];
                }
            }
            p += q;
        }
        while i < hi {
            fx[i] += ax;
            fy[i] += ay;
            torque[i] += at;
            (ax, ay, at) = (0.0, 0.0, 0.0);
            i += 1;
        }
        total.add(&e);
        lo = hi;
    }
    total
}

/// Raw pointer that may be shared across threads; each chunk touches a disjoint range.
#[derive(Clone, Copy)]
struct SyncPtr(*mut f64);
unsafe impl Send for SyncPtr {}
unsafe impl Sync for SyncPtr {}

impl SyncPtr {
    /// # Safety
    /// `[a, a + len)` must be in bounds and not aliased by any other live reference.
    unsafe fn slice<'a>(self, a: usize, len: usize) -> &'a mut [f64] {
        std::slice::from_raw_parts_mut(self.0.add(a), len)
    }
}

fn parallel_pass<const E: bool, L: PairLaw>(
    d: &mut Discs,
    nb: &mut Neighbors,
    minv: &[f64],
    law: &L,
    img: MinImage,
    dt: f64,
    s: &mut Slots,
) -> PassEnergy {
    let n = d.len();
    let np = nb.nbr.len();
    for v in [&mut s.fx, &mut s.fy, &mut s.ti, &mut s.tj] {
        v.resize(np, 0.0);
    }
    let nchunks = n.div_ceil(CHUNK);
    {
        let c = Ctx {
            x: &d.x,
            y: &d.y,
            vx: &d.vx,
            vy: &d.vy,
            w: &d.omega,
            r: &d.r,
            mat: &d.material,
            minv,
            start: &nb.start,
            nbr: &nb.nbr,
            g0: &nb.g0,
            law,
            img,
            dt,
        };
        let ptr = [
            SyncPtr(nb.us.as_mut_ptr()),
            SyncPtr(nb.mr.as_mut_ptr()),
            SyncPtr(s.fx.as_mut_ptr()),
            SyncPtr(s.fy.as_mut_ptr()),
            SyncPtr(s.ti.as_mut_ptr()),
            SyncPtr(s.tj.as_mut_ptr()),
        ];
        let avx2 = has_avx2();
        (0..nchunks)
            .into_par_iter()
            .map(|ch| {
                let (lo, hi) = (ch * CHUNK, ((ch + 1) * CHUNK).min(n));
                let mut e = PassEnergy::default();
                let mut sc = Box::<Scratch>::default();
                let mut gi = lo;
                let (mut p, pend) = (c.start[lo] as usize, c.start[hi] as usize);
                while p < pend {
                    let q = BLOCK.min(pend - p);
                    // SAFETY: pairs [p, p + q) belong to this chunk only (chunks cover
                    // disjoint pair ranges) and all six arrays have length np ≥ p + q.
                    let (u, m, fx, fy, ti, tj) = unsafe {
                        (
                            ptr[0].slice(p, q),
                            ptr[1].slice(p, q),
                            ptr[2].slice(p, q),
                            ptr[3].slice(p, q),
                            ptr[4].slice(p, q),
                            ptr[5].slice(p, q),
                        )
                    };
                    block::<E, L>(&c, p, &mut gi, u, m, &mut sc, &mut e, avx2);
                    u.copy_from_slice(&sc.us[..q]);
                    fx.copy_from_slice(&sc.fx[..q]);
                    fy.copy_from_slice(&sc.fy[..q]);
                    ti.copy_from_slice(&sc.ti[..q]);
                    tj.copy_from_slice(&sc.tj[..q]);
                    p += q;
                }
                e
            })
            .collect_into_vec(&mut s.chunk_energy);
    }
    // Gather: partner-side slots in pair order, then the disc's own pairs.
    let (start, rstart, rpair) = (&nb.start, &nb.rstart, &nb.rpair);
    let (sfx, sfy, sti, stj) = (&s.fx, &s.fy, &s.ti, &s.tj);
    let out = [
        SyncPtr(d.fx.as_mut_ptr()),
        SyncPtr(d.fy.as_mut_ptr()),
        SyncPtr(d.torque.as_mut_ptr()),
    ];
    (0..nchunks).into_par_iter().for_each(|ch| {
        let (lo, hi) = (ch * CHUNK, ((ch + 1) * CHUNK).min(n));
        // SAFETY: discs [lo, hi) belong to this chunk only; arrays have length n ≥ hi.
        let (fxs, fys, ts) = unsafe {
            (
                out[0].slice(lo, hi - lo),
                out[1].slice(lo, hi - lo),
                out[2].slice(lo, hi - lo),
            )
        };
        for k in lo..hi {
            let (fxk, fyk, tk) = (&mut fxs[k - lo], &mut fys[k - lo], &mut ts[k - lo]);
            for &p in &rpair[rstart[k] as usize..rstart[k + 1] as usize] {
                let p = p as usize;
                *fxk += sfx[p];
                *fyk += sfy[p];
                *tk += stj[p];
            }
            let (mut ax, mut ay, mut at) = (0.0, 0.0, 0.0);
            for p in start[k] as usize..start[k + 1] as usize {
                ax -= sfx[p];
                ay -= sfy[p];
                at += sti[p];
            }
            *fxk += ax;
            *fyk += ay;
            *tk += at;
        }
    });
    let mut total = PassEnergy::default();
    for e in &s.chunk_energy {
        total.add(e);
    }
    total
}
