//! The disc–disc pass by disc ownership: discs (and with them their pairs of the half list,
//! `i < j`) are split into contiguous ranges, one per worker; each worker computes its pairs
//! block by block and scatters their forces directly into the discs of its own range, in list
//! order, exactly as the one-thread pass does. A disc some of whose partner-side pairs belong
//! to an earlier range ("shared" disc, a thin layer at each range boundary: discs are sorted
//! in space) must receive those contributions first, so all its partner-side forces go to
//! per-pair slots and its own-pair sum to a per-disc slot; a second, short pass adds them in
//! list order (partner-side slots in increasing pair order, then the own sum). Every disc thus
//! sees the same sequence of floating-point additions for any split, and one range with no
//! shared discs *is* the one-thread pass: results are bit-identical for any thread count.
//!
//! Energies are summed in pair order per fixed chunk of [`CHUNK`] discs (ranges start at chunk
//! boundaries when energy is tracked) and the chunk sums added in chunk order.
//!
//! With AVX2 the pass reads the discs through packed per-disc records ([`Packed`], built once
//! per pass, see [`super::kernel`]) and scatters into per-disc accumulators [`Acc4`]
//! [f_x, f_y, torque, ·] (32 bytes): one vector addition per pair for j and a vector running
//! sum for i, instead of three scalar read-modify-writes and three scalar sums. Lane by lane
//! these are the additions of the portable scatter, in the same order; the accumulators start
//! at +0.0 like the force arrays on the portable path (which `pass` clears), so copying them
//! into `fx, fy, tq` at the end of each range gives the same bits (signed zeros included). Shared discs are untouched in the
//! accumulators (+0.0 copied) and get their sums in the second pass as before.

use super::disc_disc::{PassEnergy, Slots, CHUNK};
use super::kernel::{at, block, pack, Acc4, Ctx, PairHook, PairLaw, Scratch};
use crate::lanes::{has_avx2, Packed, PAIR_BLOCK};
use crate::team::SyncPtr;

/// The parts of the neighbour list the split needs.
pub(crate) struct ListRef<'a> {
    pub builds: u64,
    pub start: &'a [u32],
    pub nbr: &'a [u32],
    pub rstart: &'a [u32],
    pub rpair: &'a [u32],
}

/// The split of the discs into ranges for one list and thread count.
#[derive(Clone, Debug, Default)]
pub struct Plan {
    /// (list build, discs, pairs, ranges wanted, energy tracked) the plan was made for.
    key: (u64, usize, usize, usize, bool),
    /// Range r holds discs `bounds[r]..bounds[r + 1]`.
    bounds: Vec<usize>,
    /// Whether disc k is shared (gets its forces through slots).
    shared: Vec<bool>,
    /// The shared discs, increasing.
    shared_list: Vec<u32>,
    /// Dirty pairs before pair p (length pairs + 1). A disc is clean when it is not shared
    /// and none of its pairs has a shared partner; a block of pairs that reaches only clean
    /// discs (see [`Plan::plain`]) is scattered by the plain one-range code, which makes the
    /// same additions without the per-pair shared tests.
    dirty: Vec<u32>,
}

impl Plan {
    /// Whether the block of pairs `[p, p + q)` reaches only clean discs: its pairs' discs,
    /// discs without pairs before them, and the disc of pair p − 1 (still summing when the
    /// block starts).
    #[inline]
    fn plain(dirty: &[u32], p: usize, q: usize) -> bool {
        dirty[p + q] == dirty[p.saturating_sub(1)]
    }

    /// (plain, other) blocks of [`PAIR_BLOCK`] pairs counted from pair 0 (tests: both kinds run).
    #[cfg(test)]
    fn block_kinds(&self) -> (usize, usize) {
        let np = self.dirty.len().saturating_sub(1);
        let plain = (0..np)
            .step_by(PAIR_BLOCK)
            .filter(|&p| Plan::plain(&self.dirty, p, PAIR_BLOCK.min(np - p)))
            .count();
        (plain, np.div_ceil(PAIR_BLOCK) - plain)
    }

