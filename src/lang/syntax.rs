//! Parsing: source text → [`ast::File`] with byte spans, through the pest
//! grammar in `grammar/rtlang.pest`, after the limits of [`scan`].
//!
//! pest is called for 32 items at a time (its state and line index are
//! built per call). A file of at least two [`scan::MIN_PIECE`]s is cut at
//! item starts into one piece per thread, parsed with rayon and joined in
//! order; if any piece fails, the whole file is parsed again in one piece so
//! that errors read the same. After a syntax error the parse resumes at the
//! next item ([`scan::next_item`]), up to ten errors. Expressions with no
//! operator skip the Pratt parser.

use crate::lang::codes::Code;
use std::sync::LazyLock;

use pest::iterators::{Pair, Pairs};
use pest::pratt_parser::{Assoc, Op, PrattParser};
use pest::Parser;
use rayon::prelude::*;

use super::ast::*;
use super::diagnostics::Diagnostic;
use super::lexical;
use super::names;
use super::scan::{self, MAX_EXPR_DEPTH};
use super::source;

#[derive(pest_derive::Parser)]
#[grammar = "grammar/rtlang.pest"]
struct Grammar;

static PRATT: LazyLock<PrattParser<Rule>> = LazyLock::new(|| {
    PrattParser::new()
        .op(Op::infix(Rule::or, Assoc::Left))
        .op(Op::infix(Rule::and, Assoc::Left))
        .op(Op::prefix(Rule::not))
        .op(Op::infix(Rule::lt, Assoc::Left)
            | Op::infix(Rule::le, Assoc::Left)
            | Op::infix(Rule::gt, Assoc::Left)
            | Op::infix(Rule::ge, Assoc::Left)
            | Op::infix(Rule::eq, Assoc::Left)
            | Op::infix(Rule::ne, Assoc::Left))
        .op(Op::infix(Rule::add, Assoc::Left) | Op::infix(Rule::sub, Assoc::Left))
        .op(Op::infix(Rule::mul, Assoc::Left) | Op::infix(Rule::div, Assoc::Left))
        .op(Op::prefix(Rule::neg))
        .op(Op::infix(Rule::pow, Assoc::Right))
});

/// At most this many syntax errors are reported for one file; later ones
/// are mostly echoes of the earlier.
pub const MAX_SYNTAX_ERRORS: usize = 10;

/// A file parsed with recovery: the items that parsed, the syntax errors
/// (each item that failed is skipped to the next item boundary), and the
/// problems found while lowering (bad escapes, too-deep expressions).
pub struct Parsed {
    pub file: File,
    pub syntax_errors: Vec<Diagnostic>,
    pub problems: Vec<Diagnostic>,
}

/// Parses a whole file. On a syntax error returns the first one; lowering
/// problems (bad escapes, too-deep expressions) are returned alongside the
/// tree. [`parse_all`] keeps every syntax error.
pub fn parse_file(text: &str, file: u32) -> Result<(File, Vec<Diagnostic>), Box<Diagnostic>> {
    let parsed = parse_all(text, file);
    match parsed.syntax_errors.into_iter().next() {
        Some(first) => Err(Box::new(first)),
        None => Ok((parsed.file, parsed.problems)),
    }
}

/// Parses a whole file, reporting every syntax error: token-level ones
/// ([`lexical::check`]) and each grammar error, with parsing resumed at the
/// next item boundary (items holding a token-level error are skipped).
///
/// A long file is cut where [`scan::check`] finds an item boundary and the
/// pieces are parsed on all cores; the result is the same as one sequential
/// parse, which is what runs (and reports the errors) when any piece fails.
pub fn parse_all(text: &str, file: u32) -> Parsed {
    let bom = source::bom_len(text);
    if bom > 0 {
        // Spaces in place of the mark keep every offset into the file.
        return parse_all(&format!("{:bom$}{}", "", &text[bom..]), file);
    }
    let failed = |errors: Vec<Diagnostic>| Parsed {
        file: File::default(),
        syntax_errors: errors,
        problems: Vec::new(),
    };
    let pieces = (text.len() / scan::MIN_PIECE).clamp(1, rayon::current_num_threads());
    let cuts = match scan::check(text, file, pieces) {
        Ok(cuts) => cuts,
        Err(d) => return failed(vec![*d]),
    };
    let lexical = lexical::check(text, file);
    if !lexical.is_empty() {
        return failed(with_grammar_errors(text, file, lexical));
    }
    if cuts.len() > 2 {
        let parsed: Result<Vec<_>, _> = cuts
            .par_windows(2)
            .map(|w| parse_range(text, file, w[0], w[1]))
            .collect();
        if let Ok(parsed) = parsed {
            let mut items = Vec::with_capacity(parsed.iter().map(|(f, _)| f.items.len()).sum());
            let mut problems = Vec::new();
            for (piece, found) in parsed {
                items.extend(piece.items);
                problems.extend(found);
            }
            return Parsed {
                file: File { items },
                syntax_errors: Vec::new(),
                problems,
            };
        }
    }
    parse_recovering(text, file)
}

