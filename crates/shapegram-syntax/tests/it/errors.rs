//! Diagnostics: exact renderings of typical mistakes, recovery, and hostile input.

use crate::common;

use common::{parse_str, render_all};
use proptest::prelude::*;
use shapegram_syntax::{Diagnostic, Severity, SourceFile, Span, parse};

/// All diagnostics of `text`, rendered.
fn rendered(text: &str) -> String {
    let (source, parsed) = parse_str(text);
    render_all(&source, &parsed.diagnostics)
}

/// The messages of all diagnostics of `text`.
fn messages(text: &str) -> Vec<String> {
    parse_str(text)
        .1
        .diagnostics
        .into_iter()
        .map(|d| d.message)
        .collect()
}

/// Parses without panicking and checks that every span is inside the text on character
/// boundaries and that every diagnostic renders.
fn check_robust(text: &str) -> Vec<Diagnostic> {
    let source = SourceFile::new("fuzz.cga", text);
    let parsed = parse(&source);
    for d in &parsed.diagnostics {
        let Span { start, end } = d.span;
        assert!(
            start <= end && end as usize <= text.len(),
            "span {:?} out of range",
            d.span
        );
        assert!(text.is_char_boundary(start as usize) && text.is_char_boundary(end as usize));
        let out = source.render(d);
        assert!(out.contains('^'), "{out}");
    }
    parsed.diagnostics
}

#[test]
fn missing_colon_in_a_split() {
    assert_eq!(
        rendered("Facade -->\n    split(y){ 4.5 Ground | ~3 : Floor }*\n"),
        "\
error: expected `:` after the split size, found `Ground`
 --> test.cga:2:19
  |
2 |     split(y){ 4.5 Ground | ~3 : Floor }*
  |                   ^^^^^^ expected `:` here
"
    );
}

#[test]
fn missing_colon_after_a_selector_with_a_two_digit_line_number() {
    let text = format!("{}A --> comp(f){{ front A | side : B }}\n", "\n".repeat(11));
    assert_eq!(
        rendered(&text),
        "\
error: expected `:` after the selector, found `A`
  --> test.cga:12:22
   |
12 | A --> comp(f){ front A | side : B }
   |                      ^ expected `:` here
"
    );
}

