//! Meshes and instances through the scene builder: rays leaving a mesh far
//! from the origin, static transforms with normals, and one prototype placed
//! many times. Watertightness at shared edges and vertices is
//! `geometry_watertight.rs`.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use rtlang::geometry::{Ray, World};
use rtlang::sampling::Rng;
use rtlang::scene::{Material, MaterialId, MeshData, Node, Scene, Shape, Texture};

/// A closed octahedron subdivided `levels` times, vertices pushed to the
/// unit sphere, scaled by `r` and moved to `c`.
fn ball(levels: u32, c: Vec3, r: f32) -> MeshData {
    let mut positions = vec![
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ];
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..levels {
        let mut mids = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) / 2.0).normalize());
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in triangles {
            let (ab, bc, ca) = (
                mid(a, b, &mut positions),
                mid(b, c, &mut positions),
                mid(c, a, &mut positions),
            );
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        triangles = next;
    }
    MeshData {
        positions: positions.iter().map(|p| c + *p * r).collect(),
        triangles,
        ..MeshData::default()
    }
}

fn mesh_scene(mesh: MeshData) -> (Scene, Arc<MeshData>) {
    let mut s = Scene::default();
    let t = s.add_texture(Texture::Solid(Vec3::ONE));
    let m = s.add_material(Material::Lambertian { albedo: t });
    let mesh = Arc::new(mesh);
    let id = s.add_mesh(mesh.clone());
    s.objects = vec![Node::Mesh {
        mesh: id,
        materials: vec![m],
    }];
    (s, mesh)
}

#[test]
fn rays_leaving_a_mesh_far_from_the_origin_do_not_rehit_it() {
    let center = Vec3::new(1e5, -1e5, 1e5);
    let (scene, _) = mesh_scene(ball(2, center, 10.0));
    let world = World::build_in(&scene, Vec3::ZERO).expect("builds");
    let mut rng = Rng::for_sample(2, 0, 0, 0);
    for _ in 0..2000 {
        let origin = center + rng.unit_vector() * 40.0;
        let ray = Ray::new(origin, center + rng.in_unit_ball() * 5.0 - origin, 0.0);
        let hit = world
            .intersect(&ray, 0.0, f32::INFINITY)
            .expect("aimed at the mesh");
        // Leave on the outside, in a direction away from the (convex) mesh.
        let mut d = rng.unit_vector();
        if d.dot(hit.geo_normal) < 0.0 {
            d = -d;
        }
        let leave = Ray::new(hit.spawn_origin(d), d, 0.0);
        if let Some(h) = world.intersect(&leave, 0.0, f32::INFINITY) {
            panic!("re-hit at t = {} leaving {}", h.t, hit.point);
        }
    }
}

#[test]
fn transforms_place_shapes_and_normals_and_instances_share_geometry() {
    let mut s = Scene::default();
    let t = s.add_texture(Texture::Solid(Vec3::ONE));
    let m = s.add_material(Material::Lambertian { albedo: t });
    let proto = s.add_prototype(Node::Shape {
        shape: Shape::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        material: m,
    });
    // Non-uniform scale (an ellipsoid 2 wide in x), nested in a translation.
    s.objects = (0..1000)
        .map(|i| Node::Transform {
            matrix: Mat4::from_translation(Vec3::new(0.0, 0.0, -10.0 * i as f32)),
            child: Box::new(Node::Transform {
                matrix: Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)),
                child: Box::new(Node::Instance(proto)),
            }),
        })
        .collect();
    let world = World::build_in(&s, Vec3::ZERO).expect("builds");
    let h = world
        .intersect(
            &Ray::new(Vec3::new(10.0, 0.0, -5000.0), Vec3::NEG_X, 0.0),
            0.0,
            f32::INFINITY,
        )
        .expect("hits the ellipsoid at z = -5000");
    assert!(
        (h.point - Vec3::new(2.0, 0.0, -5000.0)).length() < 1e-3,
        "{}",
        h.point
    );
    assert!((h.normal - Vec3::X).length() < 1e-4);
    // On the ellipsoid (x/2)² + y² = 1 at 45° the normal is not the radius.
    let p = Vec3::new(2.0 * 0.6, 0.8, -20.0);
    let h = world
        .intersect(
            &Ray::new(p + Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y, 0.0),
            0.0,
            f32::INFINITY,
        )
        .expect("hits from above");
    let expected = Vec3::new(0.6 / 2.0, 0.8, 0.0).normalize();
    assert!(
        (h.normal - expected).length() < 1e-3,
        "{} vs {expected}",
        h.normal
    );
    assert_eq!(h.material, MaterialId(0));
}
