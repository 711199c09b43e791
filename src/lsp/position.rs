//! Byte offsets ↔ LSP positions (a line and a UTF-16 column), and file
//! URIs ↔ paths.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use lsp_types::{Position, Range, Uri};

/// The line starts of one text, for converting positions.
pub struct Lines<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    pub fn new(text: &'a str) -> Lines<'a> {
        let starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Lines { text, starts }
    }

    /// The position of byte offset `at`.
    pub fn position(&self, at: usize) -> Position {
        let at = at.min(self.text.len());
        let line = self.starts.partition_point(|&s| s <= at) - 1;
        let start = self.starts[line];
        let column = self
            .text
            .get(start..at)
            .map_or(0, |s| s.chars().map(char::len_utf16).sum::<usize>());
        Position::new(line as u32, column as u32)
    }

    /// The byte offset of `position` (clamped to its line and the text).
    pub fn offset(&self, position: Position) -> usize {
        let Some(&start) = self.starts.get(position.line as usize) else {
            return self.text.len();
        };
        let mut units = 0;
        for (i, c) in self.text[start..].char_indices() {
            if units >= position.character as usize || c == '\n' {
                return start + i;
            }
            units += c.len_utf16();
        }
        self.text.len()
    }

    /// The range of bytes `start..end`.
    pub fn range(&self, start: usize, end: usize) -> Range {
        Range::new(self.position(start), self.position(end))
    }
}

/// The positions of byte offsets asked for in increasing order, each found
/// from the one before: converting every token of a text walks it once,
/// where [`Lines::position`] would count each column from its line start
/// (quadratic on one long line).
pub struct Walker<'a> {
    text: &'a str,
    at: usize,
    position: Position,
}

impl<'a> Walker<'a> {
    pub fn new(text: &'a str) -> Walker<'a> {
        Walker {
            text,
            at: 0,
            position: Position::new(0, 0),
        }
    }

    /// The position of byte offset `to` (clamped to the text, and moved
    /// back to a character boundary); an offset before the last one asked
    /// for starts the walk over from the beginning.
    pub fn position(&mut self, to: usize) -> Position {
        let mut to = to.min(self.text.len());
        while !self.text.is_char_boundary(to) {
            to -= 1;
        }
        if to < self.at {
            (self.at, self.position) = (0, Position::new(0, 0));
        }
        for c in self.text[self.at..to].chars() {
            if c == '\n' {
                self.position = Position::new(self.position.line + 1, 0);
            } else {
                self.position.character += c.len_utf16() as u32;
            }
        }
        self.at = to;
        self.position
    }
}

/// The local path of a `file:` URI.
pub fn uri_to_path(uri: &Uri) -> Option<PathBuf> {
    let rest = uri.as_str().strip_prefix("file://")?;
    let bytes = rest.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok());
        match (bytes[i], hex.and_then(|h| u8::from_str_radix(h, 16).ok())) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8(out).ok().map(PathBuf::from)
}

/// The `file:` URI of an absolute path.
pub fn path_to_uri(path: &Path) -> Option<Uri> {
    let mut text = String::from("file://");
    for b in path.to_str()?.bytes() {
        if b.is_ascii_alphanumeric() || b"/-_.~".contains(&b) {
            text.push(b as char);
        } else {
            text.push_str(&format!("%{b:02X}"));
        }
    }
    Uri::from_str(&text).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_count_utf16_units_and_round_trip() {
        let text = "let a = 1\nlet é𝄞 = 2\n";
        let lines = Lines::new(text);
        let at = text.find("= 2").expect("in the text");
        let pos = lines.position(at);
        assert_eq!(pos, Position::new(1, 8), "é is one unit, 𝄞 two");
        assert_eq!(lines.offset(pos), at);
        assert_eq!(lines.offset(Position::new(0, 99)), 9, "clamped to the line");
    }

    #[test]
    fn the_walker_agrees_with_the_line_index() {
        let text = "let a = 1\nlet é𝄞 = \"x\"\n\nsphere {}";
        let lines = Lines::new(text);
        let mut walker = Walker::new(text);
        let offsets: Vec<usize> = (0..=text.len())
            .filter(|&i| text.is_char_boundary(i))
            .collect();
        for &at in &offsets {
            assert_eq!(walker.position(at), lines.position(at), "at {at}");
        }
        assert_eq!(walker.position(4), lines.position(4), "a step back");
    }

    #[test]
    fn paths_and_uris_round_trip() {
        let path = Path::new("/tmp/my scenes/a#b.rt");
        let uri = path_to_uri(path).expect("a valid URI");
        assert_eq!(uri.as_str(), "file:///tmp/my%20scenes/a%23b.rt");
        assert_eq!(uri_to_path(&uri).as_deref(), Some(path));
    }
}
