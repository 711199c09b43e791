//! Loading glTF 2.0 files (`.gltf` with external or `data:` buffers, and
//! `.glb`) into plain data: the default scene's meshes placed by their
//! composed node transforms, metallic-roughness materials, images (still
//! encoded: the evaluator decodes them through its own limits),
//! `KHR_lights_punctual` lights and perspective cameras.
//!
//! The `gltf` crate parses and validates the JSON; every byte it points at
//! is read here, through [`super::file`]'s bounded reads, and every
//! accessor is checked against its buffer before it is read
//! ([`super::gltf_mesh`]), so a hostile file is an error, not a panic.

use std::path::{Component, Path, PathBuf};

use base64::Engine as _;
use glam::{Mat4, Vec3};

use super::file;
use super::gltf_mesh::primitive_mesh;
use super::MeshData;

/// The most bytes a glTF file and its buffers are read with together when
/// no smaller limit is given.
pub const MAX_GLTF_BYTES: u64 = 4 << 30;

/// The deepest node hierarchy followed (deeper nodes are an error: a real
/// file nests a few levels, a hostile one without end).
const MAX_DEPTH: usize = 256;
/// The most node placements followed: nodes shared by several parents are
/// placed once per path, which a hostile file can make exponential.
const MAX_VISITS: usize = 1 << 20;

/// A loaded glTF file.
#[derive(Debug, Default)]
pub struct GltfFile {
    /// One mesh per triangle primitive, with the index into `materials`
    /// (`None`: glTF's default material).
    pub meshes: Vec<(MeshData, Option<usize>)>,
    pub materials: Vec<GltfMaterial>,
    pub images: Vec<ImageSource>,
    /// What the default scene's nodes place, in world space of the file.
    pub placed: Vec<(Mat4, Placed)>,
    /// Bytes read: the file and its buffers.
    pub bytes: u64,
    pub warnings: Vec<String>,
}

/// Something a node places.
#[derive(Clone, Debug, PartialEq)]
pub enum Placed {
    /// A mesh primitive, by its index in [`GltfFile::meshes`].
    Mesh(usize),
    Light(GltfLight),
    Camera(GltfCamera),
}

/// A glTF metallic-roughness material; textures are indices into
/// [`GltfFile::images`].
#[derive(Clone, Debug, PartialEq)]
pub struct GltfMaterial {
    pub name: String,
    /// `baseColorFactor` (RGB; alpha is not read).
    pub base_color: Vec3,
    pub base_texture: Option<usize>,
    pub metallic: f32,
    pub roughness: f32,
    pub metallic_roughness_texture: Option<usize>,
    /// `normalTexture` and its `scale`.
    pub normal: Option<(usize, f32)>,
    /// `emissiveFactor` × `KHR_materials_emissive_strength`.
    pub emissive: Vec3,
    pub emissive_texture: Option<usize>,
    pub double_sided: bool,
}

/// Where an image's encoded bytes are.
#[derive(Clone, Debug, PartialEq)]
pub enum ImageSource {
    /// A file beside the glTF file.
    File(PathBuf),
    /// Bytes inside the file (a buffer view or a `data:` URI), and a name
    /// for messages.
    Bytes(std::sync::Arc<[u8]>, String),
    /// An image that could not be found, and why.
    Missing(String),
}

/// A `KHR_lights_punctual` light in its node's space (it shines along −z),
/// in the file's photometric units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GltfLight {
    /// `intensity` in candela.
    Point { color: Vec3, intensity: f32 },
    /// `intensity` in candela on the axis; cone half angles in radians.
    Spot {
        color: Vec3,
        intensity: f32,
        inner: f32,
        outer: f32,
    },
    /// `intensity` in lux.
    Directional { color: Vec3, intensity: f32 },
}

/// A camera in its node's space (it looks along −z, +y up).
#[derive(Clone, Debug, PartialEq)]
pub struct GltfCamera {
    pub name: String,
    /// `None` for an orthographic camera, which rtlang has not.
    pub perspective: Option<Perspective>,
}

/// A perspective projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perspective {
    /// Vertical field of view in radians.
    pub yfov: f32,
    pub aspect: Option<f32>,
}

/// Why a glTF file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    #[error("cannot read `{path}`: {message}")]
    Io { path: String, message: String },
    #[error("`{path}` is not a valid glTF file: {message}")]
    Parse { path: String, message: String },
    #[error("`{path}` requires the extension {name}, which rtlang does not read")]
    Extension { path: String, name: String },
    #[error("`{path}`: {message}")]
    Invalid { path: String, message: String },
}

