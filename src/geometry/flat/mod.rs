//! A small set of flat faces (axis-aligned rects and parallelograms, as
//! the Cornell box's walls and turned boxes) tested sixteen or eight at a
//! time, every face against each ray, with no hierarchy. A rect's lane
//! repeats `Rect::crossing` operation for operation, so its crossing is the
//! scalar one bit for bit. A parallelogram's distance is `Quad::crossing`'s
//! bit for bit; its `u` and `v` come from two dot products with vectors
//! precomputed per face (the scalar test's triple products rearranged), a
//! few roundings from the scalar ones, so a ray within those roundings of an
//! edge may be judged otherwise than a walk of the set's BVH judges it, as
//! may a tie between two faces at one distance.
//!
//! For so few faces one vector pass per pack costs less than a walk, whose
//! node visits and branches follow each ray. The passes are written once, generic over the lane type
//! ([`wide::Wide`]), with the same IEEE operations per lane in every form:
//! sixteen lanes in AVX-512F registers where the CPU has them (two passes
//! for the Cornell box's eighteen faces instead of three: 1.11× its
//! samples/s), else eight lanes as plain
//! arrays that the compiler turns into vector instructions, compiled twice
//! with the AVX copy picked at run time. Not `wide::f32x8`, which the
//! project uses elsewhere: its width is fixed when `wide` is compiled, so
//! inside a function given AVX at run time it stays two SSE halves (78 % of
//! the arrays' rate).

#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(target_arch = "x86_64")]
mod avx8;
mod hits8;
mod rays8;
mod wide;

use super::primitive::Primitive;
use super::shapes::{Crossing, Quad, Rect};
use super::Ray;
use crate::simd::LANES;
#[cfg(target_arch = "x86_64")]
use avx512::Lanes16;
use glam::Vec3;
pub use hits8::Hits8;
pub use rays8::Nearest8;
use wide::{Lanes8, Wide};

/// Most faces a set may hold to be tested in passes rather than walked:
/// with more turned boxes in the Cornell box, the passes took 7 % less time
/// than the walk at 30 faces, 8 % less at 36 and as much at 48.
pub const MAX_FACES: usize = 40;

/// A pack of axis-aligned rects as [`Rect::crossing`] reads them, each
/// lane's axes picked by masks. An unused lane has a NaN plane, which no
/// ray crosses.
#[derive(Clone, Copy, Debug)]
struct RectPack<W: Wide> {
    k: W::Row,
    a: (W::Row, W::Row),
    b: (W::Row, W::Row),
    /// Normal axis x, else y, else z.
    normal_x: W::Mask,
    normal_y: W::Mask,
    /// First span axis x, else y; second span axis y, else z.
    first_x: W::Mask,
    second_y: W::Mask,
    slot: W::Row,
}

/// A pack of parallelograms, each lane's `u` and `v` found by two dot
/// products: `Quad::crossing`'s triple products `(rel × edge_v) · normal`
/// and `(edge_u × rel) · normal`, over the area, rearranged as `rel ·
/// across_u` and `rel · across_v` with `across_u = (edge_v × normal) / area`
/// and `across_v = (normal × edge_u) / area` precomputed per face. The
/// distance is `Quad::crossing`'s, bit for bit; `u` and `v` differ from it
/// by a few roundings. An unused lane has a zero normal, which gives a NaN
/// distance.
#[derive(Clone, Copy, Debug)]
struct QuadPack<W: Wide> {
    corner: [W::Row; 3],
    normal: [W::Row; 3],
    across_u: [W::Row; 3],
    across_v: [W::Row; 3],
    slot: W::Row,
}

/// A ray's origin and direction, each coordinate in every lane.
struct RayLanes<W> {
    o: [W; 3],
    d: [W; 3],
}

impl<W: Wide> RayLanes<W> {
    #[inline(always)]
    fn new(ray: &Ray) -> RayLanes<W> {
        RayLanes {
            o: ray.origin.to_array().map(W::splat),
            d: ray.dir.to_array().map(W::splat),
        }
    }
}

/// The nearest crossing so far in each lane: distance, slot, and a
/// parallelogram's `(u, v)`.
#[derive(Clone)]
struct Best<W> {
    t: W,
    /// Slots as the bits of floats, so that they blend like the rest.
    slot: W,
    u: W,
    v: W,
}

impl<W: Wide> Best<W> {
    /// Takes `other`'s crossing in each lane where it is nearer, or as
    /// near with a lower slot (a lane without one has slot bits that are a
    /// NaN, which no comparison takes; a real slot's bits are a subnormal,
    /// which compare as their integers).
    #[inline(always)]
    fn nearest_of(&mut self, other: &Best<W>) {
        let take = self.beaten_by(other.t, other.slot);
        self.keep(take, other.t, other.slot, other.u, other.v);
    }

