//! The recursive-descent parser of the main (CGA-style) syntax.
//!
//! Newlines carry no meaning in CGA, so where a rule body ends is decided by lookahead: a body
//! is a greedy list of statements that stops before the next declaration (`Name -->`,
//! `Name(…) -->`, `name =`, `name(…) =`, `attr`, `const`, `@…`, …). Matching parentheses are
//! found once up front so that this lookahead costs O(1).
//!
//! Errors are reported as they are found and the parser recovers: inside blocks it skips to the
//! next `|` or `}`, elsewhere to the next declaration that starts a line. Nesting deeper than
//! [`MAX_DEPTH`] and more than [`MAX_ERRORS`] errors stop the parse, so hostile input can neither
//! overflow the stack nor produce unbounded output.

mod body;
mod build;
mod decl;
mod expr;
mod goal;
mod michelangelo;
mod muller;
mod sgl;

pub(crate) use goal::PREDICATE_WORDS;
pub(crate) use michelangelo::RULE_KINDS;

use crate::ast::{self, Dialect, Grammar};
use crate::lexer::{Token, TokenKind};
use crate::{Diagnostic, Span};

/// How deeply the parser may recurse (a parenthesis costs about three levels, a block or branch
/// one). Real grammars stay far below; the limit keeps a debug build within 1 MB of stack, half
/// of what a spawned thread gets by default.
pub(crate) const MAX_DEPTH: usize = 128;
/// How many errors are reported before the parser gives up.
pub(crate) const MAX_ERRORS: usize = 100;

/// Words that start declarations and therefore end rule bodies.
const DECLARATION_KEYWORDS: [&str; 5] = ["attr", "const", "import", "style", "version"];
/// Words that never name an operation or successor.
const STATEMENT_KEYWORDS: [&str; 5] = ["case", "else", "NIL", "true", "false"];

/// Marks a failed parse whose error has already been reported; the caller recovers.
#[derive(Debug)]
pub(crate) struct Fail;

/// The result of a parsing function.
pub(crate) type PResult<T> = Result<T, Fail>;

/// What kind of declaration starts at a token (see [`Parser::declaration_start`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Start {
    /// A keyword, an annotation, a rule head or the end of the file: ends any block too.
    Strong,
    /// A function or parameterless-function head `name =` / `name(…) =`.
    Weak,
}

/// Where to rewind to when a speculative parse is abandoned (never after giving up).
struct Checkpoint {
    pos: usize,
    diagnostics: usize,
    errors: usize,
    last_end: u32,
}

/// Parses source text written in `dialect` into a grammar in the common AST, and diagnostics
/// (lexer ones included).
pub(crate) fn parse_dialect(src: &str, dialect: Dialect) -> (Grammar, Vec<Diagnostic>) {
    let (tokens, lex_diagnostics) = crate::lexer::lex(src, dialect);
    let mut parser = Parser::new(src, tokens, dialect);
    for d in lex_diagnostics {
        parser.report(d);
    }
    let mut grammar = Grammar {
        dialect,
        ..Grammar::default()
    };
    match dialect {
        Dialect::Cga => {
            parser.declarations(&mut grammar, false);
            // Extension rules an import redefines come after the file's own rules, so that the
            // first of those stays the default start rule.
            grammar.rules.append(&mut parser.import_rules);
        }
        Dialect::Muller2006 => parser.muller_file(&mut grammar),
        Dialect::Sgl => parser.sgl_file(&mut grammar),
        Dialect::Goal => parser.goal_file(&mut grammar),
        Dialect::Michelangelo => parser.michelangelo_file(&mut grammar),
    }
    let mut diagnostics = parser.diagnostics;
    diagnostics.sort_by_key(|d| d.span.start);
    diagnostics.extend(parser.overflow);
    (grammar, diagnostics)
}

/// The parser's state: tokens, position and reported diagnostics.
pub(crate) struct Parser<'a> {
    src: &'a str,
    /// The notation being read; it decides where declarations start.
    dialect: Dialect,
    tokens: Vec<Token>,
    /// For each `(` token, the index of its matching `)`, or `u32::MAX`.
    closing: Vec<u32>,
    pos: usize,
    /// End of the last consumed token, for the spans of constructs.
    last_end: u32,
    depth: usize,
    /// Set when the parse was given up (too deep, too many errors); silences further errors.
    aborted: bool,
    errors: usize,
    /// Set while looking ahead for a percentage arm (see [`Parser::at_percent_arm`]).
    speculating: bool,
    /// How many `[ case … ]` branches are being read: their statement lists end at a `]`
    /// that closes no `[` of their own.
    bracket_branches: usize,
    /// The rules imports redefine (`import id : "f" (Ext --> …)`), named `id.Ext`.
    import_rules: Vec<ast::Rule>,
    diagnostics: Vec<Diagnostic>,
    /// The "too many errors" note, kept apart so it stays last after sorting.
    overflow: Option<Diagnostic>,
    /// Müller notation: the rule whose body is being read (its name and parameters), for
    /// lowering `I(…)`.
    muller_rule: Option<(ast::Ident, Vec<ast::Ident>)>,
}

