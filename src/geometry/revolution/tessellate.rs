//! Mesh mode: the surface as a triangle grid, `resolution` steps along the
//! curve and around the axis, with normals from the exact curve derivative.

use std::f64::consts::TAU;

use glam::{DVec2, Vec2, Vec3};

use super::profile::Profile;
use crate::scene::{Bezier, MeshData};

/// The surface as a triangle mesh with `resolution` segments along the curve
/// and around the axis, uv = (angle / 2π, curve parameter).
///
/// The seam column is duplicated (u = 0 and u = 1) with bit-identical
/// positions, rings on the axis collapse to one point, and triangles that
/// collapse there are dropped, so the mesh is watertight and has no
/// degenerate triangles. Each triangle winds so that its geometric normal
/// agrees with the vertex normals.
pub fn tessellate(curve: &Bezier, resolution: u32) -> MeshData {
    let profile = Profile::new(curve);
    let n = resolution.max(1) as usize;
    let m = resolution.max(3) as usize;
    let ring: Vec<DVec2> = (0..=m)
        .map(|j| {
            let a = TAU * (j % m) as f64 / m as f64;
            DVec2::new(a.cos(), a.sin())
        })
        .collect();

    let mut mesh = MeshData::default();
    for i in 0..=n {
        let s = i as f64 / n as f64;
        let p = profile.eval(s).0;
        let r = p.x.abs();
        for (j, e) in ring.iter().enumerate() {
            let pos = if r == 0.0 {
                Vec3::new(0.0, p.y as f32, 0.0)
            } else {
                Vec3::new((r * e.x) as f32, p.y as f32, (r * e.y) as f32)
            };
            let (normal, _) = profile.frame(s, *e);
            mesh.positions.push(pos);
            mesh.normals.push(normal.as_vec3());
            mesh.uvs.push(Vec2::new(j as f32 / m as f32, s as f32));
        }
    }

    let index = |i: usize, j: usize| (i * (m + 1) + j) as u32;
    for i in 0..n {
        for j in 0..m {
            let quad = [
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            ];
            for tri in [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]] {
                push_oriented(&mut mesh, tri);
            }
        }
    }
    mesh
}

/// Adds `tri` unless two of its corners coincide, flipped if needed so its
/// geometric normal agrees with its vertex normals.
fn push_oriented(mesh: &mut MeshData, tri: [u32; 3]) {
    let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
    if a == b || b == c || a == c {
        return;
    }
    let geometric = (b - a).cross(c - a);
    let shading: Vec3 = tri.iter().map(|&i| mesh.normals[i as usize]).sum();
    if geometric.dot(shading) < 0.0 {
        mesh.triangles.push([tri[0], tri[2], tri[1]]);
    } else {
        mesh.triangles.push(tri);
    }
}
