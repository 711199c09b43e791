//! The analytic primitives in their object space: each one knows its bounds
//! and its nearest intersection with a ray, reported as a [`ShapeHit`] with
//! the outward normal, either at once (`intersect`) or in two steps: a
//! [`Crossing`] per candidate (`crossing`), the surface data for the nearest
//! one only (`surface`).

pub mod cuboid;
pub mod plane;
pub mod quad;
pub mod rect;
pub mod sphere;
pub mod triangle;
pub mod turned_sphere;

use glam::{BVec3, Vec3};

use super::uv::SurfaceUv;

pub use cuboid::Cuboid;
pub use plane::Plane;
pub use quad::Quad;
pub use rect::Rect;
pub use sphere::Sphere;
pub use triangle::Triangle;
pub use turned_sphere::TurnedSphere;

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

/// What a shape's test yields while a hierarchy is walked: the distance
/// that orders the hits, and the few numbers its surface data is computed
/// from. The full [`ShapeHit`] is built once, for the nearest crossing, by
/// the shape's `surface` from the same inputs with the same formulas, so it
/// is the hit the shape's `intersect` returns, bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub t: f32,
    /// Shape-specific: a sphere's distance along the unit direction and
    /// the direction's length, a quad's `(u, v)`, a triangle's barycentrics,
    /// a box's face axis and side (a rect's surface needs only `t`).
    pub data: Vec3,
}

/// The lanes equal to `axis`: for setting a face's coordinate, normal and
/// error lane by a select. Writing one lane of a vector by a computed index
/// goes through memory, and reading the vector back stalls on that store.
#[inline]
pub fn axis_lane(axis: usize) -> BVec3 {
    BVec3::new(axis == 0, axis == 1, axis == 2)
}
