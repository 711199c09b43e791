//! `rtlang fmt`: the canonical layout of [`super::pretty`] with the
//! author's comments and blank-line grouping put back.
//!
//! Comments are attached by position: those before an item or statement
//! become lines above it, those after it on its last line stay there, those
//! before a closing brace stay inside the block. A comment inside an
//! expression moves to the end of its statement's line. Runs of blank lines
//! between statements become one blank line; none is kept at the start or
//! end of a block.
//!
//! A leading byte-order mark is kept. A file whose first line ends in CRLF
//! is formatted as its LF text and written back with CRLF line endings, so
//! it formats exactly like the same file saved with LF.

use std::ops::Range;

use super::ast::File;
use super::diagnostics::Diagnostic;
use super::pretty::{self, Trivia};
use super::source::{self, Span};
use super::{syntax, trivia};

/// The formatted text of `text`, or its syntax errors (`file` is the index
/// their spans use).
pub fn format(text: &str, file: u32) -> Result<String, Vec<Diagnostic>> {
    let bom = source::bom_len(text);
    let body = &text[bom..];
    if bom == 0 && !body.contains('\r') {
        return format_lf(text, file);
    }
    // Errors are found in the text as it is, so their spans point into it.
    parse(text, file)?;
    let crlf = body.find('\n').is_some_and(|i| body[..i].ends_with('\r'));
    let formatted = format_lf(&body.replace("\r\n", "\n"), file)?;
    let formatted = if crlf {
        formatted.replace('\n', "\r\n")
    } else {
        formatted
    };
    Ok(format!("{}{formatted}", &text[..bom]))
}

/// The syntax tree of `text`, or its syntax errors.
fn parse(text: &str, file: u32) -> Result<File, Vec<Diagnostic>> {
    match syntax::parse_file(text, file) {
        Ok((ast, problems)) if problems.is_empty() => Ok(ast),
        Ok((_, problems)) => Err(problems),
        Err(d) => Err(vec![*d]),
    }
}

/// [`format`] of a text without a byte-order mark or CRLF line endings.
fn format_lf(text: &str, file: u32) -> Result<String, Vec<Diagnostic>> {
    let ast = parse(text, file)?;
    let mut comments = Interleave {
        text,
        comments: trivia::comments(text),
        next: 0,
        pos: 0,
    };
    let mut out = pretty::file_with(&ast, &mut comments);
    let fresh = out.is_empty();
    out += &comments.lines(text.len(), 0, fresh);
    Ok(out)
}

/// Hands out the comments of `text` in order as the printer walks the tree.
struct Interleave<'a> {
    text: &'a str,
    comments: Vec<Range<usize>>,
    /// The first comment not yet printed.
    next: usize,
    /// How far into `text` the printed output has reached.
    pos: usize,
}

impl Interleave<'_> {
    /// The text of comment `i`, without trailing blanks.
    fn comment(&self, i: usize) -> &str {
        self.text[self.comments[i].clone()].trim_end()
    }

    /// Whether `text[from..to]` holds a blank line.
    fn blank(&self, from: usize, to: usize) -> bool {
        self.text
            .get(from.min(to)..to)
            .is_some_and(|gap| gap.matches('\n').count() >= 2)
    }

    /// Where the text of `span` ends: the parser's spans can take in the
    /// blanks and comments after an expression, which are not its text.
    fn end_of(&self, span: Span) -> usize {
        let (start, mut end) = (span.start as usize, span.end as usize);
        loop {
            let text = self.text.get(start..end).unwrap_or("");
            end = start + text.trim_end().len();
            match self
                .comments
                .iter()
                .find(|c| c.end == end && c.start >= start)
            {
                Some(c) => end = c.start,
                None => return end,
            }
        }
    }

    /// Every comment that starts before `until`, each on a line of its own
    /// at `indent`, with the blank lines between them.
    fn lines(&mut self, until: usize, indent: usize, mut fresh: bool) -> String {
        let mut out = String::new();
        while self.next < self.comments.len() && self.comments[self.next].start < until {
            let Range { start, end } = self.comments[self.next];
            if !fresh && self.blank(self.pos, start) {
                out.push('\n');
            }
            out.push_str(&"  ".repeat(indent));
            out.push_str(self.comment(self.next));
            out.push('\n');
            self.pos = end;
            self.next += 1;
            fresh = false;
        }
        out
    }
}

impl Trivia for Interleave<'_> {
    fn before(&mut self, span: Span, indent: usize, fresh: bool) -> String {
        let start = span.start as usize;
        let mut out = self.lines(start, indent, fresh);
        let fresh = fresh && out.is_empty();
        if !fresh && self.blank(self.pos, start) {
            out.push('\n');
        }
        self.pos = self.pos.max(start);
        out
    }

    fn after(&mut self, span: Span) -> String {
        let end = self.end_of(span);
        let mut out = String::new();
        while let Some(range) = self.comments.get(self.next) {
            let gap = self.text.get(self.pos.max(end)..range.start).unwrap_or("");
            let inside = range.start < end;
            if !inside && !gap.bytes().all(|b| b == b' ' || b == b'\t') {
                break;
            }
            out.push(' ');
            out.push_str(self.comment(self.next));
            self.pos = range.end;
            self.next += 1;
        }
        self.pos = self.pos.max(end);
        out
    }

    fn inside(&mut self, empty: bool, indent: usize) -> String {
        let from = if empty {
            match trivia::find_at_depth0(self.text, self.pos, b'{') {
                Some(open) => open + 1,
                None => return String::new(),
            }
        } else {
            self.pos
        };
        let Some(close) = trivia::find_at_depth0(self.text, from, b'}') else {
            return String::new();
        };
        self.pos = self.pos.max(from);
        let out = self.lines(close, indent, empty);
        self.pos = close + 1;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::format;

    fn fmt(text: &str) -> String {
        format(text, 0).expect("the text parses")
    }

    #[test]
    fn comments_and_grouping_survive_the_canonical_layout() {
        let text = "// header\n\n\nlet a=1 // one\nlet b =  2\n\n/* block */\nsphere{radius a+b\n\n  // inside\n  center (0,0,0)   // c\n  // dangling\n}\n// end\n";
        let want = "// header\n\nlet a = 1 // one\nlet b = 2\n\n/* block */\nsphere {\n  radius a + b\n\n  // inside\n  center (0, 0, 0) // c\n  // dangling\n}\n// end\n";
        assert_eq!(fmt(text), want);
        assert_eq!(fmt(want), want, "formatting is idempotent");
    }

    #[test]
    fn comments_in_empty_blocks_and_expressions_are_kept() {
        let text = "group { /* later */ }\nlet v = (1, // x\n 2)\nif true {} else { // no\n}\n";
        // An empty `else` is no part of the tree: its comment joins the `if`.
        let want = "group {\n  /* later */\n}\nlet v = (1, 2) // x\nif true {} // no\n";
        assert_eq!(fmt(text), want);
        assert_eq!(fmt(want), want);
    }

    #[test]
    fn a_syntax_error_is_reported_not_formatted() {
        let problems = format("sphere { radius }", 0).expect_err("a syntax error");
        assert!(problems.iter().all(|d| d.is_error()));
    }
}
