//! Building a mesh's BVH: time for a generated 1 000 000-triangle mesh, and
//! the bytes per triangle of the mesh arrays plus its hierarchy.
//!
//! `cargo bench --bench mesh_build` — prints the memory line once, then
//! criterion's timing of `MeshGeometry::new`.

use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use rtlang::geometry::mesh::MeshGeometry;
use rtlang::scene::{MaterialId, MeshData};

/// A wavy height field of `n × n` quads (2·n² triangles), without normals
/// or uvs: the case the ≤ 64 bytes per triangle target is stated for.
fn height_field(n: u32) -> MeshData {
    let mut positions = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            let y = 0.05 * (20.0 * x).sin() * (17.0 * z).cos();
            positions.push(Vec3::new(x, y, z));
        }
    }
    let mut triangles = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let (b, c, d) = (a + 1, a + n + 1, a + n + 2);
            triangles.push([a, c, b]);
            triangles.push([b, c, d]);
        }
    }
    MeshData {
        positions,
        triangles,
        ..MeshData::default()
    }
}

fn bench(c: &mut Criterion) {
    let data = Arc::new(height_field(708));
    let tris = data.triangles.len();
    let mesh = MeshGeometry::new(data.clone(), vec![MaterialId(0)]);
    let arrays = data.positions.len() * 12 + tris * 12;
    let total = arrays + mesh.memory();
    println!(
        "mesh of {tris} triangles: {:.1} bytes/triangle ({:.1} arrays + {:.1} BVH and leaves)",
        total as f64 / tris as f64,
        arrays as f64 / tris as f64,
        mesh.memory() as f64 / tris as f64
    );
    let mut group = c.benchmark_group("mesh_build");
    group.sample_size(10);
    group.bench_function("bvh_1m_triangles", |b| {
        b.iter(|| MeshGeometry::new(data.clone(), vec![MaterialId(0)]))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
