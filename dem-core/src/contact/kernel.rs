//! The blocked pair kernel of the disc–disc pass: a gather loop copies up to [`PAIR_BLOCK`] pairs'
//! data into small local arrays (disc by disc, so the first disc's data is read once), a
//! branch-free loop evaluates the law over the whole block (compiled twice: baseline and AVX2,
//! chosen at run time; only correctly rounded IEEE operations and no FMA contraction are used,
//! so both give the same bits), and the caller scatters the forces.
//!
//! With AVX2 the gather reads packed per-disc records ([`Packed`], 64 bytes: [x, y, v_x, v_y]
//! and [ω, r, 1/m, 0]) built once per pass by `pack`: a pair costs two aligned vector
//! loads per disc and one vector subtraction, and 4×4 transposes in registers fill the SoA
//! scratch of four pairs at once (`gather_aos`). The values are copies or the same single
//! IEEE operations as the scalar gather's, so the scratch holds the same bits.

use super::disc_disc::PassEnergy;
use super::linear4::{self, Linear4};
use super::{ContactLaws, HertzMindlin, LinearSpringDashpot, PairKin, PairOut};
#[cfg(target_arch = "x86_64")]
use crate::lanes::{pair_columns, transpose4};
use crate::lanes::{Packed, PAIR_BLOCK};
use crate::neighbors::MinImage;

/// Unchecked read; the force pass validates all indices once per call.
macro_rules! at {
    ($s:expr, $i:expr) => {
        // SAFETY: `disc_disc::valid` checked that every disc index in the list is < n and
        // every pair index is < the slot length.
        unsafe { *$s.get_unchecked($i) }
    };
}
pub(crate) use at;

/// A contact law as the force pass sees it: the uniform laws skip the material lookup and
/// have branch-free bodies.
pub trait PairLaw: Sync {
    /// Whether the law depends on the materials (table lookup).
    const MATERIAL: bool;
    /// Whether rolling resistance may apply.
    const ROLLING: bool;
    fn force<const E: bool>(&self, mi: u16, mj: u16, k: &PairKin, us: &mut f64) -> PairOut;
    /// Elastic energy of the tangential spring (history `us`) and of the rolling spring
    /// (moment `mr`) of a contact that has just opened, at the overlap of its last touching
    /// step, estimated as δ + v_n Δt from the current overlap (exact for the linear law, whose
    /// stiffnesses do not depend on δ).
    fn released(&self, mi: u16, mj: u16, k: &PairKin, us: f64, mr: f64) -> f64;
    /// The law's parameters when it is a uniform linear law (the four-lane kernel
    /// [`super::linear4`] then evaluates it without energies).
    fn linear4(&self) -> Option<Linear4> {
        None
    }
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
        self.0.force_cn::<E, f64>(k, self.1 * k.m_eff, us)
    }
    #[inline(always)]
    fn released(&self, _: u16, _: u16, _: &PairKin, us: f64, _: f64) -> f64 {
        0.5 * self.0.ks * us * us
    }
    fn linear4(&self) -> Option<Linear4> {
        Some(Linear4::new(&self.0, false, self.1))
    }
}

impl PairLaw for LinearRatio {
    const MATERIAL: bool = false;
    const ROLLING: bool = false;
    #[inline(always)]
    fn force<const E: bool>(&self, _: u16, _: u16, k: &PairKin, us: &mut f64) -> PairOut {
        self.0
            .force_cn::<E, f64>(k, 2.0 * self.1 * (k.m_eff * self.0.kn).sqrt(), us)
    }
    #[inline(always)]
    fn released(&self, _: u16, _: u16, _: &PairKin, us: f64, _: f64) -> f64 {
        0.5 * self.0.ks * us * us
    }
    fn linear4(&self) -> Option<Linear4> {
        Some(Linear4::new(&self.0, true, self.1))
    }
}

