//! The infinite plane: unbounded, so it lives outside every BVH.

use glam::{Vec2, Vec3};

use super::ShapeHit;
use crate::geometry::ray::gamma;
use crate::geometry::Ray;

/// The plane through `point` with unit `normal` (the outward side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub point: Vec3,
    pub normal: Vec3,
}

impl Plane {
    /// The hit with `t` in `(t_min, t_max)`; rays parallel to the plane miss.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let denom = self.normal.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        let t = self.normal.dot(self.point - ray.origin) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let point = ray.at(t);
        let (u_axis, v_axis) = self.normal.any_orthonormal_pair();
        let rel = point - self.point;
        // `t` carries the rounding of `point − origin`, of two dot products
        // and a division; `ray.at(t)` two more.
        let error = gamma(10) * (ray.origin.abs() + self.point.abs() + (t * ray.dir).abs());
        Some(ShapeHit {
            t,
            point,
            error,
            normal: self.normal,
            uv: Vec2::new(rel.dot(u_axis), rel.dot(v_axis)).into(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ray::offset_origin;

    #[test]
    fn parallel_rays_miss_and_leaving_rays_do_not_rehit() {
        let p = Plane {
            point: Vec3::new(0.0, -2.0, 0.0),
            normal: Vec3::Y,
        };
        assert!(p
            .intersect(&Ray::new(Vec3::ZERO, Vec3::X, 0.0), 0.0, f32::INFINITY)
            .is_none());
        let on = Ray::new(Vec3::new(0.0, -2.0, 0.0), Vec3::X, 0.0);
        assert!(p.intersect(&on, 0.0, f32::INFINITY).is_none());
        let h = p
            .intersect(
                &Ray::new(Vec3::new(3.0, 4.0, 1e5), Vec3::new(0.1, -1.0, 0.0), 0.0),
                0.0,
                f32::INFINITY,
            )
            .expect("downward ray hits");
        assert!((h.t - 6.0).abs() < 1e-4);
        for x in [1e-3f32, 1.0, 1e3, 1e5] {
            let pt = Vec3::new(x, -2.0, -x);
            let h = p
                .intersect(&Ray::new(pt + Vec3::Y * 3.0, Vec3::NEG_Y, 0.0), 0.0, 1e9)
                .expect("hits");
            for d in [
                Vec3::new(1.0, 1e-3, 0.0),
                Vec3::Y,
                Vec3::new(-1.0, 0.5, 1.0),
            ] {
                let o = offset_origin(h.point, h.error, Vec3::Y, d);
                assert!(p
                    .intersect(&Ray::new(o, d, 0.0), 0.0, f32::INFINITY)
                    .is_none());
            }
        }
    }
}
