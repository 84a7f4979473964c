//! The uniform linear spring-dashpot law (Cundall & Strack 1979, see
//! [`super::linear_spring_dashpot`]) over four pairs at a time in AVX2 registers: the packed
//! records of the two discs of each pair are loaded and transposed ([`super::kernel`]'s
//! gather), the law is evaluated on the vectors, and only the four force columns (f_x, f_y
//! and the torques on i and j) are stored for the scatter. The kernel's general path stores
//! the gathered columns to a scratch block, evaluates the law over the block and stores the
//! forces; this path skips the gathered columns' round trip through memory (about 20 of the
//! ~230 instructions per disc-step of the dense benchmark lattice).
//!
//! Taken by the force pass (`kernel::block`) for a uniform linear law without energy tracking
//! and without reference gaps, on the AVX2 path. Every operation is the one the general path
//! performs (the same IEEE operations in the same order: `kernel::eval` with
//! [`super::LinearSpringDashpot::force_cn`]), so the results are the same bits; the tests
//! compare it with the portable path.

use super::kernel::{at, Ctx, PairHook, PairLaw, Scratch};
#[cfg(target_arch = "x86_64")]
use crate::lanes::F64x4;
use crate::lanes::{pair_columns, Packed, PAIR_BLOCK};

/// The parameters of a uniform linear law, as the four-lane kernel needs them.
#[derive(Clone, Copy, Debug)]
pub struct Linear4 {
    pub kn: f64,
    pub ks: f64,
    /// c_t / c_n.
    pub shear_damping: f64,
    pub mu: f64,
    /// c_n = γ m* (`false`) or 2ζ√(m* k_n) (`true`), with this γ or ζ.
    pub ratio: bool,
    pub c: f64,
}

impl Linear4 {
    /// The parameters of `law` with c_n = γ m* (`ratio` false, `c` = γ) or 2ζ√(m* k_n)
    /// (`ratio`, `c` = ζ).
    pub fn new(law: &super::LinearSpringDashpot, ratio: bool, c: f64) -> Linear4 {
        Linear4 {
            kn: law.kn,
            ks: law.ks,
            shear_damping: law.shear_damping,
            mu: law.mu,
            ratio,
            c,
        }
    }
}

/// Four-lane blocks evaluated (tests: the path really runs).
#[cfg(test)]
pub(crate) static BLOCKS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Gather, evaluate and store the forces of pairs p0..p0 + q (q ≤ [`PAIR_BLOCK`]) into the scratch
/// columns `fx, fy, ti, tj` (entries 0..q; the entries of the last group's unused lanes get
/// finite values, ignored as every entry ≥ q is); the tangential histories `us` (the q pairs'
/// slots) are updated in place. `gi` is left at the disc of the last pair (as the general
/// gather leaves it).
///
/// # Safety
/// The CPU must support AVX2; `pk` must hold the record of every disc and the list must be
/// valid (see `kernel::at`).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn block<
    L: PairLaw,
    H: PairHook,
    const PER: bool,
    const RATIO: bool,
    const E: bool,
    const G0: bool,
    const FUSED: bool,
