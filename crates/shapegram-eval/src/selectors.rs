//! The selectors of component splits and setbacks (`front`, `object.left`, `world.south`,
//! `street.front`, `streetSide`, `all`, `3`, `inside`, …): compiled from their words, and
//! deciding which faces and edges they take.
//!
//! A direction selector classifies a face's normal, or an edge's outward direction in its face's
//! plane, by the axis of a frame it is closest to (+z front, +x right, +y top): the shape's scope
//! (`front`), the initial shape's (`object.front`) or the world's (`world.south` is +z, `north`
//! −z, `east` +x, `west` −x, `up` +y, `down` −y). Shapegram has no streets, so `street.*` falls
//! back to `object.*`, as CityEngine does for shapes without street edges; the legacy
//! `streetSide` is `street.front` and `noStreetSide` everything else.
//!
//! Beyond directions, a selector may ask for tags (`isTagged("roof.top")`, see
//! [`crate::tags`]), for the edges of a roof (`eave`, `hip`, `valley`, `ridge`), or be a logical
//! expression of selectors and of conditions on the component (`top || front`,
//! `geometry.area() > 1 && !inside`), the conditions evaluated on each component's shape.

use std::sync::Arc;

use shapegram_geom::{DMat3, DVec3, FaceClass, Scope};
use shapegram_syntax::{Diagnostic, Span, ast};

use crate::program::{CExpr, Compiler};
use crate::tags::{Around, TagQuery};

/// The frame a direction selector classifies in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SelectorFrame {
    /// The shape's scope: `front`, `left`, …
    Scope,
    /// The initial shape's scope: `object.front`, …
    Object,
    /// The street edges: `street.front`, …, read in the initial shape's scope (no streets).
    Street,
    /// The world axes: `world.north`, `world.up`, …
    World,
}

/// The frames a derivation step classifies directions in.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frames<'a> {
    /// The shape's scope.
    pub scope: &'a Scope,
    /// The initial shape's axes.
    pub object: DMat3,
}

impl Frames<'_> {
    /// The axes of `frame`.
    fn axes(&self, frame: SelectorFrame) -> DMat3 {
        match frame {
            SelectorFrame::Scope => self.scope.axes,
            SelectorFrame::Object | SelectorFrame::Street => self.object,
            SelectorFrame::World => DMat3::IDENTITY,
        }
    }

    /// The class of a world direction in `frame`.
    pub fn class(&self, direction: DVec3, frame: SelectorFrame) -> FaceClass {
        FaceClass::of(
            direction,
            &Scope::new(DVec3::ZERO, self.axes(frame), DVec3::ONE),
        )
    }

    /// The slope of a world direction against the xz-plane of `frame`.
    pub fn slope(&self, direction: DVec3, frame: SelectorFrame) -> Slope {
        let local = self.axes(frame).transpose() * direction.normalize_or_zero();
        let elevation = local.y.clamp(-1.0, 1.0).asin().to_degrees();
        match elevation {
            e if e > 78.75 || e <= -78.75 => Slope::Horizontal,
            e if e > 11.25 => Slope::Aslant,
            e if e > -11.25 => Slope::Vertical,
            _ => Slope::Nutant,
        }
    }
}

/// How steep a component is: CityEngine's classes of the angle between its normal and the
/// scope's xz-plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Slope {
    /// More than 78.75° above the plane, or at least 78.75° below.
    Horizontal,
    /// Between 11.25° and 78.75° above.
    Aslant,
    /// Within 11.25° of the plane (up to 11.25° above, less than 11.25° below).
    Vertical,
    /// Between 11.25° and 78.75° below.
    Nutant,
}

/// The edges of a roof, as CityEngine's roof edge selectors name them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RoofEdge {
    /// A level edge along the bottom of the roof.
    Eave,
    /// An inner edge from an eave's end, not in a concavity.
    Hip,
    /// An inner edge in a concavity.
    Valley,
    /// Any other inner edge.
    Ridge,
}

