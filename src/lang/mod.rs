//! The rtlang language: grammar, syntax tree with spans, evaluation into a
//! [`crate::scene::Scene`], and diagnostics.