/// Loads the glTF or GLB file at `path`, reading at most `limit` bytes in
/// all (the file and its buffers).
pub fn load_gltf(path: &Path, limit: u64) -> Result<GltfFile, GltfError> {
    let shown = path.display().to_string();
    let invalid = |message: String| GltfError::Invalid {
        path: shown.clone(),
        message,
    };
    let bytes = file::read(path, limit).map_err(|e| GltfError::Io {
        path: shown.clone(),
        message: e.to_string(),
    })?;
    let parse = |e: gltf::Error| GltfError::Parse {
        path: shown.clone(),
        message: e.to_string(),
    };
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| match e {
            gltf::Error::Io(e) => GltfError::Io {
                path: shown.clone(),
                message: e.to_string(),
            },
            e => parse(e),
        })?;
    if let Some(name) = document
        .extensions_required()
        .find(|n| !SUPPORTED.contains(n))
    {
        return Err(GltfError::Extension {
            path: shown,
            name: name.to_string(),
        });
    }
    // An extension the file uses without requiring it may change how it
    // looks (KHR_texture_transform, KHR_materials_*): it loads, with a word.
    let warnings = document
        .extensions_used()
        .filter(|n| !SUPPORTED.contains(n))
        .map(|n| format!("the file uses the extension {n}, which rtlang does not read"))
        .collect();
    let document = gltf::Document::from_json(document.into_json()).map_err(parse)?;
    let mut out = GltfFile {
        bytes: bytes.len() as u64,
        warnings,
        ..GltfFile::default()
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.clone().ok_or_else(|| {
                invalid("buffer 0 is the GLB's binary chunk, which it has not".into())
            })?,
            gltf::buffer::Source::Uri(uri) => {
                let left = limit.saturating_sub(out.bytes);
                let data = uri_bytes(uri, dir, left).map_err(|m| {
                    invalid(format!("buffer {} (`{}`): {m}", buffer.index(), short(uri)))
                })?;
                out.bytes += data.len() as u64;
                data
            }
        };
        if data.len() < buffer.length() {
            return Err(invalid(format!(
                "buffer {} holds {} bytes, less than its byteLength {}",
                buffer.index(),
                data.len(),
                buffer.length()
            )));
        }
        buffers.push(data);
    }
    out.images = document
        .images()
        .map(|image| image_source(&image, &buffers, dir))
        .collect();
    out.materials = document.materials().map(|m| material(&m)).collect();
    let mut meshes = Vec::new();
    for mesh in document.meshes() {
        let mut prims = Vec::new();
        for p in mesh.primitives() {
            let what = format!("mesh {} primitive {}", mesh.index(), p.index());
            if p.mode() != gltf::mesh::Mode::Triangles {
                out.warnings.push(format!(
                    "`{shown}`: {what} draws {:?}, not triangles; it is skipped",
                    p.mode()
                ));
                continue;
            }
            let data = primitive_mesh(&p, &buffers).map_err(|m| invalid(format!("{what}: {m}")))?;
            for w in texcoord_warnings(&p) {
                out.warnings.push(format!("`{shown}`: {what}: {w}"));
            }
            out.meshes.push((data, p.material().index()));
            prims.push(out.meshes.len() - 1);
        }
        meshes.push(prims);
    }
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next());
    if let Some(scene) = scene {
        let mut visits = 0;
        for node in scene.nodes() {
            walk(&node, Mat4::IDENTITY, (0, &mut visits), &meshes, &mut out).map_err(invalid)?;
        }
    }
    Ok(out)
}

/// Extensions a file may require: the ones read here.
const SUPPORTED: &[&str] = &["KHR_lights_punctual", "KHR_materials_emissive_strength"];

/// A URI cut for messages (a `data:` URI may be long).
fn short(uri: &str) -> String {
    if uri.len() > 40 {
        format!("{}…", &uri[..uri.floor_char_boundary(40)])
    } else {
        uri.to_string()
    }
}

/// The bytes of a buffer or image URI: a base64 `data:` URI, or a relative
/// path inside the glTF file's folder read with at most `limit` bytes.
fn uri_bytes(uri: &str, dir: &Path, limit: u64) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or("a data URI must be base64 (`data:...;base64,...`)")?;
        if data.len() as u64 / 4 * 3 > limit {
            return Err(format!("it holds more than {limit} bytes, the most read"));
        }
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| format!("bad base64: {e}"));
    }
    let path = local_path(uri, dir)?;
    file::read(&path, limit).map_err(|e| format!("cannot read `{}`: {e}", path.display()))
}

/// The file a relative URI names, which must stay inside `dir`.
fn local_path(uri: &str, dir: &Path) -> Result<PathBuf, String> {
    if uri.contains(':') {
        return Err("only relative paths and data URIs are read, not other URIs".into());
    }
    let decoded = percent_encoding::percent_decode_str(uri)
        .decode_utf8()
        .map_err(|_| "the URI is not UTF-8 once decoded".to_string())?;
    let rel = Path::new(decoded.as_ref());
    let mut depth = 0i32;
    for c in rel.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => depth -= 1,
            Component::RootDir | Component::Prefix(_) => depth = -1,
        }
        if depth < 0 {
            return Err("the path leads outside the glTF file's folder".into());
        }
    }
    Ok(dir.join(rel))
}

