//! The fallback when Newton does not converge: de Casteljau subdivision of
//! the piece until its annular box is below the tolerance, then the box's
//! entry point along the ray is the hit (the "shell hit" refined to the
//! tolerance). Bounded by a visit budget so a ray running along the surface
//! cannot make it explode.

use glam::DVec2;

use super::shell::{AnnularBox, AxisRay};
use crate::scene::curve::split;

const MAX_VISITS: u32 = 2048;

/// The nearest `(s, t)` with `t` in `[lo, hi]` where the ray meets a box of
/// size below `tolerance` around the piece `points` over `[s0, s1]`.
pub fn subdivide(
    ray: &AxisRay,
    points: &[DVec2],
    (s0, s1): (f64, f64),
    (lo, hi): (f64, f64),
    tolerance: f64,
) -> Option<(f64, f64)> {
    let mut best: Option<(f64, f64)> = None;
    let mut visits = 0;
    let mut stack = vec![(points.to_vec(), s0, s1)];
    while let Some((pts, a, b)) = stack.pop() {
        visits += 1;
        if visits > MAX_VISITS {
            break;
        }
        let limit = best.map_or(hi, |(_, t)| t);
        let bounds = AnnularBox::of_control_points(&pts, 0.0);
        let Some(entry) = bounds.intervals(ray, lo, limit).first_entry() else {
            continue;
        };
        if bounds.size() <= tolerance || b - a < 1e-12 {
            best = Some((0.5 * (a + b), entry));
            continue;
        }
        let (left, right) = split(&pts, 0.5);
        let mid = 0.5 * (a + b);
        let (l, r) = ((left, a, mid), (right, mid, b));
        let near_left = AnnularBox::of_control_points(&l.0, 0.0)
            .intervals(ray, lo, limit)
            .first_entry()
            .unwrap_or(f64::INFINITY)
            <= AnnularBox::of_control_points(&r.0, 0.0)
                .intervals(ray, lo, limit)
                .first_entry()
                .unwrap_or(f64::INFINITY);
        if near_left {
            stack.push(r);
            stack.push(l);
        } else {
            stack.push(l);
            stack.push(r);
        }
    }
    best
}
