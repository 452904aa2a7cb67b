//! The operators of expressions: arithmetic, comparison and logic on two values, their
//! element-wise forms on arrays, ranges and indexing.

use shapegram_syntax::Span;
use shapegram_syntax::ast::{BinaryOp, UnaryOp};

use super::{Evaluator, Result};
use crate::error::DeriveError;
use crate::program::CExpr;
use crate::shape::State;
use crate::value::Value;

impl Evaluator<'_> {
    pub(super) fn binary(
        &mut self,
        op: BinaryOp,
        lhs: &CExpr,
        rhs: &CExpr,
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        use BinaryOp::*;
        if matches!(op, And | Or) {
            let left = self.condition(lhs, shape, args)?;
            return Ok(Value::Bool(match op {
                And => left && self.condition(rhs, shape, args)?,
                _ => left || self.condition(rhs, shape, args)?,
            }));
        }
        let a = self.eval(lhs, shape, args)?;
        let b = self.eval(rhs, shape, args)?;
        apply_binary(op, &a, &b, span, rhs.span)
    }

    /// `a[i]` and `a[r, c]`: an element, the elements at an array of indices or where a mask
    /// is true, and in a table, a cell, a row's cells or a column of rows.
    pub(super) fn index(
        &mut self,
        target: &CExpr,
        index: &CExpr,
        column: Option<&CExpr>,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let array = self.eval(target, shape, args)?;
        let Value::Array(items) = array else {
            return Err(DeriveError::at(
                format!("cannot index a {}", array.type_name()),
                target.span,
            ));
        };
        let rows = self.eval(index, shape, args)?;
        let Some(column) = column else {
            return select(&items, &rows, index.span);
        };
        let columns = self.eval(column, shape, args)?;
        let picked = select(&items, &rows, index.span)?;
        match (&rows, picked) {
            // One row: pick in it.
            (Value::Number(_), Value::Array(row)) => select(&row, &columns, column.span),
            // Several rows: pick in each, a column of them or a smaller table.
            (Value::Array(_), Value::Array(picked)) => {
                let mut out = Vec::with_capacity(picked.len());
                for row in picked.iter() {
                    let Value::Array(row) = row else {
                        return Err(not_2d(target.span));
                    };
                    out.push(select(row, &columns, column.span)?);
                }
                Ok(Value::Array(out.into()))
            }
            _ => Err(not_2d(target.span)),
        }
    }
}

/// A binary operator on two values (`&&` and `||` on booleans; the engine short-circuits them
/// before it gets here).
pub(super) fn apply_binary(
    op: BinaryOp,
    a: &Value,
    b: &Value,
    span: Span,
    rhs_span: Span,
) -> Result<Value> {
    use BinaryOp::*;
    let mismatch = |a: &Value, b: &Value| {
        DeriveError::at(
            format!(
                "cannot apply `{}` to a {} and a {}",
                binary_symbol(op),
                a.type_name(),
                b.type_name()
            ),
            span,
        )
    };
    Ok(match (op, a, b) {
        (Eq, _, _) => Value::Bool(a == b),
        (Ne, _, _) => Value::Bool(a != b),
        (Add, Value::Str(_), _) | (Add, _, Value::Str(_)) => Value::string(&format!("{a}{b}")),
        (_, Value::Number(x), Value::Number(y)) => {
            let (x, y) = (*x, *y);
            match op {
                Add => Value::Number(x + y),
                Sub => Value::Number(x - y),
                Mul => Value::Number(x * y),
                Div | Rem if y == 0.0 => {
                    return Err(DeriveError::at("division by zero", rhs_span));
                }
                Div => Value::Number(x / y),
                Rem => Value::Number(x % y),
                Lt => Value::Bool(x < y),
                Le => Value::Bool(x <= y),
                Gt => Value::Bool(x > y),
                Ge => Value::Bool(x >= y),
                Eq | Ne | And | Or => unreachable!("compared above or not numeric"),
            }
        }
        (And, Value::Bool(x), Value::Bool(y)) => Value::Bool(*x && *y),
        (Or, Value::Bool(x), Value::Bool(y)) => Value::Bool(*x || *y),
        (And | Or, _, _) => return Err(mismatch(a, b)),
        (Lt | Le | Gt | Ge, Value::Str(x), Value::Str(y)) => Value::Bool(match op {
            Lt => x < y,
            Le => x <= y,
            Gt => x > y,
            _ => x >= y,
        }),
        _ => return Err(mismatch(a, b)),
    })
}

pub(super) fn unary_symbol(op: UnaryOp) -> &'static str {
    match op {
        UnaryOp::Neg => "-",
        UnaryOp::Not => "!",
    }
}

pub(super) fn binary_symbol(op: BinaryOp) -> &'static str {
    use BinaryOp::*;
    match op {
        Mul => "*",
        Div => "/",
        Rem => "%",
        Add => "+",
        Sub => "-",
        Lt => "<",
        Le => "<=",
        Gt => ">",
        Ge => ">=",
        Eq => "==",
        Ne => "!=",
        And => "&&",
        Or => "||",
    }
}

