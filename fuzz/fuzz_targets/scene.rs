//! Fuzz target: arbitrary bytes as a scene file through parse, evaluate,
//! world build and a tiny render.
#![no_main]

#[path = "../../tests/support/pipeline.rs"]
mod pipeline;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    pipeline::run_scene(data);
});
