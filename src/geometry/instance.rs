//! An instance places shared geometry in its parent's space: as is, by a
//! fixed translation (a ray moves by one subtraction, a hit by one addition,
//! normals not at all), by a fixed matrix with its inverse and normal
//! matrix cached, or by a motion evaluated at the ray's time. Only moving
//! instances look at the time.
//!
//! It imports [`super::object`], which reaches it back through groups: an
//! instance places a [`Geometry`], which may be a group of instances (see
//! that module's header).

use std::sync::Arc;

use glam::{Affine3A, Mat3A, Mat4, Vec3};

use super::emitter::LightId;
use super::object::Geometry;
use super::ray::{gamma, transform_point};
use super::segments::MediumSegments;
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
    /// Moved by a fixed vector, without turning or scaling.
    Shift(Vec3),
    Static(Box<StaticTransform>),
    /// A motion compiled once at build time; evaluated per ray.
    Moving(Arc<CompiledMotion>),
}

impl Placement {
    /// The placement by the fixed affine `m`: a shift when its linear part
    /// is exactly the identity; `None` when `m` is not invertible.
    pub fn fixed(m: Mat4) -> Option<Placement> {
        if Affine3A::from_mat4(m).matrix3 == Mat3A::IDENTITY && m.w_axis.is_finite() {
            return Some(Placement::Shift(m.w_axis.truncate()));
        }
        StaticTransform::new(m).map(|s| Placement::Static(Box::new(s)))
    }

    /// The object-to-parent matrix, for a fixed placement.
    pub fn matrix(&self) -> Option<Mat4> {
        match self {
            Placement::Identity => Some(Mat4::IDENTITY),
            Placement::Shift(v) => Some(Mat4::from_translation(*v)),
            Placement::Static(s) => Some(Mat4::from(s.to_parent)),
            Placement::Moving(_) => None,
        }
    }
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

impl Instance {
    /// Places `geometry` as is or by a fixed transform.
    pub fn new(geometry: Arc<Geometry>, placement: Placement) -> Instance {
        let local = geometry.bounds();
        let bounds = match placement.matrix() {
            Some(m) if local.is_bounded() && m != Mat4::IDENTITY => local.transformed(&m),
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
            Placement::Shift(v) => self.shifted(ray, *v, t_min, t_max, media),
            Placement::Static(s) => self.transformed(ray, s, t_min, t_max, media),
            Placement::Moving(motion) => {
                let s = StaticTransform::from_pair(motion.matrices_at(ray.time))?;
                self.transformed(ray, &s, t_min, t_max, media)
            }
        }?;
        h.light = h.light.within(self.lights);
        Some(h)
    }

    /// Whether anything but the world's emitter `except` is hit with `t`
    /// in `(t_min, t_max)`.
    #[inline]
    pub fn occluded(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
        except: LightId,
    ) -> bool {
        let except = except.below(self.lights);
        let s = match &self.placement {
            Placement::Identity => return self.geometry.occluded(ray, t_min, t_max, media, except),
            Placement::Shift(v) => {
                let local = Ray::new(ray.origin - *v, ray.dir, ray.time);
                return self.geometry.occluded(&local, t_min, t_max, media, except);
            }
            Placement::Static(s) => s.as_ref(),
            Placement::Moving(motion) => {
                let Some(s) = StaticTransform::from_pair(motion.matrices_at(ray.time)) else {
                    return false;
                };
                return self
                    .geometry
                    .occluded(&s.local(ray), t_min, t_max, media, except);
            }
        };
        self.geometry
            .occluded(&s.local(ray), t_min, t_max, media, except)
    }

