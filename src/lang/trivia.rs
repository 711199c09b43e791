//! The comments of a source text, found by a byte-level pass that knows
//! strings and both comment forms (the parser throws comments away), for
//! the formatter and the language server.

use std::ops::Range;

/// The byte ranges of every comment in `text`, in order. A line comment
/// ends before its newline; an unterminated block comment at the end.
pub fn comments(text: &str) -> Vec<Range<usize>> {
    let bytes = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'"' => i = string_end(bytes, i),
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                let end = bytes[i..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .map_or(bytes.len(), |n| i + n);
                found.push(i..end);
                i = end;
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                let end = text[i + 2..].find("*/").map_or(bytes.len(), |n| i + n + 4);
                found.push(i..end);
                i = end;
            }
            _ => i += 1,
        }
    }
    found
}

/// The offset just past the string literal that opens at `start` (a
/// string cannot span lines, as in the grammar).
fn string_end(bytes: &[u8], start: usize) -> usize {
    let mut i = start + 1;
    while i < bytes.len() && bytes[i] != b'"' && bytes[i] != b'\n' {
        i += if bytes[i] == b'\\' { 2 } else { 1 };
    }
    (i + 1).min(bytes.len())
}

/// The offset of the first byte at or after `from` that is `target`,
/// outside strings and comments and at bracket depth 0; `None` if a closing
/// bracket of an outer level or the end of the text comes first.
pub fn find_at_depth0(text: &str, from: usize, target: u8) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut depth = 0usize;
    let mut i = from;
    while i < bytes.len() {
        let b = bytes[i];
        if b == target && depth == 0 {
            return Some(i);
        }
        match b {
            b'"' => {
                i = string_end(bytes, i);
                continue;
            }
            b'/' if matches!(bytes.get(i + 1), Some(b'/' | b'*')) => {
                let rest = &text[i..];
                let len = if bytes[i + 1] == b'/' {
                    rest.find('\n').unwrap_or(rest.len())
                } else {
                    rest[2..].find("*/").map_or(rest.len(), |n| n + 4)
                };
                i += len;
                continue;
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth = depth.checked_sub(1)?,
            _ => {}
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_both_comment_forms_but_not_inside_strings() {
        let text = "let a = \"x // y /* z\" // one\n/* two\n */ sphere {} /* open";
        let found: Vec<&str> = comments(text).into_iter().map(|r| &text[r]).collect();
        assert_eq!(found, ["// one", "/* two\n */", "/* open"]);
    }

    #[test]
    fn brackets_are_found_at_their_own_depth() {
        let text = "if f(\"}\") { /* } */ a (1, {}) } else {}";
        let open = find_at_depth0(text, 0, b'{').expect("the then-block");
        assert_eq!(open, 10);
        let close = find_at_depth0(text, open + 1, b'}').expect("its end");
        assert_eq!(&text[close..], "} else {}");
        assert_eq!(find_at_depth0(text, close + 1, b')'), None);
    }
}
