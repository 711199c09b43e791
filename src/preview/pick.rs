//! Which top-level object a camera ray hits, without object ids in the
//! geometry. A copy of the scene whose material slots are tags is built
//! into a world of its own: top-level object `i`'s own surfaces carry
//! `MaterialId(i)`; a prototype is copied once, shared by all its
//! placements as in the render world, its surfaces tagged `objects + copy`.
//! A hit on an object's own surface names the object; a hit on a shared
//! prototype names only the prototype, and the object is the first whose
//! placements of it, walked down to the prototype, meet the ray at the same
//! distance in that prototype alone (built in its own space on its first
//! hit). Under a motion the placement depends on the ray's time, so there
//! prototypes are copied per object instead. The copy's estimated memory is
//! charged against the scene's memory budget ([`crate::lang::budget`]):
//! past it, picking is refused with a message. The index then maps to a
//! source span through the evaluator's id table (`lang::Outcome::objects`).
//! Built on the first click after each change.

use std::collections::HashMap;
use std::sync::Mutex;

use glam::{Mat4, Vec3};

use crate::geometry::{BuildError, Hit, Ray, World};
use crate::lang::budget::{human, tree_bytes};
use crate::scene::{Material, MaterialId, Node, ProtoId, Scene};

/// Nodes visited at most to find which placement of a prototype was hit.
const MAX_WALK: u64 = 1 << 24;

/// How near, relative to the distance, the same hit is in the tagged world
/// and in a prototype alone (the two worlds round differently).
const SAME_HIT: f32 = 1e-3;

/// Why there is no picking for a scene.
#[derive(Debug, thiserror::Error)]
pub enum PickError {
    #[error(transparent)]
    Build(#[from] BuildError),
    #[error(
        "picking is off: its copy of the scene would take about {need} more, \
         past the memory budget of {budget}"
    )]
    Budget { need: String, budget: String },
}

/// The world whose hit materials are top-level object indices or shared
/// prototypes.
pub struct PickWorld {
    world: World,
    tagged: Scene,
    objects: usize,
    /// The scene point at the world's origin.
    frame: Vec3,
    /// Each shared prototype alone, in its own space, built on its first hit
    /// (`None` if it cannot be built).
    alone: Mutex<HashMap<ProtoId, Option<World>>>,
}

impl PickWorld {
    /// Builds the tagged copy of `scene` in the frame whose origin is the
    /// scene point `frame` (the rendered world's), if the render world and
    /// the copy fit in `budget` bytes together.
    pub fn build(scene: &Scene, frame: Vec3, budget: u64) -> Result<PickWorld, PickError> {
        let objects = scene.objects.len();
        let mut tagger = Tagger {
            scene,
            objects,
            tagged: Scene {
                settings: scene.settings.clone(),
                camera: scene.camera,
                textures: Vec::new(),
                materials: Vec::new(),
                meshes: scene.meshes.clone(),
                prototypes: Vec::new(),
                objects: Vec::new(),
            },
            copies: HashMap::new(),
        };
        for (i, node) in scene.objects.iter().enumerate() {
            let node = tagger.retag(node, MaterialId(i as u32), true);
            tagger.tagged.objects.push(node);
        }
        let mut tagged = tagger.tagged;
        // Non-emitting placeholders, so the copy has no lights to sample.
        let tags = objects + tagged.prototypes.len();
        tagged.materials = vec![Material::Dielectric { ior: 1.0 }; tags];
        // The copy, and each prototype once more alone.
        let need = estimate(&tagged) + prototypes_bytes(&tagged);
        if estimate(scene) + need > budget as f64 {
            return Err(PickError::Budget {
                need: human(need),
                budget: human(budget as f64),
            });
        }
        Ok(PickWorld {
            world: World::build_in(&tagged, frame)?,
            tagged,
            objects,
            frame,
            alone: Mutex::new(HashMap::new()),
        })
    }

