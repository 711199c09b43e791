//! A bottom- or mid-level object: the closed set of things an instance can
//! place, and their intersection returning a full [`Hit`].
//!
//! This module and [`super::group`], [`super::instance`] and
//! [`super::medium`] import each other on purpose: a [`Geometry`] may be a
//! group of instances of geometry, or a medium whose boundary is geometry.
//! The type is recursive across them, and one closed enum keeps the hot
//! path's dispatch a single match instead of a call through a trait object.

use std::sync::Arc;

use glam::Vec3;

use super::emitter::LightId;
use super::group::Group;
use super::hit::{facing_flat, facing_flat_with};
use super::medium::Medium;
use super::mesh::MeshGeometry;
use super::primitive::Primitive;
use super::primitives::PrimitiveSet;
use super::revolution::RevolutionSurface;
use super::segments::MediumSegments;
use super::shapes::{Plane, ShapeHit};
use super::{Aabb, Hit, Ray};
use crate::scene::MaterialId;

/// Geometry in its own object space.
pub enum Geometry {
    Primitives(PrimitiveSet),
    /// One primitive alone (a medium's boundary, a moving ball): tested
    /// directly, without a hierarchy to walk.
    Single(Primitive, MaterialId, LightId),
    Mesh(MeshGeometry),
    Revolution {
        surface: Arc<RevolutionSurface>,
        material: MaterialId,
    },
    Plane {
        plane: Plane,
        material: MaterialId,
    },
    Group(Group),
    Medium(Medium),
    /// The inner geometry with every hit's `front_face` negated.
    Flipped(Arc<Geometry>),
}

impl Geometry {
    /// Object-space bounds; infinite for planes.
    pub fn bounds(&self) -> Aabb {
        match self {
            Geometry::Primitives(p) => p.bounds(),
            Geometry::Single(p, _, _) => p.bounds(),
            Geometry::Mesh(m) => m.bounds(),
            Geometry::Revolution { surface, .. } => surface.bounds(),
            Geometry::Plane { .. } => Aabb {
                min: Vec3::NEG_INFINITY,
                max: Vec3::INFINITY,
            },
            Geometry::Group(g) => g.bounds(),
            Geometry::Medium(m) => m.bounds(),
            Geometry::Flipped(inner) => inner.bounds(),
        }
    }

    /// Whether a surface but emitter `except` (see
    /// [`LightId::blocks_beside`]) is hit with `t` in `(t_min, t_max)`:
    /// stops at the first hit found and builds no [`Hit`]. Medium segments
    /// go to `media`.
    #[inline]
    pub fn occluded(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
        except: LightId,
    ) -> bool {
        match self {
            Geometry::Primitives(p) => p.occluded(ray, t_min, t_max, except),
            Geometry::Single(p, _, light) => {
                light.blocks_beside(except) && p.crossing(ray, t_min, t_max).is_some()
            }
            Geometry::Mesh(mesh) => mesh.occluded(ray, t_min, t_max),
            Geometry::Revolution { surface, .. } => surface.occluded(ray, t_min, t_max),
            Geometry::Plane { plane, .. } => plane.intersect(ray, t_min, t_max).is_some(),
            Geometry::Group(g) => g.occluded(ray, t_min, t_max, media, except),
            Geometry::Medium(m) => {
                m.segments(ray, t_min, t_max, media);
                false
            }
            Geometry::Flipped(inner) => inner.occluded(ray, t_min, t_max, media, except),
        }
    }

    /// The nearest surface hit with `t` in `(t_min, t_max)`, ignoring media.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        self.intersect_in_media(ray, t_min, t_max, &mut MediumSegments::default())
    }

    /// The nearest surface hit with `t` in `(t_min, t_max)`; the stretches
    /// of the ray inside media (up to `t_max`) go to `media`.
    #[inline]
    pub fn intersect_in_media(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
    ) -> Option<Hit> {
        match self {
            Geometry::Primitives(p) => p.intersect_facing(ray, t_min, t_max),
            Geometry::Single(p, m, light) => single_hit(p, *m, *light, ray, t_min, t_max),
            Geometry::Mesh(mesh) => mesh.intersect_facing(ray, t_min, t_max),
            Geometry::Revolution { surface, material } => {
                revolution_hit(surface, *material, ray, t_min, t_max)
            }
            Geometry::Plane { plane, material } => plane_hit(plane, *material, ray, t_min, t_max),
            Geometry::Group(g) => g.intersect(ray, t_min, t_max, media),
            Geometry::Medium(m) => {
                m.segments(ray, t_min, t_max, media);
                None
            }
            Geometry::Flipped(inner) => {
                let mut h = inner.intersect_in_media(ray, t_min, t_max, media)?;
                h.front_face = !h.front_face;
                Some(h)
            }
        }
    }
}

/// The hit of a [`Geometry::Single`] primitive `p` with `t` in `(t_min,
/// t_max)`, facing the ray.
#[inline(always)]
pub(super) fn single_hit(
    p: &Primitive,
    m: MaterialId,
    light: LightId,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let h = p.intersect(ray, t_min, t_max)?;
    Some(facing_flat_with(h, ray.dir, m, light, |h| p.tangents(h)))
}

/// The hit of a [`Geometry::Revolution`] with `t` in `(t_min, t_max)`,
/// facing the ray.
#[inline(always)]
pub(super) fn revolution_hit(
    surface: &RevolutionSurface,
    m: MaterialId,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let s = surface.intersect(ray, t_min, t_max)?;
    let h = ShapeHit {
        t: s.t,
        point: s.point,
        error: s.error,
        normal: s.normal,
        uv: s.uv.into(),
    };
    Some(facing_flat(h, ray.dir, m, LightId::NONE))
}

/// The hit of a [`Geometry::Plane`] with `t` in `(t_min, t_max)`, facing
/// the ray.
#[inline(always)]
pub(super) fn plane_hit(
    plane: &Plane,
    m: MaterialId,
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<Hit> {
    let h = plane.intersect(ray, t_min, t_max)?;
    let tangents = |_: &ShapeHit| super::tangents::plane(plane.normal);
    Some(facing_flat_with(h, ray.dir, m, LightId::NONE, tangents))
}
