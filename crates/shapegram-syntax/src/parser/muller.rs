//! The notation of Müller et al. 2006 ("Procedural modeling of buildings"), lowered to the common
//! AST while it is read. See `docs/dialects.md` for every construct and its lowering.
//!
//! A rule is `[N:] name[(params)] [: condition] ~> successors [: probability]`; a line that starts
//! with `~>` is another alternative of the rule before it (same name, parameters and condition). Alternatives of one rule become one
//! rule: a [`Body::Stochastic`] over the probabilities, inside a [`Body::Cases`] over the
//! conditions. The main syntax's declarations (`attr`, `const`, functions, annotations) are read
//! as well, so a grammar can declare the attributes its rules use.

use std::collections::HashMap;

use super::build as b;
use super::{DECLARATION_KEYWORDS, Fail, PResult, Parser, Start};
use crate::ast::{
    Annotation, Argument, BinaryOp, Body, Expr, ExprKind, Grammar, Ident, Rule, Stmt,
};
use crate::lexer::TokenKind;
use crate::{Diagnostic, Span, suggest};

/// One rule as written: `name(params) : condition ~> body : probability`.
struct Alternative {
    annotations: Vec<Annotation>,
    name: Ident,
    params: Vec<Ident>,
    condition: Option<Expr>,
    body: Vec<Stmt>,
    probability: Option<Expr>,
    span: Span,
}

/// The parts of a `{ A | B }` block, each with its span.
type Parts = Vec<(Vec<Stmt>, Span)>;

/// What `Comp("…")` takes: the kind of component and the selector.
const COMPONENT_TYPES: [(&str, &str, &str); 19] = [
    ("faces", "f", "all"),
    ("sidefaces", "f", "side"),
    ("side", "f", "side"),
    ("topface", "f", "top"),
    ("topfaces", "f", "top"),
    ("top", "f", "top"),
    ("bottomface", "f", "bottom"),
    ("bottomfaces", "f", "bottom"),
    ("bottom", "f", "bottom"),
    ("frontface", "f", "front"),
    ("backface", "f", "back"),
    ("leftface", "f", "left"),
    ("rightface", "f", "right"),
    ("edges", "e", "all"),
    ("sideedges", "e", "vertical"),
    ("verticaledges", "e", "vertical"),
    ("horizontaledges", "e", "horizontal"),
    ("vertices", "v", "all"),
    ("points", "v", "all"),
];

/// Instance names `I(…)` maps to Shapegram's built-in assets.
const BUILTIN_ASSETS: [&str; 5] = ["cube", "cylinder", "sphere", "cone", "pyramid"];

