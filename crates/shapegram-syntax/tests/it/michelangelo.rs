//! The Michelangelo notation of goal grammars (Ilčík and Wimmer, seed 003): the paper's listings
//! as printed, the lowering of every rule kind to the main syntax's statements (as S-expressions),
//! `using` blocks, detection of both goal notations, and diagnostics.

use crate::common;

use common::{expr, goal_rule, render_all};
use proptest::prelude::*;
use shapegram_syntax::ast::{
    AttributeKind, BlockEntry, Body, ExprKind, Grammar, PredicateKind, Stmt,
};
use shapegram_syntax::{Dialect, SourceFile, Span, detect, parse, parse_as};

// --- The listings of the paper, copied from seed 003 as printed (`↪` marks a line broken in
// print; some lines end with two spaces, the paper's line breaks) ------------------------------

/// Section "Implementation and usage example": the axiom of the basic chair.
const AXIOM: &str = "new Axiom(\"chair\", \"wooden\").Size  \n  ↪ (0.4, 0.8, 0.4);\n";

/// The chair split into support, seat and lean.
const CHAIR: &str = r#"new Rules.Split(Axis.Y,  
  Relative(0.4).Goal("support").  
  ↪ Attribute("Leg.Size", Rnd  
  ↪ (0.03, 0.05)),  
  Relative(0.05).Goal("seat"),  
  Relative(0.55).Goal("lean"))  
.Fulfills("chair");
"#;

/// The pair of rules that makes the legs (printed in two code blocks, the first holding only its
/// first line).
const LEGS: &str = r#"new Rules.Split(Axis.X,

Absolute(@Double("Leg.Size")).
  ↪ goal("split-legs"),
Relative(1).Void(),
Absolute(@Double("Leg.Size")).
  ↪ goal("split-legs"))
.Fulfills("support");

new Rules.Split(Axis.Z,
  Absolute(@Double("Leg.Size")).
    ↪ Goal("leg"),
  Relative(1).Void(),
  Absolute(@Double("Leg.Size")).
    ↪ Goal("leg"))
.Fulfills("split-legs");

"#;

/// The lean.
const LEAN: &str = r#"
new Rules.Size(Axis.Z, 0.04)
.Fulfills("lean");

"#;

/// Section "Cloud queries": the grammar that overrides the support, in four code blocks.
const METAL_AXIOM: &str = r#"
new Axiom("chair", "wooden").Size
  ↪ (0.4,0.8,0.4);

"#;

const METAL_SUPPORT: &str = r#"
new Rules.Split(Axis.Y,
  Absolute(0.4).goal("stand"),
  Relative(1).goal("leg"))
.Goal("metallic")
.Fulfills("support");

"#;

const METAL_LEG: &str = r#"
new Rules.Scale(Vec3(0.5,1.0,0.5),
  ↪ Pivot.Middle)
.Fulfills("leg");

"#;

const METAL_STAND: &str = r#"
new Rules.Scale(Vec3(0.25,1.0,0.25),
  ↪ Pivot.Middle)
.Fulfills("stand");

"#;

/// Section "Cloud-based modeling": a rule for human legs, its parts elided in a comment.
const HUMAN_LEG: &str = r#"new Rules.Split(Axis.Y, /*foot, ankle,
  ↪ etc.*/).Fulfills("leg");
"#;

const USING: &str = r#"using (Predicates.IfIs("chair")) {
/*All rules in this block will inherit
  ↪ the IfIs*/}
"#;

const SYNC: &str = "var windows = new Synchronize();\n";

const REPEAT: &str = r#"new Rules.Repeat(Axis.X,
  Absolute(1.5)
  .Goal("Window")
  .Sync(windows))
.Fulfills("Floor")
.IfIs("Facade");
"#;

// --- Helpers ---------------------------------------------------------------------------------

/// Parses `text` (its notation detected), asserting that it is read as Michelangelo without
/// diagnostics.
#[track_caller]
fn read(text: &str) -> Grammar {
    let source = SourceFile::new("chair.cs", text);
    let parsed = parse(&source);
    assert!(
        parsed.diagnostics.is_empty(),
        "unexpected diagnostics:\n{}",
        render_all(&source, &parsed.diagnostics)
    );
    assert_eq!(parsed.grammar.dialect, Dialect::Michelangelo);
    assert!(parsed.grammar.is_goal_grammar());
    parsed.grammar
}

/// The goal rules as S-expressions.
fn rules(g: &Grammar) -> Vec<String> {
    g.goal_rules.iter().map(goal_rule).collect()
}

/// The axioms as `goals… [size x y z]`.
fn axioms(g: &Grammar) -> Vec<String> {
    g.axioms
        .iter()
        .map(|a| {
            let goals: Vec<&str> = a.goals.iter().map(|g| g.name.as_str()).collect();
            let size = a.size.as_ref().map_or(String::new(), |[x, y, z]| {
                format!(" [size {} {} {}]", expr(x), expr(y), expr(z))
            });
            format!("{}{size}", goals.join(" "))
        })
        .collect()
}

fn locals(g: &Grammar) -> Vec<&str> {
    g.local_goals.iter().map(|g| g.name.as_str()).collect()
}

/// The rules of `text` read as Michelangelo, without diagnostics.
#[track_caller]
fn rules_of(text: &str) -> Vec<String> {
    let source = SourceFile::new("t.cs", text);
    let parsed = parse_as(&source, Dialect::Michelangelo);
    assert!(
        parsed.diagnostics.is_empty(),
        "unexpected diagnostics:\n{}",
        render_all(&source, &parsed.diagnostics)
    );
    rules(&parsed.grammar)
}

