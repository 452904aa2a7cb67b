//! Compiling rule bodies: statements, operation calls told apart from successors, dynamic
//! imports and goal successors.

use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, AttributeKind, Body, ExprKind, Stmt},
    suggest,
};

use super::*;
use crate::goals::GoalId;
use crate::ops::{self, Op};
use crate::value::Value;

impl<'g> Compiler<'g> {
    pub(crate) fn body(&mut self, body: &Body, params: Params) -> CBody {
        match body {
            Body::Sequence(stmts) => CBody::Sequence(self.stmts(stmts, params)),
            Body::Cases {
                arms, otherwise, ..
            } => CBody::Cases(
                arms.iter()
                    .map(|(c, b)| (self.expr(c, params), self.body(b, params)))
                    .collect(),
                Box::new(self.body(otherwise, params)),
            ),
            Body::Stochastic {
                arms, otherwise, ..
            } => CBody::Stochastic(
                arms.iter()
                    .map(|(p, b)| (self.expr(p, params), self.body(b, params)))
                    .collect(),
                Box::new(self.body(otherwise, params)),
            ),
        }
    }

    pub(crate) fn stmts(&mut self, stmts: &[Stmt], params: Params) -> Vec<CStmt> {
        stmts
            .iter()
            .filter_map(|s| match s {
                Stmt::Push(_) => Some(CStmt::Push),
                Stmt::Pop(span) => Some(CStmt::Pop(*span)),
                Stmt::Nil(_) => Some(CStmt::Nil),
                Stmt::Branch(body) => Some(CStmt::Branch(Box::new(self.body(body, params)))),
                Stmt::Call(call) => self.call_stmt(call, params),
                Stmt::Goals(goals, span) => self.goal_successor(goals, *span),
            })
            .collect()
    }

    /// A call statement is a successor when a rule of that name exists, else an operation when
    /// one is known, else a successor without a rule (a leaf, as in CGA, with a warning).
    fn call_stmt(&mut self, call: &ast::Call, params: Params) -> Option<CStmt> {
        let name = &call.name.name;
        if name == ast::DYNAMIC_IMPORT {
            return self.dynamic_import(call, params);
        }
        let arity = call.args.as_ref().map_or(0, Vec::len);
        if call.block.is_none()
            && let Some(rules) = self.rule_by_name.get(name)
        {
            let rule = rules
                .iter()
                .copied()
                .find(|&r| self.rule_arity(r) == Some(arity));
            if rule.is_none() {
                let arities: Vec<String> = rules
                    .iter()
                    .filter_map(|&r| self.rule_arity(r))
                    .map(|n| n.to_string())
                    .collect();
                self.diagnostics.push(
                    Diagnostic::error(
                        format!(
                            "rule `{name}` takes {} arguments, not {arity}",
                            arities.join(" or ")
                        ),
                        call.span,
                    )
                    .with_label("wrong number of arguments"),
                );
                return None;
            }
            return Some(self.successor(call, rule, params));
        }
        // `r.` is a leaf named `r`: a terminal name without arguments is never an operation.
        let leaf_symbol = call.terminal && call.args.is_none() && call.block.is_none();
        if !leaf_symbol && let Some(op) = ops::compile(self, call, params) {
            return op.map(|op| CStmt::Op(op, call.span));
        }
        if self.goal.is_some() {
            self.diagnostics.push(
                Diagnostic::error(format!("unknown operation `{name}`"), call.name.span)
                    .with_hint(format!("in goal grammars a successor is a goal: `+{name}`")),
            );
            return None;
        }
        if call.block.is_some() {
            self.diagnostics.push(
                Diagnostic::error(format!("unknown operation `{name}`"), call.name.span)
                    .with_label("only operations take a `{…}` block"),
            );
            return None;
        }
        if !call.terminal && !self.warned.contains_key(name) {
            self.warned.insert(name.clone(), ());
            let rule_names: Vec<&str> = self.rule_by_name.keys().map(String::as_str).collect();
            let mut d = Diagnostic::warning(
                format!("no rule `{name}`: its shapes become leaves"),
                call.name.span,
            );
            if let Some(close) = suggest(name, rule_names.iter().copied()) {
                d = d.with_hint(format!("did you mean `{close}`?"));
            }
            self.diagnostics.push(d);
        }
        Some(self.successor(call, None, params))
    }

    fn successor(&mut self, call: &ast::Call, rule: Option<RuleId>, params: Params) -> CStmt {
        let args = call
            .args
            .iter()
            .flatten()
            .map(|a| self.expr(&a.value, params))
            .collect();
        CStmt::Successor {
            symbol: self.intern(&call.name.name),
            rule,
            args,
            terminal: call.terminal,
            span: call.span,
        }
    }

    /// The first statement of a dynamic import `id(a = v).Rule` (see [`ast::DYNAMIC_IMPORT`]):
    /// the attributes of import `id`, set afresh with the overrides.
    fn dynamic_import(&mut self, call: &ast::Call, params: Params) -> Option<CStmt> {
        let args = call.args.as_deref().unwrap_or_default();
        let ExprKind::Name(id) = &args.first()?.value.kind else {
            return None;
        };
        let prefix = format!("{id}.");
        let mut attrs: Vec<u32> = self
            .attr_by_name
            .iter()
            .filter(|(name, _)| name.starts_with(&prefix))
            .map(|(_, &i)| i)
            .collect();
        attrs.sort_unstable();
        let mut overrides = Vec::new();
        for a in &args[1..] {
            let attr = a.name.as_ref()?;
            let Some(&i) = self.attr_by_name.get(&format!("{prefix}{}", attr.name)) else {
                self.diagnostics.push(
                    Diagnostic::error(
                        format!("the import `{id}` has no attribute `{}`", attr.name),
                        attr.span,
                    )
                    .with_label("not an attribute of the imported file"),
                );
                return None;
            };
            overrides.push((i, self.expr(&a.value, params)));
        }
        Some(CStmt::Op(Op::Reimport { attrs, overrides }, call.span))
    }

    /// The target of `set(@name, …)`: the attribute, recorded as written, not read.
    pub(crate) fn goal_attr_target(&mut self, name: &str, span: Span) -> CExpr {
        let kind = match &mut self.goal {
            Some(scope) => {
                let attr = scope.attr(name);
                scope.write(attr);
                CKind::GoalAttr(attr, AttributeKind::Any)
            }
            None => {
                self.diagnostics.push(
                    Diagnostic::error(
                        format!("`@{name}` is a named attribute of goal grammars"),
                        span,
                    )
                    .with_hint("in the main syntax, declare `attr name = …` and `set(name, …)`"),
                );
                CKind::Value(Value::Number(0.0))
            }
        };
        CExpr { kind, span }
    }

    /// `+seat +wooden`: a goal successor (goal grammars only).
    fn goal_successor(&mut self, goals: &[ast::Goal], span: Span) -> Option<CStmt> {
        let Some(scope) = &mut self.goal else {
            self.diagnostics.push(
                Diagnostic::error("`+goal` successors belong to goal grammars", span)
                    .with_hint("in the main syntax, a successor is a rule's name"),
            );
            return None;
        };
        let mut ids: Vec<GoalId> = goals.iter().map(|g| scope.goal(&g.name)).collect();
        scope.give(&ids, span);
        ids.sort_unstable();
        ids.dedup();
        let symbol = self.intern(&goals[0].name);
        let goals = match ids.as_slice() {
            [one] => GoalList::One(*one),
            _ => GoalList::Many(ids.into()),
        };
        Some(CStmt::Goals {
            goals,
            symbol,
            span,
        })
    }
}