    /// Make (or keep) the plan for `ranges` ranges over the list `nb` of `n` discs.
    fn update(&mut self, nb: &ListRef, n: usize, ranges: usize, track: bool) {
        let np = nb.nbr.len();
        let key = (nb.builds, n, np, ranges, track);
        if self.key == key && self.bounds.len() == ranges + 1 {
            return;
        }
        self.key = key;
        self.bounds.clear();
        self.bounds.push(0);
        for r in 1..ranges {
            // Balance the pairs (the work) between the ranges.
            let want = (np as u128 * r as u128 / ranges as u128) as u32;
            let mut k = nb.start.partition_point(|&s| s < want).min(n);
            if track {
                k = (k + CHUNK / 2) / CHUNK * CHUNK;
            }
            let k = k.clamp(*self.bounds.last().unwrap_or(&0), n);
            self.bounds.push(k);
        }
        self.bounds.push(n);
        self.shared.clear();
        self.shared.resize(n, false);
        for r in 0..ranges {
            let (lo, hi) = (self.bounds[r], self.bounds[r + 1]);
            for i in lo..hi {
                for p in nb.start[i] as usize..nb.start[i + 1] as usize {
                    let j = nb.nbr[p] as usize;
                    if j >= hi {
                        self.shared[j] = true;
                    }
                }
            }
        }
        self.shared_list = (0..n as u32).filter(|&k| self.shared[k as usize]).collect();
        // Pair p is dirty when its disc is not clean, or a disc with no pairs between the
        // previous pair's disc and its own is not (that disc is flushed at pair p).
        self.dirty.clear();
        self.dirty.push(0);
        let mut count = 0;
        for r in 0..ranges {
            let (lo, hi) = (self.bounds[r], self.bounds[r + 1]);
            let mut gap_dirty = false;
            for i in lo..hi {
                let (a, b) = (nb.start[i] as usize, nb.start[i + 1] as usize);
                let dirty = self.shared[i] || nb.nbr[a..b].iter().any(|&j| self.shared[j as usize]);
                for p in a..b {
                    count += u32::from(dirty || (p == a && gap_dirty));
                    self.dirty.push(count);
                }
                gap_dirty = (a == b) && (gap_dirty || dirty);
            }
        }
    }
}

/// Mutable per-disc arrays of one range (indexed from the range's first disc).
struct DiscSide<'a> {
    fx: &'a mut [f64],
    fy: &'a mut [f64],
    tq: &'a mut [f64],
    /// Force accumulators [f_x, f_y, torque, ·] of the AVX2 scatter (empty on the portable
    /// path), +0.0 at the start of the pass and copied to `fx, fy, tq` at the end of the range.
    f: &'a mut [Acc4],
    /// Dashpot sums (energy tracking only; else empty).
    dfx: &'a mut [f64],
    dfy: &'a mut [f64],
    dtq: &'a mut [f64],
    /// Own-pair sums of shared discs: fx, fy, torque and (E) the dashpot parts.
    own: [&'a mut [f64]; 6],
}

/// Mutable per-pair arrays of one range (indexed from the range's first pair).
struct PairSide<'a> {
    us: &'a mut [f64],
    mr: &'a mut [f64],
    /// Partner-side slots for pairs whose partner is shared: fx, fy, tj and (D) dashpot parts.
    slot: [&'a mut [f64]; 6],
}

/// The scatter of one range: its outputs and its running state.
struct Sink<'a, 'b> {
    /// The range's first disc and first pair.
    lo: usize,
    p0: usize,
    shared: &'b [bool],
    /// The disc whose own pairs are being summed, and the sums: `a` = (f_x, f_y, torque, ·)
    /// (the forces on i are minus those on j), `b` = the dashpot parts (only with `D`).
    i: usize,
    a: [f64; 4],
    b: [f64; 3],
    ds: DiscSide<'a>,
    slot: [&'a mut [f64]; 6],
}

impl Sink<'_, '_> {
    #[inline(always)]
    fn is_shared<const SPLIT: bool>(&self, k: usize) -> bool {
        SPLIT && at!(self.shared, k)
    }

    /// Disc i has all its own pairs: add their sums to it (or, shared, keep them for the
    /// second pass) and go on to disc i + 1. `aos`: the forces go to the accumulators `f`
    /// (lane-wise, the same additions as to `fx, fy, tq`).
    #[inline(always)]
    fn flush<const D: bool, const SPLIT: bool>(&mut self, aos: bool) {
        let li = self.i - self.lo;
        let shared = self.is_shared::<SPLIT>(self.i);
        let (a, b, ds) = (self.a, self.b, &mut self.ds);
        if shared {
            ds.own[0][li] = a[0];
            ds.own[1][li] = a[1];
            ds.own[2][li] = a[2];
            if D {
                ds.own[3][li] = b[0];
                ds.own[4][li] = b[1];
                ds.own[5][li] = b[2];
            }
        } else {
            if aos {
                let f = &mut ds.f[li].0;
                for l in 0..4 {
                    f[l] += a[l];
                }
            } else {
                ds.fx[li] += a[0];
                ds.fy[li] += a[1];
                ds.tq[li] += a[2];
            }
            if D {
                ds.dfx[li] += b[0];
                ds.dfy[li] += b[1];
                ds.dtq[li] += b[2];
            }
        }
        self.a = [0.0; 4];
        self.b = [0.0; 3];
        self.i += 1;
    }

