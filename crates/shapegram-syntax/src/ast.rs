//! The typed syntax tree every dialect lowers to.
//!
//! The tree keeps the grammar as written: which names are rules and which are operations is
//! decided by the evaluator (a rule defined in the grammar wins over a built-in operation of the
//! same name; a name that is neither becomes a leaf, as in CGA). Every node carries its [`Span`].

use crate::Span;

/// A parsed grammar file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Grammar {
    /// The surface notation the file was written in.
    pub dialect: Dialect,
    /// The `version "…"` line, if any.
    pub version: Option<Spanned<String>>,
    /// `attr` declarations, in file order.
    pub attrs: Vec<Attr>,
    /// `const` declarations (and CGA's parameterless functions `name = expr`), in file order.
    pub consts: Vec<Const>,
    /// User functions `name(params) = expr`, in file order.
    pub functions: Vec<Function>,
    /// Rules, in file order. Several rules may share a name (stochastic rules of the Müller
    /// notation are lowered into one rule with a [`Body::Stochastic`]).
    pub rules: Vec<Rule>,
    /// Top-level statements that were parsed but are not supported yet (`style`, …), kept so
    /// `check` can warn about them with their spans.
    pub unsupported: Vec<Unsupported>,
    /// `import id : "file.cga"` statements, in file order.
    pub imports: Vec<Import>,
    /// Goal grammars: the axioms, the shapes a derivation starts from.
    pub axioms: Vec<Axiom>,
    /// Goal grammars: rules chosen by predicates over a shape's goals, tags and attributes.
    pub goal_rules: Vec<GoalRule>,
    /// Goal grammars: goals local to this grammar (only its own rules fulfil them), each
    /// where it was first declared or written in lowercase.
    pub local_goals: Vec<Goal>,
    /// Goal grammars: the synchronizations declared (`var windows = new Synchronize();`).
    pub syncs: Vec<Ident>,
    /// CGA's `style` sections, in file order; the declarations above hold the default style
    /// (see [`Grammar::with_style`]).
    pub styles: Vec<Style>,
}

/// `style Name` or `style Name extends Base`, with the declarations up to the next `style`.
#[derive(Clone, Debug, PartialEq)]
pub struct Style {
    /// The style's name.
    pub name: Ident,
    /// The style it extends; the default style when `None`.
    pub base: Option<Ident>,
    /// Its attributes, constants, functions and rules.
    pub declarations: Grammar,
    /// `style Name [extends Base]`.
    pub span: Span,
}

impl Grammar {
    /// The grammar in style `name`: the default style's declarations with those of the style
    /// and of the styles it extends laid over them, base first. A declaration replaces the one
    /// of the same name (for functions and rules, of the same name and parameter count) and
    /// keeps its place; others are added. `Default` is the grammar as it is.
    pub fn with_style(&self, name: &str) -> Result<Grammar, String> {
        let mut chain: Vec<&Style> = Vec::new();
        let mut next = Some(name);
        while let Some(wanted) = next.filter(|n| *n != "Default") {
            let Some(style) = self.styles.iter().find(|s| s.name.name == wanted) else {
                let known: Vec<&str> = self.styles.iter().map(|s| s.name.name.as_str()).collect();
                return Err(match chain.last() {
                    Some(from) => format!(
                        "style `{}` extends `{wanted}`, which is not declared",
                        from.name.name
                    ),
                    None => format!(
                        "no style `{wanted}` (the styles: Default{})",
                        known.iter().map(|k| format!(", {k}")).collect::<String>()
                    ),
                });
            };
            if chain.iter().any(|s| s.name.name == wanted) {
                return Err(format!("style `{wanted}` extends itself"));
            }
            chain.push(style);
            next = style.base.as_ref().map(|b| b.name.as_str());
        }
        let mut out = Grammar {
            styles: Vec::new(),
            ..self.clone()
        };
        for style in chain.into_iter().rev() {
            let d = &style.declarations;
            overlay(&mut out.attrs, &d.attrs, |a| (a.name.name.clone(), 0));
            overlay(&mut out.consts, &d.consts, |c| (c.name.name.clone(), 0));
            overlay(&mut out.functions, &d.functions, |f| {
                (f.name.name.clone(), f.params.len())
            });
            overlay(&mut out.rules, &d.rules, |r| {
                (r.name.name.clone(), r.params.len())
            });
        }
        Ok(out)
    }

