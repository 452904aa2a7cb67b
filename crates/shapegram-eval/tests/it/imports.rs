//! `import id : "file.cga"`: namespaces, attribute values through imports, rule overrides,
//! nested imports, cycles and errors placed in their file.

use crate::common;

use shapegram_eval::{DeriveOptions, ImportGraph, Program, derive};
use shapegram_syntax::{Diagnostic, SourceFile, ast::Grammar, parse};

/// Files by name and text, the first the grammar; `links[i]` names, for file i, the file of
/// each of its imports.
fn compile(files: &[(&str, &str)], links: &[Vec<usize>]) -> Result<Program, Vec<String>> {
    let sources: Vec<SourceFile> = files.iter().map(|(n, t)| SourceFile::new(*n, *t)).collect();
    let parsed: Vec<Grammar> = sources.iter().map(|s| parse(s).grammar).collect();
    let grammars: Vec<&Grammar> = parsed.iter().collect();
    let (program, diagnostics) = Program::compile_imports(ImportGraph {
        files: &grammars,
        links,
    });
    let errors: Vec<String> = diagnostics
        .iter()
        .filter(|(_, d)| d.is_error())
        .map(|(k, d): &(usize, Diagnostic)| sources[*k].render(d))
        .collect();
    match program {
        Some(program) if errors.is_empty() => Ok(program),
        _ => Err(errors),
    }
}

fn heights(program: &Program) -> Vec<(String, f64)> {
    let d = derive(
        program,
        &[common::lot(20.0, 30.0)],
        &DeriveOptions::default(),
    )
    .unwrap();
    d.leaves
        .iter()
        .map(|l| (d.name(l.name).to_string(), l.scope.size.y))
        .collect()
}

const TOWER: &str = "attr h = 1\nconst twice = h * 2\nTower --> extrude(twice) Top\n";

#[test]
fn imported_rules_and_attributes_live_in_their_namespace() {
    let main = "import t : \"tower.cga\"\n@StartRule\nLot --> t.Tower\n";
    let program = compile(
        &[("main.cga", main), ("tower.cga", TOWER)],
        &[vec![1], vec![]],
    )
    .unwrap();
    assert_eq!(heights(&program), [("Top".to_owned(), 2.0)]);
    assert_eq!(program.attr_names().collect::<Vec<_>>(), ["t.h"]);
    assert!(program.rule_names().contains(&"t.Tower"));
}

#[test]
fn attributes_come_from_the_import_statement_the_importer_or_the_file() {
    let files = |main: &'static str| [("main.cga", main), ("tower.cga", TOWER)];
    let links = [vec![1], vec![]];
    // Set by the import statement, in the importer's terms.
    let main = "attr big = 5\nimport t : \"tower.cga\" (h = big * 2)\nLot --> t.Tower\n";
    assert_eq!(heights(&compile(&files(main), &links).unwrap())[0].1, 20.0);
    // Taken from the importer's attribute of the same name.
    let main = "attr h = 4\nimport t : \"tower.cga\"\nLot --> t.Tower\n";
    assert_eq!(heights(&compile(&files(main), &links).unwrap())[0].1, 8.0);
    // Kept, by name or all.
    let main = "attr h = 4\nimport t : \"tower.cga\" (h)\nLot --> t.Tower\n";
    assert_eq!(heights(&compile(&files(main), &links).unwrap())[0].1, 2.0);
    let main = "attr h = 4\nimport t : \"tower.cga\" ()\nLot --> t.Tower\n";
    assert_eq!(heights(&compile(&files(main), &links).unwrap())[0].1, 2.0);
    // Set from outside by its full name.
    let main = "import t : \"tower.cga\"\nLot --> t.Tower\n";
    let program = compile(&files(main), &links).unwrap();
    let options = DeriveOptions {
        attrs: vec![("t.h".into(), shapegram_eval::Value::Number(7.0))],
        ..DeriveOptions::default()
    };
    let d = derive(&program, &[common::lot(20.0, 30.0)], &options).unwrap();
    assert_eq!(d.leaves[0].scope.size.y, 14.0);
}

