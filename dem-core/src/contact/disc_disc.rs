//! Disc–disc force pass over the neighbour list.
//!
//! Discs are processed in fixed chunks of [`CHUNK`] discs (independent of the thread count).
//! One thread: forces are scattered pair by pair in list order. Several threads: each chunk
//! writes its pairs' forces into per-pair slots, then every disc gathers its partner-side
//! slots (increasing pair order) and adds its own pairs' sum, which is the same sequence of
//! floating-point additions as the serial scatter: results are bit-identical for any thread
//! count. Energies are summed per chunk and the chunk sums added in chunk order.

use super::{ContactLaws, PairKin};
use crate::neighbors::{MinImage, Neighbors};
use crate::state::Discs;
use rayon::prelude::*;

/// Discs per work chunk (fixed so that reductions do not depend on the thread count).
pub const CHUNK: usize = 2048;

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

/// Read-only data of the pass.
struct Ctx<'a> {
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
    laws: &'a ContactLaws,
    img: MinImage,
    dt: f64,
    rolling: bool,
}

/// Force of pair p = (i, j): (fx, fy) on j (i gets the opposite), torque on i, torque on j.
#[inline(always)]
fn pair<const E: bool>(
    c: &Ctx,
    i: usize,
    j: usize,
    p: usize,
    us: &mut f64,
    mr: &mut f64,
    e: &mut PassEnergy,
) -> Option<[f64; 4]> {
    let (dx, dy) = c.img.delta(c.x[j] - c.x[i], c.y[j] - c.y[i]);
    let d2 = dx * dx + dy * dy;
    let (ri, rj) = (c.r[i], c.r[j]);
    let g0 = if c.g0.is_empty() { 0.0 } else { c.g0[p] };
    let reach = ri + rj + g0;
    if d2 >= reach * reach || reach <= 0.0 {
        *us = 0.0;
        *mr = 0.0;
        return None;
    }
    let d = d2.sqrt();
    let inv = 1.0 / d;
    let (nx, ny) = (dx * inv, dy * inv);
    let (wi, wj) = (c.w[i], c.w[j]);
    let wr = wi * ri + wj * rj;
    let rvx = c.vx[j] - c.vx[i] + wr * ny;
    let rvy = c.vy[j] - c.vy[i] - wr * nx;
    let k = PairKin {
        delta: reach - d,
        vn: rvx * nx + rvy * ny,
        vt: rvy * nx - rvx * ny,
        m_eff: 1.0 / (c.minv[i] + c.minv[j]),
        r_eff: ri * rj / (ri + rj),
        dt: c.dt,
    };
    let (mi, mj) = (c.mat[i], c.mat[j]);
    let model = c.laws.model(mi, mj);
    let o = model.force::<E>(&k, us);
    let mut m_roll = 0.0;
    if c.rolling {
        if let Some(rr) = c.laws.rolling(mi, mj) {
            let kn = model.kn(k.r_eff, k.delta);
            let diss = rr.update(kn, k.r_eff, o.f_n, wi - wj, c.dt, mr);
            m_roll = *mr;
            if E {
                e.fric += diss;
                let kr = rr.kr(kn, k.r_eff);
                if kr > 0.0 {
                    e.strain += 0.5 * m_roll * m_roll / kr;
                }
            }
        }
    }
    if E {
        e.strain += o.e_strain;
        e.damp += o.e_damp;
        e.fric += o.e_fric;
    }
    // t = (−n_y, n_x): F = F_n n + F_t t.
    let fx = o.f_n * nx - o.f_t * ny;
    let fy = o.f_n * ny + o.f_t * nx;
    Some([fx, fy, -ri * o.f_t + m_roll, -rj * o.f_t - m_roll])
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
    let parallel = rayon::current_num_threads() > 1 && d.len() > 2 * CHUNK;
    match (track_energy, parallel) {
        (true, false) => serial::<true>(d, nb, minv, laws, img, dt),
        (false, false) => serial::<false>(d, nb, minv, laws, img, dt),
        (true, true) => parallel_pass::<true>(d, nb, minv, laws, img, dt, slots),
        (false, true) => parallel_pass::<false>(d, nb, minv, laws, img, dt, slots),
    }
}

