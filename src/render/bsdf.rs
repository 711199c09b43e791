//! The scattering at one hit: a closed `Bsdf` (lambertian, fuzzy metal,
//! mirror, dielectric, the microfacet lobes of [`super::rough`], the
//! isotropic phase function of media, and emitters that only emit), built
//! once per hit with its texture already looked up
//! ([`super::material::bsdf`]). The integrator samples it, evaluates it for
//! light samples and asks its density, without knowing which one it is.
//!
//! Directions are unit vectors; `wo` points back along the arriving ray and
//! `wi` away from the hit towards where light comes from.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::fuzz;
use super::microfacet::Frame;
use super::rough;
use crate::sampling::warp::{cosine_hemisphere, uniform_sphere};
use crate::sampling::Sampler;

/// How a hit scatters light, with its colour and frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf<'a> {
    /// Ideal diffuse reflection about the shading `normal`; nothing leaves
    /// below the geometric surface.
    Lambertian {
        albedo: Vec3,
        normal: Vec3,
        geo_normal: Vec3,
    },
    /// The mirror direction blurred by a ball of radius `fuzz`
    /// (see [`super::fuzz`]); directions below the geometric surface are
    /// absorbed.
    FuzzyMetal {
        albedo: Vec3,
        fuzz: f32,
        normal: Vec3,
        geo_normal: Vec3,
    },
    /// Perfect mirror reflection (specular).
    Mirror {
        albedo: Vec3,
        normal: Vec3,
        geo_normal: Vec3,
    },
    /// Refraction or reflection by exact Fresnel (specular); `eta` is the
    /// ratio of the index of refraction the ray leaves to the one it enters.
    Dielectric { eta: f32, normal: Vec3 },
    /// A microfacet lobe (rough conductor, rough glass, plastic or glTF's
    /// metallic–roughness BRDF) about the shading `normal`, its
    /// anisotropic roughness along the tangent of [`Frame::around_y`].
    /// Reflected light never leaves below the geometric surface nor
    /// refracted light above it; rough glass's `normal` faces the viewer,
    /// its `eta` the index behind over the index in front.
    Rough {
        lobe: rough::Lobe<'a>,
        normal: Vec3,
        geo_normal: Vec3,
    },
    /// The isotropic phase function of a medium.
    Isotropic { albedo: Vec3 },
    /// A light: emits `emitted` towards the path and scatters nothing.
    Emitter { emitted: Vec3 },
}

/// One sampled direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    pub wi: Vec3,
    /// f · |cos| / pdf: what the path's throughput is multiplied by.
    pub weight: Vec3,
    /// Solid-angle density of `wi` (meaningless when `specular`).
    pub pdf: f32,
    /// Whether `wi` came from a delta lobe that light sampling cannot hit.
    pub specular: bool,
}

