//! The record of a ray/surface intersection.

use glam::{Vec2, Vec3};

use super::ray::{offset_origin, SurfacePoint};
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
    pub uv: Vec2,
    /// Whether the ray hit the outward-facing side of the surface.
    pub front_face: bool,
    pub material: MaterialId,
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
