//! Warps from uniform numbers in [0, 1) to points and directions.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};

/// Uniform on the unit sphere.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (TAU * u.y).sin_cos();
    Vec3::new(r * c, r * s, z)
}

/// Uniform in the unit disk.
#[inline]
pub fn uniform_disk(u: Vec2) -> Vec2 {
    let r = u.x.sqrt();
    let (s, c) = (TAU * u.y).sin_cos();
    Vec2::new(r * c, r * s)
}

/// Uniform in the unit ball: a direction from `u`, a radius from `w`.
#[inline]
pub fn uniform_ball(u: Vec2, w: f32) -> Vec3 {
    uniform_sphere(u) * w.cbrt()
}

/// A direction about unit `n` with density cos θ / π.
#[inline]
pub fn cosine_hemisphere(n: Vec3, u: Vec2) -> Vec3 {
    let d = uniform_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    let (t, b) = n.any_orthonormal_pair();
    (d.x * t + d.y * b + z * n).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn cosine_directions_have_the_right_mean_cosine() {
        let mut rng = Rng::for_sample(3, 0, 0, 0);
        let n = Vec3::new(0.0, 0.6, 0.8);
        let count = 200_000;
        let mean: f32 = (0..count)
            .map(|_| {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                cosine_hemisphere(n, u).dot(n)
            })
            .sum::<f32>()
            / count as f32;
        // E[cos θ] = 2/3 under the cosine density (1/2 under uniform).
        assert!((mean - 2.0 / 3.0).abs() < 0.005, "mean cosine {mean}");
    }
}
