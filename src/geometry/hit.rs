//! The record of a ray/surface intersection.

use glam::{Vec2, Vec3};

use crate::scene::MaterialId;

/// Where and how a ray hit a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit.
    pub t: f32,
    pub point: Vec3,
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
