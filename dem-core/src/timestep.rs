//! Automatic time step (PFC-style, Itasca PFC manual "timestep determination"; Potyondy &
//! Cundall 2004 §2.2):
//!
//! Δt_crit = min over integrated bodies of √(m/K_trans) and √(I/K_rot), Δt = f · Δt_crit.
//!
//! K_trans of a disc sums max(k_n, k_s) over all *listed* pairs (every partner within the skin,
//! touching or not, so a contact closing between two rebuilds cannot make the step too large),
//! its wall pairs and its bonds ([`crate::bond::Bonds::add_stiffness`]); K_rot sums k_s r² plus
//! rolling and bond bending stiffnesses. It is floored by the stiffest single contact the disc's
//! material can make (so an isolated disc still gets a finite step). Hertz stiffnesses are the
//! tangent 2E*√(R*δ) at δ = max(current overlap, [`crate::Params::hertz_reference_overlap`]·R*).
//! A rigid clump sums its members: K = Σ K_m, K_rot = Σ (K_rot,m + K_m |r_m|²).
//! The estimate is recomputed at every neighbour rebuild; the step follows it down at once and
//! up only when the estimate exceeds the step by [`crate::pipeline::DT_RAISE`] (a step that
//! flips at every rebuild costs energy accuracy). The factor f is
//! [`crate::Params::dt_factor`].

use crate::bond::Bonds;
use crate::contact::ContactLaws;
use crate::integrate::DiscCache;
use crate::neighbors::{closest_on_segment, MinImage, Neighbors};
use crate::params::Params;
use crate::state::State;

/// Fill `cache.k_trans` and `cache.k_rot` for every disc.
pub fn disc_stiffness(
    st: &State,
    nb: &Neighbors,
    laws: &ContactLaws,
    params: &Params,
    bonds: Option<&Bonds>,
    cache: &mut DiscCache,
) {
    let d = &st.discs;
    let n = d.len();
    let href = params.hertz_reference_overlap;
    let img = MinImage::new(&st.periodic);
    cache.k_trans.clear();
    cache.k_trans.resize(n, 0.0);
    cache.k_rot.clear();
    cache.k_rot.resize(n, 0.0);
    let (kt, kr) = (&mut cache.k_trans, &mut cache.k_rot);
    let pair_k = |mi: u16, mj: u16, r_eff: f64, overlap: f64| -> (f64, f64, f64) {
        let model = laws.model(mi, mj);
        let delta = overlap.max(href * r_eff);
        let (kn, ks) = (model.kn(r_eff, delta), model.ks(r_eff, delta));
        let krr = laws.rolling(mi, mj).map_or(0.0, |r| r.kr(kn, r_eff));
        (kn.max(ks), ks, krr)
    };
    for i in 0..n {
        for p in nb.start[i] as usize..nb.start[i + 1] as usize {
            let j = nb.nbr[p] as usize;
            let (dx, dy) = img.delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
            let g0 = nb.g0.get(p).copied().unwrap_or(0.0);
            let overlap = (d.r[i] + d.r[j] + g0 - (dx * dx + dy * dy).sqrt()).max(0.0);
            let r_eff = d.r[i] * d.r[j] / (d.r[i] + d.r[j]);
            let (k, ks, krr) = pair_k(d.material[i], d.material[j], r_eff, overlap);
            kt[i] += k;
            kt[j] += k;
            kr[i] += ks * d.r[i] * d.r[i] + krr;
            kr[j] += ks * d.r[j] * d.r[j] + krr;
        }
    }
    for q in 0..nb.walls.wall.len() {
        let (w, i) = (
            &st.walls[nb.walls.wall[q] as usize],
            nb.walls.disc[q] as usize,
        );
        let (_, _, dist) = closest_on_segment(w, d.x[i], d.y[i], &img);
        let (k, ks, krr) = pair_k(d.material[i], w.material, d.r[i], (d.r[i] - dist).max(0.0));
        kt[i] += k;
        kr[i] += ks * d.r[i] * d.r[i] + krr;
    }
    if let Some(b) = bonds {
        b.add_stiffness(st, kt, kr);
    }
    // Floor: the stiffest single contact the material can make (partner of any material or a
    // wall, R* up to the disc's own radius).
    let nm = laws.n_materials() as u16;
    for i in 0..n {
        let (mut fk, mut fr) = (0.0f64, 0.0f64);
        for b in 0..nm {
            let (k, ks, krr) = pair_k(d.material[i], b, d.r[i], 0.0);
            fk = fk.max(k);
            fr = fr.max(ks * d.r[i] * d.r[i] + krr);
        }
        kt[i] = kt[i].max(fk);
        kr[i] = kr[i].max(fr);
    }
}

/// Δt_crit (without the safety factor) from the stiffness sums; `None` when no integrated body
/// has a stiffness.
pub fn critical_dt(st: &State, cache: &DiscCache, index_of_id: &[u32]) -> Option<f64> {
    let d = &st.discs;
    let mut dt = f64::INFINITY;
    let mut bound = |m: f64, k: f64| {
        if k > 0.0 && m > 0.0 {
            dt = dt.min((m / k).sqrt());
        }
    };
    for i in 0..d.len() {
        if cache.inv_m[i] > 0.0 {
            bound(d.m[i], cache.k_trans[i]);
            bound(d.inertia[i], cache.k_rot[i]);
        }
    }
    let cl = &st.clumps;
    for c in 0..cl.len() {
        let (s, co) = cl.theta[c].sin_cos();
        let (mut k, mut kr) = (0.0, 0.0);
        for q in cl.member_range(c) {
            let i = index_of_id[cl.members[q] as usize] as usize;
            let rx = co * cl.offset_x[q] - s * cl.offset_y[q];
            let ry = s * cl.offset_x[q] + co * cl.offset_y[q];
            k += cache.k_trans[i];
            kr += cache.k_rot[i] + cache.k_trans[i] * (rx * rx + ry * ry);
        }
        bound(cl.m[c], k);
        bound(cl.inertia[c], kr);
    }
    dt.is_finite().then_some(dt)
}

/// Clump stiffness sums (translation, rotation), for viscous damping.
pub fn clump_stiffness(st: &State, cache: &DiscCache, index_of_id: &[u32]) -> Vec<[f64; 2]> {
    let cl = &st.clumps;
    (0..cl.len())
        .map(|c| {
            let (s, co) = cl.theta[c].sin_cos();
            let (mut k, mut kr) = (0.0, 0.0);
            for q in cl.member_range(c) {
                let i = index_of_id[cl.members[q] as usize] as usize;
                let rx = co * cl.offset_x[q] - s * cl.offset_y[q];
                let ry = s * cl.offset_x[q] + co * cl.offset_y[q];
                k += cache.k_trans[i];
                kr += cache.k_rot[i] + cache.k_trans[i] * (rx * rx + ry * ry);
            }
            [k, kr]
        })
        .collect()
}
