//! One-sided lights that face away from every other surface: a flat
//! emitter (rect or triangle) whose material emits from its front face
//! only, with no point of any other object's bounding box in front of its
//! plane, lights nothing (the picture is black but for the light itself).
//! The front is the renderer's: `+axis` for a rect, `(b − a) × (c − a)` for
//! a triangle, through transforms (by the inverse transpose) and turned by
//! each `flip`. Anything under `motion` may be anywhere, so it counts as in
//! front, and a moving light is not judged.

use glam::{Mat4, Vec3};

use super::material::Material;
use super::object::{Node, RectPlane, Shape};
use super::Scene;

/// What another object occupies, as seen from a light's plane.
enum Extent {
    /// The points of an axis-aligned box in world space.
    Box(Vec3, Vec3),
    /// An infinite plane through a point with a normal.
    Plane(Vec3, Vec3),
    /// Anywhere (under motion, or not finite).
    Anywhere,
}

/// A flat one-sided emitter: a point of it and its front normal.
struct Emitter {
    leaf: usize,
    object: usize,
    point: Vec3,
    normal: Vec3,
}

/// Everything found in one walk of the scene.
#[derive(Default)]
struct Walk {
    leaves: usize,
    emitters: Vec<Emitter>,
    extents: Vec<(usize, Extent)>,
}

/// The indices into `scene.objects` of the top-level objects holding a
/// one-sided light that faces away from every other surface (each once,
/// in order). A scene with no other surface at all has none.
pub fn lights_facing_away(scene: &Scene) -> Vec<usize> {
    let mut walk = Walk::default();
    for (i, node) in scene.objects.iter().enumerate() {
        walk.node(scene, node, i, Mat4::IDENTITY, false, 0);
    }
    let mut away: Vec<usize> = walk
        .emitters
        .iter()
        .filter(|e| {
            let others = walk.extents.iter().filter(|(leaf, _)| *leaf != e.leaf);
            let mut any = false;
            for (_, extent) in others {
                any = true;
                if in_front(e, extent) {
                    return false;
                }
            }
            any
        })
        .map(|e| e.object)
        .collect();
    away.dedup();
    away
}

/// Prototype placements nested deeper than this are not followed (the
/// language's limits keep real scenes far shallower).
const MAX_DEPTH: usize = 512;

impl Walk {
    fn node(
        &mut self,
        scene: &Scene,
        node: &Node,
        object: usize,
        m: Mat4,
        flipped: bool,
        depth: usize,
    ) {
        if depth > MAX_DEPTH {
            return;
        }
        match node {
            Node::Shape { shape, material } => {
                let leaf = self.leaf();
                let one_sided = matches!(
                    scene.material(*material),
                    Material::Light {
                        two_sided: false,
                        ..
                    }
                );
                if one_sided {
                    if let Some((point, normal)) = front(shape, m, flipped) {
                        self.emitters.push(Emitter {
                            leaf,
                            object,
                            point,
                            normal,
                        });
                    }
                }
                self.extents.push((leaf, extent(shape, m)));
            }
            Node::Mesh { mesh, .. } => {
                let leaf = self.leaf();
                let e = scene
                    .meshes
                    .get(mesh.0 as usize)
                    .and_then(|m| m.bounds())
                    .map_or(Extent::Anywhere, |(lo, hi)| boxed(&corners(lo, hi), m));
                self.extents.push((leaf, e));
            }
            Node::Group(children) => {
                for c in children {
                    self.node(scene, c, object, m, flipped, depth + 1);
                }
            }
            Node::Transform { matrix, child } => {
                self.node(scene, child, object, m * *matrix, flipped, depth + 1)
            }
            Node::Motion { .. } => {
                let leaf = self.leaf();
                self.extents.push((leaf, Extent::Anywhere));
            }
            Node::Medium { boundary, .. } => {
                self.node(scene, boundary, object, m, flipped, depth + 1)
            }
            Node::Instance(id) => {
                if let Some(p) = scene.prototypes.get(id.0 as usize) {
                    self.node(scene, p, object, m, flipped, depth + 1);
                }
            }
            Node::Flip(child) => self.node(scene, child, object, m, !flipped, depth + 1),
            Node::Lamp(_) => {}
        }
    }

    fn leaf(&mut self) -> usize {
        self.leaves += 1;
        self.leaves
    }
}

/// A point and the world-space front normal of a flat shape.
fn front(shape: &Shape, m: Mat4, flipped: bool) -> Option<(Vec3, Vec3)> {
    let (point, normal) = match shape {
        Shape::Rect { plane, a, b, k } => {
            let (axis, s0, s1) = axes(*plane);
            let mut p = Vec3::ZERO;
            p[axis] = *k;
            p[s0] = a.0;
            p[s1] = b.0;
            let mut n = Vec3::ZERO;
            n[axis] = 1.0;
            (p, n)
        }
        Shape::Triangle {
            vertices: [a, b, c],
        } => (*a, (*b - *a).cross(*c - *a)),
        _ => return None,
    };
    let sign = if flipped { -1.0 } else { 1.0 };
    let n = sign
        * (Mat4::from_mat3(glam::Mat3::from_mat4(m))
            .inverse()
            .transpose())
        .transform_vector3(normal)
        .normalize_or_zero();
    let p = m.transform_point3(point);
    (n != Vec3::ZERO && p.is_finite() && n.is_finite()).then_some((p, n))
}

