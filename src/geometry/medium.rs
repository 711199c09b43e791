//! Constant-density participating media inside a closed boundary: a ray
//! scatters at an exponentially distributed distance while inside, any number
//! of times, including rays that start inside.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::object::Geometry;
use super::{Aabb, Hit, Ray};
use crate::render::rng::Rng;
use crate::scene::MaterialId;

/// A homogeneous medium filling `boundary`.
pub struct Medium {
    pub boundary: Arc<Geometry>,
    pub density: f32,
    /// The phase function (an isotropic material).
    pub material: MaterialId,
}

/// Boundary crossings looked for per ray before giving up (a ray weaving
/// through a non-convex boundary).
const MAX_SEGMENTS: usize = 16;

impl Medium {
    pub fn bounds(&self) -> Aabb {
        self.boundary.bounds()
    }

    /// A scattering event with `t` in `(t_min, t_max)`, if the ray scatters
    /// inside the boundary before `t_max`.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32, rng: &mut Rng) -> Option<Hit> {
        if self.density <= 0.0 {
            return None;
        }
        let len = ray.dir.length();
        let mut t = t_min;
        for _ in 0..MAX_SEGMENTS {
            let first = self.boundary.intersect(ray, t, f32::INFINITY, rng)?;
            let (entry, exit) = if first.front_face {
                let after = step_past(ray, first.t);
                match self.boundary.intersect(ray, after, f32::INFINITY, rng) {
                    Some(h) => (first.t, h.t),
                    None => return None,
                }
            } else {
                (t, first.t)
            };
            if entry >= t_max {
                return None;
            }
            let exit = exit.min(t_max);
            let distance = -rng.next_f32().max(f32::MIN_POSITIVE).ln() / self.density;
            let t_hit = entry + distance / len;
            if t_hit < exit {
                return Some(Hit {
                    t: t_hit,
                    point: ray.at(t_hit),
                    // A point in a volume: no surface to leave.
                    error: Vec3::ZERO,
                    geo_normal: Vec3::X,
                    normal: Vec3::X,
                    uv: Vec2::ZERO,
                    front_face: true,
                    material: self.material,
                });
            }
            if exit >= t_max {
                return None;
            }
            t = step_past(ray, exit);
        }
        None
    }
}

/// A ray parameter just past `t`, far enough that the surface at `t` is not
/// found again.
fn step_past(ray: &Ray, t: f32) -> f32 {
    let scale = ray.at(t).abs().max_element() / ray.dir.length();
    t + (t.abs() + scale) * 1e-5
}