/// The token-level errors of a file followed (in source order) by the
/// grammar errors of the items they do not touch: each item holding a
/// token-level error is blanked (offsets kept) and the rest is parsed with
/// recovery, so a later unrelated syntax error is reported in the same run.
/// At most [`MAX_SYNTAX_ERRORS`] in all.
fn with_grammar_errors(text: &str, file: u32, lexical: Vec<Diagnostic>) -> Vec<Diagnostic> {
    let mut blanked = text.as_bytes().to_vec();
    for d in &lexical {
        let at = d.span.map_or(0, |s| s.start as usize).min(text.len());
        let start = scan::item_start(text, at);
        let end = scan::next_item(text, at).unwrap_or(text.len());
        for b in &mut blanked[start..end] {
            if *b != b'\n' {
                *b = b' ';
            }
        }
    }
    // Only ASCII bytes were written, over whole bytes of the valid text.
    let blanked = String::from_utf8_lossy(&blanked);
    let mut errors = lexical;
    errors.extend(parse_recovering(&blanked, file).syntax_errors);
    errors.sort_by_key(|d| d.span.map(|s| s.start));
    if let Some(next) = errors.get(MAX_SYNTAX_ERRORS).and_then(|d| d.span) {
        errors.truncate(MAX_SYNTAX_ERRORS);
        errors.push(stopped(Span::new(
            file,
            next.start as usize,
            next.start as usize,
        )));
    }
    errors
}

/// The note that ends a file's list of syntax errors at the cap.
fn stopped(at: Span) -> Diagnostic {
    Diagnostic::error(
        Code::Syntax,
        at,
        format!("stopped after {MAX_SYNTAX_ERRORS} syntax errors"),
    )
    .label("not parsed from here on")
    .help("fix the errors above first; later ones are often caused by them")
}

/// Parses the items in `text[start..end]`, with spans in the whole file;
/// stops at the first syntax error.
fn parse_range(
    text: &str,
    file: u32,
    start: usize,
    end: usize,
) -> Result<(File, Vec<Diagnostic>), Box<Diagnostic>> {
    let mut lower = Lower {
        file,
        offset: start,
        diagnostics: Vec::new(),
    };
    let mut items = Vec::with_capacity((end - start) / 64);
    while lower.offset < end {
        let rest = &text[lower.offset..end];
        let batch = Grammar::parse(Rule::next_items, rest)
            .map_err(|e| Box::new(syntax_error(e, text, file, lower.offset)))?
            .next()
            .map(|p| p.into_inner());
        let Some(consumed) = lower.items(batch, &mut items) else {
            break;
        };
        lower.offset += consumed;
    }
    Ok((File { items }, lower.diagnostics))
}

/// Parses the whole file, resuming after each syntax error at the next
/// line that begins an item, up to [`MAX_SYNTAX_ERRORS`].
fn parse_recovering(text: &str, file: u32) -> Parsed {
    let mut lower = Lower {
        file,
        offset: 0,
        diagnostics: Vec::new(),
    };
    let mut items = Vec::new();
    let mut errors = Vec::new();
    while lower.offset < text.len() {
        let rest = &text[lower.offset..];
        // A batch that fails is parsed again one item at a time, so the
        // items before the error are kept.
        let parsed = match Grammar::parse(Rule::next_items, rest) {
            Ok(pairs) => Ok(pairs),
            Err(_) => Grammar::parse(Rule::one_item, rest),
        };
        match parsed {
            Ok(mut pairs) => {
                let batch = pairs.next().map(|p| p.into_inner());
                let Some(consumed) = lower.items(batch, &mut items) else {
                    break;
                };
                lower.offset += consumed;
            }
            Err(e) => {
                let d = syntax_error(e, text, file, lower.offset);
                let at = d.span.map_or(lower.offset, |s| s.start as usize);
                errors.push(d);
                let item_start = text.len() - rest.trim_start().len();
                // An error that blames the end of the item before (`let c =
                // cylinder {`) makes that item part of the broken one.
                let broken = match items.last().map(Item::span) {
                    Some(last) if at < item_start && at < last.end as usize => {
                        items.pop();
                        last.start as usize
                    }
                    _ => item_start,
                };
                items.extend(placeholder(text, file, broken));
                let resume = scan::next_item(text, at.max(item_start));
                if errors.len() >= MAX_SYNTAX_ERRORS {
                    if let Some(resume) = resume {
                        errors.push(stopped(Span::new(file, resume, resume)));
                    }
                    break;
                }
                match resume {
                    Some(resume) => lower.offset = resume,
                    None => break,
                }
            }
        }
    }
    Parsed {
        file: File { items },
        syntax_errors: errors,
        problems: lower.diagnostics,
    }
}

/// For a `let` or `param` that failed to parse, a definition whose value
/// is an error, so its uses give no follow-on "unknown name" errors; for a
/// `fn` whose body failed, the function with its parameters and an error
/// as its body, so its calls give no "unknown function" errors.
fn placeholder(text: &str, file: u32, at: usize) -> Option<Item> {
    let rest = &text[at..];
    if rest.starts_with("fn") {
        return fn_placeholder(text, file, at).map(Item::Fn);
    }
    let (kw, after) = if let Some(r) = rest.strip_prefix("let") {
        ("let", r)
    } else {
        ("param", rest.strip_prefix("param")?)
    };
    let trimmed = after.trim_start();
    let name_len = trimmed
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(trimmed.len());
    if trimmed.len() == after.len() || name_len == 0 {
        return None;
    }
    let start = at + kw.len() + (after.len() - trimmed.len());
    let span = Span::new(file, start, start + name_len);
    let name = Ident {
        name: trimmed[..name_len].to_string(),
        span,
    };
    let value = Expr {
        kind: ExprKind::Error,
        span,
    };
    Some(if kw == "let" {
        Item::Let { name, value, span }
    } else {
        Item::Param { name, value, span }
    })
}

