//! A group of instances: the surfaces under one BVH (a few asked in turn
//! instead), with a short list of the unbounded ones (infinite planes)
//! tested after it, and the media, asked for their stretches last, up to
//! the nearest surface found (a few in turn, more through a BVH of their
//! own).
//!
//! It imports [`super::object`], which imports it back: a group is one
//! kind of [`Geometry`] and holds geometry (see that module's header).

use super::emitter::LightId;
use super::instance::Instance;
use super::object::Geometry;
use super::parts::Parts;
use super::segments::MediumSegments;
use super::{Aabb, Bvh, Hit, Ray};

/// Up to this many media are asked in turn rather than through a BVH: a
/// ball's early miss test costs a few dozen instructions, a walk's set-up
/// and node test over a hundred (with a haze and one ball, the book-2 scene
/// took 3.5 % more instructions through a BVH).
const FEW_MEDIA: usize = 4;

/// Up to this many bounded surfaces (a mesh, the set of a scene's other
/// shapes, a lamp's shade) are asked in turn, each behind its box's test,
/// rather than through the layer's BVH: on a mesh beside a floor and a
/// lamp, the walk over two boxes had cost a third of the mesh's own walk
/// (1.10–1.15× the samples/s asked in turn). With four, six, eight and
/// twelve surfaces (bunnies in a row) asking in turn gave 1.02, 0.99, 1.05
/// and 0.96× the walk's rate (4 rounds each, another job running): no
/// gain to chase past four.
pub(super) const FEW_SURFACES: usize = 4;

/// Instances under one hierarchy.
#[derive(Default)]
pub struct Group {
    surfaces: Layer,
    /// Media placed directly in the group. They stop no ray, so they stay
    /// out of the surfaces' BVH (a haze's ball would hold every ray's first
    /// visit) and see each ray once its nearest surface is known: a stretch
    /// that ends inside a ball then needs no crossing to be solved.
    media: Media,
}

/// A group's media: a few asked in turn, in scene order, or many under a
/// BVH of their own that skips those the ray stops short of.
enum Media {
    Few(Vec<Instance>),
    Many(Layer),
}

impl Default for Media {
    fn default() -> Media {
        Media::Few(Vec::new())
    }
}

impl Media {
    fn new(media: Vec<Instance>) -> Media {
        if media.len() <= FEW_MEDIA {
            Media::Few(media)
        } else {
            Media::Many(Layer::new(media))
        }
    }

    fn bounds(&self) -> Aabb {
        match self {
            Media::Few(list) => list.iter().fold(Aabb::EMPTY, |b, i| b.union(&i.bounds)),
            Media::Many(layer) => layer.bounds(),
        }
    }

    /// Adds the stretches of the ray inside these media, up to `t_max` (a
    /// medium finds no surface, only stretches).
    #[inline(always)]
    fn stretches(&self, ray: &Ray, t_min: f32, t_max: f32, out: &mut MediumSegments) {
        match self {
            Media::Few(list) => {
                for m in list {
                    m.intersect(ray, t_min, t_max, out);
                }
            }
            Media::Many(layer) => layer.stretches(ray, t_min, t_max, out),
        }
    }
}

/// Instances under a BVH, and the unbounded ones beside it.
#[derive(Default)]
struct Layer {
    /// In BVH order.
    bounded: Vec<Instance>,
    unbounded: Vec<Instance>,
    bvh: Bvh,
}

impl Layer {
    fn new(instances: Vec<Instance>) -> Layer {
        let (bounded, unbounded): (Vec<Instance>, Vec<Instance>) =
            instances.into_iter().partition(|i| i.bounds.is_bounded());
        let boxes: Vec<Aabb> = bounded.iter().map(|i| i.bounds).collect();
        let (bvh, order) = Bvh::build(&boxes);
        let bounded = order.iter().map(|&i| bounded[i as usize].clone()).collect();
        Layer {
            bounded,
            unbounded,
            bvh,
        }
    }

    /// Whether the bounded instances are at most [`FEW_SURFACES`]: asked in
    /// turn, in BVH order, rather than walked.
    #[inline(always)]
    fn few(&self) -> bool {
        self.bounded.len() <= FEW_SURFACES
    }

    /// Visits the bounded instances whose boxes the ray enters within
    /// `(0, t_max)`, the nearest `t` found so far narrowing `t_max` as in
    /// [`Bvh::traverse`]: a few in turn, more by the BVH.
    #[inline(always)]
    fn traverse(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut visit: impl FnMut(usize, f32) -> Option<f32>,
    ) {
        if !self.few() {
            return self.bvh.traverse(ray, t_max, visit);
        }
        let inv_dir = ray.dir.recip();
        for (slot, inst) in self.bounded.iter().enumerate() {
            if inst.bounds.entered(ray.origin, inv_dir, t_max) {
                if let Some(t) = visit(slot, t_max) {
                    t_max = t;
                }
            }
        }
    }