>(
    c: &Ctx<L, H>,
    lin: &Linear4,
    pk: &[Packed],
    p0: usize,
    q: usize,
    gi: &mut usize,
    us: &mut [f64],
    s: &mut Scratch,
) {
    assert!(q <= PAIR_BLOCK && us.len() == q && c.owner.len() == c.nbr.len());
    #[cfg(test)]
    BLOCKS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    assert!(pk.len() + 1 == c.start.len());
    let base = pk.as_ptr();
    let set = |v| F64x4::splat(v);
    let [lx, hx, ly, hy] = c.img.parts();
    let (lx, hx, nhx, ly, hy, nhy) = (set(lx), set(hx), set(-hx), set(ly), set(hy), set(-hy));
    let (zero, one, half) = (F64x4::zero(), set(1.0), set(0.5));
    let sign = set(-0.0);
    let (kn, nks, sd, mu, cc, dt) = (
        set(lin.kn),
        set(-lin.ks),
        set(lin.shear_damping),
        set(lin.mu),
        set(if RATIO { 2.0 * lin.c } else { lin.c }),
        set(c.dt),
    );
    // 1/k_s, as `force_cn` forms it.
    let inv_ks = set(if lin.ks > 0.0 { 1.0 / lin.ks } else { 0.0 });
    // ½k_n, ½k_s of the energies (`force_cn`, `released`; halving is exact).
    let (hkn, hks) = (set(0.5 * lin.kn), set(0.5 * lin.ks));
    // SAFETY (history accesses): a group reads and writes entries k..k + m, k + m <= q.
    let usp = us.as_mut_ptr();
    // One group: scratch entries k..k + 4, of which the first m are pairs with discs ii, jj.
    // (A macro, not a closure: expanded at both call sites, so always inlined.)
    macro_rules! group {
        ($k:expr, $m:expr, $ii:expr, $jj:expr, $pp:expr) => {{
            let (k, m, ii, jj): (usize, usize, [usize; 4], [usize; 4]) = ($k, $m, $ii, $jj);
            let pp: [usize; 4] = $pp;
            // SAFETY (record loads): every disc index comes from the valid list (< n =
            // pk.len()).
            let (dv, ci, cj) = pair_columns(base, ii, jj);
            let ([dx, dy, dvx, dvy], [wi, ri, mi], [wj, rj, mj]) =
                (dv.map(F64x4), ci.map(F64x4), cj.map(F64x4));
            let ms = mi + mj;
            // Minimum image (`MinImage::delta_select`).
            let (dx, dy) = if PER {
                let (ax, bx) = (dx - lx, dx + lx);
                let (ay, by) = (dy - ly, dy + ly);
                (
                    dx.gt(hx).select(ax, dx.lt(nhx).select(bx, dx)),
                    dy.gt(hy).select(ay, dy.lt(nhy).select(by, dy)),
                )
            } else {
                (dx, dy)
            };
            // `kernel::eval`.
            let d2 = dx * dx + dy * dy;
            let rc = ri + rj;
            // The reach r_i + r_j + g₀ with reference gaps (the general gather's `reach`); the
            // arms stay on the geometric overlap (`eval`'s h).
            let reach = if G0 {
                let g = pp.map(|p| at!(c.g0, p));
                rc + F64x4::load(g.as_ptr())
            } else {
                rc
            };
            let touch = d2.lt(reach * reach) & reach.gt(zero) & ms.gt(zero);
            let dd = d2.sqrt();
            let inv = one / dd;
            let (nx, ny) = (dx * inv, dy * inv);
            let h = half * (rc - dd);
            let (ai, aj) = (ri - h, rj - h);
            let wr = (wi * ri + wj * rj) - h * (wi + wj);
            let rvx = dvx + wr * ny;
            let rvy = dvy - wr * nx;
            let delta = reach - dd;
            let vn = rvx * nx + rvy * ny;
            let vt = rvy * nx - rvx * ny;
            let m_eff = one / ms;
            // `LinearGamma` / `LinearRatio`: c_n = γ m* or (2ζ) √(m* k_n).
            let cn = if RATIO {
                cc * (m_eff * kn).sqrt()
            } else {
                cc * m_eff
            };
            // `LinearSpringDashpot::force_cn`.
            let ct = sd * cn;
            let f_n = kn * delta - cn * vn;
            // The histories of the group's pairs (a partial group reads and writes a copy).
            let up = usp.add(k);
            let mut u = [0.0; 4];
            let u0 = if m == 4 {
                // SAFETY: k + 4 <= q = us.len().
                F64x4::load(up)
            } else {
                for (l, v) in u.iter_mut().enumerate().take(m) {
                    *v = *up.add(l);
                }
                F64x4::load(u.as_ptr())
            };
            let ctvt = ct * vt;
            let us1 = u0 + vt * dt;
            let ft0 = nks * us1 - ctvt;
            let f_max = mu * f_n.max(zero);
            // |f_t⁰| > f_max; the slipping force is f_max with f_t⁰'s sign.
            let slip = sign.andnot(ft0).gt(f_max);
            let ft_s = sign.andnot(f_max) | (sign & ft0);
            let us_s = ((ft_s + ctvt) ^ sign) * inv_ks;
            let f_t = slip.select(ft_s, ft0);
            let u1 = slip.select(us_s, us1);
            // SAFETY (scratch stores): k < q <= PAIR_BLOCK and k, PAIR_BLOCK are multiples of 4.
            let st = |a: &mut [f64; PAIR_BLOCK], v: F64x4| v.store(a.as_mut_ptr().add(k));
            if E {
                // `force_cn`'s energies: strain ½k_nδ² + ½k_s u², slip work
                // ½k_s (u⁰ + u_slip)(u¹ − u_slip); a pair that opens releases ½k_s (u⁰)²
                // (`released`); then `eval`'s selects (and its + 0 of the rolling terms).
                let e_fric = slip.select(hks * (u0 + us_s) * (us1 - us_s), zero);
                let e_strain = hkn * delta * delta + hks * u1 * u1;
                let released = hks * u0 * u0;
                st(&mut s.es, touch & (e_strain + zero));
                st(&mut s.ef, touch.select(e_fric + zero, released));
            }
            // Back in `eval`: a pair not touching drops its history and gives no force.
            let u1 = touch & u1;
            if m == 4 {
                u1.store(up);
            } else {
                u1.store(u.as_mut_ptr());
                for (l, v) in u.iter().enumerate().take(m) {
                    *up.add(l) = *v;
                }
            }
            let fx = f_n * nx - f_t * ny;
            let fy = f_n * ny + f_t * nx;
            // −a_i f_t + 0 (the rolling moment, none) and −a_j f_t − 0.
            let ti = (ai ^ sign) * f_t + zero;
            let tj = (aj ^ sign) * f_t;
            let (fx, fy, ti, tj) = (touch & fx, touch & fy, touch & ti, touch & tj);
            let (fx, fy, ti, tj) = match (FUSED, c.hook) {
                (true, Some(h)) => {
                    // The per-pair hook (the pairs' parallel bonds, `bond::fused`), from this
                    // geometry.
                    let g = [dd, rc, nx, ny, ai, aj, vt, wi, wj];
                    let mut f = [fx, fy, ti, tj];
                    // SAFETY: AVX2 (this function's contract); k + m <= q, pairs p0..p0 + q
                    // exist.
                    h.four(p0 + k, m, g, c.dt, &mut f);
                    f.into()
                }
                _ => (fx, fy, ti, tj),
            };
            st(&mut s.fx, fx);
            st(&mut s.fy, fy);
            st(&mut s.ti, ti);
            st(&mut s.tj, tj);
        }};
    }
    let mut k = 0;
    while k + 4 <= q {
        let p = p0 + k;
        let ii = std::array::from_fn(|l| at!(c.owner, p + l) as usize);
        let jj = std::array::from_fn(|l| at!(c.nbr, p + l) as usize);
        group!(k, 4, ii, jj, std::array::from_fn(|l| p + l));
        k += 4;
    }
    if k < q {
        // The q mod 4 last pairs; the other lanes repeat the last pair.
        let (p, m) = (p0 + k, q - k);
        let ii = std::array::from_fn(|l| at!(c.owner, p + l.min(m - 1)) as usize);
        let jj = std::array::from_fn(|l| at!(c.nbr, p + l.min(m - 1)) as usize);
        group!(k, m, ii, jj, std::array::from_fn(|l| p + l.min(m - 1)));
    }
    if q > 0 {
        *gi = at!(c.owner, p0 + q - 1) as usize;
    }
}

