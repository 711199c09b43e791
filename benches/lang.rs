//! Parse + evaluate a generated scene of 100 000 objects (the language's
//! performance target: under 1 s in release mode).

use std::fmt::Write;

use criterion::{criterion_group, criterion_main, Criterion};
use rtlang::lang::{self, Options};

fn generated_scene(objects: usize) -> String {
    let mut text =
        String::from("let m = lambertian(rgb(0.5, 0.5, 0.5))\nlet glass = dielectric(1.5)\n");
    for i in 0..objects {
        let (x, z) = ((i % 316) as f64 * 0.7, (i / 316) as f64 * 0.7);
        let material = if i % 7 == 0 { "glass" } else { "m" };
        let _ = writeln!(
            text,
            "sphere {{ center ({x}, 0.2, {z}) radius 0.2 material {material} }}"
        );
    }
    text
}

fn bench(c: &mut Criterion) {
    let dir = std::env::temp_dir().join("rtlang-bench");
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join("100k.rt");
    std::fs::write(&path, generated_scene(100_000)).expect("write the scene");
    let looped = dir.join("loop.rt");
    std::fs::write(
        &looped,
        "repeat i in 0..316 { repeat j in 0..317 { sphere { center (i * 0.7, 0.2, j * 0.7) radius 0.2 \
         material lambertian(rgb(random(i * 1000 + j), 0.5, 0.5)) } } }\n",
    )
    .expect("write the scene");
    let mut group = c.benchmark_group("lang");
    group.sample_size(10);
    group.bench_function("parse+eval 100k objects", |b| {
        b.iter(|| {
            let outcome = lang::check(&path, &Options::default());
            assert!(outcome.scene.is_some());
        })
    });
    group.bench_function("repeat loop 100k objects", |b| {
        b.iter(|| {
            let outcome = lang::check(&looped, &Options::default());
            assert!(outcome.scene.is_some());
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
