//! A hit's surface coordinates (u, v), and a sphere's (u, v) of its unit
//! normal. Shapes make them and hits carry them, so they sit below both.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

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

/// (u, v) of a unit vector: u the angle about y from −x, v from the south pole.
pub fn sphere_uv(n: Vec3) -> Vec2 {
    let theta = (-n.y).clamp(-1.0, 1.0).acos();
    let phi = (-n.z).atan2(n.x) + PI;
    Vec2::new(phi / (2.0 * PI), theta / PI)
}