/// The axis normal to a rect and the two it spans.
fn axes(plane: RectPlane) -> (usize, usize, usize) {
    match plane {
        RectPlane::Xy => (2, 0, 1),
        RectPlane::Xz => (1, 0, 2),
        RectPlane::Yz => (0, 1, 2),
    }
}

/// Where a shape is in world space.
fn extent(shape: &Shape, m: Mat4) -> Extent {
    let points: Vec<Vec3> = match shape {
        Shape::Plane { point, normal } => {
            let n = (Mat4::from_mat3(glam::Mat3::from_mat4(m))
                .inverse()
                .transpose())
            .transform_vector3(*normal);
            return Extent::Plane(m.transform_point3(*point), n);
        }
        Shape::Sphere { center, radius } => corners(*center - *radius, *center + *radius),
        Shape::Rect { plane, a, b, k } => {
            let (axis, s0, s1) = axes(*plane);
            let (mut lo, mut hi) = (Vec3::ZERO, Vec3::ZERO);
            lo[axis] = *k;
            hi[axis] = *k;
            lo[s0] = a.0;
            hi[s0] = a.1;
            lo[s1] = b.0;
            hi[s1] = b.1;
            corners(lo, hi)
        }
        Shape::Cuboid { min, max } => corners(*min, *max),
        Shape::Triangle { vertices } => vertices.to_vec(),
        Shape::Revolution { curve, .. } => {
            let r = curve.points.iter().map(|p| p.x.abs()).fold(0.0, f32::max);
            let lo = curve
                .points
                .iter()
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min);
            let hi = curve
                .points
                .iter()
                .map(|p| p.y)
                .fold(f32::NEG_INFINITY, f32::max);
            corners(Vec3::new(-r, lo, -r), Vec3::new(r, hi, r))
        }
    };
    boxed(&points, m)
}

/// The eight corners of a box.
fn corners(lo: Vec3, hi: Vec3) -> Vec<Vec3> {
    (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        })
        .collect()
}

/// The world-space box around `points` placed by `m`.
fn boxed(points: &[Vec3], m: Mat4) -> Extent {
    let placed = points.iter().map(|p| m.transform_point3(*p));
    let lo = placed.clone().fold(Vec3::INFINITY, Vec3::min);
    let hi = placed.fold(Vec3::NEG_INFINITY, Vec3::max);
    if lo.is_finite() && hi.is_finite() {
        Extent::Box(lo, hi)
    } else {
        Extent::Anywhere
    }
}

/// Whether some of `extent` lies in front of the emitter's plane (by more
/// than rounding).
fn in_front(e: &Emitter, extent: &Extent) -> bool {
    let tolerance = 1e-5 * (1.0 + e.point.abs().max_element());
    match extent {
        Extent::Anywhere => true,
        Extent::Box(lo, hi) => corners(*lo, *hi)
            .iter()
            .any(|c| (*c - e.point).dot(e.normal) > tolerance),
        Extent::Plane(point, normal) => {
            let n = normal.normalize_or_zero();
            n.cross(e.normal).length() > 1e-6 || (*point - e.point).dot(e.normal) > tolerance
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::TextureId;

    /// A scene of a one-sided light rect at y = 2 facing `+y` (flipped
    /// with `flip`) and a floor box below it.
    fn lamp_over_floor(flip: bool) -> Scene {
        let mut scene = Scene::default();
        let light = scene.add_material(Material::Light {
            emit: TextureId(0),
            two_sided: false,
        });
        let grey = scene.add_material(Material::Light {
            emit: TextureId(0),
            two_sided: true,
        });
        let rect = Node::Shape {
            shape: Shape::Rect {
                plane: RectPlane::Xz,
                a: (0.0, 1.0),
                b: (0.0, 1.0),
                k: 2.0,
            },
            material: light,
        };
        scene.objects.push(if flip {
            Node::Flip(Box::new(rect))
        } else {
            rect
        });
        scene.objects.push(Node::Shape {
            shape: Shape::Cuboid {
                min: Vec3::ZERO,
                max: Vec3::ONE,
            },
            material: grey,
        });
        scene
    }

    #[test]
    fn a_light_facing_up_over_a_floor_is_found_and_a_flipped_one_is_not() {
        assert_eq!(lights_facing_away(&lamp_over_floor(false)), vec![0]);
        assert!(lights_facing_away(&lamp_over_floor(true)).is_empty());
    }

    #[test]
    fn a_turning_transform_turns_the_front() {
        let mut scene = lamp_over_floor(false);
        let rect = scene.objects.remove(0);
        scene.objects.insert(
            0,
            Node::Transform {
                matrix: Mat4::from_rotation_x(std::f32::consts::PI),
                child: Box::new(rect),
            },
        );
        // Turned half a turn about x, the rect is at y = -2 facing -y:
        // the floor box above it is behind it.
        assert_eq!(lights_facing_away(&scene), vec![0]);
    }

    #[test]
    fn anything_in_motion_counts_as_in_front() {
        let mut scene = lamp_over_floor(false);
        let floor = scene.objects.pop().expect("the floor");
        scene.objects.push(Node::Motion {
            motion: Default::default(),
            child: Box::new(floor),
        });
        assert!(lights_facing_away(&scene).is_empty());
    }
}
