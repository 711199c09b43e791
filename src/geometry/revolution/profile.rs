//! The profile curve prepared for revolution: `f64` control points, the
//! orientation that makes normals point away from the axis side, the scale
//! that makes tolerances relative, and the surface frame (normal, uv) at a
//! curve parameter.

use std::f64::consts::TAU;

use glam::{DVec2, DVec3};

use crate::scene::curve::{control_bounds, point_and_derivative};
use crate::scene::Bezier;

/// A Bézier profile `(x(s), y(s))` revolved about the y axis, the surface
/// point at angle `φ` being `(x cos φ, y, x sin φ)`: using the signed `x`
/// keeps the parametrisation smooth where the curve crosses the axis, and
/// gives the same surface as radius `|x|`.
#[derive(Clone, Debug)]
pub struct Profile {
    pub points: Vec<DVec2>,
    /// `+1` or `-1`: the normal `orientation · (y′ e − x′ ŷ)` points away
    /// from the axis side of the profile (`e` the signed radial direction).
    pub orientation: f64,
    /// The largest extent of the surface's bounding box (≥ a tiny positive
    /// number): tolerances are fractions of it.
    pub scale: f64,
    /// Largest radius of the control points.
    pub max_radius: f64,
    /// Height range of the control points.
    pub y_range: (f64, f64),
}

impl Profile {
    /// Prepares `curve`; a curve with fewer than two points or a non-finite
    /// point is replaced by the single point at the origin (an empty
    /// surface).
    pub fn new(curve: &Bezier) -> Profile {
        let points = if curve.is_valid() {
            curve.to_f64()
        } else {
            vec![DVec2::ZERO, DVec2::ZERO]
        };
        let (lo, hi) = control_bounds(&points);
        let max_radius = lo.x.abs().max(hi.x.abs());
        let scale = (2.0 * max_radius)
            .max(hi.y - lo.y)
            .max(f64::MIN_POSITIVE * 1e6);
        let mut profile = Profile {
            points,
            orientation: 1.0,
            scale,
            max_radius,
            y_range: (lo.y, hi.y),
        };
        profile.orientation = profile.outward_orientation();
        profile
    }

    /// The orientation for which normals point away from the axis, judged by
    /// a radius-weighted vote along the curve (where the profile is far from
    /// the axis, "away" is unambiguous).
    fn outward_orientation(&self) -> f64 {
        let vote: f64 = (0..=64)
            .map(|i| {
                let (p, d) = self.eval(i as f64 / 64.0);
                d.y * p.x
            })
            .sum();
        if vote < 0.0 {
            -1.0
        } else {
            1.0
        }
    }

    /// Point and derivative at `s`.
    #[inline]
    pub fn eval(&self, s: f64) -> (DVec2, DVec2) {
        point_and_derivative(&self.points, s)
    }

    /// A tangent at `s` that is never zero: where the derivative vanishes (a
    /// repeated control point), the direction towards a nearby point.
    pub fn tangent(&self, s: f64) -> DVec2 {
        let d = self.eval(s).1;
        if d.length_squared() > 1e-24 * self.scale * self.scale {
            return d;
        }
        let h = 1e-4;
        let (a, b) = if s < 0.5 { (s, s + h) } else { (s - h, s) };
        let chord = self.eval(b).0 - self.eval(a).0;
        if chord.length_squared() > 0.0 {
            chord
        } else {
            DVec2::Y
        }
    }

    /// The sign of `x` near `s` (`+1` on the axis when the curve only
    /// touches it there).
    fn side(&self, s: f64) -> f64 {
        let x = self.eval(s).0.x;
        if x != 0.0 {
            return x.signum();
        }
        let nearby = self.eval(if s < 0.5 { s + 1e-4 } else { s - 1e-4 }).0.x;
        if nearby < 0.0 {
            -1.0
        } else {
            1.0
        }
    }

    /// Unit normal and uv at curve parameter `s` and azimuth direction
    /// `(cos θ, sin θ)` of the surface point (its actual position angle).
    pub fn frame(&self, s: f64, azimuth: DVec2) -> (DVec3, DVec2) {
        let t = self.tangent(s);
        let radial = azimuth * self.side(s);
        let n = DVec3::new(t.y * radial.x, -t.x, t.y * radial.y) * self.orientation;
        let n = n.try_normalize().unwrap_or(DVec3::Y);
        let mut u = azimuth.y.atan2(azimuth.x) / TAU;
        if u < 0.0 {
            u += 1.0;
        }
        (n, DVec2::new(u.min(1.0), s.clamp(0.0, 1.0)))
    }

    /// The azimuth direction of a point: `(x, z)` normalised, `(1, 0)` on
    /// the axis.
    pub fn azimuth(p: DVec3) -> DVec2 {
        DVec2::new(p.x, p.z).try_normalize().unwrap_or(DVec2::X)
    }
}
