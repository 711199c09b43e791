//! Speed and accuracy of the surface of revolution on the seed's vase:
//! analytic ray intersections per second at two tolerances (criterion), and
//! the geometric error (distance of hit points to the exact surface) of the
//! analytic mode and of tessellations at resolutions 8..256, printed as a
//! table. Run: `cargo bench --bench revolution`.

use criterion::{criterion_group, Criterion, Throughput};
use glam::{Vec2, Vec3};
use rtlang::geometry::revolution::{surface_distance, tessellate, RevolutionSurface};
use rtlang::geometry::Ray;
use rtlang::scene::{Bezier, MeshData};

const TOLERANCES: [f32; 2] = [1e-3, 1e-6];
const SHELL_RESOLUTION: u32 = 50;

fn vase() -> Bezier {
    Bezier {
        points: [(-2.0, 2.0), (-4.0, 0.0), (0.0, 0.0), (-2.0, -2.0)]
            .map(|(x, y)| Vec2::new(x, y))
            .to_vec(),
    }
}

/// Rays from the seed's camera position (0, 0, 9) through a grid covering
/// the vase, like primary rays of its picture.
fn camera_rays(n: usize) -> Vec<Ray> {
    let from = Vec3::new(0.0, 0.0, 9.0);
    (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) as f32 / n as f32, (k / n) as f32 / n as f32);
            let target = Vec3::new(-3.0 + 6.0 * i, -2.5 + 5.0 * j, 0.0);
            Ray::new(from, target - from, 0.0)
        })
        .collect()
}

/// The nearest hit on a mesh by brute force (Möller–Trumbore).
fn mesh_hit(mesh: &MeshData, ray: &Ray) -> Option<f32> {
    let mut best: Option<f32> = None;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let (e1, e2) = (b - a, c - a);
        let p = ray.dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = ray.origin - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = ray.dir.dot(q) / det;
        let t = e2.dot(q) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 && best.is_none_or(|b| t < b) {
            best = Some(t);
        }
    }
    best
}

/// Mean and max distance to the exact surface of the points `hits`.
fn error_stats(curve: &Bezier, hits: &[Vec3]) -> (f64, f64) {
    let d: Vec<f64> = hits.iter().map(|&p| surface_distance(curve, p)).collect();
    let mean = d.iter().sum::<f64>() / d.len().max(1) as f64;
    (mean, d.iter().copied().fold(0.0, f64::max))
}

fn accuracy_table() {
    let curve = vase();
    let rays = camera_rays(40);
    println!("mode           | hits | mean error | max error");
    for tol in TOLERANCES {
        let surface = RevolutionSurface::new(&curve, SHELL_RESOLUTION, tol);
        let hits: Vec<Vec3> = rays
            .iter()
            .filter_map(|r| surface.intersect(r, 1e-4, f32::INFINITY))
            .map(|h| h.point)
            .collect();
        let (mean, max) = error_stats(&curve, &hits);
        println!(
            "analytic {tol:.0e} | {:4} | {mean:.3e} | {max:.3e}   (Newton failures: {})",
            hits.len(),
            surface.newton_failures()
        );
    }
    for res in [8, 16, 32, 64, 128, 256] {
        let mesh = tessellate(&curve, res);
        let hits: Vec<Vec3> = rays
            .iter()
            .filter_map(|r| mesh_hit(&mesh, r).map(|t| r.at(t)))
            .collect();
        let (mean, max) = error_stats(&curve, &hits);
        println!(
            "mesh {res:3}       | {:4} | {mean:.3e} | {max:.3e}",
            hits.len()
        );
    }
}

fn analytic_speed(c: &mut Criterion) {
    let curve = vase();
    let rays = camera_rays(64);
    let mut group = c.benchmark_group("revolution_analytic");
    group.throughput(Throughput::Elements(rays.len() as u64));
    for tol in TOLERANCES {
        let surface = RevolutionSurface::new(&curve, SHELL_RESOLUTION, tol);
        group.bench_function(format!("tolerance {tol:.0e}"), |b| {
            b.iter(|| {
                rays.iter()
                    .filter_map(|r| surface.intersect(r, 1e-4, f32::INFINITY))
                    .count()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, analytic_speed);

fn main() {
    accuracy_table();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
