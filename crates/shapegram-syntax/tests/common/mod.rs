//! Test helpers: compact S-expression views of the AST, so tests can state whole trees exactly.

#![allow(dead_code)] // each test file uses a different subset

use shapegram_syntax::ast::{
    Argument, AttributeKind, BinaryOp, Block, BlockEntry, Body, Call, Expr, ExprKind, Goal,
    GoalRule, Grammar, PredicateKind, Stmt, UnaryOp,
};
use shapegram_syntax::{Diagnostic, Parsed, SourceFile, parse};

/// Parses `text` as `test.cga`.
pub fn parse_str(text: &str) -> (SourceFile, Parsed) {
    let source = SourceFile::new("test.cga", text);
    let parsed = parse(&source);
    (source, parsed)
}

/// Parses `text` and panics (showing the rendered diagnostics) unless it has no diagnostics.
pub fn parse_ok(text: &str) -> Grammar {
    let (source, parsed) = parse_str(text);
    assert!(
        parsed.diagnostics.is_empty(),
        "unexpected diagnostics:\n{}",
        render_all(&source, &parsed.diagnostics)
    );
    parsed.grammar
}

/// All diagnostics rendered, in order.
pub fn render_all(source: &SourceFile, diagnostics: &[Diagnostic]) -> String {
    diagnostics.iter().map(|d| source.render(d)).collect()
}

/// The body of the rule called `name` (the first one).
pub fn rule_body(g: &Grammar, name: &str) -> String {
    let rule = g.rules.iter().find(|r| r.name.name == name);
    body(&rule.unwrap_or_else(|| panic!("no rule {name}")).body)
}

pub fn body(b: &Body) -> String {
    match b {
        Body::Sequence(stmts) => stmts_str(stmts),
        Body::Cases {
            arms, otherwise, ..
        } => arms_str("case", arms, otherwise),
        Body::Stochastic {
            arms, otherwise, ..
        } => arms_str("pct", arms, otherwise),
    }
}

fn arms_str(head: &str, arms: &[(Expr, Body)], otherwise: &Body) -> String {
    let mut out = format!("({head}");
    for (cond, b) in arms {
        out += &format!(" [{} => {}]", expr(cond), body(b));
    }
    out + &format!(" [else => {}])", body(otherwise))
}

pub fn stmts_str(stmts: &[Stmt]) -> String {
    let parts: Vec<String> = stmts.iter().map(stmt).collect();
    format!("({})", parts.join(" "))
}

pub fn stmt(s: &Stmt) -> String {
    match s {
        Stmt::Push(_) => "[".into(),
        Stmt::Pop(_) => "]".into(),
        Stmt::Nil(_) => "NIL".into(),
        Stmt::Branch(b) => body(b),
        Stmt::Call(c) => call(c),
        Stmt::Goals(goals, _) => goals.iter().map(|g| format!("+{}", g.name)).collect(),
    }
}

