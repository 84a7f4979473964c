//! Narrow phase and laws: sphere–sphere and sphere–plane geometry → [`Kin`] → the law
//! (`GranularLaw::force_pair`, `roll`, `twist`) → forces and torques.
//!
//! Sphere pair (i, j), n = (x_j − x_i)/d, δ = r_i + r_j − d; arms to the contact point
//! a_i = r_i − δ/2, a_j = r_j − δ/2 (a_i + a_j = d); relative velocity of j's contact point
//! with respect to i's
//!
//! v_rel = v_j − v_i − (a_i ω_i + a_j ω_j) × n,  v_n = v_rel·n,  v_t = v_rel − v_n n,
//!
//! which vanishes for a rigid rotation of the pair (ω_i = ω_j = Ω, v = Ω × x). The shear
//! history is first rotated into the current tangent plane (`rotate_into`; Cundall & Strack
//! 1979, Géotechnique 29:47; the rule of LAMMPS `pair_style granular`). With the law's force
//! F = F_n n + F_t on j (−F on i): torques τ_i = −a_i n × F_t, τ_j = −a_j n × F_t; the
//! rolling moment M_r (on i, from ω_i − ω_j without its n part) and the twisting moment
//! M_tw n (on i, from (ω_i − ω_j)·n) act with opposite signs on j.

use crate::grid::Periodic;
use crate::walls::Plane;
use dem_laws::{ContactLaw, GranularHistory, GranularLaw, Kin, Out};
use nalgebra::Vector3;

pub(crate) type Hist = GranularHistory<Vector3<f64>>;

/// A listed pair and what it carries from step to step.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PairContact {
    pub i: u32,
    pub j: u32,
    pub h: Hist,
    /// Strain energy after the last evaluation (J), booked as dissipated if the contact
    /// breaks (what the springs hold is lost with it).
    pub e_prev: f64,
}

/// The result of one contact for the per-sphere reduction.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PairOut {
    /// Force on j (−f on i).
    pub f: Vector3<f64>,
    pub ti: Vector3<f64>,
    pub tj: Vector3<f64>,
    /// Dashpot parts (energy tracking).
    pub df: Vector3<f64>,
    pub dti: Vector3<f64>,
    pub dtj: Vector3<f64>,
    pub e_strain: f64,
    pub e_fric: f64,
    /// Overlap δ (m) and whether the law acts (for coordination numbers).
    pub delta: f64,
    pub active: bool,
}

/// The body-side kinematics of a contact.
pub(crate) struct Body {
    pub x: Vector3<f64>,
    pub v: Vector3<f64>,
    pub w: Vector3<f64>,
    pub r: f64,
    pub m: f64,
}

/// Shared evaluation of one contact with unit normal n (i → j), overlap δ, the relative
/// velocity and the arms; `r1, r2` for the Hamaker form.
#[allow(clippy::too_many_arguments)]
#[inline]
fn eval<const E: bool>(
    law: &GranularLaw,
    n: Vector3<f64>,
    delta: f64,
    v_rel: Vector3<f64>,
    w_rel: Vector3<f64>,
    (ai, aj): (f64, f64),
    (r1, r2, r_eff, m_eff): (f64, f64, f64, f64),
    dt: f64,
    h: &mut Hist,
) -> PairOut {
    h.rotate_into(n);
    let vn = v_rel.dot(&n);
    let k = Kin {
        delta,
        vn,
        vt: v_rel - n * vn,
        m_eff,
        r_eff,
        dt,
    };
    let o: Out<Vector3<f64>> = law.force_pair::<E, Vector3<f64>>(&k, r1, r2, h);
    let w_roll = w_rel - n * w_rel.dot(&n);
    let (m_r, d_r) = law.roll(&k, o.f_n, w_roll, h);
    let (m_tw, d_tw) = law.twist(&k, o.f_n, w_rel.dot(&n), h);
    let f = n * o.f_n + o.f_t;
    let nxt = n.cross(&o.f_t);
    let m_i = m_r + n * m_tw;
    let mut out = PairOut {
        f,
        ti: -nxt * ai + m_i,
        tj: -nxt * aj - m_i,
        delta,
        active: h.normal.touched || o.f_n != 0.0,
        ..Default::default()
    };
    if E {
        out.df = n * o.d_n + o.d_t;
        let nxd = n.cross(&o.d_t);
        out.dti = -nxd * ai;
        out.dtj = -nxd * aj;
        out.e_strain = o.e_strain;
        out.e_fric = o.e_fric + d_r + d_tw;
    }
    out
}

