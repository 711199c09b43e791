//! Source files of one evaluation: their text, byte spans into them, and the
//! mapping from byte offsets to line and column.
//!
//! A file's text is kept as read, with a leading byte-order mark if it has
//! one, so spans are byte offsets into the file; the mark is no column.

use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A byte range `start..end` in the file with index `file` of a [`SourceMap`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Span {
    pub file: u32,
    pub start: u32,
    pub end: u32,
}

impl Span {
    /// A span in `file` covering `start..end`.
    pub fn new(file: u32, start: usize, end: usize) -> Span {
        Span {
            file,
            start: start as u32,
            end: end as u32,
        }
    }

    /// The smallest span covering both (which must be in the same file).
    pub fn to(self, other: Span) -> Span {
        Span {
            file: self.file,
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    /// Length in bytes.
    pub fn len(self) -> usize {
        (self.end - self.start) as usize
    }

    /// Whether the span covers no byte.
    pub fn is_empty(self) -> bool {
        self.end == self.start
    }
}

/// The byte-order mark some editors write at the start of a UTF-8 file.
pub const BOM: char = '\u{feff}';

/// The length in bytes of the byte-order mark `text` starts with (0 or 3).
pub fn bom_len(text: &str) -> usize {
    if text.starts_with(BOM) {
        BOM.len_utf8()
    } else {
        0
    }
}

/// The 0-based column in characters of byte `at` on the line of `text`
/// that starts at byte `line_start` (a byte-order mark is not counted).
pub fn column(text: &str, line_start: usize, at: usize) -> usize {
    let start = line_start.max(bom_len(text)).min(at);
    text.get(start..at)
        .map_or(at - start, |s| s.chars().count())
}

/// One loaded source text.
#[derive(Debug)]
pub struct SourceFile {
    /// The path the file was read from (or a pseudo path such as `-D x`).
    pub path: PathBuf,
    /// The name shown in diagnostics.
    pub name: String,
    pub text: Arc<str>,
    line_starts: Vec<usize>,
}

impl SourceFile {
    /// 1-based line and column (in characters, not counting a byte-order
    /// mark) of byte offset `at`.
    pub fn line_col(&self, at: usize) -> (usize, usize) {
        let at = at.min(self.text.len());
        let line = self.line_starts.partition_point(|&s| s <= at) - 1;
        (line + 1, column(&self.text, self.line_starts[line], at) + 1)
    }
}

/// All source texts of one evaluation, indexed by [`Span::file`].
#[derive(Debug, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// Adds a text and returns its file index.
    pub fn add(&mut self, path: &Path, name: String, text: Arc<str>) -> u32 {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        self.files.push(SourceFile {
            path: path.to_path_buf(),
            name,
            text,
            line_starts,
        });
        self.files.len() as u32 - 1
    }

    /// Every file, in index order.
    pub fn files(&self) -> &[SourceFile] {
        &self.files
    }

    /// The file with index `id`.
    pub fn file(&self, id: u32) -> &SourceFile {
        &self.files[id as usize]
    }

    /// The text a span covers.
    pub fn snippet(&self, span: Span) -> &str {
        self.file(span.file)
            .text
            .get(span.start as usize..span.end as usize)
            .unwrap_or("")
    }
}
