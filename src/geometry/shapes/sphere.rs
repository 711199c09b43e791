//! Spheres, intersected with the numerically stable quadratic so that huge and
//! tiny radii keep their precision.

use glam::Vec3;

use super::{Crossing, ShapeHit};
use crate::geometry::ray::gamma;
use crate::geometry::uv::SurfaceUv;
use crate::geometry::{Aabb, Ray};

/// Relative margin of the early miss test, far above its rounding error
/// (about 12 ε ≈ 1.4e-6 of `|f|²|D|²`).
pub const MISS_MARGIN: f32 = 1e-5;

/// A sphere by centre and radius (> 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    pub fn bounds(&self) -> Aabb {
        let r = Vec3::splat(self.radius.abs());
        Aabb::new(self.center - r, self.center + r)
    }

    /// The nearest hit with `t` in `(t_min, t_max)`.
    ///
    /// With a unit direction `d` and `f = o − c`, the discriminant is taken as
    /// `r² − |f − (f·d)d|²` (no cancellation between two large squares), the
    /// far root as `q = −b − sign(b)·√disc` and the near one as `c / q`
    /// (Ray Tracing Gems, ch. 7).
    ///
    /// Most tests miss, so a cheap test without root or division comes
    /// first: the ray's line passes the centre at distance `|f × D| / |D|`,
    /// and when `|f × D|²` exceeds `r²|D|²` by more than its rounding error
    /// (a few ε of `|f|²|D|²`, bounded by the margin below) the line misses.
    /// Before it, a ray that starts outside and moves away
    /// ([`Sphere::departs`]) is done.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let c = self.crossing(ray, t_min, t_max)?;
        Some(self.surface(ray, &c))
    }

    /// The nearest crossing with `t` in `(t_min, t_max)` (see
    /// [`Sphere::intersect`]); its data holds the root it took, the
    /// distance along the unit direction, by which [`Roots::first_after`]
    /// tells the near root from the far one.
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Crossing> {
        if self.departs(ray) {
            return None;
        }
        self.roots(ray)?.crossing(t_min, t_max)
    }

    /// Whether the ray starts outside the sphere and moves away from its
    /// centre (`f·D > 0` and `|f|² > r²`), so that it meets the sphere at
    /// no `t > 0`: most rays leaving a sphere, and every ray leaving the
    /// big ground sphere of a scene, are done here without a root.
    #[inline(always)]
    pub fn departs(&self, ray: &Ray) -> bool {
        let f = ray.origin - self.center;
        f.dot(ray.dir) > 0.0 && f.length_squared() > self.radius * self.radius
    }

    /// Whether `p` is inside the ball by more than the rounding of
    /// [`Sphere::roots`] and of `p` itself could move the surface: a
    /// conservative test, false near the surface, for a negative radius and
    /// for points that are not finite.
    #[inline]
    pub fn surely_holds(&self, p: Vec3) -> bool {
        let r = self.radius;
        let slack = 1e-3 * r
            + 8.0 * f32::EPSILON * (p.abs().max_element() + self.center.abs().max_element());
        let inner = r - slack;
        inner > 0.0 && (p - self.center).length_squared() < inner * inner
    }

    /// Both roots of the ray's line, after the early miss test of
    /// [`Sphere::intersect`]; `None` when the line misses. Always inlined,
    /// as [`crate::geometry::primitive::Primitive::crossing`] is.
    #[inline(always)]
    pub fn roots(&self, ray: &Ray) -> Option<Roots> {
        let f = ray.origin - self.center;
        let dd = ray.dir.length_squared();
        let r = self.radius;
        if f.cross(ray.dir).length_squared() > (r * r + MISS_MARGIN * f.length_squared()) * dd {
            return None;
        }
        let len = dd.sqrt();
        let d = ray.dir / len;
        let b = f.dot(d);
        let perp = f - b * d;
        let disc = (r - perp.length()) * (r + perp.length());
        if disc < 0.0 {
            return None;
        }
        let q = -b - b.signum() * disc.sqrt();
        let fl = f.length();
        Some(Roots::from_quadratic((fl - r) * (fl + r), q, len))
    }

    /// The hit at crossing `c` of `ray`, as [`Sphere::intersect`] has it.
    #[inline]
    pub fn surface(&self, ray: &Ray, c: &Crossing) -> ShapeHit {
        let r = self.radius;
        // Reproject the point onto the sphere: its error is then a few
        // roundings of the radius and of the final sum (pbrt-v4).
        // A negative radius turns the normal inwards (a hollow bubble).
        // One normalisation of the point's offset from the centre, found
        // from the crossing's own `t`: the hit's chain of dependent roots
        // and divisions is the spheres' longest outside the walk (a second
        // normalisation and a unit direction would make the random spheres
        // 7 % slower).
        let rel = ray.origin + c.t * ray.dir - self.center;
        let outward = rel.normalize_or(Vec3::Y);
        let rel = outward * r.abs();
        let point = self.center + rel;
        let normal = outward * r.signum();
        ShapeHit {
            t: c.t,
            point,
            error: gamma(6) * rel.abs() + gamma(1) * point.abs(),
            normal,
            uv: SurfaceUv::Sphere(normal),
        }
    }
}

