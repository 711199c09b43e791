//! A scene material at a hit becomes its [`Bsdf`]: the one place a hit's
//! texture is looked up, and where a metal with (almost) no fuzz becomes a
//! specular mirror, a dielectric's index ratio is chosen by the side hit and
//! the microfacet materials get their lobes ([`super::rough`]). A normal or
//! bump map wrapper gives its material the mapped shading normal
//! ([`super::maps`]).

use glam::Vec3;

use super::bsdf::Bsdf;
use super::coat::Coats;
use super::fuzz::SPECULAR_FUZZ;
use super::maps;
use super::microfacet::conductor_of_reflectance;
use super::rough::{self, Lobe};
use super::texture::lookup;
use crate::geometry::Hit;
use crate::scene::material::ConductorFresnel;
use crate::scene::{Material, MaterialId, Scene};

/// The scattering of `hit`'s material at `hit`, seen from `wo`, a hit of a
/// world whose frame has its origin at the scene point `frame`: textures
/// are looked up at the hit's scene point, so they do not move with the
/// frame. A plastic reads its coat's tables from `coats`.
#[inline]
pub fn bsdf<'a>(scene: &Scene, coats: &'a Coats, hit: &Hit, wo: Vec3, frame: Vec3) -> Bsdf<'a> {
    // Maps read their textures at the offset point the scattered rays
    // leave from.
    let (base, normal) = match *scene.material(hit.material) {
        Material::NormalMap {
            base,
            map,
            strength,
        } => (
            base,
            maps::normal_mapped(scene, hit, wo, hit.point + frame, map, strength),
        ),
        Material::Bump {
            base,
            height,
            scale,
        } => (
            base,
            maps::bumped(scene, hit, wo, hit.point + frame, height, scale),
        ),
        _ => (hit.material, hit.normal),
    };
    surface(scene, coats, base, hit, normal, frame)
}

/// The scattering of the material `id` at `hit` with shading normal
/// `normal`.
#[inline(always)]
fn surface<'a>(
    scene: &Scene,
    coats: &'a Coats,
    id: MaterialId,
    hit: &Hit,
    normal: Vec3,
    frame: Vec3,
) -> Bsdf<'a> {
    let albedo = |id| lookup(scene, id, hit.uv, hit.point + frame);
    let geo_normal = hit.geo_normal;
    let rough = |lobe| Bsdf::Rough {
        lobe,
        normal,
        geo_normal,
    };
    match *scene.material(id) {
        Material::Lambertian { albedo: tex } => Bsdf::Lambertian {
            albedo: albedo(tex),
            normal,
            geo_normal,
        },
        Material::Metal { albedo: tex, fuzz } if fuzz < SPECULAR_FUZZ => Bsdf::Mirror {
            albedo: albedo(tex),
            normal,
            geo_normal,
        },
        Material::Metal { albedo: tex, fuzz } => Bsdf::FuzzyMetal {
            albedo: albedo(tex),
            fuzz,
            normal,
            geo_normal,
        },
        Material::Dielectric { ior } => Bsdf::Dielectric {
            eta: if hit.front_face { 1.0 / ior } else { ior },
            normal,
        },
        Material::Light { emit, two_sided } => Bsdf::Emitter {
            emitted: if hit.front_face || two_sided {
                albedo(emit)
            } else {
                Vec3::ZERO
            },
        },
        Material::Isotropic { albedo: tex } => Bsdf::Isotropic {
            albedo: albedo(tex),
        },
        Material::Conductor { fresnel, alpha } => {
            let (eta, k) = match fresnel {
                ConductorFresnel::Ior { eta, k } => (eta, k),
                ConductorFresnel::Reflectance(tex) => conductor_of_reflectance(albedo(tex)),
            };
            rough(Lobe::Conductor(rough::Conductor { eta, k, alpha }))
        }
        Material::RoughDielectric { ior, alpha } => rough(Lobe::Dielectric(rough::Dielectric {
            eta: if hit.front_face { ior } else { 1.0 / ior },
            alpha,
        })),
        Material::Plastic {
            albedo: tex,
            ior,
            alpha,
        } => rough(Lobe::Plastic(rough::Plastic {
            albedo: albedo(tex),
            eta: ior,
            alpha,
            coat: coats.of(id),
        })),
        Material::MetalRough {
            base,
            metallic,
            roughness,
            metallic_roughness,
        } => {
            // glTF: roughness in green, metallic in blue.
            let (r, m) = match metallic_roughness {
                Some(tex) => {
                    let t = albedo(tex);
                    (roughness * t.y, metallic * t.z)
                }
                None => (roughness, metallic),
            };
            rough(Lobe::MetalRough(rough::MetalRough {
                base: albedo(base),
                metallic: m.clamp(0.0, 1.0),
                alpha: r * r,
            }))
        }
        // The language refuses a map of a map; were one built in code,
        // its inner map is left out.
        Material::NormalMap { base, .. } | Material::Bump { base, .. } => {
            inner(scene, coats, base, hit, normal, frame)
        }
    }
}

/// [`surface`] of a map's material, out of line so that `surface` is
/// inlined where it is called.
#[inline(never)]
fn inner<'a>(
    scene: &Scene,
    coats: &'a Coats,
    id: MaterialId,
    hit: &Hit,
    normal: Vec3,
    frame: Vec3,
) -> Bsdf<'a> {
    surface(scene, coats, id, hit, normal, frame)
}
