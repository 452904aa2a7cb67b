//! Where the parts of a split go: CGA's rules for absolute, relative and floating sizes and for
//! repeated groups.
//!
//! 1. Sizes are evaluated once per split: `'r` becomes `r × length`, `~f` is a floating size
//!    with nominal value `f`, anything else is absolute.
//! 2. Repeated groups `{ … }*` share the length left after the parts outside them (at their
//!    nominal sizes): each in turn takes an equal share of what the groups before it left
//!    (at their nominal sizes times their repetitions). A group that holds a floating size repeats the number of times
//!    that stretches the floating sizes least (CityEngine's "closest to the target length"):
//!    of the two whole counts around `budget / group`, the one whose floating sizes come out
//!    nearer their nominal ones (the smaller on a tie); at least once, unless floating parts
//!    outside the group can fill the length (`{ ~w : Window | 0.25 : Wall }* | ~w : Window`
//!    is one window where one window fits). Other groups repeat `floor(budget / group)` times.
//!    Repeats nested inside a repeated group run once per repetition of the outer group.
//! 3. Floating sizes scale together to fill the length the absolute sizes leave (never below
//!    zero).
//! 4. Parts are laid out from 0. Zero or negative sizes make no part and take no room; a part
//!    that reaches past the end is cut at the end, and parts that start at or after the end are
//!    dropped.

use shapegram_syntax::Span;

use crate::error::DeriveError;
use crate::expr::Evaluator;
use crate::ops::{SplitBlock, SplitEntry};
use crate::program::{CExpr, CKind, CStmt};
use crate::shape::State;
use crate::value::Value;

/// At most this many parts per split, so a typo cannot exhaust memory before the shape limit.
const MAX_PARTS: usize = 1_000_000;

/// Layouts kept with their parts for the next splits of the same block and length: a facade's
/// floors and a floor's tiles come one after the other, so a few suffice.
const KEPT_LAYOUTS: usize = 8;

/// One laid-out part: where it starts and ends along the axis, and what to do with it.
pub(in crate::engine) struct Part<'a> {
    pub start: f64,
    pub size: f64,
    pub body: &'a [CStmt],
    /// A perimeter split's setback depth for the part.
    pub depth: Option<&'a CExpr>,
    /// The top-level repeated group the part came from and its repetition, if any.
    pub repeat: Option<Repetition>,
}

/// A repetition of a top-level repeated group: (group number, repetition number).
pub(in crate::engine) type Repetition = (u32, u32);

/// One flattened part: floating or not, nominal size, body and depth, repetition.
type FlatPart<'a> = (
    bool,
    f64,
    (&'a [CStmt], Option<&'a CExpr>),
    Option<Repetition>,
);

/// An evaluated entry of a split block. Groups are stored flat, in preorder: a group is
/// followed by the `len` items inside it.
enum Item<'a> {
    Part {
        floating: bool,
        size: f64,
        body: &'a [CStmt],
        depth: Option<&'a CExpr>,
    },
    Group {
        len: usize,
        repeat: bool,
        span: Span,
    },
}

/// The working lists of a split, kept between splits so that laying out allocates nothing.
#[derive(Default)]
pub(in crate::engine) struct Layout<'a> {
    items: Vec<Item<'a>>,
    flat: Vec<FlatPart<'a>>,
    /// The parts of the last [`Layout::lay_out`].
    pub parts: Vec<Part<'a>>,
    /// The block (its address) and length of the last layout when its sizes are all literal
    /// numbers: the parts only depend on these, and the next layout of the same block and
    /// length can keep them (splits of equal tiles lay out the same block again and again).
    last: Option<(usize, u64)>,
}

/// The layouts not in use, most recently used last: splits nest, so there can be several in
/// use at once.
#[derive(Default)]
pub(in crate::engine) struct Layouts<'a> {
    free: Vec<Layout<'a>>,
}

impl<'a> Layouts<'a> {
    /// A layout for a split of `block` along `length`: the one that last laid out that block
    /// at that length when it is kept (its parts stand, see [`Layout::lay_out`]), else one
    /// that keeps nothing, a new one, or the least recently used.
    pub(in crate::engine) fn take_for(&mut self, block: &SplitBlock, length: f64) -> Layout<'a> {
        let key = Some(key_of(block, length));
        if let Some(i) = self.free.iter().rposition(|l| l.last == key) {
            return self.free.remove(i);
        }
        if let Some(i) = self.free.iter().rposition(|l| l.last.is_none()) {
            return self.free.remove(i);
        }
        if self.free.len() < KEPT_LAYOUTS {
            return Layout::default();
        }
        self.free.remove(0)
    }

    /// A layout for a caller that changes its parts or lays out something else.
    pub(in crate::engine) fn take(&mut self) -> Layout<'a> {
        self.free.pop().unwrap_or_default()
    }

    /// Returns a layout taken with [`Layouts::take_for`] or [`Layouts::take`].
    pub(in crate::engine) fn put(&mut self, layout: Layout<'a>) {
        self.free.push(layout);
    }
}

