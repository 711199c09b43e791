//! Completion: the properties valid in the block under the cursor, the
//! keywords that may begin a statement there, functions and constructors
//! with their argument names, and the names in scope (also of included
//! files, and while the text has syntax errors). Right after a property
//! name only values are offered.

use lsp_types::{CompletionItem, CompletionItemKind, InsertTextFormat};

use super::document::Document;
use super::hover::word_at;
use super::reference;

/// Keywords that open a block, as the scan below tracks them.
const BLOCK_KEYWORDS: &[&str] = &[
    "sphere", "plane", "rect", "box", "triangle", "mesh", "revolve", "medium", "group", "repeat",
    "render", "camera", "motion", "place", "if",
];

/// Objects keywords.
const OBJECTS: &[&str] = &[
    "sphere", "plane", "rect", "box", "triangle", "mesh", "revolve", "medium", "group", "repeat",
];

/// Keywords that begin a value.
const VALUE_KEYWORDS: &[&str] = &["true", "false", "not", "if", "bezier"];

/// The completions at byte `at`.
pub fn complete(doc: &Document, at: usize) -> Vec<CompletionItem> {
    let block = block_at(&doc.text, at);
    if block.is_some_and(|b| after_property(&doc.text, at, b)) {
        return values(doc, at);
    }
    let mut items = Vec::new();
    let keyword = |name: &str| CompletionItem {
        label: name.to_string(),
        kind: Some(CompletionItemKind::KEYWORD),
        detail: reference::lookup(name).next().map(|e| e.doc.clone()),
        ..CompletionItem::default()
    };
    let Some(block) = block else {
        for e in reference::entries() {
            if e.kind == "keyword" && e.valid_in("top") {
                items.push(keyword(e.name));
            }
        }
        items.extend(OBJECTS.iter().chain(&["place", "if"]).map(|k| keyword(k)));
        return items;
    };
    for e in reference::entries() {
        if e.kind == "property" && e.valid_in(block) {
            items.push(CompletionItem {
                label: e.name.to_string(),
                kind: Some(CompletionItemKind::PROPERTY),
                detail: Some(e.doc.clone()),
                ..CompletionItem::default()
            });
        }
    }
    let transforms = !matches!(block, "render" | "camera" | "if");
    if transforms {
        items.extend(
            ["translate", "rotate", "scale", "matrix", "flip", "motion"]
                .iter()
                .map(|k| keyword(k)),
        );
    }
    if matches!(block, "group" | "repeat" | "if") {
        items.extend(OBJECTS.iter().chain(&["place", "if"]).map(|k| keyword(k)));
    }
    items.extend(values(doc, at));
    items
}

/// Whether byte `at` is where a property's value goes: after a property
/// name of `block` (and the partial word being typed) that is not itself
/// the value of a property before it.
fn after_property(text: &str, at: usize, block: &str) -> bool {
    let at = at.min(text.len());
    let start = word_at(text, at).map_or(at, |(start, _)| start.min(at));
    let Some((name_start, name_end)) = word_before(text, start) else {
        return false;
    };
    // `material glass ` is after a value, `radius 1 material ` is not.
    is_property(&text[name_start..name_end], block)
        && word_before(text, name_start).is_none_or(|(s, e)| !is_property(&text[s..e], block))
}

/// The word (`start`, `end`) that ends where the spaces before `at` begin
/// (on the same line; none if no space comes before `at`).
fn word_before(text: &str, at: usize) -> Option<(usize, usize)> {
    let before = text[..at].trim_end_matches([' ', '\t']);
    if before.len() == at {
        // No space between that word and `at`.
        return None;
    }
    word_at(text, before.len())
}

fn is_property(word: &str, block: &str) -> bool {
    reference::lookup(word).any(|e| e.kind == "property" && e.valid_in(block))
}

