//! An instance places shared geometry in its parent's space: as is, by a
//! fixed matrix with its inverse and normal matrix cached, or by a motion
//! evaluated at the ray's time. Only moving instances look at the time.

use std::sync::Arc;

use glam::{Affine3A, Mat3A, Mat4};

use super::emitter::LightId;
use super::medium::MediumSegments;
use super::object::Geometry;
use super::ray::transform_point;
use super::{Aabb, Hit, Ray};
use crate::scene::motion::CompiledMotion;

/// A fixed object-to-parent transform with what intersection needs cached.
#[derive(Clone, Debug)]
pub struct StaticTransform {
    pub to_parent: Affine3A,
    pub to_object: Affine3A,
    /// Inverse transpose of the linear part, for normals.
    pub normal: Mat3A,
}

impl StaticTransform {
    /// `None` when `m` is not an invertible affine matrix.
    pub fn new(m: Mat4) -> Option<StaticTransform> {
        let to_parent = Affine3A::from_mat4(m);
        let det = to_parent.matrix3.determinant();
        if det == 0.0 || !det.is_finite() || !m.is_finite() {
            return None;
        }
        let to_object = to_parent.inverse();
        Some(StaticTransform {
            to_parent,
            to_object,
            normal: to_object.matrix3.transpose(),
        })
    }
}

impl StaticTransform {
    /// `ray` in the object space.
    #[inline]
    pub fn local(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.to_object.transform_point3(ray.origin),
            self.to_object.transform_vector3(ray.dir),
            ray.time,
        )
    }

    /// From a matrix and its inverse computed together (by a compiled
    /// motion), without a general inversion; `None` if either is not finite.
    #[inline]
    pub fn from_pair((m, inverse): (Mat4, Mat4)) -> Option<StaticTransform> {
        if !m.is_finite() || !inverse.is_finite() {
            return None;
        }
        let to_object = Affine3A::from_mat4(inverse);
        Some(StaticTransform {
            to_parent: Affine3A::from_mat4(m),
            to_object,
            normal: to_object.matrix3.transpose(),
        })
    }
}

/// How an instance is placed.
#[derive(Clone)]
pub enum Placement {
    Identity,
    Static(Box<StaticTransform>),
    /// A motion compiled once at build time; evaluated per ray.
    Moving(Arc<CompiledMotion>),
}

/// Shared geometry and its placement, with the bounds in the parent space
/// and the base its light ids count from (a shared prototype's ids count
/// from its own first emitter).
#[derive(Clone)]
pub struct Instance {
    pub geometry: Arc<Geometry>,
    pub placement: Placement,
    pub bounds: Aabb,
    pub lights: LightId,
}

/// Whether a box is non-empty and finite (it can go into a BVH).
pub fn is_bounded(b: &Aabb) -> bool {
    !b.is_empty() && b.min.is_finite() && b.max.is_finite()
}

impl Instance {
    /// Places `geometry` as is or by a fixed transform.
    pub fn new(geometry: Arc<Geometry>, placement: Placement) -> Instance {
        let local = geometry.bounds();
        let bounds = match &placement {
            Placement::Static(s) if is_bounded(&local) => {
                local.transformed(&Mat4::from(s.to_parent))
            }
            _ => local,
        };
        Instance {
            geometry,
            placement,
            bounds,
            lights: LightId::BASE,
        }
    }

    /// The instance with its light ids counted from `base`.
    pub fn with_lights(self, base: LightId) -> Instance {
        Instance {
            lights: base,
            ..self
        }
    }

    /// Places `geometry` by a motion; `swept` bounds it over the shutter.
    pub fn moving(geometry: Arc<Geometry>, motion: Arc<CompiledMotion>, swept: Aabb) -> Instance {
        Instance {
            geometry,
            placement: Placement::Moving(motion),
            bounds: swept,
            lights: LightId::BASE,
        }
    }

    /// The nearest hit with `t` in `(t_min, t_max)`, in the parent's space.
    #[inline]
    pub fn intersect(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
    ) -> Option<Hit> {
        let mut h = match &self.placement {
            Placement::Identity => self.geometry.intersect_in_media(ray, t_min, t_max, media),
            Placement::Static(s) => self.transformed(ray, s, t_min, t_max, media),
            Placement::Moving(motion) => {
                let s = StaticTransform::from_pair(motion.matrices_at(ray.time))?;
                self.transformed(ray, &s, t_min, t_max, media)
            }
        }?;
        h.light = h.light.within(self.lights);
        Some(h)
    }

    /// Whether anything is hit with `t` in `(t_min, t_max)`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, media: &mut MediumSegments) -> bool {
        let s = match &self.placement {
            Placement::Identity => return self.geometry.occluded(ray, t_min, t_max, media),
            Placement::Static(s) => s.as_ref(),
            Placement::Moving(motion) => {
                let Some(s) = StaticTransform::from_pair(motion.matrices_at(ray.time)) else {
                    return false;
                };
                return self.geometry.occluded(&s.local(ray), t_min, t_max, media);
            }
        };
        self.geometry.occluded(&s.local(ray), t_min, t_max, media)
    }

    #[inline]
    fn transformed(
        &self,
        ray: &Ray,
        s: &StaticTransform,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
    ) -> Option<Hit> {
        let mut h = self
            .geometry
            .intersect_in_media(&s.local(ray), t_min, t_max, media)?;
        (h.point, h.error) = transform_point(&s.to_parent, h.point, h.error);
        h.geo_normal = s.normal.mul_vec3(h.geo_normal).normalize_or(h.geo_normal);
        h.normal = s.normal.mul_vec3(h.normal).normalize_or(h.geo_normal);
        Some(h)
    }
}
