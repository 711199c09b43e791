//! The sample handle the camera, materials, lights and integrator draw from:
//! `next_1d` / `next_2d` numbers in [0, 1), either independent (PCG32) or
//! Owen-scrambled Sobol' (the default).
//!
//! A sample depends only on (seed, pixel, sample index, dimension), so an
//! image is the same for any thread count, crop, tile, round, pass or
//! resume. Dimensions are allocated in fixed slots (`Dim`): the camera takes
//! slots 0–2 (pixel 2-D, lens 2-D, time 1-D) and bounce `b` the six slots
//! from `3 + 6b`: light choice, light point (2-D), BSDF direction (2-D), BSDF
//! lobe (Fresnel choice or fuzz radius), Russian roulette, and the medium's
//! free-flight distance (further medium stretches of a ray get slots
//! of their own). Each slot gets its own scrambled, index-shuffled copy of the
//! 2-D Sobol' sequence (padding, as pbrt-v4's `PaddedSobolSampler`), so the
//! first 2^m samples of a pixel are a (0,m,2)-net in every 2-D slot.
//!
//! `begin` positions the handle at a slot of the current bounce; draws after
//! it take the following slots in order. A sampler reused from sample to
//! sample (`new`, then `start`) computes the first slots' Sobol' draws for
//! eight consecutive samples at once and keeps them; `draw_ahead` computes
//! another slot's draw before it is asked for (the same numbers, earlier).
//! The independent sampler ignores slots and draws its stream in call order.

use glam::Vec2;

use super::rng::{mix, Rng};
use super::{sobol, sobol8};
use crate::simd::LANES;

/// Which sampler renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol' (the default).
    #[default]
    Sobol,
    /// Independent PCG32 numbers.
    Independent,
}

impl SamplerKind {
    pub fn name(self) -> &'static str {
        match self {
            SamplerKind::Sobol => "sobol",
            SamplerKind::Independent => "independent",
        }
    }
}

/// A slot of the dimension allocation (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    /// Camera: pixel position (2-D), then lens (2-D) and time (1-D).
    Camera,
    /// Light choice (1-D), then the point on the light (2-D).
    Light,
    /// BSDF direction (2-D), then its lobe choice (1-D).
    Bsdf,
    /// Russian roulette (1-D).
    Roulette,
    /// The free-flight distance in the `k`-th medium stretch along the ray
    /// (1-D): stretch 0 takes the bounce's spare slot, later ones slots of
    /// their own above every bounce's.
    Medium(u32),
}

/// Slots the camera uses.
const CAMERA_SLOTS: u32 = 3;
/// Slots each bounce uses.
const BOUNCE_SLOTS: u32 = 6;
/// First slot of the extra medium stretches (2^16 per bounce).
const EXTRA_SLOTS: u32 = 1 << 31;

/// Samples whose draws a reusable sampler computes together (an aligned
/// block of indices): one vector lane each.
pub const BLOCK: u32 = LANES as u32;

/// Slots whose draws a reusable sampler keeps a [`BLOCK`] at a time: the
/// camera's and those of the first ten bounces. Deeper slots, which few
/// samples reach, are drawn one at a time.
const CACHED_SLOTS: usize = (CAMERA_SLOTS + 10 * BOUNCE_SLOTS) as usize;

/// The numbers of one sample (one pixel, one sample index). A sampler made
/// by [`Sampler::new`] moves from sample to sample with [`Sampler::start`]
/// and keeps, for each of its first slots, the Sobol' draws of the eight
/// samples (an aligned block of indices) the current one belongs to: they
/// are computed together in vector lanes ([`sobol8::points8`]) when the
/// first of them asks, and are the same numbers one at a time would be.
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    seed: u64,
    /// Where each lane's sample's draws stand (the paths of a pixel's
    /// block go side by side, each drawing its own: [`Sampler::lane`]).
    lanes: [Position; BLOCK as usize],
    /// The lane whose sample draws now.
    lane: usize,
    /// The draws kept per slot (none for a one-off sampler or the
    /// independent one).
    blocks: Vec<Block>,
}

