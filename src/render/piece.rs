//! What a rendered piece is: the JSON sidecar `IMAGE.json` written beside
//! every image (`tile.exr` → `tile.exr.json`) naming the scene, the full
//! image size, the pixel bounds, every setting that changes the pixels
//! (seed, sampler, depth, light selection, clamp, noise target, pass), the
//! samples per pixel and a hash of the image's pixels, so that `rtlang
//! merge` can check that pieces belong together and each sidecar to its
//! image.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::options::{Crop, RenderOptions};
use crate::scene::digest::Fnv;
use crate::scene::Scene;

/// The version of the sidecar and checkpoint header's fields: pieces of
/// another version are refused (an older one lacks settings that change
/// the pixels, so it cannot be told apart from another render).
pub const PIECE_FORMAT: u32 = 2;

/// The sidecar of one rendered image.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PieceInfo {
    /// [`PIECE_FORMAT`] when it was written.
    pub format: u32,
    /// Identity of the evaluated scene (see [`scene_identity`]).
    pub scene: String,
    pub width: u32,
    pub height: u32,
    /// Pixel bounds `[x0, x1, y0, y1]` (half-open) of this piece.
    pub region: [u32; 4],
    pub seed: u64,
    /// The sampler's name (`sobol`, `independent`).
    pub sampler: String,
    pub max_depth: u32,
    /// How lights are chosen (`tree`, `power`), or `none` when no light is
    /// sampled (`--integrator path`).
    pub light_selection: String,
    /// The cap on each sample's radiance (`--clamp`), if any.
    pub clamp: Option<f32>,
    /// The adaptive sampling's noise target (`--noise`), if any.
    pub noise: Option<f32>,
    /// The animation frame the scene was evaluated at.
    pub frame: f64,
    pub pass: u32,
    /// Samples per pixel requested.
    pub spp: u32,
    /// Samples per pixel every pixel reached (less than `spp` when the
    /// render was interrupted).
    pub spp_reached: u32,
    /// The [`pixels_digest`] of the image written with the sidecar (none
    /// in a checkpoint's header, which has no image).
    #[serde(default)]
    pub pixels: Option<String>,
}

/// Why a sidecar could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum PieceError {
    #[error("cannot read `{}`: {message}", path.display())]
    Read { path: PathBuf, message: String },
    #[error(
        "`{}` was written by another version of rtlang (sidecar format {found}, \
         this one reads {PIECE_FORMAT}): it does not record every setting that \
         changes the pixels; render the piece again",
        path.display()
    )]
    Format { path: PathBuf, found: u32 },
    #[error("cannot write `{}`: {message}", path.display())]
    Write { path: PathBuf, message: String },
}

impl PieceInfo {
    /// The sidecar of a render of `scene` with `options` that reached `spp_reached`.
    pub fn new(
        scene: &Scene,
        options: &RenderOptions,
        region: Crop,
        frame: f64,
        spp_reached: u32,
    ) -> PieceInfo {
        PieceInfo {
            format: PIECE_FORMAT,
            scene: scene_identity(scene),
            width: options.width,
            height: options.height,
            region: [region.x0, region.x1, region.y0, region.y1],
            seed: options.seed,
            sampler: options.sampler.name().to_string(),
            max_depth: options.max_depth,
            light_selection: light_selection(options).to_string(),
            clamp: options.clamp,
            noise: options.noise,
            frame,
            pass: options.pass,
            spp: options.spp,
            spp_reached,
            pixels: None,
        }
    }

    pub fn crop(&self) -> Crop {
        let [x0, x1, y0, y1] = self.region;
        Crop { x0, x1, y0, y1 }
    }

    /// Whether every pixel got the samples asked for.
    pub fn complete(&self) -> bool {
        self.spp_reached >= self.spp
    }