/// The head `fn NAME(PARAMS)` at `at` parsed with a stand-in body; `None`
/// when the error is in the head itself.
fn fn_placeholder(text: &str, file: u32, at: usize) -> Option<Function> {
    let open = at + text[at..].find('(')?;
    let mut depth = 0usize;
    let close = text[open..].char_indices().find_map(|(i, c)| {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            _ => {}
        }
        (depth == 0).then_some(open + i)
    })?;
    // The head keeps its offsets; `0` stands in for the body that failed.
    let head = format!("{} = 0", &text[at..=close]);
    let pair = Grammar::parse(Rule::one_item, &head)
        .ok()?
        .next()?
        .into_inner()
        .next()?;
    if pair.as_rule() != Rule::fn_item {
        return None;
    }
    let mut lower = Lower {
        file,
        offset: at,
        diagnostics: Vec::new(),
    };
    let mut f = lower.function(pair);
    let span = Span::new(file, at, close + 1);
    f.body = Expr {
        kind: ExprKind::Error,
        span,
    };
    f.span = span;
    Some(f)
}

/// Parses a single expression (a `-D` value), or returns its syntax errors.
pub fn parse_expr(text: &str, file: u32) -> Result<Expr, Vec<Diagnostic>> {
    scan::check(text, file, 1).map_err(|d| vec![*d])?;
    let lexical = lexical::check(text, file);
    if !lexical.is_empty() {
        return Err(lexical);
    }
    let mut pairs = Grammar::parse(Rule::define_value, text)
        .map_err(|e| vec![syntax_error(e, text, file, 0)])?;
    let mut lower = Lower {
        file,
        offset: 0,
        diagnostics: Vec::new(),
    };
    let inner = pairs.next().and_then(|p| p.into_inner().next());
    let Some(inner) = inner else {
        return Err(Vec::new());
    };
    let expr = lower.expr(inner);
    if lower.diagnostics.is_empty() {
        Ok(expr)
    } else {
        Err(lower.diagnostics)
    }
}

/// Turns pest's error into a diagnostic with words a user understands.
/// `offset` is where the parsed text starts in the file `text`.
fn syntax_error(
    error: pest::error::Error<Rule>,
    text: &str,
    file: u32,
    offset: usize,
) -> Diagnostic {
    let (start, end) = match error.location {
        pest::error::InputLocation::Pos(p) => (offset + p, offset + p),
        pest::error::InputLocation::Span((s, e)) => (offset + s, offset + e),
    };
    if let Some(d) = hint(text, file, start) {
        return d;
    }
    let message = match &error.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } if !positives.is_empty() => {
            let mut names: Vec<String> = positives
                .iter()
                .map(|r| rule_name(*r).to_string())
                .collect();
            names.sort();
            names.dedup();
            format!("expected {}", join_or(&names))
        }
        pest::error::ErrorVariant::ParsingError { .. } => "unexpected input".to_string(),
        pest::error::ErrorVariant::CustomError { message } => message.clone(),
    };
    Diagnostic::error(Code::Syntax, Span::new(file, start, end), message)
        .label("here")
        .help("see docs/language.md for the syntax of each statement")
}

/// "missing `,`" when the bracket at `at` holds two values separated only
/// by spaces, as in `(0 1 0)`.
fn missing_comma(text: &str, file: u32, at: usize) -> Option<Diagnostic> {
    let line_end = text[at..].find('\n').map_or(text.len(), |p| at + p);
    let inner = &text[at + 1..line_end];
    if inner.trim_start().starts_with("if ") {
        return None;
    }
    let mut depth = 0usize;
    let mut prev_value_end = None;
    for (i, c) in inner.char_indices() {
        match c {
            '(' | '[' => depth += 1,
            ')' | ']' if depth == 0 => return None,
            ')' | ']' => depth -= 1,
            _ => {}
        }
        if depth > 0 && c != ')' && c != ']' {
            continue;
        }
        if c.is_whitespace() {
            continue;
        }
        let starts_value = c.is_ascii_alphanumeric() || c == '(' || c == '"' || c == '#';
        if let Some(end) = prev_value_end {
            let gap = &inner[end..i];
            let word = &inner[i..];
            let is_op = ["and", "or", "not"].iter().any(|w| word.starts_with(w));
            if starts_value && !gap.is_empty() && gap.trim().is_empty() && !is_op {
                let start = at + 1 + end;
                return Some(
                    Diagnostic::error(
                        Code::Syntax,
                        Span::new(file, start, at + 1 + i),
                        "missing `,` between two values",
                    )
                    .label("a comma belongs here")
                    .help("separate the components of a vector with commas: `(0, 1, 0)`"),
                );
            }
        }
        prev_value_end =
            (c.is_ascii_alphanumeric() || c == ')' || c == ']' || c == '"' || c == '_')
                .then(|| i + c.len_utf8());
    }
    None
}

/// Object keywords, for "did you mean" where a statement starts.
const OBJECTS: &[&str] = &[
    "sphere",
    "plane",
    "rect",
    "box",
    "triangle",
    "mesh",
    "revolve",
    "medium",
    "group",
    "repeat",
    "sun",
    "point_light",
    "spot_light",
];

