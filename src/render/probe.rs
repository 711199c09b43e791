//! Looking at one pixel: the camera ray of its first sample, and its estimate
//! with a standard error, re-traced from the same sample streams the film
//! used (so the mean equals the film's pixel bit for bit, without the film
//! having to keep second moments).

use glam::Vec3;

use super::camera::CameraRays;
use super::integrator::Tracer;
use super::lights::LightList;
use super::options::RenderOptions;
use crate::geometry::{Ray, World};
use crate::sampling::Sampler;
use crate::scene::Scene;

/// The mean and standard error of a pixel's kept samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelEstimate {
    pub mean: Vec3,
    /// Standard error of the mean, per channel (sample standard deviation
    /// over the square root of the count); infinite below two samples.
    pub std_error: Vec3,
    /// Samples traced and samples kept (finite).
    pub taken: u32,
    pub kept: u32,
}

/// The ray of sample 0 of pixel `(x, y)` (row 0 at the top), as the film
/// traced it, in the frame whose origin is the scene point `frame`.
pub fn first_ray(scene: &Scene, options: &RenderOptions, x: u32, y: u32, frame: Vec3) -> Ray {
    let camera = CameraRays::new(&scene.camera, options.width, options.height, frame);
    let mut sampler = Sampler::for_sample(
        options.sampler,
        options.seed,
        x,
        y,
        options.first_sample().unwrap_or(0),
    );
    camera.ray(x, y, &mut sampler)
}

/// Re-traces the first `samples` samples of pixel `(x, y)` of the pass
/// `options` selects. Ignores `options.clamp` and `options.noise`: it is
/// meant for films rendered without them.
pub fn estimate(
    scene: &Scene,
    world: &World,
    options: &RenderOptions,
    x: u32,
    y: u32,
    samples: u32,
) -> PixelEstimate {
    let camera = CameraRays::new(&scene.camera, options.width, options.height, world.origin());
    let lights = LightList::for_render(
        scene,
        world,
        options.light_sampling,
        options.light_selection,
    );
    let tracer = Tracer::for_options(scene, world, &lights, options);
    let first = options.first_sample().unwrap_or(0);
    let (mut sum, mut sq, mut kept) = (Vec3::ZERO, glam::DVec3::ZERO, 0u32);
    let mut sampler = Sampler::new(options.sampler, options.seed);
    for s in 0..samples {
        let (l, _) = tracer.sample(&camera, &mut sampler, (x, y), first + s);
        if l.is_finite() {
            sum += l;
            sq += l.as_dvec3() * l.as_dvec3();
            kept += 1;
        }
    }
    let mean = if kept > 0 {
        sum / kept as f32
    } else {
        Vec3::ZERO
    };
    let std_error = if kept < 2 {
        Vec3::INFINITY
    } else {
        let n = kept as f64;
        let m = mean.as_dvec3();
        let var = ((sq - n * m * m) / (n - 1.0)).max(glam::DVec3::ZERO);
        (var / n).map(f64::sqrt).as_vec3()
    };
    PixelEstimate {
        mean,
        std_error,
        taken: samples,
        kept,
    }
}
