//! Builds the intersection structures of a [`Scene`]: walks the object tree,
//! gathers analytic primitives of one space into flat arrays, composes nested
//! static transforms into one matrix, and builds each prototype once. The
//! same walk collects the emitters ([`Emitters`]) and gives each emissive
//! primitive or triangle the [`LightId`] its hits carry.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Affine3A, Mat4};

use super::bake::{flatten, primitive, Baked};
use super::emitter::{is_light, Emitters, LightId, Placed, Source};
use super::group::Group;
use super::instance::{is_bounded, Instance, Placement, StaticTransform};
use super::medium::{Medium, MediumSegments};
use super::mesh::MeshGeometry;
use super::object::Geometry;
use super::primitives::PrimitiveSet;
use super::revolution::{tessellate, RevolutionSurface};
use super::shapes::Plane;
use super::sweep::swept_bounds;
use super::{Aabb, Hit, Ray};
use crate::scene::motion::CompiledMotion;
use crate::scene::object::RevolutionMode;
use crate::scene::{MaterialId, MeshData, Node, ProtoId, Scene, Shape};

/// Why a scene's geometry could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error("a transform matrix is not invertible: {0}")]
    SingularMatrix(Mat4),
    #[error("prototype {0} does not exist")]
    MissingPrototype(u32),
    #[error("mesh {0} does not exist")]
    MissingMesh(u32),
    #[error("a mesh has no material")]
    MeshWithoutMaterial,
    #[error("prototype {0} refers to itself")]
    RecursivePrototype(u32),
}

/// The whole scene's geometry, ready to intersect.
pub struct World {
    root: Root,
    revolutions: Vec<Arc<RevolutionSurface>>,
    emitters: Emitters,
}

impl World {
    /// Builds the geometry of `scene`'s objects.
    pub fn build(scene: &Scene) -> Result<World, BuildError> {
        let mut b = Builder {
            scene,
            shutter: scene.camera.shutter,
            prototypes: HashMap::new(),
            in_progress: Vec::new(),
            revolutions: Vec::new(),
            placed: Vec::new(),
        };
        let root = b.instance(scene.objects.iter(), &At::WORLD)?;
        Ok(World {
            root: Root::new(root),
            revolutions: b.revolutions,
            emitters: Emitters::finish(scene, &b.placed),
        })
    }

    /// The emitters, numbered as the [`Hit::light`]s that name them.
    pub fn emitters(&self) -> &Emitters {
        &self.emitters
    }

    /// The nearest surface hit with `t` in `(t_min, t_max)`, ignoring media.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        self.intersect_in_media(ray, t_min, t_max, &mut MediumSegments::default())
    }

    /// The nearest surface hit with `t` in `(t_min, t_max)`; `media` is
    /// cleared and receives the stretches of the ray inside media up to
    /// `t_max` (the caller clips them at the hit).
    #[inline]
    pub fn intersect_in_media(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
    ) -> Option<Hit> {
        media.clear();
        match &self.root {
            Root::Bare(geometry) => geometry.intersect_in_media(ray, t_min, t_max, media),
            Root::Placed(instance) => instance.intersect(ray, t_min, t_max, media),
        }
    }

    /// Whether a surface is hit with `t` in `(t_min, t_max)` (a shadow
    /// ray); `media` is cleared and receives the medium stretches found
    /// (complete only when nothing is hit).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, media: &mut MediumSegments) -> bool {
        media.clear();
        match &self.root {
            Root::Bare(geometry) => geometry.occluded(ray, t_min, t_max, media),
            Root::Placed(instance) => instance.occluded(ray, t_min, t_max, media),
        }
    }

    /// The box around every object (infinite when a plane is in it).
    pub fn bounds(&self) -> Aabb {
        match &self.root {
            Root::Bare(geometry) => geometry.bounds(),
            Root::Placed(instance) => instance.bounds,
        }
    }

    /// Intersections that neither Newton nor its fallback could verify,
    /// over all analytic surfaces of revolution so far.
    pub fn newton_failures(&self) -> u64 {
        self.revolutions.iter().map(|r| r.newton_failures()).sum()
    }
}

