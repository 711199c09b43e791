//! The generated bunny stand-in and the polygoniser behind it: closed,
//! consistently oriented meshes with unit outward normals, placed in the
//! stored bunny's frame, and identical to the committed meshes/critter.obj.

use std::collections::HashMap;

use glam::{DVec3, Vec3};
use rtlang::gen::critter::{critter, CritterOptions, FLOOR, HEIGHT};
use rtlang::gen::marching::{polygonise, Field};
use rtlang::gen::obj_writer::obj_text;
use rtlang::scene::MeshData;

/// Counts how often each directed edge occurs.
fn directed_edges(mesh: &MeshData) -> HashMap<(u32, u32), u32> {
    let mut edges = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    edges
}

/// Asserts the mesh is a closed, consistently oriented 2-manifold: every
/// directed edge occurs once and its reverse once, so every undirected edge
/// is shared by exactly two triangles.
fn assert_closed_and_oriented(mesh: &MeshData) {
    let edges = directed_edges(mesh);
    for (&(a, b), &count) in &edges {
        assert_eq!(count, 1, "directed edge {a}->{b} used {count} times");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}-{b} is a border");
    }
}

/// Signed volume by the divergence theorem; positive when faces point out.
fn signed_volume(mesh: &MeshData) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Fraction of triangles whose face normal agrees with their vertex normals.
fn agreeing_fraction(mesh: &MeshData) -> f64 {
    let agree = mesh
        .triangles
        .iter()
        .filter(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let face = (b - a).cross(c - a);
            let smooth: Vec3 = t.iter().map(|&i| mesh.normals[i as usize]).sum();
            face.dot(smooth) > 0.0
        })
        .count();
    agree as f64 / mesh.triangles.len() as f64
}

struct Sphere(f64);

impl Field for Sphere {
    fn value(&self, p: DVec3) -> f64 {
        p.length() - self.0
    }
}

#[test]
fn polygonised_sphere_is_closed_outward_and_accurate() {
    let r = 1.0;
    let mesh = polygonise(&Sphere(r), DVec3::splat(-1.3), DVec3::splat(1.3), 0.1);
    assert_closed_and_oriented(&mesh);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    let volume = signed_volume(&mesh);
    assert!(
        (volume - exact).abs() / exact < 0.02,
        "volume {volume} vs {exact}"
    );
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        assert!(
            (p.length() as f64 - r).abs() < 0.01,
            "vertex off the sphere: {p}"
        );
        assert!(
            n.dot(p.normalize()) > 0.999,
            "normal {n} at {p} is not radial"
        );
    }
}

#[test]
fn critter_is_a_closed_genus_zero_surface_with_outward_normals() {
    let mesh = critter(CritterOptions::default());
    assert!(
        (10_000..=30_000).contains(&mesh.triangles.len()),
        "{} triangles",
        mesh.triangles.len()
    );
    assert_closed_and_oriented(&mesh);
    // Euler characteristic V − E + F = 2: one closed surface without handles.
    let edges = directed_edges(&mesh).len() / 2;
    let euler = mesh.positions.len() as i64 - edges as i64 + mesh.triangles.len() as i64;
    assert_eq!(euler, 2);
    assert!(signed_volume(&mesh) > 0.0, "faces point inward");
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    for n in &mesh.normals {
        assert!((n.length() - 1.0).abs() < 1e-5, "normal {n} is not unit");
    }
    let agree = agreeing_fraction(&mesh);
    assert!(
        agree > 0.99,
        "only {agree} of faces agree with their normals"
    );
}

#[test]
fn critter_sits_in_the_stored_bunnys_frame() {
    let mesh = critter(CritterOptions::default());
    let (min, max) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(a, b), &p| (a.min(p), b.max(p)),
    );
    assert!((min.y - FLOOR).abs() < 1e-5, "lowest point {}", min.y);
    assert!(
        (max.y - min.y - HEIGHT).abs() < 1e-5,
        "height {}",
        max.y - min.y
    );
    // Facing −x like the stored bunny: the ears (top 10 %) lean to the −x side.
    let top: Vec<Vec3> = mesh
        .positions
        .iter()
        .copied()
        .filter(|p| p.y > max.y - 0.1 * HEIGHT)
        .collect();
    let mean_x = top.iter().map(|p| p.x).sum::<f32>() / top.len() as f32;
    assert!(mean_x < (min.x + max.x) * 0.5, "ears at x = {mean_x}");
}

#[test]
fn critter_is_deterministic_and_matches_the_committed_obj() {
    let a = critter(CritterOptions::default());
    let b = critter(CritterOptions::default());
    assert_eq!(a, b);
    let header = [
        "rtlang's generated stand-in for the Stanford bunny",
        "rtlang gen bunny --cell 0.45",
    ];
    let text = obj_text(&a, &header);
    assert!(text.len() < 2 << 20, "OBJ is {} bytes", text.len());
    let stored =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/meshes/critter.obj"))
            .expect("committed mesh");
    assert!(
        stored == text,
        "meshes/critter.obj differs from `rtlang gen bunny`'s output: regenerate it (docs/assets.md)"
    );
}

#[test]
fn obj_writer_writes_positions_normals_and_one_based_faces() {
    let mesh = MeshData {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: vec![Vec3::Z; 3],
        triangles: vec![[0, 1, 2]],
        ..MeshData::default()
    };
    let text = obj_text(&mesh, &["hello"]);
    let expected = "# hello\n\
        v 0.00000 0.00000 0.00000\nv 1.00000 0.00000 0.00000\nv 0.00000 1.00000 0.00000\n\
        vn 0.0000 0.0000 1.0000\nvn 0.0000 0.0000 1.0000\nvn 0.0000 0.0000 1.0000\n\
        f 1//1 2//2 3//3\n";
    assert_eq!(text, expected);
}
