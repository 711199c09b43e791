//! Rendering an image: the region is cut into tiles rendered in parallel by
//! rayon; each pixel's samples are traced in index order from streams that
//! depend only on (seed, pixel, sample), so the result is bit-identical for
//! any thread count and any crop. Counters are per tile, merged at the end.

use std::time::{Duration, Instant};

use glam::Vec3;
use rayon::prelude::*;

use super::adaptive::{is_round_end, PixelEstimate};
use super::camera::CameraRays;
use super::integrator::Tracer;
use super::options::{Crop, OptionsError, RenderOptions};
use super::rng::Rng;
use crate::geometry::World;
use crate::scene::Scene;

/// Tile edge in pixels.
const TILE: u32 = 16;

/// Counters of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Camera samples traced (including dropped ones).
    pub samples: u64,
    /// Rays traced (camera and scattered).
    pub rays: u64,
    /// Samples dropped because they came out NaN or infinite.
    pub dropped: u64,
    /// Newton iterations of analytic revolution surfaces that failed.
    pub newton_failures: u64,
    pub wall: Duration,
    /// The fewest and most samples a pixel traced (they differ only with
    /// adaptive sampling).
    pub spp_min: u32,
    pub spp_max: u32,
}

/// A rendered region in linear RGB, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOutput {
    pub region: Crop,
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
    pub stats: RenderStats,
}

/// Why a render did not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Options(#[from] OptionsError),
    #[error("cannot start {threads} render threads: {message}")]
    Threads { threads: usize, message: String },
}

struct TileResult {
    tile: Crop,
    pixels: Vec<Vec3>,
    rays: u64,
    dropped: u64,
    samples: u64,
    spp_min: u32,
    spp_max: u32,
}

/// Renders `world` (built from `scene`) with `options`; `progress` is told
/// how many pixels each finished tile completed.
pub fn render(
    scene: &Scene,
    world: &World,
    options: &RenderOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    let region = options.region()?;
    let start = Instant::now();
    let tiles = tiles_of(region);
    let camera = CameraRays::new(&scene.camera, options.width, options.height);
    let tracer = Tracer {
        scene,
        world,
        max_depth: options.max_depth,
        light_sampling: options.light_sampling,
    };
    let work = || -> Vec<TileResult> {
        tiles
            .par_iter()
            .map(|tile| {
                let r = render_tile(&tracer, &camera, options, *tile);
                progress(r.pixels.len() as u64);
                r
            })
            .collect()
    };
    let results = match options.threads {
        None => work(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| RenderError::Threads {
                threads: n,
                message: e.to_string(),
            })?
            .install(work),
    };
    let (width, height) = (region.x1 - region.x0, region.y1 - region.y0);
    let mut pixels = vec![Vec3::ZERO; width as usize * height as usize];
    let mut stats = RenderStats {
        spp_min: u32::MAX,
        ..RenderStats::default()
    };
    for r in results {
        stats.samples += r.samples;
        stats.spp_min = stats.spp_min.min(r.spp_min);
        stats.spp_max = stats.spp_max.max(r.spp_max);
        stats.rays += r.rays;
        stats.dropped += r.dropped;
        let tw = (r.tile.x1 - r.tile.x0) as usize;
        for (row, y) in (r.tile.y0..r.tile.y1).enumerate() {
            let dst = (y - region.y0) as usize * width as usize + (r.tile.x0 - region.x0) as usize;
            pixels[dst..dst + tw].copy_from_slice(&r.pixels[row * tw..(row + 1) * tw]);
        }
    }
    stats.newton_failures = world.newton_failures();
    stats.wall = start.elapsed();
    Ok(RenderOutput {
        region,
        width,
        height,
        pixels,
        stats,
    })
}

/// Scales `l` down so that its largest component is at most `max`, keeping
/// its hue (biased: it darkens fireflies and true highlights alike).
#[inline]
fn clamp_radiance(l: Vec3, max: f32) -> Vec3 {
    let m = l.max_element();
    if m > max {
        l * (max / m)
    } else {
        l
    }
}

/// Tiles on a grid anchored at the image origin, clipped to `region`.
fn tiles_of(region: Crop) -> Vec<Crop> {
    let mut tiles = Vec::new();
    let mut y = region.y0;
    while y < region.y1 {
        let y1 = ((y / TILE + 1) * TILE).min(region.y1);
        let mut x = region.x0;
        while x < region.x1 {
            let x1 = ((x / TILE + 1) * TILE).min(region.x1);
            tiles.push(Crop {
                x0: x,
                x1,
                y0: y,
                y1,
            });
            x = x1;
        }
        y = y1;
    }
    tiles
}

fn render_tile(
    tracer: &Tracer,
    camera: &CameraRays,
    options: &RenderOptions,
    tile: Crop,
) -> TileResult {
    let mut pixels = Vec::with_capacity(((tile.x1 - tile.x0) * (tile.y1 - tile.y0)) as usize);
    let (mut rays, mut dropped, mut samples) = (0u64, 0u64, 0u64);
    let (mut spp_min, mut spp_max) = (u32::MAX, 0u32);
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let mut estimate = PixelEstimate::default();
            let mut traced = 0u32;
            for s in 0..options.spp {
                if let Some(target) = options.noise {
                    if is_round_end(s) && estimate.relative_error() < target as f64 {
                        break;
                    }
                }
                traced += 1;
                let mut rng = Rng::for_sample(options.seed, x, y, options.first_sample + s);
                let ray = camera.ray(x, y, &mut rng);
                let (mut l, n) = tracer.radiance(ray, &mut rng);
                if let Some(c) = options.clamp {
                    l = clamp_radiance(l, c);
                }
                rays += n as u64;
                if l.is_finite() {
                    estimate.add(l);
                } else {
                    dropped += 1;
                }
            }
            samples += traced as u64;
            spp_min = spp_min.min(traced);
            spp_max = spp_max.max(traced);
            pixels.push(if estimate.kept > 0 {
                estimate.sum / estimate.kept as f32
            } else {
                Vec3::ZERO
            });
        }
    }
    TileResult {
        tile,
        pixels,
        rays,
        dropped,
        samples,
        spp_min,
        spp_max,
    }
}