    /// Scatter the forces of pairs p..p+q (scratch entries 0..q) in list order (portable).
    #[inline(always)]
    fn scatter<const D: bool, const SPLIT: bool, L: PairLaw, H: PairHook>(
        &mut self,
        c: &Ctx<L, H>,
        p: usize,
        q: usize,
        sc: &Scratch,
    ) {
        let (mut ax, mut ay, mut at) = (self.a[0], self.a[1], self.a[2]);
        let (mut bx, mut by, mut bt) = (self.b[0], self.b[1], self.b[2]);
        for k in 0..q {
            let pp = p + k;
            while at!(c.start, self.i + 1) as usize <= pp {
                self.a = [ax, ay, at, 0.0];
                self.b = [bx, by, bt];
                self.flush::<D, SPLIT>(false);
                (ax, ay, at) = (0.0, 0.0, 0.0);
                (bx, by, bt) = (0.0, 0.0, 0.0);
            }
            // Pairs not in contact add zeros, as every other path does.
            let (f0, f1, f2, f3) = (sc.fx[k], sc.fy[k], sc.ti[k], sc.tj[k]);
            ax -= f0;
            ay -= f1;
            at += f2;
            let j = at!(c.nbr, pp) as usize;
            let lp = pp - self.p0;
            if D {
                bx -= sc.dfx[k];
                by -= sc.dfy[k];
                bt += sc.dti[k];
            }
            if SPLIT && at!(self.shared, j) {
                let [sfx, sfy, stj, sdx, sdy, sdt] = &mut self.slot;
                sfx[lp] = f0;
                sfy[lp] = f1;
                stj[lp] = f3;
                if D {
                    sdx[lp] = sc.dfx[k];
                    sdy[lp] = sc.dfy[k];
                    sdt[lp] = sc.dtj[k];
                }
            } else {
                let lj = j - self.lo;
                let ds = &mut self.ds;
                // SAFETY: j is not shared (tested, or the block reaches clean discs only,
                // `Plan::dirty`), so lo <= i < j < hi (see `Plan::update`; one range:
                // lo = 0, hi = n), and the disc slices have length hi - lo.
                unsafe {
                    *ds.fx.get_unchecked_mut(lj) += f0;
                    *ds.fy.get_unchecked_mut(lj) += f1;
                    *ds.tq.get_unchecked_mut(lj) += f3;
                }
                if D {
                    ds.dfx[lj] += sc.dfx[k];
                    ds.dfy[lj] += sc.dfy[k];
                    ds.dtq[lj] += sc.dtj[k];
                }
            }
        }
        self.a = [ax, ay, at, 0.0];
        self.b = [bx, by, bt];
    }