impl<'a> Parser<'a> {
    fn new(src: &'a str, tokens: Vec<Token>, dialect: Dialect) -> Self {
        let mut closing = vec![u32::MAX; tokens.len()];
        let mut open = Vec::new();
        for (i, t) in tokens.iter().enumerate() {
            match t.kind {
                TokenKind::LParen => open.push(i),
                TokenKind::RParen => {
                    if let Some(o) = open.pop() {
                        closing[o] = i as u32;
                    }
                }
                _ => {}
            }
        }
        Self {
            src,
            dialect,
            tokens,
            closing,
            pos: 0,
            last_end: 0,
            depth: 0,
            aborted: false,
            errors: 0,
            speculating: false,
            bracket_branches: 0,
            import_rules: Vec::new(),
            diagnostics: Vec::new(),
            overflow: None,
            muller_rule: None,
        }
    }

    // --- Looking at tokens -------------------------------------------------------------------

    fn token_at(&self, i: usize) -> &Token {
        // The token list always ends with `Eof`; looking past it sees `Eof` again.
        &self.tokens[i.min(self.tokens.len() - 1)]
    }

    fn kind_at(&self, i: usize) -> &TokenKind {
        &self.token_at(i).kind
    }

    fn peek(&self) -> &TokenKind {
        self.kind_at(self.pos)
    }

    fn peek_nth(&self, n: usize) -> &TokenKind {
        self.kind_at(self.pos + n)
    }

    fn span(&self) -> Span {
        self.token_at(self.pos).span
    }

    fn at(&self, kind: &TokenKind) -> bool {
        self.peek() == kind
    }