    /// The nearest hit of `ray` and the index of the top-level object hit.
    pub fn pick(&self, ray: &Ray) -> Option<(usize, Hit)> {
        let hit = self.world.intersect(ray, 1e-4, f32::INFINITY)?;
        let tag = hit.material.0 as usize;
        if tag < self.objects {
            return Some((tag, hit));
        }
        let proto = ProtoId((tag - self.objects) as u32);
        let in_scene = Ray::new(ray.origin + self.frame, ray.dir, ray.time);
        self.placing(proto, &in_scene, hit.t).map(|i| (i, hit))
    }

    /// The first top-level object with a placement of `proto` that `ray`
    /// (in scene coordinates) meets at distance `t`.
    fn placing(&self, proto: ProtoId, ray: &Ray, t: f32) -> Option<usize> {
        let mut alone = self.alone.lock().unwrap_or_else(|e| e.into_inner());
        let world = alone
            .entry(proto)
            .or_insert_with(|| self.build_alone(proto))
            .as_ref()?;
        let mut walk = Walk {
            tagged: &self.tagged,
            proto,
            alone: world,
            ray,
            t,
            reaches: HashMap::new(),
            visits: 0,
        };
        (0..self.objects).find(|&i| walk.hits(&self.tagged.objects[i], Mat4::IDENTITY))
    }

    /// Prototype `proto` alone, in its own space.
    fn build_alone(&self, proto: ProtoId) -> Option<World> {
        let scene = Scene {
            settings: self.tagged.settings.clone(),
            camera: self.tagged.camera,
            textures: Vec::new(),
            materials: self.tagged.materials.clone(),
            meshes: self.tagged.meshes.clone(),
            prototypes: self.tagged.prototypes.clone(),
            objects: vec![Node::Instance(proto)],
        };
        World::build_in(&scene, Vec3::ZERO).ok()
    }
}

/// The estimated bytes of `scene`'s world: each object, each prototype once.
fn estimate(scene: &Scene) -> f64 {
    let objects: f64 = scene.objects.iter().map(|n| tree_bytes(n, scene)).sum();
    objects + prototypes_bytes(scene)
}

fn prototypes_bytes(scene: &Scene) -> f64 {
    scene.prototypes.iter().map(|n| tree_bytes(n, scene)).sum()
}

/// Builds the tagged copy.
struct Tagger<'a> {
    scene: &'a Scene,
    objects: usize,
    tagged: Scene,
    /// The copy of each prototype: shared (`None`), or for one object's tag
    /// under a motion.
    copies: HashMap<(ProtoId, Option<MaterialId>), ProtoId>,
}

impl Tagger<'_> {
    /// `node` with every material replaced by `tag`; the prototypes it
    /// places are shared copies, or copies of `tag`'s own if not `shared`.
    fn retag(&mut self, node: &Node, tag: MaterialId, shared: bool) -> Node {
        let mut again = |n: &Node, shared| Box::new(self.retag(n, tag, shared));
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
                    .map(|c| self.retag(c, tag, shared))
                    .collect(),
            ),
            Node::Transform { matrix, child } => Node::Transform {
                matrix: *matrix,
                child: again(child, shared),
            },
            Node::Motion { motion, child } => Node::Motion {
                motion: motion.clone(),
                child: again(child, false),
            },
            Node::Medium {
                boundary, density, ..
            } => Node::Medium {
                boundary: again(boundary, shared),
                density: *density,
                material: tag,
            },
            Node::Flip(child) => Node::Flip(again(child, shared)),
            Node::Instance(proto) => Node::Instance(self.copy(*proto, tag, shared)),
            Node::Lamp(lamp) => Node::Lamp(*lamp),
        }
    }

    /// The copy of prototype `proto` placed under an object tagged `tag`.
    fn copy(&mut self, proto: ProtoId, tag: MaterialId, shared: bool) -> ProtoId {
        let key = (proto, (!shared).then_some(tag));
        if let Some(&copy) = self.copies.get(&key) {
            return copy;
        }
        let Some(original) = self.scene.prototypes.get(proto.0 as usize) else {
            // Left dangling on purpose: the build reports the missing prototype.
            return ProtoId(u32::MAX);
        };
        // Numbered before its content is made, so a prototype that places
        // itself refers to its copy (and the build reports the loop).
        let copy = self.tagged.add_prototype(Node::Group(Vec::new()));
        self.copies.insert(key, copy);
        let own = if shared {
            MaterialId((self.objects + copy.0 as usize) as u32)
        } else {
            tag
        };
        let node = self.retag(original, own, shared);
        self.tagged.prototypes[copy.0 as usize] = node;
        copy
    }
}

