//! Owen-scrambled Sobol' points eight samples at a time, in vector lanes:
//! [`sobol`](super::sobol)'s `point2` for eight sample indices (and, for
//! the lanes of the renderer, eight seed triples) at once, with several
//! slots' scrambles run round by round together so that their chains of
//! multiplications overlap. Every function gives the scalar numbers bit for
//! bit.

use super::sobol::{to_unit, MIX};
use crate::simd::LANES;

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

/// Eight lanes of `u32`s. Each step is written lane by lane so that the
/// compiler turns it into vector instructions.
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

/// The index shuffles of [`point2`] for `K` slots (their first seeds, per
/// lane) of sample `index[l]` in each lane `l`: the first of its two steps,
/// which [`Shuffled::points`] finishes.
///
/// [`point2`]: super::sobol::point2
#[derive(Clone, Copy, Debug)]
pub struct Shuffled<const K: usize> {
    /// The samples, one per lane.
    index: Lanes32,
    shuffles: [Lanes32; K],
}

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
    Shuffled {
        index: *index,
        shuffles: x[0],
    }
}

/// The inputs of both coordinates' scrambles (rows 0 and 1) of the slots'
/// shuffled indices.
#[inline(always)]
fn coordinate_rows<const K: usize>(shuffled: &Shuffled<K>) -> [[Lanes32; K]; 2] {
    let mut rows = [[[0; LANES]; K]; 2];
    for (k, shuffled) in shuffled.shuffles.iter().enumerate() {
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
/// two seeds, and, in the same pass, the shuffles of the same samples under
/// the first seeds `next0` of the next `K` slots. Both steps' multiplies
/// interleave, so one pass costs one chain of dependent multiplications
/// instead of two in a row.
#[inline(always)]
fn points_and_next<const K: usize>(
    shuffled: &Shuffled<K>,
    seeds: &[[Lanes32; 2]; K],
    next0: &[Lanes32; K],
) -> ([[[f32; LANES]; 2]; K], Shuffled<K>) {
    // Row 0: first coordinates; row 1: second ones; row 2: next shuffles.
    let [x, y] = coordinate_rows(shuffled);
    let mut rows = [x, y, reversed_index(&shuffled.index)];
    let row_seeds = [seeds.map(|s| s[0]), seeds.map(|s| s[1]), *next0];
    upward_mix_all(&mut rows, &row_seeds);
    let next = Shuffled {
        index: shuffled.index,
        shuffles: rows[2],
    };
    (to_points(&rows[0], &rows[1]), next)
}

/// [`point2`](super::sobol::point2) for `K` slots (seeds per lane) of
/// sample `index[l]` in each lane `l`, as 24-bit fractions in [0, 1): the same numbers as 8 · `K`
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

/// For each of `K` slots' seed sets, [`point2`](super::sobol::point2) in each lane `l` of sample
/// `index[l]` under that lane's seeds, for the CPU at hand.
#[inline]
pub fn points8_each<const K: usize>(
    index: &Lanes32,
    seeds: &[[Lanes32; 3]; K],
) -> [[[f32; LANES]; 2]; K] {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
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
    next0: &[Lanes32; K],
) -> ([[[f32; LANES]; 2]; K], Shuffled<K>) {
    points_and_next(shuffled, seeds, next0)
}

impl<const K: usize> Shuffled<K> {
    /// The index shuffles of sample `index[l]` in each lane `l` for `K`
    /// slots whose first seeds (per lane) are `seeds0`, for the CPU at
    /// hand.
    #[inline]
    pub fn new(index: &Lanes32, seeds0: &[Lanes32; K]) -> Shuffled<K> {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
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
        next0: &[Lanes32; K],
    ) -> ([[[f32; LANES]; 2]; K], Shuffled<K>) {
        #[cfg(target_arch = "x86_64")]
        if crate::simd::avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { points_and_next_avx2(self, seeds, next0) };
        }
        points_and_next(self, seeds, next0)
    }
}

/// [`point2`](super::sobol::point2) of samples `first .. first + 8` (`first` a multiple of 8)
/// for one slot's seeds, for the CPU at hand.
#[inline]
pub fn points8(first: u32, seeds: [u32; 3]) -> [[f32; LANES]; 2] {
    #[cfg(target_arch = "x86_64")]
    if crate::simd::avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { block_points_avx2(first, seeds) };
    }
    block_points(first, seeds)
}

/// [`points8`], its lanes of indices and seeds made where the points are.
/// Made by the caller, outside the AVX2 function, they would be stored in
/// halves and read whole, which the CPU cannot forward: the scalar
/// sampler's block fills would take 11.5 % of a next_week render instead of
/// 5 % for the same instructions.
#[inline(always)]
fn block_points(first: u32, seeds: [u32; 3]) -> [[f32; LANES]; 2] {
    let mut index = [first; LANES];
    let mut lanes = [[0; LANES]; 3];
    for l in 0..LANES {
        index[l] |= l as u32;
        for (row, seed) in lanes.iter_mut().zip(seeds) {
            row[l] = seed;
        }
    }
    let [points] = points8_sets(&index, &[lanes]);
    points
}

/// [`block_points`] compiled for AVX2.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn block_points_avx2(first: u32, seeds: [u32; 3]) -> [[f32; LANES]; 2] {
    block_points(first, seeds)
}

#[cfg(test)]
mod tests {
    use super::super::sobol::{point2, sobol1};
    use super::*;

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
            (points, shuffled) = shuffled.points(&now.map(|s| [s[1], s[2]]), &next.map(|s| s[0]));
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
