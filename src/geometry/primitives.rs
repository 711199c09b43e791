//! Many analytic primitives (spheres, turned spheres, rects, parallelograms,
//! boxes, triangles) with their materials and light ids in flat arrays under
//! one BVH. A walk tests candidates for their [`Crossing`] only and builds
//! the surface data of the nearest one; up to eight rays may walk it
//! together ([`PrimitiveSet::first_hits`]). A set of a few primitives is
//! tested in turn instead, a set of flat faces in vector passes.

use super::bake::Baked;
use super::bvh::{bits, Leaves};
use super::emitter::LightId;
use super::flat::{FlatFaces, Hits8, Nearest8, MAX_FACES};
use super::hit::facing_flat_with;
use super::leaf::{slots, Packs, SphereLeaf};
use super::primitive::Primitive;
use super::shapes::{Crossing, ShapeHit, Sphere};
use super::sphere_rays::SphereRays;
use super::{Aabb, Bvh, Hit, Ray};
use crate::scene::MaterialId;
use crate::simd::LANES;

/// Primitives in BVH leaf order, each with its material and light id.
#[derive(Debug, Default)]
pub struct PrimitiveSet {
    prims: Vec<Primitive>,
    materials: Vec<MaterialId>,
    /// Empty when no primitive emits.
    lights: Vec<LightId>,
    bvh: Bvh,
    /// The leaves of two or more spheres, packed for a four-lane test.
    spheres: Packs<SphereLeaf>,
    /// Rects and parallelograms only, more than [`FEW_PRIMITIVES`] and at
    /// most `flat::MAX_FACES`: tested all at once, eight or sixteen lanes
    /// at a time, instead of walked. The BVH is built all the same:
    /// its leaf order numbers the slots, which break ties between faces at
    /// one distance, and it holds the bounds.
    ///
    /// A set of at most [`FEW_PRIMITIVES`] axis-aligned rects (a floor and
    /// a lamp) has the same passes, for callers that test eight rays at
    /// once: a rect's lane is `Rect::crossing` bit for bit, so the passes
    /// find what asking the rects in turn finds. One ray still asks them
    /// in turn.
    flat: Option<FlatFaces>,
}

/// Sets of at most this many primitives are tested in turn, with neither a
/// walk nor flat-face passes. A floor and a lamp beside a mesh are one
/// rect and one parallelogram: two sixteen-lane passes with a face each,
/// which took 1.06–1.10× the time of two scalar tests over the whole
/// render of the bunny stage. At four faces the scalar tests were 1.03×
/// as fast, at six and eight as fast as the passes.
const FEW_PRIMITIVES: usize = 4;

/// Whether a set of `count` flat faces (`rects`: all axis-aligned rects)
/// finds its crossings in the faces' passes rather than in turn: more than
/// [`FEW_PRIMITIVES`], or a few rects. [`FlatFaces::new`] then takes at
/// most `flat::MAX_FACES`.
fn in_passes(count: usize, rects: bool) -> bool {
    count > FEW_PRIMITIVES || rects
}

/// Whether every primitive is an axis-aligned rect.
fn all_rects<'a>(prims: impl IntoIterator<Item = &'a Primitive>) -> bool {
    prims.into_iter().all(|p| matches!(p, Primitive::Rect(_)))
}

/// `items` cut into flat faces (rects and parallelograms) and the rest, in
/// their order, when there are both, no fewer faces than the rest, and the
/// faces alone make a set whose crossings are found eight rays at a pass
/// ([`PrimitiveSet::side_by_side`]): a glass ball among walls, or lamps
/// beside boxes, are then two parts, the walls' crossings found side by
/// side rather than by a walk of one tree over both kinds. A floor under
/// many balls stays in their set, whose packets walk it well
/// (`docs/performance.md`, "Flat faces apart from the rest").
pub fn faces_apart(items: &[Baked]) -> Option<(Vec<Baked>, Vec<Baked>)> {
    let face = |p: &Primitive| matches!(p, Primitive::Rect(_) | Primitive::Quad(_));
    let (faces, rest): (Vec<Baked>, Vec<Baked>) = items.iter().partition(|(p, _, _)| face(p));
    let rects = all_rects(faces.iter().map(|(p, _, _)| p));
    let side_by_side = faces.len() <= MAX_FACES && in_passes(faces.len(), rects);
    let split = !rest.is_empty() && faces.len() >= rest.len() && side_by_side;
    split.then_some((faces, rest))
}

