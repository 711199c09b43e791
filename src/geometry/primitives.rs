//! Many analytic primitives (spheres, turned spheres, rects, parallelograms,
//! boxes, triangles) with their materials and light ids in flat arrays under
//! one BVH.

use super::emitter::LightId;
use super::shapes::{Cuboid, Quad, Rect, ShapeHit, Sphere, Triangle, TurnedSphere};
use super::{Aabb, Bvh, Ray};
use crate::scene::MaterialId;

/// A bounded analytic primitive; the closed set matched in the hot path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    Sphere(Sphere),
    TurnedSphere(TurnedSphere),
    Rect(Rect),
    Quad(Quad),
    Cuboid(Cuboid),
    Triangle(Triangle),
}

impl Primitive {
    pub fn bounds(&self) -> Aabb {
        match self {
            Primitive::Sphere(s) => s.bounds(),
            Primitive::TurnedSphere(s) => s.bounds(),
            Primitive::Rect(r) => r.bounds(),
            Primitive::Quad(q) => q.bounds(),
            Primitive::Cuboid(c) => c.bounds(),
            Primitive::Triangle(t) => t.bounds(),
        }
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        match self {
            Primitive::Sphere(s) => s.intersect(ray, t_min, t_max),
            Primitive::TurnedSphere(s) => s.intersect(ray, t_min, t_max),
            Primitive::Rect(r) => r.intersect(ray, t_min, t_max),
            Primitive::Quad(q) => q.intersect(ray, t_min, t_max),
            Primitive::Cuboid(c) => c.intersect(ray, t_min, t_max),
            Primitive::Triangle(t) => t.intersect(ray, t_min, t_max),
        }
    }
}

/// Primitives in BVH leaf order, each with its material and light id.
#[derive(Debug, Default)]
pub struct PrimitiveSet {
    prims: Vec<Primitive>,
    materials: Vec<MaterialId>,
    /// Empty when no primitive emits.
    lights: Vec<LightId>,
    bvh: Bvh,
}

impl PrimitiveSet {
    pub fn new(items: Vec<(Primitive, MaterialId, LightId)>) -> PrimitiveSet {
        let bounds: Vec<Aabb> = items.iter().map(|(p, _, _)| p.bounds()).collect();
        let (bvh, order) = Bvh::build(&bounds);
        let (prims, materials) = order
            .iter()
            .map(|&i| (items[i as usize].0, items[i as usize].1))
            .unzip();
        let mut lights: Vec<LightId> = order.iter().map(|&i| items[i as usize].2).collect();
        if lights.iter().all(|l| *l == LightId::NONE) {
            lights = Vec::new();
        }
        PrimitiveSet {
            prims,
            materials,
            lights,
            bvh,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The nearest hit in `(t_min, t_max)` with its material and light id.
    #[inline]
    pub fn intersect(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(ShapeHit, MaterialId, LightId)> {
        let mut best = None;
        self.bvh.traverse(ray, t_max, |slot, t_max| {
            let h = self.prims[slot].intersect(ray, t_min, t_max)?;
            best = Some((h, slot));
            Some(h.t)
        });
        let (h, slot) = best?;
        let light = self.lights.get(slot).copied().unwrap_or(LightId::NONE);
        Some((h, self.materials[slot], light))
    }

    /// Whether any primitive is hit with `t` in `(t_min, t_max)`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.bvh.traverse_any(ray, t_max, |slot, t_max| {
            self.prims[slot].intersect(ray, t_min, t_max).is_some()
        })
    }

    /// Whether the set holds no primitive.
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }
}