#[test]
fn unclosed_block() {
    assert_eq!(
        rendered("A --> split(y){ 1 : B | 2 : C\nD --> E\n"),
        "\
error: unclosed `{`
 --> test.cga:1:15
  |
1 | A --> split(y){ 1 : B | 2 : C
  |               ^ this block is never closed
  = hint: close the block with `}` before the next declaration
"
    );
}

#[test]
fn missing_rule_arrow() {
    assert_eq!(
        rendered("Lot extrude(10) Mass\nMass --> X.\n"),
        "\
error: expected `-->` after the rule name `Lot`, found `extrude`
 --> test.cga:1:5
  |
1 | Lot extrude(10) Mass
  |     ^^^^^^^ expected `-->` here
  = hint: rules are written `Lot --> body`
"
    );
    assert_eq!(
        rendered("Lot -> extrude(10)\n"),
        "\
error: expected `-->`, found `->`
 --> test.cga:1:5
  |
1 | Lot -> extrude(10)
  |     ^^ expected `-->` here
  = hint: rules are written with a long arrow: `Name --> body`
"
    );
    assert_eq!(
        rendered("Lot\n"),
        "\
error: expected `-->` or `=` after `Lot`, found end of file
 --> test.cga:1:4
  |
1 | Lot
  |    ^ expected `-->` or `=` here
  = hint: a rule is written `Name --> body`, a function `name = expression`
"
    );
}

#[test]
fn the_arrow_is_recovered_so_the_rule_is_kept() {
    let (_, parsed) = parse_str("Lot extrude(10) Mass\nMass --> X.\n");
    let names: Vec<&str> = parsed
        .grammar
        .rules
        .iter()
        .map(|r| r.name.name.as_str())
        .collect();
    assert_eq!(names, ["Lot", "Mass"]);
    assert_eq!(
        common::rule_body(&parsed.grammar, "Lot"),
        "(extrude(10) Mass)"
    );
}

#[test]
fn bad_token() {
    assert_eq!(
        rendered("A --> B $ C\n"),
        "\
error: unexpected character `$`
 --> test.cga:1:9
  |
1 | A --> B $ C
  |         ^
"
    );
    assert_eq!(messages("A --> B €§ C"), ["unexpected characters `€§`"]);
}

#[test]
fn unterminated_string_stops_at_the_end_of_its_line() {
    let (source, parsed) = parse_str("attr s = \"abc\nA --> B\n");
    assert_eq!(
        render_all(&source, &parsed.diagnostics),
        "\
error: unterminated string
 --> test.cga:1:10
  |
1 | attr s = \"abc
  |          ^^^^ this string has no closing `\"`
"
    );
    assert_eq!(parsed.grammar.rules.len(), 1, "the next line still parses");
}

#[test]
fn unterminated_block_comment() {
    assert_eq!(
        rendered("A --> B\n/* open\nB --> C\n"),
        "\
error: unterminated block comment
 --> test.cga:2:1
  |
2 | /* open
  | ^^ this comment is never closed
  = hint: close it with `*/`
"
    );
}

#[test]
fn number_too_large_and_bad_escape() {
    assert_eq!(
        rendered("attr x = 1e999\n"),
        "\
error: number too large
 --> test.cga:1:10
  |
1 | attr x = 1e999
  |          ^^^^^
  = hint: numbers must fit in a 64-bit float (at most about 1.8e308)
"
    );
    assert_eq!(
        messages(r#"attr a = "bad \q""#),
        ["unknown escape sequence `\\q`"]
    );
}

#[test]
fn tabs_are_expanded_and_carets_follow() {
    assert_eq!(
        rendered("\tA -->\tsplit(x){\t1 X }\n"),
        "\
error: expected `:` after the split size, found `X`
 --> test.cga:1:20
  |
1 |     A -->    split(x){    1 X }
  |                             ^ expected `:` here
"
    );
}

#[test]
fn unclosed_parenthesis_points_at_the_opening_one() {
    assert_eq!(
        rendered("A --> t(0, 1\nB --> C\n"),
        "\
error: unclosed `(`
 --> test.cga:1:8
  |
1 | A --> t(0, 1
  |        ^ this bracket is never closed
"
    );
}

#[test]
fn several_errors_are_reported_in_one_file() {
    let text = "\
attr a =
attr b = 1 2
A --> t(0,,0) B
C --> split(x){ 1 : D E | : F }
G --> case x A else: B
H --> B else: C
I --> X case y : Z
J --> K
";
    let (source, parsed) = parse_str(text);
    let found: Vec<((usize, usize), &str)> = parsed
        .diagnostics
        .iter()
        .map(|d| (source.line_col(d.span.start), d.message.as_str()))
        .collect();
    assert_eq!(
        found,
        [
            ((2, 1), "expected an expression, found `attr`"),
            (
                (2, 12),
                "expected an operator or the next declaration after the value of `b`, found `2`"
            ),
            ((3, 11), "expected an expression, found `,`"),
            ((4, 27), "expected a split size in the block, found `:`"),
            ((5, 14), "expected `:` after the case condition, found `A`"),
            ((6, 9), "`else` without a matching `case` or percentage"),
            (
                (7, 9),
                "expected a statement or the next declaration in the rule body, found `case`"
            ),
        ]
    );
    // Recovery keeps the declarations that are fine, including the last rule.
    assert!(parsed.grammar.rules.iter().any(|r| r.name.name == "J"));
}

#[test]
fn missing_else_in_expressions() {
    assert_eq!(
        messages("attr v = 30% : 1\nattr w = case a : 1\n"),
        [
            "expected another percentage or `else`, found `attr`",
            "expected `case` or `else`, found end of file",
        ]
    );
}

#[test]
fn stray_annotation_and_stray_tokens() {
    assert_eq!(
        messages("@StartRule\n"),
        ["expected a declaration after the annotation, found end of file"]
    );
    assert_eq!(
        messages("}{ A --> B"),
        ["expected a declaration, found `}`"]
    );
    assert_eq!(
        messages("A --> [ X ] ) Y\nB --> C"),
        ["expected a statement or the next declaration in the rule body, found `)`"]
    );
}

#[test]
fn warnings_are_not_errors() {
    let (_, parsed) = parse_str("style Red\nA --> B");
    assert_eq!(parsed.diagnostics.len(), 1);
    assert_eq!(parsed.diagnostics[0].severity, Severity::Warning);
    assert!(!parsed.has_errors());
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let n = 100_000;
    let inputs = [
        format!("attr x = {}1", "(".repeat(n)),
        format!("attr x = {}1", "-".repeat(n)),
        format!("attr x = {}1", "'".repeat(n)),
        format!("attr x = {}1", "[".repeat(n)),
        format!("attr x = {}1", "f(".repeat(n)),
        format!("attr x = {}", "a ? ".repeat(n)),
        format!("attr x = {}", "case a : ".repeat(n)),
        format!("attr x = {}", "1% : ".repeat(n)),
        format!("A --> {}", "split(x){ 1 : ".repeat(n)),
        format!("A --> {}", "case a : ".repeat(n)),
        format!("A --> {}", "1% : ".repeat(n)),
        format!("A --> {}", "comp(f){ a : ".repeat(n)),
        format!("A --> X({})", "comp(f){ a : ".repeat(n)),
        format!("A --> {}", "(".repeat(n)),
    ];
    for text in &inputs {
        let diagnostics = check_robust(text);
        let messages: Vec<&str> = diagnostics.iter().map(|d| d.message.as_str()).collect();
        assert_eq!(messages, ["nesting too deep"], "{}", &text[..30]);
    }
}

#[test]
fn moderate_nesting_is_fine() {
    let text = format!("attr x = {}1{}", "(".repeat(30), ")".repeat(30));
    assert!(check_robust(&text).is_empty());
    let text = format!("A --> {}X{}", "split(x){ 1 : ".repeat(60), " }".repeat(60));
    assert!(check_robust(&text).is_empty());
}

#[test]
fn too_many_errors_stop_the_parse() {
    let text = "A --> B )\n".repeat(500);
    let diagnostics = check_robust(&text);
    assert_eq!(diagnostics.len(), 101);
    assert_eq!(
        diagnostics[100].message,
        "too many errors; stopping after 100"
    );
    let text = "$ ".repeat(10_000);
    assert_eq!(check_robust(&text).len(), 101);
}

#[test]
fn huge_inputs_parse() {
    let text = "A --> B C D(1, 2) split(x){ 1 : E | ~2 : F }*\n".repeat(50_000);
    let (_, parsed) = parse_str(&text);
    assert!(parsed.diagnostics.is_empty());
    assert_eq!(parsed.grammar.rules.len(), 50_000);
}

#[test]
fn garbage_gives_errors_without_panicking() {
    // A fixed pseudo-random byte stream (xorshift), read as lossy UTF-8.
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let bytes: Vec<u8> = (0..200_000)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state as u8
        })
        .collect();
    let text = String::from_utf8_lossy(&bytes);
    assert!(!check_robust(&text).is_empty());
    // Garbage made of the language's own characters.
    let alphabet = b"A(){}[]|:~'%.,-->=@\"#/*\n 1e5case else NIL";
    let text: String = bytes
        .iter()
        .map(|b| alphabet[*b as usize % alphabet.len()] as char)
        .collect();
    check_robust(&text);
}

#[test]
fn multi_byte_characters_do_not_break_spans() {
    for text in [
        "attr ä = \"ö\" ü",
        "Äußeres --> ß. 🏠",
        "A --> split(x){ 1 : 日本 | 語 }",
        "attr s = \"∞",
        "/* ∞",
        "A --> B\u{0}C",
        "\u{feff}A --> B",
    ] {
        check_robust(text);
    }
}

/// Token-like pieces, so generated inputs get past the lexer and into the parser.
fn cga_soup() -> impl Strategy<Value = String> {
    let piece = prop::sample::select(vec![
        "A", "b", "split(x)", "comp(f)", "{", "}", "}*", "|", ":", "=", "-->", "(", ")", "[", "]",
        ",", "~", "'", "%", "30%", "1", "2.5", "case", "else", "NIL", "attr", "const", "@Hidden",
        "\"s\"", ".", "?", "+", "*", "&&", "\n", "#c\n", "import", "style", "version",
    ]);
    prop::collection::vec(piece, 0..60).prop_map(|pieces| pieces.join(" "))
}

proptest! {
    #[test]
    fn arbitrary_strings_never_panic(text in any::<String>()) {
        check_robust(&text);
    }

    #[test]
    fn token_soup_never_panics(text in cga_soup()) {
        check_robust(&text);
    }
}

#[test]
fn line_col_counts_characters() {
    let source = SourceFile::new("x", "ab\nçd\r\n\te");
    assert_eq!(source.line_col(0), (1, 1));
    assert_eq!(source.line_col(3), (2, 1));
    assert_eq!(source.line_col(5), (2, 2), "ç is two bytes, one column");
    assert_eq!(source.line_col(4), (2, 1), "inside ç: clamped to its start");
    assert_eq!(source.line_col(9), (3, 2));
    assert_eq!(source.line_col(1000), (3, 3), "past the end: clamped");
    assert_eq!(source.name(), "x");
    assert_eq!(source.text(), "ab\nçd\r\n\te");
}

#[test]
fn rendering_of_warnings_hints_and_empty_spans() {
    let source = SourceFile::new("w.cga", "one\ntwo\n");
    let d = Diagnostic::warning("something odd", Span::new(4, 7))
        .with_hint("first hint")
        .with_hint("second hint");
    assert!(!d.is_error());
    assert_eq!(
        source.render(&d),
        "\
warning: something odd
 --> w.cga:2:1
  |
2 | two
  | ^^^
  = hint: first hint
  = hint: second hint
"
    );
    // An empty span at the very end still gets one caret; a span over a line break is cut.
    let d = Diagnostic::error("at the end", Span::new(8, 8)).with_label("here");
    assert_eq!(
        source.render(&d),
        "error: at the end\n --> w.cga:3:1\n  |\n3 | \n  | ^ here\n"
    );
    let d = Diagnostic::error("across lines", Span::new(1, 6));
    assert_eq!(
        source.render(&d),
        "error: across lines\n --> w.cga:1:2\n  |\n1 | one\n  |  ^^\n"
    );
}
