//! Compiling a parsed grammar into a [`Program`]: names resolved to indices, operations told
//! apart from successors, arity and unknown names reported with spans and hints.

use std::sync::Arc;

use rustc_hash::FxHashMap;
use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, AttributeKind, BinaryOp, Body, ExprKind, Grammar, Stmt, UnaryOp},
    suggest,
};

use crate::builtins::{Builtin, Query};
use crate::fingerprint::Fingerprints;
use crate::goals::{AttrId, GoalId, GoalRules};
use crate::imports::{ImportGraph, Origins};
use crate::library::GoalScope;
use crate::ops::{self, Op};
use crate::tag_queries::TagFn;
use crate::value::Value;

/// Index of a rule in [`Program::rules`].
pub type RuleId = u32;
/// Index of an interned symbol name in [`Program::symbols`].
pub type Sym = u32;

/// A compiled grammar, ready to derive models from any number of times.
#[derive(Debug)]
pub struct Program {
    pub(crate) symbols: Vec<String>,
    pub(crate) rules: Vec<CRule>,
    pub(crate) attrs: Vec<CAttr>,
    pub(crate) consts: Vec<CConst>,
    pub(crate) functions: Vec<CFunction>,
    rule_by_name: FxHashMap<String, Vec<RuleId>>,
    attr_by_name: FxHashMap<String, u32>,
    /// The rule marked `@StartRule`, or else the first rule.
    pub start_rule: Option<RuleId>,
    /// By rule: whether applying it asks about other shapes (occlusion queries, snapping
    /// splits), directly or through functions and constants. Such rules wait for the second
    /// phase of a derivation.
    pub(crate) context_rules: Vec<bool>,
    /// Whether any rule uses a kinematic operation: only then is a skeleton built.
    pub(crate) kinematic: bool,
    /// Whether any rule derives operands at once (`union`, `subtract`, `intersect`, `inline`):
    /// a shape's result then depends on other rules than its own.
    pub(crate) derives_now: bool,
    /// Whether the grammar reads or writes component tags (`isTagged`, `geometry.tags`, `tag`,
    /// …): only then do operations tag what they make, so grammars without tags keep their
    /// boxes and their output.
    pub(crate) tagged: bool,
    /// Whether the grammar asks for `getTreeKey`: only then do shapes keep their key.
    pub(crate) tree_keys: bool,
    /// The named poses of `@Pose` annotations, in order of first appearance.
    named_poses: Vec<(String, Vec<(String, Value)>)>,
    /// What tells an edited rule from an unchanged one when deriving again.
    pub(crate) fingerprints: Fingerprints,
    /// The goal rules, axioms and index of a goal grammar library; `None` for symbol grammars.
    pub(crate) goals: Option<Box<GoalRules>>,
    /// With imports: the file each attribute, constant, function and rule came from.
    pub(crate) origins: Option<Origins>,
}

/// A compiled rule.
#[derive(Debug)]
pub(crate) struct CRule {
    pub symbol: Sym,
    pub params: usize,
    pub body: CBody,
}

/// A compiled attribute: its default value.
#[derive(Debug)]
pub(crate) struct CAttr {
    pub name: String,
    pub value: CExpr,
}

/// A compiled constant or parameterless function.
#[derive(Debug)]
pub(crate) struct CConst {
    pub value: CExpr,
    /// Evaluated once per initial shape (`const`) rather than at each use.
    pub cached: bool,
}

/// A compiled user function.
#[derive(Debug)]
pub(crate) struct CFunction {
    pub name: String,
    pub body: CExpr,
}

/// A compiled rule body.
#[derive(Debug)]
pub(crate) enum CBody {
    Sequence(Vec<CStmt>),
    Cases(Vec<(CExpr, CBody)>, Box<CBody>),
    Stochastic(Vec<(CExpr, CBody)>, Box<CBody>),
}

