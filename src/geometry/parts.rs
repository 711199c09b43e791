//! A world of a few meshes, sets of primitives, lone primitives and
//! analytic surfaces of revolution, and of planes, none of them turned,
//! scaled, moved in time, emitting through an offset or holding a medium
//! (only a surface of revolution may stand shifted, as it stands in the
//! camera's frame): a mesh on a floor under a lamp, beside one glowing
//! ball, on an endless plane, or a vase on a floor. [`Parts`] finds a ray's
//! nearest hit part by part, in the order and with the box tests of the
//! world's group, which asks its instances in turn (so the answer is the
//! group's, bit for bit), but without the layers the group's general
//! answer passes through (the group, its instances, their geometry, each
//! returning the whole hit): on the bunny stage those took a third as many
//! instructions as the mesh's own intersections. The world asks its parts
//! so whenever it is one (`World::intersect_in_media`). The lanes ask a
//! [`View`] of them, which takes the crossings of the first set whose
//! crossings can be found eight rays at a pass (flat faces, or a few
//! rects: [`PrimitiveSet::side_by_side`]) from its caller.

use std::sync::Arc;

use arrayvec::ArrayVec;
use glam::Vec3;

use super::emitter::LightId;
use super::group::FEW_SURFACES;
use super::instance::{shifted_hit, Instance, Placement};
use super::mesh::MeshGeometry;
use super::object::{plane_hit, revolution_hit, single_hit, Geometry};
use super::primitive::Primitive;
use super::primitives::PrimitiveSet;
use super::revolution::RevolutionSurface;
use super::shapes::Plane;
use super::{Aabb, Hit, Ray};
use crate::scene::MaterialId;

/// The parts of such a world, in the order its group asks them: the
/// bounded ones, each with its box and its shift (a surface of revolution
/// only), then the planes with their materials.
pub struct Parts {
    parts: ArrayVec<(Aabb, Arc<Geometry>, Option<Vec3>), FEW_SURFACES>,
    planes: Vec<(Plane, MaterialId)>,
}

