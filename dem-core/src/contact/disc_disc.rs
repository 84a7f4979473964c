//! Disc–disc force pass over the neighbour list.
//!
//! Pairs are computed in blocks ([`super::kernel`]): gather, branch-free evaluation of the law
//! (vectorised), then a scatter loop adds the forces to the discs in pair order. Discs are
//! grouped in fixed chunks of [`CHUNK`] discs (independent of the thread count). One thread:
//! forces are scattered pair by pair in list order. Several threads: chunks run in parallel
//! and write per-pair slots, then every disc gathers its partner-side slots (increasing pair
//! order) and adds its own pairs' sum — the same sequence of floating-point additions as the
//! serial scatter, so results are bit-identical for any thread count. Energies are summed in
//! pair order within a chunk and the chunk sums added in chunk order.

use super::kernel::{at, block, has_avx2, Ctx, LinearGamma, LinearRatio, PairLaw, Scratch, BLOCK};
use super::{ContactLaws, ContactModel, NormalDamping};
use crate::neighbors::{MinImage, Neighbors};
use crate::state::Discs;
use rayon::prelude::*;

/// Discs per work chunk (fixed so that reductions do not depend on the thread count).
pub const CHUNK: usize = 512;

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
    /// Block scratch of the serial pass (allocated once).
    pub scratch: Box<Scratch>,
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub ti: Vec<f64>,
    pub tj: Vec<f64>,
    pub chunk_energy: Vec<PassEnergy>,
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
        && (nb.verified
            || ((nb.nbr.iter().fold(0u32, |m, &j| m.max(j)) as usize) < n.max(1)
                && (nb.rpair.iter().fold(0u32, |m, &p| m.max(p)) as usize) < np.max(1)
                && nb.start.windows(2).all(|w| w[0] <= w[1])))
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
    nb.verified = true;
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
        (true, false) => serial::<true, L>(d, nb, minv, law, img, dt, &mut slots.scratch),
        (false, false) => serial::<false, L>(d, nb, minv, law, img, dt, &mut slots.scratch),
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
    scratch: &mut Scratch,
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
    let sc = &mut *scratch;
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
            block::<E, L>(&c, p, &mut gi, u, m, sc, &mut e, avx2);
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

thread_local! {
    /// One block scratch per worker thread of the parallel pass, allocated once.
    static SCRATCH: std::cell::RefCell<Box<Scratch>> = std::cell::RefCell::new(Box::default());
}

/// Run `f` with this thread's block scratch.
fn with_scratch<R>(f: impl FnOnce(&mut Scratch) -> R) -> R {
    SCRATCH.with(|s| f(&mut s.borrow_mut()))
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
                with_scratch(|sc| {
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
                        block::<E, L>(&c, p, &mut gi, u, m, sc, &mut e, avx2);
                        u.copy_from_slice(&sc.us[..q]);
                        fx.copy_from_slice(&sc.fx[..q]);
                        fy.copy_from_slice(&sc.fy[..q]);
                        ti.copy_from_slice(&sc.ti[..q]);
                        tj.copy_from_slice(&sc.tj[..q]);
                        p += q;
                    }
                    e
                })
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
