//! Hover: the value and type of a definition, or the reference table's
//! docs of a keyword, property, function or constructor.

use lsp_types::{Hover, HoverContents, MarkupContent, MarkupKind, Uri};

use super::document::Document;
use super::index::DefKind;
use super::{reference, scope};

/// The hover text at byte `at`: of a definition in the document or in a
/// file it includes, to any depth, else of a built-in.
pub fn hover(uri: &Uri, doc: &Document, at: usize) -> Option<Hover> {
    let text = if let Some(found) = scope::resolve(uri, doc, at) {
        let def = found.def;
        let value = doc
            .values
            .get(&(found.site.file, def.name_span.start))
            .map_or("not evaluated".to_string(), Clone::clone);
        match (def.kind, &def.value) {
            (DefKind::Argument, _) => format!("`{}`: a parameter of the function", def.name),
            (DefKind::Loop, _) | (_, None) => format!("`{}`: a loop variable (a number)", def.name),
            (DefKind::Function, Some(source)) => format!("```rt\nfn {source}\n```"),
            (kind, Some(source)) => {
                let kw = if kind == DefKind::Let { "let" } else { "param" };
                format!("```rt\n{kw} {} = {source}\n```\n{value}", def.name)
            }
        }
    } else {
        let (start, end) = word_at(&doc.text, at)?;
        let word = &doc.text[start..end];
        let docs: Vec<String> = reference::lookup(word)
            .map(|e| format!("**{}** ({}): {}", e.name, e.kind, e.doc))
            .collect();
        if docs.is_empty() {
            return None;
        }
        docs.join("\n\n")
    };
    Some(Hover {
        contents: HoverContents::Markup(MarkupContent {
            kind: MarkupKind::Markdown,
            value: text,
        }),
        range: None,
    })
}

/// The bounds of the name (letters, digits, `_`) around byte `at`.
pub fn word_at(text: &str, at: usize) -> Option<(usize, usize)> {
    let bytes = text.as_bytes();
    let is_word = |b: u8| b.is_ascii_alphanumeric() || b == b'_';
    let at = at.min(bytes.len());
    let start = bytes[..at]
        .iter()
        .rposition(|&b| !is_word(b))
        .map_or(0, |i| i + 1);
    let end = bytes[at..]
        .iter()
        .position(|&b| !is_word(b))
        .map_or(bytes.len(), |i| at + i);
    (start < end).then_some((start, end))
}