impl PairLaw for HertzMindlin {
    const MATERIAL: bool = false;
    const ROLLING: bool = false;
    #[inline(always)]
    fn force<const E: bool>(&self, _: u16, _: u16, k: &PairKin, us: &mut f64) -> PairOut {
        HertzMindlin::force::<E, f64>(self, k, us)
    }
    #[inline(always)]
    fn released(&self, _: u16, _: u16, k: &PairKin, us: f64, _: f64) -> f64 {
        let d = (k.delta + k.vn * k.dt).max(0.0);
        0.5 * self.kt(k.r_eff, d) * us * us
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
    fn released(&self, mi: u16, mj: u16, k: &PairKin, us: f64, mr: f64) -> f64 {
        let model = self.model(mi, mj);
        let d = (k.delta + k.vn * k.dt).max(0.0);
        let mut e = model.shear_energy(k.r_eff, d, us);
        if let Some(rr) = self.rolling(mi, mj) {
            let kr = rr.kr(model.kn(k.r_eff, d), k.r_eff);
            if kr > 0.0 {
                e += 0.5 * mr * mr / kr;
            }
        }
        e
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
pub(crate) struct Ctx<'a, L: PairLaw, H: PairHook> {
    pub(crate) x: &'a [f64],
    pub(crate) y: &'a [f64],
    pub(crate) vx: &'a [f64],
    pub(crate) vy: &'a [f64],
    pub(crate) w: &'a [f64],
    pub(crate) r: &'a [f64],
    pub(crate) mat: &'a [u16],
    pub(crate) minv: &'a [f64],
    pub(crate) start: &'a [u32],
    pub(crate) nbr: &'a [u32],
    /// The disc of each pair (see [`crate::neighbors::Neighbors::owner`]).
    pub(crate) owner: &'a [u32],
    pub(crate) g0: &'a [f64],
    pub(crate) law: &'a L,
    pub(crate) img: MinImage,
    pub(crate) dt: f64,
    /// The per-pair hook evaluated with the pairs (the parallel bonds of `bond::fused`), or
    /// none.
    pub(crate) hook: Option<&'a H>,
}

/// A per-pair hook of the pass: work evaluated with the listed pairs from the geometry the
/// pass has just computed, adding to the pairs' forces before the scatter. The parallel bonds
/// of a bonded lattice are evaluated this way (`bond::fused` implements it, see there): the
/// bond module depends on this one, not the other way round. The pass is generic over the hook
/// type (static dispatch, one instantiation per type), so the hook's bodies are inlined into
/// the kernels as if written there.
pub(crate) trait PairHook: Sync {
    /// Add the hook's outputs for pairs p0..p0 + q (q ≤ [`PAIR_BLOCK`]) of a block of the general
    /// path (after [`eval`]): `c` the block's gathered columns, `out` its force columns
    /// `[fx, fy, ti, tj]` (entries 0..q). `PER`: apply the minimum image `img`.
    fn block<const PER: bool>(
        &self,
        img: &MinImage,
        dt: f64,
        p0: usize,
        q: usize,
        c: &Cols,
        out: [&mut [f64; PAIR_BLOCK]; 4],
    );

    /// The four-lane form, called by the four-lane kernel ([`super::linear4`]) for pairs
    /// p..p + m (m ≤ 4; the other lanes are ignored): the pair geometry `g` = [d, r_i + r_j,
    /// n_x, n_y, a_i, a_j, v_t, ω_i, ω_j] in registers (see [`Cols`] for its terms), outputs
    /// added to the force columns `f = [fx, fy, ti, tj]`.
    ///
    /// # Safety
    /// The CPU must support AVX2; `p + m` must not exceed the pair count.
    #[cfg(target_arch = "x86_64")]
    unsafe fn four(
        &self,
        p: usize,
        m: usize,
        g: [crate::lanes::F64x4; 9],
        dt: f64,
        f: &mut [crate::lanes::F64x4; 4],
    );
}

/// The gathered columns of a block of pairs (the pass's [`Scratch`]) that a [`PairHook`]
/// reads: raw centre differences `dx`, `dy` (before the minimum image), radii, spins and
/// velocity differences.
pub(crate) struct Cols<'a> {
    pub dx: &'a [f64; PAIR_BLOCK],
    pub dy: &'a [f64; PAIR_BLOCK],
    pub ri: &'a [f64; PAIR_BLOCK],
    pub rj: &'a [f64; PAIR_BLOCK],
    pub wi: &'a [f64; PAIR_BLOCK],
    pub wj: &'a [f64; PAIR_BLOCK],
    pub dvx: &'a [f64; PAIR_BLOCK],
    pub dvy: &'a [f64; PAIR_BLOCK],
}

/// Working arrays of one block (inputs gathered per pair, outputs per pair).
#[derive(Clone)]
pub struct Scratch {
    dx: [f64; PAIR_BLOCK],
    dy: [f64; PAIR_BLOCK],
    reach: [f64; PAIR_BLOCK],
    /// Angular velocities of i and j (combined in [`eval`], vectorised).
    wi: [f64; PAIR_BLOCK],
    wj: [f64; PAIR_BLOCK],
    dvx: [f64; PAIR_BLOCK],
    dvy: [f64; PAIR_BLOCK],
    ms: [f64; PAIR_BLOCK],
    ri: [f64; PAIR_BLOCK],
    rj: [f64; PAIR_BLOCK],
    mi: [u16; PAIR_BLOCK],
    mj: [u16; PAIR_BLOCK],
    pub(crate) us: [f64; PAIR_BLOCK],
    pub(crate) mr: [f64; PAIR_BLOCK],
    pub(crate) fx: [f64; PAIR_BLOCK],
    pub(crate) fy: [f64; PAIR_BLOCK],
    pub(crate) ti: [f64; PAIR_BLOCK],
    pub(crate) tj: [f64; PAIR_BLOCK],
    pub(crate) es: [f64; PAIR_BLOCK],
    pub(crate) ef: [f64; PAIR_BLOCK],
    /// Dashpot force on j and dashpot torques on i, j (energy tracking only).
    pub(crate) dfx: [f64; PAIR_BLOCK],
    pub(crate) dfy: [f64; PAIR_BLOCK],
    pub(crate) dti: [f64; PAIR_BLOCK],
    pub(crate) dtj: [f64; PAIR_BLOCK],
}

impl std::fmt::Debug for Scratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Scratch")
    }
}

