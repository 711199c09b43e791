//! Materials as plain data; their scattering lives in `render`.

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
}
