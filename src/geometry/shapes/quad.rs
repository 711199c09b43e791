//! Parallelograms in any orientation: what an axis-aligned rect or a box
//! face becomes under a rotation or any other affine map when the map is
//! baked into the shape (geometry/bake.rs), with the texture coordinates
//! and the outward normal of the face it came from.

use glam::{Vec2, Vec3};

use super::{Crossing, ShapeHit};
use crate::geometry::ray::gamma;
use crate::geometry::{Aabb, Ray};

/// The points `corner + u·edge_u + v·edge_v` for `u, v` in [0, 1], with
/// texture coordinates `(u, v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quad {
    pub corner: Vec3,
    pub edge_u: Vec3,
    pub edge_v: Vec3,
    /// Unit outward normal (perpendicular to both edges, on the side the
    /// face's outside was on before the map, whatever the edges' order).
    pub normal: Vec3,
    /// `1 / ((edge_u × edge_v) · normal)`: turns the triple products that
    /// measure a point against the edges into `u` and `v`.
    inv_area: f32,
}

impl Quad {
    /// The parallelogram on `corner` spanned by the edges, its normal on the
    /// side of `outward`; `None` when the edges are parallel, zero or not
    /// finite, or `outward` lies in its plane.
    pub fn new(corner: Vec3, edge_u: Vec3, edge_v: Vec3, outward: Vec3) -> Option<Quad> {
        let cross = edge_u.cross(edge_v);
        let len = cross.length();
        if !(len > 0.0 && len.is_finite() && corner.is_finite()) {
            return None;
        }
        let mut normal = cross / len;
        let side = normal.dot(outward);
        if side == 0.0 || !side.is_finite() {
            return None;
        }
        if side < 0.0 {
            normal = -normal;
        }
        let inv_area = 1.0 / cross.dot(normal);
        inv_area.is_finite().then_some(Quad {
            corner,
            edge_u,
            edge_v,
            normal,
            inv_area,
        })
    }

    /// The same parallelogram and uv with its outside on the other side.
    pub fn flipped(&self) -> Quad {
        Quad {
            normal: -self.normal,
            inv_area: -self.inv_area,
            ..*self
        }
    }

    pub fn bounds(&self) -> Aabb {
        let (a, b) = (self.corner + self.edge_u, self.corner + self.edge_v);
        let c = a + self.edge_v;
        Aabb::new(
            self.corner.min(a).min(b).min(c),
            self.corner.max(a).max(b).max(c),
        )
    }

