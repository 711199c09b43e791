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

/// `sobol1(i).reverse_bits()` without tables, for the lanes of
/// [`points8`]. Bit `j` of it is the parity of the index bits `k` with
/// C(k, j) odd, which by Lucas' theorem are the `k` whose binary digits
/// include `j`'s: a superset sum over the five-bit positions, taken one
/// digit of the position at a time (five shifts, masks and XORs).
#[inline(always)]
fn sobol1_reversed_of(i: u32) -> u32 {
    let mut x = i;
    x ^= (x >> 1) & 0x5555_5555;
    x ^= (x >> 2) & 0x3333_3333;
    x ^= (x >> 4) & 0x0f0f_0f0f;
    x ^= (x >> 8) & 0x00ff_00ff;
    x ^= (x >> 16) & 0x0000_ffff;
    x
}

/// Lanes of [`points8`]: each step is written lane by lane so that the
/// compiler turns it into vector instructions.
pub const LANES: usize = 8;

/// Eight lanes of `u32`s.
pub type Lanes32 = [u32; LANES];

/// [`upward_mix`] of every lane of `x` under the seed in the same place of
/// `seeds`, one step at a time across all of them: each step's multiplies
/// of the `R · K` vectors are independent, so their latencies overlap
/// instead of adding up as whole chains in a row would. (Loops over fixed
/// arrays: iterators over flattened slices were not vectorised.)
#[inline(always)]
fn upward_mix_all<const R: usize, const K: usize>(
    x: &mut [[Lanes32; K]; R],
    seeds: &[[Lanes32; K]; R],
) {
    for (x, seeds) in x.iter_mut().zip(seeds) {
        for (x, seeds) in x.iter_mut().zip(seeds) {
            for (x, seed) in x.iter_mut().zip(seeds) {
                *x = x.wrapping_add(*seed);
            }
        }
    }
    for c in MIX {
        for x in x.iter_mut() {
            for x in x.iter_mut() {
                for x in x.iter_mut() {
                    *x ^= x.wrapping_mul(c);
                }
            }
        }
    }
}

/// The index shuffles of [`point2`] for `K` slots (their first seeds,
/// per lane) of sample `index[l]` in each lane `l`: the first of its two
/// steps, which [`Shuffled::points`] finishes.
#[derive(Clone, Copy, Debug)]
pub struct Shuffled<const K: usize>([Lanes32; K]);

/// The shuffles' inputs: each lane's index, bits reversed.
#[inline(always)]
fn reversed_index<const K: usize>(index: &Lanes32) -> [Lanes32; K] {
    let mut reversed = [*index; K];
    for r in &mut reversed {
        for x in r {
            *x = x.reverse_bits();
        }
    }
    reversed
}

/// The `K` slots' index shuffles under their first seeds `seeds0`.
#[inline(always)]
fn shuffles<const K: usize>(index: &Lanes32, seeds0: &[Lanes32; K]) -> Shuffled<K> {
    let mut x = [reversed_index(index)];
    upward_mix_all(&mut x, &[*seeds0]);
    Shuffled(x[0])
}

/// The inputs of both coordinates' scrambles (rows 0 and 1) of the slots'
/// shuffled indices.
#[inline(always)]
fn coordinate_rows<const K: usize>(shuffled: &Shuffled<K>) -> [[Lanes32; K]; 2] {
    let mut rows = [[[0; LANES]; K]; 2];
    for (k, shuffled) in shuffled.0.iter().enumerate() {
        for (l, s) in shuffled.iter().enumerate() {
            let i = s.reverse_bits();
            rows[0][k][l] = i;
            rows[1][k][l] = sobol1_reversed_of(i);
        }
    }
    rows
}

/// The points of both coordinates' scrambled rows.
#[inline(always)]
fn to_points<const K: usize>(x: &[Lanes32; K], y: &[Lanes32; K]) -> [[[f32; LANES]; 2]; K] {
    let mut sets = [[[0.0; LANES]; 2]; K];
    for (set, (x, y)) in sets.iter_mut().zip(x.iter().zip(y)) {
        for (point, row) in set.iter_mut().zip([x, y]) {
            for (p, r) in point.iter_mut().zip(row) {
                *p = to_unit(r.reverse_bits());
            }
        }
    }
    sets
}

