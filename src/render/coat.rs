//! The tables of a rough dielectric coat that the plastic material reads,
//! built as Mitsuba 3's `roughplastic` builds them: the coat's directional
//! transmittance T(μ) at 64 cosines μ = i/63 (read by linear
//! interpolation), the albedo of its GGX refraction, and its internal
//! reflectance 2·mean(R′(μ)·μ) over the same cosines, where R′ is the
//! albedo of its GGX reflection seen from inside (index 1/η). Both albedos
//! count single scattering only, with separable masking. Building one costs
//! about a millisecond, so [`Coats`] builds each scene's tables once per
//! render, before the first path, and a hit only reads them.

use glam::{Vec2, Vec3};

use super::microfacet::{fresnel_dielectric, reflect, refract, Ggx};
use crate::scene::{Material, MaterialId, Scene};

/// Cosines the transmittance is tabulated at.
const RESOLUTION: usize = 64;

/// Quadrature points per axis over the visible-normal square.
const QUADRATURE: usize = 32;

/// One coat's tables.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    transmittance: [f32; RESOLUTION],
    internal: f32,
}

/// The albedos of GGX reflection and refraction of roughness `alpha` at
/// an interface of relative index `eta`, seen at cosine `mu`: the means of
/// F·G1 and (1 − F)·G1 over the visible normals, by the midpoint rule on
/// the square they are sampled from.
fn albedos(eta: f32, alpha: f32, mu: f32) -> (f32, f32) {
    let ggx = Ggx::new(Vec2::splat(alpha));
    let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
    let (mut reflected, mut refracted) = (0.0f64, 0.0f64);
    for i in 0..QUADRATURE {
        for j in 0..QUADRATURE {
            let u = Vec2::new(
                (i as f32 + 0.5) / QUADRATURE as f32,
                (j as f32 + 0.5) / QUADRATURE as f32,
            );
            let m = ggx.sample_visible(wo, u);
            let c = wo.dot(m);
            if c <= 0.0 {
                continue;
            }
            let (f, cos_t) = fresnel_dielectric(c, eta);
            let wi = reflect(wo, m);
            if wi.z > 0.0 {
                reflected += (f * ggx.g1(wi, m)) as f64;
            }
            let wt = refract(wo, m, eta, cos_t);
            if wt.z < 0.0 && f < 1.0 {
                refracted += ((1.0 - f) * ggx.g1(wt, m)) as f64;
            }
        }
    }
    let n = (QUADRATURE * QUADRATURE) as f64;
    ((reflected / n) as f32, (refracted / n) as f32)
}

impl Table {
    /// The tables of a coat of relative index `eta` and GGX roughness
    /// `alpha`.
    pub fn build(eta: f32, alpha: f32) -> Table {
        let mut transmittance = [0.0; RESOLUTION];
        let mut internal = 0.0f64;
        for (i, t) in transmittance.iter_mut().enumerate() {
            let mu = (i as f32 / (RESOLUTION - 1) as f32).max(1e-6);
            *t = albedos(eta, alpha, mu).1;
            internal += (albedos(1.0 / eta, alpha, mu).0 * mu) as f64;
        }
        Table {
            transmittance,
            internal: (2.0 * internal / RESOLUTION as f64) as f32,
        }
    }

    /// The coat's transmittance towards a direction of cosine `mu`,
    /// interpolated linearly.
    #[inline]
    pub fn at(&self, mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (RESOLUTION - 1) as f32;
        let i = (x as usize).min(RESOLUTION - 2);
        let w = x - i as f32;
        (1.0 - w) * self.transmittance[i] + w * self.transmittance[i + 1]
    }

    /// The coat's hemispherical internal reflectance.
    #[inline]
    pub fn internal(&self) -> f32 {
        self.internal
    }
}

/// The coat tables of a scene's plastic materials: one per distinct
/// (index, roughness), found by material.
#[derive(Debug, Default)]
pub struct Coats {
    tables: Vec<Table>,
    /// Per material of the scene: its table's index, if it is a plastic.
    of_material: Vec<Option<usize>>,
}

impl Coats {
    /// The tables every plastic of `scene` reads.
    pub fn for_scene(scene: &Scene) -> Coats {
        let mut keys: Vec<(u32, u32)> = Vec::new();
        let mut tables = Vec::new();
        let of_material = scene
            .materials
            .iter()
            .map(|m| match *m {
                Material::Plastic { ior, alpha, .. } => {
                    let key = (ior.to_bits(), alpha.to_bits());
                    Some(keys.iter().position(|k| *k == key).unwrap_or_else(|| {
                        keys.push(key);
                        tables.push(Table::build(ior, alpha));
                        tables.len() - 1
                    }))
                }
                _ => None,
            })
            .collect();
        Coats {
            tables,
            of_material,
        }
    }

    /// The table of the plastic material `id`.
    #[inline]
    pub fn of(&self, id: MaterialId) -> &Table {
        let k = self.of_material[id.index()].expect("a coat table for every plastic");
        &self.tables[k]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_smooth_coat_transmits_what_fresnel_does_not_reflect() {
        // At α → 0 the albedos are the Fresnel reflectance of the
        // direction and the rest.
        for mu in [1.0f32, 0.6, 0.2] {
            let (r, t) = albedos(1.5, 1e-4, mu);
            let f = fresnel_dielectric(mu, 1.5).0;
            assert!(
                (r - f).abs() < 1e-3 && (t - (1.0 - f)).abs() < 1e-3,
                "{mu}: {r} {t} vs {f}"
            );
        }
        // Index 1 reflects nothing and, smooth, transmits everything; a
        // rough coat's masking loses some of each.
        let (r, t) = albedos(1.0, 0.3, 0.5);
        assert!(r.abs() < 1e-6 && t < 1.0 && t > 0.9, "{r} {t}");
        let t = Table::build(1.5, 0.3);
        assert!(t.transmittance.iter().all(|&t| (0.0..=1.0).contains(&t)));
        assert!((t.at(1.0) - 0.96).abs() < 0.01, "{}", t.at(1.0));
        // Seen from inside, everything beyond the critical angle reflects:
        // the internal reflectance of a smooth coat of index 1.5 is about
        // 0.6 (1 − (1 − 0.092)/η², the hemispherical Fresnel from inside).
        let smooth = Table::build(1.5, 1e-4);
        assert!(
            (smooth.internal - 0.596).abs() < 0.02,
            "{}",
            smooth.internal
        );
    }
}
