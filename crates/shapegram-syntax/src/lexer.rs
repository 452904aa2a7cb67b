//! The hand-written lexer of the main (CGA-style) syntax.
//!
//! Whitespace and comments (`// …`, `/* … */`, `# …`) are dropped; each token remembers whether
//! it is the first on its line, which error recovery uses to find the next declaration.
//! Dotted names (`scope.sx`, `volume.Slab`) are single identifiers: a `.` joins two names only
//! when a letter or `_` follows it directly, so `Glass.` lexes as `Glass` and a terminal `.`.

use crate::{Diagnostic, Span};

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum TokenKind {
    /// A name, possibly dotted; keywords are identifiers too (the parser decides).
    Ident,
    /// A number literal.
    Number(f64),
    /// A double-quoted string with escapes resolved.
    Str(String),
    /// `-->`
    Arrow,
    /// `~`
    Tilde,
    /// `'`
    Quote,
    /// `%`
    Percent,
    /// `:`
    Colon,
    /// `;` (row separator in 2D arrays)
    Semi,
    /// `|`
    Pipe,
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `[`
    LBracket,
    /// `]`
    RBracket,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `,`
    Comma,
    /// `*`
    Star,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `/`
    Slash,
    /// `==`
    EqEq,
    /// `!=`
    Ne,
    /// `<=`
    Le,
    /// `>=`
    Ge,
    /// `<`
    Lt,
    /// `>`
    Gt,
    /// `&&`
    AndAnd,
    /// `||`
    OrOr,
    /// `!`
    Bang,
    /// `?`
    Question,
    /// `=`
    Eq,
    /// `@`
    At,
    /// `.` (the terminal marker)
    Dot,
    /// The end of the input.
    Eof,
}

/// A token with its span.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Token {
    /// What it is.
    pub kind: TokenKind,
    /// Where it is.
    pub span: Span,
    /// Whether only whitespace and comments precede it on its line.
    pub line_start: bool,
}

/// Splits `text` into tokens (ending with [`TokenKind::Eof`]) and reports malformed input.
pub(crate) fn lex(text: &str) -> (Vec<Token>, Vec<Diagnostic>) {
    let mut lexer = Lexer {
        text,
        pos: 0,
        line_start: true,
        tokens: Vec::new(),
        diagnostics: Vec::new(),
    };
    lexer.run();
    (lexer.tokens, lexer.diagnostics)
}

