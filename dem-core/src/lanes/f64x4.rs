//! [`F64x4`]: four `f64` lanes in an AVX register, with the operations the four-lane kernels
//! use written as operators and methods (rapier's `SimdReal`, here on `std::arch` alone), so a
//! kernel reads like its scalar twin: `(wi * ri + wj * rj) - h * (wi + wj)`.
//!
//! Every operation is one AVX instruction performing, lane by lane, the IEEE operation the
//! scalar code performs: `+ - * /` and `sqrt` round as `f64` does; `min`/`max` are `minpd`/
//! `maxpd`; comparisons are the ordered, quiet predicates (false on NaN), giving all-ones or
//! all-zeros lanes; `& | ^` and [`F64x4::andnot`] act on the bits. There is no fused
//! multiply-add: `a * b + c` is a multiply then an add, as in the scalar paths, so code written
//! with this type gives the scalar code's bits when it performs the same operations in the same
//! order.
//!
//! An `F64x4` is made only by its `unsafe` constructors, whose caller promises AVX2 (the
//! kernels run inside `#[target_feature(enable = "avx2")]` functions chosen by
//! [`super::has_avx2`]); the operations on a value that exists are therefore safe. They are
//! `#[inline(always)]`: inlined into those functions, each becomes its single instruction.

use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, BitXor, Div, Mul, Sub};

/// Four `f64` lanes (see the module documentation for the invariant and the operations).
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub(crate) struct F64x4(pub(crate) __m256d);

impl F64x4 {
    /// All four lanes `v`.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline(always)]
    pub(crate) unsafe fn splat(v: f64) -> F64x4 {
        F64x4(_mm256_set1_pd(v))
    }

    /// All four lanes +0.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline(always)]
    pub(crate) unsafe fn zero() -> F64x4 {
        F64x4(_mm256_setzero_pd())
    }

    /// All four lanes all ones (a mask where every lane holds).
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[inline(always)]
    pub(crate) unsafe fn all_ones() -> F64x4 {
        F64x4(_mm256_castsi256_pd(_mm256_set1_epi64x(-1)))
    }

    /// The four values at `p` (any alignment).
    ///
    /// # Safety
    /// The CPU must support AVX2; `p..p + 4` must be readable.
    #[inline(always)]
    pub(crate) unsafe fn load(p: *const f64) -> F64x4 {
        F64x4(_mm256_loadu_pd(p))
    }

    /// Stores the four lanes at `p` (any alignment).
    ///
    /// # Safety
    /// `p..p + 4` must be writable.
    #[inline(always)]
    pub(crate) unsafe fn store(self, p: *mut f64) {
        _mm256_storeu_pd(p, self.0)
    }

    /// √ of each lane (`sqrtpd`, correctly rounded as `f64::sqrt`).
    #[inline(always)]
    pub(crate) fn sqrt(self) -> F64x4 {
        // SAFETY: a value exists only where AVX2 does (module documentation).
        unsafe { F64x4(_mm256_sqrt_pd(self.0)) }
    }

    /// `maxpd`: per lane `if self > b { self } else { b }` (`b` when either is NaN).
    #[inline(always)]
    pub(crate) fn max(self, b: F64x4) -> F64x4 {
        // SAFETY: as in `sqrt`.
        unsafe { F64x4(_mm256_max_pd(self.0, b.0)) }
    }

    /// Lanes where `self < b` (ordered, quiet): all ones, else all zeros.
    #[inline(always)]
    pub(crate) fn lt(self, b: F64x4) -> F64x4 {
        // SAFETY: as in `sqrt`.
        unsafe { F64x4(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, b.0)) }
    }

    /// Lanes where `self > b` (ordered, quiet): all ones, else all zeros.
    #[inline(always)]
    pub(crate) fn gt(self, b: F64x4) -> F64x4 {
        // SAFETY: as in `sqrt`.
        unsafe { F64x4(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, b.0)) }
    }

    /// Lanes where `self >= b` (ordered, quiet): all ones, else all zeros.
    #[inline(always)]
    pub(crate) fn ge(self, b: F64x4) -> F64x4 {
        // SAFETY: as in `sqrt`.
        unsafe { F64x4(_mm256_cmp_pd::<_CMP_GE_OQ>(self.0, b.0)) }
    }

    /// The lanes' sign bits as bits 0..4 (`movmskpd`; of a comparison's mask: bit l set where
    /// lane l holds).
    #[inline(always)]
    pub(crate) fn bitmask(self) -> u32 {
        // SAFETY: as in `sqrt`.
        unsafe { _mm256_movemask_pd(self.0) as u32 }
    }

    /// Per lane `if self { t } else { f }`, `self` a comparison's mask (`blendvpd` on its
    /// sign bits).
    #[inline(always)]
    pub(crate) fn select(self, t: F64x4, f: F64x4) -> F64x4 {
        // SAFETY: as in `sqrt`.
        unsafe { F64x4(_mm256_blendv_pd(f.0, t.0, self.0)) }
    }

    /// `!self & b` on the bits (`andnpd`): with `self` = −0.0 in every lane, |b|.
    #[inline(always)]
    pub(crate) fn andnot(self, b: F64x4) -> F64x4 {
        // SAFETY: as in `sqrt`.
        unsafe { F64x4(_mm256_andnot_pd(self.0, b.0)) }
    }
}