impl Default for Scratch {
    fn default() -> Scratch {
        let z = [0.0; PAIR_BLOCK];
        Scratch {
            dx: z,
            dy: z,
            reach: z,
            wi: z,
            wj: z,
            dvx: z,
            dvy: z,
            ms: z,
            ri: z,
            rj: z,
            mi: [0; PAIR_BLOCK],
            mj: [0; PAIR_BLOCK],
            us: z,
            mr: z,
            fx: z,
            fy: z,
            ti: z,
            tj: z,
            es: z,
            ef: z,
            dfx: z,
            dfy: z,
            dti: z,
            dtj: z,
        }
    }
}

/// Gather pairs p0..p0+q (q ≤ PAIR_BLOCK) into the scratch arrays, disc by disc (`gi` is the
/// disc owning pair p0 or an earlier disc; it is advanced). The rolling history is read from
/// `mr`, the slots of these q pairs (indexed from 0). The centre differences are stored as
/// they are: [`eval`] applies the minimum image (branch-free, vectorised); the reach
/// r_i + r_j is stored only with reference gaps (`G0`), else [`eval`] forms it.
#[inline(always)]
fn gather<L: PairLaw, H: PairHook, const G0: bool>(
    c: &Ctx<L, H>,
    p0: usize,
    q: usize,
    gi: &mut usize,
    mr: &[f64],
    s: &mut Scratch,
) {
    gather_from::<L, H, G0>(c, p0, q, 0, gi, mr, s)
}

