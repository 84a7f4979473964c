//! Central-difference (leapfrog) integration of free discs, PFC local damping, viscous
//! damping and gravity (Cundall & Strack 1979; Itasca PFC manual, "law of motion"):
//!
//! v(t+Δt/2) = v(t−Δt/2) + (F + F_d + F_v + m g)/m · Δt_kick,   x(t+Δt) = x(t) + v(t+Δt/2) Δt,
//!
//! with Δt_kick = (Δt_old + Δt)/2 (equal to Δt unless the step just changed), the local damping
//! F_d = −α |F + m g| sign(v) per component (Cundall 1987; Potyondy & Cundall 2004 eq. 4) and
//! the viscous F_v = −c v, c = 2ζ√(m K) (see [`crate::Params::viscous_damping`]); the same for
//! θ, ω with the torque and I. In the fragment frame ([`crate::damping`]) the local damping
//! forces are computed before this pass and added here in place of the sign rule. Fixed discs move with their prescribed velocity. Members of rigid
//! clumps are moved by [`crate::clump`]. Kinetic energy is reported at time t with the mean of
//! the two half-step velocities.

use crate::contact::disc_disc::{Dashpot, CHUNK};
use crate::lanes::Packed;
use crate::state::Discs;
use crate::team::SyncPtr;
use serde::{Deserialize, Serialize};

/// Per-disc integration data, rebuilt with the neighbour list.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct DiscCache {
    /// 1/m for the contact effective mass (0 for fixed discs: infinite mass).
    pub minv_contact: Vec<f64>,
    /// 1/m and 1/I of integrated (free, not fixed) discs, 0 otherwise.
    pub inv_m: Vec<f64>,
    pub inv_i: Vec<f64>,
    /// Viscous damping coefficients c = 2ζ√(mK) (translation) and 2ζ√(I K_rot) (rotation).
    pub visc_t: Vec<f64>,
    pub visc_r: Vec<f64>,
    /// Stiffness sums of the time-step estimate.
    pub k_trans: Vec<f64>,
    pub k_rot: Vec<f64>,
}

/// What the integration pass reports.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Moved {
    pub ke_trans: f64,
    pub ke_rot: f64,
    /// Energy dissipated by local and viscous damping in this step (J).
    pub damp: f64,
    /// Energy dissipated by the contact dashpots in this step, −(F_d · v̄ + T_d ω̄) Δt with the
    /// mean half-step velocities (see `contact::disc_disc::Dashpot`) (J).
    pub damp_contact: f64,
    /// Work done by fixed (prescribed-velocity) discs on the others in this step (J).
    pub boundary_work: f64,
    /// Gravitational potential −Σ m g·x at time t (J).
    pub grav_pot: f64,
    /// Whether some disc moved more than the rebuild limit since the last neighbour build.
    pub exceeded: bool,
}

impl Moved {
    pub fn add(&mut self, o: &Moved) {
        self.ke_trans += o.ke_trans;
        self.ke_rot += o.ke_rot;
        self.damp += o.damp;
        self.damp_contact += o.damp_contact;
        self.boundary_work += o.boundary_work;
        self.grav_pot += o.grav_pot;
        self.exceeded |= o.exceeded;
    }
}

/// sign(v) with sign(0) = 0.
#[inline(always)]
pub fn sgn(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Step parameters of the pass.
#[derive(Clone, Copy, Debug)]
pub struct Kick {
    pub kick: f64,
    pub drift: f64,
    pub alpha: f64,
    pub gravity: [f64; 2],
    pub track: bool,
    /// Book the dashpot dissipation (with `track`, when some contact law has a dashpot: the
    /// dashpot sums are filled only then, see [`crate::contact::disc_disc::Dashpot`]).
    pub dash: bool,
    /// Squared displacement (since the last neighbour build) that calls for a rebuild.
    pub disp2_limit: f64,
}

/// The read-only disc arrays of the pass.
struct Ro<'a> {
    m: &'a [f64],
    inertia: &'a [f64],
    fx: &'a [f64],
    fy: &'a [f64],
    torque: &'a [f64],
    fixed: &'a [bool],
    /// Dashpot sums (length n when energy is tracked and `Kick::dash`).
    dash: &'a Dashpot,
    /// Local damping forces and torques computed in the fragment frame (length n, or empty
    /// when local damping acts in the lab frame or not at all).
    rel: &'a [Vec<f64>; 3],
    /// Where to pack the moved discs for the next force pass, if anywhere, and the radii
    /// for the records.
    pack: Option<PackOut>,
    r: &'a [f64],
}

