//! Shapegram's grammar language: lexer, parser, typed AST with spans, and diagnostics.
//!
//! [`parse`] reads a grammar into an [`ast::Grammar`]; it never panics and reports as many
//! problems per file as it can, each as a [`Diagnostic`] that [`SourceFile::render`] prints
//! rustc-style. Five notations are read: the main (CGA-style) syntax, the notation of Müller et
//! al. 2006, the SGL notation, and the two notations of goal grammars (the native one and
//! Michelangelo's C#-style one); [`detect()`] tells them apart and [`parse_as`] forces one. The
//! dialects are lowered to the same AST, with spans into the original text.

pub mod ast;
mod detect;
pub mod diagnostic;
mod lexer;
mod parser;
pub mod source;
mod suggest;

pub use ast::Dialect;
pub use detect::detect;
pub use diagnostic::{Diagnostic, Severity};
pub use source::SourceFile;
pub use suggest::suggest;

/// A byte range `start..end` in a source file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Span {
    /// Offset of the first byte.
    pub start: u32,
    /// Offset one past the last byte.
    pub end: u32,
}

impl Span {
    /// The span `start..end`.
    pub fn new(start: usize, end: usize) -> Self {
        Self {
            start: start as u32,
            end: end as u32,
        }
    }

    /// The smallest span covering both.
    pub fn to(self, other: Span) -> Span {
        Span {
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    /// The span as a `usize` range, for slicing the source.
    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// The result of [`parse`]: the grammar (as much of it as could be read) and the diagnostics.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    /// The parsed grammar; declarations with errors may be missing or incomplete.
    pub grammar: ast::Grammar,
    /// Errors and warnings in source order (a "too many errors" note, if any, comes last).
    pub diagnostics: Vec<Diagnostic>,
}

impl Parsed {
    /// Whether any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }
}

/// Parses a grammar, in the notation [`detect()`] finds in its text. Never panics; after an error
/// it recovers and keeps going, so one run reports several errors.
pub fn parse(source: &SourceFile) -> Parsed {
    parse_as(source, detect(source.text()))
}

/// Parses a grammar written in `dialect`, lowering the Müller and SGL notations to the common
/// AST (see `docs/dialects.md`). Never panics; spans point into the original text.
pub fn parse_as(source: &SourceFile, dialect: Dialect) -> Parsed {
    let (grammar, diagnostics) = parser::parse_dialect(source.text(), dialect);
    Parsed {
        grammar,
        diagnostics,
    }
}