/// A compiled statement.
#[derive(Debug)]
pub(crate) enum CStmt {
    Op(Op, Span),
    Successor {
        symbol: Sym,
        rule: Option<RuleId>,
        args: Vec<CExpr>,
        terminal: bool,
        span: Span,
    },
    Push,
    Pop(Span),
    Nil,
    /// `[ case … ]`: the chosen branch's statements run, then the statements after this one.
    Branch(Box<CBody>),
    /// Goal grammars: the shape goes on with these goals opened and named by `symbol`.
    Goals {
        goals: GoalList,
        symbol: Sym,
        span: Span,
    },
}

/// The goals of a `+goal` successor: most have one, kept in the statement itself, so that a
/// step reads no more memory for it.
#[derive(Debug)]
pub(crate) enum GoalList {
    One(GoalId),
    Many(Box<[GoalId]>),
}

impl GoalList {
    /// The goals, sorted.
    pub fn as_slice(&self) -> &[GoalId] {
        match self {
            Self::One(goal) => std::slice::from_ref(goal),
            Self::Many(goals) => goals,
        }
    }
}

/// A compiled expression with the span it came from.
#[derive(Debug, Clone)]
pub(crate) struct CExpr {
    pub kind: CKind,
    pub span: Span,
}

/// The kinds of compiled expression.
#[derive(Debug, Clone)]
pub(crate) enum CKind {
    Value(Value),
    Param(u16),
    Attr(u32),
    Const(u32),
    Call(u32, Vec<CExpr>),
    Builtin(Builtin, Vec<CExpr>),
    Query(Query),
    Unary(UnaryOp, Box<CExpr>),
    Binary(BinaryOp, Box<CExpr>, Box<CExpr>),
    /// An element-wise operator (`a .* b`): the operation on each element of the arrays, a
    /// single value taking part with every element.
    EachBinary(BinaryOp, Box<CExpr>, Box<CExpr>),
    /// `.!a`, `.-a`: the operation on each element.
    EachUnary(UnaryOp, Box<CExpr>),
    Conditional(Box<CExpr>, Box<CExpr>, Box<CExpr>),
    Cases(Vec<(CExpr, CExpr)>, Box<CExpr>),
    Stochastic(Vec<(CExpr, CExpr)>, Box<CExpr>),
    /// `[a, b, …]`; a range among the elements adds its numbers.
    Array(Vec<CExpr>),
    /// `a[i]` or `a[row, column]`.
    Index(Box<CExpr>, Box<CExpr>, Option<Box<CExpr>>),
    /// `start:end` or `start:step:end`.
    Range(Box<CExpr>, Option<Box<CExpr>>, Box<CExpr>),
    Relative(Box<CExpr>),
    Floating(Box<CExpr>),
    /// A bare word in an operation argument: `x`, `front`, `scopeCenter`, `world.up`.
    Selector(String),
    /// A CGA function that parses but is not implemented: an error when evaluated.
    Unsupported(String),
    /// Goal grammars: a named attribute of the shape, of the type the getter asks for.
    GoalAttr(AttrId, AttributeKind),
    /// `comp(fe) { front : 2 | all : 0 }`: a value per face edge (face after face), that of the
    /// first entry whose selector takes the edge, else 0.
    EdgeValues(Vec<(crate::ops::CompSelector, CExpr)>),
}

impl Program {
    /// Compiles a grammar. Returns `None` when there are errors; warnings come back either way.
    pub fn compile(grammar: &Grammar) -> (Option<Program>, Vec<Diagnostic>) {
        if let Some(import) = grammar.imports.first() {
            let d = Diagnostic::error(
                "this grammar imports files: they are needed to compile it",
                import.span,
            )
            .with_hint("compile it with `Program::compile_imports`, giving the imported files");
            return (None, vec![d]);
        }
        if grammar.is_goal_grammar() {
            let (program, diagnostics) = Self::compile_library(&[("grammar", grammar)]);
            return (program, diagnostics.into_iter().map(|(_, d)| d).collect());
        }
        let mut compiler = Compiler::new(grammar);
        let program = compiler.run(grammar);
        let failed = compiler.diagnostics.iter().any(Diagnostic::is_error);
        ((!failed).then_some(program), compiler.diagnostics)
    }

