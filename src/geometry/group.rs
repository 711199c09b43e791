//! A group of instances: a BVH over the bounded surfaces, a short list of
//! the unbounded ones (infinite planes), tested after it, and the media,
//! asked for their stretches last, up to the nearest surface found.

use super::instance::{is_bounded, Instance};
use super::medium::MediumSegments;
use super::object::Geometry;
use super::{Aabb, Bvh, Hit, Ray};

/// Instances under one hierarchy.
#[derive(Default)]
pub struct Group {
    bounded: Vec<Instance>,
    unbounded: Vec<Instance>,
    /// Media placed directly in the group. They stop no ray, so they stay
    /// out of the BVH (a haze's ball would hold every ray's first visit)
    /// and see each ray once its nearest surface is known: a stretch that
    /// ends inside the medium then needs no crossing to be solved.
    media: Vec<Instance>,
    bvh: Bvh,
}

impl Group {
    pub fn new(instances: Vec<Instance>) -> Group {
        let (media, surfaces): (Vec<Instance>, Vec<Instance>) = instances
            .into_iter()
            .filter(|i| !i.bounds.is_empty())
            .partition(|i| matches!(*i.geometry, Geometry::Medium(_)));
        let (bounded, unbounded): (Vec<Instance>, Vec<Instance>) =
            surfaces.into_iter().partition(|i| is_bounded(&i.bounds));
        let boxes: Vec<Aabb> = bounded.iter().map(|i| i.bounds).collect();
        let (bvh, order) = Bvh::build(&boxes);
        let bounded = order.iter().map(|&i| bounded[i as usize].clone()).collect();
        Group {
            bounded,
            unbounded,
            media,
            bvh,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.unbounded
            .iter()
            .chain(&self.media)
            .fold(self.bvh.bounds(), |b, i| b.union(&i.bounds))
    }

    /// Whether any instance is hit with `t` in `(t_min, t_max)`; the media's
    /// stretches are only looked for when nothing is.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, media: &mut MediumSegments) -> bool {
        let hit = self.bvh.traverse_any(ray, t_max, |slot, t_max| {
            self.bounded[slot].occluded(ray, t_min, t_max, media)
        }) || self
            .unbounded
            .iter()
            .any(|inst| inst.occluded(ray, t_min, t_max, media));
        if !hit {
            for m in &self.media {
                m.occluded(ray, t_min, t_max, media);
            }
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
        let mut best: Option<Hit> = None;
        self.bvh.traverse(ray, t_max, |slot, t_max| {
            let h = self.bounded[slot].intersect(ray, t_min, t_max, media)?;
            best = Some(h);
            Some(h.t)
        });
        let mut t_max = best.map_or(t_max, |h| h.t);
        for inst in &self.unbounded {
            if let Some(h) = inst.intersect(ray, t_min, t_max, media) {
                t_max = h.t;
                best = Some(h);
            }
        }
        for m in &self.media {
            m.intersect(ray, t_min, t_max, media);
        }
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
    use crate::geometry::primitives::Primitive;
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
        assert!(group.occluded(&towards, 0.0, 20.0, &mut media));
        media.clear();
        assert!(!group.occluded(&towards, 0.0, 5.0, &mut media));
        assert_eq!(stretches(&media), [(0.0, 5.0)]);
    }
}
