//! The document outline (lets, params, objects, camera, render) and the
//! semantic tokens of a file.

use lsp_types::{DocumentSymbol, SemanticToken, SemanticTokenType, SymbolKind};

use super::document::Document;
use super::position::{Lines, Walker};

/// The outline of the document.
#[allow(deprecated)] // `DocumentSymbol::deprecated` must be named to build one.
pub fn outline(doc: &Document) -> Vec<DocumentSymbol> {
    let lines = Lines::new(&doc.text);
    doc.index
        .outline
        .iter()
        .map(|(name, kind, span)| {
            let range = lines.range(span.start as usize, span.end as usize);
            DocumentSymbol {
                name: name.clone(),
                detail: Some(kind.to_string()),
                kind: match *kind {
                    "let" => SymbolKind::VARIABLE,
                    "param" => SymbolKind::CONSTANT,
                    "object" => SymbolKind::OBJECT,
                    _ => SymbolKind::MODULE,
                },
                tags: None,
                deprecated: None,
                range,
                selection_range: range,
                children: None,
            }
        })
        .collect()
}

/// The token types, in the order of their indices in [`tokens`].
pub const TOKEN_TYPES: [SemanticTokenType; 8] = [
    SemanticTokenType::KEYWORD,
    SemanticTokenType::COMMENT,
    SemanticTokenType::STRING,
    SemanticTokenType::NUMBER,
    SemanticTokenType::FUNCTION,
    SemanticTokenType::PROPERTY,
    SemanticTokenType::VARIABLE,
    SemanticTokenType::OPERATOR,
];

/// The starts of `spans` in increasing order, for [`Starts::take`].
struct Starts(std::iter::Peekable<std::vec::IntoIter<usize>>);

impl Starts {
    fn new(spans: &[crate::lang::Span]) -> Starts {
        let mut starts: Vec<usize> = spans.iter().map(|s| s.start as usize).collect();
        starts.sort_unstable();
        Starts(starts.into_iter().peekable())
    }

    /// Whether one of the starts is `at`; asked with increasing `at`, so
    /// the starts are walked once in all.
    fn take(&mut self, at: usize) -> bool {
        while self.0.next_if(|&s| s < at).is_some() {}
        self.0.next_if_eq(&at).is_some()
    }
}

/// The semantic tokens of the document, relative-encoded as LSP wants, in
/// time linear in the text (a 20 MB document is one walk).
pub fn tokens(doc: &Document) -> Vec<SemanticToken> {
    let text: &str = &doc.text;
    let bytes = text.as_bytes();
    let comments = crate::lang::trivia::comments(text);
    let mut properties = Starts::new(&doc.index.properties);
    let mut callees = Starts::new(&doc.index.callees);
    let mut found: Vec<(usize, usize, u32)> = Vec::new();
    let mut comments = comments.into_iter().peekable();
    let mut i = 0;
    while i < bytes.len() {
        while comments.next_if(|c| c.start < i).is_some() {}
        if let Some(c) = comments.next_if(|c| c.start == i) {
            found.push((c.start, c.end, 1));
            i = c.end;
            continue;
        }
        let b = bytes[i];
        let run = |pred: &dyn Fn(u8) -> bool| {
            bytes[i..]
                .iter()
                .position(|&b| !pred(b))
                .map_or(bytes.len(), |n| i + n)
        };
        let (end, kind) = match b {
            b'"' => {
                let mut j = i + 1;
                while j < bytes.len() && bytes[j] != b'"' && bytes[j] != b'\n' {
                    j += if bytes[j] == b'\\' { 2 } else { 1 };
                }
                ((j + 1).min(bytes.len()), Some(2))
            }
            b'0'..=b'9' | b'#' => (
                run(&|b| b.is_ascii_alphanumeric() || b == b'.' || b == b'#'),
                Some(3),
            ),
            b if b.is_ascii_alphabetic() || b == b'_' => {
                let end = run(&|b| b.is_ascii_alphanumeric() || b == b'_');
                let word = &text[i..end];
                let kind = if crate::lang::names::is_keyword(word) {
                    0
                } else if callees.take(i) {
                    4
                } else if properties.take(i) {
                    5
                } else {
                    6
                };
                (end, Some(kind))
            }
            b'+' | b'-' | b'*' | b'/' | b'^' | b'<' | b'>' | b'=' | b'!' => (i + 1, Some(7)),
            _ => (i + 1, None),
        };
        if let Some(kind) = kind {
            found.push((i, end, kind));
        }
        i = end;
    }
    encode(text, &found)
}

/// LSP's relative encoding; a token spanning lines is cut at each line end.
/// The tokens come in text order, so one [`Walker`] converts them all.
fn encode(text: &str, found: &[(usize, usize, u32)]) -> Vec<SemanticToken> {
    let mut out = Vec::new();
    let mut walker = Walker::new(text);
    let (mut line, mut col) = (0, 0);
    for &(start, end, kind) in found {
        let mut from = start;
        let Some(token) = text.get(start..end) else {
            continue;
        };
        for piece in token.split_inclusive('\n') {
            let to = from + piece.trim_end_matches(['\n', '\r']).len();
            let a = walker.position(from);
            let b = walker.position(to);
            if b.character > a.character {
                let delta_line = a.line - line;
                let delta_start = if delta_line == 0 {
                    a.character - col
                } else {
                    a.character
                };
                out.push(SemanticToken {
                    delta_line,
                    delta_start,
                    length: b.character - a.character,
                    token_type: kind,
                    token_modifiers_bitset: 0,
                });
                (line, col) = (a.line, a.character);
            }
            from += piece.len();
        }
    }
    out
}