#[test]
fn the_importer_defines_the_rules_an_imported_file_leaves_open_or_replaces() {
    let shell = "Tower --> extrude(3) Roof\nRoof --> color(\"#ff0000\")\n";
    let main = "import s : \"shell.cga\"\nLot --> s.Tower\ns.Roof --> Dome\n";
    let program = compile(
        &[("main.cga", main), ("shell.cga", shell)],
        &[vec![1], vec![]],
    )
    .unwrap();
    assert_eq!(heights(&program), [("Dome".to_owned(), 3.0)]);
}

#[test]
fn imports_nest_and_a_file_imported_twice_is_two_namespaces() {
    let inner = "attr h = 1\nPart --> extrude(h)\n";
    let middle = "import i : \"inner.cga\" (h = 2)\nBlock --> i.Part\n";
    let main = "import a : \"middle.cga\"\nimport b : \"inner.cga\" (h = 5)\nLot --> split(x) { ~1 : a.Block | ~1 : b.Part }\n";
    let program = compile(
        &[
            ("main.cga", main),
            ("middle.cga", middle),
            ("inner.cga", inner),
        ],
        &[vec![1, 2], vec![2], vec![]],
    )
    .unwrap();
    let mut names: Vec<&str> = program.attr_names().collect();
    names.sort();
    assert_eq!(names, ["a.i.h", "b.h"]);
    let h: Vec<f64> = heights(&program).iter().map(|(_, h)| *h).collect();
    assert_eq!(h, [2.0, 5.0]);
}

#[test]
fn only_the_importers_start_rule_counts() {
    let other = "@StartRule\nElsewhere --> extrude(9)\n";
    let main = "import o : \"other.cga\"\nLot --> extrude(1)\n";
    let program = compile(
        &[("main.cga", main), ("other.cga", other)],
        &[vec![1], vec![]],
    )
    .unwrap();
    assert_eq!(heights(&program)[0].1, 1.0);
}

#[test]
fn cycles_are_errors_at_the_import() {
    let a = "import b : \"b.cga\"\nLot --> b.X\n";
    let b = "import a : \"a.cga\"\nX --> extrude(1)\n";
    let errors = compile(&[("a.cga", a), ("b.cga", b)], &[vec![1], vec![0]]).unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with(
            "error: import cycle: the file imports one of the files importing it\n --> b.cga:1:1"
        ),
        "{}",
        errors[0]
    );
}

#[test]
fn errors_point_into_the_file_they_are_in() {
    let broken = "attr h = 1\nTower --> extrude(h) split(q) { 1 : A }\n";
    let main = "import t : \"tower.cga\"\nLot --> t.Tower\n";
    let errors = compile(
        &[("main.cga", main), ("tower.cga", broken)],
        &[vec![1], vec![]],
    )
    .unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(errors[0].contains("--> tower.cga:2:"), "{}", errors[0]);
    // At derivation time too.
    let failing = "Tower --> extrude(1) s(\"high\", '1, '1)\n";
    let program = compile(
        &[("main.cga", main), ("tower.cga", failing)],
        &[vec![1], vec![]],
    )
    .unwrap();
    let e = derive(
        &program,
        &[common::lot(20.0, 30.0)],
        &DeriveOptions::default(),
    )
    .unwrap_err();
    assert_eq!(e.file, Some(1));
    assert_eq!(
        e.span.map(|s| s.start),
        Some(failing.find("\"high\"").unwrap() as u32)
    );
}

#[test]
fn selectors_of_imported_rules_are_not_renamed_after_the_file_s_attributes() {
    // massmodeling_01.cga has `attr shape` and `shapeL(…){ shape : … }`: the key stays the
    // selector when the file is imported.
    let shapes = "attr shape = \"auto\"\nattr w = 4\n\
                  Wing --> shapeL(w, w) { shape : extrude(3) L | remainder : NIL }\n\
                  Split --> split(x) { w : A | ~1 : B }\n";
    let main = "import s : \"shapes.cga\"\nLot --> s.Wing\n";
    let program = compile(
        &[("main.cga", main), ("shapes.cga", shapes)],
        &[vec![1], vec![]],
    )
    .unwrap();
    assert_eq!(heights(&program), [("L".to_owned(), 3.0)]);
    // A split's sizes are expressions: `w` is the file's attribute.
    let main = "import s : \"shapes.cga\"\nLot --> s.Split\n";
    let program = compile(
        &[("main.cga", main), ("shapes.cga", shapes)],
        &[vec![1], vec![]],
    )
    .unwrap();
    let d = derive(
        &program,
        &[common::lot(20.0, 30.0)],
        &DeriveOptions::default(),
    )
    .unwrap();
    let widths: Vec<f64> = d.leaves.iter().map(|l| l.scope.size.x).collect();
    assert_eq!(widths, [4.0, 16.0]);
}