struct Lexer<'a> {
    text: &'a str,
    pos: usize,
    line_start: bool,
    tokens: Vec<Token>,
    diagnostics: Vec<Diagnostic>,
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_ident_continue(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

impl Lexer<'_> {
    fn peek(&self) -> Option<char> {
        self.text[self.pos..].chars().next()
    }

    fn peek_at(&self, n: usize) -> Option<char> {
        self.text[self.pos..].chars().nth(n)
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += c.len_utf8();
        Some(c)
    }

    fn eat_while(&mut self, f: impl Fn(char) -> bool) {
        while self.peek().is_some_and(&f) {
            self.bump();
        }
    }

    fn push(&mut self, kind: TokenKind, start: usize) {
        self.tokens.push(Token {
            kind,
            span: Span::new(start, self.pos),
            line_start: self.line_start,
        });
        self.line_start = false;
    }

    fn run(&mut self) {
        // Editors on Windows may start a file with a byte-order mark.
        if self.text.starts_with('\u{feff}') {
            self.pos = '\u{feff}'.len_utf8();
        }
        while let Some(c) = self.peek() {
            let start = self.pos;
            match c {
                '\n' => {
                    self.bump();
                    self.line_start = true;
                }
                c if c.is_whitespace() => {
                    self.bump();
                }
                '#' => self.eat_while(|c| c != '\n'),
                '/' if self.peek_at(1) == Some('/') => self.eat_while(|c| c != '\n'),
                '/' if self.peek_at(1) == Some('*') => self.block_comment(),
                '"' => self.string(),
                c if c.is_ascii_digit() => self.number(),
                '.' if self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) => self.number(),
                c if is_ident_start(c) => self.ident(),
                _ => self.punct(start),
            }
        }
        let end = self.tokens.last().map_or(0, |t| t.span.end as usize);
        self.tokens.push(Token {
            kind: TokenKind::Eof,
            span: Span::new(end, end),
            line_start: true,
        });
    }

    fn block_comment(&mut self) {
        let start = self.pos;
        match self.text[start + 2..].find("*/") {
            Some(i) => self.pos = start + 2 + i + 2,
            None => {
                self.pos = self.text.len();
                self.diagnostics.push(
                    Diagnostic::error("unterminated block comment", Span::new(start, start + 2))
                        .with_label("this comment is never closed")
                        .with_hint("close it with `*/`"),
                );
            }
        }
    }

    fn string(&mut self) {
        let start = self.pos;
        self.bump();
        let mut value = String::new();
        loop {
            let Some(c) = self.peek() else {
                self.unterminated_string(start);
                break;
            };
            match c {
                '"' => {
                    self.bump();
                    break;
                }
                // Strings do not span lines, so a missing quote costs one line, not the file.
                '\n' => {
                    self.unterminated_string(start);
                    break;
                }
                '\\' => {
                    let escape_start = self.pos;
                    self.bump();
                    match self.bump() {
                        Some('"') => value.push('"'),
                        Some('\\') => value.push('\\'),
                        Some('n') => value.push('\n'),
                        Some('t') => value.push('\t'),
                        other => {
                            // Leave a newline for the string's own end-of-line check.
                            if other == Some('\n') {
                                self.pos -= 1;
                            }
                            let shown = other
                                .filter(|&c| c != '\n')
                                .map_or_else(String::new, String::from);
                            self.diagnostics.push(
                                Diagnostic::error(
                                    format!("unknown escape sequence `\\{shown}`"),
                                    Span::new(escape_start, self.pos),
                                )
                                .with_hint("the escapes are `\\\"`, `\\\\`, `\\n` and `\\t`"),
                            );
                        }
                    }
                }
                c => {
                    value.push(c);
                    self.bump();
                }
            }
        }
        self.push(TokenKind::Str(value), start);
    }

    fn unterminated_string(&mut self, start: usize) {
        self.diagnostics.push(
            Diagnostic::error("unterminated string", Span::new(start, self.pos))
                .with_label("this string has no closing `\"`"),
        );
    }

    fn number(&mut self) {
        let start = self.pos;
        self.eat_while(|c| c.is_ascii_digit());
        if self.peek() == Some('.') && self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) {
            self.bump();
            self.eat_while(|c| c.is_ascii_digit());
        }
        if matches!(self.peek(), Some('e' | 'E')) {
            let digits_at = if matches!(self.peek_at(1), Some('+' | '-')) {
                2
            } else {
                1
            };
            if self.peek_at(digits_at).is_some_and(|c| c.is_ascii_digit()) {
                for _ in 0..digits_at {
                    self.bump();
                }
                self.eat_while(|c| c.is_ascii_digit());
            }
        }
        let span = Span::new(start, self.pos);
        // Only digits, one `.` and an exponent were consumed, so parsing cannot fail.
        let value: f64 = self.text[span.range()].parse().unwrap_or(0.0);
        let value = if value.is_finite() {
            value
        } else {
            self.diagnostics.push(
                Diagnostic::error("number too large", span)
                    .with_hint("numbers must fit in a 64-bit float (at most about 1.8e308)"),
            );
            0.0
        };
        self.push(TokenKind::Number(value), start);
    }

    fn ident(&mut self) {
        let start = self.pos;
        loop {
            self.eat_while(is_ident_continue);
            if self.peek() == Some('.') && self.peek_at(1).is_some_and(is_ident_start) {
                self.bump();
            } else {
                break;
            }
        }
        self.push(TokenKind::Ident, start);
    }

    fn punct(&mut self, start: usize) {
        use TokenKind as T;
        let rest = &self.text[start..];
        let (kind, len) = if rest.starts_with("-->") {
            (T::Arrow, 3)
        } else if let Some(kind) = [
            ("==", T::EqEq),
            ("!=", T::Ne),
            ("<=", T::Le),
            (">=", T::Ge),
            ("&&", T::AndAnd),
            ("||", T::OrOr),
        ]
        .into_iter()
        .find_map(|(s, k)| rest.starts_with(s).then_some(k))
        {
            (kind, 2)
        } else {
            let kind = match rest.chars().next() {
                Some('~') => T::Tilde,
                Some('\'') => T::Quote,
                Some('%') => T::Percent,
                Some(':') => T::Colon,
                Some(';') => T::Semi,
                Some('|') => T::Pipe,
                Some('{') => T::LBrace,
                Some('}') => T::RBrace,
                Some('[') => T::LBracket,
                Some(']') => T::RBracket,
                Some('(') => T::LParen,
                Some(')') => T::RParen,
                Some(',') => T::Comma,
                Some('*') => T::Star,
                Some('+') => T::Plus,
                Some('-') => T::Minus,
                Some('/') => T::Slash,
                Some('<') => T::Lt,
                Some('>') => T::Gt,
                Some('!') => T::Bang,
                Some('?') => T::Question,
                Some('=') => T::Eq,
                Some('@') => T::At,
                Some('.') => T::Dot,
                _ => return self.unknown(start),
            };
            (kind, 1)
        };
        self.pos += len;
        self.push(kind, start);
    }

    /// Reports a run of characters that start no token as one error.
    fn unknown(&mut self, start: usize) {
        self.bump();
        while let Some(c) = self.peek() {
            let starts_token = c.is_whitespace()
                || c.is_ascii_digit()
                || is_ident_start(c)
                || "\"#/~'%:;|{}[](),*+-<>=!?@.&".contains(c);
            if starts_token {
                break;
            }
            self.bump();
        }
        let span = Span::new(start, self.pos);
        let text = &self.text[span.range()];
        // Keep the headline short when a binary file is read by mistake.
        let mut shown: String = text
            .chars()
            .take(16)
            .collect::<String>()
            .escape_debug()
            .collect();
        if text.chars().nth(16).is_some() {
            shown.push('…');
        }
        let what = if text.chars().nth(1).is_none() {
            format!("unexpected character `{shown}`")
        } else {
            format!("unexpected characters `{shown}`")
        };
        self.diagnostics.push(Diagnostic::error(what, span));
    }
}
