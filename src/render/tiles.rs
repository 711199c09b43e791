//! Rendering an image: samples are added to a [`Film`] in rounds (to 1, 8,
//! 16, 32, 48, … samples per pixel), each round cut into tiles that the
//! threads of a rayon pool take one at a time, the tiles that cost most in
//! the last round first. Each pixel's samples are traced in index order (or
//! a sampler block side by side, in a world whose rays walk in packets) and
//! summed in index order, from streams that depend only on (seed, pixel,
//! sample), so the result is bit-identical for any thread count, any crop,
//! any number of rounds and any interruption resumed from a checkpoint.
//! Counters are per tile, merged at the end of each round.
//!
//! Tiles are 16×16 pixels anchored to the image grid (so a crop or a tile
//! split sees the same tiles). A pixel's samples go to the lanes
//! ([`Lanes`]) a block at a time where they apply, else to the packet or
//! the one-ray path of the [`Tracer`]. NaN and infinite samples are dropped
//! and counted; `--clamp` and adaptive `--noise` act in the per-pixel loop.
//! The coarse first round of one sample is taken only where
//! `RenderOptions::coarse_first` asks (the preview, `--time`).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use glam::Vec3;

use super::adaptive::{is_round_end, PixelEstimate};
use super::camera::CameraRays;
use super::film::Film;
use super::integrator::Tracer;
use super::lanes::Lanes;
use super::lights::LightList;
use super::options::{Crop, OptionsError, RenderOptions};
use crate::geometry::primitives::PrimitiveSet;
use crate::geometry::World;
use crate::sampling::sampler::BLOCK;
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::Scene;

/// Tile edge in pixels.
const TILE: u32 = 16;

/// Most samples per pixel added in one round.
const ROUND_MAX: u32 = 16;

/// The samples per pixel a film holds after the round that follows one
/// holding `reached`: with `coarse_first`, a first round of one sample (a
/// coarse image for the preview at once) and a second up to [`BLOCK`];
/// without, a first round of [`BLOCK`]; then doubling, at most
/// [`ROUND_MAX`] at a time (1, 8, 16, 32, 48, …), never past `spp`. The
/// sampler computes a slot's draws for a block of samples at once, anew in
/// every round that reaches the block, so rounds past the first end on
/// blocks: rounds of 1, 2 and 4 samples would recompute the first block
/// three more times, 1 % of a 64-spp Cornell render's instructions; the
/// coarse round of one sample costs the random spheres 1.3 % of their
/// instructions at 64 spp.
fn next_round(reached: u32, spp: u32, coarse_first: bool) -> u32 {
    let next = match reached {
        0 if coarse_first => 1,
        r if r < BLOCK => BLOCK,
        r => r + r.min(ROUND_MAX),
    };
    next.min(spp)
}

/// Counters of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Camera samples traced (including dropped ones).
    pub samples: u64,
    /// Rays traced (camera and scattered).
    pub rays: u64,
    /// Samples dropped because they came out NaN or infinite.
    pub dropped: u64,
    /// Intersections with analytic revolution surfaces that neither Newton
    /// nor its fallback could verify (see docs/accuracy.md).
    pub newton_failures: u64,
    /// Fewest and most samples any pixel traced (they differ under
    /// adaptive sampling).
    pub spp_min: u32,
    pub spp_max: u32,
    pub wall: Duration,
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
    #[error("the film does not cover the region being rendered")]
    FilmRegion,
}

/// What a caller may observe and steer while a film renders.
pub struct Hooks<'a> {
    /// Set (e.g. by a signal handler) to stop at the next tile boundary;
    /// tiles already started finish their round.
    pub stop: &'a AtomicBool,
    /// Told the pixel-samples each finished tile added.
    pub tile_done: &'a (dyn Fn(u64) + Sync),
    /// Called with the film after every completed round of samples.
    pub round_done: &'a mut dyn FnMut(&Film),
}

