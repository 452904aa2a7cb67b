//! The native notation of goal grammars (`.goal` files):
//!
//! ```text
//! local split_legs                          // goals only this grammar's rules fulfil
//! sync windows                              // shapes that derive alike
//! axiom chair, wooden size(0.4, 0.8, 0.4)  // a shape to start from
//!
//! fulfills(chair) -->
//!     split(y) { ~0.4 : set(@Leg.Size, rand(0.03, 0.05)) +support | ~0.05 : +seat | ~0.55 : +lean }
//!
//! using is(chair) {
//!     fulfills(lean) --> s('1, '1, 0.04)
//! }
//! ```
//!
//! A rule's head is a list of predicates, each optionally negated with `!`: `fulfills(g…)`,
//! `goal(g…)`, `is(t…)` (or `tag(t…)`), `has(a…)`, `if(expression)`, and `adds(g…)` (goals added
//! to every shape the rule makes). Bodies are the main syntax's, where `+goal` is the successor
//! (the shape goes on with that goal added), `void` deletes a part, and `@name` reads a shape's
//! attribute.

use super::{Fail, PResult, Parser, Start};
use crate::Diagnostic;
use crate::ast::{Annotation, Axiom, Goal, GoalRule, Grammar, Ident, Predicate, PredicateKind};
use crate::lexer::TokenKind;

/// The words of a rule head.
pub(crate) const PREDICATE_WORDS: [&str; 7] =
    ["fulfills", "goal", "is", "tag", "has", "if", "adds"];