    /// [`Sink::scatter`] into the force accumulators `f` (AVX2). Four pairs' forces are
    /// transposed in registers into the records (f_x, f_y, t_j, 0) for j, added to `f[j]`
    /// with one vector addition, and (f_x, f_y, −t_i, 0) for i, subtracted from the running
    /// sum (ax − f_x, ay − f_y, at − (−t_i) = at + t_i exactly, lane 3 unused): per lane the
    /// same IEEE additions in the same order as the portable scatter.
    ///
    /// # Safety
    /// The CPU must support AVX2; `f` must have the length of the range and the list must be
    /// valid (see [`at`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn scatter_aos<const D: bool, const SPLIT: bool, L: PairLaw, H: PairHook>(
        &mut self,
        c: &Ctx<L, H>,
        p: usize,
        q: usize,
        sc: &Scratch,
    ) {
        use std::arch::x86_64::*;
        assert!(q <= PAIR_BLOCK);
        let lo = self.lo;
        // Accumulator of disc k at fb + 4 k (k in lo..hi; only such addresses are accessed).
        let fb = (self.ds.f.as_mut_ptr() as *mut f64).wrapping_sub(4 * lo);
        let mut i = self.i;
        let mut next = at!(c.start, i + 1) as usize;
        let mut acc = _mm256_loadu_pd(self.a.as_ptr());
        let zero = _mm256_setzero_pd();
        let sign = _mm256_set1_pd(-0.0);
        // One pair: finish the discs before it, then add its forces.
        // A macro, not a closure: expanded at each call site, so always inlined.
        macro_rules! pair {
            ($k:expr, $vi:expr, $vj:expr) => {{
                let (k, vi, vj): (usize, __m256d, __m256d) = ($k, $vi, $vj);
                let pp = p + k;
                while pp >= next {
                    if D || (SPLIT && at!(self.shared, i)) {
                        self.i = i;
                        _mm256_storeu_pd(self.a.as_mut_ptr(), acc);
                        self.flush::<D, SPLIT>(true);
                    } else {
                        // The flush's f[i] += a, as one vector addition. SAFETY: lo <= i < hi
                        // (the range's discs), f[i - lo] is in bounds and 32-byte aligned.
                        let fi = fb.add(4 * i);
                        _mm256_store_pd(fi, _mm256_add_pd(_mm256_load_pd(fi), acc));
                    }
                    acc = zero;
                    i += 1;
                    next = at!(c.start, i + 1) as usize;
                }
                acc = _mm256_sub_pd(acc, vi);
                if D {
                    self.b[0] -= sc.dfx[k];
                    self.b[1] -= sc.dfy[k];
                    self.b[2] += sc.dti[k];
                }
                let j = at!(c.nbr, pp) as usize;
                if SPLIT && at!(self.shared, j) {
                    let lp = pp - self.p0;
                    let [sfx, sfy, stj, sdx, sdy, sdt] = &mut self.slot;
                    sfx[lp] = sc.fx[k];
                    sfy[lp] = sc.fy[k];
                    stj[lp] = sc.tj[k];
                    if D {
                        sdx[lp] = sc.dfx[k];
                        sdy[lp] = sc.dfy[k];
                        sdt[lp] = sc.dtj[k];
                    }
                } else {
                    // SAFETY: j is not shared (tested, or the block reaches clean discs only,
                    // `Plan::dirty`), so lo <= i < j < hi (see `Plan::update`; one range:
                    // lo = 0, hi = n): f[j - lo] is in bounds and 32-byte aligned.
                    let fj = fb.add(4 * j);
                    _mm256_store_pd(fj, _mm256_add_pd(_mm256_load_pd(fj), vj));
                    if D {
                        let (ds, lj) = (&mut self.ds, j - lo);
                        ds.dfx[lj] += sc.dfx[k];
                        ds.dfy[lj] += sc.dfy[k];
                        ds.dtq[lj] += sc.dtj[k];
                    }
                }
            }};
        }
        let mut g = 0;
        while g < q {
            // SAFETY: g + 4 <= PAIR_BLOCK (a multiple of 4); entries q..PAIR_BLOCK are stale but
            // finite, and not used.
            let ld = |a: &[f64; PAIR_BLOCK]| _mm256_loadu_pd(a.as_ptr().add(g));
            let (fx, fy) = (ld(&sc.fx), ld(&sc.fy));
            let nti = _mm256_xor_pd(ld(&sc.ti), sign);
            let tj = ld(&sc.tj);
            let xy_lo = _mm256_unpacklo_pd(fx, fy); // fx0 fy0 fx2 fy2
            let xy_hi = _mm256_unpackhi_pd(fx, fy); // fx1 fy1 fx3 fy3
            let ti_lo = _mm256_unpacklo_pd(nti, zero); // -ti0 0 -ti2 0
            let ti_hi = _mm256_unpackhi_pd(nti, zero);
            let tj_lo = _mm256_unpacklo_pd(tj, zero);
            let tj_hi = _mm256_unpackhi_pd(tj, zero);
            let vi = [
                _mm256_permute2f128_pd(xy_lo, ti_lo, 0x20),
                _mm256_permute2f128_pd(xy_hi, ti_hi, 0x20),
                _mm256_permute2f128_pd(xy_lo, ti_lo, 0x31),
                _mm256_permute2f128_pd(xy_hi, ti_hi, 0x31),
            ];
            let vj = [
                _mm256_permute2f128_pd(xy_lo, tj_lo, 0x20),
                _mm256_permute2f128_pd(xy_hi, tj_hi, 0x20),
                _mm256_permute2f128_pd(xy_lo, tj_lo, 0x31),
                _mm256_permute2f128_pd(xy_hi, tj_hi, 0x31),
            ];
            if g + 4 <= q {
                pair!(g, vi[0], vj[0]);
                pair!(g + 1, vi[1], vj[1]);
                pair!(g + 2, vi[2], vj[2]);
                pair!(g + 3, vi[3], vj[3]);
            } else {
                for l in 0..q - g {
                    pair!(g + l, vi[l], vj[l]);
                }
            }
            g += 4;
        }
        self.i = i;
        _mm256_storeu_pd(self.a.as_mut_ptr(), acc);
    }
}