impl Parser<'_> {
    /// Reads a whole file in the Müller notation into `grammar`.
    pub(super) fn muller_file(&mut self, grammar: &mut Grammar) {
        let mut alternatives = Vec::new();
        let mut head = None;
        while !self.at(&TokenKind::Eof) {
            let before = self.checkpoint();
            let result = self.annotations().and_then(|annotations| {
                self.muller_declaration(grammar, annotations, &mut alternatives, &mut head)
            });
            if result.is_err() {
                self.recover_to_declaration();
            }
            if self.pos == before.pos {
                self.bump();
            }
        }
        self.muller_rules(grammar, alternatives);
    }

    /// [`Parser::declaration_start`] in the Müller notation: `N:`, `name ~>`, `name(…) ~>`,
    /// `name : condition ~>` (at the start of a line, with the arrow on that line), `~>`, the
    /// main syntax's declaration keywords and functions `name = …`.
    pub(super) fn muller_declaration_start(&self, i: usize) -> Option<Start> {
        let token = self.token_at(i);
        match &token.kind {
            TokenKind::Eof | TokenKind::At | TokenKind::Arrow => Some(Start::Strong),
            TokenKind::Number(_)
                if token.line_start && *self.kind_at(i + 1) == TokenKind::Colon =>
            {
                Some(Start::Strong)
            }
            // `name : condition ~>`: the condition is what the main syntax lacks.
            TokenKind::Ident => self.named_declaration_start(i, |after| {
                let conditional = *self.kind_at(after) == TokenKind::Colon
                    && token.line_start
                    && self.arrow_on_line(after + 1);
                conditional.then_some(Start::Strong)
            }),
            _ => None,
        }
    }

    /// Whether a rule arrow follows token `i` before the next line starts.
    fn arrow_on_line(&self, mut i: usize) -> bool {
        loop {
            let token = self.token_at(i);
            match token.kind {
                TokenKind::Eof => return false,
                _ if token.line_start => return false,
                TokenKind::Arrow => return true,
                _ => i += 1,
            }
        }
    }

    fn muller_declaration(
        &mut self,
        grammar: &mut Grammar,
        annotations: Vec<Annotation>,
        alternatives: &mut Vec<Alternative>,
        head: &mut Option<(Ident, Vec<Ident>, Option<Expr>)>,
    ) -> PResult<()> {
        // The rule number as printed, `1:`, is dropped.
        if matches!(self.peek(), TokenKind::Number(_)) && *self.peek_nth(1) == TokenKind::Colon {
            self.bump();
            self.bump();
        }
        let start = self.span();
        let (name, params, condition) = match self.peek() {
            // Another alternative of the rule before, with its condition.
            TokenKind::Arrow => {
                let Some((name, params, condition)) = head.clone() else {
                    let d = Diagnostic::error("`~>` without a rule name", self.span())
                        .with_label("whose rule is this?")
                        .with_hint("rules are written `name ~> successors`");
                    self.report(d);
                    // Skip the body, so that its first successor is not read as a rule.
                    self.bump();
                    let _ = self.muller_statements();
                    return Err(Fail);
                };
                (name, params, condition)
            }
            TokenKind::Ident if DECLARATION_KEYWORDS.contains(&self.text()) => {
                return self.declaration(grammar, annotations);
            }
            TokenKind::Ident if self.is_name_at(self.pos) => {
                let after = match self.peek_nth(1) {
                    TokenKind::LParen => self
                        .closing_paren(self.pos + 1)
                        .map_or(self.pos + 1, |c| c + 1),
                    _ => self.pos + 1,
                };
                // `name = …` and `name(a) = …` are functions, as in the main syntax.
                if *self.kind_at(after) == TokenKind::Eq {
                    return self.rule_or_function(grammar, annotations);
                }
                let name = self.ident();
                let params = self.optional_params()?.unwrap_or_default();
                let condition = match self.eat(&TokenKind::Colon) {
                    Some(_) => Some(self.muller_expr()?),
                    None => None,
                };
                if !self.at(&TokenKind::Arrow) {
                    let context = format!("after the rule name `{}`", name.name);
                    let d = self
                        .expected("`~>`", &context)
                        .with_hint(format!("rules are written `{} ~> successors`", name.name));
                    self.report(d);
                    return Err(Fail);
                }
                (name, params, condition)
            }
            _ => {
                let d = self.expected("a rule", "").with_hint(
                    "rules are written `name ~> successors`, optionally numbered (`1: lot ~> …`)",
                );
                self.report(d);
                return Err(Fail);
            }
        };
        self.bump();
        *head = Some((name.clone(), params.clone(), condition.clone()));
        self.muller_rule = Some((name.clone(), params.clone()));
        let body = self.muller_statements()?;
        let probability = match self.eat(&TokenKind::Colon) {
            Some(_) => Some(self.muller_expr()?),
            None => None,
        };
        alternatives.push(Alternative {
            annotations,
            name,
            params,
            condition,
            body,
            probability,
            span: self.span_from(start),
        });
        if self.at_declaration_start() {
            return Ok(());
        }
        let d = self.expected("a successor, `: probability` or the next rule", "");
        self.report(d);
        Err(Fail)
    }

    /// An expression with the notation's names mapped (`Scope.sx` is `scope.sx`).
    fn muller_expr(&mut self) -> PResult<Expr> {
        let mut e = self.ternary()?;
        rename_queries(&mut e);
        Ok(e)
    }

    /// Successors and operations up to the end of the body (or of a block part).
    fn muller_statements(&mut self) -> PResult<Vec<Stmt>> {
        let mut out = Vec::new();
        loop {
            match self.peek() {
                TokenKind::LBracket => out.push(Stmt::Push(self.bump())),
                TokenKind::RBracket => out.push(Stmt::Pop(self.bump())),
                TokenKind::Epsilon => out.push(Stmt::Nil(self.bump())),
                TokenKind::Ident if self.at_word("NIL") => out.push(Stmt::Nil(self.bump())),
                TokenKind::Ident if self.is_name_at(self.pos) && !self.at_declaration_start() => {
                    self.muller_call(&mut out)?;
                }
                _ => return Ok(out),
            }
        }
    }

    /// `name`, `name(args)` or `name(args){ A | B }`, lowered into `out`.
    fn muller_call(&mut self, out: &mut Vec<Stmt>) -> PResult<()> {
        let name = self.ident();
        let mut span = name.span;
        let mut args = None;
        if self.at(&TokenKind::LParen) {
            let (mut list, close) = self.call_args()?;
            for a in &mut list {
                rename_queries(&mut a.value);
            }
            args = Some(list);
            span = span.to(close);
        }
        let mut block = None;
        if self.at(&TokenKind::LBrace) {
            let (parts, block_span) = self.muller_block()?;
            span = span.to(block_span);
            block = Some((parts, block_span));
        }
        self.lower_call(name, args, block, span, out);
        Ok(())
    }

    /// `{ A | B | … }`: the parts of a subdivision or component split.
    fn muller_block(&mut self) -> PResult<(Parts, Span)> {
        self.nested(|p| {
            let braced = p.braced("rule", "in the block", |p| {
                let first = p.span();
                let body = p.muller_statements()?;
                // An empty part (reported later) points at the token where it should be.
                let span = if body.is_empty() {
                    first
                } else {
                    p.span_from(first)
                };
                Ok((body, span))
            })?;
            let span = match braced.close {
                Some(close) => braced.open.to(close),
                None => p.span_from(braced.open),
            };
            Ok((braced.entries, span))
        })
    }

    // --- Lowering ------------------------------------------------------------------------------

    fn lower_call(
        &mut self,
        name: Ident,
        args: Option<Vec<Argument>>,
        block: Option<(Parts, Span)>,
        span: Span,
        out: &mut Vec<Stmt>,
    ) {
        let values: Vec<Expr> = args.iter().flatten().map(|a| a.value.clone()).collect();
        match (name.name.as_str(), block) {
            ("Subdiv", Some((parts, block_span))) => {
                self.lower_subdiv(&name, values, parts, block_span, span, out);
            }
            ("Repeat", Some((parts, block_span))) => {
                self.lower_repeat(&name, values, parts, block_span, span, out);
            }
            ("Comp", Some((parts, block_span))) => {
                self.lower_comp(&name, values, parts, block_span, span, out);
            }
            (other, Some(_)) => {
                let d = Diagnostic::error(format!("`{other}` takes no `{{…}}` block"), name.span)
                    .with_label("a block follows")
                    .with_hint(
                        "in the Müller notation only `Subdiv`, `Repeat` and `Comp` take blocks",
                    );
                self.report(d);
            }
            ("Subdiv" | "Repeat" | "Comp", None) => {
                let d =
                    Diagnostic::error(format!("`{}` needs a block of successors", name.name), span)
                        .with_hint(format!("write `{}(…){{ A | B }}`", name.name));
                self.report(d);
            }
            ("S", None) if args.is_some() => {
                if let Some(v) = self.muller_args(&name, values, 3, span, "S(x, y, z)") {
                    out.push(b::op("s", v, span));
                }
            }
            ("T", None) if args.is_some() => {
                if let Some(v) = self.muller_args(&name, values, 3, span, "T(x, y, z)") {
                    out.push(b::op("t", v, span));
                }
            }
            ("R", None) if args.is_some() => {
                if let Some(v) = self.muller_args(&name, values, 3, span, "R(x, y, z)") {
                    out.push(b::op("r", v, span));
                }
            }
            (axis @ ("Rx" | "Ry" | "Rz"), None) if args.is_some() => {
                let signature = format!("{axis}(angle)");
                if let Some(mut v) = self.muller_args(&name, values, 1, span, &signature) {
                    let angle = v.remove(0);
                    let k = usize::from(axis == "Ry") + 2 * usize::from(axis == "Rz");
                    let mut angles: Vec<Expr> = (0..3).map(|_| b::number(0.0, span)).collect();
                    angles[k] = angle;
                    out.push(b::op("r", angles, span));
                }
            }
            // Algorithm 1 of the Procedural Skeletons paper: the joint turns about the scope's
            // y axis (up, as `Subdiv("Y", …)` stacks the floors) within ±limit, posed at
            // `current` (degrees).
            ("KinematicRotation", None) if args.is_some() => {
                let signature = "KinematicRotation(limit, current)";
                if let Some(mut v) = self.muller_args(&name, values, 2, span, signature) {
                    let current = v.pop().expect("two arguments");
                    let limit = v.pop().expect("two arguments");
                    let axis = b::name("y", name.span);
                    let min = b::negated(limit.clone());
                    out.push(b::op("rotationLimits", vec![axis, min, limit], span));
                    let zero = || b::number(0.0, span);
                    out.push(b::op("rotateJoint", vec![zero(), current, zero()], span));
                }
            }
            ("I", None) if args.is_some() => {
                if let Some(mut v) = self.muller_args(&name, values, 1, span, "I(\"name\")") {
                    self.lower_instance(v.remove(0), span, out);
                }
            }
            _ => out.push(b::call(name, args.map(unnamed), None, false, span)),
        }
    }

    /// The argument values of a Müller operation, or an error when there are not `n`.
    fn muller_args(
        &mut self,
        name: &Ident,
        values: Vec<Expr>,
        n: usize,
        span: Span,
        signature: &str,
    ) -> Option<Vec<Expr>> {
        if values.len() == n {
            return Some(values);
        }
        let d = Diagnostic::error(
            format!("wrong number of arguments for `{}`", name.name),
            span,
        )
        .with_label(format!("{} given", values.len()))
        .with_hint(format!("the signature is `{signature}`"));
        self.report(d);
        None
    }

    /// The split axis written `"X"` or `X` as the arguments of `split`: `x`, `y` or `z`, and
    /// `snap` after it for the snapping forms `"XS"`, `"YS"`, `"ZS"`.
    fn muller_axis(&mut self, e: Option<&Expr>, call: &Ident) -> Option<Vec<Expr>> {
        let word = e.and_then(|e| match &e.kind {
            ExprKind::String(s) | ExprKind::Name(s) => Some(s.to_ascii_lowercase()),
            _ => None,
        });
        let (axis, snap) = match word.as_deref() {
            Some(w) => (w.strip_suffix('s').unwrap_or(w), w.ends_with('s')),
            None => ("", false),
        };
        match (axis, e) {
            ("x" | "y" | "z", Some(e)) => {
                let mut args = vec![b::name(axis, e.span)];
                if snap {
                    args.push(b::name("snap", e.span));
                }
                Some(args)
            }
            _ => {
                let span = e.map_or(call.span, |e| e.span);
                let d = Diagnostic::error("expected the axis \"X\", \"Y\" or \"Z\"", span)
                    .with_label(format!("in `{}`", call.name))
                    .with_hint("\"XS\", \"YS\" and \"ZS\" also snap the parts to snap lines");
                self.report(d);
                None
            }
        }
    }

    /// Reports empty parts of a block (the notation writes `ε` for "nothing here").
    fn check_parts(&mut self, parts: &Parts) -> bool {
        let mut ok = true;
        for (body, span) in parts {
            if body.is_empty() {
                let d = Diagnostic::error("empty part", *span)
                    .with_label("no successor here")
                    .with_hint("write `ε` for a part that is left empty");
                self.report(d);
                ok = false;
            }
        }
        ok
    }

    /// `Subdiv("X", 2, 1r){ A | B }` → `split(x){ 2 : A | ~1 : B }`.
    fn lower_subdiv(
        &mut self,
        name: &Ident,
        mut values: Vec<Expr>,
        parts: Parts,
        block_span: Span,
        span: Span,
        out: &mut Vec<Stmt>,
    ) {
        let axis = self.muller_axis(values.first(), name);
        let sizes: Vec<Expr> = values.drain(..).skip(1).collect();
        if sizes.len() != parts.len() {
            let d = Diagnostic::error(
                format!(
                    "`Subdiv` has {} sizes but {} parts",
                    sizes.len(),
                    parts.len()
                ),
                span,
            )
            .with_label("sizes and parts do not match")
            .with_hint("give one size per part: `Subdiv(\"X\", 2, 1r){ A | B }`");
            self.report(d);
            return;
        }
        let (Some(axis), true) = (axis, self.check_parts(&parts)) else {
            return;
        };
        let entries = sizes
            .into_iter()
            .zip(parts)
            .map(|(size, (body, part_span))| b::part(split_size(size), body, part_span))
            .collect();
        let block = b::block(entries, false, block_span);
        out.push(b::split(name.span, axis, block, span));
    }

    /// `Repeat("X", 2){ A }` → `split(x){ { ~2 : A }* }`.
    fn lower_repeat(
        &mut self,
        name: &Ident,
        values: Vec<Expr>,
        mut parts: Parts,
        block_span: Span,
        span: Span,
        out: &mut Vec<Stmt>,
    ) {
        let axis = self.muller_axis(values.first(), name);
        if values.len() != 2 {
            self.muller_args(name, values, 2, span, "Repeat(\"X\", size){ A }");
            return;
        }
        if parts.len() != 1 {
            let d = Diagnostic::error(
                format!("`Repeat` takes one part, found {}", parts.len()),
                block_span,
            )
            .with_hint("repeat a rule that holds the parts: `Repeat(\"X\", 3){ tile }`");
            self.report(d);
            return;
        }
        let (Some(axis), true) = (axis, self.check_parts(&parts)) else {
            return;
        };
        let size = values.into_iter().nth(1).map(|e| match e.kind {
            ExprKind::Relative(inner) => b::floating(*inner),
            _ => b::floating(e),
        });
        let Some(size) = size else { return };
        let (body, part_span) = parts.remove(0);
        let group = b::block(vec![b::part(size, body, part_span)], true, block_span);
        let block = b::block(
            vec![crate::ast::BlockEntry::Group(group)],
            false,
            block_span,
        );
        out.push(b::split(name.span, axis, block, span));
    }

    /// `Comp("sidefaces"){ A }` → `comp(f){ side : A }`; `Comp("faces"){ A | B }` gives the
    /// components by index.
    fn lower_comp(
        &mut self,
        name: &Ident,
        values: Vec<Expr>,
        parts: Parts,
        block_span: Span,
        span: Span,
        out: &mut Vec<Stmt>,
    ) {
        let Some(kind_expr) = self.muller_args(name, values, 1, span, "Comp(\"type\"){ A }") else {
            return;
        };
        let kind_expr = &kind_expr[0];
        let word = match &kind_expr.kind {
            ExprKind::String(s) | ExprKind::Name(s) => Some(s.to_ascii_lowercase()),
            _ => None,
        };
        let found = word
            .as_deref()
            .and_then(|w| COMPONENT_TYPES.iter().find(|(t, _, _)| *t == w));
        let Some(&(_, kind, selector)) = found else {
            let mut d = Diagnostic::error("unknown component type", kind_expr.span)
                .with_label("in `Comp`")
                .with_hint("the types are \"faces\", \"sidefaces\", \"topface\", \"bottomface\", \"frontface\", \"edges\", \"sideedges\" and \"vertices\"");
            if let Some(close) = word
                .as_deref()
                .and_then(|w| suggest(w, COMPONENT_TYPES.iter().map(|t| t.0)))
            {
                d = d.with_hint(format!("did you mean \"{close}\"?"));
            }
            self.report(d);
            return;
        };
        if !self.check_parts(&parts) {
            return;
        }
        let by_index = parts.len() > 1;
        if by_index && selector != "all" {
            let d = Diagnostic::error(
                format!("`Comp` of this type takes one part, found {}", parts.len()),
                block_span,
            )
            .with_hint("several parts are given to the components by index: use \"faces\", \"edges\" or \"vertices\"");
            self.report(d);
            return;
        }
        let entries = parts
            .into_iter()
            .enumerate()
            .map(|(i, (body, part_span))| {
                let key = if by_index {
                    b::number(i as f64, part_span)
                } else {
                    b::name(selector, kind_expr.span)
                };
                b::part(key, body, part_span)
            })
            .collect();
        out.push(b::call(
            b::ident("comp", name.span),
            Some(vec![b::name(kind, kind_expr.span)]),
            Some(b::block(entries, false, block_span)),
            false,
            span,
        ));
    }

    /// `I("name")` → `[ i("name.obj") Rule. ]`: a terminal copy of the shape holding the
    /// instance, named after the rule, so that several instances can be placed in one rule.
    fn lower_instance(&mut self, path: Expr, span: Span, out: &mut Vec<Stmt>) {
        let path = match &path.kind {
            ExprKind::String(s) | ExprKind::Name(s) => b::string(&asset_path(s), path.span),
            _ => path,
        };
        let Some((rule, params)) = self.muller_rule.clone() else {
            return;
        };
        let args = (!params.is_empty()).then(|| {
            params
                .iter()
                .map(|p| b::name(&p.name, span))
                .collect::<Vec<_>>()
        });
        out.push(Stmt::Push(span));
        out.push(b::op("i", vec![path], span));
        out.push(b::call(b::ident(&rule.name, span), args, None, true, span));
        out.push(Stmt::Pop(span));
    }

    /// Merges the alternatives of each rule (same name and number of parameters) into one rule.
    fn muller_rules(&mut self, grammar: &mut Grammar, alternatives: Vec<Alternative>) {
        let mut groups: Vec<Vec<Alternative>> = Vec::new();
        let mut index: HashMap<(String, usize), usize> = HashMap::new();
        for alt in alternatives {
            let key = (alt.name.name.clone(), alt.params.len());
            match index.get(&key) {
                Some(&i) => groups[i].push(alt),
                None => {
                    index.insert(key, groups.len());
                    groups.push(vec![alt]);
                }
            }
        }
        for group in groups {
            if let Some(rule) = self.merge(group) {
                grammar.rules.push(rule);
            }
        }
    }

    fn merge(&mut self, group: Vec<Alternative>) -> Option<Rule> {
        let first = &group[0];
        let name = first.name.clone();
        let params = first.params.clone();
        let span = first.span.to(group[group.len() - 1].span);
        let mut ok = true;
        for alt in &group[1..] {
            let same = alt
                .params
                .iter()
                .zip(&params)
                .all(|(a, b)| a.name == b.name);
            if !same {
                let d = Diagnostic::error(
                    format!(
                        "the alternatives of `{}` name their parameters differently",
                        name.name
                    ),
                    alt.name.span,
                )
                .with_hint("use the same parameter names in every alternative");
                self.report(d);
                ok = false;
            }
        }
        // Alternatives with the same condition (by its text) choose at random among themselves.
        let mut classes: Vec<(Option<Expr>, Vec<Alternative>)> = Vec::new();
        let mut annotations = Vec::new();
        for mut alt in group {
            annotations.append(&mut alt.annotations);
            let text = alt.condition.as_ref().map(|c| {
                self.src[c.span.range()]
                    .split_whitespace()
                    .collect::<String>()
            });
            let found = classes.iter().position(|(c, _)| {
                c.as_ref().map(|c| {
                    self.src[c.span.range()]
                        .split_whitespace()
                        .collect::<String>()
                }) == text
            });
            match found {
                Some(i) => classes[i].1.push(alt),
                None => classes.push((alt.condition.clone(), vec![alt])),
            }
        }
        let mut arms = Vec::new();
        let mut otherwise = Body::Sequence(Vec::new());
        for (condition, alts) in classes {
            let Some(body) = self.choice(&name, alts) else {
                ok = false;
                continue;
            };
            match condition {
                Some(c) => arms.push((c, body)),
                None => otherwise = body,
            }
        }
        let body = if arms.is_empty() {
            otherwise
        } else {
            Body::Cases {
                arms,
                otherwise: Box::new(otherwise),
                span,
            }
        };
        ok.then_some(Rule {
            annotations,
            name,
            params,
            body,
            span,
        })
    }

    /// One alternative as it is, or several as a random choice by their probabilities.
    fn choice(&mut self, name: &Ident, alts: Vec<Alternative>) -> Option<Body> {
        if alts.len() == 1 {
            return alts.into_iter().next().map(|a| Body::Sequence(a.body));
        }
        let mut missing = false;
        for alt in &alts {
            if alt.probability.is_none() {
                let d = Diagnostic::error(
                    format!("rule `{}` has several alternatives, but this one has no probability", name.name),
                    alt.span,
                )
                .with_label("no `: probability` at its end")
                .with_hint("alternatives are chosen at random: end each with its probability, e.g. `~> A : 0.5`");
                self.report(d);
                missing = true;
            }
        }
        if missing {
            return None;
        }
        let span = alts[0].span.to(alts[alts.len() - 1].span);
        let weights: Vec<Expr> = alts.iter().filter_map(|a| a.probability.clone()).collect();
        let percents = self.percentages(&weights)?;
        let mut bodies: Vec<Body> = alts.into_iter().map(|a| Body::Sequence(a.body)).collect();
        let otherwise = bodies.pop().unwrap_or(Body::Sequence(Vec::new()));
        Some(Body::Stochastic {
            arms: percents.into_iter().zip(bodies).collect(),
            otherwise: Box::new(otherwise),
            span,
        })
    }
}

