//! Fuzz target: arbitrary bytes as a scene file through parse, evaluate,
//! world build and a tiny render.
#![no_main]

#[path = "../../tests/support/pipeline.rs"]
mod pipeline;
// The pipeline writes its scenes in a scratch folder of the tests' own.
#[allow(dead_code)]
#[path = "../../tests/support/scratch.rs"]
mod scratch;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    pipeline::run_scene(data);
});
