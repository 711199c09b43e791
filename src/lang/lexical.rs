//! Token-level checks before pest sees a file, each reported where the
//! mistake is rather than where the grammar gives up: unterminated strings
//! and block comments at their opening, letters stuck to a number, hex
//! colours without six digits, names with a letter outside ASCII, and
//! unbalanced or mismatched brackets (an
//! unclosed one at its opening, with a guess from indentation of where it
//! should close, as rustc does).

use super::diagnostics::Diagnostic;
use super::source::Span;
use crate::lang::codes::Code;

/// Every token-level problem of `text`, in source order.
pub fn check(text: &str, file: u32) -> Vec<Diagnostic> {
    let bytes = text.as_bytes();
    let span = |a: usize, b: usize| Span::new(file, a, b);
    let mut out = Vec::new();
    let mut open: Vec<(u8, usize)> = Vec::new();
    let mut brackets_ok = true;
    // The first bracket pair whose closer, alone at the start of its line,
    // is indented differently from the opener's line.
    let mut suspect: Option<(usize, usize)> = None;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'"' => {
                let start = i;
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' && bytes[i] != b'\n' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                if i >= bytes.len() || bytes[i] == b'\n' {
                    out.push(
                        Diagnostic::error(
                            Code::Syntax,
                            span(start, start + 1),
                            "unterminated string",
                        )
                        .label("this string is never closed")
                        .help("close it with `\"` on the same line; a string cannot span lines"),
                    );
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                let start = i;
                i += 2;
                while i < bytes.len() && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                if i >= bytes.len() {
                    out.push(
                        Diagnostic::error(
                            Code::Syntax,
                            span(start, start + 2),
                            "unterminated block comment",
                        )
                        .label("this comment is never closed")
                        .help("end it with `*/`"),
                    );
                }
                i += 1;
            }
            b'0'..=b'9' if i == 0 || !is_name_byte(bytes[i - 1]) && bytes[i - 1] != b'.' => {
                let end = number_end(bytes, i);
                let suffix_end = (end..bytes.len())
                    .find(|&k| !is_name_byte(bytes[k]))
                    .unwrap_or(bytes.len());
                if suffix_end > end {
                    out.push(suffix_error(text, span(end, suffix_end), &text[i..end]));
                }
                i = suffix_end.max(i + 1) - 1;
            }
            b'#' => {
                let end = (i + 1..bytes.len())
                    .find(|&k| !is_name_byte(bytes[k]))
                    .unwrap_or(bytes.len());
                let digits = &text[i + 1..end];
                if digits.len() != 6 || !digits.bytes().all(|c| c.is_ascii_hexdigit()) {
                    out.push(hex_error(span(i, end.max(i + 1)), digits));
                }
                i = end.max(i + 1) - 1;
            }
            b'(' | b'[' | b'{' if brackets_ok => open.push((b, i)),
            b')' | b']' | b'}' if brackets_ok => match open.pop() {
                Some((o, at)) if closer(o) == b => {
                    if suspect.is_none() && misindented(text, at, i) {
                        suspect = Some((at, i));
                    }
                }
                Some((o, at)) => {
                    out.push(
                        Diagnostic::error(
                            Code::Syntax,
                            span(i, i + 1),
                            format!("mismatched closing delimiter `{}`", b as char),
                        )
                        .label(format!("expected `{}` here", closer(o) as char))
                        .related(
                            span(at, at + 1),
                            format!("this `{}` is unclosed", o as char),
                        )
                        .help(format!(
                            "close the `{}` with `{}` before this `{}`",
                            o as char,
                            closer(o) as char,
                            b as char
                        )),
                    );
                    brackets_ok = false;
                }
                None => {
                    out.push(
                        Diagnostic::error(
                            Code::Syntax,
                            span(i, i + 1),
                            format!("unexpected closing delimiter `{}`", b as char),
                        )
                        .label("this closes nothing")
                        .help("remove it, or add the bracket it was meant to close"),
                    );
                    brackets_ok = false;
                }
            },
            0x80.. => {
                if let Some((d, end)) = non_ascii_name(text, file, i) {
                    out.push(d);
                    i = end - 1;
                }
            }
            _ => {}
        }
        i += 1;
    }
    // After an unterminated string or comment, bracket errors are echoes.
    if brackets_ok && out.is_empty() {
        for &(o, at) in &open {
            match suspect {
                // The unclosed bracket is most likely the inner one whose
                // closer was taken by the outer one.
                Some((inner, _)) if inner > at && bytes[inner] == o => {
                    out.push(unclosed(text, file, o, inner));
                }
                _ => out.push(unclosed(text, file, o, at)),
            }
        }
    }
    out.sort_by_key(|d| d.span.map(|s| s.start));
    out
}

/// A word holding a letter outside ASCII (`café`), at the byte `at` of
/// that letter: the error at the whole word, and where the word ends.
fn non_ascii_name(text: &str, file: u32, at: usize) -> Option<(Diagnostic, usize)> {
    let in_word = |c: char| c.is_alphanumeric() || c == '_';
    // `at` may be inside a character that is no letter: skip its bytes.
    let letter = text.get(at..)?.chars().next().filter(|c| in_word(*c))?;
    let start = text[..at]
        .char_indices()
        .rev()
        .take_while(|(_, c)| in_word(*c))
        .last()
        .map_or(at, |(k, _)| k);
    let end = text[at..]
        .char_indices()
        .find(|(_, c)| !in_word(*c))
        .map_or(text.len(), |(k, _)| at + k);
    let word = &text[start..end];
    let d = Diagnostic::error(
        Code::Syntax,
        Span::new(file, start, end),
        format!("`{word}` is not a name: `{letter}` is not an ASCII letter"),
    )
    .label("not a name")
    .help("names are ASCII letters, digits and `_`; other text belongs in strings and comments");
    Some((d, end))
}