/// A specific message for the common mistakes at a syntax error at `at`:
/// an unknown word before `{`, `=` or `:` after a property name, commas
/// and semicolons between statements.
fn hint(text: &str, file: u32, at: usize) -> Option<Diagnostic> {
    if let Some(d) = rotate_without_angle(text, file, at) {
        return Some(d);
    }
    if let Some(d) = rect_without_plane(text, file, at) {
        return Some(d);
    }
    let bytes = text.as_bytes();
    let word_at = |i: usize| {
        let end = (i..bytes.len())
            .find(|&k| !(bytes[k].is_ascii_alphanumeric() || bytes[k] == b'_'))
            .unwrap_or(bytes.len());
        (end > i && bytes[i].is_ascii_alphabetic()).then_some(end)
    };
    // The word just before `at` (spaces skipped), if any.
    let before = text[..at].trim_end();
    let prev_start = before
        .char_indices()
        .rev()
        .find(|(_, c)| !(c.is_ascii_alphanumeric() || *c == '_'))
        .map_or(0, |(p, c)| p + c.len_utf8());
    let prev = &before[prev_start..];
    let next_non_space = |i: usize| text[i..].trim_start().bytes().next();
    let c = *bytes.get(at)?;
    // `spehre { ... }`: a word where an object or statement should start.
    let word = match word_at(at) {
        Some(end) if next_non_space(end) == Some(b'{') => Some((at, end)),
        _ if c == b'{' && !prev.is_empty() && !names::is_keyword(prev) => {
            Some((prev_start, before.len()))
        }
        _ => None,
    };
    if let Some((ws, we)) = word {
        let w = &text[ws..we];
        if !names::is_keyword(w) && w.bytes().next().is_some_and(|b| b.is_ascii_alphabetic()) {
            let help = match names::suggest(w, OBJECTS.iter().copied()) {
                Some(s) => format!("did you mean `{s}`?"),
                None => format!("objects are {}", OBJECTS.join(", ")),
            };
            return Some(
                Diagnostic::error(
                    Code::Syntax,
                    Span::new(file, ws, we),
                    format!("unknown object `{w}`"),
                )
                .label("not an object keyword")
                .help(help),
            );
        }
    }
    let span = Span::new(file, at, at + 1);
    let head = text[..prev_start].trim_end_matches([' ', '\t']);
    let starts_line = head.is_empty() || head.ends_with(['\n', '{']);
    // `Shape "sphere"`, `for i in ...`: a word that begins no statement.
    if let Some(end) = word_at(at) {
        let w = &text[at..end];
        let line_head = text[..at].trim_end_matches([' ', '\t']);
        if !names::is_keyword(w) && (line_head.is_empty() || line_head.ends_with('\n')) {
            let help = match w {
                "for" | "while" => "loops are written `repeat i in 0..10 { ... }`".to_string(),
                _ => match names::suggest(&w.to_lowercase(), OBJECTS.iter().copied()) {
                    Some(s) => format!("did you mean `{s} {{ ... }}`?"),
                    None => "a statement begins with `let`, `param`, `fn`, `include`, `render`, \
                             `camera`, `place` or an object keyword"
                        .to_string(),
                },
            };
            return Some(
                Diagnostic::error(
                    Code::Syntax,
                    Span::new(file, at, end),
                    format!("`{w}` does not begin a statement"),
                )
                .label("not a statement")
                .help(help),
            );
        }
    }
    match c {
        b'=' | b':'
            if (starts_line || is_property(prev))
                && !prev.is_empty()
                && bytes.get(at + 1) != Some(&b'=') =>
        {
            let value = text[at + 1..].lines().next().unwrap_or("");
            let value = value.trim().trim_end_matches('}').trim_end();
            Some(
                Diagnostic::error(
                    Code::Syntax,
                    span,
                    format!("unexpected `{}` after `{prev}`", c as char),
                )
                .label("not needed")
                .help(format!(
                    "a property is its name and its value: write `{prev} {value}`"
                )),
            )
        }
        b',' if prev.bytes().all(|b| b.is_ascii_digit() || b == b'.')
            && !prev.is_empty()
            && text[at + 1..]
                .trim_start_matches([' ', '\t'])
                .starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '.')
            && [
                "translate",
                "scale",
                "center",
                "from",
                "at",
                "min",
                "max",
                "normal",
            ]
            .iter()
            .any(|k| head.trim_end_matches('-').trim_end().ends_with(k)) =>
        {
            Some(
                Diagnostic::error(Code::Syntax, span, "a vector without its parentheses")
                    .label("`,` outside a vector")
                    .help("write vectors in parentheses: `(x, y, z)`"),
            )
        }
        b'<' => Some(
            Diagnostic::error(Code::Syntax, span, "unexpected `<`")
                .label("not a vector bracket")
                .help("vectors are written `(x, y, z)`, not POV-Ray's `<x, y, z>`"),
        ),
        b',' => Some(
            Diagnostic::error(Code::Syntax, span, "unexpected `,`")
                .label("not a separator here")
                .help("statements and properties are not separated by commas: remove it"),
        ),
        b'+' | b'*' | b'/' | b'^' => {
            let dangling = text[at + 1..]
                .lines()
                .next()
                .is_none_or(|l| l.trim().is_empty());
            let (label, help) = if dangling {
                (
                    "nothing follows it on this line",
                    "finish the expression after the operator on the same line, or remove the operator",
                )
            } else {
                (
                    "no left operand",
                    "an expression cannot start with an operator",
                )
            };
            Some(
                Diagnostic::error(Code::Syntax, span, format!("unexpected `{}`", c as char))
                    .label(label)
                    .help(help),
            )
        }
        b'(' => missing_comma(text, file, at),
        b';' => Some(
            Diagnostic::error(Code::Syntax, span, "unexpected `;`")
                .label("not needed")
                .help("statements end at the end of their value: remove it"),
        ),
        _ => None,
    }
}