/// One slot's draws for eight samples of a pixel: those of block `block`
/// of the pixel hashed to `pixel`, the only inputs besides the slot.
#[derive(Clone, Debug)]
struct Block {
    pixel: u64,
    block: u32,
    draws: [[f32; LANES]; 2],
}

impl Block {
    /// Makes this the block `block` of slot `slot` in the pixel `pixel`.
    #[cold]
    #[inline(never)]
    fn fill(&mut self, pixel: u64, block: u32, slot: u32) {
        *self = Block {
            pixel,
            block,
            draws: sobol8::points8(block * BLOCK, slot_seeds(pixel, slot)),
        };
    }

    /// No block: block numbers are below 2^29.
    const NONE: Block = Block {
        pixel: 0,
        block: u32::MAX,
        draws: [[0.0; LANES]; 2],
    };
}

/// A sample's place in its draws, one per lane ([`Sampler::lane`]). The
/// kept blocks are not part of it: a block holds the draws of one pixel's
/// eight samples, checked against the sample's pixel and block before it is
/// read.
#[derive(Clone, Debug)]
struct Position {
    /// The independent stream: every draw of the independent sampler
    /// (unseeded for the Sobol' sampler, which never draws from it).
    rng: Rng,
    /// Hash of (seed, pixel): the root of every slot's scramble seeds.
    pixel: u64,
    /// The sample index: its block is `index / BLOCK`, and the scrambles
    /// of a draw made alone read its bits reversed.
    index: u32,
    bounce: u32,
    slot: u32,
    /// The draw [`Sampler::draw_ahead`] made, with its slot.
    ahead: Held,
}

impl Position {
    /// The place of no sample yet: before [`Sampler::start`].
    const START: Position = Position {
        rng: Rng::UNUSED,
        pixel: 0,
        index: 0,
        bounce: 0,
        slot: 0,
        ahead: Held::NONE,
    };
}

/// A 2-D draw made ahead of its use, and its slot (`u64::MAX`, no slot,
/// when it holds none).
#[derive(Clone, Copy, Debug)]
struct Held {
    slot: u64,
    value: Vec2,
}

impl Held {
    const NONE: Held = Held {
        slot: u64::MAX,
        value: Vec2::ZERO,
    };
}

impl Sampler {
    /// A sampler for the samples of a render under `seed`, which keeps
    /// draws for the samples that follow; [`Sampler::start`] picks the
    /// sample. A pixel's samples in index order reuse each block of draws
    /// [`BLOCK`] times.
    pub fn new(kind: SamplerKind, seed: u64) -> Sampler {
        let kept = match kind {
            SamplerKind::Sobol => CACHED_SLOTS,
            SamplerKind::Independent => 0,
        };
        Sampler::keeping(kind, seed, kept)
    }

    /// The numbers of sample `index` of pixel `(x, y)` under `seed`, drawn
    /// one at a time (a sampler for one sample).
    pub fn for_sample(kind: SamplerKind, seed: u64, x: u32, y: u32, index: u32) -> Sampler {
        let mut sampler = Sampler::keeping(kind, seed, 0);
        sampler.start(x, y, index);
        sampler
    }

    /// A sampler that keeps the draws of its first `slots` slots, before
    /// [`Sampler::start`].
    fn keeping(kind: SamplerKind, seed: u64, slots: usize) -> Sampler {
        Sampler {
            kind,
            seed,
            lanes: [const { Position::START }; BLOCK as usize],
            lane: 0,
            blocks: vec![Block::NONE; slots],
        }
    }

