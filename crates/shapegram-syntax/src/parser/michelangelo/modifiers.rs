//! The parts of a rule call and the modifier chains after them (`Relative(0.4).Goal("support")`,
//! `.Fulfills(…)`, `.Attribute(…)`): sizes, faces, predicates and goal values.

use super::*;

impl Parser<'_> {
    /// `Relative(r)` or `Absolute(a)` and the part's modifiers.
    pub(super) fn size_part(&mut self) -> PResult<Part> {
        let word = self.ident();
        let open = self.bump();
        let size = self.mich_expr(None)?;
        let context = format!("after the size in `{}(…)`", word.name);
        let close = self.close(&TokenKind::RParen, open, "`)`", &context)?;
        let key = if word.name == "Relative" {
            PartKey::Relative(size, word.span.to(close))
        } else {
            PartKey::Absolute(size)
        };
        self.part_modifiers(key, word.span, None)
    }

    /// `Face.Top` and the part's modifiers (the first may be written in the same name:
    /// `Face.Top.Goal("seat")`).
    pub(super) fn face_part(&mut self) -> PResult<Part> {
        let word = self.ident();
        let mut segments = segments(&word).into_iter().skip(1);
        let Some(face) = segments.next() else {
            let d = Diagnostic::error("expected a face such as `Face.Top`", word.span)
                .with_hint(format!("the faces are {}", listing_faces()));
            self.report(d);
            return Err(Fail);
        };
        let Some(&(_, selector)) = FACES.iter().find(|(f, _)| *f == face.name) else {
            let mut d = Diagnostic::error(format!("unknown face `Face.{}`", face.name), face.span);
            d = match suggest(&face.name, FACES.iter().map(|f| f.0)) {
                Some(close) => d.with_hint(format!("did you mean `Face.{close}`?")),
                None => d.with_hint(format!("the faces are {}", listing_faces())),
            };
            self.report(d);
            return Err(Fail);
        };
        let first = segments.next();
        if let Some(extra) = segments.next() {
            return Err(self.unexpected_segment(&extra));
        }
        let face_span = word.span.to(face.span);
        self.part_modifiers(PartKey::Face(selector, face_span), word.span, first)
    }

    /// The modifiers of a part, lowered into its statements: attributes, synchronizations, then
    /// the goals; or `NIL` for `.Void()`.
    fn part_modifiers(&mut self, key: PartKey, start: Span, first: Option<Ident>) -> PResult<Part> {
        let mut sets = Vec::new();
        let mut syncs = Vec::new();
        let mut goals: Vec<Goal> = Vec::new();
        let mut goals_span: Option<Span> = None;
        let mut locals = Vec::new();
        let mut void: Option<Span> = None;
        let mut others: Option<Span> = None;
        let mut first = first;
        while let Some(modifier) = self.modifier_after(&mut first)? {
            let name = modifier.name.as_str();
            match name {
                "Goal" | "goal" => {
                    let (args, close) = self.mich_call_args()?;
                    let span = modifier.span.to(close);
                    if let Some(found) =
                        args.and_then(|a| self.goal_values(&modifier, a, "goal", span))
                    {
                        if name == "goal" {
                            locals.extend(found.iter().cloned());
                        }
                        goals.extend(found);
                    }
                    goals_span = Some(goals_span.map_or(span, |s| s.to(span)));
                    others = others.or(Some(span));
                }
                "Attribute" => {
                    let (args, close) = self.mich_call_args()?;
                    let span = modifier.span.to(close);
                    others = others.or(Some(span));
                    let Some(args) = args else { continue };
                    let found = args.len();
                    let Ok([attr, value]) = <[Argument; 2]>::try_from(args) else {
                        let d = Diagnostic::error(
                            format!("`Attribute` takes 2 arguments (name, value), found {found}"),
                            span,
                        )
                        .with_hint("write `.Attribute(\"Leg.Size\", 0.04)`");
                        self.report(d);
                        continue;
                    };
                    let ExprKind::String(attr_name) = &attr.value.kind else {
                        let d = Diagnostic::error(
                            "expected the attribute's name as a string",
                            attr.value.span,
                        )
                        .with_label("in `Attribute`")
                        .with_hint("write `.Attribute(\"Leg.Size\", 0.04)`");
                        self.report(d);
                        continue;
                    };
                    let getter = b::expr(
                        ExprKind::GoalAttribute {
                            name: attr_name.clone(),
                            kind: crate::ast::AttributeKind::Any,
                        },
                        attr.value.span,
                    );
                    sets.push(b::call(
                        b::ident("set", modifier.span),
                        Some(vec![getter, value.value]),
                        None,
                        false,
                        span,
                    ));
                }
                "Sync" => {
                    let (args, close) = self.mich_call_args()?;
                    let span = modifier.span.to(close);
                    others = others.or(Some(span));
                    let Some(args) = args else { continue };
                    match args.as_slice() {
                        [
                            Argument {
                                name: None,
                                value:
                                    Expr {
                                        kind: ExprKind::Name(var),
                                        span: var_span,
                                    },
                            },
                        ] if !var.contains('.') => {
                            syncs.push(b::call(
                                b::ident("sync", modifier.span),
                                Some(vec![b::name(var, *var_span)]),
                                None,
                                false,
                                span,
                            ));
                        }
                        _ => {
                            let d = Diagnostic::error(
                                "expected the name of a `Synchronize` variable",
                                span,
                            )
                            .with_label("in `Sync`")
                            .with_hint(
                                "declare one with `var windows = new Synchronize();` and write \
                                 `.Sync(windows)`",
                            );
                            self.report(d);
                        }
                    }
                }
                "Void" => {
                    let open = self.span();
                    let (args, close) = self.mich_call_args()?;
                    let span = modifier.span.to(close);
                    if args.is_some_and(|a| !a.is_empty()) {
                        let d = Diagnostic::error("`Void` takes no arguments", open.to(close))
                            .with_hint("write `.Void()`");
                        self.report(d);
                    }
                    if void.is_some() {
                        others = others.or(Some(span));
                    } else {
                        void = Some(span);
                    }
                }
                _ if RULE_MODIFIERS.contains(&name) => {
                    let d = Diagnostic::error(
                        format!("`{name}` is a modifier of rules, not of parts"),
                        modifier.span,
                    )
                    .with_hint(
                        "write it after the rule's closing parenthesis: \
                         `new Rules.Split(Axis.Y, …).Fulfills(\"chair\");`",
                    );
                    self.report(d);
                    self.skip_parens();
                }
                _ => {
                    self.unknown_modifier(&modifier, "part", PART_MODIFIERS);
                }
            }
        }
        if let (Some(void), Some(other)) = (void, others) {
            let d = Diagnostic::error("a void part takes no other modifier", other)
                .with_label(format!("besides `{}`", &self.src[void.range()]))
                .with_hint(
                    "`.Void()` deletes the part: its goals, attributes and synchronizations \
                     would be lost",
                );
            self.report(d);
        }
        let mut body = sets;
        body.extend(syncs);
        if let Some(span) = goals_span.filter(|_| !goals.is_empty()) {
            body.push(Stmt::Goals(goals, span));
        }
        if let Some(span) = void {
            body = vec![Stmt::Nil(span)];
        }
        Ok(Part {
            key,
            body,
            locals,
            span: self.span_from(start),
        })
    }

    /// The next `.Name` of a modifier chain (consumed), or `None` when no `.` followed by a
    /// name comes next.
    pub(super) fn next_modifier(&mut self) -> PResult<Option<Ident>> {
        if !(self.at(&TokenKind::Dot) && *self.peek_nth(1) == TokenKind::Ident) {
            return Ok(None);
        }
        self.bump();
        let name = self.ident();
        if let Some(extra) = segments(&name).get(1) {
            return Err(self.unexpected_segment(extra));
        }
        if !self.at(&TokenKind::LParen) {
            return Err(self.error_expected("`(`", &format!("after `.{}`", name.name)));
        }
        Ok(Some(name))
    }

    /// Reports `.name` written where a modifier's `(` belongs (`Face.Top.Goal.Void()`).
    pub(super) fn unexpected_segment(&mut self, segment: &Ident) -> Fail {
        let dot = Span::new(segment.span.start as usize - 1, segment.span.end as usize);
        let d = Diagnostic::error(format!("unexpected `.{}`", segment.name), dot)
            .with_label("expected `(` before it");
        self.report(d);
        Fail
    }

    /// Reports an unknown modifier of `what` (with the closest of `known`) and skips its
    /// arguments.
    pub(super) fn unknown_modifier<'k>(
        &mut self,
        modifier: &Ident,
        what: &str,
        known: impl IntoIterator<Item = &'k str> + Clone,
    ) {
        let mut d = Diagnostic::error(
            format!("unknown {what} modifier `{}`", modifier.name),
            modifier.span,
        );
        if let Some(close) = suggest(&modifier.name, known.clone()) {
            d = d.with_hint(format!("did you mean `{close}`?"));
        } else {
            let all: Vec<&str> = known.into_iter().collect();
            d = d.with_hint(format!(
                "the modifiers of a {what} are {}",
                listing(&all, ".")
            ));
        }
        self.report(d);
        self.skip_parens();
    }

    /// Skips a parenthesised group at the current token (to its `)` when it has one before the
    /// next statement).
    fn skip_parens(&mut self) {
        if !self.at(&TokenKind::LParen) {
            return;
        }
        let open = self.pos;
        self.bump();
        let _ = self.skip_to_close(open, Fail);
    }

    /// The next modifier of a chain: `first` when it was read already (then its `(` must
    /// follow), else the next `.Name(`; `None` at the end of the chain.
    fn modifier_after(&mut self, first: &mut Option<Ident>) -> PResult<Option<Ident>> {
        match first.take() {
            Some(m) if !self.at(&TokenKind::LParen) => {
                Err(self.error_expected("`(`", &format!("after `{}`", m.name)))
            }
            Some(m) => Ok(Some(m)),
            None => self.next_modifier(),
        }
    }

    /// A chain of rule modifiers `.Fulfills(…).IfIs(…)…`, the first one possibly already read
    /// (`Predicates.IfIs` names it).
    pub(super) fn modifier_chain(
        &mut self,
        first: Option<Ident>,
        chain: Chain,
    ) -> PResult<Modifiers> {
        let mut out = Modifiers::default();
        let mut first = first;
        loop {
            let Some(modifier) = self.modifier_after(&mut first)? else {
                return Ok(out);
            };
            let name = modifier.name.as_str();
            if let Some((negated, word)) = predicate_word(name) {
                if let Some((kind, close)) = self.predicate(&modifier, word)? {
                    out.predicates.push(Predicate {
                        kind,
                        negated,
                        span: modifier.span.to(close),
                    });
                }
                continue;
            }
            match name {
                "Fulfills" | "fulfills" | "Goal" | "goal" => {
                    let (args, close) = self.mich_call_args()?;
                    let span = modifier.span.to(close);
                    if chain == Chain::Using {
                        let d = Diagnostic::error(
                            "`using` gives its rules conditions, not goals to fulfil or add",
                            modifier.span,
                        )
                        .with_hint("write `.Fulfills(…)` and `.Goal(…)` on each rule");
                        self.report(d);
                        continue;
                    }
                    let goals = args.and_then(|a| self.goal_values(&modifier, a, "goal", span));
                    let Some(goals) = goals else { continue };
                    if name.starts_with(char::is_lowercase) {
                        out.locals.extend(goals.iter().cloned());
                    }
                    if name.eq_ignore_ascii_case("fulfills") {
                        out.fulfills.extend(goals);
                    } else {
                        out.adds.extend(goals);
                    }
                }
                "Attribute" | "Sync" | "Void" if chain == Chain::Rule => {
                    let d = Diagnostic::error(
                        format!("`{name}` is a modifier of parts, not of rules"),
                        modifier.span,
                    )
                    .with_hint("write it on a part: `Relative(1).Void()`");
                    self.report(d);
                    self.skip_parens();
                }
                _ => {
                    let (what, known) = match chain {
                        Chain::Rule => ("rule", &RULE_MODIFIERS[..]),
                        Chain::Using => ("predicate", &RULE_MODIFIERS[4..]),
                    };
                    self.unknown_modifier(&modifier, what, known.iter().copied());
                }
            }
        }
    }

    /// The arguments of the predicate modifier `modifier` (`word` is what it asks: `Goal`,
    /// `Is`, `Tag`, `Has`, or `""` for `If`), from its `(`; `None` when they are wrong
    /// (reported).
    fn predicate(
        &mut self,
        modifier: &Ident,
        word: &str,
    ) -> PResult<Option<(PredicateKind, Span)>> {
        if word.is_empty() {
            let open = self.bump();
            let param = self.lambda_parameter();
            let value = self.mich_expr(param.as_deref())?;
            let context = format!("after the condition of `{}`", modifier.name);
            let close = self.close(&TokenKind::RParen, open, "`)`", &context)?;
            return Ok(Some((PredicateKind::If(value), close)));
        }
        let (args, close) = self.mich_call_args()?;
        let span = modifier.span.to(close);
        let what = match word {
            "Has" => "attribute name",
            "Goal" => "goal",
            _ => "tag",
        };
        let Some(goals) = args.and_then(|a| self.goal_values(modifier, a, what, span)) else {
            return Ok(None);
        };
        let kind = match word {
            "Goal" => PredicateKind::Goal(goals),
            "Has" => PredicateKind::Has(
                goals
                    .into_iter()
                    .map(|g| Ident {
                        name: g.name,
                        span: g.span,
                    })
                    .collect(),
            ),
            _ => PredicateKind::Is(goals),
        };
        Ok(Some((kind, close)))
    }

    /// `s =>` or `(s) =>` at the start of a condition (consumed): the lambda's parameter.
    fn lambda_parameter(&mut self) -> Option<String> {
        let arrow_at = |p: &Self, i: usize| {
            *p.kind_at(i) == TokenKind::Eq
                && *p.kind_at(i + 1) == TokenKind::Gt
                && p.token_at(i).span.end == p.token_at(i + 1).span.start
        };
        let simple = |p: &Self, i: usize| p.is_name_at(i) && !p.text_at(i).contains('.');
        if simple(self, self.pos) && arrow_at(self, self.pos + 1) {
            let name = self.text().to_owned();
            for _ in 0..3 {
                self.bump();
            }
            return Some(name);
        }
        if self.at(&TokenKind::LParen)
            && simple(self, self.pos + 1)
            && *self.peek_nth(2) == TokenKind::RParen
            && arrow_at(self, self.pos + 3)
        {
            let name = self.text_at(self.pos + 1).to_owned();
            for _ in 0..5 {
                self.bump();
            }
            return Some(name);
        }
        None
    }

    /// Goals (or tags, attribute names: `what`) given as strings: at least one, none empty.
    pub(super) fn goal_values(
        &mut self,
        modifier: &Ident,
        args: Vec<Argument>,
        what: &str,
        span: Span,
    ) -> Option<Vec<Goal>> {
        let article = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
            "an"
        } else {
            "a"
        };
        if args.is_empty() {
            let d = Diagnostic::error(
                format!("`{}` takes at least one {what}", modifier.name),
                span,
            )
            .with_hint(format!("write `{}(\"name\")`", modifier.name));
            self.report(d);
            return None;
        }
        let mut goals = Vec::new();
        let mut ok = true;
        for a in args {
            let span = a.value.span;
            let d = match a.value.kind {
                ExprKind::String(name) if !name.is_empty() => {
                    goals.push(Goal { name, span });
                    continue;
                }
                ExprKind::String(_) => {
                    Diagnostic::error(format!("empty {what} in `{}`", modifier.name), span)
                }
                ExprKind::Name(name) => Diagnostic::error(
                    format!(
                        "expected {article} {what} as a string in `{}`, found `{name}`",
                        modifier.name
                    ),
                    span,
                )
                .with_hint(format!("write \"{name}\"")),
                _ => Diagnostic::error(
                    format!(
                        "expected {article} {what} as a string in `{}`",
                        modifier.name
                    ),
                    span,
                ),
            };
            self.report(d);
            ok = false;
        }
        ok.then_some(goals)
    }
}
