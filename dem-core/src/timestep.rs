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
use crate::neighbors::{closest_on_wall, MinImage, Neighbors};
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
        let (_, _, dist) = closest_on_wall(w, d.x[i], d.y[i], &img);
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

/// One body's time-step bound, from the last estimate (see [`critical_dt`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DtBound {
    /// Disc index (for a clump: its first member's index).
    pub disc: usize,
    /// Clump index when the bound is a rigid clump's.
    pub clump: Option<usize>,
    /// `true` for √(I/K_rot), `false` for √(m/K_trans).
    pub rotational: bool,
    /// Mass (kg) or moment of inertia (kg m²).
    pub inertia: f64,
    /// Stiffness sum (N/m or N m/rad).
    pub stiffness: f64,
    /// √(inertia / stiffness) (s).
    pub dt: f64,
}

/// Every integrated body's translational and rotational bound, smallest first: which discs
/// (or clumps) set the step, and whether by their mass or their inertia.
pub fn bounds(st: &State, cache: &DiscCache, index_of_id: &[u32]) -> Vec<DtBound> {
    let d = &st.discs;
    let mut out = Vec::new();
    let mut push = |disc, clump, rotational, m: f64, k: f64| {
        if k > 0.0 && m > 0.0 {
            out.push(DtBound {
                disc,
                clump,
                rotational,
                inertia: m,
                stiffness: k,
                dt: (m / k).sqrt(),
            });
        }
    };
    for i in 0..d.len() {
        if cache.inv_m[i] > 0.0 {
            push(i, None, false, d.m[i], cache.k_trans[i]);
            push(i, None, true, d.inertia[i], cache.k_rot[i]);
        }
    }
    let cl = &st.clumps;
    let k = clump_stiffness(st, cache, index_of_id);
    for (c, [kt, kr]) in k.into_iter().enumerate() {
        let first = cl
            .member_range(c)
            .next()
            .map_or(0, |q| index_of_id[cl.members[q] as usize] as usize);
        push(first, Some(c), false, cl.m[c], kt);
        push(first, Some(c), true, cl.inertia[c], kr);
    }
    out.sort_by(|a, b| a.dt.total_cmp(&b.dt));
    out
}

#[cfg(test)]
mod tests {
    use crate::contact::{LinearSpringDashpot, NormalDamping};
    use crate::{ContactLaws, ContactModel, Params, State, World};

    /// Two touching discs, one 4× lighter (half the radius): the lighter one sets the step,
    /// its translational bound is √(m/k_n) with the one contact, and the smallest bound is the
    /// world's critical step.
    #[test]
    fn bounds_name_the_lightest_disc_and_match_the_critical_step() {
        let mut st = State::default();
        st.discs.push_uniform(0.0, 0.0, 0.01, 2500.0, 1.0, 0);
        st.discs.push_uniform(0.0149, 0.0, 0.005, 2500.0, 1.0, 0);
        let kn = 1e6;
        let law = LinearSpringDashpot {
            kn,
            ks: 0.0,
            damping: NormalDamping::from_restitution(1.0),
            shear_damping: 0.0,
            mu: 0.0,
        };
        let mut w = World::new(
            st,
            Params::default(),
            ContactLaws::uniform(ContactModel::Linear(law)),
        );
        w.refresh();
        let b = w.dt_bounds();
        assert!(b.windows(2).all(|p| p[0].dt <= p[1].dt), "sorted");
        assert_eq!((b[0].disc, b[0].rotational, b[0].clump), (1, false, None));
        let m = w.state.discs.m[1];
        assert!((b[0].dt - (m / kn).sqrt()).abs() < 1e-12 * b[0].dt);
        assert_eq!(b[0].dt, w.critical_dt());
    }
}
