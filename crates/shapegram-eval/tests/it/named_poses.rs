//! `@Pose("open", 95)` annotations on attributes: named poses, and their compile errors.

use crate::common;

use shapegram_eval::Value;

const HEAD: &str = "Lot --> extrude(1) X\n";

#[test]
fn named_poses_gather_attribute_values_in_order_of_first_appearance() {
    let program = common::compile(&format!(
        r##"
@Pose("open", 95) @Pose("ajar", 20)
attr doorAngle = 0
@Pose("open", 80) @Pose("night", false) @Pose("closed", -5)
attr windowAngle = 0
attr storeys = 2
@Pose("night", "#202040")
attr color = "white"
{HEAD}"##
    ));
    let poses = program.named_poses();
    let names: Vec<&str> = poses.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["open", "ajar", "night", "closed"]);
    assert_eq!(
        poses[0].1,
        [
            ("doorAngle".to_owned(), Value::Number(95.0)),
            ("windowAngle".to_owned(), Value::Number(80.0)),
        ]
    );
    assert_eq!(poses[1].1, [("doorAngle".to_owned(), Value::Number(20.0))]);
    assert_eq!(
        poses[2].1,
        [
            ("windowAngle".to_owned(), Value::Bool(false)),
            ("color".to_owned(), Value::string("#202040")),
        ]
    );
    assert_eq!(
        poses[3].1,
        [("windowAngle".to_owned(), Value::Number(-5.0))]
    );
}

#[test]
fn grammars_without_poses_have_none() {
    assert!(
        common::compile(&format!("attr a = 1\n{HEAD}"))
            .named_poses()
            .is_empty()
    );
}

/// The one error of compiling `attr` declarations (with annotations) before a rule, and the
/// text its carets underline.
fn error(attrs: &str) -> (String, String) {
    let text = format!("{attrs}\n{HEAD}");
    let source = shapegram_syntax::SourceFile::new("test.cga", &text);
    let parsed = shapegram_syntax::parse(&source);
    assert!(parsed.diagnostics.iter().all(|d| !d.is_error()), "{attrs}");
    let (program, diagnostics) = shapegram_eval::Program::compile(&parsed.grammar);
    assert!(program.is_none(), "{attrs} compiles");
    let errors: Vec<_> = diagnostics.iter().filter(|d| d.is_error()).collect();
    assert_eq!(errors.len(), 1, "{attrs}: {errors:?}");
    (
        errors[0].message.clone(),
        text[errors[0].span.range()].to_owned(),
    )
}

#[test]
fn a_pose_value_that_is_no_literal_is_an_error_at_the_annotation() {
    for value in ["storeys * 2", "storeys", "rand(0, 1)", "[1, 2]", "-storeys"] {
        let annotation = format!("@Pose(\"open\", {value})");
        let (message, underlined) = error(&format!("attr storeys = 2\n{annotation}\nattr a = 0"));
        assert!(
            message.contains("literal number, boolean or string"),
            "{message}"
        );
        assert_eq!(underlined, annotation);
    }
}

#[test]
fn a_missing_or_malformed_pose_name_is_an_error_at_the_annotation() {
    for annotation in [
        "@Pose(95)",
        "@Pose",
        "@Pose(open, 95)",
        "@Pose(3, 95)",
        "@Pose(\"\", 95)",
        "@Pose(\"open\", 95, 3)",
        "@Pose(name=\"open\", 95)",
    ] {
        let (message, underlined) = error(&format!("{annotation}\nattr a = 0"));
        assert!(
            message.contains("name") || message.contains("two arguments"),
            "{annotation}: {message}"
        );
        assert_eq!(underlined, annotation);
    }
}

#[test]
fn an_attribute_given_twice_in_one_pose_is_an_error() {
    let (message, underlined) = error("@Pose(\"open\", 1) @Pose(\"open\", 2)\nattr a = 0");
    assert!(message.contains("twice"), "{message}");
    assert_eq!(underlined, "@Pose(\"open\", 2)");
}

#[test]
fn the_hinged_house_names_its_poses() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/hinged_house.cga"
    ))
    .unwrap();
    let poses = common::compile(&text).named_poses();
    let names: Vec<&str> = poses.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["closed", "open"]);
}

#[test]
fn a_pose_anywhere_but_on_an_attribute_is_a_warning_at_the_annotation() {
    let text = "@Pose(\"open\", 90)\nconst wide = 3\n@Pose(\"open\", 1)\n@StartRule\nLot --> extrude(wide) X.\n";
    let source = shapegram_syntax::SourceFile::new("test.cga", text);
    let parsed = shapegram_syntax::parse(&source);
    assert!(!parsed.has_errors(), "{:?}", parsed.diagnostics);
    let (program, diagnostics) = shapegram_eval::Program::compile(&parsed.grammar);
    let program = program.expect("a warning is no error");
    assert!(program.named_poses().is_empty());
    let warnings: Vec<(String, &str)> = diagnostics
        .iter()
        .map(|d| (d.message.clone(), &text[d.span.range()]))
        .collect();
    assert_eq!(
        warnings,
        [
            (
                "`@Pose` on a constant does nothing: poses set attributes".to_owned(),
                "@Pose(\"open\", 90)"
            ),
            (
                "`@Pose` on a rule does nothing: poses set attributes".to_owned(),
                "@Pose(\"open\", 1)"
            ),
        ]
    );
}
