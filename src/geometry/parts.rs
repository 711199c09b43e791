//! A world of a few meshes beside sets of primitives, none of them placed,
//! moved, emitting through an offset or holding a medium: a mesh on a floor
//! under a lamp. [`Parts`] finds a ray's nearest hit part by part, in the
//! order and with the box tests of the world's group, which asks its
//! instances in turn (so the answer is the group's, bit for bit), but
//! without the layers the group's general answer passes through (the
//! group, its instances, their geometry): on the bunny stage those took a
//! third as many instructions as the mesh's own intersections. The first
//! set among the parts whose crossings can be found eight rays at a pass
//! (flat faces, or a few rects: [`PrimitiveSet::side_by_side`]) has them
//! handed in by the caller, who finds them so.

use arrayvec::ArrayVec;

use super::emitter::LightId;
use super::group::FEW_SURFACES;
use super::instance::{Instance, Placement};
use super::mesh::MeshGeometry;
use super::object::Geometry;
use super::primitives::PrimitiveSet;
use super::{Aabb, Hit, Ray};

/// One part: a set of primitives or a mesh.
#[derive(Clone, Copy)]
enum Part<'a> {
    Set(&'a PrimitiveSet),
    Mesh(&'a MeshGeometry),
}

/// The parts of such a world, in the order its group asks them, each with
/// its box.
pub struct Parts<'a> {
    parts: ArrayVec<(Aabb, Part<'a>), FEW_SURFACES>,
    flat: Option<&'a PrimitiveSet>,
}

/// Where a ray's nearest hit lies.
pub enum Nearest {
    /// Nothing is hit.
    Miss,
    /// The flat set, at the crossing the caller handed in.
    Flat,
    /// Another part, with the hit facing the ray.
    Hit(Hit),
}

impl<'a> Parts<'a> {
    /// The parts of the instances `bounded` (a group's, in the order it
    /// asks them), or `None` unless each is a mesh or a set of primitives,
    /// unplaced, with its emitters numbered as they are, and one is a mesh.
    pub(super) fn of(bounded: &'a [Instance]) -> Option<Parts<'a>> {
        let mut parts = ArrayVec::new();
        let (mut flat, mut meshes) = (None, 0);
        for inst in bounded {
            if !matches!(inst.placement, Placement::Identity) || inst.lights != LightId::BASE {
                return None;
            }
            let part = match inst.geometry.as_ref() {
                Geometry::Mesh(m) => {
                    meshes += 1;
                    Part::Mesh(m)
                }
                Geometry::Primitives(set) => {
                    if set.side_by_side() && flat.is_none() {
                        flat = Some(set);
                    }
                    Part::Set(set)
                }
                _ => return None,
            };
            parts.try_push((inst.bounds, part)).ok()?;
        }
        (meshes > 0).then_some(Parts { parts, flat })
    }

    /// The first set whose crossings can be found eight rays at a pass,
    /// which [`Parts::nearest`] takes from its caller.
    pub fn flat(&self) -> Option<&'a PrimitiveSet> {
        self.flat
    }

    /// Where the nearest hit of `ray` with `t` in `(0, ∞)` lies, as the
    /// world's group finds it, given `flat_t`: the `t` of the nearest
    /// crossing in `(0, ∞)` of the set [`Parts::flat`] names (`None`: it
    /// has none, or there is no such set).
    #[inline]
    pub fn nearest(&self, ray: &Ray, flat_t: Option<f32>) -> Nearest {
        let inv_dir = ray.dir.recip();
        let mut t_max = f32::INFINITY;
        let mut found = Nearest::Miss;
        for (bounds, part) in &self.parts {
            if !bounds.entered(ray.origin, inv_dir, t_max) {
                continue;
            }
            match part {
                // The flat set asked with `t_max` finds its nearest
                // crossing when that lies below `t_max`, and nothing
                // otherwise.
                Part::Set(set) if self.flat.is_some_and(|f| std::ptr::eq(f, *set)) => {
                    if let Some(t) = flat_t.filter(|&t| t < t_max) {
                        (t_max, found) = (t, Nearest::Flat);
                    }
                }
                Part::Set(set) => {
                    if let Some(h) = set.intersect_facing(ray, 0.0, t_max) {
                        (t_max, found) = (h.t, Nearest::Hit(h));
                    }
                }
                Part::Mesh(mesh) => {
                    if let Some(h) = mesh.intersect_facing(ray, 0.0, t_max) {
                        (t_max, found) = (h.t, Nearest::Hit(h));
                    }
                }
            }
        }
        found
    }

    /// Whether a part is hit with `t` in `(t_min, t_max)`, as the world's
    /// group decides it.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        let inv_dir = ray.dir.recip();
        self.parts.iter().any(|(bounds, part)| {
            bounds.entered(ray.origin, inv_dir, t_max)
                && match part {
                    Part::Set(set) => set.occluded(ray, t_min, t_max),
                    Part::Mesh(mesh) => mesh.occluded(ray, t_min, t_max),
                }
        })
    }
}
