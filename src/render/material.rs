//! A scene material at a hit becomes its [`Bsdf`]: the one place a hit's
//! texture is looked up, and where a metal with (almost) no fuzz becomes a
//! specular mirror and a dielectric's index ratio is chosen by the side hit.
//! A normal or bump map wrapper gives its material the mapped shading
//! normal ([`super::maps`]).

use glam::Vec3;

use super::bsdf::Bsdf;
use super::fuzz::SPECULAR_FUZZ;
use super::maps;
use super::texture::lookup;
use crate::geometry::Hit;
use crate::scene::{Material, Scene};

/// The scattering of `hit`'s material at `hit`, seen from `wo`, a hit of a
/// world whose frame has its origin at the scene point `frame`: textures
/// are looked up at the hit's scene point, so they do not move with the
/// frame.
#[inline]
pub fn bsdf(scene: &Scene, hit: &Hit, wo: Vec3, frame: Vec3) -> Bsdf {
    match *scene.material(hit.material) {
        Material::NormalMap {
            base,
            map,
            strength,
        } => {
            let p = hit.point + frame;
            let normal = maps::normal_mapped(scene, hit, wo, p, map, strength);
            surface(scene, scene.material(base), hit, normal, frame)
        }
        Material::Bump {
            base,
            height,
            scale,
        } => {
            let p = hit.point + frame;
            let normal = maps::bumped(scene, hit, wo, p, height, scale);
            surface(scene, scene.material(base), hit, normal, frame)
        }
        ref m => surface(scene, m, hit, hit.normal, frame),
    }
}

/// The scattering of `material` at `hit` with shading normal `normal`.
#[inline(always)]
fn surface(scene: &Scene, material: &Material, hit: &Hit, normal: Vec3, frame: Vec3) -> Bsdf {
    let albedo = |id| lookup(scene, id, hit.uv, hit.point + frame);
    let geo_normal = hit.geo_normal;
    match *material {
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
        // The language refuses a map of a map; were one built in code,
        // its inner map is left out.
        Material::NormalMap { base, .. } | Material::Bump { base, .. } => {
            inner(scene, scene.material(base), hit, normal, frame)
        }
    }
}

/// [`surface`] of a map's material, out of line so that `surface` is
/// inlined where it is called.
#[inline(never)]
fn inner(scene: &Scene, material: &Material, hit: &Hit, normal: Vec3, frame: Vec3) -> Bsdf {
    surface(scene, material, hit, normal, frame)
}
