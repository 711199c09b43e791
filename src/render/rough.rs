//! The microfacet lobes, in the local frame of [`super::microfacet`] (+z
//! the shading normal, `wo` towards the viewer, `wi` towards the light):
//! a rough conductor and a rough dielectric as Mitsuba 3's
//! `roughconductor` and `roughdielectric` (GGX, separable Smith masking,
//! visible-normal sampling, radiance transport), a coated diffuse as its
//! `roughplastic`, and glTF 2.0's metallic–roughness BRDF. Each returns
//! f·cos θi and the density its sampling gives, as [`super::bsdf::Bsdf`]
//! does.

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::coat;
use super::microfacet::{
    fresnel_conductor, fresnel_dielectric, fresnel_schlick, reflect, refract, Ggx,
};

/// A sampled local direction: `wi`, f·cos/pdf and the density.
pub type Sampled = (Vec3, Vec3, f32);

/// A cosine-distributed direction about +z.
#[inline]
fn cosine(u: Vec2) -> Vec3 {
    crate::sampling::warp::cosine_hemisphere(Vec3::Z, u)
}

/// GGX reflection off a conductor of complex index `eta + i k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    pub eta: Vec3,
    pub k: Vec3,
    pub alpha: Vec2,
}

impl Conductor {
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<Sampled> {
        if wo.z <= 0.0 {
            return None;
        }
        let ggx = Ggx::new(self.alpha);
        let m = ggx.sample_visible(wo, u);
        let wi = reflect(wo, m);
        let c = wo.dot(m);
        if wi.z <= 0.0 || c <= 0.0 {
            return None;
        }
        let weight = fresnel_conductor(c, self.eta, self.k) * ggx.g1(wi, m);
        let pdf = ggx.visible(wo, m) / (4.0 * c);
        (pdf > 0.0).then_some((wi, weight, pdf))
    }

    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let ggx = Ggx::new(self.alpha);
        let m = (wo + wi).normalize();
        let c = wo.dot(m);
        let pdf = ggx.visible(wo, m) / (4.0 * c);
        if !(pdf > 0.0) {
            return None;
        }
        let f = fresnel_conductor(c, self.eta, self.k) * ggx.d(m) * ggx.g_separable(wo, wi, m)
            / (4.0 * wo.z);
        Some((f, pdf))
    }
}

/// GGX reflection and refraction at an interface where the index below
/// (−z) over the index above (+z, where `wo` is) is `eta`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    pub eta: f32,
    pub alpha: f32,
}

impl Dielectric {
    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2, u1: f32) -> Option<Sampled> {
        if wo.z <= 0.0 {
            return None;
        }
        let ggx = Ggx::new(Vec2::splat(self.alpha));
        let m = ggx.sample_visible(wo, u);
        let c = wo.dot(m);
        if c <= 0.0 {
            return None;
        }
        let visible = ggx.visible(wo, m);
        let (f, cos_t) = fresnel_dielectric(c, self.eta);
        if u1 < f {
            let wi = reflect(wo, m);
            let pdf = f * visible / (4.0 * c);
            (wi.z > 0.0 && pdf > 0.0).then(|| (wi, Vec3::splat(ggx.g1(wi, m)), pdf))
        } else {
            let eta = self.eta;
            let wi = refract(wo, m, eta, cos_t);
            let cm = wi.dot(m);
            let denom = c + eta * cm;
            let pdf = (1.0 - f) * visible * eta * eta * cm.abs() / (denom * denom);
            // Radiance is compressed by η² going into the denser side.
            let weight = ggx.g1(wi, m) / (eta * eta);
            (wi.z < 0.0 && pdf > 0.0).then_some((wi, Vec3::splat(weight), pdf))
        }
    }

    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
        if wo.z <= 0.0 || wi.z == 0.0 {
            return None;
        }
        let ggx = Ggx::new(Vec2::splat(self.alpha));
        let eta = self.eta;
        let reflected = wi.z > 0.0;
        let m = if reflected {
            (wo + wi).normalize()
        } else {
            let h = (wo + eta * wi).normalize();
            if h.z < 0.0 {
                -h
            } else {
                h
            }
        };
        let (c, cm) = (wo.dot(m), wi.dot(m));
        // Both directions must see the facet from their own side.
        if c <= 0.0 || (cm > 0.0) != reflected || cm == 0.0 || !m.is_finite() {
            return None;
        }
        let (f, _) = fresnel_dielectric(c, eta);
        let d = ggx.d(m);
        let g = ggx.g_separable(wo, wi, m);
        let visible = ggx.visible(wo, m);
        let (value, pdf) = if reflected {
            (f * d * g / (4.0 * wo.z), f * visible / (4.0 * c))
        } else {
            let denom = (c + eta * cm) * (c + eta * cm);
            (
                (1.0 - f) * d * g * c * cm.abs() / (wo.z * denom),
                (1.0 - f) * visible * eta * eta * cm.abs() / denom,
            )
        };
        (pdf > 0.0).then_some((Vec3::splat(value), pdf))
    }
}

