//! The Müller 2006 and SGL notations: each construct lowers to exactly the tree of its CGA
//! equivalent (compared as S-expressions, spans aside), detection, and diagnostics.

use crate::common;

use common::{body, expr, render_all};
use proptest::prelude::*;
use shapegram_syntax::ast::{Body, Dialect, Grammar};
use shapegram_syntax::{SourceFile, Span, detect, parse, parse_as};

// --- Helpers --------------------------------------------------------------------------------

/// The whole grammar as text: attributes, constants, functions and rules (with annotations and
/// parameters), one per line.
fn sexpr(g: &Grammar) -> String {
    let mut out = String::new();
    for a in &g.attrs {
        out += &format!("attr {} = {}\n", a.name.name, expr(&a.value));
    }
    for c in &g.consts {
        out += &format!("const {} = {}\n", c.name.name, expr(&c.value));
    }
    for f in &g.functions {
        let params: Vec<&str> = f.params.iter().map(|p| p.name.as_str()).collect();
        out += &format!(
            "fn {}({}) = {}\n",
            f.name.name,
            params.join(", "),
            expr(&f.body)
        );
    }
    for r in &g.rules {
        for a in &r.annotations {
            out += &format!("@{} ", a.name.name);
        }
        let params: Vec<&str> = r.params.iter().map(|p| p.name.as_str()).collect();
        out += &format!(
            "{}({}) --> {}\n",
            r.name.name,
            params.join(", "),
            body(&r.body)
        );
    }
    out
}

/// Parses `text` in `dialect`, asserting that there are no diagnostics.
fn read(text: &str, dialect: Dialect) -> Grammar {
    let source = SourceFile::new("test", text);
    let parsed = parse_as(&source, dialect);
    assert!(
        parsed.diagnostics.is_empty(),
        "unexpected diagnostics:\n{}",
        render_all(&source, &parsed.diagnostics)
    );
    assert_eq!(parsed.grammar.dialect, dialect);
    parsed.grammar
}

/// Asserts that `muller` (Müller notation) lowers to the tree of `cga` (main syntax).
#[track_caller]
fn same_muller(muller: &str, cga: &str) {
    assert_eq!(
        sexpr(&read(muller, Dialect::Muller2006)),
        sexpr(&read(cga, Dialect::Cga)),
        "{muller}"
    );
}

/// The CGA text of a lowered SGL rule: the depth guard, the depth count, the statements and
/// `NIL` (with `s(1, 1, 1)` first in the start rule).
fn sgl_rule(name: &str, start: bool, stmts: &str) -> String {
    let (annotation, scale) = if start {
        ("@StartRule\n", "s(1, 1, 1) ")
    } else {
        ("", "")
    };
    format!(
        "{annotation}{name} --> case sgl_depth >= max_depth : NIL\n  else : {scale}set(sgl_depth, sgl_depth + 1) {stmts} NIL\n"
    )
}

/// The attributes the SGL lowering adds when the header sets no limit.
const SGL_ATTRS: &str = "attr max_depth = 16\nattr sgl_depth = 0\n";

/// Asserts that `sgl` lowers to the tree of `cga`.
#[track_caller]
fn same_sgl(sgl: &str, cga: &str) {
    assert_eq!(
        sexpr(&read(sgl, Dialect::Sgl)),
        sexpr(&read(cga, Dialect::Cga)),
        "{sgl}"
    );
}

/// All diagnostics of `text` read in `dialect`, rendered.
fn rendered(text: &str, dialect: Dialect) -> String {
    let source = SourceFile::new("test", text);
    render_all(&source, &parse_as(&source, dialect).diagnostics)
}

fn examples() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

fn example(name: &str) -> String {
    std::fs::read_to_string(examples().join(name)).expect("the example exists")
}

// --- Müller 2006: rules -----------------------------------------------------------------------

#[test]
fn muller_arrows_rule_numbers_and_lowercase_names() {
    for arrow in [
        "~>",
        "-->",
        "\\leadsto",
        "$\\leadsto$",
        "\\rightarrow",
        "→",
        "⇝",
    ] {
        same_muller(
            &format!("1: lot {arrow} mass\n2: mass {arrow} roof"),
            "lot --> mass\nmass --> roof",
        );
    }
    same_muller(
        "lot ~>\n  facades\n  sidewings",
        "lot --> facades sidewings",
    );
}

