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

use super::disc_disc::{PassEnergy, Slots, CHUNK};
use super::kernel::{at, block, has_avx2, Ctx, PairLaw, Scratch, BLOCK};

/// The parts of the neighbour list the split needs.
pub(crate) struct ListRef<'a> {
    pub builds: u64,
    pub start: &'a [u32],
    pub nbr: &'a [u32],
    pub rstart: &'a [u32],
    pub rpair: &'a [u32],
}
use rayon::prelude::*;

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
}

impl Plan {
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
    }
}

/// Mutable per-disc arrays of one range (indexed from the range's first disc).
struct DiscSide<'a> {
    fx: &'a mut [f64],
    fy: &'a mut [f64],
    tq: &'a mut [f64],
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

/// One range of discs `[lo, hi)`: compute its pairs and scatter (see the module doc).
/// `SPLIT`: there may be shared discs (else the plain one-thread pass). `E`: energies are
/// tracked; `D` (only with `E`): the dashpot forces are summed per disc as well (see
/// [`super::disc_disc::compute`]: not needed when no law has a dashpot).
#[allow(clippy::too_many_arguments)]
fn range_pass<const E: bool, const D: bool, const SPLIT: bool, L: PairLaw>(
    c: &Ctx<L>,
    shared: &[bool],
    lo: usize,
    hi: usize,
    ds: DiscSide,
    ps: PairSide,
    energy: &mut [PassEnergy],
    sc: &mut Scratch,
    avx2: bool,
) {
    let p0 = at!(c.start, lo) as usize;
    let DiscSide {
        fx,
        fy,
        tq,
        dfx,
        dfy,
        dtq,
        own,
    } = ds;
    let PairSide { us, mr, slot } = ps;
    let [ofx, ofy, otq, odx, ody, odt] = own;
    let [sfx, sfy, stj, sdx, sdy, sdt] = slot;
    let is_shared = |k: usize| SPLIT && at!(shared, k);
    let mut i = lo;
    let (mut ax, mut ay, mut at) = (0.0, 0.0, 0.0);
    let (mut bx, mut by, mut bt) = (0.0, 0.0, 0.0);
    let mut gi = lo;
    let mut clo = lo;
    while clo < hi {
        // Energy chunk [clo, chi): a fixed CHUNK grid.
        let chi = ((clo / CHUNK + 1) * CHUNK).min(hi);
        let mut e = PassEnergy::default();
        let (mut p, pend) = (at!(c.start, clo) as usize, at!(c.start, chi) as usize);
        while p < pend {
            let q = BLOCK.min(pend - p);
            let (u, m) = (&mut us[p - p0..p - p0 + q], &mut mr[p - p0..p - p0 + q]);
            block::<E, D, L>(c, p, &mut gi, u, m, sc, &mut e, avx2);
            for k in 0..q {
                let pp = p + k;
                while at!(c.start, i + 1) as usize <= pp {
                    let li = i - lo;
                    if is_shared(i) {
                        ofx[li] = ax;
                        ofy[li] = ay;
                        otq[li] = at;
                        if D {
                            odx[li] = bx;
                            ody[li] = by;
                            odt[li] = bt;
                        }
                    } else {
                        fx[li] += ax;
                        fy[li] += ay;
                        tq[li] += at;
                        if D {
                            dfx[li] += bx;
                            dfy[li] += by;
                            dtq[li] += bt;
                        }
                    }
                    (ax, ay, at) = (0.0, 0.0, 0.0);
                    (bx, by, bt) = (0.0, 0.0, 0.0);
                    i += 1;
                }
                // Pairs not in contact add zeros, as every other path does.
                let (f0, f1, f2, f3) = (sc.fx[k], sc.fy[k], sc.ti[k], sc.tj[k]);
                ax -= f0;
                ay -= f1;
                at += f2;
                let j = at!(c.nbr, pp) as usize;
                let lp = pp - p0;
                if D {
                    bx -= sc.dfx[k];
                    by -= sc.dfy[k];
                    bt += sc.dti[k];
                }
                if is_shared(j) {
                    sfx[lp] = f0;
                    sfy[lp] = f1;
                    stj[lp] = f3;
                    if D {
                        sdx[lp] = sc.dfx[k];
                        sdy[lp] = sc.dfy[k];
                        sdt[lp] = sc.dtj[k];
                    }
                } else {
                    let lj = j - lo;
                    // SAFETY: j is not shared, so lo <= i < j < hi (see `Plan::update`;
                    // one range: lo = 0, hi = n), and the disc slices have length hi - lo.
                    unsafe {
                        *fx.get_unchecked_mut(lj) += f0;
                        *fy.get_unchecked_mut(lj) += f1;
                        *tq.get_unchecked_mut(lj) += f3;
                    }
                    if D {
                        dfx[lj] += sc.dfx[k];
                        dfy[lj] += sc.dfy[k];
                        dtq[lj] += sc.dtj[k];
                    }
                }
            }
            p += q;
        }
        while i < chi {
            let li = i - lo;
            if is_shared(i) {
                ofx[li] = ax;
                ofy[li] = ay;
                otq[li] = at;
                if D {
                    odx[li] = bx;
                    ody[li] = by;
                    odt[li] = bt;
                }
            } else {
                fx[li] += ax;
                fy[li] += ay;
                tq[li] += at;
                if D {
                    dfx[li] += bx;
                    dfy[li] += by;
                    dtq[li] += bt;
                }
            }
            (ax, ay, at) = (0.0, 0.0, 0.0);
            (bx, by, bt) = (0.0, 0.0, 0.0);
            i += 1;
        }
        if E {
            energy[clo / CHUNK - lo / CHUNK] = e;
        }
        clo = chi;
    }
}

