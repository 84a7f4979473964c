//! Rigid clumps (ORC, Ashmawy et al. 2003 / PFC `clump`): one rigid body whose members are
//! discs at fixed body-frame offsets.
//!
//! Mass properties. [`add_rigid_clump`] uses the template's own mass properties,
//! `template.achieved`: for an `orc` template these are the classic ORC sums (member masses
//! ρtπr² with overlaps counted twice, their centroid and inertia); for an `improved` template
//! they equal the grain's (mass, centroid and inertia fitted by Ye & Xu 2010), which is also
//! `template.target`. So the clump moves exactly as the template says it does. To impose other
//! properties (e.g. the grain's `target` on an ORC template), use [`add_rigid_clump_props`].
//! Member masses (ρtπr² or the fitted masses) are kept on the member discs only for contact
//! damping. All masses scale with `State::thickness / template.thickness`.
//!
//! Dynamics (per step, after all forces are known): F_c = Σ F_m, T_c = Σ (T_m + r_m × F_m)
//! with r_m = R(θ_c) offset_m; the clump is integrated like a disc (central difference, local
//! and viscous damping, gravity); members are then placed at x_c + R(θ_c) offset_m with the
//! rigid-body velocity v_c + ω_c × r_m and ω_m = ω_c.

pub mod orc;

use crate::integrate::{sgn, Kick};
use crate::state::{State, FREE};
use clumpgen::template::{MassProps, Template};

/// Bad clump input.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ClumpError {
    #[error("template {id}: {reason}")]
    Template { id: String, reason: String },
    #[error("state thickness must be positive and finite, got {0}")]
    Thickness(f64),
}

/// Add a rigid clump of `template` with its grain centroid (template origin) at (x, y), rotated
/// by `angle` (rad), members of `material`; mass properties `template.achieved` (see module
/// docs). Returns the clump index.
pub fn add_rigid_clump(
    st: &mut State,
    template: &Template,
    x: f64,
    y: f64,
    angle: f64,
    material: u16,
) -> Result<usize, ClumpError> {
    add_rigid_clump_props(st, template, x, y, angle, material, &template.achieved)
}

/// As [`add_rigid_clump`] with explicit mass properties (in the template frame and thickness).
pub fn add_rigid_clump_props(
    st: &mut State,
    template: &Template,
    x: f64,
    y: f64,
    angle: f64,
    material: u16,
    props: &MassProps,
) -> Result<usize, ClumpError> {
    let bad = |reason: String| ClumpError::Template {
        id: template.id.clone(),
        reason,
    };
    if !(st.thickness > 0.0 && st.thickness.is_finite()) {
        return Err(ClumpError::Thickness(st.thickness));
    }
    if template.discs.is_empty() {
        return Err(bad("no discs".into()));
    }
    if !(template.thickness > 0.0 && template.thickness.is_finite()) {
        return Err(bad(format!("thickness {}", template.thickness)));
    }
    let scale = st.thickness / template.thickness;
    let (m, inertia) = (props.mass * scale, props.inertia_own * scale);
    if !(m > 0.0 && m.is_finite() && inertia > 0.0 && inertia.is_finite()) {
        return Err(bad(format!("mass {m} kg, inertia {inertia} kg m^2")));
    }
    for (k, d) in template.discs.iter().enumerate() {
        if !(d.r > 0.0 && d.r.is_finite() && d.m > 0.0 && d.x.is_finite() && d.y.is_finite()) {
            return Err(bad(format!("disc {k} has r = {}, m = {}", d.r, d.m)));
        }
    }
    let (s, c) = angle.sin_cos();
    let [gx, gy] = props.centroid;
    let cl = &mut st.clumps;
    let ci = cl.len();
    if cl.member_start.is_empty() {
        cl.member_start.push(0);
    }
    cl.x.push(x + c * gx - s * gy);
    cl.y.push(y + s * gx + c * gy);
    cl.theta.push(angle);
    cl.vx.push(0.0);
    cl.vy.push(0.0);
    cl.omega.push(0.0);
    cl.m.push(m);
    cl.inertia.push(inertia);
    cl.fx.push(0.0);
    cl.fy.push(0.0);
    cl.torque.push(0.0);
    cl.template.push(template.id.clone());
    let (xc, yc) = (cl.x[ci], cl.y[ci]);
    for d in &template.discs {
        let (ox, oy) = (d.x - gx, d.y - gy);
        let mm = d.m * scale;
        let k = st.discs.push(
            xc + c * ox - s * oy,
            yc + s * ox + c * oy,
            d.r,
            mm,
            0.5 * mm * d.r * d.r,
            material,
            ci as u32,
        );
        st.discs.theta[k] = angle;
        st.discs.body[k] = ci as u32;
        let id = st.discs.id[k];
        let cl = &mut st.clumps;
        cl.members.push(id);
        cl.offset_x.push(ox);
        cl.offset_y.push(oy);
    }
    let len = st.clumps.members.len() as u32;
    st.clumps.member_start.push(len);
    Ok(ci)
}

/// Energies and displacement reported by the clump pass (see [`crate::integrate::Moved`]).
pub use crate::integrate::Moved;

/// `(θ, sin θ, cos θ)` of each clump's angle after the last clump pass, so that the next pass
/// does not evaluate `sin_cos` of the same angle again (it is a pure function: the cached
/// values are the bits a new call would return). An entry is used only when the clump's angle
/// has exactly the cached bits; `None` or a stale entry is recomputed.
pub type TrigCache = Vec<Option<[f64; 3]>>;

