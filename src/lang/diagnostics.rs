//! Diagnostics of the language: a plain record with a stable code, spans and
//! a help line, rendered as miette reports (graphical) or as JSON.

use std::fmt;
use std::sync::Arc;

use miette::{LabeledSpan, MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents};
use serde::Serialize;

use super::codes::Code;
use super::source::{self, SourceMap, Span};

/// How bad a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Error,
    Warning,
}

/// One problem found in a scene, with where it is and how to fix it.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    /// A stable code; its text is such as `rtlang::unknown-name`.
    pub code: Code,
    pub message: String,
    /// The main location; `None` for problems outside any file (a bad `-D`).
    pub span: Option<Span>,
    /// What the underline of the main span says.
    pub label: String,
    /// Further locations (for example the first of two duplicate definitions).
    pub related: Vec<(Span, String)>,
    pub help: Option<String>,
    /// Context lines printed after the help (`note: ...`), such as the loop
    /// values or the include chain that led to the problem.
    pub notes: Vec<String>,
}

impl Diagnostic {
    /// An error with code `code` at `span`.
    pub fn error(code: Code, span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            code,
            message: message.into(),
            span: Some(span),
            label: String::new(),
            related: Vec::new(),
            help: None,
            notes: Vec::new(),
        }
    }

    /// A warning with code `code` at `span`.
    pub fn warning(code: Code, span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, span, message)
        }
    }

    /// An error that points at no source text.
    pub fn global(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            span: None,
            ..Diagnostic::error(code, Span::default(), message)
        }
    }

    /// Sets the label under the main span.
    pub fn label(mut self, label: impl Into<String>) -> Diagnostic {
        self.label = label.into();
        self
    }

    /// Sets the help line.
    pub fn help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Adds a note line.
    pub fn note(mut self, note: impl Into<String>) -> Diagnostic {
        self.notes.push(note.into());
        self
    }

    /// Adds a secondary labelled location.
    pub fn related(mut self, span: Span, label: impl Into<String>) -> Diagnostic {
        self.related.push((span, label.into()));
        self
    }

    /// Whether this is an error (not a warning).
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// A miette report that renders this diagnostic with its source.
    pub fn to_report(&self, sources: &SourceMap) -> miette::Report {
        let source = self.span.map(|span| Text::new(sources, span.file));
        let mut labels = Vec::new();
        let mut elsewhere = Vec::new();
        if let Some(span) = self.span {
            labels.push(LabeledSpan::new_primary_with_span(
                Some(self.label.clone()).filter(|l| !l.is_empty()),
                to_source_span(span),
            ));
            for (other, text) in &self.related {
                if other.file == span.file && *other != span {
                    labels.push(LabeledSpan::new_with_span(
                        Some(text.clone()),
                        to_source_span(*other),
                    ));
                } else if other.file != span.file {
                    elsewhere.push(Elsewhere::new(sources, *other, text));
                }
            }
        }
        miette::Report::new(Rendered {
            diagnostic: self.clone(),
            source,
            labels,
            elsewhere,
        })
    }

    /// The machine-readable form printed by `rtlang check --format json`.
    pub fn to_json(&self, sources: &SourceMap) -> serde_json::Value {
        let (file, line, column, span) = match self.span {
            Some(s) => {
                let f = sources.file(s.file);
                let (line, column) = f.line_col(s.start as usize);
                (
                    Some(f.name.clone()),
                    Some(line),
                    Some(column),
                    Some([s.start, s.end]),
                )
            }
            None => (None, None, None, None),
        };
        let labels: Vec<serde_json::Value> = self
            .related
            .iter()
            .map(|(s, label)| {
                let f = sources.file(s.file);
                let (line, column) = f.line_col(s.start as usize);
                serde_json::json!({
                    "file": f.name,
                    "line": line,
                    "column": column,
                    "span": [s.start, s.end],
                    "label": label,
                })
            })
            .collect();
        serde_json::json!({
            "severity": self.severity,
            "code": self.code,
            "message": self.message,
            "file": file,
            "line": line,
            "column": column,
            "span": span,
            "label": self.label,
            "labels": labels,
            "help": self.help,
            "notes": self.notes,
        })
    }
}