/// The binary operators, each its one instruction.
macro_rules! binary {
    ($($trait:ident $method:ident $intrinsic:ident),*) => {$(
        impl $trait for F64x4 {
            type Output = F64x4;
            #[inline(always)]
            fn $method(self, b: F64x4) -> F64x4 {
                // SAFETY: a value exists only where AVX2 does (module documentation).
                unsafe { F64x4($intrinsic(self.0, b.0)) }
            }
        }
    )*};
}

binary!(
    Add add _mm256_add_pd,
    Sub sub _mm256_sub_pd,
    Mul mul _mm256_mul_pd,
    Div div _mm256_div_pd,
    BitAnd bitand _mm256_and_pd,
    BitOr bitor _mm256_or_pd,
    BitXor bitxor _mm256_xor_pd
);

#[cfg(test)]
mod tests {
    use super::*;

    /// The lanes of `v`.
    fn lanes(v: F64x4) -> [f64; 4] {
        let mut o = [0.0; 4];
        // SAFETY: `o` holds four f64.
        unsafe { v.store(o.as_mut_ptr()) };
        o
    }

    /// Each operation gives, lane by lane, the bits of the scalar operation (NaN, ±0, ±∞,
    /// subnormals and rounding cases among the inputs).
    #[test]
    fn operations_are_the_scalar_ones_lane_by_lane() {
        if !crate::lanes::has_avx2() {
            return;
        }
        let vals = [
            0.0,
            -0.0,
            1.0,
            -1.5,
            1.0 / 3.0,
            1e308,
            -1e-310,
            f64::INFINITY,
            f64::NAN,
            0.1 + 0.2,
            7.0,
            -2.0f64.sqrt(),
        ];
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        let mask = |c: bool| f64::from_bits(if c { u64::MAX } else { 0 });
        for w in vals.windows(4) {
            for s in [1usize, 5] {
                let a: [f64; 4] = [w[0], w[1], w[2], w[3]];
                let b: [f64; 4] = std::array::from_fn(|l| vals[(l * s + 3) % vals.len()]);
                // SAFETY: AVX2 checked above; `a`, `b` hold four f64.
                let (x, y) = unsafe { (F64x4::load(a.as_ptr()), F64x4::load(b.as_ptr())) };
                for l in 0..4 {
                    let (p, q) = (a[l], b[l]);
                    assert!(same(lanes(x + y)[l], p + q));
                    assert!(same(lanes(x - y)[l], p - q));
                    assert!(same(lanes(x * y)[l], p * q));
                    assert!(same(lanes(x / y)[l], p / q));
                    assert!(same(lanes(x.sqrt())[l], p.sqrt()));
                    assert!(same(lanes(x.max(y))[l], if p > q { p } else { q }));
                    assert!(same(lanes(x.lt(y))[l], mask(p < q)));
                    assert!(same(lanes(x.gt(y))[l], mask(p > q)));
                    assert!(same(lanes(x.ge(y))[l], mask(p >= q)));
                    assert_eq!(x.ge(y).bitmask() >> l & 1 == 1, p >= q);
                    let bits = |f: fn(u64, u64) -> u64| f64::from_bits(f(p.to_bits(), q.to_bits()));
                    assert!(same(lanes(x & y)[l], bits(|u, v| u & v)));
                    assert!(same(lanes(x | y)[l], bits(|u, v| u | v)));
                    assert!(same(lanes(x ^ y)[l], bits(|u, v| u ^ v)));
                    assert!(same(lanes(x.andnot(y))[l], bits(|u, v| !u & v)));
                    let m = x.lt(y);
                    assert!(same(lanes(m.select(x, y))[l], if p < q { p } else { q }));
                }
            }
        }
        // SAFETY: AVX2 checked above.
        let (z, t) = unsafe { (F64x4::zero(), F64x4::splat(-0.0)) };
        assert!(lanes(z).iter().all(|v| v.to_bits() == 0));
        // SAFETY: AVX2 checked above.
        let ones = unsafe { F64x4::all_ones() };
        assert!(lanes(ones).iter().all(|v| v.to_bits() == u64::MAX));
        assert_eq!(ones.bitmask(), 15);
        assert!(lanes(t).iter().all(|v| v.to_bits() == (-0.0f64).to_bits()));
    }
}
