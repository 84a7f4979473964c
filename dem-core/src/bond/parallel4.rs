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
#[cfg(target_arch = "x86_64")]
use crate::lanes::F64x4;
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
    match par {
        Par::Uniform(u) => {
            let u = u.map(|v| F64x4::splat(v));
            block_with(c, b, base, |p, _| u[p], m, out)
        }
        Par::PerBond(a) => block_with(c, b, base, |p, k| F64x4::load(a[p][k..].as_ptr()), m, out),
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
    par: impl Fn(usize, usize) -> F64x4,
    m: &mut BondsMut,
    out: &mut BlockOut,
) -> usize {
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
    let set = |v| F64x4::splat(v);
    let [lx, hx, ly, hy] = c.v.img.parts();
    let (lx, hx, nhx) = (set(lx), set(hx), set(-hx));
    let (ly, hy, nhy) = (set(ly), set(hy), set(-hy));
    let (zero, one, half, sign) = (F64x4::zero(), set(1.0), set(0.5), set(-0.0));
    let (two, two_thirds, third) = (set(2.0), set(2.0 / 3.0), set(1.0 / 3.0));
    let (t, dt) = (set(c.t), set(c.dt));
    let neg = |a: F64x4| a ^ sign;
    // SAFETY (loads and stores at k): k + 4 <= BOND_BLOCK, the arrays' length.
    let ld = |a: &[f64; BOND_BLOCK], k: usize| F64x4::load(a.as_ptr().add(k));
    let st = |a: &mut [f64; BOND_BLOCK], k: usize, v: F64x4| v.store(a.as_mut_ptr().add(k));
    // `MinImage::delta_select`: d − L when d > L/2, d + L when d < −L/2, else d (L = +∞ on
    // an axis that is not periodic: neither holds).
    let image =
        |d: F64x4, l: F64x4, h: F64x4, nh: F64x4| d.gt(h).select(d - l, d.lt(nh).select(d + l, d));
    let [ox, oy, oti, otj] = out;
    // Bits k of the block: tension and shear conditions.
    let (mut tension, mut shear) = (0u32, 0u32);
    for k in (0..BOND_BLOCK).step_by(4) {
        let ii = std::array::from_fn(|l| i_[k + l] as usize);
        let jj = std::array::from_fn(|l| j_[k + l] as usize);
        // SAFETY: every index below c.packed.len() (the contract).
        let (dv, ci, cj) = pair_columns(base_pk, ii, jj);
        let ([dx, dy, dvx, dvy], [wi, ri, _], [wj, rj, _]) =
            (dv.map(F64x4), ci.map(F64x4), cj.map(F64x4));
        let (dx, dy) = (image(dx, lx, hx, nhx), image(dy, ly, hy, nhy));
        // `normal_gap`.
        let dist = (dx * dx + dy * dy).sqrt();
        let ok = dist.gt(zero);
        let inv = one / ok.select(dist, one);
        let nx = ok.select(dx * inv, one);
        let ny = dy * inv;
        let gap = dist - ri - rj;
        let (ai, aj) = (ri + half * gap, rj + half * gap);
        // Pass 1b: tangential relative velocity at the contact point, relative spin.
        let vt = (dvx * neg(ny) + dvy * nx) - (wj * aj + wi * ai);
        let dw = wj - wi;
        // `potyondy2004::update`: Ā = 2R̄t, Ī = (2/3)R̄³t.
        let rbar = ld(rbar_, k);
        let (kn, ks) = (par(0, k), par(1, k));
        let a = two * rbar * t;
        let inertia = two_thirds * rbar * rbar * rbar * t;
        let (kn_a, ks_a, kn_i) = (kn * a, ks * a, kn * inertia);
        let f0 = neg(kn_a) * (gap - ld(g0_, k));
        let f1 = ld(f_s, k) - ks_a * (vt * dt);
        let f2 = ld(f_m, k) - kn_i * (dw * dt);
        st(f_n, k, f0);
        st(f_s, k, f1);
        st(f_m, k, f2);
        // `stress_flags`: σ̄ĀI/… as −F̄n ℓ + β̄|M̄| ≥ σ̄c Ā ℓ, |F̄s| ≥ c̄Ā + F̄n tan φ̄.
        let lever = rbar * third;
        let (fs_abs, m_abs) = (sign.andnot(f1), sign.andnot(f2));
        let sal = neg(f0) * lever + par(3, k) * m_abs;
        let ten = sal.ge(par(4, k) * a * lever);
        let lim = par(5, k) * a + f0 * par(6, k);
        let shr = fs_abs.ge(lim);
        tension |= ten.bitmask() << k;
        shear |= shr.bitmask() << k;
        // `finish`: force on j F̄n n̂ + F̄s t̂ (t̂ = (−n_y, n_x)), torques −a_i F̄s − M̄ on i and
        // −a_j F̄s + M̄ on j.
        st(ox, k, f0 * nx + f1 * neg(ny));
        st(oy, k, f0 * ny + f1 * nx);
        st(oti, k, neg(ai) * f1 - f2);
        st(otj, k, neg(aj) * f1 + f2);
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