/// The points of the shuffled indices `shuffled` under each slot's other
/// two seeds, and, in the same pass, the shuffles of `index` under the
/// first seeds `next0` of the next `K` slots. Both steps' multiplies
/// interleave, so one pass costs one chain of dependent multiplications
/// instead of two in a row.
#[inline(always)]
fn points_and_next<const K: usize>(
    shuffled: &Shuffled<K>,
    seeds: &[[Lanes32; 2]; K],
    index: &Lanes32,
    next0: &[Lanes32; K],
) -> ([[[f32; LANES]; 2]; K], Shuffled<K>) {
    // Row 0: first coordinates; row 1: second ones; row 2: next shuffles.
    let [x, y] = coordinate_rows(shuffled);
    let mut rows = [x, y, reversed_index(index)];
    let row_seeds = [seeds.map(|s| s[0]), seeds.map(|s| s[1]), *next0];
    upward_mix_all(&mut rows, &row_seeds);
    (to_points(&rows[0], &rows[1]), Shuffled(rows[2]))
}

/// [`point2`] for `K` slots (seeds per lane) of sample `index[l]` in each
/// lane `l`, as 24-bit fractions in [0, 1): the same numbers as 8 · `K`
/// calls, computed side by side. The table lookups of the scalar path
/// become the shift-and-mask form of dimension 1, which vectorises.
///
/// The loops here are plain `for` loops: the closures of `array::from_fn`
/// are compiled in functions of their own, outside the caller's AVX2.
#[inline(always)]
fn points8_sets<const K: usize>(
    index: &Lanes32,
    seeds: &[[Lanes32; 3]; K],
) -> [[[f32; LANES]; 2]; K] {
    let shuffled = shuffles(index, &seeds.map(|s| s[0]));
    let mut rows = coordinate_rows(&shuffled);
    upward_mix_all(&mut rows, &[seeds.map(|s| s[1]), seeds.map(|s| s[2])]);
    to_points(&rows[0], &rows[1])
}

/// [`points8_sets`] compiled for AVX2 (eight 32-bit lanes).
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn points8_sets_avx2<const K: usize>(
    index: &Lanes32,
    seeds: &[[Lanes32; 3]; K],
) -> [[[f32; LANES]; 2]; K] {
    points8_sets(index, seeds)
}

/// For each of `K` slots' seed sets, [`point2`] in each lane `l` of sample
/// `index[l]` under that lane's seeds, for the CPU at hand.
#[inline]
pub fn points8_each<const K: usize>(
    index: &Lanes32,
    seeds: &[[Lanes32; 3]; K],
) -> [[[f32; LANES]; 2]; K] {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2.
        return unsafe { points8_sets_avx2(index, seeds) };
    }
    points8_sets(index, seeds)
}

/// [`shuffles`] compiled for AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn shuffles_avx2<const K: usize>(index: &Lanes32, seeds0: &[Lanes32; K]) -> Shuffled<K> {
    shuffles(index, seeds0)
}

/// [`points_and_next`] compiled for AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn points_and_next_avx2<const K: usize>(
    shuffled: &Shuffled<K>,
    seeds: &[[Lanes32; 2]; K],
    index: &Lanes32,
    next0: &[Lanes32; K],
) -> ([[[f32; LANES]; 2]; K], Shuffled<K>) {
    points_and_next(shuffled, seeds, index, next0)
}

impl<const K: usize> Shuffled<K> {
    /// The index shuffles of sample `index[l]` in each lane `l` for `K`
    /// slots whose first seeds (per lane) are `seeds0`, for the CPU at
    /// hand.
    #[inline]
    pub fn new(index: &Lanes32, seeds0: &[Lanes32; K]) -> Shuffled<K> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2.
            return unsafe { shuffles_avx2(index, seeds0) };
        }
        shuffles(index, seeds0)
    }

    /// The points of these shuffled samples under each slot's other two
    /// seeds `seeds` (what [`points8_each`] gives for the three), with the
    /// shuffles of the same samples for the next `K` slots, whose first
    /// seeds are `next0`, made in the same pass.
    #[inline]
    pub fn points(
        &self,
        seeds: &[[Lanes32; 2]; K],
        index: &Lanes32,
        next0: &[Lanes32; K],
    ) -> ([[[f32; LANES]; 2]; K], Shuffled<K>) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2.
            return unsafe { points_and_next_avx2(self, seeds, index, next0) };
        }
        points_and_next(self, seeds, index, next0)
    }
}

