//! Warps from uniform numbers in [0, 1) to points and directions.

use std::f32::consts::FRAC_PI_2;

use glam::{Vec2, Vec3};

/// `(sin 2πu, cos 2πu)` for `u` in [0, 1]: the turn is split into quarter
/// turns (exact: `4u` and its rounding lose no bits of a sample), the rest
/// is an angle in [−π/4, π/4] whose sine and cosine are their Taylor
/// polynomials to x⁹ and x⁸ (truncation below 3e-8, under the rounding of
/// an `f32`), and the quarter turns rotate the pair. Plain multiplications
/// and additions, so every CPU gives the same bits, which the C library's
/// `sincosf` (a different routine with and without FMA) does not promise.
#[inline]
pub fn sin_cos_turn(u: f32) -> (f32, f32) {
    /// 1.5 · 2²³: an `f32` at least this large is an integer.
    const MAGIC: f32 = 12_582_912.0;
    // The nearest quarter turn, `⌊4u + 0.5⌋` (`4u + 0.5` cannot round
    // across an integer). Adding 1.5·2²³ rounds a number below 2²² to the
    // nearest integer; the floor is one less where that rounded up (`trunc`
    // was a call into the C library where the CPU has no rounding
    // instruction). The integer is then read from the bits of
    // `quarters + 1.5·2²³`, whose last place is 1: unlike `as i32`, which
    // saturates and so compiled to a scalar conversion and two conditional
    // moves per lane, this vectorises in the lanes.
    let half_up = 4.0 * u + 0.5;
    let nearest = (half_up + MAGIC) - MAGIC;
    let quarters = if nearest > half_up {
        nearest - 1.0
    } else {
        nearest
    };
    let x = (4.0 * u - quarters) * FRAC_PI_2;
    let x2 = x * x;
    let sin = x
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0))));
    // Rotate by the quarter turns, (sin, cos) → (cos, −sin) → (−sin, −cos) →
    // (−cos, sin), by bit operations: the quarter is as random as the
    // sample, and a branch on it would go astray three times in four.
    let q = (quarters + MAGIC).to_bits().wrapping_sub(MAGIC.to_bits());
    let swap = 0u32.wrapping_sub(q & 1);
    let (sin, cos) = (sin.to_bits(), cos.to_bits());
    let first = (cos & swap) | (sin & !swap);
    let second = (sin & swap) | (cos & !swap);
    (
        f32::from_bits(first ^ ((q & 2) << 30)),
        f32::from_bits(second ^ ((q.wrapping_add(1) & 2) << 30)),
    )
}

/// Uniform on the unit sphere.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos_turn(u.y);
    Vec3::new(r * c, r * s, z)
}

/// Uniform in the unit disk.
#[inline]
pub fn uniform_disk(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let (s, c) = sin_cos_turn(u.y);
    Vec2::new(r * c, r * s)
}

/// Uniform in the unit ball: a direction from `u`, a radius from `w`.
#[inline]
pub fn uniform_ball(u: Vec2, w: f32) -> Vec3 {
    uniform_sphere(u) * w.cbrt()
}

/// A direction about unit `n` with density cos θ / π. It is unit to a few
/// roundings without a normalisation: the disk point and its height are a
/// unit vector in the orthonormal frame of `n`.
#[inline]
pub fn cosine_hemisphere(n: Vec3, u: Vec2) -> Vec3 {
    let d = uniform_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    let (t, b) = n.any_orthonormal_pair();
    d.x * t + d.y * b + z * n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn sine_and_cosine_of_a_turn_are_within_two_ulps_of_one() {
        let mut worst = 0.0f64;
        for i in 0..=1 << 20 {
            let u = i as f32 / (1 << 20) as f32;
            let (s, c) = sin_cos_turn(u);
            let a = std::f64::consts::TAU * f64::from(u);
            worst = worst
                .max((f64::from(s) - a.sin()).abs())
                .max((f64::from(c) - a.cos()).abs());
        }
        assert!(worst < f64::from(f32::EPSILON), "error {worst:e}");
        // The quarter turns are exact.
        assert_eq!(sin_cos_turn(0.25), (1.0, 0.0));
        assert_eq!(sin_cos_turn(0.5), (0.0, -1.0));
        assert_eq!(sin_cos_turn(0.75), (-1.0, 0.0));
        assert_eq!(sin_cos_turn(1.0), (0.0, 1.0));
    }

    #[test]
    fn cosine_directions_have_the_right_mean_cosine() {
        let mut rng = Rng::for_sample(3, 0, 0, 0);
        let n = Vec3::new(0.0, 0.6, 0.8);
        let count = 200_000;
        let mean: f32 = (0..count)
            .map(|_| {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let d = cosine_hemisphere(n, u);
                assert!((d.length() - 1.0).abs() < 4.0 * f32::EPSILON, "{d}");
                d.dot(n)
            })
            .sum::<f32>()
            / count as f32;
        // E[cos θ] = 2/3 under the cosine density (1/2 under uniform).
        assert!((mean - 2.0 / 3.0).abs() < 0.005, "mean cosine {mean}");
    }
}
