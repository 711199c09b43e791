//! Triangle meshes as plain data: shared vertex arrays and index triangles.
//!
//! Loading from OBJ files lives in `scene::obj`; intersection lives in
//! `geometry`.

use glam::{Vec2, Vec3};

/// An indexed triangle mesh. `normals` and `uvs` are either empty or as long
/// as `positions`, indexed by the same triangle indices.
#[derive(Clone, Default, PartialEq, serde::Serialize)]
pub struct MeshData {
    #[serde(serialize_with = "super::digest::serialize_summary")]
    pub positions: Vec<Vec3>,
    #[serde(serialize_with = "super::digest::serialize_summary")]
    pub normals: Vec<Vec3>,
    #[serde(serialize_with = "super::digest::serialize_summary")]
    pub uvs: Vec<Vec2>,
    #[serde(serialize_with = "super::digest::serialize_summary")]
    pub triangles: Vec<[u32; 3]>,
    /// Per-triangle index into `materials`; empty when the mesh has one
    /// material slot (or none).
    #[serde(serialize_with = "super::digest::serialize_summary")]
    pub triangle_material: Vec<u16>,
    /// The materials the file itself asks for (from its MTL), one per slot;
    /// the scene maps each slot to a scene material unless it overrides them.
    pub materials: Vec<MeshMaterial>,
}

/// The arrays print as their lengths and digests.
impl std::fmt::Debug for MeshData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use super::digest::summary;
        f.debug_struct("MeshData")
            .field("positions", &summary(&self.positions))
            .field("normals", &summary(&self.normals))
            .field("uvs", &summary(&self.uvs))
            .field("triangles", &summary(&self.triangles))
            .field("triangle_material", &summary(&self.triangle_material))
            .field("materials", &self.materials)
            .finish()
    }
}

/// A material named by a mesh file, already mapped to an rtlang material
/// whose textures are given inline (the evaluator turns them into ids).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct MeshMaterial {
    pub name: String,
    pub kind: MeshMaterialKind,
    /// A bump or normal map over the material (left out of the serialized
    /// form when there is none, so scenes without maps keep their identity).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub map: Option<MeshMap>,
}

/// A map an MTL entry lays over its material.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum MeshMap {
    /// `bump` / `map_Bump`: a height field in scene units, times `scale`
    /// (its `-bm` option, 1 when absent).
    Bump {
        #[serde(serialize_with = "lossy_file")]
        file: std::path::PathBuf,
        scale: f32,
    },
    /// `norm`: a tangent-space normal map.
    Normal {
        #[serde(serialize_with = "lossy_file")]
        file: std::path::PathBuf,
    },
}

/// What an MTL entry maps to.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub enum MeshMaterialKind {
    Diffuse {
        color: Vec3,
        #[serde(serialize_with = "lossy_path")]
        texture: Option<std::path::PathBuf>,
    },
    /// A diffuse base under a GGX dielectric coat of index `ior` and
    /// roughness `alpha` (an MTL highlight: non-zero `Ks`).
    Plastic {
        color: Vec3,
        #[serde(serialize_with = "lossy_path")]
        texture: Option<std::path::PathBuf>,
        ior: f32,
        alpha: f32,
    },
    Metal {
        color: Vec3,
        fuzz: f32,
    },
    Dielectric {
        ior: f32,
    },
    Light {
        emit: Vec3,
    },
}

impl MeshMaterialKind {
    /// A plain diffuse grey, used when a file names no material.
    pub fn fallback() -> MeshMaterialKind {
        MeshMaterialKind::Diffuse {
            color: Vec3::splat(0.73),
            texture: None,
        }
    }
}

impl MeshData {
    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// Whether the mesh has no triangles.
    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }
}

impl MeshData {
    /// The smallest and largest corner of the box around every vertex, or
    /// `None` for a mesh without vertices.
    pub fn bounds(&self) -> Option<(glam::Vec3, glam::Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))),
        )
    }
}

/// A path as text (lossily when it is not UTF-8), so that serializing a mesh
/// for the scene identity cannot fail.
fn lossy_path<S: serde::Serializer>(
    path: &Option<std::path::PathBuf>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match path {
        Some(p) => s.serialize_some(&p.to_string_lossy()),
        None => s.serialize_none(),
    }
}

/// [`lossy_path`] of a path that is always there.
fn lossy_file<S: serde::Serializer>(path: &std::path::Path, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&path.to_string_lossy())
}