    /// Whether `hit` holds for a bounded instance whose box the ray enters
    /// within `(0, t_max)`, as [`Bvh::traverse_any`]: a few in turn, more
    /// by the BVH.
    #[inline(always)]
    fn traverse_any(&self, ray: &Ray, t_max: f32, mut hit: impl FnMut(usize, f32) -> bool) -> bool {
        if !self.few() {
            return self.bvh.traverse_any(ray, t_max, hit);
        }
        let inv_dir = ray.dir.recip();
        self.bounded
            .iter()
            .enumerate()
            .any(|(slot, inst)| inst.bounds.entered(ray.origin, inv_dir, t_max) && hit(slot, t_max))
    }

    fn bounds(&self) -> Aabb {
        self.unbounded
            .iter()
            .fold(self.bvh.bounds(), |b, i| b.union(&i.bounds))
    }

    /// The stretches of the ray inside media under this layer, up to
    /// `t_max`: the BVH skips those the ray stops short of.
    fn stretches(&self, ray: &Ray, t_min: f32, t_max: f32, out: &mut MediumSegments) {
        self.bvh.traverse(ray, t_max, |slot, _| {
            self.bounded[slot].intersect(ray, t_min, t_max, out);
            None
        });
        for m in &self.unbounded {
            m.intersect(ray, t_min, t_max, out);
        }
    }
}

