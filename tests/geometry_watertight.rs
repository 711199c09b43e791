//! Watertightness of the triangle test through the whole mesh path (BVH and
//! Woop–Benthin–Wald): thousands of rays fired exactly at shared vertices,
//! edge midpoints and other edge points of closed meshes (a subdivided
//! icosphere, the generated critter, a cube) all hit, no later than the
//! point they were aimed at (within the rounding of the hit distance).
//!
//! Only rays that cross the surface at the target count: a ray that merely
//! touches a silhouette vertex or edge (the adjacent faces on both sides of
//! it) enters nothing, and a miss there is not a hole. Such grazing rays are
//! what made the first version of the test fail.

use std::collections::HashMap;
use std::sync::Arc;

use glam::Vec3;
use rtlang::geometry::{Ray, World};
use rtlang::sampling::Rng;
use rtlang::scene::obj::load_obj;
use rtlang::scene::{Material, MeshData, Node, Scene, Texture};

/// The least |cos| between a counted ray and each face around its target.
const CROSSING: f32 = 1e-3;

fn icosphere(levels: u32) -> MeshData {
    let g = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mids = HashMap::new();
        let mut next = Vec::new();
        for [a, b, c] in triangles {
            let mut mid = |p: u32, q: u32| {
                *mids.entry((p.min(q), p.max(q))).or_insert_with(|| {
                    let m = (positions[p as usize] + positions[q as usize]).normalize();
                    positions.push(m);
                    positions.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        triangles = next;
    }
    MeshData {
        positions: positions
            .iter()
            .map(|p| Vec3::new(0.31, -0.27, 0.13) + *p * 1.7)
            .collect(),
        triangles,
        ..MeshData::default()
    }
}

fn cube() -> MeshData {
    let positions = (0..8)
        .map(|i| {
            Vec3::new(
                (i & 1) as f32 * 2.0 - 1.0,
                ((i >> 1) & 1) as f32 * 2.0 - 1.0,
                ((i >> 2) & 1) as f32 * 2.0 - 1.0,
            ) * 0.75
                + Vec3::new(0.1, 0.2, -0.3)
        })
        .collect();
    // Two triangles per face, counter-clockwise seen from outside.
    let triangles = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    MeshData {
        positions,
        triangles,
        ..MeshData::default()
    }
}

fn critter() -> MeshData {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/critter.obj");
    load_obj(path.as_ref()).expect("critter loads").mesh
}

fn world_of(mesh: &MeshData) -> World {
    let mut s = Scene::default();
    let t = s.add_texture(Texture::Solid(Vec3::ONE));
    let m = s.add_material(Material::Lambertian { albedo: t });
    let id = s.add_mesh(Arc::new(mesh.clone()));
    s.objects = vec![Node::Mesh {
        mesh: id,
        materials: vec![m],
    }];
    World::build_in(&s, Vec3::ZERO).expect("builds")
}

/// Points exactly on shared features, each with the faces around it: every
/// `stride`-th vertex (with its fan) and points at 1/2 and 3/4 of every
/// `stride`-th edge (with its two faces).
fn targets(mesh: &MeshData, stride: usize) -> Vec<(Vec3, Vec<usize>)> {
    let mut fans: HashMap<u32, Vec<usize>> = HashMap::new();
    let mut edges: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (f, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            fans.entry(a).or_default().push(f);
            edges.entry((a.min(b), a.max(b))).or_default().push(f);
        }
    }
    let mut fans: Vec<_> = fans.into_iter().collect();
    fans.sort_by_key(|(v, _)| *v);
    let mut edges: Vec<_> = edges.into_iter().collect();
    edges.sort_by_key(|(e, _)| *e);
    let p = |i: u32| mesh.positions[i as usize];
    let mut out: Vec<_> = fans
        .into_iter()
        .step_by(stride)
        .map(|(v, faces)| (p(v), faces))
        .collect();
    for ((a, b), faces) in edges.into_iter().step_by(stride) {
        assert_eq!(faces.len(), 2, "the mesh is closed and manifold");
        out.push(((p(a) + p(b)) * 0.5, faces.clone()));
        out.push((p(a) * 0.25 + p(b) * 0.75, faces));
    }
    out
}

/// Fires `per_target` rays from random points outside the mesh's bounding
/// sphere at every target; returns (rays that cross the surface there,
/// misses among them).
fn fire(mesh: &MeshData, stride: usize, per_target: usize, seed: u64) -> (usize, Vec<String>) {
    let world = world_of(mesh);
    let (lo, hi) = mesh.positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let (center, radius) = ((lo + hi) / 2.0, (hi - lo).length());
    let normal = |f: usize| {
        let [a, b, c] = mesh.triangles[f].map(|i| mesh.positions[i as usize]);
        (b - a).cross(c - a).normalize()
    };
    let mut rng = Rng::for_sample(seed, 0, 0, 0);
    let (mut crossing, mut misses) = (0, Vec::new());
    for (target, faces) in targets(mesh, stride) {
        for _ in 0..per_target {
            let origin = center + rng.unit_vector() * radius * 1.5;
            let dir = target - origin;
            let cosines: Vec<f32> = faces
                .iter()
                .map(|&f| normal(f).dot(dir.normalize()))
                .collect();
            let entering = cosines.iter().all(|&c| c < -CROSSING);
            let leaving = cosines.iter().all(|&c| c > CROSSING);
            if !(entering || leaving) {
                continue;
            }
            crossing += 1;
            // The hit distance of a ray at angle θ to the surface is off by
            // about the vertices' rounding over sin θ.
            let slack = 1e-6 / cosines.iter().fold(1.0f32, |m, c| m.min(c.abs()));
            let ray = Ray::new(origin, dir, 0.0);
            match world.intersect(&ray, 0.0, f32::INFINITY) {
                Some(h) if h.t <= 1.0 + slack => {}
                Some(h) => misses.push(format!("{origin} → {target}: hit only at t = {}", h.t)),
                None => misses.push(format!("{origin} → {target}: no hit")),
            }
        }
    }
    (crossing, misses)
}

/// At least `min` rays crossed the surface and none of them missed.
fn assert_no_misses((crossing, misses): (usize, Vec<String>), min: usize) {
    assert!(crossing > min, "only {crossing} crossing rays");
    assert!(
        misses.is_empty(),
        "{} misses: {:?}",
        misses.len(),
        &misses[..misses.len().min(5)]
    );
}

#[test]
fn rays_at_icosphere_vertices_and_edges_all_hit() {
    assert_no_misses(fire(&icosphere(3), 1, 4, 11), 10_000);
}

#[test]
fn rays_at_critter_vertices_and_edges_all_hit() {
    assert_no_misses(fire(&critter(), 7, 2, 12), 10_000);
}

#[test]
fn rays_at_cube_corners_and_edges_all_hit() {
    assert_no_misses(fire(&cube(), 1, 400, 13), 5_000);
}
