//! Four `f64` lanes, for weighing a light tree node's children at once,
//! behind one trait ([`Wide`]) with two kinds: [`F4`], a plain array whose
//! operations are loops over the lanes (SSE2 pairs, or what the compiler
//! makes of them), and on x86-64 [`Avx4`], one AVX register per value with
//! an AVX instruction per operation. Both do the same IEEE operation per
//! lane (no fused multiply-add), so every lane gives the bits of the scalar
//! formula. `Avx4` exists because the compiler turned some of `F4`'s
//! blends into a branch per lane even where AVX was enabled, and those
//! branches follow the data. `wide`'s `f64x4` is two SSE2 registers
//! whatever the caller is compiled for.

use std::array::from_fn;
use std::ops::{Add, BitAnd, Div, Mul, Neg, Sub};

/// Four `f64` lanes and their lane masks.
pub trait Wide:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Four lane flags.
    type Mask: Copy + BitAnd<Output = Self::Mask>;
    fn splat(x: f64) -> Self;
    fn new(lanes: [f64; 4]) -> Self;
    fn lanes(self) -> [f64; 4];
    fn sqrt(self) -> Self;
    /// The larger lane of each pair; `o` where either is NaN (as `maxpd`
    /// with `self` first).
    fn max(self, o: Self) -> Self;
    fn abs(self) -> Self;
    /// Ordered comparisons: false where either side is NaN.
    fn gt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn lt(self, o: Self) -> Self::Mask;
    fn flags(flags: [bool; 4]) -> Self::Mask;
    /// `a` where `mask` is set, else `b`, bit for bit.
    fn blend(mask: Self::Mask, a: Self, b: Self) -> Self;
}

/// Four lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct F4(pub [f64; 4]);

/// Four lane flags: all bits set where true.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Mask4([u64; 4]);

impl F4 {
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> F4 {
        F4(from_fn(|k| f(self.0[k])))
    }

    #[inline(always)]
    fn zip(self, o: F4, f: impl Fn(f64, f64) -> f64) -> F4 {
        F4(from_fn(|k| f(self.0[k], o.0[k])))
    }

    #[inline(always)]
    fn compare(self, o: F4, f: impl Fn(f64, f64) -> bool) -> Mask4 {
        Mask4(from_fn(|k| if f(self.0[k], o.0[k]) { !0 } else { 0 }))
    }
}

impl Wide for F4 {
    type Mask = Mask4;

    #[inline(always)]
    fn splat(x: f64) -> F4 {
        F4([x; 4])
    }

    #[inline(always)]
    fn new(lanes: [f64; 4]) -> F4 {
        F4(lanes)
    }

    #[inline(always)]
    fn lanes(self) -> [f64; 4] {
        self.0
    }

    #[inline(always)]
    fn sqrt(self) -> F4 {
        self.map(f64::sqrt)
    }

    #[inline(always)]
    fn max(self, o: F4) -> F4 {
        self.zip(o, |a, b| if a > b { a } else { b })
    }

    #[inline(always)]
    fn abs(self) -> F4 {
        self.map(f64::abs)
    }

    #[inline(always)]
    fn gt(self, o: F4) -> Mask4 {
        self.compare(o, |a, b| a > b)
    }

    #[inline(always)]
    fn le(self, o: F4) -> Mask4 {
        self.compare(o, |a, b| a <= b)
    }

    #[inline(always)]
    fn lt(self, o: F4) -> Mask4 {
        self.compare(o, |a, b| a < b)
    }

    #[inline(always)]
    fn flags(flags: [bool; 4]) -> Mask4 {
        Mask4(flags.map(|f| if f { !0 } else { 0 }))
    }

    #[inline(always)]
    fn blend(mask: Mask4, a: F4, b: F4) -> F4 {
        F4(from_fn(|k| {
            let m = mask.0[k];
            f64::from_bits((a.0[k].to_bits() & m) | (b.0[k].to_bits() & !m))
        }))
    }
}

/// The binary operators, lane by lane.
macro_rules! lanewise {
    ($($trait:ident $method:ident $op:tt),*) => {$(
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, o: F4) -> F4 {
                self.zip(o, |a, b| a $op b)
            }
        }
    )*};
}

lanewise!(Add add +, Sub sub -, Mul mul *, Div div /);

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        self.map(|a| -a)
    }
}

impl BitAnd for Mask4 {
    type Output = Mask4;
    #[inline(always)]
    fn bitand(self, o: Mask4) -> Mask4 {
        Mask4(from_fn(|k| self.0[k] & o.0[k]))
    }
}

/// Four lanes in one AVX register (x86-64). Its operations are safe to
/// call but run AVX instructions, so it is made only inside functions
/// compiled with AVX that run where the CPU has it ([`crate::simd::avx`]),
/// and it is not visible outside `render`.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub(super) struct Avx4(std::arch::x86_64::__m256d);

/// [`Avx4`]'s lane flags: all bits set where true.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub(super) struct AvxMask(std::arch::x86_64::__m256d);

/// The operations of [`Avx4`], each one AVX instruction.
#[cfg(target_arch = "x86_64")]
mod avx {
    use std::arch::x86_64::*;
    use std::ops::{Add, BitAnd, Div, Mul, Neg, Sub};

    use super::{Avx4, AvxMask, Wide};

    /// An AVX intrinsic's value.
    macro_rules! avx {
        ($e:expr) => {
            // SAFETY: an `Avx4` or `AvxMask` is made only in functions
            // compiled with AVX that run where the CPU has it, and every
            // pointer given is a whole `[f64; 4]`.
            unsafe { $e }
        };
    }

