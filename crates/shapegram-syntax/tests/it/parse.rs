//! The constructs of the main syntax, each with its exact tree.

use crate::common;

use common::{args_str, expr, parse_ok, rule_body};
use shapegram_syntax::Span;
use shapegram_syntax::ast::ImportAttribute;
use shapegram_syntax::ast::{
    Argument, Block, BlockEntry, Body, Call, Dialect, Expr, ExprKind, Ident, Rule, Stmt,
};

/// The value of `attr x = …` in a one-line grammar, as an S-expression.
fn value(source: &str) -> String {
    let g = parse_ok(&format!("attr x = {source}"));
    expr(&g.attrs[0].value)
}

/// The body of `A --> …`, as an S-expression.
fn body(source: &str) -> String {
    rule_body(&parse_ok(&format!("A --> {source}")), "A")
}

fn ident(name: &str, start: usize, end: usize) -> Ident {
    Ident {
        name: name.into(),
        span: Span::new(start, end),
    }
}

fn number(n: f64, start: usize, end: usize) -> Expr {
    Expr {
        kind: ExprKind::Number(n),
        span: Span::new(start, end),
    }
}

#[test]
fn empty_input_gives_an_empty_grammar() {
    for text in [
        "",
        "   \n\t\n",
        "// only a comment",
        "# only a comment\n",
        "/* block */",
    ] {
        let g = parse_ok(text);
        assert_eq!(g, Default::default(), "{text:?}");
        assert_eq!(g.dialect, Dialect::Cga);
    }
}

#[test]
fn rule_with_exact_tree_and_spans() {
    let text = "Lot --> extrude(10) Mass.";
    let g = parse_ok(text);
    assert_eq!(
        g.rules,
        vec![Rule {
            annotations: vec![],
            name: ident("Lot", 0, 3),
            params: vec![],
            body: Body::Sequence(vec![
                Stmt::Call(Call {
                    name: ident("extrude", 8, 15),
                    args: Some(vec![Argument {
                        name: None,
                        value: number(10.0, 16, 18),
                    }]),
                    block: None,
                    terminal: false,
                    span: Span::new(8, 19),
                }),
                Stmt::Call(Call {
                    name: ident("Mass", 20, 24),
                    args: None,
                    block: None,
                    terminal: true,
                    span: Span::new(20, 25),
                }),
            ]),
            span: Span::new(0, 25),
        }]
    );
}

#[test]
fn split_block_with_exact_tree_and_spans() {
    let text = "F --> split(y){ ~2 : A | { 1 : B }* }*";
    let g = parse_ok(text);
    let Body::Sequence(stmts) = &g.rules[0].body else {
        panic!("not a sequence");
    };
    let Stmt::Call(split) = &stmts[0] else {
        panic!("not a call");
    };
    let leaf = |name: &str, start: usize| {
        Stmt::Call(Call {
            name: ident(name, start, start + 1),
            args: None,
            block: None,
            terminal: false,
            span: Span::new(start, start + 1),
        })
    };
    assert_eq!(
        split.block,
        Some(Block {
            entries: vec![
                BlockEntry::Part {
                    key: Expr {
                        kind: ExprKind::Floating(Box::new(number(2.0, 17, 18))),
                        span: Span::new(16, 18),
                    },
                    merge: false,
                    body: vec![leaf("A", 21)],
                    span: Span::new(16, 22),
                },
                BlockEntry::Group(Block {
                    entries: vec![BlockEntry::Part {
                        key: number(1.0, 27, 28),
                        merge: false,
                        body: vec![leaf("B", 31)],
                        span: Span::new(27, 32),
                    }],
                    repeat: true,
                    span: Span::new(25, 35),
                }),
            ],
            repeat: true,
            span: Span::new(14, 38),
        })
    );
    assert_eq!(split.span, Span::new(6, 38));
    assert_eq!(&text[g.rules[0].span.range()], text);
}