    /// The lanes where a crossing at `t` of a face at `slot` is nearer
    /// than the best, or as near with a lower slot.
    #[inline(always)]
    fn beaten_by(&self, t: W, slot: W) -> W::Mask {
        t.lt(self.t) | (t.eq(self.t) & slot.lt(self.slot))
    }

    #[inline(always)]
    fn keep(&mut self, take: W::Mask, t: W, slot: W, u: W, v: W) {
        self.t = W::select(take, t, self.t);
        self.u = W::select(take, u, self.u);
        self.v = W::select(take, v, self.v);
        self.slot = W::select(take, slot, self.slot);
    }

    /// The slot in `lane` (`u32::MAX` where the lane found no crossing).
    #[inline(always)]
    fn slot(&self, lane: usize) -> u32 {
        self.slot.lane(lane).to_bits()
    }
}

impl<W: Wide> RectPack<W> {
    /// The distance to each plane and whether the point there lies in the
    /// rect, as `Rect::crossing` computes them: `(k − o) / d` on the normal
    /// axis (infinite or NaN where `d` is zero, which no range accepts, as
    /// `Rect::crossing` rejects such rays), then `o + t·d` on the two span
    /// axes (NaN passes, as there).
    #[inline(always)]
    fn crossings(&self, r: &RayLanes<W>) -> (W, W::Mask) {
        let pick =
            |x: W::Mask, y: W::Mask, v: &[W; 3]| W::select(x, v[0], W::select(y, v[1], v[2]));
        let o = pick(self.normal_x, self.normal_y, &r.o);
        let d = pick(self.normal_x, self.normal_y, &r.d);
        let t = (W::load(&self.k) - o) / d;
        let none = W::NONE;
        let (oi, di) = (
            W::select(self.first_x, r.o[0], r.o[1]),
            W::select(self.first_x, r.d[0], r.d[1]),
        );
        let (oj, dj) = (
            pick(none, self.second_y, &r.o),
            pick(none, self.second_y, &r.d),
        );
        let x = oi + t * di;
        let y = oj + t * dj;
        let (a0, a1) = (W::load(&self.a.0), W::load(&self.a.1));
        let (b0, b1) = (W::load(&self.b.0), W::load(&self.b.1));
        let out = x.lt(a0) | a1.lt(x) | y.lt(b0) | b1.lt(y);
        (t, !out)
    }
}

impl<W: Wide> QuadPack<W> {
    /// Each lane's `t` by `Quad::crossing`'s operations in glam's order
    /// (dot products left to right), and its `u` and `v`.
    #[inline(always)]
    fn crossings(&self, r: &RayLanes<W>) -> (W, W, W) {
        let [nx, ny, nz] = self.normal.each_ref().map(W::load);
        let [cx, cy, cz] = self.corner.each_ref().map(W::load);
        let ([ox, oy, oz], [dx, dy, dz]) = (r.o, r.d);
        let denom = nx * dx + ny * dy + nz * dz;
        let num = nx * (cx - ox) + ny * (cy - oy) + nz * (cz - oz);
        let t = num / denom;
        let rx = (ox + t * dx) - cx;
        let ry = (oy + t * dy) - cy;
        let rz = (oz + t * dz) - cz;
        let dot = |v: &[W::Row; 3]| {
            let [x, y, z] = v.each_ref().map(W::load);
            rx * x + ry * y + rz * z
        };
        (t, dot(&self.across_u), dot(&self.across_v))
    }
}

/// `u` and `v` both in [0, 1] (NaN fails, as in `Quad::crossing`).
#[inline(always)]
fn within_unit<W: Wide>(u: W, v: W) -> W::Mask {
    let (zero, one) = (W::splat(0.0), W::splat(1.0));
    zero.le(u) & u.le(one) & zero.le(v) & v.le(one)
}

/// The faces of a primitive set in packs of one kind, in slot order, as
/// wide as the CPU runs best, for one ray at a time; and one face to a pass
/// for eight rays at a time ([`rays8`]).
#[derive(Debug)]
pub struct FlatFaces {
    packs: Width,
    each: rays8::Each,
    faces: hits8::Faces,
}

/// Packs of sixteen lanes with AVX-512F, else of eight.
#[derive(Debug)]
enum Width {
    Eight(Packs<Lanes8>),
    #[cfg(target_arch = "x86_64")]
    Sixteen(Packs<Lanes16>),
}

/// The rects and the parallelograms of a set, in packs of `W::LANES`.
#[derive(Debug)]
struct Packs<W: Wide> {
    rects: Vec<RectPack<W>>,
    quads: Vec<QuadPack<W>>,
}

