//! Central-difference (leapfrog) integration of free discs, PFC local damping, viscous
//! damping and gravity (Cundall & Strack 1979; Itasca PFC manual, "law of motion"):
//!
//! v(t+Δt/2) = v(t−Δt/2) + (F + F_d + F_v + m g)/m · Δt_kick,   x(t+Δt) = x(t) + v(t+Δt/2) Δt,
//!
//! with Δt_kick = (Δt_old + Δt)/2 (equal to Δt unless the step just changed), the local damping
//! F_d = −α |F + m g| sign(v) per component (Cundall 1987; Potyondy & Cundall 2004 eq. 4) and
//! the viscous F_v = −c v, c = 2ζ√(m K) (see [`crate::Params::viscous_damping`]); the same for
//! θ, ω with the torque and I. Fixed discs move with their prescribed velocity. Members of rigid
//! clumps are moved by [`crate::clump`]. Kinetic energy is reported at time t with the mean of
//! the two half-step velocities.

use crate::contact::disc_disc::CHUNK;
use crate::state::Discs;
use rayon::prelude::*;
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
    /// Work done by fixed (prescribed-velocity) discs on the others in this step (J).
    pub boundary_work: f64,
    /// Gravitational potential −Σ m g·x at time t (J).
    pub grav_pot: f64,
    /// Largest squared displacement since the last neighbour build.
    pub max_disp2: f64,
}

impl Moved {
    pub fn add(&mut self, o: &Moved) {
        self.ke_trans += o.ke_trans;
        self.ke_rot += o.ke_rot;
        self.damp += o.damp;
        self.boundary_work += o.boundary_work;
        self.grav_pot += o.grav_pot;
        self.max_disp2 = self.max_disp2.max(o.max_disp2);
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
}

#[derive(Clone, Copy)]
struct Ptr(*mut f64);
unsafe impl Send for Ptr {}
unsafe impl Sync for Ptr {}

/// The read-only disc arrays of the pass.
struct Ro<'a> {
    m: &'a [f64],
    inertia: &'a [f64],
    fx: &'a [f64],
    fy: &'a [f64],
    torque: &'a [f64],
    fixed: &'a [bool],
}

/// One chunk [lo, hi) of the disc pass.
///
/// # Safety
/// `p` points to the x, y, theta, vx, vy, omega arrays of length ≥ hi, and no other thread
/// touches indices in [lo, hi).
#[allow(clippy::too_many_arguments)]
unsafe fn chunk(
    p: &[Ptr; 6],
    d: &Ro,
    c: &DiscCache,
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    lo: usize,
    hi: usize,
) -> Moved {
    let mut o = Moved::default();
    let [gx, gy] = k.gravity;
    for i in lo..hi {
        let x = &mut *p[0].0.add(i);
        let y = &mut *p[1].0.add(i);
        let th = &mut *p[2].0.add(i);
        let vx = &mut *p[3].0.add(i);
        let vy = &mut *p[4].0.add(i);
        let w = &mut *p[5].0.add(i);
        let im = c.inv_m[i];
        if im > 0.0 {
            let m = d.m[i];
            let (mut fx, mut fy, mut t) = (d.fx[i] + m * gx, d.fy[i] + m * gy, d.torque[i]);
            let (fx0, fy0, t0) = (fx, fy, t);
            if k.alpha > 0.0 {
                fx -= k.alpha * fx.abs() * sgn(*vx);
                fy -= k.alpha * fy.abs() * sgn(*vy);
                t -= k.alpha * t.abs() * sgn(*w);
            }
            if !c.visc_t.is_empty() {
                fx -= c.visc_t[i] * *vx;
                fy -= c.visc_t[i] * *vy;
                t -= c.visc_r[i] * *w;
            }
            let (ux, uy, uw) = (*vx, *vy, *w);
            *vx += fx * im * k.kick;
            *vy += fy * im * k.kick;
            *w += t * c.inv_i[i] * k.kick;
            if k.track {
                let (ax, ay, aw) = (0.5 * (ux + *vx), 0.5 * (uy + *vy), 0.5 * (uw + *w));
                o.ke_trans += 0.5 * m * (ax * ax + ay * ay);
                o.ke_rot += 0.5 * d.inertia[i] * aw * aw;
                o.damp -= ((fx - fx0) * ax + (fy - fy0) * ay + (t - t0) * aw) * k.kick;
                o.grav_pot -= m * (gx * *x + gy * *y);
            }
        } else if d.fixed[i] {
            if k.track {
                o.boundary_work -= (d.fx[i] * *vx + d.fy[i] * *vy + d.torque[i] * *w) * k.drift;
            }
        } else {
            continue; // member of a rigid clump: moved by the clump pass
        }
        *x += *vx * k.drift;
        *y += *vy * k.drift;
        *th += *w * k.drift;
        let (dx, dy) = (*x - x0[i], *y - y0[i]);
        o.max_disp2 = o.max_disp2.max(dx * dx + dy * dy);
    }
    o
}

/// Integrate all free and fixed discs; chunked like the force pass so that the reported sums
/// do not depend on the thread count.
pub fn integrate_discs(
    d: &mut Discs,
    c: &DiscCache,
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    parts: &mut Vec<Moved>,
) -> Moved {
    let n = d.len();
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
        ..
    } = d;
    let p = [
        Ptr(x.as_mut_ptr()),
        Ptr(y.as_mut_ptr()),
        Ptr(theta.as_mut_ptr()),
        Ptr(vx.as_mut_ptr()),
        Ptr(vy.as_mut_ptr()),
        Ptr(omega.as_mut_ptr()),
    ];
    let dr = Ro {
        m,
        inertia,
        fx,
        fy,
        torque,
        fixed,
    };
    let dr = &dr;
    let nchunks = n.div_ceil(CHUNK);
    let run = |ch: usize| {
        let (lo, hi) = (ch * CHUNK, ((ch + 1) * CHUNK).min(n));
        // SAFETY: chunks are disjoint index ranges of the six arrays (length n) behind `p`,
        // which `dr` does not borrow.
        unsafe { chunk(&p, dr, c, x0, y0, k, lo, hi) }
    };
    let mut total = Moved::default();
    if rayon::current_num_threads() > 1 && n > 2 * CHUNK {
        (0..nchunks)
            .into_par_iter()
            .map(run)
            .collect_into_vec(parts);
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
