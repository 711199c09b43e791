//! The eight-lane form of [`Wide`] in AVX registers through `std::arch`,
//! for the passes that test eight rays at once ([`super::rays8`]). The
//! eight-lane arrays of [`super::wide::Lanes8`] compiled there to a mix of
//! 128- and 256-bit instructions with their masks packed and unpacked
//! between words and bytes, and the Cornell box ran at two thirds of its
//! rate; here every operation is one AVX instruction.
//!
//! They run only inside `rays8` passes compiled with AVX2, which are entered
//! only on a CPU that has it; building the rows and masks of a pack is
//! plain arithmetic on arrays.

use std::arch::x86_64::{
    __m256, _mm256_add_ps, _mm256_and_ps, _mm256_blendv_ps, _mm256_cmp_ps, _mm256_div_ps,
    _mm256_load_ps, _mm256_movemask_ps, _mm256_mul_ps, _mm256_or_ps, _mm256_set1_ps,
    _mm256_storeu_ps, _mm256_sub_ps, _mm256_testz_ps, _mm256_xor_ps, _CMP_EQ_OQ, _CMP_LE_OQ,
    _CMP_LT_OQ,
};
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Not, Sub};

use super::wide::Wide;
use crate::simd::LANES;

/// Eight floats in one register.
#[derive(Clone, Copy, Debug)]
pub(super) struct Avx8(__m256);

/// Eight floats as a pack stores them, aligned for one load.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Row8([f32; LANES]);

/// An eight-lane mask: all bits of a lane set where true.
#[derive(Clone, Copy, Debug)]
pub(super) struct AvxMask8(__m256);

/// A lane-by-lane operator as one AVX instruction.
macro_rules! lane_op {
    ($ty:ident, $trait:ident, $f:ident, $intrinsic:ident) => {
        impl $trait for $ty {
            type Output = $ty;
            #[inline(always)]
            fn $f(self, o: $ty) -> $ty {
                // SAFETY: lanes exist only in passes run on a CPU with AVX2
                // (the module's note).
                $ty(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    };
}
lane_op!(Avx8, Add, add, _mm256_add_ps);
lane_op!(Avx8, Sub, sub, _mm256_sub_ps);
lane_op!(Avx8, Mul, mul, _mm256_mul_ps);
lane_op!(Avx8, Div, div, _mm256_div_ps);
lane_op!(AvxMask8, BitAnd, bitand, _mm256_and_ps);
lane_op!(AvxMask8, BitOr, bitor, _mm256_or_ps);

/// All bits set: what a true lane holds.
// SAFETY: eight words of all ones are the 32 bytes of a valid __m256
// (every bit pattern is).
const ALL: AvxMask8 = AvxMask8(unsafe { std::mem::transmute::<[i32; LANES], __m256>([-1; LANES]) });

impl Not for AvxMask8 {
    type Output = AvxMask8;
    #[inline(always)]
    fn not(self) -> AvxMask8 {
        // SAFETY: as for the operators.
        AvxMask8(unsafe { _mm256_xor_ps(self.0, ALL.0) })
    }
}

/// A comparison of two lane vectors as a mask.
macro_rules! compare {
    ($f:ident, $predicate:ident) => {
        #[inline(always)]
        fn $f(self, o: Avx8) -> AvxMask8 {
            // SAFETY: as for the operators.
            AvxMask8(unsafe { _mm256_cmp_ps::<$predicate>(self.0, o.0) })
        }
    };
}

impl Wide for Avx8 {
    const LANES: usize = crate::simd::LANES;
    type Row = Row8;
    type Mask = AvxMask8;
    // SAFETY: eight zero words are a valid __m256.
    const NONE: AvxMask8 =
        AvxMask8(unsafe { std::mem::transmute::<[i32; LANES], __m256>([0; LANES]) });

    #[inline(always)]
    fn row(value: impl Fn(usize) -> f32) -> Row8 {
        Row8(std::array::from_fn(value))
    }

    fn mask(flag: impl Fn(usize) -> bool) -> AvxMask8 {
        let words: [i32; LANES] = std::array::from_fn(|l| -i32::from(flag(l)));
        // SAFETY: eight words are the 32 bytes of an __m256.
        AvxMask8(unsafe { std::mem::transmute::<[i32; LANES], __m256>(words) })
    }

    #[inline(always)]
    fn load(row: &Row8) -> Avx8 {
        // SAFETY: as for the operators; the row is 32-byte aligned.
        Avx8(unsafe { _mm256_load_ps(row.0.as_ptr()) })
    }

    #[inline(always)]
    fn splat(x: f32) -> Avx8 {
        // SAFETY: as for the operators.
        Avx8(unsafe { _mm256_set1_ps(x) })
    }

    #[inline(always)]
    fn lane(self, l: usize) -> f32 {
        let mut all = [0.0; LANES];
        // SAFETY: as for the operators; `all` holds eight floats.
        unsafe { _mm256_storeu_ps(all.as_mut_ptr(), self.0) };
        all[l]
    }

    #[inline(always)]
    fn upper_half(self) -> Avx8 {
        self
    }

    #[inline(always)]
    fn least(self) -> f32 {
        let mut all = [0.0f32; LANES];
        // SAFETY: as for `lane`.
        unsafe { _mm256_storeu_ps(all.as_mut_ptr(), self.0) };
        all.into_iter()
            .fold(f32::INFINITY, |a, b| if b < a { b } else { a })
    }

    compare!(lt, _CMP_LT_OQ);
    compare!(le, _CMP_LE_OQ);
    compare!(eq, _CMP_EQ_OQ);

    #[inline(always)]
    fn select(m: AvxMask8, a: Avx8, b: Avx8) -> Avx8 {
        // SAFETY: as for the operators.
        Avx8(unsafe { _mm256_blendv_ps(b.0, a.0, m.0) })
    }

    #[inline(always)]
    fn bits<const AVX: bool>(m: AvxMask8) -> u32 {
        // SAFETY: as for the operators.
        unsafe { _mm256_movemask_ps(m.0) as u32 }
    }

    #[inline(always)]
    fn any(m: AvxMask8) -> bool {
        // SAFETY: as for the operators.
        unsafe { _mm256_testz_ps(m.0, m.0) == 0 }
    }
}
