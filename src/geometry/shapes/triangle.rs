//! Watertight ray/triangle intersection (Woop, Benthin and Wald 2013): the
//! ray is sheared onto the +z axis once, and edge functions decide coverage,
//! falling back to f64 when one is exactly zero, so rays aimed at a shared
//! edge or vertex of a closed mesh hit at least one of its triangles.
//! The float edge functions have the exact sign or are 0 (rounding is
//! monotonic), so coverage is decided exactly for the sheared, rounded
//! vertices, which every triangle of a mesh shares. A ray that only touches
//! a silhouette vertex or edge may still miss: after rounding it passes
//! beside the surface without entering it, which is no hole.

use std::ops::{Add, Mul, Sub};

use glam::{DVec2, Vec2, Vec3, Vec3A};

use super::{Crossing, ShapeHit};
use crate::geometry::ray::gamma;
use crate::geometry::{Aabb, Ray};

/// A single triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub v: [Vec3; 3],
}

/// The per-ray part of the watertight test: the permutation putting the
/// ray's dominant axis last (`axes`: x', y', then z') and the shear aligning
/// it with +z, so that a point `p` maps to `x' = (p[kx] − o[kx]) +
/// sx·(p[kz] − o[kz])`, `y' = (p[ky] − o[ky]) + sy·(p[kz] − o[kz])` and
/// `z' = sz·(p[kz] − o[kz])`: two operations per coordinate, the same
/// values as the rows of the matrix they form (whose other terms are exact
/// zeros), for points stored by coordinate (a leaf's vertex rows) and one
/// at a time alike.
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    axes: [Axis; 3],
    /// The origin's coordinates on `axes`.
    origin_on_axes: [f32; 3],
    /// `(sx, sy, sz)`.
    pub shear: [f32; 3],
}

/// A coordinate axis. Being one of three values, it picks from a
/// three-element array with no bounds check (a `usize` axis needed a check
/// or a `% 3` at every leaf a ray tests).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// The axis after this one, cyclically (x → y → z → x).
    fn next(self) -> Axis {
        match self {
            Axis::X => Axis::Y,
            Axis::Y => Axis::Z,
            Axis::Z => Axis::X,
        }
    }

    /// The element of `values` on this axis.
    #[inline(always)]
    fn of<T: Copy>(self, values: [T; 3]) -> T {
        values[self as usize]
    }
}

/// Where a ray crosses a triangle: distance and barycentric weights of the
/// three vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub bary: Vec3,
}

impl ShearedRay {
    /// Built from one-hot axis vectors and one division of three lanes,
    /// without indexing by the axes (indexing a vector by a computed lane
    /// went through the stack and stalled on the store): the shear is
    /// `(−d[kx], −d[ky], 1) / d[kz]`, the indexed construction's value
    /// (a zero may differ in sign).
    pub fn new(ray: &Ray) -> ShearedRay {
        let d = ray.dir;
        let a = d.abs();
        // The first largest |component|, as `Vec3::max_position` picks it.
        let y_over_x = a.y > a.x;
        let z_wins = a.z > if y_over_x { a.y } else { a.x };
        let y_wins = y_over_x && !z_wins;
        let one = |b: bool| f32::from(u8::from(b));
        let ez = Vec3::new(one(!y_wins && !z_wins), one(y_wins), one(z_wins));
        let ex = Vec3::new(ez.z, ez.x, ez.y);
        let ey = Vec3::new(ex.z, ex.x, ex.y);
        // A one-hot dot product is the component itself, exactly.
        let dz = d.dot(ez);
        let (ex, ey) = if dz < 0.0 { (ey, ex) } else { (ex, ey) };
        let q = Vec3A::new(-d.dot(ex), -d.dot(ey), 1.0) / dz;
        let kz = match (z_wins, y_wins) {
            (true, _) => Axis::Z,
            (false, true) => Axis::Y,
            (false, false) => Axis::X,
        };
        let (kx, ky) = (kz.next(), kz.next().next());
        let (kx, ky) = if dz < 0.0 { (ky, kx) } else { (kx, ky) };
        let o = ray.origin;
        ShearedRay {
            axes: [kx, ky, kz],
            origin_on_axes: [o.dot(ex), o.dot(ey), o.dot(ez)],
            shear: q.to_array(),
        }
    }

