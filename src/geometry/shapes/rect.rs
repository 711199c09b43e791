//! Axis-aligned rectangles.

use glam::{Vec2, Vec3};

use super::{axis_lane, Crossing, ShapeHit};
use crate::geometry::ray::gamma;
use crate::geometry::{Aabb, Ray};
use crate::scene::object::RectPlane;

/// The rectangle `a.0..a.1 × b.0..b.1` in the plane `axis = k`; the other two
/// axes, in order, are `(axis + 1) % 3`-style pairs fixed by [`RectPlane`].
/// Its outside faces +axis, or −axis when `reversed`: a flipped rect (a lamp
/// facing down) stays a rect, whose test is cheaper than a parallelogram's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// The axis normal to the rectangle.
    pub axis: u8,
    /// The axes spanned by `a` and `b`.
    pub span: [u8; 2],
    /// Whether the outside faces −axis.
    pub reversed: bool,
    pub a: (f32, f32),
    pub b: (f32, f32),
    pub k: f32,
}

impl Rect {
    pub fn new(plane: RectPlane, a: (f32, f32), b: (f32, f32), k: f32) -> Rect {
        let (axis, span) = match plane {
            RectPlane::Xy => (2, [0, 1]),
            RectPlane::Xz => (1, [0, 2]),
            RectPlane::Yz => (0, [1, 2]),
        };
        Rect {
            axis,
            span,
            reversed: false,
            a: (a.0.min(a.1), a.0.max(a.1)),
            b: (b.0.min(b.1), b.0.max(b.1)),
            k,
        }
    }

    pub fn bounds(&self) -> Aabb {
        let mut lo = Vec3::ZERO;
        let mut hi = Vec3::ZERO;
        lo[self.axis as usize] = self.k;
        hi[self.axis as usize] = self.k;
        lo[self.span[0] as usize] = self.a.0;
        hi[self.span[0] as usize] = self.a.1;
        lo[self.span[1] as usize] = self.b.0;
        hi[self.span[1] as usize] = self.b.1;
        Aabb::new(lo, hi)
    }

    /// The same rectangle and uv with its outside on the other side (as
    /// [`super::Quad::flipped`]).
    pub fn flipped(&self) -> Rect {
        Rect {
            reversed: !self.reversed,
            ..*self
        }
    }

    /// The outward normal's component along `axis`: 1, or −1 when reversed.
    #[inline(always)]
    pub fn outward(&self) -> f32 {
        if self.reversed {
            -1.0
        } else {
            1.0
        }
    }

    /// The hit with `t` in `(t_min, t_max)`; the outward normal is ±axis.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let c = self.crossing(ray, t_min, t_max)?;
        Some(self.surface(ray, &c))
    }

    /// The crossing with `t` in `(t_min, t_max)` (no data: the surface is
    /// rebuilt from `t`).
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Crossing> {
        let ax = self.axis as usize;
        let d = ray.dir[ax];
        if d == 0.0 {
            return None;
        }
        let t = (self.k - ray.origin[ax]) / d;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let point = ray.at(t);
        let (i, j) = (self.span[0] as usize, self.span[1] as usize);
        let (x, y) = (point[i], point[j]);
        if x < self.a.0 || x > self.a.1 || y < self.b.0 || y > self.b.1 {
            return None;
        }
        Some(Crossing {
            t,
            data: Vec3::ZERO,
        })
    }

    /// The hit at crossing `c` of `ray`, as [`Rect::intersect`] has it.
    #[inline(always)]
    pub fn surface(&self, ray: &Ray, c: &Crossing) -> ShapeHit {
        let (ax, t) = (self.axis as usize, c.t);
        let on = axis_lane(ax);
        let point = ray.at(t);
        let (i, j) = (self.span[0] as usize, self.span[1] as usize);
        let (x, y) = (point[i], point[j]);
        let point = Vec3::select(on, Vec3::splat(self.k), point);
        let normal = Vec3::select(on, Vec3::splat(self.outward()), Vec3::ZERO);
        // The coordinate along the normal is exact; the others come from
        // `ray.at(t)` with a rounded `t`.
        let error = gamma(4) * (ray.origin.abs() + (t * ray.dir).abs());
        let error = Vec3::select(on, Vec3::ZERO, error);
        ShapeHit {
            t,
            point,
            error,
            normal,
            uv: Vec2::new(
                (x - self.a.0) / (self.a.1 - self.a.0).max(f32::MIN_POSITIVE),
                (y - self.b.0) / (self.b.1 - self.b.0).max(f32::MIN_POSITIVE),
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
    fn hits_inside_misses_outside_and_parallel() {
        let r = Rect::new(RectPlane::Xz, (213.0, 343.0), (227.0, 332.0), 554.0);
        let h = r
            .intersect(
                &Ray::new(Vec3::new(278.0, 0.0, 278.0), Vec3::Y, 0.0),
                0.0,
                f32::INFINITY,
            )
            .expect("hits");
        assert!((h.t - 554.0).abs() < 1e-3);
        assert_eq!(h.normal, Vec3::Y);
        assert!(r.bounds().contains(h.point));
        let out = Ray::new(Vec3::new(100.0, 0.0, 278.0), Vec3::Y, 0.0);
        assert!(r.intersect(&out, 0.0, f32::INFINITY).is_none());
        let parallel = Ray::new(Vec3::new(278.0, 554.0, 0.0), Vec3::Z, 0.0);
        assert!(r.intersect(&parallel, 0.0, f32::INFINITY).is_none());
        let from = offset_origin(h.point, h.error, Vec3::Y, Vec3::new(0.3, -1.0, 0.1));
        let back = Ray::new(from, Vec3::new(0.3, -1.0, 0.1), 0.0);
        assert!(r.intersect(&back, 0.0, f32::INFINITY).is_none());
    }
}
