//! Evaluating compiled expressions against a shape.

use std::sync::Arc;

use shapegram_geom::{DMat3, DVec3, Scope};
use shapegram_syntax::{
    Span,
    ast::{AttributeKind, BinaryOp, UnaryOp},
};

use crate::builtins::{Builtin, Query};
use crate::context::{Context, Target};
use crate::error::DeriveError;
use crate::goals::AttrId;
use crate::imports::Origins;
use crate::program::{CExpr, CKind, Program};
use crate::rng::Rng;
use crate::shape::{Geometry, State};
use crate::text::{Out, Text};
use crate::value::Value;
use shapegram_kinematics::Frame;

mod assets;
mod functions;

use functions::{each_binary, each_unary, slope_angle};

/// How deep user functions may call each other before the derivation stops with an error.
const MAX_CALL_DEPTH: usize = 256;

/// The value of a constant of one initial shape: evaluated on first use.
#[derive(Clone, Debug)]
enum Slot {
    Pending,
    Evaluating,
    Done(Value),
}

/// Evaluates expressions for the shapes of one initial shape (lot).
pub(crate) struct Evaluator<'p> {
    pub program: &'p Program,
    consts: Vec<Slot>,
    /// Constants draw their random numbers from their own stream, so that their values do not
    /// depend on which shape first used them.
    const_rng: Rng,
    call_depth: usize,
    pub initial_origin: DVec3,
    /// The initial shape's axes, the frame of `object.*` selectors.
    pub object_axes: DMat3,
    /// `report(key, value)` calls, in derivation order.
    pub reports: Vec<(String, Value)>,
    /// `print(value)` output, in derivation order.
    pub prints: Vec<String>,
    /// What occlusion queries look at (phase 2 of a derivation with context rules only).
    pub context: Option<&'p Context>,
    /// The lot being derived, by its position among the initial shapes.
    pub lot: u32,
    /// Every constant's first evaluation, in order, when the derivation keeps a trace.
    pub const_log: Option<Vec<ConstEvent>>,
    /// In phase 2 of a grammar with a skeleton: the rigid motion from the rest pose of each of
    /// the lot's sections, by which occlusion queries place a shape.
    pub motions: Vec<Frame>,
    /// Where tables (`readStringTable`) are read from: the derivation's assets.
    pub assets: Option<&'p dyn crate::AssetLoader>,
    /// The rule the derivation started from (`initialShape.startRule`).
    pub start: Option<crate::program::RuleId>,
    /// While an initial shape's attributes are given their defaults: each attribute's, so
    /// that a default reading an attribute declared later evaluates that one first.
    attr_defaults: Option<Vec<Slot>>,
}

/// A constant's first evaluation in a lot: which constant, its value, and the constants'
/// random stream after it. Two derivations of a lot whose logs agree so far hold the same
/// constants with the same stream.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ConstEvent {
    index: u32,
    value: Value,
    rng: Rng,
}

/// The constants of one lot as far as they were evaluated, with their random stream.
#[derive(Clone, Debug)]
pub(crate) struct ConstMemo {
    consts: Vec<Slot>,
    rng: Rng,
}

type Result<T> = std::result::Result<T, DeriveError>;

impl<'p> Evaluator<'p> {
    /// An evaluator for one initial shape with the given seed.
    pub fn new(program: &'p Program, seed: u64, initial_origin: DVec3) -> Self {
        Self {
            program,
            consts: vec![Slot::Pending; program.consts.len()],
            const_rng: Rng::new(seed ^ 0xC0D5_7A11_5EED_0001),
            call_depth: 0,
            initial_origin,
            object_axes: DMat3::IDENTITY,
            reports: Vec::new(),
            prints: Vec::new(),
            context: None,
            lot: 0,
            const_log: None,
            motions: Vec::new(),
            assets: None,
            start: None,
            attr_defaults: None,
        }
    }