    macro_rules! binary {
        ($($trait:ident $method:ident $intrinsic:ident),*) => {$(
            impl $trait for Avx4 {
                type Output = Avx4;
                #[inline(always)]
                fn $method(self, o: Avx4) -> Avx4 {
                    Avx4(avx!($intrinsic(self.0, o.0)))
                }
            }
        )*};
    }

    binary!(Add add _mm256_add_pd, Sub sub _mm256_sub_pd, Mul mul _mm256_mul_pd, Div div _mm256_div_pd);

    impl Neg for Avx4 {
        type Output = Avx4;
        #[inline(always)]
        fn neg(self) -> Avx4 {
            Avx4(avx!(_mm256_xor_pd(self.0, _mm256_set1_pd(-0.0))))
        }
    }

    impl BitAnd for AvxMask {
        type Output = AvxMask;
        #[inline(always)]
        fn bitand(self, o: AvxMask) -> AvxMask {
            AvxMask(avx!(_mm256_and_pd(self.0, o.0)))
        }
    }

    impl Wide for Avx4 {
        type Mask = AvxMask;

        #[inline(always)]
        fn splat(x: f64) -> Avx4 {
            Avx4(avx!(_mm256_set1_pd(x)))
        }

        #[inline(always)]
        fn new(lanes: [f64; 4]) -> Avx4 {
            Avx4(avx!(_mm256_loadu_pd(lanes.as_ptr())))
        }

        #[inline(always)]
        fn lanes(self) -> [f64; 4] {
            let mut out = [0.0; 4];
            avx!(_mm256_storeu_pd(out.as_mut_ptr(), self.0));
            out
        }

        #[inline(always)]
        fn sqrt(self) -> Avx4 {
            Avx4(avx!(_mm256_sqrt_pd(self.0)))
        }

        /// `maxpd` returns its second operand where either is NaN, as
        /// `if a > b { a } else { b }`.
        #[inline(always)]
        fn max(self, o: Avx4) -> Avx4 {
            Avx4(avx!(_mm256_max_pd(self.0, o.0)))
        }

        #[inline(always)]
        fn abs(self) -> Avx4 {
            Avx4(avx!(_mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0)))
        }

        #[inline(always)]
        fn gt(self, o: Avx4) -> AvxMask {
            AvxMask(avx!(_mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0)))
        }

        #[inline(always)]
        fn le(self, o: Avx4) -> AvxMask {
            AvxMask(avx!(_mm256_cmp_pd::<_CMP_LE_OQ>(self.0, o.0)))
        }

        #[inline(always)]
        fn lt(self, o: Avx4) -> AvxMask {
            AvxMask(avx!(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0)))
        }

        #[inline(always)]
        fn flags(flags: [bool; 4]) -> AvxMask {
            let bits = flags.map(|f| if f { f64::from_bits(!0) } else { 0.0 });
            AvxMask(avx!(_mm256_loadu_pd(bits.as_ptr())))
        }

        #[inline(always)]
        fn blend(mask: AvxMask, a: Avx4, b: Avx4) -> Avx4 {
            Avx4(avx!(_mm256_blendv_pd(b.0, a.0, mask.0)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every operation of a kind of lanes, on NaNs, signed zeros and
    /// ordinary values.
    fn check<V: Wide>() {
        let a = V::new([1.5, -0.0, f64::NAN, 4.0]);
        let b = V::new([2.0, 0.0, 1.0, f64::NAN]);
        let (one, zero) = (V::splat(1.0), V::splat(0.0));
        let bits = |v: V| v.lanes().map(f64::to_bits);
        let picks = |m: V::Mask| V::blend(m, one, zero).lanes();
        assert_eq!(a.max(b).lanes()[..3], [2.0, 0.0, 1.0]);
        assert!(a.max(b).lanes()[3].is_nan());
        assert_eq!(picks(a.gt(b)), [0.0; 4]);
        assert_eq!(picks(b.gt(a)), [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(picks(a.le(b)), [1.0, 1.0, 0.0, 0.0]);
        assert_eq!(picks(a.lt(b)), [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(picks(a.le(b) & b.gt(a)), [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(
            picks(V::flags([true, false, true, false])),
            [1.0, 0.0, 1.0, 0.0]
        );
        assert_eq!(bits(V::blend(b.lt(a), a, b))[0], 2.0f64.to_bits());
        let roots = V::new([4.0, 9.0, 2.0, -1.0]).sqrt().lanes();
        assert_eq!(roots[..3], [2.0, 3.0, 2f64.sqrt()]);
        assert!(roots[3].is_nan());
        assert_eq!((a - b).lanes()[..2], [-0.5, -0.0]);
        assert_eq!((a / b).lanes()[0], 0.75);
        assert_eq!((a + b).lanes()[0], 3.5);
        assert_eq!((a * b).lanes()[0], 3.0);
        assert_eq!(bits(-a)[..2], [(-1.5f64).to_bits(), 0.0f64.to_bits()]);
        assert_eq!(
            bits(V::new([-3.0, -0.0, 2.0, 0.0]).abs()),
            [3.0, 0.0, 2.0, 0.0].map(f64::to_bits)
        );
    }

    #[test]
    fn every_lane_is_its_scalar_operation() {
        check::<F4>();
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx_lanes_are_the_array_lanes() {
        #[target_feature(enable = "avx")]
        fn with_avx() {
            check::<Avx4>();
        }
        if crate::simd::avx() {
            // SAFETY: the CPU has AVX.
            unsafe { with_avx() };
        }
    }
}
