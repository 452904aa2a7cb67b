//! Compiling goal grammars into one [`Program`]: a library of grammar files whose rules find
//! each other by goals.
//!
//! Each file keeps its identity: its local goals, its synchronizations and the grammar index
//! that makes its rules preferred for the shapes it made. Beyond what each rule's own
//! compilation reports, the library as a whole is checked: a goal asked for but never given (or
//! given but never asked for, when a similar name is asked for) is likely misspelt; an attribute
//! read but never set can never be read; a rule that gives back the goal it fulfils, without a
//! condition, would rewrite its own shapes forever.

use rustc_hash::{FxHashMap, FxHashSet};
use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, Block, BlockEntry, Body, Grammar, PredicateKind, Stmt},
    suggest,
};

use crate::goals::{self, AttrId, GoalId, GoalName, GoalRules, GrammarId};
use crate::program::{CRule, Compiler, Program};

/// The largest weight a rule may have: weights add up, and must stay finite.
const MAX_WEIGHT: f64 = 1e6;

/// Where the compiler is inside a library: the grammar being compiled and the names of all.
#[derive(Debug, Default)]
pub(crate) struct GoalScope {
    /// The grammar being compiled.
    pub grammar: GrammarId,
    /// Its local goal names.
    locals: FxHashSet<String>,
    /// Its synchronizations, by name.
    syncs: FxHashMap<String, u32>,
    goal_ids: FxHashMap<GoalName, GoalId>,
    attr_ids: FxHashMap<String, AttrId>,
    /// Attributes read by the rule being compiled (each adds an implicit `has`).
    pub reads: Vec<AttrId>,
    /// Attributes read anywhere (getters and `has`), with where, for the library's checks.
    read_at: Vec<(AttrId, GrammarId, Span)>,
    /// Attributes set anywhere.
    set: FxHashSet<AttrId>,
    /// Attributes set by the rule being compiled (its own reads of them ask for nothing).
    rule_writes: Vec<AttrId>,
    /// Goals given to shapes (axioms, `+goal`, `adds`), with where.
    given: Vec<(GoalId, GrammarId, Span)>,
    /// Goals asked for (`fulfills`, `goal(…)`), with where.
    asked: Vec<(GoalId, GrammarId, Span)>,
    /// Everything the rules of the library will need.
    pub rules: GoalRules,
}

impl GoalScope {
    /// The id of a goal as written in the current grammar.
    pub fn goal(&mut self, name: &str) -> GoalId {
        let key = GoalName {
            name: name.into(),
            local: self.locals.contains(name).then_some(self.grammar),
        };
        let next = self.rules.goals.len() as GoalId;
        *self.goal_ids.entry(key.clone()).or_insert_with(|| {
            self.rules.goals.push(key);
            next
        })
    }

    /// The id of a named attribute.
    pub fn attr(&mut self, name: &str) -> AttrId {
        let next = self.rules.attributes.len() as AttrId;
        *self.attr_ids.entry(name.to_owned()).or_insert_with(|| {
            self.rules.attributes.push(name.into());
            next
        })
    }

    /// Records a read of an attribute by a getter at `span`.
    pub fn read(&mut self, attr: AttrId, span: Span) {
        if !self.reads.contains(&attr) {
            self.reads.push(attr);
        }
        self.read_at.push((attr, self.grammar, span));
    }

    /// Records a `set(@name, …)`.
    pub fn write(&mut self, attr: AttrId) {
        self.set.insert(attr);
        self.rule_writes.push(attr);
    }

    /// Records goals given to shapes at `span`.
    pub fn give(&mut self, goals: &[GoalId], span: Span) {
        let grammar = self.grammar;
        self.given.extend(goals.iter().map(|&g| (g, grammar, span)));
    }

    /// The synchronization of this name in the current grammar.
    pub fn sync(&self, name: &str) -> Option<u32> {
        self.syncs.get(name).copied()
    }

