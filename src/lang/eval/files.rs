//! Reading scene files: size, encoding and emptiness checks, parsing, and
//! splicing `include`d files in place (each file once; cycles are errors).

use crate::lang::codes::Code;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{budget, Evaluator};
use crate::lang::ast::Item;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::{self, Span};
use crate::lang::syntax;
use crate::scene::file::{self, ReadError};

/// The largest scene file accepted.
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// The deepest chain of includes accepted.
const MAX_INCLUDE_DEPTH: usize = 32;

impl Evaluator {
    /// Reads the main file and everything it includes, in order.
    pub(super) fn load_all(&mut self, path: &Path) -> Vec<Item> {
        let mut items = Vec::new();
        let mut stack = Vec::new();
        let mut seen = Vec::new();
        self.load_file(path, None, &mut stack, &mut seen, &mut items);
        items
    }

    fn load_file(
        &mut self,
        path: &Path,
        from: Option<Span>,
        stack: &mut Vec<PathBuf>,
        seen: &mut Vec<PathBuf>,
        out: &mut Vec<Item>,
    ) {
        let key = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        if let Some(span) = from {
            if let Some(first) = stack.iter().position(|p| *p == key) {
                let chain: Vec<String> = stack[first..]
                    .iter()
                    .chain(std::iter::once(&key))
                    .map(|p| short_name(p))
                    .collect();
                self.report(
                    Diagnostic::error(
                        Code::IncludeCycle,
                        span,
                        format!("`{}` includes itself", path.display()),
                    )
                    .label("this include closes a cycle")
                    .help("remove one of the includes in the cycle")
                    .note(format!("the cycle: {}", chain.join(" includes "))),
                );
                return;
            }
            if stack.len() >= MAX_INCLUDE_DEPTH {
                self.report(
                    Diagnostic::error(
                        Code::TooDeep,
                        span,
                        format!("includes nest more than {MAX_INCLUDE_DEPTH} deep"),
                    )
                    .help("flatten the chain of includes"),
                );
                return;
            }
            if seen.contains(&key) {
                return;
            }
            let ext = path
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or_default();
            let help = match ext.to_ascii_lowercase().as_str() {
                "obj" => Some("load a mesh with `mesh \"file.obj\" { material ... }`"),
                "png" | "jpg" | "jpeg" | "hdr" | "exr" => {
                    Some("use an image as a texture with `image(\"file.png\")`")
                }
                _ => None,
            };
            if let Some(help) = help {
                self.report(
                    Diagnostic::error(
                        Code::FileType,
                        span,
                        format!("`include` reads scene files, not `.{ext}` files"),
                    )
                    .label("not a scene")
                    .help(help),
                );
                return;
            }
        }
        let Some(text) = self.read_source(path, from) else {
            return;
        };
        let file = self
            .sources
            .add(path, path.display().to_string(), text.clone());
        if text[source::bom_len(&text)..].trim().is_empty() {
            let span = Span::new(file, 0, 0);
            let d = Diagnostic::error(Code::EmptyFile, span, "the scene file is empty")
                .help("a scene needs at least one object; see docs/language.md");
            if from.is_none() {
                self.report(d);
            }
            return;
        }
        self.include_chain(file, from);
        let bytes = text.len() as f64 * budget::BYTES_PER_SOURCE_BYTE;
        let at = from.unwrap_or(Span::new(file, 0, 0));
        if self.charge(bytes, at, "this scene file").is_err() {
            return;
        }
        let parsed = syntax::parse_all(&text, file);
        // Unused-name warnings would be echoes of the parts that failed.
        self.syntax_failed |= !parsed.syntax_errors.is_empty();
        self.diagnostics.extend(parsed.syntax_errors);
        self.diagnostics.extend(parsed.problems);
        let ast = parsed.file;
        stack.push(key.clone());
        seen.push(key);
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        for item in ast.items {
            if let Item::Include { path: rel, span } = &item {
                let target = dir.join(rel);
                self.load_file(&target, Some(*span), stack, seen, out);
            } else {
                out.push(item);
            }
        }
        stack.pop();
    }

    /// Records which include brought file `file` in, for the notes of its
    /// diagnostics.
    fn include_chain(&mut self, file: u32, from: Option<Span>) {
        if let Some(span) = from {
            self.included_from.insert(file, span);
        }
    }

