//! `rtlang check`'s diagnostics as LSP diagnostics, grouped by file, with
//! their related locations.

use std::collections::BTreeMap;

use lsp_types::{
    DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    PublishDiagnosticsParams, Uri,
};

use crate::lang::{Outcome, Severity, SourceMap, Span};

use super::position::{path_to_uri, Lines};

/// The diagnostics of one check for every file they are in; `main` (file
/// 0) is always present, so fixing the last error clears the editor's list.
pub fn publish(main: &Uri, outcome: &Outcome) -> Vec<PublishDiagnosticsParams> {
    let mut by_file: BTreeMap<u32, Vec<lsp_types::Diagnostic>> = BTreeMap::new();
    by_file.insert(0, Vec::new());
    for d in &outcome.diagnostics {
        let span = d.span.unwrap_or_default();
        let related = d
            .related
            .iter()
            .filter_map(|(s, label)| {
                Some(DiagnosticRelatedInformation {
                    location: location(main, &outcome.sources, *s)?,
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
                range: range(&outcome.sources, span),
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
        .into_iter()
        .filter_map(|(file, diagnostics)| {
            let uri = file_uri(main, &outcome.sources, file)?;
            Some(PublishDiagnosticsParams::new(uri, diagnostics, None))
        })
        .collect()
}

/// The URI of source `file` (the document's own for file 0).
fn file_uri(main: &Uri, sources: &SourceMap, file: u32) -> Option<Uri> {
    if file == 0 {
        return Some(main.clone());
    }
    let path = std::fs::canonicalize(&sources.file(file).path).ok()?;
    path_to_uri(&path)
}

fn range(sources: &SourceMap, span: Span) -> lsp_types::Range {
    let lines = Lines::new(&sources.file(span.file).text);
    lines.range(span.start as usize, span.end as usize)
}

fn location(main: &Uri, sources: &SourceMap, span: Span) -> Option<Location> {
    Some(Location::new(
        file_uri(main, sources, span.file)?,
        range(sources, span),
    ))
}
