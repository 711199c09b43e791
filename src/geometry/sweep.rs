//! Conservative bounds of a moving object over a time interval.

use crate::scene::Motion;

use super::Aabb;

/// A box that contains `local` (an object-space box) transformed by
/// `motion.matrix_at(t)` for every `t` in `[t0, t1]`.
pub fn swept_bounds(motion: &Motion, local: &Aabb, t0: f32, t1: f32) -> Aabb {
    let _ = (motion, local, t0, t1);
    unimplemented!("owned by the motion work")
}
