//! The math of microfacet BSDFs, in a local frame whose +z is the surface
//! normal: the GGX (Trowbridge–Reitz) distribution of normals, its Smith
//! masking, sampling of the normals visible from a direction (Heitz 2018,
//! "Sampling the GGX Distribution of Visible Normals"), and the Fresnel
//! reflectance of dielectrics and conductors.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::sampling::warp::sin_cos_turn;

/// Roughness below this is raised to it: a GGX lobe narrower than 10⁻⁴
/// rad is a mirror to within what an f32 direction resolves.
pub const MIN_ALPHA: f32 = 1e-4;

/// An anisotropic GGX distribution of roughness `x` along the local x axis
/// and `y` along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    pub x: f32,
    pub y: f32,
}

impl Ggx {
    /// The distribution of roughness `alpha` (each component raised to
    /// [`MIN_ALPHA`]).
    #[inline]
    pub fn new(alpha: Vec2) -> Ggx {
        Ggx {
            x: alpha.x.max(MIN_ALPHA),
            y: alpha.y.max(MIN_ALPHA),
        }
    }

    /// The density of microfacet normals `m` per projected area: D(m), with
    /// ∫ D(m) cos θm dm = 1 over the hemisphere.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.x, m.y / self.y);
        let t = x * x + y * y + m.z * m.z;
        1.0 / (PI * self.x * self.y * t * t)
    }

    /// Smith's Λ(w): the masking of direction `w` is 1 / (1 + Λ).
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        if z2 == 0.0 {
            return f32::INFINITY;
        }
        let (x, y) = (self.x * w.x, self.y * w.y);
        0.5 * ((1.0 + (x * x + y * y) / z2).sqrt() - 1.0)
    }

    /// The fraction of microfacets of normal `m` seen from `w`: zero when
    /// `w` sees the back of the facet or lies on the other side of the
    /// surface from it.
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// Separable shadowing–masking G1(a)·G1(b), as Mitsuba 3's microfacet
    /// BSDFs use.
    #[inline]
    pub fn g_separable(&self, a: Vec3, b: Vec3, m: Vec3) -> f32 {
        self.g1(a, m) * self.g1(b, m)
    }

    /// Height-correlated shadowing–masking 1 / (1 + Λ(a) + Λ(b)), as the
    /// glTF 2.0 BRDF uses (both directions above the surface).
    #[inline]
    pub fn g_correlated(&self, a: Vec3, b: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(a) + self.lambda(b))
    }

    /// The density of normals visible from `w` (w.z > 0) at `m`:
    /// G1(w, m) max(0, w·m) D(m) / w.z, which integrates to 1.
    #[inline]
    pub fn visible(&self, w: Vec3, m: Vec3) -> f32 {
        self.g1(w, m) * w.dot(m).max(0.0) * self.d(m) / w.z
    }

    /// A normal drawn from [`Ggx::visible`] for `w` (w.z > 0) with uniform
    /// numbers `u`: stretch the view to the hemisphere configuration of
    /// roughness 1, sample the projected disk with its far half squeezed,
    /// lift to the hemisphere and unstretch.
    #[inline]
    pub fn sample_visible(&self, w: Vec3, u: Vec2) -> Vec3 {
        let v = Vec3::new(self.x * w.x, self.y * w.y, w.z).normalize();
        let len2 = v.x * v.x + v.y * v.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-v.y, v.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = v.cross(t1);
        let r = u.x.sqrt();
        let (sin, cos) = sin_cos_turn(u.y);
        let p1 = r * cos;
        let s = 0.5 * (1.0 + v.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * sin;
        let h = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * v;
        Vec3::new(self.x * h.x, self.y * h.y, h.z.max(1e-7)).normalize()
    }
}

/// The Fresnel reflectance of unpolarised light meeting a dielectric
/// interface at cosine `cos_i` (> 0, measured on its side) where `eta` is
/// the index beyond the interface over the index on the light's side, and
/// the cosine of the refracted direction (0 under total internal
/// reflection, when the reflectance is 1).
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> (f32, f32) {
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    (0.5 * (rs * rs + rp * rp), cos_t)
}

/// The Fresnel reflectance of unpolarised light meeting a conductor of
/// complex index of refraction `eta + i k` (per channel, relative to the
/// outside) at cosine `cos_i` in [0, 1]: the exact expressions for the s
/// and p reflectances in terms of a² + b² = |η² − sin²θ|.
#[inline]
pub fn fresnel_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let c2 = cos_i * cos_i;
    let s2 = 1.0 - c2;
    let t0 = eta * eta - k * k - Vec3::splat(s2);
    let a2b2 = (t0 * t0 + 4.0 * eta * eta * k * k).powf(0.5);
    let a = (0.5 * (a2b2 + t0)).max(Vec3::ZERO).powf(0.5);
    let t1 = a2b2 + Vec3::splat(c2);
    let t2 = 2.0 * cos_i * a;
    let rs = (t1 - t2) / (t1 + t2);
    let t3 = c2 * a2b2 + Vec3::splat(s2 * s2);
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4);
    0.5 * (rs + rp)
}