    /// The current grammar's synchronization names, for hints.
    pub fn sync_names(&self) -> impl Iterator<Item = &str> {
        self.syncs.keys().map(String::as_str)
    }
}

/// How [`Program::compile_library_with`] treats a library.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LibraryOptions {
    /// The grammars from this index on came from a repository: their rules are tried after
    /// all of the others (see `docs/repository.md`).
    pub repository_from: usize,
    /// Whether grammars outside the library may join it (a grammar published to a repository,
    /// a derivation that asks one): an attribute no grammar of it sets is then no error, since
    /// another grammar may set it (a near miss of one it sets is a warning).
    pub open: bool,
}

impl LibraryOptions {
    /// A library of `n` grammars of the user's, to which nothing is added.
    pub fn closed(n: usize) -> Self {
        Self {
            repository_from: n,
            open: false,
        }
    }
}

impl Program {
    /// Compiles goal grammars into one program: the first is the main grammar, whose axioms
    /// a derivation starts from; the rules of all find each other by goals. Returns `None`
    /// when there are errors; diagnostics come back with the index of their grammar.
    pub fn compile_library(
        grammars: &[(&str, &Grammar)],
    ) -> (Option<Program>, Vec<(usize, Diagnostic)>) {
        Self::compile_library_with(grammars, &LibraryOptions::closed(grammars.len()))
    }

    /// Compiles a library as [`Program::compile_library`] does, with the grammars' origin and
    /// openness as `options` say.
    pub fn compile_library_with(
        grammars: &[(&str, &Grammar)],
        options: &LibraryOptions,
    ) -> (Option<Program>, Vec<(usize, Diagnostic)>) {
        let empty = Grammar::default();
        let mut compiler = Compiler::new_for_goals(&empty);
        let mut diagnostics = Vec::new();
        let mut crules = Vec::new();
        for (k, (name, grammar)) in grammars.iter().enumerate() {
            let scope = compiler.goal.as_mut().expect("a goal compiler");
            scope.grammar = k as GrammarId;
            scope.rules.grammars.push((*name).to_owned());
            scope.locals = grammar.local_goals.iter().map(|g| g.name.clone()).collect();
            scope.syncs.clear();
            let mut twice = Vec::new();
            for sync in &grammar.syncs {
                let id = scope.rules.syncs.len() as u32;
                if scope.syncs.insert(sync.name.clone(), id).is_some() {
                    twice.push(Diagnostic::error(
                        format!("synchronization `{}` is declared twice", sync.name),
                        sync.span,
                    ));
                }
                scope.rules.syncs.push(sync.name.as_str().into());
            }
            for d in twice {
                compiler.report(d);
            }
            refuse_symbol_grammar(&mut compiler, grammar);
            // A library grammar's axioms are for deriving it on its own.
            if k == 0 {
                for axiom in &grammar.axioms {
                    compile_axiom(&mut compiler, axiom);
                }
            }
            for rule in &grammar.goal_rules {
                crules.push(compile_rule(&mut compiler, rule));
            }
            diagnostics.extend(compiler.diagnostics.drain(..).map(|d| (k, d)));
        }
        let mut scope = *compiler.goal.take().expect("a goal compiler");
        diagnostics.extend(check_library(&scope, options.open));
        scope.rules.goal_symbols = scope
            .rules
            .goals
            .iter()
            .map(|g| compiler.intern(&g.name))
            .collect();
        scope.rules.repository_from = (options.repository_from < grammars.len())
            .then(|| options.repository_from.max(1) as GrammarId);
        scope.rules.index();
        let failed = diagnostics.iter().any(|(_, d)| d.is_error());
        let program = compiler.finish_goals(crules, scope.rules);
        ((!failed).then_some(program), diagnostics)
    }
}