/// Gather member forces to the clumps, integrate the clumps and place their members.
/// `index_of_id` maps disc ids to current indices; `visc` are the clumps' viscous
/// coefficients (translation, rotation) or empty; `rel` the clumps' local damping force and
/// torque in the fragment frame ([`crate::damping`]) or empty; `trig` is the clumps'
/// [`TrigCache`] (resized as needed).
#[allow(clippy::too_many_arguments)]
pub fn step_clumps(
    st: &mut State,
    index_of_id: &[u32],
    dash: &crate::contact::disc_disc::Dashpot,
    visc: &[[f64; 2]],
    rel: &[[f64; 3]],
    x0: &[f64],
    y0: &[f64],
    k: &Kick,
    trig: &mut TrigCache,
) -> Moved {
    let mut o = Moved::default();
    let [gx, gy] = k.gravity;
    let (cl, d) = (&mut st.clumps, &mut st.discs);
    trig.resize(cl.len(), None);
    for (c, tc) in trig.iter_mut().enumerate() {
        let (s, co) = match *tc {
            Some([th, s, co]) if th.to_bits() == cl.theta[c].to_bits() => (s, co),
            _ => cl.theta[c].sin_cos(),
        };
        let (mut fx, mut fy, mut t) = (0.0, 0.0, 0.0);
        let (mut dfx, mut dfy, mut dt) = (0.0, 0.0, 0.0);
        for q in cl.member_range(c) {
            let i = index_of_id[cl.members[q] as usize] as usize;
            let (rx, ry) = (
                co * cl.offset_x[q] - s * cl.offset_y[q],
                s * cl.offset_x[q] + co * cl.offset_y[q],
            );
            fx += d.fx[i];
            fy += d.fy[i];
            t += d.torque[i] + rx * d.fy[i] - ry * d.fx[i];
            if k.track && k.dash {
                let (a, b) = (dash.fx[i], dash.fy[i]);
                dfx += a;
                dfy += b;
                dt += dash.t[i] + rx * b - ry * a;
            }
        }
        let m = cl.m[c];
        fx += m * gx;
        fy += m * gy;
        cl.fx[c] = fx;
        cl.fy[c] = fy;
        cl.torque[c] = t;
        let (fx0, fy0, t0) = (fx, fy, t);
        let (ux, uy, uw) = (cl.vx[c], cl.vy[c], cl.omega[c]);
        if k.alpha > 0.0 {
            fx -= k.alpha * fx.abs() * sgn(ux);
            fy -= k.alpha * fy.abs() * sgn(uy);
            t -= k.alpha * t.abs() * sgn(uw);
        }
        if let Some(r) = rel.get(c) {
            fx += r[0];
            fy += r[1];
            t += r[2];
        }
        if let Some(v) = visc.get(c) {
            fx -= v[0] * ux;
            fy -= v[0] * uy;
            t -= v[1] * uw;
        }
        cl.vx[c] += fx / m * k.kick;
        cl.vy[c] += fy / m * k.kick;
        cl.omega[c] += t / cl.inertia[c] * k.kick;
        if k.track {
            let (ax, ay, aw) = (
                0.5 * (ux + cl.vx[c]),
                0.5 * (uy + cl.vy[c]),
                0.5 * (uw + cl.omega[c]),
            );
            o.ke_trans += 0.5 * m * (ax * ax + ay * ay);
            o.ke_rot += 0.5 * cl.inertia[c] * aw * aw;
            o.damp -= ((fx - fx0) * ax + (fy - fy0) * ay + (t - t0) * aw) * k.kick;
            if k.dash {
                o.damp_contact -= (dfx * ax + dfy * ay + dt * aw) * k.kick;
            }
            o.grav_pot -= m * (gx * cl.x[c] + gy * cl.y[c]);
        }
        cl.x[c] += cl.vx[c] * k.drift;
        cl.y[c] += cl.vy[c] * k.drift;
        cl.theta[c] += cl.omega[c] * k.drift;
        let (s, co) = cl.theta[c].sin_cos();
        *tc = Some([cl.theta[c], s, co]);
        let w = cl.omega[c];
        for q in cl.member_range(c) {
            let i = index_of_id[cl.members[q] as usize] as usize;
            let (rx, ry) = (
                co * cl.offset_x[q] - s * cl.offset_y[q],
                s * cl.offset_x[q] + co * cl.offset_y[q],
            );
            d.x[i] = cl.x[c] + rx;
            d.y[i] = cl.y[c] + ry;
            d.theta[i] = cl.theta[c];
            d.vx[i] = cl.vx[c] - w * ry;
            d.vy[i] = cl.vy[c] + w * rx;
            d.omega[i] = w;
            if let (Some(&a), Some(&b)) = (x0.get(i), y0.get(i)) {
                let (dx, dy) = (d.x[i] - a, d.y[i] - b);
                o.exceeded |= dx * dx + dy * dy > k.disp2_limit;
            }
        }
    }
    o
}

/// Place every clump's members at the clump pose (used after wrapping periodic positions).
pub fn place_members(st: &mut State, index_of_id: &[u32]) {
    let (cl, d) = (&st.clumps, &mut st.discs);
    for c in 0..cl.len() {
        let (s, co) = cl.theta[c].sin_cos();
        for q in cl.member_range(c) {
            let i = index_of_id[cl.members[q] as usize] as usize;
            d.x[i] = cl.x[c] + co * cl.offset_x[q] - s * cl.offset_y[q];
            d.y[i] = cl.y[c] + s * cl.offset_x[q] + co * cl.offset_y[q];
        }
    }
}

/// Whether disc `i` is a member of a rigid clump.
#[inline]
pub fn is_member(st: &State, i: usize) -> bool {
    st.discs.body[i] != FREE
}