/// Where an image's bytes are; a missing one is kept with its reason (the
/// material falls back to its factors).
fn image_source(image: &gltf::Image, buffers: &[Vec<u8>], dir: &Path) -> ImageSource {
    let name = image
        .name()
        .map_or_else(|| format!("image {}", image.index()), str::to_string);
    match image.source() {
        gltf::image::Source::View { view, .. } => {
            let data = buffers
                .get(view.buffer().index())
                .and_then(|b| b.get(view.offset()..view.offset().checked_add(view.length())?));
            match data {
                Some(d) => ImageSource::Bytes(d.into(), name),
                None => ImageSource::Missing(format!("{name}: its buffer view is out of range")),
            }
        }
        gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
            match uri_bytes(uri, dir, MAX_GLTF_BYTES) {
                Ok(d) => ImageSource::Bytes(d.into(), name),
                Err(m) => ImageSource::Missing(format!("{name}: {m}")),
            }
        }
        gltf::image::Source::Uri { uri, .. } => match local_path(uri, dir) {
            Ok(p) => ImageSource::File(p),
            Err(m) => ImageSource::Missing(format!("{name} (`{}`): {m}", short(uri))),
        },
    }
}

/// The plain data of a material.
fn material(m: &gltf::Material) -> GltfMaterial {
    let pbr = m.pbr_metallic_roughness();
    let image = |t: gltf::texture::Texture| t.source().index();
    let [r, g, b, _] = pbr.base_color_factor();
    let strength = m.emissive_strength().unwrap_or(1.0);
    GltfMaterial {
        name: m.name().unwrap_or("").to_string(),
        base_color: Vec3::new(r, g, b),
        base_texture: pbr.base_color_texture().map(|i| image(i.texture())),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: pbr.metallic_roughness_texture().map(|i| image(i.texture())),
        normal: m.normal_texture().map(|n| (image(n.texture()), n.scale())),
        emissive: Vec3::from(m.emissive_factor()) * strength,
        emissive_texture: m.emissive_texture().map(|i| image(i.texture())),
        double_sided: m.double_sided(),
    }
}

/// Warnings for textures of a primitive's material that read a texture
/// coordinate set other than the first (only `TEXCOORD_0` is read).
fn texcoord_warnings(p: &gltf::Primitive) -> Vec<String> {
    let m = p.material();
    let pbr = m.pbr_metallic_roughness();
    let sets = [
        pbr.base_color_texture().map(|i| i.tex_coord()),
        pbr.metallic_roughness_texture().map(|i| i.tex_coord()),
        m.normal_texture().map(|i| i.tex_coord()),
        m.emissive_texture().map(|i| i.tex_coord()),
    ];
    sets.iter()
        .flatten()
        .filter(|&&s| s != 0)
        .map(|s| format!("a texture reads TEXCOORD_{s}; only TEXCOORD_0 is read"))
        .collect()
}

/// Places what `node` and its children hold, `parent` being the world
/// matrix of its parent.
fn walk(
    node: &gltf::Node,
    parent: Mat4,
    (depth, visits): (usize, &mut usize),
    meshes: &[Vec<usize>],
    out: &mut GltfFile,
) -> Result<(), String> {
    if depth >= MAX_DEPTH {
        return Err(format!(
            "the node hierarchy is deeper than {MAX_DEPTH} levels (a cycle?)"
        ));
    }
    *visits += 1;
    if *visits > MAX_VISITS {
        return Err(format!("the scene places more than {MAX_VISITS} nodes"));
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix());
    let m = parent * local;
    if !m.is_finite() {
        return Err(format!(
            "node {} has a transform that is not finite",
            node.index()
        ));
    }
    if let Some(mesh) = node.mesh() {
        for &k in &meshes[mesh.index()] {
            out.placed.push((m, Placed::Mesh(k)));
        }
    }
    if let Some(light) = node.light() {
        out.placed.push((m, Placed::Light(light_of(&light))));
    }
    if let Some(camera) = node.camera() {
        let perspective = match camera.projection() {
            gltf::camera::Projection::Perspective(p) => Some(Perspective {
                yfov: p.yfov(),
                aspect: p.aspect_ratio(),
            }),
            gltf::camera::Projection::Orthographic(_) => None,
        };
        out.placed.push((
            m,
            Placed::Camera(GltfCamera {
                name: camera
                    .name()
                    .map_or_else(|| format!("camera {}", camera.index()), str::to_string),
                perspective,
            }),
        ));
    }
    for child in node.children() {
        walk(&child, m, (depth + 1, &mut *visits), meshes, out)?;
    }
    Ok(())
}

/// The plain data of a punctual light.
fn light_of(light: &gltf::khr_lights_punctual::Light) -> GltfLight {
    let color = Vec3::from(light.color());
    let intensity = light.intensity();
    match light.kind() {
        gltf::khr_lights_punctual::Kind::Point => GltfLight::Point { color, intensity },
        gltf::khr_lights_punctual::Kind::Directional => GltfLight::Directional { color, intensity },
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => GltfLight::Spot {
            color,
            intensity,
            inner: inner_cone_angle,
            outer: outer_cone_angle,
        },
    }
}