/// Where the integrator writes the discs' packed records for the next disc–disc pass, right
/// after moving each block of discs (while in cache; see `Slots::packed_fresh`): the records,
/// one per disc. Made only when the CPU has AVX2 (the packing uses it).
#[derive(Clone, Copy)]
pub struct PackOut {
    pub(crate) pk: *mut Packed,
    pub(crate) len: usize,
    /// The records hold the discs' current radii and inverse contact masses (this step's
    /// disc–disc pass wrote or read them, for the same discs and caches): only the moving
    /// parts are rewritten (`repack_moved`).
    pub(crate) reuse: bool,
}
// SAFETY: the chunks of the pass write disjoint index ranges of the records.
unsafe impl Send for PackOut {}
unsafe impl Sync for PackOut {}

/// Discs per sub-block of [`chunk`]: the state update and the per-disc energy terms are
/// computed over a sub-block in one branch-free loop (vectorised), then the terms are summed
/// serially in disc order.
const SUB: usize = 64;

/// Per-disc energy terms of one sub-block: kinetic (translation, rotation), damping work,
/// dashpot work, gravity potential, boundary work.
type Terms = [[f64; SUB]; 6];

thread_local! {
    /// One [`Terms`] per worker thread, allocated once (not zeroed every step: the pass
    /// writes every term it reads).
    static TERMS: std::cell::RefCell<Box<Terms>> = std::cell::RefCell::new(Box::new([[0.0; SUB]; 6]));
}

/// The update of one sub-block (all slices of one length n ≤ [`SUB`]). Every argument is a
/// separate reference, so the compiler knows that they do not alias and vectorises the loop.
/// Returns whether some disc moved beyond the rebuild limit.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn sub_block<
    const E: bool,
    const D: bool,
    const DAMP: bool,
    const REL: bool,
    const VISC: bool,
    const G: bool,