#[test]
fn dynamic_imports_set_the_imported_attributes_afresh_for_the_call() {
    // PRT's dynamic_imports package: ruleB's `h`, set by the call; `h2` follows it.
    let tower = "attr h = 1\nattr h2 = h * 2\nfoo --> extrude(h2) Top\n";
    let links = [vec![1], vec![]];
    let heights_of = |main: &str| {
        let program = compile(&[("main.cga", main), ("tower.cga", tower)], &links).unwrap();
        heights(&program)
    };
    let main = "attr big = 3.5\nimport b : \"tower.cga\"\nLot --> b(h = big * 2).foo\n";
    assert_eq!(heights_of(main), [("Top".to_owned(), 14.0)]);
    // `b().foo` goes back to the import statement's values, undoing a `set`.
    let main = "import b : \"tower.cga\" (h = 3)\nLot --> set(b.h, 5) b().foo\n";
    assert_eq!(heights_of(main), [("Top".to_owned(), 6.0)]);
    // The shape that calls keeps its own values: after the brackets, `b.foo` sees h = 3.
    let main = "import b : \"tower.cga\" (h = 3)\nLot --> b(h = 1).foo t(30, 0, 0) b.foo\n";
    assert_eq!(
        heights_of(main),
        [("Top".to_owned(), 2.0), ("Top".to_owned(), 6.0)]
    );
    let errors = compile(
        &[
            (
                "main.cga",
                "import b : \"tower.cga\"\nLot --> b(width = 2).foo\n",
            ),
            ("tower.cga", tower),
        ],
        &links,
    )
    .unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].starts_with("error: the import `b` has no attribute `width`\n --> main.cga:2:11"),
        "{}",
        errors[0]
    );
}

#[test]
fn an_import_redefines_the_file_s_extension_rules() {
    let file = "extension Roof --> Flat.\nstart Main --> extrude(2) Roof\n";
    let links = [vec![1], vec![]];
    let leaves = |main: &str| -> Vec<String> {
        let program = compile(&[("main.cga", main), ("house.cga", file)], &links).unwrap();
        let d = derive(
            &program,
            &[common::lot(4.0, 4.0)],
            &DeriveOptions::default(),
        )
        .unwrap();
        d.leaves
            .iter()
            .map(|l| d.name(l.name).to_string())
            .collect()
    };
    // The file alone: `start` makes Main its start rule, and Roof makes a flat roof.
    assert_eq!(
        leaves("import h : \"house.cga\"\nLot --> h.Main\n"),
        ["Flat"]
    );
    // Redefined by the import, in the importer's terms (its own rules).
    assert_eq!(
        leaves("import h : \"house.cga\" (Roof --> Gable)\nLot --> h.Main\nGable --> Tiles.\n"),
        ["Tiles"]
    );
    let (_, parsed) = {
        let source = SourceFile::new(
            "main.cga",
            "import \"house.cga\" (Roof --> Gable)\nLot --> X\n",
        );
        let parsed = parse(&source);
        (source, parsed)
    };
    let errors: Vec<&str> = parsed
        .diagnostics
        .iter()
        .map(|d| d.message.as_str())
        .collect();
    assert_eq!(
        errors,
        ["only an import with a name can redefine the file's rules"]
    );
}

#[test]
fn an_imported_perimeter_split_reads_its_own_attributes_and_keeps_its_remainder() {
    // The imported file's `depth` and `remainder` attributes: the section's length and depth
    // are its attributes, the `remainder` key stays the selector.
    let yard = "attr depth = 3\nattr remainder = 7\nYard --> splitAndSetbackPerimeter(0) { 20 : depth : extrude(depth) Strip } { remainder : extrude(remainder) Rest }\n";
    let main = "import y : \"yard.cga\"\n@StartRule\nLot --> y.Yard\n";
    let program = compile(
        &[("main.cga", main), ("yard.cga", yard)],
        &[vec![1], vec![]],
    )
    .unwrap();
    assert_eq!(
        heights(&program),
        [("Strip".to_owned(), 3.0), ("Rest".to_owned(), 7.0)]
    );
}
