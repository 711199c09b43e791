//! Evaluation options with `-D name=value` overrides, as tests write them.

use rtlang::lang::Options;

/// Default options with the given `-D` overrides.
pub fn options(defines: &[(&str, &str)]) -> Options {
    Options {
        defines: defines
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect(),
        ..Options::default()
    }
}