/// What a ray meets first: the scene's geometry itself when the root
/// instance places it as is (most scenes), so that rays skip the
/// instance's steps; otherwise that instance.
enum Root {
    Bare(Arc<Geometry>),
    Placed(Instance),
}

impl Root {
    fn new(root: Instance) -> Root {
        match root.placement {
            Placement::Identity if root.lights == LightId::BASE => Root::Bare(root.geometry),
            _ => Root::Placed(root),
        }
    }
}

struct Builder<'a> {
    scene: &'a Scene,
    shutter: (f32, f32),
    /// Each prototype built, with its emitters in its own space.
    prototypes: HashMap<ProtoId, (Instance, Vec<Placed>)>,
    in_progress: Vec<ProtoId>,
    revolutions: Vec<Arc<RevolutionSurface>>,
    /// The emitters found so far, numbered in the space being built (the
    /// world's, or a prototype's while it is built).
    placed: Vec<Placed>,
}

/// What the walk does with the emitters below a node.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Emitting {
    /// Collects them.
    Listed,
    /// Collects none: their hits carry no light id and count in full, as
    /// those of any emitter light sampling cannot describe (under a motion,
    /// or a medium's boundary, which is never hit as a surface).
    Hidden,
}

/// Where the walk is: the map from the current space to the space the
/// emitters are numbered in, the flips around it, and what to do with
/// emitters.
#[derive(Clone, Copy)]
struct At {
    to_space: Affine3A,
    flips: u32,
    emitting: Emitting,
}

impl At {
    const WORLD: At = At {
        to_space: Affine3A::IDENTITY,
        flips: 0,
        emitting: Emitting::Listed,
    };

    /// Below a node that lists fewer emitters: a hidden one stays hidden.
    fn with(self, emitting: Emitting) -> At {
        At {
            emitting: self.emitting.max(emitting),
            ..self
        }
    }
}

