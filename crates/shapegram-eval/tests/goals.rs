//! Goal grammars: rules found by goals, tags and attributes.

mod common;

use shapegram_eval::{Derivation, DeriveOptions, Program, derive};
use shapegram_syntax::{Dialect, SourceFile, parse_as};

/// Compiles goal grammars as one library (the first is the main one); panics on errors.
fn library(files: &[(&str, &str)]) -> Program {
    let sources: Vec<SourceFile> = files.iter().map(|(n, t)| SourceFile::new(*n, *t)).collect();
    let parsed: Vec<_> = sources.iter().map(|s| parse_as(s, Dialect::Goal)).collect();
    for (p, s) in parsed.iter().zip(&sources) {
        let errors: Vec<String> = p.diagnostics.iter().map(|d| s.render(d)).collect();
        assert!(!p.has_errors(), "{}", errors.join("\n"));
    }
    let grammars: Vec<(&str, &shapegram_syntax::ast::Grammar)> = files
        .iter()
        .zip(&parsed)
        .map(|((n, _), p)| (*n, &p.grammar))
        .collect();
    let (program, diagnostics) = Program::compile_library(&grammars);
    let rendered: Vec<String> = diagnostics
        .iter()
        .map(|(k, d)| sources[*k].render(d))
        .collect();
    program.unwrap_or_else(|| panic!("{}", rendered.join("\n")))
}

fn run(program: &Program, seed: u64) -> Derivation {
    let options = DeriveOptions {
        seed,
        ..DeriveOptions::default()
    };
    derive(program, &[], &options).unwrap_or_else(|e| panic!("{e}"))
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

const WOOD: &str = r##"
fulfills(wooden) --> color("#8b5a2b")
"##;

#[test]
fn the_chair_derives_legs_seat_and_lean() {
    let program = library(&[("chair", CHAIR), ("wood", WOOD)]);
    let d = run(&program, 1);
    let names: Vec<&str> = d.leaves.iter().map(|l| &*l.name).collect();
    assert_eq!(names, ["leg", "leg", "leg", "leg", "seat", "lean"]);
    for leaf in &d.leaves {
        println!("{} {:?} {:?}", leaf.name, leaf.scope.size, leaf.semantics);
    }
}
