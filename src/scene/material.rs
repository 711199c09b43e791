//! Materials as plain data; their scattering lives in `render`.

use glam::{Vec2, Vec3};

use super::TextureId;

/// How a surface (or a medium) scatters and emits light.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Material {
    /// Ideal diffuse reflection.
    Lambertian { albedo: TextureId },
    /// Mirror reflection perturbed by `fuzz` (0 = perfect mirror, ≤ 1).
    Metal { albedo: TextureId, fuzz: f32 },
    /// Glass-like refraction with index of refraction `ior` (> 0).
    Dielectric { ior: f32 },
    /// A diffuse emitter; emits on the front face only unless `two_sided`.
    Light { emit: TextureId, two_sided: bool },
    /// Isotropic phase function, the material of participating media.
    Isotropic { albedo: TextureId },
    /// A rough metal: GGX microfacets of roughness `alpha` (α along the
    /// surface's tangent, α along its bitangent; both > 0) reflecting by
    /// the Fresnel equations of a conductor.
    Conductor {
        fresnel: ConductorFresnel,
        alpha: Vec2,
    },
    /// Rough glass: reflection and refraction through GGX microfacets of
    /// roughness `alpha` (> 0) with index of refraction `ior` (> 0).
    RoughDielectric { ior: f32, alpha: f32 },
    /// A diffuse base of colour `albedo` under a dielectric coat of index
    /// `ior` (> 0) whose GGX roughness is `alpha` (> 0).
    Plastic {
        albedo: TextureId,
        ior: f32,
        alpha: f32,
    },
    /// glTF 2.0's metallic–roughness material: `base` colour, `metallic` in
    /// [0, 1] and the perceptual `roughness` r in [0, 1] (GGX α = r²); the
    /// optional `metallic_roughness` texture multiplies roughness by its
    /// green channel and metallic by its blue one.
    MetalRough {
        base: TextureId,
        metallic: f32,
        roughness: f32,
        metallic_roughness: Option<TextureId>,
    },
}

/// Where a conductor's Fresnel reflectance comes from.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum ConductorFresnel {
    /// The complex index of refraction `eta + i k` per RGB channel.
    Ior { eta: Vec3, k: Vec3 },
    /// The reflectance at normal incidence (each channel in [0, 1]).
    Reflectance(TextureId),
}