/// [`gather`] of the block's entries k0..q only (pairs p0 + k0..p0 + q).
#[inline(always)]
fn gather_from<L: PairLaw, H: PairHook, const G0: bool>(
    c: &Ctx<L, H>,
    p0: usize,
    q: usize,
    k0: usize,
    gi: &mut usize,
    mr: &[f64],
    s: &mut Scratch,
) {
    assert!(q <= PAIR_BLOCK && mr.len() == q && k0 <= q);
    let (mut p, end) = (p0 + k0, p0 + q);
    let mut k = k0;
    while p < end {
        while at!(c.start, *gi + 1) as usize <= p {
            *gi += 1;
        }
        let i = *gi;
        let b = (at!(c.start, i + 1) as usize).min(end);
        let (xi, yi, ri, wi) = (at!(c.x, i), at!(c.y, i), at!(c.r, i), at!(c.w, i));
        let (vxi, vyi, mvi) = (at!(c.vx, i), at!(c.vy, i), at!(c.minv, i));
        let mati = if L::MATERIAL { at!(c.mat, i) } else { 0 };
        while p < b {
            let j = at!(c.nbr, p) as usize;
            s.dx[k] = at!(c.x, j) - xi;
            s.dy[k] = at!(c.y, j) - yi;
            let rj = at!(c.r, j);
            s.ri[k] = ri;
            s.rj[k] = rj;
            if G0 {
                s.reach[k] = ri + rj + at!(c.g0, p);
            }
            s.wi[k] = wi;
            s.wj[k] = at!(c.w, j);
            s.dvx[k] = at!(c.vx, j) - vxi;
            s.dvy[k] = at!(c.vy, j) - vyi;
            s.ms[k] = mvi + at!(c.minv, j);
            if L::ROLLING {
                s.mr[k] = at!(mr, k);
            }
            if L::MATERIAL {
                s.mi[k] = mati;
                s.mj[k] = at!(c.mat, j);
            }
            k += 1;
            p += 1;
        }
    }
    // Entries q..PAIR_BLOCK keep stale but finite data (or zeros) and are ignored.
}

/// One disc's force accumulator of the AVX2 scatter: [f_x, f_y, torque, unused] (32 bytes,
/// see [`super::owned`]).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(32))]
pub struct Acc4(pub(crate) [f64; 4]);

/// Pack discs `lo..lo + pk.len()` into `pk` and, with `clear`, set their accumulators `f` to
/// +0.0 (AVX2: four discs at a time, 4×4 transposes in registers; plain copies). (Without
/// `clear` the accumulators must be +0.0 already: the copy-out of the last pass clears them.)
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn pack<L: PairLaw, H: PairHook>(
    c: &Ctx<L, H>,
    lo: usize,
    pk: &mut [Packed],
    f: &mut [Acc4],
    clear: bool,
) {
    let src = PackSrc {
        x: c.x,
        y: c.y,
        vx: c.vx,
        vy: c.vy,
        w: c.w,
        r: c.r,
        minv: c.minv,
    };
    pack_records(&src, lo, pk, f, clear)
}

/// The disc arrays a packed record is made of (see [`Packed`]).
pub(crate) struct PackSrc<'a> {
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub vx: &'a [f64],
    pub vy: &'a [f64],
    pub w: &'a [f64],
    pub r: &'a [f64],
    pub minv: &'a [f64],
}

/// [`pack`] from any disc arrays: records `pk` of discs `lo..lo + pk.len()` of `c`; the
/// accumulators `f` (of the same length) are cleared when `clear` (else untouched, and may
/// be empty). Also used by the integrator, which packs each block of discs right after moving
/// them (see `Slots::packed_fresh`).
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn pack_records(
    c: &PackSrc,
    lo: usize,
    pk: &mut [Packed],
    f: &mut [Acc4],
    clear: bool,
) {
    use std::arch::x86_64::*;
    let n = pk.len();
    let len = lo + n;
    assert!(!clear || f.len() == n);
    assert!([c.x, c.y, c.vx, c.vy, c.w, c.r, c.minv]
        .iter()
        .all(|a| a.len() >= len));
    let (dst, zero) = (pk.as_mut_ptr(), _mm256_setzero_pd());
    let mut k = 0;
    while k + 4 <= n {
        let i = lo + k;
        // SAFETY: i + 4 <= lo + n <= the length of every source array (asserted); k + 4 <= n
        // = pk.len() (= f.len() when `clear`); the records are 64- and 32-byte aligned.
        let ld = |a: &[f64]| _mm256_loadu_pd(a.as_ptr().add(i));
        // Four arrays' values of discs i..i + 4 → the four discs' records.
        let a = transpose4([ld(c.x), ld(c.y), ld(c.vx), ld(c.vy)]);
        let b = transpose4([ld(c.w), ld(c.r), ld(c.minv), zero]);
        for l in 0..4 {
            let d = dst.add(k + l);
            _mm256_store_pd((*d).a.as_mut_ptr(), a[l]);
            _mm256_store_pd((*d).b.as_mut_ptr(), b[l]);
            if clear {
                // Volatile: else the compiler turns these stores into a call of `memset`,
                // a second pass over the accumulators.
                std::ptr::write_volatile(f.as_mut_ptr().add(k + l) as *mut __m256d, zero);
            }
        }
        k += 4;
    }
    for k in k..n {
        let i = lo + k;
        pk[k] = Packed {
            a: [at!(c.x, i), at!(c.y, i), at!(c.vx, i), at!(c.vy, i)],
            b: [at!(c.w, i), at!(c.r, i), at!(c.minv, i), 0.0],
        };
        if clear {
            f[k] = Acc4([0.0; 4]);
        }
    }
}