/// Goal grammars hold goal rules only: attributes, constants, functions and symbol rules of
/// the main syntax are reported.
fn refuse_symbol_grammar(compiler: &mut Compiler, grammar: &Grammar) {
    let spans = grammar
        .attrs
        .iter()
        .map(|a| ("attributes", a.span))
        .chain(grammar.consts.iter().map(|c| ("constants", c.span)))
        .chain(grammar.functions.iter().map(|f| ("functions", f.span)))
        .chain(grammar.rules.iter().map(|r| ("symbol rules", r.span)));
    for (what, span) in spans {
        compiler.report(
            Diagnostic::error(format!("goal grammars have no {what}"), span).with_hint(
                "give shapes named attributes with `set(@name, value)` and read them with `@name`",
            ),
        );
    }
}

fn compile_axiom(compiler: &mut Compiler, axiom: &ast::Axiom) {
    let scope = compiler.goal.as_mut().expect("a goal compiler");
    let goals: Vec<GoalId> = axiom.goals.iter().map(|g| scope.goal(&g.name)).collect();
    for (&goal, written) in goals.iter().zip(&axiom.goals) {
        scope.give(&[goal], written.span);
    }
    let grammar = scope.grammar;
    let size = axiom
        .size
        .as_ref()
        .map(|xyz| xyz.each_ref().map(|e| compiler.expr(e, &[])));
    let symbol = compiler.intern(&axiom.goals[0].name);
    let scope = compiler.goal.as_mut().expect("a goal compiler");
    let mut sorted = goals;
    sorted.sort_unstable();
    sorted.dedup();
    scope.rules.axioms.push(goals::Axiom {
        goals: sorted,
        size,
        symbol,
        grammar,
    });
}

