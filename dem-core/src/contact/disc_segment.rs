//! Disc–wall contacts against straight segments. A wall moves rigidly with velocity v and
//! angular velocity ω about its `center`; it is treated as a body of infinite mass and radius
//! (m* = m_disc, R* = r_disc), with the same laws and the same sign conventions as disc–disc
//! contacts where the wall plays disc j: n points from the disc centre to its closest point p
//! on the segment, the overlap is δ = r − |p − x|, and the relative velocity is that of the
//! wall material point at p, v_w = v + ω × (p − center), minus the disc's contact point
//! velocity. The wall records the force the discs exert on it, its moment about `center`,
//! and the work it does on the discs, W += −F·v_w Δt. Fixed discs do not touch walls.

use super::disc_disc::{Dashpot, PassEnergy};
use super::{ContactLaws, PairKin};
use crate::neighbors::{closest_on_wall, MinImage, WallPairs};
use crate::state::{Discs, Wall};

/// Add disc–wall forces to discs and record wall reactions (serial: walls are few and the
/// list is ordered by wall then disc, so sums are deterministic). When `track_energy` and
/// `dashpots` (some law has a dashpot, see [`super::disc_disc::Dashpot`]), the dashpot forces
/// on the discs are added to `dash` (zeroed by the disc–disc pass) and the dissipation's wall
/// part F_d · v_w Δt to the returned energy (the disc part −F_d · v̄ Δt is booked by the
/// integration pass: together −F_d · (v̄ − v_w) Δt).
#[allow(clippy::too_many_arguments)]
pub fn compute(
    d: &mut Discs,
    walls: &mut [Wall],
    wp: &mut WallPairs,
    minv: &[f64],
    laws: &ContactLaws,
    img: MinImage,
    dt: f64,
    track_energy: bool,
    dashpots: bool,
    dash: &mut Dashpot,
) -> PassEnergy {
    let dashpots = track_energy && dashpots;
    let mut e = PassEnergy::default();
    for w in walls.iter_mut() {
        w.force = [0.0; 2];
        w.moment = 0.0;
        w.stiffness = 0.0;
    }
    let rolling = laws.any_rolling();
    for q in 0..wp.wall.len() {
        let (wi, k) = (wp.wall[q] as usize, wp.disc[q] as usize);
        let w = &mut walls[wi];
        if minv[k] == 0.0 {
            continue;
        }
        let (x, y, r) = (d.x[k], d.y[k], d.r[k]);
        let (px, py, dist) = closest_on_wall(w, x, y, &img);
        let delta = r - dist;
        if dist <= 0.0 {
            wp.us[q] = 0.0;
            wp.mr[q] = 0.0;
            continue;
        }
        let (nx, ny) = ((px - x) / dist, (py - y) / dist);
        let (lx, ly) = img.delta(px - w.center[0], py - w.center[1]);
        let (vwx, vwy) = (w.v[0] - w.omega * ly, w.v[1] + w.omega * lx);
        let wr = d.omega[k] * r;
        let rvx = vwx - d.vx[k] + wr * ny;
        let rvy = vwy - d.vy[k] - wr * nx;
        let kin = PairKin {
            delta,
            vn: rvx * nx + rvy * ny,
            vt: rvy * nx - rvx * ny,
            m_eff: 1.0 / minv[k],
            r_eff: r,
            dt,
        };
        let (mi, mw) = (d.material[k], w.material);
        let model = laws.model(mi, mw);
        if delta <= 0.0 {
            // The contact opened: the spring histories are dropped and their elastic energy
            // (at the overlap of the last touching step, δ + v_n Δt) counts as friction
            // dissipation, as in the disc–disc pass.
            if track_energy && (wp.us[q] != 0.0 || wp.mr[q] != 0.0) {
                let d_prev = (delta + kin.vn * dt).max(0.0);
                e.fric += model.shear_energy(r, d_prev, wp.us[q]);
                if let Some(rr) = laws.rolling(mi, mw) {
                    let kr = rr.kr(model.kn(r, d_prev), r);
                    if kr > 0.0 {
                        e.fric += 0.5 * wp.mr[q] * wp.mr[q] / kr;
                    }
                }
            }
            wp.us[q] = 0.0;
            wp.mr[q] = 0.0;
            continue;
        }
        let o = if track_energy {
            model.force::<true>(&kin, &mut wp.us[q])
        } else {
            model.force::<false>(&kin, &mut wp.us[q])
        };
        let mut m_roll = 0.0;
        if rolling {
            if let Some(rr) = laws.rolling(mi, mw) {
                let kn = model.kn(r, delta);
                e.fric += rr.update(kn, r, o.f_n, d.omega[k] - w.omega, dt, &mut wp.mr[q]);
                m_roll = wp.mr[q];
            }
        }
        let fx = o.f_n * nx - o.f_t * ny;
        let fy = o.f_n * ny + o.f_t * nx;
        d.fx[k] -= fx;
        d.fy[k] -= fy;
        d.torque[k] += -r * o.f_t + m_roll;
        w.force[0] += fx;
        w.force[1] += fy;
        w.moment += lx * fy - ly * fx;
        if w.servo.is_some() {
            w.stiffness += model.kn(r, delta);
        }
        w.work += -(fx * vwx + fy * vwy) * dt;
        if track_energy {
            e.strain += o.e_strain;
            if dashpots {
                let (dwx, dwy) = (o.d_n * nx - o.d_t * ny, o.d_n * ny + o.d_t * nx);
                dash.fx[k] -= dwx;
                dash.fy[k] -= dwy;
                dash.t[k] += -r * o.d_t;
                e.damp -= (dwx * vwx + dwy * vwy) * dt;
            }
            e.fric += o.e_fric;
        }
    }
    e
}