    /// "`b.rt` is included from a.rt:3" lines, innermost first, for a
    /// diagnostic in file `file`.
    pub(super) fn include_notes(&self, mut file: u32) -> Vec<String> {
        let mut notes = Vec::new();
        while let Some(span) = self.included_from.get(&file) {
            let here = self.sources.file(file);
            let there = self.sources.file(span.file);
            let (line, _) = there.line_col(span.start as usize);
            notes.push(format!(
                "`{}` is included from {}:{line}",
                short_name(&here.path),
                there.name
            ));
            if notes.len() > MAX_INCLUDE_DEPTH {
                break;
            }
            file = span.file;
        }
        notes
    }

    /// The text of a source file, or a reported diagnostic.
    fn read_source(&mut self, path: &Path, from: Option<Span>) -> Option<Arc<str>> {
        let located = |d: Diagnostic| match from {
            Some(span) => Diagnostic {
                span: Some(span),
                ..d
            },
            None => d,
        };
        if let Some((_, text)) = self.options.overlay.iter().find(|(open, _)| open == path) {
            return Some(text.clone());
        }
        // Buffers are named by the editor's (absolute) paths, includes by
        // the including file's folder joined with a relative path.
        let real = (!self.options.overlays.is_empty())
            .then(|| std::fs::canonicalize(path).ok())
            .flatten();
        let buffer = self
            .options
            .overlays
            .iter()
            .find(|(open, _)| open == path || real.as_ref().is_some_and(|real| real == open));
        if let Some((_, text)) = buffer {
            return Some(text.clone());
        }
        match file::regular_size(path) {
            Ok(size) if size > MAX_FILE_BYTES => {
                let d = Diagnostic::global(
                    Code::FileTooLarge,
                    format!(
                        "`{}` is {:.1} MiB, more than the {} MiB a scene file may have",
                        path.display(),
                        size as f64 / (1u64 << 20) as f64,
                        MAX_FILE_BYTES >> 20
                    ),
                )
                .help("generate large scenes with `repeat` loops, or load geometry with `mesh`");
                self.report(located(d));
                return None;
            }
            Err(ReadError::NotRegular { kind }) => {
                let d = Diagnostic::global(
                    Code::FileType,
                    format!("`{}` is {kind}, not a scene file", path.display()),
                )
                .label("not a regular file")
                .help("scenes and includes are regular text files; a device, FIFO or folder is never read");
                if from.is_some() {
                    self.include_failed = true;
                }
                self.report(located(d));
                return None;
            }
            _ => {}
        }
        let bytes = match file::read(path, MAX_FILE_BYTES) {
            Ok(bytes) => bytes,
            Err(e) => {
                let help = match near_miss(path) {
                    Some(s) => format!("did you mean `{s}`?"),
                    None => "check the path; relative paths resolve against the including file"
                        .to_string(),
                };
                let d =
                    Diagnostic::global(Code::Io, format!("cannot read `{}`: {e}", path.display()))
                        .label("included here")
                        .help(help);
                if from.is_some() {
                    self.include_failed = true;
                }
                self.report(located(d));
                return None;
            }
        };
        if bytes.contains(&0) {
            let lossy: Arc<str> = String::from_utf8_lossy(&bytes).into();
            let nul = lossy.find('\0').unwrap_or(0);
            let file = self.sources.add(path, path.display().to_string(), lossy);
            self.report(
                Diagnostic::error(
                    Code::BinaryFile,
                    Span::new(file, nul, nul + 1),
                    format!("`{}` is a binary file, not a scene", path.display()),
                )
                .label("a NUL byte")
                .help("scene files are UTF-8 text"),
            );
            return None;
        }
        match String::from_utf8(bytes) {
            Ok(text) => Some(text.into()),
            Err(e) => {
                let at = e.utf8_error().valid_up_to();
                let lossy: Arc<str> = String::from_utf8_lossy(e.as_bytes()).into();
                let file = self.sources.add(path, path.display().to_string(), lossy);
                self.report(
                    Diagnostic::error(
                        Code::NotUtf8,
                        Span::new(file, at, at + '\u{fffd}'.len_utf8()),
                        format!("`{}` is not valid UTF-8", path.display()),
                    )
                    .label("invalid byte")
                    .help("save the file as UTF-8"),
                );
                None
            }
        }
    }
}

/// A path's file name, for short messages.
fn short_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// A file next to `path` whose name is close to its name.
fn near_miss(path: &Path) -> Option<String> {
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    let entries = std::fs::read_dir(dir.unwrap_or(Path::new("."))).ok()?;
    let names: Vec<String> = entries
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .collect();
    let wanted = path.file_name()?.to_str()?;
    let found = crate::lang::names::suggest(wanted, names.iter().map(String::as_str))?;
    Some(found.to_string())
}
