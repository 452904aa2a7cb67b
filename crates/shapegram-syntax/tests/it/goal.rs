//! The native notation of goal grammars.

use crate::common;

use common::{goal_rule, render_all};
use shapegram_syntax::{Dialect, SourceFile, parse_as};

fn parse_goal(text: &str) -> shapegram_syntax::ast::Grammar {
    let source = SourceFile::new("test.goal", text);
    let parsed = parse_as(&source, Dialect::Goal);
    assert!(
        parsed.diagnostics.is_empty(),
        "unexpected diagnostics:\n{}",
        render_all(&source, &parsed.diagnostics)
    );
    parsed.grammar
}

fn errors(text: &str) -> String {
    let source = SourceFile::new("test.goal", text);
    let parsed = parse_as(&source, Dialect::Goal);
    render_all(&source, &parsed.diagnostics)
}

const CHAIR: &str = r#"
local "split-legs"
axiom chair, wooden size(0.4, 0.8, 0.4)

fulfills(chair) -->
    split(y) { ~0.4 : set(@Leg.Size, rand(0.03, 0.05)) +support
             | ~0.05 : +seat
             | ~0.55 : +lean }

using is(chair) {
    fulfills(support) --> split(x) { @Leg.Size : +"split-legs" | ~1 : void | @Leg.Size : +"split-legs" }
    fulfills("split-legs") --> split(z) { @Leg.Size : +leg | ~1 : void | @Leg.Size : +leg }
    fulfills(lean) --> s('1, '1, 0.04)
}
"#;

#[test]
fn the_chair_parses_into_axioms_locals_and_goal_rules() {
    let g = parse_goal(CHAIR);
    assert_eq!(g.local_goals.len(), 1);
    assert_eq!(g.local_goals[0].name, "split-legs");
    assert_eq!(g.axioms.len(), 1);
    let goals: Vec<&str> = g.axioms[0].goals.iter().map(|g| g.name.as_str()).collect();
    assert_eq!(goals, ["chair", "wooden"]);
    assert!(g.axioms[0].size.is_some());
    let rules: Vec<String> = g.goal_rules.iter().map(goal_rule).collect();
    assert_eq!(
        rules,
        [
            "[fulfills chair] => (split(y){~0.4 : (set(@Leg.Size, rand(0.03, 0.05)) +support) | ~0.05 : (+seat) | ~0.55 : (+lean)})",
            "[fulfills support] [is chair] => (split(x){@Leg.Size : (+split-legs) | ~1 : (NIL) | @Leg.Size : (+split-legs)})",
            "[fulfills split-legs] [is chair] => (split(z){@Leg.Size : (+leg) | ~1 : (NIL) | @Leg.Size : (+leg)})",
            "[fulfills lean] [is chair] => (s('1, '1, 0.04))",
        ]
    );
    assert!(g.rules.is_empty());
}

#[test]
fn predicates_negate_nest_and_add_goals() {
    let g = parse_goal(
        "sync windows\n\
         using is(facade) {\n\
           using !is(ruin) {\n\
             goal(romantic) has(Leg.Size) if(scope.sx < 0.8) fulfills(setting) adds(metallic) --> color(\"#808080\") +plate +cup\n\
           }\n\
           !goal(x) fulfills(floor) --> split(x) { { ~1.5 : sync(windows) +Window }* }\n\
         }",
    );
    assert_eq!(g.syncs.len(), 1);
    let rules: Vec<String> = g.goal_rules.iter().map(goal_rule).collect();
    assert_eq!(
        rules,
        [
            "[fulfills setting] [adds metallic] [is facade] [!is ruin] [goal romantic] [has Leg.Size] [if (scope.sx < 0.8)] => (color(\"#808080\") +plate+cup)",
            "[fulfills floor] [is facade] [!goal x] => (split(x){{~1.5 : (sync(windows) +Window)}*})",
        ]
    );
}

#[test]
fn malformed_heads_are_reported_with_their_place() {
    let out = errors("!fulfills(chair) --> color(\"#fff\")\n");
    assert!(out.contains("`fulfills` cannot be negated"), "{out}");
    assert!(out.contains("1:1"), "{out}");
    let out = errors("axiom chair size(1, 2)\n");
    assert!(
        out.contains("`size` takes 3 values (x, y, z), found 2"),
        "{out}"
    );
    let out = errors("using fulfills(chair) { is(x) --> NIL }\n");
    assert!(out.contains("`using` gives its rules conditions"), "{out}");
    let out = errors("chair --> NIL\n");
    assert!(out.contains("expected a goal-grammar declaration"), "{out}");
    let out = errors("using is(chair) {\n fulfills(a) --> +b\n");
    assert!(out.contains("unclosed `{`"), "{out}");
}

#[test]
fn misspelt_predicates_are_named_and_deep_nesting_is_refused() {
    let out = errors(
        "axiom a size(1, 1, 1)\nfulfills(a) --> color(\"#fff\")\nfulfil(seat) --> color(\"#fff\")\n",
    );
    assert_eq!(out.matches("error:").count(), 1, "{out}");
    assert!(out.contains("error: unknown predicate `fulfil`"), "{out}");
    assert!(out.contains("3:1"), "{out}");
    assert!(out.contains("did you mean `fulfills`?"), "{out}");
    // `adds` alone is a head.
    let g = parse_goal("adds(b) --> color(\"#000\")\n");
    assert_eq!(goal_rule(&g.goal_rules[0]), "[adds b] => (color(\"#000\"))");
    // Nested `using` blocks stop at the parser's depth limit with an error, not a crash.
    let deep = format!(
        "{}fulfills(a) --> NIL\n{}",
        "using is(t) {\n".repeat(5_000),
        "}\n".repeat(5_000)
    );
    let out = errors(&deep);
    assert!(
        out.contains("nesting too deep"),
        "{}",
        &out[..out.len().min(300)]
    );
}