#[test]
fn version_annotations_attrs_consts_and_functions() {
    let g = parse_ok(
        r#"version "2023.0"
@Group("Facade", 3) @Range(min=5, max=40)
attr height = 12
const floorH = 3.5
tileW = floorH * 2
area(w, h) = w * h
@StartRule
Lot --> X"#,
    );
    assert_eq!(g.version.as_ref().map(|v| v.value.as_str()), Some("2023.0"));
    assert_eq!(g.version.as_ref().map(|v| v.span), Some(Span::new(8, 16)));

    let attr = &g.attrs[0];
    assert_eq!(attr.name.name, "height");
    assert_eq!(expr(&attr.value), "12");
    let annotations: Vec<String> = attr
        .annotations
        .iter()
        .map(|a| format!("{}({})", a.name.name, args_str(&a.args)))
        .collect();
    assert_eq!(
        annotations,
        ["Group(\"Facade\", 3)", "Range(min=5, max=40)"]
    );

    assert_eq!(g.consts.len(), 2);
    assert_eq!(
        (g.consts[0].name.name.as_str(), g.consts[0].is_const),
        ("floorH", true)
    );
    assert_eq!(
        (g.consts[1].name.name.as_str(), g.consts[1].is_const),
        ("tileW", false)
    );
    assert_eq!(expr(&g.consts[1].value), "(floorH * 2)");

    let f = &g.functions[0];
    assert_eq!(f.name.name, "area");
    let params: Vec<&str> = f.params.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(params, ["w", "h"]);
    assert_eq!(expr(&f.body), "(w * h)");

    assert!(g.rules[0].is_start_rule());
    assert!(g.unsupported.is_empty());
}

#[test]
fn declaration_spans_cover_keyword_to_value() {
    let text = "attr a = 1 + 2\nconst b = 3\nf(x) = x\nR(p) --> S";
    let g = parse_ok(text);
    assert_eq!(&text[g.attrs[0].span.range()], "attr a = 1 + 2");
    assert_eq!(&text[g.consts[0].span.range()], "const b = 3");
    assert_eq!(&text[g.functions[0].span.range()], "f(x) = x");
    assert_eq!(&text[g.rules[0].span.range()], "R(p) --> S");
    assert_eq!(g.rules[0].params[0], ident("p", 38, 39));
}

#[test]
fn const_with_parameters_is_a_function_and_typed_parameters_are_accepted() {
    let g = parse_ok("const f(a) = a\nR(float h, string s, bool b, float[] v) --> X");
    assert_eq!(g.functions[0].name.name, "f");
    let params: Vec<&str> = g.rules[0].params.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(params, ["h", "s", "b", "v"]);
}

#[test]
fn rule_bodies_end_at_the_next_declaration_without_newlines() {
    let g = parse_ok("A --> B C(1) D --> E F(p) --> G h = 1 i(x) = x J --> K");
    let rules: Vec<(String, String)> = g
        .rules
        .iter()
        .map(|r| (r.name.name.clone(), common::body(&r.body)))
        .collect();
    assert_eq!(
        rules,
        [
            ("A".to_string(), "(B C(1))".to_string()),
            ("D".into(), "(E)".into()),
            ("F".into(), "(G)".into()),
            ("J".into(), "(K)".into()),
        ]
    );
    assert_eq!(g.consts[0].name.name, "h");
    assert_eq!(g.functions[0].name.name, "i");
}

#[test]
fn empty_rule_bodies() {
    let g = parse_ok("A -->\nB --> C\nD -->");
    assert_eq!(rule_body(&g, "A"), "()");
    assert_eq!(rule_body(&g, "B"), "(C)");
    assert_eq!(rule_body(&g, "D"), "()");
}

#[test]
fn dotted_names_and_the_terminal_marker() {
    assert_eq!(
        body("set(material.color.r, scope.sx) volume.Slab. End. ruleB.foo X.\nY"),
        "(set(material.color.r, scope.sx) volume.Slab. End. ruleB.foo X. Y)"
    );
    let g = parse_ok("volume.Slab --> X\nA --> B.");
    assert_eq!(g.rules[0].name.name, "volume.Slab");
    assert_eq!(rule_body(&g, "A"), "(B.)");
}

#[test]
fn push_pop_and_nil() {
    assert_eq!(
        body("[ t(0, 1, 0) A ] [ B. ] NIL"),
        "([ t(0, 1, 0) A ] [ B. ] NIL)"
    );
}