#[test]
fn muller_empty_word_in_all_spellings() {
    for nil in ["ϵ", "ε", "epsilon", "\\epsilon", "$\\epsilon$", "NIL"] {
        same_muller(&format!("a ~> {nil}"), "a --> NIL");
    }
}

#[test]
fn muller_probabilities_become_one_stochastic_rule() {
    same_muller(
        "x ~> A : 0.5\n  ~> B : 0.3\n  ~> ϵ : 0.2",
        "x --> 50% : A 30% : B else : NIL",
    );
    // Alternatives may be written as separate rules, anywhere in the file; probabilities are
    // normalised.
    same_muller(
        "x ~> A : 1\ny ~> C\nx ~> B : 3",
        "x --> 25% : A else : B\ny --> C",
    );
    // Non-literal probabilities give the percentage expressions.
    same_muller(
        "x ~> A : p\n  ~> B : 1 - p",
        "x --> p / (p + (1 - p)) * 100% : A else : B",
    );
}

#[test]
fn muller_conditions_become_cases_and_continuations_share_them() {
    same_muller(
        "fac(h) : h > 9 ~> A : 0.5\n  ~> B : 0.5\nfac(h) : h > 3 ~> C\nfac(h) ~> D",
        "fac(h) --> case h > 9 : 50% : A else : B case h > 3 : C else : D",
    );
    // A lone probability is ignored; a rule with conditions only leaves other shapes alone.
    same_muller(
        "t : Scope.sx < 2 ~> W : 1",
        "t --> case scope.sx < 2 : W else :",
    );
}