fn serial<const E: bool>(
    d: &mut Discs,
    nb: &mut Neighbors,
    minv: &[f64],
    laws: &ContactLaws,
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
        laws,
        img,
        dt,
        rolling: laws.any_rolling(),
    };
    let (us, mr) = (&mut nb.us, &mut nb.mr);
    let mut total = PassEnergy::default();
    let mut lo = 0;
    while lo < n {
        let hi = (lo + CHUNK).min(n);
        let mut e = PassEnergy::default();
        for i in lo..hi {
            let (mut ax, mut ay, mut at) = (0.0, 0.0, 0.0);
            for p in c.start[i] as usize..c.start[i + 1] as usize {
                let j = c.nbr[p] as usize;
                if let Some(f) = pair::<E>(&c, i, j, p, &mut us[p], &mut mr[p], &mut e) {
                    // Same skip rule as the parallel gather (keeps signed zeros identical).
                    if f[0] != 0.0 || f[1] != 0.0 || f[2] != 0.0 {
                        ax -= f[0];
                        ay -= f[1];
                        at += f[2];
                    }
                    if f[0] != 0.0 || f[1] != 0.0 || f[3] != 0.0 {
                        fx[j] += f[0];
                        fy[j] += f[1];
                        torque[j] += f[3];
                    }
                }
            }
            fx[i] += ax;
            fy[i] += ay;
            torque[i] += at;
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

fn parallel_pass<const E: bool>(
    d: &mut Discs,
    nb: &mut Neighbors,
    minv: &[f64],
    laws: &ContactLaws,
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
            laws,
            img,
            dt,
            rolling: laws.any_rolling(),
        };
        let ptr = [
            SyncPtr(nb.us.as_mut_ptr()),
            SyncPtr(nb.mr.as_mut_ptr()),
            SyncPtr(s.fx.as_mut_ptr()),
            SyncPtr(s.fy.as_mut_ptr()),
            SyncPtr(s.ti.as_mut_ptr()),
            SyncPtr(s.tj.as_mut_ptr()),
        ];
        (0..nchunks)
            .into_par_iter()
            .map(|ch| {
                let (lo, hi) = (ch * CHUNK, ((ch + 1) * CHUNK).min(n));
                let mut e = PassEnergy::default();
                for i in lo..hi {
                    for p in c.start[i] as usize..c.start[i + 1] as usize {
                        let j = c.nbr[p] as usize;
                        // SAFETY: pair p belongs to disc i of this chunk only; chunks cover
                        // disjoint pair ranges, and all six arrays have length np > p.
                        let f = unsafe {
                            pair::<E>(
                                &c,
                                i,
                                j,
                                p,
                                &mut *ptr[0].0.add(p),
                                &mut *ptr[1].0.add(p),
                                &mut e,
                            )
                        }
                        .unwrap_or([0.0; 4]);
                        unsafe {
                            *ptr[2].0.add(p) = f[0];
                            *ptr[3].0.add(p) = f[1];
                            *ptr[4].0.add(p) = f[2];
                            *ptr[5].0.add(p) = f[3];
                        }
                    }
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
        for k in lo..hi {
            // SAFETY: disc k belongs to this chunk only; arrays have length n > k.
            let (fxk, fyk, tk) = unsafe {
                (
                    &mut *out[0].0.add(k),
                    &mut *out[1].0.add(k),
                    &mut *out[2].0.add(k),
                )
            };
            for &p in &rpair[rstart[k] as usize..rstart[k + 1] as usize] {
                let p = p as usize;
                if sfx[p] != 0.0 || sfy[p] != 0.0 || stj[p] != 0.0 {
                    *fxk += sfx[p];
                    *fyk += sfy[p];
                    *tk += stj[p];
                }
            }
            let (mut ax, mut ay, mut at) = (0.0, 0.0, 0.0);
            for p in start[k] as usize..start[k + 1] as usize {
                if sfx[p] != 0.0 || sfy[p] != 0.0 || sti[p] != 0.0 {
                    ax -= sfx[p];
                    ay -= sfy[p];
                    at += sti[p];
                }
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