impl Bsdf<'_> {
    /// Light the surface emits towards the path.
    #[inline]
    pub fn emitted(&self) -> Vec3 {
        match *self {
            Bsdf::Emitter { emitted } => emitted,
            _ => Vec3::ZERO,
        }
    }

    /// Whether every scattered direction is a delta lobe.
    #[inline]
    pub fn is_specular(&self) -> bool {
        matches!(self, Bsdf::Mirror { .. } | Bsdf::Dielectric { .. })
    }

    /// Whether next-event estimation applies: the BSDF scatters, with a
    /// density light samples can be weighed against.
    #[inline]
    pub fn samples_lights(&self) -> bool {
        !self.is_specular() && !matches!(self, Bsdf::Emitter { .. })
    }

    /// The normal bounding the directions light can scatter in from: the
    /// shading normal of a surface, zero for a phase function (light from
    /// every side). Light selection uses it to skip lights behind a surface.
    #[inline]
    pub fn facing(&self) -> Vec3 {
        match *self {
            Bsdf::Lambertian { normal, .. }
            | Bsdf::FuzzyMetal { normal, .. }
            | Bsdf::Mirror { normal, .. }
            | Bsdf::Dielectric { normal, .. } => normal,
            // Rough glass gathers light from both sides.
            Bsdf::Rough { lobe, normal, .. } if !lobe.transmits() => normal,
            Bsdf::Rough { .. } | Bsdf::Isotropic { .. } | Bsdf::Emitter { .. } => Vec3::ZERO,
        }
    }

    /// Samples `wi` with uniform numbers `u2` (direction) and `u1` (lobe
    /// choice or ball radius); `None` when the path is absorbed.
    #[inline]
    pub fn sample(&self, wo: Vec3, u2: Vec2, u1: f32) -> Option<BsdfSample> {
        let scattered = |wi, weight, pdf| {
            Some(BsdfSample {
                wi,
                weight,
                pdf,
                specular: false,
            })
        };
        let specular = |wi, weight| {
            Some(BsdfSample {
                wi,
                weight,
                pdf: 0.0,
                specular: true,
            })
        };
        match *self {
            Bsdf::Lambertian { albedo, normal, .. } => {
                let wi = cosine_hemisphere(normal, u2);
                scattered(wi, albedo, normal.dot(wi).max(0.0) * FRAC_1_PI)
            }
            Bsdf::FuzzyMetal {
                albedo,
                fuzz,
                normal,
                geo_normal,
            } => {
                let r = reflect(-wo, normal);
                let d = fuzz::sample(r, fuzz, u2, u1);
                if d.dot(geo_normal) <= 0.0 {
                    return None;
                }
                let wi = d.normalize();
                scattered(wi, albedo, fuzz::pdf(r, fuzz, wi))
            }
            Bsdf::Mirror {
                albedo,
                normal,
                geo_normal,
            } => {
                let wi = reflect(-wo, normal);
                if wi.dot(geo_normal) <= 0.0 {
                    return None;
                }
                specular(wi, albedo)
            }
            Bsdf::Dielectric { eta, normal } => {
                specular(dielectric(-wo, normal, eta, u1), Vec3::ONE)
            }
            Bsdf::Rough {
                lobe,
                normal,
                geo_normal,
            } => local_sample(normal, geo_normal, wo, |wo| lobe.sample(wo, u2, u1)),
            Bsdf::Isotropic { albedo } => scattered(uniform_sphere(u2), albedo, 1.0 / (4.0 * PI)),
            Bsdf::Emitter { .. } => None,
        }
    }

    /// [`Bsdf::sample`] with the numbers drawn from `sampler`: only those
    /// this BSDF uses, the 2-D direction before the 1-D lobe choice.
    #[inline]
    pub fn sample_from(&self, wo: Vec3, sampler: &mut Sampler) -> Option<BsdfSample> {
        let (two, one) = self.draws();
        let u2 = if two { sampler.next_2d() } else { Vec2::ZERO };
        let u1 = if one { sampler.next_1d() } else { 0.0 };
        self.sample(wo, u2, u1)
    }

    /// [`Bsdf::sample_from`] with the draws given: `first` the 2-D draw of
    /// the first BSDF slot, `second` the 1-D draw of the next, the numbers
    /// the sampler would give it there.
    #[inline]
    pub fn sample_drawn(&self, wo: Vec3, first: Vec2, second: f32) -> Option<BsdfSample> {
        let (two, one) = self.draws();
        let u2 = if two { first } else { Vec2::ZERO };
        let u1 = match (two, one) {
            (_, false) => 0.0,
            (true, true) => second,
            // The lobe choice alone takes the first slot's 1-D draw.
            (false, true) => first.x,
        };
        self.sample(wo, u2, u1)
    }

    /// Whether sampling draws a 2-D number (the direction) and a 1-D one
    /// (the lobe choice or ball radius), in that order.
    #[inline]
    fn draws(&self) -> (bool, bool) {
        match self {
            Bsdf::Lambertian { .. } | Bsdf::Isotropic { .. } => (true, false),
            Bsdf::FuzzyMetal { .. } => (true, true),
            Bsdf::Rough { lobe, .. } => (true, lobe.chooses()),
            Bsdf::Dielectric { .. } => (false, true),
            Bsdf::Mirror { .. } | Bsdf::Emitter { .. } => (false, false),
        }
    }

    /// f(wo, wi) · |cos θi| and the density [`Bsdf::sample`] gives `wi`, or
    /// `None` where either is zero (specular lobes, emitters, below the
    /// surface).
    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
        match *self {
            Bsdf::Lambertian {
                albedo,
                normal,
                geo_normal,
            } => {
                let cos = normal.dot(wi);
                (cos > 0.0 && geo_normal.dot(wi) > 0.0)
                    .then_some((albedo * FRAC_1_PI * cos, cos * FRAC_1_PI))
            }
            Bsdf::FuzzyMetal {
                albedo,
                fuzz,
                normal,
                geo_normal,
            } => {
                if geo_normal.dot(wi) <= 0.0 {
                    return None;
                }
                // The sampled weight is the albedo, so f·cos = albedo·pdf.
                let pdf = fuzz::pdf(reflect(-wo, normal), fuzz, wi);
                (pdf > 0.0).then_some((albedo * pdf, pdf))
            }
            Bsdf::Rough {
                lobe,
                normal,
                geo_normal,
            } => local_eval(normal, geo_normal, wo, wi, |wo, wi| lobe.eval_pdf(wo, wi)),
            Bsdf::Isotropic { albedo } => Some((albedo / (4.0 * PI), 1.0 / (4.0 * PI))),
            Bsdf::Mirror { .. } | Bsdf::Dielectric { .. } | Bsdf::Emitter { .. } => None,
        }
    }

    /// f(wo, wi) · |cos θi| (zero for delta lobes).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.eval_pdf(wo, wi).map_or(Vec3::ZERO, |(f, _)| f)
    }

    /// The solid-angle density [`Bsdf::sample`] gives `wi` (zero for delta
    /// lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_pdf(wo, wi).map_or(0.0, |(_, p)| p)
    }
}

