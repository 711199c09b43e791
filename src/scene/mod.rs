//! What a scene *is*: settings, camera, textures, materials and an object tree
//! as plain data, with no spans and no intersection structures.
//!
//! The language evaluator produces a [`Scene`]; the geometry builder and the
//! renderer consume it. Textures, materials, meshes and prototypes live in flat
//! arrays and are referred to by index newtypes, so a definition used many
//! times is stored once.

pub mod camera;
pub mod curve;
pub mod digest;
pub mod facing;
pub mod file;
pub mod gltf;
pub mod gltf_mesh;
pub mod image;
pub mod light;
pub mod material;
pub mod mesh;
pub mod motion;
pub mod obj;
pub mod obj_lines;
pub mod object;
pub mod reach;
pub mod settings;
pub mod texture;

use std::sync::Arc;

pub use camera::Camera;
pub use curve::Bezier;
pub use image::{Encoding, ImageData};
pub use light::Lamp;
pub use material::Material;
pub use mesh::MeshData;
pub use motion::Motion;
pub use object::{Node, Shape};
pub use settings::{Background, Environment, Settings};
pub use texture::Texture;

/// Index of a texture in [`Scene::textures`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub struct TextureId(pub u32);

/// Index of a material in [`Scene::materials`], with
/// [`MaterialId::TANGENTS`] set when the material reads a tangent frame:
/// geometry asks the bit, already at hand in a register, before it computes
/// a hit's ∂p/∂u and ∂p/∂v, so scenes without maps never compute them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub struct MaterialId(pub u32);

impl MaterialId {
    /// The bit of a material that reads a tangent frame ([`Material::needs_tangents`]).
    pub const TANGENTS: u32 = 1 << 31;

    /// The material's place in [`Scene::materials`].
    #[inline]
    pub fn index(self) -> usize {
        (self.0 & !Self::TANGENTS) as usize
    }

    /// Whether hits of the material carry ∂p/∂u and ∂p/∂v.
    #[inline]
    pub fn needs_tangents(self) -> bool {
        self.0 & Self::TANGENTS != 0
    }
}

/// Index of a triangle mesh in [`Scene::meshes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub struct MeshId(pub u32);

/// Index of a prototype (an object defined once and placed many times) in
/// [`Scene::prototypes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub struct ProtoId(pub u32);

/// A complete scene description, ready to be built into geometry and rendered.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub settings: Settings,
    pub camera: Camera,
    pub textures: Vec<Texture>,
    pub materials: Vec<Material>,
    pub meshes: Vec<Arc<MeshData>>,
    /// Objects defined once and referenced by [`Node::Instance`]; the geometry
    /// builder builds each one's acceleration structure once and shares it.
    pub prototypes: Vec<Node>,
    /// The top-level objects of the world.
    pub objects: Vec<Node>,
}

impl Scene {
    /// Appends a texture and returns its id.
    pub fn add_texture(&mut self, texture: Texture) -> TextureId {
        self.textures.push(texture);
        TextureId(self.textures.len() as u32 - 1)
    }

    /// Appends a material and returns its id.
    pub fn add_material(&mut self, material: Material) -> MaterialId {
        let flag = if material.needs_tangents() {
            MaterialId::TANGENTS
        } else {
            0
        };
        self.materials.push(material);
        MaterialId((self.materials.len() as u32 - 1) | flag)
    }

    /// Appends a mesh and returns its id.
    pub fn add_mesh(&mut self, mesh: Arc<MeshData>) -> MeshId {
        self.meshes.push(mesh);
        MeshId(self.meshes.len() as u32 - 1)
    }

    /// Appends a prototype and returns its id.
    pub fn add_prototype(&mut self, node: Node) -> ProtoId {
        self.prototypes.push(node);
        ProtoId(self.prototypes.len() as u32 - 1)
    }

    /// The texture with the given id.
    pub fn texture(&self, id: TextureId) -> &Texture {
        &self.textures[id.0 as usize]
    }

    /// The material with the given id.
    pub fn material(&self, id: MaterialId) -> &Material {
        &self.materials[id.index()]
    }
}
