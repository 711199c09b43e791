//! A group of instances: a BVH over the bounded ones and a short list of the
//! unbounded ones (infinite planes), tested after it.

use super::instance::{is_bounded, Instance};
use super::medium::MediumSegments;
use super::{Aabb, Bvh, Hit, Ray};

/// Instances under one hierarchy.
#[derive(Default)]
pub struct Group {
    bounded: Vec<Instance>,
    unbounded: Vec<Instance>,
    bvh: Bvh,
}

impl Group {
    pub fn new(instances: Vec<Instance>) -> Group {
        let (bounded, unbounded): (Vec<Instance>, Vec<Instance>) = instances
            .into_iter()
            .filter(|i| !i.bounds.is_empty())
            .partition(|i| is_bounded(&i.bounds));
        let boxes: Vec<Aabb> = bounded.iter().map(|i| i.bounds).collect();
        let (bvh, order) = Bvh::build(&boxes);
        let bounded = order.iter().map(|&i| bounded[i as usize].clone()).collect();
        Group {
            bounded,
            unbounded,
            bvh,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.unbounded
            .iter()
            .fold(self.bvh.bounds(), |b, i| b.union(&i.bounds))
    }

    /// The instances of the group (bounded ones in BVH order).
    pub fn instances(&self) -> impl Iterator<Item = &Instance> {
        self.bounded.iter().chain(&self.unbounded)
    }

    /// Whether any instance is hit with `t` in `(t_min, t_max)`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, media: &mut MediumSegments) -> bool {
        self.bvh.traverse_any(ray, t_max, |slot, t_max| {
            self.bounded[slot].occluded(ray, t_min, t_max, media)
        }) || self
            .unbounded
            .iter()
            .any(|inst| inst.occluded(ray, t_min, t_max, media))
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
        best
    }
}
