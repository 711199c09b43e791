//! The numeric built-in functions, shared by constant evaluation and the
//! constant folding of motion expressions.

use crate::lang::codes::Code;
use crate::scene::motion::{Fn1, Fn2, Fn3};

use super::issue::Issue;

/// Applies a one-argument function; domain errors are issues.
pub fn apply1(f: Fn1, x: f64) -> Result<f64, Issue> {
    let domain =
        |what: &str| Issue::new(Code::Domain, format!("{what} of {x}")).label("out of the domain");
    Ok(match f {
        Fn1::Sin => x.sin(),
        Fn1::Cos => x.cos(),
        Fn1::Tan => x.tan(),
        Fn1::Sqrt if x < 0.0 => return Err(domain("square root")),
        Fn1::Sqrt => x.sqrt(),
        Fn1::Abs => x.abs(),
        Fn1::Radians => x.to_radians(),
        Fn1::Degrees => x.to_degrees(),
        Fn1::Exp => x.exp(),
        Fn1::Ln if x <= 0.0 => return Err(domain("logarithm")),
        Fn1::Ln => x.ln(),
        Fn1::Floor => x.floor(),
    })
}

/// Applies a two-argument function.
pub fn apply2(f: Fn2, a: f64, b: f64) -> f64 {
    match f {
        Fn2::Min => a.min(b),
        Fn2::Max => a.max(b),
        Fn2::Pow => a.powf(b),
    }
}

/// Applies a three-argument function.
pub fn apply3(f: Fn3, a: f64, b: f64, c: f64) -> f64 {
    match f {
        Fn3::Lerp => a + (b - a) * c,
        Fn3::Clamp => c_clamp(a, b, c),
        Fn3::Smoothstep => {
            if b == a {
                return if c < a { 0.0 } else { 1.0 };
            }
            let x = c_clamp((c - a) / (b - a), 0.0, 1.0);
            x * x * (3.0 - 2.0 * x)
        }
    }
}

/// `clamp(x, lo, hi)` that never panics (unlike `f64::clamp` with lo > hi).
fn c_clamp(x: f64, lo: f64, hi: f64) -> f64 {
    x.max(lo).min(hi)
}

/// Piecewise interpolation of sorted `(time, value)` keys at `x`; constant
/// outside the table, smoothstep-eased between keys when `smooth`.
pub fn keyframes(keys: &[(f64, f64)], x: f64, smooth: bool) -> f64 {
    let Some(&(t0, v0)) = keys.first() else {
        return 0.0;
    };
    if x <= t0 {
        return v0;
    }
    for pair in keys.windows(2) {
        let ((ta, va), (tb, vb)) = (pair[0], pair[1]);
        if x <= tb {
            let mut u = (x - ta) / (tb - ta);
            if smooth {
                u = u * u * (3.0 - 2.0 * u);
            }
            return va + (vb - va) * u;
        }
    }
    keys[keys.len() - 1].1
}

/// A deterministic uniform number in [0, 1) hashed from `x` (splitmix64 of
/// its bits; `-0` and `0` hash alike).
pub fn random(x: f64) -> f64 {
    let x = if x == 0.0 { 0.0 } else { x };
    let mut z = x.to_bits().wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_is_deterministic_and_in_range() {
        let values: Vec<f64> = (0..1000).map(|i| random(i as f64)).collect();
        assert!(values.iter().all(|v| (0.0..1.0).contains(v)));
        assert_eq!(random(42.0), random(42.0));
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        assert!((mean - 0.5).abs() < 0.05, "mean {mean}");
    }

    #[test]
    fn keyframes_interpolate_and_hold() {
        let keys = [(0.0, 0.0), (0.5, 2.0), (1.0, 3.0)];
        assert_eq!(keyframes(&keys, -1.0, false), 0.0);
        assert_eq!(keyframes(&keys, 0.25, false), 1.0);
        assert_eq!(keyframes(&keys, 0.75, false), 2.5);
        assert_eq!(keyframes(&keys, 2.0, false), 3.0);
        assert_eq!(keyframes(&keys, 0.25, true), 1.0);
        assert!((keyframes(&keys, 0.125, true) - 2.0 * 0.15625).abs() < 1e-12);
    }
}