/// All diagnostics of `text` read as Michelangelo, rendered.
fn rendered(text: &str) -> String {
    let source = SourceFile::new("t.cs", text);
    render_all(
        &source,
        &parse_as(&source, Dialect::Michelangelo).diagnostics,
    )
}

/// The text a span covers.
fn text_at(text: &str, span: Span) -> &str {
    &text[span.range()]
}

// --- The paper's listings --------------------------------------------------------------------

#[test]
fn the_listings_keep_their_printed_line_ends() {
    // Editors strip trailing spaces; these listings are printed with them.
    assert!(AXIOM.contains(".Size  \n  ↪ "));
    assert_eq!(CHAIR.matches("  \n").count(), 6);
}

#[test]
fn the_axiom_as_printed() {
    let g = read(AXIOM);
    assert_eq!(axioms(&g), ["chair wooden [size 0.4 0.8 0.4]"]);
    assert!(g.goal_rules.is_empty());
    let g = read(METAL_AXIOM);
    assert_eq!(axioms(&g), ["chair wooden [size 0.4 0.8 0.4]"]);
    // The span runs from `new` to the closing parenthesis of the size.
    let span = g.axioms[0].span;
    assert!(text_at(METAL_AXIOM, span).starts_with("new Axiom("));
    assert!(text_at(METAL_AXIOM, span).ends_with("(0.4,0.8,0.4)"));
    let g = read("new Axiom(\"table\");");
    assert_eq!(axioms(&g), ["table"]);
    assert!(g.axioms[0].size.is_none());
}

#[test]
fn the_chair_split_as_printed() {
    let g = read(CHAIR);
    assert_eq!(
        rules(&g),
        [
            "[fulfills chair] => (split(y){~0.4 : (set(@Leg.Size, rand(0.03, 0.05)) +support) | ~0.05 : (+seat) | ~0.55 : (+lean)})"
        ]
    );
    assert!(g.local_goals.is_empty());
}

#[test]
fn the_legs_as_printed() {
    let g = read(LEGS);
    assert_eq!(
        rules(&g),
        [
            "[fulfills support] => (split(x){@Double(\"Leg.Size\") : (+split-legs) | ~1 : (NIL) | @Double(\"Leg.Size\") : (+split-legs)})",
            "[fulfills split-legs] => (split(z){@Double(\"Leg.Size\") : (+leg) | ~1 : (NIL) | @Double(\"Leg.Size\") : (+leg)})",
        ]
    );
    // `goal` in lowercase: the goal is local, once however often it is written.
    assert_eq!(locals(&g), ["split-legs"]);
    let first = g.local_goals[0].span;
    assert_eq!(text_at(LEGS, first), "\"split-legs\"");
    assert!(first.start < 80, "the first use: {first:?}");
}

#[test]
fn the_lean_as_printed() {
    assert_eq!(rules(&read(LEAN)), ["[fulfills lean] => (s('1, '1, 0.04))"]);
}

#[test]
fn the_metallic_support_as_printed() {
    let g = read(METAL_SUPPORT);
    assert_eq!(
        rules(&g),
        ["[fulfills support] [adds metallic] => (split(y){0.4 : (+stand) | ~1 : (+leg)})"]
    );
    assert_eq!(locals(&g), ["stand", "leg"]);
    assert_eq!(
        rules(&read(METAL_LEG)),
        ["[fulfills leg] => (s('0.5, '1, '0.5) center(xyz))"]
    );
    assert_eq!(
        rules(&read(METAL_STAND)),
        ["[fulfills stand] => (s('0.25, '1, '0.25) center(xyz))"]
    );
}

#[test]
fn the_human_leg_with_its_parts_elided() {
    assert_eq!(rules(&read(HUMAN_LEG)), ["[fulfills leg] => (split(y){})"]);
}

#[test]
fn the_empty_using_block_as_printed() {
    let g = read(USING);
    assert!(g.goal_rules.is_empty());
    assert!(g.axioms.is_empty());
}

#[test]
fn the_synchronization_and_the_repeat_as_printed() {
    let g = read(SYNC);
    let syncs: Vec<&str> = g.syncs.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(syncs, ["windows"]);
    assert_eq!(text_at(SYNC, g.syncs[0].span), "windows");
    assert_eq!(
        rules(&read(REPEAT)),
        ["[fulfills Floor] [is Facade] => (split(x){{~1.5 : (sync(windows) +Window)}*})"]
    );
    // Together, as one grammar.
    let text = format!("{SYNC}{REPEAT}");
    let g = read(&text);
    assert_eq!(g.syncs.len(), 1);
    assert_eq!(g.goal_rules.len(), 1);
}

/// The predicates the paper writes as a formula (`IfIs(s, "restaurant", "table") ∧ …`), in the
/// notation of its listings.
#[test]
fn the_table_setting_predicates() {
    let text = r#"new Rules.Identity()
.IfIs("restaurant", "table")
.IfGoal("romantic", "dinner")
.Fulfills("setting")
.If(s => s.Size.X < 0.8 && s.Size.Z < 0.8);"#;
    assert_eq!(
        rules(&read(text)),
        [
            "[fulfills setting] [is restaurant table] [goal romantic dinner] [if ((scope.sx < 0.8) && (scope.sz < 0.8))] => ()"
        ]
    );
}

// --- Whole grammars ----------------------------------------------------------------------------

