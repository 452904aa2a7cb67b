//! Compiling expressions: names resolved to parameters, attributes, constants, functions and
//! queries, and calls to built-in functions checked.

use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, BinaryOp, ExprKind, UnaryOp},
    suggest,
};

use super::*;
use crate::builtins::{Builtin, Query};
use crate::tag_queries::TagFn;
use crate::value::Value;

impl<'g> Compiler<'g> {
    /// Compiles an expression in which every name must resolve.
    pub(crate) fn expr(&mut self, e: &ast::Expr, params: Params) -> CExpr {
        self.expr_in(e, params, false)
    }

    /// Compiles an operation argument: a bare word that names nothing is a selector (`x`,
    /// `front`, `scopeCenter`) for the operation to interpret.
    pub(crate) fn arg(&mut self, e: &ast::Expr, params: Params) -> CExpr {
        self.expr_in(e, params, true)
    }

    fn expr_in(&mut self, e: &ast::Expr, params: Params, selectors: bool) -> CExpr {
        let sub = |c: &mut Self, x: &ast::Expr| Box::new(c.expr(x, params));
        let kind = match &e.kind {
            ExprKind::Number(n) => CKind::Value(Value::Number(*n)),
            ExprKind::String(s) => CKind::Value(Value::string(s)),
            ExprKind::Bool(b) => CKind::Value(Value::Bool(*b)),
            ExprKind::Array(items) => {
                CKind::Array(items.iter().map(|i| self.expr(i, params)).collect())
            }
            ExprKind::Name(name) => self.name(name, e.span, params, selectors),
            ExprKind::GoalAttribute { name, kind } => match &mut self.goal {
                Some(scope) => {
                    let attr = scope.attr(name);
                    scope.read(attr, e.span);
                    CKind::GoalAttr(attr, *kind)
                }
                None => {
                    self.diagnostics.push(Diagnostic::error(
                        format!("`@{name}` reads a shape's named attribute: only goal grammars have them"),
                        e.span,
                    ).with_hint("in the main syntax, declare `attr name = …` and read it by its name"));
                    CKind::Value(Value::Number(0.0))
                }
            },
            ExprKind::Call { name, args } => self.call_expr(name, args, params),
            ExprKind::Index {
                target,
                index,
                column,
            } => CKind::Index(
                sub(self, target),
                sub(self, index),
                column.as_ref().map(|c| sub(self, c)),
            ),
            ExprKind::Range { start, step, end } => CKind::Range(
                sub(self, start),
                step.as_ref().map(|s| sub(self, s)),
                sub(self, end),
            ),
            ExprKind::Unary { op, operand } => CKind::Unary(*op, sub(self, operand)),
            ExprKind::Binary { op, lhs, rhs } => CKind::Binary(*op, sub(self, lhs), sub(self, rhs)),
            ExprKind::Conditional {
                cond,
                then,
                otherwise,
            } => CKind::Conditional(sub(self, cond), sub(self, then), sub(self, otherwise)),
            ExprKind::Cases { arms, otherwise } => CKind::Cases(
                arms.iter()
                    .map(|(c, v)| (self.expr(c, params), self.expr(v, params)))
                    .collect(),
                sub(self, otherwise),
            ),
            ExprKind::Stochastic { arms, otherwise } => CKind::Stochastic(
                arms.iter()
                    .map(|(p, v)| (self.expr(p, params), self.expr(v, params)))
                    .collect(),
                sub(self, otherwise),
            ),
            ExprKind::Floating(inner) => CKind::Floating(sub(self, inner)),
            ExprKind::Relative(inner) => CKind::Relative(sub(self, inner)),
        };
        CExpr { kind, span: e.span }
    }

    /// Resolves a name: rule or function parameter, attribute, constant, built-in query; else a
    /// selector where one may stand, else an error with the nearest names.
    fn name(&mut self, name: &str, span: Span, params: Params, selectors: bool) -> CKind {
        if let Some(i) = params.iter().position(|p| p.name == name) {
            return CKind::Param(i as u16);
        }
        if let Some(&i) = self.attr_by_name.get(name) {
            return CKind::Attr(i);
        }
        if let Some(&i) = self.const_by_name.get(name) {
            self.uses.consts.push(i);
            return CKind::Const(i);
        }
        if let Some(q) = Query::from_name(name) {
            return self.query(q);
        }
        // `geometry.isConcave` and the other shape questions without arguments may be written
        // without parentheses, as the queries are.
        if let Some(b) =
            Builtin::from_name(name).filter(|b| name.starts_with("geometry.") && b.arity().0 == 0)
        {
            self.tagged |= matches!(
                b,
                Builtin::Tags(TagFn::Tags | TagFn::HasTags | TagFn::Groups)
            );
            return CKind::Builtin(b, Vec::new());
        }
        if selectors {
            return CKind::Selector(name.to_owned());
        }
        self.unknown_name(name, span, params)
    }

    /// The element-wise operators, which the parser gives as calls named `.op`.
    fn element_wise(&mut self, name: &ast::Ident, args: &[ast::Argument], params: Params) -> CKind {
        use BinaryOp as B;
        let mut operands = args.iter().map(|a| Box::new(self.expr(&a.value, params)));
        let (Some(first), second) = (operands.next(), operands.next()) else {
            return CKind::Value(Value::Number(0.0));
        };
        let Some(second) = second else {
            return match name.name.as_str() {
                ".-" => CKind::EachUnary(UnaryOp::Neg, first),
                ".!" => CKind::EachUnary(UnaryOp::Not, first),
                _ => first.kind,
            };
        };
        let op = match name.name.as_str() {
            ".*" => B::Mul,
            "./" => B::Div,
            ".%" => B::Rem,
            ".+" => B::Add,
            ".-" => B::Sub,
            ".<" => B::Lt,
            ".<=" => B::Le,
            ".>" => B::Gt,
            ".>=" => B::Ge,
            ".==" => B::Eq,
            ".!=" => B::Ne,
            ".&&" => B::And,
            _ => B::Or,
        };
        CKind::EachBinary(op, first, second)
    }

