//! A surface's derivatives ∂p/∂u and ∂p/∂v at a hit: the tangent frame that
//! normal and bump maps are read in. They are computed only for hits of a
//! material that reads them ([`crate::scene::MaterialId::needs_tangents`]),
//! after the nearest hit is known, so a scene without maps never computes
//! them: analytically for spheres, rects, parallelograms, boxes and planes,
//! from the corners and their (u, v) for triangles.

use glam::{Quat, Vec2, Vec3};

use super::primitive::Primitive;
use super::shapes::{Cuboid, Quad, Rect, ShapeHit, Sphere, TurnedSphere};

/// ∂p/∂u and ∂p/∂v of a surface at a point; both zero where the surface
/// has none (a revolved surface, a pole of a sphere, a triangle of
/// coincident uvs), and a material then builds its frame from the normal
/// alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangents {
    pub dpdu: Vec3,
    pub dpdv: Vec3,
}

impl Tangents {
    pub const NONE: Tangents = Tangents {
        dpdu: Vec3::ZERO,
        dpdv: Vec3::ZERO,
    };

    /// `self` unless either vector is zero or not finite.
    fn checked(self) -> Tangents {
        let ok = |v: Vec3| v.is_finite() && v != Vec3::ZERO;
        if ok(self.dpdu) && ok(self.dpdv) {
            self
        } else {
            Tangents::NONE
        }
    }

    /// Both vectors mapped by the linear map `f` (an instance's placement).
    pub fn map(self, f: impl Fn(Vec3) -> Vec3) -> Tangents {
        Tangents {
            dpdu: f(self.dpdu),
            dpdv: f(self.dpdv),
        }
    }
}

/// The tangents of a sphere of signed `radius` at unit normal `n` (in the
/// frame its uv are read in): u the angle about y, v from the south pole
/// ([`super::uv::sphere_uv`]).
fn sphere(radius: f32, n: Vec3) -> Tangents {
    use std::f32::consts::{PI, TAU};
    let s = (n.x * n.x + n.z * n.z).sqrt();
    if s < 1e-6 {
        return Tangents::NONE;
    }
    Tangents {
        dpdu: TAU * radius * Vec3::new(n.z, 0.0, -n.x),
        dpdv: PI * radius * Vec3::new(-n.y * n.x / s, s, -n.y * n.z / s),
    }
}

fn turned_sphere(s: &TurnedSphere, h: &ShapeHit) -> Tangents {
    let local = s.to_object * h.normal;
    let back: Quat = s.to_object.inverse();
    sphere(s.sphere.radius, local).map(|v| back * v)
}

fn rect(r: &Rect) -> Tangents {
    let axis = |i: u8, len: f32| {
        let mut v = Vec3::ZERO;
        v[i as usize] = len;
        v
    };
    Tangents {
        dpdu: axis(r.span[0], r.a.1 - r.a.0),
        dpdv: axis(r.span[1], r.b.1 - r.b.0),
    }
}

fn quad(q: &Quad) -> Tangents {
    Tangents {
        dpdu: q.edge_u,
        dpdv: q.edge_v,
    }
}

fn cuboid(b: &Cuboid, h: &ShapeHit) -> Tangents {
    let axis = h.normal.abs().max_position();
    let ext = b.max - b.min;
    let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut dpdu = Vec3::ZERO;
    let mut dpdv = Vec3::ZERO;
    dpdu[i] = ext[i];
    dpdv[j] = ext[j];
    Tangents { dpdu, dpdv }
}

/// The tangents of the triangle `p` whose corners have surface coordinates
/// `uv` (pbrt's solution of the 2 × 2 system of its edges).
pub fn triangle(p: [Vec3; 3], uv: [Vec2; 3]) -> Tangents {
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    if det == 0.0 {
        return Tangents::NONE;
    }
    let inv = 1.0 / det;
    Tangents {
        dpdu: (duv12.y * dp02 - duv02.y * dp12) * inv,
        dpdv: (duv02.x * dp12 - duv12.x * dp02) * inv,
    }
    .checked()
}

/// The tangents of a plane of unit normal `n`, whose uv run along
/// `n.any_orthonormal_pair()` (as [`super::shapes::Plane`] reads them).
pub fn plane(n: Vec3) -> Tangents {
    let (dpdu, dpdv) = n.any_orthonormal_pair();
    Tangents { dpdu, dpdv }
}

