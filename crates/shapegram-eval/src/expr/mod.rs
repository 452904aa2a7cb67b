//! Evaluating compiled expressions against a shape.

use std::sync::Arc;

use shapegram_geom::{DMat3, DVec3, Scope};
use shapegram_syntax::{Span, ast::UnaryOp};

use crate::builtins::{Builtin, Query};
use crate::context::Context;
use crate::error::DeriveError;
use crate::imports::Origins;
use crate::program::{CExpr, CKind, Program};
use crate::rng::Rng;
use crate::shape::State;
use crate::value::Value;
use shapegram_kinematics::Frame;

mod assets;
mod context;
mod dispatch;
mod files;
mod functions;
mod materials;
mod operators;
mod queries;

use operators::{each_binary, each_unary, range, unary_symbol};

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
    /// The lot each line of `prints` was printed on, parallel to it.
    pub print_lots: Vec<u32>,
    /// What occlusion queries look at (phase 2 of a derivation with context rules only).
    pub context: Option<&'p Context>,
    /// The lot being derived, by its position among the initial shapes.
    pub lot: u32,
    /// The lot's number in the whole input ([`crate::InitialShape::index`]), which names it.
    pub lot_number: u64,
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
    /// Adds a line to the printed output, on the lot being derived.
    pub fn print(&mut self, text: String) {
        self.prints.push(text);
        self.print_lots.push(self.lot);
    }

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
            print_lots: Vec::new(),
            context: None,
            lot: 0,
            lot_number: 0,
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
            CKind::Query(Query::InitialName) => {
                Value::string(&format!("shape_{}", self.lot_number))
            }
            CKind::Query(Query::TreeKey) => Value::string(
                &shape
                    .tree_key
                    .iter()
                    .map(|i| format!("{i};"))
                    .collect::<String>(),
            ),
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
                self.index(target, index, column.as_deref(), shape, args)?
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
        self.string_as("a string", e, shape, args)
    }

    /// A string argument that means `what` ("a file path"), which a wrong type's error names.
    pub(super) fn string_as(
        &mut self,
        what: &str,
        e: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Arc<str>> {
        match self.eval(e, shape, args)? {
            Value::Str(s) => Ok(s),
            other => Err(DeriveError::at(
                format!("expected {what}, found a {}", other.type_name()),
                e.span,
            )),
        }
    }

    /// A bare word (`intra`) or a string.
    pub(super) fn word(
        &mut self,
        e: &CExpr,
        shape: &mut State,
        args: &[Value],
    ) -> Result<Arc<str>> {
        match &e.kind {
            CKind::Selector(word) => Ok(Arc::from(word.as_str())),
            _ => self.string(e, shape, args),
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
}