/// A lambertian base of colour `albedo` under a rough dielectric coat of
/// relative index `eta`, as Mitsuba 3's `roughplastic`: the coat's GGX
/// reflection plus the base seen through the coat's directional
/// transmittance on the way in and out, amplified by the inter-reflections
/// under the coat (its hemispherical internal reflectance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    pub albedo: Vec3,
    pub eta: f32,
    pub alpha: f32,
}

impl Plastic {
    /// The probability of sampling the coat's reflection seen from `wo`,
    /// given the coat's transmittance `t` towards `wo`: the reflected and
    /// transmitted fractions weighted by the coat's and the base's mean
    /// reflectance.
    #[inline]
    fn specular_probability(&self, t: f32) -> f32 {
        let s = 1.0 / (1.0 + self.albedo.element_sum() / 3.0);
        let spec = (1.0 - t) * s;
        spec / (spec + t * (1.0 - s))
    }

    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2, u1: f32) -> Option<Sampled> {
        if wo.z <= 0.0 {
            return None;
        }
        let t = coat::transmittance(self.eta, self.alpha, wo.z);
        let wi = if u1 < self.specular_probability(t) {
            reflect(wo, Ggx::new(Vec2::splat(self.alpha)).sample_visible(wo, u))
        } else {
            cosine(u)
        };
        let (f, pdf) = self.eval_pdf(wo, wi)?;
        Some((wi, f / pdf, pdf))
    }

    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let ggx = Ggx::new(Vec2::splat(self.alpha));
        let m = (wo + wi).normalize();
        let c = wo.dot(m);
        let (fresnel, _) = fresnel_dielectric(c, self.eta);
        let specular = fresnel * ggx.d(m) * ggx.g_separable(wo, wi, m) / (4.0 * wo.z);
        let (t_o, t_i, internal) = coat::transmittances(self.eta, self.alpha, wo.z, wi.z);
        let diffuse =
            self.albedo / (1.0 - internal) * (FRAC_1_PI * t_o * t_i * wi.z / (self.eta * self.eta));
        let p = self.specular_probability(t_o);
        let pdf = p * ggx.visible(wo, m) / (4.0 * c) + (1.0 - p) * wi.z * FRAC_1_PI;
        (pdf > 0.0).then_some((diffuse + Vec3::splat(specular), pdf))
    }
}

/// glTF 2.0's metallic–roughness BRDF (its specification's appendix B):
/// GGX with height-correlated masking and Schlick's Fresnel, reflecting
/// the base colour for a metal, and 4 % over a lambertian base colour for
/// a dielectric, mixed linearly by `metallic`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetalRough {
    pub base: Vec3,
    pub metallic: f32,
    pub alpha: f32,
}

/// The reflectance at normal incidence of glTF's dielectric (index 1.5).
const DIELECTRIC_F0: f32 = 0.04;

impl MetalRough {
    /// The probability of sampling the GGX lobe seen from `wo`: its share
    /// of the two lobes' rough reflectances.
    #[inline]
    fn specular_probability(&self, wo: Vec3) -> f32 {
        let dielectric = 1.0 - self.metallic;
        let fresnel = fresnel_schlick(wo.z, Vec3::splat(DIELECTRIC_F0)).x;
        let spec = self.metallic + dielectric * fresnel;
        let diffuse = dielectric * (1.0 - fresnel) * self.base.element_sum() / 3.0;
        if spec + diffuse > 0.0 {
            spec / (spec + diffuse)
        } else {
            1.0
        }
    }

    #[inline]
    pub fn sample(&self, wo: Vec3, u: Vec2, u1: f32) -> Option<Sampled> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = if u1 < self.specular_probability(wo) {
            reflect(wo, Ggx::new(Vec2::splat(self.alpha)).sample_visible(wo, u))
        } else {
            cosine(u)
        };
        let (f, pdf) = self.eval_pdf(wo, wi)?;
        Some((wi, f / pdf, pdf))
    }

    #[inline]
    pub fn eval_pdf(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32)> {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let ggx = Ggx::new(Vec2::splat(self.alpha));
        let m = (wo + wi).normalize();
        let c = wo.dot(m);
        // D · V with V = G2 / (4 cos θo cos θi), times cos θi.
        let specular = ggx.d(m) * ggx.g_correlated(wo, wi) / (4.0 * wo.z);
        let metal = fresnel_schlick(c, self.base) * specular;
        let f0 = fresnel_schlick(c, Vec3::splat(DIELECTRIC_F0)).x;
        let dielectric = (1.0 - f0) * self.base * (FRAC_1_PI * wi.z) + Vec3::splat(f0 * specular);
        let f = self.metallic * metal + (1.0 - self.metallic) * dielectric;
        let p = self.specular_probability(wo);
        let pdf = p * ggx.visible(wo, m) / (4.0 * c) + (1.0 - p) * wi.z * FRAC_1_PI;
        (pdf > 0.0).then_some((f, pdf))
    }
}