/// One part, as a [`View`] holds it.
#[derive(Clone, Copy)]
enum Part<'a> {
    Set(&'a PrimitiveSet),
    Mesh(&'a MeshGeometry),
    /// A primitive alone (a lamp beside a mesh), its material and light.
    Single(&'a Primitive, MaterialId, LightId),
    /// An analytic surface of revolution, its material, and the shift
    /// that places it, if any.
    Revolution(&'a RevolutionSurface, MaterialId, Option<Vec3>),
}

impl<'a> Part<'a> {
    fn of(geometry: &'a Geometry, shift: Option<Vec3>) -> Part<'a> {
        match geometry {
            Geometry::Primitives(set) => Part::Set(set),
            Geometry::Mesh(mesh) => Part::Mesh(mesh),
            Geometry::Single(p, m, light) => Part::Single(p, *m, *light),
            Geometry::Revolution { surface, material } => {
                Part::Revolution(surface, *material, shift)
            }
            _ => unreachable!("parts are meshes, primitives and surfaces of revolution"),
        }
    }

    #[inline(always)]
    fn intersect(self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        match self {
            Part::Set(set) => set.intersect_facing(ray, t_min, t_max),
            Part::Mesh(mesh) => mesh.intersect_facing(ray, t_min, t_max),
            Part::Single(p, m, light) => single_hit(p, m, light, ray, t_min, t_max),
            Part::Revolution(surface, m, None) => revolution_hit(surface, m, ray, t_min, t_max),
            Part::Revolution(surface, m, Some(v)) => {
                let local = Ray::new(ray.origin - v, ray.dir, ray.time);
                let h = revolution_hit(surface, m, &local, t_min, t_max)?;
                Some(shifted_hit(h, v))
            }
        }
    }

    #[inline(always)]
    fn occluded(self, ray: &Ray, t_min: f32, t_max: f32, except: LightId) -> bool {
        match self {
            Part::Set(set) => set.occluded(ray, t_min, t_max, except),
            Part::Mesh(mesh) => mesh.occluded(ray, t_min, t_max),
            Part::Single(p, _, light) => {
                light.blocks_beside(except) && p.crossing(ray, t_min, t_max).is_some()
            }
            Part::Revolution(surface, _, None) => surface.occluded(ray, t_min, t_max),
            Part::Revolution(surface, _, Some(v)) => {
                let local = Ray::new(ray.origin - v, ray.dir, ray.time);
                surface.occluded(&local, t_min, t_max)
            }
        }
    }
}

/// The parts as the lanes ask them: each part's surface at hand, and the
/// set whose crossings the caller finds.
pub struct View<'a> {
    parts: ArrayVec<(Aabb, Part<'a>), FEW_SURFACES>,
    planes: &'a [(Plane, MaterialId)],
    side_by_side: Option<(usize, &'a PrimitiveSet)>,
}

/// Where a ray's nearest hit lies.
pub enum Nearest {
    /// Nothing is hit.
    Miss,
    /// The set [`View::side_by_side`] names, at the crossing handed in.
    Flat,
    /// Another part, with the hit facing the ray.
    Hit(Hit),
}

impl Parts {
    /// The parts of the instances `bounded` and `unbounded` (a group's, in
    /// the order it asks them), or `None` unless each bounded one is a
    /// mesh, a set of primitives, a lone primitive or a surface of
    /// revolution and each unbounded one a plane, all unplaced (a surface
    /// of revolution may be shifted), with their emitters numbered as they
    /// are.
    pub(super) fn of(bounded: &[Instance], unbounded: &[Instance]) -> Option<Parts> {
        let usable = |inst: &Instance| {
            matches!(inst.placement, Placement::Identity) && inst.lights == LightId::BASE
        };
        let mut parts = ArrayVec::new();
        for inst in bounded {
            let shift = match (inst.geometry.as_ref(), &inst.placement) {
                (Geometry::Revolution { .. }, Placement::Shift(v)) => Some(*v),
                (
                    Geometry::Primitives(_)
                    | Geometry::Mesh(_)
                    | Geometry::Single(..)
                    | Geometry::Revolution { .. },
                    Placement::Identity,
                ) => None,
                _ => return None,
            };
            if inst.lights != LightId::BASE {
                return None;
            }
            parts
                .try_push((inst.bounds, inst.geometry.clone(), shift))
                .ok()?;
        }
        let mut planes = Vec::with_capacity(unbounded.len());
        for inst in unbounded {
            let Geometry::Plane { plane, material } = *inst.geometry else {
                return None;
            };
            if !usable(inst) {
                return None;
            }
            planes.push((plane, material));
        }
        Some(Parts { parts, planes })
    }

    /// The nearest hit with `t` in `(t_min, t_max)`, as the world's group
    /// finds it.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, mut t_max: f32) -> Option<Hit> {
        let inv_dir = ray.dir.recip();
        let mut found = None;
        for (bounds, geometry, shift) in &self.parts {
            if bounds.entered(ray.origin, inv_dir, t_max) {
                if let Some(h) = Part::of(geometry, *shift).intersect(ray, t_min, t_max) {
                    (t_max, found) = (h.t, Some(h));
                }
            }
        }
        plane_hits(&self.planes, ray, t_min, t_max).or(found)
    }

    /// Whether a part but emitter `except` is hit with `t` in `(t_min,
    /// t_max)`, as the world's group decides it.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, except: LightId) -> bool {
        let inv_dir = ray.dir.recip();
        self.parts.iter().any(|(bounds, geometry, shift)| {
            bounds.entered(ray.origin, inv_dir, t_max)
                && Part::of(geometry, *shift).occluded(ray, t_min, t_max, except)
        }) || planes_occlude(&self.planes, ray, t_min, t_max)
    }

    /// The parts as the lanes ask them.
    pub fn view(&self) -> View<'_> {
        let parts: ArrayVec<_, FEW_SURFACES> = self
            .parts
            .iter()
            .map(|(bounds, geometry, shift)| (*bounds, Part::of(geometry, *shift)))
            .collect();
        let side_by_side = parts
            .iter()
            .enumerate()
            .find_map(|(k, (_, part))| match part {
                Part::Set(set) if set.side_by_side() => Some((k, *set)),
                _ => None,
            });
        View {
            parts,
            planes: &self.planes,
            side_by_side,
        }
    }
}

impl<'a> View<'a> {
    /// The first set whose crossings can be found eight rays at a pass,
    /// which [`View::nearest`] takes from its caller.
    pub fn side_by_side(&self) -> Option<&'a PrimitiveSet> {
        self.side_by_side.map(|(_, set)| set)
    }

    /// Where the nearest hit of `ray` with `t` in `(0, ∞)` lies, as the
    /// world's group finds it, given `flat_t`: the `t` of the nearest
    /// crossing in `(0, ∞)` of the set [`View::side_by_side`] names
    /// (`None`: it has none, or there is no such set).
    #[inline]
    pub fn nearest(&self, ray: &Ray, flat_t: Option<f32>) -> Nearest {
        let inv_dir = ray.dir.recip();
        let mut t_max = f32::INFINITY;
        let mut found = Nearest::Miss;
        let handed = self.side_by_side.map(|(k, _)| k);
        for (k, (bounds, part)) in self.parts.iter().enumerate() {
            if !bounds.entered(ray.origin, inv_dir, t_max) {
                continue;
            }
            if handed == Some(k) {
                // The set asked with `t_max` finds its nearest crossing
                // when that lies below `t_max`, and nothing otherwise.
                if let Some(t) = flat_t.filter(|&t| t < t_max) {
                    (t_max, found) = (t, Nearest::Flat);
                }
            } else if let Some(h) = part.intersect(ray, 0.0, t_max) {
                (t_max, found) = (h.t, Nearest::Hit(h));
            }
        }
        plane_hits(self.planes, ray, 0.0, t_max).map_or(found, Nearest::Hit)
    }

    /// Whether a part but emitter `except` is hit with `t` in `(t_min,
    /// t_max)`, as the world's group decides it.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32, except: LightId) -> bool {
        let inv_dir = ray.dir.recip();
        self.parts.iter().any(|(bounds, part)| {
            bounds.entered(ray.origin, inv_dir, t_max) && part.occluded(ray, t_min, t_max, except)
        }) || planes_occlude(self.planes, ray, t_min, t_max)
    }
}

