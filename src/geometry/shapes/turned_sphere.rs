//! A sphere placed by a rotation (with uniform scale and translation) baked
//! into its centre and radius (geometry/bake.rs), which keeps the rotation
//! only to turn its texture coordinates with it: it is intersected as a
//! plain sphere in its parent's space, and its uv seam and poles stay where
//! the rotation put them.

use glam::Quat;

use super::{Crossing, ShapeHit, Sphere};
use crate::geometry::uv::SurfaceUv;
use crate::geometry::{Aabb, Ray};

/// A sphere whose uv frame is turned by `to_object` (parent → object).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnedSphere {
    pub sphere: Sphere,
    /// The inverse of the rotation that placed the sphere.
    pub to_object: Quat,
}

impl TurnedSphere {
    pub fn bounds(&self) -> Aabb {
        self.sphere.bounds()
    }

    /// The sphere's hit with uv read in its own (unturned) frame.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<ShapeHit> {
        let c = self.sphere.crossing(ray, t_min, t_max)?;
        Some(self.surface(ray, &c))
    }

    /// The sphere's hit at its crossing `c`, with uv turned as above.
    #[inline]
    pub fn surface(&self, ray: &Ray, c: &Crossing) -> ShapeHit {
        let mut h = self.sphere.surface(ray, c);
        if let SurfaceUv::Sphere(n) = h.uv {
            h.uv = SurfaceUv::Sphere(self.to_object * n);
        }
        h
    }
}
