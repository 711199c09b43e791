//! Newton iteration on (curve parameter `s`, ray distance `t`) for
//! `x(s)² = ρ²(t)` and `y(s) = y(t)`, the seed's system, in `f64`.

use glam::DVec2;

use super::profile::Profile;
use super::shell::AxisRay;

/// The allowed window and the stopping rule of one Newton run.
#[derive(Clone, Copy, Debug)]
pub struct Window {
    pub s0: f64,
    pub s1: f64,
    pub t0: f64,
    pub t1: f64,
    /// Absolute geometric tolerance (object-space distance).
    pub tolerance: f64,
    pub max_iterations: u32,
}

/// Runs Newton from `(s, t)`: the root `(s, t)` if the final step and the
/// residual are both below the tolerance in object-space distance; `None`
/// if it leaves the window, meets a singular Jacobian or runs out of
/// iterations, which proves nothing about a root (the fallback settles it).
pub fn solve(
    profile: &Profile,
    ray: &AxisRay,
    mut s: f64,
    mut t: f64,
    w: &Window,
) -> Option<(f64, f64)> {
    let dir_len = ray.dir.length();
    let s_slack = 1e-3 * (w.s1 - w.s0);
    let t_slack = 1e-3 * (w.t1 - w.t0) + w.tolerance / dir_len;
    for _ in 0..w.max_iterations {
        let (p, d) = profile.eval(s);
        let rho2 = ray.radius2(t);
        let f1 = p.x * p.x - rho2;
        let f2 = p.y - (ray.origin.y + t * ray.dir.y);
        let j11 = 2.0 * p.x * d.x;
        let j12 = -2.0 * (ray.a * t + ray.b);
        let j21 = d.y;
        let j22 = -ray.dir.y;
        let det = j11 * j22 - j12 * j21;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let ds = (f1 * j22 - f2 * j12) / det;
        let dt = (j11 * f2 - j21 * f1) / det;
        s -= ds;
        t -= dt;
        if !(s.is_finite() && t.is_finite())
            || s < w.s0 - s_slack
            || s > w.s1 + s_slack
            || t < w.t0 - t_slack
            || t > w.t1 + t_slack
        {
            return None;
        }
        let step = ds.abs() * d.length() + dt.abs() * dir_len;
        if step < w.tolerance && residual(profile, ray, s, t) < w.tolerance {
            return Some((s.clamp(0.0, 1.0), t));
        }
    }
    None
}

/// The distance-like residual at `(s, t)`: the height mismatch and the
/// radius mismatch `|x(s)| − ρ(t)` in object-space units.
pub fn residual(profile: &Profile, ray: &AxisRay, s: f64, t: f64) -> f64 {
    residual_at(profile.eval(s).0, ray, t)
}

/// The residual at `t` against the profile point `p`.
pub fn residual_at(p: DVec2, ray: &AxisRay, t: f64) -> f64 {
    let rho = ray.radius2(t).max(0.0).sqrt();
    let dy = (p.y - (ray.origin.y + t * ray.dir.y)).abs();
    dy.max((p.x.abs() - rho).abs())
}
