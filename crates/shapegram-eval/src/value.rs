//! Runtime values of the grammar language.

use std::fmt;
use std::sync::Arc;

/// A value: CGA has floats, booleans, strings and arrays of them.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number (all numbers are `f64`).
    Number(f64),
    /// A boolean.
    Bool(bool),
    /// A string.
    Str(Arc<str>),
    /// An array.
    Array(Arc<[Value]>),
}

impl Value {
    /// The value's type name, for error messages.
    pub fn type_name(&self) -> &'static str {
        match self {
            Self::Number(_) => "number",
            Self::Bool(_) => "boolean",
            Self::Str(_) => "string",
            Self::Array(_) => "array",
        }
    }

    /// A string value.
    pub fn string(s: &str) -> Self {
        Self::Str(Arc::from(s))
    }

    /// Parses a value given on the command line or through the API: `true`/`false`, a number,
    /// otherwise a string.
    pub fn parse_literal(text: &str) -> Self {
        match text {
            "true" => Self::Bool(true),
            "false" => Self::Bool(false),
            _ => text
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .map_or_else(|| Self::string(text), Self::Number),
        }
    }
}

impl fmt::Display for Value {
    /// CGA's `str()`: integers without a fraction, booleans as `true`/`false`, arrays in brackets.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Number(n) if n.fract() == 0.0 && n.abs() < 1e15 => write!(f, "{}", *n as i64),
            Self::Number(n) => write!(f, "{n}"),
            Self::Bool(b) => write!(f, "{b}"),
            Self::Str(s) => f.write_str(s),
            Self::Array(items) => {
                f.write_str("[")?;
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        f.write_str(",")?;
                    }
                    write!(f, "{item}")?;
                }
                f.write_str("]")
            }
        }
    }
}
