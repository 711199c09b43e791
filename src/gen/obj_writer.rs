//! Writing a [`MeshData`] as a Wavefront OBJ file: positions, vertex
//! normals when present, and triangles, with five decimals for positions and four for normals.

use std::fmt::Write;

use crate::scene::MeshData;

/// The OBJ text of `mesh`, headed by a `#` comment line per entry of `header`.
pub fn obj_text(mesh: &MeshData, header: &[&str]) -> String {
    let mut out = String::with_capacity(mesh.positions.len() * 64 + mesh.triangles.len() * 32);
    for line in header {
        let _ = writeln!(out, "# {line}");
    }
    for p in &mesh.positions {
        let _ = writeln!(out, "v {:.5} {:.5} {:.5}", p.x, p.y, p.z);
    }
    for n in &mesh.normals {
        let _ = writeln!(out, "vn {:.4} {:.4} {:.4}", n.x, n.y, n.z);
    }
    let with_normals = mesh.normals.len() == mesh.positions.len();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i + 1);
        let _ = if with_normals {
            writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")
        } else {
            writeln!(out, "f {a} {b} {c}")
        };
    }
    out
}