fn is_name_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_'
}

fn closer(open: u8) -> u8 {
    match open {
        b'(' => b')',
        b'[' => b']',
        _ => b'}',
    }
}

/// The end of the number literal starting at `i` (digits, an optional
/// fraction and an optional exponent, as the grammar reads them).
fn number_end(bytes: &[u8], mut i: usize) -> usize {
    let digits = |mut k: usize| {
        while k < bytes.len() && bytes[k].is_ascii_digit() {
            k += 1;
        }
        k
    };
    i = digits(i);
    if bytes.get(i) == Some(&b'.') && bytes.get(i + 1).is_some_and(u8::is_ascii_digit) {
        i = digits(i + 1);
    }
    if matches!(bytes.get(i), Some(b'e' | b'E')) {
        let sign = usize::from(matches!(bytes.get(i + 1), Some(b'+' | b'-')));
        if bytes.get(i + 1 + sign).is_some_and(u8::is_ascii_digit) {
            i = digits(i + 1 + sign);
        }
    }
    i
}

fn suffix_error(text: &str, at: Span, number: &str) -> Diagnostic {
    let suffix = &text[at.start as usize..at.end as usize];
    let help = match suffix.strip_prefix('x') {
        Some(rest) if !rest.is_empty() && rest.bytes().all(|c| c.is_ascii_digit()) => {
            format!("write the size with spaces: `{number} x {rest}`")
        }
        _ => format!("numbers take no suffix: write `{number}`"),
    };
    Diagnostic::error(
        Code::Syntax,
        at,
        format!("invalid suffix `{suffix}` on the number `{number}`"),
    )
    .label("a letter stuck to a number")
    .help(help)
}

fn hex_error(at: Span, digits: &str) -> Diagnostic {
    let message = if digits.is_empty() {
        "`#` must be followed by a hex colour".to_string()
    } else if digits.bytes().all(|c| c.is_ascii_hexdigit()) {
        format!(
            "hex colours take 6 digits, `#{digits}` has {}",
            digits.len()
        )
    } else {
        format!("`#{digits}` is not a hex colour")
    };
    let help = match digits.len() {
        3 if digits.bytes().all(|c| c.is_ascii_hexdigit()) => {
            let long: String = digits.chars().flat_map(|c| [c, c]).collect();
            format!("hex colours take 6 digits, as in `#{long}`")
        }
        _ => "hex colours take 6 digits, as in `#ffcc00`".to_string(),
    };
    Diagnostic::error(Code::Syntax, at, message)
        .label("not `#rrggbb`")
        .help(help)
}

/// "unclosed `{`" at the bracket, with a guess from indentation: the first
/// later line indented no deeper than the bracket's own line probably
/// follows the missing closer.
fn unclosed(text: &str, file: u32, open: u8, at: usize) -> Diagnostic {
    let line_start = text[..at].rfind('\n').map_or(0, |p| p + 1);
    let indent = indentation(&text[line_start..]);
    let after = text[at..].find('\n').map_or(text.len(), |p| at + p + 1);
    let mut guess = None;
    let mut pos = after;
    for line in text[after..].split_inclusive('\n') {
        let trimmed = line.trim_start();
        let blank = trimmed.is_empty() || trimmed.starts_with("//");
        if !blank && indentation(line) <= indent {
            guess = Some(pos + (line.len() - trimmed.len()));
            break;
        }
        pos += line.len();
    }
    let c = closer(open) as char;
    let o = open as char;
    let d = Diagnostic::error(
        Code::Syntax,
        Span::new(file, at, at + 1),
        format!("unclosed `{o}`"),
    )
    .label(format!("this `{o}` is never closed"));
    match guess {
        Some(g) => {
            let word_end = text[g..]
                .find(|ch: char| ch.is_whitespace())
                .map_or(text.len(), |p| g + p);
            d.related(
                Span::new(file, g, word_end.max(g + 1).min(text.len())),
                format!("judging by the indentation, `{c}` belongs before this"),
            )
            .help(format!("add the missing `{c}`"))
        }
        None => d.help(format!("add the missing `{c}` at the end of the file")),
    }
}

/// Whether the closer at `close` starts its line at another indentation
/// than the line of the opener at `open` (on another line).
fn misindented(text: &str, open: usize, close: usize) -> bool {
    let start = |at: usize| text[..at].rfind('\n').map_or(0, |p| p + 1);
    let (o, c) = (start(open), start(close));
    if o == c || !text[c..close].trim().is_empty() {
        return false;
    }
    indentation(&text[o..]) != indentation(&text[c..])
}

/// The width of a line's leading whitespace (a tab counts as 4).
fn indentation(line: &str) -> usize {
    line.chars()
        .take_while(|c| *c == ' ' || *c == '\t')
        .map(|c| if c == '\t' { 4 } else { 1 })
        .sum()
}
