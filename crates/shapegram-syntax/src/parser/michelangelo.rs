//! The C#-style notation of goal grammars in Michelangelo (Ilčík and Wimmer, "Collaborative
//! Modeling with Symbolic Shape Grammars"), lowered to the goal rules of the common AST while it
//! is read. The paper's listings read as printed (`↪`, the mark of a line broken in print, is
//! whitespace):
//!
//! ```text
//! var windows = new Synchronize();
//! new Axiom("chair", "wooden").Size(0.4, 0.8, 0.4);
//!
//! new Rules.Split(Axis.Y,
//!   Relative(0.4).Goal("support").Attribute("Leg.Size", Rnd(0.03, 0.05)),
//!   Relative(0.05).Goal("seat"),
//!   Relative(0.55).Goal("lean"))
//! .Fulfills("chair");
//!
//! using (Predicates.IfIs("chair")) {
//!   new Rules.Size(Axis.Z, 0.04).Fulfills("lean");
//! }
//! ```
//!
//! A file is a list of statements, each ending with `;` (`using` blocks end with their `}`):
//!
//! - `new Axiom("g", …)` with an optional `.Size(x, y, z)`: an [`Axiom`].
//! - `var name = new Synchronize();`: a synchronization, in [`Grammar::syncs`].
//! - `new Rules.Kind(arguments)` (`new` may be left out) followed by rule modifiers: a
//!   [`GoalRule`].
//! - `using (Predicates.IfIs("t")…) { statements }`: every rule inside gets these predicates
//!   first; blocks nest.
//!
//! Rule kinds and their lowering to the main syntax's statements (the rule's body is a
//! [`Body::Sequence`] of them, as the native notation would write them):
//!
//! | Michelangelo | main syntax |
//! | --- | --- |
//! | `Split(Axis.Y, parts…)` | `split(y) { key : part \| … }`; `Relative(r)` is the floating `~r` (a share of what the absolute parts leave), `Absolute(a)` is `a` |
//! | `Repeat(Axis.X, parts…)` | `split(x) { { ~a : part \| … }* }`: both `Absolute(a)` and `Relative(a)` are `~a` (whole tiles fit) |
//! | `Size(Axis.Z, v)` | `s('1, '1, v)` (likewise for X and Y) |
//! | `Scale(Vec3(a, b, c), Pivot.P)` | `s('a, 'b, 'c)`, then `center(xyz)` for `Pivot.Middle`, `center(xz)` for `Pivot.Bottom`, nothing for `Pivot.Min` and `Pivot.Origin` |
//!
//! Shapegram adds these kinds (the paper names taper, twist and shear rules but prints none):
//!
//! | Michelangelo | main syntax |
//! | --- | --- |
//! | `Translate(Vec3(x, y, z))` | `t(x, y, z)` |
//! | `Rotate(Vec3(x, y, z))` (degrees) | `r(scopeCenter, x, y, z)` |
//! | `Color("#8b5a2b")` | `color("#8b5a2b")` |
//! | `Material("oak")` | `set(material.name, "oak")` |
//! | `Insert("file.obj")` | `i("file.obj")` |
//! | `Comp(Face.Top.Goal("seat"), Face.Side.Void(), …)` | `comp(f) { top : +seat \| side : NIL \| … }`; the faces are `Top`, `Bottom`, `Front`, `Back`, `Left`, `Right`, `Side`, `All`, `Vertical`, `Horizontal` |
//! | `Taper(Axis.Y, 0.5)` | `taper(y, 0.5)` |
//! | `Twist(Axis.Y, 45)` | `twist(y, 45)` |
//! | `Shear(Axis.Y, Axis.X, 0.2)` | `shear(y, x, 0.2)` |
//! | `Identity()` | nothing: the rule only fulfils, adds or tags |
//!
//! A part (`Relative(r)` and `Absolute(a)` in splits and repeats, `Face.X` in `Comp`) takes
//! modifiers, lowered into the part's statements in this order: each `.Attribute("name", value)`
//! is `set(@name, value)`, each `.Sync(windows)` is `sync(windows)`, and all `.Goal("g")` of the
//! part are one `+g …` successor. A part without goals goes on with the goals it inherits.
//! `.Void()` is `NIL`, and takes no other modifier.
//!
//! Rule modifiers follow the rule's closing parenthesis: `.Fulfills(g…)` (the rule's
//! [`GoalRule::fulfills`]), `.Goal(g…)` (goals added to every shape it makes, [`GoalRule::adds`]),
//! and the predicates `.IfGoal(g…)`, `.IfIs(t…)` (or `.IfTag(t…)`), `.IfHas(a…)`, `.If(e)`, each
//! also negated: `.IfNotGoal`, `.IfNotIs`, `.IfNotTag`, `.IfNotHas`, `.IfNot`.
//!
//! Lowercase means local: `.goal("g")` and `.fulfills("g")` (on rules and parts) make `g` one of
//! the grammar's [`Grammar::local_goals`], which the compiler makes local wherever it is used.
//!
//! Expressions are the main syntax's, with `Rnd(a, b)` for `rand(a, b)`, `@Double("name")` and
//! `@String("name")` for a shape's attributes, and, in `If(…)`, a C# lambda `s => …` (or
//! `(s) => …`) or the bare condition: `Size.X` and `s.Size.X` are `scope.sx`, `Position.X` and
//! `s.Position.X` are `scope.tx` (likewise for Y and Z), whatever the parameter is called.
//!
//! Also read: `//` and `/* … */` comments, empty statements (`;;`), `new Vec3(…)` for `Vec3(…)`,
//! and a trailing comma in a rule's arguments (`Split(Axis.Y, /*foot, ankle, etc.*/)`, as
//! printed). Whether `.Sync(name)` names a declared synchronization is left to the compiler, so
//! that each listing of the paper reads on its own.
//!
//! Errors are reported as the main syntax's are ("did you mean" for misspelled rule kinds,
//! modifiers, faces and pivots; argument counts with the construct's signature; a missing `;`
//! where it belongs), and a rule with an error is left out. After an error the parser skips past
//! the statement's `;` (or to a `}` that ends its block, or to a statement that starts a line:
//! `new …`, `var …`, `using (…`, `Rules.…(`), so one run reports several errors.

