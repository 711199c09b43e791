//! The path tracing integrator: iterative unidirectional path tracing with
//! Russian roulette after a few bounces and a maximum depth, and optionally
//! next-event estimation (a shadow ray to a sampled light point at every
//! diffuse or medium scattering) combined with the scattered ray's own hits
//! of lights by multiple importance sampling (power heuristic).
//!
//! Mirror, fuzzy metal and glass are not light-sampled: the emission their
//! scattered rays find counts in full. Shadow rays through media are blocked
//! by a sampled scattering event, an unbiased binary estimate of the
//! transmittance.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;

use super::lights::LightList;
use super::material::interact;
use super::sampler::{Dim, Sampler};
use super::texture::lookup;
use crate::geometry::ray::offset_origin;
use crate::geometry::{Hit, Ray, World};
use crate::scene::{Background, Material, Scene};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 4;

/// Shadow rays stop this fraction short of the light point.
const SHADOW_SHORTEN: f32 = 1e-4;

/// What one path needs: the scene's data and its geometry.
pub struct Tracer<'a> {
    pub scene: &'a Scene,
    pub world: &'a World,
    pub max_depth: u32,
    /// Whether to sample lights at diffuse and medium scatterings.
    pub light_sampling: bool,
}

/// How the last scattering chose the current ray's direction.
#[derive(Clone, Copy)]
enum Previous {
    /// A camera ray or a specular bounce: no light sampling competed.
    Specular,
    /// A light-sampled scattering at `point` whose sampling density of the
    /// direction (in solid angle) was `pdf`.
    Scattered { point: Vec3, pdf: f32 },
}

/// The power heuristic weight of a strategy with density `a` against `b`.
#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

impl Tracer<'_> {
    /// The radiance arriving along `ray` (unit direction) and the number of
    /// rays traced for it (shadow rays included).
    #[inline]
    pub fn radiance(&self, mut ray: Ray, rng: &mut Sampler) -> (Vec3, u32) {
        let lights = self.world.lights();
        let nee = self.light_sampling && !lights.is_empty();
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        let mut previous = Previous::Specular;
        let mut rays = 0u32;
        for depth in 0..self.max_depth {
            rays += 1;
            rng.start_bounce(depth);
            let Some(hit) = self.world.intersect(&ray, 0.0, f32::INFINITY, rng.rng()) else {
                radiance += throughput * background(&self.scene.settings.background, ray.dir);
                return (radiance, rays);
            };
            rng.begin(Dim::Bsdf);
            let step = interact(self.scene, &hit, ray.dir, rng);
            if step.emitted != Vec3::ZERO {
                let weight = match previous {
                    Previous::Scattered { point, pdf }
                        if nee && lights.is_sampled(hit.material) =>
                    {
                        power_heuristic(
                            pdf,
                            lights.pdf(hit.material, point, hit.point, hit.geo_normal),
                        )
                    }
                    _ => 1.0,
                };
                radiance += throughput * step.emitted * weight;
            }
            let Some((attenuation, dir)) = step.bounce else {
                return (radiance, rays);
            };
            previous = match self.scene.material(hit.material) {
                Material::Lambertian { albedo } if nee => {
                    let f = lookup(self.scene, *albedo, hit.uv, hit.point) * FRAC_1_PI;
                    rays += self.direct(
                        lights,
                        &hit,
                        ray.time,
                        rng,
                        |wi| {
                            let cos = hit.normal.dot(wi);
                            (cos > 0.0 && hit.geo_normal.dot(wi) > 0.0)
                                .then_some((f * cos, cos * FRAC_1_PI))
                        },
                        throughput,
                        &mut radiance,
                    );
                    Previous::Scattered {
                        point: hit.point,
                        pdf: hit.normal.dot(dir).max(0.0) * FRAC_1_PI,
                    }
                }
                Material::Isotropic { albedo } if nee => {
                    let f = lookup(self.scene, *albedo, hit.uv, hit.point) / (4.0 * PI);
                    rays += self.direct(
                        lights,
                        &hit,
                        ray.time,
                        rng,
                        |_| Some((f, 1.0 / (4.0 * PI))),
                        throughput,
                        &mut radiance,
                    );
                    Previous::Scattered {
                        point: hit.point,
                        pdf: 1.0 / (4.0 * PI),
                    }
                }
                _ => Previous::Specular,
            };
            throughput *= attenuation;
            if depth >= ROULETTE_AFTER {
                let survive = throughput.max_element().min(0.95);
                rng.begin(Dim::Roulette);
                if rng.next_1d() >= survive {
                    return (radiance, rays);
                }
                throughput /= survive;
            }
            ray = Ray::new(offset_origin(hit.point, hit.geo_normal, dir), dir, ray.time);
        }
        (radiance, rays)
    }

    /// Next-event estimation at `hit`: samples a light point, and if
    /// `scatter(wi)` gives the scattering value (BSDF × cosine) and its own
    /// sampling density, traces a shadow ray and adds the weighted light.
    /// Returns the rays traced.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn direct(
        &self,
        lights: &LightList,
        hit: &Hit,
        time: f32,
        rng: &mut Sampler,
        scatter: impl Fn(Vec3) -> Option<(Vec3, f32)>,
        throughput: Vec3,
        radiance: &mut Vec3,
    ) -> u32 {
        rng.begin(Dim::Light);
        let Some(s) = lights.sample(hit.point, rng) else {
            return 0;
        };
        let Some((f, scatter_pdf)) = scatter(s.dir) else {
            return 0;
        };
        if !(s.pdf > 0.0 && s.pdf.is_finite()) {
            return 0;
        }
        let origin = offset_origin(hit.point, hit.geo_normal, s.dir);
        let shadow = Ray::new(origin, s.dir, time);
        let t_max = s.dist * (1.0 - SHADOW_SHORTEN);
        if self
            .world
            .intersect(&shadow, 0.0, t_max, rng.rng())
            .is_some()
        {
            return 1;
        }
        let weight = power_heuristic(s.pdf, scatter_pdf);
        *radiance += throughput * f * s.emitted * (weight / s.pdf);
        1
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
