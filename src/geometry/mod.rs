//! Intersection: rays, bounding boxes, shapes, triangle meshes, surfaces of
//! revolution, transforms, motion, media and the BVH that holds them.

pub mod aabb;
pub mod hit;
pub mod ray;
pub mod revolution;
pub mod sweep;

pub use aabb::Aabb;
pub use hit::Hit;
pub use ray::Ray;
