//! The one error type of the crate: invalid parameters and limits.

use std::fmt;

/// Why a solid, a cave or a mesh could not be built. The message names the parameter and the
/// value that was wrong, and says what would be accepted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImplicitError {
    message: String,
}

impl ImplicitError {
    /// An error with this message.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
        }
    }

    /// The message, without any prefix.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for ImplicitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ImplicitError {}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, ImplicitError>;

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ImplicitError::new(format!(
            "invalid {name} {value}: expected a finite number greater than 0"
        )))
    }
}

/// Checks that `value` is finite.
pub(crate) fn finite(name: &str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ImplicitError::new(format!(
            "invalid {name} {value}: expected a finite number"
        )))
    }
}
