//! Static transforms baked into analytic primitives wherever the shape
//! survives the map exactly, with the same texture coordinates and outward
//! normals: a sphere under translation and positive uniform scale (under a
//! rotation too, keeping the rotation to turn its uv), a rect or box under
//! translation and positive per-axis scale, a triangle under any affine map
//! that keeps its orientation (positive determinant), and under any other
//! invertible affine map a rect as one parallelogram and a box as its six
//! faces; a flipped rect stays a rect facing the other way, a flipped box
//! or parallelogram becomes parallelograms with their outsides reversed. A
//! subtree of such shapes under groups, flips and transforms then becomes
//! plain primitives of the parent's set, one flat BVH, instead of instances
//! each with its own matrix and hierarchy.
//! Anything else (stretched or mirrored spheres, mirrored triangles, flipped
//! spheres and triangles, meshes, motion, media) keeps its instance here;
//! a mesh under a static transform gets its vertices placed instead
//! (`build::placed_mesh_data`).

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use super::emitter::LightId;
use super::primitive::Primitive;
use super::shapes::{Cuboid, Quad, Rect, Sphere, Triangle, TurnedSphere};
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

/// A baked primitive with its material and light id.
pub type Baked = (Primitive, MaterialId, LightId);

/// Asked for the light id of each shape baked: the shape, its material,
/// the map from its space to the one `flatten` was called in, and the
/// number of flips between them.
pub type LightOf<'a> = dyn FnMut(&Shape, MaterialId, &Mat4, u32) -> LightId + 'a;

/// Appends `node`'s primitives placed by `m` to `out` and returns true when
/// every shape under it survives `m` exactly; otherwise leaves `out` as it
/// was and returns false. `light` names each baked shape's light id.
pub fn flatten(m: &Mat4, node: &Node, out: &mut Vec<Baked>, light: &mut LightOf) -> bool {
    let start = out.len();
    let ok = walk(m, node, 0, out, light);
    if !ok {
        out.truncate(start);
    }
    ok
}

