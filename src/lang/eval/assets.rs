//! Files a scene refers to: image textures and OBJ meshes, loaded only when
//! used, once per path, with the path tried in every error.

use crate::lang::codes::Code;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{budget, Eval, Evaluator};
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;
use crate::scene::mesh::{MeshMap, MeshMaterial, MeshMaterialKind};
use crate::scene::obj::ObjError;
use crate::scene::obj_lines::LineError;
use crate::scene::{Encoding, ImageData, Material, MaterialId, MeshId, Texture, TextureId};

const IMAGE_TYPES: &[&str] = &["png", "jpg", "jpeg"];
const HDR_TYPES: &[&str] = &["exr", "hdr"];

impl Evaluator {
    /// Resolves `path` against the directory of the file `span` is in.
    pub(super) fn resolve(&self, path: &str, span: Span) -> PathBuf {
        let p = Path::new(path);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base_dir(span).join(p)
        }
    }

    /// An error unless `path` has one of the `allowed` extensions.
    pub(super) fn check_type(
        &mut self,
        path: &Path,
        span: Span,
        allowed: &[&str],
        what: &str,
    ) -> Eval<()> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        if allowed.contains(&ext.as_str()) {
            return Ok(());
        }
        Err(self.report(
            Diagnostic::error(
                Code::FileType,
                span,
                format!("`{}` is not a supported {what} file", path.display()),
            )
            .label("unsupported file type")
            .help(format!("{what} files must end in .{}", allowed.join(", ."))),
        ))
    }

    /// The texture of the image file `path` decoded by `encoding` (loaded
    /// once).
    pub(super) fn image_texture(
        &mut self,
        path: &str,
        span: Span,
        encoding: Encoding,
    ) -> Eval<TextureId> {
        let full = self.resolve(path, span);
        self.image_file(full, span, encoding)
    }

    /// [`Evaluator::image_texture`] of a resolved path.
    pub(super) fn image_file(
        &mut self,
        full: PathBuf,
        span: Span,
        encoding: Encoding,
    ) -> Eval<TextureId> {
        self.check_type(&full, span, IMAGE_TYPES, "image")?;
        if self.dry {
            return Ok(TextureId(0));
        }
        let key = (full, encoding);
        if let Some(&id) = self.caches.images.get(&key) {
            return Ok(id);
        }
        let full = &key.0;
        self.charge_image(full, span)?;
        match self.options.assets.image_as(full, encoding) {
            Ok(image) => {
                let id = self.scene.add_texture(image_texture(image, encoding));
                self.caches.images.insert(key, id);
                Ok(id)
            }
            Err(e) => Err(self.report(
                Diagnostic::error(Code::Io, span, e.to_string())
                    .label("image used here")
                    .help("relative paths resolve against the directory of the scene file"),
            )),
        }
    }

    /// The high-dynamic-range image `path` of an environment (loaded once).
    pub(super) fn environment_image(&mut self, path: &str, span: Span) -> Eval<Arc<ImageData>> {
        let full = self.resolve(path, span);
        let ext = full
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        if IMAGE_TYPES.contains(&ext.as_str()) {
            return Err(self.report(
                Diagnostic::error(
                    Code::FileType,
                    span,
                    format!("`{}` holds 8-bit colours, not radiance", full.display()),
                )
                .label("not a high-dynamic-range image")
                .help(
                    "an environment needs an .exr or .hdr file; convert it with e.g. \
                     `oiiotool in.png --colorconvert sRGB linear -o out.exr`, or make a \
                     sky with `rtlang gen sky`",
                ),
            ));
        }
        self.check_type(&full, span, HDR_TYPES, "environment image")?;
        if self.dry {
            return Ok(Arc::new(ImageData {
                width: 1,
                height: 1,
                pixels: vec![glam::Vec3::ZERO],
            }));
        }
        if let Some(image) = self.caches.environments.get(&full) {
            return Ok(image.clone());
        }
        self.charge_image(&full, span)?;
        match self.options.assets.hdr_image(&full) {
            Ok(image) => {
                self.caches.environments.insert(full, image.clone());
                Ok(image)
            }
            Err(e) => Err(self.report(
                Diagnostic::error(Code::Io, span, e.to_string())
                    .label("environment image used here")
                    .help(
                        "relative paths resolve against the directory of the scene file; \
                         the pixels must be finite radiance of at least 0",
                    ),
            )),
        }
    }

    /// Charges an image file's pixels to the memory budget from its header,
    /// before it is decoded.
    pub(super) fn charge_image(&mut self, full: &Path, span: Span) -> Eval<()> {
        let Some((width, height)) = ImageData::dimensions(full) else {
            return Ok(());
        };
        let bytes = width as f64 * height as f64 * budget::BYTES_PER_IMAGE_PIXEL;
        self.charge(bytes, span, "this image's pixels")
    }

    /// The mesh of the OBJ file `path` and the scene materials of its slots
    /// (loaded once; OBJ warnings become warnings at `span`).
    pub(super) fn mesh(&mut self, path: &str, span: Span) -> Eval<(MeshId, Vec<MaterialId>)> {
        let full = self.resolve(path, span);
        self.check_type(&full, span, &["obj"], "mesh")?;
        if self.dry {
            return Ok((MeshId(0), Vec::new()));
        }
        if let Some(hit) = self.caches.meshes.get(&full) {
            return Ok(hit.clone());
        }
        let limit = self.charge_file(
            &full,
            budget::BYTES_PER_OBJ_BYTE,
            span,
            "this mesh file while it is loaded",
        )?;
        let (mesh, warnings) = match self.options.assets.mesh(&full, limit) {
            Ok(loaded) => loaded,
            Err(ObjError::At { path, error }) => {
                let d = self.obj_line_error(&full, path, &error, span);
                return Err(self.report(d));
            }
            Err(e) => {
                return Err(self.report(
                    Diagnostic::error(Code::Mesh, span, e.to_string())
                        .label("mesh used here")
                        .help("relative paths resolve against the directory of the scene file"),
                ))
            }
        };
        for warning in warnings.iter() {
            self.diagnostics.push(
                Diagnostic::warning(Code::MeshWarning, span, warning)
                    .label("in this mesh")
                    .help("the mesh loads with a fallback for what is missing"),
            );
        }
        let dir = full.parent().map(Path::to_path_buf).unwrap_or_default();
        let slots: Vec<MeshMaterial> = if mesh.materials.is_empty() {
            vec![MeshMaterial {
                name: "default".into(),
                kind: MeshMaterialKind::fallback(),
                map: None,
            }]
        } else {
            mesh.materials.clone()
        };
        let materials = slots
            .iter()
            .map(|slot| {
                let base = self.mesh_material(&slot.kind, &dir, span);
                self.mesh_map(base, slot.map.as_ref(), span)
            })
            .collect();
        let id = self.scene.add_mesh(mesh);
        let entry = (id, materials);
        self.caches.meshes.insert(full, entry.clone());
        Ok(entry)
    }

    /// A problem on one line of an OBJ file, shown in that file (added to
    /// the sources as an excerpt that keeps its line numbers), with the
    /// mesh's use in the scene as the second place.
    fn obj_line_error(
        &mut self,
        full: &Path,
        name: String,
        error: &LineError,
        used: Span,
    ) -> Diagnostic {
        let (text, range) = error.excerpt();
        let file = self.sources.add(full, name, text.into());
        Diagnostic::error(
            Code::Mesh,
            Span::new(file, range.start, range.end),
            &error.message,
        )
        .label(&error.label)
        .related(used, "mesh used here")
        .help("fix the OBJ file, or export it again from its modelling tool")
    }

    /// A scene material for one of an OBJ's material slots.
    fn mesh_material(&mut self, kind: &MeshMaterialKind, dir: &Path, span: Span) -> MaterialId {
        let solid = |ev: &mut Evaluator, c: glam::Vec3| ev.scene.add_texture(Texture::Solid(c));
        let albedo = |ev: &mut Evaluator, color: glam::Vec3, texture: &Option<PathBuf>| {
            texture
                .as_ref()
                .and_then(|file| ev.mesh_texture(&dir.join(file), span, Encoding::Srgb, COLOUR))
                .unwrap_or_else(|| solid(ev, color))
        };
        let material = match kind {
            MeshMaterialKind::Diffuse { color, texture } => Material::Lambertian {
                albedo: albedo(self, *color, texture),
            },
            MeshMaterialKind::Plastic {
                color,
                texture,
                ior,
                alpha,
            } => Material::Plastic {
                albedo: albedo(self, *color, texture),
                ior: *ior,
                alpha: *alpha,
            },
            MeshMaterialKind::Metal { color, fuzz } => Material::Metal {
                albedo: solid(self, *color),
                fuzz: *fuzz,
            },
            MeshMaterialKind::Dielectric { ior } => Material::Dielectric { ior: *ior },
            MeshMaterialKind::Light { emit } => Material::Light {
                emit: solid(self, *emit),
                two_sided: false,
            },
        };
        self.scene.add_material(material)
    }

    /// `base` under an MTL entry's bump or normal map (both images read as
    /// data), or `base` itself when there is none or its image does not
    /// load (a warning).
    fn mesh_map(&mut self, base: MaterialId, map: Option<&MeshMap>, span: Span) -> MaterialId {
        let material = match map {
            None => return base,
            Some(MeshMap::Bump { file, scale }) => {
                let Some(height) = self.mesh_texture(file, span, Encoding::Data, UNMAPPED) else {
                    return base;
                };
                Material::Bump {
                    base,
                    height,
                    scale: *scale,
                }
            }
            Some(MeshMap::Normal { file }) => {
                let Some(map) = self.mesh_texture(file, span, Encoding::Data, UNMAPPED) else {
                    return base;
                };
                Material::NormalMap {
                    base,
                    map,
                    strength: 1.0,
                }
            }
        };
        self.scene.add_material(material)
    }

    /// An image named by an MTL file; a failure is a warning that ends with
    /// `fallback`, what the caller does instead.
    fn mesh_texture(
        &mut self,
        full: &Path,
        span: Span,
        encoding: Encoding,
        fallback: &str,
    ) -> Option<TextureId> {
        let key = (full.to_path_buf(), encoding);
        if let Some(&id) = self.caches.images.get(&key) {
            return Some(id);
        }
        self.charge_image(full, span).ok()?;
        match self.options.assets.image_as(full, encoding) {
            Ok(image) => {
                let id = self.scene.add_texture(image_texture(image, encoding));
                self.caches.images.insert(key, id);
                Some(id)
            }
            Err(e) => {
                self.diagnostics.push(
                    Diagnostic::warning(
                        Code::MeshWarning,
                        span,
                        format!("{e}; {fallback}"),
                    )
                    .label("in this mesh's materials")
                    .help(
                        "put the texture next to the MTL file, or override the mesh's `material`",
                    ),
                );
                None
            }
        }
    }
}

/// What a mesh does when its colour texture does not load.
const COLOUR: &str = "using the material's colour";
/// What a mesh does when its bump or normal map does not load.
const UNMAPPED: &str = "the surface stays unmapped";

/// The texture of an image decoded by `encoding`.
pub(super) fn image_texture(image: std::sync::Arc<ImageData>, encoding: Encoding) -> Texture {
    match encoding {
        Encoding::Srgb => Texture::Image(image),
        Encoding::Data => Texture::Data(image),
    }
}