use super::build as b;
use super::{Fail, PResult, Parser, Start};
use crate::ast::{
    Argument, Axiom, BlockEntry, Body, Expr, ExprKind, Goal, GoalRule, Grammar, Ident, Predicate,
    PredicateKind, Stmt,
};
use crate::lexer::TokenKind;
use crate::{Diagnostic, Span, suggest};

/// The rule kinds, written `Rules.Kind(…)`.
pub(crate) const RULE_KINDS: [&str; 14] = [
    "Split",
    "Repeat",
    "Size",
    "Scale",
    "Translate",
    "Rotate",
    "Color",
    "Material",
    "Insert",
    "Comp",
    "Taper",
    "Twist",
    "Shear",
    "Identity",
];

/// The modifiers of a rule (after its closing parenthesis); all but the first four are
/// predicates, which `using` takes too.
const RULE_MODIFIERS: [&str; 14] = [
    "Fulfills",
    "fulfills",
    "Goal",
    "goal",
    "IfGoal",
    "IfNotGoal",
    "IfIs",
    "IfNotIs",
    "IfTag",
    "IfNotTag",
    "IfHas",
    "IfNotHas",
    "If",
    "IfNot",
];

/// The modifiers of a part.
const PART_MODIFIERS: [&str; 5] = ["Goal", "goal", "Attribute", "Sync", "Void"];

/// The faces `Comp` selects, and their selectors in the main syntax.
const FACES: [(&str, &str); 10] = [
    ("Top", "top"),
    ("Bottom", "bottom"),
    ("Front", "front"),
    ("Back", "back"),
    ("Left", "left"),
    ("Right", "right"),
    ("Side", "side"),
    ("All", "all"),
    ("Vertical", "vertical"),
    ("Horizontal", "horizontal"),
];

/// The pivots of `Scale`, and the axes `center` centres on for each.
const PIVOTS: [(&str, Option<&str>); 4] = [
    ("Middle", Some("xyz")),
    ("Bottom", Some("xz")),
    ("Min", None),
    ("Origin", None),
];

/// Where a chain of modifiers is written.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Chain {
    /// After a rule's closing parenthesis.
    Rule,
    /// After `Predicates.` in `using (…)`.
    Using,
}

/// What the modifiers of a rule (or a `using`) say.
#[derive(Default)]
struct Modifiers {
    predicates: Vec<Predicate>,
    fulfills: Vec<Goal>,
    adds: Vec<Goal>,
    /// Goals written in lowercase.
    locals: Vec<Goal>,
}

/// A part of `Split`, `Repeat` or `Comp`, lowered.
struct Part {
    key: PartKey,
    /// The part's statements.
    body: Vec<Stmt>,
    /// Goals written in lowercase.
    locals: Vec<Goal>,
    span: Span,
}

enum PartKey {
    /// `Relative(r)`: the size and the span of the whole `Relative(…)`.
    Relative(Expr, Span),
    /// `Absolute(a)`: the size.
    Absolute(Expr),
    /// `Face.Top`: the selector in the main syntax.
    Face(&'static str, Span),
}

/// An argument of a rule: a part or a value (`Axis.Y`, `Vec3(…)`, `Pivot.Middle`, `0.04`).
enum Arg {
    Part(Part),
    Value(Expr),
}

impl Arg {
    fn span(&self) -> Span {
        match self {
            Arg::Part(p) => p.span,
            Arg::Value(e) => e.span,
        }
    }
}

impl Parser<'_> {
    /// A file in the Michelangelo notation.
    pub(super) fn michelangelo_file(&mut self, grammar: &mut Grammar) {
        self.mich_statements(grammar, &[], false);
    }

    /// Whether a declaration of the Michelangelo notation starts at token `i`: `new Axiom`,
    /// `new Rules.…`, `new Synchronize`, `var name`, `using (` or `Rules.…(`.
    pub(super) fn michelangelo_declaration_start(&self, i: usize) -> Option<Start> {
        match self.kind_at(i) {
            TokenKind::Eof => Some(Start::Strong),
            TokenKind::Ident => self.mich_statement_start(i).then_some(Start::Strong),
            _ => None,
        }
    }

    /// Whether a statement starts at token `i` (wherever it is on its line).
    fn mich_statement_start(&self, i: usize) -> bool {
        let next_is_ident = *self.kind_at(i + 1) == TokenKind::Ident;
        match self.text_at(i) {
            _ if *self.kind_at(i) != TokenKind::Ident => false,
            "new" => {
                next_is_ident && {
                    let next = self.text_at(i + 1);
                    matches!(next, "Axiom" | "Synchronize") || next.starts_with("Rules.")
                }
            }
            "var" => next_is_ident,
            "using" => *self.kind_at(i + 1) == TokenKind::LParen,
            word => word.starts_with("Rules.") && *self.kind_at(i + 1) == TokenKind::LParen,
        }
    }