fn walk(m: &Mat4, node: &Node, flips: u32, out: &mut Vec<Baked>, light: &mut LightOf) -> bool {
    match node {
        Node::Shape { shape, material } => {
            match primitive(shape).and_then(|p| transformed(&p, m)) {
                Some(baked) => {
                    let id = light(shape, *material, m, flips);
                    out.extend(baked.into_iter().map(|p| (p, *material, id)));
                    true
                }
                None => false,
            }
        }
        Node::Group(children) => children.iter().all(|c| walk(m, c, flips, out, light)),
        Node::Transform { matrix, child } => walk(&(*m * *matrix), child, flips, out, light),
        Node::Flip(child) => {
            let start = out.len();
            if !walk(m, child, flips + 1, out, light) {
                return false;
            }
            let mut faces = Vec::with_capacity(out.len() - start);
            for (p, material, id) in out.drain(start..) {
                if let Primitive::Rect(r) = p {
                    faces.push((Primitive::Rect(r.flipped()), material, id));
                    continue;
                }
                let Some(quads) = quads(&p, &Mat4::IDENTITY) else {
                    return false;
                };
                faces.extend(quads.into_iter().filter_map(|q| match q {
                    Primitive::Quad(q) => Some((Primitive::Quad(q.flipped()), material, id)),
                    _ => None,
                }));
            }
            out.extend(faces);
            true
        }
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

/// The parallelogram on `corner` spanned by the edges, with outward side
/// `outward`, placed by the affine `m` (normals go by the inverse transpose).
fn quad(m: &Mat4, corner: Vec3, edges: [Vec3; 2], outward: Vec3) -> Option<Primitive> {
    let normals = Mat3::from_mat4(*m).inverse().transpose();
    let q = Quad::new(
        m.transform_point3(corner),
        m.transform_vector3(edges[0]),
        m.transform_vector3(edges[1]),
        normals * outward,
    )?;
    Some(Primitive::Quad(q))
}

/// `sphere`, whose uv frame is turned by `to_object`, placed by `m` when its
/// linear part is a rotation times a positive uniform scale (within the
/// rounding of a rotation matrix's entries).
fn turned(m: &Mat4, sphere: &Sphere, to_object: Quat) -> Option<Primitive> {
    let linear = Mat3::from_mat4(*m);
    let det = linear.determinant();
    if det <= 0.0 {
        return None;
    }
    let scale = det.cbrt();
    let rotation = linear * (1.0 / scale);
    let drift = rotation.transpose() * rotation - Mat3::IDENTITY;
    if drift.to_cols_array().iter().any(|e| e.abs() > 1e-5) {
        return None;
    }
    Some(Primitive::TurnedSphere(TurnedSphere {
        sphere: Sphere {
            center: m.transform_point3(sphere.center),
            radius: scale * sphere.radius,
        },
        to_object: (to_object * Quat::from_mat3(&rotation).conjugate()).normalize(),
    }))
}

/// The unit vector along `axis`.
fn unit(axis: usize) -> Vec3 {
    Vec3::AXES[axis]
}

/// `p` placed by `m`, when the result is exactly the same surface with the
/// same uv: one primitive, or a box's six faces.
pub fn transformed(p: &Primitive, m: &Mat4) -> Option<Vec<Primitive>> {
    if m.row(3) != Vec4::W || !m.is_finite() {
        return None;
    }
    let det = m.determinant();
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let t = m.w_axis.truncate();
    let scale = axis_scale(m);
    let one = |p: Primitive| Some(vec![p]);
    match p {
        Primitive::Sphere(s) => match scale {
            Some(scale) if scale.x == scale.y && scale.y == scale.z => {
                one(Primitive::Sphere(Sphere {
                    center: scale * s.center + t,
                    radius: scale.x * s.radius,
                }))
            }
            Some(_) => None,
            None => one(turned(m, s, Quat::IDENTITY)?),
        },
        Primitive::TurnedSphere(s) => one(turned(m, &s.sphere, s.to_object)?),
        Primitive::Rect(r) => match scale {
            None => quads(p, m),
            Some(scale) => {
                let map = |axis: u8, v: f32| scale[axis as usize] * v + t[axis as usize];
                let span = |axis: u8, (lo, hi): (f32, f32)| (map(axis, lo), map(axis, hi));
                one(Primitive::Rect(Rect {
                    a: span(r.span[0], r.a),
                    b: span(r.span[1], r.b),
                    k: map(r.axis, r.k),
                    ..*r
                }))
            }
        },
        Primitive::Cuboid(c) => match scale {
            Some(scale) => one(Primitive::Cuboid(Cuboid {
                min: scale * c.min + t,
                max: scale * c.max + t,
            })),
            None => quads(p, m),
        },
        Primitive::Quad(_) => quads(p, m),
        Primitive::Triangle(tri) => (det > 0.0).then(|| {
            vec![Primitive::Triangle(Triangle {
                v: tri.v.map(|v| m.transform_point3(v)),
            })]
        }),
    }
}

/// A rect, box or parallelogram placed by the invertible affine `m` as
/// parallelograms with the same uv and outward sides: one, or a box's six
/// faces. `None` for other shapes and degenerate ones.
fn quads(p: &Primitive, m: &Mat4) -> Option<Vec<Primitive>> {
    let one = |p: Primitive| Some(vec![p]);
    match p {
        Primitive::Rect(r) => {
            let [i, j] = r.span.map(usize::from);
            let mut corner = Vec3::ZERO;
            corner[r.axis as usize] = r.k;
            corner[i] = r.a.0;
            corner[j] = r.b.0;
            let edges = [unit(i) * (r.a.1 - r.a.0), unit(j) * (r.b.1 - r.b.0)];
            one(quad(m, corner, edges, r.outward() * unit(r.axis as usize))?)
        }
        // Face `axis` of a cuboid has uv along the next two axes (cyclic).
        Primitive::Cuboid(c) => {
            let ext = c.max - c.min;
            let mut faces = Vec::with_capacity(6);
            for axis in 0..3 {
                let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
                let edges = [unit(i) * ext[i], unit(j) * ext[j]];
                for (k, sign) in [(c.min[axis], -1.0), (c.max[axis], 1.0)] {
                    let mut corner = c.min;
                    corner[axis] = k;
                    faces.push(quad(m, corner, edges, sign * unit(axis))?);
                }
            }
            Some(faces)
        }
        Primitive::Quad(q) => one(quad(m, q.corner, [q.edge_u, q.edge_v], q.normal)?),
        _ => None,
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
        let nearest = |ray: &Ray| {
            baked
                .iter()
                .filter_map(|b| b.intersect(ray, 1e-3, f32::INFINITY))
                .min_by(|a, b| a.t.total_cmp(&b.t))
        };
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
            let (want, got) = (p.intersect(&local, 1e-3, f32::INFINITY), nearest(&ray));
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
        let spin = uniform * Mat4::from_euler(glam::EulerRot::XYZ, 0.3, -1.2, 0.4);
        for m in [shift, uniform, spin] {
            agrees(&sphere, &m);
        }
        // A turned sphere turns again.
        let once = transformed(&sphere, &spin).expect("a turned sphere");
        agrees(&once[0], &Mat4::from_rotation_y(0.7));
        let rotate = shift * Mat4::from_rotation_y(0.3);
        let mirror = shift * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        for m in [shift, uniform, axes, affine, rotate, mirror] {
            agrees(&rect, &m);
            agrees(&cuboid, &m);
        }
        for m in [shift, uniform, axes, affine] {
            agrees(&triangle, &m);
        }
        // A baked parallelogram bakes again under a second map.
        let once = transformed(&rect, &rotate).expect("a quad");
        agrees(&once[0], &affine);
    }

    #[test]
    fn turned_rects_and_boxes_become_parallelograms() {
        let turn = Mat4::from_rotation_z(0.5);
        let [_, rect, cuboid, _] = shapes();
        let one = transformed(&rect, &turn).expect("a quad");
        assert!(matches!(one[..], [Primitive::Quad(_)]));
        let faces = transformed(&cuboid, &turn).expect("six quads");
        assert_eq!(faces.len(), 6);
        // Each face's outward normal points away from the box's centre.
        let centre = turn.transform_point3(cuboid.bounds().centroid());
        for f in &faces {
            let Primitive::Quad(q) = f else {
                panic!("not a quad: {f:?}")
            };
            let middle = q.corner + 0.5 * (q.edge_u + q.edge_v);
            assert!((middle - centre).dot(q.normal) > 0.0, "{q:?}");
        }
        // Axis-aligned maps keep the cheaper axis-aligned shapes.
        let shift = Mat4::from_translation(Vec3::ONE);
        assert!(matches!(
            transformed(&cuboid, &shift).as_deref(),
            Some([Primitive::Cuboid(_)])
        ));
    }

    #[test]
    fn shapes_that_would_change_keep_their_instance() {
        let rotate = Mat4::from_rotation_y(0.3);
        let stretch = Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0));
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let [sphere, rect, cuboid, triangle] = shapes();
        // A stretched or sheared sphere is an ellipsoid; a mirrored one
        // would need its uv mirrored.
        let shear = Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        for m in [stretch, rotate * stretch, shear, mirror, rotate * mirror] {
            assert!(transformed(&sphere, &m).is_none(), "{m}");
        }
        assert!(matches!(
            transformed(&sphere, &rotate).as_deref(),
            Some([Primitive::TurnedSphere(_)])
        ));
        // A singular map flattens every shape.
        let flat = Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
        for p in [sphere, rect, cuboid, triangle] {
            assert!(transformed(&p, &flat).is_none(), "{p:?}");
        }
        // A mirrored triangle would turn its front face to the back.
        assert!(transformed(&triangle, &mirror).is_none());
        let mut projective = Mat4::IDENTITY;
        projective.x_axis.w = 0.1;
        assert!(transformed(&triangle, &projective).is_none());
    }

    #[test]
    fn a_flipped_rect_faces_the_other_way_with_the_same_uv() {
        let [sphere, rect, _, _] = shapes();
        let material = MaterialId(3);
        let shape = |p| match p {
            Primitive::Rect(_) => Shape::Rect {
                plane: RectPlane::Xz,
                a: (-1.0, 1.0),
                b: (-0.5, 2.0),
                k: 0.25,
            },
            _ => Shape::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
        };
        let flip = |p| {
            Node::Flip(Box::new(Node::Shape {
                shape: shape(p),
                material,
            }))
        };
        let mut out = Vec::new();
        // The light id is asked once per shape, with the flips around it.
        let mut asked = Vec::new();
        let mut light = |_: &Shape, _, _: &Mat4, flips| {
            asked.push(flips);
            LightId::new(7)
        };
        // Flipped as it stands: a rect facing down. Turned by a quarter
        // about x first: a parallelogram facing the other way (+z, not −z).
        let turn = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
        let turned = Node::Transform {
            matrix: turn,
            child: Box::new(flip(rect)),
        };
        assert!(flatten(&Mat4::IDENTITY, &flip(rect), &mut out, &mut light));
        assert!(flatten(&Mat4::IDENTITY, &turned, &mut out, &mut light));
        let [(Primitive::Rect(r), m, id), (Primitive::Quad(q), _, _)] = out[..] else {
            panic!("not a rect and a quad: {out:?}")
        };
        assert!(r.reversed);
        assert_eq!((m, id), (material, LightId::new(7)));
        let down = Ray::new(Vec3::new(0.5, 3.0, 1.0), -Vec3::Y, 0.0);
        let want = rect.intersect(&down, 0.0, f32::INFINITY).expect("hits");
        let got = r.intersect(&down, 0.0, f32::INFINITY).expect("hits");
        assert_eq!(
            (want.t, want.point, want.uv.get()),
            (got.t, got.point, got.uv.get())
        );
        assert_eq!((want.normal, got.normal), (Vec3::Y, -Vec3::Y));
        assert!((q.normal - turn.transform_vector3(-Vec3::Y)).length() < 1e-6);
        let back = Ray::new(
            turn.transform_point3(down.origin),
            turn.transform_vector3(down.dir),
            0.0,
        );
        let got = q.intersect(&back, 0.0, f32::INFINITY).expect("hits");
        assert!((want.t - got.t).abs() < 1e-5);
        assert!((want.uv.get() - got.uv.get()).abs().max_element() < 1e-6);
        // A flipped sphere would need its uv mirrored: it keeps its instance.
        assert!(!flatten(
            &Mat4::IDENTITY,
            &flip(sphere),
            &mut out,
            &mut light
        ));
        assert_eq!(out.len(), 2);
        assert_eq!(asked, [1, 1, 1]);
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
        let mut out = vec![(shapes()[1], material, LightId::NONE)];
        let mut none = |_: &Shape, _, _: &Mat4, _| LightId::NONE;
        assert!(flatten(&m, &nested, &mut out, &mut none));
        let centres: Vec<Vec3> = out[1..]
            .iter()
            .map(|(p, _, _)| match p {
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
        assert!(!flatten(&m, &with_mesh, &mut out, &mut none));
        assert_eq!(out.len(), 3, "a failed bake leaves the list as it was");
    }
}
