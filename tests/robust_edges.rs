//! Rays along and across the edges of rectangles and boxes. For every rect
//! orientation: rays in the rect's plane or parallel to it never hit; a ray
//! crossing the plane 1 ulp inside an edge hits and 1 ulp outside misses
//! (exactly, with axis-aligned rays), and obliquely at 1e-5 inside or
//! outside. The same through a rotated, non-uniformly scaled, translated
//! rect. Rays along a box's edges and through its corners may hit or miss,
//! but every hit is finite, lies on the box where the ray is at `t`, and has
//! the unit normal of a face through that point.

use glam::{Mat4, Vec2, Vec3};
use rtlang::geometry::shapes::{Cuboid, Rect, ShapeHit};
use rtlang::geometry::{Hit, Ray, World};
use rtlang::scene::object::RectPlane;
use rtlang::scene::{Material, Node, Scene, Shape, Texture};

const PLANES: [RectPlane; 3] = [RectPlane::Xy, RectPlane::Xz, RectPlane::Yz];
const A: (f32, f32) = (-1.0, 2.0);
const B: (f32, f32) = (0.5, 3.0);
const K: f32 = 0.75;

/// A point in a rect's frame: `u`, `v` along its two spanned axes, `w` along
/// its normal axis.
fn at(r: &Rect, u: f32, v: f32, w: f32) -> Vec3 {
    let mut p = Vec3::ZERO;
    p[r.span[0] as usize] = u;
    p[r.span[1] as usize] = v;
    p[r.axis as usize] = w;
    p
}

/// One edge of a rect: which spanned coordinate is fixed (0 for u, 1 for
/// v), its value, the interval of the other coordinate, and the sign of the
/// step from the edge into the rect.
struct Edge {
    fixed: usize,
    value: f32,
    along: (f32, f32),
    inward: f32,
}

fn edges() -> [Edge; 4] {
    [
        Edge {
            fixed: 0,
            value: A.0,
            along: B,
            inward: 1.0,
        },
        Edge {
            fixed: 0,
            value: A.1,
            along: B,
            inward: -1.0,
        },
        Edge {
            fixed: 1,
            value: B.0,
            along: A,
            inward: 1.0,
        },
        Edge {
            fixed: 1,
            value: B.1,
            along: A,
            inward: -1.0,
        },
    ]
}

impl Edge {
    /// The point of the rect's frame at `across` on the fixed coordinate and
    /// `s` on the other, at height `w`.
    fn point(&self, r: &Rect, across: f32, s: f32, w: f32) -> Vec3 {
        if self.fixed == 0 {
            at(r, across, s, w)
        } else {
            at(r, s, across, w)
        }
    }

    /// The fixed coordinate one float step inside (`+1`) or outside (`-1`).
    fn ulp_step(&self, side: f32) -> f32 {
        if side * self.inward > 0.0 {
            self.value.next_up()
        } else {
            self.value.next_down()
        }
    }
}

fn rect(plane: RectPlane) -> Rect {
    Rect::new(plane, A, B, K)
}

/// Asserts that a rect hit is finite, on the plane, with the +axis normal
/// and uv in [0, 1].
fn assert_sane_rect_hit(r: &Rect, h: &ShapeHit, what: &str) {
    assert!(h.t.is_finite() && h.t > 0.0, "{what}: t {}", h.t);
    assert!(h.point.is_finite(), "{what}: point {}", h.point);
    assert_eq!(h.point[r.axis as usize], K, "{what}: off the plane");
    assert_eq!(h.normal, at(r, 0.0, 0.0, 1.0), "{what}: normal");
    let uv = h.uv.get();
    assert!(
        uv.is_finite() && uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all(),
        "{what}: uv {uv}"
    );
}