/// A search for the placement of a shared prototype that a ray met.
struct Walk<'a> {
    tagged: &'a Scene,
    proto: ProtoId,
    alone: &'a World,
    ray: &'a Ray,
    t: f32,
    /// Whether a prototype places `proto`, at any depth.
    reaches: HashMap<ProtoId, bool>,
    visits: u64,
}

impl Walk<'_> {
    /// Whether a placement of the prototype under `node`, which
    /// `to_scene` places in the scene, meets the ray at the distance.
    fn hits(&mut self, node: &Node, to_scene: Mat4) -> bool {
        self.visits += 1;
        if self.visits > MAX_WALK {
            return false;
        }
        match node {
            Node::Transform { matrix, child } => self.hits(child, to_scene * *matrix),
            Node::Group(children) => children.iter().any(|c| self.hits(c, to_scene)),
            Node::Flip(child) => self.hits(child, to_scene),
            Node::Instance(id) if *id == self.proto => self.meets(to_scene),
            Node::Instance(id) => {
                let tagged = self.tagged;
                self.reaches(*id)
                    && tagged
                        .prototypes
                        .get(id.0 as usize)
                        .is_some_and(|n| self.hits(n, to_scene))
            }
            // Own surfaces carry the object's tag; under a motion,
            // prototypes are the object's own copies.
            Node::Shape { .. }
            | Node::Mesh { .. }
            | Node::Medium { .. }
            | Node::Motion { .. }
            | Node::Lamp(_) => false,
        }
    }

    /// Whether the prototype placed by `to_scene` meets the ray at `t`.
    fn meets(&self, to_scene: Mat4) -> bool {
        let to_local = to_scene.inverse();
        if !to_local.is_finite() {
            return false;
        }
        let local = Ray::new(
            to_local.transform_point3(self.ray.origin),
            to_local.transform_vector3(self.ray.dir),
            self.ray.time,
        );
        self.alone
            .intersect(&local, 1e-4, f32::INFINITY)
            .is_some_and(|h| (h.t - self.t).abs() <= SAME_HIT * self.t.max(1.0))
    }

    /// Whether prototype `from` places the prototype searched for.
    fn reaches(&mut self, from: ProtoId) -> bool {
        if let Some(&known) = self.reaches.get(&from) {
            return known;
        }
        // No for now: a loop of prototypes reaches nothing through itself.
        self.reaches.insert(from, false);
        let tagged = self.tagged;
        let found = tagged
            .prototypes
            .get(from.0 as usize)
            .is_some_and(|n| self.places(n));
        self.reaches.insert(from, found);
        found
    }

    fn places(&mut self, node: &Node) -> bool {
        match node {
            Node::Instance(id) => *id == self.proto || self.reaches(*id),
            Node::Transform { child, .. } | Node::Flip(child) => self.places(child),
            Node::Group(children) => children.iter().any(|c| self.places(c)),
            Node::Shape { .. }
            | Node::Mesh { .. }
            | Node::Medium { .. }
            | Node::Motion { .. }
            | Node::Lamp(_) => false,
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
        let pick = PickWorld::build(&scene, Vec3::ZERO, u64::MAX).expect("the tagged scene builds");
        let at = |x: f32| {
            let ray = Ray::new(Vec3::new(x, 0.0, 0.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
            pick.pick(&ray).map(|(i, h)| (i, h.t))
        };
        assert_eq!(at(0.0), Some((0, 4.0)));
        assert_eq!(at(3.0), Some((1, 4.0)));
        assert_eq!(at(-3.0), Some((2, 4.0)));
        assert_eq!(at(10.0), None);
    }

    fn moved(m: glam::Mat4, node: Node) -> Node {
        Node::Transform {
            matrix: m,
            child: Box::new(node),
        }
    }

    fn shift(x: f32, y: f32) -> glam::Mat4 {
        glam::Mat4::from_translation(Vec3::new(x, y, -10.0))
    }

    /// The object a ray straight down -z from `(x, y)` picks, and where.
    fn pick_at(pick: &PickWorld, x: f32, y: f32) -> Option<(usize, f32)> {
        let ray = Ray::new(Vec3::new(x, y, 0.0), Vec3::new(0.0, 0.0, -1.0), 0.0);
        pick.pick(&ray).map(|(i, h)| (i, h.t))
    }

    #[test]
    fn many_placements_share_one_copy_of_their_prototype() {
        let mut scene = Scene::default();
        let ball = scene.add_prototype(sphere(Vec3::ZERO, 0));
        // A pair of balls, one of them scaled and turned: a prototype that
        // places another.
        let turned = glam::Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0))
            * glam::Mat4::from_rotation_z(0.7)
            * glam::Mat4::from_scale(Vec3::splat(0.5));
        let pair = scene.add_prototype(Node::Group(vec![
            Node::Instance(ball),
            moved(turned, Node::Instance(ball)),
        ]));
        scene.objects = (0..1000)
            .map(|i| moved(shift(3.0 * i as f32, 0.0), Node::Instance(pair)))
            .collect();
        scene.objects.push(sphere(Vec3::new(-3.0, 0.0, -10.0), 0));
        let pick = PickWorld::build(&scene, Vec3::ZERO, u64::MAX).expect("builds");
        // One copy of each prototype, however often it is placed (a copy
        // per object made 1000 of each).
        assert_eq!(pick.tagged.prototypes.len(), 2);
        assert_eq!(pick_at(&pick, 0.0, 0.0), Some((0, 9.0)));
        assert_eq!(pick_at(&pick, 3.0 * 517.0, 0.0), Some((517, 9.0)));
        let top = pick_at(&pick, 3.0 * 999.0, 1.5).expect("the small ball");
        assert_eq!(top.0, 999);
        assert!((top.1 - 9.5).abs() < 1e-3, "{top:?}");
        assert_eq!(pick_at(&pick, -3.0, 0.0), Some((1000, 9.0)));
        assert_eq!(pick_at(&pick, 1.5, 0.0), None);
    }

    #[test]
    fn overlapping_and_moving_placements_name_their_object() {
        let mut scene = Scene::default();
        let ball = scene.add_prototype(sphere(Vec3::ZERO, 0));
        let motion = crate::scene::motion::Motion { steps: Vec::new() };
        scene.objects = vec![
            // Behind the others along the ray: never the first hit.
            moved(
                shift(0.0, 0.0) * glam::Mat4::from_translation(Vec3::Z * -5.0),
                Node::Instance(ball),
            ),
            moved(shift(0.0, 0.0), Node::Instance(ball)),
            Node::Motion {
                motion,
                child: Box::new(moved(shift(5.0, 0.0), Node::Instance(ball))),
            },
        ];
        let pick = PickWorld::build(&scene, Vec3::new(1.0, 2.0, 3.0), u64::MAX).expect("builds");
        let at = |x: f32| {
            let ray = Ray::new(
                Vec3::new(x - 1.0, -2.0, -3.0),
                Vec3::new(0.0, 0.0, -1.0),
                0.0,
            );
            pick.pick(&ray).map(|(i, h)| (i, h.t))
        };
        assert_eq!(at(0.0), Some((1, 9.0)));
        assert_eq!(at(5.0), Some((2, 9.0)));
    }

    #[test]
    fn a_copy_past_the_memory_budget_is_refused() {
        let mut scene = Scene::default();
        let ball = scene.add_prototype(sphere(Vec3::ZERO, 0));
        scene.objects = (0..100)
            .map(|i| moved(shift(3.0 * i as f32, 0.0), Node::Instance(ball)))
            .collect();
        let err = PickWorld::build(&scene, Vec3::ZERO, 100_000)
            .err()
            .expect("refused");
        assert!(err.to_string().contains("memory budget"), "{err}");
        assert!(PickWorld::build(&scene, Vec3::ZERO, 1 << 20).is_ok());
    }
}
