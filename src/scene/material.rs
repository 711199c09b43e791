//! Materials as plain data; their scattering lives in `render`.

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
