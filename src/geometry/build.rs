//! Builds the intersection structures of a [`Scene`]: walks the object tree,
//! gathers analytic primitives of one space into flat arrays, composes nested
//! static transforms into one matrix, places a mesh's vertices by its static
//! transform (a copy of its arrays) rather than each ray by the inverse, and
//! builds each prototype once. The same walk collects the emitters
//! ([`Emitters`]) and gives each emissive primitive or triangle the
//! [`LightId`] its hits carry.
//!
//! The world is built in a frame whose origin is a chosen scene point,
//! normally the camera's position (pbrt-v4's camera-world space): the walk
//! moves every top-level object by `−origin` as it builds it, baking the
//! move into shapes, planes, meshes and the matrices of transforms and
//! motions. f32 coordinates are then finest where the picture is made, so
//! a small object next to a camera far from the scene's origin keeps its
//! precision, and the error an object's distance brings stays below what
//! that distance makes visible. Only a bare analytic revolution and a
//! prototype placed without a transform get an instance (a `Shift`) for
//! the move. [`World::origin`] turns frame points back into scene points
//! where the scene's own coordinates matter (texture lookups, the
//! preview's probe); the reach limits (`scene::reach`) stay in scene
//! coordinates.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Affine3A, Mat4, Vec3};

use super::bake::{flatten, primitive, Baked};
use super::emitter::{is_light, Emitters, LightId, Placed, Source};
use super::group::Group;
use super::instance::{Instance, Placement, StaticTransform};
use super::medium::Medium;
use super::mesh::MeshGeometry;
use super::object::Geometry;
use super::parts::Parts;
use super::primitives::{faces_apart, PrimitiveSet};
use super::revolution::{tessellate, RevolutionSurface};
use super::segments::MediumSegments;
use super::shapes::{Cuboid, Plane};
use super::sweep::swept_bounds;
use super::{Aabb, Hit, Ray};
use crate::scene::motion::CompiledMotion;
use crate::scene::motion::{MotionStep, Program};
use crate::scene::object::RevolutionMode;
use crate::scene::{MaterialId, MeshData, MeshId, Motion, Node, ProtoId, Scene, Shape};

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

/// The whole scene's geometry, ready to intersect, in the frame whose
/// origin is the scene point [`World::origin`]: rays, hits and emitters are
/// all in that frame.
pub struct World {
    root: Root,
    revolutions: Vec<Arc<RevolutionSurface>>,
    emitters: Emitters,
    origin: Vec3,
    /// Whether any object is a medium.
    media: bool,
    /// The root group's surfaces, when they are [`Parts`].
    parts: Option<Parts>,
}

impl World {
    /// Builds the geometry of `scene`'s objects in the frame of its camera's
    /// position (see the module doc).
    pub fn build(scene: &Scene) -> Result<World, BuildError> {
        World::build_in(scene, scene.camera.from)
    }

    /// Builds the geometry of `scene`'s objects in the frame whose origin is
    /// the scene point `origin` (`Vec3::ZERO` keeps scene coordinates).
    pub fn build_in(scene: &Scene, origin: Vec3) -> Result<World, BuildError> {
        let mut b = Builder {
            scene,
            shutter: scene.camera.shutter,
            prototypes: HashMap::new(),
            in_progress: Vec::new(),
            revolutions: Vec::new(),
            placed: Vec::new(),
            moved_meshes: HashMap::new(),
            media: false,
        };
        let at = At {
            shift: -origin,
            ..At::WORLD
        };
        let root = Root::new(b.instance(scene.objects.iter(), &at)?);
        let parts = match &root {
            Root::Bare(g) => match g.as_ref() {
                Geometry::Group(group) => group.parts(),
                _ => None,
            },
            Root::Placed(_) => None,
        };
        Ok(World {
            root,
            parts,
            revolutions: b.revolutions,
            emitters: Emitters::finish(scene, &b.placed),
            origin,
            media: b.media,
        })
    }

    /// The scene point at this frame's origin: a point `p` of the frame is
    /// the scene point `p + origin`.
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// Whether any object is a medium: without, rays cross no medium
    /// stretch, and the integrator leaves its free flights out.
    pub fn has_media(&self) -> bool {
        self.media
    }

    /// The emitters, numbered as the [`Hit::light`]s that name them.
    pub fn emitters(&self) -> &Emitters {
        &self.emitters
    }