impl Group {
    pub fn new(instances: Vec<Instance>) -> Group {
        let (media, surfaces): (Vec<Instance>, Vec<Instance>) = instances
            .into_iter()
            .filter(|i| !i.bounds.is_empty())
            .partition(|i| matches!(*i.geometry, Geometry::Medium(_)));
        Group {
            surfaces: Layer::new(surfaces),
            media: Media::new(media),
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.surfaces.bounds().union(&self.media.bounds())
    }

    /// The group as [`Parts`] (a few surfaces side by side), when it is
    /// one: no medium, nothing unbounded but planes, and few enough bounded
    /// surfaces to be asked in turn.
    pub fn parts(&self) -> Option<Parts> {
        let s = &self.surfaces;
        let media = !matches!(&self.media, Media::Few(list) if list.is_empty());
        if media || !s.few() {
            return None;
        }
        Parts::of(&s.bounded, &s.unbounded)
    }

    /// Whether any instance but emitter `except` is hit with `t` in
    /// `(t_min, t_max)`; the media's stretches are only looked for when
    /// nothing is.
    #[inline]
    pub fn occluded(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
        except: LightId,
    ) -> bool {
        let s = &self.surfaces;
        let hit = s.traverse_any(ray, t_max, |slot, t_max| {
            s.bounded[slot].occluded(ray, t_min, t_max, media, except)
        }) || s
            .unbounded
            .iter()
            .any(|inst| inst.occluded(ray, t_min, t_max, media, except));
        if !hit {
            self.media.stretches(ray, t_min, t_max, media);
        }
        hit
    }

    #[inline]
    pub fn intersect(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
    ) -> Option<Hit> {
        let s = &self.surfaces;
        let mut best: Option<Hit> = None;
        s.traverse(ray, t_max, |slot, t_max| {
            let h = s.bounded[slot].intersect(ray, t_min, t_max, media)?;
            best = Some(h);
            Some(h.t)
        });
        let mut t_max = best.map_or(t_max, |h| h.t);
        for inst in &s.unbounded {
            if let Some(h) = inst.intersect(ray, t_min, t_max, media) {
                t_max = h.t;
                best = Some(h);
            }
        }
        self.media.stretches(ray, t_min, t_max, media);
        best
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use glam::Vec3;

    use super::*;
    use crate::geometry::emitter::LightId;
    use crate::geometry::instance::Placement;
    use crate::geometry::medium::Medium;
    use crate::geometry::primitive::Primitive;
    use crate::geometry::shapes::Sphere;
    use crate::scene::MaterialId;

    fn ball(center: Vec3, radius: f32) -> Geometry {
        Geometry::Single(
            Primitive::Sphere(Sphere { center, radius }),
            MaterialId(0),
            LightId::NONE,
        )
    }

    #[test]
    fn few_or_many_media_give_every_stretch() {
        // Balls of radius 1 at z = 3, 6, 9, …: a ray along z meets each one
        // it reaches, whether the group asks them in turn or by their BVH.
        for count in [3, FEW_MEDIA + 5] {
            let media = (1..=count).map(|k| {
                let boundary = ball(Vec3::new(0.0, 0.0, 3.0 * k as f32), 1.0);
                let m = Medium::new(Arc::new(boundary), 0.1, MaterialId(1));
                Instance::new(Arc::new(Geometry::Medium(m)), Placement::Identity)
            });
            let group = Group::new(media.collect());
            let ray = Ray::new(Vec3::ZERO, Vec3::Z, 0.0);
            let mut found = MediumSegments::default();
            assert!(group
                .intersect(&ray, 0.0, f32::INFINITY, &mut found)
                .is_none());
            let mut starts: Vec<f32> = found.as_slice().iter().map(|s| s.t0).collect();
            starts.sort_by(f32::total_cmp);
            let want: Vec<f32> = (1..=count).map(|k| 3.0 * k as f32 - 1.0).collect();
            assert_eq!(starts.len(), count, "{starts:?}");
            assert!(starts.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-5));
            // Stopped at t = 7.5: the first two balls and half of neither.
            found.clear();
            assert!(!group.occluded(&ray, 0.0, 7.5, &mut found, LightId::NONE));
            assert_eq!(found.as_slice().len(), 2);
        }
    }

    #[test]
    fn media_see_the_ray_up_to_the_nearest_surface() {
        let haze = Medium::new(Arc::new(ball(Vec3::ZERO, 100.0)), 0.01, MaterialId(1));
        let group = Group::new(vec![
            Instance::new(Arc::new(Geometry::Medium(haze)), Placement::Identity),
            Instance::new(
                Arc::new(ball(Vec3::new(0.0, 0.0, 10.0), 1.0)),
                Placement::Identity,
            ),
        ]);
        assert_eq!(group.bounds().max, Vec3::splat(100.0));
        let stretches = |media: &MediumSegments| -> Vec<(f32, f32)> {
            media.as_slice().iter().map(|s| (s.t0, s.t1)).collect()
        };
        let mut media = MediumSegments::default();
        // Towards the ball: the haze up to its surface at t = 9.
        let towards = Ray::new(Vec3::ZERO, Vec3::Z, 0.0);
        let hit = group
            .intersect(&towards, 0.0, f32::INFINITY, &mut media)
            .unwrap();
        assert!((hit.t - 9.0).abs() < 1e-5);
        assert_eq!(stretches(&media), [(0.0, hit.t)]);
        // Away from it: the haze up to its own boundary.
        media.clear();
        let away = Ray::new(Vec3::ZERO, Vec3::NEG_Z, 0.0);
        assert!(group
            .intersect(&away, 0.0, f32::INFINITY, &mut media)
            .is_none());
        let found = stretches(&media);
        assert_eq!(found.len(), 1);
        assert!(
            found[0].0 == 0.0 && (found[0].1 - 100.0).abs() < 1e-4,
            "{found:?}"
        );
        // A shadow ray: blocked by the ball, or through the haze alone.
        media.clear();
        assert!(group.occluded(&towards, 0.0, 20.0, &mut media, LightId::NONE));
        media.clear();
        assert!(!group.occluded(&towards, 0.0, 5.0, &mut media, LightId::NONE));
        assert_eq!(stretches(&media), [(0.0, 5.0)]);
    }

    /// A layer of a few surfaces asks an instance exactly when the walk of
    /// its BVH would visit it: the box test in turn is one lane of the
    /// node's test. Boxes meeting at faces, rays along the axes (zero
    /// direction components, whose slab distances are NaN where the origin
    /// lies on a face), rays through box corners (where only the test's
    /// allowance for rounding keeps a ray in), from inside boxes, with a far
    /// end before, on and past the boxes.
    #[test]
    fn a_few_surfaces_in_turn_are_asked_as_the_walk_asks_them() {
        use crate::sampling::rng::numbers;
        let mut r = numbers(4);
        let mut asked = 0;
        for count in 1..=FEW_SURFACES {
            let balls = (0..count).map(|k| {
                let center = Vec3::new(k as f32 * 2.0, (k % 2) as f32, 0.5 * k as f32);
                Instance::new(Arc::new(ball(center, 1.0)), Placement::Identity)
            });
            let layer = Layer::new(balls.collect());
            assert!(layer.few());
            for i in 0..4000 {
                let kind = i % 5;
                let mut origin = Vec3::new(r() * 12.0 - 3.0, r() * 4.0 - 2.0, r() * 6.0 - 2.0);
                let dir = if kind < 3 {
                    // Along an axis, from a box face's plane half the time.
                    let mut dir = Vec3::ZERO;
                    dir[kind] = if r() < 0.5 { 1.0 } else { -1.0 };
                    if r() < 0.5 {
                        origin[(kind + 1) % 3] = [-1.0, 1.0, 2.0, 3.0][i % 4];
                    }
                    dir
                } else if kind == 3 {
                    // Through a box's corner, where the slabs' entry and
                    // exit are one distance but for their roundings.
                    let b = layer.bounded[i % count].bounds;
                    let pick = glam::BVec3::new(r() < 0.5, r() < 0.5, r() < 0.5);
                    Vec3::select(pick, b.min, b.max) - origin
                } else {
                    Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5)
                };
                let t_max = [0.5, 2.0, 1e3, f32::INFINITY][i / 4 % 4];
                let mut by_walk = Vec::new();
                layer
                    .bvh
                    .traverse(&Ray::new(origin, dir, 0.0), t_max, |slot, _| {
                        by_walk.push(slot);
                        None
                    });
                let mut in_turn = Vec::new();
                layer.traverse(&Ray::new(origin, dir, 0.0), t_max, |slot, _| {
                    in_turn.push(slot);
                    None
                });
                by_walk.sort_unstable();
                assert_eq!(in_turn, by_walk, "from {origin} along {dir} to {t_max}");
                let any = layer.traverse_any(&Ray::new(origin, dir, 0.0), t_max, |_, _| true);
                assert_eq!(any, !by_walk.is_empty());
                asked += in_turn.len();
            }
        }
        assert!(asked > 2000, "{asked}");
    }
}
