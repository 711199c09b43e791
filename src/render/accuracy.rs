//! The speed/accuracy trade of surfaces of revolution, measured: a scene is
//! rendered with every revolution surface switched to each of several modes
//! (meshes of several resolutions, analytic at several tolerances), and
//! each setting is scored by render time, the distance of its hit points to
//! the exact surface, and image RMSE against a reference setting.
//!
//! Renders of all settings share one seed (common random numbers), so the
//! RMSE shows what the geometry changes, not sampling noise; the noise floor
//! (the reference against itself with another seed) is reported beside it.

use std::time::Instant;

use glam::Vec3;

use super::camera::CameraRays;
use super::{render, RenderError, RenderOptions};
use crate::geometry::revolution::surface_distance;
use crate::geometry::{BuildError, World};
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::object::RevolutionMode;
use crate::scene::{Bezier, Node, Scene, Shape};

/// The score of one setting.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyRow {
    pub mode: RevolutionMode,
    /// Wall-clock seconds of the render (world build excluded).
    pub seconds: f64,
    /// Distance of camera-ray hit points to the exact surface, scene units.
    pub max_error: f64,
    pub mean_error: f64,
    /// Hit points the errors were taken over.
    pub hits: usize,
    /// RMSE of the linear image against the reference setting's.
    pub rmse: f64,
}

/// The whole measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyReport {
    pub rows: Vec<AccuracyRow>,
    /// RMSE of the reference against itself rendered with another seed.
    pub noise_floor: f64,
}

/// Why a measurement could not run.
#[derive(Debug, thiserror::Error)]
pub enum AccuracyError {
    #[error(transparent)]
    Build(#[from] BuildError),
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error("the scene has no surface of revolution outside a transform")]
    NoRevolution,
}

/// `scene` with every untransformed surface of revolution set to `mode`.
pub fn with_mode(scene: &Scene, mode: RevolutionMode) -> Scene {
    fn visit(node: &mut Node, mode: RevolutionMode) {
        match node {
            Node::Shape {
                shape: Shape::Revolution { mode: m, .. },
                ..
            } => *m = mode,
            Node::Group(children) => children.iter_mut().for_each(|c| visit(c, mode)),
            _ => {}
        }
    }
    let mut out = scene.clone();
    out.objects.iter_mut().for_each(|n| visit(n, mode));
    out
}

/// The untransformed revolution surfaces of `scene`, as their own scene.
fn revolutions_only(scene: &Scene) -> (Scene, Vec<Bezier>) {
    fn collect(node: &Node, out: &mut Vec<Node>) {
        match node {
            Node::Shape {
                shape: Shape::Revolution { .. },
                ..
            } => out.push(node.clone()),
            Node::Group(children) => children.iter().for_each(|c| collect(c, out)),
            _ => {}
        }
    }
    let mut nodes = Vec::new();
    scene.objects.iter().for_each(|n| collect(n, &mut nodes));
    let curves = nodes
        .iter()
        .filter_map(|n| match n {
            Node::Shape {
                shape: Shape::Revolution { curve, .. },
                ..
            } => Some(curve.clone()),
            _ => None,
        })
        .collect();
    let mut only = scene.clone();
    only.objects = nodes;
    (only, curves)
}

/// Max and mean distance to the exact surface of the hits of one camera ray
/// through each pixel, and how many rays hit.
fn hit_errors(scene: &Scene, options: &RenderOptions) -> Result<(f64, f64, usize), AccuracyError> {
    let (only, curves) = revolutions_only(scene);
    if curves.is_empty() {
        return Err(AccuracyError::NoRevolution);
    }
    // In scene coordinates, the curves' own: the distance measures the
    // surface's intersection, not the frame's rounding.
    let world = World::build_in(&only, Vec3::ZERO)?;
    let camera = CameraRays::new(&scene.camera, options.width, options.height, world.origin());
    let (mut max, mut sum, mut hits) = (0.0f64, 0.0, 0usize);
    for y in 0..options.height {
        for x in 0..options.width {
            let mut sampler = Sampler::for_sample(SamplerKind::Independent, options.seed, x, y, 0);
            let ray = camera.ray(x, y, &mut sampler);
            if let Some(h) = world.intersect(&ray, 1e-4, f32::INFINITY) {
                let d = curves
                    .iter()
                    .map(|c| surface_distance(c, h.point))
                    .fold(f64::INFINITY, f64::min);
                max = max.max(d);
                sum += d;
                hits += 1;
            }
        }
    }
    Ok((max, sum / hits.max(1) as f64, hits))
}

fn rmse(a: &[Vec3], b: &[Vec3]) -> f64 {
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).as_dvec3().length_squared())
        .sum();
    (sum / (3 * a.len().max(1)) as f64).sqrt()
}

fn timed_render(scene: &Scene, options: &RenderOptions) -> Result<(Vec<Vec3>, f64), AccuracyError> {
    let world = World::build(scene)?;
    let start = Instant::now();
    let out = render(scene, &world, options, &|_| {})?;
    Ok((out.pixels, start.elapsed().as_secs_f64()))
}

/// Scores every mode of `modes` on `scene` against `reference` (a tight
/// analytic mode), all rendered with `options`.
pub fn measure(
    scene: &Scene,
    options: &RenderOptions,
    reference: RevolutionMode,
    modes: &[RevolutionMode],
) -> Result<AccuracyReport, AccuracyError> {
    let (reference_pixels, _) = timed_render(&with_mode(scene, reference), options)?;
    let other_seed = RenderOptions {
        seed: options.seed ^ 0x5eed,
        ..options.clone()
    };
    let (noisy, _) = timed_render(&with_mode(scene, reference), &other_seed)?;
    let mut rows = Vec::new();
    for &mode in modes {
        let s = with_mode(scene, mode);
        let (pixels, seconds) = timed_render(&s, options)?;
        let (max_error, mean_error, hits) = hit_errors(&s, options)?;
        rows.push(AccuracyRow {
            mode,
            seconds,
            max_error,
            mean_error,
            hits,
            rmse: rmse(&pixels, &reference_pixels),
        });
    }
    Ok(AccuracyReport {
        rows,
        noise_floor: rmse(&noisy, &reference_pixels),
    })
}
