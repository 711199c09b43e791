//! Deterministic pseudo-random numbers for the asset generators: a
//! SplitMix64 stream and a stateless integer hash, identical on every
//! platform so a seed always yields the same asset bytes.

/// Mixes a 64-bit value into a well-distributed 64-bit hash (the SplitMix64
/// finaliser).
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Hashes integer lattice coordinates and a seed to a uniform value in [0, 1).
pub fn hash3(seed: u64, x: i64, y: i64, z: i64) -> f64 {
    let h = mix64(
        seed ^ mix64((x as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15))
            ^ mix64((y as u64).wrapping_add(0x632b_e59b_d9b4_e019))
            ^ mix64(
                (z as u64)
                    .wrapping_mul(0xd6e8_feb8_6659_fd93)
                    .wrapping_add(1),
            ),
    );
    unit(h)
}

/// Maps the top 53 bits of a hash to [0, 1).
fn unit(h: u64) -> f64 {
    (h >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A sequential random stream (SplitMix64).
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// A stream started from `seed`.
    pub fn new(seed: u64) -> Rng {
        Rng {
            state: mix64(seed ^ 0x05ee_d0fa_55e7),
        }
    }

    /// The next uniform value in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        unit(mix64(self.state))
    }

    /// A uniform value in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// A uniform integer in [0, n); `n` must be positive.
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_f64() * n as f64) as usize).min(n.saturating_sub(1))
    }
}