fn compile_rule(compiler: &mut Compiler, rule: &ast::GoalRule) -> CRule {
    let scope = compiler.goal.as_mut().expect("a goal compiler");
    scope.reads.clear();
    scope.rule_writes.clear();
    let grammar = scope.grammar;
    let mut compiled = goals::GoalRule {
        grammar,
        weight: 1.0,
        span: rule.span,
        ..goals::GoalRule::default()
    };
    let ids = |scope: &mut GoalScope, list: &[ast::Goal]| -> Vec<GoalId> {
        let mut ids: Vec<GoalId> = list.iter().map(|g| scope.goal(&g.name)).collect();
        ids.sort_unstable();
        ids.dedup();
        ids
    };
    compiled.fulfills = ids(scope, &rule.fulfills);
    compiled.adds = ids(scope, &rule.adds);
    scope.give(&compiled.adds, rule.span);
    for g in &rule.fulfills {
        let id = scope.goal(&g.name);
        scope.asked.push((id, grammar, g.span));
    }
    let mut needed = compiled.fulfills.clone();
    for p in &rule.predicates {
        match (&p.kind, p.negated) {
            (PredicateKind::Goal(list), false) => {
                for g in list {
                    let id = scope.goal(&g.name);
                    scope.asked.push((id, grammar, g.span));
                }
                needed.extend(ids(scope, list));
            }
            (PredicateKind::Goal(list), true) => compiled.not_goals.push(ids(scope, list)),
            (PredicateKind::Is(list), false) => compiled.tags.extend(ids(scope, list)),
            (PredicateKind::Is(list), true) => compiled.not_tags.push(ids(scope, list)),
            (PredicateKind::Has(list), negated) => {
                let mut attrs: Vec<AttrId> = list.iter().map(|a| scope.attr(&a.name)).collect();
                if !negated {
                    for (a, i) in attrs.iter().zip(list) {
                        scope.read_at.push((*a, grammar, i.span));
                    }
                }
                attrs.sort_unstable();
                attrs.dedup();
                if negated {
                    compiled.not_attrs.push(attrs);
                } else {
                    compiled.attrs.extend(attrs);
                }
            }
            (PredicateKind::If(_), _) => {}
        }
    }
    for p in &rule.predicates {
        if let PredicateKind::If(e) = &p.kind {
            let condition = compiler.expr(e, &[]);
            compiled.conditions.push((condition, !p.negated));
        }
    }
    // What the conditions read is read before the body runs: always asked for.
    let scope = compiler.goal.as_mut().expect("a goal compiler");
    compiled.attrs.append(&mut scope.reads);
    for a in &rule.annotations {
        match a.name.name.as_str() {
            "Weight" => match a.args.as_slice() {
                [ast::Argument { name: None, value }] => match value.kind {
                    ast::ExprKind::Number(w) if w > 0.0 && w <= MAX_WEIGHT => compiled.weight = w,
                    _ => compiler.report(
                        Diagnostic::error(
                            "a rule's weight is a number above 0 and at most a million",
                            value.span,
                        )
                        .with_hint("write `@Weight(2)` to make a rule twice as likely"),
                    ),
                },
                _ => compiler.report(Diagnostic::error(
                    "`@Weight` takes one number, such as `@Weight(2)`",
                    a.span,
                )),
            },
            other => compiler.report(
                Diagnostic::warning(
                    format!("unknown annotation `@{other}` on a goal rule"),
                    a.span,
                )
                .with_hint("goal rules know `@Weight(w)`"),
            ),
        }
    }
    let body = compiler.body(&rule.body, &[]);
    check_sync_conflicts(compiler, &rule.body);
    let scope = compiler.goal.as_mut().expect("a goal compiler");
    // Attribute getters of the body ask for their attributes, unless the rule sets them itself.
    let writes = std::mem::take(&mut scope.rule_writes);
    compiled
        .attrs
        .extend(scope.reads.drain(..).filter(|a| !writes.contains(a)));
    compiled.attrs.sort_unstable();
    compiled.attrs.dedup();
    needed.sort_unstable();
    needed.dedup();
    compiled.goals = needed;
    compiled.tags.sort_unstable();
    compiled.tags.dedup();
    let reopened: Vec<&ast::Goal> = body_goals(&rule.body)
        .into_iter()
        .chain(&rule.adds)
        .filter(|g| rule.fulfills.iter().any(|f| f.name == g.name))
        .collect();
    let unconditional = compiled.conditions.is_empty()
        && compiled.not_goals.is_empty()
        && compiled.not_tags.is_empty()
        && compiled.not_attrs.is_empty();
    if rule.fulfills.is_empty() && unconditional {
        compiler.report(
            Diagnostic::warning(
                "this rule fulfils no goal and has no condition: the shapes it makes match it again, and it may apply over and over",
                rule.span,
            )
            .with_hint("let it fulfil a goal (`fulfills(…)`), or add a condition or a negated predicate (`!is(done)`)"),
        );
    }
    if let (Some(goal), true) = (reopened.first(), unconditional) {
        compiler.report(
            Diagnostic::error(
                format!(
                    "this rule fulfils `{}` and gives it back to the shapes it makes: it would rewrite them forever",
                    goal.name
                ),
                goal.span,
            )
            .with_hint("give the parts another goal, or add a condition that ends the recursion, such as `if(scope.sx > 1)`"),
        );
    }
    let scope = compiler.goal.as_mut().expect("a goal compiler");
    let name = match rule.fulfills.first() {
        Some(g) => format!("{}:{}", scope.rules.grammars[grammar as usize], g.name),
        None => format!("{}:rule", scope.rules.grammars[grammar as usize]),
    };
    scope.rules.rules.push(compiled);
    CRule {
        symbol: compiler.intern(&name),
        params: 0,
        body,
    }
}

/// Reports statement lists that follow two synchronizations.
fn check_sync_conflicts(compiler: &mut Compiler, body: &Body) {
    let mut lists = Vec::new();
    collect_lists(body, &mut lists);
    for stmts in lists {
        let syncs: Vec<&ast::Call> = stmts
            .iter()
            .filter_map(|s| match s {
                Stmt::Call(c) if c.name.name == "sync" => Some(c),
                _ => None,
            })
            .collect();
        if let [_, second, ..] = syncs.as_slice() {
            compiler.report(
                Diagnostic::error(
                    "conflicting synchronization: a shape follows one synchronization",
                    second.span,
                )
                .with_label("a second synchronization of the same shape")
                .with_hint(
                    "synchronize the shape once; its parts may join another synchronization",
                ),
            );
        }
    }
}

