//! What an attribute's annotations ask of an editor (CityEngine's Inspector): a slider, a
//! choice, a colour picker, a group and place, a tooltip, or nothing at all. Annotations never
//! change a derivation; they are data for the studio's panel and the runtimes' interfaces.
//! Unknown or misspelt annotations (`@Hiddden`) are kept by name and otherwise ignored.

use shapegram_syntax::ast::{Annotation, Argument, Attr, ExprKind, UnaryOp};

use crate::value::Value;

/// The editor's view of one attribute, from its annotations.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AttrAnnotations {
    /// `@Range(min, max)` or `@Range(min=…, max=…, stepsize=…, restricted=…)`: a slider.
    pub range: Option<AttrRange>,
    /// `@Enum(a, b, …)` (or CityEngine's older `@Range("a", "b")`): the choices.
    pub choices: Option<Vec<Value>>,
    /// `@Enum(valuesAttr=name)`: the attribute whose value lists the choices.
    pub values_attr: Option<String>,
    /// Whether a value outside the choices or the range is refused (`restricted`, true unless
    /// written false).
    pub restricted: bool,
    /// `@Color`: a `"#rrggbb"` string picked with a colour picker.
    pub color: bool,
    /// `@Group("a", "b", order)`: the nested groups it is shown in, outermost first.
    pub group: Vec<String>,
    /// The number ending `@Group(…)`: where the (innermost) group goes among groups.
    pub group_order: Option<f64>,
    /// `@Order(n)`: where it goes in its group.
    pub order: Option<f64>,
    /// `@Hidden`: not shown.
    pub hidden: bool,
    /// `@Description("…")`: the tooltip.
    pub description: Option<String>,
    /// `@DisplayName("…")`: the label instead of the name.
    pub display_name: Option<String>,
    /// `@Angle`, `@Distance` or `@Percent`: the unit shown.
    pub unit: Option<Unit>,
    /// `@File` or `@Directory`: a path picked from files.
    pub file: bool,
    /// Every annotation's name as written, in order.
    pub names: Vec<String>,
}

/// A slider's bounds and step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttrRange {
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// The step values snap to; 0: none.
    pub step: f64,
}

/// The unit an attribute is shown in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// Degrees.
    Angle,
    /// Metres.
    Distance,
    /// A fraction shown in percent (0.1 shows as 10 %).
    Percent,
}

/// What `attr`'s annotations ask for. Arguments that are not literals (or negated numbers) are
/// skipped, as are annotations whose arguments do not fit.
pub fn attr_annotations(attr: &Attr) -> AttrAnnotations {
    let mut out = AttrAnnotations {
        restricted: true,
        ..AttrAnnotations::default()
    };
    for annotation in &attr.annotations {
        out.names.push(annotation.name.name.clone());
        apply(annotation, &mut out);
    }
    out
}

fn apply(annotation: &Annotation, out: &mut AttrAnnotations) {
    let positional: Vec<Value> = annotation
        .args
        .iter()
        .filter(|a| a.name.is_none())
        .filter_map(|a| literal(&a.value.kind))
        .collect();
    let named = |key: &str| named(&annotation.args, key);
    if let Some(Value::Bool(restricted)) = named("restricted") {
        out.restricted = restricted;
    }
    match annotation.name.name.as_str() {
        "Range" => {
            let number = |v: Option<Value>| match v {
                Some(Value::Number(n)) => Some(n),
                _ => None,
            };
            let numbers: Vec<f64> = positional
                .iter()
                .filter_map(|v| number(Some(v.clone())))
                .collect();
            let (min, max) = match (number(named("min")), number(named("max"))) {
                (Some(min), Some(max)) => (Some(min), Some(max)),
                _ if numbers.len() == 2 && positional.len() == 2 => {
                    (Some(numbers[0]), Some(numbers[1]))
                }
                _ => (None, None),
            };
            match (min, max) {
                (Some(min), Some(max)) => {
                    out.range = Some(AttrRange {
                        min: min.min(max),
                        max: min.max(max),
                        step: number(named("stepsize"))
                            .filter(|s| *s > 0.0)
                            .unwrap_or(0.0),
                    });
                }
                // CityEngine's older spelling of a choice: `@Range("a", "b", "c")`.
                _ if !positional.is_empty() => out.choices = Some(positional),
                _ => {}
            }
        }
        "Enum" => {
            if let Some(Value::Str(name)) = named("valuesAttr") {
                out.values_attr = Some(name.to_string());
            } else if let Some(ExprKind::Name(name)) = annotation
                .args
                .iter()
                .find(|a| a.name.as_ref().is_some_and(|n| n.name == "valuesAttr"))
                .map(|a| &a.value.kind)
            {
                out.values_attr = Some(name.clone());
            }
            if !positional.is_empty() {
                out.choices = Some(positional);
            }
        }
        "Color" => out.color = true,
        "Group" => {
            out.group = positional
                .iter()
                .filter_map(|v| match v {
                    Value::Str(s) => Some(s.to_string()),
                    _ => None,
                })
                .collect();
            out.group_order = match positional.last() {
                Some(Value::Number(n)) => Some(*n),
                _ => None,
            };
        }
        "Order" => {
            if let Some(Value::Number(n)) = positional.first() {
                out.order = Some(*n);
            }
        }
        "Hidden" => out.hidden = true,
        "Description" => out.description = first_string(&positional),
        "DisplayName" => out.display_name = first_string(&positional),
        "Angle" => out.unit = Some(Unit::Angle),
        "Distance" => out.unit = Some(Unit::Distance),
        "Percent" => out.unit = Some(Unit::Percent),
        "File" | "Directory" | "MaterialFile" => out.file = true,
        _ => {}
    }
}

