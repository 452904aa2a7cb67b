//! Errors of parsing, deriving and interpreting L-systems.

use std::fmt;

/// A place in an L-system file: 1-based line and column (columns count characters).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Position {
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1, in characters.
    pub column: u32,
}

impl Position {
    /// The position at `line:column`.
    pub const fn new(line: u32, column: u32) -> Self {
        Self { line, column }
    }
}

impl fmt::Display for Position {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// What went wrong, and where in the file when the problem has a place there (a limit hit
/// during derivation has none).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// Where the problem is, when it is in the text.
    pub position: Option<Position>,
    /// One line saying what is wrong.
    pub message: String,
}

impl Error {
    /// An error at a place in the text.
    pub fn at(position: Position, message: impl Into<String>) -> Self {
        Self {
            position: Some(position),
            message: message.into(),
        }
    }

    /// An error without a place in the text.
    pub fn general(message: impl Into<String>) -> Self {
        Self {
            position: None,
            message: message.into(),
        }
    }

    /// The error as `name:line:column: message`, then the offending line of `source` with a
    /// caret under the column (no caret lines when the error has no position).
    pub fn render(&self, name: &str, source: &str) -> String {
        let Some(position) = self.position else {
            return format!("{name}: {}\n", self.message);
        };
        let mut text = format!("{name}:{position}: {}\n", self.message);
        if let Some(line) = source.lines().nth(position.line as usize - 1) {
            let number = position.line.to_string();
            let pad = " ".repeat(number.len());
            let before: String = line
                .chars()
                .take(position.column as usize - 1)
                .map(|c| if c == '\t' { '\t' } else { ' ' })
                .collect();
            text.push_str(&format!("{number} | {line}\n{pad} | {before}^\n"));
        }
        text
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position {
            Some(position) => write!(f, "{position}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for Error {}
