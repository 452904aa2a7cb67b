//! The SGL notation (Sunde 2022, "Shape Grammars for Architectural Reconstruction"), lowered to
//! the common AST. See `docs/dialects.md` for the semantics chosen and every lowering.
//!
//! A file is a header of variables `name = value` and rules `name: { statements }` or
//! `name: (w){ … } (w){ … }` (weighted alternatives). In short:
//!
//! - SGL scopes are centred on their origin (a placed unit cube is centred there), so
//!   `PlaceShape` and `Subdiv` shift by half the scope; calls run on a copy of the scope.
//! - Every rule counts its depth in the attribute `sgl_depth` (the start rule is depth 1) and does
//!   nothing beyond the header's `max_depth` (default [`DEFAULT_MAX_DEPTH`]).
//! - Every rule body ends with `NIL`: SGL scopes carry no geometry, only `PlaceShape` makes some.
//! - The start rule (`start`, else the first) begins with `s(1, 1, 1)`: a unit scope at the
//!   origin of the initial shape, whatever its size.

use std::collections::BTreeMap;

use super::build as b;
use super::{Fail, PResult, Parser, Start};
use crate::ast::{Annotation, Attr, BinaryOp, Body, Expr, ExprKind, Grammar, Ident, Rule, Stmt};
use crate::lexer::TokenKind;
use crate::{Diagnostic, Span, suggest};

/// The depth limit when the header sets none.
pub(crate) const DEFAULT_MAX_DEPTH: f64 = 16.0;
/// The attribute that counts how deep a rule runs.
pub(crate) const DEPTH_ATTR: &str = "sgl_depth";
/// Header variables that set the depth limit, in order of preference.
const LIMIT_NAMES: [&str; 2] = ["max_depth", "depth"];

/// A rule as written.
struct SglRule {
    name: Ident,
    alternatives: Vec<(Option<Expr>, Vec<Stmt>)>,
    span: Span,
    /// Rules made for `AtDepth` calls in this rule.
    synthesized: Vec<Rule>,
}

/// What the lowering collects besides the rules.
#[derive(Default)]
struct Collected {
    rules: Vec<SglRule>,
    /// Every rule called, for the check that it exists.
    references: Vec<Ident>,
}