/// `rotate y material m`: an axis without its angle, so the next property's
/// name was read as the angle and the error came later on the line. Blames
/// the property name, where the angle is missing.
fn rotate_without_angle(text: &str, file: u32, at: usize) -> Option<Diagnostic> {
    let line_start = text[..at].rfind('\n').map_or(0, |p| p + 1);
    let line = &text[line_start..at];
    let kw = line.rfind("rotate ")?;
    let starts_word = line[..kw]
        .chars()
        .next_back()
        .is_none_or(|c| !(c.is_ascii_alphanumeric() || c == '_'));
    let after_kw = kw + "rotate ".len();
    let rest = line[after_kw..].trim_start();
    let axis = rest.split_whitespace().next()?;
    if !starts_word || !matches!(axis, "x" | "y" | "z") {
        return None;
    }
    let after_axis = &rest[1..];
    let word = after_axis.split_whitespace().next()?;
    if !is_property(word) {
        return None;
    }
    let start = line_start + (line.len() - after_axis.len()) + after_axis.find(word)?;
    Some(
        Diagnostic::error(
            Code::Syntax,
            Span::new(file, start, start + word.len()),
            format!("`rotate {axis}` has no angle"),
        )
        .label(format!("`{word}` read as the angle"))
        .help(format!(
            "give the angle in degrees after the axis, as in `rotate {axis} 45`"
        )),
    )
}

/// `rect xw { ... }`: the word after `rect` at `at` is not one of its
/// planes (or there is none before the block).
fn rect_without_plane(text: &str, file: u32, at: usize) -> Option<Diagnostic> {
    const PLANES: [&str; 3] = ["xy", "xz", "yz"];
    let before = text[..at].trim_end();
    let kw = before.strip_suffix("rect")?;
    if kw.ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_') {
        return None;
    }
    let rest = &text[at..];
    let len = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    let word = &rest[..len];
    let (span, message, help) = if word.is_empty() {
        (
            Span::new(file, at, at + rest.chars().next().map_or(0, char::len_utf8)),
            "`rect` without its plane".to_string(),
            "write the plane before the block, as in `rect xz { ... }`".to_string(),
        )
    } else {
        let help = match names::suggest(&word.to_ascii_lowercase(), PLANES) {
            Some(s) => format!("did you mean `rect {s}`?"),
            None => "write the plane before the block, as in `rect xz { ... }`".to_string(),
        };
        (
            Span::new(file, at, at + len),
            format!("`{word}` is not a plane of `rect`"),
            help,
        )
    };
    Some(
        Diagnostic::error(Code::Syntax, span, message)
            .label("`rect` takes a plane: `xy`, `xz` or `yz`")
            .help(help),
    )
}

/// Whether `word` is the name of a property of some block.
fn is_property(word: &str) -> bool {
    crate::lang::properties::TABLE
        .iter()
        .any(|b| b.props.iter().any(|p| p.name == word))
}

fn join_or(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} or {}", rest.join(", "), last),
    }
}

/// The words for a grammar rule in syntax errors.
fn rule_name(rule: Rule) -> &'static str {
    match rule {
        Rule::EOI => "end of file",
        Rule::next_items => "a statement",
        Rule::item | Rule::let_item | Rule::param_item | Rule::include_item => "a statement",
        Rule::fn_item | Rule::kw_fn => "a statement",
        Rule::fn_param => "a parameter",
        Rule::render_item | Rule::camera_item => "a statement",
        Rule::block => "`{`",
        Rule::stmt | Rule::property | Rule::size_prop | Rule::shutter_prop | Rule::mode_prop => {
            "a property"
        }
        Rule::translate | Rule::rotate | Rule::scale | Rule::matrix | Rule::motion => "a transform",
        Rule::place => "`place`",
        Rule::object | Rule::simple_object | Rule::shape_kw => "an object",
        Rule::rect_object | Rule::mesh_object | Rule::revolve_object | Rule::repeat_object => {
            "an object"
        }
        Rule::rect_plane => "a plane (`xy`, `xz` or `yz`)",
        Rule::axis => "an axis",
        Rule::expr | Rule::primary | Rule::prefix | Rule::neg | Rule::not => "an expression",
        Rule::if_expr => "an expression",
        Rule::infix | Rule::add | Rule::sub | Rule::mul | Rule::div | Rule::pow => "an operator",
        Rule::lt | Rule::le | Rule::gt | Rule::ge | Rule::eq | Rule::ne => "an operator",
        Rule::and | Rule::or => "an operator",
        Rule::if_stmt | Rule::kw_if => "an object",
        Rule::kw_then => "`then`",
        Rule::flip => "a property",
        Rule::kw_else => "`else`",
        Rule::call | Rule::callee => "a call",
        Rule::arg | Rule::kwarg => "an argument",
        Rule::vector => "a vector",
        Rule::list => "a list `[...]`",
        Rule::bezier | Rule::kw_bezier => "`bezier`",
        Rule::name | Rule::ident => "a name",
        Rule::number => "a number",
        Rule::string => "a string",
        Rule::boolean => "`true` or `false`",
        Rule::hex_color => "a colour `#rrggbb`",
        Rule::kw_x => "`x`",
        Rule::stmt_keyword => "a property",
        Rule::prim_keyword => "a name",
        Rule::kw_translate
        | Rule::kw_rotate
        | Rule::kw_scale
        | Rule::kw_matrix
        | Rule::kw_motion => "a transform",
        Rule::kw_place | Rule::kw_size | Rule::kw_shutter | Rule::kw_mode => "a property",
        Rule::kw_rect | Rule::kw_mesh | Rule::kw_revolve | Rule::kw_repeat => "an object",
        Rule::kw_let | Rule::kw_param | Rule::kw_include | Rule::kw_render | Rule::kw_camera => {
            "a statement"
        }
        Rule::mode_name => "`mesh` or `analytic`",
        Rule::kw_in => "`in`",
        _ => "a keyword",
    }
}

/// The pest pairs → AST pass; collects the few problems found here.
struct Lower {
    file: u32,
    /// Where the text pest is parsing starts in the file.
    offset: usize,
    diagnostics: Vec<Diagnostic>,
}

