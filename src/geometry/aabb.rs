//! Axis-aligned bounding boxes and the ray/box slab test.

use glam::{Mat4, Vec3};

use super::Ray;

/// The factor absorbing the rounding of the slab distances (robust
/// traversal, Ize 2013), so rays grazing a box edge are not lost.
pub const ROBUST: f32 = 1.0 + 2.0 * f32::EPSILON * 2.0;

/// An axis-aligned box; `min > max` on any axis means empty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    pub fn new(a: Vec3, b: Vec3) -> Aabb {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Whether the box is non-empty and finite (it can go into a BVH).
    pub fn is_bounded(&self) -> bool {
        !self.is_empty() && self.min.is_finite() && self.max.is_finite()
    }

    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn grow(&self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Surface area (0 for an empty box).
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// The box bounding this box's eight corners after `m`.
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        let mut out = Aabb::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            out = out.grow(m.transform_point3(c));
        }
        out
    }

    /// Whether a ray from `origin` with reciprocal direction `inv_dir`
    /// enters the box within `(0, t_max)`: one lane of the BVH's node test
    /// (`bvh::node`), the same operations in the same order, so a box is
    /// entered here exactly when a walk would enter it. A NaN slab distance
    /// (a zero direction component meeting a face through the origin)
    /// keeps the bound before it, as the node test's `max` does.
    #[inline(always)]
    pub fn entered(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> bool {
        let mut near = 0.0f32;
        let mut far = t_max;
        for axis in 0..3 {
            let (first, last) = if inv_dir[axis] < 0.0 {
                (self.max[axis], self.min[axis])
            } else {
                (self.min[axis], self.max[axis])
            };
            let to_first = (first - origin[axis]) * inv_dir[axis];
            let to_last = (last - origin[axis]) * inv_dir[axis];
            near = if to_first > near { to_first } else { near };
            far = if to_last < far { to_last } else { far };
        }
        near <= far * ROBUST
    }

    /// Slab test; `inv_dir` is `1 / ray.dir` per component. Returns the entry
    /// distance when the ray overlaps the box within `(t_min, t_max)`.
    #[inline]
    pub fn hit(&self, ray: &Ray, inv_dir: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
        let t0 = (self.min - ray.origin) * inv_dir;
        let t1 = (self.max - ray.origin) * inv_dir;
        let near = t0.min(t1).max_element().max(t_min);
        let far = t0.max(t1).min_element().min(t_max);
        if near <= far {
            Some(near)
        } else {
            None
        }
    }
}
