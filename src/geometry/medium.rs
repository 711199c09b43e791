//! Constant-density participating media inside a closed boundary. Geometry
//! only reports where a ray runs inside a medium (its boundary segments,
//! including rays that start inside); the integrator samples the free-flight
//! distance along them (as pbrt-v4 does), so intersection draws no random
//! numbers.
//!
//! It imports [`super::object`], which imports it back: a medium is one
//! kind of [`Geometry`] and its boundary is geometry (see that module's
//! header).

use std::sync::Arc;

use super::instance::StaticTransform;
use super::object::Geometry;
use super::segments::{MediumSegment, MediumSegments, MAX_SEGMENTS};
use super::shapes::{Cuboid, Sphere};
use super::{Aabb, Ray};
use crate::scene::MaterialId;

/// A homogeneous medium filling `boundary`.
pub struct Medium {
    boundary: Arc<Geometry>,
    /// The boundary when it is a ball, turned or not (most media): its
    /// crossings then come from one solve of its roots.
    ball: Option<Sphere>,
    /// The boundary when it is a box under an affine map (the map from
    /// the box's space to the medium's): its stretch then comes from one
    /// slab test in the box's space, where a box the map turns was six
    /// faces asked once for each crossing and once more past the exit.
    block: Option<(Cuboid, StaticTransform)>,
    density: f32,
    /// The phase function (an isotropic material).
    material: MaterialId,
}

impl Medium {
    pub fn new(boundary: Arc<Geometry>, density: f32, material: MaterialId) -> Medium {
        let ball = match &*boundary {
            Geometry::Single(p, _, _) => p.sphere(),
            _ => None,
        };
        Medium {
            boundary,
            ball,
            block: None,
            density,
            material,
        }
    }

    /// The medium whose boundary is `cuboid` placed by `to_medium` (what
    /// `boundary` is): its stretch is found by [`Cuboid::span`].
    pub fn boxed(self, cuboid: Cuboid, to_medium: StaticTransform) -> Medium {
        Medium {
            block: Some((cuboid, to_medium)),
            ..self
        }
    }

    /// Whether the stretches come from [`Medium::boxed`]'s slab test.
    #[cfg(test)]
    pub fn is_boxed(&self) -> bool {
        self.block.is_some()
    }

    pub fn bounds(&self) -> Aabb {
        self.boundary.bounds()
    }

    /// Adds to `out` every stretch of the ray inside the boundary with `t`
    /// in `(t_min, t_max)`.
    pub fn segments(&self, ray: &Ray, t_min: f32, t_max: f32, out: &mut MediumSegments) {
        if self.density <= 0.0 {
            return;
        }
        if let Some((cuboid, to_medium)) = &self.block {
            // A box is convex: one stretch, from where the ray is first
            // inside to where it leaves (the box's `t` is the ray's).
            let Some((near, far)) = cuboid.span(&to_medium.local(ray)) else {
                return;
            };
            let (t0, t1) = (near.max(t_min), far.min(t_max));
            if t0 < t1 {
                out.push(MediumSegment {
                    t0,
                    t1,
                    density: self.density,
                    material: self.material,
                });
            }
            return;
        }
        match self.ball {
            Some(ball) => {
                // A ray that starts inside a ball is inside it up to one
                // exit (a ball is convex): up to `t_max` when that end is
                // inside too, with no roots to solve (most rays under a
                // haze), else up to the far root.
                if ball.surely_holds(ray.at(t_min)) && t_min < t_max {
                    let exit = if ball.surely_holds(ray.at(t_max)) {
                        t_max
                    } else {
                        match ball.roots(ray).and_then(|r| r.first_after(t_min)) {
                            Some((exit, false)) => exit.min(t_max),
                            _ => return self.ball_segments(ball, ray, t_min, t_max, out),
                        }
                    };
                    out.push(MediumSegment {
                        t0: t_min,
                        t1: exit,
                        density: self.density,
                        material: self.material,
                    });
                } else {
                    self.ball_segments(ball, ray, t_min, t_max, out);
                }
            }
            None => self.walk(ray, t_min, t_max, out, |t| {
                let h = self.boundary.intersect(ray, t, f32::INFINITY)?;
                Some((h.t, h.front_face))
            }),
        }
    }

    /// The stretches inside a ball from one solve of its roots: the ray
    /// enters at the near root (the far one for a negative radius, whose
    /// normals face inwards), with no surface computed.
    fn ball_segments(
        &self,
        ball: Sphere,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        out: &mut MediumSegments,
    ) {
        if let Some(roots) = ball.roots(ray) {
            let outward = ball.radius > 0.0;
            self.walk(ray, t_min, t_max, out, |t| {
                let (at, near) = roots.first_after(t)?;
                Some((at, near == outward))
            });
        }
    }

