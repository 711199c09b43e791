//! The per-sample random stream: a PCG32 generator whose state is a hash of
//! (scene seed, pixel x, pixel y, sample index) and nothing else, so a pixel's
//! samples are the same whatever thread or tile renders them.

use glam::{Vec2, Vec3};

use super::warp;

/// PCG-XSH-RR 32-bit output, 64-bit state.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

const MULTIPLIER: u64 = 6_364_136_223_846_793_005;

/// SplitMix64's finaliser: a bijective 64-bit mixer.
pub(crate) fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl Rng {
    /// A stream for a sampler that never draws from it (the Sobol' one):
    /// no hashing, and a valid (odd) increment.
    pub const UNUSED: Rng = Rng { state: 0, inc: 1 };

    /// The stream of sample `index` of pixel `(x, y)` under `seed`.
    pub fn for_sample(seed: u64, x: u32, y: u32, index: u32) -> Rng {
        let pixel = ((y as u64) << 32) | x as u64;
        let a = mix(seed ^ mix(pixel.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        let b = mix(a ^ (index as u64).wrapping_mul(0xd1b5_4a32_d192_ed03));
        let mut rng = Rng {
            state: 0,
            inc: (mix(b ^ 0x5851_f42d_4c95_7f2d) << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(b);
        rng.next_u32();
        rng
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(MULTIPLIER).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// Uniform on the unit sphere.
    #[inline]
    pub fn unit_vector(&mut self) -> Vec3 {
        let u = Vec2::new(self.next_f32(), self.next_f32());
        warp::uniform_sphere(u)
    }

    /// Uniform in the unit ball.
    #[inline]
    pub fn in_unit_ball(&mut self) -> Vec3 {
        self.unit_vector() * self.next_f32().cbrt()
    }
}

/// The uniform numbers in [0, 1) of the stream of `seed`, as a closure:
/// random data for tests (geometry's among them, which draw no samples).
#[cfg(test)]
pub fn numbers(seed: u64) -> impl FnMut() -> f32 {
    let mut rng = Rng::for_sample(seed, 0, 0, 0);
    move || rng.next_f32()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_depend_on_every_input_and_are_uniform() {
        let first = |s, x, y, i| Rng::for_sample(s, x, y, i).next_u32();
        let base = first(1, 2, 3, 4);
        assert_eq!(base, first(1, 2, 3, 4));
        for other in [
            first(0, 2, 3, 4),
            first(1, 3, 3, 4),
            first(1, 2, 2, 4),
            first(1, 2, 3, 5),
        ] {
            assert_ne!(base, other);
        }
        let mut rng = Rng::for_sample(7, 0, 0, 0);
        let n = 100_000;
        let mean = (0..n).map(|_| rng.next_f32() as f64).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
    }
}
