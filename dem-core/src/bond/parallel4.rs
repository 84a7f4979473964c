//! The parallel bond of Potyondy & Cundall (2004) with the maximum-stress criterion (see
//! [`super::potyondy2004`] and [`super::criteria`]) over four bonds at a time in AVX2
//! registers: the contact pass's packed records of the two discs of each bond are loaded and
//! transposed (`lanes::pair_columns`), geometry, kinematics, the force update and the
//! criterion are evaluated on the vectors, and only the new bond forces and the four output
//! columns (force on j along x, y, torques on i and j) are stored. The block kernel's
//! straight-line path stores the gathered columns and the geometry to work arrays and reads
//! them back: on the bonded benchmark lattice the gather and block loop cost 183 instructions
//! per disc-step, this kernel 135 (cachegrind; the scatter's ~85 are unchanged).
//!
//! Taken by the block kernel (`kernel::block`) for a full block of intact parallel bonds with
//! the stress criterion (one group or several: the parameters are read per bond from
//! `StressParams`), when the packed records are there (AVX2). Every operation is the one the
//! general path performs (the same IEEE operations in the same order: `MinImage::delta_select`,
//! `normal_gap`, the tangential velocity of pass 1b, `potyondy2004::update`,
//! `criteria::stress_flags` and `finish`), so the results are the same bits; the tests
//! compare it with the general path.

use super::criteria::BreakMode;
use super::kernel::{BlockOut, BondsIn, BondsMut, Ctx, NEW};
use crate::lanes::pair_columns;
use crate::lanes::BOND_BLOCK;