/// Renders `world` (built from `scene`) with `options`; `progress` is told
/// how many pixel-samples each finished tile added.
pub fn render(
    scene: &Scene,
    world: &World,
    options: &RenderOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    let region = options.region()?;
    let mut film = Film::new(region);
    let stop = AtomicBool::new(false);
    let mut hooks = Hooks {
        stop: &stop,
        tile_done: progress,
        round_done: &mut |_| {},
    };
    let stats = render_film(scene, world, options, &mut film, &mut hooks)?;
    Ok(RenderOutput {
        region,
        width: region.width(),
        height: region.height(),
        pixels: film.pixels(),
        stats,
    })
}

/// Adds samples to `film` until every pixel has `options.spp` (or `hooks.stop`
/// is set), in rounds of growing size over all tiles. `film` may already hold
/// samples (a resumed checkpoint): each pixel continues from its own count.
pub fn render_film(
    scene: &Scene,
    world: &World,
    options: &RenderOptions,
    film: &mut Film,
    hooks: &mut Hooks,
) -> Result<RenderStats, RenderError> {
    let region = options.region()?;
    if film.region != region {
        return Err(RenderError::FilmRegion);
    }
    let first = options.first_sample().unwrap_or(0);
    let start = Instant::now();
    let tiles = tiles_of(region);
    let camera = CameraRays::new(&scene.camera, options.width, options.height, world.origin());
    let lights = LightList::for_render(
        scene,
        world,
        options.light_sampling,
        options.light_selection,
    );
    let tracer = Tracer::for_options(scene, world, &lights, options);
    // Paths in lanes draw Sobol' blocks and trace whole blocks: not for the
    // independent sampler nor for adaptive sampling, which stops per sample.
    let lanes = (options.lanes && options.sampler == SamplerKind::Sobol && options.noise.is_none())
        .then(|| Lanes::new(&tracer, &camera))
        .flatten();
    let pool = match options.threads {
        None => None,
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| RenderError::Threads {
                    threads: n,
                    message: e.to_string(),
                })?,
        ),
    };
    let mut stats = RenderStats {
        spp_min: u32::MAX,
        ..RenderStats::default()
    };
    let mut reached = film.spp_reached();
    // Rays each tile traced in the last round: the next round starts the
    // costliest tiles first.
    let mut cost = vec![0u64; tiles.len()];
    while reached < options.spp && !hooks.stop.load(Ordering::Relaxed) {
        // Adaptive sampling decides per pixel, inside one round to the cap.
        let target = if options.noise.is_some() {
            options.spp
        } else {
            next_round(reached, options.spp, options.coarse_first)
        };
        let job = Job {
            tracer: &tracer,
            lanes: lanes.as_ref(),
            camera: &camera,
            seed: options.seed,
            sampler: options.sampler,
            first,
            target,
            clamp: options.clamp,
            noise: options.noise,
            packets: tracer.packets.filter(|_| options.noise.is_none()),
        };
        let order = costliest_first(&cost);
        let next = AtomicUsize::new(0);
        let shared: &Film = film;
        let work = || -> Vec<(usize, TileResult)> {
            rayon::broadcast(|_| {
                let mut done = Vec::new();
                while !hooks.stop.load(Ordering::Relaxed) {
                    let Some(&t) = order.get(next.fetch_add(1, Ordering::Relaxed)) else {
                        break;
                    };
                    let r = job.tile(shared, tiles[t]);
                    (hooks.tile_done)(r.samples);
                    done.push((t, r));
                }
                done
            })
            .into_iter()
            .flatten()
            .collect()
        };
        let results = match &pool {
            None => work(),
            Some(p) => p.install(work),
        };
        for (t, r) in results {
            cost[t] = r.rays;
            stats.samples += r.samples;
            stats.rays += r.rays;
            stats.dropped += r.dropped;
            stats.spp_min = stats.spp_min.min(r.spp_min);
            stats.spp_max = stats.spp_max.max(r.spp_max);
            let tw = r.tile.width() as usize;
            for (row, y) in (r.tile.y0..r.tile.y1).enumerate() {
                let dst = film.index(r.tile.x0, y);
                let src = row * tw..(row + 1) * tw;
                film.sums[dst..dst + tw].copy_from_slice(&r.sums[src.clone()]);
                film.kept[dst..dst + tw].copy_from_slice(&r.kept[src.clone()]);
                film.taken[dst..dst + tw].copy_from_slice(&r.taken[src]);
            }
        }
        reached = film.spp_reached();
        if reached >= target {
            (hooks.round_done)(film);
        }
    }
    // Without adaptive sampling every pixel's count is its `taken`; with it,
    // the single round's tiles reported what each pixel traced.
    if options.noise.is_none() || stats.spp_min == u32::MAX {
        stats.spp_min = film.spp_reached();
        stats.spp_max = film.taken.iter().copied().max().unwrap_or(0);
    }
    stats.newton_failures = world.newton_failures();
    stats.wall = start.elapsed();
    Ok(stats)
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