/// Where a ray's line crosses a sphere: the two roots `t0 ≤ t1` as
/// distances along the unit direction, and the direction's length.
#[derive(Clone, Copy, Debug)]
pub struct Roots {
    t0: f32,
    t1: f32,
    len: f32,
}

impl Roots {
    /// The roots `c / q` and `q` of the stable quadratic (both 0 when `q`
    /// is), in order.
    #[inline]
    pub fn from_quadratic(c: f32, q: f32, len: f32) -> Roots {
        let (mut t0, mut t1) = (c / q, q);
        if q == 0.0 {
            (t0, t1) = (0.0, 0.0);
        }
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        Roots { t0, t1, len }
    }

    /// The nearer root with `t` in `(t_min, t_max)`, as
    /// [`Sphere::crossing`] gives it.
    #[inline]
    pub fn crossing(&self, t_min: f32, t_max: f32) -> Option<Crossing> {
        let (lo, hi) = (t_min * self.len, t_max * self.len);
        let t = if self.t0 > lo && self.t0 < hi {
            self.t0
        } else if self.t1 > lo && self.t1 < hi {
            self.t1
        } else {
            return None;
        };
        Some(Crossing {
            t: t / self.len,
            data: Vec3::new(t, 0.0, 0.0),
        })
    }

    /// The first root after `t` (on the ray's scale) and whether it is the
    /// near one: where the ray's line enters the ball, while the far root is
    /// where it leaves. This holds for grazing rays too, where the sign of
    /// a rounded normal against the direction may not.
    #[inline]
    pub fn first_after(&self, t: f32) -> Option<(f32, bool)> {
        let c = self.crossing(t, f32::INFINITY)?;
        Some((c.t, c.data.x == self.t0))
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;
    use crate::geometry::ray::offset_origin;

    #[test]
    fn a_ball_surely_holds_only_points_well_inside() {
        let ball = Sphere {
            center: Vec3::new(3.0, -1.0, 2.0),
            radius: 2.0,
        };
        for d in dirs() {
            assert!(ball.surely_holds(ball.center + d * 1.99));
            assert!(ball.surely_holds(ball.center));
            assert!(!ball.surely_holds(ball.center + d * 1.9999));
            assert!(!ball.surely_holds(ball.center + d * 2.5));
        }
        assert!(!ball.surely_holds(Vec3::INFINITY));
        assert!(!ball.surely_holds(Vec3::NAN));
        let hollow = Sphere {
            radius: -2.0,
            ..ball
        };
        assert!(!hollow.surely_holds(ball.center));
        // A unit ball 1e6 from the origin: the margin, 8 ε of the
        // coordinates' size (2e6), is 1.9, more than the radius, so not even
        // a point half a radius from the centre is sure.
        let far = Sphere {
            center: Vec3::splat(1e6),
            radius: 1.0,
        };
        assert!(!far.surely_holds(far.center + Vec3::X * 0.5));
    }

    fn dirs() -> Vec<Vec3> {
        let mut v = Vec::new();
        for i in 0..40 {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / 40.0;
            let phi = i as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            v.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        v
    }

    #[test]
    fn leaving_rays_never_rehit_at_extreme_radii() {
        for (center, radius) in [
            (Vec3::ZERO, 1e-4),
            (Vec3::new(0.3, -0.2, 0.1), 1e-4),
            (Vec3::ZERO, 1e5),
            (Vec3::new(2e5, 0.0, -1e5), 1e5),
            (Vec3::new(1.0, 2.0, 3.0), 1.0),
        ] {
            let s = Sphere { center, radius };
            for n in dirs() {
                let towards = Ray::new(center + n * (3.0 * radius), -n, 0.0);
                let h = s
                    .intersect(&towards, 0.0, f32::INFINITY)
                    .expect("aimed at the centre");
                for d in dirs() {
                    let o = offset_origin(h.point, h.error, h.normal, d);
                    let hit = s.intersect(&Ray::new(o, d, 0.0), 0.0, f32::INFINITY);
                    if d.dot(n) > 0.0 {
                        assert!(hit.is_none(), "re-hit leaving r={radius} {hit:?}");
                    } else if let Some(h) = hit {
                        // Entering: the hit must be the far side, not the start.
                        assert!(h.t > radius * 1e-3, "self-hit entering r={radius}: {h:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn grazing_and_central_hits() {
        let s = Sphere {
            center: Vec3::ZERO,
            radius: 2.0,
        };
        let h = s
            .intersect(
                &Ray::new(Vec3::new(0.0, 0.0, -10.0), Vec3::Z * 3.0, 0.0),
                0.0,
                f32::INFINITY,
            )
            .expect("central ray hits");
        assert!((h.t - 8.0 / 3.0).abs() < 1e-5);
        assert!((h.normal - Vec3::NEG_Z).length() < 1e-5);
        let graze = Ray::new(Vec3::new(2.0001, 0.0, -10.0), Vec3::Z, 0.0);
        assert!(s.intersect(&graze, 0.0, f32::INFINITY).is_none());
        let inside = Ray::new(Vec3::ZERO, Vec3::X, 0.0);
        let h = s
            .intersect(&inside, 0.0, f32::INFINITY)
            .expect("inside hits");
        assert!((h.t - 2.0).abs() < 1e-5);
    }

    #[test]
    fn early_miss_test_keeps_lines_just_inside() {
        // Lines passing the centre at 0.999 r hit and at 1.001 r miss, for
        // tiny spheres far along the ray and unnormalized directions.
        for (radius, dist) in [(1e-3, 1e3), (1.0, 1e5), (1e4, 1.0), (0.5, 2.0)] {
            let s = Sphere {
                center: Vec3::ZERO,
                radius,
            };
            for len in [1.0, 3.0, 1e-3] {
                for (offset, hits) in [(0.999, true), (1.001, false)] {
                    let origin = Vec3::new(-(dist + radius), offset * radius, 0.0);
                    let ray = Ray::new(origin, Vec3::X * len, 0.0);
                    let h = s.intersect(&ray, 0.0, f32::INFINITY);
                    assert_eq!(h.is_some(), hits, "r {radius} at {dist}, |D| {len}");
                }
            }
        }
    }

    #[test]
    fn a_departing_ray_is_one_the_roots_never_meet() {
        // Rays leaving the surface (from offset origins), entering it, and
        // from points inside and outside: `departs` says yes only where no
        // root lies ahead, and says it for every ray leaving outwards.
        let mut left = 0;
        for (center, radius) in [
            (Vec3::ZERO, 1.0),
            (Vec3::new(1e3, -2.0, 5.0), 1e-3),
            (Vec3::new(-1e5, 3.0, 1e5), 1.0),
            (Vec3::new(0.0, -1000.0, 0.0), 1000.0),
            (Vec3::new(2.0, 1.0, 0.0), -0.5),
        ] {
            let s = Sphere { center, radius };
            for n in dirs() {
                let onto = Ray::new(center + n * (3.0 * radius.abs()), -n, 0.0);
                let h = s
                    .intersect(&onto, 0.0, f32::INFINITY)
                    .expect("aimed at the centre");
                for d in dirs() {
                    let o = offset_origin(h.point, h.error, h.normal, d);
                    for from in [
                        o,
                        center + n * (0.5 * radius.abs()),
                        center + n * (4.0 * radius.abs()),
                    ] {
                        let ray = Ray::new(from, d * 3.0, 0.0);
                        let ahead = s.roots(&ray).and_then(|r| r.crossing(0.0, f32::INFINITY));
                        if s.departs(&ray) {
                            assert!(ahead.is_none(), "{s:?} {ray:?} departs but meets {ahead:?}");
                        }
                    }
                    let leaving = Ray::new(o, d, 0.0);
                    if d.dot(n) > 1e-3 {
                        assert!(s.departs(&leaving), "{s:?} {leaving:?} leaves outwards");
                        left += 1;
                    }
                }
            }
        }
        assert!(left > 1000, "{left}");
    }

    #[test]
    fn uv_is_taken_from_the_hit_normal_when_read() {
        let s = Sphere {
            center: Vec3::new(3.0, -1.0, 2.0),
            radius: 0.5,
        };
        // From +x onto the equator: u = 1/2, v = 1/2; from above onto the
        // north pole: v = 1; from -z: u = 3/4.
        for (from, want) in [
            (Vec3::X, Vec2::new(0.5, 0.5)),
            (Vec3::NEG_Z, Vec2::new(0.75, 0.5)),
        ] {
            let ray = Ray::new(s.center + 4.0 * from, -from, 0.0);
            let h = s
                .intersect(&ray, 0.0, f32::INFINITY)
                .expect("aimed at centre");
            assert!((h.uv.get() - want).length() < 1e-6, "{from}: {:?}", h.uv);
        }
        let down = Ray::new(s.center + 4.0 * Vec3::Y, Vec3::NEG_Y, 0.0);
        let h = s
            .intersect(&down, 0.0, f32::INFINITY)
            .expect("aimed at centre");
        assert!((h.uv.get().y - 1.0).abs() < 1e-6, "{:?}", h.uv);
    }

    #[test]
    fn bounds_contain_surface_points() {
        let s = Sphere {
            center: Vec3::new(1e3, -5.0, 2.0),
            radius: 7.0,
        };
        let b = s.bounds();
        for n in dirs() {
            assert!(b.contains(s.center + n * s.radius * 0.999_99));
        }
    }
}