#[test]
fn the_basic_chair_as_one_file() {
    let text = format!("{AXIOM}\n{CHAIR}\n{LEGS}{LEAN}");
    let g = read(&text);
    assert_eq!(axioms(&g), ["chair wooden [size 0.4 0.8 0.4]"]);
    assert_eq!(
        rules(&g),
        [
            "[fulfills chair] => (split(y){~0.4 : (set(@Leg.Size, rand(0.03, 0.05)) +support) | ~0.05 : (+seat) | ~0.55 : (+lean)})",
            "[fulfills support] => (split(x){@Double(\"Leg.Size\") : (+split-legs) | ~1 : (NIL) | @Double(\"Leg.Size\") : (+split-legs)})",
            "[fulfills split-legs] => (split(z){@Double(\"Leg.Size\") : (+leg) | ~1 : (NIL) | @Double(\"Leg.Size\") : (+leg)})",
            "[fulfills lean] => (s('1, '1, 0.04))",
        ]
    );
    assert_eq!(locals(&g), ["split-legs"]);
    assert!(g.syncs.is_empty() && g.rules.is_empty());
}

#[test]
fn the_metallic_support_override_as_one_file() {
    let text = format!("{METAL_AXIOM}{METAL_SUPPORT}{METAL_LEG}{METAL_STAND}");
    let g = read(&text);
    assert_eq!(axioms(&g), ["chair wooden [size 0.4 0.8 0.4]"]);
    assert_eq!(
        rules(&g),
        [
            "[fulfills support] [adds metallic] => (split(y){0.4 : (+stand) | ~1 : (+leg)})",
            "[fulfills leg] => (s('0.5, '1, '0.5) center(xyz))",
            "[fulfills stand] => (s('0.25, '1, '0.25) center(xyz))",
        ]
    );
    assert_eq!(locals(&g), ["stand", "leg"]);
}

/// The lowered nodes point into the original text.
#[test]
fn spans_point_into_the_printed_text() {
    let g = read(CHAIR);
    let rule = &g.goal_rules[0];
    let whole = text_at(CHAIR, rule.span);
    assert!(whole.starts_with("new Rules.Split(Axis.Y,"));
    assert!(whole.ends_with(".Fulfills(\"chair\")"));
    assert_eq!(text_at(CHAIR, rule.fulfills[0].span), "\"chair\"");
    let Body::Sequence(stmts) = &rule.body else {
        panic!("a sequence");
    };
    let Stmt::Call(split) = &stmts[0] else {
        panic!("a call");
    };
    assert_eq!(text_at(CHAIR, split.name.span), "Rules.Split");
    let block = split.block.as_ref().expect("a block");
    let BlockEntry::Part {
        key, body, span, ..
    } = &block.entries[0]
    else {
        panic!("a part");
    };
    assert_eq!(text_at(CHAIR, key.span), "Relative(0.4)");
    assert!(text_at(CHAIR, *span).starts_with("Relative(0.4).Goal(\"support\")."));
    assert!(text_at(CHAIR, *span).ends_with("(0.03, 0.05))"));
    let Stmt::Call(set) = &body[0] else {
        panic!("set");
    };
    assert_eq!(set.name.name, "set");
    let args = set.args.as_ref().expect("arguments");
    assert_eq!(
        args[0].value.kind,
        ExprKind::GoalAttribute {
            name: "Leg.Size".into(),
            kind: AttributeKind::Any
        }
    );
    assert_eq!(text_at(CHAIR, args[0].value.span), "\"Leg.Size\"");
    let Stmt::Goals(goals, goals_span) = &body[1] else {
        panic!("goals");
    };
    assert_eq!(goals[0].name, "support");
    assert_eq!(text_at(CHAIR, *goals_span), "Goal(\"support\")");
}

// --- `using` blocks ----------------------------------------------------------------------------

#[test]
fn using_blocks_give_their_rules_predicates_first() {
    // The chair wrapped as the paper advises: all but the rule that fulfils `chair`.
    let text = format!("{AXIOM}{CHAIR}\nusing (Predicates.IfIs(\"chair\")) {{\n{LEGS}{LEAN}}}\n");
    let g = read(&text);
    assert_eq!(
        rules(&g),
        [
            "[fulfills chair] => (split(y){~0.4 : (set(@Leg.Size, rand(0.03, 0.05)) +support) | ~0.05 : (+seat) | ~0.55 : (+lean)})",
            "[fulfills support] [is chair] => (split(x){@Double(\"Leg.Size\") : (+split-legs) | ~1 : (NIL) | @Double(\"Leg.Size\") : (+split-legs)})",
            "[fulfills split-legs] [is chair] => (split(z){@Double(\"Leg.Size\") : (+leg) | ~1 : (NIL) | @Double(\"Leg.Size\") : (+leg)})",
            "[fulfills lean] [is chair] => (s('1, '1, 0.04))",
        ]
    );
}

#[test]
fn using_blocks_chain_predicates_and_nest() {
    let text = r#"
using (Predicates.IfIs("chair").IfNotGoal("x")) {
    using (Predicates.IfHas("Leg.Size").IfNot(Size.Y > 1)) {
        Rules.Identity().IfTag("wooden").Fulfills("a");
    }
    new Rules.Identity().Fulfills("b");
}
new Rules.Identity().Fulfills("c");
"#;
    assert_eq!(
        rules(&read(text)),
        [
            "[fulfills a] [is chair] [!goal x] [has Leg.Size] [!if (scope.sy > 1)] [is wooden] => ()",
            "[fulfills b] [is chair] [!goal x] => ()",
            "[fulfills c] => ()",
        ]
    );
}

// --- Rules, parts and predicates -------------------------------------------------------------