    /// Whether the grammar is a goal grammar (it has axioms or goal rules).
    pub fn is_goal_grammar(&self) -> bool {
        matches!(self.dialect, Dialect::Goal | Dialect::Michelangelo)
            || !self.axioms.is_empty()
            || !self.goal_rules.is_empty()
    }
}

/// The surface notations Shapegram reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Dialect {
    /// CityEngine-style CGA (the main syntax).
    #[default]
    Cga,
    /// The notation of Müller et al. 2006 (`Subdiv`, `Repeat`, `Comp`, `S`, `T`, `I`, …).
    Muller2006,
    /// The SGL notation (`T() R() S() Subdiv(…, sgprod{…}) PlaceShape(…)`, `(w){…}` alternatives).
    Sgl,
    /// The native notation of goal grammars (`axiom chair size(…)`, `fulfills(chair) --> …`).
    Goal,
    /// The C#-style notation of goal grammars in Ilčík and Wimmer's Michelangelo
    /// (`new Rules.Split(Axis.Y, …).Fulfills("chair");`).
    Michelangelo,
}

/// A value with the span it was written at.
#[derive(Clone, Debug, PartialEq)]
pub struct Spanned<T> {
    /// The value.
    pub value: T,
    /// Where it was written.
    pub span: Span,
}

/// A name as written, e.g. `Facade`, `scope.sx`, `material.color.r`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Ident {
    /// The name, dots included.
    pub name: String,
    /// Where it was written.
    pub span: Span,
}

/// An annotation such as `@StartRule`, `@Range(min=5, max=40)` or `@Group("Facade", 3)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Annotation {
    /// The name without `@`.
    pub name: Ident,
    /// Arguments, positional or `key=value`.
    pub args: Vec<Argument>,
    /// The whole annotation.
    pub span: Span,
}

/// One argument of a call or annotation, optionally named (`min=5`).
#[derive(Clone, Debug, PartialEq)]
pub struct Argument {
    /// The name before `=`, for named arguments.
    pub name: Option<Ident>,
    /// The value.
    pub value: Expr,
}

/// `attr name = value`: a parameter of the grammar that users may override.
#[derive(Clone, Debug, PartialEq)]
pub struct Attr {
    /// Annotations written before it.
    pub annotations: Vec<Annotation>,
    /// The attribute's name.
    pub name: Ident,
    /// Its default value (evaluated per initial shape: it may call `rand`).
    pub value: Expr,
    /// The whole declaration.
    pub span: Span,
}

/// `const name = value` (or a parameterless function `name = value`).
#[derive(Clone, Debug, PartialEq)]
pub struct Const {
    /// Annotations written before it.
    pub annotations: Vec<Annotation>,
    /// The constant's name.
    pub name: Ident,
    /// Its value.
    pub value: Expr,
    /// Whether it was written with the `const` keyword (evaluated once) rather than as a
    /// parameterless function (evaluated at each use).
    pub is_const: bool,
    /// The whole declaration.
    pub span: Span,
}

/// `name(a, b) = expr`: a user function.
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    /// Annotations written before it.
    pub annotations: Vec<Annotation>,
    /// The function's name.
    pub name: Ident,
    /// Parameter names.
    pub params: Vec<Ident>,
    /// The body.
    pub body: Expr,
    /// The whole declaration.
    pub span: Span,
}

/// `Name(params) --> body`.
#[derive(Clone, Debug, PartialEq)]
pub struct Rule {
    /// Annotations written before it (`@StartRule`, …).
    pub annotations: Vec<Annotation>,
    /// The predecessor symbol.
    pub name: Ident,
    /// Parameter names (empty when written without parentheses).
    pub params: Vec<Ident>,
    /// What the rule does.
    pub body: Body,
    /// The whole rule.
    pub span: Span,
}

impl Rule {
    /// Whether the rule carries the `@StartRule` annotation.
    pub fn is_start_rule(&self) -> bool {
        self.annotations.iter().any(|a| a.name.name == "StartRule")
    }
}

/// The right-hand side of a rule, or of one branch of a `case` or stochastic choice.
#[derive(Clone, Debug, PartialEq)]
pub enum Body {
    /// Operations and successors, applied left to right.
    Sequence(Vec<Stmt>),
    /// `case c1 : b1 case c2 : b2 … else : b`: the first branch whose condition holds.
    Cases {
        /// Condition and branch, in order.
        arms: Vec<(Expr, Body)>,
        /// The `else` branch (an empty sequence when omitted).
        otherwise: Box<Body>,
        /// The whole construct.
        span: Span,
    },
    /// `30% : b1 20% : b2 else : b`: one branch drawn with the given percentages.
    Stochastic {
        /// Percentage (0–100) and branch, in order.
        arms: Vec<(Expr, Body)>,
        /// The `else` branch taking the remaining probability (empty when omitted).
        otherwise: Box<Body>,
        /// The whole construct.
        span: Span,
    },
}

