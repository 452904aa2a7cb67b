//! A cursor over the characters of one line of an L-system file, which knows its position.

use crate::error::{Error, Position};

/// Reads `chars[pos..end]` of line `line`; columns are character indices plus one.
#[derive(Clone, Debug)]
pub(crate) struct Cursor<'a> {
    chars: &'a [char],
    pos: usize,
    end: usize,
    line: u32,
}

impl<'a> Cursor<'a> {
    /// A cursor over `chars[start..end]` of line `line`.
    pub fn new(chars: &'a [char], start: usize, end: usize, line: u32) -> Self {
        Self {
            chars,
            pos: start,
            end,
            line,
        }
    }

    /// The next character, if any before the end.
    pub fn peek(&self) -> Option<char> {
        (self.pos < self.end).then(|| self.chars[self.pos])
    }

    /// The character after the next one.
    pub fn peek_second(&self) -> Option<char> {
        (self.pos + 1 < self.end).then(|| self.chars[self.pos + 1])
    }

    /// Moves past the next character.
    pub fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += 1;
        Some(c)
    }

    /// Moves past `c` if it is next.
    pub fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    /// The items of a parenthesised list whose `(` was just eaten, through the `)`. `after`
    /// says what an item is (`after a parameter name`) when neither `,` nor `)` follows one.
    pub fn list_rest<T>(
        &mut self,
        after: &str,
        mut item: impl FnMut(&mut Self) -> Result<T, Error>,
    ) -> Result<Vec<T>, Error> {
        let mut items = Vec::new();
        loop {
            items.push(item(self)?);
            self.skip_space();
            if self.eat(',') {
                continue;
            }
            if self.eat(')') {
                return Ok(items);
            }
            return Err(self.error(format!(
                "expected ',' or ')' {after}, found {}",
                describe(self.peek())
            )));
        }
    }

    /// Skips spaces and tabs.
    pub fn skip_space(&mut self) {
        while self.peek().is_some_and(char::is_whitespace) {
            self.pos += 1;
        }
    }

    /// Whether only whitespace is left.
    pub fn at_end(&mut self) -> bool {
        self.skip_space();
        self.pos >= self.end
    }

    /// The index of the next character in the line.
    pub fn index(&self) -> usize {
        self.pos
    }

    /// The position of the next character.
    pub fn position(&self) -> Position {
        self.position_of(self.pos)
    }

    /// The position of character `index` of the line.
    pub fn position_of(&self, index: usize) -> Position {
        Position::new(self.line, index as u32 + 1)
    }

    /// An error at the next character.
    pub fn error(&self, message: impl Into<String>) -> Error {
        Error::at(self.position(), message)
    }

    /// The characters `from..self.index()` as a string.
    pub fn text_since(&self, from: usize) -> String {
        self.chars[from..self.pos].iter().collect()
    }

    /// Reads an identifier (`[A-Za-z_][A-Za-z0-9_]*`), if one is next.
    pub fn identifier(&mut self) -> Option<String> {
        let start = self.pos;
        if !self
            .peek()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        {
            return None;
        }
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            self.pos += 1;
        }
        Some(self.text_since(start))
    }
}

/// A description of the next character for messages: `'x'` or `the end of the line`.
pub(crate) fn describe(c: Option<char>) -> String {
    match c {
        Some(c) => format!("'{c}'"),
        None => "the end of the line".to_string(),
    }
}