#[test]
fn every_rule_kind_lowers_to_the_main_syntax() {
    let text = r##"
Rules.Split(Axis.X, Absolute(0.1), Relative(2).Goal("a"), Relative(1).Void());
Rules.Repeat(Axis.Z, Absolute(2).Goal("tile"), Relative(0.5).Goal("gap"));
Rules.Size(Axis.X, 0.5);
Rules.Size(Axis.Y, 2);
new Rules.Scale(Vec3(1, 2, 3), Pivot.Bottom);
new Rules.Scale(Vec3(1, 2, 3), Pivot.Min);
new Rules.Scale(new Vec3(1, 2, 3), Pivot.Origin);
Rules.Translate(Vec3(1, 2, -3));
Rules.Rotate(Vec3(0, 90, 0));
Rules.Color("#8b5a2b");
Rules.Material("oak");
Rules.Insert("chair.obj");
Rules.Comp(Face.Top.Goal("seat"), Face.Side.Void(), Face.Bottom, Face.Vertical.Goal("v"), Face.Horizontal.goal("h"));
Rules.Comp(Face.Front.Goal("a"), Face.Back.Goal("b"), Face.Left.Goal("c"), Face.Right.Goal("d"), Face.All.Goal("e"));
Rules.Taper(Axis.Y, 0.5);
Rules.Twist(Axis.Y, 45);
Rules.Shear(Axis.Y, Axis.X, 0.2);
Rules.Identity();
"##;
    assert_eq!(
        rules_of(text),
        [
            "=> (split(x){0.1 : () | ~2 : (+a) | ~1 : (NIL)})",
            "=> (split(z){{~2 : (+tile) | ~0.5 : (+gap)}*})",
            "=> (s(0.5, '1, '1))",
            "=> (s('1, 2, '1))",
            "=> (s('1, '2, '3) center(xz))",
            "=> (s('1, '2, '3))",
            "=> (s('1, '2, '3))",
            "=> (t(1, 2, (-3)))",
            "=> (r(scopeCenter, 0, 90, 0))",
            "=> (color(\"#8b5a2b\"))",
            "=> (set(material.name, \"oak\"))",
            "=> (i(\"chair.obj\"))",
            "=> (comp(f){top : (+seat) | side : (NIL) | bottom : () | vertical : (+v) | horizontal : (+h)})",
            "=> (comp(f){front : (+a) | back : (+b) | left : (+c) | right : (+d) | all : (+e)})",
            "=> (taper(y, 0.5))",
            "=> (twist(y, 45))",
            "=> (shear(y, x, 0.2))",
            "=> ()",
        ]
    );
}

#[test]
fn part_modifiers_lower_in_a_fixed_order() {
    let text = r#"
var windows = new Synchronize();
var doors = new Synchronize();
new Rules.Split(Axis.Y,
    Relative(1).Goal("a").Sync(windows).Attribute("Leg.Size", @Double("w") / 2).goal("b", "c")
        .Attribute("Style", @String("style")).Sync(doors),
    Absolute(Size.Y / 3 + 0.1).Goal("d").Goal("e"))
.fulfills("c").Goal("f").goal("g");
"#;
    let g = read(text);
    assert_eq!(
        rules(&g),
        [
            "[fulfills c] [adds f g] => (split(y){~1 : (set(@Leg.Size, (@Double(\"w\") / 2)) set(@Style, @String(\"style\")) sync(windows) sync(doors) +a+b+c) | ((scope.sy / 3) + 0.1) : (+d+e)})"
        ]
    );
    // Lowercase makes goals local, each once, in the order first written.
    assert_eq!(locals(&g), ["b", "c", "g"]);
}

#[test]
fn predicates_negate_and_read_lambdas() {
    let text = r#"new Rules.Identity()
.IfNotGoal("a").IfNotIs("b").IfNotTag("c").IfNotHas("d", "e")
.If(shape => shape.Size.X < 0.8 || !(shape.Position.Z >= 1))
.If((s) => Size.Y == @Double("h"))
.IfNot(s.Size.Z != 2 && Position.X > Rnd(0, 1));"#;
    assert_eq!(
        rules_of(text),
        [
            "[!goal a] [!is b] [!is c] [!has d e] [if ((scope.sx < 0.8) || (!(scope.tz >= 1)))] [if (scope.sy == @Double(\"h\"))] [!if ((scope.sz != 2) && (scope.tx > rand(0, 1)))] => ()"
        ]
    );
    let g = parse_as(
        &SourceFile::new("t", "Rules.Identity().IfHas(\"Leg.Size\");"),
        Dialect::Michelangelo,
    )
    .grammar;
    let PredicateKind::Has(names) = &g.goal_rules[0].predicates[0].kind else {
        panic!("has");
    };
    assert_eq!(names[0].name, "Leg.Size");
}

#[test]
fn comments_empty_statements_and_a_trailing_comma() {
    let text = "// a chair\n/* two\n lines */ new Axiom(\"chair\");;\nRules.Split(Axis.Y, Relative(1).Goal(\"a\"), /* more later */);\n";
    let g = read(text);
    assert_eq!(axioms(&g), ["chair"]);
    assert_eq!(rules(&g), ["=> (split(y){~1 : (+a)})"]);
}

// --- Detection ---------------------------------------------------------------------------------

