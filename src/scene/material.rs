//! Materials as plain data; their scattering lives in `render`.

use glam::{Vec2, Vec3};

use super::{MaterialId, TextureId};

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
    /// `base` with its shading normal read from a tangent-space normal map
    /// (`map`, an image read as data: x, y, z = 2·rgb − 1 along ∂p/∂u, ∂p/∂v
    /// and the normal), its tilt scaled by `strength` (≥ 0).
    NormalMap {
        base: MaterialId,
        map: TextureId,
        strength: f32,
    },
    /// `base` with its shading normal tilted by the slope of the height
    /// field `scale` × `height` over the surface's (u, v).
    Bump {
        base: MaterialId,
        height: TextureId,
        scale: f32,
    },
}

impl Material {
    /// Whether the material reads a tangent frame at its hits.
    pub fn needs_tangents(&self) -> bool {
        matches!(self, Material::NormalMap { .. } | Material::Bump { .. })
    }
}

/// Where a conductor's Fresnel reflectance comes from.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum ConductorFresnel {
    /// The complex index of refraction `eta + i k` per RGB channel.
    Ior { eta: Vec3, k: Vec3 },
    /// The reflectance at normal incidence (each channel in [0, 1]).
    Reflectance(TextureId),
}

/// The named conductors `conductor("Au")` accepts: name, η and k per RGB
/// channel. The values are Mitsuba 3's spectral data (`data/ior/*.spd`,
/// from Palik's handbook of optical constants) reduced to linear sRGB by
/// Mitsuba 3.9.1's `scalar_rgb` variant, so that twin scenes agree.
pub const CONDUCTORS: &[(&str, Vec3, Vec3)] = &[
    (
        "Ag",
        Vec3::new(0.155276, 0.116728, 0.138388),
        Vec3::new(4.82835, 3.12222, 2.1469),
    ),
    (
        "Al",
        Vec3::new(1.6575, 0.880405, 0.521244),
        Vec3::new(9.22381, 6.2695, 4.837),
    ),
    (
        "Au",
        Vec3::new(0.143036, 0.375307, 1.44205),
        Vec3::new(3.983, 2.38556, 1.60336),
    ),
    (
        "Cr",
        Vec3::new(4.36967, 2.91651, 1.6549),
        Vec3::new(5.20655, 4.23131, 3.7547),
    ),
    (
        "Cu",
        Vec3::new(0.201005, 0.92375, 1.10222),
        Vec3::new(3.91326, 2.45305, 2.14209),
    ),
];
