//! Geometric error: the distance of a point to the exact surface, and a
//! bound on how far a tessellation can stray from it.

use std::f64::consts::PI;

use glam::{DVec2, Vec3};

use super::profile::Profile;
use crate::scene::curve::sub_curve;
use crate::scene::Bezier;

const SAMPLES: usize = 512;

/// The distance from `p` (object space) to the surface of revolution of
/// `curve`: the distance, in the half-plane through the axis and `p`, from
/// `(ρ, y)` to the folded profile `(|x(s)|, y(s))`. Dense sampling finds the
/// nearest stretch, a golden-section search refines it.
pub fn surface_distance(curve: &Bezier, p: Vec3) -> f64 {
    let profile = Profile::new(curve);
    let p = p.as_dvec3();
    let q = DVec2::new(DVec2::new(p.x, p.z).length(), p.y);
    let dist = |s: f64| {
        let c = profile.eval(s).0;
        DVec2::new(c.x.abs(), c.y).distance(q)
    };
    let h = 1.0 / SAMPLES as f64;
    let best = (0..=SAMPLES)
        .map(|i| i as f64 * h)
        .min_by(|a, b| dist(*a).total_cmp(&dist(*b)))
        .unwrap_or(0.0);
    let (mut lo, mut hi) = ((best - h).max(0.0), (best + h).min(1.0));
    let ratio = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let a = hi - ratio * (hi - lo);
        let b = lo + ratio * (hi - lo);
        if dist(a) < dist(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    dist(0.5 * (lo + hi)).min(dist(best))
}

/// An upper bound on the distance from any point of
/// `tessellate(curve, resolution)` to the exact surface: per band, the
/// deviation of the curve from its chord (≤ n(n−1)/8 · the largest second
/// difference of the band's control points) plus the ring's sagitta
/// `r (1 − cos(π/m))` (a convex combination of ring points lies at least
/// `cos(π/m)` times the radius from the axis).
pub fn tessellation_error_bound(curve: &Bezier, resolution: u32) -> f64 {
    let profile = Profile::new(curve);
    let n = resolution.max(1) as usize;
    let m = resolution.max(3) as f64;
    let deg = (profile.points.len() - 1) as f64;
    (0..n)
        .map(|i| {
            let (s0, s1) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
            let pts = sub_curve(&profile.points, s0, s1);
            let second = pts
                .windows(3)
                .map(|w| (w[2] - 2.0 * w[1] + w[0]).length())
                .fold(0.0, f64::max);
            let chord = deg * (deg - 1.0) / 8.0 * second;
            let (a, b) = (pts[0].x, pts[pts.len() - 1].x);
            let r_max = pts.iter().map(|p| p.x.abs()).fold(0.0, f64::max);
            let fold = if a * b < 0.0 {
                2.0 * a.abs().min(b.abs())
            } else {
                0.0
            };
            chord + fold + r_max * (1.0 - (PI / m).cos())
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cylinder_is_at_its_radius() {
        let curve = Bezier {
            points: vec![glam::Vec2::new(1.0, 0.0), glam::Vec2::new(1.0, 2.0)],
        };
        let d = surface_distance(&curve, Vec3::new(3.0, 1.0, 0.0));
        assert!((d - 2.0).abs() < 1e-9);
        let d = surface_distance(&curve, Vec3::new(0.0, 3.0, 0.0));
        assert!((d - 2f64.sqrt()).abs() < 1e-9);
    }
}