#[test]
fn muller_figure_12_as_printed() {
    same_muller(
        r#"1: lot \leadsto S(1r,building_height,1r)
Subdiv("Z",Scope.sz*rand(0.3,0.5),1r){ facades | sidewings }
2: sidewings \leadsto
Subdiv("X",Scope.sx*rand(0.2,0.6),1r){ siding | ϵ }
Subdiv("X",1r,Scope.sx*rand(0.2,0.6)){ ϵ | siding }
3: siding
 \leadsto S(1r,1r,Scope.sz*rand(0.4,1.0)) facades : 0.5
 \leadsto S(1r,Scope.sy*rand(0.2,0.9),Scope.sz*rand(0.4,1.0))
facades : 0.3
 $\leadsto \epsilon$: 0.2
4: facades \leadsto Comp("sidefaces"){ facade }"#,
        "lot --> s('1, building_height, '1)
           split(z){ scope.sz*rand(0.3,0.5) : facades | ~1 : sidewings }
         sidewings --> split(x){ scope.sx*rand(0.2,0.6) : siding | ~1 : NIL }
                       split(x){ ~1 : NIL | scope.sx*rand(0.2,0.6) : siding }
         siding --> 50% : s('1, '1, scope.sz*rand(0.4,1.0)) facades
                    30% : s('1, scope.sy*rand(0.2,0.9), scope.sz*rand(0.4,1.0)) facades
                    else : NIL
         facades --> comp(f){ side : facade }",
    );
}

#[test]
fn muller_reads_the_main_syntax_declarations() {
    same_muller(
        "version \"1\"\nattr h = 12\nconst w = 2\nhalf(x) = x / 2\n@StartRule\nlot ~> S(1r, h, half(w)) mass",
        "version \"1\"\nattr h = 12\nconst w = 2\nhalf(x) = x / 2\n@StartRule\nlot --> s('1, h, half(w)) mass",
    );
}

// --- Müller 2006: operations ------------------------------------------------------------------

#[test]
fn muller_subdiv_and_repeat() {
    same_muller(
        "a ~> Subdiv(\"X\", 2, 1r, Scope.sx / 4, 0.5r){ B | C | D | E }",
        "a --> split(x){ 2 : B | ~1 : C | scope.sx / 4 : D | ~0.5 : E }",
    );
    same_muller(
        "a ~> Subdiv(Y, 1r, 1r){ B | [ T(0, 0, 1) C ] D }",
        "a --> split(y){ ~1 : B | ~1 : [ t(0, 0, 1) C ] D }",
    );
    same_muller("a ~> Subdiv(\"z\", 3){ B }", "a --> split(z){ 3 : B }");
    same_muller(
        "a ~> Repeat(\"Y\", 3){ floor }",
        "a --> split(y){ { ~3 : floor }* }",
    );
    same_muller(
        "a ~> Repeat(\"X\", 2r){ tile }",
        "a --> split(x){ { ~2 : tile }* }",
    );
    // Nested blocks.
    same_muller(
        "a ~> Subdiv(\"X\", 1r, 1r){ Repeat(\"Y\", 2){ B } | ε }",
        "a --> split(x){ ~1 : split(y){ { ~2 : B }* } | ~1 : NIL }",
    );
}

#[test]
fn muller_component_splits() {
    for (kind, cga) in [
        ("sidefaces", "comp(f){ side : B }"),
        ("faces", "comp(f){ all : B }"),
        ("topface", "comp(f){ top : B }"),
        ("bottomfaces", "comp(f){ bottom : B }"),
        ("frontface", "comp(f){ front : B }"),
        ("edges", "comp(e){ all : B }"),
        ("sideedges", "comp(e){ vertical : B }"),
        ("vertices", "comp(v){ all : B }"),
        ("SideFaces", "comp(f){ side : B }"),
    ] {
        same_muller(
            &format!("a ~> Comp(\"{kind}\"){{ B }}"),
            &format!("a --> {cga}"),
        );
    }
    same_muller(
        "a ~> Comp(\"faces\"){ B | C | ϵ }",
        "a --> comp(f){ 0 : B | 1 : C | 2 : NIL }",
    );
}

#[test]
fn muller_scope_operations() {
    same_muller(
        "a ~> S(1r, 5, 0.5r) T(1, 2r, -1) Rx(30) Ry(45) Rz(-10) R(1, 2, 3) B",
        "a --> s('1, 5, '0.5) t(1, '2, -1) r(30, 0, 0) r(0, 45, 0) r(0, 0, -10) r(1, 2, 3) B",
    );
    same_muller(
        "a ~> [ T(0, 0, 1) S(rand(1, 2), 1r, Scope.sz) B ] C(Scope.sx)",
        "a --> [ t(0, 0, 1) s(rand(1, 2), '1, scope.sz) B ] C(scope.sx)",
    );
}

#[test]
fn muller_instances_are_terminal_copies_named_after_the_rule() {
    same_muller(
        "a ~> I(cube) I(\"Cylinder\") I(\"window\") I(\"door.obj\") I(pyramid)",
        "a --> [ i(\"builtin:cube\") a. ] [ i(\"builtin:cylinder\") a. ] [ i(\"window.obj\") a. ] [ i(\"door.obj\") a. ] [ i(\"builtin:pyramid\") a. ]",
    );
    same_muller(
        "fac(h, w) ~> S(1r, h, 1r) I(\"cube\")",
        "fac(h, w) --> s('1, h, '1) [ i(\"builtin:cube\") fac(h, w). ]",
    );
}

#[test]
fn muller_figure_7_of_seed_001() {
    let g = read(&example("cga_shape_fig7.mul"), Dialect::Muller2006);
    assert_eq!(
        sexpr(&g),
        sexpr(&read(
            "A --> [ t(0,0,1) s(1,2,1) [ i(\"builtin:cube\") A. ] t(0,0,1) s(1.2,2.2,1) [ i(\"roof.obj\") A. ] ]
                   t(1,2,3) s(1,1,3) [ i(\"builtin:cylinder\") A. ]
                   t(0,0,3.5) s(0.7,0.7,0.5) [ i(\"builtin:cylinder\") A. ]
                   t(0,0,1) s(1,1,0.5) [ i(\"builtin:cone\") A. ]",
            Dialect::Cga
        ))
    );
}

#[test]
fn muller_spans_point_into_the_original_text() {
    let text = "lot ~> Subdiv(\"X\", 2, 1r){ A | B }";
    let g = read(text, Dialect::Muller2006);
    let Body::Sequence(stmts) = &g.rules[0].body else {
        panic!("not a sequence");
    };
    let shapegram_syntax::ast::Stmt::Call(split) = &stmts[0] else {
        panic!("not a call");
    };
    assert_eq!(split.name.name, "split");
    assert_eq!(&text[split.name.span.range()], "Subdiv");
    assert_eq!(&text[split.span.range()], &text[7..]);
    let block = split.block.as_ref().expect("a block");
    let shapegram_syntax::ast::BlockEntry::Part { key, span, .. } = &block.entries[1] else {
        panic!("not a part");
    };
    assert_eq!(&text[key.span.range()], "1r");
    assert_eq!(&text[span.range()], "B");
    assert_eq!(g.rules[0].span, Span::new(0, text.len()));
}

// --- SGL --------------------------------------------------------------------------------------

#[test]
fn sgl_rules_get_the_depth_guard_and_end_with_nil() {
    same_sgl(
        "start: { a() }\na: { T(1, 2, 3) }",
        &format!(
            "{SGL_ATTRS}{}{}",
            sgl_rule("start", true, "a"),
            sgl_rule("a", false, "t(1, 2, 3)")
        ),
    );
    // Without a rule called `start`, the first rule is the start rule.
    same_sgl(
        "tree: { edge() }\nedge: { }",
        &format!(
            "{SGL_ATTRS}{}{}",
            sgl_rule("tree", true, "edge"),
            sgl_rule("edge", false, "")
        ),
    );
    // `start` need not come first.
    same_sgl(
        "a: { }\nstart: { a() }",
        &format!(
            "{SGL_ATTRS}{}{}",
            sgl_rule("a", false, ""),
            sgl_rule("start", true, "a")
        ),
    );
}

#[test]
fn sgl_header_variables_and_the_depth_limit() {
    same_sgl(
        "max_depth = 5\nh = 2 * 3;\nstart: { T(0, h, 0) }",
        &format!(
            "attr max_depth = 5\nattr h = 2 * 3\nattr sgl_depth = 0\n{}",
            sgl_rule("start", true, "t(0, h, 0)")
        ),
    );
    // `depth` is the limit's other name.
    let g = read("depth = 3\nstart: { }", Dialect::Sgl);
    let text = sexpr(&g);
    assert!(
        text.starts_with("attr depth = 3\nattr sgl_depth = 0\n"),
        "{text}"
    );
    assert!(text.contains("(sgl_depth >= depth)"), "{text}");
}

#[test]
fn sgl_transformations_and_the_stack() {
    same_sgl(
        "start: { T(1, -2, .5) R(0, 45, 0) S(-1, 1, 2) SS(.2, 2, .2) Push() Pop(); T(0,0,0), }",
        &format!(
            "{SGL_ATTRS}{}",
            sgl_rule(
                "start",
                true,
                "t(1, -2, 0.5) r(0, 45, 0) s('-1, '1, '2) s(0.2, 2, 0.2) [ ] t(0, 0, 0)"
            )
        ),
    );
}

#[test]
fn sgl_place_shape_centres_unit_shapes_on_the_scope_origin() {
    same_sgl(
        "start: { PlaceShape(\"Cube\") PlaceShape(\"Cylinder\") PlaceShape(\"sphere\") PlaceShape(\"Tree\") }",
        &format!(
            "{SGL_ATTRS}{}",
            sgl_rule(
                "start",
                true,
                "[ t('-0.5, '-0.5, '-0.5) i(\"builtin:cube\") Cube. ]
                 [ s('1, '2, '1) t('-0.5, '-0.5, '-0.5) i(\"builtin:cylinder\") Cylinder. ]
                 [ t('-0.5, '-0.5, '-0.5) i(\"builtin:sphere\") sphere. ]
                 [ t('-0.5, '-0.5, '-0.5) i(\"Tree.obj\") Tree. ]"
            )
        ),
    );
}

#[test]
fn sgl_the_tree_edge_as_printed() {
    same_sgl(
        "edge: {\n    Push() T(0, 1, 0) SS(.2, 2, .2) PlaceShape(\"Cube\") Pop() }",
        &format!(
            "{SGL_ATTRS}{}",
            sgl_rule(
                "edge",
                true,
                "[ t(0, 1, 0) s(0.2, 2, 0.2) [ t('-0.5, '-0.5, '-0.5) i(\"builtin:cube\") Cube. ] ]"
            )
        ),
    );
}

#[test]
fn sgl_subdiv_cuts_the_centred_scope_into_centred_parts() {
    for (axis, word, minus, plus) in [
        ("0", "x", "'-0.5, 0, 0", "'0.5, 0, 0"),
        ("1", "y", "0, '-0.5, 0", "0, '0.5, 0"),
        ("2", "z", "0, 0, '-0.5", "0, 0, '0.5"),
    ] {
        same_sgl(
            &format!(
                "start: {{ Subdiv(3, {axis}, sgprod{{ a(), b(), a() }}) }}\na: {{ }}\nb: {{ }}"
            ),
            &format!(
                "{SGL_ATTRS}{}{}{}",
                sgl_rule(
                    "start",
                    true,
                    &format!(
                        "[ t({minus}) split({word}){{ '(1/3) : t({plus}) a | '(1/3) : t({plus}) b | '(1/3) : t({plus}) a }} ]"
                    )
                ),
                sgl_rule("a", false, ""),
                sgl_rule("b", false, "")
            ),
        );
    }
}

#[test]
fn sgl_at_depth_calls_through_a_rule_of_its_own() {
    same_sgl(
        "branch: { AtDepth(10, sgprod{ box() }) AtDepth(3, sgprod{ box(), box() }) branch() }\nbox: { }",
        &format!(
            "{SGL_ATTRS}{}branch.AtDepth1 --> case sgl_depth + 1 == 10 : box NIL else : NIL\nbranch.AtDepth2 --> case sgl_depth + 1 == 3 : box box NIL else : NIL\n{}",
            sgl_rule("branch", true, "branch.AtDepth1 branch.AtDepth2 branch"),
            sgl_rule("box", false, "")
        ),
    );
}

#[test]
fn sgl_weighted_alternatives_become_percentages() {
    let first = "set(sgl_depth, sgl_depth + 1) t(0, 2, 0) NIL";
    let second = "set(sgl_depth, sgl_depth + 1) s('1, '1, '1) NIL";
    same_sgl(
        "start: { b() }\nb:\n(1){ T(0, 2, 0) }\n(.1){ S(1, 1, 1) }",
        &format!(
            "{SGL_ATTRS}{}b --> case sgl_depth >= max_depth : NIL else : {}% : {first} else : {second}\n",
            sgl_rule("start", true, "b"),
            // 1 / 1.1 as a percentage, rounded to 1e-9 as the lowering does.
            (100.0 / 1.1 * 1e9_f64).round() / 1e9
        ),
    );
    same_sgl(
        "start: (1){ } (1) { } (2){ }",
        &format!(
            "{SGL_ATTRS}@StartRule start --> case sgl_depth >= max_depth : NIL else : 25% : s(1,1,1) set(sgl_depth, sgl_depth + 1) NIL 25% : s(1,1,1) set(sgl_depth, sgl_depth + 1) NIL else : s(1,1,1) set(sgl_depth, sgl_depth + 1) NIL\n"
        ),
    );
    // Weights that are not numbers give the expressions.
    same_sgl(
        "w = 3\nstart: (w){ } (1){ }",
        "attr w = 3\nattr max_depth = 16\nattr sgl_depth = 0\n@StartRule start --> case sgl_depth >= max_depth : NIL else : w / (w + 1) * 100% : s(1,1,1) set(sgl_depth, sgl_depth + 1) NIL else : s(1,1,1) set(sgl_depth, sgl_depth + 1) NIL\n",
    );
}

#[test]
fn sgl_menger_sponge_as_printed() {
    let g = read(&example("sgl_menger.sgl"), Dialect::Sgl);
    let names: Vec<&str> = g.rules.iter().map(|r| r.name.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "start",
            "cx",
            "cy",
            "cy1",
            "cz",
            "cz1",
            "branch",
            "branch.AtDepth1",
            "box",
            "null"
        ]
    );
    let text = sexpr(&g);
    assert!(
        text.contains(
            "branch.AtDepth1() --> (case [((sgl_depth + 1) == 14) => (box NIL)] [else => (NIL)])"
        ),
        "{text}"
    );
    assert!(
        text.starts_with("attr max_depth = 14\nattr sgl_depth = 0\n"),
        "{text}"
    );
}

// --- Detection --------------------------------------------------------------------------------

#[test]
fn detection_from_the_text() {
    for (text, dialect) in [
        ("lot ~> A", Dialect::Muller2006),
        ("1: lot \\leadsto A", Dialect::Muller2006),
        ("A → B", Dialect::Muller2006),
        ("A --> Subdiv(\"X\", 1r, 1r){ B | C }", Dialect::Muller2006),
        ("A --> Comp(\"sidefaces\"){ B }", Dialect::Muller2006),
        ("1: lot --> A", Dialect::Muller2006),
        ("a --> ϵ", Dialect::Muller2006),
        ("tree: { edge() }", Dialect::Sgl),
        ("branch:\n(1){ T(0, 2, 0) }", Dialect::Sgl),
        ("x = 1\nb: (1) { }", Dialect::Sgl),
        ("b { Subdiv(3, 0, sgprod{ a() }) }", Dialect::Sgl),
        ("Lot --> extrude(10) Mass", Dialect::Cga),
        ("", Dialect::Cga),
        (
            "// lot ~> A\n/* tree: { } */ Lot --> \"~>\" X",
            Dialect::Cga,
        ),
        (
            "F --> split(y){\n 4 : Ground\n| ~3 : Floor(1) }",
            Dialect::Cga,
        ),
        ("A --> comp(f){\n  front : B\n| side : C }", Dialect::Cga),
        // The first telltale sign decides.
        ("a: { b() }\nc ~> d", Dialect::Sgl),
        ("c ~> d\na: { b() }", Dialect::Muller2006),
    ] {
        assert_eq!(detect(text), dialect, "{text:?}");
        let source = SourceFile::new("t", text);
        assert_eq!(parse(&source).grammar.dialect, dialect, "{text:?}");
    }
}

#[test]
fn the_examples_are_detected_and_read_without_diagnostics() {
    for (name, dialect) in [
        ("mueller2006_fig12.mul", Dialect::Muller2006),
        ("cga_shape_fig7.mul", Dialect::Muller2006),
        ("sgl_tree.sgl", Dialect::Sgl),
        ("sgl_menger.sgl", Dialect::Sgl),
        ("sgl_medieval_house.sgl", Dialect::Sgl),
        ("office.cga", Dialect::Cga),
    ] {
        let text = example(name);
        assert_eq!(detect(&text), dialect, "{name}");
        let source = SourceFile::new(name, text);
        let parsed = parse(&source);
        assert!(
            parsed.diagnostics.is_empty(),
            "{}",
            render_all(&source, &parsed.diagnostics)
        );
    }
}

#[test]
fn parse_as_forces_a_dialect() {
    let source = SourceFile::new("t", "tree: { edge() }\nedge: { }");
    let parsed = parse_as(&source, Dialect::Cga);
    assert_eq!(parsed.grammar.dialect, Dialect::Cga);
    assert!(parsed.has_errors());
    let parsed = parse_as(&source, Dialect::Sgl);
    assert!(!parsed.has_errors());
    // A main-syntax grammar without dialect markers reads the same in the Müller notation.
    let text = "attr h = 3\nLot --> extrude(h) Mass\nMass --> A B";
    assert_eq!(
        sexpr(&read(text, Dialect::Muller2006)),
        sexpr(&read(text, Dialect::Cga))
    );
}

// --- Diagnostics ------------------------------------------------------------------------------

#[test]
fn muller_errors_point_into_the_text() {
    assert_eq!(
        rendered("a ~> Subdiv(\"X\", 2, 1r){ B }", Dialect::Muller2006),
        "\
error: `Subdiv` has 2 sizes but 1 parts
 --> test:1:6
  |
1 | a ~> Subdiv(\"X\", 2, 1r){ B }
  |      ^^^^^^^^^^^^^^^^^^^^^^^ sizes and parts do not match
  = hint: give one size per part: `Subdiv(\"X\", 2, 1r){ A | B }`
"
    );
    assert_eq!(
        rendered("a ~> Subdiv(\"W\", 1r){ B }", Dialect::Muller2006),
        "\
error: expected the axis \"X\", \"Y\" or \"Z\"
 --> test:1:13
  |
1 | a ~> Subdiv(\"W\", 1r){ B }
  |             ^^^ in `Subdiv`
  = hint: \"XS\", \"YS\" and \"ZS\" also snap the parts to snap lines
"
    );
    assert_eq!(
        rendered("a ~> Comp(\"sidefacs\"){ B }", Dialect::Muller2006),
        "\
error: unknown component type
 --> test:1:11
  |
1 | a ~> Comp(\"sidefacs\"){ B }
  |           ^^^^^^^^^^ in `Comp`
  = hint: the types are \"faces\", \"sidefaces\", \"topface\", \"bottomface\", \"frontface\", \"edges\", \"sideedges\" and \"vertices\"
  = hint: did you mean \"sidefaces\"?
"
    );
    assert_eq!(
        rendered("x ~> A : 0.5\n  ~> B", Dialect::Muller2006),
        "\
error: rule `x` has several alternatives, but this one has no probability
 --> test:2:3
  |
2 |   ~> B
  |   ^^^^ no `: probability` at its end
  = hint: alternatives are chosen at random: end each with its probability, e.g. `~> A : 0.5`
"
    );
    assert_eq!(
        rendered("a ~> S(1r, 2) B", Dialect::Muller2006),
        "\
error: wrong number of arguments for `S`
 --> test:1:6
  |
1 | a ~> S(1r, 2) B
  |      ^^^^^^^^ 2 given
  = hint: the signature is `S(x, y, z)`
"
    );
    assert_eq!(
        rendered(
            "~> B\na ~> Subdiv(\"X\", 1r, 1r){ B | }",
            Dialect::Muller2006
        ),
        "\
error: `~>` without a rule name
 --> test:1:1
  |
1 | ~> B
  | ^^ whose rule is this?
  = hint: rules are written `name ~> successors`
error: empty part
 --> test:2:31
  |
2 | a ~> Subdiv(\"X\", 1r, 1r){ B | }
  |                               ^ no successor here
  = hint: write `ε` for a part that is left empty
"
    );
    assert_eq!(
        rendered("a \\leadto B", Dialect::Muller2006),
        "\
error: unexpected `\\leadto`
 --> test:1:3
  |
1 | a \\leadto B
  |   ^^^^^^^
  = hint: the LaTeX commands read here are `\\leadsto`, `\\rightarrow` and `\\epsilon`
error: expected `~>` after the rule name `a`, found `B`
 --> test:1:11
  |
1 | a \\leadto B
  |           ^ expected `~>` here
  = hint: rules are written `a ~> successors`
"
    );
}

#[test]
fn muller_recovers_and_keeps_the_other_rules() {
    let source = SourceFile::new("t", "a ~> Subdiv(\"X\", 1r){ B | C }\nb ~> D ) E\nc ~> F");
    let parsed = parse_as(&source, Dialect::Muller2006);
    let messages: Vec<&str> = parsed
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(
        messages,
        [
            "`Subdiv` has 1 sizes but 2 parts",
            "expected a successor, `: probability` or the next rule, found `)`"
        ]
    );
    let names: Vec<&str> = parsed
        .grammar
        .rules
        .iter()
        .map(|r| r.name.name.as_str())
        .collect();
    assert_eq!(names, ["a", "b", "c"]);
    assert_eq!(body(&parsed.grammar.rules[2].body), "(F)");
}

#[test]
fn sgl_errors_point_into_the_text() {
    assert_eq!(
        rendered("start: { brnch() }\nbranch: { }", Dialect::Sgl),
        "\
error: unknown rule `brnch`
 --> test:1:10
  |
1 | start: { brnch() }
  |          ^^^^^ no rule of this name
  = hint: did you mean `branch`?
"
    );
    assert_eq!(
        rendered("p3:\n(1)\\{ a() \\}\na: { }", Dialect::Sgl),
        "\
error: `\\{` is a LaTeX escape
 --> test:2:4
  |
2 | (1)\\{ a() \\}
  |    ^^ read as a brace
  = hint: write `{` without the backslash
error: `\\}` is a LaTeX escape
 --> test:2:11
  |
2 | (1)\\{ a() \\}
  |           ^^ read as a brace
  = hint: write `}` without the backslash
"
    );
    assert_eq!(
        rendered("p1:\n(1){ a()\n(1){ a() }\na: { }", Dialect::Sgl),
        "\
error: unclosed `{`
 --> test:2:4
  |
2 | (1){ a()
  |    ^ this body is never closed
  = hint: close the body with `}`
"
    );
    assert_eq!(
        rendered("a: { Subdiv(3, 0, sgprod{ a(), a() }) }", Dialect::Sgl),
        "\
error: `Subdiv` into 3 parts needs 3 rules, found 2
 --> test:1:13
  |
1 | a: { Subdiv(3, 0, sgprod{ a(), a() }) }
  |             ^ the number of parts
  = hint: give one rule per part in `sgprod{ … }`
"
    );
    assert_eq!(
        rendered(
            "a: { Subdiv(2, 3, sgprod{ a(), a() })\n Push() Pop() Pop() }",
            Dialect::Sgl
        ),
        "\
error: expected the axis 0, 1 or 2 (x, y or z)
 --> test:1:16
  |
1 | a: { Subdiv(2, 3, sgprod{ a(), a() })
  |                ^ in `Subdiv`
error: `Pop()` without a matching `Push()`
 --> test:2:15
  |
2 |  Push() Pop() Pop() }
  |               ^^^^^
  = hint: every `Pop()` restores the scope saved by a `Push()` before it
"
    );
    assert_eq!(
        rendered("a: { T(1, 2) a(3) }\na: { }\nb { }", Dialect::Sgl),
        "\
error: wrong number of arguments for `T`
 --> test:1:6
  |
1 | a: { T(1, 2) a(3) }
  |      ^^^^^^^ 2 given
  = hint: the signature is `T(x, y, z)`
error: SGL rules take no arguments
 --> test:1:14
  |
1 | a: { T(1, 2) a(3) }
  |              ^^^^ `a` is called with arguments
  = hint: call it as `a()`
error: rule `a` is defined twice
 --> test:2:1
  |
2 | a: { }
  | ^
  = hint: write the alternatives as one rule: `a: (1){ … } (1){ … }`
error: expected `:` or `=` after `b`, found `{`
 --> test:3:3
  |
3 | b { }
  |   ^ expected `:` or `=` here
  = hint: a rule is written `name: { … }`, a header variable `name = value`
"
    );
}

// --- Robustness -------------------------------------------------------------------------------

/// Parses `text` in every dialect: no panic, every span inside the text on character boundaries.
fn check_robust(text: &str) {
    let source = SourceFile::new("fuzz", text);
    for dialect in [Dialect::Cga, Dialect::Muller2006, Dialect::Sgl] {
        for d in &parse_as(&source, dialect).diagnostics {
            let Span { start, end } = d.span;
            assert!(
                start <= end && end as usize <= text.len(),
                "{dialect:?}: {:?}",
                d.span
            );
            assert!(text.is_char_boundary(start as usize) && text.is_char_boundary(end as usize));
            assert!(source.render(d).contains('^'));
        }
    }
    let _ = detect(text);
}

#[test]
fn deep_nesting_is_an_error_in_the_dialects_too() {
    let n = 100_000;
    let muller = format!("a ~> {}", "Subdiv(\"X\", 1){ ".repeat(n));
    let parsed = parse_as(&SourceFile::new("t", muller.as_str()), Dialect::Muller2006);
    let messages: Vec<&str> = parsed
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(messages, ["nesting too deep"]);
    let sgl = format!("a: {{ T({}1, 0, 0) }}", "(".repeat(n));
    let parsed = parse_as(&SourceFile::new("t", sgl.as_str()), Dialect::Sgl);
    let messages: Vec<&str> = parsed
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(messages, ["nesting too deep"]);
}

#[test]
fn printed_fragments_and_garbage_never_panic() {
    for text in [
        "(1)\\{ long_hall_sm() T(0, 0, -2) S(1, 1, -1) end_sm() \\}",
        "$\\leadsto \\epsilon$: 0.2",
        "1: \n2: ~>\n~> ~> :",
        "a: (",
        "a: (1)",
        "a: { Subdiv(",
        "a: { AtDepth(1, sgprod{ ",
        "a: { PlaceShape(1) Push( }",
        "x ~> Comp(){ } Repeat(\"X\"){ A | B } I() Rx(1, 2)",
        "ϵ ε \\ $ → ⇝ 1r 2r3 r1",
        "a ~> Subdiv(\"X\", 1r, 1r){ A | B",
        "p1:\n(1){ a() \n(1)\\{ b() \\}\n",
    ] {
        check_robust(text);
    }
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let alphabet: Vec<char> = "a(){}[]|:~>'%.,-=@\"#/*\n 1r5 ϵ$\\sgprod Subdiv PlaceShape AtDepth"
        .chars()
        .collect();
    let text: String = (0..50_000)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            alphabet[(state % alphabet.len() as u64) as usize]
        })
        .collect();
    check_robust(&text);
}

/// Pieces of both notations, so generated inputs get into the dialect parsers.
fn dialect_soup() -> impl Strategy<Value = String> {
    let piece = prop::sample::select(vec![
        "a",
        "lot",
        "1:",
        "~>",
        "\\leadsto",
        "ϵ",
        "$",
        "Subdiv(\"X\", 1r, 2)",
        "Repeat(\"Y\", 3)",
        "Comp(\"sidefaces\")",
        "S(1r, 2, 1r)",
        "I(cube)",
        "{",
        "}",
        "|",
        "[",
        "]",
        ":",
        "0.5",
        "name:",
        "(1)",
        "(.1)",
        "T(0, 1, 0)",
        "SS(1, 1, 1)",
        "Push()",
        "Pop()",
        "PlaceShape(\"Cube\")",
        "Subdiv(3, 0, sgprod{ a(), a(), a() })",
        "AtDepth(2, sgprod{ a() })",
        "a()",
        "x = 1",
        "\n",
        ",",
        ";",
        "(",
        ")",
        "\\{",
        "//c\n",
    ]);
    prop::collection::vec(piece, 0..60).prop_map(|pieces| pieces.join(" "))
}

proptest! {
    #[test]
    fn arbitrary_strings_never_panic_in_any_dialect(text in any::<String>()) {
        check_robust(&text);
    }

    #[test]
    fn dialect_soup_never_panics(text in dialect_soup()) {
        check_robust(&text);
    }
}