impl Primitive {
    /// The tangents at `h`, a hit of this primitive. Out of line: only
    /// hits of mapped materials ask.
    #[inline(never)]
    pub fn tangents(&self, h: &ShapeHit) -> Tangents {
        let t = match self {
            Primitive::Sphere(Sphere { radius, .. }) => sphere(*radius, h.normal),
            Primitive::TurnedSphere(s) => turned_sphere(s, h),
            Primitive::Rect(r) => rect(r),
            Primitive::Quad(q) => quad(q),
            Primitive::Cuboid(b) => cuboid(b, h),
            Primitive::Triangle(t) => {
                let [a, b, c] = t.v;
                Tangents {
                    dpdu: b - a,
                    dpdv: c - a,
                }
            }
        };
        t.checked()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::uv::SurfaceUv;
    use crate::geometry::Ray;

    /// A primitive's tangents are the derivatives of its point by its uv:
    /// moving the hit point by ε·dp/du along the surface changes u by ε,
    /// found by intersecting a ray along the normal there.
    #[test]
    fn tangents_are_the_derivatives_of_the_point_by_uv() {
        let quad = Quad::new(
            Vec3::new(0.2, 0.1, 0.3),
            Vec3::new(1.0, 0.2, 0.0),
            Vec3::new(-0.1, 1.3, 0.4),
            Vec3::new(0.0, -0.3, 1.0),
        )
        .expect("a parallelogram");
        let prims = [
            Primitive::Sphere(Sphere {
                center: Vec3::new(0.3, -0.2, 0.1),
                radius: 1.5,
            }),
            Primitive::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: -0.7,
            }),
            Primitive::TurnedSphere(TurnedSphere {
                sphere: Sphere {
                    center: Vec3::ZERO,
                    radius: 1.0,
                },
                to_object: Quat::from_rotation_x(0.7) * Quat::from_rotation_z(-0.3),
            }),
            Primitive::Rect(Rect::new(
                crate::scene::object::RectPlane::Xz,
                (-1.0, 2.0),
                (0.5, 1.5),
                0.3,
            )),
            Primitive::Quad(quad),
            Primitive::Cuboid(Cuboid {
                min: Vec3::new(-1.0, -0.5, -2.0),
                max: Vec3::new(1.0, 1.5, 0.5),
            }),
            Primitive::Triangle(crate::geometry::shapes::Triangle {
                v: [
                    Vec3::new(0.0, 0.0, 1.0),
                    Vec3::new(1.0, 0.2, 1.0),
                    Vec3::new(0.3, 1.0, 1.5),
                ],
            }),
        ];
        let mut r = crate::sampling::rng::numbers(7);
        let mut checked = 0;
        for p in prims {
            for _ in 0..200 {
                let target =
                    p.bounds().centroid() + Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 0.8;
                let origin = target + Vec3::new(r() - 0.5, r() - 0.5, 4.0 + r());
                let ray = Ray::new(origin, (target - origin).normalize(), 0.0);
                let Some(h) = p.intersect(&ray, 0.0, f32::INFINITY) else {
                    continue;
                };
                let t = p.tangents(&h);
                if t == Tangents::NONE {
                    continue;
                }
                let uv = |h: &ShapeHit| match h.uv {
                    SurfaceUv::At(uv) => uv,
                    SurfaceUv::Sphere(n) => crate::geometry::uv::sphere_uv(n),
                };
                let eps = 1e-3;
                for (d, which) in [(t.dpdu, Vec2::X), (t.dpdv, Vec2::Y)] {
                    let moved = h.point + eps * d;
                    let probe = Ray::new(moved + h.normal, -h.normal, 0.0);
                    let Some(h2) = p.intersect(&probe, 0.0, f32::INFINITY) else {
                        continue;
                    };
                    let du = uv(&h2) - uv(&h);
                    if du.x.abs() > 0.5 {
                        continue; // across a sphere's seam
                    }
                    let want = eps * which;
                    assert!(
                        (du - want).length() < 0.1 * eps,
                        "{p:?} at {}: uv moved {du}, want {want}",
                        h.point
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    #[test]
    fn triangle_tangents_follow_its_uvs_and_refuse_coincident_ones() {
        let p = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        ];
        let t = triangle(p, [Vec2::ZERO, Vec2::X, Vec2::Y]);
        assert_eq!(t.dpdu, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(t.dpdv, Vec3::new(0.0, 3.0, 0.0));
        // u runs down the image: dp/dv flips.
        let t = triangle(p, [Vec2::ZERO, Vec2::X, -Vec2::Y]);
        assert_eq!(t.dpdv, Vec3::new(0.0, -3.0, 0.0));
        assert_eq!(triangle(p, [Vec2::ONE; 3]), Tangents::NONE);
    }
}
