//! The fuzzy-metal lobe: directions normalize(r + fuzz·u) with r the unit
//! mirror direction and u uniform in the unit ball, and the closed-form
//! solid-angle density of that distribution, so light sampling can weigh it.
//!
//! The points r + fuzz·u fill a ball of radius f = fuzz around r with density
//! 1 / (4/3 π f³). A direction w collects the points t·w, t ≥ 0, inside the
//! ball: t in [t0, t1] with t0,1 = w·r ∓ sqrt(f² − |w × r|²), so its density
//! is ∫ t² dt / (4/3 π f³) = (t1³ − max(t0, 0)³) / (4 π f³).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::sampling::warp::uniform_ball;

/// Fuzz below which a metal is a perfect mirror (a specular lobe). A sampled
/// direction is normalised in f32, which moves it by up to about 1e-7; the
/// density above depends on |w × r| measured against f, so at f = 1e-4 that
/// error is 0.1 % of the lobe's radius (the histogram test holds there), and
/// below it the density of the directions actually produced stops being the
/// formula's. A lobe 1e-4 rad wide is also far below a pixel of any camera.
pub const SPECULAR_FUZZ: f32 = 1e-4;

/// The unnormalised direction r + fuzz·u for uniform numbers `u2`, `u1`.
#[inline]
pub fn sample(r: Vec3, fuzz: f32, u2: Vec2, u1: f32) -> Vec3 {
    r + fuzz * uniform_ball(u2, u1)
}

