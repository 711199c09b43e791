//! Mesh mode of the surface of revolution: sizes, watertightness, poles,
//! normals from the exact derivative, uv, and the error bound.

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use rtlang::geometry::revolution::{surface_distance, tessellate, tessellation_error_bound};
use rtlang::scene::{Bezier, MeshData};

fn vase() -> Bezier {
    Bezier {
        points: vec![
            Vec2::new(-2.0, 2.0),
            Vec2::new(-4.0, 0.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(-2.0, -2.0),
        ],
    }
}

/// A closed capsule-like profile that starts and ends on the axis with
/// horizontal tangents there.
fn capsule() -> Bezier {
    Bezier {
        points: vec![
            Vec2::new(0.0, -1.0),
            Vec2::new(1.3, -1.0),
            Vec2::new(1.3, 1.0),
            Vec2::new(0.0, 1.0),
        ],
    }
}

/// Edge → how many triangles use it, keyed by the bits of its endpoints
/// (so duplicated seam vertices count as the same corner).
fn edge_uses(mesh: &MeshData) -> HashMap<([u32; 3], [u32; 3]), u32> {
    let key = |i: u32| {
        mesh.positions[i as usize]
            .to_array()
            .map(|c| (c + 0.0).to_bits())
    };
    let mut uses = HashMap::new();
    for t in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (key(t[k]), key(t[(k + 1) % 3]));
            *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    uses
}

#[test]
fn vase_grid_has_the_expected_size_and_open_ends() {
    let mesh = tessellate(&vase(), 16);
    assert_eq!(mesh.positions.len(), 17 * 17);
    assert_eq!(mesh.len(), 2 * 16 * 16);
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    assert_eq!(mesh.uvs.len(), mesh.positions.len());
    let uses = edge_uses(&mesh);
    let mut open = 0;
    for ((a, b), n) in &uses {
        assert!(*n == 1 || *n == 2, "an edge used {n} times");
        if *n == 1 {
            open += 1;
            let ya = f32::from_bits(a[1]);
            let yb = f32::from_bits(b[1]);
            assert!(
                ya.abs() == 2.0 && ya == yb,
                "an open edge inside the surface"
            );
        }
    }
    assert_eq!(open, 2 * 16, "exactly the top and bottom rings are open");
}

#[test]
fn profile_touching_the_axis_gives_a_closed_mesh_without_degenerate_triangles() {
    let mesh = tessellate(&capsule(), 12);
    assert!(edge_uses(&mesh).values().all(|&n| n == 2), "not closed");
    assert_eq!(
        mesh.len(),
        2 * 12 * 12 - 2 * 12,
        "one triangle per pole quad is dropped"
    );
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        assert!((b - a).cross(c - a).length() > 1e-6);
    }
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-5);
        if p.x == 0.0 && p.z == 0.0 {
            assert!(
                (*n - Vec3::Y * p.y.signum()).length() < 1e-6,
                "pole normal {n}"
            );
        }
    }
}

#[test]
fn normals_are_perpendicular_to_the_surface_and_point_away_from_the_axis() {
    let curve = vase();
    let mesh = tessellate(&curve, 64);
    let ring = 65;
    for i in 1..64 {
        for j in [1, 9, 40] {
            let k = i * ring + j;
            let (p, n) = (mesh.positions[k], mesh.normals[k]);
            let along = mesh.positions[k + ring] - mesh.positions[k - ring];
            let around = mesh.positions[k + 1] - mesh.positions[k - 1];
            assert!(n.dot(along.normalize()).abs() < 2e-3);
            assert!(n.dot(around.normalize()).abs() < 2e-3);
            // Away from the axis wherever the wall is not horizontal.
            let radial = Vec3::new(p.x, 0.0, p.z).normalize();
            assert!(n.dot(radial) > 0.0, "inward normal at {p}");
        }
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let shading: Vec3 = t.iter().map(|&i| mesh.normals[i as usize]).sum();
        assert!((b - a).cross(c - a).dot(shading) > 0.0, "winding disagrees");
    }
}

#[test]
fn uv_is_angle_and_curve_parameter_with_a_shared_seam() {
    let mesh = tessellate(&vase(), 8);
    let ring = 9;
    for i in 0..=8 {
        let first = mesh.positions[i * ring];
        let last = mesh.positions[i * ring + 8];
        assert_eq!(first, last, "seam positions differ");
        assert_eq!(mesh.uvs[i * ring], Vec2::new(0.0, i as f32 / 8.0));
        assert_eq!(mesh.uvs[i * ring + 8], Vec2::new(1.0, i as f32 / 8.0));
        let p = mesh.positions[i * ring + 3];
        let angle = p.z.atan2(p.x) / std::f32::consts::TAU;
        assert!((angle - 3.0 / 8.0).abs() < 1e-6);
    }
}

#[test]
fn vertices_lie_on_the_surface_and_triangles_within_the_bound() {
    let curve = vase();
    for res in [8, 32] {
        let mesh = tessellate(&curve, res);
        let bound = tessellation_error_bound(&curve, res);
        for p in &mesh.positions {
            assert!(surface_distance(&curve, *p) < 1e-5);
        }
        let mut worst: f64 = 0.0;
        for t in mesh.triangles.iter().step_by(3) {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            let centroid = (a + b + c) / 3.0;
            worst = worst.max(surface_distance(&curve, centroid));
        }
        assert!(worst <= bound, "res {res}: {worst} > bound {bound}");
        assert!(
            worst > 0.1 * bound,
            "res {res}: bound {bound} is too loose ({worst})"
        );
    }
    assert!(tessellation_error_bound(&curve, 64) < tessellation_error_bound(&curve, 16) / 8.0);
}