/// One range of discs `[lo, hi)`: compute its pairs and scatter (see the module doc).
/// `SPLIT`: there may be shared discs (else the plain one-thread pass). `E`: energies are
/// tracked; `D` (only with `E`): the dashpot forces are summed per disc as well (see
/// [`super::disc_disc::compute`]: not needed when no law has a dashpot). `pk`: the packed
/// disc records (then `ds.f` has the range's accumulators and the AVX2 gather and scatter
/// run, which need `avx2`) or empty (portable gather and scatter).
#[allow(clippy::too_many_arguments)]
fn range_pass<const E: bool, const D: bool, const SPLIT: bool, L: PairLaw, H: PairHook>(
    c: &Ctx<L, H>,
    pk: &[Packed],
    shared: &[bool],
    (lo, hi): (usize, usize),
    dirty: &[u32],
    ds: DiscSide,
    ps: PairSide,
    energy: &mut [PassEnergy],
    sc: &mut Scratch,
    avx2: bool,
) {
    let aos = !pk.is_empty();
    assert!(!aos || (avx2 && ds.f.len() == hi - lo));
    let p0 = at!(c.start, lo) as usize;
    let PairSide { us, mr, slot } = ps;
    let mut sink = Sink {
        lo,
        p0,
        shared,
        i: lo,
        a: [0.0; 4],
        b: [0.0; 3],
        ds,
        slot,
    };
    let mut gi = lo;
    let mut clo = lo;
    while clo < hi {
        // Energy chunk [clo, chi): a fixed CHUNK grid.
        let chi = ((clo / CHUNK + 1) * CHUNK).min(hi);
        let mut e = PassEnergy::default();
        let (mut p, pend) = (at!(c.start, clo) as usize, at!(c.start, chi) as usize);
        while p < pend {
            let q = PAIR_BLOCK.min(pend - p);
            let (u, m) = (&mut us[p - p0..p - p0 + q], &mut mr[p - p0..p - p0 + q]);
            block::<E, D, L, H>(c, pk, p, &mut gi, u, m, sc, &mut e, avx2);
            // In a block of clean discs the split's tests are all false (see `Plan::dirty`).
            let plain = !SPLIT || Plan::plain(dirty, p, q);
            #[cfg(target_arch = "x86_64")]
            if aos {
                // SAFETY: `aos` implies AVX2 (asserted above) and `f` of the range's length.
                unsafe {
                    if plain {
                        sink.scatter_aos::<D, false, L, H>(c, p, q, sc)
                    } else {
                        sink.scatter_aos::<D, SPLIT, L, H>(c, p, q, sc)
                    }
                };
            }
            if !aos {
                if plain {
                    sink.scatter::<D, false, L, H>(c, p, q, sc);
                } else {
                    sink.scatter::<D, SPLIT, L, H>(c, p, q, sc);
                }
            }
            p += q;
        }
        while sink.i < chi {
            sink.flush::<D, SPLIT>(aos);
        }
        if E {
            energy[clo / CHUNK - lo / CHUNK] = e;
        }
        clo = chi;
    }
    #[cfg(target_arch = "x86_64")]
    if aos {
        let ds = &mut sink.ds;
        // SAFETY: `aos` implies AVX2 (asserted above).
        unsafe { copy_out(ds.f, ds.fx, ds.fy, ds.tq) };
    }
}

/// Copy the accumulators `acc` to `fx, fy, tq` (AVX2: four discs at a time,
/// transposed in registers) and clear them to +0.0 for the next pass (see
/// [`Slots::acc_zero`](super::disc_disc::Slots)). They started at +0.0, as `fx, fy, tq` do
/// on the portable path (cleared by [`pass`]), and received the same additions: copying them
/// gives the same bits.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn copy_out(acc: &mut [Acc4], fx: &mut [f64], fy: &mut [f64], tq: &mut [f64]) {
    use std::arch::x86_64::*;
    let n = acc.len();
    assert!(fx.len() == n && fy.len() == n && tq.len() == n);
    let f = acc.as_mut_ptr() as *mut f64;
    let zero = _mm256_setzero_pd();
    let mut k = 0;
    while k + 4 <= n {
        // SAFETY: k + 4 <= n: the four records and the stores are in bounds; the records
        // are 32-byte aligned.
        let r = |l: usize| _mm256_load_pd(f.add(4 * (k + l)));
        let [cx, cy, ct, _] = crate::lanes::transpose4([r(0), r(1), r(2), r(3)]);
        _mm256_storeu_pd(fx.as_mut_ptr().add(k), cx);
        _mm256_storeu_pd(fy.as_mut_ptr().add(k), cy);
        _mm256_storeu_pd(tq.as_mut_ptr().add(k), ct);
        // Clear the records for the next pass while their lines are in cache (volatile:
        // else the compiler may move the stores into a separate `memset` pass).
        for l in 0..4 {
            std::ptr::write_volatile(f.add(4 * (k + l)) as *mut __m256d, zero);
        }
        k += 4;
    }
    for k in k..n {
        let a = acc[k].0;
        fx[k] = a[0];
        fy[k] = a[1];
        tq[k] = a[2];
        acc[k] = Acc4::default();
    }
}

/// Run `f(r)` for every range r in 0..ranges, in parallel, on the step's team
/// ([`crate::team`]): with one range per worker thread (the usual split) range r runs on
/// worker r at every call, so a worker meets the same discs and pairs in its own caches at
/// every step (measured with `rayon::broadcast`, which also fixes the worker: +6 % on the
/// dense lattice on two threads, 10 alternating rounds).
fn for_each_range(ranges: usize, f: impl Fn(usize) + Sync) {
    crate::team::run(ranges, &f);
}

