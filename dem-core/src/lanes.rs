//! The ground floor of the hot path: what the disc–disc pass ([`crate::contact`]), the bond
//! kernels ([`crate::bond`]) and the integrator share about their blocked and four-lane (AVX2)
//! code. This module imports no other module of the crate; they import it.
//!
//! - [`has_avx2`]: the one run-time CPU-feature check. Every AVX2 path (the contact kernel's
//!   gather, evaluation and scatter, the bond kernels, the integrator's packing) is chosen by
//!   it. The AVX2 builds perform the IEEE operations of the portable ones in the same order
//!   (no FMA contraction), so results do not depend on the answer.
//! - [`PAIR_BLOCK`] and [`BOND_BLOCK`]: the block sizes of the contact pass and of the bond
//!   kernel, with their reasons.
//! - `F64x4` (x86-64): four `f64` lanes with the kernels' IEEE operations as operators, so the
//!   four-lane kernels read like their scalar twins (`lanes/f64x4.rs`).
//! - [`Packed`]: one disc's 64-byte record of the AVX2 gathers, `transpose4` and
//!   `pair_columns`: the loads and transposes that turn records into the SoA columns of
//!   four pairs (or bonds).
//!
//! The minimum image is `neighbors::MinImage` (beside the cell grid, whose periodic box it
//! wraps): compare and select, d − L when d > L/2, d + L when d < −L/2 (L = +∞ on an axis that
//! is not periodic, so neither holds). The contact pass, the disc–wall pass, the bond kernels
//! (scalar and four-lane) and the fused bonds all use it; the bond kernels' earlier
//! d − L·round(d/L) gave the same bits for every bond shorter than L/2.

#[cfg(target_arch = "x86_64")]
mod f64x4;
#[cfg(target_arch = "x86_64")]
pub(crate) use f64x4::F64x4;

/// Pairs per block of the disc–disc pass (`contact::kernel`): a block's pairs are gathered
/// into a scratch of columns, evaluated branch-free over the whole block (a fixed trip count
/// the compiler vectorises: the law runs on full vectors whatever the branches a pair would
/// take) and scattered in pair order. The scratch is 22 `f64` and 2 `u16` columns, 11.3 KiB
/// at 64 pairs, so it stays in L1 beside the disc records it streams. Also the unit of the
/// multi-thread split's test for shared discs (`contact::owned::Plan::plain`) and of the
/// block form of the per-pair hook (`contact::kernel::PairHook`, the fused bonds).
///
/// Why two sizes: each kernel chose its own when it was written (this one with the blocked
/// force kernel, the bond one with the blocked bond kernel); the history records no
/// measurement of either, and they were never tuned against each other. They need not be
/// equal: no array is shared between a pair block and a bond block. A change of either is a
/// performance change to measure (docs/performance.md).
pub const PAIR_BLOCK: usize = 64;

/// Bonds per block of the bond kernel (`bond::kernel`): the geometry of a whole block is
/// computed first (independent, branch-free work the CPU overlaps), then the law and the
/// criterion (branch-free too for a block of intact parallel bonds with the stress criterion),
/// then the scatter. Work arrays: 15 `f64` columns and 4 output columns, 4.75 KiB at 32 bonds.
/// Also the unit of the kernel's fast paths (a block takes the straight-line stress path,
/// `bond::kernel::StressParams`, or the four-lane kernel, `bond::parallel4`, only when all its
/// bonds qualify, so one broken bond sends its whole block to the general path) and of the
/// parallel split's ranges (`bond::split`: whole blocks per worker). See [`PAIR_BLOCK`] for
/// why the sizes differ.
pub const BOND_BLOCK: usize = 32;

/// Does the CPU support AVX2? The one run-time check of the crate (`std` caches the answer).
#[inline]
pub fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// One disc's data packed for the AVX2 gathers (the contact pass's `gather_aos` and four-lane
/// kernel, the bond kernels): `a` = [x, y, v_x, v_y], `b` = [ω, r, 1/m, 0] (the inverse
/// contact mass), 64 bytes, one cache line. Built once per force pass by the contact pass's
/// `pack` from the SoA disc arrays, or by the integrator right after moving the discs (plain
/// copies: the same bits).
#[derive(Clone, Copy, Debug, Default)]
#[repr(C, align(64))]
pub struct Packed {
    pub(crate) a: [f64; 4],
    pub(crate) b: [f64; 4],
}

/// The 4×4 transpose of four rows [a, b, c, d]ₖ (k = 0..3) into the four columns
/// [a₀ a₁ a₂ a₃], [b..], [c..], [d..] in registers (AVX: two unpacks and a lane permute per
/// column; plain moves, so the values keep their bits). Used by the packing of the disc
/// records and by the packed gathers of the contact and bond passes.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
pub(crate) unsafe fn transpose4(
    r: [std::arch::x86_64::__m256d; 4],
) -> [std::arch::x86_64::__m256d; 4] {
    use std::arch::x86_64::*;
    let t0 = _mm256_unpacklo_pd(r[0], r[1]); // a0 a1 c0 c1
    let t1 = _mm256_unpackhi_pd(r[0], r[1]); // b0 b1 d0 d1
    let t2 = _mm256_unpacklo_pd(r[2], r[3]);
    let t3 = _mm256_unpackhi_pd(r[2], r[3]);
    [
        _mm256_permute2f128_pd(t0, t2, 0x20),
        _mm256_permute2f128_pd(t1, t3, 0x20),
        _mm256_permute2f128_pd(t0, t2, 0x31),
        _mm256_permute2f128_pd(t1, t3, 0x31),
    ]
}

/// The columns of four pairs (discs `ii[l]`, `jj[l]`) from the packed records at `base`:
/// [d_x, d_y, Δv_x, Δv_y] (the records' [x, y, v_x, v_y]_j − [..]_i, one lane-wise subtraction
/// per pair, then a transpose) and [ω, r, 1/m] of the four i and of the four j. Plain loads,
/// moves and the same subtractions as the scalar gathers: the same bits. Shared by the contact
/// pass's packed gather and four-lane linear kernel and by the bond stage's four-lane kernel.
///
/// # Safety
/// The CPU must support AVX2; every index must be that of a record at `base` (64-byte
/// aligned, so both halves are aligned).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
#[allow(clippy::type_complexity)]
pub(crate) unsafe fn pair_columns(
    base: *const Packed,
    ii: [usize; 4],
    jj: [usize; 4],
) -> (
    [std::arch::x86_64::__m256d; 4],
    [std::arch::x86_64::__m256d; 3],
    [std::arch::x86_64::__m256d; 3],
) {
    use std::arch::x86_64::*;
    let ld_a = |k: usize| _mm256_load_pd((*base.add(k)).a.as_ptr());
    let ld_b = |k: usize| _mm256_load_pd((*base.add(k)).b.as_ptr());
    let d = |l: usize| _mm256_sub_pd(ld_a(jj[l]), ld_a(ii[l]));
    let dv = transpose4([d(0), d(1), d(2), d(3)]);
    let [wi, ri, mi, _] = transpose4([ld_b(ii[0]), ld_b(ii[1]), ld_b(ii[2]), ld_b(ii[3])]);
    let [wj, rj, mj, _] = transpose4([ld_b(jj[0]), ld_b(jj[1]), ld_b(jj[2]), ld_b(jj[3])]);
    (dv, [wi, ri, mi], [wj, rj, mj])
}