/// Which components an entry of `comp` (or edges of a setback) takes.
#[derive(Clone, Debug)]
pub(crate) enum CompSelector {
    /// A direction class in a frame (`front`, `object.left`, `world.north`, `streetSide`).
    Class(FaceClass, SelectorFrame),
    /// The four side classes in a frame (`side`, `object.side`, `world.side`).
    Side(SelectorFrame),
    /// Everything the class does not take (`noStreetSide`).
    NotClass(FaceClass, SelectorFrame),
    All,
    Vertical,
    Horizontal,
    Aslant,
    /// Facing down at a slant (between 11.25° and 78.75° below the scope's xz-plane).
    Nutant,
    Index(usize),
    Inside,
    Border,
    /// Components the tag query matches, on themselves or the edges or vertices around them
    /// (`isTagged("q")`, `isTagged("q", e)`).
    Tagged(Arc<TagQuery>, Around),
    /// The same with the query an expression (`isTagged(prefix + ".top")`), evaluated on each
    /// component's shape.
    TaggedBy(Box<CExpr>, Around),
    /// The edges of a roof of one kind (`eave`, `hip`, `valley`, `ridge`; edges only).
    Roof(RoofEdge),
    /// `!s`.
    Not(Box<CompSelector>),
    /// `a && b`.
    And(Box<CompSelector>, Box<CompSelector>),
    /// `a || b`.
    Or(Box<CompSelector>, Box<CompSelector>),
    /// A condition evaluated on each component's shape (`geometry.area() > 1`).
    Test(Box<CExpr>),
    /// A selector we do not know how to evaluate: selects nothing (with a warning).
    Never,
}

/// The names of the direction classes in the world frame, by [`FaceClass`].
const WORLD_NAMES: [(FaceClass, &str); 6] = [
    (FaceClass::Front, "south"),
    (FaceClass::Back, "north"),
    (FaceClass::Left, "west"),
    (FaceClass::Right, "east"),
    (FaceClass::Top, "up"),
    (FaceClass::Bottom, "down"),
];

/// The direction classes in the order of their names in [`CompSelector::NAMES`].
const CLASSES: [FaceClass; 6] = [
    FaceClass::Front,
    FaceClass::Back,
    FaceClass::Left,
    FaceClass::Right,
    FaceClass::Top,
    FaceClass::Bottom,
];

impl CompSelector {
    /// The names `comp.sel` gives, by [`CompSelector::code`]; an index selector has no name.
    pub const NAMES: [&'static str; 37] = [
        "",
        "front",
        "back",
        "left",
        "right",
        "top",
        "bottom",
        "side",
        "all",
        "vertical",
        "horizontal",
        "aslant",
        "inside",
        "border",
        "object.front",
        "object.back",
        "object.left",
        "object.right",
        "object.top",
        "object.bottom",
        "object.side",
        "street.front",
        "street.back",
        "street.left",
        "street.right",
        "street.top",
        "street.bottom",
        "street.side",
        "world.south",
        "world.north",
        "world.west",
        "world.east",
        "world.up",
        "world.down",
        "world.side",
        "noStreetSide",
        "nutant",
    ];

    /// The selector's position in [`CompSelector::NAMES`].
    pub fn code(&self) -> u8 {
        let frame_base = |frame| match frame {
            SelectorFrame::Scope => 1,
            SelectorFrame::Object => 14,
            SelectorFrame::Street => 21,
            SelectorFrame::World => 28,
        };
        let class_index = |class| CLASSES.iter().position(|c| *c == class).unwrap_or(0) as u8;
        match self {
            Self::Class(class, frame) => frame_base(*frame) + class_index(*class),
            Self::Side(frame) => frame_base(*frame) + 6,
            Self::NotClass(..) => 35,
            Self::All => 8,
            Self::Vertical => 9,
            Self::Horizontal => 10,
            Self::Aslant => 11,
            Self::Nutant => 36,
            Self::Inside => 12,
            Self::Border => 13,
            Self::Index(_)
            | Self::Never
            | Self::Tagged(..)
            | Self::TaggedBy(..)
            | Self::Roof(_)
            | Self::Not(_)
            | Self::And(..)
            | Self::Or(..)
            | Self::Test(_) => 0,
        }
    }

