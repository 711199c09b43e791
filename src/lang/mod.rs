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
use std::path::{Path, PathBuf};

use crate::scene::Scene;

pub use diagnostics::{Diagnostic, Severity};
pub use eval::{budget, random, Options, Outcome, DEFAULT_STEP_BUDGET, PREDEFINED};
pub use source::{SourceMap, Span};

/// A scene compiled from source, with the warnings found on the way.
pub struct Loaded {
    pub scene: Scene,
    pub warnings: Vec<miette::Report>,
    /// Every file the scene was read from: the scene file, its includes and
    /// its assets (what a render must not write over).
    pub files: Vec<PathBuf>,
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
    let files = outcome.sources.files().iter().map(|f| f.path.clone());
    let files = files.chain(outcome.assets.iter().cloned()).collect();
    match outcome.scene {
        Some(scene) => Ok(Loaded {
            scene,
            warnings: reports.collect(),
            files,
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

/// The text of the scene file at `path` read by itself (to format, parse
/// or navigate it): a regular file of at most the size a scene may have.
pub fn read_scene_text(path: &Path) -> Result<String, crate::scene::file::ReadError> {
    crate::scene::file::read_text(path, eval::MAX_FILE_BYTES)
}

/// Parses one file for `rtlang parse`: its canonical source, or the syntax
/// diagnostics with their sources.
pub fn parse_to_canonical(path: &Path) -> Result<String, (Vec<Diagnostic>, SourceMap)> {
    let mut sources = SourceMap::default();
    let text = match read_scene_text(path) {
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
