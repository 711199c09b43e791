//! Axis-aligned boxes intersected as one slab test, with the normal of the
//! face the ray crossed.

use glam::{Vec2, Vec3};

use super::{axis_lane, Crossing, ShapeHit};
use crate::geometry::ray::gamma;
use crate::geometry::{Aabb, Ray};

/// A solid box from `min` to `max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cuboid {
    pub min: Vec3,
    pub max: Vec3,
}

impl Cuboid {
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    /// The nearest crossing of the box surface with `t` in `(t_min, t_max)`:
    /// the entry face from outside, the exit face from inside.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let c = self.crossing(ray, t_min, t_max)?;
        Some(self.surface(ray, &c))
    }

    /// The crossing with `t` in `(t_min, t_max)`; its data holds the face's
    /// axis and whether it is the `max` side (1) or the `min` side (0).
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Crossing> {
        let (near, far) = self.slabs(ray);
        let (t_near, t_far) = (near.max_element(), far.min_element());
        if t_near > t_far {
            return None;
        }
        let (t, axis, at_max) = if t_near > t_min && t_near < t_max {
            let axis = near.max_position();
            (t_near, axis, ray.dir[axis] < 0.0)
        } else if t_far > t_min && t_far < t_max {
            let axis = far.min_position();
            (t_far, axis, ray.dir[axis] > 0.0)
        } else {
            return None;
        };
        Some(Crossing {
            t,
            data: Vec3::new(axis as f32, f32::from(u8::from(at_max)), 0.0),
        })
    }

    /// Where the ray's line enters and leaves the solid box, `(t_near,
    /// t_far)`, if it meets it: the two crossings [`Cuboid::crossing`]
    /// chooses from, found by one slab test.
    #[inline]
    pub fn span(&self, ray: &Ray) -> Option<(f32, f32)> {
        let (near, far) = self.slabs(ray);
        let (t_near, t_far) = (near.max_element(), far.min_element());
        (t_near <= t_far).then_some((t_near, t_far))
    }

    /// Per axis, the ray's entry into and exit from the box's slab.
    #[inline(always)]
    fn slabs(&self, ray: &Ray) -> (Vec3, Vec3) {
        let inv = ray.dir.recip();
        let t0 = (self.min - ray.origin) * inv;
        let t1 = (self.max - ray.origin) * inv;
        // A ray parallel to a slab is inside it for every t or for none; on
        // its boundary 0·∞ would give a NaN that picks a wrong face.
        let parallel = ray.dir.cmpeq(Vec3::ZERO);
        let inside = ray.origin.cmpge(self.min) & ray.origin.cmple(self.max);
        let (all, none) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let near = Vec3::select(parallel, Vec3::select(inside, none, all), t0.min(t1));
        let far = Vec3::select(parallel, Vec3::select(inside, all, none), t0.max(t1));
        (near, far)
    }

    /// The hit at crossing `c` of `ray`, as [`Cuboid::intersect`] has it.
    #[inline]
    pub fn surface(&self, ray: &Ray, c: &Crossing) -> ShapeHit {
        let (t, axis, at_max) = (c.t, c.data.x as usize, c.data.y > 0.0);
        let on = axis_lane(axis);
        let (face, side) = if at_max {
            (self.max, 1.0)
        } else {
            (self.min, -1.0)
        };
        let point = Vec3::select(on, face, ray.at(t)).clamp(self.min, self.max);
        let normal = Vec3::select(on, Vec3::splat(side), Vec3::ZERO);
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        let ext = (self.max - self.min).max(Vec3::splat(f32::MIN_POSITIVE));
        // The face coordinate is exact; the others come from `ray.at(t)`.
        let error = gamma(4) * (ray.origin.abs() + (t * ray.dir).abs());
        let error = Vec3::select(on, Vec3::ZERO, error);
        ShapeHit {
            t,
            point,
            error,
            normal,
            uv: Vec2::new(
                (point[i] - self.min[i]) / ext[i],
                (point[j] - self.min[j]) / ext[j],
            )
            .into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ray::offset_origin;

    #[test]
    fn entry_exit_and_face_normals() {
        let c = Cuboid {
            min: Vec3::ZERO,
            max: Vec3::new(165.0, 330.0, 165.0),
        };
        let h = c
            .intersect(
                &Ray::new(Vec3::new(50.0, 50.0, -100.0), Vec3::Z, 0.0),
                0.0,
                f32::INFINITY,
            )
            .expect("hits front face");
        assert_eq!(h.normal, Vec3::NEG_Z);
        assert!((h.t - 100.0).abs() < 1e-4);
        let inside = Ray::new(Vec3::new(50.0, 50.0, 50.0), Vec3::Y, 0.0);
        let h = c.intersect(&inside, 0.0, f32::INFINITY).expect("exits top");
        assert_eq!(h.normal, Vec3::Y);
        assert!((h.t - 280.0).abs() < 1e-3);
        let along_face = Ray::new(Vec3::new(-1.0, 50.0, 200.0), Vec3::X, 0.0);
        assert!(c.intersect(&along_face, 0.0, f32::INFINITY).is_none());
    }

    #[test]
    fn leaving_rays_do_not_rehit_far_from_origin() {
        let base = Vec3::splat(1e5);
        let c = Cuboid {
            min: base,
            max: base + Vec3::splat(10.0),
        };
        let above = base + Vec3::new(5.0, 13.0, 5.0);
        let top = c
            .intersect(&Ray::new(above, Vec3::NEG_Y, 0.0), 0.0, f32::INFINITY)
            .expect("hits the top");
        let p = top.point;
        for d in [
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(1.0, 1e-3, 0.0),
            Vec3::new(-0.3, 0.2, 0.9),
        ] {
            let o = offset_origin(p, top.error, Vec3::Y, d);
            assert!(c
                .intersect(&Ray::new(o, d, 0.0), 0.0, f32::INFINITY)
                .is_none());
        }
        let inward = Vec3::new(0.2, -1.0, 0.1);
        let o = offset_origin(p, top.error, Vec3::Y, inward);
        let h = c
            .intersect(&Ray::new(o, inward, 0.0), 0.0, f32::INFINITY)
            .expect("exits bottom");
        assert_eq!(h.normal, Vec3::NEG_Y);
    }
}