/// The order in which a round's threads take the tiles: the most rays
/// traced in the last round first (ties, and the first round, in grid
/// order), so that the round does not end waiting on an expensive tile
/// started last. Each tile's pixels come out the same in any order.
fn costliest_first(cost: &[u64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..cost.len()).collect();
    order.sort_by_key(|&t| std::cmp::Reverse(cost[t]));
    order
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

/// One round: every pixel brought up to `target` samples of the pass that
/// starts at sample index `first`.
struct Job<'a> {
    tracer: &'a Tracer<'a>,
    /// The tracer in lanes, when the scene and options allow it.
    lanes: Option<&'a Lanes<'a>>,
    camera: &'a CameraRays,
    seed: u64,
    sampler: SamplerKind,
    first: u32,
    target: u32,
    /// Largest component a sample's radiance may have (biased; off by default).
    clamp: Option<f32>,
    /// Adaptive target: a pixel stops at a round end once the relative
    /// standard error of its mean luminance is below it.
    noise: Option<f32>,
    /// The set a pixel's samples walk a block at a time, in packets
    /// ([`Tracer::samples`]): the tracer's, unless adaptive sampling (which
    /// stops per sample) is on.
    packets: Option<&'a PrimitiveSet>,
}

struct TileResult {
    tile: Crop,
    sums: Vec<Vec3>,
    kept: Vec<u32>,
    taken: Vec<u32>,
    samples: u64,
    rays: u64,
    dropped: u64,
    spp_min: u32,
    spp_max: u32,
}

/// One pixel's running totals in a round: the sum of its kept samples,
/// their count, the samples traced, and the estimate adaptive sampling
/// reads.
struct PixelSums {
    sum: Vec3,
    kept: u32,
    traced: u32,
    estimate: PixelEstimate,
}

impl PixelSums {
    /// Adds a traced sample of radiance `l` that took `rays` rays, clamped
    /// to `clamp`; a NaN or infinite one is dropped and counted in `r`.
    #[inline]
    fn add(&mut self, mut l: Vec3, rays: u32, clamp: Option<f32>, r: &mut TileResult) {
        self.traced += 1;
        if let Some(c) = clamp {
            l = clamp_radiance(l, c);
        }
        r.rays += rays as u64;
        r.samples += 1;
        if l.is_finite() {
            self.sum += l;
            self.kept += 1;
            self.estimate.add(l);
        } else {
            r.dropped += 1;
        }
    }
}

