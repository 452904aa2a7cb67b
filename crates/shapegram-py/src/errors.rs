//! The module's exceptions, and the engine's errors turned into them.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::exceptions::{PyException, PyOSError, PyValueError};
use pyo3::prelude::*;
use shapegram_runtime::{Error as EngineError, ErrorKind};

pyo3::create_exception!(
    shapegram,
    Error,
    PyException,
    "Every error of the engine: the others derive from it."
);
pyo3::create_exception!(
    shapegram,
    GrammarError,
    Error,
    "The grammar has errors; the message has each with its file, line and column."
);
pyo3::create_exception!(
    shapegram,
    DeriveError,
    Error,
    "The derivation failed; the message says where in the grammar when it has a place."
);
pyo3::create_exception!(
    shapegram,
    UnknownAttributeError,
    Error,
    "The grammar has no attribute of that name."
);
pyo3::create_exception!(
    shapegram,
    AttributeTypeError,
    Error,
    "An attribute was given a value of another type than its declaration's."
);

pyo3::create_exception!(
    shapegram,
    PackageError,
    Error,
    "A rule package (.rpk) cannot be used: not a 7-Zip archive, only compiled rules, no such rule file."
);

/// The exception of an engine error.
pub fn to_py(error: EngineError) -> PyErr {
    let message = error.message;
    match error.kind {
        ErrorKind::Grammar => GrammarError::new_err(message),
        ErrorKind::Derive => DeriveError::new_err(message),
        ErrorKind::UnknownAttribute => UnknownAttributeError::new_err(message),
        ErrorKind::AttributeType => AttributeTypeError::new_err(message),
        ErrorKind::InvalidArgument => PyValueError::new_err(message),
        ErrorKind::Cancelled => Error::new_err(message),
        ErrorKind::Io => PyOSError::new_err(message),
        ErrorKind::Package => PackageError::new_err(message),
    }
}

/// Runs `call` with a panic turned into a `shapegram.Error` (PyO3 would raise a
/// `PanicException`, which `except Exception` does not catch).
pub fn guard<T>(call: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(call)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".to_owned());
        Err(Error::new_err(format!(
            "internal error (please report it): {what}"
        )))
    })
}