#[test]
fn rays_in_or_parallel_to_a_rect_plane_never_hit() {
    let mut cases = 0;
    for plane in PLANES {
        let r = rect(plane);
        for e in edges() {
            let mid = 0.5 * (e.along.0 + e.along.1);
            let across = [
                e.value,
                e.ulp_step(1.0),
                e.ulp_step(-1.0),
                e.value + e.inward,
                e.value - e.inward,
            ];
            let heights = [K, K.next_up(), K.next_down(), K + 0.5, K - 0.5];
            // Along the edge both ways, diagonally and across it, all in
            // directions with no component along the rect's normal.
            let dirs = [
                e.point(&r, 0.0, 1.0, 0.0),
                e.point(&r, 0.0, -1.0, 0.0),
                e.point(&r, 1.0, 1.0, 0.0),
                e.point(&r, -1.0, 0.3, 0.0),
                e.point(&r, e.inward, 0.0, 0.0),
            ];
            for c in across {
                for w in heights {
                    for s in [e.along.0 - 1.0, mid, e.along.1 + 1.0] {
                        for d in dirs {
                            let ray = Ray::new(e.point(&r, c, s, w), d, 0.0);
                            let hit = r.intersect(&ray, 0.0, f32::INFINITY);
                            assert!(hit.is_none(), "{plane:?} {ray:?} hit {hit:?}");
                            cases += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!(cases, 3 * 4 * 5 * 5 * 3 * 5);
}

#[test]
fn axis_rays_hit_on_and_one_ulp_inside_an_edge_and_miss_one_ulp_outside() {
    for plane in PLANES {
        let r = rect(plane);
        for e in edges() {
            let len = e.along.1 - e.along.0;
            for f in [0.25, 0.5, 0.75] {
                let s = e.along.0 + f * len;
                for (across, hits) in [
                    (e.value, true),
                    (e.ulp_step(1.0), true),
                    (e.ulp_step(-1.0), false),
                ] {
                    for side in [1.0f32, -1.0] {
                        let origin = e.point(&r, across, s, K + 2.0 * side);
                        let ray = Ray::new(origin, at(&r, 0.0, 0.0, -side), 0.0);
                        let what = format!("{plane:?} {ray:?}");
                        match r.intersect(&ray, 0.0, f32::INFINITY) {
                            Some(h) => {
                                assert!(hits, "{what}: hit outside the edge");
                                assert_sane_rect_hit(&r, &h, &what);
                                assert_eq!(h.t, 2.0, "{what}");
                                assert_eq!(h.point, e.point(&r, across, s, K), "{what}");
                            }
                            None => assert!(!hits, "{what}: missed inside the edge"),
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn oblique_rays_hit_just_inside_an_edge_and_miss_just_outside() {
    const MARGIN: f32 = 1e-5;
    for plane in PLANES {
        let r = rect(plane);
        for e in edges() {
            for f in [0.1, 0.5, 0.9] {
                let s = e.along.0 + f * (e.along.1 - e.along.0);
                for (side, hits) in [(1.0f32, true), (-1.0, false)] {
                    let across = e.value + side * e.inward * MARGIN;
                    let target = e.point(&r, across, s, K);
                    for d in [
                        e.point(&r, 0.7, 0.2, -1.0),
                        e.point(&r, -0.4, 0.9, 1.0),
                        e.point(&r, 3.0, -2.0, -0.05),
                        e.point(&r, e.inward, 0.0, 1.0),
                    ] {
                        let ray = Ray::new(target - 2.0 * d, d, 0.0);
                        let what = format!("{plane:?} {ray:?}");
                        match r.intersect(&ray, 0.0, f32::INFINITY) {
                            Some(h) => {
                                assert!(hits, "{what}: hit outside the edge");
                                assert_sane_rect_hit(&r, &h, &what);
                                assert!((h.t - 2.0).abs() < 1e-5, "{what}: t {}", h.t);
                                assert!((h.point - target).abs().max_element() < 5e-6, "{what}");
                            }
                            None => assert!(!hits, "{what}: missed inside the edge"),
                        }
                    }
                }
            }
        }
    }
}

/// A world holding `shape` (white diffuse) under `matrix`.
fn world_of(shape: Shape, matrix: Mat4) -> World {
    let mut s = Scene::default();
    let white = s.add_texture(Texture::Solid(Vec3::ONE));
    let material = s.add_material(Material::Lambertian { albedo: white });
    s.objects = vec![Node::Transform {
        matrix,
        child: Box::new(Node::Shape { shape, material }),
    }];
    World::build_in(&s, Vec3::ZERO).expect("builds")
}

/// A rotation about a skew axis, a non-uniform scale and a translation.
fn placement() -> Mat4 {
    Mat4::from_translation(Vec3::new(0.3, -20.0, 7.0))
        * Mat4::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7)
        * Mat4::from_scale(Vec3::new(2.0, 0.5, 1.5))
}

/// Asserts that a hit record is finite, with unit normals facing the ray,
/// at the ray's point for its `t`.
fn assert_sane_hit(ray: &Ray, h: &Hit, what: &str) {
    assert!(h.t.is_finite() && h.t > 0.0, "{what}: t {}", h.t);
    assert!(
        h.point.is_finite() && h.uv.get().is_finite(),
        "{what}: {h:?}"
    );
    for n in [h.geo_normal, h.normal] {
        assert!((n.length() - 1.0).abs() < 1e-5, "{what}: normal {n}");
    }
    assert!(
        h.geo_normal.dot(ray.dir) <= 1e-4 * ray.dir.length(),
        "{what}: the normal faces away"
    );
    let scale = 1.0 + ray.origin.abs().max_element() + h.t * ray.dir.length();
    assert!(
        (h.point - ray.at(h.t)).length() <= 1e-5 * scale,
        "{what}: point {} but the ray is at {} at t {}",
        h.point,
        ray.at(h.t),
        h.t
    );
}

#[test]
fn a_rotated_scaled_rect_keeps_its_edges() {
    let m = placement();
    let normal_matrix = m.inverse().transpose();
    let (mut grazing_hits, mut grazing) = (0, 0);
    for plane in PLANES {
        let r = rect(plane);
        let world = world_of(
            Shape::Rect {
                plane,
                a: A,
                b: B,
                k: K,
            },
            m,
        );
        let n = normal_matrix
            .transform_vector3(at(&r, 0.0, 0.0, 1.0))
            .normalize();
        let size = (m.transform_point3(at(&r, A.1, B.1, K))
            - m.transform_point3(at(&r, A.0, B.0, K)))
        .length();
        for e in edges() {
            let dir_along = m.transform_vector3(e.point(&r, 0.0, 1.0, 0.0));
            let dir_diagonal = m.transform_vector3(e.point(&r, 1.0, 1.0, 0.0));
            for s in [e.along.0 - 1.0, 0.5 * (e.along.0 + e.along.1)] {
                let on_edge = m.transform_point3(e.point(&r, e.value, s, K));
                // Parallel to the plane, off it by 1e-3 of the rect's size:
                // never a hit, whatever the rounding of the transform.
                for offset in [1e-3 * size, -1e-3 * size, 0.5, -0.5] {
                    for d in [dir_along, -dir_along, dir_diagonal] {
                        let ray = Ray::new(on_edge + offset * n, d, 0.0);
                        let hit = world.intersect(&ray, 0.0, f32::INFINITY);
                        assert!(hit.is_none(), "{plane:?} {ray:?}: {hit:?}");
                    }
                }
                // In the plane, along the edge: the transform's rounding
                // decides hit or miss; a hit must still be a sane record.
                for d in [dir_along, -dir_along, dir_diagonal, -dir_diagonal] {
                    let ray = Ray::new(on_edge, d, 0.0);
                    grazing += 1;
                    if let Some(h) = world.intersect(&ray, 0.0, f32::INFINITY) {
                        grazing_hits += 1;
                        assert_sane_hit(&ray, &h, &format!("{plane:?} grazing {ray:?}"));
                    }
                }
            }
            // Crossing 1e-4 of the extent inside or outside the edge.
            for f in [0.2, 0.5, 0.8] {
                let s = e.along.0 + f * (e.along.1 - e.along.0);
                for (side, hits) in [(1.0f32, true), (-1.0, false)] {
                    let across = e.value + side * e.inward * 1e-4 * (A.1 - A.0);
                    let target = m.transform_point3(e.point(&r, across, s, K));
                    for d in [-n, n, (dir_diagonal.normalize() - n).normalize()] {
                        let ray = Ray::new(target - 3.0 * d, d, 0.0);
                        let what = format!("{plane:?} {ray:?}");
                        match world.intersect(&ray, 0.0, f32::INFINITY) {
                            Some(h) => {
                                assert!(hits, "{what}: hit outside the edge");
                                assert_sane_hit(&ray, &h, &what);
                                assert!((h.point - target).length() < 1e-4, "{what}: {h:?}");
                                assert!(h.geo_normal.dot(n).abs() > 1.0 - 1e-5, "{what}: {h:?}");
                            }
                            None => assert!(!hits, "{what}: missed inside the edge"),
                        }
                    }
                }
            }
        }
    }
    assert_eq!(grazing, 3 * 4 * 2 * 4);
    assert!(grazing_hits < grazing, "every grazing ray hit");
}

const BOX_MIN: Vec3 = Vec3::new(-1.0, -2.0, 0.5);
const BOX_MAX: Vec3 = Vec3::new(2.0, 1.0, 3.0);

/// The twelve edges of the box: (axis the edge runs along, a point of it).
fn box_edges() -> Vec<(usize, Vec3)> {
    let mut out = Vec::new();
    for axis in 0..3 {
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        for ci in [BOX_MIN[i], BOX_MAX[i]] {
            for cj in [BOX_MIN[j], BOX_MAX[j]] {
                let mut p = BOX_MIN;
                p[i] = ci;
                p[j] = cj;
                out.push((axis, p));
            }
        }
    }
    out
}

fn box_corners() -> Vec<Vec3> {
    (0..8)
        .map(|c: u32| {
            Vec3::new(
                if c & 1 == 0 { BOX_MIN.x } else { BOX_MAX.x },
                if c & 2 == 0 { BOX_MIN.y } else { BOX_MAX.y },
                if c & 4 == 0 { BOX_MIN.z } else { BOX_MAX.z },
            )
        })
        .collect()
}

/// Rays along every edge (on it and one ulp off it on either side, before,
/// inside and past the box) and through and from every corner.
fn edge_and_corner_rays() -> Vec<Ray> {
    let mut rays = Vec::new();
    let nudges = |x: f32| [x, x.next_up(), x.next_down()];
    for (axis, p) in box_edges() {
        let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
        for ci in nudges(p[i]) {
            for cj in nudges(p[j]) {
                for start in [
                    BOX_MIN[axis] - 1.0,
                    BOX_MIN[axis],
                    0.5 * (BOX_MIN[axis] + BOX_MAX[axis]),
                    BOX_MAX[axis] + 1.0,
                ] {
                    let mut o = p;
                    (o[i], o[j], o[axis]) = (ci, cj, start);
                    let mut d = Vec3::ZERO;
                    for sign in [1.0, -1.0] {
                        d[axis] = sign;
                        rays.push(Ray::new(o, d, 0.0));
                    }
                }
            }
        }
    }
    for c in box_corners() {
        for k in 0..27 {
            let d = Vec3::new(
                (k % 3) as f32 - 1.0,
                (k / 3 % 3) as f32 - 1.0,
                (k / 9) as f32 - 1.0,
            );
            if d == Vec3::ZERO {
                continue;
            }
            rays.push(Ray::new(c - 2.0 * d, d, 0.0));
            rays.push(Ray::new(c, d, 0.0));
        }
    }
    rays
}

/// Asserts that a box hit is finite, where the ray is at `t`, on a face of
/// the box whose outward normal it reports.
fn assert_sane_box_hit(ray: &Ray, h: &ShapeHit, what: &str) {
    assert!(h.t.is_finite() && h.t > 0.0, "{what}: t {}", h.t);
    assert!(
        h.point.is_finite() && h.uv.get().is_finite(),
        "{what}: {h:?}"
    );
    assert!((h.point - ray.at(h.t)).length() < 1e-5, "{what}: {h:?}");
    assert!(
        h.uv.get().cmpge(Vec2::ZERO).all() && h.uv.get().cmple(Vec2::ONE).all(),
        "{what}: {h:?}"
    );
    let axis = h.normal.abs().max_position();
    assert_eq!(h.normal.abs()[axis], 1.0, "{what}: {h:?}");
    assert_eq!(h.normal.length(), 1.0, "{what}: {h:?}");
    let face = if h.normal[axis] > 0.0 {
        BOX_MAX[axis]
    } else {
        BOX_MIN[axis]
    };
    assert_eq!(
        h.point[axis], face,
        "{what}: not on the face of its normal: {h:?}"
    );
}

#[test]
fn rays_along_box_edges_and_through_corners_give_sane_hits() {
    let c = Cuboid {
        min: BOX_MIN,
        max: BOX_MAX,
    };
    let (mut hits, mut misses) = (0, 0);
    for ray in edge_and_corner_rays() {
        match c.intersect(&ray, 0.0, f32::INFINITY) {
            Some(h) => {
                hits += 1;
                assert_sane_box_hit(&ray, &h, &format!("{ray:?}"));
            }
            None => misses += 1,
        }
    }
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}

#[test]
fn box_faces_end_exactly_at_their_edges() {
    let c = Cuboid {
        min: BOX_MIN,
        max: BOX_MAX,
    };
    // A ray perpendicular to a face, one ulp inside one of its edges, hits
    // that face at the exact distance; one ulp outside, it misses.
    for face_axis in 0..3 {
        for (edge_axis, p) in box_edges() {
            if edge_axis == face_axis {
                continue;
            }
            let across = 3 - face_axis - edge_axis;
            let mid = 0.5 * (BOX_MIN[edge_axis] + BOX_MAX[edge_axis]);
            let inward = if p[across] == BOX_MIN[across] {
                1.0
            } else {
                -1.0
            };
            for (x, hits) in [
                (
                    if inward > 0.0 {
                        p[across].next_up()
                    } else {
                        p[across].next_down()
                    },
                    true,
                ),
                (
                    if inward > 0.0 {
                        p[across].next_down()
                    } else {
                        p[across].next_up()
                    },
                    false,
                ),
            ] {
                let face = p[face_axis];
                let out = if face == BOX_MIN[face_axis] {
                    -1.0
                } else {
                    1.0
                };
                let mut o = p;
                (o[across], o[edge_axis], o[face_axis]) = (x, mid, face + 2.0 * out);
                let mut d = Vec3::ZERO;
                d[face_axis] = -out;
                let ray = Ray::new(o, d, 0.0);
                let what = format!("{ray:?}");
                match c.intersect(&ray, 0.0, f32::INFINITY) {
                    Some(h) => {
                        assert!(hits, "{what}: hit outside the edge: {h:?}");
                        assert_sane_box_hit(&ray, &h, &what);
                        assert_eq!(h.t, 2.0, "{what}");
                        assert_eq!(h.normal[face_axis], out, "{what}: {h:?}");
                    }
                    None => assert!(!hits, "{what}: missed inside the edge"),
                }
            }
        }
    }
}

#[test]
fn a_rotated_box_gives_sane_hits_at_its_edges_and_corners() {
    let m = placement();
    let world = world_of(
        Shape::Cuboid {
            min: BOX_MIN,
            max: BOX_MAX,
        },
        m,
    );
    let (mut hits, mut misses) = (0, 0);
    for local in edge_and_corner_rays() {
        let ray = Ray::new(
            m.transform_point3(local.origin),
            m.transform_vector3(local.dir),
            0.0,
        );
        match world.intersect(&ray, 0.0, f32::INFINITY) {
            Some(h) => {
                hits += 1;
                assert_sane_hit(&ray, &h, &format!("{ray:?}"));
            }
            None => misses += 1,
        }
    }
    assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
}