    /// Compiles a grammar with the files it imports (see [`ImportGraph`]): one program, each
    /// file's declarations in its namespace. Returns `None` when there are errors; diagnostics
    /// come back with the index of their file.
    pub fn compile_imports(graph: ImportGraph<'_>) -> (Option<Program>, Vec<(usize, Diagnostic)>) {
        let (merged, origins) = match crate::imports::merge(graph) {
            Ok(merged) => merged,
            Err(errors) => return (None, errors),
        };
        let mut compiler = Compiler::new(&merged);
        compiler.origins = Some(origins);
        // What the compiler found before compiling declarations (rules defined twice) is the
        // importing file's.
        compiler.attribute(|_| 0);
        let mut program = compiler.run(&merged);
        compiler.attribute(|_| 0);
        let files = std::mem::take(&mut compiler.diagnostic_files);
        let diagnostics: Vec<(usize, Diagnostic)> = files
            .into_iter()
            .map(usize::from)
            .zip(compiler.diagnostics)
            .collect();
        let failed = diagnostics.iter().any(|(_, d)| d.is_error());
        if graph.files.len() < 2 {
            program.origins = None;
        }
        ((!failed).then_some(program), diagnostics)
    }

    /// Tells a program compiled with imports where each file of its [`ImportGraph`] lies:
    /// its folder relative to the importing grammar's, `/`-separated (`""` for the grammar's
    /// own). A rule then names files (`i("win.obj")`, `texture("a.png")`) from its own file's
    /// folder first (see [`crate::AssetLoader::beside`]).
    pub fn set_file_folders(&mut self, folders: Vec<String>) {
        if let Some(origins) = &mut self.origins {
            origins.folders = folders.into_iter().map(Arc::from).collect();
        }
    }

    /// The folder of the file rule `rule` came from, relative to the grammar's; `None` for the
    /// grammar's own folder or when it is not known.
    pub(crate) fn rule_folder(&self, rule: RuleId) -> Option<&str> {
        let origins = self.origins.as_ref()?;
        let file = *origins.rules.get(rule as usize)?;
        let folder = origins.folders.get(usize::from(file))?;
        (!folder.is_empty()).then_some(&**folder)
    }

    /// Whether the program is a library of goal grammars, which starts from its axioms.
    pub fn is_goal_grammar(&self) -> bool {
        self.goals.is_some()
    }

    /// The name of a symbol.
    pub fn symbol_name(&self, sym: Sym) -> &str {
        &self.symbols[sym as usize]
    }

    /// The rule with this name taking `arity` arguments, if any.
    pub fn rule(&self, name: &str, arity: usize) -> Option<RuleId> {
        self.rule_by_name
            .get(name)?
            .iter()
            .copied()
            .find(|&r| self.rules[r as usize].params == arity)
    }

    /// A rule's name and how many parameters it takes (`None` when there is no such rule).
    pub fn rule_signature(&self, rule: RuleId) -> Option<(&str, usize)> {
        let r = self.rules.get(rule as usize)?;
        Some((self.symbol_name(r.symbol), r.params))
    }

    /// Names of all rules, in file order without repeats.
    pub fn rule_names(&self) -> Vec<&str> {
        let mut seen = Vec::new();
        for r in &self.rules {
            let name = self.symbol_name(r.symbol);
            if !seen.contains(&name) {
                seen.push(name);
            }
        }
        seen
    }

    /// Index of the attribute with this name.
    pub fn attr(&self, name: &str) -> Option<u32> {
        self.attr_by_name.get(name).copied()
    }

    /// Names of the attributes, in file order.
    pub fn attr_names(&self) -> impl Iterator<Item = &str> {
        self.attrs.iter().map(|a| a.name.as_str())
    }