    /// The nearest hit of `ray` on the geometry moved by `v`. Kept out of
    /// line: inlined, it grew next_week's instructions by 0.9 %.
    #[inline(never)]
    fn shifted(
        &self,
        ray: &Ray,
        v: Vec3,
        t_min: f32,
        t_max: f32,
        media: &mut MediumSegments,
    ) -> Option<Hit> {
        let local = Ray::new(ray.origin - v, ray.dir, ray.time);
        let h = self
            .geometry
            .intersect_in_media(&local, t_min, t_max, media)?;
        Some(shifted_hit(h, v))
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
        if h.material.needs_tangents() {
            h.tangents = h.tangents.map(|v| s.to_parent.transform_vector3(v));
        }
        Some(h)
    }
}

/// A hit found on geometry moved by `v`, with its ray's origin less `v`,
/// as a hit of the moved geometry.
#[inline(always)]
pub(super) fn shifted_hit(mut h: Hit, v: Vec3) -> Hit {
    // One rounding of the sum: |fl(p + v) − (p + v)| ≤ γ₁·|fl(p + v)|.
    h.point += v;
    h.error += gamma(1) * h.point.abs();
    h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mesh::MeshGeometry;
    use crate::sampling::rng::numbers;
    use crate::scene::{MaterialId, MeshData};

    /// A mesh moved by a translation is placed by a shift, whose hits are
    /// the matrix placement's and whose points' error boxes reach the
    /// exactly moved surface, far from the origin too.
    #[test]
    fn a_shift_places_like_its_matrix_and_bounds_its_points_error() {
        let corners = [
            Vec3::new(-1.0, -0.3, 0.2),
            Vec3::new(1.3, -0.1, -0.4),
            Vec3::new(0.1, 1.2, 0.3),
        ];
        let mesh = Arc::new(MeshData {
            positions: corners.to_vec(),
            triangles: vec![[0, 1, 2]],
            ..MeshData::default()
        });
        let geometry = Arc::new(Geometry::Mesh(MeshGeometry::new(mesh, vec![MaterialId(0)])));
        let mut next = numbers(5);
        let mut hits = 0;
        for v in [
            Vec3::new(0.37, -2.5, 7.1),
            Vec3::new(1e3 + 0.37, -2.5e2, 7.1e4),
        ] {
            let m = Mat4::from_translation(v);
            let shifted = Instance::new(geometry.clone(), Placement::fixed(m).expect("invertible"));
            assert!(matches!(shifted.placement, Placement::Shift(_)));
            let matrix = StaticTransform::new(m).expect("invertible");
            let by_matrix = Instance::new(geometry.clone(), Placement::Static(Box::new(matrix)));
            let exact = corners.map(|c| c.as_dvec3() + v.as_dvec3());
            let n = (exact[1] - exact[0]).cross(exact[2] - exact[0]).normalize();
            for _ in 0..2000 {
                let target = v + corners[0] * next() + corners[1] * next() + corners[2] * next();
                let dir = Vec3::new(next() - 0.5, next() - 0.5, next() + 0.2).normalize();
                let ray = Ray::new(target - 3.0 * dir, dir, 0.0);
                let mut media = MediumSegments::default();
                let a = shifted.intersect(&ray, 0.0, f32::INFINITY, &mut media);
                let b = by_matrix.intersect(&ray, 0.0, f32::INFINITY, &mut media);
                assert_eq!(a.is_some(), b.is_some(), "{ray:?}");
                assert_eq!(
                    shifted.occluded(&ray, 0.0, f32::INFINITY, &mut media, LightId::NONE),
                    a.is_some()
                );
                let (Some(a), Some(b)) = (a, b) else { continue };
                hits += 1;
                assert!((a.t - b.t).abs() <= 1e-5 * (1.0 + a.t), "{} {}", a.t, b.t);
                assert_eq!(a.geo_normal, b.geo_normal.normalize());
                // The error box reaches the moved plane.
                let off = (a.point.as_dvec3() - exact[0]).dot(n).abs();
                let reach = n.abs().dot(a.error.as_dvec3());
                assert!(
                    off <= reach,
                    "{} off by {off}, error reaches {reach}",
                    a.point
                );
                assert!(shifted.bounds.contains(a.point), "{}", a.point);
            }
        }
        assert!(hits > 2000, "{hits}");
    }
}