impl Job<'_> {
    /// Adds to `px` the samples `from..target` of pixel `(x, y)` in a
    /// world whose rays walk `set` in packets: a block of the sampler at a
    /// time, its paths side by side, each bounce's rays one packet. Kept
    /// out of the tile loop: inlined there, it changed how the compiler
    /// lays out the one-ray path of other worlds, and the book-2 scene runs
    /// 5 % slower with no more instructions.
    #[inline(never)]
    fn packet_pixel(
        &self,
        set: &PrimitiveSet,
        sampler: &mut Sampler,
        (x, y): (u32, u32),
        from: u32,
        px: &mut PixelSums,
        r: &mut TileResult,
    ) {
        let mut s = from;
        while s < self.target {
            let index = self.first + s;
            let count = (BLOCK - index % BLOCK).min(self.target - s);
            self.tracer.samples(
                set,
                self.camera,
                sampler,
                (x, y),
                index..index + count,
                |l, rays| px.add(l, rays, self.clamp, r),
            );
            s += count;
        }
    }

    fn tile(&self, film: &Film, tile: Crop) -> TileResult {
        let n = (tile.width() * tile.height()) as usize;
        let mut r = TileResult {
            tile,
            sums: Vec::with_capacity(n),
            kept: Vec::with_capacity(n),
            taken: Vec::with_capacity(n),
            samples: 0,
            rays: 0,
            dropped: 0,
            spp_min: u32::MAX,
            spp_max: 0,
        };
        let mut sampler = Sampler::new(self.sampler, self.seed);
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let i = film.index(x, y);
                let mut px = PixelSums {
                    sum: film.sums[i],
                    kept: film.kept[i],
                    traced: film.taken[i],
                    estimate: PixelEstimate::default(),
                };
                let done = film.taken[i].max(self.target);
                match (self.lanes, self.packets) {
                    (Some(lanes), _) => {
                        let root = sampler.pixel_seeds(x, y);
                        let mut s = film.taken[i];
                        while s < self.target {
                            let index = self.first + s;
                            let lane0 = (index % BLOCK) as usize;
                            let count = (BLOCK as usize - lane0).min((self.target - s) as usize);
                            let live = std::array::from_fn(|l| l >= lane0 && l < lane0 + count);
                            let (ls, rs) = lanes.block(root, (x, y), index / BLOCK, live);
                            for (l, rays) in ls.into_iter().zip(rs).skip(lane0).take(count) {
                                px.add(l, rays, self.clamp, &mut r);
                            }
                            s += count as u32;
                        }
                    }
                    (None, Some(set)) => {
                        let from = film.taken[i];
                        self.packet_pixel(set, &mut sampler, (x, y), from, &mut px, &mut r);
                    }
                    (None, None) => {
                        for s in film.taken[i]..self.target {
                            if let Some(goal) = self.noise {
                                if is_round_end(s) && px.estimate.relative_error() < f64::from(goal)
                                {
                                    break;
                                }
                            }
                            let (l, rays) = self.tracer.sample(
                                self.camera,
                                &mut sampler,
                                (x, y),
                                self.first + s,
                            );
                            px.add(l, rays, self.clamp, &mut r);
                        }
                    }
                }
                r.spp_min = r.spp_min.min(px.traced);
                r.spp_max = r.spp_max.max(px.traced);
                r.sums.push(px.sum);
                r.kept.push(px.kept);
                r.taken.push(done);
            }
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::{costliest_first, next_round, BLOCK};

    #[test]
    fn rounds_start_with_one_sample_then_end_on_the_samplers_blocks() {
        let rounds = |spp: u32, coarse: bool| {
            let mut at = vec![0];
            while *at.last().unwrap() < spp {
                at.push(next_round(*at.last().unwrap(), spp, coarse));
            }
            at
        };
        assert_eq!(rounds(64, true), [0, 1, 8, 16, 32, 48, 64]);
        assert_eq!(rounds(12, true), [0, 1, 8, 12]);
        assert_eq!(rounds(1, true), [0, 1]);
        assert_eq!(rounds(64, false), [0, 8, 16, 32, 48, 64]);
        assert_eq!(rounds(5, false), [0, 5]);
        // A resumed film goes on to the next block, then by blocks.
        assert_eq!(next_round(4, 64, true), 8);
        assert_eq!(next_round(4, 64, false), 8);
        for spp in 1..200 {
            assert!(rounds(spp, true)[2..]
                .iter()
                .all(|&r| r % BLOCK == 0 || r == spp));
            assert!(rounds(spp, false)[1..]
                .iter()
                .all(|&r| r % BLOCK == 0 || r == spp));
        }
    }

    #[test]
    fn tiles_are_taken_costliest_first_and_ties_in_grid_order() {
        assert_eq!(costliest_first(&[3, 9, 0, 9, 5]), vec![1, 3, 4, 0, 2]);
        // The first round knows no costs: grid order.
        assert_eq!(costliest_first(&[0; 4]), vec![0, 1, 2, 3]);
    }
}