thread_local! {
    /// One block scratch per worker thread, allocated once.
    static SCRATCH: std::cell::RefCell<Box<Scratch>> = std::cell::RefCell::new(Box::default());
}

/// Raw pointer that may be shared across threads; each range touches disjoint index ranges.
#[derive(Clone, Copy)]
struct SyncPtr(*mut f64);
unsafe impl Send for SyncPtr {}
unsafe impl Sync for SyncPtr {}

impl SyncPtr {
    fn of(v: &mut [f64]) -> SyncPtr {
        SyncPtr(v.as_mut_ptr())
    }

    /// # Safety
    /// `[a, a + len)` must be in bounds of the array and not aliased by any live reference.
    unsafe fn slice<'a>(self, a: usize, len: usize) -> &'a mut [f64] {
        if len == 0 {
            return &mut [];
        }
        std::slice::from_raw_parts_mut(self.0.add(a), len)
    }
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
/// [`range_pass`]. (Kept out of line: inlined into its caller it compiles to slower code.)
#[inline(never)]
pub(crate) fn pass<const E: bool, const D: bool, L: PairLaw>(
    c: &Ctx<L>,
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
    let Outs { fx, fy, tq, dash } = outs;
    let [dfx, dfy, dtq] = dash;
    if ranges <= 1 || n == 0 {
        let ds = DiscSide {
            fx,
            fy,
            tq,
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
        range_pass::<E, D, false, L>(c, &[], 0, n, ds, ps, &mut s.chunk_energy, sc, avx2);
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
        let ddp = [SyncPtr::of(dfx), SyncPtr::of(dfy), SyncPtr::of(dtq)];
        let op = own.each_mut().map(|v| SyncPtr::of(v));
        let pp = [SyncPtr::of(us), SyncPtr::of(mr)];
        let sp = [
            &mut *sfx, &mut *sfy, &mut *stj, &mut *sdx, &mut *sdy, &mut *sdt,
        ]
        .map(|v| SyncPtr::of(v));
        let ep = chunk_energy.as_mut_ptr() as usize;
        let (b, shared) = (&plan.bounds, &plan.shared);
        (0..ranges).into_par_iter().for_each(|r| {
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
                range_pass::<E, D, true, L>(c, shared, lo, hi, ds, ps, en, sc, avx2);
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
    let mut total = PassEnergy::default();
    for e in &s.chunk_energy {
        total.add(e);
    }
    total
}

#[cfg(test)]
mod tests {
    use crate::bond::bench::shaken_hex_lattice;
    use crate::contact::{LinearSpringDashpot, NormalDamping};
    use crate::{ContactLaws, ContactModel, Params, World};

    /// The split pass gives the one-thread bits for 2, 3 and 5 ranges, with and without
    /// energy tracking, and really has shared discs to finish.
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
                    let shared = w.slots.plan.shared_list.len();
                    let d = &w.state.discs;
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    let dp = &w.slots.dashpot;
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