impl Parser<'_> {
    /// A file in the native goal notation.
    pub(super) fn goal_file(&mut self, grammar: &mut Grammar) {
        self.goal_declarations(grammar, &[], false);
    }

    /// Declarations up to the end of the file or, inside a `using` block, to its `}`; the rules
    /// read get the block's predicates first.
    fn goal_declarations(&mut self, grammar: &mut Grammar, inherited: &[Predicate], block: bool) {
        loop {
            if self.at(&TokenKind::Eof) || block && self.at(&TokenKind::RBrace) {
                return;
            }
            let before = self.pos;
            let result = self
                .annotations()
                .and_then(|annotations| self.goal_declaration(grammar, annotations, inherited));
            if result.is_err() {
                self.recover_to_declaration();
                // A `}` ends the block the failed declaration was in.
            }
            if self.pos == before {
                if block && self.at(&TokenKind::RBrace) {
                    return;
                }
                self.bump();
            }
        }
    }

    fn goal_declaration(
        &mut self,
        grammar: &mut Grammar,
        annotations: Vec<Annotation>,
        inherited: &[Predicate],
    ) -> PResult<()> {
        match self.peek() {
            TokenKind::Eof if !annotations.is_empty() => {
                Err(self.error_expected("a rule", "after the annotation"))
            }
            TokenKind::Ident if self.at_word("local") && annotations.is_empty() => {
                self.bump();
                let goals = self.goal_list("a goal", "after `local`")?;
                grammar.local_goals.extend(goals);
                Ok(())
            }
            TokenKind::Ident if self.at_word("sync") && annotations.is_empty() => {
                self.bump();
                loop {
                    if *self.peek() != TokenKind::Ident {
                        return Err(self.error_expected("a synchronization's name", "after `sync`"));
                    }
                    grammar.syncs.push(self.ident());
                    if self.eat(&TokenKind::Comma).is_none() {
                        return Ok(());
                    }
                }
            }
            TokenKind::Ident if self.at_word("axiom") && annotations.is_empty() => {
                self.axiom(grammar)
            }
            TokenKind::Ident if self.at_word("using") && annotations.is_empty() => {
                self.using_block(grammar, inherited)
            }
            TokenKind::Bang | TokenKind::Ident if self.goal_rule_start(self.pos).is_some() => {
                self.goal_rule(grammar, annotations, inherited)
            }
            _ => {
                let d = self.expected("a goal-grammar declaration", "").with_hint(
                    "a goal grammar holds `axiom goals size(x, y, z)`, `local goals`, `sync name`, \
                     rules `fulfills(goal) --> body` and `using is(tag) { rules }`",
                );
                self.report(d);
                Err(Fail)
            }
        }
    }

    /// `axiom chair, wooden size(0.4, 0.8, 0.4)`.
    fn axiom(&mut self, grammar: &mut Grammar) -> PResult<()> {
        let start = self.bump();
        let goals = self.goal_list("a goal", "after `axiom`")?;
        let size = if self.at_word("size") && *self.peek_nth(1) == TokenKind::LParen {
            let open = self.bump();
            let (args, close) = self.call_args()?;
            let [x, y, z]: [_; 3] = match args
                .into_iter()
                .map(|a| a.value)
                .collect::<Vec<_>>()
                .try_into()
            {
                Ok(xyz) => xyz,
                Err(values) => {
                    let d = Diagnostic::error(
                        format!("`size` takes 3 values (x, y, z), found {}", values.len()),
                        open.to(close),
                    );
                    self.report(d);
                    return Err(Fail);
                }
            };
            Some([x, y, z])
        } else {
            None
        };
        grammar.axioms.push(Axiom {
            goals,
            size,
            span: self.span_from(start),
        });
        Ok(())
    }

    /// `using is(chair) has(Leg.Size) { rules }`.
    fn using_block(&mut self, grammar: &mut Grammar, inherited: &[Predicate]) -> PResult<()> {
        self.bump();
        let mut predicates = inherited.to_vec();
        let head = self.predicates()?;
        if let Some(fulfills) = head.fulfills.first().or(head.adds.first()) {
            let d = Diagnostic::error(
                "`using` gives its rules conditions, not goals to fulfil or add",
                fulfills.span,
            )
            .with_hint("write `fulfills(…)` and `adds(…)` on each rule");
            self.report(d);
            return Err(Fail);
        }
        if head.predicates.is_empty() {
            return Err(self.error_expected("a predicate such as `is(chair)`", "after `using`"));
        }
        predicates.extend(head.predicates);
        let Some(open) = self.eat(&TokenKind::LBrace) else {
            return Err(self.error_expected("`{`", "after the predicates of `using`"));
        };
        self.nested(|p| {
            p.goal_declarations(grammar, &predicates, true);
            Ok(())
        })?;
        if self.eat(&TokenKind::RBrace).is_none() {
            let d = Diagnostic::error("unclosed `{`", open)
                .with_label("this `using` block is never closed")
                .with_hint("close it with `}` after its last rule");
            self.report(d);
        }
        Ok(())
    }

    /// `predicates --> body`.
    fn goal_rule(
        &mut self,
        grammar: &mut Grammar,
        annotations: Vec<Annotation>,
        inherited: &[Predicate],
    ) -> PResult<()> {
        let start = self.span();
        let head = self.predicates()?;
        self.expect(&TokenKind::Arrow, "`-->`", "after the rule's predicates")?;
        let body = self.body()?;
        let mut predicates = inherited.to_vec();
        predicates.extend(head.predicates);
        grammar.goal_rules.push(GoalRule {
            annotations,
            predicates,
            fulfills: head.fulfills,
            adds: head.adds,
            body,
            span: self.span_from(start),
        });
        if self.at(&TokenKind::RBrace) || self.at_declaration_start() {
            Ok(())
        } else {
            Err(self.error_expected("an operation, `+goal` or the next rule", "in the rule body"))
        }
    }

    /// The predicates of a rule head or `using`, up to the `-->` or `{`.
    fn predicates(&mut self) -> PResult<Head> {
        let mut head = Head::default();
        loop {
            let bang = self.eat(&TokenKind::Bang);
            if *self.peek() == TokenKind::Ident
                && !PREDICATE_WORDS.contains(&self.text())
                && *self.peek_nth(1) == TokenKind::LParen
            {
                let word = self.text();
                let mut d = Diagnostic::error(format!("unknown predicate `{word}`"), self.span());
                if let Some(close) = crate::suggest(word, PREDICATE_WORDS) {
                    d = d.with_hint(format!("did you mean `{close}`?"));
                }
                self.report(d);
                // Past the word, so that recovery goes on to the next declaration.
                self.bump();
                return Err(Fail);
            }
            if *self.peek() != TokenKind::Ident || !PREDICATE_WORDS.contains(&self.text()) {
                let empty =
                    head.predicates.is_empty() && head.fulfills.is_empty() && head.adds.is_empty();
                if bang.is_none() && !empty {
                    return Ok(head);
                }
                let d = self.expected("a predicate", "").with_hint(
                    "predicates are `fulfills(…)`, `goal(…)`, `is(…)`, `has(…)`, `if(…)` and \
                     `adds(…)`, each negated with `!` (except `fulfills` and `adds`)",
                );
                self.report(d);
                return Err(Fail);
            }
            let word = self.ident();
            let open = self.expect(&TokenKind::LParen, "`(`", &format!("after `{}`", word.name))?;
            let what = format!("in `{}(…)`", word.name);
            let kind = match word.name.as_str() {
                "fulfills" | "adds" => {
                    let goals = self.goal_list("a goal", &what)?;
                    if let Some(bang) = bang {
                        let d =
                            Diagnostic::error(format!("`{}` cannot be negated", word.name), bang)
                                .with_hint("to ask that a shape lacks a goal, write `!goal(…)`");
                        self.report(d);
                    }
                    if word.name == "fulfills" {
                        head.fulfills.extend(goals);
                    } else {
                        head.adds.extend(goals);
                    }
                    None
                }
                "goal" => Some(PredicateKind::Goal(self.goal_list("a goal", &what)?)),
                "is" | "tag" => Some(PredicateKind::Is(self.goal_list("a tag", &what)?)),
                "has" => Some(PredicateKind::Has(
                    self.goal_list("an attribute name", &what)?
                        .into_iter()
                        .map(|g| Ident {
                            name: g.name,
                            span: g.span,
                        })
                        .collect(),
                )),
                _ => Some(PredicateKind::If(self.expr()?)),
            };
            let close = self.close(&TokenKind::RParen, open, "`)`", &what)?;
            if let Some(kind) = kind {
                head.predicates.push(Predicate {
                    kind,
                    negated: bang.is_some(),
                    span: bang.unwrap_or(word.span).to(close),
                });
            }
        }
    }

    /// `a, b, "c-d"`: goals (or attribute names) as names or strings, at least one.
    fn goal_list(&mut self, what: &str, context: &str) -> PResult<Vec<Goal>> {
        let mut goals = vec![self.goal_name(what, context)?];
        while self.eat(&TokenKind::Comma).is_some() {
            goals.push(self.goal_name(what, context)?);
        }
        Ok(goals)
    }

    /// A goal (or attribute name): a name, or a string when it holds other characters.
    fn goal_name(&mut self, what: &str, context: &str) -> PResult<Goal> {
        match self.peek().clone() {
            TokenKind::Ident => {
                let ident = self.ident();
                Ok(Goal {
                    name: ident.name,
                    span: ident.span,
                })
            }
            TokenKind::Str(name) if !name.is_empty() => Ok(Goal {
                name,
                span: self.bump(),
            }),
            _ => Err(self.error_expected(what, context)),
        }
    }

    /// `+seat +"split-legs"`: the goals of a successor (the current token is `+`).
    pub(super) fn goal_successor(&mut self) -> PResult<crate::ast::Stmt> {
        let start = self.span();
        let mut goals = Vec::new();
        while self.eat(&TokenKind::Plus).is_some() {
            goals.push(self.goal_name("a goal", "after `+`")?);
        }
        Ok(crate::ast::Stmt::Goals(goals, self.span_from(start)))
    }

    /// Whether a declaration of the native goal notation starts at token `i`.
    pub(super) fn goal_declaration_start(&self, i: usize) -> Option<Start> {
        match self.kind_at(i) {
            TokenKind::Eof | TokenKind::At => Some(Start::Strong),
            TokenKind::Ident => match self.text_at(i) {
                "local" | "axiom" => {
                    matches!(self.kind_at(i + 1), TokenKind::Ident | TokenKind::Str(_))
                        .then_some(Start::Strong)
                }
                "sync" => (*self.kind_at(i + 1) == TokenKind::Ident).then_some(Start::Strong),
                "using" => Some(Start::Strong),
                _ => self.goal_rule_start(i),
            },
            TokenKind::Bang => self.goal_rule_start(i),
            _ => None,
        }
    }

    /// Whether tokens from `i` are a rule head: predicates followed by `-->`.
    fn goal_rule_start(&self, mut i: usize) -> Option<Start> {
        let first = i;
        loop {
            // A head is on one line: a body's last operation may stand at the start of the line
            // before the next rule.
            if i > first && self.token_at(i).line_start {
                return None;
            }
            if *self.kind_at(i) == TokenKind::Bang {
                i += 1;
            }
            // Any `word(…)` counts, so that a misspelt predicate is reported as one.
            if *self.kind_at(i) != TokenKind::Ident || *self.kind_at(i + 1) != TokenKind::LParen {
                return None;
            }
            i = self.closing_paren(i + 1)? + 1;
            if *self.kind_at(i) == TokenKind::Arrow {
                return Some(Start::Strong);
            }
        }
    }
}

/// A rule head as read: its predicates and the goals it fulfils and adds.
#[derive(Default)]
struct Head {
    predicates: Vec<Predicate>,
    fulfills: Vec<Goal>,
    adds: Vec<Goal>,
}