thread_local! {
    /// One block scratch per worker thread, allocated once.
    static SCRATCH: std::cell::RefCell<Box<Scratch>> = std::cell::RefCell::new(Box::default());
}

/// The disc arrays the pass writes (length n) and the per-disc dashpot sums (length n when
/// `D`, else unused).
pub(crate) struct Outs<'a> {
    pub fx: &'a mut [f64],
    pub fy: &'a mut [f64],
    pub tq: &'a mut [f64],
    pub dash: [&'a mut [f64]; 3],
}

/// Run the pass over `ranges` ranges (1: the one-thread pass, no rayon). `c.start`, `c.nbr`
/// are those of `nb`; `us`, `mr` its history arrays. Returns the energies. `E`, `D`: see
/// [`range_pass`]. The forces `outs.fx, fy, tq` are replaced (the portable path clears them
/// first; the AVX2 path copies its accumulators, cleared by `pack`, into every disc). (Kept out of line: inlined into its caller it compiles to slower code.)
#[inline(never)]
pub(crate) fn pass<const E: bool, const D: bool, L: PairLaw, H: PairHook>(
    c: &Ctx<L, H>,
    us: &mut [f64],
    mr: &mut [f64],
    nb: &ListRef,
    outs: Outs,
    s: &mut Slots,
    ranges: usize,
) -> PassEnergy {
    let n = c.start.len() - 1;
    let np = c.nbr.len();
    let nchunks = n.div_ceil(CHUNK);
    s.chunk_energy.clear();
    s.chunk_energy.resize(nchunks, PassEnergy::default());
    let avx2 = has_avx2();
    // The packed gather and the accumulator scatter (AVX2; see `lanes::Packed`).
    let aos = cfg!(target_arch = "x86_64") && avx2 && !s.portable && n > 0;
    // Every record is written below (packed by the integrator or here).
    s.packed_current = aos;
    // Records written by the last step's integrator (valid for this pass only: the pipeline
    // clears the flag after it).
    let fresh = aos && s.packed_fresh && s.packed.len() == n;
    #[cfg(target_arch = "x86_64")]
    if aos {
        s.packed.resize(n, Packed::default());
        s.acc.resize(n, Acc4::default());
        // Cleared by the last pass's copy-out (the usual case), else here by `pack`.
        let clear = !s.acc_zero;
        s.acc_zero = false;
        // SAFETY (`pack`): `aos` implies AVX2.
        if fresh {
            // The integrator packed the records (see `Slots::packed_fresh`).
            if clear {
                s.acc.fill(Acc4::default());
            }
        } else if ranges <= 1 {
            unsafe { pack(c, 0, &mut s.packed, &mut s.acc, clear) };
        } else {
            // Each range packs its own discs, on the worker that will then mostly read them
            // (the split's ranges, in the same parallel loop shape as the force pass).
            s.plan.update(nb, n, ranges, E);
            let b = &s.plan.bounds;
            let (pp, fp) = (SyncPtr::of(&mut s.packed), SyncPtr::of(&mut s.acc));
            for_each_range(ranges, |r| {
                let (lo, hi) = (b[r], b[r + 1]);
                // SAFETY: the ranges [lo, hi) are disjoint and within the n records of
                // `packed` and `acc` (resized above); `pack` needs AVX2 (`aos`).
                unsafe { pack(c, lo, pp.slice(lo, hi - lo), fp.slice(lo, hi - lo), clear) }
            });
        }
    }
    let (pk, acc): (&[Packed], &mut [Acc4]) = if aos {
        (&s.packed, &mut s.acc)
    } else {
        (&[], &mut [])
    };
    let Outs { fx, fy, tq, dash } = outs;
    if !aos {
        for v in [&mut *fx, &mut *fy, &mut *tq] {
            v.fill(0.0);
        }
    }
    let [dfx, dfy, dtq] = dash;
    if ranges <= 1 || n == 0 {
        let ds = DiscSide {
            fx,
            fy,
            tq,
            f: acc,
            dfx,
            dfy,
            dtq,
            own: Default::default(),
        };
        let ps = PairSide {
            us,
            mr,
            slot: Default::default(),
        };
        let sc = &mut *s.scratch;
        range_pass::<E, D, false, L, H>(
            c,
            pk,
            &[],
            (0, n),
            &[],
            ds,
            ps,
            &mut s.chunk_energy,
            sc,
            avx2,
        );
    } else {
        let Slots {
            plan,
            fx: sfx,
            fy: sfy,
            tj: stj,
            dfx: sdx,
            dfy: sdy,
            dtj: sdt,
            own,
            chunk_energy,
            ..
        } = s;
        plan.update(nb, n, ranges, E);
        let (ns, no) = if D { (np, n) } else { (0, 0) };
        for (k, v) in [
            &mut *sfx, &mut *sfy, &mut *stj, &mut *sdx, &mut *sdy, &mut *sdt,
        ]
        .into_iter()
        .enumerate()
        {
            v.resize(if k < 3 { np } else { ns }, 0.0);
        }
        for (k, v) in own.iter_mut().enumerate() {
            v.resize(if k < 3 { n } else { no }, 0.0);
        }
        let dp = [SyncPtr::of(fx), SyncPtr::of(fy), SyncPtr::of(tq)];
        let ap = SyncPtr::of(acc);
        let ddp = [SyncPtr::of(dfx), SyncPtr::of(dfy), SyncPtr::of(dtq)];
        let op = own.each_mut().map(|v| SyncPtr::of(v));
        let pp = [SyncPtr::of(us), SyncPtr::of(mr)];
        let sp = [
            &mut *sfx, &mut *sfy, &mut *stj, &mut *sdx, &mut *sdy, &mut *sdt,
        ]
        .map(|v| SyncPtr::of(v));
        let ep = chunk_energy.as_mut_ptr() as usize;
        let (b, shared, dirty) = (&plan.bounds, &plan.shared, &plan.dirty);
        for_each_range(ranges, |r| {
            let (lo, hi) = (b[r], b[r + 1]);
            let (p0, p1) = (c.start[lo] as usize, c.start[hi] as usize);
            let (nd, npr) = (hi - lo, p1 - p0);
            let (nde, npe) = if D { (nd, npr) } else { (0, 0) };
            // SAFETY: ranges are disjoint disc ranges [lo, hi) and pair ranges [p0, p1) of
            // arrays of length n and np (the E-only arrays are touched only when E, then
            // they have these lengths too); energy chunks: with E the non-empty ranges start
            // at chunk boundaries, so range r owns chunks [lo/CHUNK, ceil(hi/CHUNK)); without
            // E the energies are neither written nor read.
            let (ds, ps, en) = unsafe {
                let ds = DiscSide {
                    fx: dp[0].slice(lo, nd),
                    fy: dp[1].slice(lo, nd),
                    tq: dp[2].slice(lo, nd),
                    f: ap.slice(lo, if aos { nd } else { 0 }),
                    dfx: ddp[0].slice(lo, nde),
                    dfy: ddp[1].slice(lo, nde),
                    dtq: ddp[2].slice(lo, nde),
                    own: [
                        op[0].slice(lo, nd),
                        op[1].slice(lo, nd),
                        op[2].slice(lo, nd),
                        op[3].slice(lo, nde),
                        op[4].slice(lo, nde),
                        op[5].slice(lo, nde),
                    ],
                };
                let ps = PairSide {
                    us: pp[0].slice(p0, npr),
                    mr: pp[1].slice(p0, npr),
                    slot: [
                        sp[0].slice(p0, npr),
                        sp[1].slice(p0, npr),
                        sp[2].slice(p0, npr),
                        sp[3].slice(p0, npe),
                        sp[4].slice(p0, npe),
                        sp[5].slice(p0, npe),
                    ],
                };
                let en: &mut [PassEnergy] = if E && hi > lo {
                    let (c0, c1) = (lo / CHUNK, hi.div_ceil(CHUNK));
                    std::slice::from_raw_parts_mut((ep as *mut PassEnergy).add(c0), c1 - c0)
                } else {
                    &mut []
                };
                (ds, ps, en)
            };
            SCRATCH.with(|sc| {
                let sc = &mut sc.borrow_mut();
                let lh = (lo, hi);
                range_pass::<E, D, true, L, H>(c, pk, shared, lh, dirty, ds, ps, en, sc, avx2);
            });
        });
        // Shared discs: partner-side slots in increasing pair order, then the own sum.
        let (rstart, rpair) = (nb.rstart, nb.rpair);
        for &k in &plan.shared_list {
            let k = k as usize;
            for &p in &rpair[rstart[k] as usize..rstart[k + 1] as usize] {
                let p = p as usize;
                fx[k] += sfx[p];
                fy[k] += sfy[p];
                tq[k] += stj[p];
                if D {
                    dfx[k] += sdx[p];
                    dfy[k] += sdy[p];
                    dtq[k] += sdt[p];
                }
            }
            fx[k] += own[0][k];
            fy[k] += own[1][k];
            tq[k] += own[2][k];
            if D {
                dfx[k] += own[3][k];
                dfy[k] += own[4][k];
                dtq[k] += own[5][k];
            }
        }
    }
    // Every range copied its accumulators out and cleared them.
    s.acc_zero = aos;
    let mut total = PassEnergy::default();
    for e in &s.chunk_energy {
        total.add(e);
    }
    total
}