impl Builder<'_> {
    /// The light id of a shape of `material` (`source`, if it is a kind
    /// the list describes), mapped from its own space to the current one by
    /// `to_here`, at `at` with `flips` more flips: a new emitter if it is a
    /// light that can be listed here, otherwise `NONE`.
    fn emitter(
        &mut self,
        source: Option<Source>,
        material: MaterialId,
        to_here: Affine3A,
        flips: u32,
        at: &At,
    ) -> LightId {
        if !is_light(self.scene, material) {
            return LightId::NONE;
        }
        match (at.emitting, source) {
            (Emitting::Listed, Some(source)) => {
                self.placed.push(Placed {
                    source,
                    to_world: at.to_space * to_here,
                    flips: at.flips + flips,
                    material,
                });
                LightId::new(self.placed.len() - 1)
            }
            _ => LightId::NONE,
        }
    }

    fn placed(&self, geometry: Geometry, placement: Placement) -> Instance {
        Instance::new(Arc::new(geometry), placement)
    }

    /// One instance holding `nodes`, in the current space.
    fn instance<'n>(
        &mut self,
        nodes: impl Iterator<Item = &'n Node>,
        at: &At,
    ) -> Result<Instance, BuildError> {
        let mut prims = Vec::new();
        let mut items = Vec::new();
        for node in nodes {
            self.collect(node, at, &mut prims, &mut items)?;
        }
        let geometry = match &prims[..] {
            [] => None,
            [(p, m, light)] => Some(Geometry::Single(*p, *m, *light)),
            _ => Some(Geometry::Primitives(PrimitiveSet::new(prims))),
        };
        if let Some(geometry) = geometry {
            items.push(self.placed(geometry, Placement::Identity));
        }
        if items.len() == 1 {
            return Ok(items.remove(0));
        }
        Ok(self.placed(Geometry::Group(Group::new(items)), Placement::Identity))
    }

    /// Bakes `node` placed by `m` into `prims` if every shape under it
    /// survives the map ([`flatten`]), listing its emitters; otherwise
    /// leaves both as they were and returns false.
    fn flatten(&mut self, m: &Mat4, node: &Node, at: &At, prims: &mut Vec<Baked>) -> bool {
        let start = self.placed.len();
        let ok = flatten(m, node, prims, &mut |shape, material, m, flips| {
            self.emitter(
                Source::of(shape),
                material,
                Affine3A::from_mat4(*m),
                flips,
                at,
            )
        });
        if !ok {
            self.placed.truncate(start);
        }
        ok
    }

    fn collect(
        &mut self,
        node: &Node,
        at: &At,
        prims: &mut Vec<Baked>,
        items: &mut Vec<Instance>,
    ) -> Result<(), BuildError> {
        match node {
            Node::Shape { shape, material } => self.shape(shape, *material, at, prims, items)?,
            Node::Mesh { mesh, materials } => {
                let data = self
                    .scene
                    .meshes
                    .get(mesh.0 as usize)
                    .ok_or(BuildError::MissingMesh(mesh.0))?;
                if materials.is_empty() {
                    return Err(BuildError::MeshWithoutMaterial);
                }
                let lights = self.mesh_emitters(data, materials, at);
                let geometry = Geometry::Mesh(
                    MeshGeometry::new(data.clone(), materials.clone()).with_lights(lights),
                );
                items.push(self.placed(geometry, Placement::Identity));
            }
            Node::Group(children) => {
                for c in children {
                    self.collect(c, at, prims, items)?;
                }
            }
            // Shapes that survive the matrix exactly join this space's
            // primitives; anything else becomes a placed instance.
            Node::Transform { matrix, child } => {
                if !self.flatten(matrix, child, at, prims) {
                    let inner_at = At {
                        to_space: at.to_space * Affine3A::from_mat4(*matrix),
                        ..*at
                    };
                    let inner = self.instance(std::iter::once(&**child), &inner_at)?;
                    items.push(self.transform(*matrix, inner)?);
                }
            }
            Node::Motion { motion, child } => {
                // Light sampling does not follow a motion, not even one
                // that turns out to stand still.
                let at = at.with(Emitting::Hidden);
                let compiled = CompiledMotion::new(motion);
                if compiled.is_identity() {
                    return self.collect(child, &at, prims, items);
                }
                let inner = self.instance(std::iter::once(&**child), &at)?;
                // A motion that does not depend on time is a static transform
                // and costs nothing per ray.
                if let Some(matrix) = compiled.fixed() {
                    items.push(self.transform(matrix, inner)?);
                } else {
                    let geometry = self.unplaced(inner);
                    let bounds = geometry.bounds();
                    let swept = if is_bounded(&bounds) {
                        swept_bounds(motion, &bounds, self.shutter.0, self.shutter.1)
                    } else {
                        bounds
                    };
                    items.push(Instance::moving(geometry, Arc::new(compiled), swept));
                }
            }
            Node::Medium {
                boundary,
                density,
                material,
            } => {
                let inner =
                    self.instance(std::iter::once(&**boundary), &at.with(Emitting::Hidden))?;
                let medium = Medium::new(self.unplaced(inner), *density, *material);
                items.push(self.placed(Geometry::Medium(medium), Placement::Identity));
            }
            Node::Instance(id) => items.push(self.prototype(*id, at)?),
            Node::Flip(child) => {
                if self.flatten(&Mat4::IDENTITY, node, at, prims) {
                    return Ok(());
                }
                let inner_at = At {
                    flips: at.flips + 1,
                    ..*at
                };
                let inner = self.instance(std::iter::once(&**child), &inner_at)?;
                let geometry = Geometry::Flipped(self.unplaced(inner));
                items.push(self.placed(geometry, Placement::Identity));
            }
        }
        Ok(())
    }

    /// The light id of each triangle of the mesh `data` whose slots map to
    /// `materials`; empty when no triangle emits.
    fn mesh_emitters(
        &mut self,
        data: &MeshData,
        materials: &[MaterialId],
        at: &At,
    ) -> Vec<LightId> {
        if !materials.iter().any(|m| is_light(self.scene, *m)) {
            return Vec::new();
        }
        (0..data.triangles.len())
            .map(|i| {
                let slot = data.triangle_material.get(i).copied().unwrap_or(0) as usize;
                let material = materials[slot.min(materials.len() - 1)];
                match data.triangles[i].map(|k| data.positions.get(k as usize).copied()) {
                    [Some(a), Some(b), Some(c)] => {
                        let source = Source::Triangle([a, b, c]);
                        self.emitter(Some(source), material, Affine3A::IDENTITY, 0, at)
                    }
                    _ => LightId::NONE,
                }
            })
            .collect()
    }

    fn shape(
        &mut self,
        shape: &Shape,
        material: MaterialId,
        at: &At,
        prims: &mut Vec<Baked>,
        items: &mut Vec<Instance>,
    ) -> Result<(), BuildError> {
        let light = self.emitter(Source::of(shape), material, Affine3A::IDENTITY, 0, at);
        let prim = match shape {
            Shape::Plane { point, normal } => {
                let plane = Plane {
                    point: *point,
                    normal: normal.normalize_or(glam::Vec3::Y),
                };
                items.push(self.placed(Geometry::Plane { plane, material }, Placement::Identity));
                return Ok(());
            }
            Shape::Revolution { curve, mode } => {
                let geometry = match *mode {
                    RevolutionMode::Mesh { resolution } => {
                        let mesh = Arc::new(tessellate(curve, resolution));
                        Geometry::Mesh(MeshGeometry::new(mesh, vec![material]))
                    }
                    RevolutionMode::Analytic {
                        resolution,
                        tolerance,
                    } => {
                        let surface =
                            Arc::new(RevolutionSurface::new(curve, resolution, tolerance));
                        self.revolutions.push(surface.clone());
                        Geometry::Revolution { surface, material }
                    }
                };
                items.push(self.placed(geometry, Placement::Identity));
                return Ok(());
            }
            bounded => primitive(bounded),
        };
        prims.extend(prim.map(|p| (p, material, light)));
        Ok(())
    }

    /// Places `inner` by `m` after its own placement, composing static
    /// matrices into one; the identity leaves it as it is.
    fn transform(&self, m: Mat4, inner: Instance) -> Result<Instance, BuildError> {
        if m == Mat4::IDENTITY {
            return Ok(inner);
        }
        let composed = match &inner.placement {
            Placement::Identity => m,
            Placement::Static(s) => m * Mat4::from(s.to_parent),
            Placement::Moving(_) => {
                let geometry = self.unplaced(inner);
                let s = StaticTransform::new(m).ok_or(BuildError::SingularMatrix(m))?;
                return Ok(Instance::new(geometry, Placement::Static(Box::new(s))));
            }
        };
        let s = StaticTransform::new(composed).ok_or(BuildError::SingularMatrix(m))?;
        Ok(Instance::new(inner.geometry, Placement::Static(Box::new(s))).with_lights(inner.lights))
    }

    /// Geometry whose own space is `inner`'s parent space.
    fn unplaced(&self, inner: Instance) -> Arc<Geometry> {
        match inner.placement {
            Placement::Identity if inner.lights == LightId::BASE => inner.geometry,
            _ => Arc::new(Geometry::Group(Group::new(vec![inner]))),
        }
    }

    /// A placement of prototype `id` at `at`: built once, in its own space
    /// with its own emitters, which each placement appends (placed by
    /// `at`) to the list being built, its instance counting its emitters'
    /// ids from there.
    fn prototype(&mut self, id: ProtoId, at: &At) -> Result<Instance, BuildError> {
        if !self.prototypes.contains_key(&id) {
            if self.in_progress.contains(&id) {
                return Err(BuildError::RecursivePrototype(id.0));
            }
            let scene = self.scene;
            let node = scene
                .prototypes
                .get(id.0 as usize)
                .ok_or(BuildError::MissingPrototype(id.0))?;
            self.in_progress.push(id);
            let outer = std::mem::take(&mut self.placed);
            let inst = self.instance(std::iter::once(node), &At::WORLD);
            let own = std::mem::replace(&mut self.placed, outer);
            self.in_progress.pop();
            self.prototypes.insert(id, (inst?, own));
        }
        let Some((inst, own)) = self.prototypes.get(&id) else {
            return Err(BuildError::MissingPrototype(id.0));
        };
        let base = match at.emitting {
            Emitting::Listed => {
                let base = LightId::new(self.placed.len());
                self.placed.extend(own.iter().map(|p| Placed {
                    to_world: at.to_space * p.to_world,
                    flips: at.flips + p.flips,
                    ..*p
                }));
                base
            }
            Emitting::Hidden => LightId::NONE,
        };
        Ok(inst.clone().with_lights(base))
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::geometry::emitter::{Emitter, LightShape};
    use crate::scene::object::RectPlane;
    use crate::scene::{Material, Motion, Texture};

    /// A scene with one light material (and a grey one), and its id.
    fn lit() -> (Scene, MaterialId) {
        let mut scene = Scene::default();
        let t = scene.add_texture(Texture::Solid(Vec3::ONE));
        let light = scene.add_material(Material::Light {
            emit: t,
            two_sided: false,
        });
        scene.add_material(Material::Lambertian { albedo: t });
        (scene, light)
    }

    fn moved(x: f32, y: f32, child: Node) -> Node {
        Node::Transform {
            matrix: Mat4::from_translation(Vec3::new(x, y, 0.0)),
            child: Box::new(child),
        }
    }

    /// The emitter a ray straight down onto `(x, z)` hits.
    fn emitter_below(world: &World, x: f32, z: f32) -> Option<Emitter> {
        let ray = Ray::new(Vec3::new(x, 50.0, z), Vec3::NEG_Y, 0.0);
        let hit = world.intersect(&ray, 0.0, f32::INFINITY)?;
        world.emitters().list[hit.light.index()?]
    }

    fn centre(e: Option<Emitter>) -> Option<Vec3> {
        match e?.shape {
            LightShape::Sphere { center, .. } => Some(center),
            _ => None,
        }
    }

    /// A world of one placed prototype has that placement as its root,
    /// which rays and shadow rays must go through: the ball is found where
    /// it was moved to, not where its prototype has it.
    #[test]
    fn a_root_placed_by_a_transform_is_intersected_where_it_stands() {
        let (mut scene, light) = lit();
        scene.prototypes.push(Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::ZERO,
                radius: 0.5,
            },
            material: light,
        });
        scene.objects = vec![moved(10.0, 0.0, Node::Instance(ProtoId(0)))];
        let world = World::build(&scene).expect("builds");
        assert!(matches!(world.root, Root::Placed(_)));
        assert_eq!(
            centre(emitter_below(&world, 10.0, 0.0)),
            Some(Vec3::new(10.0, 0.0, 0.0))
        );
        assert!(emitter_below(&world, 0.0, 0.0).is_none());
        let down = |x: f32| Ray::new(Vec3::new(x, 50.0, 0.0), Vec3::NEG_Y, 0.0);
        let mut media = MediumSegments::default();
        assert!(world.occluded(&down(10.0), 0.0, 100.0, &mut media));
        assert!(!world.occluded(&down(0.0), 0.0, 100.0, &mut media));
        // The prototype placed without a transform: the root is its geometry.
        scene.objects = vec![Node::Instance(ProtoId(0))];
        let world = World::build(&scene).expect("builds");
        assert!(matches!(world.root, Root::Bare(_)));
        assert_eq!(centre(emitter_below(&world, 0.0, 0.0)), Some(Vec3::ZERO));
        assert!(world.occluded(&down(0.0), 0.0, 100.0, &mut media));
    }

    /// A prototype's geometry is built once and shared, yet each placement
    /// of it (nested placements too) has emitters of its own, and a hit on
    /// a placement names that placement's emitter.
    #[test]
    fn every_placement_of_a_shared_emitter_is_an_emitter_of_its_own() {
        let (mut scene, light) = lit();
        let ball = Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::ZERO,
                radius: 0.5,
            },
            material: light,
        };
        // Prototype 0: a ball and a grey ball; prototype 1: two of it.
        let grey = Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::new(0.0, 0.0, 5.0),
                radius: 0.5,
            },
            material: MaterialId(1),
        };
        scene.prototypes.push(Node::Group(vec![ball, grey]));
        scene.prototypes.push(Node::Group(vec![
            moved(0.0, 0.0, Node::Instance(ProtoId(0))),
            moved(2.0, 1.0, Node::Instance(ProtoId(0))),
        ]));
        scene.objects = vec![
            moved(10.0, 0.0, Node::Instance(ProtoId(1))),
            moved(20.0, 0.0, Node::Instance(ProtoId(1))),
            Node::Instance(ProtoId(0)),
        ];
        let world = World::build(&scene).expect("builds");
        let want = [
            (10.0, 0.0),
            (12.0, 1.0),
            (20.0, 0.0),
            (22.0, 1.0),
            (0.0, 0.0),
        ];
        assert_eq!(world.emitters().list.len(), want.len());
        for (k, (x, y)) in want.into_iter().enumerate() {
            let c = Vec3::new(x, y, 0.0);
            assert_eq!(centre(world.emitters().list[k]), Some(c), "emitter {k}");
            assert_eq!(centre(emitter_below(&world, x, 0.0)), Some(c), "{c}");
            assert_eq!(emitter_below(&world, x, 5.0), None, "the grey ball");
        }
    }

    /// Baked shapes (a rect moved and flipped) and mesh triangles carry
    /// their ids too; a flip turns a flat emitter's normal; an emitter
    /// under a motion has no id, and the static shapes of its material keep
    /// theirs.
    #[test]
    fn baked_flipped_mesh_and_moving_emitters_are_named_as_listed() {
        let (mut scene, light) = lit();
        let rect = Node::Flip(Box::new(Node::Shape {
            shape: Shape::Rect {
                plane: RectPlane::Xz,
                a: (-0.5, 0.5),
                b: (-0.5, 0.5),
                k: 0.0,
            },
            material: light,
        }));
        let mesh = scene.add_mesh(Arc::new(MeshData {
            positions: vec![
                Vec3::new(-1.0, 0.0, -1.0),
                Vec3::new(1.0, 0.0, -1.0),
                Vec3::new(0.0, 0.0, 1.0),
            ],
            triangles: vec![[0, 2, 1]],
            ..MeshData::default()
        }));
        scene.objects = vec![
            moved(3.0, 2.0, rect),
            moved(
                -3.0,
                0.0,
                Node::Mesh {
                    mesh,
                    materials: vec![light],
                },
            ),
        ];
        let world = World::build(&scene).expect("builds");
        match emitter_below(&world, 3.0, 0.0).map(|e| e.shape) {
            Some(LightShape::Parallelogram { corner, normal, .. }) => {
                assert_eq!((corner, normal), (Vec3::new(2.5, 2.0, -0.5), Vec3::NEG_Y))
            }
            other => panic!("not the rect: {other:?}"),
        }
        match emitter_below(&world, -3.0, 0.0).map(|e| e.shape) {
            Some(LightShape::Triangle { v, normal }) => {
                assert_eq!(v[0], Vec3::new(-4.0, 0.0, -1.0));
                assert_eq!(normal, Vec3::Y);
            }
            other => panic!("not the triangle: {other:?}"),
        }
        scene.objects.push(Node::Motion {
            motion: Motion::default(),
            child: Box::new(moved(9.0, 0.0, scene.objects[1].clone())),
        });
        let world = World::build(&scene).expect("builds");
        assert_eq!(world.emitters().list.len(), 2);
        let hit = world.intersect(
            &Ray::new(Vec3::new(6.0, 5.0, 0.0), Vec3::NEG_Y, 0.0),
            0.0,
            f32::INFINITY,
        );
        assert_eq!(hit.map(|h| h.light), Some(LightId::NONE));
        assert!(matches!(
            emitter_below(&world, -3.0, 0.0).map(|e| e.shape),
            Some(LightShape::Triangle { .. })
        ));
    }
}