/// Every statement list of a body: its sequences and the parts of its blocks.
fn collect_lists<'a>(body: &'a Body, out: &mut Vec<&'a [Stmt]>) {
    match body {
        Body::Sequence(stmts) => collect_stmts(stmts, out),
        Body::Cases {
            arms, otherwise, ..
        }
        | Body::Stochastic {
            arms, otherwise, ..
        } => {
            for (_, b) in arms {
                collect_lists(b, out);
            }
            collect_lists(otherwise, out);
        }
    }
}

fn collect_stmts<'a>(stmts: &'a [Stmt], out: &mut Vec<&'a [Stmt]>) {
    out.push(stmts);
    for s in stmts {
        match s {
            Stmt::Call(ast::Call {
                block: Some(block), ..
            }) => collect_block(block, out),
            Stmt::Branch(body) => collect_lists(body, out),
            _ => {}
        }
    }
}

fn collect_block<'a>(block: &'a Block, out: &mut Vec<&'a [Stmt]>) {
    for entry in &block.entries {
        match entry {
            BlockEntry::Part { body, .. } => collect_stmts(body, out),
            BlockEntry::Group(group) => collect_block(group, out),
        }
    }
}

/// The goals a body gives with `+goal`.
fn body_goals(body: &Body) -> Vec<&ast::Goal> {
    let mut lists = Vec::new();
    collect_lists(body, &mut lists);
    lists
        .into_iter()
        .flatten()
        .filter_map(|s| match s {
            Stmt::Goals(goals, _) => Some(goals),
            _ => None,
        })
        .flatten()
        .collect()
}