    /// The named poses of the grammar's `@Pose("open", 95)` annotations: each pose's name and
    /// the attribute values it sets (other attributes keep theirs), in order of first
    /// appearance.
    pub fn named_poses(&self) -> Vec<(String, Vec<(String, Value)>)> {
        self.named_poses.clone()
    }
}

/// Names visible in the expression being compiled: the parameters of the enclosing rule or
/// function.
type Params<'a> = &'a [ast::Ident];

pub(crate) struct Compiler<'g> {
    pub(crate) diagnostics: Vec<Diagnostic>,
    symbols: Vec<String>,
    symbol_ids: FxHashMap<String, Sym>,
    rule_by_name: FxHashMap<String, Vec<RuleId>>,
    attr_by_name: FxHashMap<String, u32>,
    const_by_name: FxHashMap<&'g str, u32>,
    function_by_name: FxHashMap<&'g str, Vec<(usize, u32)>>,
    /// Parameter count of each rule, by rule id.
    rule_arity: Vec<usize>,
    /// What the rule, function, constant or attribute being compiled uses.
    pub(crate) uses: Uses,
    /// Keys of warnings already given, so each missing rule or unsupported operation is
    /// reported once.
    warned: FxHashMap<String, ()>,
    /// Whether a kinematic operation was compiled.
    pub(crate) kinematic: bool,
    /// Whether an operation that derives operands at once was compiled.
    pub(crate) derives_now: bool,
    /// Whether something that reads or writes component tags was compiled.
    pub(crate) tagged: bool,
    /// Whether `getTreeKey` was compiled.
    pub(crate) tree_keys: bool,
    /// Compiling goal grammars: the library's names and what its checks need.
    pub(crate) goal: Option<Box<GoalScope>>,
    /// With imports: the file of each declaration, and of each diagnostic so far.
    origins: Option<Origins>,
    diagnostic_files: Vec<u16>,
}

impl<'g> Compiler<'g> {
    fn new(grammar: &'g Grammar) -> Self {
        let mut c = Self {
            diagnostics: Vec::new(),
            symbols: Vec::new(),
            symbol_ids: FxHashMap::default(),
            rule_by_name: FxHashMap::default(),
            attr_by_name: FxHashMap::default(),
            const_by_name: FxHashMap::default(),
            function_by_name: FxHashMap::default(),
            rule_arity: grammar.rules.iter().map(|r| r.params.len()).collect(),
            uses: Uses::default(),
            warned: FxHashMap::default(),
            kinematic: false,
            derives_now: false,
            tagged: false,
            tree_keys: false,
            goal: None,
            origins: None,
            diagnostic_files: Vec::new(),
        };
        for (i, rule) in grammar.rules.iter().enumerate() {
            let list = c.rule_by_name.entry(rule.name.name.clone()).or_default();
            if list
                .iter()
                .any(|&r| grammar.rules[r as usize].params.len() == rule.params.len())
            {
                c.diagnostics.push(
                    Diagnostic::error(
                        format!(
                            "rule `{}` is defined twice with {} parameters",
                            rule.name.name,
                            rule.params.len()
                        ),
                        rule.name.span,
                    )
                    .with_hint("rules of the same name must differ in their number of parameters"),
                );
            }
            list.push(i as RuleId);
        }
        for (i, attr) in grammar.attrs.iter().enumerate() {
            if c.attr_by_name
                .insert(attr.name.name.clone(), i as u32)
                .is_some()
            {
                c.diagnostics.push(Diagnostic::error(
                    format!("attribute `{}` is declared twice", attr.name.name),
                    attr.name.span,
                ));
            }
        }
        for (i, constant) in grammar.consts.iter().enumerate() {
            if c.const_by_name
                .insert(&constant.name.name, i as u32)
                .is_some()
            {
                c.diagnostics.push(Diagnostic::error(
                    format!("`{}` is defined twice", constant.name.name),
                    constant.name.span,
                ));
            }
        }
        for (i, function) in grammar.functions.iter().enumerate() {
            c.function_by_name
                .entry(&function.name.name)
                .or_default()
                .push((function.params.len(), i as u32));
        }
        c
    }

