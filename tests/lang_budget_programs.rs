//! Property test of the step budget: random programs of functions calling
//! each other and themselves, and `repeat` nests of up to a billion
//! iterations, all end within a small budget with the scene or an error
//! naming the bound they crossed (never a hang, a panic or an error that
//! is only a consequence of one).

use proptest::prelude::*;

#[path = "support/programs.rs"]
mod programs;

/// Steps each program may take: a few milliseconds of evaluation.
const STEPS: u64 = 100_000;

proptest! {
    // About 5 ms a program.
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_programs_end_within_the_budget(bytes in proptest::collection::vec(any::<u8>(), 0..48)) {
        let text = programs::program(&bytes);
        if let Some(wrong) = programs::ends_within(&text, STEPS) {
            panic!("{wrong}");
        }
    }
}

/// A few programs of the kind written out, so a change to the generator
/// that stopped making them would show.
#[test]
fn the_generator_makes_recursions_and_loop_nests() {
    let texts: Vec<String> = (0..64u8)
        .map(|b| programs::program(&[b, b / 3, b / 7]))
        .collect();
    let all = texts.join("\n");
    assert!(all.contains("repeat a1 in 0.."), "{all}");
    assert!(all.contains("fn g0(n)"), "{all}");
    assert!(texts
        .iter()
        .any(|t| t.contains("then") && t.contains("f0(n - 1)")));
}
