//! Errors that stop a derivation.

use shapegram_syntax::{Diagnostic, Span};

/// Why a derivation stopped: a message, the place in the grammar when there is one, and hints.
#[derive(Clone, Debug, PartialEq)]
pub struct DeriveError {
    /// What went wrong, in one line.
    pub message: String,
    /// Where in the grammar, when the error comes from an expression or operation.
    pub span: Option<Span>,
    /// Suggestions for fixing it.
    pub hints: Vec<String>,
    /// For a library of grammars, the index of the file the span is in (`None`: the first).
    pub file: Option<usize>,
}

impl DeriveError {
    /// An error at a place in the grammar.
    pub fn at(message: impl Into<String>, span: Span) -> Self {
        Self {
            message: message.into(),
            span: Some(span),
            hints: Vec::new(),
            file: None,
        }
    }

    /// An error about the derivation as a whole (limits, options).
    pub fn general(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
            span: None,
            hints: Vec::new(),
            file: None,
        }
    }

    /// The same error with a hint.
    pub fn with_hint(mut self, hint: impl Into<String>) -> Self {
        self.hints.push(hint.into());
        self
    }

    /// The same error, placed in file `file` of a library unless it was placed already.
    pub fn in_file(mut self, file: u16) -> Self {
        self.file.get_or_insert(usize::from(file));
        self
    }

    /// The error as a diagnostic to render against the grammar's source (`None` without a span).
    pub fn to_diagnostic(&self) -> Option<Diagnostic> {
        let mut d = Diagnostic::error(self.message.clone(), self.span?);
        for hint in &self.hints {
            d = d.with_hint(hint.clone());
        }
        Some(d)
    }
}

impl std::fmt::Display for DeriveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for DeriveError {}
