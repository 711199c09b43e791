//! Which `-D` values an error depends on: the `param`s set on the command
//! line that the text under the error's span names, directly or through the
//! `let`s it names, or whose `-D` text the span is in. Each gets a note, so
//! an error caused by a command-line value says so.

use std::collections::HashSet;

use super::Evaluator;
use crate::lang::source::Span;

/// The most definitions followed from one span (a long chain of `let`s
/// still stops).
const MAX_FOLLOWED: usize = 256;

impl Evaluator {
    /// One note per `param` set by `-D` that the text at `span` depends on.
    pub(super) fn define_notes(&self, span: Span) -> Vec<String> {
        if self.defines.is_empty() {
            return Vec::new();
        }
        let mut seen = HashSet::new();
        let mut found = Vec::new();
        let mut todo = vec![span];
        while let Some(span) = todo.pop() {
            if seen.len() >= MAX_FOLLOWED {
                break;
            }
            // The span lies in a `-D` text itself.
            for &index in &self.defines {
                if self.defs[index].value.span.file == span.file && seen.insert(index) {
                    found.push(index);
                }
            }
            let Some(text) = self
                .sources
                .file(span.file)
                .text
                .get(span.start as usize..span.end as usize)
            else {
                continue;
            };
            for word in words(text) {
                let Some(&index) = self.def_index.get(word) else {
                    continue;
                };
                if !seen.insert(index) {
                    continue;
                }
                if self.defines.contains(&index) {
                    found.push(index);
                } else {
                    todo.push(self.defs[index].value.span);
                }
            }
        }
        found
            .into_iter()
            .map(|index| {
                let name = &self.defs[index].name.name;
                let value = self.defs[index].value.span;
                let given = &self.sources.file(value.file).text;
                format!("`{name}` is set by `-D {name}={given}` on the command line")
            })
            .collect()
    }
}

/// The names in expression text: identifiers outside strings, comments
/// and numbers (so the `e5` of `1e5` is no name).
fn words(text: &str) -> Vec<&str> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'"' {
            i += 1;
            while i < bytes.len() && bytes[i] != b'"' {
                i += if bytes[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
        } else if c == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
        } else if c.is_ascii_alphanumeric() || c == b'_' {
            let start = i;
            while i < bytes.len()
                && (bytes[i].is_ascii_alphanumeric()
                    || bytes[i] == b'_'
                    || (c.is_ascii_digit() && bytes[i] == b'.'))
            {
                i += 1;
            }
            if !c.is_ascii_digit() {
                out.push(&text[start..i]);
            }
        } else {
            i += 1;
        }
    }
    out
}