    /// The hit with `t` in `(t_min, t_max)`. The point is rebuilt from its
    /// `(u, v)`, so its error bound is a few roundings of the corner and the
    /// two scaled edges (as pbrt-v4's bilinear patches), not of the ray.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let c = self.crossing(ray, t_min, t_max)?;
        Some(self.surface(&c))
    }

    /// `1 / ((edge_u × edge_v) · normal)`.
    pub fn inv_area(&self) -> f32 {
        self.inv_area
    }

    /// The crossing with `t` in `(t_min, t_max)`; its data holds `(u, v)`.
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Crossing> {
        let n = self.normal;
        let denom = n.dot(ray.dir);
        let t = n.dot(self.corner - ray.origin) / denom;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let rel = ray.at(t) - self.corner;
        let u = rel.cross(self.edge_v).dot(n) * self.inv_area;
        let v = self.edge_u.cross(rel).dot(n) * self.inv_area;
        if !((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)) {
            return None;
        }
        Some(Crossing {
            t,
            data: Vec3::new(u, v, 0.0),
        })
    }

    /// The hit at crossing `c`, as [`Quad::intersect`] has it.
    #[inline]
    pub fn surface(&self, c: &Crossing) -> ShapeHit {
        let (u, v) = (c.data.x, c.data.y);
        let (du, dv) = (u * self.edge_u, v * self.edge_v);
        ShapeHit {
            t: c.t,
            point: self.corner + du + dv,
            error: gamma(7) * (self.corner.abs() + du.abs() + dv.abs()),
            normal: self.normal,
            uv: Vec2::new(u, v).into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ray::offset_origin;

    fn tilted(base: Vec3) -> Quad {
        Quad::new(
            base,
            Vec3::new(3.0, 0.4, -1.0),
            Vec3::new(0.5, 2.0, 1.5),
            Vec3::new(1.0, -1.0, 1.0),
        )
        .expect("a parallelogram")
    }

    #[test]
    fn hits_report_uv_and_the_outward_normal_and_miss_outside() {
        let q = tilted(Vec3::ZERO);
        assert!(q.normal.dot(Vec3::new(1.0, -1.0, 1.0)) > 0.0);
        for (u, v) in [(0.25f32, 0.5f32), (0.9, 0.1), (0.01, 0.99)] {
            let target = q.corner + u * q.edge_u + v * q.edge_v;
            let origin = target + 5.0 * q.normal + Vec3::new(0.3, 0.1, -0.2);
            let h = q
                .intersect(&Ray::new(origin, target - origin, 0.0), 0.0, f32::INFINITY)
                .expect("hits");
            assert!((h.t - 1.0).abs() < 1e-5, "t {}", h.t);
            assert!((h.uv.get() - Vec2::new(u, v)).abs().max_element() < 1e-5);
            assert!(h.point.distance(target) < 1e-5);
            assert_eq!(h.normal, q.normal);
        }
        for (u, v) in [(-0.01f32, 0.5f32), (0.5, 1.01), (1.2, 0.2)] {
            let target = q.corner + u * q.edge_u + v * q.edge_v;
            let origin = target + 5.0 * q.normal;
            let ray = Ray::new(origin, target - origin, 0.0);
            assert!(q.intersect(&ray, 0.0, f32::INFINITY).is_none(), "{u} {v}");
        }
        let parallel = Ray::new(q.corner + q.normal, q.edge_u, 0.0);
        assert!(q.intersect(&parallel, 0.0, f32::INFINITY).is_none());
    }

    #[test]
    fn a_flipped_quad_has_the_same_hits_and_uv_with_the_normal_reversed() {
        let q = tilted(Vec3::new(1.0, 2.0, 3.0));
        let f = q.flipped();
        let target = q.corner + 0.3 * q.edge_u + 0.6 * q.edge_v;
        let origin = target + 2.0 * q.normal;
        let ray = Ray::new(origin, target - origin, 0.0);
        let (a, b) = (
            q.intersect(&ray, 0.0, f32::INFINITY).expect("hits"),
            f.intersect(&ray, 0.0, f32::INFINITY).expect("hits"),
        );
        assert_eq!((a.t, a.point, a.uv), (b.t, b.point, b.uv));
        assert_eq!(a.normal, -b.normal);
    }

    #[test]
    fn degenerate_parallelograms_are_refused() {
        assert!(Quad::new(Vec3::ZERO, Vec3::X, 2.0 * Vec3::X, Vec3::Y).is_none());
        assert!(Quad::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, Vec3::Z).is_none());
        assert!(Quad::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X).is_none());
        assert!(Quad::new(Vec3::NAN, Vec3::X, Vec3::Y, Vec3::Z).is_none());
    }

    #[test]
    fn leaving_rays_do_not_rehit_near_or_far_from_the_origin() {
        for base in [Vec3::ZERO, Vec3::new(1e4, -3e3, 500.0), Vec3::splat(1e5)] {
            let q = tilted(base);
            let mut checked = 0;
            for i in 0..200 {
                let a = i as f32 * 0.618_034;
                let (u, v) = (a.fract(), (a * 1.7).fract());
                let target = q.corner + u * q.edge_u + v * q.edge_v;
                let origin = target + 4.0 * q.normal + Vec3::new(a.sin(), a.cos(), 0.3);
                let ray = Ray::new(origin, target - origin, 0.0);
                let Some(h) = q.intersect(&ray, 0.0, f32::INFINITY) else {
                    continue;
                };
                checked += 1;
                // Leaving on the near side, grazing or steep: no re-hit.
                let tangent = q.edge_u.normalize();
                for d in [
                    q.normal,
                    (tangent + 1e-3 * q.normal),
                    (q.normal - 0.5 * tangent),
                ] {
                    let o = offset_origin(h.point, h.error, h.normal, d);
                    let leave = Ray::new(o, d, 0.0);
                    assert!(
                        q.intersect(&leave, 0.0, f32::INFINITY).is_none(),
                        "{base}: re-hit leaving along {d}"
                    );
                }
            }
            assert!(checked > 150, "{base}: {checked} hits");
        }
    }
}
