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

/// u = 2⁻²⁴, half an ulp of 1: the relative error of one f32 rounding.
const ULP_HALF: f32 = f32::EPSILON * 0.5;

/// Higham's γₙ = nu / (1 − nu): the relative error bound of `n` chained
/// f32 roundings.
#[inline]
pub const fn gamma(n: u32) -> f32 {
    let nu = n as f32 * ULP_HALF;
    nu / (1.0 - nu)
}

/// Moves a surface point `p`, whose components are off the true surface by at
/// most `error`, past that error box along the geometric normal `n`, to the
/// side that `dir` leaves towards, so that a ray spawned there cannot re-hit
/// the surface it left.
///
/// The box reaches `d = |n|·error` along `n`. pbrt-v4 moves by `d` and then
/// steps every moved component one float further from `p`, so that rounding
/// `p + offset` cannot undo the move. Here the move itself is made long
/// enough that the rounding cannot: with u = 2⁻²⁴, each component of the
/// sum is off by at most u·|p + offset|, which moves the point back along
/// `n` by at most u·(|n|·|p| + d) plus the roundings of `n·d` and of the
/// sum, so `d·(1 + 16u) + 2u·(|n|·|p|)` leaves at least `d + u·(|n|·|p|)`
/// after all of them (the unit test checks it in f64): about pbrt-v4's one
/// float. A point with no error along `n` does not move, as in pbrt-v4
/// (moved by the rounding margin, a floor 1e6 from the origin rose 0.24
/// units towards a lamp 4 units above it, and its `nee` and `path` images
/// disagreed: tests/robust_far.rs). No branch per component: which way a
/// component steps is as random as the directions rays leave in, and such
/// branches cost 4 % of a Cornell render's instructions and more of its
/// time.
#[inline(always)]
pub fn offset_origin(p: Vec3, error: Vec3, n: Vec3, dir: Vec3) -> Vec3 {
    let na = n.abs();
    let d = na.dot(error);
    // An exact point (no error along `n`) stays, as in pbrt-v4: a ray from
    // it meets its own surface at t = 0, which no test takes.
    let d = if d > 0.0 {
        d * (1.0 + 16.0 * ULP_HALF) + 2.0 * ULP_HALF * na.dot(p.abs())
    } else {
        0.0
    };
    let offset = if n.dot(dir) < 0.0 { -(n * d) } else { n * d };
    p + offset
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
        // No error: the point moves by nothing.
        assert_eq!(offset_origin(p, Vec3::ZERO, n, Vec3::Y), p);
    }

    /// The offset point, measured in f64, lies beyond the error box's
    /// reach along the normal on the side of the direction, for points near
    /// and far from the origin, tiny and large errors (zero among them),
    /// and normals along the axes and in between.
    #[test]
    fn offsets_clear_the_error_box_after_rounding() {
        let mut next = crate::sampling::rng::numbers(21);
        let mut least_margin = f64::INFINITY;
        for k in 0..200_000 {
            let scale = 10f32.powf(next() * 12.0 - 4.0);
            // Every seventh point at the origin, where only the error's
            // reach and its own rounding count.
            let p = (Vec3::new(next(), next(), next()) - 0.5) * 2.0 * scale;
            let p = if k % 7 == 0 { Vec3::ZERO } else { p };
            let error = match k % 4 {
                0 => Vec3::ZERO,
                1 => p.abs() * 4.0 * ULP_HALF,
                _ => Vec3::new(next(), next(), next()) * scale * 1e-5,
            };
            let n = match k % 3 {
                0 => [Vec3::X, -Vec3::Y, Vec3::Z][k % 9 / 3],
                _ => (Vec3::new(next(), next(), next()) - 0.5).normalize(),
            };
            let dir = (Vec3::new(next(), next(), next()) - 0.5).normalize();
            let q = offset_origin(p, error, n, dir);
            let side = if n.dot(dir) < 0.0 { -1.0 } else { 1.0 };
            let moved = (q.as_dvec3() - p.as_dvec3()).dot(n.as_dvec3()) * side;
            let reach = n.abs().as_dvec3().dot(error.as_dvec3());
            let bound = n.abs().as_dvec3().dot(p.abs().as_dvec3());
            // An exact point stays (as in pbrt-v4).
            assert!(
                moved > reach || reach == 0.0 && q == p,
                "{p} {error} {n}: moved {moved}, reach {reach}"
            );
            // Beyond the box, but not far: within 32 u of the reach and 4 u
            // of |n|·|p| past it.
            let u = f64::from(ULP_HALF);
            assert!(
                moved <= reach * (1.0 + 32.0 * u) + 4.0 * u * bound + 1e-38,
                "{p} {error} {n}: moved {moved}, reach {reach}"
            );
            if bound > 0.0 && reach > 0.0 {
                least_margin = least_margin.min((moved - reach) / bound);
            }
        }
        // The margin is the u the documentation promises, not luck.
        assert!(
            least_margin > 0.5 * f64::from(ULP_HALF),
            "margin {least_margin}"
        );
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
