//! Time-budgeted rendering in whole-image rounds of doubling spp, each
//! with new sample indices, averaged by sample count, until the next round
//! would not fit the remaining budget (the result depends on the machine's
//! speed by design; the caller says what was reached). It drives
//! [`super::tiles::render`] from above, apart from the per-pixel adaptive
//! sampling in [`super::adaptive`] that the tile loop itself uses.

use std::time::{Duration, Instant};

use super::options::RenderOptions;
use super::tiles::{render, RenderError, RenderOutput};
use crate::geometry::World;
use crate::scene::Scene;

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