    /// Makes lane `lane` (below [`BLOCK`]) the one that draws: its sample
    /// goes on from where its own draws stood, whatever other lanes drew
    /// since (the paths of a pixel's block go side by side, each drawing
    /// its own). Switching copies nothing: a copy of the place just written
    /// waited on the store of each field (a forwarding stall).
    #[inline]
    pub fn lane(&mut self, lane: usize) {
        debug_assert!(lane < BLOCK as usize);
        self.lane = lane % BLOCK as usize;
    }

    /// The current lane's place.
    #[inline(always)]
    fn at(&self) -> &Position {
        &self.lanes[self.lane % BLOCK as usize]
    }

    /// The current lane's place, to move on.
    #[inline(always)]
    fn at_mut(&mut self) -> &mut Position {
        &mut self.lanes[self.lane % BLOCK as usize]
    }

    /// Moves to sample `index` of pixel `(x, y)`, at its first bounce.
    #[inline]
    pub fn start(&mut self, x: u32, y: u32, index: u32) {
        let (kind, seed, pixel) = (self.kind, self.seed, self.pixel_seeds(x, y).0);
        let at = self.at_mut();
        if kind == SamplerKind::Independent {
            at.rng = Rng::for_sample(seed, x, y, index);
        }
        at.pixel = pixel;
        at.index = index;
        at.bounce = 0;
        at.slot = 0;
        at.ahead = Held::NONE;
    }

    /// The Sobol' 2-D draw of `slot` from its kept block (computing the
    /// block first if it is another sample's), or `None` for a slot whose
    /// draws are not kept.
    #[inline]
    fn kept(&mut self, slot: u32) -> Option<Vec2> {
        let (pixel, index) = (self.at().pixel, self.at().index);
        let block = index / BLOCK;
        let kept = self.blocks.get_mut(slot as usize)?;
        if kept.pixel != pixel || kept.block != block {
            kept.fill(pixel, block, slot);
        }
        let lane = (index % BLOCK) as usize;
        Some(Vec2::new(kept.draws[0][lane], kept.draws[1][lane]))
    }

    /// The root of pixel `(x, y)`'s scramble seeds under this sampler's
    /// seed.
    #[inline]
    pub fn pixel_seeds(&self, x: u32, y: u32) -> PixelSeeds {
        let pixel = ((y as u64) << 32) | x as u64;
        PixelSeeds(mix(self.seed ^ mix(pixel ^ 0x2545_f491_4f6c_dd1d)))
    }

    /// Sets the bounce that [`Sampler::begin`] allocates slots in.
    #[inline]
    pub fn start_bounce(&mut self, depth: u32) {
        self.at_mut().bounce = depth;
    }

    /// Moves to the first slot of `dim` (in the current bounce).
    #[inline]
    pub fn begin(&mut self, dim: Dim) {
        self.at_mut().slot = self.slot_of(dim);
    }

    /// The first slot of `dim` in the current bounce.
    #[inline]
    fn slot_of(&self, dim: Dim) -> u32 {
        slot_in(self.at().bounce, dim)
    }

    /// Makes now the 2-D draw of the first slot of `dim` in the current
    /// bounce. A later `next_2d` at that slot returns the held draw, and a
    /// `next_1d` its first number, which is that slot's 1-D draw: the
    /// numbers are the same as without it, only computed earlier. A caller
    /// draws ahead what it will need after a long computation that does not
    /// depend on it (a ray's intersection), so that the scramble's chain of
    /// dependent multiplications runs beside it instead of after it.
    /// Sobol' only: the independent sampler draws in call order.
    #[inline]
    pub fn draw_ahead(&mut self, dim: Dim) {
        if self.kind != SamplerKind::Sobol {
            return;
        }
        let slot = self.slot_of(dim);
        if (slot as usize) < self.blocks.len() {
            return;
        }
        self.at_mut().ahead = Held {
            slot: u64::from(slot),
            value: self.sobol_2d(slot),
        };
    }