    /// The stretches of `ray` inside the boundary from the crossings
    /// `next(t)` finds (the first one after `t` and whether the ray enters
    /// there), each search starting just past the last crossing.
    fn walk(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        out: &mut MediumSegments,
        mut next: impl FnMut(f32) -> Option<(f32, bool)>,
    ) {
        let mut t = t_min;
        for _ in 0..MAX_SEGMENTS {
            let Some((first, enters)) = next(t) else {
                return;
            };
            let (entry, exit) = if enters {
                match next(step_past(ray, first)) {
                    Some((exit, _)) => (first, exit),
                    None => return,
                }
            } else {
                (t, first)
            };
            if entry >= t_max {
                return;
            }
            out.push(MediumSegment {
                t0: entry,
                t1: exit.min(t_max),
                density: self.density,
                material: self.material,
            });
            if exit >= t_max {
                return;
            }
            t = step_past(ray, exit);
        }
    }
}

/// A ray parameter just past `t`, far enough that the surface at `t` is not
/// found again.
fn step_past(ray: &Ray, t: f32) -> f32 {
    let scale = ray.at(t).abs().max_element() / ray.dir.length();
    t + (t.abs() + scale) * 1e-5
}

#[cfg(test)]
mod tests {
    use glam::{Quat, Vec3};

    use super::*;
    use crate::geometry::emitter::LightId;
    use crate::geometry::primitive::Primitive;
    use crate::geometry::primitives::PrimitiveSet;
    use crate::geometry::shapes::TurnedSphere;
    use crate::sampling::rng::numbers;

    fn medium(boundary: Geometry) -> Medium {
        Medium::new(Arc::new(boundary), 0.5, MaterialId(3))
    }

    fn found(m: &Medium, ray: &Ray, t_min: f32, t_max: f32) -> Vec<(f32, f32)> {
        let mut out = MediumSegments::default();
        m.segments(ray, t_min, t_max, &mut out);
        out.as_slice().iter().map(|s| (s.t0, s.t1)).collect()
    }

    #[test]
    fn a_ball_gives_the_stretch_between_its_crossings() {
        let ball = Sphere {
            center: Vec3::new(0.0, 0.0, 10.0),
            radius: 2.0,
        };
        let m = medium(Geometry::Single(
            Primitive::Sphere(ball),
            MaterialId(0),
            LightId::NONE,
        ));
        let close = |a: &[(f32, f32)], b: &[(f32, f32)]| {
            a.len() == b.len()
                && a.iter()
                    .zip(b)
                    .all(|(x, y)| (x.0 - y.0).abs() < 1e-5 && (x.1 - y.1).abs() < 1e-5)
        };
        let through = Ray::new(Vec3::ZERO, Vec3::Z, 0.0);
        assert!(close(
            &found(&m, &through, 0.0, f32::INFINITY),
            &[(8.0, 12.0)]
        ));
        assert!(close(&found(&m, &through, 0.0, 9.0), &[(8.0, 9.0)]));
        assert!(found(&m, &through, 0.0, 7.0).is_empty());
        // From inside: the stretch starts at t_min.
        assert!(close(
            &found(&m, &through, 10.0, f32::INFINITY),
            &[(10.0, 12.0)]
        ));
        let beside = Ray::new(Vec3::new(2.5, 0.0, 0.0), Vec3::Z, 0.0);
        assert!(found(&m, &beside, 0.0, f32::INFINITY).is_empty());
        let away = Ray::new(Vec3::ZERO, Vec3::NEG_Z, 0.0);
        assert!(found(&m, &away, 0.0, f32::INFINITY).is_empty());
    }

