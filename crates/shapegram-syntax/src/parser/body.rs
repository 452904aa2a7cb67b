//! Rule bodies: statement sequences, `case` and percentage branches, and `{ … }` blocks.
//!
//! A branch body runs until the next `case`, `else` or percentage arm, so nesting is greedy: a
//! branch that starts with `case` takes all following `case` arms and at most one `else`; the
//! next `else` belongs to the enclosing construct.

use super::{Fail, PResult, Parser, Start};
use crate::ast::{
    Argument, Block, BlockEntry, Body, Call, DYNAMIC_IMPORT, Dialect, Expr, ExprKind, Ident, Stmt,
};
use crate::lexer::TokenKind;
use crate::{Diagnostic, Span};

impl Parser<'_> {
    /// A rule body or branch body.
    pub(super) fn body(&mut self) -> PResult<Body> {
        self.nested(|p| {
            if p.at_word("case") {
                p.cases()
            } else if p.at_percent_arm() {
                p.stochastic()
            } else {
                Ok(Body::Sequence(p.statements(true)?))
            }
        })
    }

    fn cases(&mut self) -> PResult<Body> {
        let start = self.span();
        let arms = self.case_arms(Self::body)?;
        let otherwise = self.else_body()?;
        Ok(Body::Cases {
            arms,
            otherwise: Box::new(otherwise),
            span: self.span_from(start),
        })
    }

    fn stochastic(&mut self) -> PResult<Body> {
        let start = self.span();
        let mut arms = Vec::new();
        while self.at_percent_arm() {
            let percent = self.ternary()?;
            self.expect(&TokenKind::Percent, "`%`", "after the percentage")?;
            self.expect(&TokenKind::Colon, "`:`", "after the percentage")?;
            arms.push((percent, self.body()?));
        }
        let otherwise = self.else_body()?;
        Ok(Body::Stochastic {
            arms,
            otherwise: Box::new(otherwise),
            span: self.span_from(start),
        })
    }

    /// An optional `else : body`; an empty sequence when absent.
    fn else_body(&mut self) -> PResult<Body> {
        if !self.at_word("else") {
            return Ok(Body::Sequence(Vec::new()));
        }
        self.bump();
        self.expect(&TokenKind::Colon, "`:`", "after `else`")?;
        self.body()
    }

    /// Statements up to the first token that cannot start one, or the next declaration. In a
    /// rule body (`in_body`), a percentage arm also ends the list.
    pub(super) fn statements(&mut self, in_body: bool) -> PResult<Vec<Stmt>> {
        let mut statements = Vec::new();
        // `[`s opened in this list: a `]` beyond them closes the `[` before an enclosing branch.
        let mut open = 0usize;
        loop {
            let statement = match self.peek().clone() {
                TokenKind::LBracket => {
                    open += 1;
                    let push = Stmt::Push(self.bump());
                    if in_body && (self.at_word("case") || self.at_percent_arm()) {
                        statements.push(push);
                        self.bracket_branches += 1;
                        let branch = self.body();
                        self.bracket_branches -= 1;
                        Stmt::Branch(Box::new(branch?))
                    } else {
                        push
                    }
                }
                TokenKind::RBracket if open == 0 && self.bracket_branches > 0 => {
                    return Ok(statements);
                }
                TokenKind::RBracket => {
                    open = open.saturating_sub(1);
                    Stmt::Pop(self.bump())
                }
                TokenKind::Ident if self.at_word("NIL") => Stmt::Nil(self.bump()),
                TokenKind::Plus if self.dialect == Dialect::Goal => self.goal_successor()?,
                TokenKind::Ident if self.dialect == Dialect::Goal && self.at_word("void") => {
                    Stmt::Nil(self.bump())
                }
                TokenKind::Ident if self.dialect == Dialect::Cga && self.at_dynamic_import() => {
                    statements.extend(self.dynamic_import()?);
                    continue;
                }
                TokenKind::Ident
                    if self.is_name_at(self.pos)
                        && !self.at_declaration_start()
                        && !(in_body && self.at_percent_arm()) =>
                {
                    Stmt::Call(self.call_statement()?)
                }
                _ => return Ok(statements),
            };
            statements.push(statement);
        }
    }

    /// Whether a dynamic import call `id(a = v).Rule` starts here: a call whose `)` is followed,
    /// with nothing between, by `.` and a name.
    fn at_dynamic_import(&self) -> bool {
        if *self.kind_at(self.pos + 1) != TokenKind::LParen {
            return false;
        }
        let Some(close) = self.closing_paren(self.pos + 1) else {
            return false;
        };
        let touching =
            |a: usize, b: usize| self.token_at(a).span.end == self.token_at(b).span.start;
        *self.kind_at(close + 1) == TokenKind::Dot
            && *self.kind_at(close + 2) == TokenKind::Ident
            && touching(close, close + 1)
            && touching(close + 1, close + 2)
    }

    /// `id(a = v, …).Rule(args)`: the imported file's rule called with its attributes set
    /// afresh. It is read as `[ «set id's attributes» id.Rule(args) ]`, the first statement a
    /// call of [`DYNAMIC_IMPORT`] with the import's name and the overrides: the successor takes
    /// the shape with the new values, and the shape itself keeps its own.
    fn dynamic_import(&mut self) -> PResult<Vec<Stmt>> {
        let id = self.ident();
        let (overrides, close) = self.call_args()?;
        if let Some(positional) = overrides.iter().find(|a| a.name.is_none()) {
            let d = Diagnostic::error(
                "a dynamic import sets attributes: `id(name = value).Rule`",
                positional.value.span,
            )
            .with_label("an attribute name and `=` are missing");
            self.report(d);
            return Err(Fail);
        }
        let dot = self.bump();
        let rule = self.ident();
        let mut args = vec![Argument {
            name: None,
            value: Expr {
                kind: ExprKind::Name(id.name.clone()),
                span: id.span,
            },
        }];
        args.extend(overrides);
        let reset = Call {
            name: Ident {
                name: DYNAMIC_IMPORT.to_owned(),
                span: id.span,
            },
            args: Some(args),
            block: None,
            terminal: false,
            span: id.span.to(close),
        };
        let mut successor = Call {
            name: Ident {
                name: format!("{}.{}", id.name, rule.name),
                span: id.span.to(rule.span),
            },
            args: None,
            block: None,
            terminal: false,
            span: id.span.to(rule.span),
        };
        if self.at(&TokenKind::LParen) {
            let (args, close) = self.call_args()?;
            successor.args = Some(args);
            successor.span = successor.span.to(close);
        }
        let end = successor.span;
        Ok(vec![
            Stmt::Push(id.span),
            Stmt::Call(reset),
            Stmt::Call(successor),
            Stmt::Pop(dot.to(end)),
        ])
    }

    /// `name`, `name(args)`, `name(args){ … }`, `name(args){ … }*`, each optionally with `.`.
    fn call_statement(&mut self) -> PResult<Call> {
        let name = self.ident();
        let mut span = name.span;
        let mut args = None;
        let mut block = None;
        let operand_form = self.dialect == Dialect::Cga && OPERAND_FORMS.contains(&&*name.name);
        if self.at(&TokenKind::LParen) {
            let (list, close) = self.call_args()?;
            args = Some(list);
            span = span.to(close);
            if self.at(&TokenKind::LBrace) {
                let mut b = self.block(key_kind(&name.name))?;
                if name.name == PERIMETER_SPLIT {
                    b = self.perimeter_blocks(b)?;
                }
                span = span.to(b.span);
                block = Some(b);
            }
        }
        if operand_form && block.is_none() {
            block = self.operand(&mut span)?;
        }
        let terminal = match self.eat(&TokenKind::Dot) {
            Some(dot) => {
                span = span.to(dot);
                true
            }
            None => false,
        };
        Ok(Call {
            name,
            args,
            block,
            terminal,
            span,
        })
    }

    /// The blocks of `splitAndSetbackPerimeter(…) { len : depth : … }[*] { remainder : … }`
    /// as one: the sections' block as a group, then the entries of the remainder's block.
    fn perimeter_blocks(&mut self, sections: Block) -> PResult<Block> {
        let mut span = sections.span;
        let mut entries = vec![BlockEntry::Group(sections)];
        if self.at(&TokenKind::LBrace) {
            let rest = self.block("selector")?;
            span = span.to(rest.span);
            entries.extend(rest.entries);
        }
        Ok(Block {
            entries,
            repeat: false,
            span,
        })
    }

    /// The operand of `union`, `subtract`, `intersect` and `inline` written without parentheses
    /// or after them: `{ ops | ops }`, or one call (`union Rule`, `inline(unify) split(y) {…}`),
    /// read as a block of one entry. `None` when neither follows (the operation reports it).
    fn operand(&mut self, span: &mut Span) -> PResult<Option<Block>> {
        if self.at(&TokenKind::LBrace) {
            let b = self.block(BODY_ONLY)?;
            *span = span.to(b.span);
            return Ok(Some(b));
        }
        let starts_call = *self.peek() == TokenKind::Ident
            && self.is_name_at(self.pos)
            && !self.at_word("NIL")
            && !self.at_declaration_start();
        if !starts_call {
            return Ok(None);
        }
        let call = self.call_statement()?;
        *span = span.to(call.span);
        let start = call.span;
        Ok(Some(Block {
            entries: vec![BlockEntry::Part {
                key: Expr {
                    kind: ExprKind::Name("all".to_owned()),
                    span: Span::new(start.start as usize, start.start as usize),
                },
                merge: false,
                body: vec![Stmt::Call(call)],
                span: start,
            }],
            repeat: false,
            span: start,
        }))
    }

    /// `{ entry | entry | … }` with an optional `*`. `key` names what the keys are, for errors.
    fn block(&mut self, key: &'static str) -> PResult<Block> {
        self.nested(|p| {
            let Braced {
                open,
                entries,
                close,
            } = p.braced("declaration", "after the block entry", |p| {
                p.block_entry(key)
            })?;
            let Some(close) = close else {
                return Ok(Block {
                    entries,
                    repeat: false,
                    span: p.span_from(open),
                });
            };
            let mut span = open.to(close);
            let repeat = match p.eat(&TokenKind::Star) {
                Some(star) => {
                    span = span.to(star);
                    true
                }
                None => false,
            };
            Ok(Block {
                entries,
                repeat,
                span,
            })
        })
    }

    /// `{ entry | entry | … }` from its `{` (the current token) to its `}`, each entry read by
    /// `entry`; shared by the main syntax's blocks and the Müller notation's. An entry that fails
    /// is skipped to the next `|` or `}`. A block still open at the next rule or declaration is
    /// reported as unclosed ("close the block with `}` before the next {`next`}") and ends there,
    /// without a `close`; `context` says where a missing `|` or `}` was expected.
    pub(super) fn braced<T>(
        &mut self,
        next: &str,
        context: &str,
        mut entry: impl FnMut(&mut Self) -> PResult<T>,
    ) -> PResult<Braced<T>> {
        let open = self.bump();
        let mut entries = Vec::new();
        loop {
            match entry(self) {
                Ok(e) => entries.push(e),
                Err(Fail) => self.recover_in_block(),
            }
            if self.eat(&TokenKind::Pipe).is_some() {
                continue;
            }
            if self.at(&TokenKind::RBrace) {
                break;
            }
            if self.declaration_start(self.pos) == Some(Start::Strong) {
                let d = Diagnostic::error("unclosed `{`", open)
                    .with_label("this block is never closed")
                    .with_hint(format!("close the block with `}}` before the next {next}"));
                self.report(d);
                return Ok(Braced {
                    open,
                    entries,
                    close: None,
                });
            }
            self.report(self.expected("`|` or `}`", context));
            self.recover_in_block();
            if self.eat(&TokenKind::Pipe).is_none() && !self.at(&TokenKind::RBrace) {
                return Err(Fail);
            }
        }
        let close = Some(self.bump());
        Ok(Braced {
            open,
            entries,
            close,
        })
    }

    /// `key : statements`, `key = statements` or a nested `{ … }` group.
    fn block_entry(&mut self, key_kind: &'static str) -> PResult<BlockEntry> {
        if self.at(&TokenKind::LBrace) {
            return Ok(BlockEntry::Group(self.block(key_kind)?));
        }
        if key_kind == BODY_ONLY {
            // The body applies to every part the operation makes: its key is `all`.
            let start = self.span();
            let body = self.statements(false)?;
            return Ok(BlockEntry::Part {
                key: Expr {
                    kind: ExprKind::Name("all".to_owned()),
                    span: Span::new(start.start as usize, start.start as usize),
                },
                merge: false,
                body,
                span: self.span_from(start),
            });
        }
        if !self.at_expression_start() {
            return Err(self.error_expected(&format!("a {key_kind}"), "in the block"));
        }
        let key = self.ternary()?;
        let merge = match self.peek() {
            TokenKind::Colon => {
                self.bump();
                false
            }
            TokenKind::Eq => {
                self.bump();
                true
            }
            // Most often a forgotten `:`; report it and read on as if it were there.
            _ => {
                self.report(self.expected("`:`", &format!("after the {key_kind}")));
                false
            }
        };
        let key = if key_kind == PERIMETER_SECTION {
            self.section_depth(key)?
        } else {
            key
        };
        let body = self.statements(false)?;
        Ok(BlockEntry::Part {
            span: self.span_from(key.span),
            key,
            merge,
            body,
        })
    }

    /// The `depth :` after a section's length in a perimeter split: the key becomes the pair
    /// `[length, depth]`.
    fn section_depth(&mut self, length: Expr) -> PResult<Expr> {
        if !self.at_expression_start() {
            return Err(self.error_expected("the section's setback depth", "after its length"));
        }
        let depth = self.ternary()?;
        if self.eat(&TokenKind::Colon).is_none() {
            self.report(self.expected("`:`", "after the section's depth"));
        }
        let span = length.span.to(depth.span);
        Ok(Expr {
            kind: ExprKind::Array(vec![length, depth]),
            span,
        })
    }
}