#[test]
fn calls_with_and_without_arguments_and_spaces() {
    assert_eq!(
        body(
            "reverseNormals color (\"#fff\") Facade(2, 1,\n 3) report(\"x\", geometry.area()) A()"
        ),
        "(reverseNormals color(\"#fff\") Facade(2, 1, 3) report(\"x\", geometry.area()) A())"
    );
}

#[test]
fn blocks_repeats_groups_and_merges() {
    assert_eq!(
        body("split(y){ 4.5 : G | { ~3 : F }* | '0.5 : H I }*"),
        "(split(y){4.5 : (G) | {~3 : (F)}* | '0.5 : (H I)}*)"
    );
    assert_eq!(
        body("comp(f){ front : A | side = B | top : NIL | 0 : C | all : }"),
        "(comp(f){front : (A) | side = (B) | top : (NIL) | 0 : (C) | all : ()})"
    );
    assert_eq!(
        body("split(x){ ~1 : split(y){ 1 : [ A ] | { ~1 : B | 2 : C }* } | 1 : D }"),
        "(split(x){~1 : (split(y){1 : ([ A ]) | {~1 : (B) | 2 : (C)}*}) | 1 : (D)})"
    );
    assert_eq!(
        body("split(x){ (5 - 0.3) * dx : A }  split(y){ 2.5 : B } *"),
        "(split(x){((5 - 0.3) * dx) : (A)} split(y){2.5 : (B)}*)"
    );
}

#[test]
fn size_prefixes_take_the_whole_expression() {
    assert_eq!(
        body("split(x){ ~scope.sx/n : A | '(1/3) : B | ~rand(1, 2) : C | '1.85*8 : D }"),
        "(split(x){~(scope.sx / n) : (A) | '(1 / 3) : (B) | ~rand(1, 2) : (C) | '(1.85 * 8) : (D)})"
    );
    assert_eq!(
        body("s('1, '0.5, 2) t('-0.2, 0, 0)"),
        "(s('1, '0.5, 2) t('(-0.2), 0, 0))"
    );
}

#[test]
fn case_bodies() {
    assert_eq!(
        body("case a > 1 : B C case b : D else : E"),
        "(case [(a > 1) => (B C)] [b => (D)] [else => (E)])"
    );
    assert_eq!(body("case a : B"), "(case [a => (B)] [else => ()])");
}

#[test]
fn nested_cases_take_one_else_each() {
    // As in envelope2002.cga: the inner `case` takes the first `else`, the outer the second.
    assert_eq!(
        body("case a : case b : X else : NIL else : Y Z."),
        "(case [a => (case [b => (X)] [else => (NIL)])] [else => (Y Z.)])"
    );
    // An `else` body may itself start with `case`.
    assert_eq!(
        body("case a : X else : case b : Y case c : Z else : W"),
        "(case [a => (X)] [else => (case [b => (Y)] [c => (Z)] [else => (W)])])"
    );
}

#[test]
fn stochastic_bodies() {
    assert_eq!(
        body("30% : A B 20.5 % : C else : D"),
        "(pct [30 => (A B)] [20.5 => (C)] [else => (D)])"
    );
    assert_eq!(body("p% : A else : B"), "(pct [p => (A)] [else => (B)])");
    assert_eq!(body("(p * 2)% : A"), "(pct [(p * 2) => (A)] [else => ()])");
    assert_eq!(
        body("case a : 80% : X else : NIL else : Y"),
        "(case [a => (pct [80 => (X)] [else => (NIL)])] [else => (Y)])"
    );
    // Each rule of several on one line keeps its own choice.
    let g = parse_ok("A -->10%: X else: NIL\nB -->10%: Y else: NIL");
    assert_eq!(rule_body(&g, "B"), "(pct [10 => (Y)] [else => (NIL)])");
}

#[test]
fn construct_spans_in_bodies() {
    let text = "A --> case x : B else : C";
    let g = parse_ok(text);
    let Body::Cases { span, .. } = &g.rules[0].body else {
        panic!("not cases");
    };
    assert_eq!(&text[span.range()], "case x : B else : C");
    let text = "A --> 30% : B else : C";
    let g = parse_ok(text);
    let Body::Stochastic { span, .. } = &g.rules[0].body else {
        panic!("not stochastic");
    };
    assert_eq!(&text[span.range()], "30% : B else : C");
}

