//! The path tracing integrator: iterative unidirectional path tracing with
//! Russian roulette after a few bounces and a maximum depth.

use glam::Vec3;

use super::material::interact;
use super::rng::Rng;
use crate::geometry::ray::offset_origin;
use crate::geometry::{Ray, World};
use crate::scene::{Background, Scene};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 4;

/// What one path needs: the scene's data and its geometry.
pub struct Tracer<'a> {
    pub scene: &'a Scene,
    pub world: &'a World,
    pub max_depth: u32,
}

impl Tracer<'_> {
    /// The radiance arriving along `ray` (unit direction) and the number of
    /// rays traced for it.
    #[inline]
    pub fn radiance(&self, mut ray: Ray, rng: &mut Rng) -> (Vec3, u32) {
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        for depth in 0..self.max_depth {
            let Some(hit) = self.world.intersect(&ray, 0.0, f32::INFINITY, rng) else {
                radiance += throughput * background(&self.scene.settings.background, ray.dir);
                return (radiance, depth + 1);
            };
            let step = interact(self.scene, &hit, ray.dir, rng);
            radiance += throughput * step.emitted;
            let Some((attenuation, dir)) = step.bounce else {
                return (radiance, depth + 1);
            };
            throughput *= attenuation;
            if depth >= ROULETTE_AFTER {
                let survive = throughput.max_element().min(0.95);
                if rng.next_f32() >= survive {
                    return (radiance, depth + 1);
                }
                throughput /= survive;
            }
            ray = Ray::new(offset_origin(hit.point, hit.geo_normal, dir), dir, ray.time);
        }
        (radiance, self.max_depth)
    }
}

/// The colour seen along a ray that leaves the scene.
#[inline]
pub fn background(bg: &Background, dir: Vec3) -> Vec3 {
    match *bg {
        Background::Solid(c) => c,
        Background::Gradient { bottom, top } => {
            let t = 0.5 * (dir.normalize_or_zero().y + 1.0);
            bottom.lerp(top, t)
        }
    }
}