/// [`point2`] of samples `first .. first + 8` (`first` a multiple of 8)
/// for one slot's seeds.
#[inline]
pub fn points8(first: u32, seeds: [u32; 3]) -> [[f32; LANES]; 2] {
    let index = std::array::from_fn(|l| first | l as u32);
    let [points] = points8_each(&index, &[seeds.map(|s| [s; LANES])]);
    points
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

    #[test]
    fn dimension_one_by_shifts_is_dimension_one_by_tables() {
        for i in
            (0..70_000u32)
                .map(|i| i.wrapping_mul(0x9e37_79b9))
                .chain([0, 1, u32::MAX, 1 << 31])
        {
            assert_eq!(sobol1_reversed_of(i), sobol1(i).reverse_bits(), "{i:#x}");
        }
    }

    #[test]
    fn eight_points_at_once_are_the_points_one_at_a_time() {
        for (first, seeds) in [
            (0u32, [1u32, 2, 3]),
            (8, [0xdead_beef, 7, 0x1234_5678]),
            (u32::MAX - 7, [5, 0, u32::MAX]),
        ] {
            let index = std::array::from_fn(|l| first | l as u32);
            let broadcast = seeds.map(|s| [s; LANES]);
            let both = [points8(first, seeds), points8_sets(&index, &[broadcast])[0]];
            for l in 0..LANES as u32 {
                let (a, b) = point2(first + l, seeds);
                for [x, y] in both {
                    assert_eq!((x[l as usize], y[l as usize]), (to_unit(a), to_unit(b)));
                }
            }
        }
    }

    #[test]
    fn points_made_a_bounce_after_their_shuffles_are_point2s() {
        let index: Lanes32 = std::array::from_fn(|l| 4096 + l as u32);
        let seeds_of = |bounce: usize| -> [[Lanes32; 3]; 2] {
            std::array::from_fn(|k| {
                std::array::from_fn(|j| {
                    std::array::from_fn(|l| {
                        ((bounce * 97 + k * 31 + j * 7 + l) as u32).wrapping_mul(0x9e37_79b9)
                    })
                })
            })
        };
        let mut shuffled = Shuffled::new(&index, &seeds_of(0).map(|s| s[0]));
        for bounce in 0..3 {
            let (now, next) = (seeds_of(bounce), seeds_of(bounce + 1));
            let points;
            (points, shuffled) =
                shuffled.points(&now.map(|s| [s[1], s[2]]), &index, &next.map(|s| s[0]));
            for (k, [x, y]) in points.into_iter().enumerate() {
                for l in 0..LANES {
                    let (a, b) = point2(index[l], [now[k][0][l], now[k][1][l], now[k][2][l]]);
                    assert_eq!(
                        (x[l], y[l]),
                        (to_unit(a), to_unit(b)),
                        "bounce {bounce}, slot {k}, lane {l}"
                    );
                }
            }
        }
    }

    #[test]
    fn each_lane_draws_its_own_sample_under_its_own_seeds() {
        // Scattered indices and a distinct seed triple per lane and slot.
        let index: Lanes32 = std::array::from_fn(|l| (l as u32).wrapping_mul(0x9e37_79b9) ^ 77);
        let seeds: [[Lanes32; 3]; 3] = std::array::from_fn(|k| {
            std::array::from_fn(|j| {
                std::array::from_fn(|l| ((k * 31 + j * 7 + l) as u32).wrapping_mul(0x85eb_ca6b))
            })
        });
        let sets = points8_each(&index, &seeds);
        for (k, [x, y]) in sets.into_iter().enumerate() {
            for l in 0..LANES {
                let s = [seeds[k][0][l], seeds[k][1][l], seeds[k][2][l]];
                let (a, b) = point2(index[l], s);
                assert_eq!((x[l], y[l]), (to_unit(a), to_unit(b)), "set {k}, lane {l}");
            }
        }
    }
}
