//! The lane arithmetic the flat-face passes are written in: the [`Wide`]
//! trait, and its eight-lane form as plain arrays whose branch-free loops
//! the compiler turns into vector instructions (AVX where the pass is
//! compiled with it, SSE otherwise).

use std::array::from_fn;
use std::fmt::Debug;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Not, Sub};

use crate::simd::LANES;

/// A vector of floats, one per face of a pack, with the IEEE operations of
/// the scalar tests lane by lane, so that every width gives each face the
/// same bits.
pub(super) trait Wide:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// Faces per pass.
    const LANES: usize;
    /// The lanes as a pack stores them.
    type Row: Copy + Debug;
    /// One flag per lane.
    type Mask: Copy
        + Debug
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + Not<Output = Self::Mask>;
    /// No lane set.
    const NONE: Self::Mask;

    /// A row of `value(lane)`: built with the packs, and for each pass of
    /// eight rays (their coordinates), so every impl is always inlined (a
    /// call there costs each pass six calls and their stack round trips).
    fn row(value: impl Fn(usize) -> f32) -> Self::Row;
    /// A mask of `flag(lane)` (built with the packs).
    fn mask(flag: impl Fn(usize) -> bool) -> Self::Mask;
    fn load(row: &Self::Row) -> Self;
    fn splat(x: f32) -> Self;
    fn lane(self, l: usize) -> f32;
    /// Lanes 8–15 moved onto lanes 0–7 where there are sixteen; eight
    /// lanes stay as they are.
    fn upper_half(self) -> Self;
    /// The smallest lane (no lane is NaN).
    fn least(self) -> f32;
    /// Ordered comparisons: false where either side is NaN.
    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn eq(self, o: Self) -> Self::Mask;
    /// `a` where `m` is set, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// Bit `lane` set where the lane is; `AVX` says the pass is compiled
    /// with AVX.
    fn bits<const AVX: bool>(m: Self::Mask) -> u32;
    fn any(m: Self::Mask) -> bool;
}

/// Eight floats. Each operation is a loop over the lanes with no branch.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Lanes8([f32; LANES]);

/// An eight-lane mask: all bits set where true.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Mask8([i32; LANES]);

/// A lane-by-lane operator of one of the two lane types.
macro_rules! lane_op {
    ($ty:ident, $trait:ident, $f:ident, $op:tt) => {
        impl $trait for $ty {
            type Output = $ty;
            #[inline(always)]
            fn $f(self, o: $ty) -> $ty {
                $ty(from_fn(|l| self.0[l] $op o.0[l]))
            }
        }
    };
}
lane_op!(Lanes8, Add, add, +);
lane_op!(Lanes8, Sub, sub, -);
lane_op!(Lanes8, Mul, mul, *);
lane_op!(Lanes8, Div, div, /);
lane_op!(Mask8, BitAnd, bitand, &);
lane_op!(Mask8, BitOr, bitor, |);

impl Not for Mask8 {
    type Output = Mask8;
    #[inline(always)]
    fn not(self) -> Mask8 {
        Mask8(self.0.map(|m| !m))
    }
}

impl Mask8 {
    /// [`Wide::bits`] in the copy compiled with AVX: one `vmovmskps`. The
    /// portable loop compiled there to a `vmovmskps` of the low half and
    /// shuffles, ands and ors for the high half (AVX has no 256-bit integer
    /// compare, so the lanes were split), some twenty instructions.
    ///
    /// # Safety
    /// Only in code compiled with AVX, on a CPU that has it.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn bits_avx(self) -> u32 {
        use std::arch::x86_64::{__m256, _mm256_movemask_ps};
        // SAFETY: eight i32 are the 32 bytes of an __m256; the caller
        // guarantees AVX.
        unsafe { _mm256_movemask_ps(std::mem::transmute::<[i32; LANES], __m256>(self.0)) as u32 }
    }
}

impl Wide for Lanes8 {
    const LANES: usize = crate::simd::LANES;
    type Row = Lanes8;
    type Mask = Mask8;
    const NONE: Mask8 = Mask8([0; LANES]);

    #[inline(always)]
    fn row(value: impl Fn(usize) -> f32) -> Lanes8 {
        Lanes8(from_fn(value))
    }

    fn mask(flag: impl Fn(usize) -> bool) -> Mask8 {
        Mask8(from_fn(|l| -i32::from(flag(l))))
    }

    #[inline(always)]
    fn load(row: &Lanes8) -> Lanes8 {
        *row
    }

    #[inline(always)]
    fn splat(x: f32) -> Lanes8 {
        Lanes8([x; LANES])
    }

    #[inline(always)]
    fn lane(self, l: usize) -> f32 {
        self.0[l]
    }

    #[inline(always)]
    fn upper_half(self) -> Lanes8 {
        self
    }

    /// Halving the lanes three times.
    #[inline(always)]
    fn least(self) -> f32 {
        let min = |a: f32, b: f32| if b < a { b } else { a };
        let x = self.0;
        let four: [f32; 4] = from_fn(|l| min(x[l], x[l + 4]));
        let two: [f32; 2] = from_fn(|l| min(four[l], four[l + 2]));
        min(two[0], two[1])
    }

    #[inline(always)]
    fn lt(self, o: Lanes8) -> Mask8 {
        Mask8(from_fn(|l| -i32::from(self.0[l] < o.0[l])))
    }

    #[inline(always)]
    fn le(self, o: Lanes8) -> Mask8 {
        Mask8(from_fn(|l| -i32::from(self.0[l] <= o.0[l])))
    }

    #[inline(always)]
    fn eq(self, o: Lanes8) -> Mask8 {
        Mask8(from_fn(|l| -i32::from(self.0[l] == o.0[l])))
    }

    #[inline(always)]
    fn select(m: Mask8, a: Lanes8, b: Lanes8) -> Lanes8 {
        Lanes8(from_fn(|l| if m.0[l] < 0 { a.0[l] } else { b.0[l] }))
    }

    /// [`Mask8::bits_avx`] in the AVX copy, else a loop over the lanes.
    #[inline(always)]
    fn bits<const AVX: bool>(m: Mask8) -> u32 {
        #[cfg(target_arch = "x86_64")]
        if AVX {
            // SAFETY: `AVX` is true only in the copies compiled with AVX,
            // which run only where the CPU has it.
            return unsafe { m.bits_avx() };
        }
        let mut bits = 0;
        for l in 0..LANES {
            bits |= (m.0[l] as u32 & 1) << l;
        }
        bits
    }

    #[inline(always)]
    fn any(m: Mask8) -> bool {
        let mut any = 0;
        for x in m.0 {
            any |= x;
        }
        any != 0
    }
}