impl FlatFaces {
    /// The packs of primitives in slot order, sixteen to a pack where the
    /// CPU has AVX-512F; `None` unless every one is a rect or a
    /// parallelogram and there are at most [`MAX_FACES`].
    pub fn new(prims: &[Primitive]) -> Option<FlatFaces> {
        #[cfg(target_arch = "x86_64")]
        let packs = if crate::simd::avx512f() {
            Width::Sixteen(Packs::new(prims)?)
        } else {
            Width::Eight(Packs::new(prims)?)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let packs = Width::Eight(Packs::new(prims)?);
        Some(FlatFaces {
            packs,
            each: rays8::Each::new(prims),
            faces: hits8::Faces::new(prims),
        })
    }

    /// The nearest crossing with `t` in `(t_min, t_max)` and its slot.
    #[inline]
    pub fn nearest(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(usize, Crossing)> {
        match &self.packs {
            Width::Eight(p) => {
                #[cfg(target_arch = "x86_64")]
                if crate::simd::avx() {
                    // SAFETY: the CPU has AVX.
                    return unsafe { p.nearest_avx(ray, t_min, t_max) };
                }
                p.nearest_lanes::<false>(ray, t_min, t_max)
            }
            // SAFETY: sixteen-lane packs are built only where the CPU has
            // AVX-512F.
            #[cfg(target_arch = "x86_64")]
            Width::Sixteen(p) => unsafe { p.nearest_avx512(ray, t_min, t_max) },
        }
    }

    /// [`FlatFaces::nearest`] for eight rays, ray `l` in lane `l`, bit for
    /// bit.
    #[inline]
    pub fn nearest8(&self, rays: &[Ray; LANES], t_min: f32, t_max: f32) -> Nearest8 {
        self.each.nearest(rays, t_min, t_max)
    }

    /// The hits of eight rays at their crossings `near`
    /// ([`FlatFaces::nearest8`]), as the one-ray hits give them, written
    /// into `out`; false where the CPU lacks AVX2.
    #[inline]
    pub fn hits8(&self, rays: &[Ray; LANES], near: &Nearest8, out: &mut Hits8) -> bool {
        self.faces.hits(rays, near, out)
    }

    /// Whether some face is crossed with `t` in `(t_min, t_max)`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        match &self.packs {
            Width::Eight(p) => {
                #[cfg(target_arch = "x86_64")]
                if crate::simd::avx() {
                    // SAFETY: the CPU has AVX.
                    return unsafe { p.occluded_avx(ray, t_min, t_max) };
                }
                p.occluded_lanes(ray, t_min, t_max)
            }
            // SAFETY: as in `nearest`.
            #[cfg(target_arch = "x86_64")]
            Width::Sixteen(p) => unsafe { p.occluded_avx512(ray, t_min, t_max) },
        }
    }
}

impl Packs<Lanes8> {
    /// [`Packs::nearest_lanes`] compiled with AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn nearest_avx(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(usize, Crossing)> {
        self.nearest_lanes::<true>(ray, t_min, t_max)
    }

    /// [`Packs::occluded_lanes`] compiled with AVX.
    ///
    /// # Safety
    /// The CPU must support AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn occluded_avx(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.occluded_lanes(ray, t_min, t_max)
    }
}

#[cfg(target_arch = "x86_64")]
impl Packs<Lanes16> {
    /// [`Packs::nearest_lanes`] in sixteen lanes, compiled with AVX-512F.
    ///
    /// # Safety
    /// The CPU must support AVX-512F.
    #[target_feature(enable = "avx512f")]
    unsafe fn nearest_avx512(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(usize, Crossing)> {
        self.nearest_lanes::<true>(ray, t_min, t_max)
    }

    /// [`Packs::occluded_lanes`] in sixteen lanes, compiled with AVX-512F.
    ///
    /// # Safety
    /// The CPU must support AVX-512F.
    #[target_feature(enable = "avx512f")]
    unsafe fn occluded_avx512(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.occluded_lanes(ray, t_min, t_max)
    }
}

impl<W: Wide> Packs<W> {
    /// See [`FlatFaces::new`].
    fn new(prims: &[Primitive]) -> Option<Packs<W>> {
        if prims.is_empty() || prims.len() > MAX_FACES {
            return None;
        }
        let (rects, quads) = by_kind(prims)?;
        Some(Packs {
            rects: rects.chunks(W::LANES).map(rect_pack).collect(),
            quads: quads.chunks(W::LANES).map(quad_pack).collect(),
        })
    }

