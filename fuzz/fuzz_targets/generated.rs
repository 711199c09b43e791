//! Fuzz target: the input steers the grammar-aware generator, whose scene
//! goes through parse, evaluate, world build and a tiny render.
#![no_main]

// Shared with the test suite, which also seeds the generator by number.
#[allow(dead_code)]
#[path = "../../tests/support/gen.rs"]
mod gen;
#[path = "../../tests/support/pipeline.rs"]
mod pipeline;
// The pipeline writes its scenes in a scratch folder of the tests' own.
#[allow(dead_code)]
#[path = "../../tests/support/scratch.rs"]
mod scratch;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = gen::Gen::from_bytes(data).scene();
    pipeline::run_scene(text.as_bytes());
});
