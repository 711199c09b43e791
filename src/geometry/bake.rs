//! Static transforms baked into analytic primitives wherever the shape
//! survives the map exactly, with the same texture coordinates and outward
//! normals: a sphere under translation and positive uniform scale, a rect or
//! box under translation and positive per-axis scale, a triangle under any
//! affine map that keeps its orientation (positive determinant). A subtree
//! of such shapes under groups and transforms then becomes plain primitives
//! of the parent's set, one flat BVH, instead of instances each with its own
//! matrix and hierarchy. Anything else (rotated spheres and boxes, meshes,
//! motion, media, flips) keeps its instance.

use glam::{Mat4, Vec3, Vec4};

use super::primitives::Primitive;
use super::shapes::{Cuboid, Rect, Sphere, Triangle};
use crate::scene::{MaterialId, Node, Shape};

/// The analytic primitive of a bounded shape in its own space; `None` for
/// planes and surfaces of revolution, which are not primitives.
pub fn primitive(shape: &Shape) -> Option<Primitive> {
    Some(match shape {
        Shape::Sphere { center, radius } => Primitive::Sphere(Sphere {
            center: *center,
            radius: *radius,
        }),
        Shape::Rect { plane, a, b, k } => Primitive::Rect(Rect::new(*plane, *a, *b, *k)),
        Shape::Cuboid { min, max } => Primitive::Cuboid(Cuboid {
            min: min.min(*max),
            max: min.max(*max),
        }),
        Shape::Triangle { vertices } => Primitive::Triangle(Triangle { v: *vertices }),
        Shape::Plane { .. } | Shape::Revolution { .. } => return None,
    })
}

/// Appends `node`'s primitives placed by `m` to `out` and returns true when
/// every shape under it survives `m` exactly; otherwise leaves `out` as it
/// was and returns false.
pub fn flatten(m: &Mat4, node: &Node, out: &mut Vec<(Primitive, MaterialId)>) -> bool {
    let start = out.len();
    let ok = walk(m, node, out);
    if !ok {
        out.truncate(start);
    }
    ok
}

fn walk(m: &Mat4, node: &Node, out: &mut Vec<(Primitive, MaterialId)>) -> bool {
    match node {
        Node::Shape { shape, material } => {
            match primitive(shape).and_then(|p| transformed(&p, m)) {
                Some(p) => {
                    out.push((p, *material));
                    true
                }
                None => false,
            }
        }
        Node::Group(children) => children.iter().all(|c| walk(m, c, out)),
        Node::Transform { matrix, child } => walk(&(*m * *matrix), child, out),
        _ => false,
    }
}

/// The per-axis scale of an affine `m` whose linear part is a positive
/// diagonal (no rotation, shear or mirror), if it is one.
fn axis_scale(m: &Mat4) -> Option<Vec3> {
    let diagonal = Vec3::new(m.x_axis.x, m.y_axis.y, m.z_axis.z);
    let off = [
        m.x_axis.y, m.x_axis.z, m.y_axis.x, m.y_axis.z, m.z_axis.x, m.z_axis.y,
    ];
    (off.iter().all(|&v| v == 0.0) && diagonal.cmpgt(Vec3::ZERO).all()).then_some(diagonal)
}

