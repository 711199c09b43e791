//! Which top-level object a camera ray hits, without object ids in the
//! geometry: a copy of the scene whose every material slot under top-level
//! object `i` is rewritten to `MaterialId(i)` is built into its own world,
//! so the material of a hit in that world is the object's index. The index
//! then maps to a source span through the evaluator's id table
//! (`lang::Outcome::objects`). Built on the first click after each change.

use std::collections::HashMap;

use glam::Vec3;

use crate::geometry::{BuildError, Hit, Ray, World};
use crate::scene::{Material, MaterialId, Node, ProtoId, Scene};

/// The world whose hit materials are top-level object indices.
pub struct PickWorld {
    world: World,
}

impl PickWorld {
    /// Builds the tagged copy of `scene` in the frame whose origin is the
    /// scene point `frame` (the rendered world's).
    pub fn build(scene: &Scene, frame: Vec3) -> Result<PickWorld, BuildError> {
        let mut tagged = Scene {
            settings: scene.settings.clone(),
            camera: scene.camera,
            textures: Vec::new(),
            materials: Vec::new(),
            meshes: scene.meshes.clone(),
            prototypes: Vec::new(),
            objects: Vec::new(),
        };
        let mut copies = HashMap::new();
        for (i, node) in scene.objects.iter().enumerate() {
            let tag = MaterialId(i as u32);
            let node = retag(node, tag, scene, &mut tagged, &mut copies);
            tagged.objects.push(node);
        }
        // Non-emitting placeholders, so the copy has no lights to sample.
        tagged.materials = vec![Material::Dielectric { ior: 1.0 }; scene.objects.len()];
        Ok(PickWorld {
            world: World::build_in(&tagged, frame)?,
        })
    }

    /// The nearest hit of `ray` and the index of the top-level object hit.
    pub fn pick(&self, ray: &Ray) -> Option<(usize, Hit)> {
        let hit = self.world.intersect(ray, 1e-4, f32::INFINITY)?;
        Some((hit.material.0 as usize, hit))
    }
}

/// `node` with every material replaced by `tag`; prototypes it places are
/// copied once per tag.
fn retag(
    node: &Node,
    tag: MaterialId,
    scene: &Scene,
    tagged: &mut Scene,
    copies: &mut HashMap<(ProtoId, MaterialId), ProtoId>,
) -> Node {
    let mut again = |n: &Node, tagged: &mut Scene| Box::new(retag(n, tag, scene, tagged, copies));
    match node {
        Node::Shape { shape, .. } => Node::Shape {
            shape: shape.clone(),
            material: tag,
        },
        Node::Mesh { mesh, materials } => Node::Mesh {
            mesh: *mesh,
            materials: vec![tag; materials.len()],
        },
        Node::Group(children) => Node::Group(
            children
                .iter()
                .map(|c| retag(c, tag, scene, tagged, copies))
                .collect(),
        ),
        Node::Transform { matrix, child } => Node::Transform {
            matrix: *matrix,
            child: again(child, tagged),
        },
        Node::Motion { motion, child } => Node::Motion {
            motion: motion.clone(),
            child: again(child, tagged),
        },
        Node::Medium {
            boundary, density, ..
        } => Node::Medium {
            boundary: again(boundary, tagged),
            density: *density,
            material: tag,
        },
        Node::Flip(child) => Node::Flip(again(child, tagged)),
        Node::Instance(proto) => {
            if let Some(&copy) = copies.get(&(*proto, tag)) {
                return Node::Instance(copy);
            }
            let Some(original) = scene.prototypes.get(proto.0 as usize) else {
                // Left dangling on purpose: the build reports the missing prototype.
                return Node::Instance(ProtoId(u32::MAX));
            };
            let copy = retag(original, tag, scene, tagged, copies);
            let id = tagged.add_prototype(copy);
            copies.insert((*proto, tag), id);
            Node::Instance(id)
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scene::Shape;

    fn sphere(center: Vec3, material: u32) -> Node {
        Node::Shape {
            shape: Shape::Sphere {
                center,
                radius: 1.0,
            },
            material: MaterialId(material),
        }
    }

    #[test]
    fn hits_name_the_top_level_object_even_through_prototypes() {
        let mut scene = Scene::default();
        let proto = scene.add_prototype(sphere(Vec3::ZERO, 0));
        scene.objects = vec![
            sphere(Vec3::new(0.0, 0.0, -5.0), 0),
            Node::Transform {
                matrix: glam::Mat4::from_translation(Vec3::new(3.0, 0.0, -5.0)),
                child: Box::new(Node::Instance(proto)),
            },
            Node::Transform {
                matrix: glam::Mat4::from_translation(Vec3::new(-3.0, 0.0, -5.0)),
                child: Box::new(Node::Instance(proto)),
            },
        ];
        let pick = PickWorld::build(&scene, Vec3::ZERO).expect("the tagged scene builds");
        let at = |x: f32| {
            let ray = Ray::new(Vec3::new(x, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
            pick.pick(&ray).map(|(i, h)| (i, h.t))
        };
        assert_eq!(at(0.0), Some((0, 4.0)));
        assert_eq!(at(3.0), Some((1, 4.0)));
        assert_eq!(at(-3.0), Some((2, 4.0)));
        assert_eq!(at(10.0), None);
    }
}