    /// The frames selectors classify directions in, for a shape of this scope.
    pub fn frames<'s>(&self, scope: &'s Scope) -> crate::selectors::Frames<'s> {
        crate::selectors::Frames {
            scope,
            object: self.object_axes,
        }
    }

    /// Takes on constants evaluated elsewhere in the same order: their values, the stream after
    /// the last, and their entries in the log.
    pub fn replay_consts(&mut self, events: &[ConstEvent]) {
        for event in events {
            self.consts[event.index as usize] = Slot::Done(event.value.clone());
            self.const_rng = event.rng.clone();
        }
        if let Some(log) = &mut self.const_log {
            log.extend_from_slice(events);
        }
    }

    /// The lot's constants so far, to go on with in another evaluator of the same lot.
    pub fn memo(&self) -> ConstMemo {
        ConstMemo {
            consts: self.consts.clone(),
            rng: self.const_rng.clone(),
        }
    }

    /// Goes on with the constants of an earlier evaluator of the same lot.
    pub fn restore(&mut self, memo: ConstMemo) {
        self.consts = memo.consts;
        self.const_rng = memo.rng;
    }

    /// Evaluates an expression for a shape; `args` are the values of the enclosing rule's or
    /// function's parameters.
    pub fn eval(&mut self, e: &CExpr, shape: &mut State, args: &[Value]) -> Result<Value> {
        let value = match &e.kind {
            CKind::Value(v) => v.clone(),
            CKind::Param(i) => args[*i as usize].clone(),
            CKind::Attr(i) if self.attr_defaults.is_some() => {
                self.attr_default(*i as usize, shape)?
            }
            CKind::Attr(i) => shape.attrs[*i as usize].clone(),
            CKind::Const(i) => self.constant(*i, shape)?,
            CKind::Call(f, params) => self.call(*f, params, shape, args, e.span)?,
            CKind::Builtin(b, params) => self.builtin(*b, params, shape, args, e.span)?,
            CKind::Query(Query::CompSel) => {
                Value::string(crate::ops::CompSelector::NAMES[usize::from(shape.comp_sel)])
            }
            CKind::Query(Query::StartRule) => Value::string(self.start.map_or("", |rule| {
                self.program
                    .symbol_name(self.program.rules[rule as usize].symbol)
            })),
            CKind::Query(q) => Value::Number(self.query(*q, shape)),
            CKind::GoalAttr(attr, kind) => self.goal_attribute(*attr, *kind, shape, e.span)?,
            CKind::EdgeValues(entries) => self.edge_values(entries, shape, args)?,
            CKind::Unary(op, operand) => {
                let v = self.eval(operand, shape, args)?;
                match (op, v) {
                    (UnaryOp::Neg, Value::Number(n)) => Value::Number(-n),
                    (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
                    (op, v) => {
                        return Err(DeriveError::at(
                            format!(
                                "cannot apply `{}` to a {}",
                                unary_symbol(*op),
                                v.type_name()
                            ),
                            e.span,
                        ));
                    }
                }
            }
            CKind::Binary(op, lhs, rhs) => self.binary(*op, lhs, rhs, shape, args, e.span)?,
            CKind::EachBinary(op, lhs, rhs) => {
                let a = self.eval(lhs, shape, args)?;
                let b = self.eval(rhs, shape, args)?;
                each_binary(*op, &a, &b, e.span, rhs.span)?
            }
            CKind::EachUnary(op, operand) => {
                let v = self.eval(operand, shape, args)?;
                each_unary(*op, &v, e.span)?
            }
            CKind::Conditional(cond, then, otherwise) => {
                if self.condition(cond, shape, args)? {
                    self.eval(then, shape, args)?
                } else {
                    self.eval(otherwise, shape, args)?
                }
            }
            CKind::Cases(arms, otherwise) => {
                for (cond, value) in arms {
                    if self.condition(cond, shape, args)? {
                        return self.eval(value, shape, args);
                    }
                }
                self.eval(otherwise, shape, args)?
            }
            CKind::Stochastic(arms, otherwise) => {
                let draw = shape.rng.next_f64() * 100.0;
                let mut acc = 0.0;
                for (percent, value) in arms {
                    acc += self.number(percent, shape, args)?;
                    if draw < acc {
                        return self.eval(value, shape, args);
                    }
                }
                self.eval(otherwise, shape, args)?
            }
            CKind::Array(items) => {
                let mut values = Vec::with_capacity(items.len());
                for item in items {
                    match (&item.kind, self.eval(item, shape, args)?) {
                        // `[1:3, 7]` is `[1, 2, 3, 7]`.
                        (CKind::Range(..), Value::Array(range)) => values.extend_from_slice(&range),
                        (_, value) => values.push(value),
                    }
                }
                Value::Array(values.into())
            }
            CKind::Range(start, step, end) => {
                let from = self.number(start, shape, args)?;
                let by = match step {
                    Some(step) => self.number(step, shape, args)?,
                    None => 1.0,
                };
                let to = self.number(end, shape, args)?;
                Value::Array(range(from, by, to, e.span)?.into())
            }
            CKind::Index(target, index, column) => {
                let array = self.eval(target, shape, args)?;
                let Value::Array(items) = array else {
                    return Err(DeriveError::at(
                        format!("cannot index a {}", array.type_name()),
                        target.span,
                    ));
                };
                let rows = self.eval(index, shape, args)?;
                match column {
                    None => select(&items, &rows, index.span)?,
                    Some(column) => {
                        let columns = self.eval(column, shape, args)?;
                        let picked = select(&items, &rows, index.span)?;
                        match (&rows, picked) {
                            // One row: pick in it.
                            (Value::Number(_), Value::Array(row)) => {
                                select(&row, &columns, column.span)?
                            }
                            // Several rows: pick in each, a column of them or a smaller table.
                            (Value::Array(_), Value::Array(picked)) => {
                                let mut out = Vec::with_capacity(picked.len());
                                for row in picked.iter() {
                                    let Value::Array(row) = row else {
                                        return Err(not_2d(target.span));
                                    };
                                    out.push(select(row, &columns, column.span)?);
                                }
                                Value::Array(out.into())
                            }
                            _ => return Err(not_2d(target.span)),
                        }
                    }
                }
            }
            CKind::Relative(_) | CKind::Floating(_) => {
                return Err(DeriveError::at(
                    "relative (') and floating (~) sizes are only allowed in split sizes and operation arguments",
                    e.span,
                ));
            }
            CKind::Selector(word) => {
                return Err(DeriveError::at(format!("unknown name `{word}`"), e.span));
            }
            CKind::Unsupported(name) => {
                return Err(DeriveError::at(
                    format!("`{name}` is not supported yet"),
                    e.span,
                ));
            }
        };
        // `minimumDistance` is infinite when nothing is near: CGA's `isinf` asks for that.
        let infinite_allowed = matches!(e.kind, CKind::Builtin(Builtin::MinimumDistance, _));
        if let Value::Number(n) = value
            && !n.is_finite()
            && !infinite_allowed
        {
            return Err(DeriveError::at(
                "this evaluates to a number that is not finite (NaN or infinity)",
                e.span,
            ));
        }
        Ok(value)
    }

    /// Evaluates to a number, or fails with the expression's span.
    /// `comp(fe) { selector : value | … }`: a value per edge of the shape's faces, face after
    /// face, each the value of the first entry whose selector takes it (evaluated once for the
    /// shape), else 0.
    fn edge_values(
        &mut self,
        entries: &[(crate::ops::CompSelector, CExpr)],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let values = entries
            .iter()
            .map(|(_, e)| self.eval(e, shape, args))
            .collect::<Result<Vec<_>>>()?;
        let Some(world) = shape.geometry.world_mesh(&shape.scope) else {
            return Ok(Value::Array(Arc::from([])));
        };
        let mut out = Vec::new();
        for f in 0..world.face_count() {
            let normal = world.face_normal(f);
            let points: Vec<DVec3> = world.face_points(f).collect();
            for (i, &a) in points.iter().enumerate() {
                let b = points[(i + 1) % points.len()];
                let outward = (b - a).cross(normal);
                let value = entries
                    .iter()
                    .position(|(s, _)| s.takes_edge(outward, i, &self.frames(&shape.scope)))
                    .map_or(Value::Number(0.0), |k| values[k].clone());
                out.push(value);
            }
        }
        Ok(Value::Array(out.into()))
    }

    /// `fileSearch(q)` (a string list, `a;b;`), `filesSearch(q)` (an array) and `fileRandom(q)`
    /// (one of them drawn from the shape's random stream, `""` when none): the files the
    /// derivation's assets find for the query, sorted.
    fn search_files(
        &mut self,
        b: Builtin,
        query: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let text = match self.eval(query, shape, args)? {
            Value::Str(s) => s,
            other => {
                return Err(DeriveError::at(
                    format!("expected a search query, found a {}", other.type_name()),
                    query.span,
                ));
            }
        };
        let Some(assets) = self.assets else {
            return Err(DeriveError::at(
                format!("cannot search for `{text}`: this derivation reads no files"),
                query.span,
            ));
        };
        let found = assets
            .search(&text)
            .map_err(|why| DeriveError::at(why, query.span))?;
        Ok(match b {
            Builtin::FileSearch => {
                Value::string(&found.iter().map(|f| format!("{f};")).collect::<String>())
            }
            Builtin::FilesSearch => Value::Array(found.iter().map(|f| Value::string(f)).collect()),
            _ => match found.len() {
                0 => Value::string(""),
                n => {
                    let at = ((shape.rng.next_f64() * n as f64) as usize).min(n - 1);
                    Value::string(&found[at])
                }
            },
        })
    }

    /// `readStringTable(path)` and `readFloatTable(path)`: the file's table, read through the
    /// derivation's assets.
    fn read_table(
        &mut self,
        b: Builtin,
        path: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        let name = match self.eval(path, shape, args)? {
            Value::Str(s) => s,
            other => {
                return Err(DeriveError::at(
                    format!("expected a file path, found a {}", other.type_name()),
                    path.span,
                ));
            }
        };
        let Some(assets) = self.assets else {
            return Err(DeriveError::at(
                format!("cannot read `{name}`: this derivation reads no files"),
                path.span,
            ));
        };
        let text = assets
            .text(&name)
            .map_err(|why| DeriveError::at(why, path.span))?;
        let rows = crate::tables::rows(&text);
        if b == Builtin::ReadStringTable {
            return Ok(crate::tables::string_table(&rows));
        }
        crate::tables::float_table(&rows).map_err(|(r, c, field)| {
            DeriveError::at(
                format!("`{name}` row {r}, column {c}: `{field}` is not a number"),
                path.span,
            )
            .with_hint("read it with readStringTable, or convert fields with float()")
        })
    }

    /// A named attribute of a goal grammar's shape, checked against the getter's type.
    fn goal_attribute(
        &self,
        attr: AttrId,
        kind: AttributeKind,
        shape: &State,
        span: Span,
    ) -> Result<Value> {
        let name = || {
            self.program
                .goals
                .as_ref()
                .map_or("?", |g| &g.attributes[attr as usize])
                .to_owned()
        };
        let Some(value) = shape.semantics.as_ref().and_then(|s| s.get(attr)) else {
            return Err(DeriveError::at(
                format!("the shape has no attribute `{}`", name()),
                span,
            )
            .with_hint("only rules read attributes (they apply to shapes that have them); set it with `set(@name, value)`"));
        };
        let wanted = match (kind, value) {
            (AttributeKind::Number, Value::Number(_))
            | (AttributeKind::String, Value::Str(_))
            | (AttributeKind::Any, _) => return Ok(value.clone()),
            (AttributeKind::Number, _) => "a number (`@Double`)",
            (AttributeKind::String, _) => "a string (`@String`)",
        };
        Err(DeriveError::at(
            format!(
                "attribute `{}` is a {}, not {wanted}",
                name(),
                value.type_name()
            ),
            span,
        ))
    }

    pub fn number(&mut self, e: &CExpr, shape: &mut State, args: &[Value]) -> Result<f64> {
        // Most sizes are literals: no need to go through `eval`.
        if let CKind::Value(Value::Number(n)) = e.kind
            && n.is_finite()
        {
            return Ok(n);
        }
        match self.eval(e, shape, args)? {
            Value::Number(n) => Ok(n),
            other => Err(DeriveError::at(
                format!("expected a number, found a {}", other.type_name()),
                e.span,
            )),
        }
    }

    /// Evaluates to a boolean, or fails with the expression's span.
    pub fn condition(&mut self, e: &CExpr, shape: &mut State, args: &[Value]) -> Result<bool> {
        match self.eval(e, shape, args)? {
            Value::Bool(b) => Ok(b),
            other => Err(DeriveError::at(
                format!(
                    "expected a boolean condition, found a {}",
                    other.type_name()
                ),
                e.span,
            )),
        }
    }

    /// Evaluates to a string, or fails with the expression's span.
    pub fn string(&mut self, e: &CExpr, shape: &mut State, args: &[Value]) -> Result<Arc<str>> {
        match self.eval(e, shape, args)? {
            Value::Str(s) => Ok(s),
            other => Err(DeriveError::at(
                format!("expected a string, found a {}", other.type_name()),
                e.span,
            )),
        }
    }

    /// The value of attribute defaults for a new initial shape, with overrides applied.
    pub fn initial_attrs(
        &mut self,
        shape: &mut State,
        overrides: &[(u32, Value)],
    ) -> Result<Vec<Value>> {
        let count = self.program.attrs.len();
        let mut slots = vec![Slot::Pending; count];
        for (i, v) in overrides {
            slots[*i as usize] = Slot::Done(v.clone());
        }
        // Defaults may read other attributes (`attr groundH = floorH + 1`), declared before
        // or after them as in CityEngine: in file order, each evaluating the ones it reads
        // first (see `attr_default`).
        let outer = self.attr_defaults.replace(slots);
        let evaluated = (0..count).try_for_each(|i| self.attr_default(i, shape).map(drop));
        let slots = std::mem::replace(&mut self.attr_defaults, outer).unwrap_or_default();
        evaluated?;
        Ok(slots
            .into_iter()
            .map(|slot| match slot {
                Slot::Done(v) => v,
                Slot::Pending | Slot::Evaluating => Value::Number(0.0),
            })
            .collect())
    }

    /// Attribute `i`'s value while the attributes are given their defaults: its override or
    /// default, evaluated on first use; a default that reads itself, directly or through
    /// others, is an error.
    fn attr_default(&mut self, i: usize, shape: &mut State) -> Result<Value> {
        let program = self.program;
        let slots = self
            .attr_defaults
            .as_mut()
            .expect("called while defaults are given");
        match &slots[i] {
            Slot::Done(v) => return Ok(v.clone()),
            Slot::Evaluating => {
                return Err(DeriveError::at(
                    format!(
                        "the default of attribute `{}` reads itself",
                        program.attrs[i].name
                    ),
                    program.attrs[i].value.span,
                ));
            }
            Slot::Pending => slots[i] = Slot::Evaluating,
        }
        let value = self.eval(&program.attrs[i].value, shape, &[]);
        let value = self.placed(value, |o| o.attrs[i])?;
        if let Some(slots) = &mut self.attr_defaults {
            slots[i] = Slot::Done(value.clone());
        }
        Ok(value)
    }

    /// Sets the attributes `attrs` of the shape afresh: those in `overrides` to their value,
    /// the others to their defaults, evaluated in order (a default sees the values before it).
    pub fn reset_attrs(
        &mut self,
        shape: &mut State,
        attrs: &[u32],
        overrides: &[(u32, Value)],
    ) -> Result<()> {
        let program = self.program;
        let mut values: Vec<Value> = shape.attrs.to_vec();
        for (i, v) in overrides {
            values[*i as usize] = v.clone();
        }
        for &i in attrs {
            if overrides.iter().any(|(o, _)| *o == i) {
                continue;
            }
            shape.attrs = std::rc::Rc::new(values.clone());
            let value = self.eval(&program.attrs[i as usize].value, shape, &[]);
            values[i as usize] = self.placed(value, |o| o.attrs[i as usize])?;
        }
        shape.attrs = std::rc::Rc::new(values);
        Ok(())
    }

    fn constant(&mut self, i: u32, shape: &mut State) -> Result<Value> {
        let program = self.program;
        let constant = &program.consts[i as usize];
        if !constant.cached {
            let value = self.eval(&constant.value, shape, &[]);
            return self.placed(value, |o| o.consts[i as usize]);
        }
        match &self.consts[i as usize] {
            Slot::Done(v) => return Ok(v.clone()),
            Slot::Evaluating => {
                return Err(DeriveError::at(
                    "this constant is defined in terms of itself",
                    constant.value.span,
                ));
            }
            Slot::Pending => {}
        }
        self.consts[i as usize] = Slot::Evaluating;
        // Constants use their own random stream (see `const_rng`) on a copy of the shape.
        let mut scratch = shape.clone();
        std::mem::swap(&mut scratch.rng, &mut self.const_rng);
        let result = self.eval(&constant.value, &mut scratch, &[]);
        std::mem::swap(&mut scratch.rng, &mut self.const_rng);
        let value = self.placed(result, |o| o.consts[i as usize])?;
        self.consts[i as usize] = Slot::Done(value.clone());
        if let Some(log) = &mut self.const_log {
            log.push(ConstEvent {
                index: i,
                value: value.clone(),
                rng: self.const_rng.clone(),
            });
        }
        Ok(value)
    }

    fn call(
        &mut self,
        f: u32,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        let values = params
            .iter()
            .map(|p| self.eval(p, shape, args))
            .collect::<Result<Vec<_>>>()?;
        if self.call_depth >= MAX_CALL_DEPTH {
            let name = &self.program.functions[f as usize].name;
            return Err(DeriveError::at(
                format!("function `{name}` recursed more than {MAX_CALL_DEPTH} levels deep"),
                span,
            ));
        }
        self.call_depth += 1;
        let program = self.program;
        let result = self.eval(&program.functions[f as usize].body, shape, &values);
        self.call_depth -= 1;
        self.placed(result, |o| o.functions[f as usize])
    }

    /// An evaluation's result, its error placed in the file of the declaration `file` picks
    /// (for grammars with imports; an error placed deeper keeps its file).
    fn placed<T>(&self, result: Result<T>, file: impl Fn(&Origins) -> u16) -> Result<T> {
        match &self.program.origins {
            Some(origins) => result.map_err(|e| e.in_file(file(origins))),
            None => result,
        }
    }

    /// `inside(target, label)` and friends, and Müller's `occ(label)`.
    fn occlusion(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        let Some(context) = self.context else {
            return Err(DeriveError::at(
                "occlusion queries can only be asked in rules (not in attributes or in rules \
                 made before the derivation starts)",
                span,
            ));
        };
        let mut target = Target::All;
        let mut label = None;
        if b == Builtin::Occ {
            // `occ("noparent")`: ancestors never count, so "noparent" is every occluder.
            if let Some(p) = params.first() {
                let text = self.word(p, shape, args)?;
                if !matches!(&*text, "noparent" | "all" | "") {
                    label = Some(text);
                }
            }
        } else {
            if let Some(p) = params.first() {
                let word = self.word(p, shape, args)?;
                target = Target::from_name(&word).ok_or_else(|| {
                    DeriveError::at(
                        format!("expected the target `all`, `intra` or `inter`, found `{word}`"),
                        p.span,
                    )
                })?;
            }
            if let Some(p) = params.get(1) {
                let text = self.string(p, shape, args)?;
                label = (!text.is_empty()).then_some(text);
            }
        }
        let motion = self.motions.get(shape.section as usize);
        let found = context.query(shape, motion, self.lot, target, label.as_deref());
        Ok(match b {
            Builtin::Inside => Value::Bool(found.inside),
            Builtin::Overlaps => Value::Bool(found.overlaps),
            Builtin::Touches => Value::Bool(found.touches),
            _ => Value::string(if found.inside {
                "full"
            } else if found.touches {
                "part"
            } else {
                "none"
            }),
        })
    }

    /// `geometry.isRectangular(tolerance)` and the other questions about the shape's mesh
    /// (see `shapegram_geom::shape_metrics`); a shape without geometry has no faces.
    fn measure(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
    ) -> Result<Value> {
        use shapegram_geom::shape_metrics as m;
        let tolerance = match params.first() {
            Some(p) => self.number(p, shape, args)?,
            None => 0.0,
        };
        let scope = shape.scope;
        if b == Builtin::Height {
            let height = shape
                .geometry
                .world_mesh(&scope)
                .and_then(|mesh| mesh.bounds())
                .map_or(0.0, |b| b.size().y);
            return Ok(Value::Number(height));
        }
        let mesh = shape.geometry.local_mesh(scope.size).unwrap_or_default();
        Ok(match b {
            Builtin::IsRectangular => Value::Bool(m::is_rectangular(&mesh, tolerance)),
            Builtin::IsConcave => Value::Bool(m::is_concave(&mesh)),
            Builtin::IsPlanar => Value::Bool(m::is_planar(&mesh, tolerance)),
            Builtin::IsClosedSurface => Value::Bool(m::is_closed_surface(&mesh)),
            Builtin::EdgeCount => Value::Number(m::edge_count(&mesh) as f64),
            _ => Value::Number(m::boundary_length(&mesh)),
        })
    }

    /// A string or string-list function: its numeric arguments as numbers, the others as
    /// strings (`listFromArray` takes an array of strings).
    fn text(
        &mut self,
        t: Text,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        if t == Text::ListFromArray {
            return match self.eval(&params[0], shape, args)? {
                Value::Array(items) => Ok(Value::string(
                    &items.iter().map(|i| format!("{i};")).collect::<String>(),
                )),
                other => Err(DeriveError::at(
                    format!("expected an array, found a {}", other.type_name()),
                    params[0].span,
                )),
            };
        }
        let values = params
            .iter()
            .map(|p| self.eval(p, shape, args))
            .collect::<Result<Vec<_>>>()?;
        // `findFirst(array, value)`: the index of the first element equal to the value.
        if let (Text::FindFirst, [Value::Array(items), value]) = (t, values.as_slice()) {
            let at = items.iter().position(|i| i == value);
            return Ok(Value::Number(at.map_or(-1.0, |i| i as f64)));
        }
        let mut strings = Vec::new();
        let mut numbers = Vec::new();
        for (i, (value, p)) in values.iter().zip(params).enumerate() {
            let wrong = |what: &str| {
                DeriveError::at(
                    format!("expected {what}, found a {}", value.type_name()),
                    p.span,
                )
            };
            match value {
                Value::Number(n) if t.numeric(i) => numbers.push(*n),
                Value::Str(s) if !t.numeric(i) => strings.push(s.clone()),
                _ if t.numeric(i) => return Err(wrong("a number")),
                _ => return Err(wrong("a string")),
            }
        }
        let texts: Vec<&str> = strings.iter().map(|s| &**s).collect();
        let out = t
            .apply(&texts, &numbers, || shape.rng.next_f64())
            .map_err(|e| DeriveError::at(e, span))?;
        Ok(match out {
            Out::Number(n) => Value::Number(n),
            Out::Str(s) => Value::string(&s),
            Out::Strings(parts) => Value::Array(parts.iter().map(|p| Value::string(p)).collect()),
        })
    }

    /// A bare word (`intra`) or a string.
    fn word(&mut self, e: &CExpr, shape: &mut State, args: &[Value]) -> Result<Arc<str>> {
        match &e.kind {
            CKind::Selector(word) => Ok(Arc::from(word.as_str())),
            _ => self.string(e, shape, args),
        }
    }

    fn builtin(
        &mut self,
        b: Builtin,
        params: &[CExpr],
        shape: &mut State,
        args: &[Value],
        span: Span,
    ) -> Result<Value> {
        match b {
            Builtin::Inside | Builtin::Overlaps | Builtin::Touches | Builtin::Occ => {
                return self.occlusion(b, params, shape, args, span);
            }
            Builtin::ContextCount | Builtin::ContextCompare | Builtin::MinimumDistance => {
                return self.context_function(b, params, shape, args, span);
            }
            Builtin::Convert => return self.convert(params, shape, args, span),
            Builtin::Print => {
                // As a function, `print` gives its value on.
                let value = self.eval(&params[0], shape, args)?;
                self.prints.push(value.to_string());
                return Ok(value);
            }
            Builtin::Text(t) => return self.text(t, params, shape, args, span),
            Builtin::Uv(q) => return self.uv_query(q, params, shape, args),
            Builtin::Tags(f) => return self.tag_function(f, params, shape, args),
            Builtin::Array(f) => {
                let values = params
                    .iter()
                    .map(|p| self.eval(p, shape, args))
                    .collect::<Result<Vec<_>>>()?;
                return f.apply(&values).map_err(|e| DeriveError::at(e, span));
            }
            Builtin::Color(f) => return self.color(f, params, shape, args),
            Builtin::IsRectangular
            | Builtin::IsConcave
            | Builtin::IsPlanar
            | Builtin::IsClosedSurface
            | Builtin::EdgeCount
            | Builtin::BoundaryLength
            | Builtin::Height => return self.measure(b, params, shape, args),
            Builtin::Str => {
                return Ok(Value::string(
                    &self.eval(&params[0], shape, args)?.to_string(),
                ));
            }
            Builtin::Bool => {
                return Ok(Value::Bool(match self.eval(&params[0], shape, args)? {
                    Value::Bool(b) => b,
                    Value::Number(n) => n != 0.0,
                    Value::Str(s) => !s.is_empty() && &*s != "false",
                    Value::Array(a) => !a.is_empty(),
                }));
            }
            Builtin::Float => {
                return match self.eval(&params[0], shape, args)? {
                    Value::Number(n) => Ok(Value::Number(n)),
                    Value::Bool(b) => Ok(Value::Number(f64::from(u8::from(b)))),
                    Value::Str(s) => s.trim().parse::<f64>().map(Value::Number).map_err(|_| {
                        DeriveError::at(format!("`{s}` is not a number"), params[0].span)
                    }),
                    Value::Array(_) => Err(DeriveError::at(
                        "cannot convert an array to a number",
                        params[0].span,
                    )),
                };
            }
            Builtin::ReadStringTable | Builtin::ReadFloatTable => {
                return self.read_table(b, &params[0], shape, args);
            }
            Builtin::FileSearch | Builtin::FilesSearch | Builtin::FileRandom => {
                return self.search_files(b, &params[0], shape, args);
            }
            Builtin::AssetInfo | Builtin::AssetBestSize => {
                return self.asset_function(b, params, shape, args);
            }
            Builtin::FileExists | Builtin::ReadTextFile => {
                return self.read_file(b, &params[0], shape, args);
            }
            Builtin::Angle => {
                let which = self.word(&params[0], shape, args)?;
                return slope_angle(&which, shape).map_err(|e| DeriveError::at(e, params[0].span));
            }
            Builtin::Rows | Builtin::Columns => {
                let table = self.eval(&params[0], shape, args)?;
                let Value::Array(rows) = &table else {
                    return Err(DeriveError::at(
                        format!(
                            "expected a table (an array of rows), found a {}",
                            table.type_name()
                        ),
                        params[0].span,
                    ));
                };
                let n = match (b, rows.first()) {
                    (Builtin::Rows, _) => rows.len(),
                    (_, Some(Value::Array(row))) => row.len(),
                    (_, Some(_)) => 1,
                    (_, None) => 0,
                };
                return Ok(Value::Number(n as f64));
            }
            Builtin::Len => {
                return match self.eval(&params[0], shape, args)? {
                    Value::Array(a) => Ok(Value::Number(a.len() as f64)),
                    Value::Str(s) => Ok(Value::Number(s.chars().count() as f64)),
                    other => Err(DeriveError::at(
                        format!(
                            "`size` needs an array or a string, not a {}",
                            other.type_name()
                        ),
                        params[0].span,
                    )),
                };
            }
            _ => {}
        }
        let mut n = Vec::with_capacity(params.len());
        for p in params {
            n.push(self.number(p, shape, args)?);
        }
        let deg = std::f64::consts::PI / 180.0;
        let value = match b {
            Builtin::Rand => match n.as_slice() {
                [] => shape.rng.next_f64(),
                [hi] => shape.rng.range(0.0, *hi),
                [lo, hi, ..] => shape.rng.range(*lo, *hi),
            },
            Builtin::P => return Ok(Value::Bool(shape.rng.next_f64() < n[0])),
            Builtin::Floor => n[0].floor(),
            Builtin::Ceil => n[0].ceil(),
            Builtin::Round => n[0].round(),
            // CGA's rint is C's: to the nearest integer, halves to the even one.
            Builtin::Rint => n[0].round_ties_even(),
            // Kept for CGA files that test their numbers: an expression that is not a finite
            // number is an error here, so these are false for every number that gets this far.
            Builtin::IsNan => return Ok(Value::Bool(n[0].is_nan())),
            Builtin::IsInf => return Ok(Value::Bool(n[0].is_infinite())),
            Builtin::Abs => n[0].abs(),
            Builtin::Min => n[0].min(n[1]),
            Builtin::Max => n[0].max(n[1]),
            Builtin::Sqrt => n[0].sqrt(),
            Builtin::Pow => n[0].powf(n[1]),
            Builtin::Exp => n[0].exp(),
            Builtin::Ln => n[0].ln(),
            Builtin::Log10 => n[0].log10(),
            // CGA's trigonometry works in degrees.
            Builtin::Sin => (n[0] * deg).sin(),
            Builtin::Cos => (n[0] * deg).cos(),
            Builtin::Tan => (n[0] * deg).tan(),
            Builtin::Asin => n[0].asin() / deg,
            Builtin::Acos => n[0].acos() / deg,
            Builtin::Atan => n[0].atan() / deg,
            Builtin::Atan2 => n[0].atan2(n[1]) / deg,
            Builtin::Clamp => n[0].max(n[1]).min(n[2]),
            Builtin::Str
            | Builtin::Bool
            | Builtin::Float
            | Builtin::Len
            | Builtin::Inside
            | Builtin::Overlaps
            | Builtin::Touches
            | Builtin::Occ
            | Builtin::IsRectangular
            | Builtin::IsConcave
            | Builtin::IsPlanar
            | Builtin::IsClosedSurface
            | Builtin::EdgeCount
            | Builtin::BoundaryLength
            | Builtin::Height
            | Builtin::ReadStringTable
            | Builtin::ReadFloatTable
            | Builtin::Rows
            | Builtin::Columns
            | Builtin::FileSearch
            | Builtin::FilesSearch
            | Builtin::FileRandom
            | Builtin::FileExists
            | Builtin::ReadTextFile
            | Builtin::Angle
            | Builtin::ContextCount
            | Builtin::ContextCompare
            | Builtin::MinimumDistance
            | Builtin::Print
            | Builtin::Convert
            | Builtin::AssetInfo
            | Builtin::AssetBestSize
            | Builtin::Text(_)
            | Builtin::Array(_)
            | Builtin::Color(_)
            | Builtin::Uv(_)
            | Builtin::Tags(_) => unreachable!("handled above"),
        };
        if !value.is_finite() {
            return Err(DeriveError::at(
                format!(
                    "`{}` gives no finite number for these arguments",
                    b.signature()
                ),
                span,
            ));
        }
        Ok(Value::Number(value))
    }

    fn binary(
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

    fn query(&self, q: Query, shape: &State) -> f64 {
        let scope = &shape.scope;
        match q {
            Query::ScopeSize(i) => scope.size[i],
            Query::ScopeOrigin(i) => scope.origin[i],
            Query::Elevation => scope.origin.y,
            Query::ScopeRotation(i) => {
                // Intrinsic x, y, z like `r(…)`.
                let (x, y, z) =
                    shapegram_geom::DQuat::from_mat3(&scope.axes).to_euler(glam::EulerRot::XYZ);
                [x, y, z][i].to_degrees()
            }
            Query::SplitIndex => f64::from(shape.split.0),
            Query::SplitTotal => f64::from(shape.split.1),
            Query::CompIndex => f64::from(shape.comp.0),
            Query::CompTotal => f64::from(shape.comp.1),
            Query::GeometryArea => match &shape.geometry {
                Geometry::Empty => 0.0,
                g => g.local_mesh(scope.size).map_or(0.0, |m| m.area()),
            },
            Query::GeometryVolume => shape
                .geometry
                .local_mesh(scope.size)
                .map_or(0.0, |m| m.signed_volume().abs()),
            Query::GeometryVertices => shape
                .geometry
                .local_mesh(scope.size)
                .map_or(0.0, |m| m.vertex_count() as f64),
            Query::GeometryFaces => shape
                .geometry
                .local_mesh(scope.size)
                .map_or(0.0, |m| m.face_count() as f64),
            Query::GeometryHoles => 0.0,
            Query::InitialOrigin(i) => self.initial_origin[i],
            // A number in [0, 1) stable for the shape: CGA's `seedian`.
            Query::Seed => (crate::rng::mix(shape.seed) >> 11) as f64 / (1u64 << 53) as f64,
            Query::Depth => f64::from(shape.depth),
            Query::CompSel | Query::StartRule => {
                unreachable!("string queries are evaluated in `eval`")
            }
        }
    }
}

/// A binary operator on two values (`&&` and `||` on booleans; the engine short-circuits them
/// before it gets here).
fn apply_binary(op: BinaryOp, a: &Value, b: &Value, span: Span, rhs_span: Span) -> Result<Value> {
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

fn unary_symbol(op: UnaryOp) -> &'static str {
    match op {
        UnaryOp::Neg => "-",
        UnaryOp::Not => "!",
    }
}

fn binary_symbol(op: BinaryOp) -> &'static str {
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
fn range(from: f64, by: f64, to: f64, span: Span) -> Result<Vec<Value>> {
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
fn select(items: &[Value], at: &Value, span: Span) -> Result<Value> {
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
fn not_2d(span: Span) -> DeriveError {
    DeriveError::at(
        "two indices need a 2D array (rows written `[a, b; c, d]`)",
        span,
    )
}