>(
    x: &mut [f64],
    y: &mut [f64],
    th: &mut [f64],
    vx: &mut [f64],
    vy: &mut [f64],
    w: &mut [f64],
    ro: [&[f64]; 17],
    fixed: &[bool],
    k: &Kick,
    t: &mut Terms,
) -> bool {
    let n = x.len();
    let [m, inertia, fx, fy, tq, im, ii, x0, y0, cvt, cvr, dfx, dfy, dtq, rfx, rfy, rtq] = ro;
    let (y, th, vx, vy, w) = (
        &mut y[..n],
        &mut th[..n],
        &mut vx[..n],
        &mut vy[..n],
        &mut w[..n],
    );
    let (m, inertia, fx, fy, tq) = (&m[..n], &inertia[..n], &fx[..n], &fy[..n], &tq[..n]);
    let (im, ii, x0, y0) = (&im[..n], &ii[..n], &x0[..n], &y0[..n]);
    let (cvt, cvr, dfx, dfy, dtq) = (&cvt[..n], &cvr[..n], &dfx[..n], &dfy[..n], &dtq[..n]);
    let (rfx, rfy, rtq) = (&rfx[..n], &rfy[..n], &rtq[..n]);
    let fixed = &fixed[..n];
    let [t_kt, t_kr, t_dmp, t_dc, t_gp, t_bw] = t;
    let (t_kt, t_kr, t_dmp) = (&mut t_kt[..n], &mut t_kr[..n], &mut t_dmp[..n]);
    let (t_dc, t_gp, t_bw) = (&mut t_dc[..n], &mut t_gp[..n], &mut t_bw[..n]);
    let [gx, gy] = k.gravity;
    let mut exceeded = false;
    for i in 0..n {
        // Without gravity (`G` false: g = 0) the weight m g is +0 or −0 and adding it leaves
        // the force's bits unchanged (a force sum is never −0: it starts at +0 and adds in
        // round-to-nearest), so the masses are not read.
        let (mut ax, mut ay, mut at) = if G {
            (fx[i] + m[i] * gx, fy[i] + m[i] * gy, tq[i])
        } else {
            (fx[i], fy[i], tq[i])
        };
        let (f0x, f0y, t0) = (ax, ay, at);
        let (ux, uy, uw) = (vx[i], vy[i], w[i]);
        if DAMP {
            ax -= k.alpha * ax.abs() * sgn(ux);
            ay -= k.alpha * ay.abs() * sgn(uy);
            at -= k.alpha * at.abs() * sgn(uw);
        }
        if REL {
            ax += rfx[i];
            ay += rfy[i];
            at += rtq[i];
        }
        if VISC {
            ax -= cvt[i] * ux;
            ay -= cvt[i] * uy;
            at -= cvr[i] * uw;
        }
        let (nvx, nvy, nw) = (
            ux + ax * im[i] * k.kick,
            uy + ay * im[i] * k.kick,
            uw + at * ii[i] * k.kick,
        );
        vx[i] = nvx;
        vy[i] = nvy;
        w[i] = nw;
        let (xo, yo) = (x[i], y[i]);
        let (xn, yn) = (xo + nvx * k.drift, yo + nvy * k.drift);
        x[i] = xn;
        y[i] = yn;
        th[i] += nw * k.drift;
        let (dx, dy) = (xn - x0[i], yn - y0[i]);
        exceeded |= dx * dx + dy * dy > k.disp2_limit;
        if E {
            // Free discs: kinetic energy and damping work with the mean velocity; fixed
            // discs: boundary work and dashpot work with their prescribed velocity.
            let free = im[i] > 0.0;
            // (Written with the load first: the loop then vectorises.)
            let fix = fixed[i] && !free;
            let (mx, my, mw) = (0.5 * (ux + nvx), 0.5 * (uy + nvy), 0.5 * (uw + nw));
            let kt = 0.5 * m[i] * (mx * mx + my * my);
            let kr = 0.5 * inertia[i] * mw * mw;
            let dmp = ((ax - f0x) * mx + (ay - f0y) * my + (at - t0) * mw) * k.kick;
            let gp = m[i] * (gx * xo + gy * yo);
            let bw = (fx[i] * ux + fy[i] * uy + tq[i] * uw) * k.drift;
            t_kt[i] = if free { kt } else { -0.0 };
            t_kr[i] = if free { kr } else { -0.0 };
            t_dmp[i] = if free { dmp } else { 0.0 };
            if D {
                let (ex, ey, et) = (dfx[i], dfy[i], dtq[i]);
                let dc_free = (ex * mx + ey * my + et * mw) * k.kick;
                let dc_fixed = (ex * ux + ey * uy + et * uw) * k.kick;
                let dc_other = if fix { dc_fixed } else { 0.0 };
                t_dc[i] = if free { dc_free } else { dc_other };
            }
            t_gp[i] = if free { gp } else { 0.0 };
            t_bw[i] = if fix { bw } else { 0.0 };
        }
    }
    exceeded
}

