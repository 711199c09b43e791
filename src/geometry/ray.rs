//! Rays with a time, and spawning rays off surfaces without self-intersection.

use glam::Vec3;

/// A ray `origin + t·dir` at time `time` (for motion blur). `dir` need not be
/// unit length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub time: f32,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3, time: f32) -> Ray {
        Ray { origin, dir, time }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// Moves a surface point off the surface along the geometric normal `n`, to
/// the side that `dir` leaves towards, by a margin proportional to the
/// point's magnitude (the rounding error of a computed hit point grows with
/// it), so that a ray spawned there does not re-hit the surface it left.
#[inline]
pub fn offset_origin(p: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    const RELATIVE: f32 = 1.0 / (1 << 16) as f32;
    const ABSOLUTE: f32 = 1e-30;
    let margin = p.abs().max_element() * RELATIVE + ABSOLUTE;
    let offset = n * margin;
    if n.dot(dir) >= 0.0 {
        p + offset
    } else {
        p - offset
    }
}