/// [`pack_records`] for discs whose records already hold their radius and inverse contact
/// mass (lanes 1 and 2 of `b`: the records of this step's disc–disc pass, for the same discs
/// and caches): only [x, y, v_x, v_y] and ω are written, so the integrator, which repacks
/// the discs it has just moved, does not stream the radius and mass arrays. The kept lanes
/// are the copies `pack_records` would write (and lane 3 stays 0): the same bits.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(crate) unsafe fn repack_moved(c: &PackSrc, pk: &mut [Packed]) {
    use std::arch::x86_64::*;
    let n = pk.len();
    assert!([c.x, c.y, c.vx, c.vy, c.w].iter().all(|a| a.len() >= n));
    let dst = pk.as_mut_ptr();
    let mut k = 0;
    while k + 4 <= n {
        // SAFETY: k + 4 <= n <= the length of every source array (asserted) and of pk; the
        // records are 64-byte aligned.
        let ld = |a: &[f64]| _mm256_loadu_pd(a.as_ptr().add(k));
        let a = transpose4([ld(c.x), ld(c.y), ld(c.vx), ld(c.vy)]);
        for (l, &al) in a.iter().enumerate() {
            let d = dst.add(k + l);
            _mm256_store_pd((*d).a.as_mut_ptr(), al);
            let w = _mm256_broadcast_sd(&*c.w.as_ptr().add(k + l));
            let b = _mm256_blend_pd::<0b0001>(_mm256_load_pd((*d).b.as_ptr()), w);
            _mm256_store_pd((*d).b.as_mut_ptr(), b);
        }
        k += 4;
    }
    for (k, r) in pk.iter_mut().enumerate().skip(k) {
        r.a = [at!(c.x, k), at!(c.y, k), at!(c.vx, k), at!(c.vy, k)];
        r.b[0] = at!(c.w, k);
    }
}

/// [`gather`] from the packed records (AVX2): for four pairs at a time, the two records of
/// each partner j and of its disc i are loaded as vectors, [x, y, v_x, v_y]_j − [..]_i is
/// one lane-wise subtraction (the same IEEE operations as the scalar x_j − x_i, ...), and
/// 4×4 transposes in registers turn the four per-pair rows into the SoA columns of the
/// scratch that [`eval`] vectorises over: d_x, d_y, Δv_x, Δv_y, ω_i, ω_j, r_i, r_j and
/// 1/m_i + 1/m_j (the same sum as the scalar gather's, in the same operand order), see
/// [`pair_columns`]. The discs i of the pairs are read from the owner array (no walk along
/// `start`, so no data-dependent branches). The q mod 4 last pairs take the scalar gather.
/// Every scratch entry thus has the bits the portable [`gather`] writes.
///
/// # Safety
/// The CPU must support AVX2; `pk` must hold the packed record of every disc (`pk.len() + 1
/// == c.start.len()`) and the list must be valid (see [`at`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn gather_aos<L: PairLaw, H: PairHook, const G0: bool>(
    c: &Ctx<L, H>,
    pk: &[Packed],
    p0: usize,
    q: usize,
    gi: &mut usize,
    mr: &[f64],
    s: &mut Scratch,
) {
    use std::arch::x86_64::*;
    assert!(q <= PAIR_BLOCK && mr.len() == q);
    let base = pk.as_ptr();
    assert!(c.owner.len() == c.nbr.len());
    let mut k = 0;
    while k + 4 <= q {
        let p = p0 + k;
        // The discs i and j of the four pairs (owners: no walk along `start`, no branches).
        let ii: [usize; 4] = std::array::from_fn(|l| at!(c.owner, p + l) as usize);
        let jj: [usize; 4] = std::array::from_fn(|l| at!(c.nbr, p + l) as usize);
        // SAFETY: every disc index comes from the valid list (< n = pk.len()).
        let ([dx, dy, dvx, dvy], [wi, ri, mi], [wj, rj, mj]) = pair_columns(base, ii, jj);
        // SAFETY (scratch stores): k + 4 <= q <= PAIR_BLOCK.
        let st = |a: &mut [f64; PAIR_BLOCK], v| _mm256_storeu_pd(a.as_mut_ptr().add(k), v);
        st(&mut s.dx, dx);
        st(&mut s.dvx, dvx);
        st(&mut s.dy, dy);
        st(&mut s.dvy, dvy);
        st(&mut s.wi, wi);
        st(&mut s.wj, wj);
        st(&mut s.ri, ri);
        st(&mut s.rj, rj);
        st(&mut s.ms, _mm256_add_pd(mi, mj));
        if G0 {
            // (r_i + r_j) + g₀, as the scalar gather. SAFETY: p + 4 <= p0 + q <= np.
            let g = _mm256_loadu_pd(c.g0.as_ptr().add(p));
            st(&mut s.reach, _mm256_add_pd(_mm256_add_pd(ri, rj), g));
        }
        for l in 0..4 {
            if L::ROLLING {
                s.mr[k + l] = at!(mr, k + l);
            }
            if L::MATERIAL {
                s.mi[k + l] = at!(c.mat, ii[l]);
                s.mj[k + l] = at!(c.mat, jj[l]);
            }
        }
        k += 4;
    }
    if k > 0 {
        // The disc of the last pair gathered (at most that of the next pair).
        *gi = at!(c.owner, p0 + k - 1) as usize;
    }
    if k < q {
        gather_from::<L, H, G0>(c, p0, q, k, gi, mr, s);
    }
}