    /// Statements up to the end of the file or, inside a `using` block, to its `}`; the rules
    /// read get `inherited` predicates first.
    fn mich_statements(&mut self, grammar: &mut Grammar, inherited: &[Predicate], block: bool) {
        loop {
            if self.at(&TokenKind::Eof) || block && self.at(&TokenKind::RBrace) {
                return;
            }
            let before = self.pos;
            if self.mich_statement(grammar, inherited).is_err() {
                self.mich_recover();
            }
            if self.pos == before {
                if block && self.at(&TokenKind::RBrace) {
                    return;
                }
                self.bump();
            }
        }
    }

    /// Skips what is left of a statement that failed: past its `;`, or to a `}` that closes the
    /// block it is in, or to a statement that starts a line.
    fn mich_recover(&mut self) {
        let mut depth = 0usize;
        loop {
            if self.at_resume_point() {
                return;
            }
            match self.peek() {
                TokenKind::Eof => return,
                TokenKind::Semi if depth == 0 => {
                    self.bump();
                    return;
                }
                TokenKind::RBrace if depth == 0 => return,
                TokenKind::LParen | TokenKind::LBrace | TokenKind::LBracket => depth += 1,
                TokenKind::RParen | TokenKind::RBrace | TokenKind::RBracket => {
                    depth = depth.saturating_sub(1);
                }
                _ => {}
            }
            self.bump();
        }
    }

    fn mich_statement(&mut self, grammar: &mut Grammar, inherited: &[Predicate]) -> PResult<()> {
        let start = self.span();
        match self.peek() {
            // An empty statement, as C# allows.
            TokenKind::Semi => {
                self.bump();
                Ok(())
            }
            TokenKind::RBrace => {
                let d = Diagnostic::error("unexpected `}`", start)
                    .with_label("no `using` block is open here");
                self.report(d);
                self.bump();
                Ok(())
            }
            TokenKind::Ident if self.at_word("new") => {
                self.bump();
                match self.peek() {
                    TokenKind::Ident if self.at_word("Axiom") => self.mich_axiom(grammar, start),
                    TokenKind::Ident if self.text().starts_with("Rules") => {
                        self.mich_rule(grammar, inherited, start)
                    }
                    TokenKind::Ident if self.at_word("Synchronize") => {
                        let d = Diagnostic::error(
                            "a `Synchronize` must be kept in a variable",
                            start.to(self.span()),
                        )
                        .with_hint("declare it as `var windows = new Synchronize();`");
                        self.report(d);
                        Err(Fail)
                    }
                    _ => {
                        let d = self.expected("`Axiom(…)` or `Rules.…(…)`", "after `new`");
                        self.report(d);
                        Err(Fail)
                    }
                }
            }
            TokenKind::Ident if self.at_word("var") => self.mich_sync(grammar),
            TokenKind::Ident if self.at_word("using") => self.mich_using(grammar, inherited),
            TokenKind::Ident if self.text().starts_with("Rules") => {
                self.mich_rule(grammar, inherited, start)
            }
            _ => {
                let d = self.expected("a statement", "").with_hint(
                    "a Michelangelo grammar holds `new Axiom(\"goal\", …);`, \
                     `var name = new Synchronize();`, rules `new Rules.Split(…).Fulfills(\"goal\");` \
                     and `using (Predicates.IfIs(\"tag\")) { rules }`",
                );
                self.report(d);
                Err(Fail)
            }
        }
    }

    /// The `;` that ends a statement. When it is missing, the error points where it belongs:
    /// after the statement when the next token starts a line, else at that token. Parsing goes
    /// on without skipping when the next statement (or the end of a block) follows.
    fn mich_end(&mut self, what: &str) -> PResult<()> {
        if self.eat(&TokenKind::Semi).is_some() {
            return Ok(());
        }
        let token = self.token_at(self.pos);
        let message = format!("expected `;` after {what}, found {}", self.describe());
        let d = if token.line_start {
            Diagnostic::error(
                message,
                Span::new(self.last_end as usize, self.last_end as usize),
            )
            .with_label("add `;` here")
        } else {
            Diagnostic::error(message, token.span).with_label("expected `;` here")
        };
        self.report(d);
        let next_statement = self.at(&TokenKind::Eof)
            || self.at(&TokenKind::RBrace)
            || self.mich_statement_start(self.pos);
        if next_statement { Ok(()) } else { Err(Fail) }
    }

    // --- Axioms, synchronizations and `using` ---------------------------------------------------

    /// `new Axiom("chair", "wooden").Size(0.4, 0.8, 0.4);` (from `Axiom`).
    fn mich_axiom(&mut self, grammar: &mut Grammar, start: Span) -> PResult<()> {
        let errors = self.errors;
        let name = self.ident();
        if !self.at(&TokenKind::LParen) {
            return Err(self.error_expected("`(`", "after `Axiom`"));
        }
        let (args, close) = self.mich_call_args()?;
        let goals = args
            .and_then(|args| self.goal_values(&name, args, "goal", name.span.to(close)))
            .unwrap_or_default();
        let mut size: Option<[Expr; 3]> = None;
        while let Some(modifier) = self.next_modifier()? {
            if modifier.name != "Size" {
                self.unknown_modifier(&modifier, "axiom", ["Size"]);
                continue;
            }
            let (args, close) = self.mich_call_args()?;
            let Some(args) = args else { continue };
            let found = args.len();
            match <[Argument; 3]>::try_from(args) {
                Ok([x, y, z]) if size.is_none() => size = Some([x.value, y.value, z.value]),
                Ok(_) => {
                    let d = Diagnostic::error("the axiom's size is given twice", modifier.span)
                        .with_label("a second `Size`");
                    self.report(d);
                }
                Err(_) => {
                    let d = Diagnostic::error(
                        format!("`Size` takes 3 values (x, y, z), found {found}"),
                        modifier.span.to(close),
                    );
                    self.report(d);
                }
            }
        }
        let span = self.span_from(start);
        if self.errors == errors {
            grammar.axioms.push(Axiom { goals, size, span });
        }
        self.mich_end("the axiom")
    }

