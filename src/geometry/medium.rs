//! Constant-density participating media inside a closed boundary. Geometry
//! only reports where a ray runs inside a medium (its boundary segments,
//! including rays that start inside); the integrator samples the free-flight
//! distance along them (as pbrt-v4 does), so intersection draws no random
//! numbers.

use std::sync::Arc;

use arrayvec::ArrayVec;

use super::object::Geometry;
use super::{Aabb, Ray};
use crate::scene::MaterialId;

/// A homogeneous medium filling `boundary`.
pub struct Medium {
    pub boundary: Arc<Geometry>,
    pub density: f32,
    /// The phase function (an isotropic material).
    pub material: MaterialId,
}

/// Boundary crossings looked for per ray before giving up (a ray weaving
/// through a non-convex boundary), and the segments one query can hold.
const MAX_SEGMENTS: usize = 16;

/// A stretch `t0..t1` of a ray inside a medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumSegment {
    pub t0: f32,
    pub t1: f32,
    pub density: f32,
    pub material: MaterialId,
}

/// The medium segments a query found, in a fixed-capacity array (no
/// allocation, and not zero-filled: a query that meets no medium writes
/// nothing); segments past its capacity are dropped, as crossings past
/// `MAX_SEGMENTS` always were.
#[derive(Clone, Debug, Default)]
pub struct MediumSegments {
    items: ArrayVec<MediumSegment, MAX_SEGMENTS>,
}

impl MediumSegments {
    #[inline]
    pub fn clear(&mut self) {
        self.items.clear();
    }

    #[inline]
    fn push(&mut self, s: MediumSegment) {
        let _ = self.items.try_push(s);
    }

    /// The segments found.
    #[inline]
    pub fn as_slice(&self) -> &[MediumSegment] {
        &self.items
    }
}

impl Medium {
    pub fn bounds(&self) -> Aabb {
        self.boundary.bounds()
    }

    /// Adds to `out` every stretch of the ray inside the boundary with `t`
    /// in `(t_min, t_max)`.
    pub fn segments(&self, ray: &Ray, t_min: f32, t_max: f32, out: &mut MediumSegments) {
        if self.density <= 0.0 {
            return;
        }
        let mut t = t_min;
        for _ in 0..MAX_SEGMENTS {
            let Some(first) = self.boundary.intersect(ray, t, f32::INFINITY) else {
                return;
            };
            let (entry, exit) = if first.front_face {
                let after = step_past(ray, first.t);
                match self.boundary.intersect(ray, after, f32::INFINITY) {
                    Some(h) => (first.t, h.t),
                    None => return,
                }
            } else {
                (t, first.t)
            };
            if entry >= t_max {
                return;
            }
            out.push(MediumSegment {
                t0: entry,
                t1: exit.min(t_max),
                density: self.density,
                material: self.material,
            });
            if exit >= t_max {
                return;
            }
            t = step_past(ray, exit);
        }
    }
}

/// A ray parameter just past `t`, far enough that the surface at `t` is not
/// found again.
fn step_past(ray: &Ray, t: f32) -> f32 {
    let scale = ray.at(t).abs().max_element() / ray.dir.length();
    t + (t.abs() + scale) * 1e-5
}