    /// Reads the sidecar of `image` (a regular file of at most
    /// [`MAX_SIDECAR_BYTES`]), refusing one of another format.
    pub fn read(image: &Path) -> Result<PieceInfo, PieceError> {
        let path = sidecar_path(image);
        let err = |message: String| PieceError::Read {
            path: path.clone(),
            message,
        };
        let bytes =
            crate::scene::file::read(&path, MAX_SIDECAR_BYTES).map_err(|e| err(e.to_string()))?;
        PieceInfo::parse(&bytes).map_err(|e| match e {
            Parsed::Format(found) => PieceError::Format {
                path: path.clone(),
                found,
            },
            Parsed::Json(e) => err(e.to_string()),
        })
    }

    /// The piece described by the JSON `bytes`, if of [`PIECE_FORMAT`].
    pub fn parse(bytes: &[u8]) -> Result<PieceInfo, Parsed> {
        #[derive(Deserialize)]
        struct Version {
            #[serde(default)]
            format: u32,
        }
        let version: Version = serde_json::from_slice(bytes).map_err(Parsed::Json)?;
        if version.format != PIECE_FORMAT {
            return Err(Parsed::Format(version.format));
        }
        serde_json::from_slice(bytes).map_err(Parsed::Json)
    }

    /// Writes the sidecar of `image`, whose pixels are `pixels`,
    /// atomically.
    pub fn write(&self, image: &Path, pixels: &[Vec3]) -> Result<(), PieceError> {
        let path = sidecar_path(image);
        let info = PieceInfo {
            pixels: Some(pixels_digest(pixels.iter().map(|p| p.to_array()))),
            ..self.clone()
        };
        let text = serde_json::to_string_pretty(&info).map_err(|e| PieceError::Write {
            path: path.clone(),
            message: e.to_string(),
        })?;
        super::output::write_atomically(&path, |w| Ok(w.write_all(text.as_bytes())?)).map_err(|e| {
            PieceError::Write {
                path: path.clone(),
                message: e.to_string(),
            }
        })
    }
}

/// Why JSON did not give a [`PieceInfo`].
#[derive(Debug)]
pub enum Parsed {
    /// Another format version (0 when the field is missing).
    Format(u32),
    Json(serde_json::Error),
}

/// The most bytes a sidecar is read with (one is a few hundred).
pub const MAX_SIDECAR_BYTES: u64 = 1 << 20;

/// A hex hash of an image's linear pixels: the 64-bit FNV-1a of the
/// little-endian bits of each pixel's red, green and blue f32, row by row,
/// which an EXR stores exactly; it ties a sidecar to its image.
pub fn pixels_digest(pixels: impl Iterator<Item = [f32; 3]>) -> String {
    let mut h = Fnv::default();
    for p in pixels {
        for c in p {
            h.bytes(&c.to_le_bytes());
        }
    }
    format!("{:016x}", h.finish())
}

/// What the sidecar records of how `options` chooses lights.
fn light_selection(options: &RenderOptions) -> &'static str {
    match options.light_sampling {
        true => options.light_selection.name(),
        false => "none",
    }
}

/// `image` with `.json` appended: `tile.exr` → `tile.exr.json`.
pub fn sidecar_path(image: &Path) -> PathBuf {
    let mut name = image.as_os_str().to_owned();
    name.push(".json");
    PathBuf::from(name)
}

/// The version of the scene identity's definition: bump it whenever a
/// change to the scene types moves the hash of an unchanged scene (the test
/// `identity_of_a_fixed_scene_is_stable` says when), so that old pieces and
/// checkpoints are refused rather than matched by accident.
pub const IDENTITY_VERSION: u32 = 2;

/// What the scene identity covers, in the order it is serialized.
#[derive(Serialize)]
struct IdentityView<'a> {
    version: u32,
    camera: &'a crate::scene::Camera,
    textures: &'a [crate::scene::Texture],
    materials: &'a [crate::scene::Material],
    meshes: &'a [std::sync::Arc<crate::scene::MeshData>],
    prototypes: &'a [crate::scene::Node],
    objects: &'a [crate::scene::Node],
    background: &'a crate::scene::Background,
}

