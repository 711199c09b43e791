//! `rtlang check`'s diagnostics as LSP diagnostics, grouped by file, with
//! their related locations; an error in an included file is also shown at
//! the `include` line of the document that brings it in.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use lsp_types::{
    DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    PublishDiagnosticsParams, Uri,
};

use crate::lang::{Outcome, Severity, SourceMap, Span};

use super::document::Document;
use super::position::{path_to_uri, Lines};

/// The most errors of an included file listed as related information of
/// its `include` line.
const MAX_RELATED: usize = 20;

/// The diagnostics of one check of `doc` for every file they are in;
/// `main` (file 0) is always present, so fixing the last error clears the
/// editor's list.
pub fn publish(main: &Uri, doc: &Document, outcome: &Outcome) -> Vec<PublishDiagnosticsParams> {
    let ranges = &mut Ranges::new(&outcome.sources);
    let mut by_file: BTreeMap<u32, Vec<lsp_types::Diagnostic>> = BTreeMap::new();
    by_file.insert(0, Vec::new());
    for d in &outcome.diagnostics {
        let span = d.span.unwrap_or_default();
        let related = d
            .related
            .iter()
            .filter_map(|(s, label)| {
                Some(DiagnosticRelatedInformation {
                    location: location(main, ranges, *s)?,
                    message: label.clone(),
                })
            })
            .collect::<Vec<_>>();
        let mut message = d.message.clone();
        if let Some(help) = &d.help {
            message = format!("{message}\nhelp: {help}");
        }
        by_file
            .entry(span.file)
            .or_default()
            .push(lsp_types::Diagnostic {
                range: ranges.range(span),
                severity: Some(match d.severity {
                    Severity::Error => DiagnosticSeverity::ERROR,
                    Severity::Warning => DiagnosticSeverity::WARNING,
                }),
                code: Some(NumberOrString::String(d.code.to_string())),
                source: Some("rtlang".to_string()),
                message,
                related_information: (!related.is_empty()).then_some(related),
                ..lsp_types::Diagnostic::default()
            });
    }
    by_file
        .entry(0)
        .or_default()
        .extend(at_includes(main, doc, outcome, ranges));
    by_file
        .into_iter()
        .filter_map(|(file, diagnostics)| {
            let uri = file_uri(main, &outcome.sources, file)?;
            let version = (file == 0).then_some(doc.version);
            Some(PublishDiagnosticsParams::new(uri, diagnostics, version))
        })
        .collect()
}

/// One error at each `include` line of the document through which errors
/// of included files (at any depth) came in, with those errors as related
/// information.
fn at_includes(
    main: &Uri,
    doc: &Document,
    outcome: &Outcome,
    ranges: &mut Ranges,
) -> Vec<lsp_types::Diagnostic> {
    let errors: Vec<(u32, &crate::lang::Diagnostic)> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .filter_map(|d| Some((d.span?.file, d)).filter(|(f, _)| *f != 0))
        .collect();
    if errors.is_empty() {
        return Vec::new();
    }
    let parents = include_parents(doc);
    let mut by_line: BTreeMap<(u32, u32), Vec<&crate::lang::Diagnostic>> = BTreeMap::new();
    for (mut file, d) in errors {
        // Up the chain of includes to the document's own `include` item.
        let mut steps = 0;
        while let Some(&(parent, span)) = parents.get(&file) {
            if parent == 0 {
                by_line.entry((span.start, span.end)).or_default().push(d);
                break;
            }
            file = parent;
            steps += 1;
            if steps > parents.len() {
                break;
            }
        }
    }
    let lines = Lines::new(&doc.text);
    by_line
        .into_iter()
        .map(|((start, end), found)| {
            let first = found[0].message.lines().next().unwrap_or_default();
            let more = match found.len() {
                1 => String::new(),
                n => format!(" (and {} more)", n - 1),
            };
            let related = found
                .iter()
                .take(MAX_RELATED)
                .filter_map(|d| {
                    Some(DiagnosticRelatedInformation {
                        location: location(main, ranges, d.span?)?,
                        message: d.message.clone(),
                    })
                })
                .collect();
            lsp_types::Diagnostic {
                range: lines.range(start as usize, end as usize),
                severity: Some(DiagnosticSeverity::ERROR),
                code: Some(NumberOrString::String("rtlang::included-error".to_string())),
                source: Some("rtlang".to_string()),
                message: format!("the included file has an error: {first}{more}"),
                related_information: Some(related),
                ..lsp_types::Diagnostic::default()
            }
        })
        .collect()
}

/// For each included file of the document's last check (by id), the file
/// whose `include` item brought it in first and that item's span.
fn include_parents(doc: &Document) -> HashMap<u32, (u32, Span)> {
    let by_path: HashMap<&Path, u32> = doc
        .included
        .iter()
        .map(|i| (i.path.as_path(), i.file))
        .collect();
    let files = std::iter::once((0, doc.path.as_path(), &doc.index)).chain(
        doc.included
            .iter()
            .map(|i| (i.file, i.path.as_path(), &i.index)),
    );
    let mut parents = HashMap::new();
    for (file, path, index) in files {
        let dir = path.parent().unwrap_or(Path::new(""));
        for (rel, span) in &index.includes {
            let Ok(target) = std::fs::canonicalize(dir.join(rel)) else {
                continue;
            };
            if let Some(&child) = by_path.get(target.as_path()) {
                parents.entry(child).or_insert((file, *span));
            }
        }
    }
    parents
}

/// The URI of source `file` (the document's own for file 0).
fn file_uri(main: &Uri, sources: &SourceMap, file: u32) -> Option<Uri> {
    if file == 0 {
        return Some(main.clone());
    }
    let path = std::fs::canonicalize(&sources.file(file).path).ok()?;
    path_to_uri(&path)
}

/// The line index of each file, built once for all of a check's
/// diagnostics (one per diagnostic is quadratic in a file with many).
struct Ranges<'a> {
    sources: &'a SourceMap,
    lines: HashMap<u32, Lines<'a>>,
}

impl<'a> Ranges<'a> {
    fn new(sources: &'a SourceMap) -> Ranges<'a> {
        Ranges {
            sources,
            lines: HashMap::new(),
        }
    }

    fn range(&mut self, span: Span) -> lsp_types::Range {
        let sources = self.sources;
        self.lines
            .entry(span.file)
            .or_insert_with(|| Lines::new(&sources.file(span.file).text))
            .range(span.start as usize, span.end as usize)
    }
}

fn location(main: &Uri, ranges: &mut Ranges, span: Span) -> Option<Location> {
    Some(Location::new(
        file_uri(main, ranges.sources, span.file)?,
        ranges.range(span),
    ))
}