/// What may begin a value: the names in scope, the predefined ones,
/// functions and constructors, and the keywords that begin values.
fn values(doc: &Document, at: usize) -> Vec<CompletionItem> {
    let mut items: Vec<CompletionItem> = VALUE_KEYWORDS
        .iter()
        .map(|k| CompletionItem {
            label: k.to_string(),
            kind: Some(CompletionItemKind::KEYWORD),
            detail: reference::lookup(k).next().map(|e| e.doc.clone()),
            ..CompletionItem::default()
        })
        .collect();
    items.extend(crate::lang::PREDEFINED.iter().map(|n| CompletionItem {
        label: n.to_string(),
        kind: Some(CompletionItemKind::CONSTANT),
        ..CompletionItem::default()
    }));
    for e in reference::entries() {
        if let (true, Some(sig)) = (
            matches!(e.kind, "function" | "texture" | "material"),
            e.signature(),
        ) {
            items.push(CompletionItem {
                label: e.name.to_string(),
                kind: Some(match e.kind {
                    "function" => CompletionItemKind::FUNCTION,
                    _ => CompletionItemKind::CONSTRUCTOR,
                }),
                detail: Some(sig.to_string()),
                documentation: Some(lsp_types::Documentation::String(e.doc.clone())),
                insert_text: Some(format!("{}($0)", e.name)),
                insert_text_format: Some(InsertTextFormat::SNIPPET),
                ..CompletionItem::default()
            });
        }
    }
    // The document's names (and those a syntax error hides for now), then
    // the top-level names of the files it includes.
    let included = doc
        .included
        .iter()
        .flat_map(|i| i.index.defs.iter().filter(|d| !d.kind.is_scoped()));
    let mut seen = std::collections::HashSet::new();
    for def in doc.index.in_scope(at).chain(&doc.recalled).chain(included) {
        if seen.insert(def.name.as_str()) {
            items.push(CompletionItem {
                label: def.name.clone(),
                kind: Some(CompletionItemKind::VARIABLE),
                detail: def.value.clone(),
                ..CompletionItem::default()
            });
        }
    }
    items
}

/// The keyword of the innermost block open at byte `at`, found by a scan of
/// the text (so it works while the text does not parse): each `{` belongs
/// to the last block keyword before it.
pub fn block_at(text: &str, at: usize) -> Option<&'static str> {
    let mut comments = crate::lang::trivia::comments(text).into_iter().peekable();
    let bytes = text.as_bytes();
    let mut stack: Vec<Option<&'static str>> = Vec::new();
    let mut pending = None;
    let mut i = 0;
    let at = at.min(bytes.len());
    while i < at {
        while comments.next_if(|c| c.start < i).is_some() {}
        if let Some(c) = comments.next_if(|c| c.start == i) {
            i = c.end;
            continue;
        }
        match bytes[i] {
            b'"' => {
                i += 1;
                while i < at && bytes[i] != b'"' && bytes[i] != b'\n' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
            }
            b'{' => stack.push(pending.take()),
            b'}' => {
                stack.pop();
            }
            b if b.is_ascii_alphabetic() || b == b'_' => {
                let end = bytes[i..]
                    .iter()
                    .position(|b| !(b.is_ascii_alphanumeric() || *b == b'_'))
                    .map_or(bytes.len(), |n| i + n);
                let word = &text[i..end];
                if word == "else" {
                    pending = Some("if");
                } else if let Some(k) = BLOCK_KEYWORDS.iter().find(|k| **k == word) {
                    pending = Some(k);
                }
                i = end;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    stack.pop().flatten()
}

#[cfg(test)]
mod tests {
    use super::block_at;

    #[test]
    fn the_block_under_the_cursor_is_found_in_text_that_does_not_parse() {
        let text =
            "render { samples 4 }\nmedium { boundary sphere { rad\n  }\n  den /* { */ \"{\" \n";
        let at = |needle: &str| text.find(needle).expect("in the text") + needle.len();
        assert_eq!(block_at(text, at("samples")), Some("render"));
        assert_eq!(block_at(text, at("rad")), Some("sphere"));
        assert_eq!(block_at(text, at("den")), Some("medium"));
        assert_eq!(block_at(text, 0), None);
    }
}
