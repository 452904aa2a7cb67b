//! Expressions: a Pratt parser plus CGA's `case` and percentage expressions.
//!
//! Binding, loosest first: `c ? a : b`, `||`, `&&`, `== !=`, `< <= > >=`, `+ -`, `* / %`,
//! prefix `- !`, postfix calls and `a[i]`. The size prefixes `~` and `'` take everything after
//! them (`~scope.sx/n` is `~(scope.sx/n)`, `'1.85*8` is `'(1.85*8)`), as CGA authors expect.
//! A `%` directly followed by `:` is never the remainder operator: it ends a percentage
//! (`30% : …`).

use super::{Fail, PResult, Parser};
use crate::Diagnostic;
use crate::ast::{Argument, AttributeKind, BinaryOp, Expr, ExprKind, Ident, UnaryOp};
use crate::lexer::TokenKind;

/// Binding power of prefix `-` and `!` (postfix indexing binds tighter still).
const PREFIX_BP: u8 = 13;

impl Parser<'_> {
    /// A full expression: `case … else …`, `30% : … else …`, or a conditional expression.
    pub(super) fn expr(&mut self) -> PResult<Expr> {
        self.nested(|p| {
            if p.at_word("case") {
                return p.case_expr();
            }
            let first = p.ternary()?;
            if p.at_percent_colon() {
                return p.stochastic_expr(first);
            }
            Ok(first)
        })
    }

    /// An expression without `case` or percentage arms: conditions, percentages, split sizes.
    pub(super) fn ternary(&mut self) -> PResult<Expr> {
        self.nested(|p| {
            let cond = p.binary(0)?;
            if p.eat(&TokenKind::Question).is_none() {
                return Ok(cond);
            }
            let then = p.ternary()?;
            p.expect(&TokenKind::Colon, "`:`", "in the conditional expression")?;
            let otherwise = p.ternary()?;
            let span = cond.span.to(otherwise.span);
            Ok(Expr {
                kind: ExprKind::Conditional {
                    cond: Box::new(cond),
                    then: Box::new(then),
                    otherwise: Box::new(otherwise),
                },
                span,
            })
        })
    }

    /// Whether the current tokens are `%` `:`, the end of a percentage.
    pub(super) fn at_percent_colon(&self) -> bool {
        self.at(&TokenKind::Percent) && *self.peek_nth(1) == TokenKind::Colon
    }

    /// Whether a percentage arm `expr % :` starts here (a speculative parse, then rewound).
    pub(super) fn at_percent_arm(&mut self) -> bool {
        let could_start = match self.peek() {
            TokenKind::Number(_) | TokenKind::LParen | TokenKind::Minus => true,
            TokenKind::Ident => self.is_name_at(self.pos),
            _ => false,
        };
        if !could_start {
            return false;
        }
        let checkpoint = self.checkpoint();
        let outer = std::mem::replace(&mut self.speculating, true);
        let found = self.ternary().is_ok() && self.at_percent_colon();
        self.speculating = outer;
        // Nesting too deep here is too deep for the real parse as well: keep that verdict.
        if self.aborted {
            return false;
        }
        self.rewind(checkpoint);
        found
    }

    /// The `case condition : branch` arms at the current token, for `case` in rule bodies and in
    /// expressions alike: `branch` reads what follows each `:` (a body or a value).
    pub(super) fn case_arms<T>(
        &mut self,
        mut branch: impl FnMut(&mut Self) -> PResult<T>,
    ) -> PResult<Vec<(Expr, T)>> {
        let mut arms = Vec::new();
        while self.at_word("case") {
            self.bump();
            let cond = self.ternary()?;
            self.expect(&TokenKind::Colon, "`:`", "after the case condition")?;
            arms.push((cond, branch(self)?));
        }
        Ok(arms)
    }

    fn case_expr(&mut self) -> PResult<Expr> {
        let start = self.span();
        let arms = self.case_arms(Self::expr)?;
        let otherwise = self.else_value("a `case` expression")?;
        let span = start.to(otherwise.span);
        Ok(Expr {
            kind: ExprKind::Cases {
                arms,
                otherwise: Box::new(otherwise),
            },
            span,
        })
    }

    fn stochastic_expr(&mut self, first: Expr) -> PResult<Expr> {
        let start = first.span;
        let mut percent = first;
        let mut arms = Vec::new();
        loop {
            self.expect(&TokenKind::Percent, "`%`", "after the percentage")?;
            self.expect(&TokenKind::Colon, "`:`", "after the percentage")?;
            arms.push((percent, self.expr()?));
            if self.at_word("else") {
                break;
            }
            if !self.at_percent_arm() {
                let d = self
                    .expected("another percentage or `else`", "")
                    .with_hint("a percentage expression needs an `else` branch");
                self.report(d);
                return Err(Fail);
            }
            percent = self.ternary()?;
        }
        let otherwise = self.else_value("a percentage expression")?;
        let span = start.to(otherwise.span);
        Ok(Expr {
            kind: ExprKind::Stochastic {
                arms,
                otherwise: Box::new(otherwise),
            },
            span,
        })
    }

    /// `else : value`, required at the end of `case` and percentage expressions.
    fn else_value(&mut self, construct: &str) -> PResult<Expr> {
        if !self.at_word("else") {
            let message = format!("expected `case` or `else`, found {}", self.describe());
            let d = Diagnostic::error(message, self.span())
                .with_label("expected `else` here")
                .with_hint(format!("{construct} needs an `else` branch"));
            self.report(d);
            return Err(Fail);
        }
        self.bump();
        self.expect(&TokenKind::Colon, "`:`", "after `else`")?;
        self.expr()
    }

    /// Operators binding at least as tightly as `min_bp`.
    fn binary(&mut self, min_bp: u8) -> PResult<Expr> {
        self.nested(|p| {
            let mut lhs = p.prefix()?;
            loop {
                if *p.peek() == TokenKind::LBracket {
                    lhs = p.index(lhs)?;
                    continue;
                }
                if let Some(each) = p.element_wise_infix(&lhs, min_bp)? {
                    lhs = each;
                    continue;
                }
                let Some((op, left_bp)) = p.infix_op() else {
                    break;
                };
                if left_bp < min_bp {
                    break;
                }
                p.bump();
                let rhs = p.binary(left_bp + 1)?;
                let span = lhs.span.to(rhs.span);
                lhs = Expr {
                    kind: ExprKind::Binary {
                        op,
                        lhs: Box::new(lhs),
                        rhs: Box::new(rhs),
                    },
                    span,
                };
            }
            Ok(lhs)
        })
    }

    /// Whether the current token is a `.` written right against the operator after it: CGA's
    /// element-wise operators on arrays (`[1, 2] .* 2`, `names .== "a"`, `.![true]`).
    fn at_element_wise(&self) -> bool {
        self.at(&TokenKind::Dot)
            && self.token_at(self.pos).span.end == self.token_at(self.pos + 1).span.start
    }

    /// An element-wise infix operator with `lhs` on its left, if one binding at least as tightly
    /// as `min_bp` follows. It is read as a call of the built-in named by the operator (`.==`).
    fn element_wise_infix(&mut self, lhs: &Expr, min_bp: u8) -> PResult<Option<Expr>> {
        if !self.at_element_wise() {
            return Ok(None);
        }
        let saved = self.pos;
        self.pos += 1;
        let op = self.infix_op();
        self.pos = saved;
        let Some((_, left_bp)) = op.filter(|(_, bp)| *bp >= min_bp) else {
            return Ok(None);
        };
        let start = self.bump();
        let symbol = format!(".{}", self.text());
        let op_span = start.to(self.bump());
        let rhs = self.binary(left_bp + 1)?;
        let span = lhs.span.to(rhs.span);
        Ok(Some(element_wise_call(
            symbol,
            op_span,
            vec![lhs.clone(), rhs],
            span,
        )))
    }

    /// The infix operator at the current token and its (left) binding power.
    fn infix_op(&self) -> Option<(BinaryOp, u8)> {
        use BinaryOp as B;
        Some(match self.peek() {
            TokenKind::OrOr => (B::Or, 1),
            TokenKind::AndAnd => (B::And, 3),
            TokenKind::EqEq => (B::Eq, 5),
            TokenKind::Ne => (B::Ne, 5),
            TokenKind::Lt => (B::Lt, 7),
            TokenKind::Le => (B::Le, 7),
            TokenKind::Gt => (B::Gt, 7),
            TokenKind::Ge => (B::Ge, 7),
            TokenKind::Plus => (B::Add, 9),
            TokenKind::Minus => (B::Sub, 9),
            TokenKind::Star => (B::Mul, 11),
            TokenKind::Slash => (B::Div, 11),
            TokenKind::Percent if !self.at_percent_colon() => (B::Rem, 11),
            _ => return None,
        })
    }

    fn index(&mut self, target: Expr) -> PResult<Expr> {
        self.bump();
        let index = self.bracket_item()?;
        let column = match self.eat(&TokenKind::Comma) {
            Some(_) => Some(Box::new(self.bracket_item()?)),
            None => None,
        };
        let close = self.expect(&TokenKind::RBracket, "`]`", "after the index")?;
        Ok(Expr {
            span: target.span.to(close),
            kind: ExprKind::Index {
                target: Box::new(target),
                index: Box::new(index),
                column,
            },
        })
    }

    /// An expression in array brackets, where CGA's colon operator may make it a range:
    /// `a`, `a:b` or `a:step:b`.
    fn bracket_item(&mut self) -> PResult<Expr> {
        let start = self.expr()?;
        if self.eat(&TokenKind::Colon).is_none() {
            return Ok(start);
        }
        let second = self.expr()?;
        let (step, end) = match self.eat(&TokenKind::Colon) {
            Some(_) => (Some(Box::new(second)), self.expr()?),
            None => (None, second),
        };
        Ok(Expr {
            span: start.span.to(end.span),
            kind: ExprKind::Range {
                start: Box::new(start),
                step,
                end: Box::new(end),
            },
        })
    }

    fn prefix(&mut self) -> PResult<Expr> {
        let start = self.span();
        if self.at_element_wise()
            && matches!(
                self.kind_at(self.pos + 1),
                TokenKind::Bang | TokenKind::Minus | TokenKind::Plus
            )
        {
            self.bump();
            let symbol = format!(".{}", self.text());
            let op_span = start.to(self.bump());
            let operand = self.binary(PREFIX_BP)?;
            let span = start.to(operand.span);
            return Ok(element_wise_call(symbol, op_span, vec![operand], span));
        }
        if self.at(&TokenKind::Plus) {
            // CGA's unary plus (`h ++.3048` is `h + +0.3048`) leaves its operand as it is.
            self.bump();
            let operand = self.binary(PREFIX_BP)?;
            return Ok(Expr {
                span: start.to(operand.span),
                kind: operand.kind,
            });
        }
        let (wrap, bp): (fn(Box<Expr>) -> ExprKind, u8) = match self.peek() {
            TokenKind::Minus => (
                |e| ExprKind::Unary {
                    op: UnaryOp::Neg,
                    operand: e,
                },
                PREFIX_BP,
            ),
            TokenKind::Bang => (
                |e| ExprKind::Unary {
                    op: UnaryOp::Not,
                    operand: e,
                },
                PREFIX_BP,
            ),
            TokenKind::Tilde => (ExprKind::Floating, 0),
            TokenKind::Quote => (ExprKind::Relative, 0),
            _ => return self.primary(),
        };
        self.bump();
        let operand = self.binary(bp)?;
        Ok(Expr {
            span: start.to(operand.span),
            kind: wrap(Box::new(operand)),
        })
    }

    fn primary(&mut self) -> PResult<Expr> {
        let span = self.span();
        let kind = match self.peek().clone() {
            TokenKind::Number(n) => {
                self.bump();
                ExprKind::Number(n)
            }
            // `1r` of the Müller notation; what it means depends on the operation.
            TokenKind::RelNumber(n) => {
                self.bump();
                ExprKind::Relative(Box::new(Expr {
                    kind: ExprKind::Number(n),
                    span,
                }))
            }
            TokenKind::Str(s) => {
                self.bump();
                ExprKind::String(s)
            }
            TokenKind::LParen => {
                self.bump();
                let inner = self.expr()?;
                let close = self.close(&TokenKind::RParen, span, "`)`", "after the expression")?;
                return Ok(Expr {
                    kind: inner.kind,
                    span: span.to(close),
                });
            }
            TokenKind::LBracket => return self.array(),
            TokenKind::At => return self.attribute_getter(),
            TokenKind::Ident => match self.text() {
                word @ ("true" | "false") => {
                    self.bump();
                    ExprKind::Bool(word == "true")
                }
                _ if self.is_name_at(self.pos) => return self.name_or_call(),
                _ => return Err(self.error_expected("an expression", "")),
            },
            _ => return Err(self.error_expected("an expression", "")),
        };
        Ok(Expr { kind, span })
    }

    /// A goal grammar's attribute getter: `@Leg.Size`, `@Double("Leg.Size")` or
    /// `@String("Style")` (the compiler refuses them outside goal grammars).
    fn attribute_getter(&mut self) -> PResult<Expr> {
        let at = self.bump();
        if *self.peek() != TokenKind::Ident {
            return Err(self.error_expected("an attribute name", "after `@`"));
        }
        let typed = match self.text() {
            "Double" | "Number" => Some(AttributeKind::Number),
            "String" => Some(AttributeKind::String),
            _ => None,
        };
        let (name, kind, span) = match typed {
            Some(kind) if *self.kind_at(self.pos + 1) == TokenKind::LParen => {
                self.bump();
                self.bump();
                let TokenKind::Str(name) = self.peek().clone() else {
                    return Err(self.error_expected("the attribute's name as a string", "in `(`"));
                };
                self.bump();
                let close =
                    self.close(&TokenKind::RParen, at, "`)`", "after the attribute's name")?;
                (name, kind, at.to(close))
            }
            _ => {
                let name = self.ident();
                (name.name, AttributeKind::Any, at.to(name.span))
            }
        };
        Ok(Expr {
            kind: ExprKind::GoalAttribute { name, kind },
            span,
        })
    }

    fn name_or_call(&mut self) -> PResult<Expr> {
        let name = self.ident();
        if !self.at(&TokenKind::LParen) {
            return Ok(Expr {
                span: name.span,
                kind: ExprKind::Name(name.name),
            });
        }
        let (mut args, close) = self.call_args()?;
        let mut span = name.span.to(close);
        // CGA's comp function `comp(fe){ all : 3 }` lowers to `comp(fe, all = 3)`. A
        // speculative parse stops before the block: no percentage arm contains one, and
        // skipping it keeps nested `comp(f){ … }` statements from being re-read at each level.
        if name.name == "comp" && self.at(&TokenKind::LBrace) && !self.speculating {
            let (entries, end) = self.comp_function_block()?;
            args.extend(entries);
            span = span.to(end);
        }
        Ok(Expr {
            kind: ExprKind::Call { name, args },
            span,
        })
    }

    /// `{ selector : value | … }` after `comp(…)` in an expression, as named arguments.
    fn comp_function_block(&mut self) -> PResult<(Vec<Argument>, crate::Span)> {
        self.nested(|p| {
            p.bump();
            let mut entries = Vec::new();
            loop {
                let selector = match p.peek() {
                    TokenKind::Ident | TokenKind::Number(_) => p.ident(),
                    _ => return Err(p.error_expected("a selector", "in the comp function")),
                };
                // `sel = v` (CityEngine's grouping form) gives the value as `sel : v` does.
                if p.eat(&TokenKind::Eq).is_none() {
                    p.expect(&TokenKind::Colon, "`:`", "after the selector")?;
                }
                entries.push(Argument {
                    name: Some(selector),
                    value: p.expr()?,
                });
                if p.eat(&TokenKind::Pipe).is_none() {
                    break;
                }
            }
            let close = p.expect(&TokenKind::RBrace, "`|` or `}`", "in the comp function")?;
            Ok((entries, close))
        })
    }

    /// Consumes the closing bracket `kind` of the bracket opened at `open`. When it is missing
    /// and the next declaration (or the end) follows, the error points at the opening bracket.
    pub(super) fn close(
        &mut self,
        kind: &TokenKind,
        open: crate::Span,
        what: &str,
        context: &str,
    ) -> PResult<crate::Span> {
        if let Some(span) = self.eat(kind) {
            return Ok(span);
        }
        if self.at(&TokenKind::Eof) || self.at_resume_point() {
            let bracket = &self.src[open.range()];
            let d = Diagnostic::error(format!("unclosed `{bracket}`"), open)
                .with_label("this bracket is never closed");
            self.report(d);
            return Err(Fail);
        }
        Err(self.error_expected(what, context))
    }

    /// Whether an expression can start at the current token.
    pub(super) fn at_expression_start(&self) -> bool {
        match self.peek() {
            TokenKind::Number(_)
            | TokenKind::RelNumber(_)
            | TokenKind::Str(_)
            | TokenKind::LParen
            | TokenKind::LBracket
            | TokenKind::Minus
            | TokenKind::Bang
            | TokenKind::Tilde
            | TokenKind::At
            | TokenKind::Quote => true,
            TokenKind::Ident => {
                self.is_name_at(self.pos) || self.at_word("true") || self.at_word("false")
            }
            _ => false,
        }
    }

    /// The current token as an [`Ident`] (consumed).
    pub(super) fn ident(&mut self) -> Ident {
        let name = self.text().to_string();
        Ident {
            name,
            span: self.bump(),
        }
    }

    /// `[a, b]`, or `[a, b; c, d]` (rows, lowered to an array of arrays).
    fn array(&mut self) -> PResult<Expr> {
        let open = self.bump();
        let mut rows: Vec<Vec<Expr>> = vec![Vec::new()];
        let mut row_spans = vec![self.span()];
        if !self.at(&TokenKind::RBracket) {
            loop {
                let element = self.bracket_item()?;
                let last = rows.len() - 1;
                row_spans[last] = if rows[last].is_empty() {
                    element.span
                } else {
                    row_spans[last].to(element.span)
                };
                rows[last].push(element);
                if self.eat(&TokenKind::Comma).is_some() {
                    continue;
                }
                if self.eat(&TokenKind::Semi).is_some() {
                    rows.push(Vec::new());
                    row_spans.push(self.span());
                    continue;
                }
                break;
            }
        }
        let close = self.close(&TokenKind::RBracket, open, "`,` or `]`", "in the array")?;
        let span = open.to(close);
        let kind = if rows.len() == 1 {
            ExprKind::Array(rows.pop().unwrap_or_default())
        } else {
            ExprKind::Array(
                rows.into_iter()
                    .zip(row_spans)
                    .map(|(row, span)| Expr {
                        kind: ExprKind::Array(row),
                        span,
                    })
                    .collect(),
            )
        };
        Ok(Expr { kind, span })
    }

    /// `( arg, name = arg, … )`, returning the arguments and the span of `)`. An error inside
    /// is recovered by skipping to the matching `)` when there is one.
    pub(super) fn call_args(&mut self) -> PResult<(Vec<Argument>, crate::Span)> {
        let open = self.pos;
        let open_span = self.bump();
        let mut args = Vec::new();
        match self.arguments(&mut args, open_span) {
            Ok(close) => Ok((args, close)),
            Err(fail) => match self.closing_paren(open) {
                Some(close) if !self.aborted && close >= self.pos => {
                    while self.pos < close {
                        // A `)` past the next declaration belongs to something else.
                        if self.at_resume_point() {
                            return Err(fail);
                        }
                        self.bump();
                    }
                    Ok((args, self.bump()))
                }
                _ => Err(fail),
            },
        }
    }

    fn arguments(&mut self, args: &mut Vec<Argument>, open: crate::Span) -> PResult<crate::Span> {
        if let Some(close) = self.eat(&TokenKind::RParen) {
            return Ok(close);
        }
        loop {
            let name = if self.is_name_at(self.pos) && *self.peek_nth(1) == TokenKind::Eq {
                let name = self.ident();
                self.bump();
                Some(name)
            } else {
                None
            };
            let value = self.expr()?;
            args.push(Argument { name, value });
            if self.eat(&TokenKind::Comma).is_none() {
                return self.close(
                    &TokenKind::RParen,
                    open,
                    "`,` or `)`",
                    "in the argument list",
                );
            }
        }
    }
}

/// `a .op b` (or `.op a`) as the call `.op(a, b)` of the element-wise built-in.
fn element_wise_call(
    symbol: String,
    op_span: crate::Span,
    operands: Vec<Expr>,
    span: crate::Span,
) -> Expr {
    Expr {
        kind: ExprKind::Call {
            name: Ident {
                name: symbol,
                span: op_span,
            },
            args: operands
                .into_iter()
                .map(|value| Argument { name: None, value })
                .collect(),
        },
        span,
    }
}