/// One step of a rule body.
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// A call: an operation (`extrude(10)`, `split(x){…}`) or a successor symbol
    /// (`Facade(2, 1)`, `Window`); see the module docs.
    Call(Call),
    /// `[`: push the current shape's scope and state.
    Push(Span),
    /// `]`: pop back to the pushed state.
    Pop(Span),
    /// `NIL` (or ε in the Müller notation): delete the current shape.
    Nil(Span),
    /// `[ case c: A else: B ]`: a `case` or percentage choice right after `[`, up to the
    /// matching `]`. The statements after it go on from the chosen branch.
    Branch(Box<Body>),
    /// Goal grammars: `+seat +wooden`, the shape goes on with these goals added and the rules
    /// that match it are sought (a successor without a symbol).
    Goals(Vec<Goal>, Span),
}

/// The name of the statement a dynamic import `id(a = v).Rule` begins with (see
/// [`Stmt`]): a call whose first argument names the import and whose named arguments set its
/// attributes. No name written in a grammar can take this form.
pub const DYNAMIC_IMPORT: &str = "import()";

/// A name with optional arguments and an optional block, e.g. `split(y){ … }*`, `A(1, 2)`, `B.`.
#[derive(Clone, Debug, PartialEq)]
pub struct Call {
    /// The operation or successor name.
    pub name: Ident,
    /// Arguments; `None` when written without parentheses (`Window` vs `Window()`).
    pub args: Option<Vec<Argument>>,
    /// The `{ … }` block of splits, component splits and similar operations. A perimeter split's
    /// two blocks `splitAndSetbackPerimeter(…) { len : depth : … }* { remainder : … }` are one:
    /// the sections' block as a group whose keys are the pairs `[len, depth]`, then the
    /// remainder's entries.
    pub block: Option<Block>,
    /// Whether a terminal marker `.` follows (`Glass.`).
    pub terminal: bool,
    /// The whole call, block included.
    pub span: Span,
}

/// `{ key : body | key : body | { … }* }` with an optional trailing `*` (repeat).
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// Entries in order.
    pub entries: Vec<BlockEntry>,
    /// Whether the block is followed by `*` (repeat it to fill the scope).
    pub repeat: bool,
    /// From `{` to `}` (or `*`).
    pub span: Span,
}

/// One entry of a [`Block`].
#[derive(Clone, Debug, PartialEq)]
pub enum BlockEntry {
    /// `key : body` (or `key = body`, CGA's merging selector in component splits).
    Part {
        /// A size (`2`, `~2`, `'0.5`) in splits, a selector (`front`, `side`, `0`) in
        /// component splits.
        key: Expr,
        /// Whether written with `=` instead of `:`.
        merge: bool,
        /// What to do with the part.
        body: Vec<Stmt>,
        /// The whole entry.
        span: Span,
    },
    /// A nested `{ … }` group, usually repeated: `{ ~3 : Tile }*`.
    Group(Block),
}

/// An expression with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// What kind of expression.
    pub kind: ExprKind,
    /// Where it was written.
    pub span: Span,
}