    /// A vertex `p` (one coordinate, or one lane row of coordinates, per
    /// axis; `splat` makes a ray value one such) on the permuted, sheared
    /// axes: `(x', y')`, and its offset `p[kz] − o[kz]` along the dominant
    /// axis, which `z' = sz·(p[kz] − o[kz])` scales once a hit is likely.
    /// The scalar test and a leaf's four lanes both map vertices here, so
    /// they round alike.
    #[inline(always)]
    pub fn project<T>(&self, p: [T; 3], splat: impl Fn(f32) -> T) -> ((T, T), T)
    where
        T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>,
    {
        let [kx, ky, kz] = self.axes;
        let [ox, oy, oz] = self.origin_on_axes;
        let [sx, sy, _] = self.shear;
        let (x, y, z) = (
            kx.of(p) - splat(ox),
            ky.of(p) - splat(oy),
            kz.of(p) - splat(oz),
        );
        ((x + splat(sx) * z, y + splat(sy) * z), z)
    }

    /// The hit on triangle `p` with `t` in `(t_min, t_max)`.
    #[inline(always)]
    pub fn intersect(&self, p: [Vec3; 3], t_min: f32, t_max: f32) -> Option<TriangleHit> {
        let project = |v: Vec3| self.project(v.to_array(), |x| x);
        let ((a, a_z), (b, b_z), (c, c_z)) = (project(p[0]), project(p[1]), project(p[2]));
        let xy = [a, b, c];
        let [a, b, c] = xy.map(|(x, y)| Vec2::new(x, y));
        let mut u = c.x * b.y - c.y * b.x;
        let mut v = a.x * c.y - a.y * c.x;
        let mut w = b.x * a.y - b.y * a.x;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let [a, b, c] = xy.map(|(x, y)| DVec2::new(x as f64, y as f64));
            u = (c.x * b.y - c.y * b.x) as f32;
            v = (a.x * c.y - a.y * c.x) as f32;
            w = (b.x * a.y - b.y * a.x) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let sz = self.shear[2];
        let z = [sz * a_z, sz * b_z, sz * c_z];
        let t_scaled = u * z[0] + v * z[1] + w * z[2];
        let mut t = t_scaled / det;
        if !t_scaled.is_finite() {
            // Coordinates past about 1e12 overflow the f32 product (an area
            // times a distance); f64 holds it up to the evaluator's limit.
            let f = |x: f32| x as f64;
            let exact = f(u) * f(z[0]) + f(v) * f(z[1]) + f(w) * f(z[2]);
            t = (exact / f(det)) as f32;
        }
        if !(t > t_min && t < t_max) {
            return None;
        }
        Some(TriangleHit {
            t,
            bary: Vec3::new(u, v, w) / det,
        })
    }
}

impl TriangleHit {
    /// The error bound of the point `bary · p` (pbrt-v4's barycentric
    /// reconstruction bound).
    #[inline]
    pub fn error(&self, p: [Vec3; 3]) -> Vec3 {
        let w = self.bary;
        gamma(7) * ((w.x * p[0]).abs() + (w.y * p[1]).abs() + (w.z * p[2]).abs())
    }
}

/// The unit normal of the counter-clockwise triangle `a b c`, or `None` if
/// it is degenerate. The f32 cross product's squared length overflows for
/// edges above about 2e9 units (and underflows below about 1e-10); those
/// are normalized in f64, so a triangle's normal does not depend on its
/// scale.
#[inline]
pub fn unit_normal(a: Vec3, b: Vec3, c: Vec3) -> Option<Vec3> {
    (b - a).cross(c - a).try_normalize().or_else(|| {
        let [a, b, c] = [a, b, c].map(|p| p.as_dvec3());
        (b - a).cross(c - a).try_normalize().map(|n| n.as_vec3())
    })
}

impl Triangle {
    pub fn bounds(&self) -> Aabb {
        let [a, b, c] = self.v;
        Aabb::new(a.min(b).min(c), a.max(b).max(c))
    }

