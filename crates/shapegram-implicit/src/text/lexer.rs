//! Splitting a line of a `.cave` text into tokens.

use super::*;

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Token {
    Name(String),
    /// A number and how many characters it took.
    Number(f64, usize),
    Punct(char),
}

impl Token {
    pub(super) fn describe(&self) -> String {
        match self {
            Self::Name(n) => format!("'{n}'"),
            Self::Number(v, _) => format!("number {v}"),
            Self::Punct(c) => format!("'{c}'"),
        }
    }
}

/// Splits one line into tokens with their positions; `#` starts a comment.
pub(super) fn lex(line: &str, line_no: usize) -> Result<Vec<(Token, Pos)>, TextError> {
    let chars: Vec<char> = line.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let pos = Pos {
            line: line_no,
            column: i + 1,
        };
        if c == '#' {
            break;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push((Token::Name(chars[start..i].iter().collect()), pos));
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let text: String = chars[start..i].iter().collect();
            let value: f64 = text
                .parse()
                .map_err(|_| pos.error(format!("invalid number '{text}'")))?;
            if !value.is_finite() {
                return Err(pos.error(format!("number '{text}' is too large")));
            }
            tokens.push((Token::Number(value, i - start), pos));
        } else if "(),.+-&{}=%".contains(c) {
            tokens.push((Token::Punct(c), pos));
            i += 1;
        } else {
            return Err(pos.error(format!("unexpected character '{}'", c.escape_debug())));
        }
    }
    Ok(tokens)
}
