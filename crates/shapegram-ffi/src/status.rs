//! Status codes, and the errors behind them.

use shapegram_runtime::ErrorKind;

/// What a call did: `SG_OK`, or why it did nothing. The message of every status but `SG_OK` is
/// in `sg_state_last_error`.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum sg_status {
    /// The call did what it was asked.
    SG_OK = 0,
    /// A pointer argument that may not be NULL was NULL.
    SG_NULL_ARGUMENT = 1,
    /// A string argument was not UTF-8.
    SG_INVALID_UTF8 = 2,
    /// An argument is out of range: an unknown kind, a lot of fewer than three corners or
    /// without area, a coordinate that is not finite.
    SG_INVALID_ARGUMENT = 3,
    /// A file could not be read.
    SG_IO = 4,
    /// The grammar has errors; the message has each with its file, line and column.
    SG_GRAMMAR_ERROR = 5,
    /// The call needs a grammar and none is loaded.
    SG_NO_GRAMMAR = 6,
    /// The grammar has no attribute of that name (or no attributes at all).
    SG_UNKNOWN_ATTRIBUTE = 7,
    /// The attribute's default value has another type than the value set.
    SG_ATTRIBUTE_TYPE = 8,
    /// The derivation failed (a limit, an operation that cannot apply); the message says
    /// where, with file, line and column when the grammar has a place for it.
    SG_DERIVE_ERROR = 9,
    /// `sg_state_cancel` stopped the derivation.
    SG_CANCELLED = 10,
    /// Another call on the same handle is running on another thread.
    SG_BUSY = 11,
    /// The library hit a bug (a Rust panic, caught at the boundary); the handle stays usable.
    SG_INTERNAL = 12,
    /// A rule package (`.rpk`) cannot be used: it is not a 7-Zip archive or is damaged, holds
    /// only compiled rules (`.cgb`) or none, or has no rule file of the name given (or several
    /// and none was named); the message says which, listing its rule files.
    SG_PACKAGE_ERROR = 13,
}

/// An error: its status and its message.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// The status the call returns.
    pub status: sg_status,
    /// What `sg_state_last_error` gives.
    pub message: String,
}

impl Error {
    /// An error of the given status.
    pub fn new(status: sg_status, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
        }
    }

    /// `SG_INVALID_ARGUMENT`.
    pub fn invalid(message: impl Into<String>) -> Self {
        Self::new(sg_status::SG_INVALID_ARGUMENT, message)
    }
}

impl From<shapegram_runtime::Error> for Error {
    fn from(error: shapegram_runtime::Error) -> Self {
        let status = match error.kind {
            ErrorKind::InvalidArgument => sg_status::SG_INVALID_ARGUMENT,
            ErrorKind::Grammar => sg_status::SG_GRAMMAR_ERROR,
            ErrorKind::UnknownAttribute => sg_status::SG_UNKNOWN_ATTRIBUTE,
            ErrorKind::AttributeType => sg_status::SG_ATTRIBUTE_TYPE,
            ErrorKind::Derive => sg_status::SG_DERIVE_ERROR,
            ErrorKind::Cancelled => sg_status::SG_CANCELLED,
            ErrorKind::Io => sg_status::SG_IO,
            ErrorKind::Package => sg_status::SG_PACKAGE_ERROR,
        };
        Self::new(status, error.message)
    }
}
