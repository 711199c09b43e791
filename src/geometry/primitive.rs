//! One bounded analytic primitive (sphere, turned sphere, rect,
//! parallelogram, box, triangle): its bounds and its intersection, whole
//! or in the two steps a walk takes. Both the primitive sets and the flat
//! face passes built from them use it, so it sits below both.

use super::shapes::{Crossing, Cuboid, Quad, Rect, ShapeHit, Sphere, Triangle, TurnedSphere};
use super::{Aabb, Ray};

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

    /// The sphere a (turned) sphere is intersected as.
    pub fn sphere(&self) -> Option<Sphere> {
        match self {
            Primitive::Sphere(s) => Some(*s),
            Primitive::TurnedSphere(s) => Some(s.sphere),
            _ => None,
        }
    }

    /// The nearest hit with `t` in `(t_min, t_max)`.
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

    /// The nearest crossing with `t` in `(t_min, t_max)`, without its
    /// surface data. Always inlined: a BVH walk's visit is this test, and
    /// kept out of the walk it cost the random spheres 2.3 % more
    /// instructions.
    #[inline(always)]
    pub fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Crossing> {
        match self {
            Primitive::Sphere(s) => s.crossing(ray, t_min, t_max),
            Primitive::TurnedSphere(s) => s.sphere.crossing(ray, t_min, t_max),
            Primitive::Rect(r) => r.crossing(ray, t_min, t_max),
            Primitive::Quad(q) => q.crossing(ray, t_min, t_max),
            Primitive::Cuboid(c) => c.crossing(ray, t_min, t_max),
            Primitive::Triangle(t) => t.crossing(ray, t_min, t_max),
        }
    }

    /// The hit at a crossing this primitive gave for `ray`. Always inlined:
    /// with two callers (the one-ray and the packet walks' hits) the
    /// compiler kept it out of line, and the random spheres took 0.6 % more
    /// instructions (callgrind, 100×56 at 16 spp on one thread).
    #[inline(always)]
    pub fn surface(&self, ray: &Ray, c: &Crossing) -> ShapeHit {
        match self {
            Primitive::Sphere(s) => s.surface(ray, c),
            Primitive::TurnedSphere(s) => s.surface(ray, c),
            Primitive::Rect(r) => r.surface(ray, c),
            Primitive::Quad(q) => q.surface(c),
            Primitive::Cuboid(b) => b.surface(ray, c),
            Primitive::Triangle(t) => t.surface(c),
        }
    }
}