    /// `var windows = new Synchronize();`.
    fn mich_sync(&mut self, grammar: &mut Grammar) -> PResult<()> {
        self.bump();
        if !self.is_name_at(self.pos) || self.text().contains('.') {
            return Err(self.error_expected("a variable name", "after `var`"));
        }
        let name = self.ident();
        let context = format!("after `var {}`", name.name);
        self.expect(&TokenKind::Eq, "`=`", &context)?;
        if !(self.at_word("new") && self.is_word_at(self.pos + 1, "Synchronize")) {
            let d = self
                .expected(
                    "`new Synchronize()`",
                    &format!("after `var {} =`", name.name),
                )
                .with_hint("`var` declares synchronizations: `var windows = new Synchronize();`");
            self.report(d);
            return Err(Fail);
        }
        self.bump();
        self.bump();
        self.expect(&TokenKind::LParen, "`(`", "after `Synchronize`")?;
        if self.eat(&TokenKind::RParen).is_none() {
            let d = self
                .expected("`)`", "after `new Synchronize(`")
                .with_hint("`Synchronize` takes no arguments");
            self.report(d);
            return Err(Fail);
        }
        if let Some(first) = grammar.syncs.iter().find(|s| s.name == name.name) {
            let line = line_of(self.src, first.span);
            let d = Diagnostic::error(
                format!("the synchronization `{}` is declared twice", name.name),
                name.span,
            )
            .with_label(format!("first declared on line {line}"));
            self.report(d);
        } else {
            grammar.syncs.push(name);
        }
        self.mich_end("the declaration")
    }

    /// `using (Predicates.IfIs("chair")…) { statements }`.
    fn mich_using(&mut self, grammar: &mut Grammar, inherited: &[Predicate]) -> PResult<()> {
        self.bump();
        let open = self.expect(&TokenKind::LParen, "`(`", "after `using`")?;
        let first = match self.peek() {
            TokenKind::Ident if self.text().starts_with("Predicates.") => {
                let word = self.ident();
                let mut segments = segments(&word);
                if let Some(extra) = segments.get(2) {
                    return Err(self.unexpected_segment(extra));
                }
                segments.pop()
            }
            TokenKind::Ident if self.at_word("Predicates") => {
                self.bump();
                None
            }
            _ => {
                let d = self
                    .expected("`Predicates.`", "in `using (…)`")
                    .with_hint("a `using` block gives its rules predicates: `using (Predicates.IfIs(\"chair\")) { … }`");
                self.report(d);
                return Err(Fail);
            }
        };
        let errors = self.errors;
        let head = self.modifier_chain(first, Chain::Using)?;
        self.close(
            &TokenKind::RParen,
            open,
            "`)`",
            "after the predicates of `using`",
        )?;
        if head.predicates.is_empty() && self.errors == errors {
            let d = Diagnostic::error("`using` without a predicate", open)
                .with_hint("write at least one, e.g. `using (Predicates.IfIs(\"chair\")) { … }`");
            self.report(d);
        }
        let mut predicates = inherited.to_vec();
        predicates.extend(head.predicates);
        let Some(brace) = self.eat(&TokenKind::LBrace) else {
            return Err(self.error_expected("`{`", "after `using (…)`"));
        };
        self.nested(|p| {
            p.mich_statements(grammar, &predicates, true);
            Ok(())
        })?;
        if self.eat(&TokenKind::RBrace).is_none() {
            let d = Diagnostic::error("unclosed `{`", brace)
                .with_label("this `using` block is never closed")
                .with_hint("close it with `}` after its last rule");
            self.report(d);
        }
        Ok(())
    }

    // --- Rules -------------------------------------------------------------------------------

    /// `Rules.Kind(arguments).Modifier(…)…;` (from `Rules.Kind`).
    fn mich_rule(
        &mut self,
        grammar: &mut Grammar,
        inherited: &[Predicate],
        start: Span,
    ) -> PResult<()> {
        let errors = self.errors;
        let head = self.ident();
        let kind = head
            .name
            .strip_prefix("Rules.")
            .and_then(|k| RULE_KINDS.iter().find(|&&r| r == k));
        let Some(&kind) = kind else {
            let written = head.name.strip_prefix("Rules.").unwrap_or("");
            let mut d = Diagnostic::error(format!("unknown rule `{}`", head.name), head.span);
            d = match suggest(written, RULE_KINDS) {
                Some(close) if !written.is_empty() => {
                    d.with_hint(format!("did you mean `Rules.{close}`?"))
                }
                _ => d.with_hint(format!("the rules are {}", listing(&RULE_KINDS, "Rules."))),
            };
            self.report(d);
            return Err(Fail);
        };
        if !self.at(&TokenKind::LParen) {
            return Err(self.error_expected("`(`", &format!("after `{}`", head.name)));
        }
        let open = self.span();
        let (args, close) = self.mich_call_args_of(&head)?;
        let mut body = Vec::new();
        let mut locals = Vec::new();
        if let Some(args) = args {
            let call = Call {
                kind,
                head: &head,
                span: head.span.to(close),
                args_span: open.to(close),
            };
            self.lower_rule(&call, args, &mut body, &mut locals);
        }
        let modifiers = self.modifier_chain(None, Chain::Rule)?;
        let span = self.span_from(start);
        if self.errors == errors {
            locals.extend(modifiers.locals);
            for goal in locals {
                if !grammar.local_goals.iter().any(|g| g.name == goal.name) {
                    grammar.local_goals.push(goal);
                }
            }
            let mut predicates = inherited.to_vec();
            predicates.extend(modifiers.predicates);
            grammar.goal_rules.push(GoalRule {
                annotations: Vec::new(),
                predicates,
                fulfills: modifiers.fulfills,
                adds: modifiers.adds,
                body: Body::Sequence(body),
                span,
            });
        }
        self.mich_end("the rule")
    }

