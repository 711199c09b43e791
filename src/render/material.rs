//! Scattering and emission of each material at a hit: lambertian (cosine
//! sampling), metal with fuzz, dielectric with exact Fresnel and total
//! internal reflection, diffuse lights, and the isotropic phase function.

use glam::Vec3;

use super::texture::lookup;
use crate::geometry::Hit;
use crate::sampling::warp::{cosine_hemisphere, uniform_ball, uniform_sphere};
use crate::sampling::Sampler;
use crate::scene::{Material, Scene};

/// What a surface does to a path arriving along `dir`.
pub struct Interaction {
    /// Light emitted towards the path.
    pub emitted: Vec3,
    /// The attenuation and new direction, if the path continues.
    pub bounce: Option<(Vec3, Vec3)>,
}

/// How the material of `hit` scatters a path arriving along unit `dir`.
#[inline]
pub fn interact(scene: &Scene, hit: &Hit, dir: Vec3, sampler: &mut Sampler) -> Interaction {
    let albedo = |id| lookup(scene, id, hit.uv, hit.point);
    let bounce = |attenuation, d| Interaction {
        emitted: Vec3::ZERO,
        bounce: Some((attenuation, d)),
    };
    match *scene.material(hit.material) {
        Material::Lambertian { albedo: tex } => bounce(
            albedo(tex),
            cosine_hemisphere(hit.normal, sampler.next_2d()),
        ),
        Material::Metal { albedo: tex, fuzz } => {
            let u = sampler.next_2d();
            let d = reflect(dir, hit.normal) + fuzz * uniform_ball(u, sampler.next_1d());
            if d.dot(hit.geo_normal) <= 0.0 {
                return Interaction {
                    emitted: Vec3::ZERO,
                    bounce: None,
                };
            }
            bounce(albedo(tex), d.normalize())
        }
        Material::Dielectric { ior } => {
            bounce(Vec3::ONE, dielectric(dir, hit, ior, sampler.next_1d()))
        }
        Material::Light { emit, two_sided } => Interaction {
            emitted: if hit.front_face || two_sided {
                albedo(emit)
            } else {
                Vec3::ZERO
            },
            bounce: None,
        },
        Material::Isotropic { albedo: tex } => {
            bounce(albedo(tex), uniform_sphere(sampler.next_2d()))
        }
    }
}

#[inline]
fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refracts or reflects unit `dir` at `hit`, choosing by the exact Fresnel
/// reflectance of unpolarised light against the uniform number `u`.
fn dielectric(dir: Vec3, hit: &Hit, ior: f32, u: f32) -> Vec3 {
    let eta = if hit.front_face { 1.0 / ior } else { ior };
    let n = hit.normal;
    let cos_i = (-dir.dot(n)).clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return reflect(dir, n);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let fresnel = 0.5 * (rs * rs + rp * rp);
    if u < fresnel {
        reflect(dir, n)
    } else {
        (eta * dir + (eta * cos_i - cos_t) * n).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// A hit at the origin on a surface with normal +y, seen from its
    /// front (outside) or back (inside).
    fn upward_hit(front_face: bool) -> Hit {
        Hit {
            t: 1.0,
            point: Vec3::ZERO,
            error: Vec3::ZERO,
            geo_normal: Vec3::Y,
            normal: Vec3::Y,
            uv: glam::Vec2::ZERO.into(),
            front_face,
            material: crate::scene::MaterialId(0),
        }
    }

    #[test]
    fn ior_one_passes_straight_and_total_internal_reflection_reflects() {
        let mut rng = Rng::for_sample(1, 2, 3, 4);
        let dir = Vec3::new(0.6, -0.8, 0.0);
        let hit = upward_hit(true);
        for _ in 0..100 {
            assert!((dielectric(dir, &hit, 1.0, rng.next_f32()) - dir).length() < 1e-6);
        }
        let inside = upward_hit(false);
        let grazing = Vec3::new(0.9, -(1.0f32 - 0.81).sqrt(), 0.0);
        let out = dielectric(grazing, &inside, 1.5, rng.next_f32());
        assert!(out.y > 0.0, "total internal reflection expected, got {out}");
    }

    /// The fraction of `count` paths arriving along `dir` at a surface of
    /// ior 10 (normal +y) that it reflects.
    fn reflected_fraction(dir: Vec3, front_face: bool, count: u32) -> f64 {
        let hit = upward_hit(front_face);
        let mut rng = Rng::for_sample(10, 0, 0, 0);
        let reflected = (0..count)
            .filter(|_| dielectric(dir, &hit, 10.0, rng.next_f32()).y > 0.0)
            .count();
        reflected as f64 / count as f64
    }

    #[test]
    fn ior_ten_reflects_its_fresnel_fraction() {
        // Binomial standard error at 200 000 draws is below 0.0012; allow 5.
        let (count, tolerance) = (200_000, 0.006);
        // Normal incidence, from either side: ((n − 1)/(n + 1))² = 0.669.
        let normal = (9.0f64 / 11.0).powi(2);
        for front_face in [true, false] {
            let f = reflected_fraction(Vec3::NEG_Y, front_face, count);
            assert!(
                (f - normal).abs() < tolerance,
                "{front_face}: {f} vs {normal}"
            );
        }
        // At Brewster's angle (tan θ = n) only the s-polarised half reflects:
        // R = ((n² − 1)/(n² + 1))² / 2 = 0.480.
        let brewster = 10.0f32.atan();
        let dir = Vec3::new(brewster.sin(), -brewster.cos(), 0.0);
        let f = reflected_fraction(dir, true, count);
        let expected = (99.0f64 / 101.0).powi(2) / 2.0;
        assert!(
            (f - expected).abs() < tolerance,
            "Brewster: {f} vs {expected}"
        );
    }
}
