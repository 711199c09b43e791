//! Rays with a time, and spawning rays off surfaces without self-intersection:
//! a hit point carries a conservative bound on its floating-point error, and
//! a spawned ray starts just outside that box along the geometric normal
//! (pbrt-v4's `OffsetRayOrigin` and `SpawnRayTo`).

use glam::{Affine3A, Vec3};

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

/// A shadow ray from [`spawn_to`] is tested over `(0, SHADOW_END)`: it stops
/// just short of its target, whose own offset already keeps it off the
/// target's surface.
pub const SHADOW_END: f32 = 1.0 - 1e-4;

/// Higham's γₙ = nu / (1 − nu), u = 2⁻²⁴: the relative error bound of `n`
/// chained f32 roundings.
#[inline]
pub const fn gamma(n: u32) -> f32 {
    let nu = n as f32 * (f32::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// Moves a surface point `p`, whose components are off the true surface by at
/// most `error`, past that error box along the geometric normal `n`, to the
/// side that `dir` leaves towards, rounding every moved component away from
/// `p`, so that a ray spawned there cannot re-hit the surface it left.
#[inline(always)]
pub fn offset_origin(p: Vec3, error: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    let d = n.abs().dot(error);
    let offset = if n.dot(dir) < 0.0 { -(n * d) } else { n * d };
    let moved = p + offset;
    Vec3::new(
        away(moved.x, offset.x),
        away(moved.y, offset.y),
        away(moved.z, offset.z),
    )
}

/// `v` moved to the next float in the direction of `o`'s sign (unchanged
/// when `o` is zero or `v` not finite): `next_up` / `next_down` as one
/// integer step on the bits, one ulp away from zero when `v` and `o` have
/// the same sign and towards it otherwise.
#[inline(always)]
fn away(v: f32, o: f32) -> f32 {
    if o == 0.0 || !v.is_finite() {
        return v;
    }
    if v == 0.0 {
        return f32::from_bits(1).copysign(o);
    }
    let step = if (v > 0.0) == (o > 0.0) { 1 } else { u32::MAX };
    f32::from_bits(v.to_bits().wrapping_add(step))
}

/// A point of a surface with the bound of its error and its geometric normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    pub point: Vec3,
    pub error: Vec3,
    pub normal: Vec3,
}

/// The segment from `from` to `to`, each end offset off its surface towards
/// the other: trace it over `t ∈ (0, SHADOW_END)` to ask whether anything
/// lies between the two surfaces.
#[inline]
pub fn spawn_to(from: SurfacePoint, to: SurfacePoint, time: f32) -> Ray {
    let origin = offset_origin(from.point, from.error, from.normal, to.point - from.point);
    let target = offset_origin(to.point, to.error, to.normal, origin - to.point);
    Ray::new(origin, target - origin, time)
}

/// Transforms point `p` with component error `error` by the affine map `m`,
/// returning the image and the bound of its error (pbrt-v4's transform of a
/// `Point3fi`): the rounding of the matrix product plus the input error
/// carried through the linear part.
#[inline]
pub fn transform_point(m: &Affine3A, p: Vec3, error: Vec3) -> (Vec3, Vec3) {
    let linear = m.matrix3.abs();
    let rounding = gamma(3) * (linear * p.abs() + Vec3::from(m.translation).abs());
    let carried = (1.0 + gamma(3)) * (linear * error);
    (m.transform_point3(p), rounding + carried)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_clear_the_error_box_on_the_side_of_the_direction() {
        let p = Vec3::new(1e5, 3.0, -2.0);
        let error = Vec3::splat(0.01);
        let n = Vec3::new(0.0, 0.6, 0.8);
        let up = offset_origin(p, error, n, Vec3::Y);
        let down = offset_origin(p, error, n, -Vec3::Y);
        // The distance along n must exceed the error box's extent along n.
        let reach = n.abs().dot(error);
        assert!((up - p).dot(n) > reach, "{up} from {p}");
        assert!((down - p).dot(n) < -reach, "{down} from {p}");
        // No error: the point moves by nothing (no component is offset).
        assert_eq!(offset_origin(p, Vec3::ZERO, n, Vec3::Y), p);
    }

    #[test]
    fn one_step_away_is_next_up_or_next_down() {
        let values = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::from_bits(1),
            -f32::from_bits(1),
            f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            1e5,
            -3.7e-20,
        ];
        for v in values {
            assert_eq!(away(v, 0.5).to_bits(), v.next_up().to_bits(), "{v} up");
            assert_eq!(away(v, -2.0).to_bits(), v.next_down().to_bits(), "{v} down");
            assert_eq!(away(v, 0.0).to_bits(), v.to_bits());
        }
        assert_eq!(away(f32::INFINITY, 1.0), f32::INFINITY);
        assert!(away(f32::NAN, 1.0).is_nan());
    }

    #[test]
    fn transformed_error_bounds_cover_the_f64_image() {
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::splat(3.7),
            glam::Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 0.7),
            Vec3::new(1e4, -3e3, 7.0),
        );
        let cols = m.to_cols_array().map(f64::from);
        for p in [Vec3::new(0.1, 0.2, 0.3), Vec3::new(-1e3, 5.0, 2e2)] {
            let (q, err) = transform_point(&m, p, Vec3::ZERO);
            let p64 = p.as_dvec3();
            for i in 0..3 {
                let exact =
                    cols[i] * p64.x + cols[3 + i] * p64.y + cols[6 + i] * p64.z + cols[9 + i];
                assert!(
                    (q[i] as f64 - exact).abs() <= err[i] as f64,
                    "component {i}: {} vs {exact}, bound {}",
                    q[i],
                    err[i]
                );
            }
            assert!(err.max_element() < 1e-2, "bound {err} is loose");
        }
    }
}