/// The nearest hit on `planes` with `t` in `(t_min, t_max)`, asked in turn
/// as the group asks its unbounded instances after the bounded ones.
#[inline(always)]
fn plane_hits(
    planes: &[(Plane, MaterialId)],
    ray: &Ray,
    t_min: f32,
    mut t_max: f32,
) -> Option<Hit> {
    let mut found = None;
    for (plane, material) in planes {
        if let Some(h) = plane_hit(plane, *material, ray, t_min, t_max) {
            (t_max, found) = (h.t, Some(h));
        }
    }
    found
}

/// Whether one of `planes` is hit with `t` in `(t_min, t_max)`.
#[inline(always)]
fn planes_occlude(planes: &[(Plane, MaterialId)], ray: &Ray, t_min: f32, t_max: f32) -> bool {
    planes
        .iter()
        .any(|(plane, _)| plane.intersect(ray, t_min, t_max).is_some())
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Vec2};

    use super::*;
    use crate::geometry::group::Group;
    use crate::geometry::primitive::Primitive;
    use crate::geometry::segments::MediumSegments;
    use crate::geometry::shapes::{Rect, Sphere};
    use crate::sampling::rng::numbers;
    use crate::scene::object::RectPlane;
    use crate::scene::{Bezier, MaterialId, MeshData};

    fn placed(geometry: Geometry) -> Instance {
        Instance::new(Arc::new(geometry), Placement::Identity)
    }

    /// A mesh of random triangles over a floor and a lamp (two rects, a
    /// set whose crossings can be handed in), a set of a ball and a wall,
    /// a glowing ball alone and an endless plane across the back, slanted
    /// through the wall: the parts find every ray's hit and occluder as
    /// the group's general walk does, bit for bit, whether they ask each
    /// part or take the rects' crossing from the caller. Two of the
    /// triangles lie in the floor's plane, so some rays meet a triangle and
    /// the floor at one `t`: the part asked first keeps it, as in the group.
    #[test]
    fn the_parts_find_the_groups_hits_and_occluders_bit_for_bit() {
        let mut r = numbers(17);
        let mut positions: Vec<Vec3> = (0..60)
            .map(|_| Vec3::new(r() * 4.0 - 2.0, r() * 2.0, r() * 4.0 - 2.0))
            .collect();
        positions.extend([
            Vec3::new(-1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
        ]);
        let mut triangles: Vec<[u32; 3]> = (0..20).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
        triangles.extend([[60, 62, 61], [61, 62, 63]]);
        let data = MeshData {
            positions,
            triangles,
            ..MeshData::default()
        };
        let mesh = MeshGeometry::new(Arc::new(data), vec![MaterialId(0)]);
        let others = PrimitiveSet::new(vec![
            (
                Primitive::Sphere(Sphere {
                    center: Vec3::new(1.5, 0.6, 1.0),
                    radius: 0.6,
                }),
                MaterialId(3),
                LightId::NONE,
            ),
            (
                rect(RectPlane::Xy, (-3.0, 3.0), (0.0, 3.0), -2.5),
                MaterialId(4),
                LightId::NONE,
            ),
        ]);
        assert!(!others.side_by_side());
        let lamp = Primitive::Sphere(Sphere {
            center: Vec3::new(-1.2, 1.8, -0.8),
            radius: 0.4,
        });
        let group = Group::new(vec![
            placed(Geometry::Mesh(mesh)),
            placed(Geometry::Primitives(stage())),
            placed(Geometry::Primitives(others)),
            placed(Geometry::Single(lamp, MaterialId(5), LightId::new(1))),
            placed(back_wall()),
        ]);
        let seen = agree(&group, &mut r);
        assert!(
            seen.hits > 3000 && seen.flat > 2000 && seen.ties > 100,
            "{seen:?}"
        );
        assert!(
            [0, 3, 4, 5, 6].iter().all(|&m| seen.by_material[m] > 200),
            "{seen:?}"
        );
    }

    /// Surfaces of revolution beside the floor and lamp and the plane, one
    /// where it was made and one shifted (as every surface of revolution
    /// stands in the camera's frame): the parts agree with the group, bit
    /// for bit, on both.
    #[test]
    fn surfaces_of_revolution_shifted_or_not_are_parts_too() {
        let vase = |points: [(f32, f32); 4], material| {
            let curve = Bezier {
                points: points.iter().map(|&(x, y)| Vec2::new(x, y)).collect(),
            };
            Arc::new(Geometry::Revolution {
                surface: Arc::new(RevolutionSurface::new(&curve, 8, 1e-6)),
                material: MaterialId(material),
            })
        };
        let tall = vase([(0.3, 0.0), (0.9, 0.4), (0.1, 0.8), (0.4, 1.2)], 7);
        let bowl = vase([(0.2, 0.0), (1.0, 0.1), (0.8, 0.6), (0.9, 0.7)], 8);
        let shift = Mat4::from_translation(Vec3::new(-1.6, 0.1, 1.4));
        let shifted = Instance::new(tall, Placement::fixed(shift).expect("a shift"));
        assert!(matches!(shifted.placement, Placement::Shift(_)));
        let group = Group::new(vec![
            Instance::new(bowl, Placement::Identity),
            shifted,
            placed(Geometry::Primitives(stage())),
            placed(back_wall()),
        ]);
        assert!(group.parts().is_some());
        let seen = agree(&group, &mut numbers(23));
        assert!(seen.flat > 2000, "{seen:?}");
        assert!(
            [1, 6, 7, 8].iter().all(|&m| seen.by_material[m] > 200),
            "{seen:?}"
        );
    }

    fn rect(plane: RectPlane, a: (f32, f32), b: (f32, f32), k: f32) -> Primitive {
        Primitive::Rect(Rect::new(plane, a, b, k))
    }

    /// A floor and a lamp above it (materials 1 and 2): two rects, a set
    /// whose crossings can be handed in.
    fn stage() -> PrimitiveSet {
        let set = PrimitiveSet::new(vec![
            (
                rect(RectPlane::Xz, (-3.0, 3.0), (-3.0, 3.0), 0.0),
                MaterialId(1),
                LightId::NONE,
            ),
            (
                rect(RectPlane::Xz, (-0.5, 0.5), (-0.5, 0.5), 2.5),
                MaterialId(2),
                LightId::new(0),
            ),
        ]);
        assert!(set.side_by_side());
        set
    }

    /// An endless plane across the back (material 6).
    fn back_wall() -> Geometry {
        Geometry::Plane {
            plane: Plane {
                point: Vec3::new(0.0, 0.0, -2.0),
                normal: Vec3::new(0.3, 0.0, 1.0).normalize(),
            },
            material: MaterialId(6),
        }
    }

    /// What [`agree`] saw: hits in all, nearest hits on the handed-in set,
    /// of those ties with another part, and hits per material.
    #[derive(Debug, Default)]
    struct Seen {
        hits: usize,
        flat: usize,
        ties: usize,
        by_material: [usize; 9],
    }

    /// Asserts that 20 000 rays through the stage find the same nearest
    /// hit and occluders by `group`'s parts, by their view and by the group
    /// itself; a quarter of the rays aim at the floor's middle square.
    fn agree(group: &Group, r: &mut impl FnMut() -> f32) -> Seen {
        let parts = group.parts().expect("parts");
        let view = parts.view();
        let flat = view.side_by_side().expect("the two rects");
        let mut media = MediumSegments::default();
        let mut seen = Seen::default();
        for k in 0..20_000 {
            let from = Vec3::new(r() * 8.0 - 4.0, r() * 4.0 - 0.5, r() * 8.0 - 4.0);
            let to = if k % 4 == 0 {
                Vec3::new(r() * 2.0 - 1.0, 0.0, r() * 2.0 - 1.0)
            } else {
                Vec3::new(r() * 6.0 - 3.0, r() * 3.0, r() * 6.0 - 3.0)
            };
            let ray = Ray::new(from, to - from, 0.0);
            let want = group.intersect(&ray, 0.0, f32::INFINITY, &mut media);
            assert_eq!(parts.intersect(&ray, 0.0, f32::INFINITY), want);
            let flat_t = flat
                .flat_crossing(&ray, 0.0, f32::INFINITY)
                .map(|(_, c)| c.t);
            match (view.nearest(&ray, flat_t), want) {
                (Nearest::Miss, None) => {}
                (Nearest::Flat, Some(h)) => {
                    assert_eq!(Some(h.t), flat_t);
                    assert!(h.material == MaterialId(1) || h.material == MaterialId(2));
                    seen.flat += 1;
                    seen.by_material[h.material.index()] += 1;
                }
                (Nearest::Hit(got), Some(h)) => {
                    assert_eq!(got, h);
                    seen.ties += usize::from(flat_t == Some(h.t));
                    seen.by_material[h.material.index()] += 1;
                    seen.hits += 1;
                }
                (_, want) => panic!("ray {k}: the group finds {want:?}"),
            }
            for t_max in [f32::INFINITY, 6.0 * r()] {
                let want = group.occluded(&ray, 0.0, t_max, &mut media, LightId::NONE);
                assert_eq!(parts.occluded(&ray, 0.0, t_max, LightId::NONE), want);
                assert_eq!(view.occluded(&ray, 0.0, t_max, LightId::NONE), want);
            }
        }
        seen
    }
}
