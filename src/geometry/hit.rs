//! The record of a ray/surface intersection.

use glam::{Vec2, Vec3};

use super::emitter::LightId;
use super::ray::{offset_origin, SurfacePoint};
use super::shapes::sphere::sphere_uv;
use super::shapes::ShapeHit;
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

/// Turns an outward-normal hit into a [`Hit`] whose normals face the ray.
#[inline]
pub fn facing(h: ShapeHit, shading: Vec3, dir: Vec3, material: MaterialId, light: LightId) -> Hit {
    let front_face = h.normal.dot(dir) < 0.0;
    let sign = if front_face { 1.0 } else { -1.0 };
    let geo_normal = h.normal * sign;
    let mut normal = shading * sign;
    if normal.dot(geo_normal) < 0.0 {
        normal = geo_normal;
    }
    Hit {
        t: h.t,
        point: h.point,
        error: h.error,
        geo_normal,
        normal,
        uv: h.uv,
        front_face,
        material,
        light,
    }
}

/// A hit's (u, v), kept in the form its shape found cheapest: most shapes
/// have it at hand, but a sphere's needs `acos` and `atan2`, so a sphere hit
/// keeps its unit normal and the angles are taken only when a texture reads
/// uv from the one hit that is shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceUv {
    At(Vec2),
    /// The sphere's unit normal in its object space (see [`sphere_uv`]).
    Sphere(Vec3),
}

impl SurfaceUv {
    #[inline]
    pub fn get(self) -> Vec2 {
        match self {
            SurfaceUv::At(uv) => uv,
            SurfaceUv::Sphere(n) => sphere_uv(n),
        }
    }
}

impl From<Vec2> for SurfaceUv {
    #[inline]
    fn from(uv: Vec2) -> SurfaceUv {
        SurfaceUv::At(uv)
    }
}