    fn run(&mut self, grammar: &Grammar) -> Program {
        let mut attr_uses = Vec::new();
        let attrs: Vec<CAttr> = grammar
            .attrs
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let value = self.expr(&a.value, &[]);
                self.attribute(|o| o.attrs[i]);
                attr_uses.push(std::mem::take(&mut self.uses));
                CAttr {
                    name: a.name.name.clone(),
                    value,
                }
            })
            .collect();
        let mut const_uses = Vec::new();
        let consts = grammar
            .consts
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let value = self.expr(&c.value, &[]);
                self.attribute(|o| o.consts[i]);
                const_uses.push(std::mem::take(&mut self.uses));
                CConst {
                    value,
                    cached: c.is_const,
                }
            })
            .collect();
        let mut function_uses = Vec::new();
        let functions = grammar
            .functions
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let body = self.expr(&f.body, &f.params);
                self.attribute(|o| o.functions[i]);
                function_uses.push(std::mem::take(&mut self.uses));
                CFunction {
                    name: f.name.name.clone(),
                    body,
                }
            })
            .collect();
        let mut rule_uses = Vec::new();
        let rules = grammar
            .rules
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let rule = CRule {
                    symbol: self.intern(&r.name.name),
                    params: r.params.len(),
                    body: self.body(&r.body, &r.params),
                };
                self.attribute(|o| o.rules[i]);
                rule_uses.push(std::mem::take(&mut self.uses));
                rule
            })
            .collect();
        let closure = ContextClosure::new(&function_uses, &const_uses);
        for (i, (attr, uses)) in grammar.attrs.iter().zip(&attr_uses).enumerate() {
            if closure.asks(uses) {
                self.attribute(|_| 0);
                self.diagnostics.push(
                    Diagnostic::error(
                        "attribute values cannot ask about other shapes",
                        attr.value.span,
                    )
                    .with_label("uses an occlusion query")
                    .with_hint(
                        "ask in a rule instead: `Tile --> case inside(): Wall else: Window`",
                    ),
                );
                self.attribute(|o| o.attrs[i]);
            }
        }
        let context_rules = rule_uses.iter().map(|u| closure.asks(u)).collect();
        let named_poses = crate::named_poses::compile(grammar, &mut self.diagnostics);
        // Without `@StartRule`, the first rule a shape can start from: one without parameters.
        let start_rule = grammar
            .rules
            .iter()
            .position(ast::Rule::is_start_rule)
            .or_else(|| grammar.rules.iter().position(|r| r.params.is_empty()))
            .or((!grammar.rules.is_empty()).then_some(0))
            .map(|i| i as RuleId);
        Program {
            symbols: std::mem::take(&mut self.symbols),
            rules,
            attrs,
            consts,
            functions,
            rule_by_name: std::mem::take(&mut self.rule_by_name),
            attr_by_name: std::mem::take(&mut self.attr_by_name),
            start_rule,
            context_rules,
            kinematic: self.kinematic,
            derives_now: self.derives_now,
            tagged: self.tagged,
            tree_keys: self.tree_keys,
            named_poses,
            fingerprints: Fingerprints::of(grammar),
            goals: None,
            origins: self.origins.take(),
        }
    }

    /// Gives the diagnostics reported since the last call the file `file` picks from the
    /// declarations' origins (when compiling a grammar with imports).
    fn attribute(&mut self, file: impl Fn(&Origins) -> u16) {
        if let Some(origins) = &self.origins {
            let file = file(origins);
            self.diagnostic_files.resize(self.diagnostics.len(), file);
        }
    }

    /// A compiler for goal grammars (whose rules come in through [`crate::library`]).
    pub(crate) fn new_for_goals(empty: &'g Grammar) -> Self {
        let mut c = Self::new(empty);
        c.goal = Some(Box::default());
        c
    }

    /// The program of a goal library.
    pub(crate) fn finish_goals(&mut self, rules: Vec<CRule>, goals: GoalRules) -> Program {
        Program {
            symbols: std::mem::take(&mut self.symbols),
            context_rules: vec![false; rules.len()],
            rules,
            attrs: Vec::new(),
            consts: Vec::new(),
            functions: Vec::new(),
            rule_by_name: FxHashMap::default(),
            attr_by_name: FxHashMap::default(),
            start_rule: None,
            kinematic: self.kinematic,
            derives_now: self.derives_now,
            tagged: self.tagged,
            tree_keys: self.tree_keys,
            named_poses: Vec::new(),
            fingerprints: Fingerprints::default(),
            goals: Some(Box::new(goals)),
            origins: None,
        }
    }

    pub(crate) fn intern(&mut self, name: &str) -> Sym {
        if let Some(&s) = self.symbol_ids.get(name) {
            return s;
        }
        let s = self.symbols.len() as Sym;
        self.symbols.push(name.to_owned());
        self.symbol_ids.insert(name.to_owned(), s);
        s
    }

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

    fn rule_arity(&self, rule: RuleId) -> Option<usize> {
        self.rule_arity.get(rule as usize).copied()
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

    /// Whether `name` is a parameter, attribute, constant or function the grammar declares (so
    /// a selector by that name is a condition, not an unknown selector word).
    pub(crate) fn knows_name(&self, name: &str, params: &[ast::Ident]) -> bool {
        params.iter().any(|p| p.name == name)
            || self.attr_by_name.contains_key(name)
            || self.const_by_name.contains_key(name)
            || self.function_by_name.contains_key(name)
    }

    /// A query of the shape, noting what the derivation must keep for it.
    fn query(&mut self, q: Query) -> CKind {
        self.tree_keys |= q == Query::TreeKey;
        CKind::Query(q)
    }

    /// Attribute names, for hints.
    pub(crate) fn attr_names(&self) -> impl Iterator<Item = &str> {
        self.attr_by_name.keys().map(String::as_str)
    }

    /// Reports a diagnostic.
    pub(crate) fn report(&mut self, d: Diagnostic) {
        self.diagnostics.push(d);
    }

    /// How many errors have been reported so far.
    pub(crate) fn error_count(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }

    /// Reports a warning once per `key`.
    pub(crate) fn warn_once(&mut self, key: &str, d: Diagnostic) {
        if self.warned.insert(key.to_owned(), ()).is_none() {
            self.diagnostics.push(d);
        }
    }
}