/// Whether `wo` and `wi` lie on the sides of the geometric surface
/// (normal `geo`, facing `wo`'s side) their local cosines put them on, so
/// that a lobe never leaks light through the surface: reflection stays
/// above it, transmission below.
#[inline]
fn consistent(geo: Vec3, wo: Vec3, wi: Vec3, local_wi: Vec3) -> bool {
    wo.dot(geo) > 0.0 && (wi.dot(geo) > 0.0) == (local_wi.z > 0.0)
}

/// A microfacet lobe's sample, drawn in the local frame of `normal`.
#[inline]
fn local_sample(
    normal: Vec3,
    geo: Vec3,
    wo: Vec3,
    sample: impl FnOnce(Vec3) -> Option<rough::Sampled>,
) -> Option<BsdfSample> {
    let frame = Frame::around_y(normal);
    let (local, weight, pdf) = sample(frame.to_local(wo))?;
    let wi = frame.to_world(local);
    consistent(geo, wo, wi, local).then_some(BsdfSample {
        wi,
        weight,
        pdf,
        specular: false,
    })
}

/// A microfacet lobe's f·cos and density, in the local frame of `normal`.
#[inline]
fn local_eval(
    normal: Vec3,
    geo: Vec3,
    wo: Vec3,
    wi: Vec3,
    eval: impl FnOnce(Vec3, Vec3) -> Option<(Vec3, f32)>,
) -> Option<(Vec3, f32)> {
    let frame = Frame::around_y(normal);
    let local = frame.to_local(wi);
    if !consistent(geo, wo, wi, local) {
        return None;
    }
    eval(frame.to_local(wo), local)
}