    fn text_at(&self, i: usize) -> &'a str {
        &self.src[self.token_at(i).span.range()]
    }

    /// The current token's text.
    fn text(&self) -> &'a str {
        self.text_at(self.pos)
    }

    /// Whether token `i` is the identifier `word`.
    fn is_word_at(&self, i: usize, word: &str) -> bool {
        *self.kind_at(i) == TokenKind::Ident && self.text_at(i) == word
    }

    fn at_word(&self, word: &str) -> bool {
        self.is_word_at(self.pos, word)
    }

    /// Whether token `i` is an identifier that is not a keyword.
    fn is_name_at(&self, i: usize) -> bool {
        *self.kind_at(i) == TokenKind::Ident && {
            let text = self.text_at(i);
            !STATEMENT_KEYWORDS.contains(&text) && !DECLARATION_KEYWORDS.contains(&text)
        }
    }

    /// The index of the `)` matching the `(` at `i`.
    fn closing_paren(&self, i: usize) -> Option<usize> {
        self.closing
            .get(i)
            .filter(|&&c| c != u32::MAX)
            .map(|&c| c as usize)
    }

    /// Whether a declaration starts at token `i`, and which kind.
    fn declaration_start(&self, i: usize) -> Option<Start> {
        match self.dialect {
            Dialect::Cga => self.cga_declaration_start(i),
            Dialect::Muller2006 => self.muller_declaration_start(i),
            Dialect::Sgl => self.sgl_declaration_start(i),
            Dialect::Goal => self.goal_declaration_start(i),
            Dialect::Michelangelo => self.michelangelo_declaration_start(i),
        }
    }

    /// [`Parser::declaration_start`] in the main syntax.
    fn cga_declaration_start(&self, i: usize) -> Option<Start> {
        match self.kind_at(i) {
            TokenKind::Eof | TokenKind::At => Some(Start::Strong),
            TokenKind::Ident => self.named_declaration_start(i, |_| None),
            _ => None,
        }
    }

    /// [`Parser::declaration_start`] at the identifier `i`, as the dialects that share the main
    /// syntax's declarations see it: a declaration keyword, or a name with optional `(…)`
    /// followed by the rule arrow (a rule) or `=` (a function). What else may follow the head
    /// is the dialect's: `other` decides, given the index of the token after the head.
    fn named_declaration_start(
        &self,
        i: usize,
        other: impl FnOnce(usize) -> Option<Start>,
    ) -> Option<Start> {
        if DECLARATION_KEYWORDS.contains(&self.text_at(i)) {
            return Some(Start::Strong);
        }
        if !self.is_name_at(i) {
            return None;
        }
        // `extension Ext -->` and `start Main -->`: rules with a keyword before them.
        if matches!(self.text_at(i), "extension" | "start") && self.is_rule_head(i + 1) {
            return Some(Start::Strong);
        }
        let after = match self.kind_at(i + 1) {
            TokenKind::LParen => self.closing_paren(i + 1)? + 1,
            _ => i + 1,
        };
        match self.kind_at(after) {
            TokenKind::Arrow => Some(Start::Strong),
            TokenKind::Eq => Some(Start::Weak),
            _ => other(after),
        }
    }

    /// Whether a rule's head, a name with optional `(…)` and the arrow, starts at token `i`.
    fn is_rule_head(&self, i: usize) -> bool {
        if !self.is_name_at(i) {
            return false;
        }
        let after = match self.kind_at(i + 1) {
            TokenKind::LParen => match self.closing_paren(i + 1) {
                Some(close) => close + 1,
                None => return false,
            },
            _ => i + 1,
        };
        *self.kind_at(after) == TokenKind::Arrow
    }

    fn at_declaration_start(&self) -> bool {
        self.declaration_start(self.pos).is_some()
    }

    /// Whether the current token starts a line and a declaration: a safe place to resume.
    fn at_resume_point(&self) -> bool {
        self.token_at(self.pos).line_start && self.at_declaration_start()
    }

    /// A short description of the current token for "found …" messages.
    fn describe(&self) -> String {
        match self.peek() {
            TokenKind::Eof => "end of file".to_string(),
            TokenKind::Str(_) => "a string".to_string(),
            _ => {
                let text = self.text();
                match text.char_indices().nth(32) {
                    Some((cut, _)) => format!("`{}…`", &text[..cut]),
                    None => format!("`{text}`"),
                }
            }
        }
    }

    // --- Consuming tokens --------------------------------------------------------------------

    /// From the start of `start` to the end of the last consumed token.
    fn span_from(&self, start: Span) -> Span {
        Span {
            start: start.start,
            end: self.last_end.max(start.end),
        }
    }

    /// Consumes the current token (never moving past `Eof`) and returns its span.
    fn bump(&mut self) -> Span {
        let span = self.span();
        if self.pos < self.tokens.len() - 1 {
            self.pos += 1;
            self.last_end = span.end;
        }
        span
    }

    /// Consumes the current token if it is `kind`.
    fn eat(&mut self, kind: &TokenKind) -> Option<Span> {
        self.at(kind).then(|| self.bump())
    }

    /// Consumes `kind` or reports "expected `what` …, found …" at the current token.
    fn expect(&mut self, kind: &TokenKind, what: &str, context: &str) -> PResult<Span> {
        match self.eat(kind) {
            Some(span) => Ok(span),
            None => Err(self.error_expected(what, context)),
        }
    }

    /// Reports "expected {what} {context}, found …" at the current token.
    fn error_expected(&mut self, what: &str, context: &str) -> Fail {
        let d = self.expected(what, context);
        self.report(d);
        Fail
    }

    /// The diagnostic "expected {what} {context}, found …" at the current token.
    fn expected(&self, what: &str, context: &str) -> Diagnostic {
        let message = if context.is_empty() {
            format!("expected {what}, found {}", self.describe())
        } else {
            format!("expected {what} {context}, found {}", self.describe())
        };
        Diagnostic::error(message, self.span()).with_label(format!("expected {what} here"))
    }

    // --- Diagnostics, nesting and speculation --------------------------------------------------

    /// Records a diagnostic unless the parse was given up; gives up after too many errors.
    fn report(&mut self, d: Diagnostic) {
        if self.aborted {
            return;
        }
        if d.is_error() {
            self.errors += 1;
            if self.errors > MAX_ERRORS {
                self.overflow = Some(Diagnostic::error(
                    format!("too many errors; stopping after {MAX_ERRORS}"),
                    d.span,
                ));
                self.abort();
                return;
            }
        }
        self.diagnostics.push(d);
    }

    /// Gives up: jumps to the end so that every loop finishes without further reports.
    fn abort(&mut self) {
        self.aborted = true;
        self.pos = self.tokens.len() - 1;
    }

    /// Runs `f` one nesting level deeper, giving up past [`MAX_DEPTH`].
    fn nested<T>(&mut self, f: impl FnOnce(&mut Self) -> PResult<T>) -> PResult<T> {
        if self.depth >= MAX_DEPTH {
            let d = Diagnostic::error("nesting too deep", self.span())
                .with_label("this is nested too deeply")
                .with_hint("split the expression or rule into smaller ones");
            self.report(d);
            self.abort();
            return Err(Fail);
        }
        self.depth += 1;
        let result = f(self);
        self.depth -= 1;
        result
    }

    fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            pos: self.pos,
            diagnostics: self.diagnostics.len(),
            errors: self.errors,
            last_end: self.last_end,
        }
    }

    fn rewind(&mut self, c: Checkpoint) {
        self.pos = c.pos;
        self.diagnostics.truncate(c.diagnostics);
        self.errors = c.errors;
        self.last_end = c.last_end;
    }

    // --- Recovery ------------------------------------------------------------------------------

    /// Skips to the next declaration that starts a line (or the end).
    fn recover_to_declaration(&mut self) {
        while !self.at(&TokenKind::Eof) && !self.at_resume_point() {
            self.bump();
        }
    }

    /// Skips to the next `|` or `}` of the current block, or to a declaration that starts a line.
    fn recover_in_block(&mut self) {
        let mut depth = 0usize;
        loop {
            match self.peek() {
                TokenKind::Eof => return,
                TokenKind::LBrace => depth += 1,
                TokenKind::RBrace if depth == 0 => return,
                TokenKind::RBrace => depth -= 1,
                TokenKind::Pipe if depth == 0 => return,
                _ if self.at_resume_point()
                    && self.declaration_start(self.pos) == Some(Start::Strong) =>
                {
                    return;
                }
                _ => {}
            }
            self.bump();
        }
    }
}