#[cfg(test)]
mod tests {
    use crate::bond::bench::shaken_hex_lattice;
    use crate::contact::{LinearSpringDashpot, NormalDamping};
    use crate::{ContactLaws, ContactModel, Params, World};
    use std::sync::atomic::Ordering;

    /// The four-lane kernel gives the bits of the portable path (state, forces, histories)
    /// for both damping forms, periodic and bounded boxes, 1 and 2 threads, on a strongly
    /// shaken lattice whose contacts open, close and slip, with partial groups of pairs; and,
    /// with energy tracking (contacts without dashpots, so no dashpot sums), the bits of its
    /// energies (strain, slip work, the history released by opening contacts); and with
    /// reference gaps on some pairs.
    #[test]
    fn four_lane_kernel_gives_the_portable_bits() {
        for (periodic, ratio, track, offsets) in [
            (true, false, false, false),
            (true, true, false, false),
            (false, false, false, false),
            (false, true, false, false),
            (true, false, true, false),
            (false, true, true, false),
            (true, false, false, true),
            (false, true, true, true),
        ] {
            let mut st = shaken_hex_lattice([15, 9], 7, 0.5, 300.0);
            // Every third disc a little smaller: gaps that open and close.
            for k in (0..st.discs.len()).step_by(3) {
                st.discs.r[k] *= 0.99;
            }
            if !periodic {
                st.periodic.length = [None, None];
            }
            let law = LinearSpringDashpot {
                kn: 1e5,
                ks: 3e4,
                damping: match (ratio, track) {
                    (true, false) => NormalDamping::Ratio(0.3),
                    (false, false) => NormalDamping::Gamma(100.0),
                    (true, true) => NormalDamping::Ratio(0.0),
                    (false, true) => NormalDamping::Gamma(0.0),
                },
                shear_damping: 0.5,
                mu: 0.3,
            };
            let run = |portable: bool, threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .expect("pool");
                pool.install(|| {
                    let params = Params {
                        dt_fixed: Some(2e-7),
                        skin: Some(1e-4),
                        track_energy: track,
                        ..Params::default()
                    };
                    let laws = ContactLaws::uniform(ContactModel::Linear(law));
                    let mut w = World::new(st.clone(), params, laws);
                    if offsets {
                        // Discs 2k and 2k + 1 share a lattice cell and touch.
                        for a in (0..st.discs.len() as u32 - 1).step_by(8) {
                            w.set_contact_offset(a, a + 1, -2e-6);
                        }
                        w.refresh();
                        assert!(!w.nb.g0.is_empty());
                    }
                    w.ws.slots.portable = portable;
                    let before = super::BLOCKS.load(Ordering::Relaxed);
                    // Energies at every step (strain is that of the step's contacts).
                    let mut energies = Vec::new();
                    for _ in 0..40 {
                        w.run(1);
                        let e = w.energy();
                        energies.push([e.strain_contact, e.friction].map(f64::to_bits));
                    }
                    let ran = super::BLOCKS.load(Ordering::Relaxed) > before;
                    let d = &w.state.discs;
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    let out = [
                        &d.x, &d.y, &d.vx, &d.vy, &d.omega, &d.fx, &d.fy, &d.torque, &w.nb.us,
                    ]
                    .map(|v| bits(v));
                    (out, ran, w.nb.us.clone(), w.n_pairs(), energies)
                })
            };
            let (want, _, us, np, e_want) = run(true, 1);
            // Open and touching pairs, and a list whose length is not a multiple of four.
            assert!(us.contains(&0.0) && us.iter().any(|&u| u != 0.0));
            assert!(np % 4 != 0, "{np} pairs");
            if !crate::lanes::has_avx2() {
                return;
            }
            for threads in [1, 2] {
                let (got, ran, _, _, e_got) = run(false, threads);
                assert!(ran, "four-lane kernel not used");
                let what =
                    format!("periodic {periodic} ratio {ratio} energy {track} threads {threads}");
                assert!(got == want, "{what}");
                assert!(e_got == e_want, "energies, {what}");
            }
        }
    }
}
