//! Fuzz target: the input steers a program of recursive functions and
//! `repeat` nests (up to a billion iterations), which must end within a
//! small step budget with the scene or an error naming the bound crossed.
#![no_main]

// Shared with the property test `tests/lang_budget_programs.rs`.
#[path = "../../tests/support/programs.rs"]
mod programs;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = programs::program(data);
    if let Some(wrong) = programs::ends_within(&text, 100_000) {
        panic!("{wrong}");
    }
});
