//! Bad input: every malformed file gets one error with its line and column, never a panic.

use proptest::prelude::*;
use shapegram_lsystem::{DeriveOptions, LSystem};

fn error(text: &str) -> String {
    match LSystem::parse(text) {
        Ok(_) => panic!("parsed: {text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn malformed_productions() {
    let cases = [
        (
            "axiom: A\nAB -> C\n",
            "2:2: the predecessor must be exactly one module, found 2 (write contexts with < and >)",
        ),
        (
            "axiom: A\n -> C\n",
            "2:2: the predecessor must be exactly one module, found 0",
        ),
        (
            "axiom: A\nA(x -> B\n",
            "2:2: this '(' is not closed before the production's arrow",
        ),
        (
            "axiom: A\nA(x) : (x > 1 -> B\n",
            "2:8: this '(' is not closed before the production's arrow",
        ),
        (
            "axiom: A\nA -> B(1\n",
            "2:9: expected ',' or ')' after a parameter of 'B', found the end of the line",
        ),
        (
            "axiom: A\nA -> B(1 +)\n",
            "2:11: expected a number, a name or '(', found ')'",
        ),
        (
            "axiom: A\nA(x) -> B(y)\n",
            "2:11: unknown name 'y' (not a parameter of this production or a defined constant)",
        ),
        (
            "axiom: A\nA(x, x) -> B\n",
            "2:1: the parameter name 'x' is used twice in this production",
        ),
        (
            "axiom: A\nA(1) -> B\n",
            "2:3: expected a parameter name in the predecessor, found '1'",
        ),
        (
            "axiom: A\nA (x) -> B\n",
            "2:4: unknown name 'x' (not a parameter of this production or a defined constant) (a weight in parentheses must be a number; parameters follow their module without a space: F(x))",
        ),
        (
            "axiom: A\nA (0) -> B\n",
            "2:4: a weight must be positive, not 0",
        ),
        (
            "axiom: A\nA -> B\nA -> C\n",
            "3:1: another production with the same left side is on line 2: give each alternative a weight, as in `A (0.5) -> …`",
        ),
        (
            "axiom: A\nA < B < C -> D\n",
            "2:7: a production has at most one left context '<'",
        ),
        (
            "axiom: A\n< A -> B\n",
            "2:1: expected a left context before '<'",
        ),
        (
            "axiom: A\nA > -> B\n",
            "2:3: expected a right context after '>'",
        ),
        (
            "axiom: A[B]\n[ < A -> B\n",
            "2:1: a left context cannot hold brackets: it is read along the path to the root",
        ),
        (
            "axiom: A\nA(x) : x > -> B\n",
            "2:12: expected a number, a name or '(', found the end of the line",
        ),
        (
            "axiom: A\nA(x) : x > 1 (0.5) -> B\n",
            "2:14: unexpected '(' after the condition (a weight goes before the condition: `A(x) (0.5) : x > 1 -> …`)",
        ),
        (
            "axiom: A\nA -> B (1)\n",
            "2:8: expected a module, found '(' (parameters follow their module without a space: F(1))",
        ),
        ("axiom: A\nA -> [(1)\n", "2:6: '[' takes no parameters"),
    ];
    for (text, expected) in cases {
        assert_eq!(error(text), expected, "{text}");
    }
}

#[test]
fn unknown_symbols_in_contexts() {
    assert_eq!(
        error("axiom: baaa\nc < a -> b\n"),
        "2:1: unknown symbol 'c' in a context: it is in neither the axiom nor any successor, so the production could never apply"
    );
    assert_eq!(
        error("axiom: A(1)A(2)\nA < A(x) -> B\n"),
        "2:1: 'A' never has 0 parameters in a word (it has 1), so this context could never match"
    );
    assert_eq!(
        error("ignore: F\naxiom: JFFJ\nJF < F > J -> G\n"),
        "3:2: 'F' is in the ignore set, which context matching skips, so this context could never match (drop it from the context or from `ignore:`)"
    );
}

#[test]
fn malformed_settings() {
    let cases = [
        ("", "the L-system has no axiom: add a line like `axiom: F`"),
        (
            "n: 3\n",
            "the L-system has no axiom: add a line like `axiom: F`",
        ),
        (
            "axiom: A\nn: -1\n",
            "2:4: n must be a whole number from 0 to 10000, not -1",
        ),
        (
            "axiom: A\nn: 2.5\n",
            "2:4: n must be a whole number from 0 to 10000, not 2.5",
        ),
        (
            "axiom: A\nangle: x\n",
            "2:8: unknown name 'x' (not a parameter of this production or a defined constant)",
        ),
        ("axiom: A\nstep: 0\n", "2:7: step must be positive, not 0"),
        ("axiom: A\nsides: 2\n", "2:8: sides must be at least 3"),
        (
            "axiom: A\nangel: 20\n",
            "2:1: unknown setting 'angel' (the settings are: n, angle, step, width, width-factor, seed, sides, colors, ignore, draw, move, define, axiom)",
        ),
        (
            "axiom: A\naxiom: B\n",
            "2:1: 'axiom' is set twice (first on line 1)",
        ),
        (
            "axiom: A\nhello\n",
            "2:6: expected a setting like `n: 5` or a production like `A -> AB`",
        ),
        (
            "axiom: A\ndefine: 3 = 4\n",
            "2:9: expected a name after `define:`, as in `define: r = 0.5`",
        ),
        (
            "axiom: A\ndefine: r\n",
            "2:10: expected '=' after the name 'r', found the end of the line",
        ),
        (
            "axiom: A\ncolors: #12345z\n",
            "2:9: invalid colour '#12345z': expected #rrggbb",
        ),
        ("axiom: A\nn: 3 4\n", "2:6: unexpected '4' after the value"),
        (
            "axiom: A(\n",
            "1:10: expected a number, a name or '(', found the end of the line",
        ),
        ("axiom: A(1/0)\n", "1:10: the value is not a finite number"),
        (
            "ignore: +[\naxiom: A\n",
            "1:9: brackets cannot be ignored: they give words their branch structure",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(error(text), expected, "{text}");
    }
    assert_eq!(
        error("axiom: A\ndecomposition:\n"),
        "2:1: decomposition rules are not supported (interpretation rules are: `homomorphism:`)"
    );
}

#[test]
fn derivation_length_is_limited_from_options_too() {
    // The word stays one module long: only the limit stops a billion steps.
    let system = LSystem::parse("axiom: A\nA -> A\n").unwrap();
    let derive = |n| {
        system.derive(&DeriveOptions {
            iterations: Some(n),
            ..DeriveOptions::default()
        })
    };
    assert_eq!(
        derive(10_001).unwrap_err().to_string(),
        "10,001 derivation steps asked for; at most 10,000 are allowed"
    );
    assert_eq!(
        derive(1_000_000_000).unwrap_err().to_string(),
        "1,000,000,000 derivation steps asked for; at most 10,000 are allowed"
    );
    assert_eq!(system.word_text(&derive(10_000).unwrap()), "A");
}

#[test]
fn errors_render_with_a_caret() {
    let text = "axiom: A\nA -> B(1 +)\n";
    let err = LSystem::parse(text).unwrap_err();
    assert_eq!(
        err.render("plant.lsys", text),
        "plant.lsys:2:11: expected a number, a name or '(', found ')'\n2 | A -> B(1 +)\n  |           ^\n"
    );
}

#[test]
fn comments_blank_lines_and_unicode_arrows_are_fine() {
    let text = "# a comment\n\nω: a   # the axiom\na → ab  # grows\nb -> a\nn: 3\ncolors: #aabbcc #123 # two colours\n";
    let system = LSystem::parse(text).unwrap();
    assert_eq!(system.settings.colors.len(), 2);
    let word = system.derive(&DeriveOptions::default()).unwrap();
    assert_eq!(system.word_text(&word), "abaab");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Any text either parses or gives an error; a parsed system derives or gives an error.
    #[test]
    fn arbitrary_text_never_panics(text in "(axiom: [AB()\\[\\]+x,0-9]{0,8}\n)?([AB<>:()x,+*/0-9 \\[\\]-]{0,14}(->|: )[AB()x,+*/0-9 \\[\\]-]{0,10}\n){0,4}") {
        if let Ok(system) = LSystem::parse(&text) {
            let options = DeriveOptions { iterations: Some(4), max_modules: 10_000, ..DeriveOptions::default() };
            let _ = system.derive(&options);
        }
    }
}
