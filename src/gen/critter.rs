//! The generated rabbit-like figure that stands in for the Stanford bunny:
//! an implicit surface of smoothly blended ellipsoids (body, haunches, feet,
//! chest, head, snout, two long ears, a tail), polygonised by marching
//! tetrahedra with vertex normals from the field's gradient. The result is
//! placed in the stored `bunny_28k.obj`'s frame — facing −x, 0.154 units
//! tall, lowest point at y = 0.0333 — so a scene's transform for the real
//! bunny fits it unchanged.

use glam::{DMat3, DVec3, Vec3};

use super::marching::{polygonise, scale_translate, Field};
use crate::scene::MeshData;

/// Options for [`critter`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CritterOptions {
    /// Grid spacing in design units (the figure is about 17 units tall
    /// before it is scaled into place); smaller means more triangles.
    pub cell: f64,
}

impl Default for CritterOptions {
    fn default() -> Self {
        CritterOptions { cell: 0.45 }
    }
}

/// Height of the finished figure, as the stored bunny's.
pub const HEIGHT: f32 = 0.1537;
/// Lowest y of the finished figure, as the stored bunny's.
pub const FLOOR: f32 = 0.0333;

/// An ellipsoid: centre, semi-axes, and orientation (local → design space).
struct Ellipsoid {
    centre: DVec3,
    radii: DVec3,
    frame: DMat3,
}

impl Ellipsoid {
    fn new(centre: [f64; 3], radii: [f64; 3]) -> Ellipsoid {
        Ellipsoid {
            centre: DVec3::from(centre),
            radii: DVec3::from(radii),
            frame: DMat3::IDENTITY,
        }
    }

    /// Tilts the ellipsoid by `z` radians about z, then `x` radians about x.
    fn tilted(mut self, z: f64, x: f64) -> Ellipsoid {
        self.frame = DMat3::from_rotation_x(x) * DMat3::from_rotation_z(z);
        self
    }

    /// An approximate signed distance (exact on the surface, a bound
    /// elsewhere): k0·(k0 − 1)/k1 with k0 = |q/r|, k1 = |q/r²|.
    fn distance(&self, p: DVec3) -> f64 {
        let q = self.frame.transpose() * (p - self.centre);
        let k0 = (q / self.radii).length();
        let k1 = (q / (self.radii * self.radii)).length();
        if k1 < 1e-12 {
            return -self.radii.min_element();
        }
        k0 * (k0 - 1.0) / k1
    }
}

/// Polynomial smooth minimum: blends two distances over a width `k`.
fn smooth_min(a: f64, b: f64, k: f64) -> f64 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k * 0.25
}

/// The figure's field, in design units: parts blended into the body with
/// a generous radius, the thin ears with a small one.
struct Critter {
    body: Vec<Ellipsoid>,
    ears: Vec<Ellipsoid>,
}

impl Critter {
    fn new() -> Critter {
        let mut body = vec![
            Ellipsoid::new([1.5, 8.0, 0.0], [6.5, 4.8, 4.8]),
            Ellipsoid::new([-3.5, 9.8, 0.0], [3.0, 3.4, 3.1]),
            Ellipsoid::new([-5.6, 12.6, 0.0], [3.3, 2.8, 2.6]).tilted(-0.25, 0.0),
            Ellipsoid::new([-8.3, 11.9, 0.0], [1.6, 1.4, 1.5]),
            Ellipsoid::new([8.2, 9.0, 0.0], [1.6, 1.6, 1.6]),
        ];
        for side in [-1.0, 1.0] {
            body.push(Ellipsoid::new([3.6, 6.4, 3.1 * side], [3.6, 2.9, 1.9]));
            body.push(Ellipsoid::new([2.3, 3.9, 3.4 * side], [3.2, 0.8, 1.2]));
            body.push(Ellipsoid::new([-4.6, 4.0, 2.0 * side], [2.2, 0.8, 1.0]));
            body.push(Ellipsoid::new([-4.0, 5.6, 2.0 * side], [0.9, 2.0, 0.9]));
        }
        let ears = [-1.0, 1.0]
            .map(|side| {
                Ellipsoid::new([-4.0, 16.6, 1.3 * side], [1.2, 4.0, 0.7])
                    .tilted(-0.35 + 0.12 * side, 0.22 * side)
            })
            .into();
        Critter { body, ears }
    }
}

impl Field for Critter {
    fn value(&self, p: DVec3) -> f64 {
        let body = self
            .body
            .iter()
            .map(|e| e.distance(p))
            .reduce(|a, b| smooth_min(a, b, 1.6))
            .unwrap_or(f64::INFINITY);
        self.ears
            .iter()
            .fold(body, |d, e| smooth_min(d, e.distance(p), 0.7))
    }
}

/// Generates the figure as a closed triangle mesh with unit outward vertex
/// normals, scaled and moved into the stored bunny's frame.
pub fn critter(opts: CritterOptions) -> MeshData {
    let field = Critter::new();
    let lo = DVec3::new(-12.0, 1.5, -7.5);
    let hi = DVec3::new(11.5, 22.0, 7.5);
    let mut mesh = polygonise(&field, lo, hi, opts.cell);
    let (min, max) = mesh.positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(a, b), &p| (a.min(p), b.max(p)),
    );
    let s = HEIGHT / (max.y - min.y).max(f32::EPSILON);
    let centre_x = (min.x + max.x) * 0.5;
    scale_translate(
        &mut mesh,
        s,
        Vec3::new(-0.017 - centre_x * s, FLOOR - min.y * s, 0.0),
    );
    mesh
}