impl Parser<'_> {
    /// Reads a whole file in the SGL notation into `grammar`.
    pub(super) fn sgl_file(&mut self, grammar: &mut Grammar) {
        let mut collected = Collected::default();
        while !self.at(&TokenKind::Eof) {
            let before = self.checkpoint();
            if self.sgl_declaration(grammar, &mut collected).is_err() {
                self.recover_to_declaration();
            }
            if self.pos == before.pos {
                self.bump();
            }
        }
        self.sgl_finish(grammar, collected);
    }

    /// [`Parser::declaration_start`] in SGL: `name:` and `name =`.
    pub(super) fn sgl_declaration_start(&self, i: usize) -> Option<Start> {
        match self.kind_at(i) {
            TokenKind::Eof => Some(Start::Strong),
            TokenKind::Ident
                if self.is_name_at(i)
                    && matches!(self.kind_at(i + 1), TokenKind::Colon | TokenKind::Eq) =>
            {
                Some(Start::Strong)
            }
            _ => None,
        }
    }

    fn sgl_declaration(&mut self, grammar: &mut Grammar, collected: &mut Collected) -> PResult<()> {
        if !self.is_name_at(self.pos) {
            let d = self.expected(
                "a rule `name: { … }` or a header variable `name = value`",
                "",
            );
            self.report(d);
            return Err(Fail);
        }
        let name = self.ident();
        match self.peek() {
            TokenKind::Eq => {
                self.bump();
                let value = self.expr()?;
                self.eat(&TokenKind::Semi);
                grammar.attrs.push(Attr {
                    annotations: Vec::new(),
                    span: self.span_from(name.span),
                    name,
                    value,
                });
                Ok(())
            }
            TokenKind::Colon => {
                self.bump();
                self.sgl_rule(name, collected)
            }
            _ => {
                let context = format!("after `{}`", name.name);
                let d = self
                    .expected("`:` or `=`", &context)
                    .with_hint("a rule is written `name: { … }`, a header variable `name = value`");
                self.report(d);
                Err(Fail)
            }
        }
    }

    /// The body of `name:`: `{ … }` or weighted alternatives `(w){ … } (w){ … }`.
    fn sgl_rule(&mut self, name: Ident, collected: &mut Collected) -> PResult<()> {
        let mut rule = SglRule {
            name,
            alternatives: Vec::new(),
            span: Span::default(),
            synthesized: Vec::new(),
        };
        match self.peek() {
            TokenKind::LBrace => {
                let body = self.sgl_braced(&mut rule, collected)?;
                rule.alternatives.push((None, body));
            }
            TokenKind::LParen => {
                while self.at(&TokenKind::LParen) {
                    let open = self.bump();
                    let weight = self.expr()?;
                    self.close(&TokenKind::RParen, open, "`)`", "after the weight")?;
                    if !self.at(&TokenKind::LBrace) {
                        return Err(self.error_expected("`{`", "after the weight"));
                    }
                    let body = self.sgl_braced(&mut rule, collected)?;
                    rule.alternatives.push((Some(weight), body));
                }
            }
            _ => {
                let context = format!("after `{}:`", rule.name.name);
                let d = self
                    .expected("`{` or a weight `(1)`", &context)
                    .with_hint("rules are written `name: { … }` or `name: (1){ … } (1){ … }`");
                self.report(d);
                return Err(Fail);
            }
        }
        rule.span = self.span_from(rule.name.span);
        collected.rules.push(rule);
        Ok(())
    }

    /// `{ statements }`. A missing `}` is reported and the body ends before the next rule or
    /// weighted alternative.
    fn sgl_braced(&mut self, rule: &mut SglRule, collected: &mut Collected) -> PResult<Vec<Stmt>> {
        let open = self.bump();
        let mut body = Vec::new();
        loop {
            match self.peek() {
                TokenKind::RBrace => {
                    self.bump();
                    break;
                }
                TokenKind::Semi | TokenKind::Comma => {
                    self.bump();
                }
                TokenKind::Eof => {
                    self.unclosed_body(open);
                    break;
                }
                TokenKind::LParen if self.token_at(self.pos).line_start => {
                    self.unclosed_body(open);
                    break;
                }
                _ if self.at_resume_point() => {
                    self.unclosed_body(open);
                    break;
                }
                TokenKind::Ident if self.is_name_at(self.pos) => {
                    if self.sgl_statement(rule, collected, &mut body).is_err() {
                        self.sgl_recover();
                    }
                }
                _ => {
                    let d = self.expected("a statement or `}`", "in the rule body");
                    self.report(d);
                    self.sgl_recover();
                }
            }
        }
        self.check_push_pop(&body);
        Ok(body)
    }

    fn unclosed_body(&mut self, open: Span) {
        let d = Diagnostic::error("unclosed `{`", open)
            .with_label("this body is never closed")
            .with_hint("close the body with `}`");
        self.report(d);
    }

    /// Skips the rest of a bad statement: to the next line, `;` or `}`.
    fn sgl_recover(&mut self) {
        let start = self.pos;
        while !self.at(&TokenKind::Eof) {
            let token = self.token_at(self.pos);
            let stop = matches!(token.kind, TokenKind::RBrace | TokenKind::Semi)
                || (token.line_start && self.pos > start);
            if stop {
                return;
            }
            self.bump();
        }
    }

    /// Reports `Pop()` without a `Push()` before it.
    fn check_push_pop(&mut self, body: &[Stmt]) {
        let mut open = 0usize;
        for stmt in body {
            match stmt {
                Stmt::Push(_) => open += 1,
                Stmt::Pop(span) if open == 0 => {
                    let d = Diagnostic::error("`Pop()` without a matching `Push()`", *span)
                        .with_hint(
                            "every `Pop()` restores the scope saved by a `Push()` before it",
                        );
                    self.report(d);
                }
                Stmt::Pop(_) => open -= 1,
                _ => {}
            }
        }
    }

    /// One statement, lowered into `out`.
    fn sgl_statement(
        &mut self,
        rule: &mut SglRule,
        collected: &mut Collected,
        out: &mut Vec<Stmt>,
    ) -> PResult<()> {
        let name = self.ident();
        match name.name.as_str() {
            "Subdiv" => return self.sgl_subdiv(name, collected, out),
            "AtDepth" => return self.sgl_at_depth(name, rule, collected, out),
            _ => {}
        }
        let (args, span) = if self.at(&TokenKind::LParen) {
            let (args, close) = self.call_args()?;
            (
                args.into_iter().map(|a| a.value).collect(),
                name.span.to(close),
            )
        } else {
            (Vec::new(), name.span)
        };
        // Errors found once the whole call is read drop the statement; reading goes on.
        let arity = |p: &mut Self, n: usize, signature: &str| -> Option<()> {
            if args.len() == n {
                return Some(());
            }
            let d = Diagnostic::error(
                format!("wrong number of arguments for `{}`", name.name),
                span,
            )
            .with_label(format!("{} given", args.len()))
            .with_hint(format!("the signature is `{signature}`"));
            p.report(d);
            None
        };
        match name.name.as_str() {
            "T" => {
                if arity(self, 3, "T(x, y, z)").is_some() {
                    out.push(b::op("t", args, span));
                }
            }
            "R" => {
                if arity(self, 3, "R(x, y, z)").is_some() {
                    out.push(b::op("r", args, span));
                }
            }
            "S" => {
                if arity(self, 3, "S(x, y, z)").is_some() {
                    out.push(b::op(
                        "s",
                        args.into_iter().map(b::relative).collect(),
                        span,
                    ));
                }
            }
            "SS" => {
                if arity(self, 3, "SS(x, y, z)").is_some() {
                    out.push(b::op("s", args, span));
                }
            }
            "Push" => {
                if arity(self, 0, "Push()").is_some() {
                    out.push(Stmt::Push(span));
                }
            }
            "Pop" => {
                if arity(self, 0, "Pop()").is_some() {
                    out.push(Stmt::Pop(span));
                }
            }
            "PlaceShape" => {
                if arity(self, 1, "PlaceShape(\"Cube\")").is_some() {
                    self.place_shape(&args[0], span, out);
                }
            }
            _ => {
                if !args.is_empty() {
                    let d = Diagnostic::error("SGL rules take no arguments", span)
                        .with_label(format!("`{}` is called with arguments", name.name))
                        .with_hint(format!("call it as `{}()`", name.name));
                    self.report(d);
                }
                out.push(b::successor(&name.name, name.span));
                collected.references.push(name);
            }
        }
        Ok(())
    }

    /// `PlaceShape("Cube")` → `[ t('-0.5, '-0.5, '-0.5) i("builtin:cube") Cube. ]`: a unit
    /// shape centred on the scope origin and scaled by the scope size, as Unity places its
    /// primitives. The cylinder (and capsule) of Unity is twice as tall as wide.
    fn place_shape(&mut self, arg: &Expr, span: Span, out: &mut Vec<Stmt>) {
        let ExprKind::String(shape) = &arg.kind else {
            let d = Diagnostic::error("expected the name of a shape, like \"Cube\"", arg.span)
                .with_label("in `PlaceShape`");
            self.report(d);
            return;
        };
        let lower = shape.to_ascii_lowercase();
        let (path, tall) = match lower.as_str() {
            "cube" | "box" => ("builtin:cube".to_owned(), false),
            "sphere" => ("builtin:sphere".to_owned(), false),
            "cylinder" | "capsule" => ("builtin:cylinder".to_owned(), true),
            "cone" => ("builtin:cone".to_owned(), false),
            "pyramid" => ("builtin:pyramid".to_owned(), false),
            _ if shape.contains('.') => (shape.clone(), false),
            _ => (format!("{shape}.obj"), false),
        };
        let symbol: String = shape
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let symbol = if symbol.is_empty() {
            "Shape".to_owned()
        } else {
            symbol
        };
        let half = || b::relative(b::number(-0.5, span));
        out.push(Stmt::Push(span));
        if tall {
            let one = || b::relative(b::number(1.0, span));
            out.push(b::op(
                "s",
                vec![one(), b::relative(b::number(2.0, span)), one()],
                span,
            ));
        }
        out.push(b::op("t", vec![half(), half(), half()], span));
        out.push(b::op("i", vec![b::string(&path, arg.span)], span));
        out.push(b::call(b::ident(&symbol, arg.span), None, None, true, span));
        out.push(Stmt::Pop(span));
    }

    /// `sgprod{ a(), b() }`: the rules a `Subdiv` or `AtDepth` calls.
    fn sgl_products(&mut self, collected: &mut Collected) -> PResult<Vec<Ident>> {
        if !self.at_word("sgprod") {
            return Err(self.error_expected("`sgprod{ … }`", "with the rules to call"));
        }
        self.bump();
        let open = self.expect(&TokenKind::LBrace, "`{`", "after `sgprod`")?;
        let mut products = Vec::new();
        loop {
            if self.at(&TokenKind::RBrace) {
                break;
            }
            if !self.is_name_at(self.pos) {
                return Err(self.error_expected("a rule name", "in `sgprod{ … }`"));
            }
            let name = self.ident();
            if self.at(&TokenKind::LParen) {
                let (args, close) = self.call_args()?;
                if !args.is_empty() {
                    let d = Diagnostic::error("SGL rules take no arguments", name.span.to(close))
                        .with_hint(format!("call it as `{}()`", name.name));
                    self.report(d);
                }
            }
            collected.references.push(name.clone());
            products.push(name);
            if self.eat(&TokenKind::Comma).is_none() {
                break;
            }
        }
        self.close(&TokenKind::RBrace, open, "`,` or `}`", "in `sgprod{ … }`")?;
        Ok(products)
    }

    /// `Subdiv(n, axis, sgprod{ a(), b(), … })` → `[ t(-½ along the axis) split(axis){ '(1/n) :
    /// t(½ along the axis) a | … } ]`: the centred scope is cut into `n` equal parts, each
    /// centred on its own origin.
    fn sgl_subdiv(
        &mut self,
        name: Ident,
        collected: &mut Collected,
        out: &mut Vec<Stmt>,
    ) -> PResult<()> {
        let open = self.expect(&TokenKind::LParen, "`(`", "after `Subdiv`")?;
        let count = self.expr()?;
        self.expect(&TokenKind::Comma, "`,`", "after the number of parts")?;
        let axis = self.expr()?;
        self.expect(&TokenKind::Comma, "`,`", "after the axis")?;
        let products = self.sgl_products(collected)?;
        let close = self.close(&TokenKind::RParen, open, "`)`", "after `sgprod{ … }`")?;
        let span = name.span.to(close);
        let k = match &axis.kind {
            ExprKind::Number(n) if [0.0, 1.0, 2.0].contains(n) => *n as usize,
            ExprKind::Name(n) | ExprKind::String(n) if ["x", "y", "z"].contains(&n.as_str()) => {
                usize::from(n == "y") + 2 * usize::from(n == "z")
            }
            _ => {
                let d = Diagnostic::error("expected the axis 0, 1 or 2 (x, y or z)", axis.span)
                    .with_label("in `Subdiv`");
                self.report(d);
                return Ok(());
            }
        };
        if let ExprKind::Number(n) = count.kind
            && n != products.len() as f64
        {
            let d = Diagnostic::error(
                format!(
                    "`Subdiv` into {n} parts needs {n} rules, found {}",
                    products.len()
                ),
                count.span,
            )
            .with_label("the number of parts")
            .with_hint("give one rule per part in `sgprod{ … }`");
            self.report(d);
            return Ok(());
        }
        if products.is_empty() {
            let d = Diagnostic::error("`Subdiv` needs at least one rule", span);
            self.report(d);
            return Ok(());
        }
        let along = |v: f64| -> Vec<Expr> {
            (0..3)
                .map(|i| {
                    if i == k {
                        b::relative(b::number(v, span))
                    } else {
                        b::number(0.0, span)
                    }
                })
                .collect()
        };
        let size = b::relative(b::binary(
            BinaryOp::Div,
            b::number(1.0, count.span),
            count.clone(),
        ));
        let entries = products
            .iter()
            .map(|p| {
                let body = vec![b::op("t", along(0.5), span), b::successor(&p.name, p.span)];
                b::part(size.clone(), body, p.span)
            })
            .collect();
        let axis_name = ["x", "y", "z"][k];
        out.push(Stmt::Push(span));
        out.push(b::op("t", along(-0.5), span));
        out.push(b::split(
            name.span,
            vec![b::name(axis_name, axis.span)],
            b::block(entries, false, span),
            span,
        ));
        out.push(Stmt::Pop(span));
        Ok(())
    }

    /// `AtDepth(d, sgprod{ a(), … })` → a successor `rule.AtDepthN` whose rule is
    /// `case sgl_depth + 1 == d : a … NIL else : NIL`: the rules run when they run at depth `d`.
    fn sgl_at_depth(
        &mut self,
        name: Ident,
        rule: &mut SglRule,
        collected: &mut Collected,
        out: &mut Vec<Stmt>,
    ) -> PResult<()> {
        let open = self.expect(&TokenKind::LParen, "`(`", "after `AtDepth`")?;
        let depth = self.expr()?;
        self.expect(&TokenKind::Comma, "`,`", "after the depth")?;
        let products = self.sgl_products(collected)?;
        let close = self.close(&TokenKind::RParen, open, "`)`", "after `sgprod{ … }`")?;
        let span = name.span.to(close);
        let synthesized = format!("{}.AtDepth{}", rule.name.name, rule.synthesized.len() + 1);
        let condition = b::binary(
            BinaryOp::Eq,
            b::binary(
                BinaryOp::Add,
                b::name(DEPTH_ATTR, span),
                b::number(1.0, span),
            ),
            depth,
        );
        let mut calls: Vec<Stmt> = products
            .iter()
            .map(|p| b::successor(&p.name, p.span))
            .collect();
        calls.push(Stmt::Nil(span));
        rule.synthesized.push(Rule {
            annotations: Vec::new(),
            name: b::ident(&synthesized, name.span),
            params: Vec::new(),
            body: Body::Cases {
                arms: vec![(condition, Body::Sequence(calls))],
                otherwise: Box::new(Body::Sequence(vec![Stmt::Nil(span)])),
                span,
            },
            span,
        });
        out.push(b::successor(&synthesized, span));
        Ok(())
    }

    /// Checks the calls, adds the depth attributes and turns the rules into the common AST.
    fn sgl_finish(&mut self, grammar: &mut Grammar, collected: Collected) {
        let mut seen: BTreeMap<&str, Span> = BTreeMap::new();
        for rule in &collected.rules {
            if seen.insert(&rule.name.name, rule.name.span).is_some() {
                let d = Diagnostic::error(
                    format!("rule `{}` is defined twice", rule.name.name),
                    rule.name.span,
                )
                .with_hint(format!(
                    "write the alternatives as one rule: `{}: (1){{ … }} (1){{ … }}`",
                    rule.name.name
                ));
                self.report(d);
            }
        }
        for call in &collected.references {
            if !seen.contains_key(call.name.as_str()) {
                let mut d = Diagnostic::error(format!("unknown rule `{}`", call.name), call.span)
                    .with_label("no rule of this name");
                if let Some(close) = suggest(&call.name, seen.keys().copied()) {
                    d = d.with_hint(format!("did you mean `{close}`?"));
                }
                self.report(d);
            }
        }
        let limit = LIMIT_NAMES
            .iter()
            .find(|n| grammar.attrs.iter().any(|a| a.name.name == **n))
            .map_or(LIMIT_NAMES[0], |n| *n);
        let synthesized_attr = |name: &str, value: f64| Attr {
            annotations: Vec::new(),
            name: b::ident(name, Span::default()),
            value: b::number(value, Span::default()),
            span: Span::default(),
        };
        if !grammar.attrs.iter().any(|a| a.name.name == limit) {
            grammar
                .attrs
                .push(synthesized_attr(limit, DEFAULT_MAX_DEPTH));
        }
        if !grammar.attrs.iter().any(|a| a.name.name == DEPTH_ATTR) {
            grammar.attrs.push(synthesized_attr(DEPTH_ATTR, 0.0));
        }
        let start = collected
            .rules
            .iter()
            .position(|r| r.name.name == "start")
            .unwrap_or(0);
        for (i, rule) in collected.rules.into_iter().enumerate() {
            let name_span = rule.name.span;
            let mut prefix = Vec::new();
            if i == start {
                let one = || b::number(1.0, name_span);
                prefix.push(b::op("s", vec![one(), one(), one()], name_span));
            }
            prefix.push(b::op(
                "set",
                vec![
                    b::name(DEPTH_ATTR, name_span),
                    b::binary(
                        BinaryOp::Add,
                        b::name(DEPTH_ATTR, name_span),
                        b::number(1.0, name_span),
                    ),
                ],
                name_span,
            ));
            let weights: Vec<Expr> = rule
                .alternatives
                .iter()
                .filter_map(|(w, _)| w.clone())
                .collect();
            let mut bodies: Vec<Body> = rule
                .alternatives
                .into_iter()
                .map(|(_, stmts)| {
                    let mut all = prefix.clone();
                    all.extend(stmts);
                    all.push(Stmt::Nil(name_span));
                    Body::Sequence(all)
                })
                .collect();
            let inner = if bodies.len() > 1 {
                let Some(percents) = self.percentages(&weights) else {
                    continue;
                };
                let otherwise = bodies.pop().unwrap_or(Body::Sequence(Vec::new()));
                Body::Stochastic {
                    arms: percents.into_iter().zip(bodies).collect(),
                    otherwise: Box::new(otherwise),
                    span: rule.span,
                }
            } else {
                bodies.pop().unwrap_or(Body::Sequence(Vec::new()))
            };
            let guard = b::binary(
                BinaryOp::Ge,
                b::name(DEPTH_ATTR, name_span),
                b::name(limit, name_span),
            );
            let annotations = if i == start {
                vec![Annotation {
                    name: b::ident("StartRule", name_span),
                    args: Vec::new(),
                    span: name_span,
                }]
            } else {
                Vec::new()
            };
            grammar.rules.push(Rule {
                annotations,
                name: rule.name,
                params: Vec::new(),
                body: Body::Cases {
                    arms: vec![(guard, Body::Sequence(vec![Stmt::Nil(name_span)]))],
                    otherwise: Box::new(inner),
                    span: rule.span,
                },
                span: rule.span,
            });
            grammar.rules.extend(rule.synthesized);
        }
    }
}