/// What a layout of literal sizes depends on: the block (its address) and the length.
fn key_of(block: &SplitBlock, length: f64) -> (usize, u64) {
    (std::ptr::from_ref(block) as usize, length.to_bits())
}

impl<'a> Layout<'a> {
    /// Lays out the parts of `block` along a length into [`Layout::parts`].
    pub(in crate::engine) fn lay_out(
        &mut self,
        block: &'a SplitBlock,
        length: f64,
        span: Span,
        ev: &mut Evaluator,
        shape: &mut State,
        args: &[Value],
    ) -> Result<(), DeriveError> {
        let key = key_of(block, length);
        if self.last == Some(key) {
            return Ok(());
        }
        self.last = None;
        self.items.clear();
        self.flat.clear();
        self.parts.clear();
        if block.repeat {
            // `split(y){ … }*` repeats the whole block.
            self.items.push(Item::Group {
                len: 0,
                repeat: true,
                span,
            });
        }
        evaluate(block, length, ev, shape, args, &mut self.items)?;
        let inside = self.items.len().saturating_sub(1);
        if let Some(Item::Group { len, .. }) = self.items.first_mut().filter(|_| block.repeat) {
            *len = inside;
        }
        expand(&self.items, length, &mut self.flat, None)?;
        let flat = &self.flat;
        let fixed: f64 = flat.iter().filter(|p| !p.0).map(|p| p.1).sum();
        let floating: f64 = flat.iter().filter(|p| p.0).map(|p| p.1).sum();
        let scale = if floating > 0.0 {
            ((length - fixed) / floating).max(0.0)
        } else {
            0.0
        };
        let eps = 1e-9 * length.abs().max(1.0);
        let mut at = 0.0;
        for &(is_floating, nominal, (body, depth), repeat) in flat {
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
            self.parts.push(Part {
                start: at,
                size: size.min(length - at),
                body,
                depth,
                repeat,
            });
            at += size;
        }
        if literal(block) {
            self.last = Some(key);
        }
        Ok(())
    }
}

impl Layout<'_> {
    /// Forgets the block and length of the last layout, for a caller that changes the parts.
    pub(in crate::engine) fn forget(&mut self) {
        self.last = None;
    }

    /// Moves boundaries of the laid-out parts to snap positions (distances along the axis,
    /// ascending), as Müller et al. 2006 describe: for each position, the nearest boundary
    /// moves onto it. A boundary inside a repeated group redistributes the group: its
    /// repetitions stay evenly spaced on either side of every boundary fixed so far. Boundaries
    /// between parts of one repetition never snap, the ends of the split never move, and a snap
    /// that would reorder boundaries or empty a part is skipped. The total size is unchanged.
    pub(super) fn snap(&mut self, positions: &[f64]) {
        self.last = None;
        let parts = &mut self.parts;
        let n = parts.len();
        if n < 2 {
            return;
        }
        let original: Vec<f64> = parts
            .iter()
            .map(|p| p.start)
            .chain(std::iter::once(parts[n - 1].start + parts[n - 1].size))
            .collect();
        let movable = |i: usize| {
            (1..n).contains(&i)
                && !(parts[i].repeat.is_some() && parts[i].repeat == parts[i - 1].repeat)
        };
        let mut fixed: Vec<Option<f64>> = vec![None; n + 1];
        let mut bounds = original.clone();
        for &s in positions {
            let nearest = (1..n)
                .filter(|&i| movable(i) && fixed[i].is_none())
                .min_by(|&a, &b| (bounds[a] - s).abs().total_cmp(&(bounds[b] - s).abs()));
            let Some(i) = nearest else { break };
            let below = (0..i)
                .rev()
                .find(|&j| j == 0 || fixed[j].is_some())
                .unwrap_or(0);
            let above = (i + 1..=n)
                .find(|&j| j == n || fixed[j].is_some())
                .unwrap_or(n);
            if !(bounds[below] < s && s < bounds[above]) {
                continue;
            }
            fixed[i] = Some(s);
            let trial = redistribute(&original, &fixed, parts);
            if trial.windows(2).all(|w| w[1] > w[0]) {
                bounds = trial;
            } else {
                fixed[i] = None;
            }
        }
        for (i, part) in parts.iter_mut().enumerate() {
            part.start = bounds[i];
            part.size = bounds[i + 1] - bounds[i];
        }
    }
}

