//! The one handle through which the integrator, camera, materials and lights
//! draw their random numbers, one or two dimensions at a time, so that a
//! low-discrepancy sampler can replace the stream behind it.

use glam::Vec2;

use super::Rng;

/// The sample values of one pixel sample.
#[derive(Clone, Debug)]
pub struct Sampler {
    rng: Rng,
}

impl Sampler {
    /// The values of sample `index` of pixel `(x, y)` under `seed`.
    pub fn for_sample(seed: u64, x: u32, y: u32, index: u32) -> Sampler {
        Sampler {
            rng: Rng::for_sample(seed, x, y, index),
        }
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        self.rng.next_f32()
    }

    /// Uniform in [0, 1)².
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let x = self.rng.next_f32();
        Vec2::new(x, self.rng.next_f32())
    }
}