/// The entries of a `{ … }` block, as [`Parser::braced`] reads them.
pub(super) struct Braced<T> {
    /// The span of the `{`.
    pub(super) open: Span,
    /// The entries read, in order; those that failed are left out.
    pub(super) entries: Vec<T>,
    /// The span of the `}`; `None` when the block was left unclosed (already reported).
    pub(super) close: Option<Span>,
}

/// What the keys of an operation's block are called in messages.
fn key_kind(operation: &str) -> &'static str {
    if operation == PERIMETER_SPLIT {
        PERIMETER_SECTION
    } else if operation.starts_with("split") {
        "split size"
    } else if operation == "scatter" || OPERAND_FORMS.contains(&operation) {
        BODY_ONLY
    } else {
        "selector"
    }
}

/// The operation whose blocks [`Parser::perimeter_blocks`] reads.
const PERIMETER_SPLIT: &str = "splitAndSetbackPerimeter";

/// The key kind of a perimeter split's sections: `length : depth : body`.
const PERIMETER_SECTION: &str = "section length";

/// The operations whose operands are derived and merged back: their blocks hold bodies
/// without keys, and a single call may stand for the block.
const OPERAND_FORMS: &[&str] = &["union", "subtract", "intersect", "inline"];

/// The key kind of blocks whose one entry is a body without a key (`scatter(…){ Tree }`).
const BODY_ONLY: &str = "body";