#[cfg(test)]
mod tests {
    use crate::bond::bench::shaken_hex_lattice;
    use crate::contact::{LinearSpringDashpot, NormalDamping, RollingResistance};
    use crate::{ContactLaws, ContactModel, Params, World};

    /// The packed gather and accumulator scatter (AVX2) give the bits of the portable gather
    /// and scatter: forces, state, histories and energies, for 1 and 3 threads, with and
    /// without energy tracking, with reference gaps and with a material table with rolling
    /// resistance. (Without AVX2 both runs take the portable path.)
    #[test]
    fn packed_gather_and_scatter_give_the_portable_bits() {
        let st = shaken_hex_lattice([24, 10], 17, 0.02, 20.0);
        let law = LinearSpringDashpot {
            kn: 1e5,
            ks: 3e4,
            damping: NormalDamping::Ratio(0.2),
            shear_damping: 0.5,
            mu: 0.3,
        };
        let mut table = ContactLaws::new(2, ContactModel::Linear(law));
        table.set_rolling(0, 1, Some(RollingResistance::new(0.1)));
        for (threads, track, offsets, laws) in [
            (
                1,
                false,
                false,
                ContactLaws::uniform(ContactModel::Linear(law)),
            ),
            (
                1,
                true,
                true,
                ContactLaws::uniform(ContactModel::Linear(law)),
            ),
            (
                3,
                false,
                true,
                ContactLaws::uniform(ContactModel::Linear(law)),
            ),
            (3, true, false, table.clone()),
            (1, true, false, table.clone()),
        ] {
            let run = |portable: bool| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool");
                pool.install(|| {
                    let mut st = st.clone();
                    if laws.n_materials() > 1 {
                        for k in (0..st.discs.len()).step_by(3) {
                            st.discs.material[k] = 1;
                        }
                    }
                    let params = Params {
                        dt_fixed: Some(1e-7),
                        skin: Some(1e-4),
                        track_energy: track,
                        ..Params::default()
                    };
                    let mut w = World::new(st, params, laws.clone());
                    w.ws.slots.portable = portable;
                    if offsets {
                        for k in 0..40 {
                            w.set_contact_offset(k, k + 1, -1e-5);
                        }
                    }
                    w.run(25);
                    let d = &w.state.discs;
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    (
                        [
                            &d.fx, &d.fy, &d.torque, &d.x, &d.vy, &d.omega, &w.nb.us, &w.nb.mr,
                        ]
                        .map(|v| bits(v)),
                        format!("{:?}", w.energy()),
                    )
                })
            };
            let (a, b) = (run(false), run(true));
            assert!(a.0[0].iter().any(|&b| f64::from_bits(b) != 0.0));
            assert_eq!(a, b, "{threads} threads, track {track}, offsets {offsets}");
        }
    }

    /// The split pass gives the one-thread bits for 2, 3 and 5 ranges, with and without
    /// energy tracking, and really has shared discs to finish and both plain blocks (scattered
    /// by the one-range code) and blocks with shared discs.
    #[test]
    fn any_split_gives_the_one_thread_bits() {
        let st = shaken_hex_lattice([40, 12], 5, 0.01, 10.0);
        let law = LinearSpringDashpot {
            kn: 1e5,
            ks: 3e4,
            damping: NormalDamping::Gamma(100.0),
            shear_damping: 0.5,
            mu: 0.3,
        };
        for track in [false, true] {
            let params = Params {
                dt_fixed: Some(1e-7),
                skin: Some(1e-4),
                track_energy: track,
                ..Params::default()
            };
            let run = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool");
                pool.install(|| {
                    let laws = ContactLaws::uniform(ContactModel::Linear(law));
                    let mut w = World::new(st.clone(), params.clone(), laws);
                    w.run(20);
                    let shared = w.ws.slots.plan.shared_list.len();
                    if threads > 1 {
                        let (plain, other) = w.ws.slots.plan.block_kinds();
                        assert!(plain > 0 && other > 0, "{threads}: {plain} {other}");
                    }
                    let d = &w.state.discs;
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    let dp = &w.ws.slots.dashpot;
                    (
                        [&d.fx, &d.fy, &d.torque, &d.x, &dp.fx, &dp.t].map(|v| bits(v)),
                        format!("{:?}", w.energy()),
                        shared,
                    )
                })
            };
            let one = run(1);
            assert!(one.0[0].iter().any(|&b| f64::from_bits(b) != 0.0));
            for t in [2, 3, 5] {
                let other = run(t);
                assert!(other.2 > 0, "{t} ranges: no shared discs");
                assert_eq!(one.0, other.0, "{t} threads, track {track}");
                assert_eq!(one.1, other.1, "{t} threads, track {track}");
            }
        }
    }
}