    /// The arguments of a rule `( arg, … )`, each a part or a value, optionally with a trailing
    /// comma. `None` when an argument failed (reported, and skipped to the closing parenthesis).
    fn mich_call_args_of(&mut self, head: &Ident) -> PResult<(Option<Vec<Arg>>, Span)> {
        let open_at = self.pos;
        let open = self.bump();
        let mut args = Vec::new();
        if let Some(close) = self.eat(&TokenKind::RParen) {
            return Ok((Some(args), close));
        }
        let context = format!("in the arguments of `{}`", head.name);
        let result = loop {
            match self.mich_arg() {
                Ok(arg) => args.push(arg),
                Err(fail) => break Err(fail),
            }
            if self.eat(&TokenKind::Comma).is_none() {
                break self.close(&TokenKind::RParen, open, "`,` or `)`", &context);
            }
            // A trailing comma, as where the paper elides the parts: `Split(Axis.Y, /*…*/)`.
            if let Some(close) = self.eat(&TokenKind::RParen) {
                break Ok(close);
            }
        };
        match result {
            Ok(close) => Ok((Some(args), close)),
            Err(fail) => self.skip_to_close(open_at, fail).map(|close| (None, close)),
        }
    }

    /// After an error inside the parentheses opened at token `open`: skips to their `)` when it
    /// is before the next statement, else fails.
    fn skip_to_close(&mut self, open: usize, fail: Fail) -> PResult<Span> {
        match self.closing_paren(open) {
            Some(close) if !self.aborted && close >= self.pos => {
                while self.pos < close {
                    if self.at_resume_point() {
                        return Err(fail);
                    }
                    self.bump();
                }
                Ok(self.bump())
            }
            _ => Err(fail),
        }
    }

    /// Arguments `( value, … )` of a modifier, `Axiom` or `Vec3`; `None` when one failed
    /// (reported).
    fn mich_call_args(&mut self) -> PResult<(Option<Vec<Argument>>, Span)> {
        let errors = self.errors;
        let (mut args, close) = self.call_args()?;
        for a in &mut args {
            rename(&mut a.value, None);
        }
        Ok(((self.errors == errors).then_some(args), close))
    }

    /// One argument of a rule.
    fn mich_arg(&mut self) -> PResult<Arg> {
        if *self.peek() == TokenKind::Ident {
            let text = self.text();
            if matches!(text, "Relative" | "Absolute") && *self.peek_nth(1) == TokenKind::LParen {
                return self.size_part().map(Arg::Part);
            }
            if text == "Face" || text.starts_with("Face.") {
                return self.face_part().map(Arg::Part);
            }
            if text == "new" && self.is_word_at(self.pos + 1, "Vec3") {
                self.bump();
            }
        }
        self.mich_expr(None).map(Arg::Value)
    }

    /// An expression, with the notation's names mapped (see [`rename`]).
    fn mich_expr(&mut self, param: Option<&str>) -> PResult<Expr> {
        let mut e = self.expr()?;
        rename(&mut e, param);
        Ok(e)
    }

