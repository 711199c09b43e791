//! Builds the intersection structures of a [`Scene`]: walks the object tree,
//! gathers analytic primitives of one space into flat arrays, composes nested
//! static transforms into one matrix, and builds each prototype once.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Mat4;

use super::bake::{flatten, primitive};
use super::group::Group;
use super::instance::{is_bounded, Instance, Placement, StaticTransform};
use super::medium::{Medium, MediumSegments};
use super::mesh::MeshGeometry;
use super::object::Geometry;
use super::primitives::{Primitive, PrimitiveSet};
use super::revolution::{tessellate, RevolutionSurface};
use super::shapes::Plane;
use super::sweep::swept_bounds;
use super::{Aabb, Hit, Ray};
use crate::scene::motion::CompiledMotion;
use crate::scene::object::RevolutionMode;
use crate::scene::{MaterialId, Node, ProtoId, Scene, Shape};

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
    root: Instance,
    revolutions: Vec<Arc<RevolutionSurface>>,
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
        };
        let root = b.instance(scene.objects.iter())?;
        Ok(World {
            root,
            revolutions: b.revolutions,
        })
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
        self.root.intersect(ray, t_min, t_max, media)
    }

    /// Whether a surface is hit with `t` in `(t_min, t_max)` (a shadow
    /// ray); `media` is cleared and receives the medium stretches found
    /// (complete only when nothing is hit).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, media: &mut MediumSegments) -> bool {
        media.clear();
        self.root.occluded(ray, t_min, t_max, media)
    }

    /// The box around every object (infinite when a plane is in it).
    pub fn bounds(&self) -> Aabb {
        self.root.bounds
    }

    /// Intersections that neither Newton nor its fallback could verify,
    /// over all analytic surfaces of revolution so far.
    pub fn newton_failures(&self) -> u64 {
        self.revolutions.iter().map(|r| r.newton_failures()).sum()
    }
}

struct Builder<'a> {
    scene: &'a Scene,
    shutter: (f32, f32),
    prototypes: HashMap<ProtoId, Instance>,
    in_progress: Vec<ProtoId>,
    revolutions: Vec<Arc<RevolutionSurface>>,
}

impl Builder<'_> {
    fn placed(&self, geometry: Geometry, placement: Placement) -> Instance {
        Instance::new(Arc::new(geometry), placement)
    }

    /// One instance holding `nodes`, in the current space.
    fn instance<'n>(
        &mut self,
        nodes: impl Iterator<Item = &'n Node>,
    ) -> Result<Instance, BuildError> {
        let mut prims = Vec::new();
        let mut items = Vec::new();
        for node in nodes {
            self.collect(node, &mut prims, &mut items)?;
        }
        let geometry = match &prims[..] {
            [] => None,
            [(p, m)] => Some(Geometry::Single(*p, *m)),
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

    fn collect(
        &mut self,
        node: &Node,
        prims: &mut Vec<(Primitive, MaterialId)>,
        items: &mut Vec<Instance>,
    ) -> Result<(), BuildError> {
        match node {
            Node::Shape { shape, material } => self.shape(shape, *material, prims, items)?,
            Node::Mesh { mesh, materials } => {
                let data = self
                    .scene
                    .meshes
                    .get(mesh.0 as usize)
                    .ok_or(BuildError::MissingMesh(mesh.0))?;
                if materials.is_empty() {
                    return Err(BuildError::MeshWithoutMaterial);
                }
                let geometry = Geometry::Mesh(MeshGeometry::new(data.clone(), materials.clone()));
                items.push(self.placed(geometry, Placement::Identity));
            }
            Node::Group(children) => {
                for c in children {
                    self.collect(c, prims, items)?;
                }
            }
            // Shapes that survive the matrix exactly join this space's
            // primitives; anything else becomes a placed instance.
            Node::Transform { matrix, child } => {
                if !flatten(matrix, child, prims) {
                    let inner = self.instance(std::iter::once(&**child))?;
                    items.push(self.transform(*matrix, inner)?);
                }
            }
            Node::Motion { motion, child } => {
                let compiled = CompiledMotion::new(motion);
                if compiled.is_identity() {
                    return self.collect(child, prims, items);
                }
                let inner = self.instance(std::iter::once(&**child))?;
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
                let inner = self.instance(std::iter::once(&**boundary))?;
                let medium = Medium {
                    boundary: self.unplaced(inner),
                    density: *density,
                    material: *material,
                };
                items.push(self.placed(Geometry::Medium(medium), Placement::Identity));
            }
            Node::Instance(id) => items.push(self.prototype(*id)?),
            Node::Flip(child) => {
                if flatten(&Mat4::IDENTITY, node, prims) {
                    return Ok(());
                }
                let inner = self.instance(std::iter::once(&**child))?;
                let geometry = Geometry::Flipped(self.unplaced(inner));
                items.push(self.placed(geometry, Placement::Identity));
            }
        }
        Ok(())
    }

    fn shape(
        &mut self,
        shape: &Shape,
        material: MaterialId,
        prims: &mut Vec<(Primitive, MaterialId)>,
        items: &mut Vec<Instance>,
    ) -> Result<(), BuildError> {
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
        prims.extend(prim.map(|p| (p, material)));
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
        Ok(Instance::new(
            inner.geometry,
            Placement::Static(Box::new(s)),
        ))
    }

    /// Geometry whose own space is `inner`'s parent space.
    fn unplaced(&self, inner: Instance) -> Arc<Geometry> {
        match inner.placement {
            Placement::Identity => inner.geometry,
            _ => Arc::new(Geometry::Group(Group::new(vec![inner]))),
        }
    }

    fn prototype(&mut self, id: ProtoId) -> Result<Instance, BuildError> {
        if let Some(inst) = self.prototypes.get(&id) {
            return Ok(inst.clone());
        }
        if self.in_progress.contains(&id) {
            return Err(BuildError::RecursivePrototype(id.0));
        }
        let scene = self.scene;
        let node = scene
            .prototypes
            .get(id.0 as usize)
            .ok_or(BuildError::MissingPrototype(id.0))?;
        self.in_progress.push(id);
        let inst = self.instance(std::iter::once(node));
        self.in_progress.pop();
        let inst = inst?;
        self.prototypes.insert(id, inst.clone());
        Ok(inst)
    }
}
