//! Compiling a parsed grammar into a [`Program`]: names resolved to indices, operations told
//! apart from successors, arity and unknown names reported with spans and hints.

use std::sync::Arc;

use rustc_hash::FxHashMap;
use shapegram_syntax::{
    Diagnostic, Span,
    ast::{self, AttributeKind, BinaryOp, Grammar, UnaryOp},
};

use crate::builtins::{Builtin, Query};
use crate::fingerprint::Fingerprints;
use crate::goals::{AttrId, GoalId, GoalRules};
use crate::imports::{ImportGraph, Origins};
use crate::library::GoalScope;
use crate::ops::Op;
use crate::value::Value;

mod compiler;
mod expressions;
mod statements;

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
    /// Whether any rule makes an implicit solid (`implicit(…)`): only then are the leaves
    /// looked through for solids to mesh.
    pub(crate) solids: bool,
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

    /// Whether a rule asks about other shapes (occlusion, context functions, snapping): then
    /// a lot's model depends on the lots around it.
    pub fn has_context_rules(&self) -> bool {
        self.context_rules.contains(&true)
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

    /// The symbols' names in symbol order, as a derivation's leaves are named by
    /// ([`crate::Derivation::names`]).
    pub(crate) fn symbol_names(&self) -> Arc<[Arc<str>]> {
        self.symbols.iter().map(|s| Arc::from(s.as_str())).collect()
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
    /// Whether `implicit(…)` was compiled.
    pub(crate) solids: bool,
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

/// What a rule, function, constant or attribute uses, as far as finding context-dependent rules
/// goes.
#[derive(Debug, Default)]
pub(crate) struct Uses {
    /// It asks about other shapes itself (an occlusion query or a snapping split).
    pub context: bool,
    functions: Vec<u32>,
    consts: Vec<u32>,
}
