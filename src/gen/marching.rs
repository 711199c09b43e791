//! Polygonising an implicit surface by marching tetrahedra over the
//! Freudenthal (Kuhn) split of a regular grid: six tetrahedra per cube, all
//! sharing the cube's main diagonal, so neighbouring cubes split their
//! common face the same way and the result is a closed, consistently
//! oriented triangle mesh whenever the surface stays inside the grid.
//! Vertex normals come from the field's gradient.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::scene::MeshData;

/// A signed field: negative inside the solid, positive outside.
pub trait Field {
    fn value(&self, p: DVec3) -> f64;

    /// The outward unit normal: the normalised central-difference gradient.
    fn normal(&self, p: DVec3, h: f64) -> DVec3 {
        let d = |e: DVec3| self.value(p + e) - self.value(p - e);
        DVec3::new(d(DVec3::X * h), d(DVec3::Y * h), d(DVec3::Z * h)).normalize_or(DVec3::Y)
    }
}

/// The six tetrahedra of a cube, as corner indices (bit 0 = +x, bit 1 = +y,
/// bit 2 = +z): one per order in which the path 0 → 7 takes the three axes.
const TETRAHEDRA: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// Samples of the field on the grid points of `lo..hi` with spacing `cell`.
struct Grid {
    lo: DVec3,
    cell: f64,
    n: [usize; 3],
    values: Vec<f64>,
}

impl Grid {
    fn sample(field: &impl Field, lo: DVec3, hi: DVec3, cell: f64) -> Grid {
        let count = |a: f64, b: f64| ((b - a) / cell).ceil() as usize + 1;
        let n = [count(lo.x, hi.x), count(lo.y, hi.y), count(lo.z, hi.z)];
        let mut grid = Grid {
            lo,
            cell,
            n,
            values: Vec::with_capacity(n[0] * n[1] * n[2]),
        };
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let f = field.value(grid.point(i, j, k));
                    // A value exactly on the surface would make a zero-length
                    // edge; count it as outside by a hair.
                    grid.values.push(if f.abs() < 1e-12 { 1e-12 } else { f });
                }
            }
        }
        grid
    }

    fn point(&self, i: usize, j: usize, k: usize) -> DVec3 {
        self.lo + DVec3::new(i as f64, j as f64, k as f64) * self.cell
    }

    fn index(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.n[1] + j) * self.n[0] + i
    }

    fn position(&self, index: usize) -> DVec3 {
        let i = index % self.n[0];
        let j = (index / self.n[0]) % self.n[1];
        let k = index / (self.n[0] * self.n[1]);
        self.point(i, j, k)
    }
}

/// Builds the triangle mesh, sharing one vertex per crossed grid edge.
struct Builder<'a, F: Field> {
    field: &'a F,
    grid: &'a Grid,
    vertex_of_edge: HashMap<(usize, usize), u32>,
    mesh: MeshData,
}

impl<F: Field> Builder<'_, F> {
    fn vertex(&mut self, a: usize, b: usize) -> u32 {
        let key = (a.min(b), a.max(b));
        if let Some(&v) = self.vertex_of_edge.get(&key) {
            return v;
        }
        let (fa, fb) = (self.grid.values[key.0], self.grid.values[key.1]);
        let (pa, pb) = (self.grid.position(key.0), self.grid.position(key.1));
        let p = pa + (pb - pa) * (fa / (fa - fb));
        let n = self.field.normal(p, self.grid.cell * 0.25);
        let id = self.mesh.positions.len() as u32;
        self.mesh.positions.push(p.as_vec3());
        self.mesh.normals.push(n.as_vec3());
        self.vertex_of_edge.insert(key, id);
        id
    }

    fn triangle(&mut self, edges: [(usize, usize); 3], flip: bool) {
        let mut t = edges.map(|(a, b)| self.vertex(a, b));
        if flip {
            t.swap(1, 2);
        }
        self.mesh.triangles.push(t);
    }

    /// Emits the surface inside one tetrahedron `v` (grid point indices).
    fn tetrahedron(&mut self, v: [usize; 4]) {
        let inside: Vec<usize> = (0..4).filter(|&i| self.grid.values[v[i]] < 0.0).collect();
        if inside.is_empty() || inside.len() == 4 {
            return;
        }
        let outside: Vec<usize> = (0..4).filter(|i| !inside.contains(i)).collect();
        let order: Vec<usize> = match inside.len() {
            1 => vec![inside[0], outside[0], outside[1], outside[2]],
            3 => vec![outside[0], inside[0], inside[1], inside[2]],
            _ => vec![inside[0], inside[1], outside[0], outside[1]],
        };
        let p = order
            .iter()
            .map(|&i| self.grid.position(v[i]))
            .collect::<Vec<_>>();
        let positive = (p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0])) > 0.0;
        let w = order.iter().map(|&i| v[i]).collect::<Vec<_>>();
        match inside.len() {
            // Triangle (w0w1, w0w2, w0w3) faces away from w0 when the ordered
            // tetrahedron is positive; outward is away from an inside w0 and
            // towards an outside one.
            1 => self.triangle([(w[0], w[1]), (w[0], w[2]), (w[0], w[3])], !positive),
            3 => self.triangle([(w[0], w[1]), (w[0], w[2]), (w[0], w[3])], positive),
            // The quad (w0w2, w0w3, w1w3, w1w2) faces from {w0, w1} towards
            // {w2, w3} when the ordered tetrahedron is positive.
            _ => {
                self.triangle([(w[0], w[2]), (w[0], w[3]), (w[1], w[3])], !positive);
                self.triangle([(w[0], w[2]), (w[1], w[3]), (w[1], w[2])], !positive);
            }
        }
    }
}

/// Polygonises the zero set of `field` inside the box `lo..hi` with grid
/// spacing `cell`. The field must be positive on the box's boundary for the
/// mesh to be closed.
pub fn polygonise(field: &impl Field, lo: DVec3, hi: DVec3, cell: f64) -> MeshData {
    let grid = Grid::sample(field, lo, hi, cell);
    let mut builder = Builder {
        field,
        grid: &grid,
        vertex_of_edge: HashMap::new(),
        mesh: MeshData::default(),
    };
    for k in 0..grid.n[2] - 1 {
        for j in 0..grid.n[1] - 1 {
            for i in 0..grid.n[0] - 1 {
                let corner = |c: usize| grid.index(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
                for tet in TETRAHEDRA {
                    builder.tetrahedron(tet.map(corner));
                }
            }
        }
    }
    builder.mesh
}

/// Applies a uniform scale `s` then a translation to every position; normals
/// are unchanged by such a map.
pub fn scale_translate(mesh: &mut MeshData, s: f32, offset: Vec3) {
    for p in &mut mesh.positions {
        *p = *p * s + offset;
    }
}