    /// Whether the selector takes a face or an edge by its direction (the face's normal, the
    /// edge's outward direction in its face's plane) and index; `None` when it decides by
    /// something else (the face's tag).
    pub fn takes_direction(&self, direction: DVec3, index: usize, frames: &Frames) -> Option<bool> {
        Some(match self {
            Self::All => true,
            Self::Index(i) => *i == index,
            Self::Never => false,
            Self::Class(class, frame) => frames.class(direction, *frame) == *class,
            Self::Side(frame) => frames.slope(direction, *frame) != Slope::Horizontal,
            Self::NotClass(class, frame) => frames.class(direction, *frame) != *class,
            Self::Vertical => frames.slope(direction, SelectorFrame::Scope) == Slope::Vertical,
            Self::Horizontal => frames.slope(direction, SelectorFrame::Scope) == Slope::Horizontal,
            Self::Aslant => frames.slope(direction, SelectorFrame::Scope) == Slope::Aslant,
            Self::Nutant => frames.slope(direction, SelectorFrame::Scope) == Slope::Nutant,
            Self::Not(s) => !s.takes_direction(direction, index, frames)?,
            Self::And(a, b) => {
                a.takes_direction(direction, index, frames)?
                    && b.takes_direction(direction, index, frames)?
            }
            Self::Or(a, b) => {
                a.takes_direction(direction, index, frames)?
                    || b.takes_direction(direction, index, frames)?
            }
            Self::Inside
            | Self::Border
            | Self::Tagged(..)
            | Self::TaggedBy(..)
            | Self::Roof(_)
            | Self::Test(_) => return None,
        })
    }

    /// Whether the selector decides by direction and index alone (no tags, roof edges,
    /// conditions or offset parts).
    fn decides_by_direction(&self) -> bool {
        match self {
            Self::Inside
            | Self::Border
            | Self::Tagged(..)
            | Self::TaggedBy(..)
            | Self::Roof(_)
            | Self::Test(_) => false,
            Self::Not(s) => s.decides_by_direction(),
            Self::And(a, b) | Self::Or(a, b) => {
                a.decides_by_direction() && b.decides_by_direction()
            }
            _ => true,
        }
    }

    /// Whether deciding needs each component's shape (a [`CompSelector::Test`] somewhere).
    pub fn tests(&self) -> bool {
        match self {
            Self::Test(_) | Self::TaggedBy(..) => true,
            Self::Not(s) => s.tests(),
            Self::And(a, b) | Self::Or(a, b) => a.tests() || b.tests(),
            _ => false,
        }
    }

    /// Whether the selector takes edge `index` of a face (counted within the face), whose
    /// outward direction in the face's plane is `outward`.
    pub fn takes_edge(&self, outward: DVec3, index: usize, frames: &Frames) -> bool {
        self.takes_direction(outward, index, frames)
            .unwrap_or(false)
    }
}

/// The selector a word names, `None` for words that are no selector.
pub(crate) fn named(word: &str) -> Option<CompSelector> {
    use CompSelector::*;
    let class = |name: &str| CLASSES.iter().copied().find(|c| c.name() == name);
    let in_frame = |name: &str, frame| match name {
        "side" => Some(Side(frame)),
        _ => class(name).map(|c| Class(c, frame)),
    };
    Some(match word {
        "all" => All,
        "vertical" => Vertical,
        "horizontal" => Horizontal,
        "aslant" => Aslant,
        "nutant" => Nutant,
        "inside" => Inside,
        "border" => Border,
        "streetSide" => Class(FaceClass::Front, SelectorFrame::Street),
        "noStreetSide" => NotClass(FaceClass::Front, SelectorFrame::Street),
        _ => {
            if let Some(rest) = word.strip_prefix("object.") {
                return in_frame(rest, SelectorFrame::Object);
            }
            if let Some(rest) = word.strip_prefix("street.") {
                return in_frame(rest, SelectorFrame::Street);
            }
            if let Some(rest) = word.strip_prefix("world.") {
                if rest == "side" {
                    return Some(Side(SelectorFrame::World));
                }
                let (c, _) = WORLD_NAMES.iter().find(|(_, n)| *n == rest)?;
                return Some(Class(*c, SelectorFrame::World));
            }
            return in_frame(word, SelectorFrame::Scope);
        }
    })
}

