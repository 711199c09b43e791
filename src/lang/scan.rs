//! The byte-level pre-scan of a source file, before pest sees it: bounds
//! bracket and operator nesting (so no input can exhaust the parser's
//! stack), and finds where a long file can be cut into pieces that parse on
//! their own.

use super::diagnostics::Diagnostic;
use super::source::Span;
use crate::lang::codes::Code;

/// Deepest bracket nesting accepted in a file.
pub const MAX_NESTING: usize = 64;
/// Deepest expression tree accepted (operator chains count one per operator).
pub const MAX_EXPR_DEPTH: usize = 256;
/// The smallest piece of a file worth parsing on a core of its own.
pub const MIN_PIECE: usize = 256 * 1024;

/// Keywords that begin a top-level item and can never continue the item
/// before them (`then`, `else`, `and`, `or`, `in` and `x` are not here, nor
/// is anything an expression may begin with). A line that starts with one,
/// outside all brackets and comments, is a place to cut the file. Leaving a
/// keyword out only means fewer places to cut.
const ITEM_KEYWORDS: [&[u8]; 18] = [
    b"let",
    b"fn",
    b"param",
    b"include",
    b"render",
    b"camera",
    b"place",
    b"if",
    b"sphere",
    b"plane",
    b"box",
    b"triangle",
    b"medium",
    b"group",
    b"rect",
    b"mesh",
    b"revolve",
    b"repeat",
];

/// Refuses text whose brackets nest deeper than [`MAX_NESTING`] or whose
/// `^` or `-` chains are longer than [`MAX_EXPR_DEPTH`]. Returns the byte
/// offsets that cut the text into at most `pieces` parts of about equal
/// size, starting with 0 and ending with the text's length.
pub fn check(text: &str, file: u32, pieces: usize) -> Result<Vec<usize>, Box<Diagnostic>> {
    let bytes = text.as_bytes();
    let mut cuts = vec![0];
    let mut next_cut = bytes.len() / pieces.max(1);
    let mut depth = 0usize;
    let mut pow_run = 0usize;
    let mut neg_run = 0usize;
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_alphanumeric() || bytes[i] == b'.' || bytes[i] == b'_' {
            // Names and numbers: the common case, which only ends a run of `-`.
            neg_run = 0;
            i += 1;
            continue;
        }
        match bytes[i] {
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' && bytes[i] != b'\n' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i += 1;
            }
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(Diagnostic::error(
                        Code::TooDeep,
                        Span::new(file, i, i + 1),
                        format!("brackets nest more than {MAX_NESTING} deep"),
                    )
                    .label("this bracket is too deep")
                    .help("flatten the expression with `let` definitions")
                    .into());
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            _ => {}
        }
        let Some(&byte) = bytes.get(i) else { break };
        match byte {
            b'(' | b')' | b'[' | b']' | b'{' | b'}' | b',' => pow_run = 0,
            b'^' => pow_run += 1,
            _ => {}
        }
        match byte {
            b'-' => neg_run += 1,
            b' ' | b'\t' | b'\r' | b'\n' => {}
            _ => neg_run = 0,
        }
        if pow_run > MAX_EXPR_DEPTH || neg_run > MAX_EXPR_DEPTH {
            return Err(Diagnostic::error(
                Code::TooDeep,
                Span::new(file, i, i + 1),
                format!("more than {MAX_EXPR_DEPTH} chained `^` or `-` operators"),
            )
            .label("too deep")
            .help("split the expression into several `let` definitions")
            .into());
        }
        i += 1;
        if byte == b'\n' && depth == 0 && i >= next_cut && starts_an_item(&bytes[i..]) {
            cuts.push(i);
            next_cut = i + bytes.len() / pieces.max(1);
        }
    }
    cuts.push(bytes.len());
    Ok(cuts)
}

/// The first line start after the line holding `from` whose line begins
/// (in column 0) with an item keyword: where parsing resumes after a
/// syntax error.
pub fn next_item(text: &str, from: usize) -> Option<usize> {
    let bytes = text.as_bytes();
    let mut at = from;
    loop {
        at += bytes.get(at..)?.iter().position(|&b| b == b'\n')? + 1;
        if starts_an_item(&bytes[at..]) {
            return Some(at);
        }
    }
}

/// The start of the line (at or before `at`) that begins with an item
/// keyword in column 0, or 0: the start of the item holding `at`.
pub fn item_start(text: &str, at: usize) -> usize {
    let bytes = text.as_bytes();
    let mut line = text[..at].rfind('\n').map_or(0, |p| p + 1);
    while line > 0 && !starts_an_item(&bytes[line..]) {
        line = text[..line - 1].rfind('\n').map_or(0, |p| p + 1);
    }
    line
}

/// Whether `rest` begins with an item keyword followed by a non-name byte.
fn starts_an_item(rest: &[u8]) -> bool {
    ITEM_KEYWORDS.iter().any(|k| {
        rest.starts_with(k)
            && rest
                .get(k.len())
                .is_none_or(|b| !(b.is_ascii_alphanumeric() || *b == b'_'))
    })
}
