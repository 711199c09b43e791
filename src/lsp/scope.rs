//! Names across a document and the files it includes, to any depth: once
//! included files are spliced in, the scene is one scope, so a top-level
//! name defined in any of them is visible in all (a loop variable or a
//! parameter only in its own file).

use lsp_types::{Location, Uri};

use super::document::Document;
use super::index::{Def, Index};
use super::position::{path_to_uri, Lines};

/// One file of the scene: the document itself or a file it includes.
pub struct Site<'a> {
    pub uri: Uri,
    pub text: &'a str,
    pub index: &'a Index,
    /// Its id in the document's last check (0 for the document).
    pub file: u32,
}

impl Site<'_> {
    /// The location of bytes `start..end` of this file.
    pub fn location(&self, lines: &Lines, span: crate::lang::Span) -> Location {
        Location::new(
            self.uri.clone(),
            lines.range(span.start as usize, span.end as usize),
        )
    }
}

/// The document, then each file its last check included.
pub fn sites<'a>(uri: &Uri, doc: &'a Document) -> impl Iterator<Item = Site<'a>> {
    let own = Site {
        uri: uri.clone(),
        text: &doc.text,
        index: &doc.index,
        file: 0,
    };
    let included = doc.included.iter().filter_map(|i| {
        Some(Site {
            uri: path_to_uri(&i.path)?,
            text: &i.text,
            index: &i.index,
            file: i.file,
        })
    });
    std::iter::once(own).chain(included)
}

/// A definition and the file it is in.
pub struct Found<'a> {
    pub site: Site<'a>,
    pub def: &'a Def,
}

/// The definition the name at byte `at` of the document means: one of its
/// own, else a top-level one of a file it includes.
pub fn resolve<'a>(uri: &Uri, doc: &'a Document, at: usize) -> Option<Found<'a>> {
    let mut sites = sites(uri, doc);
    let own = sites.next()?;
    if let Some(def) = doc.index.resolve(at) {
        return Some(Found { site: own, def });
    }
    let (start, end) = super::hover::word_at(&doc.text, at)?;
    let name = &doc.text[start..end];
    sites.find_map(|site| {
        let def = site
            .index
            .defs
            .iter()
            .find(|d| d.name == name && !d.kind.is_scoped())?;
        Some(Found { site, def })
    })
}

/// Every occurrence of `found`'s definition in the document and the files
/// it includes: a loop variable's or parameter's in its own file, a
/// top-level name's wherever a use of it is not a loop variable or
/// parameter of the same name.
pub fn occurrences(uri: &Uri, doc: &Document, found: &Found) -> Vec<Location> {
    let own = Lines::new(found.site.text);
    let def = found.def;
    if def.kind.is_scoped() {
        return found
            .site
            .index
            .occurrences(def)
            .into_iter()
            .map(|s| found.site.location(&own, s))
            .collect();
    }
    let mut out = vec![found.site.location(&own, def.name_span)];
    for site in sites(uri, doc) {
        let global = |(n, s): &&(String, crate::lang::Span)| {
            *n == def.name
                && site
                    .index
                    .lookup(n, s.start as usize)
                    .is_none_or(|d| !d.kind.is_scoped())
        };
        let spans: Vec<_> = site.index.uses.iter().filter(global).collect();
        if spans.is_empty() {
            continue;
        }
        let lines = Lines::new(site.text);
        out.extend(spans.into_iter().map(|(_, s)| site.location(&lines, *s)));
    }
    out
}