    #[test]
    fn the_ball_shortcut_gives_the_stretch_the_roots_give() {
        // Rays that start inside the ball take a shortcut (no roots when the
        // end is inside too, no walk past the exit otherwise); they must get
        // the stretches the roots give, bit for bit, near and far from the
        // origin, for tiny and huge balls, with ends a hair inside the
        // surface.
        let mut next = numbers(23);
        let mut shortcuts = 0;
        for (centre, radius) in [
            (Vec3::new(1.0, -2.0, 3.0), 1.5),
            (Vec3::ZERO, 5000.0),
            (Vec3::new(1e5, 0.0, -1e5), 1.0),
            (Vec3::new(0.3, 0.1, 0.0), 1e-3),
        ] {
            let ball = Sphere {
                center: centre,
                radius,
            };
            let m = medium(Geometry::Single(
                Primitive::Sphere(ball),
                MaterialId(0),
                LightId::NONE,
            ));
            for _ in 0..20_000 {
                // Origins and ends within 1.2 radii: a third just inside
                // the surface, a third well inside, a third anywhere.
                let mut end = || {
                    let p = Vec3::new(next(), next(), next()) * 2.0 - Vec3::ONE;
                    let u = next();
                    if u < 1.0 / 3.0 {
                        p.normalize_or(Vec3::X) * (1.0 - 1e-3 * next())
                    } else if u < 2.0 / 3.0 {
                        p * 0.55
                    } else {
                        p * 1.2
                    }
                };
                let (a, b) = (end(), end());
                let (from, to) = (centre + a * radius, centre + b * radius);
                let ray = Ray::new(from, to - from, 0.0);
                // Shadow rays end at t = 1; others run on.
                let t_max = if next() < 0.5 { 1.0 } else { f32::INFINITY };
                let mut roots = MediumSegments::default();
                m.ball_segments(ball, &ray, 0.0, t_max, &mut roots);
                shortcuts += usize::from(ball.surely_holds(ray.at(0.0)));
                let got: Vec<(f32, f32)> = found(&m, &ray, 0.0, t_max);
                let want: Vec<(f32, f32)> = roots.as_slice().iter().map(|s| (s.t0, s.t1)).collect();
                assert_eq!(got, want, "{ray:?} {radius}");
            }
        }
        assert!(shortcuts > 10_000, "{shortcuts}");
    }

    #[test]
    fn a_ball_alone_gives_the_segments_of_the_general_walk() {
        let mut next = numbers(11);
        for scale in [1e-3f32, 1.0, 1e5] {
            let ball = Sphere {
                center: Vec3::new(1.0, -2.0, 3.0) * scale,
                radius: 1.5 * scale,
            };
            let alone = medium(Geometry::Single(
                Primitive::Sphere(ball),
                MaterialId(0),
                LightId::NONE,
            ));
            let set = medium(Geometry::Primitives(PrimitiveSet::new(vec![(
                Primitive::Sphere(ball),
                MaterialId(0),
                LightId::NONE,
            )])));
            for _ in 0..4000 {
                // Origins inside and outside, rays through and beside.
                let mut v = || Vec3::new(next(), next(), next()) * 2.0 - Vec3::ONE;
                let (origin, aim) = (v() * 3.0, v() * 1.6);
                let (origin, aim) = (ball.center + origin * scale, ball.center + aim * scale);
                let ray = Ray::new(origin, (aim - origin).normalize_or(Vec3::Z), 0.0);
                let t_max = if next() < 0.5 {
                    f32::INFINITY
                } else {
                    next() * 5.0 * scale
                };
                assert_eq!(
                    found(&alone, &ray, 0.0, t_max),
                    found(&set, &ray, 0.0, t_max),
                    "{ray:?} {t_max}"
                );
            }
        }
    }

    #[test]
    fn grazing_rays_get_stretches_inside_the_ball_only() {
        let mut next = numbers(5);
        for scale in [1e-3f32, 1.0, 1e5] {
            let ball = Sphere {
                center: Vec3::new(-4.0, 1.0, 2.0) * scale,
                radius: 2.0 * scale,
            };
            let turned = TurnedSphere {
                sphere: ball,
                to_object: Quat::from_rotation_y(0.7),
            };
            for m in [Primitive::Sphere(ball), Primitive::TurnedSphere(turned)]
                .map(|p| medium(Geometry::Single(p, MaterialId(0), LightId::NONE)))
            {
                grazing_stretches_stay_inside(&m, ball, &mut next);
            }
        }
    }