/// The percentages of all but the last of `weights`: `w / Σw × 100`, computed when all are
/// numbers, else as an expression.
impl Parser<'_> {
    pub(super) fn percentages(&mut self, weights: &[Expr]) -> Option<Vec<Expr>> {
        let numbers: Option<Vec<f64>> = weights
            .iter()
            .map(|w| match w.kind {
                ExprKind::Number(n) => Some(n),
                _ => None,
            })
            .collect();
        let shown = &weights[..weights.len().saturating_sub(1)];
        match numbers {
            Some(numbers) => {
                let sum: f64 = numbers.iter().sum();
                if sum.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    let span = weights[0].span.to(weights[weights.len() - 1].span);
                    let d = Diagnostic::error("the weights add up to zero", span)
                        .with_hint("give at least one alternative a positive weight");
                    self.report(d);
                    return None;
                }
                Some(
                    shown
                        .iter()
                        .zip(numbers)
                        .map(|(w, n)| b::number(percent(n, sum), w.span))
                        .collect(),
                )
            }
            None => {
                let sum = weights
                    .iter()
                    .cloned()
                    .reduce(|a, b| b::binary(BinaryOp::Add, a, b))?;
                Some(
                    shown
                        .iter()
                        .map(|w| {
                            let share = b::binary(BinaryOp::Div, w.clone(), sum.clone());
                            b::binary(BinaryOp::Mul, share, b::number(100.0, w.span))
                        })
                        .collect(),
                )
            }
        }
    }
}