#[test]
fn both_goal_notations_are_detected() {
    for (text, dialect) in [
        ("new Axiom(\"chair\");", Dialect::Michelangelo),
        ("Rules.Size(Axis.Z, 0.04);", Dialect::Michelangelo),
        ("new Rules.Splitt(Axis.Y);", Dialect::Michelangelo),
        ("var windows = new Synchronize();", Dialect::Michelangelo),
        (
            "using (Predicates.IfIs(\"chair\")) { }",
            Dialect::Michelangelo,
        ),
        ("// Rules.Split(\nnew Axiom(\"a\");", Dialect::Michelangelo),
        ("axiom chair, wooden size(0.4, 0.8, 0.4)", Dialect::Goal),
        ("axiom \"split-legs\"", Dialect::Goal),
        ("local \"split-legs\"", Dialect::Goal),
        ("local legs", Dialect::Goal),
        ("sync windows", Dialect::Goal),
        ("fulfills(chair) --> split(y) { ~1 : +seat }", Dialect::Goal),
        (
            "goal(a) !is(b) has(c) if(scope.sx < 1) adds(d) --> NIL",
            Dialect::Goal,
        ),
        ("!tag(ruin) fulfills(x) --> NIL", Dialect::Goal),
        (
            "using is(chair) {\n fulfills(lean) --> s('1, '1, 0.04)\n}",
            Dialect::Goal,
        ),
        // Not at the start of a line, not followed by a name, not a rule head: CGA.
        ("Lot --> axiom Mass", Dialect::Cga),
        ("axiom --> A", Dialect::Cga),
        ("sync --> A\nlocal = 2", Dialect::Cga),
        ("is(x) = x + 1\nLot --> is(1) A", Dialect::Cga),
        ("fulfills(a)\n --> A", Dialect::Cga),
        ("Rules.Splitter(1)", Dialect::Cga),
        ("Lot --> new(1) Rules", Dialect::Cga),
        // The paper's CGA listing.
        ("import B: \"book.cga\"  \nBook --> B.Book\n", Dialect::Cga),
    ] {
        assert_eq!(detect(text), dialect, "{text:?}");
    }
    // The native notation's chair (tests/goal.rs) and the paper's listings.
    let native = "local \"split-legs\"\naxiom chair, wooden size(0.4, 0.8, 0.4)\n\nfulfills(chair) -->\n    split(y) { ~1 : +seat }\n";
    assert_eq!(detect(native), Dialect::Goal);
    for listing in [
        AXIOM,
        CHAIR,
        LEGS,
        LEAN,
        METAL_AXIOM,
        METAL_SUPPORT,
        METAL_LEG,
        METAL_STAND,
        HUMAN_LEG,
        USING,
        SYNC,
        REPEAT,
    ] {
        assert_eq!(detect(listing), Dialect::Michelangelo, "{listing}");
    }
}

#[test]
fn the_cga_examples_are_not_goal_grammars() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("the examples folder") {
        let path = entry.expect("an entry").path();
        if path.extension().is_some_and(|e| e == "cga") {
            let text = std::fs::read_to_string(&path).expect("readable");
            assert_eq!(detect(&text), Dialect::Cga, "{}", path.display());
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} examples");
}

#[test]
fn the_arrow_mark_is_whitespace_only_here() {
    let text = "new Axiom(\"a\")\n  ↪ .Size(1, 2, 3);";
    assert_eq!(axioms(&read(text)), ["a [size 1 2 3]"]);
    let source = SourceFile::new("t", "Lot --> ↪ A");
    assert!(parse_as(&source, Dialect::Cga).has_errors());
}

// --- Diagnostics -------------------------------------------------------------------------------

