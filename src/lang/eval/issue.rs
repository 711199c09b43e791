//! A problem found by a helper that does not know where it is: the caller
//! attaches the span (typst's `.at(span)` pattern), turning it into a
//! [`Diagnostic`].

use crate::lang::codes::Code;
use crate::lang::diagnostics::Diagnostic;
use crate::lang::source::Span;

/// A diagnostic without a location yet.
#[derive(Clone, Debug)]
pub struct Issue {
    pub code: Code,
    pub message: String,
    pub label: Option<String>,
    pub help: Option<String>,
}

impl Issue {
    /// An issue with a stable code and a message.
    pub fn new(code: Code, message: impl Into<String>) -> Issue {
        Issue {
            code,
            message: message.into(),
            label: None,
            help: None,
        }
    }

    /// Sets the label under the span.
    pub fn label(mut self, label: impl Into<String>) -> Issue {
        self.label = Some(label.into());
        self
    }

    /// Sets the help line.
    pub fn help(mut self, help: impl Into<String>) -> Issue {
        self.help = Some(help.into());
        self
    }

    /// The diagnostic at `span`.
    pub fn at(self, span: Span) -> Diagnostic {
        let mut d = Diagnostic::error(self.code, span, self.message);
        if let Some(label) = self.label {
            d = d.label(label);
        }
        if let Some(help) = self.help {
            d = d.help(help);
        }
        d
    }
}
