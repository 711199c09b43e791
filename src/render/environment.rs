//! The environment light: a latitude–longitude image of radiance around
//! the scene ([`crate::scene::Environment`], Mitsuba's orientation),
//! looked up at the nearest pixel and importance-sampled by a piecewise-
//! constant distribution over its pixels weighted by luminance × sin θ
//! (each row covers a band of solid angle proportional to sin θ), so the
//! density of a direction is the pixel's share over the solid angle of
//! the pixel: pdf(ω) = pdf(u, v) / (2π² sin θ).

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use crate::sampling::distribution::Distribution2D;
use crate::scene::{Environment, ImageData};

use super::lights::luminance;

/// An environment image ready to be looked up and sampled.
#[derive(Clone, Debug)]
pub struct EnvironmentMap {
    image: std::sync::Arc<ImageData>,
    strength: f32,
    /// Sine and cosine of the turn about +y.
    sin: f32,
    cos: f32,
    distribution: Distribution2D,
}

impl EnvironmentMap {
    pub fn new(env: &Environment) -> EnvironmentMap {
        let image = env.image.clone();
        let (w, h) = (image.width as usize, image.height as usize);
        let weights: Vec<f64> = image
            .pixels
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let theta = PI * ((k / w) as f32 + 0.5) / h as f32;
                f64::from(luminance(*p)) * f64::from(theta.sin())
            })
            .collect();
        let (sin, cos) = env.rotate.to_radians().sin_cos();
        EnvironmentMap {
            distribution: Distribution2D::new(&weights, w),
            image,
            strength: env.strength,
            sin,
            cos,
        }
    }

    /// ∫ luminance(L(ω)) dω over the sphere (the distribution's total of
    /// luminance × sin θ times each pixel's 2π/w × π/h).
    pub fn luminous_integral(&self) -> f64 {
        let (w, h) = (f64::from(self.image.width), f64::from(self.image.height));
        f64::from(self.strength) * self.distribution.total() * 2.0 * std::f64::consts::PI.powi(2)
            / (w * h)
    }

    /// The image coordinates (u right, v down, both in [0, 1]) seen along
    /// the world direction `dir` (unit), and sin θ there.
    fn uv(&self, dir: Vec3) -> (Vec2, f32) {
        // Into the image's own frame: turned back about +y.
        let x = self.cos * dir.x - self.sin * dir.z;
        let z = self.sin * dir.x + self.cos * dir.z;
        let y = dir.y;
        let mut u = x.atan2(-z) / TAU;
        if u < 0.0 {
            u += 1.0;
        }
        // θ and sin θ from the horizontal length too: acos and 1 − y² lose
        // their digits near the poles.
        let horizontal = (x * x + z * z).sqrt();
        (Vec2::new(u, horizontal.atan2(y) / PI), horizontal)
    }

    /// The world direction of image coordinates `uv` and its sin θ.
    fn direction(&self, uv: Vec2) -> (Vec3, f32) {
        let (sin_t, cos_t) = (PI * uv.y).sin_cos();
        let (sin_p, cos_p) = (TAU * uv.x).sin_cos();
        let (x, z) = (sin_t * sin_p, -sin_t * cos_p);
        let world = Vec3::new(
            self.cos * x + self.sin * z,
            cos_t,
            -self.sin * x + self.cos * z,
        );
        (world, sin_t)
    }

    /// The pixel at image coordinates `uv`, scaled by the strength.
    fn lookup(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.image.width, self.image.height);
        let x = ((uv.x * w as f32) as u32).min(w - 1);
        let y = ((uv.y * h as f32) as u32).min(h - 1);
        self.image.pixels[(y * w + x) as usize] * self.strength
    }

    /// The radiance arriving along the unit direction `dir` from the
    /// environment (seen looking along `dir`).
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        self.lookup(self.uv(dir).0)
    }

    /// The solid-angle density of [`EnvironmentMap::sample`] choosing `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let (uv, sin_t) = self.uv(dir);
        if sin_t <= 0.0 {
            return 0.0;
        }
        (self.distribution.density(uv) / (2.0 * std::f64::consts::PI.powi(2) * f64::from(sin_t)))
            as f32
    }

    /// A direction drawn by `u`, its radiance and solid-angle density
    /// (`None` at a pole, where the density is unbounded).
    pub fn sample(&self, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
        let (uv, pdf_uv) = self.distribution.sample(u);
        let (dir, sin_t) = self.direction(uv);
        if sin_t <= 0.0 || pdf_uv <= 0.0 {
            return None;
        }
        let pdf = pdf_uv / (2.0 * std::f64::consts::PI.powi(2) * f64::from(sin_t));
        Some((dir, self.lookup(uv), pdf as f32))
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::sampling::Rng;

    /// An image bright in one corner region and dim elsewhere, 16 × 8.
    fn lopsided(rotate: f32) -> EnvironmentMap {
        let (w, h) = (16u32, 8u32);
        let pixels = (0..w * h)
            .map(|k| {
                let (x, y) = (k % w, k / w);
                let v = if x < 3 && y < 4 {
                    20.0
                } else {
                    0.5 + 0.1 * x as f32
                };
                Vec3::new(v, 0.5 * v, 0.25 * v)
            })
            .collect();
        EnvironmentMap::new(&Environment {
            image: Arc::new(ImageData {
                width: w,
                height: h,
                pixels,
            }),
            rotate,
            strength: 1.5,
        })
    }

    #[test]
    fn directions_and_image_coordinates_round_trip_in_mitsubas_orientation() {
        let env = lopsided(0.0);
        // The centre of the image faces +z, a quarter in from the left +x.
        let (uv, _) = env.uv(Vec3::Z);
        assert!((uv - Vec2::new(0.5, 0.5)).length() < 1e-6, "{uv}");
        let (uv, _) = env.uv(Vec3::X);
        assert!((uv - Vec2::new(0.25, 0.5)).length() < 1e-6, "{uv}");
        assert!(env.uv(Vec3::Y).0.y < 1e-6);
        for rotate in [0.0, 90.0, 33.0] {
            let env = lopsided(rotate);
            for k in 0..50 {
                let uv = Vec2::new(
                    (k as f32 * 0.137) % 1.0,
                    0.02 + 0.96 * ((k as f32 * 0.311) % 1.0),
                );
                let (dir, _) = env.direction(uv);
                let (back, _) = env.uv(dir);
                let du = (back.x - uv.x).abs();
                assert!(du.min(1.0 - du) < 1e-4 && (back.y - uv.y).abs() < 1e-4);
            }
        }
        // Turned by 90° about +y, what faced +z now faces +x.
        let turned = lopsided(90.0);
        assert_eq!(turned.radiance(Vec3::X), lopsided(0.0).radiance(Vec3::Z));
    }

    /// The solid-angle density integrates to 1 over the sphere (midpoint
    /// rule on a fine grid of directions), every sample's density is the
    /// density of its direction, and a histogram of sampled directions over
    /// the pixels matches the pixels' probabilities (χ² below the 0.999
    /// quantile).
    #[test]
    fn the_density_integrates_to_one_and_matches_the_sampled_histogram() {
        for rotate in [0.0, 71.0] {
            let env = lopsided(rotate);
            let (nu, nv) = (256, 128);
            let mut integral = 0.0f64;
            for j in 0..nv {
                let theta = PI * (j as f32 + 0.5) / nv as f32;
                for i in 0..nu {
                    let phi = TAU * (i as f32 + 0.5) / nu as f32;
                    let dir = Vec3::new(
                        theta.sin() * phi.cos(),
                        theta.cos(),
                        theta.sin() * phi.sin(),
                    );
                    let dw = (TAU / nu as f32) * (PI / nv as f32) * theta.sin();
                    integral += f64::from(env.pdf(dir) * dw);
                }
            }
            assert!((integral - 1.0).abs() < 2e-3, "{integral}");
            let mut rng = Rng::for_sample(3, 0, 0, 0);
            let (w, h) = (16usize, 8usize);
            let mut counts = vec![0f64; w * h];
            let n = 100_000;
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let (dir, l, pdf) = env.sample(u).expect("a direction");
                assert!(
                    (env.pdf(dir) - pdf).abs() <= 1e-3 * pdf,
                    "{} vs {pdf}",
                    env.pdf(dir)
                );
                assert_eq!(l, env.radiance(dir));
                let (uv, _) = env.uv(dir);
                let (x, y) = (
                    ((uv.x * 16.0) as usize).min(15),
                    ((uv.y * 8.0) as usize).min(7),
                );
                counts[y * w + x] += 1.0;
            }
            let total = env.distribution.total();
            let mut chi2 = 0.0;
            for (k, p) in env.image.pixels.iter().enumerate() {
                let theta = PI * ((k / w) as f32 + 0.5) / h as f32;
                let expected = n as f64 * f64::from(luminance(*p) * theta.sin()) / total;
                chi2 += (counts[k] - expected).powi(2) / expected;
            }
            // 127 degrees of freedom: the 0.999 quantile is about 181.
            assert!(chi2 < 181.0, "χ² = {chi2}");
        }
    }
}