/// Most numbers a range may hold: enough for any table, few enough to stop a runaway range.
const MAX_RANGE: usize = 10_000_000;

/// The numbers of `from:by:to`: from `from` in steps of `by` while not past `to`.
pub(super) fn range(from: f64, by: f64, to: f64, span: Span) -> Result<Vec<Value>> {
    if !(from.is_finite() && by.is_finite() && to.is_finite()) || by == 0.0 {
        return Err(DeriveError::at(
            format!("the range {from}:{by}:{to} needs finite ends and a step other than 0"),
            span,
        ));
    }
    // A step that divides the span up to rounding still reaches the end: 0:0.1:0.3 has 4.
    let count = ((to - from) / by + 1e-9).floor() + 1.0;
    if count > MAX_RANGE as f64 {
        return Err(DeriveError::at(
            format!("the range {from}:{by}:{to} has more than {MAX_RANGE} numbers"),
            span,
        ));
    }
    let count = count.max(0.0) as usize;
    Ok((0..count)
        .map(|i| Value::Number(from + by * i as f64))
        .collect())
}

/// The element of `items` at the index `at` (a number), or the elements at the indices of an
/// array of numbers, or where an array of booleans is true, as an array.
pub(super) fn select(items: &[Value], at: &Value, span: Span) -> Result<Value> {
    let one = |i: f64| {
        let k = i.floor();
        if k < 0.0 || k >= items.len() as f64 {
            return Err(DeriveError::at(
                format!("index {i} is out of range for an array of {}", items.len()),
                span,
            ));
        }
        Ok(items[k as usize].clone())
    };
    match at {
        Value::Number(i) => one(*i),
        // A mask (`names .== "oak"`) keeps the elements where it is true.
        Value::Array(mask)
            if mask.iter().all(|m| matches!(m, Value::Bool(_))) && !mask.is_empty() =>
        {
            if mask.len() != items.len() {
                return Err(DeriveError::at(
                    format!(
                        "a mask of {} booleans cannot select from an array of {}",
                        mask.len(),
                        items.len()
                    ),
                    span,
                ));
            }
            let kept = items
                .iter()
                .zip(mask.iter())
                .filter(|(_, m)| **m == Value::Bool(true))
                .map(|(item, _)| item.clone());
            Ok(Value::Array(kept.collect::<Vec<_>>().into()))
        }
        Value::Array(indices) => indices
            .iter()
            .map(|i| match i {
                Value::Number(i) => one(*i),
                other => Err(DeriveError::at(
                    format!("an index must be a number, found a {}", other.type_name()),
                    span,
                )),
            })
            .collect::<Result<Vec<_>>>()
            .map(|v| Value::Array(v.into())),
        other => Err(DeriveError::at(
            format!("an index must be a number, found a {}", other.type_name()),
            span,
        )),
    }
}

/// Two indices on an array that is not a table of rows.
pub(super) fn not_2d(span: Span) -> DeriveError {
    DeriveError::at(
        "two indices need a 2D array (rows written `[a, b; c, d]`)",
        span,
    )
}
/// An element-wise operator: arrays element by element (of the same size), a single value with
/// every element of an array.
pub(super) fn each_binary(
    op: BinaryOp,
    a: &Value,
    b: &Value,
    span: Span,
    rhs_span: Span,
) -> Result<Value> {
    let items = match (a, b) {
        (Value::Array(x), Value::Array(y)) if x.len() != y.len() => {
            return Err(DeriveError::at(
                format!(
                    "`.{}` needs arrays of the same size, not {} and {} elements",
                    binary_symbol(op),
                    x.len(),
                    y.len()
                ),
                span,
            ));
        }
        (Value::Array(x), Value::Array(y)) => x
            .iter()
            .zip(y.iter())
            .map(|(x, y)| each_binary(op, x, y, span, rhs_span))
            .collect::<Result<Vec<_>>>()?,
        (Value::Array(x), y) => x
            .iter()
            .map(|x| each_binary(op, x, y, span, rhs_span))
            .collect::<Result<Vec<_>>>()?,
        (x, Value::Array(y)) => y
            .iter()
            .map(|y| each_binary(op, x, y, span, rhs_span))
            .collect::<Result<Vec<_>>>()?,
        (x, y) => return apply_binary(op, x, y, span, rhs_span),
    };
    Ok(Value::Array(items.into()))
}

/// `.-` and `.!` on every element.
pub(super) fn each_unary(op: UnaryOp, v: &Value, span: Span) -> Result<Value> {
    Ok(match (op, v) {
        (_, Value::Array(items)) => Value::Array(
            items
                .iter()
                .map(|x| each_unary(op, x, span))
                .collect::<Result<Vec<_>>>()?
                .into(),
        ),
        (UnaryOp::Neg, Value::Number(n)) => Value::Number(-n),
        (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
        (op, v) => {
            return Err(DeriveError::at(
                format!(
                    "cannot apply `.{}` to a {}",
                    unary_symbol(op),
                    v.type_name()
                ),
                span,
            ));
        }
    })
}
