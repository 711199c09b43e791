//! Owen-scrambled Sobol' points: the first two dimensions of the Sobol'
//! sequence (a (0,2)-sequence in base 2), randomised by hash-based nested
//! uniform (Owen) scrambling of each coordinate and of the sample index.
//!
//! Only the first two Sobol' dimensions are needed: the sampler pads its
//! dimensions with independently scrambled copies of this 2-D sequence (as
//! pbrt-v4's `PaddedSobolSampler` does), so the direction numbers are the
//! identity (dimension 0, the van der Corput sequence) and Pascal's triangle
//! mod 2 (dimension 1, primitive polynomial x + 1, all initial m = 1).
//!
//! Every map here is a bijection of `u32` in which output bit `k` depends
//! only on input bits at or above `k` (in digit order). Such maps send each
//! elementary interval onto one of the same shape, so the scrambled points
//! keep the (0,m,2)-net property of every aligned block of 2^m indices.

/// Sobol' dimension 0 of index `i` as a 32-bit fraction: its bits reversed.
#[inline]
pub fn sobol0(i: u32) -> u32 {
    i.reverse_bits()
}

/// Direction numbers of Sobol' dimension 1: `v_k` (for index bit `k`) is
/// row `k` of Pascal's triangle mod 2 read from the top bit down:
/// `v_0 = 1 << 31`, `v_{k+1} = v_k ^ (v_k >> 1)`.
const fn directions1() -> [u32; 32] {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    v
}