#[cfg(test)]
thread_local! {
    /// Blocks evaluated on this thread (tests: the path really runs).
    pub(super) static BLOCKS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The parameters k̄n, k̄s, λ̄, β̄, σ̄c, c̄, tan φ̄ of a block's bonds: the same for all (one
/// group) or per bond (`StressParams::block`: several groups; 56 more bytes read per bond).
pub(super) enum Par<'a> {
    Uniform([f64; 7]),
    PerBond([&'a [f64; BOND_BLOCK]; 7]),
}

/// Update the full block of intact bonds `base..base + BOND_BLOCK` (`m` holds that block's
/// entries): new forces in `m`, the outputs `[fx, fy, ti, tj]` of every bond in `out`, and
/// the status of the bonds breaking now ([`NEW`] + mode). Returns the number of bonds broken
/// now.
///
/// # Safety
/// The CPU must support AVX2; `c.packed` must hold the record of every disc and every disc
/// index of the block's bonds must be below its length.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub(super) unsafe fn block(
    c: &Ctx,
    b: &BondsIn,
    base: usize,
    par: Par,
    m: &mut BondsMut,
    out: &mut BlockOut,
) -> usize {
    use std::arch::x86_64::*;
    match par {
        Par::Uniform(u) => {
            let u = u.map(|v| _mm256_set1_pd(v));
            block_with(c, b, base, |p, _| u[p], m, out)
        }
        Par::PerBond(a) => block_with(
            c,
            b,
            base,
            |p, k| _mm256_loadu_pd(a[p][k..].as_ptr()),
            m,
            out,
        ),
    }
}

/// [`block`] with parameter q of the bonds k..k + 4 from `par(q, k)`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn block_with(
    c: &Ctx,
    b: &BondsIn,
    base: usize,
    par: impl Fn(usize, usize) -> std::arch::x86_64::__m256d,
    m: &mut BondsMut,
    out: &mut BlockOut,
) -> usize {
    use std::arch::x86_64::*;
    #[cfg(test)]
    BLOCKS.with(|b| b.set(b.get() + 1));
    let r = base..base + BOND_BLOCK;
    // (Bounds checked here, once: every access below is at k + l < BOND_BLOCK.)
    let (i_, j_): (&[u32; BOND_BLOCK], &[u32; BOND_BLOCK]) = (
        b.i[r.clone()].try_into().expect("a full block"),
        b.j[r.clone()].try_into().expect("a full block"),
    );
    let (g0_, rbar_): (&[f64; BOND_BLOCK], &[f64; BOND_BLOCK]) = (
        b.g0[r.clone()].try_into().expect("a full block"),
        b.rbar[r].try_into().expect("a full block"),
    );
    let f_n: &mut [f64; BOND_BLOCK] = (&mut *m.fn_).try_into().expect("a full block");
    let f_s: &mut [f64; BOND_BLOCK] = (&mut *m.fs).try_into().expect("a full block");
    let f_m: &mut [f64; BOND_BLOCK] = (&mut *m.m).try_into().expect("a full block");
    let status: &mut [u8; BOND_BLOCK] = (&mut *m.status).try_into().expect("a full block");
    let base_pk = c.packed.as_ptr();
    let set = _mm256_set1_pd;
    let [lx, hx, ly, hy] = c.v.img.parts();
    let (lx, hx, nhx) = (set(lx), set(hx), set(-hx));
    let (ly, hy, nhy) = (set(ly), set(hy), set(-hy));
    let (zero, one, half, sign) = (_mm256_setzero_pd(), set(1.0), set(0.5), set(-0.0));
    let (two, two_thirds, third) = (set(2.0), set(2.0 / 3.0), set(1.0 / 3.0));
    let (t, dt) = (set(c.t), set(c.dt));
    let (add, sub, mul) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd);
    let neg = |a| _mm256_xor_pd(a, sign);
    // SAFETY (loads and stores at k): k + 4 <= BOND_BLOCK, the arrays' length.
    let ld = |a: &[f64; BOND_BLOCK], k: usize| _mm256_loadu_pd(a.as_ptr().add(k));
    let st = |a: &mut [f64; BOND_BLOCK], k: usize, v| _mm256_storeu_pd(a.as_mut_ptr().add(k), v);
    // `MinImage::delta_select`: d − L when d > L/2, d + L when d < −L/2, else d (L = +∞ on
    // an axis that is not periodic: neither holds).
    let image = |d, l, h, nh| {
        let above = _mm256_cmp_pd::<_CMP_GT_OQ>(d, h);
        let below = _mm256_cmp_pd::<_CMP_LT_OQ>(d, nh);
        _mm256_blendv_pd(_mm256_blendv_pd(d, add(d, l), below), sub(d, l), above)
    };
    let [ox, oy, oti, otj] = out;
    // Bits k of the block: tension and shear conditions.
    let (mut tension, mut shear) = (0u32, 0u32);
    for k in (0..BOND_BLOCK).step_by(4) {
        let ii = std::array::from_fn(|l| i_[k + l] as usize);
        let jj = std::array::from_fn(|l| j_[k + l] as usize);
        // SAFETY: every index below c.packed.len() (the contract).
        let ([dx, dy, dvx, dvy], [wi, ri, _], [wj, rj, _]) = pair_columns(base_pk, ii, jj);
        let (dx, dy) = (image(dx, lx, hx, nhx), image(dy, ly, hy, nhy));
        // `normal_gap`.
        let dist = _mm256_sqrt_pd(add(mul(dx, dx), mul(dy, dy)));
        let ok = _mm256_cmp_pd::<_CMP_GT_OQ>(dist, zero);
        let inv = _mm256_div_pd(one, _mm256_blendv_pd(one, dist, ok));
        let nx = _mm256_blendv_pd(one, mul(dx, inv), ok);
        let ny = mul(dy, inv);
        let gap = sub(sub(dist, ri), rj);
        let (ai, aj) = (add(ri, mul(half, gap)), add(rj, mul(half, gap)));
        // Pass 1b: tangential relative velocity at the contact point, relative spin.
        let vt = sub(
            add(mul(dvx, neg(ny)), mul(dvy, nx)),
            add(mul(wj, aj), mul(wi, ai)),
        );
        let dw = sub(wj, wi);
        // `potyondy2004::update`: Ā = 2R̄t, Ī = (2/3)R̄³t.
        let rbar = ld(rbar_, k);
        let (kn, ks) = (par(0, k), par(1, k));
        let a = mul(mul(two, rbar), t);
        let inertia = mul(mul(mul(mul(two_thirds, rbar), rbar), rbar), t);
        let (kn_a, ks_a, kn_i) = (mul(kn, a), mul(ks, a), mul(kn, inertia));
        let f0 = mul(neg(kn_a), sub(gap, ld(g0_, k)));
        let f1 = sub(ld(f_s, k), mul(ks_a, mul(vt, dt)));
        let f2 = sub(ld(f_m, k), mul(kn_i, mul(dw, dt)));
        st(f_n, k, f0);
        st(f_s, k, f1);
        st(f_m, k, f2);
        // `stress_flags`: σ̄ĀI/… as −F̄n ℓ + β̄|M̄| ≥ σ̄c Ā ℓ, |F̄s| ≥ c̄Ā + F̄n tan φ̄.
        let lever = mul(rbar, third);
        let (fs_abs, m_abs) = (_mm256_andnot_pd(sign, f1), _mm256_andnot_pd(sign, f2));
        let sal = add(mul(neg(f0), lever), mul(par(3, k), m_abs));
        let ten = _mm256_cmp_pd::<_CMP_GE_OQ>(sal, mul(mul(par(4, k), a), lever));
        let lim = add(mul(par(5, k), a), mul(f0, par(6, k)));
        let shr = _mm256_cmp_pd::<_CMP_GE_OQ>(fs_abs, lim);
        tension |= (_mm256_movemask_pd(ten) as u32) << k;
        shear |= (_mm256_movemask_pd(shr) as u32) << k;
        // `finish`: force on j F̄n n̂ + F̄s t̂ (t̂ = (−n_y, n_x)), torques −a_i F̄s − M̄ on i and
        // −a_j F̄s + M̄ on j.
        st(ox, k, add(mul(f0, nx), mul(f1, neg(ny))));
        st(oy, k, add(mul(f0, ny), mul(f1, nx)));
        st(oti, k, sub(mul(neg(ai), f1), f2));
        st(otj, k, add(mul(neg(aj), f1), f2));
    }
    // Tension takes precedence when both conditions hold (`finish`).
    let shear = shear & !tension;
    let mut broke = 0;
    if tension | shear != 0 {
        for (k, s) in status.iter_mut().enumerate() {
            let mode = if tension >> k & 1 != 0 {
                BreakMode::Tension
            } else if shear >> k & 1 != 0 {
                BreakMode::Shear
            } else {
                continue;
            };
            *s = NEW + mode.index() as u8;
            broke += 1;
        }
    }
    broke
}
