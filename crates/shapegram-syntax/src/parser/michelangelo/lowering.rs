//! Lowering a Michelangelo rule call to the goal rules of the common AST: each rule kind's
//! arguments checked and turned into the main syntax's statements.

use super::*;

impl Parser<'_> {
    pub(super) fn lower_rule(
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