/// Boundary positions with the fixed ones in place: other boundaries of a repeated group are
/// spread evenly (an affine map of their original positions) between the group's ends and its
/// fixed boundaries; boundaries outside groups stay where they were.
fn redistribute(original: &[f64], fixed: &[Option<f64>], parts: &[Part]) -> Vec<f64> {
    let mut bounds: Vec<f64> = original
        .iter()
        .zip(fixed)
        .map(|(&o, f)| f.unwrap_or(o))
        .collect();
    let group = |i: usize| parts[i].repeat.map(|(g, _)| g);
    let mut i = 0;
    while i < parts.len() {
        let Some(g) = group(i) else {
            i += 1;
            continue;
        };
        let mut end = i + 1;
        while end < parts.len() && group(end) == Some(g) {
            end += 1;
        }
        let anchors: Vec<usize> = (i..=end)
            .filter(|&k| k == i || k == end || fixed[k].is_some())
            .collect();
        for pair in anchors.windows(2) {
            let (a, c) = (pair[0], pair[1]);
            let scale = (bounds[c] - bounds[a]) / (original[c] - original[a]);
            for k in a + 1..c {
                bounds[k] = bounds[a] + (original[k] - original[a]) * scale;
            }
        }
        i = end;
    }
    bounds
}

/// Whether every size in a block is a literal number (absolute, floating or relative), so that
/// evaluating them draws no random numbers and reads nothing but the length.
fn literal(block: &SplitBlock) -> bool {
    block.entries.iter().all(|entry| match entry {
        SplitEntry::Part { size, .. } => {
            let inner = match &size.kind {
                CKind::Floating(inner) | CKind::Relative(inner) => inner,
                _ => size,
            };
            matches!(inner.kind, CKind::Value(Value::Number(n)) if n.is_finite())
        }
        SplitEntry::Group(group) => literal(group),
    })
}

/// Evaluates the sizes of a block's entries, in order, appending them to `out`.
fn evaluate<'a>(
    block: &'a SplitBlock,
    length: f64,
    ev: &mut Evaluator,
    shape: &mut State,
    args: &[Value],
    out: &mut Vec<Item<'a>>,
) -> Result<(), DeriveError> {
    for entry in &block.entries {
        match entry {
            SplitEntry::Part { size, depth, body } => {
                let (floating, value) = match &size.kind {
                    CKind::Floating(inner) => (true, ev.number(inner, shape, args)?),
                    CKind::Relative(inner) => (false, ev.number(inner, shape, args)? * length),
                    _ => (false, ev.number(size, shape, args)?),
                };
                out.push(Item::Part {
                    floating,
                    size: value,
                    body,
                    depth: depth.as_ref(),
                });
            }
            SplitEntry::Group(group) => {
                let at = out.len();
                out.push(Item::Group {
                    len: 0,
                    repeat: group.repeat,
                    span: group.entries.first().map_or(Span::default(), |e| match e {
                        SplitEntry::Part { size, .. } => size.span,
                        SplitEntry::Group(_) => Span::default(),
                    }),
                });
                evaluate(group, length, ev, shape, args, out)?;
                let end = out.len();
                if let Item::Group { len, .. } = &mut out[at] {
                    *len = end - at - 1;
                }
            }
        }
    }
    Ok(())
}

/// The top-level items of a flat item list, each with the items inside it (empty for parts).
fn top<'s, 'a>(items: &'s [Item<'a>]) -> impl Iterator<Item = (&'s Item<'a>, &'s [Item<'a>])> {
    let mut rest = items;
    std::iter::from_fn(move || {
        let (first, tail) = rest.split_first()?;
        let len = match first {
            Item::Group { len, .. } => *len,
            Item::Part { .. } => 0,
        };
        let (inner, after) = tail.split_at(len);
        rest = after;
        Some((first, inner))
    })
}

/// Nominal length of one item at one repetition; repeated groups inside count once.
fn nominal_of(item: &Item, inner: &[Item]) -> f64 {
    match item {
        Item::Part { size, .. } => size.max(0.0),
        Item::Group { .. } => nominal(inner),
    }
}

