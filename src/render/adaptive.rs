//! Adaptive and time-budgeted sampling.
//!
//! - Per-pixel adaptivity (`--noise TARGET`): a pixel traces samples in
//!   rounds that double its count, starting at [`FIRST_ROUND`]; after each
//!   round the relative standard error of its mean luminance (from the
//!   running variance) is compared with the target, and the pixel stops once
//!   below it or at the spp cap. The decision uses that pixel's samples only,
//!   so the image stays deterministic and independent of threads and crops.
//! - Time budget (`--time`): whole-image rounds of doubling spp, each with
//!   new sample indices, averaged by sample count, until the next round
//!   would not fit the remaining budget (the result depends on the machine's
//!   speed by design; the summary says what was reached).

use std::time::{Duration, Instant};

use glam::Vec3;

use super::options::RenderOptions;
use super::tiles::{render, RenderError, RenderOutput};
use crate::geometry::World;
use crate::scene::Scene;

/// Samples every pixel traces before its error is first estimated. Long
/// enough that a run of samples which all missed the pixel's light (zero
/// variance, so a zero error estimate) is rare: at 16, about one pixel in
/// twenty on the Cornell box's shadowed box face stopped black
/// (`tests/converge_adaptive.rs`); the chance of such a run falls as the
/// power of the round's length.
pub const FIRST_ROUND: u32 = 64;

/// Luminance added to a pixel's mean before dividing, so black pixels stop.
const DARK: f64 = 1e-2;

/// The running sums of one pixel's samples.
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelEstimate {
    pub sum: Vec3,
    pub kept: u32,
    lum: f64,
    lum_sq: f64,
}

impl PixelEstimate {
    #[inline]
    pub fn add(&mut self, l: Vec3) {
        self.sum += l;
        self.kept += 1;
        let y = l.dot(Vec3::new(0.2126, 0.7152, 0.0722)) as f64;
        self.lum += y;
        self.lum_sq += y * y;
    }

    /// The relative standard error of the mean luminance.
    pub fn relative_error(&self) -> f64 {
        if self.kept < 2 {
            return f64::INFINITY;
        }
        let n = self.kept as f64;
        let mean = self.lum / n;
        let var = ((self.lum_sq - n * mean * mean) / (n - 1.0)).max(0.0);
        (var / n).sqrt() / (mean.abs() + DARK)
    }
}

/// Whether a pixel that has traced `done` samples (a round boundary) should
/// stop under `target`.
#[inline]
pub fn is_round_end(done: u32) -> bool {
    done >= FIRST_ROUND && done.is_power_of_two()
}

/// What a time-budgeted render reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progressive {
    pub spp: u32,
    pub rounds: u32,
}

/// Renders rounds of 1, 1, 2, 4, … spp (new samples each round) while the
/// next round is predicted to fit in `budget`; at least one round runs.
pub fn render_for(
    scene: &Scene,
    world: &World,
    options: &RenderOptions,
    budget: Duration,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(RenderOutput, Progressive), RenderError> {
    let start = Instant::now();
    let mut round = options.clone();
    round.sample_offset = 0;
    round.spp = 1;
    let mut acc = render(scene, world, &round, progress)?;
    let mut rounds = 1;
    let mut done = 1u32;
    let mut last = acc.stats.wall;
    loop {
        // The next round traces `done` more samples: about twice the last.
        let predicted = last.mul_f64(done as f64 / round.spp as f64);
        if start.elapsed() + predicted > budget || done.checked_mul(2).is_none() {
            acc.stats.wall = start.elapsed();
            acc.stats.spp_min = done;
            acc.stats.spp_max = done;
            return Ok((acc, Progressive { spp: done, rounds }));
        }
        round.sample_offset = done;
        round.spp = done;
        let out = render(scene, world, &round, progress)?;
        last = out.stats.wall;
        rounds += 1;
        for (p, q) in acc.pixels.iter_mut().zip(&out.pixels) {
            *p = (*p + *q) * 0.5;
        }
        acc.stats.samples += out.stats.samples;
        acc.stats.rays += out.stats.rays;
        acc.stats.dropped += out.stats.dropped;
        acc.stats.newton_failures = out.stats.newton_failures;
        done *= 2;
    }
}
