//! The hand-written lexer of the main (CGA-style) syntax.
//!
//! Whitespace and comments (`// …`, `/* … */`, `# …`) are dropped; each token remembers whether
//! it is the first on its line, which error recovery uses to find the next declaration.
//! Dotted names (`scope.sx`, `volume.Slab`) are single identifiers: a `.` joins two names only
//! when a letter or `_` follows it directly, so `Glass.` lexes as `Glass` and a terminal `.`.
//!
//! The dialects add a few tokens. The Müller notation reads the rule arrows `~>`, `\leadsto`,
//! `\rightarrow`, `→`, `⇝` (besides `-->`), the empty word `ε`, `ϵ`, `\epsilon`, `epsilon`,
//! relative numbers `1r`, and ignores the `$` of LaTeX maths as printed in papers. In both the
//! Müller and the SGL notation, the escapes `\{` and `\}` of printed grammars are reported and
//! read as braces. In the Michelangelo notation, `↪` (the mark of a line broken in print) is
//! whitespace, and the token after it continues its line.

use crate::ast::Dialect;
use crate::{Diagnostic, Span};

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum TokenKind {
    /// A name, possibly dotted; keywords are identifiers too (the parser decides).
    Ident,
    /// A number literal.
    Number(f64),
    /// A relative number `1r` (Müller notation only).
    RelNumber(f64),
    /// The empty word `ε` (Müller notation only).
    Epsilon,
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
    /// `^`: only in `@Handle(shape=Rule^2)`, which names the second application of a rule.
    Caret,
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
pub(crate) fn lex(text: &str, dialect: Dialect) -> (Vec<Token>, Vec<Diagnostic>) {
    let mut lexer = Lexer {
        text,
        dialect,
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
    dialect: Dialect,
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
                // Printed Michelangelo listings mark a broken line with `↪`: the text goes on.
                '↪' if self.dialect == Dialect::Michelangelo => {
                    self.bump();
                    self.line_start = false;
                }
                '#' => self.eat_while(|c| c != '\n'),
                '/' if self.peek_at(1) == Some('/') => self.eat_while(|c| c != '\n'),
                '/' if self.peek_at(1) == Some('*') => self.block_comment(),
                '"' => self.string(),
                c if c.is_ascii_digit() => self.number(),
                '.' if self.peek_at(1).is_some_and(|c| c.is_ascii_digit()) => self.number(),
                '\\' if self.dialect != Dialect::Cga => self.latex(start),
                c if self.dialect == Dialect::Muller2006 && self.muller_symbol(c, start) => {}
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
        // `1r` in the Müller notation: a relative size.
        let relative = self.dialect == Dialect::Muller2006
            && self.peek() == Some('r')
            && !self.peek_at(1).is_some_and(is_ident_continue);
        if relative {
            self.bump();
        }
        let value = if value.is_finite() {
            value
        } else {
            self.diagnostics.push(
                Diagnostic::error("number too large", span)
                    .with_hint("numbers must fit in a 64-bit float (at most about 1.8e308)"),
            );
            0.0
        };
        let kind = if relative {
            TokenKind::RelNumber(value)
        } else {
            TokenKind::Number(value)
        };
        self.push(kind, start);
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
        let word = &self.text[start..self.pos];
        let kind = if self.dialect == Dialect::Muller2006 && matches!(word, "epsilon" | "ε") {
            TokenKind::Epsilon
        } else {
            TokenKind::Ident
        };
        self.push(kind, start);
    }

    /// Symbols of the Müller notation that are not ASCII punctuation: `~>`, arrows, `ϵ`, and
    /// the `$` of LaTeX maths (skipped). Returns whether `c` was one.
    fn muller_symbol(&mut self, c: char, start: usize) -> bool {
        match c {
            '$' => {
                self.bump();
            }
            '~' if self.peek_at(1) == Some('>') => {
                self.pos += 2;
                self.push(TokenKind::Arrow, start);
            }
            '→' | '⇝' | '⟶' | '↝' => {
                self.bump();
                self.push(TokenKind::Arrow, start);
            }
            'ϵ' => {
                self.bump();
                self.push(TokenKind::Epsilon, start);
            }
            _ => return false,
        }
        true
    }

    /// A backslash in a dialect: a LaTeX command as printed in papers (`\leadsto`,
    /// `\epsilon`) or an escaped brace `\{`.
    fn latex(&mut self, start: usize) {
        self.bump();
        if let Some(brace @ ('{' | '}')) = self.peek() {
            self.bump();
            let kind = if brace == '{' {
                TokenKind::LBrace
            } else {
                TokenKind::RBrace
            };
            self.diagnostics.push(
                Diagnostic::error(
                    format!("`\\{brace}` is a LaTeX escape"),
                    Span::new(start, self.pos),
                )
                .with_label("read as a brace")
                .with_hint(format!("write `{brace}` without the backslash")),
            );
            self.push(kind, start);
            return;
        }
        self.eat_while(|c| c.is_ascii_alphabetic());
        let command = &self.text[start + 1..self.pos];
        let kind = match command {
            "leadsto" | "rightarrow" | "to" | "longrightarrow" | "rightsquigarrow"
                if self.dialect == Dialect::Muller2006 =>
            {
                TokenKind::Arrow
            }
            "epsilon" | "varepsilon" if self.dialect == Dialect::Muller2006 => TokenKind::Epsilon,
            _ => {
                let shown: String = format!("\\{command}").chars().take(20).collect();
                let d = Diagnostic::error(
                    format!("unexpected `{shown}`"),
                    Span::new(start, self.pos.max(start + 1)),
                );
                self.diagnostics.push(if self.dialect == Dialect::Muller2006 {
                    d.with_hint("the LaTeX commands read here are `\\leadsto`, `\\rightarrow` and `\\epsilon`")
                } else {
                    d
                });
                return;
            }
        };
        self.push(kind, start);
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
                Some('^') => T::Caret,
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