/// `d` mirrored about the plane of unit normal `n`.
#[inline]
fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refracts or reflects unit `dir` at a surface of normal `n` (facing
/// against `dir`) with index ratio `eta`, choosing by the exact Fresnel
/// reflectance of unpolarised light against the uniform number `u`.
fn dielectric(dir: Vec3, n: Vec3, eta: f32, u: f32) -> Vec3 {
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

    fn uniforms(rng: &mut Rng) -> (Vec2, f32) {
        (Vec2::new(rng.next_f32(), rng.next_f32()), rng.next_f32())
    }

    /// A tilted shading normal over a flat geometric one, and a direction
    /// towards the viewer `elevation` degrees above the surface.
    fn frame(elevation: f32) -> (Vec3, Vec3, Vec3) {
        let geo_normal = Vec3::Y;
        let normal = Vec3::new(0.1, 1.0, 0.05).normalize();
        let e = elevation.to_radians();
        let wo = Vec3::new(-e.cos(), e.sin(), 0.0);
        (normal, geo_normal, wo)
    }

    /// Every scattering BSDF under test, with the direction it is seen from.
    fn scattering() -> Vec<(Bsdf<'static>, Vec3)> {
        let albedo = Vec3::new(0.9, 0.5, 0.2);
        let mut out = Vec::new();
        for elevation in [70.0, 25.0] {
            let (normal, geo_normal, wo) = frame(elevation);
            out.push((
                Bsdf::Lambertian {
                    albedo,
                    normal,
                    geo_normal,
                },
                wo,
            ));
            for fuzz in [0.05, 0.3, 1.0] {
                out.push((
                    Bsdf::FuzzyMetal {
                        albedo,
                        fuzz,
                        normal,
                        geo_normal,
                    },
                    wo,
                ));
            }
        }
        out.push((Bsdf::Isotropic { albedo }, Vec3::X));
        out
    }

    /// Mean and standard error of `count` draws of `f` (summed in f64).
    fn estimate(count: u32, mut f: impl FnMut() -> Vec3) -> (Vec3, Vec3) {
        let (mut sum, mut sum2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
        for _ in 0..count {
            let x = f().as_dvec3();
            sum += x;
            sum2 += x * x;
        }
        let n = count as f64;
        let mean = sum / n;
        let var = (sum2 / n - mean * mean).max(glam::DVec3::ZERO);
        (mean.as_vec3(), (var / n).powf(0.5).as_vec3())
    }

    #[test]
    fn sample_weights_average_to_the_integral_of_eval() {
        // Two independent estimates of the directional albedo ∫ f·|cos| dwi:
        // the mean sample weight (0 when absorbed) and a uniform-sphere
        // Monte Carlo integral of eval. They must agree within 5 combined
        // standard errors, and a fully-above lobe must give the albedo.
        let count = 400_000;
        for (bsdf, wo) in scattering() {
            let mut rng = Rng::for_sample(5, 0, 0, 0);
            let (sampled, se_s) = estimate(count, || {
                let (u2, u1) = uniforms(&mut rng);
                bsdf.sample(wo, u2, u1).map_or(Vec3::ZERO, |s| s.weight)
            });
            let mut rng = Rng::for_sample(6, 0, 0, 0);
            let (integral, se_i) = estimate(count, || {
                let wi = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                bsdf.eval(wo, wi) * (4.0 * PI)
            });
            let se = (se_s * se_s + se_i * se_i).powf(0.5);
            assert!(
                (sampled - integral).abs().cmple(5.0 * se + 1e-6).all(),
                "{bsdf:?}: sampled {sampled} vs integral {integral} (se {se})"
            );
            assert!(sampled.cmple(Vec3::new(0.9, 0.5, 0.2) + 5.0 * se).all());
        }
        // Lambertian and isotropic lose nothing: exactly the albedo.
        let albedo = Vec3::new(0.9, 0.5, 0.2);
        for (bsdf, wo) in scattering() {
            if let Bsdf::Lambertian { .. } | Bsdf::Isotropic { .. } = bsdf {
                let mut rng = Rng::for_sample(8, 0, 0, 0);
                let (integral, se) = estimate(count, || {
                    let wi = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                    bsdf.eval(wo, wi) * (4.0 * PI)
                });
                assert!(
                    (integral - albedo).abs().cmple(5.0 * se + 1e-6).all(),
                    "{bsdf:?}: {integral}"
                );
            }
        }
    }

    #[test]
    fn a_fuzzy_lobe_well_above_the_surface_returns_its_albedo() {
        let albedo = Vec3::new(0.9, 0.5, 0.2);
        let (_, geo_normal, _) = frame(90.0);
        let bsdf = Bsdf::FuzzyMetal {
            albedo,
            fuzz: 0.3,
            normal: Vec3::Y,
            geo_normal,
        };
        // Straight down onto the surface: the lobe (≤ 17.5° wide) is above.
        let wo = Vec3::Y;
        let mut rng = Rng::for_sample(9, 0, 0, 0);
        let (integral, se) = estimate(1_000_000, || {
            let wi = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
            bsdf.eval(wo, wi) * (4.0 * PI)
        });
        assert!(
            (integral - albedo).abs().cmple(5.0 * se).all(),
            "{integral} ± {se}"
        );
        let mut rng = Rng::for_sample(10, 0, 0, 0);
        for _ in 0..1000 {
            let (u2, u1) = uniforms(&mut rng);
            assert_eq!(bsdf.sample(wo, u2, u1).map(|s| s.weight), Some(albedo));
        }
    }

    #[test]
    fn eval_and_pdf_agree_with_what_sample_returns() {
        for (bsdf, wo) in scattering() {
            assert!(!bsdf.is_specular() && bsdf.samples_lights());
            let mut rng = Rng::for_sample(12, 0, 0, 0);
            let mut rim = 0;
            for _ in 0..20_000 {
                let (u2, u1) = uniforms(&mut rng);
                let Some(s) = bsdf.sample(wo, u2, u1) else {
                    continue;
                };
                assert!(!s.specular);
                // A lambertian sample above the shading but below the
                // geometric surface (the shading normal is tilted) leaves as
                // it always did, but light from there is not gathered.
                if let Bsdf::Lambertian { geo_normal, .. } = bsdf {
                    if s.wi.dot(geo_normal) <= 0.0 {
                        continue;
                    }
                }
                let pdf = bsdf.pdf(wo, s.wi);
                let f = bsdf.eval(wo, s.wi);
                // The sampled point lies inside the ball, so its density is
                // positive; only directions on the ball's rim may round to 0.
                if pdf == 0.0 {
                    rim += 1;
                    continue;
                }
                assert!(
                    (pdf - s.pdf).abs() <= 1e-4 * pdf,
                    "{bsdf:?}: {pdf} vs {}",
                    s.pdf
                );
                let weight = f / pdf;
                assert!(
                    (weight - s.weight).abs().max_element() <= 1e-4,
                    "{bsdf:?}: {weight} vs {}",
                    s.weight
                );
            }
            assert!(rim <= 2, "{bsdf:?}: {rim} samples of zero density");
        }
    }

    #[test]
    fn diffuse_and_phase_are_reciprocal_and_the_fuzzy_lobe_is_symmetric() {
        let mut rng = Rng::for_sample(13, 0, 0, 0);
        for (bsdf, _) in scattering() {
            for _ in 0..10_000 {
                let a = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                let b = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                match bsdf {
                    Bsdf::Lambertian { normal, .. } => {
                        // f itself (value over the cosine) is reciprocal.
                        let fab = bsdf.eval(a, b) / normal.dot(b).abs();
                        let fba = bsdf.eval(b, a) / normal.dot(a).abs();
                        let above = |w: Vec3| normal.dot(w) > 0.0 && Vec3::Y.dot(w) > 0.0;
                        if above(a) && above(b) {
                            assert!((fab - fba).abs().max_element() < 1e-5, "{fab} {fba}");
                        }
                    }
                    Bsdf::Isotropic { .. } => assert_eq!(bsdf.eval(a, b), bsdf.eval(b, a)),
                    // The seed's fuzzy metal weights every sample by its
                    // albedo, so f = albedo·pdf / cos is not reciprocal; its
                    // density is (the angle of b to a's mirror is the
                    // angle of a to b's).
                    _ => {
                        let (p, q) = (bsdf.pdf(a, b), bsdf.pdf(b, a));
                        if Vec3::Y.dot(a) > 0.0 && Vec3::Y.dot(b) > 0.0 {
                            assert!((p - q).abs() <= 1e-3 * p.max(q) + 1e-6, "{p} vs {q}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn specular_lobes_and_emitters_have_no_density() {
        let (normal, geo_normal, wo) = frame(40.0);
        let mirror = Bsdf::Mirror {
            albedo: Vec3::splat(0.8),
            normal,
            geo_normal,
        };
        let glass = Bsdf::Dielectric {
            eta: 1.0 / 1.5,
            normal,
        };
        let light = Bsdf::Emitter { emitted: Vec3::ONE };
        for bsdf in [mirror, glass] {
            assert!(bsdf.is_specular() && !bsdf.samples_lights());
            let s = bsdf.sample(wo, Vec2::splat(0.3), 0.9).expect("scatters");
            assert!(s.specular);
            assert_eq!(bsdf.eval_pdf(wo, s.wi), None);
        }
        let s = mirror.sample(wo, Vec2::ZERO, 0.0).expect("reflects");
        assert!((s.wi - reflect(-wo, normal)).length() < 1e-6);
        assert!(!light.samples_lights());
        assert_eq!(light.sample(wo, Vec2::ZERO, 0.0), None);
        assert_eq!(light.emitted(), Vec3::ONE);
        assert_eq!(mirror.emitted(), Vec3::ZERO);
    }

    #[test]
    fn ior_one_passes_straight_and_total_internal_reflection_reflects() {
        let mut rng = Rng::for_sample(1, 2, 3, 4);
        let dir = Vec3::new(0.6, -0.8, 0.0);
        for _ in 0..100 {
            assert!((dielectric(dir, Vec3::Y, 1.0, rng.next_f32()) - dir).length() < 1e-6);
        }
        // From inside (eta = ior) at a grazing angle.
        let grazing = Vec3::new(0.9, -(1.0f32 - 0.81).sqrt(), 0.0);
        let out = dielectric(grazing, Vec3::Y, 1.5, rng.next_f32());
        assert!(out.y > 0.0, "total internal reflection expected, got {out}");
    }

    /// The fraction of `count` paths arriving along `dir` at a surface of
    /// index ratio `eta` (normal +y) that it reflects.
    fn reflected_fraction(dir: Vec3, eta: f32, count: u32) -> f64 {
        let mut rng = Rng::for_sample(10, 0, 0, 0);
        let reflected = (0..count)
            .filter(|_| dielectric(dir, Vec3::Y, eta, rng.next_f32()).y > 0.0)
            .count();
        reflected as f64 / count as f64
    }

    #[test]
    fn ior_ten_reflects_its_fresnel_fraction() {
        // Binomial standard error at 200 000 draws is below 0.0012; allow 5.
        let (count, tolerance) = (200_000, 0.006);
        // Normal incidence, from either side: ((n − 1)/(n + 1))² = 0.669.
        let normal = (9.0f64 / 11.0).powi(2);
        for eta in [0.1, 10.0] {
            let f = reflected_fraction(Vec3::NEG_Y, eta, count);
            assert!((f - normal).abs() < tolerance, "{eta}: {f} vs {normal}");
        }
        // At Brewster's angle (tan θ = n) only the s-polarised half reflects:
        // R = ((n² − 1)/(n² + 1))² / 2 = 0.480.
        let brewster = 10.0f32.atan();
        let dir = Vec3::new(brewster.sin(), -brewster.cos(), 0.0);
        let f = reflected_fraction(dir, 0.1, count);
        let expected = (99.0f64 / 101.0).powi(2) / 2.0;
        assert!(
            (f - expected).abs() < tolerance,
            "Brewster: {f} vs {expected}"
        );
    }
}