fn first_string(values: &[Value]) -> Option<String> {
    match values.first() {
        Some(Value::Str(s)) => Some(s.to_string()),
        _ => None,
    }
}

/// The literal value of the argument named `key`.
fn named(args: &[Argument], key: &str) -> Option<Value> {
    args.iter()
        .find(|a| a.name.as_ref().is_some_and(|n| n.name == key))
        .and_then(|a| literal(&a.value.kind))
}

/// A literal's value: a number (perhaps negated), a string or a boolean.
fn literal(kind: &ExprKind) -> Option<Value> {
    match kind {
        ExprKind::Number(n) => Some(Value::Number(*n)),
        ExprKind::String(s) => Some(Value::string(s)),
        ExprKind::Bool(b) => Some(Value::Bool(*b)),
        ExprKind::Unary {
            op: UnaryOp::Neg,
            operand,
        } => match literal(&operand.kind) {
            Some(Value::Number(n)) => Some(Value::Number(-n)),
            _ => None,
        },
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn annotations(text: &str) -> Vec<AttrAnnotations> {
        let source = shapegram_syntax::SourceFile::new("t.cga", text);
        let parsed = shapegram_syntax::parse(&source);
        assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
        parsed.grammar.attrs.iter().map(attr_annotations).collect()
    }

    #[test]
    fn ranges_in_both_spellings_with_steps() {
        let found = annotations(
            "@Range(min=1, max=4, stepsize=1, restricted=false)\nattr a = 2\n\
             @Range(28,150)\nattr b = 30\n@Range(-5, 5)\nattr c = 0\n",
        );
        assert_eq!(
            found[0].range,
            Some(AttrRange {
                min: 1.0,
                max: 4.0,
                step: 1.0
            })
        );
        assert!(!found[0].restricted);
        assert_eq!(
            found[1].range,
            Some(AttrRange {
                min: 28.0,
                max: 150.0,
                step: 0.0
            })
        );
        assert!(found[1].restricted);
        assert_eq!(
            found[2].range,
            Some(AttrRange {
                min: -5.0,
                max: 5.0,
                step: 0.0
            })
        );
    }

    #[test]
    fn choices_colours_groups_and_the_rest() {
        let found = annotations(
            "@Enum(\"Visualization\",\"3DPrint\")\n@Group(\"Building\", \"Roof\", 2) @Order(3)\nattr mode = \"Visualization\"\n\
             @Range(\"commercial\", \"residential\")\nattr use = \"commercial\"\n\
             @Color @Description(\"Wall colour\") @DisplayName(\"Wall\")\nattr wall = \"#ffffff\"\n\
             @Hidden @Hiddden @Percent\nattr share = 0.2\n@Enum(valuesAttr=names)\nattr pick = \"a\"\n",
        );
        assert_eq!(
            found[0].choices,
            Some(vec![
                Value::string("Visualization"),
                Value::string("3DPrint")
            ])
        );
        assert_eq!(found[0].group, ["Building", "Roof"]);
        assert_eq!(found[0].group_order, Some(2.0));
        assert_eq!(found[0].order, Some(3.0));
        assert_eq!(
            found[1].choices,
            Some(vec![
                Value::string("commercial"),
                Value::string("residential")
            ])
        );
        assert!(found[2].color);
        assert_eq!(found[2].description.as_deref(), Some("Wall colour"));
        assert_eq!(found[2].display_name.as_deref(), Some("Wall"));
        assert!(found[3].hidden);
        assert_eq!(found[3].unit, Some(Unit::Percent));
        assert_eq!(found[3].names, ["Hidden", "Hiddden", "Percent"]);
        assert_eq!(found[4].values_attr.as_deref(), Some("names"));
        assert_eq!(found[4].choices, None);
    }
}
