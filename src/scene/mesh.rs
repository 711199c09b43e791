//! Triangle meshes as plain data: shared vertex arrays and index triangles.
//!
//! Loading from OBJ files lives in `scene::obj`; intersection lives in
//! `geometry`.

use glam::{Vec2, Vec3};

/// An indexed triangle mesh. `normals` and `uvs` are either empty or as long
/// as `positions`, indexed by the same triangle indices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
    /// Per-triangle index into `materials`; empty when the mesh has one
    /// material slot (or none).
    pub triangle_material: Vec<u16>,
    /// The materials the file itself asks for (from its MTL), one per slot;
    /// the scene maps each slot to a scene material unless it overrides them.
    pub materials: Vec<MeshMaterial>,
}

/// A material named by a mesh file, already mapped to an rtlang material
/// whose textures are given inline (the evaluator turns them into ids).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshMaterial {
    pub name: String,
    pub kind: MeshMaterialKind,
}

/// What an MTL entry maps to.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshMaterialKind {
    Diffuse {
        color: Vec3,
        texture: Option<std::path::PathBuf>,
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