/// `n / sum` as a percentage, rounded to 1e-9 so that `0.3` gives exactly `30`.
pub(super) fn percent(n: f64, sum: f64) -> f64 {
    (n / sum * 100.0 * 1e9).round() / 1e9
}

/// A size of `Subdiv`: `1r` (a share of what the absolute sizes leave) is CGA's floating `~1`.
fn split_size(size: Expr) -> Expr {
    match size.kind {
        ExprKind::Relative(inner) => b::floating(*inner),
        _ => size,
    }
}

/// The path `i(…)` inserts for `I(name)`: a built-in asset, or `name.obj`.
fn asset_path(name: &str) -> String {
    let lower = name.to_ascii_lowercase();
    if BUILTIN_ASSETS.contains(&lower.as_str()) {
        format!("builtin:{lower}")
    } else if name.contains('.') || name.contains(':') {
        name.to_owned()
    } else {
        format!("{name}.obj")
    }
}

fn unnamed(args: Vec<Argument>) -> Vec<Expr> {
    args.into_iter().map(|a| a.value).collect()
}

/// Maps the notation's names to Shapegram's: `Scope.sx` → `scope.sx`.
fn rename_queries(e: &mut Expr) {
    e.walk_mut(&mut |x| {
        if let ExprKind::Name(n) = &mut x.kind
            && let Some(rest) = n.strip_prefix("Scope.")
        {
            *n = format!("scope.{rest}");
        }
    });
}