/// Sphere–sphere contact (module docs). `reach` is the law's largest reach: beyond it an
/// untouched pair is skipped.
#[inline]
#[allow(clippy::too_many_arguments)]
pub(crate) fn sphere_sphere<const E: bool>(
    law: &GranularLaw,
    reach: f64,
    per: &Periodic,
    a: &Body,
    b: &Body,
    dt: f64,
    c: &mut PairContact,
) -> (PairOut, f64) {
    let d = per.delta(b.x - a.x);
    let dist = d.norm();
    let delta = a.r + b.r - dist;
    let mut released = 0.0;
    if (delta <= -reach && !c.h.normal.touched) || dist == 0.0 {
        if E {
            released = c.e_prev;
        }
        c.h = Hist::default();
        c.e_prev = 0.0;
        return (
            PairOut {
                delta,
                ..Default::default()
            },
            released,
        );
    }
    let n = d / dist;
    let (ai, aj) = (a.r - 0.5 * delta, b.r - 0.5 * delta);
    let v_rel = b.v - a.v - (a.w * ai + b.w * aj).cross(&n);
    let r_eff = a.r * b.r / (a.r + b.r);
    let m_eff = a.m * b.m / (a.m + b.m);
    let was = c.h.normal.touched;
    let out = eval::<E>(
        law,
        n,
        delta,
        v_rel,
        a.w - b.w,
        (ai, aj),
        (a.r, b.r, r_eff, m_eff),
        dt,
        &mut c.h,
    );
    if E {
        if was && !c.h.normal.touched {
            released = c.e_prev - out.e_strain;
        }
        c.e_prev = out.e_strain;
    }
    (out, released)
}

/// Sphere–plane contact (the wall is body i; [`crate::walls`]). Returns the output (force,
/// torque `tj` on the sphere) and the released energy.
#[inline]
pub(crate) fn sphere_plane<const E: bool>(
    law: &GranularLaw,
    reach: f64,
    p: &Plane,
    s: &Body,
    dt: f64,
    h: &mut Hist,
    e_prev: &mut f64,
) -> (PairOut, f64) {
    let delta = s.r - p.gap(&s.x);
    let mut released = 0.0;
    if delta <= -reach && !h.normal.touched {
        if E {
            released = *e_prev;
        }
        *h = Hist::default();
        *e_prev = 0.0;
        return (
            PairOut {
                delta,
                ..Default::default()
            },
            released,
        );
    }
    let n = p.normal;
    let aj = s.r - 0.5 * delta;
    let v_rel = s.v - p.velocity - s.w.cross(&n) * aj;
    let was = h.normal.touched;
    let out = eval::<E>(
        law,
        n,
        delta,
        v_rel,
        -s.w,
        (0.0, aj),
        (s.r, 1e9 * s.r, s.r, s.m),
        dt,
        h,
    );
    if E {
        if was && !h.normal.touched {
            released = *e_prev - out.e_strain;
        }
        *e_prev = out.e_strain;
    }
    (out, released)
}

/// Time scale √(m*/k) of a contact of effective mass `m_eff` and radius `r_eff` at overlap
/// `delta`, k the larger of the law's normal and tangential stiffness (∞ stiffness: 0).
pub fn contact_time_scale(law: &GranularLaw, m_eff: f64, r_eff: f64, delta: f64) -> f64 {
    let kn = <GranularLaw as ContactLaw<Vector3<f64>>>::kn(law, r_eff, delta);
    let ks = <GranularLaw as ContactLaw<Vector3<f64>>>::ks(law, r_eff, delta);
    let k = kn.max(ks);
    if k > 0.0 {
        (m_eff / k).sqrt()
    } else {
        f64::INFINITY
    }
}

/// The law's reach for effective radius `r_eff` (ContactLaw::reach).
pub(crate) fn reach(law: &GranularLaw, r_eff: f64) -> f64 {
    <GranularLaw as ContactLaw<Vector3<f64>>>::reach(law, r_eff)
}
