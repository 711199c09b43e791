//! The fallback when Newton finds no root in a span: de Casteljau
//! subdivision of the piece that settles every sub-piece — free of
//! crossings (its annular box misses the ray's span, or the crossing
//! polynomial keeps one sign on it), holding exactly one crossing (bracketed
//! and solved), or, once its box is below a thousandth of the tolerance,
//! Newton from inside it. What none of these settles (a ray touching the
//! surface that closely, or the visit budget running out) is unverified.
//! Nearest sub-piece first; the visit budget keeps a ray running along the
//! surface from making it explode.

use glam::DVec2;

use super::meridian::{bracketed_root, ray_distance, signs, Signs, Weights};
use super::newton::{self, residual, Window};
use super::profile::Profile;
use super::shell::{AnnularBox, AxisRay};
use crate::scene::curve::split;

const MAX_VISITS: u32 = 2048;

/// A sub-piece whose box is below this fraction of the tolerance is not
/// subdivided further: the ray passes that close to the surface.
const LEAF: f64 = 1e-3;

/// What the fallback established about a span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Verdict {
    /// No crossing with `t` in the span.
    Miss,
    /// The nearest crossing in the span, proven (a sign change of the
    /// crossing polynomial, or a converged Newton run) and located to the
    /// tolerance.
    Hit { s: f64, t: f64 },
    /// Not settled: the nearest point found where the ray passes within the
    /// tolerance of the surface, if any.
    Unverified(Option<(f64, f64)>),
}

/// Settles the piece with control points `points` over the window's
/// parameter range, for `t` in the window's `[t0, t1]`; `known` is the
/// sign pattern of the whole piece, which the caller has computed.
pub fn settle(
    profile: &Profile,
    weights: &Weights,
    ray: &AxisRay,
    points: &[DVec2],
    w: &Window,
    known: Signs,
) -> Verdict {
    // A piece with one crossing is settled without the walk's allocations;
    // where that crossing cannot be located, the walk subdivides at once.
    let first = match known {
        Signs::One => match one_crossing(profile, ray, points, w) {
            Some(verdict) => return verdict,
            None => Signs::Unknown,
        },
        other => other,
    };
    // (s, t, proven)
    let mut best: Option<(f64, f64, bool)> = None;
    let mut visits = 0;
    let mut stack = vec![(points.to_vec(), w.s0, w.s1)];
    while let Some((pts, a, b)) = stack.pop() {
        visits += 1;
        if visits > MAX_VISITS {
            return Verdict::Unverified(best.map(|(s, t, _)| (s, t)));
        }
        let limit = best.map_or(w.t1, |(_, t, _)| t);
        let bounds = AnnularBox::of_control_points(&pts, 0.0);
        let Some(entry) = bounds.intervals(ray, w.t0, limit).first_entry() else {
            continue;
        };
        let pattern = if visits == 1 {
            first
        } else {
            signs(ray, &pts, weights)
        };
        match pattern {
            Signs::Free => continue,
            Signs::One => {
                if let Some((s, t)) = located(profile, ray, (a, b), w.tolerance) {
                    if t >= w.t0 && t <= limit {
                        best = Some((s, t, true));
                    }
                    continue;
                }
            }
            Signs::Unknown => {}
        }
        if bounds.size() <= LEAF * w.tolerance || b - a < 1e-12 {
            let inside = Window {
                s0: a,
                s1: b,
                t1: limit,
                ..*w
            };
            best = match newton::solve(profile, ray, 0.5 * (a + b), entry, &inside) {
                Some((s, t)) if t >= w.t0 && t <= limit => Some((s, t, true)),
                _ => Some((0.5 * (a + b), entry, false)),
            };
            continue;
        }
        let (left, right) = split(&pts, 0.5);
        let mid = 0.5 * (a + b);
        let entry_of = |p: &[DVec2]| {
            AnnularBox::of_control_points(p, 0.0)
                .intervals(ray, w.t0, limit)
                .first_entry()
                .unwrap_or(f64::INFINITY)
        };
        let near_left = entry_of(&left) <= entry_of(&right);
        let (l, r) = ((left, a, mid), (right, mid, b));
        if near_left {
            stack.push(r);
            stack.push(l);
        } else {
            stack.push(l);
            stack.push(r);
        }
    }
    match best {
        None => Verdict::Miss,
        Some((s, t, true)) => Verdict::Hit { s, t },
        Some((s, t, false)) => Verdict::Unverified(Some((s, t))),
    }
}

/// The verdict on a whole piece known to hold exactly one crossing — what
/// the first visit of [`settle`]'s walk would find — or `None` where the
/// crossing cannot be located and the piece must be subdivided.
fn one_crossing(profile: &Profile, ray: &AxisRay, points: &[DVec2], w: &Window) -> Option<Verdict> {
    let bounds = AnnularBox::of_control_points(points, 0.0);
    if bounds.intervals(ray, w.t0, w.t1).first_entry().is_none() {
        return Some(Verdict::Miss);
    }
    let (s, t) = located(profile, ray, (w.s0, w.s1), w.tolerance)?;
    Some(if t >= w.t0 && t <= w.t1 {
        Verdict::Hit { s, t }
    } else {
        Verdict::Miss
    })
}

/// The one crossing in `[s0, s1]` and its ray distance, if bracketed and
/// on the surface to the tolerance.
fn located(
    profile: &Profile,
    ray: &AxisRay,
    span: (f64, f64),
    tolerance: f64,
) -> Option<(f64, f64)> {
    bracketed_root(profile, ray, span, 1e-3 * tolerance)
        .map(|s| (s, ray_distance(profile, ray, s)))
        .filter(|&(s, t)| residual(profile, ray, s, t) <= tolerance)
}
