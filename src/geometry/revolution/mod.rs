//! Surfaces of revolution of a Bézier profile about the y axis: tessellation
//! (mesh mode) and analytic intersection by Newton iteration.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Vec2, Vec3};

use crate::geometry::{Aabb, Ray};
use crate::scene::{Bezier, MeshData};

/// A hit on a surface of revolution, in its object space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    pub t: f32,
    pub point: Vec3,
    /// Unit normal pointing away from the axis side of the profile.
    pub normal: Vec3,
    /// (angle / 2π, curve parameter).
    pub uv: Vec2,
}

/// The analytic surface of revolution.
pub struct RevolutionSurface {
    newton_failures: AtomicU64,
}

impl RevolutionSurface {
    pub fn new(curve: &Bezier, resolution: u32, tolerance: f32) -> RevolutionSurface {
        let _ = (curve, resolution, tolerance);
        unimplemented!("owned by the revolution work")
    }

    pub fn bounds(&self) -> Aabb {
        unimplemented!("owned by the revolution work")
    }

    /// The nearest hit with `t` in `(t_min, t_max)`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
        let _ = (ray, t_min, t_max);
        unimplemented!("owned by the revolution work")
    }

    /// How many intersections fell back because Newton did not converge.
    pub fn newton_failures(&self) -> u64 {
        self.newton_failures.load(Ordering::Relaxed)
    }
}

/// The surface as a triangle mesh with `resolution` segments along the curve
/// and around the axis, uv = (angle / 2π, curve parameter).
pub fn tessellate(curve: &Bezier, resolution: u32) -> MeshData {
    let _ = (curve, resolution);
    unimplemented!("owned by the revolution work")
}