impl Lower {
    /// Lowers a batch of items into `out`; returns how far the batch
    /// reached from `self.offset`, or `None` when it held no item.
    fn items(&mut self, batch: Option<Pairs<Rule>>, out: &mut Vec<Item>) -> Option<usize> {
        let mut consumed = None;
        for pair in batch.into_iter().flatten() {
            if pair.as_rule() == Rule::EOI {
                break;
            }
            consumed = Some(pair.as_span().end());
            out.push(self.item(pair));
        }
        consumed
    }

    fn span(&self, pair: &Pair<Rule>) -> Span {
        let s = pair.as_span();
        Span::new(self.file, self.offset + s.start(), self.offset + s.end())
    }

    fn ident(&self, pair: Pair<Rule>) -> Ident {
        Ident {
            name: pair.as_str().to_string(),
            span: self.span(&pair),
        }
    }

    fn item(&mut self, pair: Pair<Rule>) -> Item {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.clone().into_inner();
        match rule {
            Rule::let_item | Rule::param_item => {
                inner.next();
                let name = self.ident(next(&mut inner));
                let value = self.expr(next(&mut inner));
                if rule == Rule::let_item {
                    Item::Let { name, value, span }
                } else {
                    Item::Param { name, value, span }
                }
            }
            Rule::fn_item => Item::Fn(self.function(pair)),
            Rule::include_item => {
                inner.next();
                let path = self.string(next(&mut inner));
                Item::Include { path, span }
            }
            Rule::render_item => {
                inner.next();
                Item::Render {
                    body: self.block(next(&mut inner)),
                    span,
                }
            }
            Rule::camera_item => {
                inner.next();
                Item::Camera {
                    body: self.block(next(&mut inner)),
                    span,
                }
            }
            _ => Item::Stmt(self.stmt(pair)),
        }
    }

    /// `fn NAME(params) = EXPR` or `fn NAME(params) { ... }`.
    fn function(&mut self, pair: Pair<Rule>) -> Function {
        let span = self.span(&pair);
        let mut inner = pair.into_inner();
        inner.next();
        let name = self.ident(next(&mut inner));
        let mut params = Vec::new();
        let mut body = None;
        for p in inner {
            match p.as_rule() {
                Rule::fn_param => {
                    let mut kv = p.into_inner();
                    let name = self.ident(next(&mut kv));
                    let default = kv.next().map(|d| self.expr(d));
                    params.push(Param { name, default });
                }
                Rule::block => {
                    let block_span = self.span(&p);
                    let object = Object {
                        kind: ObjectKind::Group,
                        body: self.block(p),
                        span: block_span,
                        head: name.span,
                    };
                    body = Some((ExprKind::Object(Box::new(object)), block_span, true));
                }
                _ => {
                    let e = self.expr(p);
                    body = Some((e.kind, e.span, false));
                }
            }
        }
        let (kind, body_span, block) =
            body.unwrap_or_else(|| unreachable!("the grammar guarantees a body"));
        Function {
            name,
            params,
            body: Expr {
                kind,
                span: body_span,
            },
            block,
            span,
        }
    }

    /// The arguments of a call, positional or `name: value`.
    fn args(&mut self, pairs: Pairs<Rule>) -> Vec<Arg> {
        pairs
            .map(|a| {
                if a.as_rule() == Rule::kwarg {
                    let mut kv = a.into_inner();
                    let name = self.ident(next(&mut kv));
                    Arg {
                        name: Some(name),
                        value: self.expr(next(&mut kv)),
                    }
                } else {
                    Arg {
                        name: None,
                        value: self.expr(a),
                    }
                }
            })
            .collect()
    }

    fn block(&mut self, pair: Pair<Rule>) -> Vec<Stmt> {
        pair.into_inner().map(|p| self.stmt(p)).collect()
    }

    fn stmt(&mut self, pair: Pair<Rule>) -> Stmt {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.clone().into_inner();
        match rule {
            Rule::property => {
                let name = self.ident(next(&mut inner));
                let value = self.expr(next(&mut inner));
                Stmt::Property { name, value, span }
            }
            Rule::mode_prop => {
                let name = self.ident(next(&mut inner));
                let arg = next(&mut inner);
                let value = if arg.as_rule() == Rule::mode_name {
                    Expr {
                        kind: ExprKind::Name(arg.as_str().to_string()),
                        span: self.span(&arg),
                    }
                } else {
                    self.expr(arg)
                };
                Stmt::Property { name, value, span }
            }
            Rule::size_prop => {
                inner.next();
                let width = self.expr(next(&mut inner));
                inner.next();
                let height = self.expr(next(&mut inner));
                Stmt::Size {
                    width,
                    height,
                    span,
                }
            }
            Rule::shutter_prop => {
                inner.next();
                let open = self.expr(next(&mut inner));
                let close = self.expr(next(&mut inner));
                Stmt::Shutter { open, close, span }
            }
            Rule::motion => {
                inner.next();
                Stmt::Motion {
                    body: self.block(next(&mut inner)),
                    span,
                }
            }
            Rule::place => {
                inner.next();
                let target = next(&mut inner);
                let (name, args) = if target.as_rule() == Rule::call {
                    let mut call = target.into_inner();
                    let name = self.ident(next(&mut call));
                    (name, Some(self.args(call)))
                } else {
                    (self.ident(target), None)
                };
                let body = inner.next().map(|b| self.block(b)).unwrap_or_default();
                Stmt::Place {
                    name,
                    args,
                    body,
                    span,
                }
            }
            Rule::object => Stmt::Object(self.object(pair)),
            Rule::flip => Stmt::Flip { span },
            Rule::if_stmt => {
                inner.next();
                let cond = self.expr(next(&mut inner));
                let then = self.block(next(&mut inner));
                inner.next();
                let otherwise = match inner.next() {
                    Some(p) if p.as_rule() == Rule::if_stmt => vec![self.stmt(p)],
                    Some(p) => self.block(p),
                    None => Vec::new(),
                };
                Stmt::If {
                    cond,
                    then,
                    otherwise,
                    span,
                }
            }
            _ => Stmt::Transform(self.transform(pair)),
        }
    }