/// Nominal length of items at one repetition each; repeated groups count once.
fn nominal(items: &[Item]) -> f64 {
    top(items).map(|(i, inner)| nominal_of(i, inner)).sum()
}

/// Nominal length of the floating parts of items at one repetition each.
fn floating_nominal(items: &[Item]) -> f64 {
    top(items)
        .map(|(i, inner)| match i {
            Item::Part { floating, size, .. } => f64::from(u8::from(*floating)) * size.max(0.0),
            Item::Group { .. } => floating_nominal(inner),
        })
        .sum()
}

/// How often a repeated group of nominal length `unit`, `floating` of it floating, repeats in
/// `budget` (its share of the length beyond the nominal parts outside the groups, `outside` of
/// which float): the whole count around `budget / unit` whose floating sizes stretch least
/// from nominal, the smaller on a tie; zero only when floating parts outside can fill.
fn least_stretching_count(budget: f64, unit: f64, floating: f64, outside: f64) -> f64 {
    let lowest = if outside > 0.0 { 0.0 } else { 1.0 };
    // What the floating sizes are multiplied by with `r` repetitions; never a fit below zero.
    let stretch = |r: f64| {
        let fixed = r * (unit - floating);
        let floats = outside + r * floating;
        let scale = (budget + outside - fixed) / floats;
        if scale > 0.0 && scale.is_finite() {
            (scale - 1.0).abs()
        } else {
            f64::INFINITY
        }
    };
    let ideal = budget / unit;
    let (below, above) = (ideal.floor().max(lowest), ideal.ceil().max(lowest));
    if stretch(above) < stretch(below) {
        above
    } else {
        below
    }
}

fn has_floating(items: &[Item]) -> bool {
    items
        .iter()
        .any(|i| matches!(i, Item::Part { floating: true, .. }))
}

/// Flattens items into parts, repeating groups as rule 2 says. Parts of a top-level repeated
/// group are marked with their repetition (`within` is the mark of an enclosing one).
fn expand<'a>(
    items: &[Item<'a>],
    length: f64,
    out: &mut Vec<FlatPart<'a>>,
    within: Option<Repetition>,
) -> Result<(), DeriveError> {
    let outside: f64 = top(items)
        .map(|(i, inner)| match i {
            Item::Group { repeat: true, .. } => 0.0,
            // The sum of one term, as the nominal length of a one-item list.
            other => std::iter::once(nominal_of(other, inner)).sum(),
        })
        .sum();
    let outside_floating: f64 = top(items)
        .map(|(i, inner)| match i {
            Item::Group { repeat: true, .. } => 0.0,
            Item::Group { .. } => floating_nominal(inner),
            Item::Part { floating, size, .. } => f64::from(u8::from(*floating)) * size.max(0.0),
        })
        .sum();
    let repeats = top(items)
        .filter(|(i, _)| matches!(i, Item::Group { repeat: true, .. }))
        .count();
    // Groups take their share of what is left in turn, so two groups that each fit 2.4 times
    // make 5 repetitions between them, not 4 or 6.
    let mut left = (length - outside).max(0.0);
    let mut groups_left = repeats;
    for (g, (item, inner)) in top(items).enumerate() {
        match item {
            Item::Part {
                floating,
                size,
                body,
                depth,
            } => out.push((*floating, *size, (body, *depth), within)),
            Item::Group { repeat: false, .. } => expand(inner, nominal(inner), out, within)?,
            Item::Group {
                repeat: true, span, ..
            } => {
                let unit = nominal(inner);
                if unit <= 0.0 {
                    return Err(DeriveError::at(
                        "a repeated split group needs a positive size",
                        *span,
                    ));
                }
                let budget = left / groups_left as f64;
                let count = if has_floating(inner) {
                    let shared = outside_floating / repeats as f64;
                    least_stretching_count(budget, unit, floating_nominal(inner), shared)
                } else {
                    (budget / unit + 1e-9).floor()
                };
                left = (left - count * unit).max(0.0);
                groups_left -= 1;
                if count > MAX_PARTS as f64 || out.len() as f64 + count > MAX_PARTS as f64 {
                    return Err(DeriveError::at(
                        format!("this repeat would make {count} parts (the limit is {MAX_PARTS})"),
                        *span,
                    )
                    .with_hint(
                        "check the sizes: a tiny size in a repeat fills the scope with slivers",
                    ));
                }
                for r in 0..count as u32 {
                    expand(inner, unit, out, within.or(Some((g as u32, r))))?;
                }
            }
        }
    }
    Ok(())
}