/// Dimension 1 with input and output bit-reversed (the order the Owen
/// scrambles work in), as the XOR of each byte's table entry: bit `j` of the
/// reversed index is index bit `31 − j`, worth `v_{31−j}` reversed. Four
/// lookups instead of a loop over 32 bits. Each entry also carries, in its
/// upper half, its byte's bits reversed into their place in the reversed
/// word, so the same four lookups give `r.reverse_bits()` (the bit reversal
/// is some twenty instructions on baseline x86-64, which has no instruction
/// for it).
const fn reversed_byte_tables1() -> [[u64; 256]; 4] {
    let v = directions1();
    let mut t = [[0u64; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut b = 0;
        while b < 256 {
            let mut x = 0u32;
            let mut bit = 0;
            while bit < 8 {
                if b & (1 << bit) != 0 {
                    x ^= v[31 - (byte * 8 + bit)].reverse_bits();
                }
                bit += 1;
            }
            let reversed = ((b as u32) << (8 * byte)).reverse_bits();
            t[byte][b] = (x as u64) | ((reversed as u64) << 32);
            b += 1;
        }
        byte += 1;
    }
    t
}

static REVERSED_TABLES1: [[u64; 256]; 4] = reversed_byte_tables1();

/// `sobol1(r.reverse_bits()).reverse_bits()` in the low half and
/// `r.reverse_bits()` in the high half.
#[inline]
fn sobol1_and_reverse(r: u32) -> u64 {
    let t = &REVERSED_TABLES1;
    let [a, b, c, d] = r.to_le_bytes();
    t[0][a as usize] ^ t[1][b as usize] ^ t[2][c as usize] ^ t[3][d as usize]
}

/// `sobol1(r.reverse_bits()).reverse_bits()`.
#[inline]
fn sobol1_reversed(r: u32) -> u32 {
    sobol1_and_reverse(r) as u32
}

/// Sobol' dimension 1 of index `i` as a 32-bit fraction.
#[inline]
pub fn sobol1(i: u32) -> u32 {
    sobol1_reversed(i.reverse_bits()).reverse_bits()
}

/// A hash-based bijection in which bit `k` of the result depends only on
/// bits `0..=k` of `x` (additions and multiplications carry upwards only),
/// and on `seed`. The constants are Vegdahl's variant of the Laine–Karras
/// permutation that Burley uses for hash-based Owen scrambling.
#[inline(always)]
fn upward_mix(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    for c in MIX {
        x ^= x.wrapping_mul(c);
    }
    x
}

/// The multipliers of [`upward_mix`]'s four rounds `x ^= x · c`.
pub(super) const MIX: [u32; 4] = [0x6c50_b47c, 0xb82f_1e52, 0xc7af_e638, 0x8d22_f6e6];

/// Nested uniform scrambling of a 32-bit fraction: whether digit `k` (from
/// the top) flips depends only on `seed` and the digits above it.
#[inline]
pub fn owen(x: u32, seed: u32) -> u32 {
    upward_mix(x.reverse_bits(), seed).reverse_bits()
}

/// A 32-bit fraction as an `f32` in [0, 1) (the top 24 bits, exactly).
#[inline(always)]
pub fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The scrambled 2-D point of sample `index` for the three seeds of one
/// dimension pair: the index is shuffled (an Owen scramble of its bits read
/// from the top, so each aligned block of 2^m indices maps onto an aligned
/// block), then both coordinates are Owen-scrambled. That is
/// `(owen(sobol0(i), s1), owen(sobol1(i), s2))` with `i = owen(index, s0)`,
/// written with four bit reversals instead of seven: the shuffled index's
/// reversal comes with its dimension-1 lookups, and the two coordinates are
/// reversed back together as one 64-bit word.
#[inline]
pub fn point2(index: u32, seeds: [u32; 3]) -> (u32, u32) {
    let r = upward_mix(index.reverse_bits(), seeds[0]);
    let both = sobol1_and_reverse(r);
    let x = upward_mix((both >> 32) as u32, seeds[1]);
    let y = upward_mix(both as u32, seeds[2]);
    let back = (u64::from(y) | (u64::from(x) << 32)).reverse_bits();
    (back as u32, (back >> 32) as u32)
}

/// The scrambled 1-D point of sample `index`: the first coordinate of
/// [`point2`] (a scrambled van der Corput sequence over a shuffled index).
#[inline]
pub fn point1(index: u32, seeds: [u32; 2]) -> u32 {
    let r = upward_mix(index.reverse_bits(), seeds[0]);
    upward_mix(r.reverse_bits(), seeds[1]).reverse_bits()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(x: u32) -> f64 {
        f64::from(x) / 4_294_967_296.0
    }

    #[test]
    fn unscrambled_points_are_the_published_sobol_points() {
        // Dimensions 1 and 2 of Joe & Kuo's table (our 0 and 1), points 0..8,
        // as published (and as scipy.stats.qmc.Sobol gives them unscrambled):
        // in Gray-code order, so point i is our index i ^ (i >> 1).
        let d0 = [0.0, 0.5, 0.75, 0.25, 0.375, 0.875, 0.625, 0.125];
        let d1 = [0.0, 0.5, 0.25, 0.75, 0.375, 0.875, 0.125, 0.625];
        for i in 0..8u32 {
            let g = i ^ (i >> 1);
            assert_eq!(unit(sobol0(g)), d0[i as usize], "dim 0, point {i}");
            assert_eq!(unit(sobol1(g)), d1[i as usize], "dim 1, point {i}");
        }
        // Index 11 = 0b1011 of dimension 1: v0 ^ v1 ^ v3 = .1 ^ .11 ^ .1111 = .1011.
        assert_eq!(unit(sobol1(11)), 0.6875);
    }

    #[test]
    fn byte_tables_agree_with_the_direction_numbers_bit_by_bit() {
        let v = directions1();
        let slow = |i: u32| (0..32).filter(|k| i >> k & 1 != 0).fold(0, |x, k| x ^ v[k]);
        for i in (0..4096u32).chain([u32::MAX, 0x8000_0001, 0xdead_beef, 0x1234_5678]) {
            assert_eq!(sobol1(i), slow(i), "index {i:#x}");
        }
        // Row 31 of Pascal's triangle mod 2 is all ones.
        assert_eq!(v[31], u32::MAX);
    }

    #[test]
    fn the_tables_upper_halves_reverse_the_index() {
        for r in (0..70_000u32)
            .map(|i| i.wrapping_mul(0x9e37_79b9))
            .chain([0, u32::MAX, 1])
        {
            assert_eq!(
                (sobol1_and_reverse(r) >> 32) as u32,
                r.reverse_bits(),
                "{r:#x}"
            );
        }
    }

    #[test]
    fn points_are_the_scrambles_of_the_shuffled_index_written_out() {
        for (index, s) in [
            (0u32, [1u32, 2, 3]),
            (77, [9, 8, 7]),
            (u32::MAX, [0xdead_beef, 5, 0x1234_5678]),
        ] {
            let i = owen(index, s[0]);
            assert_eq!(
                point2(index, s),
                (owen(sobol0(i), s[1]), owen(sobol1(i), s[2]))
            );
            assert_eq!(point1(index, [s[0], s[1]]), owen(sobol0(i), s[1]));
        }
    }

    /// Whether every elementary interval of shape 2^a × 2^(m−a) holds
    /// exactly one of the 2^m points.
    fn is_net(points: &[(u32, u32)], m: u32) -> bool {
        assert_eq!(points.len(), 1 << m);
        (0..=m).all(|a| {
            let mut seen = vec![false; 1 << m];
            points.iter().all(|&(x, y)| {
                let cell = if a == 0 { 0 } else { (x >> (32 - a)) as usize };
                let row = if a == m {
                    0
                } else {
                    (y >> (32 - (m - a))) as usize
                };
                let k = (cell << (m - a)) | row;
                !std::mem::replace(&mut seen[k], true)
            })
        })
    }

    #[test]
    fn every_aligned_block_is_a_net_scrambled_or_not() {
        for m in 0..=8u32 {
            for block in [0u32, 1, 5, 1000] {
                let indices = (block << m)..((block + 1) << m);
                let plain: Vec<_> = indices.clone().map(|i| (sobol0(i), sobol1(i))).collect();
                assert!(is_net(&plain, m), "plain m={m} block {block}");
                for seeds in [[1, 2, 3], [0xdead_beef, 7, 0x1234_5678]] {
                    let s: Vec<_> = indices.clone().map(|i| point2(i, seeds)).collect();
                    assert!(is_net(&s, m), "scrambled m={m} block {block} {seeds:?}");
                }
            }
        }
        // A random point set is almost never a net: the test can fail.
        let random: Vec<_> = (0..64u32)
            .map(|i| {
                (
                    owen(i.wrapping_mul(0x9e37_79b9), 5),
                    i.wrapping_mul(0x85eb_ca6b),
                )
            })
            .collect();
        assert!(!is_net(&random, 6));
    }

    #[test]
    fn one_dimension_is_stratified_in_every_prefix_of_power_of_two_length() {
        for m in 0..=10u32 {
            let mut cells = vec![0u32; 1 << m];
            for i in 0..(1u32 << m) {
                cells[(point1(i, [9, 4]) as u64 >> (32 - m)) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "m={m}");
        }
    }

    #[test]
    fn scrambles_are_bijections_that_change_with_the_seed() {
        let mut seen = std::collections::HashSet::new();
        for x in 0..(1u32 << 16) {
            assert!(seen.insert(owen(x << 16, 77) >> 16));
        }
        assert_ne!(owen(12345, 1), owen(12345, 2));
        assert_ne!(point2(3, [1, 2, 3]), point2(3, [4, 2, 3]));
    }

    #[test]
    fn scrambled_coordinates_are_uniform_over_seeds() {
        // A fixed point, many seeds: the mean of a uniform is 1/2 with a
        // standard error of 0.29/√n.
        let n = 100_000u32;
        let mean = (0..n)
            .map(|s| unit(point2(5, [s, s.wrapping_mul(31), s ^ 0xabcd]).1))
            .sum::<f64>()
            / f64::from(n);
        assert!(
            (mean - 0.5).abs() < 5.0 * 0.29 / f64::from(n).sqrt(),
            "{mean}"
        );
    }
}