/// Schlick's approximation of the Fresnel reflectance at cosine `cos`
/// given the reflectance `f0` at normal incidence.
#[inline]
pub fn fresnel_schlick(cos: f32, f0: Vec3) -> Vec3 {
    let t = (1.0 - cos).clamp(0.0, 1.0);
    let t5 = (t * t) * (t * t) * t;
    f0 + (Vec3::ONE - f0) * t5
}

/// The conductor whose Fresnel reflectance at normal incidence is `r`
/// (each channel below 1): index 1 and extinction 2√r / √(1 − r), as
/// pbrt-v4 derives a conductor from a reflectance.
#[inline]
pub fn conductor_of_reflectance(r: Vec3) -> (Vec3, Vec3) {
    let r = r.clamp(Vec3::ZERO, Vec3::splat(0.9999));
    (Vec3::ONE, 2.0 * r.powf(0.5) / (Vec3::ONE - r).powf(0.5))
}

/// An orthonormal frame: `t` (the direction of the first roughness), `b`,
/// and the normal `n`.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    t: Vec3,
    b: Vec3,
    n: Vec3,
}

impl Frame {
    /// The frame of normal `n` whose tangent runs around the scene's y
    /// axis (along the parallels of a sphere whose poles are on y), or an
    /// arbitrary one where `n` is (nearly) y.
    #[inline]
    pub fn around_y(n: Vec3) -> Frame {
        let t = Vec3::Y.cross(n);
        let len2 = t.length_squared();
        let (t, b) = if len2 > 1e-8 {
            let t = t / len2.sqrt();
            (t, n.cross(t))
        } else {
            n.any_orthonormal_pair()
        };
        Frame { t, b, n }
    }

    /// `v` in local coordinates (+z the normal).
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }

    /// The local vector `v` back in the scene.
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        v.x * self.t + v.y * self.b + v.z * self.n
    }
}

