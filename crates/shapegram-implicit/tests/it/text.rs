//! The `.cave` text form: the examples run, the paper's experiment matches the generator, and
//! every kind of mistake gets a line:column error.

use glam::DVec3;
use shapegram_implicit::text::parse;
use shapegram_implicit::{CaveParams, MeshOptions, Metrics, Operation, generate, mesh};

fn example(name: &str) -> String {
    let path = format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The error message of a text that must fail (to parse or to run).
fn error(text: &str) -> String {
    match parse(text) {
        Err(e) => e.to_string(),
        Ok(program) => program.run(None).unwrap_err().to_string(),
    }
}

#[test]
fn the_paper_examples_are_the_generators_caves() {
    for (file, lod) in [
        ("cave_paper_experiment.cave", 10),
        ("cave_paper_lod32.cave", 32),
    ] {
        let program = parse(&example(file)).unwrap();
        assert_eq!((program.lod, program.seed), (Some(lod), 1));
        let run = program.run(None).unwrap();
        let generated = generate(&CaveParams {
            lod,
            ..CaveParams::default()
        })
        .unwrap();
        assert_eq!(run.builder.solid(), generated.solid(), "{file}");
        assert_eq!(run.builder.elements(), generated.builder.elements());
    }
}

#[test]
fn the_grotto_example() {
    let program = parse(&example("grotto.cave")).unwrap();
    assert_eq!(
        (program.lod, program.seed, program.overlap),
        (Some(14), 7, 0.25)
    );
    let run = program.run(None).unwrap();
    let applied = run.builder.applied();
    let names: Vec<&str> = applied.iter().map(|a| a.operation.name()).collect();
    assert_eq!(
        names,
        [
            "sum",
            "sum",
            "sum",
            "sum",
            "sum",
            "sum",
            "sum",
            "morph",
            "difference",
            "difference",
            "difference",
            "sum",
            "sum",
            "intersection"
        ]
    );
    assert_eq!(run.builder.elements(), 16);
    let m = mesh(
        run.builder.solid(),
        &MeshOptions::with_cell_size(1.0 / 14.0),
    )
    .unwrap();
    let metrics = Metrics::measure(&m, run.builder.elements());
    assert!(metrics.edges.is_watertight(), "{metrics:?}");
    assert!(
        metrics.mesh_volume > 50.0 && metrics.area > 100.0,
        "{metrics:?}"
    );
    // A different seed draws other chamber sizes.
    let other = program.run(Some(8)).unwrap();
    assert_ne!(other.builder.solid(), run.builder.solid());
}

#[test]
fn expressions_build_the_solids_they_say() {
    let program = parse(
        "overlap 0\n\
         let a = box(2, 2, 2) - sphere(0.8)\n\
         let b = a.move(1, 0, 0) & box(1, 1, 1).scale(4, 1, 1)\n\
         add b\n",
    )
    .unwrap();
    let solid = program.run(None).unwrap().builder.solid().clone();
    // The box minus the ball, moved by +1 on x, cut to |y|, |z| < 0.5.
    assert!(solid.value(DVec3::new(1.9, 0.0, 0.0)) > 0.0);
    assert!(solid.value(DVec3::new(1.0, 0.0, 0.0)) < 0.0);
    assert!(solid.value(DVec3::new(1.9, 0.7, 0.0)) < 0.0);
    // Names are resolved where they are used: a later `let a` does not change `b`.
    let shadowed = parse("let a = sphere(1)\nlet b = a\nlet a = sphere(2)\nadd b\n").unwrap();
    let s = shadowed.run(None).unwrap().builder.solid().clone();
    assert_eq!(s.value(DVec3::ZERO), 1.0);
    // morph(…, …, 50%) and a fraction mean the same; rand draws anew at every use.
    let halves = parse("add morph(sphere(1), box(2, 2, 2), 50%)\n").unwrap();
    let fraction = parse("add morph(sphere(1), box(2, 2, 2), 0.5)\n").unwrap();
    assert_eq!(
        halves.run(None).unwrap().builder.solid(),
        fraction.run(None).unwrap().builder.solid()
    );
    let repeated = parse("repeat 2 {\n  add sphere(rand(1, 2)) at +x\n}\n").unwrap();
    let run = repeated.run(None).unwrap();
    let (first, second) = (run.builder.applied()[0], run.builder.applied()[1]);
    assert_eq!(first.operation, Operation::Sum);
    assert!(second.label.is_some());
    let b = run.builder.solid().bounds().unwrap();
    assert!(b.size().y != 2.0 * b.size().z || b.size().x > b.size().y);
}

#[test]
fn productions_default_to_the_current_direction() {
    let program =
        parse("direction -y\nadd box(1, 1, 1)\nadd box(1, 1, 1)\nadd box(1, 1, 1)\n").unwrap();
    let solid = program.run(None).unwrap().builder.solid().clone();
    let b = solid.bounds().unwrap();
    assert!(
        (b.min.y + 2.0).abs() < 1e-12 && (b.max.y - 0.5).abs() < 1e-12,
        "{b:?}"
    );
}

#[test]
fn mistakes_have_line_and_column() {
    let cases = [
        (
            "add sphere(1",
            "1:13: expected ',' or ')' before the end of the line",
        ),
        ("add sphere(1, 2)", "1:5: sphere takes 1 number, found 2"),
        (
            "add sphere(-1)",
            "1:5: invalid sphere radius -1: expected a finite number greater than 0",
        ),
        (
            "add blob",
            "1:5: unknown solid 'blob': define it above with 'let blob = …'",
        ),
        (
            "let a = a + sphere(1)",
            "1:9: 'a' cannot be used in its own definition",
        ),
        (
            "let box = sphere(1)",
            "1:5: 'box' is a reserved word and cannot name a solid",
        ),
        (
            "lod 40",
            "1:5: invalid level of detail 40: expected a whole number from 1 to 32",
        ),
        ("lod 3\nlod 4", "2:1: 'lod' is set twice (first at 1:1)"),
        (
            "seed -3",
            "1:6: invalid seed -3: expected a whole number from 0 to 18446744073709551615",
        ),
        ("overlap 2", "1:9: invalid overlap 2: expected 0 to 1"),
        (
            "add sphere(1)\nadd sphere(1) at +w",
            "2:18: invalid direction '+w': expected -x, +x, -y, +y, -z, +z or random",
        ),
        (
            "add sphere(1) at",
            "1:17: expected a direction: -x, +x, -y, +y, -z, +z or random",
        ),
        (
            "morph sphere(1) 120%",
            "1:1: invalid morphing parameter 120%: expected 0 to 100",
        ),
        (
            "morph sphere(1) 20",
            "1:19: expected '%' before the end of the line",
        ),
        ("add sphere(1) $", "1:15: unexpected character '$'"),
        (
            "add sphere(1).twist(3)",
            "1:15: unknown transform 'twist': expected move, rotate or scale",
        ),
        (
            "add sphere(1).rotate(w, 3)",
            "1:22: expected the axis x, y or z",
        ),
        (
            "add sphere(1).scale(0)",
            "1:15: invalid scale x 0: expected a finite non-zero number",
        ),
        ("add sphere(1e999)", "1:12: number '1e999' is too large"),
        (
            "add torus(1, 2)",
            "1:5: invalid torus: the minor radius 2 must be less than the major radius 1",
        ),
        (
            "repeat 3 {\nadd sphere(1)\n",
            "1:1: this 'repeat' block has no '}' to close it",
        ),
        ("}", "1:1: '}' without a 'repeat' block to close"),
        (
            "fly 3",
            "1:1: unknown statement 'fly': expected lod, seed, overlap, direction, let, add, subtract, intersect, morph, repeat or generate",
        ),
        (
            "add sphere(1)\nadd box(1, 1, 1) at +x extra",
            "2:24: expected the end of the line, found 'extra'",
        ),
        (
            "add sphere(rand(2, 1))",
            "1:16: invalid rand(2, 1): the lower bound is above the upper",
        ),
        (
            "generate classic 2 flavour 3",
            "1:20: unknown generate option 'flavour': expected classic, morphic, direction, morph or per_shape",
        ),
        (
            "generate morph 150%",
            "1:1: invalid morphing parameter 150%: expected 0 to 100",
        ),
        (
            "repeat 10 {\nrepeat 200 {\nadd sphere(1)\n}\n}",
            "1:1: more than 1000 productions",
        ),
        (
            "add sphere(1)\nrepeat 999 {\nadd sphere(1)\n}\nadd sphere(1)",
            "5:1: more than 1000 productions",
        ),
        (
            "generate classic 600 morphic 401",
            "1:1: more than 1000 productions",
        ),
        (
            "add box(1, 1, 1)\nadd sphere(1) at +q",
            "2:18: invalid direction '+q': expected -x, +x, -y, +y, -z, +z or random",
        ),
        (
            "add sphere(1)\nsubtract sphere(3) at centre\nadd sphere(1) at +x",
            "3:1: the base has no open bond facing +x for a sum",
        ),
    ];
    for (text, message) in cases {
        assert_eq!(error(text), message, "{text}");
    }
}

#[test]
fn long_expressions_and_deep_names_are_errors() {
    let long = format!("add sphere(1){}", " + sphere(1)".repeat(300));
    assert_eq!(
        error(&long),
        "1:3087: more than 256 operators and transforms in one statement: split it with 'let'"
    );
    let mut chain = String::from("let a0 = sphere(1)\n");
    for i in 1..150 {
        chain += &format!("let a{i} = a{}\n", i - 1);
    }
    chain += "add a149\n";
    assert_eq!(
        error(&chain),
        "151:1: the solid nests deeper than 128 operations and names: build it from fewer, wider parts"
    );
    let mut deep = format!("let a0 = sphere(1){}\n", " + sphere(1)".repeat(200));
    for i in 1..8 {
        deep += &format!("let a{i} = a{}{}\n", i - 1, " + sphere(1)".repeat(200));
    }
    deep += "add a7\n";
    assert_eq!(
        error(&deep),
        "9:1: the solid nests deeper than 128 operations and names: build it from fewer, wider parts"
    );
}

#[test]
fn definitions_that_double_up_hit_the_budget() {
    let mut text = String::from("let a0 = sphere(1)\n");
    for i in 1..40 {
        text += &format!("let a{i} = a{} + a{}\n", i - 1, i - 1);
    }
    text += "add a39\n";
    assert_eq!(
        error(&text),
        "41:1: the solids are too large: more than 1000000 parts evaluated"
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(400))]

    /// Token soup never panics: it parses (and then runs) or fails with a located error.
    #[test]
    fn token_soup_never_panics(
        tokens in proptest::collection::vec(
            proptest::sample::select(vec![
                "add", "subtract", "intersect", "morph", "let", "a", "b", "=", "sphere", "box",
                "torus", "cone", "pyramid", "capsule", "cylinder", "(", ")", ",", "1", "0", "-2",
                "0.5", "1e3", "%", "+", "-", "&", ".", "move", "rotate", "scale", "x", "at", "+x",
                "centre", "random", "rand", "smooth_union", "lod", "seed", "overlap", "direction",
                "\n", "\n", "\n", "#", "{", "}", "$", "é",
            ]),
            0..40,
        )
    ) {
        let text = tokens.join(" ");
        match parse(&text) {
            Err(e) => proptest::prop_assert!(e.line >= 1 && e.column >= 1, "{e}"),
            Ok(program) => {
                if let Err(e) = program.run(None) {
                    proptest::prop_assert!(e.line >= 1 && e.column >= 1, "{e}");
                }
            }
        }
    }
}

#[test]
fn a_number_where_a_solid_belongs_explains_the_morphing_amount() {
    assert_eq!(
        error("add sphere(1)\nmorph sphere(1) -5%\n"),
        "2:18: expected a solid: a primitive, a name, morph(…) or '(', found number 5 (after a solid, + - & combine it with another; a morphing amount is 0 to 100 %, as in `morph hall 55%`)"
    );
}
