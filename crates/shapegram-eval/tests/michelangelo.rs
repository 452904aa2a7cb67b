//! Goal grammars in the Michelangelo notation derive as their native equivalents: the paper's
//! basic chair (seed 003, its listings as printed, wrapped in `using` as the paper advises) and
//! the native chair of `goals.rs` give the same leaves, seed for seed.

use shapegram_eval::{Derivation, DeriveOptions, Program, derive};
use shapegram_syntax::{Dialect, SourceFile, parse};

const MICHELANGELO: &str = r#"new Axiom("chair", "wooden").Size  
  ↪ (0.4, 0.8, 0.4);

new Rules.Split(Axis.Y,  
  Relative(0.4).Goal("support").  
  ↪ Attribute("Leg.Size", Rnd  
  ↪ (0.03, 0.05)),  
  Relative(0.05).Goal("seat"),  
  Relative(0.55).Goal("lean"))  
.Fulfills("chair");

using (Predicates.IfIs("chair")) {
new Rules.Split(Axis.X,

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

new Rules.Size(Axis.Z, 0.04)
.Fulfills("lean");
}
"#;

const NATIVE: &str = r#"
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

const WOOD: &str = r##"fulfills(wooden) --> color("#8b5a2b")"##;

/// Compiles the files (each in the notation detected) as one library, the first the main one,
/// asserting that there are no diagnostics.
fn library(files: &[(&str, &str)]) -> Program {
    let sources: Vec<SourceFile> = files.iter().map(|(n, t)| SourceFile::new(*n, *t)).collect();
    let parsed: Vec<_> = sources.iter().map(parse).collect();
    for (p, s) in parsed.iter().zip(&sources) {
        let shown: String = p.diagnostics.iter().map(|d| s.render(d)).collect();
        assert!(p.diagnostics.is_empty(), "{shown}");
    }
    let grammars: Vec<(&str, &shapegram_syntax::ast::Grammar)> = files
        .iter()
        .zip(&parsed)
        .map(|((n, _), p)| (*n, &p.grammar))
        .collect();
    let (program, diagnostics) = Program::compile_library(&grammars);
    let shown: String = diagnostics
        .iter()
        .map(|(k, d)| sources[*k].render(d))
        .collect();
    assert!(diagnostics.is_empty(), "{shown}");
    program.expect("no errors")
}

/// Every leaf: name, scope, colour and semantics.
fn leaves(d: &Derivation) -> Vec<String> {
    d.leaves
        .iter()
        .map(|l| {
            format!(
                "{} {:?} {:?} {:?} {:?}",
                l.name, l.scope.origin, l.scope.size, l.color, l.semantics
            )
        })
        .collect()
}

#[test]
fn the_papers_chair_derives_as_the_native_one() {
    let michelangelo = library(&[("chair", MICHELANGELO), ("wood", WOOD)]);
    let native = library(&[("chair", NATIVE), ("wood", WOOD)]);
    assert_eq!(
        parse(&SourceFile::new("chair", MICHELANGELO))
            .grammar
            .dialect,
        Dialect::Michelangelo
    );
    for seed in 0..5 {
        let options = DeriveOptions {
            seed,
            ..DeriveOptions::default()
        };
        let a = derive(&michelangelo, &[], &options).expect("derives");
        let b = derive(&native, &[], &options).expect("derives");
        let names: Vec<&str> = a.leaves.iter().map(|l| &*l.name).collect();
        assert_eq!(names, ["leg", "leg", "leg", "leg", "seat", "lean"]);
        assert_eq!(leaves(&a), leaves(&b), "seed {seed}");
    }
}