impl PrimitiveSet {
    pub fn new(items: Vec<(Primitive, MaterialId, LightId)>) -> PrimitiveSet {
        let bounds: Vec<Aabb> = items.iter().map(|(p, _, _)| p.bounds()).collect();
        // Spheres get full leaves, packed; other primitives keep the scalar
        // tree's leaves (whose order decides ties between coplanar faces).
        // Pricing every leaf as packed would make the boxes' leaves full too
        // and cost the book-2 scene 27 % more instructions; pricing only the
        // leaves of spheres as packed saves it 1.3 %.
        let spheres: Vec<bool> = items.iter().map(|(p, _, _)| p.sphere().is_some()).collect();
        let leaves = if spheres.iter().all(|&s| s) {
            Leaves::Packed
        } else {
            Leaves::PackedWhere(&spheres)
        };
        let (bvh, order) = Bvh::build_leaves(&bounds, leaves);
        let (prims, materials): (Vec<Primitive>, Vec<MaterialId>) = order
            .iter()
            .map(|&i| (items[i as usize].0, items[i as usize].1))
            .unzip();
        let mut lights: Vec<LightId> = order.iter().map(|&i| items[i as usize].2).collect();
        if lights.iter().all(|l| *l == LightId::NONE) {
            lights = Vec::new();
        }
        let spheres = Packs::new(&bvh, prims.len(), |first, count| {
            let leaf: Option<Vec<Sphere>> = prims[first..first + count]
                .iter()
                .map(Primitive::sphere)
                .collect();
            leaf.filter(|l| l.len() > 1)
                .map(|l: Vec<Sphere>| SphereLeaf::new(&l))
        });
        let flat = if in_passes(prims.len(), all_rects(&prims)) {
            FlatFaces::new(&prims)
        } else {
            None
        };
        PrimitiveSet {
            prims,
            materials,
            lights,
            bvh,
            spheres,
            flat,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// Whether the set holds at most [`FEW_PRIMITIVES`], tested in turn,
    /// one after another.
    #[inline(always)]
    fn few(&self) -> bool {
        self.prims.len() <= FEW_PRIMITIVES
    }

    /// The nearest hit in `(t_min, t_max)` and the slot of its primitive,
    /// by the walk of the tree (built for flat sets too, so right for any
    /// set). The world asks [`PrimitiveSet::intersect_facing`], which takes a
    /// flat set's eight-lane passes instead.
    #[inline]
    pub(super) fn intersect_slot(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(ShapeHit, usize)> {
        let mut best = None;
        // The leaf visit is inlined into the walk rather than called once per
        // leaf: with the eight-wide walk, renders of the Cornell box and the
        // spheres take 3 % and 6 % fewer instructions and 3.5 % and 6 % less
        // CPU time than with a call.
        self.bvh.traverse_leaves(
            ray,
            t_max,
            #[inline(always)]
            |first, count, mut t_max| {
                let mut found = None;
                let mut keep = |slot: usize, c: Crossing, t_max: &mut f32| {
                    best = Some((c, slot));
                    (*t_max, found) = (c.t, Some(c.t));
                };
                if let Some(leaf) = self.spheres.get(first) {
                    let lanes = leaf.candidates(ray);
                    if lanes != 0 {
                        let roots = leaf.roots(ray);
                        for slot in slots(first, lanes) {
                            let c = roots[slot - first].and_then(|r| r.crossing(t_min, t_max));
                            if let Some(c) = c {
                                keep(slot, c, &mut t_max);
                            }
                        }
                    }
                } else {
                    for slot in first..first + count {
                        if let Some(c) = self.prims[slot].crossing(ray, t_min, t_max) {
                            keep(slot, c, &mut t_max);
                        }
                    }
                }
                found
            },
        );
        let (c, slot) = best?;
        Some((self.prims[slot].surface(ray, &c), slot))
    }

    /// The nearest hit in `(t_min, t_max)` as the [`Hit`] facing the ray,
    /// what the world asks a set for. A flat set builds it in
    /// [`PrimitiveSet::flat_hit`]. Inlined where the world asks, so that a
    /// flat set's hit is written once, into the caller's result.
    #[inline(always)]
    pub fn intersect_facing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        if self.few() {
            return self.in_turn(ray, t_min, t_max);
        }
        if let Some(flat) = &self.flat {
            return self.flat_hit(flat, ray, t_min, t_max);
        }
        let (h, slot) = self.intersect_slot(ray, t_min, t_max)?;
        let (material, light) = self.ids(slot);
        Some(self.faced(slot, h, ray.dir, material, light))
    }

    /// [`PrimitiveSet::intersect_facing`] of a set of at most
    /// [`FEW_PRIMITIVES`]: every primitive's crossing in slot order, the
    /// first of equal distances kept (as [`PrimitiveSet::first_hits`] keeps
    /// the lowest slot). Kept out of line, as [`PrimitiveSet::flat_hit`].
    #[inline(never)]
    fn in_turn(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let mut best = None;
        let mut t_max = t_max;
        for (slot, p) in self.prims.iter().enumerate() {
            if let Some(c) = p.crossing(ray, t_min, t_max) {
                t_max = c.t;
                best = Some((slot, c));
            }
        }
        let (slot, c) = best?;
        let (h, material, light) = self.hit(slot, ray, &c);
        Some(self.faced(slot, h, ray.dir, material, light))
    }

    /// [`facing_flat_with`] the tangents of slot `slot`'s primitive.
    #[inline(always)]
    fn faced(
        &self,
        slot: usize,
        h: ShapeHit,
        dir: glam::Vec3,
        material: MaterialId,
        light: LightId,
    ) -> Hit {
        facing_flat_with(h, dir, material, light, |h| self.prims[slot].tangents(h))
    }

    /// The nearest hits in `(t_min, ∞)` of up to [`LANES`] rays that cross
    /// much the same boxes (a pixel's camera rays), facing their rays,
    /// written into `out` (one per ray). They are found in one walk of the
    /// packet ([`Bvh::traverse_packet`]; the tree of a flat set serves too). A
    /// ray's hit does not depend on the rays beside it nor on the order the
    /// walk shows it the leaves: it is the crossing with the least `t`,
    /// ties going to the lowest slot (the one-ray walk keeps the first it
    /// finds, so the two part only where two surfaces meet a ray at one
    /// `t`). Every crossing is found out to infinity and compared after.
    pub fn first_hits(&self, rays: &[Ray], t_min: f32, out: &mut [Option<Hit>]) {
        let mut t_max = [f32::INFINITY; LANES];
        let mut best: [Option<(Crossing, usize)>; LANES] = [None; LANES];
        let mut keep = |k: usize, slot: usize, c: Crossing, t_max: &mut [f32; LANES]| {
            // Below the best (t, slot) so far; never a crossing at infinity.
            let closer =
                c.t < t_max[k] || (c.t == t_max[k] && best[k].is_some_and(|(_, s)| slot < s));
            if closer {
                best[k] = Some((c, slot));
                t_max[k] = c.t;
            }
        };
        let mut sphere_rays = None;
        self.bvh.traverse_packet(
            rays,
            &mut t_max,
            #[inline(always)]
            |first, count, mask, t_max| {
                if let Some(leaf) = self.spheres.get(first) {
                    if mask.count_ones() as usize > count {
                        // More rays than spheres: a pass per sphere.
                        // Set up at the first such leaf. Written so: with
                        // `get_or_insert_with` it stayed a call, and with
                        // `Option::insert` the spheres under a sky took
                        // 3.3 M more instructions in this walk.
                        if sphere_rays.is_none() {
                            sphere_rays = Some(SphereRays::new(rays));
                        }
                        let Some(lanes) = &sphere_rays else { return };
                        for i in 0..count {
                            let (center, radius) = leaf.sphere(i);
                            let kept = lanes.candidates(center, radius) & mask;
                            if kept == 0 {
                                continue;
                            }
                            let (found, t, root) = lanes.crossings(center, radius, t_min);
                            for k in bits(found & kept) {
                                let data = glam::Vec3::new(root[k], 0.0, 0.0);
                                keep(k, first + i, Crossing { t: t[k], data }, t_max);
                            }
                        }
                        return;
                    }
                    for k in bits(mask) {
                        let ray = &rays[k];
                        let lanes = leaf.candidates(ray);
                        if lanes == 0 {
                            continue;
                        }
                        let (found, t, root) = leaf.crossings(ray, t_min);
                        for slot in slots(first, lanes & found) {
                            let i = slot - first;
                            let data = glam::Vec3::new(root[i], 0.0, 0.0);
                            keep(k, slot, Crossing { t: t[i], data }, t_max);
                        }
                    }
                } else {
                    for k in bits(mask) {
                        for slot in first..first + count {
                            let c = self.prims[slot].crossing(&rays[k], t_min, f32::INFINITY);
                            if let Some(c) = c {
                                keep(k, slot, c, t_max);
                            }
                        }
                    }
                }
            },
        );
        // `best` by reference: moved into the iterator, it was copied first
        // (a call to memmove), and each crossing read back from the copy
        // waited on its stores.
        for ((ray, hit), found) in rays.iter().zip(out.iter_mut()).zip(&best) {
            *hit = found.map(|(c, slot)| {
                // A sphere's surface built in its own arm: through the
                // shared match of `Primitive::surface`, each shape wrote
                // its hit to one stack slot a field at a time, and reading
                // it back waited on those stores.
                let (h, material, light) = match &self.prims[slot] {
                    Primitive::Sphere(sphere) => {
                        let (material, light) = self.ids(slot);
                        (sphere.surface(ray, &c), material, light)
                    }
                    _ => self.hit(slot, ray, &c),
                };
                self.faced(slot, h, ray.dir, material, light)
            });
        }
    }

    /// [`PrimitiveSet::intersect_facing`] of a flat set, built in the one
    /// function that writes the caller's result. Kept out of line: inlined,
    /// it makes the walk's own code too large to inline its tests, and the
    /// random spheres take 3 % more instructions. Returned through two
    /// layers (the set's hit, then the facing one), the hit is copied field
    /// by field between stack slots: the Cornell box takes 2 % more
    /// instructions and 3 % more time.
    #[inline(never)]
    fn flat_hit(&self, flat: &FlatFaces, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let (slot, c) = flat.nearest(ray, t_min, t_max)?;
        Some(self.flat_hit_at(slot, ray, &c))
    }

    /// Whether the set is tested in flat-face passes.
    pub fn is_flat(&self) -> bool {
        !self.few() && self.flat.is_some()
    }

    /// Whether the set's crossings can be found by
    /// [`PrimitiveSet::flat_crossings8`]: a flat set, or a few rects.
    pub fn side_by_side(&self) -> bool {
        self.flat.is_some()
    }

    /// The nearest crossing in `(t_min, t_max)` and its slot of a set
    /// [`PrimitiveSet::side_by_side`] says yes for (none for another).
    #[inline]
    pub fn flat_crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(usize, Crossing)> {
        self.flat.as_ref()?.nearest(ray, t_min, t_max)
    }

    /// [`PrimitiveSet::flat_crossing`] for eight rays at once.
    #[inline]
    pub fn flat_crossings8(&self, rays: &[Ray; LANES], t_min: f32, t_max: f32) -> Option<Nearest8> {
        Some(self.flat.as_ref()?.nearest8(rays, t_min, t_max))
    }

    /// The hits of eight rays at crossings `near` that
    /// [`PrimitiveSet::flat_crossings8`] gave, written into `out`:
    /// [`PrimitiveSet::flat_hit_at`]'s points, error bounds and normals,
    /// lane by lane (all eight at once where the CPU has AVX2, else a lane
    /// at a time). A set that
    /// [`PrimitiveSet::side_by_side`] says no for writes nothing.
    #[inline]
    pub fn flat_hits8(&self, rays: &[Ray; LANES], near: &Nearest8, out: &mut Hits8) {
        let Some(flat) = self.flat.as_ref() else {
            return;
        };
        if !flat.hits8(rays, near, out) {
            self.flat_hits_each(rays, near, out);
        }
    }

    /// [`PrimitiveSet::flat_hits8`] a lane at a time (CPUs without AVX2;
    /// kept out of the callers' loops).
    #[cold]
    #[inline(never)]
    pub(super) fn flat_hits_each(&self, rays: &[Ray; LANES], near: &Nearest8, out: &mut Hits8) {
        for (l, ray) in rays.iter().enumerate() {
            let Some((slot, c)) = near.crossing(l) else {
                continue;
            };
            let h = self.flat_hit_at(slot, ray, &c);
            for a in 0..3 {
                out.point[a][l] = h.point[a];
                out.error[a][l] = h.error[a];
                out.normal[a][l] = h.geo_normal[a];
            }
        }
    }

    /// The hit facing `ray` at a crossing `c` of slot `slot` that
    /// [`PrimitiveSet::flat_crossing`] gave: what
    /// [`PrimitiveSet::intersect_facing`] returns.
    #[inline(always)]
    pub fn flat_hit_at(&self, slot: usize, ray: &Ray, c: &Crossing) -> Hit {
        let h = self.flat_surface(slot, ray, c);
        let (material, light) = self.ids(slot);
        self.faced(slot, h, ray.dir, material, light)
    }

    /// The surface at crossing `c` of a flat set's slot `slot`: the two
    /// shapes such a set holds are built here, inlined, rather than called
    /// through `Primitive::surface`, whose hit comes back in memory (0.7 %
    /// fewer instructions, faster in 27 of 32 timed runs).
    #[inline(always)]
    pub fn flat_surface(&self, slot: usize, ray: &Ray, c: &Crossing) -> ShapeHit {
        match &self.prims[slot] {
            Primitive::Rect(r) => r.surface(ray, c),
            Primitive::Quad(q) => q.surface(c),
            p => p.surface(ray, c),
        }
    }

    /// The hit at crossing `c` of slot `slot` with its material and light id.
    #[inline(always)]
    fn hit(&self, slot: usize, ray: &Ray, c: &Crossing) -> (ShapeHit, MaterialId, LightId) {
        let (material, light) = self.ids(slot);
        (self.prims[slot].surface(ray, c), material, light)
    }

    /// Slot `slot`'s material and light id.
    #[inline(always)]
    pub fn ids(&self, slot: usize) -> (MaterialId, LightId) {
        (self.materials[slot], self.light(slot))
    }

    /// Slot `slot`'s light id.
    #[inline(always)]
    fn light(&self, slot: usize) -> LightId {
        self.lights.get(slot).copied().unwrap_or(LightId::NONE)
    }

    /// Whether any primitive but emitter `except` (the light a shadow
    /// segment ends on, or `NONE`) is hit with `t` in `(t_min, t_max)`.
    /// Packed sphere leaves and flat faces test all their primitives: the
    /// comparisons cost more there than the one test they would spare
    /// (`docs/performance.md`, the tried table).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, except: LightId) -> bool {
        let tested = |slot: usize| self.light(slot).blocks_beside(except);
        if self.few() {
            return (0..self.prims.len()).any(|slot| {
                tested(slot) && self.prims[slot].crossing(ray, t_min, t_max).is_some()
            });
        }
        if let Some(flat) = &self.flat {
            return flat.occluded(ray, t_min, t_max);
        }
        // Spheres a packed leaf at a time, as `intersect_slot` tests them.
        self.bvh.traverse_any_leaves(
            ray,
            t_max,
            #[inline(always)]
            |first, count, t_max| {
                let Some(leaf) = self.spheres.get(first) else {
                    return (first..first + count).any(|slot| {
                        tested(slot) && self.prims[slot].crossing(ray, t_min, t_max).is_some()
                    });
                };
                let lanes = leaf.candidates(ray);
                if lanes == 0 {
                    return false;
                }
                let roots = leaf.roots(ray);
                bits(lanes).any(|lane| roots[lane].and_then(|r| r.crossing(t_min, t_max)).is_some())
            },
        )
    }

    /// Whether the set holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::geometry::shapes::Triangle;
    use crate::sampling::rng::numbers;

    /// A hit's bits (uv aside, which only a texture reads): t, point,
    /// error, normal, side and material.
    type Bits = (u32, [[u32; 3]; 3], bool, u32);

    fn bits(h: &Option<Hit>) -> Option<Bits> {
        let v = |v: Vec3| v.to_array().map(f32::to_bits);
        h.map(|h| {
            let vectors = [v(h.point), v(h.error), v(h.normal)];
            (h.t.to_bits(), vectors, h.front_face, h.material.0)
        })
    }

    /// A packet's hits are each ray's least (t, slot) crossing, the same
    /// traced alone or beside any other rays, and the one-ray walk's hit
    /// where no two surfaces meet the ray at one `t`; a shadow ray is
    /// blocked exactly where one of the primitives crosses it. The set holds random
    /// spheres (some twice, at one place, with other materials: ties),
    /// triangles among them, and a ground sphere far larger than the rest.
    #[test]
    fn a_packets_hits_are_each_rays_own_whatever_its_packet() {
        let mut r = numbers(21);
        let mut items = Vec::new();
        let id = |items: &Vec<_>| MaterialId(items.len() as u32);
        items.push((
            Primitive::Sphere(Sphere {
                center: Vec3::new(0.0, -1000.0, 0.0),
                radius: 1000.0,
            }),
            MaterialId(0),
            LightId::NONE,
        ));
        for k in 0..300 {
            let center = Vec3::new(r() * 20.0 - 10.0, r() * 2.0, r() * 20.0 - 10.0);
            let radius = 0.05 + r() * 0.5;
            let s = Primitive::Sphere(Sphere { center, radius });
            items.push((s, id(&items), LightId::NONE));
            if k % 10 == 0 {
                items.push((s, id(&items), LightId::NONE));
            }
            if k % 7 == 0 {
                let v = [0, 1, 2].map(|_| center + Vec3::new(r(), r(), r()) - 0.5);
                items.push((
                    Primitive::Triangle(Triangle { v }),
                    id(&items),
                    LightId::NONE,
                ));
            }
        }
        let set = PrimitiveSet::new(items);
        assert!(!set.is_flat());
        let (mut ties, mut hits, mut shadowed) = (0, 0, 0);
        for p in 0..400 {
            let n = 1 + p % LANES;
            let from = Vec3::new(r() * 30.0 - 15.0, 0.5 + r() * 4.0, r() * 30.0 - 15.0);
            let to = Vec3::new(r() * 20.0 - 10.0, r() * 2.0 - 0.5, r() * 20.0 - 10.0);
            let spread = if p % 3 == 0 { 10.0 } else { 0.3 };
            let rays: Vec<Ray> = (0..n)
                .map(|_| {
                    let at = to + Vec3::new(r(), r(), r()) * spread;
                    Ray::new(from, (at - from).normalize(), 0.0)
                })
                .collect();
            let mut packet = [None; LANES];
            set.first_hits(&rays, 0.0, &mut packet[..n]);
            for (k, ray) in rays.iter().enumerate() {
                let mut alone = [None];
                set.first_hits(std::slice::from_ref(ray), 0.0, &mut alone);
                assert_eq!(bits(&packet[k]), bits(&alone[0]), "packet {p}, ray {k}");
                // By brute force: the least (t, slot).
                let least = (0..set.prims.len())
                    .filter_map(|s| Some((set.prims[s].crossing(ray, 0.0, f32::INFINITY)?.t, s)))
                    .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
                let found = packet[k].map(|h| (h.t, h.material));
                assert_eq!(found, least.map(|(t, s)| (t, set.materials[s])));
                let tied = least.is_some_and(|(t, s)| {
                    (0..set.prims.len()).any(|o| {
                        o != s
                            && set.prims[o].crossing(ray, 0.0, f32::INFINITY).map(|c| c.t)
                                == Some(t)
                    })
                });
                if tied {
                    ties += 1;
                } else {
                    let one = set.intersect_facing(ray, 0.0, f32::INFINITY);
                    assert_eq!(bits(&packet[k]), bits(&one), "packet {p}, ray {k}");
                }
                hits += usize::from(packet[k].is_some());
                // A shadow ray ending just before, at or after the hit, or
                // anywhere: blocked as the primitives one by one say (the
                // spheres' packed leaves tested four at once).
                let t = least.map_or(5.0, |(t, _)| t);
                for end in [t * 0.999, t, t * 1.001, 30.0 * r()] {
                    let blocked = (0..set.prims.len())
                        .any(|s| set.prims[s].crossing(ray, 0.0, end).is_some());
                    assert_eq!(
                        set.occluded(ray, 0.0, end, LightId::NONE),
                        blocked,
                        "{ray:?} to {end}"
                    );
                    shadowed += usize::from(blocked);
                }
            }
        }
        assert!(ties > 20 && hits > 1000, "{ties} ties, {hits} hits");
        assert!(shadowed > 1000, "{shadowed} shadow rays blocked");
    }

    /// A set of a few primitives, tested in turn, finds what a packet finds:
    /// each ray's least (t, slot), the lower slot where two faces meet the
    /// ray at one distance (a lamp lying on its floor), with the same bits;
    /// and a shadow ray is blocked exactly when a hit is found before its
    /// end. Sets of two to four rects, parallelograms, spheres and
    /// triangles, each ray traced alone and in packets of up to eight.
    #[test]
    fn a_few_primitives_in_turn_find_each_rays_least_crossing() {
        use crate::geometry::shapes::{Quad, Rect};
        use crate::scene::object::RectPlane;
        let mut r = numbers(8);
        let floor = Primitive::Rect(Rect::new(RectPlane::Xz, (-5.0, 5.0), (-5.0, 5.0), 0.0));
        let lamp = Primitive::Rect(Rect::new(RectPlane::Xz, (-1.0, 1.0), (-1.0, 1.0), 0.0));
        let tilted = Quad::new(
            Vec3::new(-2.0, 0.5, -2.0),
            Vec3::new(3.0, 0.4, 0.2),
            Vec3::new(0.1, 1.5, 2.5),
            Vec3::Y,
        )
        .map(Primitive::Quad)
        .expect("a parallelogram");
        let ball = Primitive::Sphere(Sphere {
            center: Vec3::new(1.0, 0.8, 0.5),
            radius: 0.7,
        });
        let v = [
            Vec3::new(-1.5, 0.0, 1.0),
            Vec3::new(0.5, 2.0, -1.0),
            Vec3::new(2.0, 0.3, 1.5),
        ];
        let triangle = Primitive::Triangle(Triangle { v });
        let ground = Primitive::Sphere(Sphere {
            center: Vec3::new(0.0, -1000.0, 0.0),
            radius: 1000.0,
        });
        let other = Primitive::Sphere(Sphere {
            center: Vec3::new(0.2, 1.0, -0.5),
            radius: 0.6,
        });
        let sets: [&[Primitive]; 6] = [
            &[floor, lamp],
            &[lamp, floor, tilted],
            &[floor, tilted, ball, triangle],
            &[ball, triangle],
            &[ground, ball, other],
            &[ball, other],
        ];
        let (mut ties, mut hits) = (0, 0);
        for prims in sets {
            let items = prims.iter().enumerate();
            let items = items.map(|(k, p)| (*p, MaterialId(k as u32), LightId::NONE));
            let set = PrimitiveSet::new(items.collect());
            assert!(set.few() && !set.is_flat());
            let mut rays = Vec::new();
            for k in 0..3000 {
                let from = Vec3::new(r() * 8.0 - 4.0, r() * 4.0 - 0.5, r() * 8.0 - 4.0);
                let to = Vec3::new(r() * 6.0 - 3.0, r() * 2.0 - 0.5, r() * 6.0 - 3.0);
                let ray = Ray::new(from, to - from, 0.0);
                let one = set.intersect_facing(&ray, 0.0, f32::INFINITY);
                let mut packet = [None];
                set.first_hits(std::slice::from_ref(&ray), 0.0, &mut packet);
                assert_eq!(bits(&one), bits(&packet[0]), "{ray:?}");
                // Packets of one to eight rays (more rays than spheres take
                // a pass per sphere) find each ray's own hit.
                rays.push((ray, one));
                if rays.len() > (k / LANES) % LANES {
                    let mut packet = [None; LANES];
                    let only: Vec<Ray> = rays.iter().map(|(ray, _)| *ray).collect();
                    set.first_hits(&only, 0.0, &mut packet[..rays.len()]);
                    for ((ray, one), hit) in rays.drain(..).zip(packet) {
                        assert_eq!(bits(&one), bits(&hit), "{ray:?} in a packet");
                    }
                }
                let crossings: Vec<f32> = (0..set.prims.len())
                    .filter_map(|s| Some(set.prims[s].crossing(&ray, 0.0, f32::INFINITY)?.t))
                    .collect();
                ties += usize::from(
                    one.is_some_and(|h| crossings.iter().filter(|&&t| t == h.t).count() > 1),
                );
                hits += usize::from(one.is_some());
                for end in [0.5, 1.0, 3.0] {
                    let blocked = one.is_some_and(|h| h.t < end);
                    assert_eq!(
                        set.occluded(&ray, 0.0, end, LightId::NONE),
                        blocked,
                        "{ray:?} to {end}"
                    );
                }
            }
        }
        assert!(ties > 100 && hits > 5000, "{ties} ties, {hits} hits");
    }

    /// Faces go apart from the rest only where they make a side-by-side
    /// set and are no fewer than the rest; a world cut so finds the hits of
    /// the one set it replaces: t, normal, side and material bit for bit,
    /// the point within both error bounds.
    #[test]
    fn faces_apart_from_a_ball_find_the_one_sets_hits() {
        use crate::geometry::group::Group;
        use crate::geometry::instance::{Instance, Placement};
        use crate::geometry::object::Geometry;
        use crate::geometry::segments::MediumSegments;
        use crate::geometry::shapes::{Quad, Rect};
        use crate::scene::object::RectPlane;
        use std::sync::Arc;

        let rect = |plane, a, b, k, m| {
            let p = Primitive::Rect(Rect::new(plane, a, b, k));
            (p, MaterialId(m), LightId::NONE)
        };
        let ball = |c: Vec3, r: f32, m| {
            let p = Primitive::Sphere(Sphere {
                center: c,
                radius: r,
            });
            (p, MaterialId(m), LightId::NONE)
        };
        let quad = |c: Vec3, u: Vec3, v: Vec3, m| {
            let q = Quad::new(c, u, v, u.cross(v)).expect("a parallelogram");
            (Primitive::Quad(q), MaterialId(m), LightId::NONE)
        };
        // A floor, a back wall, a lamp and a turned box's four sides (seven
        // faces), a glass ball and a small lamp ball.
        let mut items = vec![
            rect(RectPlane::Xz, (-6.0, 6.0), (-6.0, 6.0), 0.0, 0),
            rect(RectPlane::Xy, (-6.0, 6.0), (0.0, 6.0), -3.0, 1),
            rect(RectPlane::Xz, (-0.3, 0.3), (-0.3, 0.3), 4.0, 2),
            ball(Vec3::new(-1.4, 0.8, 0.0), 0.8, 3),
        ];
        let (u, v, h) = (Vec3::new(1.0, 0.0, 0.4), Vec3::new(-0.4, 0.0, 1.0), Vec3::Y);
        let corner = Vec3::new(0.6, 0.0, -0.6);
        for (k, (c, e)) in [
            (corner, u),
            (corner + u, v),
            (corner + u + v, -u),
            (corner + v, -v),
        ]
        .into_iter()
        .enumerate()
        {
            items.push(quad(c, e, h, 4 + k as u32));
        }
        items.push(ball(Vec3::new(2.0, 2.5, 1.0), 0.2, 8));
        let (faces, rest) = faces_apart(&items).expect("seven faces beside two balls");
        assert_eq!((faces.len(), rest.len()), (7, 2));
        let parts = |set: Vec<Baked>| {
            Instance::new(
                Arc::new(Geometry::Primitives(PrimitiveSet::new(set))),
                Placement::Identity,
            )
        };
        let faces_set = PrimitiveSet::new(faces.clone());
        assert!(faces_set.side_by_side());
        let apart = Group::new(vec![parts(faces), parts(rest)]);
        let whole = PrimitiveSet::new(items.clone());
        let mut media = MediumSegments::default();
        let mut r = numbers(5);
        let mut seen = [0; 9];
        for _ in 0..20_000 {
            let from = Vec3::new(r() * 10.0 - 5.0, r() * 5.0 + 0.1, r() * 8.0 - 2.0);
            let to = Vec3::new(r() * 6.0 - 3.0, r() * 3.0, r() * 4.0 - 2.0);
            let ray = Ray::new(from, to - from, 0.0);
            let want = whole.intersect_facing(&ray, 0.0, f32::INFINITY);
            let got = apart.intersect(&ray, 0.0, f32::INFINITY, &mut media);
            let (Some(want), Some(got)) = (want, got) else {
                assert_eq!(got.is_some(), want.is_some(), "{ray:?}");
                continue;
            };
            // The faces' passes may round a parallelogram's point apart
            // from the scalar test by an ulp, within both error bounds.
            let mut aligned = want;
            (aligned.point, aligned.error) = (got.point, got.error);
            assert_eq!(bits(&Some(aligned)), bits(&Some(got)), "{ray:?}");
            let apart_by = (got.point - want.point).abs();
            assert!(apart_by.cmple(got.error.min(want.error)).all(), "{ray:?}");
            seen[want.material.index()] += 1;
        }
        assert!(seen.iter().all(|&n| n > 20), "{seen:?}");

        // Not cut: a floor under many balls, faces beyond one pass, faces
        // alone, and a few parallelograms (tested in turn, not side by side).
        let mut grid = vec![rect(RectPlane::Xz, (-6.0, 6.0), (-6.0, 6.0), 0.0, 0)];
        grid.extend((0..9).map(|k| ball(Vec3::new(k as f32, 0.5, 0.0), 0.4, 1)));
        assert!(faces_apart(&grid).is_none());
        let mut many: Vec<Baked> = (0..=MAX_FACES)
            .map(|k| rect(RectPlane::Xy, (0.0, 1.0), (0.0, 1.0), -(k as f32), 0))
            .collect();
        assert!(faces_apart(&many).is_none());
        many.truncate(MAX_FACES);
        many.push(ball(Vec3::ZERO, 1.0, 1));
        assert!(faces_apart(&many).is_some());
        assert!(faces_apart(&items[..3]).is_none());
        // A floor beside one lamp ball: as many faces as the rest.
        assert!(faces_apart(&[items[0], items[3]]).is_some());
        let sides = [items[4], items[5], ball(Vec3::ZERO, 1.0, 1)];
        assert!(faces_apart(&sides).is_none());
    }
}