    /// The held draw of `slot`, if [`Sampler::draw_ahead`] made it.
    #[inline]
    fn held(&self, slot: u32) -> Option<Vec2> {
        let ahead = self.at().ahead;
        (ahead.slot == u64::from(slot)).then_some(ahead.value)
    }

    /// The Sobol' 2-D draw of `slot`, computed alone.
    #[inline]
    fn sobol_2d(&self, slot: u32) -> Vec2 {
        let seeds = slot_seeds(self.at().pixel, slot);
        let (a, b) = sobol::point2(self.at().index, seeds);
        Vec2::new(sobol::to_unit(a), sobol::to_unit(b))
    }

    /// One number in [0, 1).
    #[inline(always)]
    pub fn next_1d(&mut self) -> f32 {
        match self.kind {
            SamplerKind::Independent => self.at_mut().rng.next_f32(),
            SamplerKind::Sobol => {
                let slot = self.at().slot;
                self.at_mut().slot = slot.wrapping_add(1);
                if let Some(v) = self.held(slot).or_else(|| self.kept(slot)) {
                    return v.x;
                }
                let h = slot_hash(self.at().pixel, slot);
                sobol::to_unit(sobol::point1(self.at().index, [h as u32, (h >> 32) as u32]))
            }
        }
    }

    /// Passes over a 1-D draw that would not be used, leaving every later
    /// draw as it would be had it been made.
    #[inline]
    pub fn skip_1d(&mut self) {
        match self.kind {
            SamplerKind::Independent => {
                self.at_mut().rng.next_u32();
            }
            SamplerKind::Sobol => {
                let at = self.at_mut();
                at.slot = at.slot.wrapping_add(1);
            }
        }
    }

    /// Passes over a 2-D draw, as [`Sampler::skip_1d`].
    #[inline]
    pub fn skip_2d(&mut self) {
        if self.kind == SamplerKind::Independent {
            self.at_mut().rng.next_u32();
        }
        self.skip_1d();
    }

    /// Two numbers in [0, 1).
    #[inline(always)]
    pub fn next_2d(&mut self) -> Vec2 {
        match self.kind {
            SamplerKind::Independent => {
                let x = self.at_mut().rng.next_f32();
                Vec2::new(x, self.at_mut().rng.next_f32())
            }
            SamplerKind::Sobol => {
                let slot = self.at().slot;
                let v = match self.held(slot).or_else(|| self.kept(slot)) {
                    Some(v) => v,
                    None => self.sobol_2d(slot),
                };
                self.at_mut().slot = slot.wrapping_add(1);
                v
            }
        }
    }
}

/// The root of one pixel's scramble seeds ([`Sampler::pixel_seeds`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelSeeds(u64);

impl PixelSeeds {
    /// The scramble seeds of the first slot of `dim` in bounce `bounce`
    /// plus `offset`: with them, sample `i`'s draw at that slot is
    /// `sobol::point2(i, seeds)` (as 24-bit fractions), the numbers
    /// [`Sampler::next_2d`] and [`Sampler::next_1d`] give it there.
    #[inline]
    pub fn slot(self, bounce: u32, dim: Dim, offset: u32) -> [u32; 3] {
        slot_seeds(self.0, slot_in(bounce, dim) + offset)
    }
}

/// The first slot of `dim` in bounce `bounce`.
#[inline]
fn slot_in(bounce: u32, dim: Dim) -> u32 {
    let first = CAMERA_SLOTS.saturating_add(bounce.saturating_mul(BOUNCE_SLOTS));
    match dim {
        Dim::Camera => 0,
        Dim::Light => first,
        Dim::Bsdf => first + 2,
        Dim::Roulette => first + 4,
        Dim::Medium(0) => first + 5,
        Dim::Medium(k) => EXTRA_SLOTS
            .wrapping_add(bounce.wrapping_mul(1 << 16))
            .wrapping_add(k),
    }
}