    /// The world's one set of flat faces, when that is all it holds (a
    /// room of rects and turned boxes): its crossings can be found for many
    /// rays before any of their hits is built.
    pub fn flat_set(&self) -> Option<&PrimitiveSet> {
        self.bare_set().filter(|set| set.is_flat())
    }

    /// The world's one set of primitives when that is all it holds and it is
    /// not flat (no medium, no instance): a pixel's rays walk it in packets
    /// ([`PrimitiveSet::first_hits`]). Flat sets have passes of their own.
    pub fn packet_set(&self) -> Option<&PrimitiveSet> {
        self.bare_set().filter(|set| !set.is_flat())
    }

    /// The world as a few surfaces side by side ([`Parts`]), when that is
    /// what it holds: rays find their nearest hits part by part.
    pub fn parts(&self) -> Option<&Parts> {
        self.parts.as_ref()
    }

    /// The world's one set of primitives, when that is all it holds.
    fn bare_set(&self) -> Option<&PrimitiveSet> {
        match &self.root {
            Root::Bare(g) => match g.as_ref() {
                Geometry::Primitives(set) => Some(set),
                _ => None,
            },
            Root::Placed(_) => None,
        }
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
        if let Some(parts) = &self.parts {
            return parts.intersect(ray, t_min, t_max);
        }
        match &self.root {
            Root::Bare(geometry) => geometry.intersect_in_media(ray, t_min, t_max, media),
            Root::Placed(instance) => instance.intersect(ray, t_min, t_max, media),
        }
    }

