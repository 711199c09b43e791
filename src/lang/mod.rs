//! The rtlang language: grammar, syntax tree with spans, evaluation into a
//! [`crate::scene::Scene`], and diagnostics.
//!
//! [`load_scene`] is the entry point for commands that need a scene;
//! [`check`] returns every diagnostic with the sources they point into, for
//! `rtlang check`.

pub mod ast;
pub mod builtins;
pub mod cache;
pub mod codes;
pub mod diagnostics;
mod eval;
pub mod expr;
pub mod format;
pub mod lexical;
pub mod names;
pub mod pretty;
pub mod properties;
pub mod scan;
pub mod source;
pub mod syntax;
pub mod trivia;

use crate::lang::codes::Code;
use std::path::Path;

use crate::scene::Scene;

pub use diagnostics::{Diagnostic, Severity};
pub use eval::{random, Options, Outcome, DEFAULT_STEP_BUDGET};
pub use source::{SourceMap, Span};

/// A scene compiled from source, with the warnings found on the way.
pub struct Loaded {
    pub scene: Scene,
    pub warnings: Vec<miette::Report>,
}

/// Parses and evaluates the scene file at `path`, with command-line
/// parameter overrides `defines` (`-D name=value`).
pub fn load_scene(
    path: &Path,
    defines: &[(String, String)],
) -> Result<Loaded, Vec<miette::Report>> {
    let options = Options {
        defines: defines.to_vec(),
        ..Options::default()
    };
    load_scene_with(path, &options)
}

/// [`load_scene`] with every option (animation frame and rate too).
pub fn load_scene_with(path: &Path, options: &Options) -> Result<Loaded, Vec<miette::Report>> {
    let outcome = check(path, options);
    let reports = outcome
        .diagnostics
        .iter()
        .map(|d| d.to_report(&outcome.sources));
    match outcome.scene {
        Some(scene) => Ok(Loaded {
            scene,
            warnings: reports.collect(),
        }),
        None => Err(reports.collect()),
    }
}

/// Parses and evaluates the scene at `path`, returning all diagnostics
/// (the error that ended evaluation first, then the others in source order)
/// and the scene if there was no error.
pub fn check(path: &Path, options: &Options) -> Outcome {
    let mut outcome = eval::evaluate(path, options);
    outcome.diagnostics.sort_by_key(|d| {
        (
            !(d.is_error() && d.code.ends_evaluation()),
            d.span.is_some(),
            d.span.map(|s| (s.file, s.start)).unwrap_or_default(),
        )
    });
    outcome
}

/// Parses one file for `rtlang parse`: its canonical source, or the syntax
/// diagnostics with their sources.
pub fn parse_to_canonical(path: &Path) -> Result<String, (Vec<Diagnostic>, SourceMap)> {
    let mut sources = SourceMap::default();
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) => {
            let d = Diagnostic::global(Code::Io, format!("cannot read `{}`: {e}", path.display()))
                .help("check the path");
            return Err((vec![d], sources));
        }
    };
    let file = sources.add(path, path.display().to_string(), text.as_str().into());
    let parsed = syntax::parse_all(&text, file);
    if parsed.syntax_errors.is_empty() && parsed.problems.is_empty() {
        Ok(pretty::file(&parsed.file))
    } else {
        let mut problems = parsed.syntax_errors;
        problems.extend(parsed.problems);
        Err((problems, sources))
    }
}
