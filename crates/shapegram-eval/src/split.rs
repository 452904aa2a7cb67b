//! Where the parts of a split go: CGA's rules for absolute, relative and floating sizes and for
//! repeated groups.
//!
//! 1. Sizes are evaluated once per split: `'r` becomes `r × length`, `~f` is a floating size
//!    with nominal value `f`, anything else is absolute.
//! 2. Repeated groups `{ … }*` share the length left after the parts outside them (at their
//!    nominal sizes), equally. A group repeats `max(1, round(budget / group))` times when it
//!    holds a floating size, else `floor(budget / group)` times. Repeats nested inside a
//!    repeated group run once per repetition of the outer group.
//! 3. Floating sizes scale together to fill the length the absolute sizes leave (never below
//!    zero).
//! 4. Parts are laid out from 0. Zero or negative sizes make no part and take no room; a part
//!    that reaches past the end is cut at the end, and parts that start at or after the end are
//!    dropped.

use shapegram_syntax::Span;

use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::ops::{SplitBlock, SplitEntry};
use crate::program::{CKind, CStmt};
use crate::shape::State;
use crate::value::Value;

/// At most this many parts per split, so a typo cannot exhaust memory before the shape limit.
pub(crate) const MAX_PARTS: usize = 1_000_000;

/// One laid-out part: where it starts and ends along the axis, and what to do with it.
pub(crate) struct Part<'a> {
    pub start: f64,
    pub size: f64,
    pub body: &'a [CStmt],
}

enum Item<'a> {
    Part {
        floating: bool,
        size: f64,
        body: &'a [CStmt],
    },
    Group {
        items: Vec<Item<'a>>,
        repeat: bool,
        span: Span,
    },
}

/// Lays out the parts of `block` along a length.
pub(crate) fn layout<'a>(
    block: &'a SplitBlock,
    length: f64,
    span: Span,
    ev: &mut Evaluator,
    shape: &mut State,
    args: &[Value],
) -> Result<Vec<Part<'a>>, DeriveError> {
    let items = evaluate(block, length, ev, shape, args)?;
    let mut flat = Vec::new();
    if block.repeat {
        // `split(y){ … }*` repeats the whole block.
        let whole = [Item::Group {
            items,
            repeat: true,
            span,
        }];
        expand(&whole, length, &mut flat)?;
    } else {
        expand(&items, length, &mut flat)?;
    }
    let fixed: f64 = flat.iter().filter(|p| !p.0).map(|p| p.1).sum();
    let floating: f64 = flat.iter().filter(|p| p.0).map(|p| p.1).sum();
    let scale = if floating > 0.0 {
        ((length - fixed) / floating).max(0.0)
    } else {
        0.0
    };
    let eps = 1e-9 * length.abs().max(1.0);
    let mut parts = Vec::new();
    let mut at = 0.0;
    for (is_floating, nominal, body) in flat {
        let size = if is_floating {
            nominal * scale
        } else {
            nominal
        };
        if size <= 0.0 {
            continue;
        }
        if at >= length - eps {
            break;
        }
        parts.push(Part {
            start: at,
            size: size.min(length - at),
            body,
        });
        at += size;
    }
    Ok(parts)
}

fn evaluate<'a>(
    block: &'a SplitBlock,
    length: f64,
    ev: &mut Evaluator,
    shape: &mut State,
    args: &[Value],
) -> Result<Vec<Item<'a>>, DeriveError> {
    block
        .entries
        .iter()
        .map(|entry| {
            Ok(match entry {
                SplitEntry::Part { size, body } => {
                    let (floating, value) = match &size.kind {
                        CKind::Floating(inner) => (true, ev.number(inner, shape, args)?),
                        CKind::Relative(inner) => (false, ev.number(inner, shape, args)? * length),
                        _ => (false, ev.number(size, shape, args)?),
                    };
                    Item::Part {
                        floating,
                        size: value,
                        body,
                    }
                }
                SplitEntry::Group(group) => Item::Group {
                    items: evaluate(group, length, ev, shape, args)?,
                    repeat: group.repeat,
                    span: group.entries.first().map_or(Span::default(), |e| match e {
                        SplitEntry::Part { size, .. } => size.span,
                        SplitEntry::Group(_) => Span::default(),
                    }),
                },
            })
        })
        .collect()
}

/// Nominal length of items at one repetition each; repeated groups count once.
fn nominal(items: &[Item]) -> f64 {
    items
        .iter()
        .map(|i| match i {
            Item::Part { size, .. } => size.max(0.0),
            Item::Group { items, .. } => nominal(items),
        })
        .sum()
}

fn has_floating(items: &[Item]) -> bool {
    items.iter().any(|i| match i {
        Item::Part { floating, .. } => *floating,
        Item::Group { items, .. } => has_floating(items),
    })
}

/// Flattens items into `(floating, nominal size, body)` parts, repeating groups as rule 2 says.
fn expand<'a>(
    items: &[Item<'a>],
    length: f64,
    out: &mut Vec<(bool, f64, &'a [CStmt])>,
) -> Result<(), DeriveError> {
    let outside: f64 = items
        .iter()
        .map(|i| match i {
            Item::Group { repeat: true, .. } => 0.0,
            other => nominal(std::slice::from_ref(other)),
        })
        .sum();
    let repeats = items
        .iter()
        .filter(|i| matches!(i, Item::Group { repeat: true, .. }))
        .count();
    let budget = if repeats > 0 {
        (length - outside).max(0.0) / repeats as f64
    } else {
        0.0
    };
    for item in items {
        match item {
            Item::Part {
                floating,
                size,
                body,
            } => out.push((*floating, *size, body)),
            Item::Group {
                items,
                repeat: false,
                ..
            } => expand(items, nominal(items), out)?,
            Item::Group {
                items,
                repeat: true,
                span,
            } => {
                let unit = nominal(items);
                if unit <= 0.0 {
                    return Err(DeriveError::at(
                        "a repeated split group needs a positive size",
                        *span,
                    ));
                }
                let count = if has_floating(items) {
                    (budget / unit).round().max(1.0)
                } else {
                    (budget / unit + 1e-9).floor()
                };
                if count > MAX_PARTS as f64 || out.len() as f64 + count > MAX_PARTS as f64 {
                    return Err(DeriveError::at(
                        format!("this repeat would make {count} parts (the limit is {MAX_PARTS})"),
                        *span,
                    )
                    .with_hint(
                        "check the sizes: a tiny size in a repeat fills the scope with slivers",
                    ));
                }
                for _ in 0..count as usize {
                    expand(items, unit, out)?;
                }
            }
        }
    }
    Ok(())
}