    #[test]
    fn a_placed_box_gives_the_stretches_of_its_faces() {
        // The box's one slab test against the general walk over the box's
        // faces placed in the medium's space (six parallelograms where the
        // map turns it), as the builder makes them: turned, sheared,
        // stretched, tiny, huge and far from the origin; rays from inside
        // and outside, shadow segments and open rays.
        use crate::geometry::bake::transformed;
        use glam::Mat4;
        let mut next = numbers(31);
        let cuboid = Cuboid {
            min: Vec3::new(-1.0, 0.0, -0.5),
            max: Vec3::new(1.5, 2.0, 0.5),
        };
        let maps = [
            Mat4::from_rotation_y(0.26) * Mat4::from_translation(Vec3::new(2.0, 0.0, 3.0)),
            Mat4::from_scale_rotation_translation(
                Vec3::new(3.0, 0.5, 1.0),
                Quat::from_euler(glam::EulerRot::XYZ, 0.4, -1.1, 2.0),
                Vec3::new(-5.0, 1.0, 0.0),
            ),
            Mat4::from_scale(Vec3::splat(1e-3)) * Mat4::from_rotation_x(1.0),
            Mat4::from_translation(Vec3::new(1e5, -2e5, 0.0)) * Mat4::from_rotation_z(0.7),
            Mat4::from_scale(Vec3::new(1e4, 2e4, 1e4)) * Mat4::from_rotation_y(-0.3),
            Mat4::from_translation(Vec3::new(0.5, 0.5, 0.5)),
        ];
        let (mut stretches, mut inside) = (0, 0);
        for m in maps {
            let faces = transformed(&Primitive::Cuboid(cuboid), &m).unwrap();
            let set = faces
                .into_iter()
                .map(|f| (f, MaterialId(0), LightId::NONE))
                .collect();
            let walked = medium(Geometry::Primitives(PrimitiveSet::new(set)));
            let boxed = medium(Geometry::Primitives(PrimitiveSet::default()))
                .boxed(cuboid, StaticTransform::new(m).unwrap());
            let size = m.transform_vector3(cuboid.max - cuboid.min).length();
            for _ in 0..5000 {
                // A third of the rays start inside the box.
                let reach = if next() < 1.0 / 3.0 { 0.95 } else { 3.0 };
                let mut at = |reach: f32| {
                    let u = Vec3::new(next(), next(), next());
                    let p = cuboid.min + u * (cuboid.max - cuboid.min);
                    let centre = 0.5 * (cuboid.min + cuboid.max);
                    m.transform_point3(centre + (p - centre) * reach)
                };
                let (from, to) = (at(reach), at(1.2));
                let ray = Ray::new(from, to - from, 0.0);
                let t_max = if next() < 0.5 { 1.0 } else { f32::INFINITY };
                // Stretches shorter than the rounding of either are left out:
                // a corner grazed may give one and not the other.
                let tol = 1e-4 * (size + from.abs().max_element()) / ray.dir.length();
                let long = |v: Vec<(f32, f32)>| -> Vec<(f32, f32)> {
                    v.into_iter().filter(|(a, b)| b - a > tol).collect()
                };
                let (want, got) = (
                    long(found(&walked, &ray, 0.0, t_max)),
                    long(found(&boxed, &ray, 0.0, t_max)),
                );
                assert_eq!(want.len(), got.len(), "{m:?} {ray:?} {want:?} {got:?}");
                for ((a0, a1), (b0, b1)) in want.iter().zip(&got) {
                    assert!(
                        (a0 - b0).abs() <= tol && (a1 - b1).abs() <= tol,
                        "{want:?} {got:?}"
                    );
                    stretches += 1;
                    inside += usize::from(*b0 == 0.0);
                }
            }
        }
        // Rays that meet the box, and some that start inside it.
        assert!(stretches > 10_000 && inside > 5_000, "{stretches} {inside}");
    }

    /// Lines passing the centre of `ball` within a few ulps of its radius
    /// get no stretch outside it. (Taking the crossings' sides from the
    /// rounded normal, as the general walk does, gives about one such
    /// stretch in a thousand of these rays.)
    fn grazing_stretches_stay_inside(m: &Medium, ball: Sphere, next: &mut impl FnMut() -> f32) {
        for k in 0..40_000 {
            // From 1 to 21 radii in front of the ball, passing its centre at
            // the radius times 1 ± up to 200 steps of 6e-8.
            let dir = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize();
            let side = dir.any_orthonormal_vector();
            let miss = 1.0 + ((k % 400) as f32 - 200.0) * 6e-8;
            let back = 1.0 + 20.0 * next();
            let origin = ball.center + side * ball.radius * miss - dir * back * ball.radius;
            let ray = Ray::new(origin, dir, 0.0);
            for (t0, t1) in found(m, &ray, 0.0, f32::INFINITY) {
                assert!(t0 <= t1, "{ray:?}");
                let mid = ray.at(0.5 * (t0 + t1));
                let off = (mid - ball.center).length() / ball.radius;
                assert!(
                    off < 1.0 + 1e-4,
                    "{ray:?}: stretch {t0}..{t1} outside the ball ({off})"
                );
            }
        }
    }
}
