//! Building AST nodes for the lowerings of the dialects. Every node built here takes the span of
//! the construct it stands for, so diagnostics about it point at the original text.

use crate::Span;
use crate::ast::{
    Argument, BinaryOp, Block, BlockEntry, Call, Expr, ExprKind, Ident, Stmt, UnaryOp,
};

pub(super) fn ident(name: &str, span: Span) -> Ident {
    Ident {
        name: name.to_owned(),
        span,
    }
}

pub(super) fn expr(kind: ExprKind, span: Span) -> Expr {
    Expr { kind, span }
}

/// A number literal; negative numbers are built as `-(n)`, as the parser reads `-0.5`.
pub(super) fn number(n: f64, span: Span) -> Expr {
    if n < 0.0 {
        expr(
            ExprKind::Unary {
                op: UnaryOp::Neg,
                operand: Box::new(expr(ExprKind::Number(-n), span)),
            },
            span,
        )
    } else {
        expr(ExprKind::Number(n), span)
    }
}

pub(super) fn name(n: &str, span: Span) -> Expr {
    expr(ExprKind::Name(n.to_owned()), span)
}

pub(super) fn string(s: &str, span: Span) -> Expr {
    expr(ExprKind::String(s.to_owned()), span)
}

/// `'e`: relative to the scope size.
pub(super) fn relative(e: Expr) -> Expr {
    let span = e.span;
    expr(ExprKind::Relative(Box::new(e)), span)
}

/// `~e`: a floating split size.
pub(super) fn floating(e: Expr) -> Expr {
    let span = e.span;
    expr(ExprKind::Floating(Box::new(e)), span)
}

pub(super) fn negated(e: Expr) -> Expr {
    let span = e.span;
    expr(
        ExprKind::Unary {
            op: UnaryOp::Neg,
            operand: Box::new(e),
        },
        span,
    )
}

pub(super) fn binary(op: BinaryOp, lhs: Expr, rhs: Expr) -> Expr {
    let span = lhs.span.to(rhs.span);
    expr(
        ExprKind::Binary {
            op,
            lhs: Box::new(lhs),
            rhs: Box::new(rhs),
        },
        span,
    )
}

pub(super) fn positional(args: Vec<Expr>) -> Vec<Argument> {
    args.into_iter()
        .map(|value| Argument { name: None, value })
        .collect()
}

/// A call statement `name(args){block}` (with `.` when `terminal`).
pub(super) fn call(
    name: Ident,
    args: Option<Vec<Expr>>,
    block: Option<Block>,
    terminal: bool,
    span: Span,
) -> Stmt {
    Stmt::Call(Call {
        name,
        args: args.map(positional),
        block,
        terminal,
        span,
    })
}

/// `split(args){ block }` (the axis first, then options such as `snap`), the lowering of the
/// dialects' subdivisions: its name takes `name_span`, the span of the operation it stands for
/// (`Subdiv`, `Repeat`, …).
pub(super) fn split(name_span: Span, args: Vec<Expr>, block: Block, span: Span) -> Stmt {
    call(
        ident("split", name_span),
        Some(args),
        Some(block),
        false,
        span,
    )
}

/// An operation call `name(args)` whose name and whole call take `span`.
pub(super) fn op(name: &str, args: Vec<Expr>, span: Span) -> Stmt {
    call(ident(name, span), Some(args), None, false, span)
}

/// A successor `name` without arguments.
pub(super) fn successor(name: &str, span: Span) -> Stmt {
    call(ident(name, span), None, None, false, span)
}

/// `key : body`.
pub(super) fn part(key: Expr, body: Vec<Stmt>, span: Span) -> BlockEntry {
    BlockEntry::Part {
        key,
        merge: false,
        body,
        span,
    }
}

pub(super) fn block(entries: Vec<BlockEntry>, repeat: bool, span: Span) -> Block {
    Block {
        entries,
        repeat,
        span,
    }
}