/// The hash of `slot` in the pixel hashed to `pixel`: its first two scramble
/// seeds (index shuffle, first coordinate).
#[inline]
fn slot_hash(pixel: u64, slot: u32) -> u64 {
    mix(pixel ^ u64::from(slot).wrapping_mul(0x9e37_79b9_7f4a_7c15))
}

/// The three scramble seeds of `slot` in the pixel hashed to `pixel`.
#[inline]
fn slot_seeds(pixel: u64, slot: u32) -> [u32; 3] {
    let h = slot_hash(pixel, slot);
    [h as u32, (h >> 32) as u32, mix(h) as u32]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn draws(kind: SamplerKind, seed: u64, x: u32, y: u32, i: u32) -> Vec<f32> {
        let mut s = Sampler::for_sample(kind, seed, x, y, i);
        s.begin(Dim::Camera);
        let Vec2 { x: a, y: b } = s.next_2d();
        s.start_bounce(3);
        s.begin(Dim::Roulette);
        vec![a, b, s.next_1d()]
    }

    #[test]
    fn samples_depend_on_every_input_and_nothing_else() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let base = draws(kind, 1, 2, 3, 4);
            assert_eq!(base, draws(kind, 1, 2, 3, 4));
            for other in [
                draws(kind, 0, 2, 3, 4),
                draws(kind, 1, 3, 3, 4),
                draws(kind, 1, 2, 2, 4),
                draws(kind, 1, 2, 3, 5),
            ] {
                assert_ne!(base, other, "{kind:?}");
            }
        }
    }

    #[test]
    fn independent_draws_are_the_old_stream_in_call_order() {
        let mut s = Sampler::for_sample(SamplerKind::Independent, 9, 1, 2, 3);
        let mut rng = Rng::for_sample(9, 1, 2, 3);
        s.begin(Dim::Bsdf);
        let x = rng.next_f32();
        assert_eq!(s.next_2d(), Vec2::new(x, rng.next_f32()));
        s.begin(Dim::Camera);
        assert_eq!(s.next_1d(), rng.next_f32());
    }

    #[test]
    fn sobol_slots_are_fixed_by_bounce_and_dimension() {
        // Reaching a slot by `begin` or by drawing the slots before it gives
        // the same number.
        let mut a = Sampler::for_sample(SamplerKind::Sobol, 5, 7, 8, 9);
        a.start_bounce(2);
        a.begin(Dim::Roulette);
        let direct = a.next_1d();
        let mut b = Sampler::for_sample(SamplerKind::Sobol, 5, 7, 8, 9);
        b.start_bounce(2);
        b.begin(Dim::Light);
        b.next_1d();
        b.next_2d();
        b.next_2d();
        b.next_1d();
        assert_eq!(b.next_1d(), direct);
        // Another bounce, another number.
        b.start_bounce(1);
        b.begin(Dim::Roulette);
        assert_ne!(b.next_1d(), direct);
    }

    #[test]
    fn draws_made_ahead_are_the_draws_made_in_place() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            for (bounce, i) in [(0, 0), (3, 17), (12, 1000)] {
                // Drawn in place: the direction, its lobe, roulette, the
                // next bounce's direction, and a 1-D draw of its first slot.
                let mut plain = Sampler::for_sample(kind, 2, 3, 4, i);
                let mut ahead = plain.clone();
                let draw = |s: &mut Sampler, early: bool| {
                    s.start_bounce(bounce);
                    if early {
                        s.draw_ahead(Dim::Bsdf);
                    }
                    s.begin(Dim::Bsdf);
                    let (dir, lobe) = (s.next_2d(), s.next_1d());
                    s.begin(Dim::Roulette);
                    let roulette = s.next_1d();
                    s.start_bounce(bounce + 1);
                    if early {
                        s.draw_ahead(Dim::Bsdf);
                    }
                    s.begin(Dim::Bsdf);
                    (dir, lobe, roulette, s.next_1d())
                };
                let (a, b) = (draw(&mut plain, false), draw(&mut ahead, true));
                assert_eq!(a, b, "{kind:?}, bounce {bounce}, sample {i}");
                // A held draw is not a stale one: the next bounce's slot
                // gave its own number, not the previous bounce's.
                if kind == SamplerKind::Sobol {
                    assert_ne!(a.0.x, a.3);
                }
            }
        }
    }

    #[test]
    fn a_pixels_seeds_give_the_numbers_the_sampler_draws() {
        // Kept slots (the camera's, bounce 3's) and drawn-alone ones
        // (bounce 40's), 2-D and 1-D, one-off samplers and a reused one.
        let mut reused = Sampler::new(SamplerKind::Sobol, 11);
        for (x, y, index) in [(0, 0, 0), (5, 9, 13), (640, 3, 1000)] {
            for (bounce, dim, offset) in [
                (0, Dim::Camera, 0),
                (0, Dim::Camera, 2),
                (3, Dim::Light, 1),
                (3, Dim::Roulette, 0),
                (40, Dim::Bsdf, 0),
            ] {
                let seeds = reused.pixel_seeds(x, y).slot(bounce, dim, offset);
                let (a, b) = sobol::point2(index, seeds);
                let want = Vec2::new(sobol::to_unit(a), sobol::to_unit(b));
                for s in [
                    &mut Sampler::for_sample(SamplerKind::Sobol, 11, x, y, index),
                    &mut reused,
                ] {
                    s.start(x, y, index);
                    s.start_bounce(bounce);
                    s.begin(dim);
                    for _ in 0..offset {
                        s.next_1d();
                    }
                    assert_eq!(s.next_2d(), want, "({x}, {y}) #{index} {dim:?}+{offset}");
                }
                reused.start(x, y, index);
                reused.start_bounce(bounce);
                reused.begin(dim);
                for _ in 0..offset {
                    reused.next_1d();
                }
                assert_eq!(reused.next_1d(), want.x);
            }
        }
    }

    #[test]
    fn a_skipped_draw_leaves_the_following_ones_unchanged() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let mut drawn = Sampler::for_sample(kind, 4, 5, 6, 7);
            let mut skipped = drawn.clone();
            drawn.begin(Dim::Camera);
            skipped.begin(Dim::Camera);
            drawn.next_2d();
            skipped.skip_2d();
            drawn.next_1d();
            skipped.skip_1d();
            assert_eq!(drawn.next_2d(), skipped.next_2d(), "{kind:?}");
            assert_eq!(drawn.next_1d(), skipped.next_1d(), "{kind:?}");
        }
    }

    #[test]
    fn medium_stretches_take_slots_no_other_draw_takes() {
        let mut s = Sampler::for_sample(SamplerKind::Sobol, 1, 2, 3, 4);
        let mut seen = std::collections::HashSet::new();
        for bounce in 0..64 {
            s.start_bounce(bounce);
            let mut slots = Vec::new();
            for dim in [Dim::Light, Dim::Bsdf, Dim::Roulette] {
                s.begin(dim);
                slots.push(s.at().slot);
            }
            // Light takes 3 slots (choice, point), the BSDF 2 (direction, lobe).
            slots.extend([slots[0] + 1, slots[1] + 1]);
            slots.extend((0..16).map(|k| {
                s.begin(Dim::Medium(k));
                s.at().slot
            }));
            for slot in slots {
                assert!(seen.insert(slot), "bounce {bounce}: slot {slot} twice");
            }
        }
        s.begin(Dim::Camera);
        for slot in 0..CAMERA_SLOTS {
            assert!(seen.insert(s.at().slot + slot), "camera slot {slot} reused");
        }
    }

    /// The pixel's first 2^m samples in one slot fill every cell of a
    /// 2^(m/2) × 2^(m/2) grid once (a consequence of the net property).
    #[test]
    fn a_pixels_samples_are_stratified_in_each_slot() {
        let m = 6;
        for (bounce, dim) in [(0, Dim::Camera), (0, Dim::Bsdf), (4, Dim::Light)] {
            let mut cells = [0u32; 64];
            for i in 0..(1u32 << m) {
                let mut s = Sampler::for_sample(SamplerKind::Sobol, 3, 10, 20, i);
                s.start_bounce(bounce);
                s.begin(dim);
                if dim == Dim::Light {
                    s.next_1d();
                }
                let Vec2 { x: a, y: b } = s.next_2d();
                cells[(a * 8.0) as usize * 8 + (b * 8.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "{dim:?}: {cells:?}");
        }
        // Independent numbers leave some cells empty (with near certainty).
        let mut cells = [0u32; 64];
        for i in 0..64 {
            let Vec2 { x: a, y: b } =
                Sampler::for_sample(SamplerKind::Independent, 3, 10, 20, i).next_2d();
            cells[(a * 8.0) as usize * 8 + (b * 8.0) as usize] += 1;
        }
        assert!(cells.contains(&0));
    }

    #[test]
    fn different_slots_are_not_correlated() {
        // Over many pixels' 16 samples, the correlation of two slots'
        // numbers is zero within noise (3 standard errors of 1/√n).
        let (mut sxy, mut n) = (0.0f64, 0.0f64);
        for px in 0..256 {
            for i in 0..16 {
                let mut s = Sampler::for_sample(SamplerKind::Sobol, 1, px, 0, i);
                s.begin(Dim::Camera);
                let a = s.next_2d().x;
                let c = s.next_2d().x;
                sxy += f64::from(a - 0.5) * f64::from(c - 0.5) * 12.0;
                n += 1.0;
            }
        }
        let r = sxy / n;
        assert!(r.abs() < 3.0 / n.sqrt(), "correlation {r}");
    }

    /// Every draw of a sample: the camera's slots and those of `bounces`
    /// bounces, 1-D and 2-D alike, through every slot kind.
    fn all_draws(s: &mut Sampler, bounces: u32) -> Vec<f32> {
        let mut out = Vec::new();
        s.begin(Dim::Camera);
        out.extend(s.next_2d().to_array());
        out.push(s.next_1d());
        for b in 0..bounces {
            s.start_bounce(b);
            s.draw_ahead(Dim::Bsdf);
            s.begin(Dim::Light);
            out.push(s.next_1d());
            out.extend(s.next_2d().to_array());
            s.begin(Dim::Bsdf);
            out.extend(s.next_2d().to_array());
            out.push(s.next_1d());
            for dim in [Dim::Roulette, Dim::Medium(0), Dim::Medium(3)] {
                s.begin(dim);
                out.push(s.next_1d());
            }
        }
        out
    }

    #[test]
    fn a_reused_sampler_draws_what_one_off_samplers_draw() {
        // Pixels revisited, a block of eight left for the same block of
        // another pixel, blocks entered in the middle and left early, indices
        // far apart, and paths deeper than the kept slots.
        let visits = [
            (3, 4, 0..3),
            (3, 4, 3..13),
            (9, 4, 12..14),
            (9, 4, 5..6),
            (3, 4, 13..40),
            (0, 0, 1000..1009),
            (3, 4, 40..41),
            (7, 7, u32::MAX - 9..u32::MAX),
        ];
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let mut reused = Sampler::new(kind, 17);
            for (x, y, indices) in visits.clone() {
                for i in indices {
                    let bounces = 1 + i % 14;
                    reused.start(x, y, i);
                    let mut alone = Sampler::for_sample(kind, 17, x, y, i);
                    assert_eq!(
                        all_draws(&mut reused, bounces),
                        all_draws(&mut alone, bounces),
                        "{kind:?} pixel ({x}, {y}) sample {i}"
                    );
                }
            }
        }
    }
}