/// The library's checks (see the module docs), as diagnostics with their grammar.
fn check_library(scope: &GoalScope, open: bool) -> Vec<(usize, Diagnostic)> {
    let mut out = Vec::new();
    let name = |scope: &GoalScope, g: GoalId| scope.rules.goals[g as usize].name.to_string();
    let given: FxHashSet<GoalId> = scope.given.iter().map(|(g, _, _)| *g).collect();
    let asked: FxHashSet<GoalId> = scope.asked.iter().map(|(g, _, _)| *g).collect();
    // Sorted, so that ties between suggestions go the same way on every run.
    let names_of = |ids: &FxHashSet<GoalId>| {
        let mut names: Vec<String> = ids.iter().map(|&g| name(scope, g)).collect();
        names.sort_unstable();
        names.dedup();
        names
    };
    let given_names = names_of(&given);
    let asked_names = names_of(&asked);
    // Another goal of the same name is no suggestion.
    let others = |names: &'_ [String], goal: &str| -> Vec<String> {
        names.iter().filter(|n| *n != goal).cloned().collect()
    };
    let mut reported = FxHashSet::default();
    // A local goal and a global goal of the same name are two goals: say so rather than
    // suggest the name itself. (Two grammars' local goals of one name never meet.)
    let twin = |scope: &GoalScope, goal: GoalId| {
        let this = &scope.rules.goals[goal as usize];
        scope
            .rules
            .goals
            .iter()
            .find(|g| g.name == this.name && (g.local.is_none() != this.local.is_none()))
            .cloned()
    };
    let grammar_name = |k: GrammarId| scope.rules.grammars[k as usize].as_str();
    for &(goal, grammar, span) in &scope.asked {
        if given.contains(&goal) || !reported.insert(goal) {
            continue;
        }
        let goal_name = name(scope, goal);
        let local = scope.rules.goals[goal as usize].local;
        let mut d = match local {
            Some(owner) => Diagnostic::warning(
                format!(
                    "no shape is given the goal `{goal_name}` local to `{}`",
                    grammar_name(owner)
                ),
                span,
            ),
            None => Diagnostic::warning(
                format!("no grammar of the library gives any shape the goal `{goal_name}`"),
                span,
            ),
        };
        let given_twin =
            twin(scope, goal).filter(|t| scope.goal_ids.get(t).is_some_and(|g| given.contains(g)));
        match (given_twin, local) {
            (Some(twin), None) => {
                let owner = twin.local.map_or("", grammar_name);
                d = d.with_hint(format!(
                    "the `{goal_name}` of `{owner}` is local to it: this rule does not fulfil it"
                ));
            }
            (Some(_), Some(_)) => {
                d = d.with_hint(format!(
                    "the `{goal_name}` that other grammars give is another goal: local goals are fulfilled by their own grammar only"
                ));
            }
            // A rule for a goal no one gives yet is normal in a library (grammars added later
            // may give it); a near miss is not.
            (None, _) => match suggest(
                &goal_name,
                others(&given_names, &goal_name).iter().map(String::as_str),
            ) {
                Some(close) => d = d.with_hint(format!("did you mean `{close}`?")),
                None => continue,
            },
        }
        out.push((grammar as usize, d));
    }
    for &(goal, grammar, span) in &scope.given {
        if asked.contains(&goal) || !reported.insert(goal) {
            continue;
        }
        let goal_name = name(scope, goal);
        // An open goal is normal (grammars added later may fulfil it); a near miss is not,
        // nor a local goal its own grammar leaves open while others fulfil its namesake.
        let asked_twin =
            twin(scope, goal).filter(|t| scope.goal_ids.get(t).is_some_and(|g| asked.contains(g)));
        match (scope.rules.goals[goal as usize].local, asked_twin) {
            (Some(owner), Some(_)) => out.push((
                grammar as usize,
                Diagnostic::warning(
                    format!(
                        "no rule of `{}` fulfils its local goal `{goal_name}`",
                        grammar_name(owner)
                    ),
                    span,
                )
                .with_hint("other grammars' rules for a goal of this name do not apply to it"),
            )),
            (None, Some(_)) => {}
            // A local goal is declared on purpose: often the name of a finished part.
            (Some(_), None) => {}
            (None, None) => {
                if let Some(close) = suggest(
                    &goal_name,
                    others(&asked_names, &goal_name).iter().map(String::as_str),
                ) {
                    out.push((
                        grammar as usize,
                        Diagnostic::warning(
                            format!("no rule fulfils the goal `{goal_name}`"),
                            span,
                        )
                        .with_hint(format!("did you mean `{close}`?")),
                    ));
                }
            }
        }
    }
    let set_names: Vec<String> = scope
        .set
        .iter()
        .map(|&a| scope.rules.attributes[a as usize].to_string())
        .collect();
    let mut reported = FxHashSet::default();
    for &(attr, grammar, span) in &scope.read_at {
        if scope.set.contains(&attr) || !reported.insert((attr, grammar)) {
            continue;
        }
        let attr_name = scope.rules.attributes[attr as usize].to_string();
        let close = suggest(&attr_name, set_names.iter().map(String::as_str));
        // In an open library another grammar may set it: only a near miss is worth a word.
        let mut d = match (open, &close) {
            (true, None) => continue,
            (true, Some(_)) => Diagnostic::warning(
                format!("no grammar of the library sets the attribute `{attr_name}`"),
                span,
            ),
            (false, _) => Diagnostic::error(
                format!(
                    "no grammar of the library sets the attribute `{attr_name}`: the rule can never apply"
                ),
                span,
            ),
        };
        if let Some(close) = close {
            d = d.with_hint(format!("did you mean `{close}`?"));
        } else {
            d = d.with_hint(format!(
                "set it where a shape is made: `set(@{attr_name}, value)` (`.Attribute(\"{attr_name}\", value)`)"
            ));
        }
        out.push((grammar as usize, d));
    }
    out
}
