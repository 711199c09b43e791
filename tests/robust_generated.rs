//! The grammar-aware generator's wild scenes go through the whole pipeline
//! (check, build, tiny render) without a panic or a non-finite pixel.
//! `RTLANG_GEN_CASES=N` runs N seeds instead of the default (for long runs
//! in release: see docs/testing.md); `RTLANG_GEN_DUMP=DIR` also writes each
//! scene to DIR (to seed a fuzzing corpus).

mod support;

use support::gen::Gen;
use support::pipeline::{run_scene, Reached};

fn cases() -> u64 {
    std::env::var("RTLANG_GEN_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(300)
}

#[test]
fn generated_scenes_never_panic_and_render_finite_pixels() {
    let mut reached = [0u32; 3];
    for seed in 0..cases() {
        let text = Gen::from_seed(seed).scene();
        if let Ok(dir) = std::env::var("RTLANG_GEN_DUMP") {
            std::fs::write(format!("{dir}/gen-{seed}.rt"), &text).expect("dump directory");
        }
        let r = std::panic::catch_unwind(|| run_scene(text.as_bytes()))
            .unwrap_or_else(|_| panic!("seed {seed} panicked on:\n{text}"));
        reached[r as usize] += 1;
    }
    // The generator must exercise every stage, not only the diagnostics.
    assert!(reached[Reached::Rendered as usize] > 0, "{reached:?}");
    assert!(reached[Reached::Diagnosed as usize] > 0, "{reached:?}");
}

#[test]
fn the_generator_is_deterministic() {
    assert_eq!(Gen::from_seed(7).scene(), Gen::from_seed(7).scene());
    assert_ne!(Gen::from_seed(7).scene(), Gen::from_seed(8).scene());
    assert_eq!(
        Gen::from_bytes(b"abc").scene(),
        Gen::from_bytes(b"abc").scene()
    );
}
