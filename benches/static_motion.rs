//! What motion costs: the same scene with no motion block, with a motion
//! block that folds to the identity, and with a genuinely time-dependent
//! motion that moves nothing (x = 0·t).
//!
//! `cargo bench --bench static_motion` (wall time). The same three scenes
//! are in benches/scenes/motion_cost_*.rt for instruction counts under
//! callgrind, which do not depend on the machine's load.

use criterion::{criterion_group, criterion_main, Criterion};
use rtlang::geometry::World;
use rtlang::render::{render, RenderOptions};
use rtlang::scene::Scene;

fn scene(motion: &str) -> Scene {
    let source = format!(
        "render {{ size 64 x 64  samples 4  depth 8  seed 1  background rgb(0.7, 0.8, 1.0) }}
         camera {{ from (0, 3, 12)  at (0, 0, 0)  fov 40 }}
         let white = lambertian(rgb(0.73, 0.73, 0.73))
         plane {{ point (0, -1, 0)  normal (0, 1, 0)  material white }}
         group {{
           repeat i in 0..10 {{ repeat j in 0..10 {{
             sphere {{ center (i - 4.5, 0, j - 4.5)  radius 0.4  material white }}
           }} }}
           {motion}
         }}"
    );
    let path = std::env::temp_dir().join(format!("rtlang-static-motion-{}.rt", std::process::id()));
    std::fs::write(&path, source).expect("write scene");
    let loaded = rtlang::lang::load_scene(&path, &[]).unwrap_or_else(|e| panic!("{e:?}"));
    let _ = std::fs::remove_file(&path);
    loaded.scene
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("static_motion");
    group.sample_size(20);
    for (name, motion) in [
        ("static", ""),
        ("identity_motion_block", "motion { translate (0, 0, 0) }"),
        (
            "time_dependent_zero_motion",
            "motion { translate (0 * t, 0, 0) }",
        ),
    ] {
        let s = scene(motion);
        let world = World::build(&s).expect("builds");
        let options = RenderOptions::from_settings(&s.settings);
        group.bench_function(name, |b| {
            b.iter(|| render(&s, &world, &options, &|_| {}).expect("renders"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
