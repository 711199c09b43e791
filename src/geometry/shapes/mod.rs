//! The analytic primitives in their object space: each one knows its bounds
//! and its nearest intersection with a ray, reported as a [`ShapeHit`] with
//! the outward normal.

pub mod cuboid;
pub mod plane;
pub mod rect;
pub mod sphere;
pub mod triangle;

use glam::Vec3;

use super::hit::SurfaceUv;

pub use cuboid::Cuboid;
pub use plane::Plane;
pub use rect::Rect;
pub use sphere::Sphere;
pub use triangle::Triangle;

/// A ray/shape intersection before facing is decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    pub point: Vec3,
    /// Bound of the absolute error of each component of `point`.
    pub error: Vec3,
    /// Unit outward normal.
    pub normal: Vec3,
    pub uv: SurfaceUv,
}