fn to_source_span(span: Span) -> SourceSpan {
    SourceSpan::new((span.start as usize).into(), span.len())
}

/// A file's text as miette reads it, named, with the column miette shows
/// in a report's `[file:line:column]` counted in characters like
/// [`Diagnostic::to_json`] and the language server (miette counts bytes).
#[derive(Debug)]
struct Text {
    name: String,
    text: Arc<str>,
}

impl Text {
    fn new(sources: &SourceMap, file: u32) -> Text {
        let file = sources.file(file);
        Text {
            name: file.name.clone(),
            text: file.text.clone(),
        }
    }
}

impl SourceCode for Text {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let read = self
            .text
            .read_span(span, context_lines_before, context_lines_after)?;
        let at = read.span().offset();
        let line_start = self
            .text
            .get(..at)
            .and_then(|t| t.rfind('\n'))
            .map_or(0, |p| p + 1);
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            read.data(),
            *read.span(),
            read.line(),
            source::column(&self.text, line_start, at),
            read.line_count(),
        )))
    }
}

/// A diagnostic paired with its source text, as miette wants it.
#[derive(Debug)]
struct Rendered {
    diagnostic: Diagnostic,
    source: Option<Text>,
    labels: Vec<LabeledSpan>,
    /// The labels that point into another file than the main span's (a
    /// call site, say), each shown as a snippet of its own file.
    elsewhere: Vec<Elsewhere>,
}

/// A secondary label in another file, rendered by miette as a related
/// report (`☞ in this call of ...` above a snippet of the other file).
#[derive(Debug)]
struct Elsewhere {
    message: String,
    source: Text,
    label: LabeledSpan,
}

impl Elsewhere {
    fn new(sources: &SourceMap, span: Span, label: &str) -> Elsewhere {
        Elsewhere {
            message: label.to_string(),
            source: Text::new(sources, span.file),
            label: LabeledSpan::new_primary_with_span(None, to_source_span(span)),
        }
    }
}

impl fmt::Display for Elsewhere {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Elsewhere {}

impl miette::Diagnostic for Elsewhere {
    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Advice)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        Some(&self.source)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(std::iter::once(self.label.clone())))
    }
}

impl fmt::Display for Rendered {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.diagnostic.message)
    }
}

impl std::error::Error for Rendered {}

impl miette::Diagnostic for Rendered {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.diagnostic.code))
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(match self.diagnostic.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
        })
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        let d = &self.diagnostic;
        if d.help.is_none() && d.notes.is_empty() {
            return None;
        }
        let mut text = d.help.clone().unwrap_or_default();
        for note in &d.notes {
            if !text.is_empty() {
                text.push('\n');
            }
            text.push_str("note: ");
            text.push_str(note);
        }
        Some(Box::new(text))
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        self.source.as_ref().map(|s| s as &dyn miette::SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        if self.labels.is_empty() {
            None
        } else {
            Some(Box::new(self.labels.iter().cloned()))
        }
    }

    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
        if self.elsewhere.is_empty() {
            None
        } else {
            Some(Box::new(
                self.elsewhere.iter().map(|e| e as &dyn miette::Diagnostic),
            ))
        }
    }
}

/// Renders a report as miette's graphical output without colours at a fixed
/// width, the form used by snapshot tests and `rtlang check` when piped.
pub fn render_plain(report: &miette::Report, width: usize) -> String {
    let handler =
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .with_width(width);
    let mut out = String::new();
    match handler.render_report(&mut out, report.as_ref()) {
        Ok(()) => out,
        Err(_) => report.to_string(),
    }
}
