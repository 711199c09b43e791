//! The sixteen-lane form of [`Wide`]: AVX-512F registers and mask
//! registers, through `std::arch` (the compiler does not widen the
//! eight-lane array loops to 512 bits by itself: sixteen-element arrays came
//! out as a mix of 128- and 256-bit instructions). One pass tests sixteen
//! faces, so the Cornell box's six rects and twelve box faces take two
//! passes instead of three.
//!
//! Every operation here is an AVX-512F instruction. They run only inside
//! `Packs::<Lanes16>` passes compiled with AVX-512F, which
//! `FlatFaces` enters only on a CPU that has it ([`crate::simd::avx512f`]); building the
//! rows and masks of a pack is plain arithmetic on arrays.

use std::arch::x86_64::{
    __m512, _mm512_add_ps, _mm512_cmp_ps_mask, _mm512_div_ps, _mm512_load_ps, _mm512_mask_blend_ps,
    _mm512_mul_ps, _mm512_reduce_min_ps, _mm512_set1_ps, _mm512_shuffle_f32x4, _mm512_storeu_ps,
    _mm512_sub_ps, _CMP_EQ_OQ, _CMP_LE_OQ, _CMP_LT_OQ,
};
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Not, Sub};

use super::wide::Wide;

/// Sixteen lanes.
const SIXTEEN: usize = 16;

/// Sixteen floats in one register.
#[derive(Clone, Copy, Debug)]
pub(super) struct Lanes16(__m512);

/// Sixteen floats as a pack stores them, aligned for one load.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Row16([f32; SIXTEEN]);

/// A sixteen-lane mask: bit `lane` set where true.
#[derive(Clone, Copy, Debug)]
pub(super) struct Mask16(u16);

/// A lane-by-lane operator as one AVX-512F instruction.
macro_rules! lane_op {
    ($trait:ident, $f:ident, $intrinsic:ident) => {
        impl $trait for Lanes16 {
            type Output = Lanes16;
            #[inline(always)]
            fn $f(self, o: Lanes16) -> Lanes16 {
                // SAFETY: lanes exist only in passes run on a CPU with
                // AVX-512F (the module's note).
                Lanes16(unsafe { $intrinsic(self.0, o.0) })
            }
        }
    };
}
lane_op!(Add, add, _mm512_add_ps);
lane_op!(Sub, sub, _mm512_sub_ps);
lane_op!(Mul, mul, _mm512_mul_ps);
lane_op!(Div, div, _mm512_div_ps);

impl BitAnd for Mask16 {
    type Output = Mask16;
    #[inline(always)]
    fn bitand(self, o: Mask16) -> Mask16 {
        Mask16(self.0 & o.0)
    }
}

impl BitOr for Mask16 {
    type Output = Mask16;
    #[inline(always)]
    fn bitor(self, o: Mask16) -> Mask16 {
        Mask16(self.0 | o.0)
    }
}

impl Not for Mask16 {
    type Output = Mask16;
    #[inline(always)]
    fn not(self) -> Mask16 {
        Mask16(!self.0)
    }
}

/// A comparison of two lane vectors as a mask register.
macro_rules! compare {
    ($f:ident, $predicate:ident) => {
        #[inline(always)]
        fn $f(self, o: Lanes16) -> Mask16 {
            // SAFETY: as for the operators.
            Mask16(unsafe { _mm512_cmp_ps_mask::<$predicate>(self.0, o.0) })
        }
    };
}

impl Wide for Lanes16 {
    const LANES: usize = SIXTEEN;
    type Row = Row16;
    type Mask = Mask16;
    const NONE: Mask16 = Mask16(0);

    #[inline(always)]
    fn row(value: impl Fn(usize) -> f32) -> Row16 {
        Row16(std::array::from_fn(value))
    }

    fn mask(flag: impl Fn(usize) -> bool) -> Mask16 {
        Mask16((0..SIXTEEN).fold(0, |m, l| m | (u16::from(flag(l)) << l)))
    }

    #[inline(always)]
    fn load(row: &Row16) -> Lanes16 {
        // SAFETY: as for the operators; the row is 64-byte aligned.
        Lanes16(unsafe { _mm512_load_ps(row.0.as_ptr()) })
    }

    #[inline(always)]
    fn splat(x: f32) -> Lanes16 {
        // SAFETY: as for the operators.
        Lanes16(unsafe { _mm512_set1_ps(x) })
    }

    #[inline(always)]
    fn lane(self, l: usize) -> f32 {
        let mut all = [0.0; SIXTEEN];
        // SAFETY: as for the operators; `all` holds sixteen floats.
        unsafe { _mm512_storeu_ps(all.as_mut_ptr(), self.0) };
        all[l]
    }

    /// The two halves of eight swapped.
    #[inline(always)]
    fn upper_half(self) -> Lanes16 {
        // SAFETY: as for the operators.
        Lanes16(unsafe { _mm512_shuffle_f32x4::<0b0100_1110>(self.0, self.0) })
    }

    #[inline(always)]
    fn least(self) -> f32 {
        // SAFETY: as for the operators.
        unsafe { _mm512_reduce_min_ps(self.0) }
    }

    compare!(lt, _CMP_LT_OQ);
    compare!(le, _CMP_LE_OQ);
    compare!(eq, _CMP_EQ_OQ);

    #[inline(always)]
    fn select(m: Mask16, a: Lanes16, b: Lanes16) -> Lanes16 {
        // SAFETY: as for the operators.
        Lanes16(unsafe { _mm512_mask_blend_ps(m.0, b.0, a.0) })
    }

    #[inline(always)]
    fn bits<const AVX: bool>(m: Mask16) -> u32 {
        u32::from(m.0)
    }

    #[inline(always)]
    fn any(m: Mask16) -> bool {
        m.0 != 0
    }
}