/// A selector of the components `comp` takes: a word, a whole number for an index,
/// `isTagged(…)`, or a logical expression of selectors and conditions (compiled against the
/// rule's `params`). Unknown words select nothing, with a warning.
pub(crate) fn comp_selector(
    c: &mut Compiler,
    key: &ast::Expr,
    params: &[ast::Ident],
    span: Span,
) -> CompSelector {
    use ast::ExprKind;
    let part = |c: &mut Compiler, e: &ast::Expr| comp_selector(c, e, params, e.span);
    match &key.kind {
        ExprKind::Name(n) => {
            if let Some(selector) = named(n).or_else(|| roof_edge(n).map(CompSelector::Roof)) {
                return selector;
            }
            if c.knows_name(n, params) {
                return CompSelector::Test(Box::new(c.expr(key, params)));
            }
        }
        ExprKind::Number(n) if *n >= 0.0 && n.fract() == 0.0 => {
            return CompSelector::Index(*n as usize);
        }
        ExprKind::Bool(true) => return CompSelector::All,
        ExprKind::Bool(false) => return CompSelector::Never,
        ExprKind::Call { name, args } if name.name == "isTagged" => {
            c.tagged = true;
            return tagged(c, args, params, span);
        }
        ExprKind::Unary {
            op: ast::UnaryOp::Not,
            operand,
        } => return CompSelector::Not(Box::new(part(c, operand))),
        ExprKind::Binary {
            op: op @ (ast::BinaryOp::And | ast::BinaryOp::Or),
            lhs,
            rhs,
        } => {
            let (a, b) = (Box::new(part(c, lhs)), Box::new(part(c, rhs)));
            return if *op == ast::BinaryOp::And {
                CompSelector::And(a, b)
            } else {
                CompSelector::Or(a, b)
            };
        }
        ExprKind::Call { .. } | ExprKind::Binary { .. } | ExprKind::Unary { .. } => {
            return CompSelector::Test(Box::new(c.expr(key, params)));
        }
        _ => {}
    }
    c.report(Diagnostic::warning(
        "this component selector is not supported yet: it selects nothing",
        span,
    ));
    CompSelector::Never
}

/// The roof edge a word names.
fn roof_edge(word: &str) -> Option<RoofEdge> {
    Some(match word {
        "eave" => RoofEdge::Eave,
        "hip" => RoofEdge::Hip,
        "valley" => RoofEdge::Valley,
        "ridge" => RoofEdge::Ridge,
        _ => return None,
    })
}

/// `isTagged(query [, e | v])`: a query written out is parsed once, any other expression
/// evaluated on each component.
fn tagged(
    c: &mut Compiler,
    args: &[ast::Argument],
    params: &[ast::Ident],
    span: Span,
) -> CompSelector {
    let query = match args.first().map(|a| &a.value) {
        Some(ast::Expr {
            kind: ast::ExprKind::String(q),
            ..
        }) => Ok(Arc::new(TagQuery::parse(q))),
        Some(e @ ast::Expr { kind, .. }) if !matches!(kind, ast::ExprKind::Number(_)) => {
            Err(Box::new(c.expr(e, params)))
        }
        _ => {
            c.report(Diagnostic::error(
                "`isTagged` takes a tag query, a string: `isTagged(\"roof.top\")`",
                span,
            ));
            return CompSelector::Never;
        }
    };
    let around = match args.get(1).map(|a| &a.value.kind) {
        None => Around::Itself,
        Some(ast::ExprKind::Name(w)) if w == "e" => Around::Edges,
        Some(ast::ExprKind::Name(w)) if w == "v" => Around::Vertices,
        Some(_) => {
            c.report(Diagnostic::error(
                "`isTagged`'s second argument selects the components around: `e` or `v`",
                args[1].value.span,
            ));
            return CompSelector::Never;
        }
    };
    if args.len() > 2 {
        c.report(Diagnostic::error(
            "`isTagged` takes a tag query and at most `e` or `v`",
            span,
        ));
        return CompSelector::Never;
    }
    match query {
        Ok(query) => CompSelector::Tagged(query, around),
        Err(expr) => CompSelector::TaggedBy(expr, around),
    }
}

/// A selector of the edges a `setback` moves (or the comp function values): the direction
/// selectors, `all` or an index; face selectors select nothing, with a warning.
pub(crate) fn edge_selector(c: &mut Compiler, key: &ast::Expr, span: Span) -> CompSelector {
    use CompSelector::*;
    let selector = comp_selector(c, key, &[], span);
    if let Vertical | Horizontal | Aslant | Nutant | Inside | Border = selector {
        c.report(Diagnostic::warning(
            "this selector is for faces, not the edges of a setback: it selects nothing",
            span,
        ));
        return Never;
    }
    if selector.tests() || !selector.decides_by_direction() {
        c.report(Diagnostic::warning(
            "setback and the comp function select edges by direction, index or `all` only: \
             this selector selects nothing",
            span,
        ));
        return Never;
    }
    selector
}
