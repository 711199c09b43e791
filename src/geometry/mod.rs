//! Intersection: rays, bounding boxes, shapes, triangle meshes, surfaces of
//! revolution, transforms, motion, media and the BVH that holds them.

pub mod aabb;
pub mod bake;
pub mod build;
pub mod bvh;
pub mod emitter;
pub mod flat;
pub mod group;
pub mod hit;
pub mod instance;
pub mod leaf;
pub mod medium;
pub mod mesh;
pub mod object;
pub mod parts;
pub mod primitive;
pub mod primitives;
pub mod ray;
pub mod revolution;
pub mod segments;
pub mod shapes;
pub mod sphere_rays;
pub mod sweep;
pub mod tangents;
pub mod uv;

pub use aabb::Aabb;
pub use build::{BuildError, World};
pub use bvh::Bvh;
pub use hit::Hit;
pub use ray::Ray;
pub use tangents::Tangents;
pub use uv::SurfaceUv;
