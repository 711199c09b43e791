//! A glTF file's metallic-roughness materials as scene materials.
//!
//! - `baseColorFactor` × `baseColorTexture` (sRGB) is the base colour of
//!   a [`Material::MetalRough`]; `metallicFactor` and `roughnessFactor`
//!   are its metallic and perceptual roughness, scaled by the blue and
//!   green channels of `metallicRoughnessTexture` (read as data).
//! - `normalTexture` wraps it in a [`Material::NormalMap`] of strength
//!   `scale`.
//! - A material with a non-zero `emissiveFactor` (× `emissiveTexture`,
//!   × `KHR_materials_emissive_strength`) becomes a [`Material::Light`]
//!   of that radiance, one-sided unless `doubleSided`: it emits and does
//!   not reflect (its base colour is not used).
//!
//! A factor times a texture is baked into one image. An image that fails
//! to load is a warning; the material then uses its factor alone.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Vec3;

use super::Evaluator;
use crate::lang::source::Span;
use crate::scene::gltf::{GltfFile, GltfMaterial, ImageSource};
use crate::scene::{Encoding, ImageData, Material, MaterialId, Texture, TextureId};

/// glTF's default material: white, metallic 1, roughness 1.
fn default_material() -> GltfMaterial {
    GltfMaterial {
        name: "default".into(),
        base_color: Vec3::ONE,
        base_texture: None,
        metallic: 1.0,
        roughness: 1.0,
        metallic_roughness_texture: None,
        normal: None,
        emissive: Vec3::ZERO,
        emissive_texture: None,
        double_sided: false,
    }
}

/// Decoded images of one file, by image index and encoding (`None`: it
/// failed, and the warning was given).
type Images = HashMap<(usize, Encoding), Option<Arc<ImageData>>>;

impl Evaluator {
    /// The scene material of each of the file's materials, then of glTF's
    /// default material (for primitives that name none).
    pub(super) fn gltf_materials(&mut self, file: &GltfFile, span: Span) -> Vec<MaterialId> {
        let mut images = Images::new();
        let mut out = Vec::with_capacity(file.materials.len() + 1);
        for m in file.materials.iter().cloned().chain([default_material()]) {
            let mut image = |ev: &mut Evaluator, k: Option<usize>, e: Encoding| {
                let k = k?;
                if let Some(hit) = images.get(&(k, e)) {
                    return hit.clone();
                }
                let loaded = ev.gltf_image(file.images.get(k)?, span, e);
                images.insert((k, e), loaded.clone());
                loaded
            };
            let material = if m.emissive.max_element() > 0.0 {
                let tex = image(self, m.emissive_texture, Encoding::Srgb);
                Material::Light {
                    emit: self.factor_texture(tex, m.emissive.max(Vec3::ZERO), Encoding::Srgb),
                    two_sided: m.double_sided,
                }
            } else {
                let tex = image(self, m.base_texture, Encoding::Srgb);
                let base = self.factor_texture(
                    tex,
                    m.base_color.clamp(Vec3::ZERO, Vec3::ONE),
                    Encoding::Srgb,
                );
                let mr = image(self, m.metallic_roughness_texture, Encoding::Data)
                    .map(|i| self.factor_texture(Some(i), Vec3::ONE, Encoding::Data));
                Material::MetalRough {
                    base,
                    metallic: m.metallic.clamp(0.0, 1.0),
                    roughness: m.roughness.clamp(0.0, 1.0),
                    metallic_roughness: mr,
                }
            };
            let mut id = self.scene.add_material(material);
            if let Some((k, scale)) = m.normal {
                if m.emissive.max_element() <= 0.0 {
                    if let Some(map) = image(self, Some(k), Encoding::Data) {
                        let map = self.factor_texture(Some(map), Vec3::ONE, Encoding::Data);
                        id = self.scene.add_material(Material::NormalMap {
                            base: id,
                            map,
                            strength: scale.max(0.0),
                        });
                    }
                }
            }
            out.push(id);
        }
        out
    }

    /// `image` × `factor` as one texture (`factor` alone without an image).
    fn factor_texture(
        &mut self,
        image: Option<Arc<ImageData>>,
        factor: Vec3,
        encoding: Encoding,
    ) -> TextureId {
        let Some(image) = image else {
            return self.scene.add_texture(Texture::Solid(factor));
        };
        let image = if factor == Vec3::ONE {
            image
        } else {
            let mut scaled = (*image).clone();
            scaled.pixels.iter_mut().for_each(|p| *p *= factor);
            Arc::new(scaled)
        };
        self.scene
            .add_texture(super::assets::image_texture(image, encoding))
    }

    /// One image of the file decoded by `encoding`, its pixels charged to
    /// the memory budget; a failure is a warning and `None`.
    fn gltf_image(
        &mut self,
        source: &ImageSource,
        span: Span,
        encoding: Encoding,
    ) -> Option<Arc<ImageData>> {
        let loaded = match source {
            ImageSource::File(path) => {
                self.charge_image(path, span).ok()?;
                self.options
                    .assets
                    .image_as(path, encoding)
                    .map_err(|e| e.to_string())
            }
            ImageSource::Bytes(bytes, name) => {
                if let Some((w, h)) = ImageData::bytes_dimensions(bytes) {
                    let pixels = w as f64 * h as f64 * super::budget::BYTES_PER_IMAGE_PIXEL;
                    self.charge(pixels, span, "this glTF image's pixels").ok()?;
                }
                ImageData::from_bytes(bytes, name, encoding)
                    .map(Arc::new)
                    .map_err(|e| e.to_string())
            }
            ImageSource::Missing(why) => Err(why.clone()),
        };
        match loaded {
            Ok(image) => Some(image),
            Err(why) => {
                self.warn_gltf(
                    span,
                    format!("a texture did not load ({why}); its material uses its factor alone"),
                );
                None
            }
        }
    }
}