    fn transform(&mut self, pair: Pair<Rule>) -> Transform {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        inner.next();
        let first = next(&mut inner);
        let kind = match rule {
            Rule::translate => TransformKind::Translate(self.expr(first)),
            Rule::scale => TransformKind::Scale(self.expr(first)),
            Rule::matrix => TransformKind::Matrix(self.expr(first)),
            _ if first.as_rule() == Rule::axis => {
                let axis = match first.as_str() {
                    "x" => Axis::X,
                    "y" => Axis::Y,
                    _ => Axis::Z,
                };
                TransformKind::RotateAxis(axis, self.expr(next(&mut inner)))
            }
            _ => {
                let axis = self.expr(first);
                let angle = self.expr(next(&mut inner));
                self.swapped_rotate(axis, angle)
            }
        };
        Transform { kind, span }
    }

    /// `rotate 45 y`: the angle before the axis. Reported at the angle and
    /// read as `rotate y 45`, so no follow-on type or name errors come.
    fn swapped_rotate(&mut self, axis: Expr, angle: Expr) -> TransformKind {
        let named_axis = match &angle.kind {
            ExprKind::Name(n) if n == "x" => Some(Axis::X),
            ExprKind::Name(n) if n == "y" => Some(Axis::Y),
            ExprKind::Name(n) if n == "z" => Some(Axis::Z),
            _ => None,
        };
        let (Some(named), ExprKind::Number(degrees)) = (named_axis, &axis.kind) else {
            return TransformKind::Rotate(axis, angle);
        };
        let letter = ["x", "y", "z"][named as usize];
        self.diagnostics.push(
            Diagnostic::error(
                Code::Syntax,
                axis.span,
                format!("the axis comes first: `rotate {letter} {degrees}`"),
            )
            .label("an angle where the axis belongs")
            .help(format!(
                "write the axis, then the angle in degrees: `rotate {letter} {degrees}`"
            )),
        );
        TransformKind::RotateAxis(named, axis)
    }

    fn object(&mut self, pair: Pair<Rule>) -> Object {
        let span = self.span(&pair);
        let pair = next(&mut pair.into_inner());
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let keyword = next(&mut inner);
        let mut head = self.span(&keyword);
        let kind = match rule {
            Rule::simple_object => match keyword.as_str() {
                "sphere" => ObjectKind::Sphere,
                "plane" => ObjectKind::Plane,
                "box" => ObjectKind::Box,
                "triangle" => ObjectKind::Triangle,
                "medium" => ObjectKind::Medium,
                "sun" => ObjectKind::Sun,
                "point_light" => ObjectKind::PointLight,
                "spot_light" => ObjectKind::SpotLight,
                _ => ObjectKind::Group,
            },
            Rule::rect_object => {
                let plane = next(&mut inner);
                head = head.to(self.span(&plane));
                ObjectKind::Rect(match plane.as_str() {
                    "xy" => RectPlane::Xy,
                    "xz" => RectPlane::Xz,
                    _ => RectPlane::Yz,
                })
            }
            Rule::mesh_object | Rule::revolve_object => {
                let arg = self.primary(next(&mut inner));
                head = head.to(arg.span);
                if rule == Rule::mesh_object {
                    ObjectKind::Mesh(arg)
                } else {
                    ObjectKind::Revolve(arg)
                }
            }
            _ => {
                let var = self.ident(next(&mut inner));
                inner.next();
                let from = self.expr(next(&mut inner));
                let to = self.expr(next(&mut inner));
                head = head.to(to.span);
                ObjectKind::Repeat { var, from, to }
            }
        };
        let body = inner.next().map(|b| self.block(b)).unwrap_or_default();
        Object {
            kind,
            body,
            span,
            head,
        }
    }

    fn expr(&mut self, pair: Pair<Rule>) -> Expr {
        let mut inner = pair.into_inner();
        if inner.len() == 1 {
            // One primary and no operator, as most expressions in large files.
            return self.primary(next(&mut inner));
        }
        let (file, offset) = (self.file, self.offset);
        let cell = std::cell::RefCell::new(std::mem::take(&mut self.diagnostics));
        let result = PRATT
            .map_primary(|p| {
                let mut lower = Lower {
                    file,
                    offset,
                    diagnostics: Vec::new(),
                };
                let e = lower.primary(p);
                cell.borrow_mut().extend(lower.diagnostics);
                e
            })
            .map_prefix(|op, rhs| {
                let span = Span::new(file, offset + op.as_span().start(), 0).to(rhs.span);
                let shape = shape_of(&[&rhs]);
                let not = op.as_rule() == Rule::not;
                bounded(&cell, span, shape, move || {
                    if not {
                        ExprKind::Not(Box::new(rhs))
                    } else {
                        ExprKind::Neg(Box::new(rhs))
                    }
                })
            })
            .map_infix(|lhs, op, rhs| {
                let span = lhs.span.to(rhs.span);
                let bin = match op.as_rule() {
                    Rule::add => BinOp::Add,
                    Rule::sub => BinOp::Sub,
                    Rule::mul => BinOp::Mul,
                    Rule::div => BinOp::Div,
                    Rule::lt => BinOp::Lt,
                    Rule::le => BinOp::Le,
                    Rule::gt => BinOp::Gt,
                    Rule::ge => BinOp::Ge,
                    Rule::eq => BinOp::Eq,
                    Rule::ne => BinOp::Ne,
                    Rule::and => BinOp::And,
                    Rule::or => BinOp::Or,
                    _ => BinOp::Pow,
                };
                let shape = shape_of(&[&lhs, &rhs]);
                bounded(&cell, span, shape, move || {
                    ExprKind::Binary(bin, Box::new(lhs), Box::new(rhs))
                })
            })
            .parse(inner);
        self.diagnostics = cell.into_inner();
        result
    }

