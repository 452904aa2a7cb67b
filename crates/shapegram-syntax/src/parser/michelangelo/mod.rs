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

mod lowering;
mod modifiers;

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