/// A goal rule as `[fulfills a b] [adds c] [is x] [!goal y] [if e] => body`.
pub fn goal_rule(rule: &GoalRule) -> String {
    let names = |goals: &[Goal]| {
        goals
            .iter()
            .map(|g| g.name.as_str())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut out = String::new();
    if !rule.fulfills.is_empty() {
        out += &format!("[fulfills {}] ", names(&rule.fulfills));
    }
    if !rule.adds.is_empty() {
        out += &format!("[adds {}] ", names(&rule.adds));
    }
    for p in &rule.predicates {
        let bang = if p.negated { "!" } else { "" };
        out += &match &p.kind {
            PredicateKind::Goal(g) => format!("[{bang}goal {}] ", names(g)),
            PredicateKind::Is(g) => format!("[{bang}is {}] ", names(g)),
            PredicateKind::Has(a) => {
                let a: Vec<&str> = a.iter().map(|i| i.name.as_str()).collect();
                format!("[{bang}has {}] ", a.join(" "))
            }
            PredicateKind::If(e) => format!("[{bang}if {}] ", expr(e)),
        };
    }
    out + &format!("=> {}", body(&rule.body))
}

pub fn call(c: &Call) -> String {
    let mut out = c.name.name.clone();
    if let Some(args) = &c.args {
        out += &format!("({})", args_str(args));
    }
    if let Some(b) = &c.block {
        out += &block(b);
    }
    if c.terminal {
        out.push('.');
    }
    out
}

pub fn block(b: &Block) -> String {
    let entries: Vec<String> = b
        .entries
        .iter()
        .map(|e| match e {
            BlockEntry::Part {
                key, merge, body, ..
            } => {
                format!(
                    "{} {} {}",
                    expr(key),
                    if *merge { "=" } else { ":" },
                    stmts_str(body)
                )
            }
            BlockEntry::Group(g) => block(g),
        })
        .collect();
    format!(
        "{{{}}}{}",
        entries.join(" | "),
        if b.repeat { "*" } else { "" }
    )
}

/// Arguments as `a, name=b`.
pub fn args_str(args: &[Argument]) -> String {
    let parts: Vec<String> = args
        .iter()
        .map(|a| match &a.name {
            Some(n) => format!("{}={}", n.name, expr(&a.value)),
            None => expr(&a.value),
        })
        .collect();
    parts.join(", ")
}

pub fn expr(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number(n) => format!("{n}"),
        ExprKind::String(s) => format!("{s:?}"),
        ExprKind::Bool(b) => format!("{b}"),
        ExprKind::Array(items) => {
            let parts: Vec<String> = items.iter().map(expr).collect();
            format!("[{}]", parts.join(", "))
        }
        ExprKind::Name(n) => n.clone(),
        ExprKind::Call { name, args } => format!("{}({})", name.name, args_str(args)),
        ExprKind::Index {
            target,
            index,
            column: None,
        } => format!("{}[{}]", expr(target), expr(index)),
        ExprKind::Index {
            target,
            index,
            column: Some(column),
        } => format!("{}[{}, {}]", expr(target), expr(index), expr(column)),
        ExprKind::Range {
            start,
            step: None,
            end,
        } => format!("{}:{}", expr(start), expr(end)),
        ExprKind::Range {
            start,
            step: Some(step),
            end,
        } => format!("{}:{}:{}", expr(start), expr(step), expr(end)),
        ExprKind::Unary { op, operand } => {
            let op = match op {
                UnaryOp::Neg => "-",
                UnaryOp::Not => "!",
            };
            format!("({op}{})", expr(operand))
        }
        ExprKind::Binary { op, lhs, rhs } => {
            format!("({} {} {})", expr(lhs), binop(*op), expr(rhs))
        }
        ExprKind::Conditional {
            cond,
            then,
            otherwise,
        } => {
            format!("({} ? {} : {})", expr(cond), expr(then), expr(otherwise))
        }
        ExprKind::Cases { arms, otherwise } => expr_arms("case", arms, otherwise),
        ExprKind::Stochastic { arms, otherwise } => expr_arms("pct", arms, otherwise),
        ExprKind::Floating(inner) => format!("~{}", expr(inner)),
        ExprKind::Relative(inner) => format!("'{}", expr(inner)),
        ExprKind::GoalAttribute { name, kind } => match kind {
            AttributeKind::Any => format!("@{name}"),
            AttributeKind::Number => format!("@Double({name:?})"),
            AttributeKind::String => format!("@String({name:?})"),
        },
    }
}

fn expr_arms(head: &str, arms: &[(Expr, Expr)], otherwise: &Expr) -> String {
    let mut out = format!("({head}");
    for (cond, value) in arms {
        out += &format!(" [{} => {}]", expr(cond), expr(value));
    }
    out + &format!(" [else => {}])", expr(otherwise))
}

fn binop(op: BinaryOp) -> &'static str {
    match op {
        BinaryOp::Mul => "*",
        BinaryOp::Div => "/",
        BinaryOp::Rem => "%",
        BinaryOp::Add => "+",
        BinaryOp::Sub => "-",
        BinaryOp::Lt => "<",
        BinaryOp::Le => "<=",
        BinaryOp::Gt => ">",
        BinaryOp::Ge => ">=",
        BinaryOp::Eq => "==",
        BinaryOp::Ne => "!=",
        BinaryOp::And => "&&",
        BinaryOp::Or => "||",
    }
}