    /// `Relative(r)` or `Absolute(a)` and the part's modifiers.
    fn size_part(&mut self) -> PResult<Part> {
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
    fn face_part(&mut self) -> PResult<Part> {
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
    fn next_modifier(&mut self) -> PResult<Option<Ident>> {
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
    fn unexpected_segment(&mut self, segment: &Ident) -> Fail {
        let dot = Span::new(segment.span.start as usize - 1, segment.span.end as usize);
        let d = Diagnostic::error(format!("unexpected `.{}`", segment.name), dot)
            .with_label("expected `(` before it");
        self.report(d);
        Fail
    }

    /// Reports an unknown modifier of `what` (with the closest of `known`) and skips its
    /// arguments.
    fn unknown_modifier<'k>(
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
    fn modifier_chain(&mut self, first: Option<Ident>, chain: Chain) -> PResult<Modifiers> {
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
    fn goal_values(
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

    // --- Lowering ------------------------------------------------------------------------------

    fn lower_rule(
        &mut self,
        call: &Call<'_>,
        args: Vec<Arg>,
        out: &mut Vec<Stmt>,
        locals: &mut Vec<Goal>,
    ) {
        let (min, max, signature) = arity(call.kind);
        let n = args.len();
        if n < min || max.is_some_and(|max| n > max) {
            let count = |k: usize| match k {
                0 => "no arguments".to_owned(),
                1 => "1 argument".to_owned(),
                k => format!("{k} arguments"),
            };
            let expected = match max {
                Some(max) if max == min => count(max),
                _ => format!("at least {}", count(min)),
            };
            let d = Diagnostic::error(
                format!("`{}` takes {expected}, found {n}", call.head.name),
                call.span,
            )
            .with_hint(format!("write `{signature}`"));
            self.report(d);
            return;
        }
        let span = call.span;
        let name_span = call.head.span;
        match call.kind {
            "Split" | "Repeat" | "Comp" => {
                let mut args = args.into_iter();
                let axis = if call.kind == "Comp" {
                    Some(b::name("f", name_span))
                } else {
                    let Some(axis) = args.next() else { return };
                    self.axis(axis, call)
                };
                let Some(entries) = self.part_entries(args.collect(), call, locals) else {
                    return;
                };
                let Some(axis) = axis else { return };
                let block = match call.kind {
                    "Repeat" => {
                        let group = b::block(entries, true, call.args_span);
                        b::block(vec![BlockEntry::Group(group)], false, call.args_span)
                    }
                    _ => b::block(entries, false, call.args_span),
                };
                let name = if call.kind == "Comp" { "comp" } else { "split" };
                out.push(b::call(
                    b::ident(name, name_span),
                    Some(vec![axis]),
                    Some(block),
                    false,
                    span,
                ));
            }
            "Size" => {
                let Ok([axis, value]) = <[Arg; 2]>::try_from(args) else {
                    return;
                };
                let axis = self.axis(axis, call);
                let value = self.value(value, call, "a size");
                let (Some(axis), Some(value)) = (axis, value) else {
                    return;
                };
                let mut sizes: Vec<Expr> = (0..3)
                    .map(|_| b::relative(b::number(1.0, name_span)))
                    .collect();
                sizes[axis_index(&axis)] = value;
                out.push(operation("s", sizes, call));
            }
            "Scale" => {
                let Ok([factors, pivot]) = <[Arg; 2]>::try_from(args) else {
                    return;
                };
                let factors = self.vec3(factors, call);
                let pivot = self.pivot(pivot, call);
                let (Some(factors), Some((axes, pivot_span))) = (factors, pivot) else {
                    return;
                };
                let factors = factors.into_iter().map(b::relative).collect();
                out.push(operation("s", factors, call));
                if let Some(axes) = axes {
                    out.push(b::op("center", vec![b::name(axes, pivot_span)], pivot_span));
                }
            }
            "Translate" | "Rotate" => {
                let Ok([v]) = <[Arg; 1]>::try_from(args) else {
                    return;
                };
                let Some(mut v) = self.vec3(v, call) else {
                    return;
                };
                if call.kind == "Translate" {
                    out.push(operation("t", v, call));
                } else {
                    v.insert(0, b::name("scopeCenter", name_span));
                    out.push(operation("r", v, call));
                }
            }
            "Color" | "Material" | "Insert" => {
                let Ok([v]) = <[Arg; 1]>::try_from(args) else {
                    return;
                };
                let what = match call.kind {
                    "Color" => "a colour",
                    "Material" => "a material's name",
                    _ => "a file name",
                };
                let Some(v) = self.value(v, call, what) else {
                    return;
                };
                out.push(match call.kind {
                    "Color" => operation("color", vec![v], call),
                    "Material" => {
                        let target = b::name("material.name", name_span);
                        operation("set", vec![target, v], call)
                    }
                    _ => operation("i", vec![v], call),
                });
            }
            "Taper" | "Twist" | "Shear" => {
                let axes = if call.kind == "Shear" { 2 } else { 1 };
                let mut values = Vec::new();
                for (i, arg) in args.into_iter().enumerate() {
                    values.push(if i < axes {
                        self.axis(arg, call)
                    } else if call.kind == "Twist" {
                        self.value(arg, call, "an angle")
                    } else {
                        self.value(arg, call, "an amount")
                    });
                }
                let Some(values) = values.into_iter().collect::<Option<Vec<_>>>() else {
                    return;
                };
                let name = call.kind.to_ascii_lowercase();
                out.push(operation(&name, values, call));
            }
            // `Identity`: no operation.
            _ => {}
        }
    }

    /// The block entries of the parts of `Split`, `Repeat` (sizes) or `Comp` (faces); `None`
    /// when one is of the wrong kind (reported).
    fn part_entries(
        &mut self,
        parts: Vec<Arg>,
        call: &Call<'_>,
        locals: &mut Vec<Goal>,
    ) -> Option<Vec<BlockEntry>> {
        let comp = call.kind == "Comp";
        let mut entries = Vec::new();
        let mut ok = true;
        for arg in parts {
            let part = match arg {
                Arg::Part(part) => part,
                Arg::Value(e) => {
                    let d = if comp {
                        Diagnostic::error("expected a face such as `Face.Top`", e.span)
                            .with_label(format!("in `{}`", call.head.name))
                            .with_hint(
                                "parts of `Rules.Comp` are written `Face.Top.Goal(\"seat\")`",
                            )
                    } else {
                        Diagnostic::error("expected a part `Relative(…)` or `Absolute(…)`", e.span)
                            .with_label(format!("in `{}`", call.head.name))
                            .with_hint(
                                "parts are written `Relative(0.4).Goal(\"support\")` or \
                                 `Absolute(0.04).Void()`",
                            )
                    };
                    self.report(d);
                    ok = false;
                    continue;
                }
            };
            let key = match (part.key, comp) {
                (PartKey::Face(selector, span), true) => b::name(selector, span),
                (PartKey::Relative(size, span), false) => {
                    b::expr(ExprKind::Floating(Box::new(size)), span)
                }
                (PartKey::Absolute(size), false) if call.kind == "Repeat" => {
                    let span = size.span;
                    b::expr(ExprKind::Floating(Box::new(size)), span)
                }
                (PartKey::Absolute(size), false) => size,
                (_, true) => {
                    let d = Diagnostic::error("expected a face such as `Face.Top`", part.span)
                        .with_label(format!("in `{}`", call.head.name))
                        .with_hint("`Relative(…)` and `Absolute(…)` are parts of splits");
                    self.report(d);
                    ok = false;
                    continue;
                }
                (PartKey::Face(..), false) => {
                    let d = Diagnostic::error(
                        "expected a part `Relative(…)` or `Absolute(…)`",
                        part.span,
                    )
                    .with_label(format!("in `{}`", call.head.name))
                    .with_hint("faces are parts of `Rules.Comp`");
                    self.report(d);
                    ok = false;
                    continue;
                }
            };
            locals.extend(part.locals);
            entries.push(b::part(key, part.body, part.span));
        }
        ok.then_some(entries)
    }

    /// `Axis.X`, `Axis.Y` or `Axis.Z` as the name `x`, `y` or `z`.
    fn axis(&mut self, arg: Arg, call: &Call<'_>) -> Option<Expr> {
        let span = arg.span();
        let word = match &arg {
            Arg::Value(Expr {
                kind: ExprKind::Name(n),
                ..
            }) => Some(n.as_str()),
            _ => None,
        };
        let axis = match word {
            Some("Axis.X") => "x",
            Some("Axis.Y") => "y",
            Some("Axis.Z") => "z",
            _ => {
                let mut d = Diagnostic::error("expected `Axis.X`, `Axis.Y` or `Axis.Z`", span)
                    .with_label(format!("in `{}`", call.head.name));
                let letter = word.and_then(|w| w.strip_prefix("Axis."));
                if let Some(close) = letter.and_then(|l| suggest(l, ["X", "Y", "Z"])) {
                    d = d.with_hint(format!("did you mean `Axis.{close}`?"));
                }
                self.report(d);
                return None;
            }
        };
        Some(b::name(axis, span))
    }

    /// `Vec3(x, y, z)` as its three values.
    fn vec3(&mut self, arg: Arg, call: &Call<'_>) -> Option<Vec<Expr>> {
        let span = arg.span();
        if let Arg::Value(Expr {
            kind: ExprKind::Call { name, args },
            ..
        }) = arg
            && name.name == "Vec3"
        {
            if args.len() == 3 && args.iter().all(|a| a.name.is_none()) {
                return Some(args.into_iter().map(|a| a.value).collect());
            }
            let d = Diagnostic::error(
                format!("`Vec3` takes 3 values (x, y, z), found {}", args.len()),
                span,
            );
            self.report(d);
            return None;
        }
        let d = Diagnostic::error("expected `Vec3(x, y, z)`", span)
            .with_label(format!("in `{}`", call.head.name));
        self.report(d);
        None
    }

    /// `Pivot.Middle` and the others: the axes to centre on (none for `Min` and `Origin`) and
    /// the pivot's span.
    fn pivot(&mut self, arg: Arg, call: &Call<'_>) -> Option<(Option<&'static str>, Span)> {
        let span = arg.span();
        let written = match &arg {
            Arg::Value(Expr {
                kind: ExprKind::Name(n),
                ..
            }) => n.strip_prefix("Pivot."),
            _ => None,
        };
        let found = written.and_then(|w| PIVOTS.iter().find(|(p, _)| *p == w));
        if let Some(&(_, axes)) = found {
            return Some((axes, span));
        }
        let message = match written {
            Some(w) => format!("unknown pivot `Pivot.{w}`"),
            None => "expected a pivot such as `Pivot.Middle`".to_owned(),
        };
        let mut d = Diagnostic::error(message, span).with_label(format!("in `{}`", call.head.name));
        if let Some(close) = written.and_then(|w| suggest(w, PIVOTS.iter().map(|p| p.0))) {
            d = d.with_hint(format!("did you mean `Pivot.{close}`?"));
        }
        d = d.with_hint(format!(
            "the pivots are {}",
            listing(&PIVOTS.map(|p| p.0), "Pivot.")
        ));
        self.report(d);
        None
    }

    /// A value argument (not a part).
    fn value(&mut self, arg: Arg, call: &Call<'_>, what: &str) -> Option<Expr> {
        match arg {
            Arg::Value(e) => Some(e),
            Arg::Part(part) => {
                let d = Diagnostic::error(format!("expected {what}, found a part"), part.span)
                    .with_label(format!("in `{}`", call.head.name));
                self.report(d);
                None
            }
        }
    }
}

/// A rule call being lowered.
struct Call<'a> {
    /// The kind, as in [`RULE_KINDS`].
    kind: &'static str,
    /// `Rules.Kind` as written.
    head: &'a Ident,
    /// From `Rules.Kind` to the closing parenthesis.
    span: Span,
    /// From `(` to `)`.
    args_span: Span,
}

/// How many arguments a rule kind takes (at least, at most) and how it is written.
fn arity(kind: &str) -> (usize, Option<usize>, &'static str) {
    match kind {
        "Split" => (
            1,
            None,
            "Rules.Split(Axis.Y, Relative(0.5), Absolute(0.1), …)",
        ),
        "Repeat" => (2, None, "Rules.Repeat(Axis.X, Absolute(1.5), …)"),
        "Size" => (2, Some(2), "Rules.Size(Axis.Z, 0.04)"),
        "Scale" => (2, Some(2), "Rules.Scale(Vec3(0.5, 1, 0.5), Pivot.Middle)"),
        "Translate" => (1, Some(1), "Rules.Translate(Vec3(x, y, z))"),
        "Rotate" => (1, Some(1), "Rules.Rotate(Vec3(x, y, z))"),
        "Color" => (1, Some(1), "Rules.Color(\"#8b5a2b\")"),
        "Material" => (1, Some(1), "Rules.Material(\"oak\")"),
        "Insert" => (1, Some(1), "Rules.Insert(\"file.obj\")"),
        "Comp" => (
            1,
            None,
            "Rules.Comp(Face.Top.Goal(\"seat\"), Face.Side.Void(), …)",
        ),
        "Taper" => (2, Some(2), "Rules.Taper(Axis.Y, 0.5)"),
        "Twist" => (2, Some(2), "Rules.Twist(Axis.Y, 45)"),
        "Shear" => (3, Some(3), "Rules.Shear(Axis.Y, Axis.X, 0.2)"),
        _ => (0, Some(0), "Rules.Identity()"),
    }
}

/// 0, 1 or 2 for the axis names `x`, `y`, `z` (built by [`Parser::axis`]).
fn axis_index(axis: &Expr) -> usize {
    match &axis.kind {
        ExprKind::Name(n) if n == "y" => 1,
        ExprKind::Name(n) if n == "z" => 2,
        _ => 0,
    }
}

/// The operation `name(args)` a rule lowers to: its name takes the span of `Rules.Kind`, the
/// whole call the span of the rule's call.
fn operation(name: &str, args: Vec<Expr>, call: &Call<'_>) -> Stmt {
    b::call(
        b::ident(name, call.head.span),
        Some(args),
        None,
        false,
        call.span,
    )
}

/// The parts of a dotted name, each with its span.
fn segments(ident: &Ident) -> Vec<Ident> {
    let mut at = ident.span.start as usize;
    ident
        .name
        .split('.')
        .map(|part| {
            let segment = b::ident(part, Span::new(at, at + part.len()));
            at += part.len() + 1;
            segment
        })
        .collect()
}

/// The 1-based line of a span's start.
fn line_of(src: &str, span: Span) -> usize {
    src.as_bytes()[..(span.start as usize).min(src.len())]
        .iter()
        .filter(|&&c| c == b'\n')
        .count()
        + 1
}

/// "`A`, `B` and `C`" with each name prefixed.
fn listing(names: &[&str], prefix: &str) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("`{prefix}{n}`")).collect();
    match quoted.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => last.clone(),
        None => String::new(),
    }
}

fn listing_faces() -> String {
    listing(&FACES.map(|f| f.0), "Face.")
}

/// Whether `name` is a predicate modifier: whether it is negated and what it asks (`Goal`,
/// `Is`, `Tag`, `Has`, or `""` for `If`/`IfNot`).
fn predicate_word(name: &str) -> Option<(bool, &str)> {
    let (negated, rest) = match name.strip_prefix("IfNot") {
        Some(rest) => (true, rest),
        None => (false, name.strip_prefix("If")?),
    };
    matches!(rest, "" | "Goal" | "Is" | "Tag" | "Has").then_some((negated, rest))
}

/// Maps the notation's names to the main syntax's, everywhere in `e`: `Rnd(a, b)` is
/// `rand(a, b)`; `Size.X` is `scope.sx` and `Position.X` is `scope.tx` (likewise for Y and Z),
/// also written after the lambda's parameter `param` (`s.Size.X`), or after any name when there
/// is no lambda.
fn rename(e: &mut Expr, param: Option<&str>) {
    match &mut e.kind {
        ExprKind::Name(n) => {
            if let Some(query) = scope_query(n, param) {
                *n = query;
            }
        }
        ExprKind::Call { name, args } => {
            if name.name == "Rnd" {
                name.name = "rand".to_owned();
            }
            for a in args {
                rename(&mut a.value, param);
            }
        }
        ExprKind::Array(items) => items.iter_mut().for_each(|i| rename(i, param)),
        ExprKind::Index {
            target,
            index,
            column,
        } => {
            rename(target, param);
            rename(index, param);
            if let Some(column) = column {
                rename(column, param);
            }
        }
        ExprKind::Range { start, step, end } => {
            rename(start, param);
            if let Some(step) = step {
                rename(step, param);
            }
            rename(end, param);
        }
        ExprKind::Unary { operand, .. } => rename(operand, param),
        ExprKind::Binary { lhs, rhs, .. } => {
            rename(lhs, param);
            rename(rhs, param);
        }
        ExprKind::Conditional {
            cond,
            then,
            otherwise,
        } => {
            rename(cond, param);
            rename(then, param);
            rename(otherwise, param);
        }
        ExprKind::Cases { arms, otherwise } | ExprKind::Stochastic { arms, otherwise } => {
            for (a, v) in arms {
                rename(a, param);
                rename(v, param);
            }
            rename(otherwise, param);
        }
        ExprKind::Floating(inner) | ExprKind::Relative(inner) => rename(inner, param),
        ExprKind::Number(_)
        | ExprKind::String(_)
        | ExprKind::Bool(_)
        | ExprKind::GoalAttribute { .. } => {}
    }
}

/// `scope.sx` for `Size.X`, `s.Size.X` (see [`rename`]), and so on.
fn scope_query(name: &str, param: Option<&str>) -> Option<String> {
    let parts: Vec<&str> = name.split('.').collect();
    let rest = match (parts.as_slice(), param) {
        ([_, _], _) => &parts[..],
        ([first, _, _], Some(p)) if first == &p => &parts[1..],
        ([_, _, _], None) => &parts[1..],
        _ => return None,
    };
    let prefix = match rest[0] {
        "Size" => "s",
        "Position" => "t",
        _ => return None,
    };
    let axis = match rest[1] {
        "X" => "x",
        "Y" => "y",
        "Z" => "z",
        _ => return None,
    };
    Some(format!("scope.{prefix}{axis}"))
}
