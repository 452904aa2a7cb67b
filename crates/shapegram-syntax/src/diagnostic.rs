//! Errors and warnings with spans, hints and labels.

use crate::Span;

/// How serious a [`Diagnostic`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Severity {
    /// The grammar cannot be used as written.
    Error,
    /// The grammar can be used, but something is ignored or suspicious.
    Warning,
}

/// A message about a span of a source file, rendered by [`SourceFile::render`](crate::SourceFile::render).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// The headline, e.g. "expected `:` after the split size".
    pub message: String,
    /// Where the problem is.
    pub span: Span,
    /// A short text printed next to the carets, e.g. "expected `:` here".
    pub label: Option<String>,
    /// Suggestions printed as `= hint: …` lines.
    pub hints: Vec<String>,
}

impl Diagnostic {
    /// An error at `span`.
    pub fn error(message: impl Into<String>, span: Span) -> Self {
        Self::new(Severity::Error, message.into(), span)
    }

    /// A warning at `span`.
    pub fn warning(message: impl Into<String>, span: Span) -> Self {
        Self::new(Severity::Warning, message.into(), span)
    }

    fn new(severity: Severity, message: String, span: Span) -> Self {
        Self {
            severity,
            message,
            span,
            label: None,
            hints: Vec::new(),
        }
    }

    /// Sets the text printed next to the carets.
    pub fn with_label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }

    /// Adds a `= hint: …` line.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Self {
        self.hints.push(hint.into());
        self
    }

    /// Whether this is an error (rather than a warning).
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}