#[test]
fn a_missing_semicolon_is_reported_where_it_belongs_and_the_next_rule_is_read() {
    assert_eq!(
        rendered(
            "new Rules.Size(Axis.Z, 0.04)\n.Fulfills(\"lean\")\nnew Rules.Identity().Fulfills(\"a\");\n"
        ),
        "\
error: expected `;` after the rule, found `new`
 --> t.cs:2:18
  |
2 | .Fulfills(\"lean\")
  |                  ^ add `;` here
"
    );
    assert_eq!(
        rendered("new Axiom(\"a\") Rules.Identity();"),
        "\
error: expected `;` after the axiom, found `Rules.Identity`
 --> t.cs:1:16
  |
1 | new Axiom(\"a\") Rules.Identity();
  |                ^^^^^^^^^^^^^^ expected `;` here
"
    );
    let source = SourceFile::new(
        "t",
        "var w = new Synchronize()\nRules.Identity().Fulfills(\"a\")\nRules.Identity().Fulfills(\"b\");",
    );
    let parsed = parse_as(&source, Dialect::Michelangelo);
    let messages: Vec<&str> = parsed
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(
        messages,
        [
            "expected `;` after the declaration, found `Rules.Identity`",
            "expected `;` after the rule, found `Rules.Identity`",
        ]
    );
    // Both rules are kept: only the `;` is missing.
    assert_eq!(
        rules(&parsed.grammar),
        ["[fulfills a] => ()", "[fulfills b] => ()"]
    );
}

#[test]
fn unknown_rules_and_modifiers_get_suggestions() {
    assert_eq!(
        rendered("new Rules.Splitt(Axis.Y, Relative(1)).Fulfills(\"chair\");"),
        "\
error: unknown rule `Rules.Splitt`
 --> t.cs:1:5
  |
1 | new Rules.Splitt(Axis.Y, Relative(1)).Fulfills(\"chair\");
  |     ^^^^^^^^^^^^
  = hint: did you mean `Rules.Split`?
"
    );
    assert_eq!(
        rendered("Rules.Extrude(2);"),
        "\
error: unknown rule `Rules.Extrude`
 --> t.cs:1:1
  |
1 | Rules.Extrude(2);
  | ^^^^^^^^^^^^^
  = hint: the rules are `Rules.Split`, `Rules.Repeat`, `Rules.Size`, `Rules.Scale`, `Rules.Translate`, `Rules.Rotate`, `Rules.Color`, `Rules.Material`, `Rules.Insert`, `Rules.Comp`, `Rules.Taper`, `Rules.Twist`, `Rules.Shear` and `Rules.Identity`
"
    );
    assert_eq!(
        rendered("new Rules.Split(Axis.Y, Relative(1))\n.Fullfills(\"chair\");"),
        "\
error: unknown rule modifier `Fullfills`
 --> t.cs:2:2
  |
2 | .Fullfills(\"chair\");
  |  ^^^^^^^^^
  = hint: did you mean `Fulfills`?
"
    );
    assert_eq!(
        rendered("Rules.Split(Axis.Y, Relative(1).Atribute(\"a\", 1));"),
        "\
error: unknown part modifier `Atribute`
 --> t.cs:1:33
  |
1 | Rules.Split(Axis.Y, Relative(1).Atribute(\"a\", 1));
  |                                 ^^^^^^^^
  = hint: did you mean `Attribute`?
"
    );
    assert_eq!(
        rendered("using (Predicates.IfIz(\"a\")) { }"),
        "\
error: unknown predicate modifier `IfIz`
 --> t.cs:1:19
  |
1 | using (Predicates.IfIz(\"a\")) { }
  |                   ^^^^
  = hint: did you mean `IfIs`?
"
    );
    assert_eq!(
        rendered("using (Predicates) { }"),
        "\
error: `using` without a predicate
 --> t.cs:1:7
  |
1 | using (Predicates) { }
  |       ^
  = hint: write at least one, e.g. `using (Predicates.IfIs(\"chair\")) { … }`
"
    );
}

#[test]
fn wrong_argument_counts_name_the_construct() {
    assert_eq!(
        rendered("new Rules.Size(Axis.Z).Fulfills(\"lean\");"),
        "\
error: `Rules.Size` takes 2 arguments, found 1
 --> t.cs:1:5
  |
1 | new Rules.Size(Axis.Z).Fulfills(\"lean\");
  |     ^^^^^^^^^^^^^^^^^^
  = hint: write `Rules.Size(Axis.Z, 0.04)`
"
    );
    assert_eq!(
        rendered("Rules.Repeat(Axis.X);"),
        "\
error: `Rules.Repeat` takes at least 2 arguments, found 1
 --> t.cs:1:1
  |
1 | Rules.Repeat(Axis.X);
  | ^^^^^^^^^^^^^^^^^^^^
  = hint: write `Rules.Repeat(Axis.X, Absolute(1.5), …)`
"
    );
    assert_eq!(
        rendered("Rules.Identity(1);"),
        "\
error: `Rules.Identity` takes no arguments, found 1
 --> t.cs:1:1
  |
1 | Rules.Identity(1);
  | ^^^^^^^^^^^^^^^^^
  = hint: write `Rules.Identity()`
"
    );
    assert_eq!(
        rendered("Rules.Color();"),
        "\
error: `Rules.Color` takes 1 argument, found 0
 --> t.cs:1:1
  |
1 | Rules.Color();
  | ^^^^^^^^^^^^^
  = hint: write `Rules.Color(\"#8b5a2b\")`
"
    );
    assert_eq!(
        rendered("new Axiom(\"chair\").Size(0.4, 0.8);"),
        "\
error: `Size` takes 3 values (x, y, z), found 2
 --> t.cs:1:20
  |
1 | new Axiom(\"chair\").Size(0.4, 0.8);
  |                    ^^^^^^^^^^^^^^
"
    );
    assert_eq!(
        rendered("Rules.Scale(Vec3(1, 1), Pivot.Middle);"),
        "\
error: `Vec3` takes 3 values (x, y, z), found 2
 --> t.cs:1:13
  |
1 | Rules.Scale(Vec3(1, 1), Pivot.Middle);
  |             ^^^^^^^^^^
"
    );
    assert_eq!(
        rendered("Rules.Split(Axis.Y, Relative(1).Attribute(\"a\"));"),
        "\
error: `Attribute` takes 2 arguments (name, value), found 1
 --> t.cs:1:33
  |
1 | Rules.Split(Axis.Y, Relative(1).Attribute(\"a\"));
  |                                 ^^^^^^^^^^^^^^
  = hint: write `.Attribute(\"Leg.Size\", 0.04)`
"
    );
}

#[test]
fn wrong_arguments_are_explained() {
    assert_eq!(
        rendered("Rules.Scale(Vec3(1, 1, 1), Pivot.Midle);"),
        "\
error: unknown pivot `Pivot.Midle`
 --> t.cs:1:28
  |
1 | Rules.Scale(Vec3(1, 1, 1), Pivot.Midle);
  |                            ^^^^^^^^^^^ in `Rules.Scale`
  = hint: did you mean `Pivot.Middle`?
  = hint: the pivots are `Pivot.Middle`, `Pivot.Bottom`, `Pivot.Min` and `Pivot.Origin`
"
    );
    assert_eq!(
        rendered("Rules.Size(Axis.y, 1);"),
        "\
error: expected `Axis.X`, `Axis.Y` or `Axis.Z`
 --> t.cs:1:12
  |
1 | Rules.Size(Axis.y, 1);
  |            ^^^^^^ in `Rules.Size`
  = hint: did you mean `Axis.Y`?
"
    );
    assert_eq!(
        rendered("Rules.Split(Axis.Y, 0.5, Face.Top);"),
        "\
error: expected a part `Relative(…)` or `Absolute(…)`
 --> t.cs:1:21
  |
1 | Rules.Split(Axis.Y, 0.5, Face.Top);
  |                     ^^^ in `Rules.Split`
  = hint: parts are written `Relative(0.4).Goal(\"support\")` or `Absolute(0.04).Void()`
error: expected a part `Relative(…)` or `Absolute(…)`
 --> t.cs:1:26
  |
1 | Rules.Split(Axis.Y, 0.5, Face.Top);
  |                          ^^^^^^^^ in `Rules.Split`
  = hint: faces are parts of `Rules.Comp`
"
    );
    assert_eq!(
        rendered("Rules.Comp(Face.Sides.Void());"),
        "\
error: unknown face `Face.Sides`
 --> t.cs:1:17
  |
1 | Rules.Comp(Face.Sides.Void());
  |                 ^^^^^
  = hint: did you mean `Face.Side`?
"
    );
    assert_eq!(
        rendered("Rules.Identity().Fulfills(chair);"),
        "\
error: expected a goal as a string in `Fulfills`, found `chair`
 --> t.cs:1:27
  |
1 | Rules.Identity().Fulfills(chair);
  |                           ^^^^^
  = hint: write \"chair\"
"
    );
    assert_eq!(
        rendered("Rules.Identity().IfHas();"),
        "\
error: `IfHas` takes at least one attribute name
 --> t.cs:1:18
  |
1 | Rules.Identity().IfHas();
  |                  ^^^^^^^
  = hint: write `IfHas(\"name\")`
"
    );
    assert_eq!(
        rendered("Rules.Repeat(Axis.X, Absolute(1).Sync(\"windows\"));"),
        "\
error: expected the name of a `Synchronize` variable
 --> t.cs:1:34
  |
1 | Rules.Repeat(Axis.X, Absolute(1).Sync(\"windows\"));
  |                                  ^^^^^^^^^^^^^^^ in `Sync`
  = hint: declare one with `var windows = new Synchronize();` and write `.Sync(windows)`
"
    );
}

#[test]
fn modifiers_in_the_wrong_place() {
    assert_eq!(
        rendered("Rules.Split(Axis.Y, Relative(1).Void().Goal(\"x\"));"),
        "\
error: a void part takes no other modifier
 --> t.cs:1:40
  |
1 | Rules.Split(Axis.Y, Relative(1).Void().Goal(\"x\"));
  |                                        ^^^^^^^^^ besides `Void()`
  = hint: `.Void()` deletes the part: its goals, attributes and synchronizations would be lost
"
    );
    assert_eq!(
        rendered("Rules.Split(Axis.Y,\n  Relative(1).Goal(\"a\")\n.Fulfills(\"b\");"),
        "\
error: `Fulfills` is a modifier of rules, not of parts
 --> t.cs:3:2
  |
3 | .Fulfills(\"b\");
  |  ^^^^^^^^
  = hint: write it after the rule's closing parenthesis: `new Rules.Split(Axis.Y, …).Fulfills(\"chair\");`
error: expected `,` or `)` in the arguments of `Rules.Split`, found `;`
 --> t.cs:3:15
  |
3 | .Fulfills(\"b\");
  |               ^ expected `,` or `)` here
"
    );
    assert_eq!(
        rendered("Rules.Split(Axis.Y, Relative(1)).Void();"),
        "\
error: `Void` is a modifier of parts, not of rules
 --> t.cs:1:34
  |
1 | Rules.Split(Axis.Y, Relative(1)).Void();
  |                                  ^^^^
  = hint: write it on a part: `Relative(1).Void()`
"
    );
    assert_eq!(
        rendered("using (Predicates.IfIs(\"a\").Fulfills(\"b\")) { }"),
        "\
error: `using` gives its rules conditions, not goals to fulfil or add
 --> t.cs:1:29
  |
1 | using (Predicates.IfIs(\"a\").Fulfills(\"b\")) { }
  |                             ^^^^^^^^
  = hint: write `.Fulfills(…)` and `.Goal(…)` on each rule
"
    );
}

#[test]
fn statements_blocks_and_declarations() {
    assert_eq!(
        rendered("using (Predicates.IfIs(\"a\")) {\n  Rules.Identity();\n"),
        "\
error: unclosed `{`
 --> t.cs:1:30
  |
1 | using (Predicates.IfIs(\"a\")) {
  |                              ^ this `using` block is never closed
  = hint: close it with `}` after its last rule
"
    );
    assert_eq!(
        rendered("}\nchair.Split();"),
        "\
error: unexpected `}`
 --> t.cs:1:1
  |
1 | }
  | ^ no `using` block is open here
error: expected a statement, found `chair.Split`
 --> t.cs:2:1
  |
2 | chair.Split();
  | ^^^^^^^^^^^ expected a statement here
  = hint: a Michelangelo grammar holds `new Axiom(\"goal\", …);`, `var name = new Synchronize();`, rules `new Rules.Split(…).Fulfills(\"goal\");` and `using (Predicates.IfIs(\"tag\")) { rules }`
"
    );
    assert_eq!(
        rendered("var w = new Synchronize();\nvar w = new Synchronize();\nvar v = new List();"),
        "\
error: the synchronization `w` is declared twice
 --> t.cs:2:5
  |
2 | var w = new Synchronize();
  |     ^ first declared on line 1
error: expected `new Synchronize()` after `var v =`, found `new`
 --> t.cs:3:9
  |
3 | var v = new List();
  |         ^^^ expected `new Synchronize()` here
  = hint: `var` declares synchronizations: `var windows = new Synchronize();`
"
    );
    assert_eq!(
        rendered("new Synchronize();"),
        "\
error: a `Synchronize` must be kept in a variable
 --> t.cs:1:1
  |
1 | new Synchronize();
  | ^^^^^^^^^^^^^^^
  = hint: declare it as `var windows = new Synchronize();`
"
    );
}

#[test]
fn one_run_reports_several_errors_and_keeps_the_good_rules() {
    let text = "\
new Axiom(\"chair\").Size(1, 2);
new Rules.Splitt(Axis.Y, Relative(1)).Fulfills(\"chair\");
new Rules.Size(Axis.Z, 0.04).Fulfills(\"lean\");
new Rules.Split(Axis.Y, Relative(1)).Fullfills(\"a\")
new Rules.Scale(Vec3(1, 1, 1), Pivot.Top).Fulfills(\"b\");
using (Predicates.IfIs(\"chair\")) {
    Rules.Twist(Axis.Y).Fulfills(\"c\");
    Rules.Twist(Axis.Y, 45).Fulfills(\"d\");
}
new Rules.Identity().Fulfills(\"e\");
";
    let source = SourceFile::new("t", text);
    let parsed = parse_as(&source, Dialect::Michelangelo);
    let found: Vec<String> = parsed
        .diagnostics
        .iter()
        .map(|d| {
            let (line, col) = source.line_col(d.span.start);
            format!("{line}:{col} {}", d.message)
        })
        .collect();
    assert_eq!(
        found,
        [
            "1:20 `Size` takes 3 values (x, y, z), found 2",
            "2:5 unknown rule `Rules.Splitt`",
            "4:38 unknown rule modifier `Fullfills`",
            "4:52 expected `;` after the rule, found `new`",
            "5:32 unknown pivot `Pivot.Top`",
            "7:5 `Rules.Twist` takes 2 arguments, found 1",
        ]
    );
    assert!(parsed.grammar.axioms.is_empty());
    assert_eq!(
        rules(&parsed.grammar),
        [
            "[fulfills lean] => (s('1, '1, 0.04))",
            "[fulfills d] [is chair] => (twist(y, 45))",
            "[fulfills e] => ()",
        ]
    );
}

// --- Robustness --------------------------------------------------------------------------------

/// Parses `text` in both goal notations: no panic, every span inside the text on character
/// boundaries, every diagnostic renders.
fn check_robust(text: &str) {
    let source = SourceFile::new("fuzz", text);
    for dialect in [Dialect::Michelangelo, Dialect::Goal] {
        for d in &parse_as(&source, dialect).diagnostics {
            let Span { start, end } = d.span;
            assert!(
                start <= end && end as usize <= text.len(),
                "{dialect:?}: {d:?}"
            );
            assert!(text.is_char_boundary(start as usize) && text.is_char_boundary(end as usize));
            assert!(source.render(d).contains('^'));
        }
    }
    let _ = detect(text);
}

#[test]
fn deep_nesting_is_an_error() {
    let n = 100_000;
    for text in [
        "using (Predicates.IfIs(\"a\")) {".repeat(n),
        format!("Rules.Size(Axis.Z, {}1);", "(".repeat(n)),
        format!("Rules.Identity().If(s => {}1);", "!".repeat(n)),
    ] {
        let parsed = parse_as(&SourceFile::new("t", text.as_str()), Dialect::Michelangelo);
        let messages: Vec<&str> = parsed
            .diagnostics
            .iter()
            .map(|d| d.message.as_str())
            .collect();
        assert_eq!(messages, ["nesting too deep"]);
    }
}

#[test]
fn fragments_and_garbage_never_panic() {
    for text in [
        "new",
        "new Rules.",
        "Rules.Split(",
        "Rules.Split(Axis.Y, Relative(",
        "Rules.Split(Axis.Y, Relative(1).",
        "Rules.Split(Axis.Y, Relative(1).Goal(",
        "Rules.Comp(Face.",
        "Rules.Comp(Face.Top.Goal.Void())",
        "Rules.Identity().If(s =>",
        "Rules.Identity().If((s) =>",
        "using (",
        "using (Predicates.IfIs.X(\"a\")) {",
        "var",
        "var x = new Synchronize(1",
        "new Axiom(\"a\").Size(",
        "↪ ↪ ;;; } } {",
        ".Fulfills(\"a\");",
        "Rules.Scale(Vec3(1, 2, 3)",
    ] {
        check_robust(text);
    }
}

/// Pieces of the notation, so generated inputs get deep into the parser.
fn soup() -> impl Strategy<Value = String> {
    let piece = prop::sample::select(vec![
        "new",
        "Axiom(\"a\")",
        "Rules.Split",
        "Rules.Repeat",
        "Rules.Comp",
        "Rules.Scale",
        "Rules.Size",
        "Rules.Identity()",
        "(",
        ")",
        "{",
        "}",
        ",",
        ";",
        ".",
        "Axis.Y",
        "Relative(1)",
        "Absolute(@Double(\"w\"))",
        "Face.Top",
        ".Goal(\"g\")",
        ".goal(\"l\")",
        ".Void()",
        ".Sync(w)",
        ".Attribute(\"a\", Rnd(0, 1))",
        ".Fulfills(\"f\")",
        ".IfIs(\"t\")",
        ".If(s => s.Size.X < 1)",
        "Vec3(1, 2, 3)",
        "Pivot.Middle",
        "using (Predicates.IfIs(\"c\"))",
        "var w = new Synchronize()",
        "↪",
        "\n",
        "/*",
        "*/",
    ]);
    prop::collection::vec(piece, 0..60).prop_map(|pieces| pieces.join(" "))
}

proptest! {
    #[test]
    fn arbitrary_strings_never_panic(text in any::<String>()) {
        check_robust(&text);
    }

    #[test]
    fn soup_never_panics(text in soup()) {
        check_robust(&text);
    }
}
