//! Four `f64` lanes as a plain array, for weighing a light tree node's
//! children at once. Each operation is a branch-free loop over the lanes,
//! which the compiler turns into one AVX instruction where the caller is
//! compiled with AVX and into SSE2 pairs elsewhere, with the same IEEE
//! operation per lane either way (no fused multiply-add), so every lane
//! gives the bits of the scalar formula. `wide`'s `f64x4` is two SSE2
//! registers whatever the caller is compiled for, which halved the
//! throughput of the weighing on AVX machines.

use std::array::from_fn;
use std::ops::{Add, BitAnd, Div, Mul, MulAssign, Neg, Sub};

/// Four lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct F4(pub [f64; 4]);

/// Four lane flags: all bits set where true.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Mask4([u64; 4]);

impl F4 {
    pub const ZERO: F4 = F4([0.0; 4]);
    pub const ONE: F4 = F4([1.0; 4]);

    #[inline(always)]
    pub fn splat(x: f64) -> F4 {
        F4([x; 4])
    }

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

    #[inline(always)]
    pub fn sqrt(self) -> F4 {
        self.map(f64::sqrt)
    }

    /// The larger lane of each pair; `o` where `self` is NaN (as
    /// `maxpd` with `self` first).
    #[inline(always)]
    pub fn max(self, o: F4) -> F4 {
        self.zip(o, |a, b| if a > b { a } else { b })
    }

    #[inline(always)]
    pub fn abs(self) -> F4 {
        self.map(f64::abs)
    }

    /// Ordered comparisons: false where either side is NaN.
    #[inline(always)]
    pub fn gt(self, o: F4) -> Mask4 {
        self.compare(o, |a, b| a > b)
    }

    #[inline(always)]
    pub fn le(self, o: F4) -> Mask4 {
        self.compare(o, |a, b| a <= b)
    }

    #[inline(always)]
    pub fn lt(self, o: F4) -> Mask4 {
        self.compare(o, |a, b| a < b)
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

impl MulAssign for F4 {
    #[inline(always)]
    fn mul_assign(&mut self, o: F4) {
        *self = *self * o;
    }
}

impl Mask4 {
    #[inline(always)]
    pub fn from_flags(flags: [bool; 4]) -> Mask4 {
        Mask4(flags.map(|f| if f { !0 } else { 0 }))
    }

    /// `a` where the flag is set, else `b`, bit for bit.
    #[inline(always)]
    pub fn blend(self, a: F4, b: F4) -> F4 {
        F4(from_fn(|k| {
            let m = self.0[k];
            f64::from_bits((a.0[k].to_bits() & m) | (b.0[k].to_bits() & !m))
        }))
    }
}

impl BitAnd for Mask4 {
    type Output = Mask4;
    #[inline(always)]
    fn bitand(self, o: Mask4) -> Mask4 {
        Mask4(from_fn(|k| self.0[k] & o.0[k]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_lane_is_its_scalar_operation() {
        let a = F4([1.5, -0.0, f64::NAN, 4.0]);
        let b = F4([2.0, 0.0, 1.0, f64::NAN]);
        assert_eq!(a.max(b).0[..2], [2.0, 0.0]);
        assert_eq!(a.max(b).0[2], 1.0);
        assert!(a.max(b).0[3].is_nan());
        let m = a.gt(b);
        assert_eq!(m.0, [0, 0, 0, 0]);
        assert_eq!(b.gt(a).0, [!0, 0, 0, 0]);
        assert_eq!(a.le(b).0, [!0, !0, 0, 0]);
        let picked = b.lt(a).blend(a, b);
        assert_eq!(picked.0[0].to_bits(), 2.0f64.to_bits());
        assert_eq!(
            Mask4::from_flags([true, false, true, false])
                .blend(F4::ONE, F4::ZERO)
                .0,
            [1.0, 0.0, 1.0, 0.0]
        );
        assert_eq!(
            F4([4.0, 9.0, 2.0, -1.0]).sqrt().0[..3],
            [2.0, 3.0, 2f64.sqrt()]
        );
        assert_eq!((a - b).0[0], -0.5);
        assert_eq!((a / b).0[0], 0.75);
        assert_eq!((a + b).0[0], 3.5);
        assert_eq!((-a).0[0], -1.5);
        assert_eq!((F4::splat(-3.0).abs() * F4::ONE).0, [3.0; 4]);
    }
}