/// `p` placed by `m`, when the result is exactly the same kind of shape.
pub fn transformed(p: &Primitive, m: &Mat4) -> Option<Primitive> {
    if m.row(3) != Vec4::W || !m.is_finite() {
        return None;
    }
    let t = m.w_axis.truncate();
    match p {
        Primitive::Sphere(s) => {
            let scale = axis_scale(m)?;
            (scale.x == scale.y && scale.y == scale.z).then(|| {
                Primitive::Sphere(Sphere {
                    center: scale * s.center + t,
                    radius: scale.x * s.radius,
                })
            })
        }
        Primitive::Rect(r) => {
            let scale = axis_scale(m)?;
            let map = |axis: u8, v: f32| scale[axis as usize] * v + t[axis as usize];
            let span = |axis: u8, (lo, hi): (f32, f32)| (map(axis, lo), map(axis, hi));
            Some(Primitive::Rect(Rect {
                axis: r.axis,
                span: r.span,
                a: span(r.span[0], r.a),
                b: span(r.span[1], r.b),
                k: map(r.axis, r.k),
            }))
        }
        Primitive::Cuboid(c) => {
            let scale = axis_scale(m)?;
            Some(Primitive::Cuboid(Cuboid {
                min: scale * c.min + t,
                max: scale * c.max + t,
            }))
        }
        Primitive::Triangle(tri) => (m.determinant() > 0.0).then(|| {
            Primitive::Triangle(Triangle {
                v: tri.v.map(|v| m.transform_point3(v)),
            })
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use crate::scene::object::RectPlane;

    fn shapes() -> [Primitive; 4] {
        [
            Primitive::Sphere(Sphere {
                center: Vec3::new(0.5, 0.2, -0.3),
                radius: 0.7,
            }),
            Primitive::Rect(Rect::new(RectPlane::Xz, (-1.0, 1.0), (-0.5, 2.0), 0.25)),
            Primitive::Cuboid(Cuboid {
                min: Vec3::new(-0.5, -1.0, -0.2),
                max: Vec3::new(0.4, 0.3, 0.9),
            }),
            Primitive::Triangle(Triangle {
                v: [
                    Vec3::new(-1.0, -0.5, 0.1),
                    Vec3::new(1.2, -0.4, 0.0),
                    Vec3::new(0.1, 1.0, -0.2),
                ],
            }),
        ]
    }

    /// The baked shape hit by a world ray must match the original hit by the
    /// same ray taken into object space (what an instance does): same
    /// distance, world point, outward normal direction and uv.
    fn agrees(p: &Primitive, m: &Mat4) {
        let baked = transformed(p, m).expect("survives");
        let inv = m.inverse();
        let (mut hits, mut flips) = (0, 0);
        for i in 0..400 {
            let a = i as f32 * 0.618_034;
            // Aim at a point of the shape's own box, so most rays hit.
            let b = p.bounds();
            let f = 0.5 + 0.3 * Vec3::new(a.sin(), (1.7 * a).cos(), (2.3 * a).sin());
            let target = m.transform_point3(b.min + f * b.extent());
            let origin = target + 6.0 * Vec3::new((3.1 * a).cos(), (0.7 * a).sin(), a.cos());
            let ray = Ray::new(origin, (target - origin).normalize(), 0.0);
            let local = Ray::new(
                inv.transform_point3(ray.origin),
                inv.transform_vector3(ray.dir),
                0.0,
            );
            let (want, got) = (
                p.intersect(&local, 1e-3, f32::INFINITY),
                baked.intersect(&ray, 1e-3, f32::INFINITY),
            );
            // Grazing rays may flip between hit and miss by rounding.
            if want.is_some() != got.is_some() {
                flips += 1;
                continue;
            }
            let (Some(w), Some(g)) = (want, got) else {
                continue;
            };
            hits += 1;
            let normal = inv.transpose().transform_vector3(w.normal).normalize();
            assert!(
                (w.t - g.t).abs() < 1e-4 * w.t,
                "{p:?}: t {} vs {}",
                w.t,
                g.t
            );
            let gap = m.transform_point3(w.point).distance(g.point);
            assert!(
                gap < 1e-4 * (w.t + g.point.length()),
                "{p:?}: points {gap} apart"
            );
            assert!(normal.dot(g.normal.normalize()) > 0.9999, "{p:?}: normal");
            // u wraps at a sphere's seam and means nothing at its poles.
            let (wuv, guv) = (w.uv.get(), g.uv.get());
            let du = (wuv.x - guv.x).abs();
            let pole = wuv.y < 1e-2 || wuv.y > 1.0 - 1e-2;
            assert!(
                pole || ((wuv.y - guv.y).abs() < 1e-4 && du.min(1.0 - du) < 1e-4),
                "{p:?}: uv {wuv} vs {guv}"
            );
        }
        assert!(hits > 100, "{p:?}: only {hits} hits");
        assert!(flips <= 2, "{p:?}: {flips} rays hit one and miss the other");
    }

    #[test]
    fn shapes_that_survive_a_map_hit_as_their_instances_do() {
        let shift = Mat4::from_translation(Vec3::new(3.0, -2.0, 7.5));
        let uniform = shift * Mat4::from_scale(Vec3::splat(2.5));
        let axes = shift * Mat4::from_scale(Vec3::new(0.5, 2.0, 3.0));
        let affine =
            shift * Mat4::from_rotation_y(0.4) * Mat4::from_scale(Vec3::new(1.0, 2.0, 0.5));
        let [sphere, rect, cuboid, triangle] = shapes();
        for m in [shift, uniform] {
            agrees(&sphere, &m);
        }
        for m in [shift, uniform, axes] {
            agrees(&rect, &m);
            agrees(&cuboid, &m);
        }
        for m in [shift, uniform, axes, affine] {
            agrees(&triangle, &m);
        }
    }

    #[test]
    fn shapes_that_would_change_keep_their_instance() {
        let rotate = Mat4::from_rotation_y(0.3);
        let stretch = Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0));
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let [sphere, rect, cuboid, triangle] = shapes();
        // A rotated sphere would move its uv seam; a stretched one is an ellipsoid.
        assert!(transformed(&sphere, &rotate).is_none());
        assert!(transformed(&sphere, &stretch).is_none());
        assert!(transformed(&rect, &rotate).is_none());
        assert!(transformed(&cuboid, &rotate).is_none());
        assert!(transformed(&cuboid, &mirror).is_none());
        // A mirrored triangle would turn its front face to the back.
        assert!(transformed(&triangle, &mirror).is_none());
        let mut projective = Mat4::IDENTITY;
        projective.x_axis.w = 0.1;
        assert!(transformed(&triangle, &projective).is_none());
    }

    #[test]
    fn a_group_bakes_whole_or_not_at_all() {
        let material = MaterialId(0);
        let ball = |x: f32| Node::Shape {
            shape: Shape::Sphere {
                center: Vec3::new(x, 0.0, 0.0),
                radius: 0.5,
            },
            material,
        };
        let nested = Node::Group(vec![
            ball(0.0),
            Node::Transform {
                matrix: Mat4::from_translation(Vec3::Y),
                child: Box::new(ball(1.0)),
            },
        ]);
        let m = Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0));
        let mut out = vec![(shapes()[1], material)];
        assert!(flatten(&m, &nested, &mut out));
        let centres: Vec<Vec3> = out[1..]
            .iter()
            .map(|(p, _)| match p {
                Primitive::Sphere(s) => s.center,
                other => panic!("not a sphere: {other:?}"),
            })
            .collect();
        assert_eq!(
            centres,
            [Vec3::new(10.0, 0.0, 0.0), Vec3::new(11.0, 1.0, 0.0)]
        );
        let with_mesh = Node::Group(vec![
            ball(0.0),
            Node::Mesh {
                mesh: crate::scene::MeshId(0),
                materials: vec![material],
            },
        ]);
        assert!(!flatten(&m, &with_mesh, &mut out));
        assert_eq!(out.len(), 3, "a failed bake leaves the list as it was");
    }
}