/// The kinds of [`Expr`].
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// A number literal.
    Number(f64),
    /// A string literal (escapes resolved).
    String(String),
    /// `true` or `false`.
    Bool(bool),
    /// `[a, b, c]`; a 2D array `[1, 2; 3, 4]` is an array of row arrays.
    Array(Vec<Expr>),
    /// A name: attribute, constant, parameter, parameterless function, or a dotted query such
    /// as `scope.sx`, `split.index`, `geometry.area`; also bare words used as arguments
    /// (`split(x)`, `comp(f)`, `front`).
    Name(String),
    /// `f(a, b)`. CGA's comp function `comp(fe){ all : 3 | 0 : 1 }` is written here as
    /// `comp(fe, all = 3, 0 = 1)`: its entries become named arguments after the positional ones.
    Call {
        /// The function's name.
        name: Ident,
        /// The arguments.
        args: Vec<Argument>,
    },
    /// `a[i]`, or `a[row, column]` for a 2D array; an index may be a [`ExprKind::Range`] or an
    /// array of indices, which selects several elements.
    Index {
        /// The array.
        target: Box<Expr>,
        /// The index (the row's, for a 2D array).
        index: Box<Expr>,
        /// The column's index, for a 2D array.
        column: Option<Box<Expr>>,
    },
    /// CGA's colon operator `start:end` or `start:step:end`, written in array brackets (an
    /// element of `[…]` or an index): the numbers from `start` to `end` in steps of `step`
    /// (1 unless given), `end` included when reached.
    Range {
        /// The first number.
        start: Box<Expr>,
        /// The step, when written.
        step: Option<Box<Expr>>,
        /// The last number.
        end: Box<Expr>,
    },
    /// A prefix operator.
    Unary {
        /// Which operator.
        op: UnaryOp,
        /// The operand.
        operand: Box<Expr>,
    },
    /// An infix operator.
    Binary {
        /// Which operator.
        op: BinaryOp,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
    },
    /// `cond ? a : b`.
    Conditional {
        /// The condition.
        cond: Box<Expr>,
        /// Value when true.
        then: Box<Expr>,
        /// Value when false.
        otherwise: Box<Expr>,
    },
    /// `case c1 : v1 case c2 : v2 else : v` as an expression.
    Cases {
        /// Condition and value, in order.
        arms: Vec<(Expr, Expr)>,
        /// The `else` value.
        otherwise: Box<Expr>,
    },
    /// `30% : v1 else : v2` as an expression.
    Stochastic {
        /// Percentage and value, in order.
        arms: Vec<(Expr, Expr)>,
        /// The `else` value.
        otherwise: Box<Expr>,
    },
    /// `~e`: a floating size (split keys).
    Floating(Box<Expr>),
    /// `'e`: a relative size (split keys, `s(…)` arguments); `1r` in the Müller notation.
    Relative(Box<Expr>),
    /// Goal grammars: the value of a shape's named attribute (`@Leg.Size`,
    /// `@Double("Leg.Size")`); a rule that reads one applies only to shapes that have it.
    GoalAttribute {
        /// The attribute's name.
        name: String,
        /// The type the getter asks for.
        kind: AttributeKind,
    },
}

impl Expr {
    /// Calls `f` on this expression and then on every expression inside it, outermost first
    /// (call arguments included): how passes rewrite names throughout an expression.
    pub fn walk_mut(&mut self, f: &mut impl FnMut(&mut Expr)) {
        f(self);
        match &mut self.kind {
            ExprKind::Call { args, .. } => args.iter_mut().for_each(|a| a.value.walk_mut(f)),
            ExprKind::Array(items) => items.iter_mut().for_each(|i| i.walk_mut(f)),
            ExprKind::Index {
                target,
                index,
                column,
            } => {
                target.walk_mut(f);
                index.walk_mut(f);
                if let Some(column) = column {
                    column.walk_mut(f);
                }
            }
            ExprKind::Range { start, step, end } => {
                start.walk_mut(f);
                if let Some(step) = step {
                    step.walk_mut(f);
                }
                end.walk_mut(f);
            }
            ExprKind::Unary { operand, .. } => operand.walk_mut(f),
            ExprKind::Binary { lhs, rhs, .. } => {
                lhs.walk_mut(f);
                rhs.walk_mut(f);
            }
            ExprKind::Conditional {
                cond,
                then,
                otherwise,
            } => {
                cond.walk_mut(f);
                then.walk_mut(f);
                otherwise.walk_mut(f);
            }
            ExprKind::Cases { arms, otherwise } | ExprKind::Stochastic { arms, otherwise } => {
                for (a, v) in arms {
                    a.walk_mut(f);
                    v.walk_mut(f);
                }
                otherwise.walk_mut(f);
            }
            ExprKind::Floating(inner) | ExprKind::Relative(inner) => inner.walk_mut(f),
            ExprKind::Number(_)
            | ExprKind::String(_)
            | ExprKind::Bool(_)
            | ExprKind::Name(_)
            | ExprKind::GoalAttribute { .. } => {}
        }
    }
}

/// The type an attribute getter of a goal grammar asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AttributeKind {
    /// Any value (`@name`).
    Any,
    /// A number (`@Double("name")`).
    Number,
    /// A string (`@String("name")`).
    String,
}

/// Prefix operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// `-x`.
    Neg,
    /// `!x`.
    Not,
}

