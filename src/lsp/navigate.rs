//! Go to definition (names and `include` paths), find references and
//! rename.

use std::collections::HashMap;
use std::path::Path;

use lsp_types::{Location, TextEdit, Uri, WorkspaceEdit};

use super::document::Document;
use super::index::contains;
use super::position::{path_to_uri, Lines};
use super::scope;

/// Where the name or `include` at byte `at` is defined: in the document or
/// in a file it includes, to any depth.
pub fn definition(uri: &Uri, doc: &Document, at: usize) -> Option<Location> {
    if let Some((path, _)) = doc.index.includes.iter().find(|(_, s)| contains(*s, at)) {
        let dir = doc.path.parent().unwrap_or(Path::new(""));
        let target = std::fs::canonicalize(dir.join(path)).ok()?;
        return Some(Location::new(path_to_uri(&target)?, Default::default()));
    }
    let found = scope::resolve(uri, doc, at)?;
    let lines = Lines::new(found.site.text);
    Some(found.site.location(&lines, found.def.name_span))
}

/// Every occurrence of the definition under byte `at`, in the document
/// and the files it includes.
pub fn references(uri: &Uri, doc: &Document, at: usize, declaration: bool) -> Vec<Location> {
    let Some(found) = scope::resolve(uri, doc, at) else {
        return Vec::new();
    };
    let mut all = scope::occurrences(uri, doc, &found);
    if !declaration {
        // The declaration comes first.
        all.remove(0);
    }
    all
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