/// `w` mirrored about the unit normal `m`.
#[inline]
pub fn reflect(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// `w` (on the side `m` points to) refracted through the unit normal `m`
/// into the medium of relative index `eta`, given the refracted cosine.
#[inline]
pub fn refract(w: Vec3, m: Vec3, eta: f32, cos_t: f32) -> Vec3 {
    (w.dot(m) / eta - cos_t) * m - w / eta
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::uniform_sphere;
    use crate::sampling::Rng;

    fn uniform(rng: &mut Rng) -> Vec2 {
        Vec2::new(rng.next_f32(), rng.next_f32())
    }

    /// ∫ g over the sphere by a stratified uniform estimate (f64 sum).
    fn sphere_integral(n: u32, mut g: impl FnMut(Vec3) -> f32) -> f64 {
        let mut sum = 0.0f64;
        let mut rng = Rng::for_sample(3, 1, 4, 1);
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new(
                    (i as f32 + rng.next_f32()) / n as f32,
                    (j as f32 + rng.next_f32()) / n as f32,
                );
                sum += g(uniform_sphere(u)) as f64;
            }
        }
        sum * 4.0 * std::f64::consts::PI / (n as f64 * n as f64)
    }

    /// Roughnesses under test: the integrals are estimated by uniform
    /// sampling, so the narrowest lobes are left to the sampling tests.
    const ALPHAS: [(f32, f32); 5] = [(0.05, 0.05), (0.2, 0.2), (0.5, 0.1), (1.0, 1.0), (0.3, 0.9)];

    #[test]
    fn projected_normals_cover_the_surface_once() {
        for (ax, ay) in ALPHAS {
            let ggx = Ggx::new(Vec2::new(ax, ay));
            let total = sphere_integral(1500, |m| ggx.d(m) * m.z.max(0.0));
            assert!((total - 1.0).abs() < 0.01, "α {ax},{ay}: ∫D cos = {total}");
        }
    }

    #[test]
    fn visible_normals_integrate_to_one_and_match_their_sampling() {
        let mut rng = Rng::for_sample(7, 0, 0, 0);
        for (ax, ay) in ALPHAS {
            let ggx = Ggx::new(Vec2::new(ax, ay));
            for cos in [1.0f32, 0.5, 0.05] {
                let w = Vec3::new(
                    (1.0 - cos * cos).sqrt() * 0.6,
                    (1.0 - cos * cos).sqrt() * 0.8,
                    cos,
                );
                let total = sphere_integral(1500, |m| ggx.visible(w, m));
                assert!((total - 1.0).abs() < 0.01, "α {ax},{ay} cos {cos}: {total}");
                // The mean of m·z under sampling equals ∫ m.z D_w(m) dm.
                let expected = sphere_integral(1500, |m| ggx.visible(w, m) * m.z);
                let n = 200_000;
                let mean = (0..n)
                    .map(|_| ggx.sample_visible(w, uniform(&mut rng)).z as f64)
                    .sum::<f64>()
                    / n as f64;
                assert!(
                    (mean - expected).abs() < 0.01,
                    "α {ax},{ay} cos {cos}: {mean} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn masking_is_one_facing_the_normal_and_falls_to_zero_at_grazing() {
        let ggx = Ggx::new(Vec2::splat(0.5));
        assert_eq!(ggx.g1(Vec3::Z, Vec3::Z), 1.0);
        let grazing = Vec3::new(1.0, 0.0, 1e-4).normalize();
        assert!(ggx.g1(grazing, Vec3::Z) < 1e-3);
        // Back-facing microfacets are never seen.
        assert_eq!(ggx.g1(Vec3::Z, Vec3::new(0.0, 0.0, -1.0)), 0.0);
        // Λ for α = 1 at 45°: (√2 − 1) / 2.
        let one = Ggx::new(Vec2::ONE);
        let w = Vec3::new(1.0, 0.0, 1.0).normalize();
        assert!((one.lambda(w) - (2f32.sqrt() - 1.0) / 2.0).abs() < 1e-6);
    }

    #[test]
    fn fresnel_matches_its_closed_forms() {
        // Normal incidence: ((η − 1)/(η + 1))², the same from either side.
        let (f, cos_t) = fresnel_dielectric(1.0, 1.5);
        assert!((f - 0.04).abs() < 1e-6 && (cos_t - 1.0).abs() < 1e-6);
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5).0 - 0.04).abs() < 1e-6);
        // Total internal reflection beyond the critical angle.
        assert_eq!(fresnel_dielectric(0.3, 1.0 / 1.5).0, 1.0);
        // Brewster's angle: only s reflects.
        let b = 1.5f32.atan();
        let rs = ((1.5f32 * 1.5 - 1.0) / (1.5 * 1.5 + 1.0)).powi(2);
        assert!((fresnel_dielectric(b.cos(), 1.5).0 - 0.5 * rs).abs() < 1e-5);
        // A conductor with k = 0 is a dielectric.
        for cos in [1.0, 0.7, 0.2, 0.01] {
            let c = fresnel_conductor(cos, Vec3::splat(1.5), Vec3::ZERO);
            let d = fresnel_dielectric(cos, 1.5).0;
            assert!(
                (c - Vec3::splat(d)).abs().max_element() < 1e-5,
                "{cos}: {c} vs {d}"
            );
        }
        // Normal incidence on a conductor: ((η−1)² + k²)/((η+1)² + k²).
        let (eta, k) = (Vec3::new(0.2, 0.9, 1.1), Vec3::new(3.9, 2.5, 2.1));
        let expected = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
        assert!(
            (fresnel_conductor(1.0, eta, k) - expected)
                .abs()
                .max_element()
                < 1e-5
        );
        // Grazing incidence reflects everything.
        assert!(
            (fresnel_conductor(0.0, eta, k) - Vec3::ONE)
                .abs()
                .max_element()
                < 1e-5
        );
        // A conductor made from a reflectance reflects it at normal incidence.
        let r = Vec3::new(0.9, 0.6, 0.05);
        let (e, k) = conductor_of_reflectance(r);
        assert!((fresnel_conductor(1.0, e, k) - r).abs().max_element() < 1e-5);
        assert_eq!(fresnel_schlick(1.0, r), r);
        assert_eq!(fresnel_schlick(0.0, r), Vec3::ONE);
    }

    #[test]
    fn refraction_obeys_snell_and_frames_are_orthonormal() {
        let w = Vec3::new(0.6, 0.0, 0.8);
        let (_, cos_t) = fresnel_dielectric(0.8, 1.5);
        let t = refract(w, Vec3::Z, 1.5, cos_t);
        assert!((t.length() - 1.0).abs() < 1e-6 && t.z < 0.0);
        assert!((0.6 - 1.5 * t.x.abs()).abs() < 1e-6, "{t}");
        assert!((reflect(w, Vec3::Z) - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
        for n in [Vec3::Y, Vec3::new(0.3, -0.5, 0.8).normalize(), Vec3::X] {
            let f = Frame::around_y(n);
            let v = Vec3::new(0.2, 0.7, -0.4);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-6);
        }
    }
}
