//! Renderer throughput: samples/s and rays/s on the Cornell box and the
//! book-2 final scene contents at 400×400, depth 50, on 1 thread and 2.
//! Criterion reports samples/s as its element throughput; rays per sample
//! are printed once per scene. 4 spp keeps a run short; the throughput per
//! sample does not depend on the sample count.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rtlang::geometry::World;
use rtlang::render::scenes::{book2_final, cornell_box};
use rtlang::render::{render, RenderOptions};
use rtlang::scene::Scene;

const SIZE: u32 = 400;
const SPP: u32 = 4;

fn bench_scene(c: &mut Criterion, name: &str, scene: &Scene) {
    let world = World::build(scene).expect("scene builds");
    let mut group = c.benchmark_group(name);
    group.sample_size(10);
    group.throughput(Throughput::Elements(SIZE as u64 * SIZE as u64 * SPP as u64));
    for threads in [1, 2] {
        let mut options = RenderOptions::from_settings(&scene.settings);
        options.threads = Some(threads);
        let out = render(scene, &world, &options, &|_| {}).expect("renders");
        eprintln!(
            "{name}, {threads} thread(s): {:.2} rays per sample, {} dropped",
            out.stats.rays as f64 / out.stats.samples as f64,
            out.stats.dropped
        );
        group.bench_function(format!("{threads}-thread"), |b| {
            b.iter(|| render(scene, &world, &options, &|_| {}).expect("renders"))
        });
    }
    group.finish();
}

fn benches(c: &mut Criterion) {
    bench_scene(c, "cornell", &cornell_box(SIZE, SPP));
    bench_scene(c, "book2-final", &book2_final(SIZE, SPP));
}

criterion_group!(render_benches, benches);
criterion_main!(render_benches);