/// A hex hash of the evaluated scene: the 64-bit FNV-1a of the CBOR
/// (RFC 8949) encoding of its camera, textures, materials, meshes (every
/// vertex), objects and background, after [`IDENTITY_VERSION`]. CBOR fixes
/// the bytes of every value (floats by their exact bits), so the identity
/// moves only when the scene or the serialized types do, never with a `Debug`
/// format or a dependency's printing. The settings that command-line options
/// override (size, spp, seed, depth) are left out; they are recorded and
/// checked one by one.
pub fn scene_identity(scene: &Scene) -> String {
    let view = IdentityView {
        version: IDENTITY_VERSION,
        camera: &scene.camera,
        textures: &scene.textures,
        materials: &scene.materials,
        meshes: &scene.meshes,
        prototypes: &scene.prototypes,
        objects: &scene.objects,
        background: &scene.settings.background,
    };
    let mut h = Fnv::default();
    // A hash never fails to take bytes and every scene type serializes (paths
    // lossily), so this error cannot occur; should it, it still enters the hash.
    if let Err(e) = ciborium::into_writer(&view, &mut h) {
        h.bytes(e.to_string().as_bytes());
    }
    format!("{:016x}", h.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_ignores_overridable_settings_but_not_the_camera() {
        let a = Scene::default();
        let mut b = a.clone();
        b.settings.spp = 999;
        b.settings.seed = 5;
        assert_eq!(scene_identity(&a), scene_identity(&b));
        b.camera.vfov += 1.0;
        assert_ne!(scene_identity(&a), scene_identity(&b));
    }

    #[test]
    fn identity_sees_one_changed_vertex_or_pixel() {
        use crate::scene::{ImageData, MeshData, Texture};
        use glam::Vec3;
        use std::sync::Arc;
        let mut a = Scene::default();
        a.meshes.push(Arc::new(MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            triangles: vec![[0, 1, 2]],
            ..MeshData::default()
        }));
        a.textures.push(Texture::Image(Arc::new(ImageData {
            width: 2,
            height: 1,
            pixels: vec![Vec3::ONE, Vec3::ZERO],
        })));
        let mut moved = a.clone();
        Arc::make_mut(&mut moved.meshes[0]).positions[2].y = f32::from_bits(1.0f32.to_bits() + 1);
        assert_ne!(scene_identity(&a), scene_identity(&moved));
        let mut repainted = a.clone();
        repainted.textures[0] = Texture::Image(Arc::new(ImageData {
            width: 2,
            height: 1,
            pixels: vec![Vec3::ONE, Vec3::new(0.0, 0.0, 1e-30)],
        }));
        assert_ne!(scene_identity(&a), scene_identity(&repainted));
        assert_eq!(scene_identity(&a), scene_identity(&a.clone()));
    }

    /// A committed hash: it changes only when the scene types or their
    /// serialization do, and then [`IDENTITY_VERSION`] must be bumped.
    #[test]
    fn identity_of_a_fixed_scene_is_stable() {
        use crate::scene::{Material, MaterialId, MeshData, Node, Shape, Texture};
        use glam::Vec3;
        use std::sync::Arc;
        let mut scene = Scene::default();
        let red = scene.add_texture(Texture::Solid(Vec3::new(0.8, 0.1, 0.1)));
        scene.add_material(Material::Lambertian { albedo: red });
        scene.add_mesh(Arc::new(MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            triangles: vec![[0, 1, 2]],
            ..MeshData::default()
        }));
        scene.objects.push(Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::new(0.0, 1.0, -2.0),
                radius: 0.5,
            },
            material: MaterialId(0),
        });
        assert_eq!(IDENTITY_VERSION, 2);
        assert_eq!(scene_identity(&scene), "551733ea0467bc06");
        // The mesh arrays enter as their digests: any bit of a vertex counts.
        let mut moved = scene.clone();
        let mut mesh = (*moved.meshes[0]).clone();
        mesh.positions[2].y = f32::from_bits(mesh.positions[2].y.to_bits() + 1);
        moved.meshes[0] = Arc::new(mesh);
        assert_ne!(scene_identity(&scene), scene_identity(&moved));
    }

    #[test]
    fn sidecar_is_the_image_path_plus_json() {
        assert_eq!(
            sidecar_path(Path::new("out/t.exr")),
            PathBuf::from("out/t.exr.json")
        );
    }
}
