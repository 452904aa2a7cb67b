//! Named poses: `@Pose("open", 95)` on an attribute means "in the pose `open`, this attribute is
//! 95". A named pose is the set of attribute values that name it; the others keep theirs.

use shapegram_syntax::{
    Diagnostic,
    ast::{Annotation, ExprKind, Grammar, UnaryOp},
};

use crate::value::Value;

/// The annotation's name.
const POSE: &str = "Pose";

/// Each named pose with its attribute overrides, in order of first appearance (poses, and the
/// attributes within a pose, in file order); every malformed annotation is reported.
pub(crate) fn compile(
    grammar: &Grammar,
    diagnostics: &mut Vec<Diagnostic>,
) -> Vec<(String, Vec<(String, Value)>)> {
    let mut poses: Vec<(String, Vec<(String, Value)>)> = Vec::new();
    for attr in &grammar.attrs {
        for annotation in attr.annotations.iter().filter(|a| a.name.name == POSE) {
            let (name, value) = match pose(annotation) {
                Ok(pose) => pose,
                Err(d) => {
                    diagnostics.push(d);
                    continue;
                }
            };
            let index = match poses.iter().position(|(n, _)| *n == name) {
                Some(i) => i,
                None => {
                    poses.push((name.clone(), Vec::new()));
                    poses.len() - 1
                }
            };
            let overrides = &mut poses[index].1;
            if overrides.iter().any(|(a, _)| *a == attr.name.name) {
                diagnostics.push(
                    Diagnostic::error(
                        format!(
                            "attribute `{}` is given twice in the pose \"{name}\"",
                            attr.name.name
                        ),
                        annotation.span,
                    )
                    .with_label("a second value for the same pose"),
                );
                continue;
            }
            overrides.push((attr.name.name.clone(), value));
        }
    }
    // Only attributes have values a pose can set: the annotation anywhere else does nothing.
    let elsewhere = grammar
        .consts
        .iter()
        .map(|c| (&c.annotations, "a constant"))
        .chain(
            grammar
                .functions
                .iter()
                .map(|f| (&f.annotations, "a function")),
        )
        .chain(grammar.rules.iter().map(|r| (&r.annotations, "a rule")));
    for (annotations, what) in elsewhere {
        for annotation in annotations.iter().filter(|a| a.name.name == POSE) {
            diagnostics.push(
                Diagnostic::warning(
                    format!("`@Pose` on {what} does nothing: poses set attributes"),
                    annotation.span,
                )
                .with_label("ignored")
                .with_hint("put it on the `attr` whose value the pose sets"),
            );
        }
    }
    poses
}

/// The pose's name and the attribute's value in it, or the error.
fn pose(annotation: &Annotation) -> Result<(String, Value), Diagnostic> {
    let usage = "write `@Pose(\"open\", 95)`: the pose's name, then the attribute's value in it";
    let error = |message: &str, label: &str| {
        Diagnostic::error(message, annotation.span)
            .with_label(label)
            .with_hint(usage)
    };
    if annotation.args.len() != 2 || annotation.args.iter().any(|a| a.name.is_some()) {
        return Err(error(
            "`@Pose` takes two arguments: a name and a value",
            "expected `@Pose(name, value)`",
        ));
    }
    let name = match &annotation.args[0].value.kind {
        ExprKind::String(s) if !s.is_empty() => s.clone(),
        ExprKind::String(_) => return Err(error("a pose's name cannot be empty", "empty name")),
        _ => {
            return Err(error(
                "a pose's name must be a string",
                "expected a name in quotes",
            ));
        }
    };
    let value = &annotation.args[1].value;
    let value = match &value.kind {
        ExprKind::Number(n) => Value::Number(*n),
        ExprKind::Bool(b) => Value::Bool(*b),
        ExprKind::String(s) => Value::string(s),
        ExprKind::Unary {
            op: UnaryOp::Neg,
            operand,
        } => match operand.kind {
            ExprKind::Number(n) => Value::Number(-n),
            _ => return Err(not_literal(annotation, usage)),
        },
        _ => return Err(not_literal(annotation, usage)),
    };
    Ok((name, value))
}

fn not_literal(annotation: &Annotation, usage: &str) -> Diagnostic {
    Diagnostic::error(
        "a pose's value must be a literal number, boolean or string",
        annotation.span,
    )
    .with_label("not a literal")
    .with_hint(usage)
}