    /// The hit with `t` in `(t_min, t_max)`; the outward normal follows the
    /// counter-clockwise winding, uv are the barycentrics of vertices 1, 2.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let c = self.crossing(ray, t_min, t_max)?;
        Some(self.surface(&c))
    }

    /// The crossing with `t` in `(t_min, t_max)`; its data holds the
    /// barycentrics.
    #[inline]
    pub fn crossing(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Crossing> {
        let h = ShearedRay::new(ray).intersect(self.v, t_min, t_max)?;
        Some(Crossing {
            t: h.t,
            data: h.bary,
        })
    }

    /// The hit at crossing `c`, as [`Triangle::intersect`] has it.
    #[inline]
    pub fn surface(&self, c: &Crossing) -> ShapeHit {
        let h = TriangleHit {
            t: c.t,
            bary: c.data,
        };
        let [a, b, c] = self.v;
        ShapeHit {
            t: h.t,
            point: h.bary.x * a + h.bary.y * b + h.bary.z * c,
            error: h.error([a, b, c]),
            normal: unit_normal(a, b, c).unwrap_or(Vec3::Y),
            uv: Vec2::new(h.bary.y, h.bary.z).into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ray::offset_origin;

    /// The axes and shear as first written: the axes found by
    /// `max_position`, each value found by indexing with them.
    fn indexed(dir: Vec3) -> ([usize; 3], [f32; 3]) {
        let kz = dir.abs().max_position();
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = [-(dir[kx] / dir[kz]), -(dir[ky] / dir[kz]), 1.0 / dir[kz]];
        ([kx, ky, kz], shear)
    }

    #[test]
    fn the_shear_is_the_indexed_construction() {
        let mut next = crate::sampling::rng::numbers(7);
        let mut dirs: Vec<Vec3> = (0..20_000)
            .map(|_| Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5))
            .collect();
        // Ties between the largest components, signed zeros and the axes.
        for s in [1.0f32, -1.0] {
            for (x, y, z) in [
                (1.0, 1.0, 0.5),
                (1.0, -1.0, 1.0),
                (0.5, 1.0, -1.0),
                (1.0, 1.0, 1.0),
            ] {
                dirs.push(Vec3::new(x, y, z) * s);
            }
            dirs.extend([Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(-0.0, 0.0, 1.0)].map(|d| d * s));
        }
        for dir in dirs {
            let origin = Vec3::new(next(), -next(), next()) * 100.0;
            let got = ShearedRay::new(&Ray::new(origin, dir, 0.0));
            let (axes, shear) = indexed(dir);
            assert_eq!(got.axes.map(|a| a as usize), axes, "{dir}");
            // Equal as numbers: a zero shear may have either sign (the
            // one-hot dot of `(−0, 0, 1)` is +0), which changes no
            // comparison the test makes.
            assert_eq!(got.shear, shear, "{dir}");
            assert_eq!(got.origin_on_axes, axes.map(|k| origin[k]), "{dir}");
        }
    }

    #[test]
    fn hits_interior_misses_outside_and_degenerate() {
        let tri = Triangle {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        };
        let h = tri
            .intersect(
                &Ray::new(Vec3::new(0.25, 0.25, 2.0), Vec3::NEG_Z, 0.0),
                0.0,
                f32::INFINITY,
            )
            .expect("hits");
        assert!((h.t - 2.0).abs() < 1e-6);
        assert!((h.point - Vec3::new(0.25, 0.25, 0.0)).length() < 1e-6);
        assert_eq!(h.normal, Vec3::Z);
        let miss = Ray::new(Vec3::new(0.75, 0.75, 2.0), Vec3::NEG_Z, 0.0);
        assert!(tri.intersect(&miss, 0.0, f32::INFINITY).is_none());
        let flat = Triangle {
            v: [Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
        };
        let r = Ray::new(Vec3::new(0.5, 0.0, 1.0), Vec3::NEG_Z, 0.0);
        assert!(flat.intersect(&r, 0.0, f32::INFINITY).is_none());
        let parallel = Ray::new(Vec3::new(-1.0, 0.25, 0.0), Vec3::X, 0.0);
        assert!(tri.intersect(&parallel, 0.0, f32::INFINITY).is_none());
    }

    #[test]
    fn leaving_rays_do_not_rehit_far_from_origin() {
        let o = Vec3::splat(1e5);
        let tri = Triangle {
            v: [o, o + Vec3::X * 3.0, o + Vec3::Y * 3.0],
        };
        let p = o + Vec3::new(1.0, 1.0, 0.0);
        let h = tri
            .intersect(&Ray::new(p + Vec3::Z * 7.0, Vec3::NEG_Z, 0.0), 0.0, 1e9)
            .expect("hits");
        let p = h.point;
        for d in [
            Vec3::Z,
            Vec3::new(1.0, 0.0, 1e-3),
            Vec3::new(-0.5, 0.3, 0.2),
        ] {
            let from = offset_origin(p, h.error, Vec3::Z, d);
            assert!(tri
                .intersect(&Ray::new(from, d, 0.0), 0.0, f32::INFINITY)
                .is_none());
            let from = offset_origin(p, h.error, Vec3::Z, -d);
            assert!(tri
                .intersect(&Ray::new(from, -d, 0.0), 0.0, f32::INFINITY)
                .is_none());
        }
    }
}
