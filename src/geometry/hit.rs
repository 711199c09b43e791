//! The record of a ray/surface intersection. `facing` turns a shape's
//! outward-normal `ShapeHit` into the [`Hit`]
//! facing the ray; `facing_flat` does the same, one test shorter, where the
//! shading normal is the geometric one (every shape but an interpolated
//! mesh), with the same bits.

use glam::Vec3;

use super::emitter::LightId;
use super::ray::{offset_origin, SurfacePoint};
use super::shapes::ShapeHit;
use super::tangents::Tangents;
use super::uv::SurfaceUv;
use crate::scene::MaterialId;

/// Where and how a ray hit a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit.
    pub t: f32,
    pub point: Vec3,
    /// Bound of the absolute error of each component of `point`, for
    /// spawning rays off the surface ([`crate::geometry::ray::offset_origin`]).
    pub error: Vec3,
    /// Unit geometric normal, facing against the ray.
    pub geo_normal: Vec3,
    /// Unit shading normal (interpolated for meshes), on the same side as
    /// `geo_normal`.
    pub normal: Vec3,
    /// Surface coordinates, computed when a texture reads them.
    pub uv: SurfaceUv,
    /// Whether the ray hit the outward-facing side of the surface.
    pub front_face: bool,
    pub material: MaterialId,
    /// ∂p/∂u and ∂p/∂v, for a material that reads a tangent frame
    /// ([`MaterialId::needs_tangents`]); [`Tangents::NONE`] for any other.
    pub tangents: Tangents,
    /// The emitter hit, if the surface is one the world lists
    /// ([`crate::geometry::emitter::Emitters`]).
    pub light: LightId,
}

impl Hit {
    /// The origin of a ray leaving the surface in direction `dir`.
    #[inline]
    pub fn spawn_origin(&self, dir: Vec3) -> Vec3 {
        offset_origin(self.point, self.error, self.geo_normal, dir)
    }

    /// The hit as one end of a shadow segment.
    #[inline]
    pub fn surface_point(&self) -> SurfacePoint {
        SurfacePoint {
            point: self.point,
            error: self.error,
            normal: self.geo_normal,
        }
    }
}

/// [`facing`] for a hit whose shading normal is its geometric one: both
/// turned by the same sign are the same vector, whose dot product with
/// itself is never negative, so the test for an inward shading normal is
/// left out (the same `Hit`, bit for bit).
#[inline]
pub fn facing_flat(h: ShapeHit, dir: Vec3, material: MaterialId, light: LightId) -> Hit {
    let front_face = h.normal.dot(dir) < 0.0;
    let sign = if front_face { 1.0 } else { -1.0 };
    let geo_normal = h.normal * sign;
    Hit {
        t: h.t,
        point: h.point,
        error: h.error,
        geo_normal,
        normal: geo_normal,
        uv: h.uv,
        front_face,
        material,
        tangents: Tangents::NONE,
        light,
    }
}

/// [`facing_flat`] with the tangents `tangents` gives when `material`
/// reads them (a primitive's or a plane's, built only then).
#[inline(always)]
pub fn facing_flat_with(
    h: ShapeHit,
    dir: Vec3,
    material: MaterialId,
    light: LightId,
    tangents: impl FnOnce(&ShapeHit) -> Tangents,
) -> Hit {
    let mut hit = facing_flat(h, dir, material, light);
    if material.needs_tangents() {
        hit.tangents = tangents(&h);
    }
    hit
}

/// Turns an outward-normal hit into a [`Hit`] whose normals face the ray:
/// [`facing_flat`]'s, with the shading normal `shading` turned the same
/// way, unless that points into the surface.
#[inline]
pub fn facing(h: ShapeHit, shading: Vec3, dir: Vec3, material: MaterialId, light: LightId) -> Hit {
    let mut hit = facing_flat(h, dir, material, light);
    let normal = shading * if hit.front_face { 1.0 } else { -1.0 };
    hit.normal = if normal.dot(hit.geo_normal) < 0.0 {
        hit.geo_normal
    } else {
        normal
    };
    hit
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::rng::numbers;

    /// A hit whose shading normal is its geometric one faces the ray the
    /// same, bit for bit, without the test for an inward shading normal:
    /// unit, tiny, huge, zero and NaN normals, along and across the ray.
    #[test]
    fn a_flat_hit_faces_the_ray_as_any_hit_does() {
        let mut r = numbers(11);
        let mut v = || Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5);
        let mut normals = vec![
            Vec3::ZERO,
            Vec3::NAN,
            Vec3::new(1e-30, 0.0, -1e-30),
            Vec3::splat(1e30),
        ];
        normals.extend((0..2000).map(|k| v() * [1.0, 1e-20, 1e20][k % 3]));
        let bits = |h: &Hit| {
            let v = |v: Vec3| v.to_array().map(f32::to_bits);
            (v(h.geo_normal), v(h.normal), h.front_face)
        };
        for n in normals {
            for dir in [v(), n, -n, Vec3::X] {
                let h = ShapeHit {
                    t: 1.0,
                    point: Vec3::ONE,
                    error: Vec3::ZERO,
                    normal: n,
                    uv: SurfaceUv::At(glam::Vec2::ZERO),
                };
                let any = facing(h, h.normal, dir, MaterialId(3), LightId::NONE);
                let flat = facing_flat(h, dir, MaterialId(3), LightId::NONE);
                assert_eq!(bits(&flat), bits(&any), "normal {n}, dir {dir}");
            }
        }
    }
}