/// One chunk [lo, hi) of the disc pass. Every disc gets the same branch-free update (1/m = 0
/// leaves fixed discs and clump members at their velocity; members are then placed by the
/// clump pass), so the loop vectorises; energies are summed only when `E`, the dashpot
/// dissipation only when `D` as well (else it is exactly +0, see
/// [`crate::contact::disc_disc::Dashpot`]).
///
/// Energy terms: each disc's kinetic energy, damping work, dashpot work, gravity potential and
/// (fixed discs) boundary work are computed in the vectorised loop into per-disc arrays, with
/// a neutral term for discs that do not contribute (−0.0 for the sums that add, +0.0 for those
/// that subtract: x + (−0) and x − (+0) are x bit for bit, for every x), then summed one disc
/// after the other: each sum sees the same sequence of operations as when the terms were added
/// inside the update loop, so the results are the same bits.
///
/// # Safety
/// `p` points to the x, y, theta, vx, vy, omega arrays of length ≥ hi, and no other thread
/// touches indices in [lo, hi).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn chunk<
    const E: bool,
    const D: bool,
    const DAMP: bool,
    const REL: bool,
    const VISC: bool,
>(
    p: &[SyncPtr<f64>; 6],
    d: &Ro,
    c: &DiscCache,
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    lo: usize,
    hi: usize,
    terms: &mut Terms,
) -> Moved {
    let mut o = Moved::default();
    let mut exceeded = false;
    let mut b0 = lo;
    while b0 < hi {
        let b1 = (b0 + SUB).min(hi);
        let n = b1 - b0;
        let r = b0..b1;
        let im = &c.inv_m[r.clone()];
        let (cvt, cvr) = if VISC {
            (&c.visc_t[r.clone()], &c.visc_r[r.clone()])
        } else {
            (im, im)
        };
        let (dfx, dfy, dtq) = if D {
            (
                &d.dash.fx[r.clone()],
                &d.dash.fy[r.clone()],
                &d.dash.t[r.clone()],
            )
        } else {
            (im, im, im)
        };
        let (rfx, rfy, rtq) = if REL {
            (
                &d.rel[0][r.clone()],
                &d.rel[1][r.clone()],
                &d.rel[2][r.clone()],
            )
        } else {
            (im, im, im)
        };
        let ro = [
            &d.m[r.clone()],
            &d.inertia[r.clone()],
            &d.fx[r.clone()],
            &d.fy[r.clone()],
            &d.torque[r.clone()],
            im,
            &c.inv_i[r.clone()],
            &x0[r.clone()],
            &y0[r.clone()],
            cvt,
            cvr,
            dfx,
            dfy,
            dtq,
            rfx,
            rfy,
            rtq,
        ];
        let xs = [0, 1, 2, 3, 4, 5].map(|a| p[a].slice(b0, n));
        let [x, y, th, vx, vy, w] = xs;
        let fixed = &d.fixed[r];
        exceeded |= if k.gravity != [0.0, 0.0] {
            sub_block::<E, D, DAMP, REL, VISC, true>(x, y, th, vx, vy, w, ro, fixed, k, terms)
        } else {
            sub_block::<E, D, DAMP, REL, VISC, false>(x, y, th, vx, vy, w, ro, fixed, k, terms)
        };
        #[cfg(target_arch = "x86_64")]
        if let Some(po) = d.pack {
            // The moved discs b0..b1, packed as the force pass's `pack` would (plain copies).
            // SAFETY: a `PackOut` exists only when the CPU has AVX2 (`pack_records` needs
            // it); p[..] point to arrays of length n_discs >= b1 (the caller's contract),
            // po.len >= b1 (asserted by `integrate_discs`), and no other thread touches
            // indices b0..b1.
            let sl = |a: usize| std::slice::from_raw_parts(p[a].ptr().add(b0) as *const f64, n);
            let src = crate::contact::kernel::PackSrc {
                x: sl(0),
                y: sl(1),
                vx: sl(3),
                vy: sl(4),
                w: sl(5),
                r: &d.r[b0..b1],
                minv: &c.minv_contact[b0..b1],
            };
            let pk = std::slice::from_raw_parts_mut(po.pk.add(b0), n);
            if po.reuse {
                crate::contact::kernel::repack_moved(&src, pk);
            } else {
                crate::contact::kernel::pack_records(&src, 0, pk, &mut [], false);
            }
        }
        if E {
            let [t_kt, t_kr, t_dmp, t_dc, t_gp, t_bw] = &*terms;
            for i in 0..n {
                o.ke_trans += t_kt[i];
                o.ke_rot += t_kr[i];
                o.damp -= t_dmp[i];
                if D {
                    o.damp_contact -= t_dc[i];
                }
                o.grav_pot -= t_gp[i];
                o.boundary_work -= t_bw[i];
            }
        }
        b0 = b1;
    }
    o.exceeded = exceeded;
    o
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn chunk_avx2<
    const E: bool,
    const D: bool,
    const DAMP: bool,
    const REL: bool,
    const VISC: bool,
>(
    p: &[SyncPtr<f64>; 6],
    d: &Ro,
    c: &DiscCache,
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    lo: usize,
    hi: usize,
    terms: &mut Terms,
) -> Moved {
    chunk::<E, D, DAMP, REL, VISC>(p, d, c, x0, y0, k, lo, hi, terms)
}

/// Dispatch on the instruction set (same bits either way: no FMA contraction).
#[allow(clippy::too_many_arguments)]
unsafe fn chunk_best<
    const E: bool,
    const D: bool,
    const DAMP: bool,
    const REL: bool,
    const VISC: bool,
>(
    p: &[SyncPtr<f64>; 6],
    d: &Ro,
    c: &DiscCache,
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    lo: usize,
    hi: usize,
    terms: &mut Terms,
) -> Moved {
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::has_avx2() {
        return chunk_avx2::<E, D, DAMP, REL, VISC>(p, d, c, x0, y0, k, lo, hi, terms);
    }
    chunk::<E, D, DAMP, REL, VISC>(p, d, c, x0, y0, k, lo, hi, terms)
}

/// Integrate all free and fixed discs; chunked like the force pass so that the reported sums
/// do not depend on the thread count. `pack`: where to pack the moved discs for the next
/// disc–disc pass (see [`PackOut`]), if anywhere. `workers`: the step's team size
/// (`crate::team::Threads`; one: no split). `rel`: the local damping forces and torques of
/// the fragment frame ([`crate::damping`]; length n), or three empty vectors.
#[allow(clippy::too_many_arguments)]
pub fn integrate_discs(
    d: &mut Discs,
    dash: &Dashpot,
    rel: &[Vec<f64>; 3],
    c: &DiscCache,
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    parts: &mut Vec<Moved>,
    pack: Option<PackOut>,
    workers: usize,
) -> Moved {
    let n = d.len();
    assert!(pack.is_none_or(|po| po.len >= n && d.r.len() >= n && c.minv_contact.len() >= n));
    let with_rel = !rel[0].is_empty();
    assert!(!with_rel || rel.iter().all(|v| v.len() == n) && k.alpha == 0.0);
    let Discs {
        x,
        y,
        theta,
        vx,
        vy,
        omega,
        m,
        inertia,
        fx,
        fy,
        torque,
        fixed,
        r,
        ..
    } = d;
    let p = [
        SyncPtr::of(x),
        SyncPtr::of(y),
        SyncPtr::of(theta),
        SyncPtr::of(vx),
        SyncPtr::of(vy),
        SyncPtr::of(omega),
    ];
    let dr = Ro {
        m,
        inertia,
        fx,
        fy,
        torque,
        fixed,
        dash,
        rel,
        pack,
        r,
    };
    let dr = &dr;
    let nchunks = n.div_ceil(CHUNK);
    let run = |ch: usize| {
        let (lo, hi) = (ch * CHUNK, ((ch + 1) * CHUNK).min(n));
        // SAFETY: chunks are disjoint index ranges of the six arrays (length n) behind `p`,
        // which `dr` does not borrow.
        TERMS.with(|t| unsafe {
            let t = &mut **t.borrow_mut();
            // One monomorphised pass per combination of: energy tracking, dashpot sums (only
            // with tracking), local damping in the lab frame, in the fragment frame (never
            // both: the fragment frame runs with alpha 0), viscous damping.
            macro_rules! go {
                ($e:literal, $d:literal, $a:literal, $r:literal, $v:literal) => {
                    chunk_best::<$e, $d, $a, $r, $v>(&p, dr, c, x0, y0, k, lo, hi, t)
                };
            }
            let visc = !c.visc_t.is_empty();
            match (k.track, k.dash, k.alpha > 0.0, with_rel, visc) {
                (false, _, false, false, false) => go!(false, false, false, false, false),
                (false, _, false, false, true) => go!(false, false, false, false, true),
                (false, _, true, _, false) => go!(false, false, true, false, false),
                (false, _, true, _, true) => go!(false, false, true, false, true),
                (false, _, false, true, false) => go!(false, false, false, true, false),
                (false, _, false, true, true) => go!(false, false, false, true, true),
                (true, false, false, false, false) => go!(true, false, false, false, false),
                (true, false, false, false, true) => go!(true, false, false, false, true),
                (true, false, true, _, false) => go!(true, false, true, false, false),
                (true, false, true, _, true) => go!(true, false, true, false, true),
                (true, false, false, true, false) => go!(true, false, false, true, false),
                (true, false, false, true, true) => go!(true, false, false, true, true),
                (true, true, false, false, false) => go!(true, true, false, false, false),
                (true, true, false, false, true) => go!(true, true, false, false, true),
                (true, true, true, _, false) => go!(true, true, true, false, false),
                (true, true, true, _, true) => go!(true, true, true, false, true),
                (true, true, false, true, false) => go!(true, true, false, true, false),
                (true, true, false, true, true) => go!(true, true, false, true, true),
            }
        })
    };
    let mut total = Moved::default();
    let threads = workers;
    if threads > 1 && n > 2 * CHUNK {
        // Worker w of the step's team (`crate::team`) integrates the w-th of `threads`
        // contiguous runs of chunks, at every step: about the discs of its range in the
        // disc–disc pass. Each chunk's sums go to its own slot, added in chunk order.
        parts.clear();
        parts.resize(nchunks, Moved::default());
        let out = SyncPtr::of(parts);
        crate::team::run(threads, &|w| {
            for ch in w * nchunks / threads..(w + 1) * nchunks / threads {
                let m = run(ch);
                // SAFETY: chunk ch < nchunks = parts.len(), written by this part only.
                unsafe { *out.ptr().add(ch) = m };
            }
        });
        for m in parts.iter() {
            total.add(m);
        }
    } else {
        for ch in 0..nchunks {
            total.add(&run(ch));
        }
    }
    total
}

/// Sets each servo wall's velocity for the next step from the force and contact stiffness of
/// this one ([`crate::wall_servo`]); `thickness` the discs' t (m).
pub fn servo_walls(walls: &mut [crate::state::Wall], dt: f64, thickness: f64) {
    for w in walls {
        if let Some(s) = w.servo {
            w.v = s.velocity(w.force, w.stiffness, dt, thickness);
        }
    }
}

/// Move walls rigidly: rotate by ω dt about `center`, then translate by v dt.
pub fn advance_walls(walls: &mut [crate::state::Wall], dt: f64) {
    for w in walls {
        if w.omega != 0.0 {
            let (s, c) = (w.omega * dt).sin_cos();
            let center = w.center;
            for p in [&mut w.a, &mut w.b].into_iter().chain(w.via.iter_mut()) {
                let (rx, ry) = (p[0] - center[0], p[1] - center[1]);
                p[0] = center[0] + c * rx - s * ry;
                p[1] = center[1] + s * rx + c * ry;
            }
        }
        if w.v != [0.0, 0.0] {
            w.translate([w.v[0] * dt, w.v[1] * dt]);
        }
    }
}