/// What a rule, function, constant or attribute uses, as far as finding context-dependent rules
/// goes.
#[derive(Debug, Default)]
pub(crate) struct Uses {
    /// It asks about other shapes itself (an occlusion query or a snapping split).
    pub context: bool,
    functions: Vec<u32>,
    consts: Vec<u32>,
}

/// Which functions and constants ask about other shapes, directly or through each other.
struct ContextClosure {
    functions: Vec<bool>,
    consts: Vec<bool>,
}

impl ContextClosure {
    fn new(functions: &[Uses], consts: &[Uses]) -> Self {
        let mut closure = Self {
            functions: vec![false; functions.len()],
            consts: vec![false; consts.len()],
        };
        // Each pass marks at least one more item or ends: at most one pass per item.
        loop {
            let mut changed = false;
            for (i, uses) in functions.iter().enumerate() {
                if !closure.functions[i] && closure.asks(uses) {
                    closure.functions[i] = true;
                    changed = true;
                }
            }
            for (i, uses) in consts.iter().enumerate() {
                if !closure.consts[i] && closure.asks(uses) {
                    closure.consts[i] = true;
                    changed = true;
                }
            }
            if !changed {
                return closure;
            }
        }
    }

    fn asks(&self, uses: &Uses) -> bool {
        uses.context
            || uses.functions.iter().any(|&f| self.functions[f as usize])
            || uses.consts.iter().any(|&c| self.consts[c as usize])
    }
}