    #[inline(always)]
    fn nearest_lanes<const AVX: bool>(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(usize, Crossing)> {
        let r = RayLanes::<W>::new(ray);
        let t_min = W::splat(t_min);
        let zero = W::splat(0.0);
        let mut best = Best {
            t: W::splat(t_max),
            slot: W::splat(f32::from_bits(u32::MAX)),
            u: zero,
            v: zero,
        };
        // A later pack's lane holds a rect or a parallelogram of any slot,
        // so a tie within a lane goes to the lower slot.
        for p in &self.rects {
            let (t, inside) = p.crossings(&r);
            let slot = W::load(&p.slot);
            let take = t_min.lt(t) & best.beaten_by(t, slot) & inside;
            best.keep(take, t, slot, zero, zero);
        }
        for p in &self.quads {
            let (t, u, v) = p.crossings(&r);
            let slot = W::load(&p.slot);
            let take = t_min.lt(t) & best.beaten_by(t, slot) & within_unit(u, v);
            best.keep(take, t, slot, u, v);
        }
        // The nearest lane; of equal distances, the lowest slot. A lane
        // without a crossing keeps `t_max`, and every crossing is strictly
        // nearer, so the least distance is a crossing unless there is none.
        let near = best.t.least();
        let mut lanes = W::bits::<AVX>(best.t.eq(W::splat(near)));
        // Lanes without a crossing keep `t_max` and slot `u32::MAX`, whose
        // bits are a NaN: a slot equal to itself (a float comparison; a
        // real slot's bits are a subnormal, which compares as itself) is a
        // crossing. Testing `near < t_max` instead would say the same, but
        // then the compiler takes the slots out of their vector and runs
        // the passes a lane at a time: 747 M → 1 064 M instructions for a
        // Cornell render. Comparing the slots' bits as integers split the
        // comparison in halves (AVX has no 256-bit integer compare) and cost
        // some twenty instructions more than this, with `bits`. One lane (the common case) is told by a power-of-two test,
        // not `count_ones`, which is a dozen instructions without POPCNT.
        lanes &= W::bits::<AVX>(best.slot.eq(best.slot));
        let lane = if lanes & lanes.wrapping_sub(1) == 0 {
            (lanes != 0).then(|| lanes.trailing_zeros() as usize)
        } else {
            (0..W::LANES)
                .filter(|l| lanes & (1 << l) != 0)
                .min_by_key(|&l| best.slot(l))
        };
        let l = lane?;
        Some((
            best.slot(l) as usize,
            Crossing {
                t: best.t.lane(l),
                data: Vec3::new(best.u.lane(l), best.v.lane(l), 0.0),
            },
        ))
    }

    /// Plain loops, not iterator adaptors: a closure the compiler keeps
    /// out of line is compiled without AVX, whatever calls it.
    #[inline(always)]
    fn occluded_lanes(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let r = RayLanes::<W>::new(ray);
        let (t_min, t_max) = (W::splat(t_min), W::splat(t_max));
        // Parallelograms first: in a room they are what stands inside.
        for p in &self.quads {
            let (t, u, v) = p.crossings(&r);
            if W::any(t_min.lt(t) & t.lt(t_max) & within_unit(u, v)) {
                return true;
            }
        }
        for p in &self.rects {
            let (t, inside) = p.crossings(&r);
            if W::any(t_min.lt(t) & t.lt(t_max) & inside) {
                return true;
            }
        }
        false
    }
}

/// The rects and the parallelograms of `prims` with their slots, each in
/// slot order; `None` if it holds another kind.
#[allow(clippy::type_complexity)]
fn by_kind(prims: &[Primitive]) -> Option<(Vec<(u32, Rect)>, Vec<(u32, Quad)>)> {
    let mut rects = Vec::new();
    let mut quads = Vec::new();
    for (slot, p) in (0u32..).zip(prims) {
        match p {
            Primitive::Rect(r) => rects.push((slot, *r)),
            Primitive::Quad(q) => quads.push((slot, *q)),
            _ => return None,
        }
    }
    Some((rects, quads))
}

/// Up to `W::LANES` rects with their slots as one pack.
fn rect_pack<W: Wide>(faces: &[(u32, Rect)]) -> RectPack<W> {
    let lane = |f: &dyn Fn(&Rect) -> f32, empty: f32| {
        W::row(|l| faces.get(l).map_or(empty, |(_, r)| f(r)))
    };
    let flag = |f: &dyn Fn(&Rect) -> bool| W::mask(|l| faces.get(l).is_some_and(|(_, r)| f(r)));
    RectPack {
        k: lane(&|r| r.k, f32::NAN),
        a: (lane(&|r| r.a.0, 0.0), lane(&|r| r.a.1, 0.0)),
        b: (lane(&|r| r.b.0, 0.0), lane(&|r| r.b.1, 0.0)),
        normal_x: flag(&|r| r.axis == 0),
        normal_y: flag(&|r| r.axis == 1),
        first_x: flag(&|r| r.span[0] == 0),
        second_y: flag(&|r| r.span[1] == 1),
        slot: slots::<W, _>(faces),
    }
}

/// Up to `W::LANES` parallelograms with their slots as one pack.
fn quad_pack<W: Wide>(faces: &[(u32, Quad)]) -> QuadPack<W> {
    let vec = |f: &dyn Fn(&Quad) -> Vec3| {
        [0, 1, 2].map(|axis| W::row(|l| faces.get(l).map_or(0.0, |(_, q)| f(q)[axis])))
    };
    QuadPack {
        corner: vec(&|q| q.corner),
        normal: vec(&|q| q.normal),
        across_u: vec(&|q| q.edge_v.cross(q.normal) * q.inv_area()),
        across_v: vec(&|q| q.normal.cross(q.edge_u) * q.inv_area()),
        slot: slots::<W, _>(faces),
    }
}

/// The faces' slots as float bits, `u32::MAX` in unused lanes.
fn slots<W: Wide, F>(faces: &[(u32, F)]) -> W::Row {
    W::row(|l| f32::from_bits(faces.get(l).map_or(u32::MAX, |f| f.0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::numbers;
    use crate::scene::object::RectPlane;

    /// Rects in all three planes, facing either way, and turned
    /// parallelograms around `at`, `size` across: 18 rects and 22
    /// parallelograms (40, the most a set packs), so packs of eight and of
    /// sixteen are full and partial.
    fn faces(at: Vec3, size: f32, r: &mut impl FnMut() -> f32) -> Vec<Primitive> {
        let mut out = Vec::new();
        for (i, plane) in [RectPlane::Xy, RectPlane::Xz, RectPlane::Yz]
            .repeat(6)
            .into_iter()
            .enumerate()
        {
            let lo = (r() - 0.5) * size;
            let span = (lo, lo + size * (0.2 + r()));
            let k = at[[2, 1, 0][i % 3]] + (r() - 0.5) * size;
            // The centre's coordinates on the rect's two span axes.
            let (a, b) = match plane {
                RectPlane::Xy => (at.x, at.y),
                RectPlane::Xz => (at.x, at.z),
                RectPlane::Yz => (at.y, at.z),
            };
            let rect = Rect::new(plane, (a + span.0, a + span.1), (b + span.0, b + span.1), k);
            // Every other one facing −axis.
            out.push(Primitive::Rect(if i % 2 == 1 {
                rect.flipped()
            } else {
                rect
            }));
        }
        while out.len() < MAX_FACES {
            let v = |r: &mut dyn FnMut() -> f32| Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * size;
            let corner = at + v(r);
            let (u, w) = (v(r), v(r));
            if let Some(q) = Quad::new(corner, u, w, u.cross(w)) {
                out.push(Primitive::Quad(q));
            }
        }
        out
    }

    /// Rays through the faces' region, some aimed at corners and edges, some
    /// parallel to an axis or with zero components.
    fn rays(prims: &[Primitive], at: Vec3, size: f32, r: &mut impl FnMut() -> f32) -> Vec<Ray> {
        let mut out = Vec::new();
        for i in 0..4000 {
            let from = at + Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 3.0 * size;
            let target = match (i % 4, &prims[i % prims.len()]) {
                (0, Primitive::Quad(q)) => q.corner + q.edge_u * (i % 3) as f32 * 0.5,
                (1, Primitive::Rect(rc)) => {
                    let mut p = Vec3::splat(rc.k);
                    p[rc.span[0] as usize] = rc.a.1;
                    p[rc.span[1] as usize] = rc.b.0 + r() * (rc.b.1 - rc.b.0);
                    p
                }
                _ => at + Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * size,
            };
            let mut dir = target - from;
            if i % 7 == 0 {
                dir[i % 3] = 0.0;
            }
            if i % 11 == 0 {
                dir = Vec3::ZERO.with_x(-1.0);
            }
            out.push(Ray::new(from, dir, 0.0));
        }
        out
    }

    /// Every face's own test, slot by slot (a later face replaces an earlier
    /// one only when strictly nearer).
    fn one_by_one(
        prims: &[Primitive],
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(usize, Crossing)> {
        let mut best = None;
        let mut t_max = t_max;
        for (slot, p) in prims.iter().enumerate() {
            if let Some(c) = p.crossing(ray, t_min, t_max) {
                t_max = c.t;
                best = Some((slot, c));
            }
        }
        best
    }

    /// How far from a parallelogram's edges the ray's line meets its plane,
    /// in `u` and `v`, by `Quad::crossing`'s operations without its range
    /// test: the smallest of |u|, |1 − u|, |v|, |1 − v|. Infinite for rects.
    fn edge_distance(p: &Primitive, ray: &Ray) -> f32 {
        let Primitive::Quad(q) = p else {
            return f32::INFINITY;
        };
        let t = q.normal.dot(q.corner - ray.origin) / q.normal.dot(ray.dir);
        let rel = ray.at(t) - q.corner;
        let u = rel.cross(q.edge_v).dot(q.normal) * q.inv_area();
        let v = q.edge_u.cross(rel).dot(q.normal) * q.inv_area();
        [u, 1.0 - u, v, 1.0 - v]
            .map(f32::abs)
            .into_iter()
            .fold(f32::INFINITY, f32::min)
    }

    /// What rounding may decide: a parallelogram met within this of an edge.
    const GRAZE: f32 = 1e-5;

    #[test]
    fn each_lane_gives_the_face_own_crossing() {
        let mut r = numbers(11);
        let (mut hits, mut blocked, mut grazes) = (0, 0, 0);
        for (at, size) in [
            (Vec3::ZERO, 1.0),
            (Vec3::new(1e5, -3e4, 7e3), 300.0),
            (Vec3::splat(-40.0), 1e-2),
        ] {
            let prims = faces(at, size, &mut r);
            let flat = FlatFaces::new(&prims).expect("rects and parallelograms only");
            let eight = Packs::<Lanes8>::new(&prims).expect("rects and parallelograms only");
            #[cfg(target_arch = "x86_64")]
            let sixteen =
                crate::simd::avx512f().then(|| Packs::<Lanes16>::new(&prims).expect("packed"));
            for ray in rays(&prims, at, size, &mut r) {
                let want = one_by_one(&prims, &ray, 0.0, f32::INFINITY);
                let grazed = || prims.iter().any(|p| edge_distance(p, &ray) < GRAZE);
                // Eight lanes as compiled for any CPU, the copy this CPU
                // runs, and sixteen lanes where the CPU has AVX-512F.
                let mut answers = vec![
                    eight.nearest_lanes::<false>(&ray, 0.0, f32::INFINITY),
                    flat.nearest(&ray, 0.0, f32::INFINITY),
                ];
                #[cfg(target_arch = "x86_64")]
                if let Some(p) = &sixteen {
                    // SAFETY: built only where the CPU has AVX-512F.
                    answers.push(unsafe { p.nearest_avx512(&ray, 0.0, f32::INFINITY) });
                }
                // Every width and copy runs the same operations per face.
                let bits = |a: &Option<(usize, Crossing)>| {
                    a.map(|(s, c)| (s, c.t.to_bits(), c.data.to_array().map(f32::to_bits)))
                };
                for other in &answers[1..] {
                    assert_eq!(bits(other), bits(&answers[0]), "{ray:?}");
                }
                for got in answers {
                    match (got, want) {
                        (None, None) => {}
                        // Another face than the scalar loop's only in a tie.
                        (Some((gs, g)), Some((_, w))) if g.t == w.t => {
                            // A tie may go to either face. The distance is
                            // the face's own, bit for bit; a rect's data too,
                            // a parallelogram's (u, v) to a few roundings.
                            let own = prims[gs].crossing(&ray, 0.0, f32::INFINITY);
                            if let Some(own) = own {
                                assert_eq!(own.t.to_bits(), g.t.to_bits());
                                let off = (own.data - g.data).abs().max_element();
                                assert!(off <= 4.0 * f32::EPSILON, "{own:?} {g:?}");
                            } else {
                                assert!(edge_distance(&prims[gs], &ray) < GRAZE);
                            }
                            hits += 1;
                        }
                        // Otherwise the two tests judged a graze otherwise.
                        _ => {
                            assert!(grazed(), "{got:?} against {want:?} for {ray:?}");
                            grazes += 1;
                        }
                    }
                }
                for t_max in [f32::INFINITY, r() * size, want.map_or(1.0, |w| w.1.t)] {
                    let any = prims.iter().any(|p| p.crossing(&ray, 0.0, t_max).is_some());
                    let mut answers = vec![
                        eight.occluded_lanes(&ray, 0.0, t_max),
                        flat.occluded(&ray, 0.0, t_max),
                    ];
                    #[cfg(target_arch = "x86_64")]
                    if let Some(p) = &sixteen {
                        // SAFETY: as above.
                        answers.push(unsafe { p.occluded_avx512(&ray, 0.0, t_max) });
                    }
                    for blocks in answers {
                        assert!(blocks == any || grazed(), "{ray:?} to {t_max}");
                    }
                    blocked += usize::from(any);
                }
            }
        }
        eprintln!("{hits} hits, {blocked} blocked, {grazes} grazes");
        assert!(
            hits > 10_000 && blocked > 10_000 && grazes < 100,
            "{hits} hits, {blocked} blocked, {grazes} grazes"
        );
    }

    /// Rays in groups of eight, as the lanes trace them.
    fn eights(rays: &[Ray]) -> impl Iterator<Item = [Ray; LANES]> + '_ {
        rays.chunks_exact(LANES)
            .map(|c| std::array::from_fn(|l| c[l]))
    }

    #[test]
    fn eight_rays_side_by_side_cross_where_each_alone_does() {
        let mut r = numbers(23);
        let mut crossed = 0;
        for (at, size) in [(Vec3::ZERO, 1.0), (Vec3::new(-2e4, 5e3, 1e5), 50.0)] {
            let prims = faces(at, size, &mut r);
            let flat = FlatFaces::new(&prims).expect("rects and parallelograms only");
            let forms = rays8::tests::every_form(&prims);
            for eight in eights(&rays(&prims, at, size, &mut r)) {
                for t_max in [f32::INFINITY, size] {
                    for near in forms.iter().map(|f| f.nearest(&eight, 0.0, t_max)) {
                        for (l, ray) in eight.iter().enumerate() {
                            let alone = flat.nearest(ray, 0.0, t_max);
                            let side = (near.slot[l] != u32::MAX).then(|| {
                                let data = [near.u[l], near.v[l], 0.0].map(f32::to_bits);
                                (near.slot[l] as usize, near.t[l].to_bits(), data)
                            });
                            let alone = alone.map(|(s, c)| {
                                (s, c.t.to_bits(), c.data.to_array().map(f32::to_bits))
                            });
                            assert_eq!(side, alone, "{ray:?} to {t_max}");
                            crossed += usize::from(side.is_some());
                        }
                    }
                }
            }
        }
        assert!(crossed > 10_000, "{crossed} crossings");
    }

    #[test]
    fn a_tie_goes_to_the_lowest_slot_side_by_side() {
        // One square as a rect and as parallelograms at several slots: the
        // same distance bit for bit (an axis normal's dot products are
        // exact), so every crossing is a tie between chains.
        let rect = Rect::new(RectPlane::Xy, (0.0, 1.0), (0.0, 1.0), 0.0);
        let quad = Quad::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).expect("a square");
        let (r, q) = (Primitive::Rect(rect), Primitive::Quad(quad));
        let mut rng = numbers(3);
        // Every order of kinds: the one-ray packs put rects and
        // parallelograms in separate packs whose lanes meet.
        for (prims, want) in [
            (vec![q, q, r, q], 0),
            (vec![r, q, q], 0),
            (vec![q, r, q, q], 0),
        ] {
            let flat = FlatFaces::new(&prims).expect("flat");
            let eight: [Ray; LANES] = std::array::from_fn(|_| {
                let target = Vec3::new(0.1 + 0.8 * rng(), 0.1 + 0.8 * rng(), 0.0);
                let from = Vec3::new(rng(), rng(), 2.0 + rng());
                Ray::new(from, target - from, 0.0)
            });
            let near = flat.nearest8(&eight, 0.0, f32::INFINITY);
            for form in rays8::tests::every_form(&prims) {
                let other = form.nearest(&eight, 0.0, f32::INFINITY);
                assert_eq!((other.slot, other.t), (near.slot, near.t), "{prims:?}");
            }
            for (l, ray) in eight.iter().enumerate() {
                assert_eq!(near.slot[l], want, "{prims:?}");
                let eight_lanes = Packs::<Lanes8>::new(&prims).expect("packed");
                let alone = flat.nearest(ray, 0.0, f32::INFINITY).expect("a crossing");
                let portable = eight_lanes.nearest_lanes::<false>(ray, 0.0, f32::INFINITY);
                for (slot, c) in [alone, portable.expect("a crossing")] {
                    assert_eq!(slot, want as usize, "{prims:?}");
                    assert_eq!(c.t.to_bits(), near.t[l].to_bits());
                }
            }
        }
        // The parallelograms alone: slot 1 in the second chain, 2 in the first.
        let flat = FlatFaces::new(&[r, q, q]).expect("flat");
        let down = Ray::new(Vec3::new(0.5, 0.5, 1.0), -Vec3::Z, 0.0);
        let near = flat.nearest8(&[down; LANES], 0.0, f32::INFINITY);
        assert_eq!(near.slot, [0; LANES]);
        let flat = FlatFaces::new(&[q, q]).expect("flat");
        let near = flat.nearest8(&[down; LANES], 0.0, f32::INFINITY);
        assert_eq!(near.slot, [0; LANES]);
    }

    #[test]
    fn eight_hits_side_by_side_are_each_face_own_hit() {
        use crate::geometry::emitter::LightId;
        use crate::geometry::hit::facing;
        use crate::scene::MaterialId;
        let mut r = numbers(29);
        // Every sixth face (seven: a table of eight slots with the blank
        // one), every third (fourteen: a table of sixteen), every second
        // (twenty: a table of 32) and all of them (gathered), rects and
        // parallelograms in each.
        let mut built = [0; 4];
        let places = [(Vec3::ZERO, 1.0), (Vec3::new(3e4, -1e3, 2e2), 20.0)];
        for ((at, size), (kind, step)) in places
            .into_iter()
            .flat_map(|place| [(0, 6), (1, 3), (2, 2), (3, 1)].map(|k| (place, k)))
        {
            let prims: Vec<Primitive> = faces(at, size, &mut r).into_iter().step_by(step).collect();
            let kinds = |quad| {
                prims
                    .iter()
                    .any(|p| matches!(p, Primitive::Quad(_)) == quad)
            };
            assert!(kinds(true) && kinds(false));
            let flat = FlatFaces::new(&prims).expect("flat");
            for eight in eights(&rays(&prims, at, size, &mut r)) {
                let near = flat.nearest8(&eight, 0.0, f32::INFINITY);
                let mut hits = Hits8::default();
                if !flat.hits8(&eight, &near, &mut hits) {
                    return; // a CPU without AVX2 builds hits one at a time
                }
                for (l, ray) in eight.iter().enumerate() {
                    let Some((slot, c)) = near.crossing(l) else {
                        continue;
                    };
                    let h = match &prims[slot] {
                        Primitive::Rect(rect) => rect.surface(ray, &c),
                        Primitive::Quad(quad) => quad.surface(&c),
                        _ => unreachable!("a flat set holds rects and parallelograms"),
                    };
                    let want = facing(h, h.normal, ray.dir, MaterialId(0), LightId::NONE);
                    let lane = |v: &[[f32; LANES]; 3]| Vec3::new(v[0][l], v[1][l], v[2][l]);
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(lane(&hits.point)), bits(want.point), "{ray:?}");
                    assert_eq!(bits(lane(&hits.error)), bits(want.error), "{ray:?}");
                    assert_eq!(bits(lane(&hits.normal)), bits(want.geo_normal), "{ray:?}");
                    assert_eq!(bits(want.normal), bits(want.geo_normal));
                    built[kind] += 1;
                }
            }
        }
        assert!(built.iter().all(|&b| b > 1_000), "{built:?} hits");
    }

    #[test]
    fn a_sets_hits_side_by_side_are_its_hits_one_at_a_time() {
        use crate::geometry::emitter::LightId;
        use crate::geometry::primitives::PrimitiveSet;
        use crate::scene::MaterialId;
        let mut r = numbers(31);
        let prims = faces(Vec3::new(7.0, -3.0, 40.0), 5.0, &mut r);
        let rays = rays(&prims, Vec3::new(7.0, -3.0, 40.0), 5.0, &mut r);
        let set = PrimitiveSet::new(
            prims
                .into_iter()
                .map(|p| (p, MaterialId(0), LightId::NONE))
                .collect(),
        );
        let mut compared = 0;
        for eight in eights(&rays) {
            let near = set
                .flat_crossings8(&eight, 0.0, f32::INFINITY)
                .expect("a flat set");
            let (mut side, mut each) = (Hits8::default(), Hits8::default());
            set.flat_hits8(&eight, &near, &mut side);
            set.flat_hits_each(&eight, &near, &mut each);
            for l in (0..LANES).filter(|&l| near.crossing(l).is_some()) {
                for a in 0..3 {
                    let bits = |h: &Hits8| {
                        [h.point[a][l], h.error[a][l], h.normal[a][l]].map(f32::to_bits)
                    };
                    assert_eq!(bits(&side), bits(&each), "{:?}", eight[l]);
                }
                compared += 1;
            }
        }
        assert!(compared > 2_000, "{compared} hits");
    }

    #[test]
    fn only_small_sets_of_flat_faces_are_packed() {
        let mut r = numbers(5);
        let prims = faces(Vec3::ZERO, 1.0, &mut r);
        assert!(FlatFaces::new(&prims).is_some());
        assert!(FlatFaces::new(&[]).is_none());
        let many: Vec<Primitive> = prims.iter().cycle().take(MAX_FACES + 1).copied().collect();
        assert!(FlatFaces::new(&many).is_none());
        let sphere = Primitive::Sphere(crate::geometry::shapes::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        });
        assert!(FlatFaces::new(&[prims[0], sphere]).is_none());
    }
}