    fn primary(&mut self, pair: Pair<Rule>) -> Expr {
        let span = self.span(&pair);
        let kind = match pair.as_rule() {
            Rule::number => match pair.as_str().parse::<f64>() {
                Ok(v) if v.is_finite() => ExprKind::Number(v),
                _ => {
                    self.diagnostics.push(
                        Diagnostic::error(Code::Number, span, "number out of range")
                            .label("not a finite number")
                            .help("numbers must fit in a 64-bit float"),
                    );
                    ExprKind::Error
                }
            },
            Rule::string => ExprKind::Str(self.string(pair)),
            Rule::boolean => ExprKind::Bool(pair.as_str() == "true"),
            Rule::hex_color => ExprKind::Hex(pair.as_str()[1..].to_string()),
            Rule::name => ExprKind::Name(pair.as_str().to_string()),
            Rule::vector => ExprKind::Tuple(self.exprs(pair.into_inner())),
            Rule::list => ExprKind::List(self.exprs(pair.into_inner())),
            Rule::bezier => {
                let list = pair.into_inner().nth(1).map(|l| l.into_inner());
                ExprKind::Bezier(list.map(|l| self.exprs(l)).unwrap_or_default())
            }
            Rule::object => ExprKind::Object(Box::new(self.object(pair))),
            Rule::if_expr => {
                let mut inner = pair.into_inner();
                inner.next();
                let cond = self.expr(next(&mut inner));
                inner.next();
                let then = self.expr(next(&mut inner));
                inner.next();
                let otherwise = self.expr(next(&mut inner));
                ExprKind::If(Box::new(cond), Box::new(then), Box::new(otherwise))
            }
            Rule::call => {
                let mut inner = pair.into_inner();
                let callee = self.ident(next(&mut inner));
                let args = self.args(inner);
                ExprKind::Call { callee, args }
            }
            _ => ExprKind::Error,
        };
        Expr { kind, span }
    }

    fn exprs(&mut self, pairs: Pairs<Rule>) -> Vec<Expr> {
        pairs.map(|p| self.expr(p)).collect()
    }

    /// The value of a string literal with its escapes resolved.
    fn string(&mut self, pair: Pair<Rule>) -> String {
        let raw = pair.as_str();
        let body = &raw[1..raw.len() - 1];
        let mut out = String::with_capacity(body.len());
        let mut chars = body.char_indices();
        while let Some((i, c)) = chars.next() {
            if c != '\\' {
                out.push(c);
                continue;
            }
            match chars.next() {
                Some((_, '"')) => out.push('"'),
                Some((_, '\\')) => out.push('\\'),
                Some((_, 'n')) => out.push('\n'),
                Some((_, 't')) => out.push('\t'),
                other => {
                    let start = self.offset + pair.as_span().start() + 1 + i;
                    let end = start + 1 + other.map_or(0, |(_, c)| c.len_utf8());
                    self.diagnostics.push(
                        Diagnostic::error(
                            Code::BadEscape,
                            Span::new(self.file, start, end),
                            "unknown escape in string",
                        )
                        .label("not an escape")
                        .help("strings know `\\\"`, `\\\\`, `\\n` and `\\t`"),
                    );
                }
            }
        }
        out
    }
}

/// Builds a node unless it would make the tree deeper than
/// [`MAX_EXPR_DEPTH`]; then reports once and returns an error leaf.
fn bounded(
    diagnostics: &std::cell::RefCell<Vec<Diagnostic>>,
    span: Span,
    (deepest, has_error): (usize, bool),
    build: impl FnOnce() -> ExprKind,
) -> Expr {
    if has_error {
        return Expr {
            kind: ExprKind::Error,
            span,
        };
    }
    if deepest + 1 > MAX_EXPR_DEPTH {
        diagnostics.borrow_mut().push(
            Diagnostic::error(
                Code::TooDeep,
                span,
                format!("expression is more than {MAX_EXPR_DEPTH} operators deep"),
            )
            .label("too deep")
            .help("split it into several `let` definitions"),
        );
        return Expr {
            kind: ExprKind::Error,
            span,
        };
    }
    Expr {
        kind: build(),
        span,
    }
}

/// The deepest child and whether any child is an error leaf.
fn shape_of(children: &[&Expr]) -> (usize, bool) {
    let deepest = children.iter().map(|c| depth(c)).max().unwrap_or(0);
    (deepest, children.iter().any(|c| c.kind == ExprKind::Error))
}

/// Depth of an expression's operator spine (the only part that can be long
/// without brackets).
fn depth(e: &Expr) -> usize {
    let mut d = 0;
    let mut stack = vec![(e, 1usize)];
    while let Some((e, level)) = stack.pop() {
        d = d.max(level);
        match &e.kind {
            ExprKind::Neg(x) | ExprKind::Not(x) => stack.push((x, level + 1)),
            ExprKind::Binary(_, a, b) => {
                stack.push((a, level + 1));
                stack.push((b, level + 1));
            }
            _ => {}
        }
    }
    d
}

fn next<'a>(pairs: &mut Pairs<'a, Rule>) -> Pair<'a, Rule> {
    pairs
        .next()
        .unwrap_or_else(|| unreachable!("the grammar guarantees this child"))
}