/// The solid-angle density of normalize(r + fuzz·u) at unit `w`.
#[inline]
pub fn pdf(r: Vec3, fuzz: f32, w: Vec3) -> f32 {
    // |w × r|² = |r|² − (w·r)² for unit w, without the cancellation.
    let s2 = fuzz * fuzz - w.cross(r).length_squared();
    if s2 <= 0.0 {
        return 0.0;
    }
    let s = s2.sqrt();
    let b = w.dot(r);
    let (t0, t1) = (b - s, b + s);
    if t1 <= 0.0 {
        return 0.0;
    }
    // t1³ − t0³ = (t1 − t0)(t1² + t1·t0 + t0²), exact in the width 2s.
    let cubes = if t0 > 0.0 {
        2.0 * s * (t1 * t1 + t1 * t0 + t0 * t0)
    } else {
        t1 * t1 * t1
    };
    cubes / (4.0 * PI * fuzz * fuzz * fuzz)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;
    use std::f64::consts::PI as PI64;

    /// A frame (t, b, r) around unit `r`.
    fn frame(r: Vec3) -> (Vec3, Vec3) {
        r.any_orthonormal_pair()
    }

    /// The direction at angle `theta` from `r` and azimuth `phi`.
    fn direction(r: Vec3, theta: f64, phi: f64) -> Vec3 {
        let (t, b) = frame(r);
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        (t * (st * cp) as f32 + b * (st * sp) as f32 + r * ct as f32).normalize()
    }

    /// ∫ pdf · 1[w · n > 0] over θ in [θa, θb) and φ in [φa, φb) around r,
    /// by the midpoint rule on a fine grid (the lobe lies within θ ≤ asin f).
    fn integral(r: Vec3, fuzz: f32, n: Vec3, th: (f64, f64), ph: (f64, f64)) -> f64 {
        let steps = 400;
        let (dt, dp) = ((th.1 - th.0) / steps as f64, (ph.1 - ph.0) / steps as f64);
        let mut sum = 0.0;
        for i in 0..steps {
            let theta = th.0 + (i as f64 + 0.5) * dt;
            for j in 0..steps {
                let w = direction(r, theta, ph.0 + (j as f64 + 0.5) * dp);
                if w.dot(n) > 0.0 {
                    sum += pdf(r, fuzz, w) as f64 * theta.sin() * dt * dp;
                }
            }
        }
        sum
    }

    /// The widest angle of the lobe around r.
    fn lobe_angle(fuzz: f32) -> f64 {
        (fuzz as f64).min(1.0).asin()
    }

    #[test]
    fn the_density_integrates_to_one_when_the_lobe_is_above_the_surface() {
        let r = Vec3::new(0.3, 0.9, -0.2).normalize();
        // The normal r itself: the whole lobe (θ < 90°) is above it.
        for fuzz in [SPECULAR_FUZZ, 0.01, 0.3, 0.9] {
            let total = integral(r, fuzz, r, (0.0, lobe_angle(fuzz)), (0.0, 2.0 * PI64));
            assert!((total - 1.0).abs() < 2e-3, "fuzz {fuzz}: {total}");
        }
        // fuzz 1: the ball touches the origin, the lobe is the hemisphere.
        let total = integral(r, 1.0, r, (0.0, PI64 / 2.0), (0.0, 2.0 * PI64));
        assert!((total - 1.0).abs() < 2e-3, "fuzz 1: {total}");
    }

    #[test]
    fn the_density_integrates_to_the_fraction_of_samples_above_a_grazing_surface() {
        // A mirror direction 10° above the surface with a lobe of 30°: part
        // of the ball falls below and is absorbed.
        let n = Vec3::Y;
        let r = Vec3::new(10f32.to_radians().cos(), 10f32.to_radians().sin(), 0.0);
        let fuzz = 0.5;
        let total = integral(r, fuzz, n, (0.0, lobe_angle(fuzz)), (0.0, 2.0 * PI64));
        let mut rng = Rng::for_sample(7, 0, 0, 0);
        let count = 400_000;
        let above = (0..count)
            .filter(|_| {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                sample(r, fuzz, u, rng.next_f32()).dot(n) > 0.0
            })
            .count() as f64
            / count as f64;
        // Binomial standard error below 8e-4: allow 5 of them.
        assert!(above < 0.95, "the test should clip the lobe: {above}");
        assert!((total - above).abs() < 4e-3, "{total} vs {above}");
    }

    #[test]
    fn sampled_directions_follow_the_density() {
        // An 8 × 8 histogram in (θ, φ) around r, clipped by a grazing
        // surface; each bin's count must be within 5 binomial standard
        // errors (plus 0.2 % of the quadrature) of count × ∫bin pdf.
        let n = Vec3::Y;
        for (elevation, fuzz) in [(10f32, 0.5f32), (60.0, 0.05), (45.0, SPECULAR_FUZZ)] {
            let e = elevation.to_radians();
            let r = Vec3::new(e.cos(), e.sin(), 0.0);
            let (t, b) = frame(r);
            let top = lobe_angle(fuzz);
            let bins = 8;
            let count = 200_000;
            let mut hist = vec![0u32; bins * bins];
            let mut rng = Rng::for_sample(11, 1, 2, 3);
            for _ in 0..count {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let d = sample(r, fuzz, u, rng.next_f32());
                if d.dot(n) <= 0.0 {
                    continue;
                }
                let w = d.normalize();
                let theta = (w.cross(r).length() as f64).atan2(w.dot(r) as f64);
                let phi = (w.dot(b) as f64)
                    .atan2(w.dot(t) as f64)
                    .rem_euclid(2.0 * PI64);
                let i = ((theta / top * bins as f64) as usize).min(bins - 1);
                let j = ((phi / (2.0 * PI64) * bins as f64) as usize).min(bins - 1);
                hist[i * bins + j] += 1;
            }
            for i in 0..bins {
                for j in 0..bins {
                    let th = (
                        top * i as f64 / bins as f64,
                        top * (i + 1) as f64 / bins as f64,
                    );
                    let step = 2.0 * PI64 / bins as f64;
                    let ph = (step * j as f64, step * (j + 1) as f64);
                    let p = integral(r, fuzz, n, th, ph);
                    let expected = p * count as f64;
                    let sigma = (count as f64 * p * (1.0 - p)).sqrt();
                    let got = hist[i * bins + j] as f64;
                    assert!(
                        (got - expected).abs() <= 5.0 * sigma + 2e-3 * expected + 1.0,
                        "fuzz {fuzz}, bin ({i}, {j}): {got} vs {expected:.1}"
                    );
                }
            }
        }
    }
}