/// Evaluate the law for all PAIR_BLOCK entries (branch-free, fixed trip count: vectorisable).
/// `E`: energies; `D` (only with `E`): the dashpot parts of the forces (for their per-disc sums).
/// `PER`: apply the minimum image `img` (else the box is not periodic and
/// [`MinImage::delta`] would be the identity); `G0`: the reach was gathered (else it is
/// r_i + r_j). `us`: the tangential spring histories of the block, updated in place.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // one index over many arrays: the vectorisable form
fn eval<const E: bool, const D: bool, const PER: bool, const G0: bool, L: PairLaw>(
    law: &L,
    dt: f64,
    img: &MinImage,
    s: &mut Scratch,
    us: &mut [f64; PAIR_BLOCK],
) {
    for k in 0..PAIR_BLOCK {
        let (dx, dy) = if PER {
            img.delta_select(s.dx[k], s.dy[k])
        } else {
            (s.dx[k], s.dy[k])
        };
        let d2 = dx * dx + dy * dy;
        let (ri, rj) = (s.ri[k], s.rj[k]);
        let rc = if G0 { s.reach[k] } else { ri + rj };
        let touch = d2 < rc * rc && rc > 0.0 && s.ms[k] > 0.0;
        let d = d2.sqrt();
        let inv = 1.0 / d;
        let (nx, ny) = (dx * inv, dy * inv);
        // Contact point midway in the geometric overlap r_i + r_j − d, on the line of
        // centres: arms a_i = r_i − h, a_j = r_j − h with a_i + a_j = d (see `super`).
        let h = 0.5 * (ri + rj - d);
        let (ai, aj) = (ri - h, rj - h);
        let (wi, wj) = (s.wi[k], s.wj[k]);
        let wr = (wi * ri + wj * rj) - h * (wi + wj);
        let rvx = s.dvx[k] + wr * ny;
        let rvy = s.dvy[k] - wr * nx;
        let kin = PairKin {
            delta: rc - d,
            vn: rvx * nx + rvy * ny,
            vt: rvy * nx - rvx * ny,
            m_eff: 1.0 / s.ms[k],
            r_eff: ri * rj / (ri + rj),
            dt,
        };
        let mut u = us[k];
        // A contact that opens drops its spring histories: their elastic energy is counted as
        // dissipated by friction (it is not returned to the discs).
        let released = if E && !touch {
            law.released(s.mi[k], s.mj[k], &kin, u, s.mr[k])
        } else {
            0.0
        };
        let o = law.force::<E>(s.mi[k], s.mj[k], &kin, &mut u);
        let mut m = s.mr[k];
        let roll = if L::ROLLING && touch {
            law.rolling(s.mi[k], s.mj[k], &kin, o.f_n, wi - wj, &mut m)
        } else {
            [0.0; 3]
        };
        us[k] = if touch { u } else { 0.0 };
        s.mr[k] = if touch { m } else { 0.0 };
        // t = (−n_y, n_x): F = F_n n + F_t t.
        let fx = o.f_n * nx - o.f_t * ny;
        let fy = o.f_n * ny + o.f_t * nx;
        let ti = -ai * o.f_t + roll[0];
        let tj = -aj * o.f_t - roll[0];
        s.fx[k] = if touch { fx } else { 0.0 };
        s.fy[k] = if touch { fy } else { 0.0 };
        s.ti[k] = if touch { ti } else { 0.0 };
        s.tj[k] = if touch { tj } else { 0.0 };
        if E {
            s.es[k] = if touch { o.e_strain + roll[2] } else { 0.0 };
            if D {
                let (dn, dt_) = (o.d_n, o.d_t);
                s.dfx[k] = if touch { dn * nx - dt_ * ny } else { 0.0 };
                s.dfy[k] = if touch { dn * ny + dt_ * nx } else { 0.0 };
                s.dti[k] = if touch { -ai * dt_ } else { 0.0 };
                s.dtj[k] = if touch { -aj * dt_ } else { 0.0 };
            }
            s.ef[k] = if touch { o.e_fric + roll[1] } else { released };
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
unsafe fn eval_avx2<const E: bool, const D: bool, const PER: bool, const G0: bool, L: PairLaw>(
    law: &L,
    dt: f64,
    img: &MinImage,
    s: &mut Scratch,
    us: &mut [f64; PAIR_BLOCK],
) {
    eval::<E, D, PER, G0, L>(law, dt, img, s, us)
}

/// Evaluate one gathered block with the best instruction set available.
#[inline(always)]
fn eval_best<
    const E: bool,
    const D: bool,
    const PER: bool,
    const G0: bool,
    L: PairLaw,
    H: PairHook,
>(
    c: &Ctx<L, H>,
    s: &mut Scratch,
    us: &mut [f64; PAIR_BLOCK],
    avx2: bool,
) {
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is true only when the CPU reports AVX2 (see `has_avx2`).
        unsafe { eval_avx2::<E, D, PER, G0, L>(c.law, c.dt, &c.img, s, us) };
        return;
    }
    let _ = avx2;
    eval::<E, D, PER, G0, L>(c.law, c.dt, &c.img, s, us)
}

/// Run the hook over pairs p0..p0 + q of a block after the law (`PairHook::block`, from the
/// gathered columns, adding to the block's outputs; compiled for AVX2 when there is one, as
/// [`eval`] is).
fn hook_block<L: PairLaw, H: PairHook>(
    c: &Ctx<L, H>,
    h: &H,
    p0: usize,
    q: usize,
    s: &mut Scratch,
    avx2: bool,
) {
    #[inline(always)]
    fn go<L: PairLaw, H: PairHook>(c: &Ctx<L, H>, h: &H, p0: usize, q: usize, s: &mut Scratch) {
        let cols = Cols {
            dx: &s.dx,
            dy: &s.dy,
            ri: &s.ri,
            rj: &s.rj,
            wi: &s.wi,
            wj: &s.wj,
            dvx: &s.dvx,
            dvy: &s.dvy,
        };
        let out = [&mut s.fx, &mut s.fy, &mut s.ti, &mut s.tj];
        if c.img.is_periodic() {
            h.block::<true>(&c.img, c.dt, p0, q, &cols, out);
        } else {
            h.block::<false>(&c.img, c.dt, p0, q, &cols, out);
        }
    }
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn go_avx2<L: PairLaw, H: PairHook>(
        c: &Ctx<L, H>,
        h: &H,
        p0: usize,
        q: usize,
        s: &mut Scratch,
    ) {
        go(c, h, p0, q, s)
    }
    #[cfg(target_arch = "x86_64")]
    if avx2 {
        // SAFETY: `avx2` is true only when the CPU reports AVX2 (see `has_avx2`).
        unsafe { go_avx2(c, h, p0, q, s) };
        return;
    }
    let _ = avx2;
    go(c, h, p0, q, s)
}

/// Evaluate pairs p0..p0+q: gather, evaluate, write the rolling history back and add the
/// energies in pair order. Forces stay in the scratch [..q]; the tangential histories `us`
/// (the q pairs' slots) are updated in place (a full block directly, a partial one through
/// the scratch). `pk`: the packed disc records of this pass ([`pack`]; then the AVX2 gather
/// [`gather_aos`] runs, which needs `avx2`) or empty (the portable gather).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn block<const E: bool, const D: bool, L: PairLaw, H: PairHook>(
    c: &Ctx<L, H>,
    pk: &[Packed],
    p0: usize,
    gi: &mut usize,
    us: &mut [f64],
    mr: &mut [f64],
    s: &mut Scratch,
    e: &mut PassEnergy,
    avx2: bool,
) {
    let q = us.len();
    let g0 = !c.g0.is_empty();
    #[cfg(target_arch = "x86_64")]
    if let (false, false, Some(lin)) = (pk.is_empty(), D, c.law.linear4()) {
        // A uniform linear law without dashpot sums: in registers.
        assert!(avx2);
        let per = c.img.is_periodic();
        // (`FUSED` separately compiled: scenes without fused bonds run the kernel without
        // the bond hook.)
        let fz = c.hook.is_some();
        macro_rules! go {
            ($($per:literal $ratio:literal $g0:literal $fz:literal),*) => {
                match (per, lin.ratio, g0, fz) {
                    $(($per, $ratio, $g0, $fz) => {
                        linear4::block::<L, H, $per, $ratio, E, $g0, $fz>(c, &lin, pk, p0, q, gi, us, s)
                    })*
                }
            };
        }
        // SAFETY: the CPU has AVX2 (`avx2`, see `has_avx2`); `pk` holds one record per disc
        // (asserted by the callee) and the list is valid.
        unsafe {
            go!(
                false false false false, false true false false, true false false false,
                true true false false, false false true false, false true true false,
                true false true false, true true true false, false false false true,
                false true false true, true false false true, true true false true,
                false false true true, false true true true, true false true true,
                true true true true
            )
        }
        if E {
            for k in 0..q {
                e.strain += s.es[k];
                e.fric += s.ef[k];
            }
        }
        return;
    }
    #[cfg(target_arch = "x86_64")]
    if !pk.is_empty() {
        assert!(avx2 && pk.len() + 1 == c.start.len());
        // SAFETY: the CPU has AVX2 (`avx2`, see `has_avx2`); `pk` holds one record per disc.
        unsafe {
            if g0 {
                gather_aos::<L, H, true>(c, pk, p0, q, gi, mr, s);
            } else {
                gather_aos::<L, H, false>(c, pk, p0, q, gi, mr, s);
            }
        }
    }
    if pk.is_empty() {
        if g0 {
            gather::<L, H, true>(c, p0, q, gi, mr, s);
        } else {
            gather::<L, H, false>(c, p0, q, gi, mr, s);
        }
    }
    let run = |s: &mut Scratch, u: &mut [f64; PAIR_BLOCK]| match (c.img.is_periodic(), g0) {
        (false, false) => eval_best::<E, D, false, false, L, H>(c, s, u, avx2),
        (true, false) => eval_best::<E, D, true, false, L, H>(c, s, u, avx2),
        (false, true) => eval_best::<E, D, false, true, L, H>(c, s, u, avx2),
        (true, true) => eval_best::<E, D, true, true, L, H>(c, s, u, avx2),
    };
    match <&mut [f64; PAIR_BLOCK]>::try_from(&mut *us) {
        Ok(u) => run(s, u),
        Err(_) => {
            // Entries q..PAIR_BLOCK of the history keep stale but finite data and are ignored.
            let mut u = s.us;
            u[..q].copy_from_slice(us);
            run(s, &mut u);
            us.copy_from_slice(&u[..q]);
            s.us = u;
        }
    }
    if L::ROLLING {
        mr.copy_from_slice(&s.mr[..q]);
    }
    if let Some(h) = c.hook {
        hook_block(c, h, p0, q, s, avx2);
    }
    if E {
        for k in 0..q {
            e.strain += s.es[k];
            e.fric += s.ef[k];
        }
    }
}