#[test]
fn expression_precedence() {
    assert_eq!(
        value("1 + 2 * 3 - 4 / 5 % 6"),
        "((1 + (2 * 3)) - ((4 / 5) % 6))"
    );
    assert_eq!(
        value("a || b && c == d < e + f * -g"),
        "(a || (b && (c == (d < (e + (f * (-g)))))))"
    );
    assert_eq!(
        value("!a && b != c <= d >= e > f"),
        "((!a) && (b != (((c <= d) >= e) > f)))"
    );
    assert_eq!(value("(1 + 2) * 3"), "((1 + 2) * 3)");
    assert_eq!(value("a ? b : c ? d : e"), "(a ? b : (c ? d : e))");
    assert_eq!(value("x > 1 ? 2 + 3 : 4"), "((x > 1) ? (2 + 3) : 4)");
    assert_eq!(value("-a[0] * f(1)[2]"), "((-a[0]) * f(1)[2])");
    assert_eq!(value("xi%3 == 0"), "((xi % 3) == 0)");
}

#[test]
fn literals_and_strings() {
    assert_eq!(value("12"), "12");
    assert_eq!(value("3.5"), "3.5");
    assert_eq!(value(".5"), "0.5");
    assert_eq!(value("1e-3"), "0.001");
    assert_eq!(value("2E+2"), "200");
    let g = parse_ok("attr big = 1e308");
    assert_eq!(g.attrs[0].value.kind, ExprKind::Number(1e308));
    assert_eq!(value("true && !false"), "(true && (!false))");
    let g = parse_ok(r#"attr s = "a\"b\\c\nd\te""#);
    assert_eq!(
        g.attrs[0].value.kind,
        ExprKind::String("a\"b\\c\nd\te".into())
    );
    let g = parse_ok("attr s = \"héllo wörld ✓\" # ünïcödé comment");
    assert_eq!(
        g.attrs[0].value.kind,
        ExprKind::String("héllo wörld ✓".into())
    );
}

#[test]
fn arrays_and_rows() {
    assert_eq!(value("[]"), "[]");
    assert_eq!(value("[1, \"a\", true]"), "[1, \"a\", true]");
    assert_eq!(value("[1, 2, 3; 4, 5, 6]"), "[[1, 2, 3], [4, 5, 6]]");
    assert_eq!(value("[x[0], [1]][1]"), "[x[0], [1]][1]");
}

#[test]
fn calls_with_named_and_prefixed_arguments() {
    assert_eq!(value("f(1, min = 2, '3, ~4)"), "f(1, min=2, '3, ~4)");
    assert_eq!(value("f(a == b)"), "f((a == b))");
    assert_eq!(
        value("geometry.isRectangular(1)"),
        "geometry.isRectangular(1)"
    );
}

#[test]
fn comp_function_lowers_to_named_arguments() {
    let g = parse_ok("A --> setback(comp(fe){ all : 2 | 0 : x + 1 }) { all : B | remainder : C }");
    assert_eq!(
        rule_body(&g, "A"),
        "(setback(comp(fe, all=2, 0=(x + 1))){all : (B) | remainder : (C)})"
    );
}

#[test]
fn case_and_percentage_expressions() {
    assert_eq!(
        value("case a > 1 : 2 case b : 3 else : 4"),
        "(case [(a > 1) => 2] [b => 3] [else => 4])"
    );
    assert_eq!(
        value("20% : 0 else : rand(3, 6)"),
        "(pct [20 => 0] [else => rand(3, 6)])"
    );
    assert_eq!(
        value("case t == \"v\" : \"p\" else : 80% : \"c\" else : \"p\""),
        "(case [(t == \"v\") => \"p\"] [else => (pct [80 => \"c\"] [else => \"p\"])])"
    );
    assert_eq!(
        body("set(n, 25% : \"S\" 25% : \"A\" else : \"H\") X"),
        "(set(n, (pct [25 => \"S\"] [25 => \"A\"] [else => \"H\"])) X)"
    );
    let g = parse_ok("side = 50% :0 else:1\nA --> B");
    assert_eq!(expr(&g.consts[0].value), "(pct [50 => 0] [else => 1])");
}

#[test]
fn comments_of_all_three_kinds() {
    let g = parse_ok(
        "/* header\n * block */\n# hash comment\nA --> B // line comment\n  C # after\n/**/D --> E",
    );
    assert_eq!(rule_body(&g, "A"), "(B C)");
    assert_eq!(rule_body(&g, "D"), "(E)");
    // `#` inside a string is not a comment.
    let g = parse_ok("attr c = \"#fff\" # colour");
    assert_eq!(expr(&g.attrs[0].value), "\"#fff\"");
}

#[test]
fn annotations_without_spaces_and_with_comments_between() {
    let g = parse_ok("@Order(1)@Hidden #@Range(0, 1)\n@Enum(1, 2)\nattr a = 1");
    let names: Vec<&str> = g.attrs[0]
        .annotations
        .iter()
        .map(|a| a.name.name.as_str())
        .collect();
    assert_eq!(names, ["Order", "Hidden", "Enum"]);
}

#[test]
fn imports_are_recorded_and_styles_warned_about() {
    let text = "import b : \"b.cga\" (h = 10, w)\nimport \"c.cga\"\nattr h = 1\n@Description(\"x\")\nstyle Red\nattr h = 2\nA --> B\nstyle Blue\nattr h = 3";
    let (source, parsed) = common::parse_str(text);
    let imports: Vec<String> = parsed
        .grammar
        .imports
        .iter()
        .map(|i| {
            let attributes: Vec<String> = i
                .attributes
                .iter()
                .flatten()
                .map(|a| match a {
                    ImportAttribute::Set(name, value) => format!("{}={}", name.name, expr(value)),
                    ImportAttribute::Keep(name) => name.name.clone(),
                })
                .collect();
            format!(
                "{:?} {} {:?} [{}]",
                i.id.as_ref().map(|id| id.name.as_str()),
                i.path.value,
                &text[i.span.range()],
                attributes.join(" ")
            )
        })
        .collect();
    assert_eq!(
        imports,
        [
            r#"Some("b") b.cga "import b : \"b.cga\" (h = 10, w)" [h=10 w]"#,
            r#"None c.cga "import \"c.cga\"" []"#,
        ]
    );
    let what: Vec<(&str, &str)> = parsed
        .grammar
        .unsupported
        .iter()
        .map(|u| (u.what.as_str(), &text[u.span.range()]))
        .collect();
    assert_eq!(what, [("style", "style Red"), ("style", "style Blue")]);
    assert!(parsed.diagnostics.iter().all(|d| !d.is_error()));
    let messages: Vec<&str> = parsed
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(
        messages,
        [
            "`style` is derived only when chosen",
            "`style` is derived only when chosen",
        ]
    );
    // Only the default style's declarations are kept.
    assert_eq!(parsed.grammar.attrs.len(), 1);
    assert_eq!(expr(&parsed.grammar.attrs[0].value), "1");
    assert!(parsed.grammar.rules.is_empty());
    assert_eq!(
        source.render(&parsed.diagnostics[0]),
        "warning: `style` is derived only when chosen\n --> test.cga:5:1\n  |\n5 | style Red\n  | ^^^^^^^^^ not derived by default\n  = hint: the default style is derived; `shapegram derive --style Red` derives this one\n"
    );
}

#[test]
fn byte_order_mark_and_crlf_line_endings() {
    let g = parse_ok("\u{feff}attr a = 1\r\nA --> B\r\n  C.\r\nD --> E # note\r\n");
    assert_eq!(rule_body(&g, "A"), "(B C.)");
    assert_eq!(rule_body(&g, "D"), "(E)");
    let (source, parsed) = common::parse_str("A --> B\r\nC --> split(x){ 1 X }\r\n");
    assert_eq!(
        common::render_all(&source, &parsed.diagnostics),
        "error: expected `:` after the split size, found `X`\n --> test.cga:2:19\n  |\n2 | C --> split(x){ 1 X }\n  |                   ^ expected `:` here\n"
    );
}

#[test]
fn colon_ranges_and_two_indices_in_brackets() {
    assert_eq!(value("[1:5]"), "[1:5]");
    assert_eq!(value("[0:2 ; 3, 3, 3]"), "[[0:2], [3, 3, 3]]");
    assert_eq!(value("m[1:n, 0]"), "m[1:n, 0]");
    assert_eq!(value("m[n:-1:1, 4]"), "m[n:(-1):1, 4]");
    assert_eq!(value("m[i + 1]"), "m[(i + 1)]");
    // Outside brackets a colon still ends a case condition.
    assert_eq!(
        body("case a[0:1] == b : X else : Y"),
        "(case [(a[0:1] == b) => (X)] [else => (Y)])"
    );
}

#[test]
fn scatter_takes_a_body_without_a_selector() {
    assert_eq!(
        body("scatter(surface, 10, uniform){ Plant.Generate(p) } NIL"),
        "(scatter(surface, 10, uniform){all : (Plant.Generate(p))} NIL)"
    );
}

#[test]
fn styles_lay_their_declarations_over_the_default_style() {
    let text = "attr h = 10\nattr w = 4\nLot --> extrude(h) Mass\n\
                style Tall\nattr h = 30\nLot --> extrude(h) Tower\n\
                style Slim extends Tall\nattr w = 2\nattr roof = 1\n\
                style Loop extends Loop\nattr h = 1";
    let (_, parsed) = common::parse_str(text);
    let g = &parsed.grammar;
    let names: Vec<(&str, Option<&str>)> = g
        .styles
        .iter()
        .map(|s| {
            (
                s.name.name.as_str(),
                s.base.as_ref().map(|b| b.name.as_str()),
            )
        })
        .collect();
    assert_eq!(
        names,
        [
            ("Tall", None),
            ("Slim", Some("Tall")),
            ("Loop", Some("Loop"))
        ]
    );
    // The grammar itself is the default style.
    let attrs = |g: &shapegram_syntax::ast::Grammar| -> Vec<String> {
        g.attrs
            .iter()
            .map(|a| format!("{}={}", a.name.name, expr(&a.value)))
            .collect()
    };
    assert_eq!(attrs(g), ["h=10", "w=4"]);
    let slim = g.with_style("Slim").unwrap();
    assert_eq!(attrs(&slim), ["h=30", "w=2", "roof=1"]);
    assert_eq!(slim.rules.len(), 1);
    assert_eq!(
        common::stmts_str(match &slim.rules[0].body {
            shapegram_syntax::ast::Body::Sequence(s) => s,
            other => panic!("{other:?}"),
        }),
        "(extrude(h) Tower)"
    );
    assert!(slim.styles.is_empty());
    assert_eq!(attrs(&g.with_style("Default").unwrap()), ["h=10", "w=4"]);
    assert_eq!(
        g.with_style("Red").unwrap_err(),
        "no style `Red` (the styles: Default, Tall, Slim, Loop)"
    );
    assert_eq!(
        g.with_style("Loop").unwrap_err(),
        "style `Loop` extends itself"
    );
}

#[test]
fn perimeter_split_sections_carry_length_and_depth_and_the_remainder_block_follows() {
    assert_eq!(
        body("splitAndSetbackPerimeter(6) { 40 : 5 : Y | ~2 : rand(3, 4) : B }* { remainder : G }"),
        "(splitAndSetbackPerimeter(6){{[40, 5] : (Y) | [~2, rand(3, 4)] : (B)}* | remainder : (G)})"
    );
    assert_eq!(
        body("splitAndSetbackPerimeter(0) { 2 : 1 : X }"),
        "(splitAndSetbackPerimeter(0){{[2, 1] : (X)}})"
    );
    let (source, parsed) = common::parse_str("A --> splitAndSetbackPerimeter(0) { 2 : X }");
    let shown = common::render_all(&source, &parsed.diagnostics);
    assert!(
        shown.contains("expected `:` after the section's depth"),
        "{shown}"
    );
}

#[test]
fn boolean_operations_take_two_bodies_or_one_successor() {
    assert_eq!(
        body("union { A. | t(1, 0, 0) B. } C"),
        "(union{all : (A.) | all : (t(1, 0, 0) B.)} C)"
    );
    assert_eq!(
        body("subtract(swap) Hole Next"),
        "(subtract(swap){all : (Hole)} Next)"
    );
    assert_eq!(
        body("inline(unify) split(y) { 1 : A | ~1 : B } C"),
        "(inline(unify){all : (split(y){1 : (A) | ~1 : (B)})} C)"
    );
    // With nothing to derive after it, the operation is left for the compiler to report.
    assert_eq!(body("extrude(1) union"), "(extrude(1) union)");
}