/// Infix operators, loosest binding last.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `a * b`.
    Mul,
    /// `a / b`.
    Div,
    /// `a % b`.
    Rem,
    /// `a + b` (also string concatenation).
    Add,
    /// `a - b`.
    Sub,
    /// `a < b`.
    Lt,
    /// `a <= b`.
    Le,
    /// `a > b`.
    Gt,
    /// `a >= b`.
    Ge,
    /// `a == b`.
    Eq,
    /// `a != b`.
    Ne,
    /// `a && b`.
    And,
    /// `a || b`.
    Or,
}

/// A construct that parses but is not supported yet.
#[derive(Clone, Debug, PartialEq)]
pub struct Unsupported {
    /// What it is, e.g. `import`, `style`.
    pub what: String,
    /// Where.
    pub span: Span,
}

/// A goal as written: `chair`, `"split-legs"`.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Goal {
    /// The goal's name.
    pub name: String,
    /// Where it was written.
    pub span: Span,
}

/// A shape a goal-grammar derivation starts from: its goals and, optionally, its size (a box
/// at the origin); without a size it starts from each initial shape (lot) given.
#[derive(Clone, Debug, PartialEq)]
pub struct Axiom {
    /// The goals the shape should fulfil.
    pub goals: Vec<Goal>,
    /// The box's size along x, y and z.
    pub size: Option<[Expr; 3]>,
    /// The whole declaration.
    pub span: Span,
}

/// A rule of a goal grammar: `fulfills(support) is(chair) --> split(x) { … }`.
#[derive(Clone, Debug, PartialEq)]
pub struct GoalRule {
    /// Annotations written before it (`@Weight(2)`).
    pub annotations: Vec<Annotation>,
    /// What a shape must be for the rule to apply, all of them (`using` blocks included).
    pub predicates: Vec<Predicate>,
    /// The goals the rule fulfils: a shape must have them, and every shape the rule makes has
    /// them as tags instead.
    pub fulfills: Vec<Goal>,
    /// Goals the rule adds to every shape it makes (`.Goal("metallic")` on a rule).
    pub adds: Vec<Goal>,
    /// What the rule does.
    pub body: Body,
    /// The whole rule.
    pub span: Span,
}

/// A condition on the left side of a goal rule.
#[derive(Clone, Debug, PartialEq)]
pub struct Predicate {
    /// What is asked.
    pub kind: PredicateKind,
    /// Whether it is the `IfNot…` form.
    pub negated: bool,
    /// Where it was written.
    pub span: Span,
}

/// The kinds of [`Predicate`].
#[derive(Clone, Debug, PartialEq)]
pub enum PredicateKind {
    /// `IfGoal`: the shape has all these goals open.
    Goal(Vec<Goal>),
    /// `IfIs`/`IfTag`: the shape has all these tags (fulfilled goals).
    Is(Vec<Goal>),
    /// `IfHas`: the shape has all these attributes.
    Has(Vec<Ident>),
    /// `If(…)`: the expression holds for the shape (its scope, attributes).
    If(Expr),
}

/// `import id : "file.cga"`, optionally with `(a = value, b)`: the rules, attributes, constants
/// and functions of the file become `id.Name`.
#[derive(Clone, Debug, PartialEq)]
pub struct Import {
    /// The namespace the file's declarations go into; `None` (`import "file.cga"`) merges them
    /// into the importing file's.
    pub id: Option<Ident>,
    /// The file, as written.
    pub path: Spanned<String>,
    /// What the parenthesised list says of the file's attributes: `None` without one.
    pub attributes: Option<Vec<ImportAttribute>>,
    /// The whole statement.
    pub span: Span,
}

/// An entry of an import's attribute list.
#[derive(Clone, Debug, PartialEq)]
pub enum ImportAttribute {
    /// `a = value`: the imported attribute `a` takes this value (an expression of the
    /// importing file).
    Set(Ident, Expr),
    /// `a`: the imported attribute keeps its own value, even if the importing file has an
    /// attribute of that name.
    Keep(Ident),
}

/// Lays `over` on `under`: an item whose key is already there replaces it in place, the others
/// are added at the end.
fn overlay<T: Clone>(under: &mut Vec<T>, over: &[T], key: impl Fn(&T) -> (String, usize)) {
    for item in over {
        let k = key(item);
        match under.iter().position(|u| key(u) == k) {
            Some(i) => under[i] = item.clone(),
            None => under.push(item.clone()),
        }
    }
}
