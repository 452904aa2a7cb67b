//! Why a runtime call did nothing.

/// The kind of an [`Error`]: what a host reports it as (the C ABI maps each to a status).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// An argument is out of range: a lot of fewer than three corners or without area, a
    /// coordinate that is not finite.
    InvalidArgument,
    /// The grammar has errors; the message has each with its file, line and column.
    Grammar,
    /// The grammar has no attribute of that name (or no attributes at all).
    UnknownAttribute,
    /// The attribute's default value has another type than the value set.
    AttributeType,
    /// The derivation failed (a limit, an operation that cannot apply); the message says
    /// where, with file, line and column when the grammar has a place for it.
    Derive,
    /// The derivation was cancelled through its control.
    Cancelled,
    /// A file or folder could not be read or written (a goal grammar's library, a rule
    /// package, a lot file, a tileset).
    Io,
    /// A rule package cannot be used: it is not a 7-Zip archive or is damaged, holds no CGA
    /// source (only compiled `.cgb` rules, or no rules), or has no rule file of the name asked
    /// for (or several, none named).
    Package,
}

/// An error: its kind and its message.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// What kind of failure it is.
    pub kind: ErrorKind,
    /// What went wrong, with the place in the grammar when there is one.
    pub message: String,
    /// The one place in the grammar's text the error is at, when its parser or engine gives
    /// one, for editors that mark it (a CGA-style grammar's errors, which may be many, are in
    /// the message only).
    pub place: Option<Place>,
}

/// A place in a grammar's text and what is wrong there.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Place {
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1, in characters.
    pub column: usize,
    /// What is wrong, without the place.
    pub message: String,
}

impl Error {
    /// An error of the given kind.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
            place: None,
        }
    }

    /// The error at `line:column` of the text, `message` saying what is wrong there.
    pub fn at(mut self, line: usize, column: usize, message: impl Into<String>) -> Self {
        self.place = Some(Place {
            line,
            column,
            message: message.into(),
        });
        self
    }

    /// [`ErrorKind::Grammar`].
    pub fn grammar(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Grammar, message)
    }

    /// [`ErrorKind::Derive`].
    pub fn derive(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Derive, message)
    }

    /// [`ErrorKind::UnknownAttribute`].
    pub fn attribute(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::UnknownAttribute, message)
    }

    /// [`ErrorKind::AttributeType`].
    pub fn attribute_type(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::AttributeType, message)
    }

    /// [`ErrorKind::Cancelled`].
    pub fn cancelled() -> Self {
        Self::new(ErrorKind::Cancelled, "the derivation was cancelled")
    }

    /// [`ErrorKind::Io`].
    pub fn io(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Io, message)
    }

    /// [`ErrorKind::Package`].
    pub fn package(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::Package, message)
    }

    /// [`ErrorKind::InvalidArgument`].
    pub fn invalid(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::InvalidArgument, message)
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}