    /// Reports a name that resolves to nothing (a warning for CGA queries not implemented yet)
    /// and returns what stands in its place.
    pub(crate) fn unknown_name(&mut self, name: &str, span: Span, params: Params) -> CKind {
        if Query::is_known_unsupported(name) {
            self.diagnostics.push(Diagnostic::warning(
                format!("`{name}` is not supported yet"),
                span,
            ));
            return CKind::Unsupported(name.to_owned());
        }
        let candidates: Vec<&str> = params
            .iter()
            .map(|p| p.name.as_str())
            .chain(self.attr_by_name.keys().map(String::as_str))
            .chain(self.const_by_name.keys().copied())
            .chain(Query::NAMES.iter().copied())
            .collect();
        let mut d = Diagnostic::error(format!("unknown name `{name}`"), span)
            .with_label("not a parameter, attribute, constant or query");
        if let Some(close) = suggest(name, candidates) {
            d = d.with_hint(format!("did you mean `{close}`?"));
        }
        self.diagnostics.push(d);
        CKind::Value(Value::Number(0.0))
    }

    fn call_expr(&mut self, name: &ast::Ident, args: &[ast::Argument], params: Params) -> CKind {
        if name.name.starts_with('.') {
            return self.element_wise(name, args, params);
        }
        if let ("comp", [first, entries @ ..]) = (name.name.as_str(), args)
            && matches!(&first.value.kind, ExprKind::Name(k) if k == "fe")
            && first.name.is_none()
        {
            return self.edge_values(entries, params);
        }
        if Builtin::is_known_unsupported(&name.name) {
            // Never evaluated, so its arguments (`touches(intra, "wall")`) are not checked.
            self.diagnostics.push(Diagnostic::warning(
                format!("function `{}` is not supported yet", name.name),
                name.span,
            ));
            return CKind::Unsupported(name.name.clone());
        }
        if args.is_empty() {
            // CGA writes some queries as calls: `geometry.area()`.
            if let Some(q) = Query::from_name(&name.name) {
                return self.query(q);
            }
        }
        // Occlusion queries take bare target words (`inside(intra)`), uv queries a space
        // (`geometry.du(0, unitSpace)`).
        let words = Builtin::from_name(&name.name).is_some_and(Builtin::takes_words);
        let compiled: Vec<CExpr> = args
            .iter()
            .map(|a| self.expr_in(&a.value, params, words))
            .collect();
        if let Some(overloads) = self.function_by_name.get(name.name.as_str()) {
            if let Some(&(_, f)) = overloads.iter().find(|(n, _)| *n == compiled.len()) {
                self.uses.functions.push(f);
                return CKind::Call(f, compiled);
            }
            let counts: Vec<String> = overloads.iter().map(|(n, _)| n.to_string()).collect();
            self.diagnostics.push(
                Diagnostic::error(
                    format!(
                        "function `{}` takes {} arguments, not {}",
                        name.name,
                        counts.join(" or "),
                        compiled.len()
                    ),
                    name.span,
                )
                .with_label("wrong number of arguments"),
            );
            return CKind::Value(Value::Number(0.0));
        }
        if let Some(builtin) = Builtin::from_name(&name.name) {
            let (lo, hi) = builtin.arity();
            if compiled.len() < lo || compiled.len() > hi {
                self.diagnostics.push(
                    Diagnostic::error(
                        format!("wrong number of arguments for `{}`", name.name),
                        name.span,
                    )
                    .with_hint(format!("the signature is `{}`", builtin.signature())),
                );
                return CKind::Value(Value::Number(0.0));
            }
            self.uses.context |= builtin.is_context_query();
            self.tagged |= matches!(
                builtin,
                Builtin::Tags(TagFn::Tags | TagFn::HasTags | TagFn::Groups)
            );
            return CKind::Builtin(builtin, compiled);
        }
        let mut candidates: Vec<&str> = self.function_by_name.keys().copied().collect();
        for builtin in Builtin::all_names() {
            candidates.push(builtin);
        }
        let mut d = Diagnostic::error(format!("unknown function `{}`", name.name), name.span);
        if let Some(close) = suggest(&name.name, candidates) {
            d = d.with_hint(format!("did you mean `{close}`?"));
        }
        self.diagnostics.push(d);
        CKind::Value(Value::Number(0.0))
    }

    /// The entries of `comp(fe) { selector : value | … }` (read as named arguments).
    fn edge_values(&mut self, entries: &[ast::Argument], params: Params) -> CKind {
        let mut compiled = Vec::with_capacity(entries.len());
        for entry in entries {
            let Some(selector) = &entry.name else {
                self.report(Diagnostic::error(
                    "expected `selector : value` in the comp function",
                    entry.value.span,
                ));
                continue;
            };
            let key = ast::Expr {
                kind: match selector.name.parse::<u32>() {
                    Ok(i) => ExprKind::Number(f64::from(i)),
                    Err(_) => ExprKind::Name(selector.name.clone()),
                },
                span: selector.span,
            };
            let selector = crate::ops::edge_selector(self, &key, key.span);
            compiled.push((selector, self.expr(&entry.value, params)));
        }
        CKind::EdgeValues(compiled)
    }

    /// A query of the shape, noting what the derivation must keep for it.
    fn query(&mut self, q: Query) -> CKind {
        self.tree_keys |= q == Query::TreeKey;
        CKind::Query(q)
    }
}