    /// Whether a surface is hit with `t` in `(t_min, t_max)` (a shadow
    /// ray) but emitter `except`, the light the segment ends on (`NONE`
    /// for none: see [`LightId::blocks_beside`]); `media` is cleared and
    /// receives the medium stretches found (complete only when nothing is
    /// hit).
    #[inline]
    pub fn occluded(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
        except: LightId,
    ) -> bool {
        media.clear();
        if let Some(parts) = &self.parts {
            return parts.occluded(ray, t_min, t_max, except);
        }
        match &self.root {
            Root::Bare(geometry) => geometry.occluded(ray, t_min, t_max, media, except),
            Root::Placed(instance) => instance.occluded(ray, t_min, t_max, media, except),
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
    /// Whether a medium has been built.
    media: bool,
    /// The emitters found so far, numbered in the space being built (the
    /// world's, or a prototype's while it is built).
    placed: Vec<Placed>,
    /// Each mesh placed bare at the world level, its vertices moved into
    /// the world's frame (one copy however often it is placed).
    moved_meshes: HashMap<MeshId, Arc<MeshData>>,
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

/// Where the walk is: the move from the current space into the space it is
/// built in, the map from that space to the space the emitters are
/// numbered in, the flips around it, and what to do with emitters.
#[derive(Clone, Copy)]
struct At {
    /// Zero except at the world level, where objects move by `−origin`
    /// into the world's frame; a matrix below takes the move into itself.
    shift: Vec3,
    to_space: Affine3A,
    flips: u32,
    emitting: Emitting,
}

impl At {
    const WORLD: At = At {
        shift: Vec3::ZERO,
        to_space: Affine3A::IDENTITY,
        flips: 0,
        emitting: Emitting::Listed,
    };

    /// The move as a matrix.
    fn moved(&self) -> Mat4 {
        Mat4::from_translation(self.shift)
    }

    /// Inside a node whose matrix has taken the move into itself.
    fn unmoved(self) -> At {
        At {
            shift: Vec3::ZERO,
            ..self
        }
    }

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
        let sets = match faces_apart(&prims) {
            Some((faces, rest)) => vec![faces, rest],
            None => vec![prims],
        };
        for prims in sets {
            let geometry = match &prims[..] {
                [] => continue,
                [(p, m, light)] => Geometry::Single(*p, *m, *light),
                _ => Geometry::Primitives(PrimitiveSet::new(prims)),
            };
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
        let moving = at.shift != Vec3::ZERO;
        match node {
            // Other shapes are placed by the move: a bounded shape stays a
            // shape of this space's set, an analytic surface of revolution
            // gets an instance for it.
            Node::Shape { shape, .. } if moving && !moves_itself(shape) => {
                self.placed_by(at.moved(), node, at, prims, items)?
            }
            Node::Shape { shape, material } => self.shape(shape, *material, at, prims, items)?,
            // Nothing to intersect: the renderer places lamps itself.
            Node::Lamp(_) => {}
            Node::Mesh { mesh, materials } => {
                let data = self.mesh(*mesh, at.shift)?;
                items.push(self.mesh_instance(data, materials, at)?);
            }
            Node::Group(children) => {
                for c in children {
                    self.collect(c, at, prims, items)?;
                }
            }
            Node::Transform { matrix, child } => {
                self.placed_by(at.moved() * *matrix, child, at, prims, items)?
            }
            Node::Motion { motion, child } => {
                // Light sampling does not follow a motion, not even one
                // that turns out to stand still.
                let at = at.with(Emitting::Hidden);
                if CompiledMotion::new(motion).is_identity() {
                    return self.collect(child, &at, prims, items);
                }
                // The world's move becomes the motion's last, fixed step.
                let motion = &moved_motion(motion, at.shift);
                let compiled = CompiledMotion::new(motion);
                let inner = self.instance(std::iter::once(&**child), &at.unmoved())?;
                // A motion that does not depend on time is a static transform
                // and costs nothing per ray.
                if let Some(matrix) = compiled.fixed() {
                    items.push(self.transform(matrix, inner)?);
                } else {
                    let geometry = self.unplaced(inner);
                    let bounds = geometry.bounds();
                    let swept = if bounds.is_bounded() {
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
                let mut medium = Medium::new(self.unplaced(inner), *density, *material);
                if let Some((cuboid, to_medium)) = placed_box(boundary, at.moved()) {
                    medium = medium.boxed(cuboid, to_medium);
                }
                self.media = true;
                items.push(self.placed(Geometry::Medium(medium), Placement::Identity));
            }
            Node::Instance(_) if moving => self.placed_by(at.moved(), node, at, prims, items)?,
            Node::Instance(id) => items.push(self.prototype(*id, at)?),
            Node::Flip(child) => {
                if self.flatten(&at.moved(), node, at, prims) {
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

    /// `child` placed by `matrix` (which has taken in the current space's
    /// move): shapes that survive the matrix exactly join this space's
    /// primitives, a mesh has its vertices placed by it
    /// ([`placed_mesh_data`]), and anything else becomes a placed instance.
    fn placed_by(
        &mut self,
        matrix: Mat4,
        child: &Node,
        at: &At,
        prims: &mut Vec<Baked>,
        items: &mut Vec<Instance>,
    ) -> Result<(), BuildError> {
        if self.flatten(&matrix, child, at, prims) {
            return Ok(());
        }
        if let Some((id, materials, m)) = placed_mesh(matrix, child) {
            let data = self.mesh(id, Vec3::ZERO)?;
            if let Some(placed) = placed_mesh_data(&data, &m) {
                items.push(self.mesh_instance(Arc::new(placed), materials, at)?);
                return Ok(());
            }
        }
        let inner_at = At {
            to_space: at.to_space * Affine3A::from_mat4(matrix),
            ..at.unmoved()
        };
        let inner = self.instance(std::iter::once(child), &inner_at)?;
        items.push(self.transform(matrix, inner)?);
        Ok(())
    }

    /// The mesh `data` in the current space, its slots mapped to
    /// `materials`, placed as it stands.
    fn mesh_instance(
        &mut self,
        data: Arc<MeshData>,
        materials: &[MaterialId],
        at: &At,
    ) -> Result<Instance, BuildError> {
        if materials.is_empty() {
            return Err(BuildError::MeshWithoutMaterial);
        }
        let lights = self.mesh_emitters(&data, materials, at);
        let geometry =
            Geometry::Mesh(MeshGeometry::new(data, materials.to_vec()).with_lights(lights));
        Ok(self.placed(geometry, Placement::Identity))
    }

    /// Mesh `id`'s data, its vertices moved by `shift` (a copy, made once).
    fn mesh(&mut self, id: MeshId, shift: Vec3) -> Result<Arc<MeshData>, BuildError> {
        let data = self
            .scene
            .meshes
            .get(id.0 as usize)
            .ok_or(BuildError::MissingMesh(id.0))?;
        if shift == Vec3::ZERO {
            return Ok(data.clone());
        }
        let moved = self
            .moved_meshes
            .entry(id)
            .or_insert_with(|| Arc::new(moved_mesh((**data).clone(), shift)));
        Ok(moved.clone())
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
                    point: *point + at.shift,
                    normal: normal.normalize_or(glam::Vec3::Y),
                };
                items.push(self.placed(Geometry::Plane { plane, material }, Placement::Identity));
                return Ok(());
            }
            Shape::Revolution { curve, mode } => {
                let geometry = match *mode {
                    RevolutionMode::Mesh { resolution } => {
                        let mesh = Arc::new(moved_mesh(tessellate(curve, resolution), at.shift));
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
        let composed = match inner.placement.matrix() {
            Some(own) => m * own,
            None => {
                let geometry = self.unplaced(inner);
                let p = Placement::fixed(m).ok_or(BuildError::SingularMatrix(m))?;
                return Ok(Instance::new(geometry, p));
            }
        };
        let p = Placement::fixed(composed).ok_or(BuildError::SingularMatrix(m))?;
        Ok(Instance::new(inner.geometry, p).with_lights(inner.lights))
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

/// Whether [`Builder::shape`] builds `shape` moved by itself: a plane moves
/// its point, a tessellated surface of revolution its vertices.
fn moves_itself(shape: &Shape) -> bool {
    matches!(
        shape,
        Shape::Plane { .. }
            | Shape::Revolution {
                mode: RevolutionMode::Mesh { .. },
                ..
            }
    )
}

/// The mesh under `node` and the map placing it, `m` after the matrices of
/// the transforms between: `node` is a mesh, or a static transform of one.
fn placed_mesh(m: Mat4, node: &Node) -> Option<(MeshId, &[MaterialId], Mat4)> {
    match node {
        Node::Mesh { mesh, materials } => Some((*mesh, materials, m)),
        Node::Transform { matrix, child } => placed_mesh(m * *matrix, child),
        _ => None,
    }
}

/// `data` with its vertices placed by the affine `m` and its normals by
/// `m`'s normal matrix, so that the mesh is intersected where it stands
/// with no transform per ray, as pbrt-v4 and Mitsuba place theirs. A copy
/// per placement: the memory budget charges a mesh's arrays per placement
/// already (`lang/eval/budget.rs`). `None`, leaving the mesh
/// to an instance, when `m` turns the mesh inside out (a mirror reverses
/// the winding that decides which side faces out) or is singular, or when
/// a placed vertex or normal is not finite.
fn placed_mesh_data(data: &MeshData, m: &Mat4) -> Option<MeshData> {
    let affine = Affine3A::from_mat4(*m);
    let det = affine.matrix3.determinant();
    if !(det > 0.0 && det.is_finite()) {
        return None;
    }
    // The normals are left unnormalised, so that their interpolation is
    // the one an instance makes in its own space, turned; the normal
    // matrix is scaled to a largest entry of one, which keeps them from
    // overflowing or vanishing under tiny or huge scales.
    let normal = affine.matrix3.inverse().transpose();
    let largest = [normal.x_axis, normal.y_axis, normal.z_axis]
        .iter()
        .map(|c| c.abs().max_element())
        .fold(0.0, f32::max);
    let normal = normal * (1.0 / largest);
    let positions: Vec<Vec3> = data
        .positions
        .iter()
        .map(|&p| affine.transform_point3(p))
        .collect();
    let normals: Vec<Vec3> = data.normals.iter().map(|&n| normal.mul_vec3(n)).collect();
    if !positions.iter().chain(&normals).all(|v| v.is_finite()) {
        return None;
    }
    Some(MeshData {
        positions,
        normals,
        uvs: data.uvs.clone(),
        triangles: data.triangles.clone(),
        triangle_material: data.triangle_material.clone(),
        materials: data.materials.clone(),
    })
}

/// `data` with every vertex moved by `shift`.
fn moved_mesh(mut data: MeshData, shift: Vec3) -> MeshData {
    for p in &mut data.positions {
        *p += shift;
    }
    data
}

/// `motion` followed by the fixed move `shift` (itself when there is none).
/// A step of its own costs next_week's moving ball no instructions that
/// cachegrind counts; adding the move to the programs of a last translation
/// cost it 0.8 % more (the programs' stack machine runs two more ops).
fn moved_motion(motion: &Motion, shift: Vec3) -> Motion {
    let mut motion = motion.clone();
    if shift != Vec3::ZERO {
        let step = MotionStep::Translate(shift.to_array().map(Program::constant));
        motion.steps.push(step);
    }
    motion
}

/// The box `node` is, with the map from its space to the one `node` is
/// in after `m`: a box under static transforms (and groups of one), whose
/// map is invertible. Flips are left out (they turn inside out).
fn placed_box(node: &Node, m: Mat4) -> Option<(Cuboid, StaticTransform)> {
    match node {
        Node::Shape {
            shape: Shape::Cuboid { min, max },
            ..
        } => {
            let cuboid = Cuboid {
                min: min.min(*max),
                max: min.max(*max),
            };
            Some((cuboid, StaticTransform::new(m)?))
        }
        Node::Transform { matrix, child } => placed_box(child, m * *matrix),
        Node::Group(children) => match children.as_slice() {
            [child] => placed_box(child, m),
            _ => None,
        },
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::geometry::emitter::{Emitter, LightShape};
    use crate::scene::object::RectPlane;
    use crate::scene::{Material, Motion, Texture};

    #[test]
    fn a_medium_boundary_is_a_placed_box_only_under_transforms() {
        let block = Node::Shape {
            shape: Shape::Cuboid {
                min: Vec3::new(1.0, 2.0, 3.0),
                max: Vec3::ZERO,
            },
            material: MaterialId(0),
        };
        let turn = Mat4::from_rotation_y(0.3) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let turned = Node::Transform {
            matrix: turn,
            child: Box::new(Node::Group(vec![block.clone()])),
        };
        let shift = Mat4::from_translation(Vec3::new(0.0, -4.0, 0.0));
        let (cuboid, map) = placed_box(&turned, shift).unwrap();
        assert_eq!(
            (cuboid.min, cuboid.max),
            (Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0))
        );
        let corner = (shift * turn).transform_point3(cuboid.max);
        assert!((map.to_parent.transform_point3(cuboid.max) - corner).length() < 1e-5);
        // A flip turns the box inside out; two boxes are not one.
        assert!(placed_box(&Node::Flip(Box::new(block.clone())), shift).is_none());
        assert!(placed_box(&Node::Group(vec![block.clone(), block]), shift).is_none());
    }

    /// The builder gives a medium in a turned box (or a plain one) the
    /// box's slab test, and a flipped box the general walk.
    #[test]
    fn a_box_of_medium_is_built_with_its_slab_test() {
        let mut scene = Scene::default();
        let t = scene.add_texture(Texture::Solid(Vec3::ONE));
        let fog = scene.add_material(Material::Isotropic { albedo: t });
        let block = Node::Shape {
            shape: Shape::Cuboid {
                min: Vec3::ZERO,
                max: Vec3::new(1.0, 2.0, 3.0),
            },
            material: fog,
        };
        let turned = Node::Transform {
            matrix: Mat4::from_rotation_y(0.3),
            child: Box::new(block.clone()),
        };
        let boxed = |boundary: Node| {
            let mut scene = scene.clone();
            scene.objects = vec![Node::Medium {
                boundary: Box::new(boundary),
                density: 0.5,
                material: fog,
            }];
            let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
            match &world.root {
                Root::Bare(g) => match g.as_ref() {
                    Geometry::Medium(m) => m.is_boxed(),
                    _ => panic!("the root is not the medium"),
                },
                Root::Placed(_) => panic!("the medium is placed"),
            }
        };
        assert!(boxed(turned));
        assert!(boxed(block.clone()));
        assert!(!boxed(Node::Flip(Box::new(block))));
    }

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
        let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
        assert!(matches!(world.root, Root::Placed(_)));
        assert_eq!(
            centre(emitter_below(&world, 10.0, 0.0)),
            Some(Vec3::new(10.0, 0.0, 0.0))
        );
        assert!(emitter_below(&world, 0.0, 0.0).is_none());
        let down = |x: f32| Ray::new(Vec3::new(x, 50.0, 0.0), Vec3::NEG_Y, 0.0);
        let mut media = MediumSegments::default();
        assert!(world.occluded(&down(10.0), 0.0, 100.0, &mut media, LightId::NONE));
        assert!(!world.occluded(&down(0.0), 0.0, 100.0, &mut media, LightId::NONE));
        // The prototype placed without a transform: the root is its geometry.
        scene.objects = vec![Node::Instance(ProtoId(0))];
        let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
        assert!(matches!(world.root, Root::Bare(_)));
        assert_eq!(centre(emitter_below(&world, 0.0, 0.0)), Some(Vec3::ZERO));
        assert!(world.occluded(&down(0.0), 0.0, 100.0, &mut media, LightId::NONE));
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
        let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
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
        let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
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
        let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
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

    /// Every kind of node, built in a frame far from the scene's origin,
    /// stands where it stands in scene coordinates: the same rays (moved
    /// into the frame) hit the same surfaces at the same distances and
    /// points, with the same light ids, emitters and medium stretches.
    #[test]
    fn every_kind_of_node_built_in_a_moved_frame_stands_where_it_stood() {
        let (mut scene, light) = lit();
        let grey = MaterialId(1);
        let ball = |x: f32, material| Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::new(x, 0.0, 0.0),
                radius: 0.5,
            },
            material,
        };
        let rect = |x: f32| Node::Shape {
            shape: Shape::Rect {
                plane: RectPlane::Xz,
                a: (x - 0.5, x + 0.5),
                b: (-0.5, 0.5),
                k: 0.0,
            },
            material: light,
        };
        let mesh = scene.add_mesh(Arc::new(MeshData {
            positions: vec![
                Vec3::new(11.0, 1.0, -1.0),
                Vec3::new(13.0, 1.0, -1.0),
                Vec3::new(12.0, 1.0, 1.0),
            ],
            triangles: vec![[0, 2, 1]],
            ..MeshData::default()
        }));
        let mesh = Node::Mesh {
            mesh,
            materials: vec![light],
        };
        let profile = |y: f32| crate::scene::Bezier {
            points: vec![
                glam::Vec2::new(1.0, y),
                glam::Vec2::new(1.5, y + 0.5),
                glam::Vec2::new(1.5, y + 1.5),
                glam::Vec2::new(1.0, y + 2.0),
            ],
        };
        let proto = scene.add_prototype(ball(27.0, light));
        let time = Program::time();
        let zero = Program::constant(0.0);
        scene.objects = vec![
            ball(0.0, light),
            rect(3.0),
            Node::Shape {
                shape: Shape::Cuboid {
                    min: Vec3::new(5.5, -0.5, -0.5),
                    max: Vec3::new(6.5, 0.5, 0.5),
                },
                material: grey,
            },
            Node::Shape {
                shape: Shape::Triangle {
                    vertices: [
                        Vec3::new(8.0, 0.0, -1.0),
                        Vec3::new(9.0, 0.0, 1.0),
                        Vec3::new(10.0, 0.0, -1.0),
                    ],
                },
                material: light,
            },
            mesh.clone(),
            Node::Shape {
                shape: Shape::Revolution {
                    curve: profile(-10.0),
                    mode: RevolutionMode::Mesh { resolution: 16 },
                },
                material: grey,
            },
            Node::Shape {
                shape: Shape::Revolution {
                    curve: profile(-20.0),
                    mode: RevolutionMode::Analytic {
                        resolution: 8,
                        tolerance: 1e-5,
                    },
                },
                material: grey,
            },
            moved(18.0, 0.0, ball(0.0, grey)),
            moved(21.0, 0.0, mesh),
            Node::Motion {
                motion: Motion {
                    steps: vec![MotionStep::Translate([time, zero.clone(), zero])],
                },
                child: Box::new(ball(24.0, grey)),
            },
            Node::Instance(proto),
            Node::Motion {
                motion: Motion {
                    steps: vec![MotionStep::Rotate {
                        axis: Vec3::Y,
                        degrees: Program::time(),
                    }],
                },
                child: Box::new(ball(36.0, grey)),
            },
            Node::Medium {
                boundary: Box::new(ball(30.0, grey)),
                density: 0.5,
                material: grey,
            },
            Node::Flip(Box::new(rect(33.0))),
            Node::Shape {
                shape: Shape::Plane {
                    point: Vec3::new(0.0, -30.0, 0.0),
                    normal: Vec3::Y,
                },
                material: grey,
            },
        ];
        let mut rays: Vec<Ray> = (0..13)
            .map(|i| Ray::new(Vec3::new(3.0 * i as f32, 50.0, 0.1), Vec3::NEG_Y, 0.2))
            .collect();
        rays.extend([-9.0, -19.0].map(|y| Ray::new(Vec3::new(-50.0, y, 0.1), Vec3::X, 0.0)));
        rays.push(Ray::new(
            Vec3::new(40.0, 5.0, 3.0),
            Vec3::new(-1.0, -0.2, -0.1),
            0.5,
        ));
        let origin = Vec3::new(1000.0, 250.0, -500.0);
        let here = World::build_in(&scene, Vec3::ZERO).expect("builds");
        let there = World::build_in(&scene, origin).expect("builds");
        assert_eq!(there.origin(), origin);
        let emitters = |w: &World| w.emitters().list.len();
        assert_eq!(emitters(&here), emitters(&there));
        assert!(emitters(&here) >= 5, "{}", emitters(&here));
        let anchor = |w: &World, h: &Hit| {
            let e = w.emitters().list[h.light.index()?]?;
            Some(
                match e.shape {
                    LightShape::Sphere { center, .. } => center,
                    LightShape::Parallelogram { corner, .. } => corner,
                    LightShape::Triangle { v, .. } => v[0],
                } + w.origin(),
            )
        };
        let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 2e-3;
        let (mut hits, mut stretches) = (0, 0);
        for ray in &rays {
            let moved_ray = Ray::new(ray.origin - origin, ray.dir, ray.time);
            let (mut m1, mut m2) = (MediumSegments::default(), MediumSegments::default());
            let a = here.intersect_in_media(ray, 0.0, f32::INFINITY, &mut m1);
            let b = there.intersect_in_media(&moved_ray, 0.0, f32::INFINITY, &mut m2);
            let (Some(a), Some(b)) = (a, b) else {
                panic!("{ray:?}: {a:?} against {b:?}");
            };
            hits += 1;
            assert!(
                (a.t - b.t).abs() < 2e-3,
                "{ray:?}: t {} against {}",
                a.t,
                b.t
            );
            assert!(
                close(a.point, b.point + origin),
                "{ray:?}: {} {}",
                a.point,
                b.point
            );
            assert_eq!(
                (a.material, a.front_face),
                (b.material, b.front_face),
                "{ray:?}"
            );
            assert_eq!(
                a.light.index().is_some(),
                b.light.index().is_some(),
                "{ray:?}"
            );
            match (anchor(&here, &a), anchor(&there, &b)) {
                (Some(p), Some(q)) => assert!(close(p, q), "{ray:?}: emitter {p} against {q}"),
                (p, q) => assert_eq!(p.is_some(), q.is_some(), "{ray:?}"),
            }
            let (s1, s2) = (m1.as_slice(), m2.as_slice());
            assert_eq!(s1.len(), s2.len(), "{ray:?}");
            for (x, y) in s1.iter().zip(s2) {
                assert!(
                    (x.t0 - y.t0).abs() < 2e-3 && (x.t1 - y.t1).abs() < 2e-3,
                    "{ray:?}"
                );
                stretches += 1;
            }
        }
        assert_eq!((hits, stretches), (rays.len(), 1));
    }

    /// A mesh under static transforms is built with its vertices placed
    /// (no instance) and hits as its instance by the same matrix does: the
    /// same side out, distances and normals within roundings, an error box
    /// that reaches the exactly placed surface, its emitters where it
    /// stands. Turned, stretched, tiny and huge far from the origin; a
    /// mirror keeps its instance.
    #[test]
    fn a_mesh_placed_by_a_transform_hits_as_its_instance() {
        use crate::sampling::rng::numbers;
        let (mut scene, light) = lit();
        // An octahedron with outward vertex normals tilted off the faces'.
        let positions = vec![
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ];
        let normals = positions.iter().map(|p| *p + Vec3::splat(0.2)).collect();
        let triangles = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        let data = Arc::new(MeshData {
            positions,
            normals,
            triangles,
            ..MeshData::default()
        });
        let mesh = scene.add_mesh(data.clone());
        let turn = Mat4::from_rotation_y(0.7) * Mat4::from_rotation_x(-0.4);
        let maps = [
            (
                turn * Mat4::from_scale(Vec3::new(2.0, 0.5, 1.3)),
                Vec3::new(3.0, -1.0, 2.0),
            ),
            (
                Mat4::from_scale(Vec3::splat(1e-5)),
                Vec3::new(1e-4, 0.0, -2e-4),
            ),
            (
                turn * Mat4::from_scale(Vec3::splat(3e3)),
                Vec3::new(4e6, -2e6, 1e6),
            ),
            (Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)), Vec3::ONE),
        ];
        let mut r = numbers(12);
        let mut hits = 0;
        for (k, (linear, offset)) in maps.into_iter().enumerate() {
            let m = Mat4::from_translation(offset) * linear;
            let node = Node::Mesh {
                mesh,
                materials: vec![light],
            };
            // Two nested transforms, composed into one placement.
            let half = Mat4::from_translation(offset * 0.5);
            scene.objects = vec![Node::Transform {
                matrix: half,
                child: Box::new(Node::Transform {
                    matrix: half.inverse() * m,
                    child: Box::new(node),
                }),
            }];
            let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
            let mirrored = linear.determinant() < 0.0;
            let placed = match &world.root {
                Root::Bare(root) => matches!(**root, Geometry::Mesh(_)),
                Root::Placed(_) => false,
            };
            assert_eq!(placed, !mirrored, "map {k}");
            let by_instance = Instance::new(
                Arc::new(Geometry::Mesh(MeshGeometry::new(data.clone(), vec![light]))),
                Placement::fixed(m).expect("invertible"),
            );
            let size = linear.transform_vector3(Vec3::ONE).length();
            for _ in 0..500 {
                // At a point well inside a face, from outside the solid.
                let face = data.triangles[(r() * 8.0) as usize % 8];
                let (a, b) = (0.1 + 0.6 * r(), 0.1 + 0.6 * r());
                let w = Vec3::new(1.0 - a.max(b), a.min(b), a.max(b) - a.min(b));
                let local = face
                    .iter()
                    .zip(w.to_array())
                    .fold(Vec3::ZERO, |p, (&i, w)| p + w * data.positions[i as usize]);
                let target = m.transform_point3(local);
                let md = m.as_dmat4();
                let [p, q, c] =
                    face.map(|i| md.transform_point3(data.positions[i as usize].as_dvec3()));
                let n = (q - p).cross(c - p).normalize();
                // Towards the face's outside, which the ray then meets
                // first (the solid is convex; a mirror turns it inside),
                // within 53° of the face's normal: along a grazing ray a
                // rounding across the face moves the point far along it.
                let inward = if mirrored { n } else { -n };
                let spread = Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * 1.6;
                let dir = (inward.as_vec3() + spread.clamp_length_max(0.8)).normalize();
                let ray = Ray::new(target - 4.0 * size * dir, dir * size, 0.0);
                let mut media = MediumSegments::default();
                let a = world.intersect(&ray, 0.0, f32::INFINITY);
                let b = by_instance.intersect(&ray, 0.0, f32::INFINITY, &mut media);
                let (Some(a), Some(b)) = (a, b) else {
                    assert!(a.is_none() && b.is_none(), "map {k}: {ray:?}");
                    continue;
                };
                hits += 1;
                assert_eq!(a.front_face, b.front_face, "map {k}");
                // Both points on the face's exact plane, within roundings
                // of the size and of the coordinates' spacing far from the
                // origin.
                let slack =
                    1e-4 * size as f64 + 32.0 * f64::from(f32::EPSILON) * offset.length() as f64;
                for h in [a, b] {
                    let off = (h.point.as_dvec3() - p).dot(n).abs();
                    assert!(off <= slack, "map {k}: {} off by {off}", h.point);
                }
                assert!(a.geo_normal.dot(b.geo_normal) > 0.9999, "map {k}");
                // The shading normal stays on the side the ray meets. The
                // instance checks that in its own space, which a stretch
                // does not keep: there its turned normal may lean behind
                // the face, and the placed mesh's is the face's own.
                assert!(a.normal.dot(a.geo_normal) >= 0.0, "map {k}");
                if b.normal.dot(b.geo_normal) >= 0.0 {
                    assert!(a.normal.dot(b.normal) > 0.9999, "map {k}");
                } else {
                    assert_eq!(a.normal, a.geo_normal, "map {k}");
                }
                // The error box reaches the exactly placed face's plane.
                let off = (a.point.as_dvec3() - p).dot(n).abs();
                assert!(
                    off <= n.abs().dot(a.error.as_dvec3()),
                    "map {k}: off by {off}"
                );
                // The emitter hit stands where the face does.
                let e = world.emitters().list[a.light.index().expect("an emitter")];
                let Some(Emitter {
                    shape: LightShape::Triangle { v, .. },
                    ..
                }) = e
                else {
                    panic!("map {k}: {e:?}");
                };
                let centre = (v[0] + v[1] + v[2]).as_dvec3() / 3.0;
                assert!((centre - p).dot(n).abs() <= slack, "map {k}");
            }
        }
        assert!(hits > 1800, "{hits}");
    }
}
