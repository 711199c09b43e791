//! Go to definition (names and `include` paths), find references and
//! rename.

use std::collections::HashMap;
use std::path::Path;

use lsp_types::{Location, TextEdit, Uri, WorkspaceEdit};

use crate::lang::syntax;

use super::document::Document;
use super::index::{contains, Index};
use super::position::{path_to_uri, Lines};

/// Where the name or `include` at byte `at` is defined.
pub fn definition(uri: &Uri, doc: &Document, at: usize) -> Option<Location> {
    let lines = Lines::new(&doc.text);
    if let Some(def) = doc.index.resolve(at) {
        let range = lines.range(def.name_span.start as usize, def.name_span.end as usize);
        return Some(Location::new(uri.clone(), range));
    }
    let dir = doc.path.parent().unwrap_or(Path::new(""));
    if let Some((path, _)) = doc.index.includes.iter().find(|(_, s)| contains(*s, at)) {
        let target = std::fs::canonicalize(dir.join(path)).ok()?;
        return Some(Location::new(path_to_uri(&target)?, Default::default()));
    }
    let (start, end) = super::hover::word_at(&doc.text, at)?;
    included_definition(dir, &doc.index, &doc.text[start..end])
}

/// A top-level definition of `name` in a file this one includes.
fn included_definition(dir: &Path, index: &Index, name: &str) -> Option<Location> {
    index.includes.iter().find_map(|(path, _)| {
        let target = std::fs::canonicalize(dir.join(path)).ok()?;
        let text = crate::lang::read_scene_text(&target).ok()?;
        let (ast, _) = syntax::parse_file(&text, 0).ok()?;
        let def = Index::new(&ast)
            .defs
            .into_iter()
            .find(|d| d.name == name && !d.kind.is_scoped())?;
        let range =
            Lines::new(&text).range(def.name_span.start as usize, def.name_span.end as usize);
        Some(Location::new(path_to_uri(&target)?, range))
    })
}

/// Every occurrence of the definition under byte `at`.
pub fn references(uri: &Uri, doc: &Document, at: usize, declaration: bool) -> Vec<Location> {
    let Some(def) = doc.index.resolve(at) else {
        return Vec::new();
    };
    let lines = Lines::new(&doc.text);
    doc.index
        .occurrences(def)
        .into_iter()
        .filter(|s| declaration || *s != def.name_span)
        .map(|s| Location::new(uri.clone(), lines.range(s.start as usize, s.end as usize)))
        .collect()
}

/// Renames the definition under byte `at` and all its uses.
pub fn rename(uri: &Uri, doc: &Document, at: usize, new_name: &str) -> Option<WorkspaceEdit> {
    let def = doc.index.resolve(at)?;
    let lines = Lines::new(&doc.text);
    let edits = doc
        .index
        .occurrences(def)
        .into_iter()
        .map(|s| {
            TextEdit::new(
                lines.range(s.start as usize, s.end as usize),
                new_name.to_string(),
            )
        })
        .collect();
    Some(WorkspaceEdit::new(HashMap::from([(uri.clone(), edits)])))
}
